//! Deformation transfer (correspondence and transfer) over families of
//! procedural tubes, and bad input. (Sumner's horse and camel of
//! ../shared/data/dt are in the `shared_data` binary.)

use std::f64::consts::{PI, TAU};
use std::path::Path;

use crate::common::{all_finite, assert_close, max_distance, mean, norm, self_transfer, sub};
use meshmorph::shapes::{bend, octahedron, tube};
use meshmorph::MIN_MARKERS;
use meshmorph::{
    correspond, io, CorrespondOptions, CorrespondResult, Correspondence, Error, Markers, Mesh3,
    Transfer, TransferOptions, VertexNumbering,
};

// ---------------------------------------------------------------------------
// Shared helpers
// ---------------------------------------------------------------------------

type P3 = [f64; 3];
type M3 = [[f64; 3]; 3];

/// A small seeded generator (SplitMix64): the tests never depend on chance.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e3779b97f4a7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d049bb133111eb);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    fn shuffle<T>(&mut self, v: &mut [T]) {
        for i in (1..v.len()).rev() {
            v.swap(i, self.below(i + 1));
        }
    }
    /// A random rotation (uniform axis, angle in (0.1, π)).
    fn rotation(&mut self) -> M3 {
        let z: f64 = self.range(-1.0, 1.0);
        let phi = self.range(0.0, TAU);
        let r = (1.0 - z * z).sqrt();
        rotation([r * phi.cos(), r * phi.sin(), z], self.range(0.1, PI))
    }
}

fn mul(r: &M3, p: P3) -> P3 {
    std::array::from_fn(|i| r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2])
}

/// Rotation by `angle` about the unit `axis` (Rodrigues).
fn rotation(axis: P3, angle: f64) -> M3 {
    let [x, y, z] = axis;
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [c + x * x * t, x * y * t - z * s, x * z * t + y * s],
        [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
        [z * x * t - y * s, z * y * t + x * s, c + z * z * t],
    ]
}

/// The mesh with every vertex moved by `f`.
fn mapped(m: &Mesh3, f: impl Fn(P3) -> P3) -> Mesh3 {
    m.with_positions(m.positions().iter().map(|&p| f(p)).collect())
        .unwrap()
}

/// `x ↦ R x + t` on every vertex.
fn rigid(m: &Mesh3, r: &M3, t: P3) -> Mesh3 {
    mapped(m, |p| {
        let q = mul(r, p);
        [q[0] + t[0], q[1] + t[1], q[2] + t[2]]
    })
}

/// Twists a mesh along x from 0 to `length`: the cross-section at `x`
/// turns about the x axis by `angle · x / length`.
fn twist(m: &Mesh3, length: f64, angle: f64) -> Mesh3 {
    mapped(m, |[x, y, z]| {
        let (s, c) = (angle * x / length).sin_cos();
        [x, c * y - s * z, s * y + c * z]
    })
}

/// Scales along x by `along` and across by `across`, growing with x (not affine).
fn stretch(m: &Mesh3, along: f64, across: f64) -> Mesh3 {
    mapped(m, |[x, y, z]| {
        let k = across * (1.0 + 0.1 * x);
        [along * x, k * y, k * z]
    })
}

/// Two meshes side by side in one (their components stay apart).
fn union(a: &Mesh3, b: &Mesh3) -> Mesh3 {
    let off = a.num_vertices() as u32;
    let mut p = a.positions().to_vec();
    p.extend_from_slice(b.positions());
    let mut t = a.triangles().to_vec();
    t.extend(b.triangles().iter().map(|t| t.map(|v| v + off)));
    Mesh3::new(p, t).unwrap()
}

/// Vertex `s` of ring `r` of a [`tube`] with `segments` vertices per ring.
fn ring_vertex(segments: usize, r: usize, s: usize) -> u32 {
    (r * segments + s % segments) as u32
}

/// A [`tube`] without its caps (and without the two cap centres): two
/// boundary loops.
fn open_tube(length: f64, radius: f64, rings: usize, segments: usize) -> Mesh3 {
    let closed = tube(length, radius, rings, segments);
    let side = 2 * (rings - 1) * segments;
    let (mut p, t) = closed.into_parts();
    p.truncate(rings * segments);
    Mesh3::new(p, t[..side].to_vec()).unwrap()
}

/// Glues a fin triangle onto the axial edge from ring `r` to ring `r + 1` at
/// segment 0 of a tube, its tip at `y = height`: the edge gets a third
/// triangle and becomes non-manifold.
fn with_fin(m: &Mesh3, segments: usize, r: usize, height: f64) -> Mesh3 {
    let (a, b) = (ring_vertex(segments, r, 0), ring_vertex(segments, r + 1, 0));
    let (pa, pb) = (m.positions()[a as usize], m.positions()[b as usize]);
    let (mut p, mut t) = m.clone().into_parts();
    p.push([0.5 * (pa[0] + pb[0]), height, 0.05 * height]);
    t.push([a, b, p.len() as u32 - 1]);
    Mesh3::new(p, t).unwrap()
}

/// Centroid of ring `r` of a tube output.
fn ring_centroid(p: &[P3], segments: usize, r: usize) -> P3 {
    mean(&p[r * segments..(r + 1) * segments])
}

/// A tube's parameters, to find corresponding vertices of two tubes.
#[derive(Clone, Copy, Debug)]
struct TubeSpec {
    length: f64,
    radius: f64,
    rings: usize,
    segments: usize,
}

impl TubeSpec {
    fn mesh(self) -> Mesh3 {
        tube(self.length, self.radius, self.rings, self.segments)
    }
    /// Position along the axis and angle around it of every vertex
    /// (cap centres at angle 0 with a flag).
    fn axial(self, v: usize) -> (f64, f64, bool) {
        let n = self.rings * self.segments;
        if v >= n {
            return (if v == n { 0.0 } else { self.length }, 0.0, true);
        }
        let (r, s) = (v / self.segments, v % self.segments);
        (
            self.length * r as f64 / (self.rings - 1) as f64,
            TAU * s as f64 / self.segments as f64,
            false,
        )
    }
}

/// Markers between two tubes: each source vertex in `picks` with the target
/// vertex nearest to it along the axis and around it (the radii differ).
fn tube_markers(source: TubeSpec, target: TubeSpec, picks: &[u32]) -> Markers {
    let n = target.rings * target.segments + 2;
    let pairs = picks
        .iter()
        .map(|&v| {
            let (x, a, cap) = source.axial(v as usize);
            let t = (0..n)
                .min_by(|&i, &j| {
                    let cost = |k: usize| {
                        let (y, b, c) = target.axial(k);
                        let da = (a - b).rem_euclid(TAU);
                        let da = da.min(TAU - da);
                        (x - y).abs() + da + if c == cap { 0.0 } else { 100.0 }
                    };
                    cost(i).total_cmp(&cost(j))
                })
                .unwrap();
            [v, t as u32]
        })
        .collect();
    Markers::new(pairs)
}

/// Marker picks on a source tube: both cap centres and, on every `every`-th
/// ring, the vertices at 0°, 90°, 180° and 270° (`segments` divisible by 4).
fn tube_picks(s: TubeSpec, every: usize) -> Vec<u32> {
    let n = (s.rings * s.segments) as u32;
    let mut picks = vec![n, n + 1];
    for r in (0..s.rings).step_by(every) {
        for q in 0..4 {
            picks.push(ring_vertex(s.segments, r, q * s.segments / 4));
        }
    }
    picks
}

/// The usual source, target and a very coarse source: all along x from 0 to 4.
const THIN: TubeSpec = TubeSpec {
    length: 4.0,
    radius: 0.5,
    rings: 17,
    segments: 16,
};
const THICK: TubeSpec = TubeSpec {
    length: 4.0,
    radius: 0.65,
    rings: 25,
    segments: 20,
};
const COARSE: TubeSpec = TubeSpec {
    rings: 5,
    segments: 8,
    ..THIN
};

