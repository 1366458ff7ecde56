//! Invariants of as-rigid-as-possible interpolation over families of
//! procedural meshes. (The real 2D meshes of ../shared/data are in the
//! `shared_data` binary.)

use std::f64::consts::PI;

use crate::common::{max_distance, max_flipped};
use meshmorph::shapes::{curl, rigid_motion, strip};
use meshmorph::{Error, Interpolator, InterpolatorOptions, Mesh2, StretchMode};

/// A stretch that grows along the strip and a shear, applied to every vertex.
fn stretched(m: &Mesh2, sx: f64, shear: f64) -> Mesh2 {
    m.with_positions(
        m.positions()
            .iter()
            .map(|p| [p[0] * sx + shear * p[1], p[1] * (1.0 + 0.1 * p[0])])
            .collect(),
    )
    .unwrap()
}

/// Pairs (source, target) of different kinds: bends, spirals, rigid motions,
/// stretches, coarse and fine.
fn family() -> Vec<(&'static str, Mesh2, Mesh2)> {
    let s = strip(10.0, 0.5, 60, 3);
    let fine = strip(4.0, 1.0, 40, 10);
    vec![
        ("bend 90", s.clone(), curl(&s, 0.5 * PI)),
        ("spiral 540", s.clone(), curl(&s, 3.0 * PI)),
        (
            "rigid 170",
            s.clone(),
            rigid_motion(&s, 170f64.to_radians(), [1.0, 2.0], [3.0, -1.0]),
        ),
        ("stretch", fine.clone(), stretched(&fine, 1.5, 0.3)),
        (
            "stretch and curl",
            fine.clone(),
            curl(&stretched(&fine, 2.0, 0.0), PI),
        ),
    ]
}

#[test]
fn endpoints_are_reproduced() {
    for (name, source, target) in family() {
        for stretch in [
            StretchMode::Linear,
            StretchMode::Log,
            StretchMode::AreaBlend,
        ] {
            let opts = InterpolatorOptions::default().with_stretch(stretch);
            let m = Interpolator::new(&source, &target, &opts).unwrap();
            let tol = 1e-9
                * source
                    .bounding_box_diagonal()
                    .max(target.bounding_box_diagonal());
            let d0 = max_distance(&m.at(0.0), source.positions());
            let d1 = max_distance(&m.at(1.0), target.positions());
            assert!(d0 < tol && d1 < tol, "{name} {stretch:?}: {d0:e} {d1:e}");
        }
    }
}

#[test]
fn rigid_motions_stay_rigid() {
    let shapes = [strip(3.0, 1.0, 12, 4), curl(&strip(6.0, 0.5, 30, 2), 1.5)];
    for source in &shapes {
        for angle in [0.3, 2.0, 3.1, -2.5] {
            let target = rigid_motion(source, angle, [0.5, 0.2], [4.0, 1.0]);
            let m = Interpolator::new(source, &target, &InterpolatorOptions::default()).unwrap();
            let scale = source.bounding_box_diagonal();
            for k in 0..=10 {
                let t = k as f64 / 10.0;
                let x = m.at(t);
                for tri in source.triangles() {
                    for e in 0..3 {
                        let (a, b) = (tri[e] as usize, tri[(e + 1) % 3] as usize);
                        let p = source.positions();
                        let before = (p[a][0] - p[b][0]).hypot(p[a][1] - p[b][1]);
                        let after = (x[a][0] - x[b][0]).hypot(x[a][1] - x[b][1]);
                        assert!((before - after).abs() < 1e-9 * scale, "angle {angle} t {t}");
                    }
                }
                // The rotation grows linearly with t.
                let p = source.positions();
                let (u, v) = (
                    [p[1][0] - p[0][0], p[1][1] - p[0][1]],
                    [x[1][0] - x[0][0], x[1][1] - x[0][1]],
                );
                let turned = (u[0] * v[1] - u[1] * v[0]).atan2(u[0] * v[0] + u[1] * v[1]);
                assert!(
                    (turned - t * angle).abs() < 1e-9,
                    "angle {angle} t {t}: {turned}"
                );
            }
        }
    }
}

