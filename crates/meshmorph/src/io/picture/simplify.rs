//! Closed loops thinned within a tolerance (Douglas and Peucker 1973).

/// The points of the closed loop `points` kept so that every point left
/// out lies within `tolerance` of the chord that replaces it: the point
/// farthest from the first splits the loop in two, and each half is
/// thinned by recursive Douglas-Peucker. The first point is always kept;
/// loops of fewer than 4 points are returned as they are.
pub fn simplify_loop(points: &[[f64; 2]], tolerance: f64) -> Vec<[f64; 2]> {
    let n = points.len();
    if n < 4 {
        return points.to_vec();
    }
    let d2 = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
    let far = (1..n)
        .max_by(|&i, &j| d2(points[0], points[i]).total_cmp(&d2(points[0], points[j])))
        .unwrap_or(n / 2);
    let mut keep = vec![false; n + 1];
    keep[0] = true;
    keep[far] = true;
    keep[n] = true;
    let at = |i: usize| points[i % n];
    // Stack of spans (first, last) still to split, last == n meaning point 0.
    let mut spans = vec![(0, far), (far, n)];
    while let Some((a, b)) = spans.pop() {
        if b <= a + 1 {
            continue;
        }
        let (p, q) = (at(a), at(b));
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let len = (dx * dx + dy * dy).sqrt();
        let dist = |i: usize| {
            let r = at(i);
            if len == 0.0 {
                d2(p, r).sqrt()
            } else {
                ((r[0] - p[0]) * dy - (r[1] - p[1]) * dx).abs() / len
            }
        };
        let (worst, d) = (a + 1..b)
            .map(|i| (i, dist(i)))
            .max_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap_or((a, 0.0));
        if d > tolerance {
            keep[worst] = true;
            spans.push((a, worst));
            spans.push((worst, b));
        }
    }
    (0..n).filter(|&i| keep[i]).map(|i| points[i]).collect()
}