fn tube_correspondence(source: TubeSpec, target: TubeSpec) -> CorrespondResult {
    let markers = tube_markers(source, target, &tube_picks(source, 4));
    correspond(
        &source.mesh(),
        &target.mesh(),
        &markers,
        &CorrespondOptions::default(),
    )
    .unwrap()
}

/// Asserts `e` is the variant `matches` says and its message holds every needle.
#[track_caller]
fn assert_error(e: Error, matches: fn(&Error) -> bool, needles: &[&str]) {
    let msg = e.to_string();
    assert!(matches(&e), "wrong variant: {e:?}");
    for n in needles {
        assert!(msg.contains(n), "`{n}` not in: {msg}");
    }
}

// ---------------------------------------------------------------------------
// 1. Identity: S0 = T0 and the identity correspondence reproduce every pose
// ---------------------------------------------------------------------------

/// Meshes along x from 0 to `length`, each with poses that bend, twist and
/// stretch it.
fn identity_family() -> Vec<(String, Mesh3, f64)> {
    let mut family = Vec::new();
    for (rings, segments) in [(2, 3), (5, 6), (9, 12), (33, 8), (12, 40)] {
        family.push((
            format!("tube {rings}x{segments}"),
            tube(4.0, 0.5, rings, segments),
            4.0,
        ));
    }
    family.push(("open tube".into(), open_tube(3.0, 0.4, 10, 10), 3.0));
    family.push((
        "tube with a fin".into(),
        with_fin(&tube(3.0, 0.4, 10, 10), 10, 4, 0.8),
        3.0,
    ));
    family.push((
        "open tube with a fin".into(),
        with_fin(&open_tube(3.0, 0.4, 10, 10), 10, 0, 0.8),
        3.0,
    ));
    let second = mapped(&tube(4.0, 0.3, 7, 9), |[x, y, z]| [x, y + 2.0, z - 1.0]);
    family.push((
        "two tubes".into(),
        union(&tube(4.0, 0.5, 9, 12), &second),
        4.0,
    ));
    family
}

fn identity_poses(m: &Mesh3, length: f64) -> Vec<(String, Mesh3)> {
    let mut poses = vec![("rest".to_string(), m.clone())];
    for deg in [-60.0, 10.0, 90.0, 180.0, 300.0] {
        let a = f64::to_radians(deg);
        poses.push((format!("bend {deg}"), bend(m, length, a)));
        poses.push((format!("twist {deg}"), twist(m, length, a)));
        poses.push((
            format!("bend {deg} twisted"),
            bend(&twist(m, length, -a), length, 0.5 * a),
        ));
    }
    poses.push(("stretch".into(), stretch(m, 1.7, 0.6)));
    poses.push(("squash".into(), stretch(m, 0.5, 1.3)));
    poses.push((
        "stretch, bend, move".into(),
        rigid(
            &bend(&stretch(m, 1.3, 0.8), 1.3 * length, 2.0),
            &rotation([0.0, 0.6, 0.8], 2.5),
            [10.0, -3.0, 7.0],
        ),
    ));
    let mut rng = Rng(7);
    poses.push((
        "noise".into(),
        mapped(m, |p| p.map(|x| x + 0.05 * (x * 37.0).sin())),
    ));
    let jitter: Vec<P3> = m
        .positions()
        .iter()
        .map(|p| p.map(|x| x + rng.range(-0.1, 0.1)))
        .collect();
    poses.push(("random jitter".into(), m.with_positions(jitter).unwrap()));
    poses
}

#[test]
fn identity_correspondence_reproduces_every_pose() {
    for (name, mesh, length) in identity_family() {
        let transfer = self_transfer(&mesh);
        let poses = identity_poses(&mesh, length);
        let all = transfer
            .apply_all(&poses.iter().map(|p| p.1.clone()).collect::<Vec<_>>())
            .unwrap();
        for ((pose_name, pose), out) in poses.iter().zip(&all) {
            assert_close(
                out,
                pose.positions(),
                pose,
                1e-8,
                &format!("{name}, {pose_name}"),
            );
        }
    }
}

/// (boundary edges, non-manifold edges, connected parts) of a mesh.
fn topology_of(m: &Mesh3) -> (usize, usize, usize) {
    let counts = m.surface_counts();
    (counts.boundary_edges, counts.crowded_edges, counts.parts)
}

#[test]
fn the_identity_family_has_boundaries_fins_and_parts() {
    let kinds: Vec<(String, (usize, usize, usize))> = identity_family()
        .into_iter()
        .map(|(name, m, _)| (name, topology_of(&m)))
        .collect();
    let of = |name: &str| kinds.iter().find(|k| k.0 == name).unwrap().1;
    assert_eq!(of("tube 9x12"), (0, 0, 1));
    // Two loops of 10 edges; the fin adds two boundary edges.
    assert_eq!(of("open tube"), (20, 0, 1));
    assert_eq!(of("tube with a fin"), (2, 1, 1));
    assert_eq!(of("open tube with a fin"), (22, 1, 1));
    assert_eq!(of("two tubes"), (0, 0, 2));
}

#[test]
fn components_of_a_self_transfer_move_independently() {
    // Each tube gets its own rigid motion and bend; the output follows both.
    let (a, b) = (
        tube(4.0, 0.5, 9, 12),
        mapped(&tube(2.0, 0.3, 5, 7), |p| [p[0], p[1] + 3.0, p[2]]),
    );
    let mesh = union(&a, &b);
    let transfer = self_transfer(&mesh);
    let mut rng = Rng(11);
    for k in 0..4 {
        let a1 = rigid(
            &bend(&a, 4.0, 0.7 * k as f64),
            &rng.rotation(),
            [1.0, 2.0, 3.0],
        );
        let b1 = rigid(&twist(&b, 2.0, 1.0), &rng.rotation(), [-5.0, 0.0, 1.0]);
        let pose = union(&a1, &b1);
        let out = transfer.apply(&pose).unwrap();
        assert_close(&out, pose.positions(), &pose, 1e-8, &format!("pose {k}"));
    }
}

// ---------------------------------------------------------------------------
// 2. Rigid motions carry over to a different target
// ---------------------------------------------------------------------------

/// Source and target tubes for the rigid-motion test: the target as made by
/// `spec.mesh()`, then changed by `edit` (moved away, given a fin, ...).
struct RigidCase {
    name: &'static str,
    source: TubeSpec,
    target: TubeSpec,
    edit: fn(Mesh3, TubeSpec) -> Mesh3,
    /// The correspondence must leave some target triangle unpaired.
    unpaired: bool,
}

fn rigid_cases() -> Vec<RigidCase> {
    let keep: fn(Mesh3, TubeSpec) -> Mesh3 = |m, _| m;
    vec![
        RigidCase {
            name: "thin to thick",
            source: THIN,
            target: THICK,
            edit: keep,
            unpaired: false,
        },
        RigidCase {
            name: "thick to coarser",
            source: THICK,
            target: TubeSpec {
                rings: 9,
                segments: 12,
                ..THIN
            },
            edit: keep,
            unpaired: false,
        },
        // Many target triangles per source triangle: the centroid of the
        // paired source triangles is not the target's centroid.
        RigidCase {
            name: "coarse to thick",
            source: COARSE,
            target: THICK,
            edit: keep,
            unpaired: false,
        },
        RigidCase {
            name: "thin to thick, target elsewhere",
            source: THIN,
            target: THICK,
            edit: |m, _| rigid(&m, &rotation([0.0, 0.0, 1.0], 0.4), [0.5, 2.0, -1.0]),
            unpaired: false,
        },
        // The fin is too far from the source to be paired: it takes the
        // rotation of its neighbours.
        RigidCase {
            name: "thin to thick with a fin",
            source: THIN,
            target: THICK,
            edit: |m, spec| with_fin(&m, spec.segments, 10, 2.5),
            unpaired: true,
        },
    ]
}

