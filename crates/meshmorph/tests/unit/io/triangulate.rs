use meshmorph::io::triangulate::*;

fn signed_area(p: &[[f64; 3]], t: [u32; 3]) -> f64 {
    let [a, b, c] = t.map(|i| p[i as usize]);
    0.5 * turn([a[0], a[1]], [b[0], b[1]], [c[0], c[1]])
}

#[test]
fn l_shape_both_orientations() {
    let p: Vec<[f64; 3]> = [[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]]
        .iter()
        .map(|q| [q[0], q[1], 0.0])
        .collect();
    for reversed in [false, true] {
        let mut poly: Vec<u32> = (0..6).collect();
        if reversed {
            poly.reverse();
        }
        let mut out = Vec::new();
        triangulate_polygon(&p, &poly, &mut out);
        assert_eq!(out.len(), 4);
        let sign = if reversed { -1.0 } else { 1.0 };
        let areas: Vec<f64> = out.iter().map(|&t| sign * signed_area(&p, t)).collect();
        assert!(areas.iter().all(|&a| a > 0.0), "{out:?}");
        assert!((areas.iter().sum::<f64>() - 3.0).abs() < 1e-12);
    }
}

#[test]
fn convex_quad_uses_shorter_diagonal() {
    let p = vec![[0., 0., 0.], [3., 0., 0.], [3.5, 1., 0.], [0., 1., 0.]];
    let mut out = Vec::new();
    triangulate_polygon(&p, &[0, 1, 2, 3], &mut out);
    // |p1 - p3| = sqrt(10) < |p0 - p2| = sqrt(13.25)
    assert_eq!(out, vec![[1, 2, 3], [1, 3, 0]]);
}

#[test]
fn tilted_polygon_and_degenerate_fallback() {
    // A concave pentagon in the plane x = z.
    let p: Vec<[f64; 3]> = [[0., 0.], [4., 0.], [4., 4.], [2., 1.], [0., 4.]]
        .iter()
        .map(|q| [q[0], q[1], q[0]])
        .collect();
    let mut out = Vec::new();
    triangulate_polygon(&p, &[0, 1, 2, 3, 4], &mut out);
    assert_eq!(out.len(), 3);
    let area: f64 = out.iter().map(|&t| signed_area(&p, t)).sum();
    assert!((area - 10.0).abs() < 1e-12, "{out:?}");
    assert!(out.iter().all(|&t| signed_area(&p, t) > 0.0));
    // All on a line: a fan, no panic.
    let line = vec![[0., 0., 0.], [1., 0., 0.], [2., 0., 0.], [3., 0., 0.]];
    out.clear();
    triangulate_polygon(&line, &[0, 1, 2, 3], &mut out);
    assert_eq!(out.len(), 2);
}

#[test]
fn large_star_polygons() {
    for n in [40, 600, 3000] {
        // A star: alternating radii, so every other vertex is reflex.
        let p: Vec<[f64; 3]> = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                let r = if k % 2 == 0 { 1.0 } else { 0.8 };
                [r * a.cos(), r * a.sin(), 0.0]
            })
            .collect();
        let poly: Vec<u32> = (0..n as u32).collect();
        let mut out = Vec::new();
        triangulate_polygon(&p, &poly, &mut out);
        assert_eq!(out.len(), n - 2);
        let area: f64 = (0..n)
            .map(|k| {
                let (a, b) = (p[k], p[(k + 1) % n]);
                0.5 * (a[0] * b[1] - a[1] * b[0])
            })
            .sum();
        let sum: f64 = out.iter().map(|&t| signed_area(&p, t)).sum();
        assert!((sum - area).abs() < 1e-9, "{n}: {sum} vs {area}");
        if n <= EAR_CLIPPING_LIMIT {
            assert!(out.iter().all(|&t| signed_area(&p, t) > 0.0), "{n}");
        }
    }
}

#[test]
fn repeats() {
    assert_eq!(repeated_index(&[1, 2, 3]), None);
    assert_eq!(repeated_index(&[1, 2, 1]), Some(1));
    let mut big: Vec<u32> = (0..40).collect();
    assert_eq!(repeated_index(&big), None);
    big.push(7);
    assert_eq!(repeated_index(&big), Some(7));
}
