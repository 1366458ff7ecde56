use meshmorph::expressions::template::ExpressionTemplate;

use meshmorph::expressions::openings::*;

/// Points along the template's mouth, from `from` to `to` of the way
/// between its corners, a hair apart across it, and the edges between
/// each pair.
fn lined(t: &ExpressionTemplate, from: f64, to: f64) -> (Vec<[f64; 3]>, Vec<(u32, u32)>) {
    let at = |n: &str| t.head.positions()[t.landmark(n).unwrap() as usize];
    let (a, b) = (at("49"), at("55"));
    let mut positions = Vec::new();
    let mut cut = Vec::new();
    for k in 0..=40 {
        let s = from + (to - from) * k as f64 / 40.0;
        let p: [f64; 3] = std::array::from_fn(|i| a[i] + s * (b[i] - a[i]));
        positions.push(p);
        positions.push([p[0], p[1] - 1e-4, p[2]]);
        cut.push((2 * k, 2 * k + 1));
    }
    (positions, cut)
}

#[test]
fn lips_joined_across_the_mouth_are_found_cuts_near_its_corners_are_not() {
    let t = ExpressionTemplate::arkit();
    let corner = |v: u32| t.head.positions()[v as usize];
    let (positions, cut) = lined(&t, 0.05, 0.95);
    let w = joined_openings(&t, corner, &positions, &cut);
    assert!(w.len() == 1 && w[0].contains("lips of the mouth"), "{w:?}");
    for (from, to) in [(0.0, 0.2), (0.8, 1.0)] {
        let (positions, cut) = lined(&t, from, to);
        assert!(joined_openings(&t, corner, &positions, &cut).is_empty());
    }
}