#[test]
fn a_strip_curled_by_540_degrees_does_not_flip_with_consistency() {
    let source = strip(10.0, 0.5, 100, 4);
    let target = curl(&source, 3.0 * PI);
    let on = Interpolator::new(&source, &target, &InterpolatorOptions::default()).unwrap();
    assert_eq!(max_flipped(&on, 101), 0);
    let spread = on
        .angles()
        .iter()
        .cloned()
        .fold(f64::NEG_INFINITY, f64::max)
        - on.angles().iter().cloned().fold(f64::INFINITY, f64::min);
    assert!((spread - 3.0 * PI).abs() < 0.1, "angles span {spread}");
    let off = Interpolator::new(
        &source,
        &target,
        &InterpolatorOptions::default().with_consistency(false),
    )
    .unwrap();
    assert!(
        max_flipped(&off, 101) > 0,
        "without consistency the strip should tear"
    );
}

#[test]
fn extra_turns_keep_endpoints_and_add_full_turns() {
    let source = strip(4.0, 1.0, 8, 2);
    let target = curl(&source, 1.0);
    let plain = Interpolator::new(&source, &target, &InterpolatorOptions::default()).unwrap();
    let turned = Interpolator::new(
        &source,
        &target,
        &InterpolatorOptions::default().with_turns(-1),
    )
    .unwrap();
    for (a, b) in plain.angles().iter().zip(turned.angles()) {
        assert!((a - 2.0 * PI - b).abs() < 1e-12);
    }
    let tol = 1e-9 * source.bounding_box_diagonal();
    assert!(max_distance(&turned.at(1.0), target.positions()) < tol);
    assert!(max_distance(&turned.at(0.5), &plain.at(0.5)) > 0.1);
    assert_eq!(max_flipped(&turned, 41), 0);
}

#[test]
fn log_stretch_never_collapses_when_extrapolating() {
    let source = strip(2.0, 1.0, 8, 4);
    let target = source
        .with_positions(
            source
                .positions()
                .iter()
                .map(|p| [p[0] * 0.3, p[1]])
                .collect(),
        )
        .unwrap();
    let log = Interpolator::new(
        &source,
        &target,
        &InterpolatorOptions::default().with_stretch(StretchMode::Log),
    )
    .unwrap();
    let linear = Interpolator::new(&source, &target, &InterpolatorOptions::default()).unwrap();
    for t in [-2.0, -0.5, 1.5, 3.0] {
        assert_eq!(log.count_flipped(&log.at(t)), 0, "t = {t}");
    }
    // Linear stretch reaches zero width at t = 1 / (1 - 0.3).
    assert!(linear.count_flipped(&linear.at(1.0 / 0.7)) > 0);
}

/// Renumbers vertices and triangles and rotates the corners of each triangle.
fn shuffled(m: &Mesh2, seed: u64) -> (Mesh2, Vec<usize>) {
    let n = m.num_vertices();
    let mut perm: Vec<usize> = (0..n).collect();
    let mut state = seed;
    let mut next = |k: usize| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) as usize % k
    };
    for i in (1..n).rev() {
        perm.swap(i, next(i + 1));
    }
    // perm[new] = old
    let mut new_of = vec![0u32; n];
    for (new, &old) in perm.iter().enumerate() {
        new_of[old] = new as u32;
    }
    let positions = perm.iter().map(|&old| m.positions()[old]).collect();
    let mut triangles: Vec<[u32; 3]> = m
        .triangles()
        .iter()
        .map(|t| {
            let t = t.map(|v| new_of[v as usize]);
            match next(3) {
                0 => t,
                1 => [t[1], t[2], t[0]],
                _ => [t[2], t[0], t[1]],
            }
        })
        .collect();
    for i in (1..triangles.len()).rev() {
        triangles.swap(i, next(i + 1));
    }
    (Mesh2::new(positions, triangles).unwrap(), perm)
}

