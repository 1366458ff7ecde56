//! As-rigid-as-possible interpolation, keyframe sequences and blends of
//! surfaces in space: invariants over procedural meshes. (Sumner's horse
//! poses from ../shared/data are in the `shared_data` binary.)

use std::f64::consts::PI;

use crate::common::{dist, edge_lengths, max_distance};
use meshmorph::shapes::{bend, rigid_motion3, rotation_matrix, tube, twist};
use meshmorph::{Blend, Error, InterpolatorOptions, Mesh3, Sequence, StretchMode};

type P = [f64; 3];

/// The largest distance between `a` and `b` after the rigid motion that best
/// aligns `a` onto `b` (the rotation of the best similarity: Horn's, the
/// same as Kabsch's).
fn rigid_distance(a: &[P], b: &[P]) -> f64 {
    let n = a.len() as f64;
    let ca: P = std::array::from_fn(|k| a.iter().map(|p| p[k]).sum::<f64>() / n);
    let cb: P = std::array::from_fn(|k| b.iter().map(|p| p[k]).sum::<f64>() / n);
    let r = meshmorph::Similarity::fit(a, b).unwrap().rotation;
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            let x: P = std::array::from_fn(|i| {
                (0..3).map(|k| r[i][k] * (p[k] - ca[k])).sum::<f64>() + cb[i]
            });
            dist(x, *q)
        })
        .fold(0.0, f64::max)
}

fn opts() -> InterpolatorOptions {
    InterpolatorOptions::default()
}

/// Pairs of different kinds: bends, twists, a rigid motion, a stretch.
fn family() -> Vec<(&'static str, Mesh3, Mesh3)> {
    let t = tube(4.0, 0.3, 21, 10);
    let stretched = t
        .with_positions(
            t.positions()
                .iter()
                .map(|p| [1.3 * p[0], p[1] * (1.0 + 0.1 * p[0]), p[2]])
                .collect(),
        )
        .unwrap();
    vec![
        ("bend 90", t.clone(), bend(&t, 4.0, 0.5 * PI)),
        ("bend 540", t.clone(), bend(&t, 4.0, 3.0 * PI)),
        ("twist 300", t.clone(), twist(&t, 4.0, 300f64.to_radians())),
        (
            "rigid 200",
            t.clone(),
            rigid_motion3(
                &t,
                rotation_matrix([0.0, 200f64.to_radians(), 0.0]),
                [1.0, -2.0, 3.0],
            ),
        ),
        ("stretch and bend", t.clone(), bend(&stretched, 5.2, 2.0)),
    ]
}

#[test]
fn keys_are_reproduced() {
    for (name, a, b) in family() {
        for stretch in [StretchMode::Linear, StretchMode::Log] {
            let o = opts().with_stretch(stretch);
            let c = twist(&b, 4.0, 0.7);
            let seq = Sequence::<3>::new(&[a.clone(), b.clone(), c.clone()], &o).unwrap();
            let tol = 1e-9 * a.bounding_box_diagonal().max(b.bounding_box_diagonal());
            for (s, key) in [(0.0, &a), (1.0, &b), (2.0, &c)] {
                let d = max_distance(&seq.at(s), key.positions());
                assert!(d < tol, "{name} {stretch:?} key {s}: {d}");
            }
        }
    }
}

#[test]
fn rigid_motions_give_rigid_frames() {
    let t = tube(4.0, 0.3, 21, 10);
    let rest = edge_lengths(&t, t.positions());
    for (axis, angle) in [
        ([0.0, 0.0, 1.0], 270f64),
        ([1.0, 0.0, 0.0], 270.0),
        ([0.6, 0.0, 0.8], 179.0),
        ([0.0, 1.0, 0.0], 90.0),
    ] {
        let w: P = axis.map(|x| x * angle.to_radians());
        let moved = rigid_motion3(&t, rotation_matrix(w), [2.0, 1.0, -1.0]);
        let seq = Sequence::<3>::new(&[t.clone(), moved], &opts()).unwrap();
        for s in [0.25, 0.5, 0.75, 1.5] {
            let f = seq.at(s);
            let worst = edge_lengths(&t, &f)
                .iter()
                .zip(&rest)
                .map(|(x, y)| (x / y - 1.0).abs())
                .fold(0.0, f64::max);
            assert!(worst < 1e-9, "{axis:?} {angle} at {s}: {worst}");
        }
    }
}

