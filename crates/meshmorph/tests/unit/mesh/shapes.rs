use meshmorph::mesh::shapes::*;

#[test]
fn strip_counts_and_orientation() {
    let m = strip(4.0, 1.0, 8, 2);
    assert_eq!(m.num_vertices(), 27);
    assert_eq!(m.num_triangles(), 32);
    assert!(m
        .signed_areas()
        .iter()
        .all(|&a| (a - 4.0 / 32.0).abs() < 1e-12));
}

#[test]
fn curl_keeps_the_centre_line_length_and_orientation() {
    let m = strip(10.0, 0.4, 100, 4);
    let c = curl(&m, 3.0 * std::f64::consts::PI);
    assert!(c.signed_areas().iter().all(|&a| a > 0.0));
    // Vertices on the centre line (row 2) stay 0.1 apart.
    let row: Vec<[f64; 2]> = c.positions()[2 * 101..3 * 101].to_vec();
    for w in row.windows(2) {
        let d = ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt();
        assert!((d - 0.1).abs() < 1e-3, "{d}");
    }
}

#[test]
fn tube_is_closed_and_bends() {
    let t = tube(4.0, 0.5, 9, 12);
    let e = meshmorph::mesh::topology::edges(t.triangles());
    assert!(e.iter().all(|e| e.triangles.len() == 2));
    let b = bend(&t, 4.0, std::f64::consts::FRAC_PI_2);
    assert_eq!(b.num_vertices(), t.num_vertices());
}

#[test]
fn stroke_outline_is_counter_clockwise_with_the_stroke_area() {
    use std::f64::consts::PI;
    let area = |p: &[[f64; 2]]| {
        (0..p.len())
            .map(|i| {
                let (a, b) = (p[i], p[(i + 1) % p.len()]);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum::<f64>()
            / 2.0
    };
    // A straight stroke: a rectangle and two half discs.
    let straight = stroke_outline([1.0, 2.0], 0.7, &[(4.0, 0.0)], &|_| 0.5, 0.01);
    let expected = 4.0 * 1.0 + PI * 0.25;
    assert!((area(&straight) - expected).abs() < 1e-3 * expected);
    // Bent by a quarter turn on an arc of radius 2: the same area.
    let bent = stroke_outline(
        [0.0, 0.0],
        0.0,
        &[(1.0, 0.0), (PI, PI / 2.0), (1.0, 0.0)],
        &|_| 0.5,
        0.01,
    );
    let expected = (2.0 + PI) * 1.0 + PI * 0.25;
    assert!((area(&bent) - expected).abs() < 1e-3 * expected);
    // Tapered: every point is finite up to the tip.
    let tapered = stroke_outline(
        [0.0, 0.0],
        0.0,
        &[(3.0, 2.0)],
        &|s| 0.3 * (1.0 - s).max(0.0).sqrt() + 0.05,
        0.05,
    );
    assert!(tapered.iter().flatten().all(|x| x.is_finite()));
    assert!(area(&tapered) > 0.0);
}