#[test]
fn results_do_not_depend_on_numbering() {
    for (name, source, target) in family() {
        let m = Interpolator::new(&source, &target, &InterpolatorOptions::default()).unwrap();
        for seed in [1, 2] {
            let (s2, perm) = shuffled(&source, seed);
            let t2 = s2
                .with_positions(perm.iter().map(|&old| target.positions()[old]).collect())
                .unwrap();
            // The same corners in both: rebuild the target's triangles from the source's.
            let m2 = Interpolator::new(&s2, &t2, &InterpolatorOptions::default()).unwrap();
            for t in [0.25, 0.5, 0.8] {
                let (a, b) = (m.at(t), m2.at(t));
                let back: Vec<[f64; 2]> = (0..a.len())
                    .map(|old| b[perm.iter().position(|&o| o == old).unwrap()])
                    .collect();
                let d = max_distance(&a, &back);
                assert!(
                    d < 1e-9 * source.bounding_box_diagonal(),
                    "{name} seed {seed} t {t}: {d:e}"
                );
            }
        }
    }
}

/// Puts two meshes side by side in one (two components).
fn union(a: &Mesh2, b: &Mesh2) -> Mesh2 {
    let off = a.num_vertices() as u32;
    let mut p = a.positions().to_vec();
    p.extend_from_slice(b.positions());
    let mut t = a.triangles().to_vec();
    t.extend(b.triangles().iter().map(|t| t.map(|v| v + off)));
    Mesh2::new(p, t).unwrap()
}

#[test]
fn components_move_independently() {
    let a = strip(3.0, 0.2, 15, 2);
    let b = rigid_motion(&strip(2.0, 1.0, 6, 3), 0.0, [0.0, 0.0], [0.0, 5.0]);
    let (a1, b1) = (
        curl(&a, 2.5 * PI),
        rigid_motion(&stretched(&b, 1.3, 0.2), -2.8, [1.0, 5.5], [7.0, 0.0]),
    );
    let whole = Interpolator::new(
        &union(&a, &b),
        &union(&a1, &b1),
        &InterpolatorOptions::default(),
    )
    .unwrap();
    let ma = Interpolator::new(&a, &a1, &InterpolatorOptions::default()).unwrap();
    let mb = Interpolator::new(&b, &b1, &InterpolatorOptions::default()).unwrap();
    for t in [0.0, 0.3, 0.7, 1.0, 1.4] {
        let w = whole.at(t);
        let (wa, wb) = w.split_at(a.num_vertices());
        assert!(max_distance(wa, &ma.at(t)) < 1e-9);
        assert!(max_distance(wb, &mb.at(t)) < 1e-9);
    }
}

#[test]
fn parallel_frames_equal_single_frames() {
    let source = strip(10.0, 0.5, 40, 2);
    let target = curl(&source, 2.0 * PI);
    let m = Interpolator::new(&source, &target, &InterpolatorOptions::default()).unwrap();
    let times: Vec<f64> = (0..17).map(|k| k as f64 / 16.0).collect();
    for (t, frame) in times.iter().zip(m.frames(&times)) {
        assert_eq!(frame, m.at(*t));
    }
}

