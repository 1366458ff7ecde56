//! Separate parts of one mesh between keys: parts that sit in a larger part
//! (eyes in a head) turn with it; parts that move on their own keep their
//! straight paths. And frames at the keys' times are the keys.

use std::f64::consts::PI;

use meshmorph::shapes::{octahedron, rigid_motion, rigid_motion3, strip, tube};
use meshmorph::{Blend, Interpolator, InterpolatorOptions, Mesh, Mesh2, Mesh3, Sequence};

/// The meshes' vertices and triangles one after the other.
fn joined<const D: usize>(parts: &[Mesh<D>]) -> Mesh<D> {
    let (mut positions, mut triangles) = (Vec::new(), Vec::new());
    for m in parts {
        let offset = positions.len() as u32;
        positions.extend_from_slice(m.positions());
        triangles.extend(m.triangles().iter().map(|t| t.map(|v| v + offset)));
    }
    Mesh::new(positions, triangles).unwrap()
}

fn moved3(m: &Mesh3, by: [f64; 3]) -> Mesh3 {
    rigid_motion3(m, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], by)
}

/// The rotation by `angle` about the unit `axis`.
fn rotation(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let (s, c) = angle.sin_cos();
    let [x, y, z] = axis;
    [
        [
            c + x * x * (1.0 - c),
            x * y * (1.0 - c) - z * s,
            x * z * (1.0 - c) + y * s,
        ],
        [
            y * x * (1.0 - c) + z * s,
            c + y * y * (1.0 - c),
            y * z * (1.0 - c) - x * s,
        ],
        [
            z * x * (1.0 - c) - y * s,
            z * y * (1.0 - c) + x * s,
            c + z * z * (1.0 - c),
        ],
    ]
}

/// A "head" (a capped tube along x) with two "eyes" (small tubes) just off
/// its surface and a "tooth" inside it, away from the origin.
fn head() -> Mesh3 {
    let head = tube(2.0, 0.5, 9, 10);
    let eye = tube(0.2, 0.1, 3, 6);
    let tooth = tube(0.3, 0.08, 3, 5);
    let at = [3.0, -1.0, 2.0];
    let shift = |m: &Mesh3, by: [f64; 3]| moved3(m, std::array::from_fn(|i| by[i] + at[i]));
    joined(&[
        shift(&head, [0.0; 3]),
        shift(&eye, [1.2, 0.55, 0.2]),
        shift(&eye, [1.2, 0.55, -0.2]),
        shift(&tooth, [0.4, -0.2, 0.0]),
    ])
}

/// The largest change of distance between any two vertices of `a` and `b`,
/// over the diagonal of `a`'s bounding box: 0 for a rigid motion.
fn non_rigidity<const D: usize>(a: &[[f64; D]], b: &[[f64; D]]) -> f64 {
    let dist =
        |p: &[f64; D], q: &[f64; D]| (0..D).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt();
    let mut worst: f64 = 0.0;
    for i in 0..a.len() {
        for j in i + 1..a.len() {
            worst = worst.max((dist(&a[i], &a[j]) - dist(&b[i], &b[j])).abs());
        }
    }
    let (lo, hi) = a
        .iter()
        .fold(([f64::MAX; D], [f64::MIN; D]), |(lo, hi), p| {
            (
                std::array::from_fn(|k| lo[k].min(p[k])),
                std::array::from_fn(|k| hi[k].max(p[k])),
            )
        });
    worst / dist(&lo, &hi)
}

fn max_distance<const D: usize>(a: &[[f64; D]], b: &[[f64; D]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (0..D).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt())
        .fold(0.0, f64::max)
}

#[test]
fn eyes_and_teeth_turn_with_the_head() {
    let rest = head();
    let options = InterpolatorOptions::default();
    for (axis, degrees) in [
        ([0.0, 0.0, 1.0], 90.0),
        ([0.6, 0.0, 0.8], 150.0),
        ([0.0, 1.0, 0.0], 270.0),
    ] {
        let turned = rigid_motion3(
            &rest,
            rotation(axis, degrees * PI / 180.0),
            [0.5, 1.0, -2.0],
        );
        let morph = Interpolator::new(&rest, &turned, &options).unwrap();
        for t in [0.25, 0.5, 0.75] {
            let frame = morph.at(t);
            let err = non_rigidity(rest.positions(), &frame);
            assert!(err < 1e-9, "{degrees}° at t = {t}: not rigid ({err:.2e})");
        }
        assert!(max_distance(&morph.at(1.0), turned.positions()) < 1e-9);
        // The same turn as a blend of weight 1/2 and as a sequence of three keys.
        let blend = Blend::new(&rest, std::slice::from_ref(&turned), &options).unwrap();
        assert!(non_rigidity(rest.positions(), &blend.at(&[0.5])) < 1e-9);
        let half = rigid_motion3(&rest, rotation(axis, degrees * PI / 360.0), [0.0; 3]);
        let keys = [rest.clone(), half, turned.clone()];
        let sequence = Sequence::new(&keys, &options).unwrap();
        for s in [0.5, 1.0, 1.5] {
            assert!(non_rigidity(rest.positions(), &sequence.at(s)) < 1e-9);
        }
        assert!(max_distance(&sequence.at(2.0), turned.positions()) < 1e-9);
    }
}