#[test]
fn a_tube_bent_through_540_degrees_is_bent_through_270_halfway() {
    let t = tube(10.0, 0.1, 121, 8);
    let target = bend(&t, 10.0, 3.0 * PI);
    let expected = bend(&t, 10.0, 1.5 * PI);
    let diag = t.bounding_box_diagonal();
    let with = Sequence::<3>::new(&[t.clone(), target.clone()], &opts()).unwrap();
    let d_with = rigid_distance(&with.at(0.5), expected.positions()) / diag;
    let without =
        Sequence::<3>::new(&[t.clone(), target], &opts().with_consistency(false)).unwrap();
    let d_without = rigid_distance(&without.at(0.5), expected.positions()) / diag;
    println!("bend 540, halfway against bend 270: {d_with:.2e} with consistency, {d_without:.2e} without");
    assert!(d_with < 0.005, "{d_with}");
    assert!(d_without > 0.05, "{d_without}");
}

#[test]
fn a_tube_twisted_by_540_degrees_is_twisted_by_270_halfway() {
    let t = tube(10.0, 0.25, 101, 12);
    let target = twist(&t, 10.0, 3.0 * PI);
    let expected = twist(&t, 10.0, 1.5 * PI);
    let diag = t.bounding_box_diagonal();
    let with = Sequence::<3>::new(&[t.clone(), target.clone()], &opts()).unwrap();
    let d_with = rigid_distance(&with.at(0.5), expected.positions()) / diag;
    let without =
        Sequence::<3>::new(&[t.clone(), target], &opts().with_consistency(false)).unwrap();
    let d_without = rigid_distance(&without.at(0.5), expected.positions()) / diag;
    println!("twist 540, halfway against twist 270: {d_with:.2e} with consistency, {d_without:.2e} without; whole turns {:?} of {}", with.triangles_with_whole_turns(), t.num_triangles());
    assert!(d_with < 0.02, "{d_with}");
}

#[test]
fn results_do_not_depend_on_numbering() {
    let t = tube(4.0, 0.3, 21, 10);
    let b = twist(&bend(&t, 4.0, 3.0 * PI), 4.0, 1.0);
    let n = t.num_vertices();
    // Vertices in a scrambled order, triangles reversed, corners rotated.
    let perm: Vec<usize> = (0..n).map(|i| (i * 37 + 11) % n).collect();
    assert_eq!(
        {
            let mut p = perm.clone();
            p.sort();
            p.dedup();
            p.len()
        },
        n
    );
    let mut inverse = vec![0u32; n];
    for (new, &old) in perm.iter().enumerate() {
        inverse[old] = new as u32;
    }
    let renumber = |m: &Mesh3| {
        let pos: Vec<P> = perm.iter().map(|&old| m.positions()[old]).collect();
        let tris: Vec<[u32; 3]> = m
            .triangles()
            .iter()
            .rev()
            .enumerate()
            .map(|(k, t)| {
                let t = t.map(|v| inverse[v as usize]);
                match k % 3 {
                    0 => t,
                    1 => [t[1], t[2], t[0]],
                    _ => [t[2], t[0], t[1]],
                }
            })
            .collect();
        Mesh3::new(pos, tris).unwrap()
    };
    let a = Sequence::<3>::new(&[t.clone(), b.clone()], &opts()).unwrap();
    let r = Sequence::<3>::new(&[renumber(&t), renumber(&b)], &opts()).unwrap();
    let tol = 1e-9 * t.bounding_box_diagonal();
    for s in [0.3, 0.5, 0.8] {
        let (fa, fr) = (a.at(s), r.at(s));
        let back: Vec<P> = (0..n).map(|old| fr[inverse[old] as usize]).collect();
        let d = max_distance(&fa, &back);
        assert!(d < tol, "at {s}: {d}");
    }
}

