//! Property tests (proptest) over random inputs: every mesh survives a
//! write-read round trip in every format bit for bit, and rigid motions and
//! renumberings commute with interpolation and transfer.

use std::f64::consts::PI;

use meshmorph::io::{parse_mesh, write_positions, Format};
use meshmorph::shapes::{bend, curl, strip, tube};
use meshmorph::{
    Correspondence, Interpolator, InterpolatorOptions, Mesh2, Mesh3, Transfer, TransferOptions,
};
use proptest::prelude::*;

/// Any finite number, the awkward ones included (subnormals, -0, huge).
fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e3..1e3f64,
        any::<f64>().prop_filter("finite", |x| x.is_finite()),
        Just(-0.0),
        Just(f64::MIN_POSITIVE / 8.0),
        Just(f64::MAX),
    ]
}

/// A mesh with 3 to 40 vertices and 1 to 60 triangles of distinct corners
/// (vertices no triangle uses included).
fn mesh() -> impl Strategy<Value = Mesh3> {
    (3usize..40).prop_flat_map(|n| {
        let triangle = (0..n as u32, 0..n as u32, 0..n as u32)
            .prop_filter("distinct corners", |(a, b, c)| a != b && b != c && a != c)
            .prop_map(|(a, b, c)| [a, b, c]);
        (
            prop::collection::vec([coordinate(), coordinate(), coordinate()], n),
            prop::collection::vec(triangle, 1..60),
        )
            .prop_map(|(p, t)| Mesh3::new(p, t).expect("a valid mesh"))
    })
}

fn bits(mesh: &Mesh3) -> (Vec<[u64; 3]>, Vec<[u32; 3]>) {
    (
        mesh.positions()
            .iter()
            .map(|p| p.map(f64::to_bits))
            .collect(),
        mesh.triangles().to_vec(),
    )
}

/// `angle` about the origin, then `shift`.
fn moved(p: [f64; 2], angle: f64, shift: [f64; 2]) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    [
        c * p[0] - s * p[1] + shift[0],
        s * p[0] + c * p[1] + shift[1],
    ]
}

/// A permutation of `0..n` from a seed.
fn permutation(n: usize, seed: u64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n).collect();
    let mut x = seed | 1;
    for i in (1..n).rev() {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        order.swap(i, (x % (i as u64 + 1)) as usize);
    }
    order
}