#[test]
fn a_ball_centred_in_a_pipe_turns_with_the_pipe() {
    // Centred on the axis, the ball's offset from the pipe's vertices
    // around it is zero up to rounding whichever way the pipe turns: it
    // must still follow the pipe (it slid along the axis at some angles).
    // The keys as a file holds them: 12 significant digits.
    let written = |m: &Mesh3| {
        let p: Vec<[f64; 3]> = m
            .positions()
            .iter()
            .map(|p| p.map(|x| format!("{x:.11e}").parse().unwrap()))
            .collect();
        m.with_positions(p).unwrap()
    };
    let pipe = tube(4.0, 0.6, 15, 16);
    let rest = written(&joined(&[pipe, octahedron([3.5, 0.0, 0.0], 0.2)]));
    let options = InterpolatorOptions::default();
    for degrees in [30.0, 60.0, 90.0, 120.0, 150.0] {
        // About the pipe's middle, (2, 0, 0).
        let (s, c) = (degrees * PI / 180.0).sin_cos();
        let about_middle: Vec<[f64; 3]> = rest
            .positions()
            .iter()
            .map(|&[x, y, z]| [c * (x - 2.0) - s * y + 2.0, s * (x - 2.0) + c * y, z])
            .collect();
        let turned = written(&rest.with_positions(about_middle).unwrap());
        let keys = [rest.clone(), turned.clone()];
        let morph = Sequence::new(&keys, &options).unwrap();
        assert_eq!(morph.parts_following_host(), 1, "{degrees}°");
        let err = non_rigidity(rest.positions(), &morph.at(0.5));
        assert!(err < 1e-8, "{degrees}°: not rigid ({err:.2e})");
        let blend = Blend::new(&rest, std::slice::from_ref(&turned), &options).unwrap();
        assert_eq!(blend.parts_following_host(), 1, "{degrees}°");
        assert!(non_rigidity(rest.positions(), &blend.at(&[0.5])) < 1e-8);
    }
}

/// Parts that follow their anchors are placed the same whether frames are
/// solved together or one at a time.
#[test]
fn attached_parts_are_placed_alike_in_frames_solved_together() {
    let rest = head();
    let turned = rigid_motion3(&rest, rotation([0.6, 0.0, 0.8], 2.5), [0.5, 1.0, -2.0]);
    let morph = Interpolator::new(&rest, &turned, &InterpolatorOptions::default()).unwrap();
    let times: Vec<f64> = (0..9).map(|k| k as f64 / 8.0).collect();
    let diag = rest.bounding_box_diagonal();
    for (&t, frame) in times.iter().zip(morph.frames(&times)) {
        assert!(max_distance(&frame, &morph.at(t)) < 1e-12 * diag, "at {t}");
    }
}

#[test]
fn eyes_that_move_in_their_sockets_reach_every_key() {
    // The head turns by 120 degrees while the eyes slide along its surface.
    let rest = head();
    let mut key = rest.positions().to_vec();
    let head_vertices = 9 * 10 + 2;
    for p in &mut key[head_vertices..head_vertices + 2 * (3 * 6 + 2)] {
        p[0] += 0.3;
    }
    let slid = rest.with_positions(key).unwrap();
    let turned = rigid_motion3(&slid, rotation([0.0, 0.0, 1.0], 2.0 * PI / 3.0), [0.0; 3]);
    let morph = Interpolator::new(&rest, &turned, &InterpolatorOptions::default()).unwrap();
    assert!(max_distance(&morph.at(0.0), rest.positions()) < 1e-9);
    assert!(max_distance(&morph.at(1.0), turned.positions()) < 1e-9);
    // Halfway, the eyes are halfway along their slide, on the turned head.
    let halfway = morph.at(0.5);
    let expected = rigid_motion3(
        &rest
            .with_positions(
                rest.positions()
                    .iter()
                    .enumerate()
                    .map(|(v, p)| {
                        let slide = if (head_vertices..head_vertices + 40).contains(&v) {
                            0.15
                        } else {
                            0.0
                        };
                        [p[0] + slide, p[1], p[2]]
                    })
                    .collect(),
            )
            .unwrap(),
        rotation([0.0, 0.0, 1.0], PI / 3.0),
        [0.0; 3],
    );
    let err = non_rigidity(expected.positions(), &halfway);
    assert!(err < 1e-6, "{err:.3e}");
}

