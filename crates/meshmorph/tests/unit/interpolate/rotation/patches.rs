use meshmorph::linalg::quaternion::{quat_exp, quat_log, quat_mul, Quat};
use meshmorph::linalg::vector::{add, norm, scale, sub};
use meshmorph::mesh::topology::TriangleAdjacency;
use std::f64::consts::{PI, TAU};

use meshmorph::interpolate::rotation::patches::*;

/// A strip of triangles `0-1-2-...` (each sharing an edge with the next).
fn chain(n: u32) -> TriangleAdjacency {
    let tris: Vec<[u32; 3]> = (0..n).map(|i| [i, i + 1, i + 2]).collect();
    TriangleAdjacency::new(&tris)
}

fn principal(w: [f64; 3]) -> Quat {
    meshmorph::linalg::quaternion::quat_principal(quat_exp(w))
}

/// The lifted rotation vector of triangle `i` at `t = 1`, i.e. the total
/// turn its interpolation makes (exact when `c` and `e` are parallel).
fn lifted(q: Quat, c: [f64; 3]) -> [f64; 3] {
    add(c, quat_log(q))
}

#[test]
fn a_chain_turning_three_half_turns_is_unwrapped() {
    // True angles grow by 0.1π per step about a fixed axis, to 3π.
    let n = 31;
    let axis = [0.0, 0.6, 0.8];
    let truth: Vec<f64> = (0..n).map(|i| 0.1 * PI * i as f64).collect();
    let q: Vec<Quat> = truth.iter().map(|&a| principal(scale(axis, a))).collect();
    let c = whole_turns(&q, &chain(n as u32), |_, _| 1.0, &[0], None);
    for i in 0..n {
        let l = lifted(q[i], c[i]);
        let want = scale(axis, truth[i]);
        assert!(norm(sub(l, want)) < 1e-9, "{i}: {l:?} {want:?}");
    }
}

#[test]
fn rotations_under_half_a_turn_get_no_turns() {
    // A noisy non-rigid field whose rotations stay under 0.45π: nothing
    // changes, whatever the noise between neighbours.
    let mut r = crate::linalg::polar::rng(9);
    let n = 200;
    let q: Vec<Quat> = (0..n)
        .map(|_| {
            let w = [r(), r(), r()];
            principal(scale(w, 0.45 * PI / 3f64.sqrt()))
        })
        .collect();
    let c = whole_turns(&q, &chain(n as u32), |_, _| 1.0, &[0], None);
    assert!(c.iter().all(|&v| v == [0.0; 3]));
}

#[test]
fn a_turn_carried_through_small_rotations_with_stray_axes() {
    // A twist about x to 3π in which every rotation also carries a small
    // rotation about an axis that varies from triangle to triangle (as a
    // twisted tube's shear does): near a full turn the principal
    // rotations are small with stray axes, and the turn carries through.
    let n = 61;
    let x = [1.0, 0.0, 0.0];
    let mut expected = Vec::new();
    let q: Vec<Quat> = (0..n)
        .map(|i| {
            let a = 3.0 * PI * i as f64 / (n - 1) as f64;
            let phi = 0.7 * i as f64;
            let shear = [0.0, 0.2 * phi.cos(), 0.2 * phi.sin()];
            expected.push(a);
            principal(quat_log(quat_mul(quat_exp(scale(x, a)), quat_exp(shear))))
        })
        .collect();
    let c = whole_turns(&q, &chain(n as u32), |_, _| 1.0, &[0], None);
    for i in 0..n {
        let turns = norm(c[i]) / TAU;
        let want = ((expected[i] - PI) / TAU).ceil().max(0.0);
        // Near exactly π and 3π either side of the jump is fine.
        let near = ((expected[i] / PI) - (expected[i] / PI).round()).abs() < 0.06;
        if !near {
            assert_eq!(turns.round(), want, "{i}");
            if turns > 0.5 {
                assert!(c[i][0] > 0.99 * norm(c[i]), "{i}: {:?}", c[i]);
            }
        }
    }
}