#[test]
fn rigid_motions_of_the_source_move_the_target_rigidly() {
    for case in rigid_cases() {
        let s0 = case.source.mesh();
        let t0 = (case.edit)(case.target.mesh(), case.target);
        let markers = tube_markers(case.source, case.target, &tube_picks(case.source, 4));
        let c = correspond(&s0, &t0, &markers, &CorrespondOptions::default())
            .unwrap()
            .correspondence;
        let what = format!(
            "{} ({} pairs, unpaired: {} source, {} target triangles)",
            case.name,
            c.pairs().len(),
            c.unmatched_source(),
            c.unmatched_target()
        );
        assert_eq!(c.unmatched_target() > 0, case.unpaired, "{what}");
        let transfer = Transfer::new(&s0, &t0, &c, &TransferOptions::default()).unwrap();
        let rest = transfer.apply(&s0).unwrap();
        assert_close(&rest, t0.positions(), &t0, 1e-8, &format!("{what}: rest"));
        let mut rng = Rng(3);
        for k in 0..6 {
            let r = rng.rotation();
            let t = [
                rng.range(-5.0, 5.0),
                rng.range(-5.0, 5.0),
                rng.range(-5.0, 5.0),
            ];
            let out = transfer.apply(&rigid(&s0, &r, t)).unwrap();
            // The source is brought onto the target by the alignment A: the
            // target moves by the same motion seen in its frame, A M A⁻¹.
            let a = c.alignment();
            let want = mapped(&t0, |p| {
                let q = sub(p, a.translation).map(|x| x / a.scale);
                let back: P3 =
                    std::array::from_fn(|j| (0..3).map(|i| a.rotation[i][j] * q[i]).sum());
                let moved = mul(&r, back);
                a.apply([moved[0] + t[0], moved[1] + t[1], moved[2] + t[2]])
            });
            assert_close(
                &out,
                want.positions(),
                &t0,
                1e-8,
                &format!("{what}: motion {k}"),
            );
        }
    }
}

#[test]
fn target_parts_without_pairs_keep_their_shape() {
    // The thick tube, a small tube far away (no pair at all) and a triangle
    // hanging from one tube vertex, far from the source (no pair, and no
    // edge shared with a paired triangle).
    let s0 = THIN.mesh();
    let thick = THICK.mesh();
    let far = mapped(&tube(1.0, 0.3, 3, 5), |p| [p[0], p[1] + 6.0, p[2]]);
    let hang_at = ring_vertex(THICK.segments, 12, 0);
    let p = thick.positions()[hang_at as usize];
    let (mut positions, mut triangles) = union(&thick, &far).into_parts();
    let first = positions.len() as u32;
    positions.push([p[0] + 0.2, p[1] + 1.5, 0.3]);
    positions.push([p[0] - 0.2, p[1] + 1.5, -0.3]);
    triangles.push([hang_at, first, first + 1]);
    let t0 = Mesh3::new(positions, triangles).unwrap();
    let hanging = t0.num_triangles() - 1;
    let far_vertices = thick.num_vertices()..thick.num_vertices() + far.num_vertices();

    let markers = tube_markers(THIN, THICK, &tube_picks(THIN, 4));
    let c = correspond(&s0, &t0, &markers, &CorrespondOptions::default())
        .unwrap()
        .correspondence;
    assert!(c
        .pairs()
        .iter()
        .all(|p| (p[1] as usize) < thick.num_triangles()));
    let transfer = Transfer::new(&s0, &t0, &c, &TransferOptions::default()).unwrap();
    let mut rng = Rng(21);
    for k in 0..4 {
        let pose = rigid(
            &bend(&s0, 4.0, 0.5 * k as f64),
            &rng.rotation(),
            [1.0, 2.0, 3.0],
        );
        let out = transfer.apply(&pose).unwrap();
        assert!(all_finite(&out), "pose {k}");
        // The far tube, a part without pairs, is carried rigidly by the
        // nearest surface: it keeps its shape.
        for a in far_vertices.clone().step_by(3) {
            for b in far_vertices.clone().step_by(5) {
                let (p, q) = (t0.positions(), &out);
                let d = norm(sub(q[a], q[b])) - norm(sub(p[a], p[b]));
                assert!(d.abs() < 1e-9, "pose {k}: far tube stretched by {d:e}");
            }
        }
        // The hanging triangle keeps its shape (turned with the surface).
        let rest = t0.corners(hanging);
        let now = t0.triangles()[hanging].map(|v| out[v as usize]);
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            let d = norm(sub(now[i], now[j])) - norm(sub(rest[i], rest[j]));
            assert!(
                d.abs() < 1e-3 * norm(sub(rest[i], rest[j])),
                "pose {k}: hanging triangle edge {i}{j} off by {d:e}"
            );
        }
    }
}

// ---------------------------------------------------------------------------
// 3. Order independence: markers and poses
// ---------------------------------------------------------------------------

#[test]
fn marker_order_does_not_matter() {
    // Tubes are symmetric: many triangles have two equally near partners,
    // and the last bits of the deformed source decide which one is taken.
    // Markers on every ring put neighbours along the axis in the same rows
    // of the system.
    for (source, target) in [(THIN, THICK), (COARSE, THICK), (THICK, THIN)] {
        let (s0, t0) = (source.mesh(), target.mesh());
        let pose = bend(&twist(&s0, 4.0, 1.0), 4.0, 1.2);
        for every in [1, 2, 4] {
            let what = format!(
                "{}x{} -> {}x{}, markers on every {every} rings",
                source.rings, source.segments, target.rings, target.segments
            );
            let markers = tube_markers(source, target, &tube_picks(source, every));
            let opts = CorrespondOptions::default();
            let base = correspond(&s0, &t0, &markers, &opts).unwrap();
            let transfer =
                Transfer::new(&s0, &t0, &base.correspondence, &Default::default()).unwrap();
            let want = transfer.apply(&pose).unwrap();
            let mut rng = Rng(5);
            for k in 0..4 {
                let mut pairs = markers.pairs().to_vec();
                rng.shuffle(&mut pairs);
                let shuffled = correspond(&s0, &t0, &Markers::on_surfaces(pairs), &opts).unwrap();
                assert_eq!(
                    shuffled.correspondence, base.correspondence,
                    "{what}, shuffle {k}: other pairs"
                );
                assert_eq!(
                    shuffled.deformed_source, base.deformed_source,
                    "{what}, shuffle {k}: other deformed source"
                );
                let t =
                    Transfer::new(&s0, &t0, &shuffled.correspondence, &Default::default()).unwrap();
                assert_eq!(t.apply(&pose).unwrap(), want, "{what}, shuffle {k}");
            }
        }
    }
}