#[test]
fn a_middle_key_on_the_way_reproduces_the_two_key_interpolation() {
    let t = tube(6.0, 0.2, 61, 8);
    for (name, end) in [
        ("bend 540", bend(&t, 6.0, 3.0 * PI)),
        ("twist 400", twist(&t, 6.0, 400f64.to_radians())),
        ("bend and twist", twist(&bend(&t, 6.0, 2.5), 6.0, 2.0)),
    ] {
        let two = Sequence::<3>::new(&[t.clone(), end.clone()], &opts()).unwrap();
        let middle = t.with_positions(two.at(0.5)).unwrap();
        let three = Sequence::<3>::new(&[t.clone(), middle, end.clone()], &opts()).unwrap();
        let diag = t.bounding_box_diagonal();
        for (s, u) in [(0.5, 0.25), (1.0, 0.5), (1.5, 0.75), (2.0, 1.0)] {
            let d = rigid_distance(&three.at(s), &two.at(u)) / diag;
            println!("{name}: sequence at {s} against two keys at {u}: {d:.2e}");
            assert!(d < 2e-3, "{name} at {s}: {d}");
        }
    }
}

#[test]
fn a_sequence_keeps_turning_across_keys() {
    // Keys bent by 0, 150, 300 and 450 degrees: each step is under half a
    // turn, the last key is principal 90 degrees the other way; the frame at
    // 2.5 is the 375-degree bend.
    let t = tube(10.0, 0.1, 121, 8);
    let keys: Vec<Mesh3> = [0.0, 150.0, 300.0, 450.0f64]
        .iter()
        .map(|a| bend(&t, 10.0, a.to_radians()))
        .collect();
    let seq = Sequence::<3>::new(&keys, &opts()).unwrap();
    let expected = bend(&t, 10.0, 375f64.to_radians());
    let d = rigid_distance(&seq.at(2.5), expected.positions()) / t.bounding_box_diagonal();
    assert!(d < 0.005, "{d}");
}

#[test]
fn blends_reproduce_their_shapes_and_extrapolate() {
    let t = tube(4.0, 0.3, 21, 10);
    let a = bend(&t, 4.0, 3.0 * PI);
    let b = twist(&t, 4.0, 2.0);
    let blend = Blend::<3>::new(&t, &[a.clone(), b.clone()], &opts()).unwrap();
    let tol = 1e-9 * a.bounding_box_diagonal();
    assert!(max_distance(&blend.at(&[0.0, 0.0]), t.positions()) < tol);
    assert!(max_distance(&blend.at(&[1.0, 0.0]), a.positions()) < tol);
    assert!(max_distance(&blend.at(&[0.0, 1.0]), b.positions()) < tol);
    // One shape with weight t is the interpolation with S^t.
    let seq = Sequence::<3>::new(
        &[t.clone(), a.clone()],
        &opts().with_stretch(StretchMode::Log),
    )
    .unwrap();
    assert!(max_distance(&blend.at(&[0.4, 0.0]), &seq.at(0.4)) < tol);
    // Extrapolation and negative weights: nothing collapses.
    for w in [[1.5, 0.5], [-0.5, 1.0], [2.0, -1.0], [-1.0, -1.0]] {
        let f = blend.at(&w);
        let m = t.with_positions(f).unwrap();
        let smallest = m.triangle_areas().into_iter().fold(f64::INFINITY, f64::min);
        println!(
            "blend {w:?}: smallest triangle area {smallest:.2e}, turned over {}",
            blend.count_turned_over(m.positions())
        );
        assert!(smallest > 1e-4, "{w:?}: {smallest}");
    }
}