#[test]
fn bad_input_gets_clear_errors() {
    let s = strip(2.0, 1.0, 4, 2);
    let opts = InterpolatorOptions::default();
    // Different vertex counts.
    let other = strip(2.0, 1.0, 5, 2);
    let e = Interpolator::new(&s, &other, &opts).unwrap_err();
    assert!(
        matches!(e, Error::Mismatch(_)) && e.to_string().contains("vertices"),
        "{e}"
    );
    // Same vertex count, different triangles.
    let mut tris = s.triangles().to_vec();
    tris[3] = [tris[3][0], tris[3][2], tris[3][1]];
    let e = Interpolator::new(
        &s,
        &Mesh2::new(s.positions().to_vec(), tris).unwrap(),
        &opts,
    )
    .unwrap_err();
    assert!(e.to_string().contains("triangle 3"), "{e}");
    // Zero-area source triangles: every vertex on one line.
    let flat = s
        .with_positions(s.positions().iter().map(|q| [q[0], 0.0]).collect())
        .unwrap();
    let e = Interpolator::new(&flat, &s, &opts).unwrap_err();
    assert!(
        matches!(e, Error::DegenerateTriangles { count: 16, .. }),
        "{e}"
    );
    assert!(
        e.to_string().contains("triangles 0, 1, 2, 3, 4, ..."),
        "{e}"
    );
    // Reversed triangles: mirror the target.
    let mirrored = s
        .with_positions(s.positions().iter().map(|q| [-q[0], q[1]]).collect())
        .unwrap();
    let e = Interpolator::new(&s, &mirrored, &opts).unwrap_err();
    assert!(
        matches!(e, Error::FlippedTriangles { count: 16, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("allow_flips"), "{e}");
    assert!(!e.to_string().contains("--"), "no command-line flag: {e}");
    let m = Interpolator::new(&s, &mirrored, &opts.clone().with_allow_flips(true)).unwrap();
    assert!(max_distance(&m.at(1.0), mirrored.positions()) < 1e-9);
    for mode in [StretchMode::Linear, StretchMode::Log] {
        let m = Interpolator::new(
            &s,
            &mirrored,
            &opts.clone().with_allow_flips(true).with_stretch(mode),
        )
        .unwrap();
        assert!(m
            .at(0.5)
            .iter()
            .all(|p| p[0].is_finite() && p[1].is_finite()));
    }
    // NaN and empty meshes are refused when the mesh is built.
    assert!(Mesh2::new(
        vec![[0.0, f64::NAN], [1.0, 0.0], [0.0, 1.0]],
        vec![[0, 1, 2]]
    )
    .is_err());
    assert!(Mesh2::new(vec![], vec![]).is_err());
}

#[test]
fn unused_vertices_move_on_straight_lines() {
    let s = strip(2.0, 1.0, 2, 1);
    let mut p = s.positions().to_vec();
    p.push([5.0, 5.0]);
    let last = p.len() - 1;
    let src = Mesh2::new(p.clone(), s.triangles().to_vec()).unwrap();
    p[last] = [7.0, 1.0];
    let tgt = src.with_positions(p).unwrap();
    let m = Interpolator::new(&src, &tgt, &InterpolatorOptions::default()).unwrap();
    assert_eq!(m.at(0.5)[last], [6.0, 3.0]);
}

/// Two strips that share one vertex only (a bow-tie): angles cannot cross
/// from one to the other, so each needs its own seed.
#[test]
fn parts_joined_at_a_single_vertex_are_each_made_consistent() {
    let s = strip(10.0, 0.5, 100, 4);
    let curled = curl(&s, 3.0 * PI);
    let half_turn = |m: &Mesh2, to: [f64; 2]| {
        let p0 = m.positions()[0];
        rigid_motion(m, PI, p0, [to[0] - p0[0], to[1] - p0[1]])
    };
    // Part B is part A turned by half a turn about A's vertex 0, in both shapes.
    let join = |a: &Mesh2, b: &Mesh2| {
        let n = a.num_vertices() as u32;
        let mut p = a.positions().to_vec();
        p.extend_from_slice(&b.positions()[1..]);
        let mut t = a.triangles().to_vec();
        t.extend(
            b.triangles()
                .iter()
                .map(|t| t.map(|v| if v == 0 { 0 } else { v + n - 1 })),
        );
        Mesh2::new(p, t).unwrap()
    };
    let source = join(&s, &half_turn(&s, s.positions()[0]));
    let target = join(&curled, &half_turn(&curled, curled.positions()[0]));
    let m = Interpolator::new(&source, &target, &InterpolatorOptions::default()).unwrap();
    assert_eq!(max_flipped(&m, 101), 0);
}

/// A planar keyframe sequence and a planar blend give what the same keys
/// give embedded in space with z = 0 (one machinery for both dimensions),
/// and two planar keys as a sequence give the interpolation exactly.
#[test]
fn planar_sequences_and_blends_agree_with_the_same_keys_in_space() {
    use meshmorph::{Blend, Sequence};
    let lift = |m: &Mesh2| m.to_3d();
    let flat = |p: &[[f64; 3]]| -> Vec<[f64; 2]> { p.iter().map(|q| [q[0], q[1]]).collect() };
    for (name, source, target) in family() {
        let third = rigid_motion(&curl(&source, 1.2), 2.5, [1.0, 0.0], [0.5, 2.0]);
        let keys = [source.clone(), target.clone(), third.clone()];
        let keys3: Vec<_> = keys.iter().map(lift).collect();
        let tol = 1e-9 * source.bounding_box_diagonal();
        for stretch in [StretchMode::Linear, StretchMode::Log] {
            for consistency in [true, false] {
                let o = InterpolatorOptions::default()
                    .with_stretch(stretch)
                    .with_consistency(consistency)
                    .with_allow_flips(true);
                let plane = Sequence::new(&keys, &o).unwrap();
                let space = Sequence::new(&keys3, &o).unwrap();
                for s in [-0.3, 0.0, 0.25, 0.5, 1.0, 1.4, 2.0, 2.5] {
                    let d = max_distance(&plane.at(s), &flat(&space.at(s)));
                    assert!(d < tol, "{name} {stretch:?} {consistency} s = {s}: {d}");
                }
                let two = Interpolator::new(&source, &target, &o).unwrap();
                let pair = Sequence::new(&keys[..2], &o).unwrap();
                for t in [0.0, 0.3, 0.5, 1.0, 1.7] {
                    assert_eq!(two.at(t), pair.at(t), "{name} {stretch:?} t = {t}");
                }
            }
        }
        let o = InterpolatorOptions::default().with_allow_flips(true);
        let plane = Blend::new(&source, &keys[1..], &o).unwrap();
        let space = Blend::new(&keys3[0], &keys3[1..], &o).unwrap();
        for w in [[0.5, 0.0], [1.0, 0.0], [0.3, 0.6], [-0.4, 1.3]] {
            let d = max_distance(&plane.at(&w), &flat(&space.at(&w)));
            assert!(d < tol, "{name} blend {w:?}: {d}");
        }
        let d = max_distance(&plane.at(&[0.0, 1.0]), third.positions());
        assert!(d < tol, "{name} blend reproduces a shape: {d}");
    }
}

/// Where no triangle is stretched one way and squeezed the other (a rigid
/// turn), the area-kept blend is the linear blend; elsewhere its frames
/// are never larger than the linear blend's, and near the straight blend
/// of the keys' areas.
#[test]
fn area_blend_is_the_linear_blend_where_nothing_swells() {
    let area = |m: &Mesh2, x: &[[f64; 2]]| -> f64 {
        m.triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| x[v as usize]);
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
            })
            .sum()
    };
    for (name, source, target) in family() {
        let linear = Interpolator::new(&source, &target, &InterpolatorOptions::default()).unwrap();
        let kept = Interpolator::new(
            &source,
            &target,
            &InterpolatorOptions::default().with_stretch(StretchMode::AreaBlend),
        )
        .unwrap();
        let ends = [
            area(&source, source.positions()),
            area(&source, target.positions()),
        ];
        let tol = 1e-9 * source.bounding_box_diagonal();
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            let (x, y) = (linear.at(t), kept.at(t));
            if name == "rigid 170" {
                let d = max_distance(&x, &y);
                assert!(d < tol, "{name}, t = {t}: {d:e} from the linear blend");
            } else {
                // Only ever thinner than the linear blend's triangles, so
                // never larger than its frame; near the blend of the ends.
                let blend = (1.0 - t) * ends[0] + t * ends[1];
                let (by_linear, by_kept) = (area(&source, &x), area(&source, &y));
                assert!(
                    by_kept <= by_linear * (1.0 + 1e-9),
                    "{name}, t = {t}: area {by_kept} above the linear blend's {by_linear}"
                );
                let off = (by_kept / blend - 1.0).abs();
                assert!(off < 0.05, "{name}, t = {t}: area {off:.3} off the blend");
            }
        }
    }
}