#[test]
fn pose_order_does_not_matter_and_batches_equal_single_poses() {
    let (s0, t0) = (THIN.mesh(), THICK.mesh());
    let result = tube_correspondence(THIN, THICK);
    let transfer = Transfer::new(&s0, &t0, &result.correspondence, &Default::default()).unwrap();
    let poses: Vec<Mesh3> = (0..9)
        .map(|k| {
            let a = 0.4 * k as f64 - 1.0;
            twist(&bend(&s0, 4.0, a), 4.0, 0.3 * a)
        })
        .collect();
    let single: Vec<Vec<P3>> = poses.iter().map(|p| transfer.apply(p).unwrap()).collect();
    assert_eq!(transfer.apply_all(&poses).unwrap(), single);
    let mut rng = Rng(9);
    for _ in 0..3 {
        let mut order: Vec<usize> = (0..poses.len()).collect();
        rng.shuffle(&mut order);
        let permuted: Vec<Mesh3> = order.iter().map(|&k| poses[k].clone()).collect();
        let out = transfer.apply_all(&permuted).unwrap();
        for (o, &k) in out.iter().zip(&order) {
            assert_eq!(o, &single[k], "pose {k}");
        }
    }
    // apply_into with one workspace reused over all poses: the same again.
    let mut ws = transfer.workspace();
    let mut out = vec![[0.0; 3]; t0.num_vertices()];
    for (p, want) in poses.iter().zip(&single).rev() {
        transfer.apply_into(p.positions(), &mut out, &mut ws);
        assert_eq!(&out, want);
    }
}

// ---------------------------------------------------------------------------
// 4. Bad input
// ---------------------------------------------------------------------------

fn is_mismatch(e: &Error) -> bool {
    matches!(e, Error::Mismatch(_) | Error::TriangleMismatch { .. })
}
fn is_invalid_argument(e: &Error) -> bool {
    matches!(e, Error::InvalidArgument(_) | Error::InvalidMarker { .. })
}
fn is_invalid_mesh(e: &Error) -> bool {
    matches!(
        e,
        Error::InvalidMesh(_) | Error::InvalidVertex { .. } | Error::InvalidTriangle { .. }
    )
}
fn is_parse(e: &Error) -> bool {
    matches!(e, Error::Parse { .. })
}
fn is_degenerate(e: &Error) -> bool {
    matches!(e, Error::DegenerateTriangles { .. })
}

#[test]
fn poses_that_do_not_fit_the_source_are_refused() {
    let s0 = tube(4.0, 0.5, 9, 12);
    let transfer = self_transfer(&s0);
    let bigger = tube(4.0, 0.5, 9, 13);
    assert_error(
        transfer.apply(&bigger).unwrap_err(),
        is_mismatch,
        &["the pose has 119 vertices but the source reference has 110"],
    );
    // Same vertices, one fewer triangle.
    let (p, t) = s0.clone().into_parts();
    let fewer = Mesh3::new(p.clone(), t[1..].to_vec()).unwrap();
    assert_error(
        transfer.apply(&fewer).unwrap_err(),
        is_mismatch,
        &["triangles but the source reference has"],
    );
    // Same counts, triangle 5 turned over.
    let mut flipped = t.clone();
    flipped[5].swap(1, 2);
    let flipped = Mesh3::new(p, flipped).unwrap();
    assert_error(
        transfer.check_pose(&flipped).unwrap_err(),
        is_mismatch,
        &[
            "triangle 5 is",
            "in the pose but",
            "in the source reference",
        ],
    );
    // In a batch the error names the pose.
    let poses = [s0.clone(), bend(&s0, 4.0, 1.0), flipped];
    assert_error(
        transfer.apply_all(&poses).unwrap_err(),
        is_mismatch,
        &["pose 2:", "triangle 5"],
    );
}

#[test]
#[should_panic(expected = "pose has the wrong number of vertices")]
fn apply_into_panics_on_a_pose_of_the_wrong_size() {
    let s0 = tube(4.0, 0.5, 3, 4);
    let transfer = self_transfer(&s0);
    let mut out = vec![[0.0; 3]; s0.num_vertices()];
    transfer.apply_into(&[[0.0; 3]; 3], &mut out, &mut transfer.workspace());
}

#[test]
fn bad_markers_are_refused() {
    let (s0, t0) = (THIN.mesh(), THICK.mesh());
    let (ns, nt) = (s0.num_vertices() as u32, t0.num_vertices() as u32);
    let good = tube_markers(THIN, THICK, &tube_picks(THIN, 8))
        .vertex_pairs()
        .unwrap();
    let run = |pairs: Vec<[u32; 2]>| {
        correspond(
            &s0,
            &t0,
            &Markers::new(pairs),
            &CorrespondOptions::default(),
        )
        .map(|_| ())
        .unwrap_err()
    };
    let with = |extra: [u32; 2]| {
        let mut p = good.clone();
        p.push(extra);
        p
    };
    assert_error(
        run(with([ns, 0])),
        is_invalid_argument,
        &[
            &format!("marker {}", good.len()),
            &format!("source vertex {ns} is out of range (the source has {ns} vertices)"),
            "if the file counts vertices from 1, read it so (--one-based on the command line)",
        ],
    );
    assert_error(
        run(with([3, nt + 7])),
        is_invalid_argument,
        &[&format!("target vertex {} is out of range", nt + 7)],
    );
    assert_error(
        run(with(good[2])),
        is_invalid_argument,
        &[&format!(
            "the pair source vertex {}, target vertex {} repeats marker 2",
            good[2][0], good[2][1]
        )],
    );
    let other = (good[3][1] + 1) % nt;
    assert_error(
        run(with([good[3][0], other])),
        is_invalid_argument,
        &[&format!(
            "source vertex {} is paired with target vertex {other} here and with target vertex {} in marker 3",
            good[3][0], good[3][1]
        )],
    );
    // Too few (none is another case: two shapes that stand alike, tested
    // on its own).
    for k in 1..MIN_MARKERS {
        assert_error(
            run(good[..k].to_vec()),
            is_invalid_argument,
            &[
                &format!("{k} marker pair"),
                &format!("at least {MIN_MARKERS}"),
            ],
        );
    }
}

/// The correspondence with the default options.
fn found_by(source: &Mesh3, target: &Mesh3, markers: &Markers) -> CorrespondResult {
    correspond(source, target, markers, &CorrespondOptions::default()).unwrap()
}

#[test]
fn a_source_part_without_a_marker_is_drawn_onto_the_target() {
    let (s0, t0) = (THIN.mesh(), THICK.mesh());
    let markers = tube_markers(THIN, THICK, &tube_picks(THIN, 8));
    let alone = found_by(&s0, &t0, &markers).correspondence;
    // A second source tube, far from the target and without a marker: the
    // first tube's correspondence is as it was, the second is left unmatched.
    let far = mapped(&s0, |p| [p[0], p[1] + 3.0, p[2]]);
    let two = found_by(&union(&s0, &far), &t0, &markers).correspondence;
    assert_eq!(two.pairs(), alone.pairs());
    // A second source tube beside the first, without a marker, a little off
    // the target's second tube (a tenth of its radius, within the
    // closest-point cut-off): drawn onto it, its triangles paired with the
    // second tube's.
    let beside = |m: &Mesh3, dy: f64| mapped(m, |p| [p[0], p[1] + dy, p[2]]);
    let source = union(&s0, &beside(&s0, 2.05));
    let target = union(&t0, &beside(&s0, 2.0));
    let found = found_by(&source, &target, &markers);
    let (ns, nt) = (s0.num_triangles() as u32, t0.num_triangles() as u32);
    let second: Vec<&[u32; 2]> = found
        .correspondence
        .pairs()
        .iter()
        .filter(|p| p[0] >= ns)
        .collect();
    assert!(second.len() as u32 >= ns, "{} pairs", second.len());
    assert!(second.iter().all(|p| p[1] >= nt), "paired across the tubes");
    // Its vertices lie on the target's second tube (about y = 2), but for
    // the centres of its ends.
    let off: Vec<f64> = found.deformed_source.positions()[s0.num_vertices()..]
        .iter()
        .zip(s0.positions())
        .filter(|(_, rest)| rest[1].hypot(rest[2]) > 0.5 * THIN.radius)
        .map(|(p, _)| ((p[1] - 2.0).hypot(p[2]) - THIN.radius).abs())
        .collect();
    let mean = off.iter().sum::<f64>() / off.len() as f64;
    let worst = off.iter().copied().fold(0.0, f64::max);
    assert!(mean < 0.01 && worst < 0.05, "mean {mean}, worst {worst}");
}