#[test]
fn a_part_that_stays_put_beside_a_turning_part_stays_put() {
    // Two tubes side by side, touching: one turns by 90 degrees about its
    // own middle, the other does not move.
    let a = tube(1.0, 0.5, 5, 8);
    let b = moved3(&tube(0.6, 0.3, 4, 6), [0.2, 0.8, 0.0]);
    let rest = joined(&[a.clone(), b.clone()]);
    let middle = [0.5, 0.0, 0.0];
    let r = rotation([0.0, 0.0, 1.0], PI / 2.0);
    let turn: [f64; 3] =
        std::array::from_fn(|i| middle[i] - (0..3).map(|k| r[i][k] * middle[k]).sum::<f64>());
    let pose = joined(&[rigid_motion3(&a, r, turn), b.clone()]);
    let morph = Interpolator::new(&rest, &pose, &InterpolatorOptions::default()).unwrap();
    let n = a.num_vertices();
    for t in [0.25, 0.5, 0.75] {
        let frame = morph.at(t);
        assert!(max_distance(&frame[n..], b.positions()) < 1e-12, "t = {t}");
        assert!(non_rigidity(a.positions(), &frame[..n]) < 1e-9);
    }
}

#[test]
fn planar_parts_turn_with_the_largest() {
    // A strip and a small square beside it, turned together by 200 degrees.
    let body = strip(4.0, 1.0, 8, 2);
    let square = Mesh2::new(
        vec![[1.0, 1.1], [1.4, 1.1], [1.4, 1.5], [1.0, 1.5]],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap();
    let rest = joined(&[body, square]);
    let turned = rigid_motion(&rest, 200f64.to_radians(), [2.0, 0.5], [1.0, -3.0]);
    let morph = Interpolator::new(&rest, &turned, &InterpolatorOptions::default()).unwrap();
    for t in [0.25, 0.5, 0.75] {
        assert!(
            non_rigidity(rest.positions(), &morph.at(t)) < 1e-9,
            "t = {t}"
        );
    }
    assert!(max_distance(&morph.at(1.0), turned.positions()) < 1e-9);
}

#[test]
fn frames_at_the_keys_are_the_keys_to_the_bit() {
    let rest = head();
    let bent = rigid_motion3(&rest, rotation([0.0, 0.6, 0.8], 1.1), [0.3, 0.2, 0.1]);
    let third = rigid_motion3(&rest, rotation([1.0, 0.0, 0.0], 0.4), [0.0, 0.0, 1.0]);
    let keys = [rest.clone(), bent.clone(), third.clone()];
    let options = InterpolatorOptions::default();
    let sequence = Sequence::new(&keys, &options).unwrap();
    for (s, key) in keys.iter().enumerate() {
        assert_eq!(sequence.at(s as f64), key.positions(), "key {s}");
    }
    let blend = Blend::new(&rest, &[bent.clone(), third.clone()], &options).unwrap();
    assert_eq!(blend.at(&[0.0, 0.0]), rest.positions());
    assert_eq!(blend.at(&[1.0, 0.0]), bent.positions());
    assert_eq!(blend.at(&[0.0, 1.0]), third.positions());
}

/// A strip between two rails 3 apart, and a tiny triangle just outside the
/// first rail: the vertices nearest to it all lie on that rail.
fn rails() -> Mesh3 {
    let (mut p, mut t) = (Vec::new(), Vec::new());
    for k in 0..21 {
        p.push([0.1 * k as f64, 0.0, 0.0]);
        p.push([0.1 * k as f64, 3.0, 0.0]);
    }
    for k in 0..20u32 {
        let (a0, b0, a1, b1) = (2 * k, 2 * k + 1, 2 * k + 2, 2 * k + 3);
        t.push([a0, a1, b1]);
        t.push([a0, b1, b0]);
    }
    let b = p.len() as u32;
    p.extend([[1.0, -0.05, 0.0], [1.02, -0.05, 0.0], [1.01, -0.06, 0.01]]);
    t.push([b, b + 1, b + 2]);
    Mesh3::new(p, t).unwrap()
}

#[test]
fn a_part_whose_neighbours_lie_on_a_line_does_not_jump_at_the_keys() {
    // Nearest vertices on one line do not say how they turn about it: the
    // part keeps its straight path, and frames next to the keys are next
    // to the keys.
    let rest = rigid_motion3(&rails(), rotation([0.3, -0.7, 0.2], 0.9), [0.0; 3]);
    for (axis, angle) in [
        ([0.8, 0.4, 0.4], 0.8),
        ([0.0, 0.0, 1.0], 1.5),
        ([-0.4, 0.1, 0.9], 2.5),
    ] {
        let norm = (axis.iter().map(|x: &f64| x * x).sum::<f64>()).sqrt();
        let axis = axis.map(|x| x / norm);
        let turned = rigid_motion3(&rest, rotation(axis, angle), [0.0; 3]);
        let morph = Interpolator::new(&rest, &turned, &InterpolatorOptions::default()).unwrap();
        assert!(max_distance(&morph.at(1e-9), rest.positions()) < 1e-6);
        assert!(max_distance(&morph.at(1.0 - 1e-9), turned.positions()) < 1e-6);
    }
}