#[test]
fn bad_input_is_named() {
    let t = tube(4.0, 0.3, 11, 8);
    let b = bend(&t, 4.0, 1.0);
    // Different triangles.
    let mut tris = t.triangles().to_vec();
    tris.swap(5, 6);
    let other = Mesh3::new(b.positions().to_vec(), tris).unwrap();
    let e = Sequence::<3>::new(&[t.clone(), b.clone(), other], &opts()).unwrap_err();
    assert!(
        matches!(e, Error::TriangleMismatch { triangle: 5, .. }),
        "{e}"
    );
    assert!(
        e.to_string().contains("key 2") && e.to_string().contains("triangle 5"),
        "{e}"
    );
    // A sheet with one vertex pushed past its neighbour: the triangles
    // between them are folded back through their neighbours.
    let sheet = meshmorph::shapes::strip(4.0, 1.0, 8, 4).to_3d();
    let mut p = sheet.positions().to_vec();
    p[2 * 9 + 4][0] += 0.8;
    let folded = sheet.with_positions(p).unwrap();
    let e = Sequence::<3>::new(&[sheet.clone(), folded.clone()], &opts()).unwrap_err();
    assert!(matches!(e, Error::ReflectedTriangles { .. }), "{e}");
    assert!(e.to_string().contains("key 1"), "{e}");
    assert!(Sequence::<3>::new(&[sheet.clone(), folded], &opts().with_allow_flips(true)).is_ok());
    // Degenerate first key.
    let mut p = t.positions().to_vec();
    p[1] = p[0];
    p[2] = p[0];
    let flat = t.with_positions(p).unwrap();
    let e = Sequence::<3>::new(&[flat, b.clone()], &opts()).unwrap_err();
    assert!(matches!(e, Error::DegenerateTriangles { .. }), "{e}");
    // Whole extra turns have no axis in space; one key is not a sequence.
    assert!(matches!(
        Sequence::<3>::new(&[t.clone(), b.clone()], &opts().with_turns(1)),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        Sequence::<3>::new(std::slice::from_ref(&t), &opts()),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        Blend::<3>::new(&t, &[], &opts()),
        Err(Error::InvalidArgument(_))
    ));
    // A later key or a blend shape with coordinates whose products overflow
    // (found by fuzzing: its frames were infinite) is named as overflow.
    let mut p = b.positions().to_vec();
    p[7][0] = -1.7976931340154918e308;
    let huge = b.with_positions(p).unwrap();
    for (e, name) in [
        (
            Sequence::<3>::new(&[t.clone(), huge.clone()], &opts().with_allow_flips(true))
                .unwrap_err(),
            "key 1",
        ),
        (
            Blend::<3>::new(&t, &[b.clone(), huge], &opts().with_allow_flips(true)).unwrap_err(),
            "blend shape 2",
        ),
    ] {
        assert!(
            matches!(e, Error::InvalidTriangle { triangle: 12, .. }),
            "{e}"
        );
        assert!(
            e.to_string().contains(name) && e.to_string().contains("overflow"),
            "{e}"
        );
    }
    // Coordinates whose triangles' areas fit but whose maps from the first
    // key square past the range (found by fuzzing: NaN frames).
    let mut p = b.positions().to_vec();
    p[7][2] = -1e251;
    let far = b.with_positions(p).unwrap();
    for (e, name) in [
        (
            Sequence::<3>::new(&[t.clone(), far.clone()], &opts().with_allow_flips(true))
                .unwrap_err(),
            "key 1",
        ),
        (
            Blend::<3>::new(&t, &[far], &opts().with_allow_flips(true)).unwrap_err(),
            "blend shape 1",
        ),
    ] {
        assert!(matches!(e, Error::InvalidTriangle { .. }), "{e}");
        assert!(
            e.to_string().contains(name) && e.to_string().contains("overflows"),
            "{e}"
        );
    }
}

/// Two keys in space through `Interpolator<3>` are the two-key sequence.
#[test]
fn the_interpolator_in_space_is_the_two_key_sequence() {
    use meshmorph::Interpolator;
    let t = tube(4.0, 0.3, 21, 10);
    let b = bend(&t, 4.0, 3.0 * PI);
    let two = Interpolator::<3>::new(&t, &b, &opts()).unwrap();
    let seq = Sequence::<3>::new(&[t.clone(), b.clone()], &opts()).unwrap();
    for s in [0.0, 0.3, 0.5, 1.0, 1.2] {
        assert_eq!(two.at(s), seq.at(s), "s = {s}");
    }
    assert_eq!(two.count_flipped(&two.at(0.5)), 0);
    // Whole turns where the tube bends beyond half a turn.
    assert!(two
        .rotations()
        .iter()
        .any(|r| r.turns.iter().any(|&c| c != 0.0)));
}

/// The shortest edge of the surface `m` with positions `p`.
fn shortest_edge(m: &Mesh3, p: &[P]) -> f64 {
    edge_lengths(m, p).into_iter().fold(f64::INFINITY, f64::min)
}