#[test]
fn marker_files_that_do_not_parse_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.cons");
    for (text, line, needle) in [
        ("3\n0 1\n1 x\n2 2\n", 3, "`x` is not a vertex index"),
        ("# comment\n0 1\n\n1 2 3\n", 4, "expected `source target`"),
        (
            "5\n0 1\n1 2\n",
            1,
            "the count line says 5 pairs but 2 follow",
        ),
        ("0 1\n4 -2\n", 2, "out of range"),
    ] {
        std::fs::write(&path, text).unwrap();
        let e = Markers::read(&path, VertexNumbering::FromZero).unwrap_err();
        match &e {
            Error::Parse {
                line: l, path: p, ..
            } => {
                assert_eq!(*l, Some(line), "{e}");
                assert_eq!(p, &path);
            }
            other => panic!("not a parse error: {other:?}"),
        }
        assert_error(e, is_parse, &["bad.cons", &format!("line {line}"), needle]);
    }
    // 1-based files refuse a 0.
    std::fs::write(&path, "1 1\n0 2\n").unwrap();
    assert_error(
        Markers::read(&path, VertexNumbering::FromOne).unwrap_err(),
        is_parse,
        &["line 2", "1-based"],
    );
    // A file that parses but names a vertex the mesh lacks: the line is named.
    std::fs::write(&path, "0 0\n1 1\n999 2\n").unwrap();
    let m = Markers::read(&path, VertexNumbering::FromZero).unwrap();
    assert_error(
        m.validate(&THIN.mesh(), &THIN.mesh()).unwrap_err(),
        is_invalid_argument,
        &["bad.cons", "line 3", "source vertex 999"],
    );
    // A missing file.
    assert!(matches!(
        Markers::read(&dir.path().join("none.cons"), VertexNumbering::FromZero).unwrap_err(),
        Error::Io { .. }
    ));
}

#[test]
fn correspondences_made_for_other_meshes_are_refused() {
    let s0 = tube(4.0, 0.5, 9, 12);
    let t0 = tube(4.0, 0.7, 9, 12);
    let c = Correspondence::new(vec![[0, 0], [5, 7], [5, 8], [200, 1]], &s0, &t0);
    assert!(c.check_fits(&s0, &t0).is_ok());
    // Other counts, source or target.
    let other = tube(4.0, 0.5, 10, 12);
    for (s, t, name) in [
        (&other, &t0, "source reference"),
        (&s0, &other, "target reference"),
    ] {
        assert_error(
            c.check_fits(s, t).unwrap_err(),
            is_mismatch,
            &[
                name,
                "of 110 vertices and 216 triangles",
                "this one has 122 vertices",
            ],
        );
        assert_error(
            Transfer::new(s, t, &c, &TransferOptions::default()).unwrap_err(),
            is_mismatch,
            &[name],
        );
    }
    // Same counts, other triangles: two triangles swapped.
    let (p, mut tris) = s0.clone().into_parts();
    tris.swap(0, 1);
    let renumbered = Mesh3::new(p, tris).unwrap();
    assert_error(
        Transfer::new(&renumbered, &t0, &c, &TransferOptions::default()).unwrap_err(),
        is_mismatch,
        &["source reference with other triangles (same counts"],
    );
    // Moving vertices is fine: only connectivity counts.
    assert!(c.check_fits(&bend(&s0, 4.0, 1.0), &t0).is_ok());
}

#[test]
fn correspondence_files_round_trip_and_name_bad_lines() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.txt");
    let result = tube_correspondence(THIN, THICK);
    let c = result.correspondence;
    c.save(&path).unwrap();
    let back = Correspondence::load(&path).unwrap();
    assert_eq!(back, c);
    assert!(back.check_fits(&THIN.mesh(), &THICK.mesh()).is_ok());
    assert_eq!(back.unmatched_source(), c.unmatched_source());
    assert_eq!(back.unmatched_target(), c.unmatched_target());
    // The file remembers which meshes it was made for.
    for (s, t, needle) in [
        (
            COARSE.mesh(),
            THICK.mesh(),
            "source reference of 274 vertices",
        ),
        (THIN.mesh(), THIN.mesh(), "target reference of 502 vertices"),
    ] {
        assert_error(
            Transfer::new(&s, &t, &back, &TransferOptions::default()).unwrap_err(),
            is_mismatch,
            &[needle],
        );
    }
    let (p, mut tris) = THICK.mesh().into_parts();
    tris.swap(3, 4);
    assert_error(
        Transfer::new(
            &THIN.mesh(),
            &Mesh3::new(p, tris).unwrap(),
            &back,
            &TransferOptions::default(),
        )
        .unwrap_err(),
        is_mismatch,
        &["target reference with other triangles (same counts"],
    );

    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    // Header, comment, source, target, alignment, pair count, then pairs
    // from line 7.
    assert!(lines[4].starts_with("alignment "), "{text}");
    assert!(lines[5].starts_with("pairs "), "{text}");
    let corrupt = |line: usize, with: &str| {
        let mut l = lines.clone();
        l[line - 1] = with;
        let bad = dir.path().join(format!("bad-{line}.txt"));
        std::fs::write(&bad, l.join("\n")).unwrap();
        Correspondence::load(&bad).unwrap_err()
    };
    for (line, with, needle) in [
        (
            1,
            "meshmorph-correspondence 9",
            "not a meshmorph correspondence",
        ),
        (
            3,
            "source 10 x 0",
            "expected `source VERTICES TRIANGLES HASH`",
        ),
        (
            4,
            "source 1 2 3",
            "expected `target VERTICES TRIANGLES HASH`",
        ),
        (5, "alignment 1 2", "expected `alignment SCALE"),
        (6, "pairs many", "expected `pairs COUNT`"),
        (9, "12 abc", "expected `SOURCE TARGET`, found `12 abc`"),
        (10, "1 2 3", "expected `SOURCE TARGET`"),
        (11, "0 99999", "triangle pair 0 99999 is out of range"),
    ] {
        let e = corrupt(line, with);
        assert!(
            matches!(&e, Error::Parse { line: Some(l), .. } if *l == line),
            "line {line}: {e:?}"
        );
        assert_error(e, is_parse, &[&format!("line {line}"), needle]);
    }
    // Truncated: no line to name, but the message says what is missing.
    let short = dir.path().join("short.txt");
    std::fs::write(&short, lines[..9].join("\n")).unwrap();
    assert_error(
        Correspondence::load(&short).unwrap_err(),
        is_parse,
        &["short.txt", "ends before all pairs are listed"],
    );
    // An extra line after the pairs.
    let long = dir.path().join("long.txt");
    std::fs::write(&long, format!("{text}0 0\n")).unwrap();
    assert_error(
        Correspondence::load(&long).unwrap_err(),
        is_parse,
        &[&format!("line {}", lines.len() + 1), "more lines than"],
    );
}

/// A tube whose first cap triangle has zero area: the cap centre moved onto
/// the midpoint of the opposite edge.
fn tube_with_degenerate_triangle(spec: TubeSpec) -> (Mesh3, usize) {
    let m = spec.mesh();
    let n = spec.rings * spec.segments;
    let mut p = m.positions().to_vec();
    let (a, b) = (p[0], p[1]);
    p[n] = std::array::from_fn(|i| 0.5 * (a[i] + b[i]));
    let first_cap = 2 * (spec.rings - 1) * spec.segments;
    (m.with_positions(p).unwrap(), first_cap)
}