/// The mesh with vertex `k` moved to `new_of[k]` and triangles reordered by `tri_order`.
fn renumbered<const D: usize>(
    positions: &[[f64; D]],
    triangles: &[[u32; 3]],
    new_of: &[usize],
    tri_order: &[usize],
) -> (Vec<[f64; D]>, Vec<[u32; 3]>) {
    let mut p = vec![[0.0; D]; positions.len()];
    for (k, &n) in new_of.iter().enumerate() {
        p[n] = positions[k];
    }
    let t = tri_order
        .iter()
        .map(|&k| triangles[k].map(|v| new_of[v as usize] as u32))
        .collect();
    (p, t)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn every_format_round_trips_bit_for_bit(mesh in mesh()) {
        let dir = tempfile::tempdir().unwrap();
        for format in [Format::Obj, Format::Off, Format::Ply] {
            let path = dir.path().join(format!("m.{format}"));
            write_positions(&path, mesh.positions(), mesh.triangles(), format).unwrap();
            let bytes = std::fs::read(&path).unwrap();
            let back = parse_mesh(&bytes, format, &path).unwrap();
            prop_assert_eq!(bits(&back), bits(&mesh), "{}", format);
        }
    }

    #[test]
    fn interpolation_commutes_with_rigid_motions_and_renumbering(
        nx in 8usize..16,
        turn in 0.1f64..1.0,
        angle in -PI..PI,
        shift in [-50.0f64..50.0, -50.0f64..50.0],
        seed in any::<u64>(),
        t in -0.5f64..1.5,
    ) {
        // Fine enough that the curl reverses no triangle.
        let a = strip(3.0, 0.6, nx, 2);
        let b = curl(&a, turn * PI);
        let morph = Interpolator::new(&a, &b, &InterpolatorOptions::default()).unwrap();
        let frame = morph.at(t);
        let scale = 3.0;

        let moved_mesh = |m: &Mesh2| Mesh2::new(
            m.positions().iter().map(|&p| moved(p, angle, shift)).collect(),
            m.triangles().to_vec(),
        ).unwrap();
        let rigid = Interpolator::new(&moved_mesh(&a), &moved_mesh(&b), &InterpolatorOptions::default()).unwrap();
        for (p, q) in frame.iter().zip(rigid.at(t)) {
            let expected = moved(*p, angle, shift);
            prop_assert!((expected[0] - q[0]).hypot(expected[1] - q[1]) < 1e-9 * (scale + 50.0));
        }

        let new_of = permutation(a.num_vertices(), seed);
        let tri_order = permutation(a.num_triangles(), seed.rotate_left(17));
        let (pa, ta) = renumbered(a.positions(), a.triangles(), &new_of, &tri_order);
        let (pb, tb) = renumbered(b.positions(), b.triangles(), &new_of, &tri_order);
        let shuffled = Interpolator::new(&Mesh2::new(pa, ta).unwrap(), &Mesh2::new(pb, tb).unwrap(), &InterpolatorOptions::default()).unwrap();
        let g = shuffled.at(t);
        for (k, p) in frame.iter().enumerate() {
            let q = g[new_of[k]];
            prop_assert!((p[0] - q[0]).hypot(p[1] - q[1]) < 1e-9 * scale);
        }
    }

    #[test]
    fn transfer_commutes_with_rigid_motions_and_renumbering(
        rings in 4usize..8,
        bend_turn in 0.0f64..0.6,
        angle in -PI..PI,
        shift in [-20.0f64..20.0, -20.0f64..20.0, -20.0f64..20.0],
        seed in any::<u64>(),
    ) {
        // The identity correspondence from a tube to itself: a pose moved
        // rigidly moves the result by the same motion, and renumbering the
        // target's vertices renumbers the result.
        let rest = tube(2.0, 0.3, rings, 8);
        let pose = bend(&rest, 2.0, bend_turn * PI);
        let transfer = Transfer::new(&rest, &rest, &Correspondence::identity(&rest), &TransferOptions::default()).unwrap();
        let out = transfer.apply(&pose).unwrap();

        let (s, c) = angle.sin_cos();
        let motion = |p: [f64; 3]| [c * p[0] - s * p[1] + shift[0], s * p[0] + c * p[1] + shift[1], p[2] + shift[2]];
        let moved_pose = rest.with_positions(pose.positions().iter().map(|&p| motion(p)).collect()).unwrap();
        let moved_out = transfer.apply(&moved_pose).unwrap();
        for (p, q) in out.iter().zip(&moved_out) {
            let e = motion(*p);
            let d = ((e[0] - q[0]).powi(2) + (e[1] - q[1]).powi(2) + (e[2] - q[2]).powi(2)).sqrt();
            prop_assert!(d < 1e-8 * 40.0, "{d}");
        }

        let new_of = permutation(rest.num_vertices(), seed);
        let tri_order = permutation(rest.num_triangles(), seed.rotate_left(29));
        let (pt, tt) = renumbered(rest.positions(), rest.triangles(), &new_of, &tri_order);
        let target = Mesh3::new(pt, tt).unwrap();
        // Source triangle k pairs with the target triangle now at the place of k in `tri_order`.
        let mut place = vec![0u32; tri_order.len()];
        for (new, &old) in tri_order.iter().enumerate() {
            place[old] = new as u32;
        }
        let pairs = (0..rest.num_triangles()).map(|k| [k as u32, place[k]]).collect();
        let renumbered_transfer = Transfer::new(&rest, &target, &Correspondence::new(pairs, &rest, &target), &TransferOptions::default()).unwrap();
        let g = renumbered_transfer.apply(&pose).unwrap();
        for (k, p) in out.iter().enumerate() {
            let q = g[new_of[k]];
            let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
            prop_assert!(d < 1e-8, "{d}");
        }
    }
}