#[test]
fn a_tail_bent_then_twisted_keeps_its_shape_between_later_keys() {
    // Keys of a tail: straight, bent 90 degrees, bent further, then twisted
    // about its own axis under the same bend. The rotations measured from
    // key 0 turn about different axes, whose vectors do not subtract: the
    // last segment must not tear, and must turn as the two-key
    // interpolation from key 2 to key 3 does (with as many whole turns
    // where the twist goes beyond half a turn).
    let (length, t) = (4.0, tube(4.0, 0.3, 41, 16));
    let diag = t.bounding_box_diagonal();
    for (bent, twisted) in [(200.0f64, 90.0f64), (200.0, 270.0), (300.0, 200.0)] {
        let name = format!("bent {bent}, twisted {twisted}");
        let keys = vec![
            t.clone(),
            bend(&t, length, 90f64.to_radians()),
            bend(&t, length, bent.to_radians()),
            bend(
                &twist(&t, length, twisted.to_radians()),
                length,
                bent.to_radians(),
            ),
        ];
        let seq = Sequence::<3>::new(&keys, &opts()).unwrap();
        for (j, key) in keys.iter().enumerate() {
            let d = max_distance(&seq.at(j as f64), key.positions());
            assert!(d < 1e-9 * diag, "{name}, key {j}: {d}");
        }
        let shortest_key = keys
            .iter()
            .map(|k| shortest_edge(&t, k.positions()))
            .fold(f64::INFINITY, f64::min);
        let mut worst = f64::INFINITY;
        for i in 0..=60 {
            let s = 3.0 * i as f64 / 60.0;
            let f = seq.at(s);
            assert_eq!(seq.count_turned_over(&f), 0, "{name}, s = {s}");
            let e = shortest_edge(&t, &f);
            worst = worst.min(e);
            assert!(
                e > 0.5 * shortest_key,
                "{name}, s = {s}: {e} against {shortest_key}"
            );
        }
        // The last segment alone, as a two-key interpolation from key 2:
        // nearly the same frames (not exactly: the sequence measures
        // stretches from key 0 and fits on key 0's triangles), the same
        // whole turns.
        let alone = Sequence::<3>::new(&[keys[2].clone(), keys[3].clone()], &opts()).unwrap();
        let mut apart = 0.0f64;
        for u in [0.25, 0.5, 0.75] {
            apart = apart.max(rigid_distance(&seq.at(2.0 + u), &alone.at(u)) / diag);
        }
        println!(
            "tail {name}: shortest edge of any frame {worst:.4}, of the keys {shortest_key:.4}; last segment against the two keys alone {apart:.2e}; whole turns {:?}",
            seq.triangles_with_whole_turns()
        );
        assert!(apart < 1e-2, "{name}: {apart}");
        assert_eq!(
            seq.triangles_with_whole_turns()[2],
            alone.triangles_with_whole_turns()[0],
            "{name}"
        );
    }
}

#[test]
fn a_rigid_turn_through_keys_keeps_turning_and_stays_rigid() {
    // Keys turned about one axis by 0, 100, 200 and 300 degrees (beyond
    // half a turn from key 0 from key 2 on): every frame is rigid, the
    // rotation of the frame at s is 100 s degrees, on the way forward.
    let t = tube(4.0, 0.3, 21, 10);
    let axis = [0.48, 0.6, 0.64];
    let turned = |degrees: f64| {
        let a = degrees.to_radians();
        rigid_motion3(&t, rotation_matrix(axis.map(|x| x * a)), [0.5, -1.0, 2.0])
    };
    let keys: Vec<Mesh3> = [0.0, 100.0, 200.0, 300.0].map(turned).to_vec();
    let seq = Sequence::<3>::new(&keys, &opts()).unwrap();
    let diag = t.bounding_box_diagonal();
    for i in 0..=30 {
        let s = 3.0 * i as f64 / 30.0;
        let f = seq.at(s);
        // Rigid: the pose turned by 100 s degrees, up to a translation
        // (the centroid runs on straight lines between the keys').
        let expected = turned(100.0 * s);
        let centre = |p: &[P]| -> P {
            std::array::from_fn(|k| p.iter().map(|x| x[k]).sum::<f64>() / p.len() as f64)
        };
        let (cf, ce) = (centre(&f), centre(expected.positions()));
        let d = f
            .iter()
            .zip(expected.positions())
            .map(|(a, b)| {
                dist(
                    std::array::from_fn(|k| a[k] - cf[k]),
                    std::array::from_fn(|k| b[k] - ce[k]),
                )
            })
            .fold(0.0, f64::max)
            / diag;
        assert!(d < 1e-9, "s = {s}: {d}");
    }
    // Keys 0, 100 and 300 degrees are the same meshes as 0, 100 and -60:
    // nothing tells a turn of 200 degrees from one of -160 between the
    // last two, and the segment takes the shortest way, as two keys do.
    let short = Sequence::<3>::new(
        &[keys[0].clone(), keys[1].clone(), keys[3].clone()],
        &opts(),
    )
    .unwrap();
    let d = rigid_distance(&short.at(1.5), turned(20.0).positions()) / diag;
    assert!(d < 1e-9, "{d}");
    // Turned by 170 degrees about x, then by 170 more about y: from key 0
    // the rotation vectors of the keys differ by more than half a turn
    // (they do not subtract), but between the two later keys every
    // triangle turns by 170 degrees, and the segment takes that way.
    let composed = |a: f64, b: f64| {
        let m = |w: [f64; 3]| rotation_matrix(w.map(|x| x * PI / 180.0));
        let (x, y) = (m([a, 0.0, 0.0]), m([0.0, b, 0.0]));
        let r: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..3).map(|k| y[i][k] * x[k][j]).sum())
        });
        rigid_motion3(&t, r, [0.0; 3])
    };
    let keys = [t.clone(), composed(170.0, 0.0), composed(170.0, 170.0)];
    let seq = Sequence::<3>::new(&keys, &opts()).unwrap();
    assert_eq!(seq.triangles_with_whole_turns(), [0, 0]);
    for u in [0.25, 0.5, 0.75] {
        let d = rigid_distance(&seq.at(1.0 + u), composed(170.0, 170.0 * u).positions()) / diag;
        assert!(d < 1e-9, "at {u}: {d}");
    }
}