#[test]
fn degenerate_triangles_are_named_and_never_give_nan() {
    let (bad_s, ts) = tube_with_degenerate_triangle(THIN);
    let (bad_t, tt) = tube_with_degenerate_triangle(THICK);
    let (s0, t0) = (THIN.mesh(), THICK.mesh());
    let markers = tube_markers(THIN, THICK, &tube_picks(THIN, 4));
    let opts = CorrespondOptions::default();
    let source_msg =
        format!("1 degenerate (zero-area) triangle in the source reference: triangle {ts}");
    let target_msg =
        format!("1 degenerate (zero-area) triangle in the target reference: triangle {tt}");
    let e = correspond(&bad_s, &t0, &markers, &opts).unwrap_err();
    assert_error(e, is_degenerate, &[&source_msg]);
    let e = correspond(&s0, &bad_t, &markers, &opts).unwrap_err();
    assert_error(e, is_degenerate, &[&target_msg]);

    let pairs: Vec<[u32; 2]> = (0..s0.num_triangles().min(t0.num_triangles()) as u32)
        .map(|t| [t, t])
        .collect();
    let c = Correspondence::new(pairs.clone(), &bad_s, &t0);
    let e = Transfer::new(&bad_s, &t0, &c, &TransferOptions::default()).unwrap_err();
    assert_error(e, is_degenerate, &[&source_msg]);
    let c = Correspondence::new(pairs, &s0, &bad_t);
    let e = Transfer::new(&s0, &bad_t, &c, &TransferOptions::default()).unwrap_err();
    assert_error(e, is_degenerate, &[&target_msg]);

    // Many: the message counts them all and lists the first few.
    let m = tube(4.0, 0.5, 5, 8);
    let squashed = mapped(&m, |[x, _, _]| [x, 0.0, 0.0]);
    let e = self_transfer_err(&squashed);
    assert_error(
        e,
        is_degenerate,
        &[&format!(
            "{} degenerate (zero-area) triangles in the source reference: triangles 0, 1, 2, 3, 4, ...",
            m.num_triangles()
        )],
    );

    // Degenerate triangles in a pose are allowed and give finite output,
    // whether one triangle collapses or the whole pose is one point.
    let result = tube_correspondence(THIN, THICK);
    let transfer = Transfer::new(
        &s0,
        &t0,
        &result.correspondence,
        &TransferOptions::default(),
    )
    .unwrap();
    let point = mapped(&s0, |_| [1.0, 2.0, 3.0]);
    let line = mapped(&s0, |[x, _, _]| [x, 0.0, 0.0]);
    for (name, pose) in [
        ("one triangle", &bad_s),
        ("a point", &point),
        ("a line", &line),
    ] {
        let out = transfer.apply(pose).unwrap();
        assert!(all_finite(&out), "{name}: non-finite output");
    }
    // A pose collapsed to a point collapses the target to that point
    // (brought onto the target by the alignment).
    let out = transfer.apply(&point).unwrap();
    let at = result.correspondence.alignment().apply([1.0, 2.0, 3.0]);
    assert!(max_distance(&out, &vec![at; out.len()]) < 1e-9, "point");
}

fn self_transfer_err(m: &Mesh3) -> Error {
    Transfer::new(
        m,
        m,
        &Correspondence::identity(m),
        &TransferOptions::default(),
    )
    .unwrap_err()
}

#[test]
fn nan_coordinates_are_refused() {
    let m = tube(4.0, 0.5, 3, 4);
    let mut p = m.positions().to_vec();
    p[5][1] = f64::NAN;
    assert_error(
        Mesh3::new(p.clone(), m.triangles().to_vec()).unwrap_err(),
        is_invalid_mesh,
        &["vertex 5", "not a finite number"],
    );
    assert_error(
        m.with_positions(p.clone()).unwrap_err(),
        is_invalid_mesh,
        &["vertex 5"],
    );
    p[5][1] = f64::INFINITY;
    assert_error(
        m.with_positions(p).unwrap_err(),
        is_invalid_mesh,
        &["vertex 5"],
    );
    // From a file.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nan.obj");
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 NaN 0\nf 1 2 3\n").unwrap();
    assert_error(
        io::read_mesh(&path).unwrap_err(),
        is_parse,
        &["nan.obj", "line 3", "not a finite number"],
    );
    // Pinned positions too.
    let opts = TransferOptions::default().with_pins(vec![(0, [0.0, f64::NAN, 0.0])]);
    assert_error(
        Transfer::new(&m, &m, &Correspondence::identity(&m), &opts).unwrap_err(),
        is_invalid_argument,
        &["pinned target vertex 0 has a non-finite position"],
    );
}

// ---------------------------------------------------------------------------
// 5. A bend carries over to a thicker, differently tessellated tube
// ---------------------------------------------------------------------------

/// The angle (degrees) by which a tube's axis turns, from the circle through
/// the centroids of its first, middle and last rings: the angle those
/// centroids span seen from the circle's centre. [`bend`] puts every ring
/// centroid on one arc, so this is the bend angle at any tessellation.
/// Also the largest |z| of the ring centroids (bends are about z: the axis
/// should stay in z = 0).
fn arc_angle(p: &[P3], spec: TubeSpec) -> (f64, f64) {
    let c = |r| ring_centroid(p, spec.segments, r);
    let n = spec.rings;
    let (a, b, e) = (c(0), c(n / 2), c(n - 1));
    // Circumcentre of a, b, e in the xy plane.
    let (bx, by, ex, ey) = (b[0] - a[0], b[1] - a[1], e[0] - a[0], e[1] - a[1]);
    let d = 2.0 * (bx * ey - by * ex);
    let (b2, e2) = (bx * bx + by * by, ex * ex + ey * ey);
    let centre = [
        a[0] + (ey * b2 - by * e2) / d,
        a[1] + (bx * e2 - ex * b2) / d,
        0.0,
    ];
    let turn = |u: P3, v: P3| {
        let (u, v) = (sub(u, centre), sub(v, centre));
        (u[0] * v[1] - u[1] * v[0])
            .atan2(u[0] * v[0] + u[1] * v[1])
            .to_degrees()
    };
    let z = (0..n).map(|r| c(r)[2].abs()).fold(0.0, f64::max);
    (turn(a, b) + turn(b, e), z)
}

#[test]
fn bends_carry_over_to_a_thicker_tube() {
    // (source, target, tolerance in degrees): a source of four segments
    // along its length carries the bend less faithfully. Onto a target
    // coarser than its source (13 rings for 25), the correspondence, which
    // keeps each source triangle's shape up to a turn and a size, slides
    // along the axis by a few hundredths of a target ring at the ends: the
    // axis then turns by up to 1 % more than the source's.
    for (source, target, tolerance) in [
        (THIN, THICK, 1.0),
        (
            THICK,
            TubeSpec {
                radius: 0.8,
                rings: 13,
                segments: 12,
                ..THIN
            },
            2.0,
        ),
        (COARSE, THICK, 4.0),
    ] {
        let (s0, t0) = (source.mesh(), target.mesh());
        let result = tube_correspondence(source, target);
        let transfer = Transfer::new(
            &s0,
            &t0,
            &result.correspondence,
            &TransferOptions::default(),
        )
        .unwrap();
        let what = format!(
            "{}x{} -> {}x{}",
            source.rings, source.segments, target.rings, target.segments
        );
        for deg in [20.0, 45.0, 90.0, 135.0, 180.0] {
            let pose = bend(&s0, source.length, f64::to_radians(deg));
            let out = transfer.apply(&pose).unwrap();
            assert!(all_finite(&out), "{what}, {deg}°: non-finite output");
            let (got, z) = arc_angle(&out, target);
            let ideal = bend(&t0, target.length, f64::to_radians(deg));
            let (exact, _) = arc_angle(ideal.positions(), target);
            assert!((exact - deg).abs() < 1e-9, "the measure: {exact} for {deg}");
            let d = max_distance(&out, ideal.positions()) / t0.bounding_box_diagonal();
            println!(
                "{what}, {deg}°: the axis turns by {got:.2}°, max distance to the ideal bend \
                 {d:.4} of the diagonal"
            );
            assert!(
                (got - deg).abs() < tolerance,
                "{what}, {deg}°: the axis turns by {got:.2}°"
            );
            assert!(
                z < 1e-3 * t0.bounding_box_diagonal(),
                "{what}, {deg}°: the axis leaves z = 0 by {z:e}"
            );
            assert!(d < 0.05, "{what}, {deg}°: {d} from the ideal bend");
        }
    }
}

