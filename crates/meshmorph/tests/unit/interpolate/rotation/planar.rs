use meshmorph::interpolate::rotation::Rotations;
use meshmorph::linalg::polar::rotation;
use meshmorph::Space;
use std::f64::consts::TAU;

use meshmorph::interpolate::rotation::planar::*;
use std::f64::consts::PI;

#[test]
fn branches() {
    assert!((nearest_branch(-0.9 * PI, 0.95 * PI) - 1.1 * PI).abs() < 1e-12);
    assert!((nearest_branch(0.1, 4.0 * PI) - (0.1 + 4.0 * PI)).abs() < 1e-12);
    assert_eq!(nearest_branch(0.5, 0.4), 0.5);
}

#[test]
fn segments_exp_and_turns() {
    type P = Space<2>;
    for a in [-3.0, -0.5, 0.0, 1.0, 3.1] {
        let (angle, _) = P::polar(&P::exp(&a));
        assert!((angle - a).abs() < 1e-14);
        // From the identity, bit for bit R(u θ).
        let s = segment(0.0, a + TAU, true);
        assert_eq!(P::segment_at(&s, &[], 0.3, true), rotation(0.3 * (a + TAU)));
        assert!(P::has_whole_turns(&s));
        let short = segment(2.0, a + TAU, false);
        assert!(!P::has_whole_turns(&short));
    }
    assert_eq!(P::add_turns(&0.25, -1), 0.25 - TAU);
    assert_eq!(P::angle(&-0.25), 0.25);
}