#[test]
fn a_tube_bent_further_at_every_key_bends_monotonically() {
    // Keys bent by 0, 150, 300 and 450 degrees: the direction of the tube's
    // end turns forward all the way, through 450 degrees, and no frame
    // turns a triangle over.
    let (length, t) = (10.0, tube(10.0, 0.1, 121, 8));
    let keys: Vec<Mesh3> = [0.0, 150.0, 300.0, 450.0f64]
        .iter()
        .map(|a| bend(&t, length, a.to_radians()))
        .collect();
    let seq = Sequence::<3>::new(&keys, &opts()).unwrap();
    // The end's direction: from the centre of the last ring but one to the
    // centre of the end cap (the last vertex).
    let n = t.num_vertices();
    let (rings, segments) = (121, 8);
    let direction = |p: &[P]| {
        let ring = (rings - 2) * segments;
        let c: P = std::array::from_fn(|k| {
            (0..segments).map(|s| p[ring + s][k]).sum::<f64>() / segments as f64
        });
        let end = p[n - 1];
        (end[1] - c[1]).atan2(end[0] - c[0])
    };
    let (mut previous, mut unwrapped) = (0.0, 0.0);
    for i in 1..=90 {
        let s = 3.0 * i as f64 / 90.0;
        let f = seq.at(s);
        assert_eq!(seq.count_turned_over(&f), 0, "s = {s}");
        let a = direction(&f);
        let step = (a - previous + PI).rem_euclid(2.0 * PI) - PI;
        assert!(step > 0.0 && step < 0.5, "s = {s}: the end turns by {step}");
        unwrapped += step;
        previous = a;
    }
    assert!(
        (unwrapped - 450f64.to_radians()).abs() < 0.05,
        "{unwrapped}"
    );
}

#[test]
fn a_whole_turn_between_two_later_keys_is_made() {
    // Keys bent (or twisted) by 0, 180 and 540 degrees: between the last
    // two the end turns by a whole turn, where its rotation relative to the
    // previous key is the identity with a stray axis; halfway it is the
    // 360-degree bend (twist), within 0.5 % (2 %: a twist shears) of the
    // diagonal.
    let (length, t) = (6.0, tube(6.0, 0.2, 61, 8));
    type Deform = fn(&Mesh3, f64, f64) -> Mesh3;
    for (name, deform, tolerance) in [("bend", bend as Deform, 0.005), ("twist", twist, 0.02)] {
        let keys: Vec<Mesh3> = [0.0, 180.0, 540.0f64]
            .iter()
            .map(|a| deform(&t, length, a.to_radians()))
            .collect();
        let seq = Sequence::<3>::new(&keys, &opts()).unwrap();
        let diag = t.bounding_box_diagonal();
        let whole = deform(&t, length, 2.0 * PI);
        let f = seq.at(1.5);
        let d = rigid_distance(&f, whole.positions()) / diag;
        println!(
            "{name} 0, 180, 540: at 1.5 against 360: {d:.2e}; whole turns {:?}",
            seq.triangles_with_whole_turns()
        );
        assert!(d < tolerance, "{name}: {d}");
        for i in 0..=20 {
            let s = 1.0 + i as f64 / 20.0;
            assert_eq!(seq.count_turned_over(&seq.at(s)), 0, "{name} at {s}");
        }
    }
}