#[test]
fn correspondence_reports_progress_and_pairs_the_tubes() {
    let (s0, t0) = (THIN.mesh(), THICK.mesh());
    let markers = tube_markers(THIN, THICK, &tube_picks(THIN, 4));
    let opts = CorrespondOptions::default();
    let mut steps = Vec::new();
    let result =
        meshmorph::correspond_with_progress(&s0, &t0, &markers, &opts, &mut |k| steps.push(k))
            .unwrap();
    assert_eq!(steps, (1..=opts.steps()).collect::<Vec<_>>());
    // The deformed source lies on the target: every vertex near the thick radius.
    for p in result.deformed_source.positions() {
        let r = p[1].hypot(p[2]);
        let on_cap = p[0].abs() < 1e-6 || (p[0] - 4.0).abs() < 1e-6;
        assert!(
            on_cap || (r - THICK.radius).abs() < 0.02,
            "deformed vertex {p:?} at radius {r}"
        );
    }
    // Each pair joins triangles that face the same way around the axis.
    let c = &result.correspondence;
    assert!(
        c.unmatched_source() * 10 < s0.num_triangles(),
        "{}",
        c.unmatched_source()
    );
    for &[s, t] in c.pairs() {
        let cs = mean(&s0.corners(s as usize));
        let ct = mean(&t0.corners(t as usize));
        assert!((cs[0] - ct[0]).abs() < 0.3, "pair {s} {t}: {cs:?} {ct:?}");
    }
}

// ---------------------------------------------------------------------------
// 6. Loose vertices, bad options, parts and what stays still
// ---------------------------------------------------------------------------

/// A source with a vertex no triangle uses (as OBJ files often have) still
/// corresponds: the vertex stays where it is, the pairs are the same.
#[test]
fn unused_source_vertices_do_not_stop_the_correspondence() {
    let plain = tube_correspondence(THIN, THICK);
    let source = THIN.mesh();
    let mut p = source.positions().to_vec();
    p.push([10.0, 10.0, 10.0]);
    let with_extra = Mesh3::new(p, source.triangles().to_vec()).unwrap();
    let markers = tube_markers(THIN, THICK, &tube_picks(THIN, 4));
    let r = correspond(
        &with_extra,
        &THICK.mesh(),
        &markers,
        &CorrespondOptions::default(),
    )
    .unwrap();
    assert_eq!(r.correspondence.pairs(), plain.correspondence.pairs());
    // An unused vertex only follows the markers' alignment.
    let moved = r.marker_fit.apply([10.0, 10.0, 10.0]);
    assert!(max_distance(&[*r.deformed_source.positions().last().unwrap()], &[moved]) < 1e-12);
}

#[test]
fn options_that_cannot_be_solved_are_refused() {
    let markers = tube_markers(THIN, THICK, &tube_picks(THIN, 4));
    for (options, needle) in [
        (
            CorrespondOptions::default().with_weights(1.0, 0.0),
            "identity weight",
        ),
        (
            CorrespondOptions::default().with_closest_weights(vec![1.0, -2.0]),
            "closest-point weight",
        ),
        (
            CorrespondOptions::default().with_match_threshold(f64::NAN),
            "match threshold",
        ),
    ] {
        let e = correspond(&THIN.mesh(), &THICK.mesh(), &markers, &options).unwrap_err();
        assert_error(e, is_invalid_argument, &[needle]);
    }
}

/// A marker on a vertex that no triangle uses (a loose `v` line) is refused,
/// naming the marker, its line and the vertex: pinning it would throw the
/// alignment off.
#[test]
fn markers_on_vertices_in_no_triangle_are_refused() {
    let with_loose = |m: &Mesh3| {
        let mut p = m.positions().to_vec();
        p.push([100.0, 100.0, 100.0]);
        Mesh3::new(p, m.triangles().to_vec()).unwrap()
    };
    let (s0, t0) = (THIN.mesh(), THICK.mesh());
    let (s1, t1) = (with_loose(&s0), with_loose(&t0));
    let (ls, lt) = (s0.num_vertices() as u32, t0.num_vertices() as u32);
    let good = tube_markers(THIN, THICK, &tube_picks(THIN, 4))
        .vertex_pairs()
        .unwrap();
    let text = |extra: [u32; 2]| {
        good.iter()
            .chain([&extra])
            .map(|p| format!("{} {}\n", p[0], p[1]))
            .collect::<String>()
    };
    let line = good.len() + 1;
    let path = Path::new("loose.txt");
    let options = CorrespondOptions::default();
    let refused = |source: &Mesh3, target: &Mesh3, markers: &Markers| {
        let found = correspond(source, target, markers, &options);
        found.map(|_| ()).unwrap_err()
    };
    for (source, target, extra, needle) in [
        (
            &s0,
            &t1,
            [5, lt],
            format!("target vertex {lt} is in no triangle"),
        ),
        (
            &s1,
            &t0,
            [ls, 5],
            format!("source vertex {ls} is in no triangle"),
        ),
    ] {
        let markers = Markers::parse(&text(extra), path, VertexNumbering::FromZero).unwrap();
        let e = refused(source, target, &markers);
        assert!(
            matches!(e, Error::InvalidMarker { marker, line: Some(l), .. }
                if marker == good.len() && l == line),
            "{e:?}"
        );
        assert_error(
            e,
            is_invalid_argument,
            &[&format!("`loose.txt`, line {line}"), &needle],
        );
        // In memory: named by its index.
        let mut pairs = good.clone();
        pairs.push(extra);
        let e = refused(source, target, &Markers::new(pairs));
        assert_error(
            e,
            is_invalid_argument,
            &[&format!("marker {}", good.len()), &needle],
        );
    }
    // The loose vertices themselves do not matter when no marker names them.
    let plain = found_by(&s0, &t0, &Markers::new(good.clone())).correspondence;
    let loose = found_by(&s1, &t1, &Markers::new(good)).correspondence;
    assert_eq!(plain.pairs(), loose.pairs());
}

/// The length along x of the vertices `range` of `p`.
fn extent_x(p: &[P3], range: std::ops::Range<usize>) -> f64 {
    let xs = p[range].iter().map(|q| q[0]);
    xs.clone().fold(f64::MIN, f64::max) - xs.fold(f64::MAX, f64::min)
}

