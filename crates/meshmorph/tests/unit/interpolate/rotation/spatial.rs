use meshmorph::interpolate::rotation::Rotations;
use meshmorph::linalg::vector::norm;
use meshmorph::Space;

use meshmorph::interpolate::rotation::spatial::*;
use meshmorph::linalg::quaternion::exp_rotation;
use std::f64::consts::PI;

#[test]
fn polar_exp_and_segments() {
    type P = Space<3>;
    let w = [0.3, -1.2, 0.8];
    let (q, S) = P::polar(&exp_rotation(w));
    assert!((P::angle(&q) - norm(w)).abs() < 1e-12);
    assert!(S
        .iter()
        .enumerate()
        .all(|(i, r)| (r[i] - 1.0).abs() < 1e-12));
    let log = P::principal_log(&q);
    let back = P::exp(&log);
    let R = exp_rotation(w);
    assert!((0..3).all(|i| (0..3).all(|j| (back[i][j] - R[i][j]).abs() < 1e-13)));
    // A segment from the identity reaches the key at u = 1, with a whole
    // turn added to the log turning through 2π + |w|.
    let turned = P::add_turns(&log, 1);
    assert!((norm(turned.lifted()) - (2.0 * PI + norm(w))).abs() < 1e-12);
    let id = ([P::IDENTITY; 2], [RotationLog3::default(); 2]);
    let to = ([q, q], [turned, turned]);
    let (s, turns) = P::segments((&id.0, &id.1), (&to.0, &to.1), true);
    // Both triangles share one whole-turn vector.
    assert_eq!(turns.0.len(), 1);
    let mut turns_at = Vec::new();
    P::turns_at(&turns, 1.0, &mut turns_at);
    for s in &s {
        assert!(P::has_whole_turns(s));
        let end = P::segment_at(s, &turns_at, 1.0, true);
        assert!((0..3).all(|i| (0..3).all(|j| (end[i][j] - R[i][j]).abs() < 1e-12)));
    }
    let (short, turns) = P::segments((&id.0, &id.1), (&to.0, &to.1), false);
    assert!(turns.0.is_empty() && !P::has_whole_turns(&short[0]));
}