#[test]
fn exactly_half_a_turn_between_later_keys_does_not_tear() {
    // Keys bent (or twisted) so that the end turns by exactly half a turn
    // between the last two: which side of the half turn rounding puts each
    // triangle on must not tear the segment, which turns as the two keys
    // alone do.
    let (length, t) = (4.0, tube(4.0, 0.3, 41, 16));
    let diag = t.bounding_box_diagonal();
    type Deform = fn(&Mesh3, f64, f64) -> Mesh3;
    for (name, deform) in [("bend", bend as Deform), ("twist", twist)] {
        for angles in [[0.0, 90.0, 270.0f64], [0.0, 200.0, 20.0]] {
            let keys: Vec<Mesh3> = angles
                .iter()
                .map(|a| deform(&t, length, a.to_radians()))
                .collect();
            let seq = Sequence::<3>::new(&keys, &opts()).unwrap();
            let alone = Sequence::<3>::new(&[keys[1].clone(), keys[2].clone()], &opts()).unwrap();
            let (mut apart, mut shortest, mut shortest_alone) =
                (0.0f64, f64::INFINITY, f64::INFINITY);
            for i in 0..=20 {
                let u = i as f64 / 20.0;
                let (f, g) = (seq.at(1.0 + u), alone.at(u));
                assert_eq!(seq.count_turned_over(&f), 0, "{name} {angles:?} at {u}");
                apart = apart.max(rigid_distance(&f, &g) / diag);
                shortest = shortest.min(shortest_edge(&t, &f));
                shortest_alone = shortest_alone.min(shortest_edge(&t, &g));
            }
            println!("{name} {angles:?}: against the two keys alone {apart:.2e}; shortest edge {shortest:.4} (alone {shortest_alone:.4})");
            assert!(apart < 5e-3, "{name} {angles:?}: {apart}");
            assert!(
                shortest > 0.9 * shortest_alone,
                "{name} {angles:?}: {shortest} against {shortest_alone}"
            );
        }
    }
}

/// Frames solved together (one substitution for several) are the frames
/// solved one at a time: in both stretch modes, over three keys, with times
/// at the keys, across them and beyond the ends, in any order.
#[test]
fn frames_solved_together_are_the_frames_solved_one_by_one() {
    let t = tube(4.0, 0.3, 21, 10);
    let keys = [
        t.clone(),
        bend(&t, 4.0, 3.0 * PI),
        twist(&bend(&t, 4.0, 1.0), 4.0, 2.0),
    ];
    let times = [
        0.1, 0.2, 0.3, 0.9, 1.0, 1.2, 1.25, 0.0, 1.5, 1.7, 1.9, 2.0, 2.4, -0.3, 0.6,
    ];
    let diag = t.bounding_box_diagonal();
    for stretch in [StretchMode::Linear, StretchMode::Log] {
        let morph = Sequence::<3>::new(&keys, &opts().with_stretch(stretch)).unwrap();
        let mut frames = vec![vec![[0.0; 3]; t.num_vertices()]; times.len()];
        let mut outs: Vec<&mut [P]> = frames.iter_mut().map(Vec::as_mut_slice).collect();
        morph.frames_into(&times, &mut outs, &mut morph.workspace());
        for ((&s, together), parallel) in times.iter().zip(&frames).zip(morph.frames(&times)) {
            let alone = morph.at(s);
            assert!(
                max_distance(together, &alone) < 1e-12 * diag,
                "{stretch:?} at {s}"
            );
            assert!(
                max_distance(&parallel, &alone) < 1e-12 * diag,
                "{stretch:?} at {s}"
            );
        }
    }
}

/// The area-kept stretch blend is planar: a surface's is refused, naming it.
#[test]
fn area_blend_is_refused_in_space() {
    let (_, source, target) = family().remove(0);
    let err = Sequence::new(
        &[source, target],
        &opts().with_stretch(StretchMode::AreaBlend),
    )
    .unwrap_err();
    assert!(
        matches!(&err, Error::InvalidArgument(m) if m.contains("AreaBlend") && m.contains("planar")),
        "{err}"
    );
}