/// A separate part of the target with exactly half of its area paired (one
/// triangle of every rectangle of an open tube) follows its partners, in
/// any units: the result scales with the target at 1, 1000 and 1e-3. With
/// one pair fewer it is carried rigidly, again in any units.
#[test]
fn a_part_with_half_its_area_paired_is_decided_the_same_in_any_units() {
    let body = THIN.mesh();
    for (rings, segments) in [(4, 6), (5, 7), (3, 10), (6, 9)] {
        let part = mapped(&open_tube(1.0, 0.3, rings, segments), |p| {
            [p[0] + 1.5, p[1] + 1.2, p[2]]
        });
        let s0 = union(&body, &part);
        let (nb, np) = (body.num_triangles() as u32, part.num_triangles() as u32);
        let part_vertices = body.num_vertices()..s0.num_vertices();
        // The part stretches to 1.5 times its length in the pose.
        let pose = s0.with_positions(
            s0.positions()
                .iter()
                .enumerate()
                .map(|(v, &p)| {
                    if part_vertices.contains(&v) {
                        [1.5 + 1.5 * (p[0] - 1.5), p[1], p[2]]
                    } else {
                        p
                    }
                })
                .collect(),
        );
        let pose = pose.unwrap();
        let rest_length = extent_x(s0.positions(), part_vertices.clone());
        for (paired_in_part, carried) in [(np / 2, false), (np / 2 - 1, true)] {
            let mut pairs: Vec<[u32; 2]> = (0..nb).map(|t| [t, t]).collect();
            // The first triangle of each rectangle: exactly half the area.
            pairs.extend((0..paired_in_part).map(|k| [nb + 2 * k, nb + 2 * k]));
            let mut first: Option<Vec<P3>> = None;
            for scale in [1.0, 1000.0, 1e-3] {
                let t0 = mapped(&s0, |p| p.map(|x| x * scale));
                let alignment = meshmorph::Similarity::fit(s0.positions(), t0.positions()).unwrap();
                let c = Correspondence::new(pairs.clone(), &s0, &t0).with_alignment(alignment);
                let out = Transfer::new(&s0, &t0, &c, &TransferOptions::default())
                    .unwrap()
                    .apply(&pose)
                    .unwrap();
                let out: Vec<P3> = out.iter().map(|p| p.map(|x| x / scale)).collect();
                let what = format!("{rings}x{segments}, {paired_in_part} of {np} paired, x{scale}");
                let stretch = extent_x(&out, part_vertices.clone()) / rest_length;
                if carried {
                    assert!((stretch - 1.0).abs() < 1e-6, "{what}: stretched {stretch}");
                } else {
                    assert!(stretch > 1.2, "{what}: stretched only {stretch}");
                }
                match &first {
                    None => first = Some(out),
                    Some(f) => {
                        let d = max_distance(&out, f) / s0.bounding_box_diagonal();
                        assert!(d < 1e-6, "{what}: {d:e} of the diagonal from x1");
                    }
                }
            }
        }
    }
}

#[test]
fn what_stays_still_in_the_source_stays_still_in_the_target() {
    // The source's far half bends by 60 degrees, its near half stays: the
    // target's near end stays where it is (a skull while the jaw opens),
    // although the whole target's shape changes.
    let corr = tube_correspondence(THIN, THICK).correspondence;
    let (source, target) = (THIN.mesh(), THICK.mesh());
    let transfer = Transfer::new(&source, &target, &corr, &TransferOptions::default()).unwrap();
    let half = THIN.length / 2.0;
    let bent_half = mapped(&source, |[x, y, z]| {
        if x <= half {
            return [x, y, z];
        }
        let (angle, r) = (PI / 3.0, half / (PI / 3.0));
        let phi = angle * (x - half) / half;
        let rho = r - y;
        [half + rho * phi.sin(), r - rho * phi.cos(), z]
    });
    let out = transfer.apply(&bent_half).unwrap();
    let rest = target.positions();
    let diagonal = target.bounding_box_diagonal();
    let near = norm(sub(
        ring_centroid(&out, THICK.segments, 0),
        ring_centroid(rest, THICK.segments, 0),
    ));
    let far = norm(sub(
        ring_centroid(&out, THICK.segments, THICK.rings - 1),
        ring_centroid(rest, THICK.segments, THICK.rings - 1),
    ));
    eprintln!(
        "near end moved {:.2e}, far end {:.2e} of the diagonal",
        near / diagonal,
        far / diagonal
    );
    assert!(far > 0.1 * diagonal);
    assert!(near < 1e-3 * diagonal);
}

#[test]
fn a_ball_carried_in_a_pipe_goes_to_one_place_whatever_the_rounding() {
    // A ball centred on the target pipe's axis is carried by the pipe's
    // vertices around it, whole rings equally near. The target in single
    // precision (as a float PLY holds it) must carry it to the same place
    // up to that rounding: taking 4 of a ring's vertices by the last bits
    // of their coordinates moved it by 0.15 % of the diagonal.
    let s0 = THIN.mesh();
    let exact = union(&THICK.mesh(), &octahedron([3.5, 0.0, 0.0], 0.2));
    let single = mapped(&exact, |p| p.map(|x| f64::from(x as f32)));
    let markers = tube_markers(THIN, THICK, &tube_picks(THIN, 4));
    let pose = bend(&s0, 4.0, 1.2);
    let carried_ball = |target: &Mesh3| {
        let result = correspond(&s0, target, &markers, &CorrespondOptions::default()).unwrap();
        let transfer =
            Transfer::new(&s0, target, &result.correspondence, &Default::default()).unwrap();
        assert_eq!(transfer.carried_parts(), 1);
        let out = transfer.apply(&pose).unwrap();
        out[out.len() - 6..].to_vec()
    };
    let d = max_distance(&carried_ball(&exact), &carried_ball(&single));
    assert!(
        d < 1e-5 * exact.bounding_box_diagonal(),
        "the ball moves by {d:.2e} with the rounding"
    );
}

#[test]
fn without_markers_shapes_that_stand_alike_correspond_and_others_are_refused() {
    let (source, target) = (THIN.mesh(), THICK.mesh());
    // The target moved and scaled, but standing as the source does.
    let moved = mapped(&target, |p| {
        [2.0 * p[0] + 3.0, 2.0 * p[1] - 1.0, 2.0 * p[2] + 5.0]
    });
    let none = Markers::new(Vec::new());
    let options = CorrespondOptions::default();
    let found = correspond(&source, &moved, &none, &options).unwrap();
    assert!(found.marker_residuals.is_empty());
    let marked = tube_correspondence(THIN, THICK);
    // The bent source carried over with each correspondence: the same
    // bend (the target's moved copy brought back onto the target).
    let pose = bend(&source, THIN.length, 0.5 * PI);
    let result = |c: &Correspondence, target: &Mesh3| {
        Transfer::new(&source, target, c, &TransferOptions::default())
            .unwrap()
            .apply(&pose)
            .unwrap()
    };
    let unmarked = result(&found.correspondence, &moved);
    let unmarked: Vec<P3> = unmarked
        .iter()
        .map(|p| [(p[0] - 3.0) / 2.0, (p[1] + 1.0) / 2.0, (p[2] - 5.0) / 2.0])
        .collect();
    let with_markers = result(&marked.correspondence, &target);
    assert_close(&unmarked, &with_markers, &target, 0.01, "without markers");
    // Lying across the source's axis, the target does not stand alike: refused.
    let across = rigid(
        &target,
        &rotation([0.0, 0.0, 1.0], 0.5 * PI),
        [2.0, -2.0, 0.0],
    );
    let e = correspond(&source, &across, &none, &options).unwrap_err();
    assert_error(
        e,
        |e| matches!(e, Error::PoorFit(_)),
        &[
            "without markers",
            "found no partner",
            "give at least 3 markers",
        ],
    );
    // One or two markers fix nothing: refused as before.
    let one = Markers::on_surfaces(marked_pairs(1));
    let e = correspond(&source, &target, &one, &options).unwrap_err();
    assert_error(
        e,
        |e| matches!(e, Error::InvalidArgument(_)),
        &["1 marker pair given", "or none"],
    );
}

/// The first `n` marker pairs of the usual thin-to-thick tube markers.
fn marked_pairs(n: usize) -> Vec<[meshmorph::SurfacePoint; 2]> {
    tube_markers(THIN, THICK, &tube_picks(THIN, 4)).pairs()[..n].to_vec()
}
