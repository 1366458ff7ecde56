//! From two or more drawings to compatible meshes: outlines in, the same
//! triangles out, every one positively oriented in every mesh, ready for
//! [`Interpolator`](crate::Interpolator) and
//! [`Sequence`](crate::Sequence).
//!
//! The way, one file a step:
//!
//! 1. `drawing`: each drawing checked (loops simple, apart, holes inside)
//!    and oriented (outer loop counter-clockwise, holes clockwise);
//!    `anchors`: matched points sorted into those on the outlines and
//!    those inside.
//! 2. `boundary`: each drawing's outer loop matched to the first's by
//!    aligning their turning-angle signatures (dynamic time warping over
//!    every start), the union of both loops' points put on each; `holes`
//!    pairs the holes by where they sit once the outer loops are laid over
//!    each other, and each pair is matched the same way; `common` puts
//!    every pair's matched points on every drawing.
//! 3. `cuts`: each hole opened to the outer loop by a straight cut at the
//!    same matched points in both drawings, so both become disks with the
//!    same boundary.
//! 4. `disk`: each disk triangulated with no inside points (constrained
//!    Delaunay, `spade`); `overlay`: the two triangulations laid over
//!    each other as chords of one convex polygon (Aronov, Seidel and
//!    Souvaine 1993), which gives triangles valid in both drawings
//!    whatever the shapes.
//! 5. `improve`: compatible edge flips, splits and smoothing that raise
//!    the smallest angle and keep every triangle positive in every mesh.
//!
//! Before steps 3 and 4, `mapped` tries the first way: one drawing meshed
//! with good angles (constrained Delaunay refinement), mapped into the
//! others with the matched boundary and the anchors fixed and untangled
//! (Garanzha et al. 2021), the thinnest drawing's mesh first; anchors
//! inside are vertices of that mesh from the start, fixed at their points
//! in the others like the boundary, and when no drawing's mesh untangles
//! so, it is made again with rings of free points around each anchor
//! (no triangle then holds an anchor and another fixed point). It is kept
//! when every triangle is positive in every mesh, and the overlay is made
//! only when no drawing's mesh untangles. With three or more drawings the overlay is made for the
//! first two, and its mesh mapped into each further drawing (through the
//! first drawing's own pair with it, `carry`, where mapping alone turns a
//! triangle over).

#[doc(hidden)]
pub mod anchors;
#[doc(hidden)]
pub mod boundary;
#[doc(hidden)]
pub mod carry;
#[doc(hidden)]
pub mod common;
#[doc(hidden)]
pub mod cuts;
#[doc(hidden)]
pub mod disk;
#[doc(hidden)]
pub mod drawing;
#[doc(hidden)]
pub mod energy;
#[doc(hidden)]
pub mod geometry;
#[doc(hidden)]
pub mod holes;
#[doc(hidden)]
pub mod improve;
#[doc(hidden)]
pub mod lbfgs;
#[doc(hidden)]
pub mod mapped;
#[doc(hidden)]
pub mod mend;
#[doc(hidden)]
pub mod overlay;
#[doc(hidden)]
pub mod settle;
#[doc(hidden)]
pub mod untangle;
#[doc(hidden)]
pub mod untie;
#[doc(hidden)]
pub mod widest;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::Instant;

use rayon::prelude::*;

pub use drawing::Drawing;
pub use mend::FrameMender;
pub use untie::OutlineUntier;

use self::boundary::{match_loops, MatchedPoint, TieBreak};
use self::geometry::{dist, lerp, point_segment_distance, ArcLoop};
use self::overlay::OverlayVertex;
use crate::error::{Error, Result};
use crate::mesh::Mesh2;

/// A pair of points kept matched: `a` on the first drawing, `b` on the
/// second's. Either both on the outlines, on loops that pair (the outer
/// loop or a hole; points within 1 % of the drawing's size from its
/// outline are moved onto it), or both inside the shapes, where each is
/// a vertex of its mesh at exactly that point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anchor {
    /// The point on the first drawing.
    pub a: [f64; 2],
    /// The point on the second drawing.
    pub b: [f64; 2],
}

/// How the compatible meshes are made.
#[derive(Clone, Debug)]
pub struct OutlineOptions {
    /// Samples along each loop for the fine alignment of the outlines'
    /// signatures. Default 256: a start found to a fraction of 1/256 of
    /// the loop's length.
    pub samples: usize,
    /// Rounds of compatible flips and smoothing after the overlay (0: the
    /// overlay as it is). Default 12.
    pub improvement_rounds: usize,
    /// Triangles whose smallest angle (in either mesh) is below this many
    /// degrees have their longest inside edge split during the
    /// improvement. Default 20.
    pub target_angle_degrees: f64,
    /// Try the fast way first: the first drawing meshed with good angles
    /// and mapped into the second (untangled so that every triangle is
    /// positive), the overlay kept as the fallback. Default true.
    pub mapped_first: bool,
    /// L-BFGS steps of each mesh's relaxation after the compatible flips
    /// and splits, when the smallest angle is still below
    /// `target_angle_degrees` (its inside points moved to even out its
    /// angles, every triangle kept positive; 0: none). Default 200.
    pub relaxation_steps: usize,
    /// The smallest angle the first drawing's mesh is refined towards on
    /// the fast way, degrees. Default 25.
    pub mapped_angle_degrees: f64,
    /// The mapped meshes from the first drawing tried are kept without
    /// mapping from the others when every triangle is positive in all and
    /// their smallest angle is at least this many degrees; below it every
    /// drawing's mesh is tried as the source and the best kept. Default 10.
    pub accept_angle_degrees: f64,
    /// L-BFGS steps of each round that makes the map from one drawing's
    /// mesh to another's as rigid as it can be (inside points moved,
    /// boundary points that are not a drawing's own slid along its
    /// outline; the drawings' points and the anchors stay; 0: none). The
    /// steps are preconditioned by the energy's stiffness along each
    /// unknown, and settle within about 50 on the benchmark's pairs.
    /// Default 100.
    pub settle_steps: usize,
    /// After the settle, as many steps again on each map's robust distance
    /// from rigid motions ([`settle::settle`]): most triangles stay rigid
    /// and what must give gives in a few, such as the squeeze at an
    /// elbow's inner corner where a bent forearm hides part of the upper
    /// arm. For sprites, whose texture the inside's map carries
    /// ([`OutlineOptions::for_pictures`]; photos keep the smooth warp):
    /// on the demo's arm sprite it keeps 51 % of the texture within 10 %
    /// of rigid half-way instead of 43 % (seven anchors), 52 % instead of
    /// 20 % (five). Drawings show
    /// only their outlines, on which it is neither better nor worse
    /// (`outline_benchmark`: the edges' deviation 0.1 to 2.7 points either
    /// way, the smallest angles lower). Default false.
    pub rigid_parts: bool,
}

/// Which way the compatible meshes were made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutlinePath {
    /// The first drawing's refined mesh mapped into the second and
    /// untangled.
    Mapped,
    /// The overlay of both drawings' triangulations, then improved.
    Overlay,
}

impl Default for OutlineOptions {
    fn default() -> Self {
        Self {
            samples: 256,
            improvement_rounds: 12,
            target_angle_degrees: 20.0,
            relaxation_steps: 200,
            mapped_first: true,
            mapped_angle_degrees: 25.0,
            accept_angle_degrees: 10.0,
            settle_steps: 100,
            rigid_parts: false,
        }
    }
}

impl OutlineOptions {
    /// The defaults, with [`OutlineOptions::rigid_parts`]: how pictures'
    /// compatible meshes are made.
    pub fn for_pictures() -> Self {
        Self {
            rigid_parts: true,
            ..Self::default()
        }
    }
}

/// What [`compatible_meshes`] made, and how well.
#[derive(Clone, Debug)]
pub struct OutlineReport {
    /// Points of each drawing as stored (repeats removed).
    pub drawing_points: Vec<usize>,
    /// Points of the matched boundary (every loop), the same on both
    /// meshes: each drawing's own points and the other's carried over.
    pub boundary_points: usize,
    /// Anchors inside the shapes (vertices of every mesh).
    pub inside_anchors: usize,
    /// Mesh vertices neither on the boundary nor anchors (Steiner points).
    pub steiner_points: usize,
    /// Triangles of each mesh.
    pub triangles: usize,
    /// Smallest angle of any triangle in each mesh, degrees, after the
    /// improvement.
    pub min_angle_degrees: Vec<f64>,
    /// The same straight after the overlay, before the improvement, when
    /// the overlay was made.
    pub overlay_min_angle_degrees: Option<Vec<f64>>,
    /// Which way the meshes were made.
    pub path: OutlinePath,
    /// Wall-clock seconds for the whole call.
    pub seconds: f64,
}

impl std::fmt::Display for OutlineReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let join = |v: &[f64]| {
            v.iter()
                .map(|x| format!("{x:.2}"))
                .collect::<Vec<_>>()
                .join("/")
        };
        let points: Vec<String> = self.drawing_points.iter().map(|p| p.to_string()).collect();
        write!(
            f,
            "{} points, {} on the matched boundary, {} Steiner, {} triangles; smallest angle {} degrees by the {}",
            points.join(" + "),
            self.boundary_points,
            self.steiner_points,
            self.triangles,
            join(&self.min_angle_degrees),
            match self.path {
                OutlinePath::Mapped => "mapped mesh",
                OutlinePath::Overlay => "overlay",
            },
        )?;
        if self.inside_anchors > 0 {
            write!(f, "; {} anchors inside", self.inside_anchors)?;
        }
        if let Some(o) = &self.overlay_min_angle_degrees {
            write!(f, " (overlay before improvement {})", join(o))?;
        }
        write!(f, "; {:.1} ms", self.seconds * 1e3)
    }
}

/// Two meshes with the same triangles, one inside each drawing.
#[derive(Clone, Debug)]
pub struct CompatibleMeshes {
    /// The mesh inside the first drawing.
    pub a: Mesh2,
    /// The mesh inside the second drawing (same triangles as `a`).
    pub b: Mesh2,
    /// The matched boundary loops as vertex indices, the same in both
    /// meshes: the outer loop first (counter-clockwise), then the holes in
    /// the first drawing's order (clockwise).
    pub loops: Vec<Vec<u32>>,
    /// For each loop of the first drawing as given and each of its given
    /// points, the vertex at that point.
    pub given_a: Vec<Vec<u32>>,
    /// The same for the second drawing, its loops in its own order as
    /// given.
    pub given_b: Vec<Vec<u32>>,
    /// How it went.
    pub report: OutlineReport,
}

/// Snaps `p` onto the closest loop of `loops`: (loop, arc-length
/// fraction, point on the loop, distance).
pub(crate) fn snap(loops: &[Vec<[f64; 2]>], p: [f64; 2]) -> (usize, f64, [f64; 2], f64) {
    let mut best = (0, 0.0, p, f64::INFINITY);
    for (l, pts) in loops.iter().enumerate() {
        let arc = ArcLoop::new(pts);
        let n = pts.len();
        for i in 0..n {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            let d = point_segment_distance(p, a, b);
            if d < best.3 {
                let e = [b[0] - a[0], b[1] - a[1]];
                let len2 = e[0] * e[0] + e[1] * e[1];
                let s = (((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / len2).clamp(0.0, 1.0);
                let t = (arc.cumulative[i] + s * dist(a, b)) / arc.length();
                best = (l, t, lerp(a, b, s), d);
            }
        }
    }
    best
}

/// The guaranteed way for two drawings: the overlay of both drawings'
/// triangulations in a common convex domain: the positions in each and
/// the triangles.
fn overlay_pair(
    matched: &[Vec<MatchedPoint>],
    points_a: &[[f64; 2]],
    points_b: &[[f64; 2]],
) -> Result<Positioned> {
    let cuts = cuts::find_cuts(&matched[0], &matched[1..])?;
    let lengths: Vec<usize> = matched.iter().map(Vec::len).collect();
    let disk = disk::Disk::new(&lengths, &cuts);
    let tri_a = disk.triangulate(points_a, &[], "first drawing")?;
    let cut_points: Vec<[usize; 2]> = cuts
        .iter()
        .enumerate()
        .map(|(h, c)| [c.outer, disk.loop_start[h + 1] + c.hole])
        .collect();
    let shared = disk::shared_chords(&disk, &tri_a, points_b, &cut_points);
    let tri_b = match disk.triangulate(points_b, &shared, "second drawing") {
        Ok(t) => t,
        Err(_) => disk.triangulate(points_b, &[], "second drawing")?,
    };
    let over = overlay::overlay(disk.copies.len(), &tri_a, &tri_b);
    // Vertices: the boundary points, then the crossings.
    let mut pos_a = points_a.to_vec();
    let mut pos_b = points_b.to_vec();
    let mut vertex_of = Vec::with_capacity(over.vertices.len());
    for v in &over.vertices {
        match *v {
            OverlayVertex::Copy(c) => vertex_of.push(disk.copies[c] as u32),
            OverlayVertex::Crossing { a, s, b, r } => {
                let p = |c: usize| disk.copies[c];
                vertex_of.push(pos_a.len() as u32);
                pos_a.push(lerp(points_a[p(a.0)], points_a[p(a.1)], s));
                pos_b.push(lerp(points_b[p(b.0)], points_b[p(b.1)], r));
            }
        }
    }
    let triangles: Vec<[u32; 3]> = over
        .triangles
        .iter()
        .map(|t| t.map(|v| vertex_of[v as usize]))
        .collect();
    Ok((vec![pos_a, pos_b], triangles))
}

/// The compatible improvement of meshes whose first `num_fixed` vertices
/// (the outline points, then the anchors inside) stay where they are,
/// adding at most `extra` vertices besides those that split the chords
/// between fixed points ([`improve::split_chords`]): the smallest angles
/// (radians) before and after.
fn improve_set(
    meshes: &mut [Vec<[f64; 2]>],
    triangles: &mut Vec<[u32; 3]>,
    num_fixed: usize,
    extra: usize,
    options: &OutlineOptions,
) -> (Vec<f64>, Vec<f64>) {
    let mut fixed: Vec<bool> = (0..meshes[0].len()).map(|v| v < num_fixed).collect();
    let mut pair = improve::Pair {
        meshes,
        triangles,
        fixed: &mut fixed,
    };
    improve::split_chords(&mut pair);
    let before = improve::smallest_angles(&pair);
    improve::improve(
        &mut pair,
        options.improvement_rounds,
        options.target_angle_degrees.to_radians(),
        extra,
    );
    // Each mesh's inside points relaxed on their own (the meshes share
    // only their triangles), then flipped and split again; kept when the
    // smallest angle rises.
    let improved = improve::smallest_angles(&pair);
    if options.relaxation_steps > 0 && worst(&improved) < options.target_angle_degrees.to_radians()
    {
        let saved = (
            pair.meshes.to_vec(),
            pair.triangles.clone(),
            pair.fixed.clone(),
        );
        // (Each mesh on its own: on a core that is free, if one is.)
        let triangles = &*pair.triangles;
        pair.meshes.par_iter_mut().for_each(|mesh| {
            mapped::relax(mesh, triangles, num_fixed, options.relaxation_steps);
        });
        improve::improve(
            &mut pair,
            options.improvement_rounds,
            options.target_angle_degrees.to_radians(),
            extra / 2,
        );
        if worst(&improve::smallest_angles(&pair)) <= worst(&improved) {
            pair.meshes.clone_from_slice(&saved.0);
            (*pair.triangles, *pair.fixed) = (saved.1, saved.2);
        }
    }
    (before, improve::smallest_angles(&pair))
}

/// How round a drawing is, from its matched boundary: its area over that
/// of the circle with its outer loop's length (1 for a circle, near 0 for
/// a thin band).
fn roundness(points: &[[f64; 2]], loop_start: &[usize]) -> f64 {
    let outer = &points[..loop_start[1]];
    let length: f64 = (0..outer.len())
        .map(|i| dist(outer[i], outer[(i + 1) % outer.len()]))
        .sum();
    let area: f64 = loop_start
        .windows(2)
        .map(|w| 0.5 * geometry::signed_area2(&points[w[0]..w[1]]))
        .sum();
    4.0 * std::f64::consts::PI * area.abs() / (length * length)
}

/// Compatible meshes as they are made: the positions in each drawing and
/// the shared triangles.
pub(crate) type Positioned = (Vec<Vec<[f64; 2]>>, Vec<[u32; 3]>);

/// The smallest of several angles.
pub fn worst(angles: &[f64]) -> f64 {
    angles.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Compatible meshes being chosen: positions in each drawing, the
/// triangles, the smallest angles (radians) and the way taken.
struct Candidate {
    meshes: Vec<Vec<[f64; 2]>>,
    triangles: Vec<[u32; 3]>,
    angles: Vec<f64>,
    path: OutlinePath,
    overlay_angles: Option<Vec<f64>>,
    /// The drawing whose mesh the others' were mapped from (the first
    /// for the overlay).
    source: usize,
}

/// Two compatible meshes, one inside each drawing: the same triangles,
/// every one positively oriented in both, every given outline point a
/// vertex at exactly its position, each mesh's boundary its drawing's
/// loops. The boundary correspondence is found automatically
/// (invariant to where each loop starts, its direction, and the drawings'
/// position, scale and rotation); `anchors` are kept matched exactly,
/// on the outlines or inside the shapes.
///
/// [`compatible_set`] for two drawings; see it for the way, the errors and
/// the cost.
///
/// # Errors
/// As [`compatible_set`].
pub fn compatible_meshes(
    a: &Drawing,
    b: &Drawing,
    anchors: &[Anchor],
    options: &OutlineOptions,
) -> Result<CompatibleMeshes> {
    let anchors: Vec<Vec<[f64; 2]>> = anchors.iter().map(|x| vec![x.a, x.b]).collect();
    let set = compatible_set(&[a.clone(), b.clone()], &anchors, options)?;
    let mut meshes = set.meshes.into_iter();
    let mut given = set.given.into_iter();
    let (Some(mesh_a), Some(mesh_b), Some(given_a), Some(given_b)) =
        (meshes.next(), meshes.next(), given.next(), given.next())
    else {
        unreachable!("compatible_set returns one mesh per drawing")
    };
    Ok(CompatibleMeshes {
        a: mesh_a,
        b: mesh_b,
        loops: set.loops,
        given_a,
        given_b,
        report: set.report,
    })
}

/// Meshes with the same triangles, one inside each of two or more
/// drawings, for a keyframe sequence through them all.
#[derive(Clone, Debug)]
pub struct CompatibleSet {
    /// The mesh inside each drawing, in the drawings' order (the same
    /// triangles in all).
    pub meshes: Vec<Mesh2>,
    /// The matched boundary loops as vertex indices, the same in every
    /// mesh: the outer loop first (counter-clockwise), then the holes in
    /// the first drawing's order (clockwise).
    pub loops: Vec<Vec<u32>>,
    /// For each drawing, each of its loops as given and each of their
    /// given points, the vertex at that point.
    pub given: Vec<Vec<Vec<u32>>>,
    /// The vertex of each anchor (for one on an outline, the boundary
    /// vertex at it).
    pub anchors: Vec<u32>,
    /// How it went.
    pub report: OutlineReport,
}

/// Whether a pass of the mapped way takes up each source's untangling
/// where the pass before left it, or starts it again from the placed
/// mesh.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Start {
    TakenUp,
    Afresh,
}

/// Meshes with the same triangles inside two or more drawings: every
/// triangle positively oriented in every mesh, every given outline point a
/// vertex at exactly its position, each mesh's boundary its drawing's
/// loops. Each drawing's outlines are matched to the first's
/// automatically (invariant to where each loop starts, its direction, and
/// the drawings' position, scale and rotation), and the matched points of
/// every pair put on every drawing. `anchors` hold one point per drawing
/// each and are kept matched exactly: on the outlines (all of its points
/// within 1 % of the drawing's size from an outline, on loops that pair)
/// or inside the shapes (all of them), where each becomes a vertex at
/// exactly that point in every mesh.
///
/// The triangles come first from a refined mesh of one drawing mapped
/// into the others and untangled ([`OutlinePath::Mapped`]): the thinnest
/// drawing's mesh first, then each other's while the smallest angle is
/// below [`OutlineOptions::accept_angle_degrees`], and when no drawing's
/// mesh untangles quickly, again with a patient untangling, and with
/// anchors inside, again with rings of free points around each. Only when
/// that fails too do they come from the overlay
/// of Aronov, Seidel and Souvaine (1993) of the first drawing with each
/// other ([`OutlinePath::Overlay`]), which cannot fail on drawings that
/// pass [`Drawing::new`] and whose holes can be cut straight to the outer
/// loop at matched points in both; with three or more drawings the pairs'
/// meshes are laid over each other in the first drawing, and anchors
/// inside are put into the overlay and moved to their places in the other
/// drawings by the untangling. Compatible flips, splits and smoothing then
/// raise the smallest angle (reported in
/// [`OutlineReport::min_angle_degrees`], the way taken in
/// [`OutlineReport::path`]).
///
/// # Errors
/// [`Error::IncompatibleDrawings`] when fewer than two drawings are given,
/// the drawings have different numbers of loops, an anchor has not one
/// point per drawing, is on the outline in one drawing and inside (or
/// outside) in another, its outline points lie on loops that do not pair,
/// anchors come in different orders on two outlines, a hole cannot be cut
/// straight to the outer loop, or anchors inside cannot be reached without
/// turning a triangle over.
///
/// # Performance
/// Two like 500-point outlines take under 20 ms on the mapped way, on one
/// core; unlike ones (a star and a thin spiral band) about 0.4 s, a third
/// of it in the patient untangling and a third in the improvement. The
/// overlay grows with how differently the two shapes' triangulations run
/// (up to quadratically in the points: seconds for two unlike 500-point
/// outlines).
pub fn compatible_set(
    drawings: &[Drawing],
    anchors: &[Vec<[f64; 2]>],
    options: &OutlineOptions,
) -> Result<CompatibleSet> {
    let start = Instant::now();
    let count = drawings.len();
    if count < 2 {
        return Err(Error::IncompatibleDrawings(format!(
            "{count} drawing given: compatible meshes need two or more"
        )));
    }
    let first = &drawings[0];
    for (k, d) in drawings.iter().enumerate().skip(1) {
        if d.num_loops() != first.num_loops() {
            let holes = |d: &Drawing| match d.num_loops() - 1 {
                0 => "no hole".to_string(),
                1 => "1 hole".to_string(),
                h => format!("{h} holes"),
            };
            return Err(Error::IncompatibleDrawings(format!(
                "the first drawing has {} loop{} ({}) but drawing {} has {} ({}): every drawing needs the same number of holes",
                first.num_loops(),
                if first.num_loops() == 1 { "" } else { "s" },
                holes(first),
                k + 1,
                d.num_loops(),
                holes(d)
            )));
        }
    }
    let placed = anchors::place(drawings, anchors)?;
    // Each drawing after the first matched to the first.
    let mut matched_pairs: Vec<Vec<Vec<MatchedPoint>>> = Vec::with_capacity(count - 1);
    let mut pairings: Vec<Vec<usize>> = vec![(0..first.num_loops()).collect()];
    for (k, d) in drawings.iter().enumerate().skip(1) {
        let on_loops = |l: usize, m: usize| placed.on_loops(k, l, m);
        let outer = match_loops(
            &first.loops()[0],
            &d.loops()[0],
            &on_loops(0, 0)?,
            options.samples,
            Some(&if first.num_loops() > 1 {
                TieBreak::Holes(&first.loops()[1..], &d.loops()[1..])
            } else {
                TieBreak::Turn
            }),
        )?;
        let frame = holes::Similarity::of_outer(&outer);
        let pairing = holes::pair_holes(&first.loops()[1..], &d.loops()[1..], &frame);
        let mut matched = vec![outer];
        for (h, &g) in pairing.iter().enumerate() {
            matched.push(match_loops(
                &first.loops()[h + 1],
                &d.loops()[g + 1],
                &on_loops(h + 1, g + 1)?,
                options.samples,
                Some(&TieBreak::Frame(&frame)),
            )?);
        }
        pairings.push(
            std::iter::once(0)
                .chain(pairing.iter().map(|g| g + 1))
                .collect(),
        );
        matched_pairs.push(matched);
    }
    let boundary = common::common_boundary(first.loops(), &matched_pairs);
    let n = boundary.loop_start[boundary.loop_start.len() - 1];
    let inside = placed.inside.len();
    // Every drawing's fixed points: the boundary, then the anchors inside.
    let fixed: Vec<Vec<[f64; 2]>> = (0..count)
        .map(|d| {
            let mut p = boundary.points[d].clone();
            p.extend(placed.inside.iter().map(|a| a[d]));
            p
        })
        .collect();
    let accept = options.accept_angle_degrees.to_radians();
    let mut best: Option<Candidate> = None;
    if options.mapped_first {
        // The thinnest drawing first (smallest area for its outline's
        // length): its mesh, mapped into a fatter drawing, has room to
        // spread, where a fat drawing's mesh squeezed into a thin band
        // often cannot be untangled. A quick try from every drawing, then,
        // when none gave valid meshes, a patient one.
        let mut sources: Vec<usize> = (0..count).collect();
        sources.sort_by(|&x, &y| {
            roundness(&fixed[x], &boundary.loop_start)
                .total_cmp(&roundness(&fixed[y], &boundary.loop_start))
        });
        // The patient pass takes up each drawing's untangling where the
        // first look left it (the same mesh, no rounds run twice), both
        // lowering the regularisation briskly; where that gives up, a
        // patient untangling afresh at the paper's pace. With anchors
        // inside, a last pair of passes with rings of free points around
        // each anchor (one ring, then two), so that no triangle holds an
        // anchor and another fixed point (those passes make their meshes
        // anew, so start afresh whatever they are marked).
        let passes = [
            (0, untangle::Patience::FIRST_LOOK.brisk(), Start::TakenUp),
            (0, untangle::Patience::LONG.brisk(), Start::TakenUp),
            (0, untangle::Patience::LONG, Start::Afresh),
            (1, untangle::Patience::LONG, Start::Afresh),
            (2, untangle::Patience::LONG, Start::Afresh),
        ];
        let source_meshes: Vec<OnceLock<Option<mapped::Refined>>> =
            sources.iter().map(|_| OnceLock::new()).collect();
        let mappings: Vec<Mutex<Option<mapped::Mapping>>> =
            sources.iter().map(|_| Mutex::new(None)).collect();
        'passes: for (pass, &(rings, patience, start)) in passes.iter().enumerate() {
            if rings > 0 && inside == 0 {
                break;
            }
            // Every source of the pass at once (on the machine's cores),
            // then taken in order as one after the other would be: the
            // same meshes whatever the number of threads. A source taken
            // (any valid meshes after the first pass, good enough angles
            // in it) calls off the sources after it, which would not be
            // looked at: on one core a thin drawing's quick success no
            // longer waits for a fat one's long failure.
            let called_off: Vec<AtomicBool> =
                sources.iter().map(|_| AtomicBool::new(false)).collect();
            let taken = |k: usize| {
                for later in &called_off[k + 1..] {
                    later.store(true, Ordering::Relaxed);
                }
            };
            let tried: Vec<Option<Candidate>> = sources
                .par_iter()
                .enumerate()
                .map(|(k, &source)| {
                    if called_off[k].load(Ordering::Relaxed) {
                        return None;
                    }
                    let patience = patience.unless(&called_off[k]);
                    let (mut meshes, mut triangles) = if rings == 0 {
                        let refined = source_meshes[k]
                            .get_or_init(|| {
                                mapped::source_mesh(
                                    &fixed,
                                    source,
                                    &boundary.loop_start,
                                    0,
                                    options.mapped_angle_degrees,
                                )
                            })
                            .as_ref()?;
                        let mut kept = mappings[k].lock().ok()?;
                        if start == Start::Afresh {
                            *kept = None;
                        }
                        let mapping = kept
                            .get_or_insert_with(|| mapped::Mapping::start(&fixed, source, refined));
                        if !mapping.go(patience) {
                            return None;
                        }
                        kept.take()?.finish()?
                    } else {
                        mapped::compatible(
                            &fixed,
                            source,
                            &boundary.loop_start,
                            rings,
                            options.mapped_angle_degrees,
                            patience,
                        )?
                    };
                    if pass > 0 {
                        taken(k);
                    }
                    let (_, angles) =
                        improve_set(&mut meshes, &mut triangles, n + inside, n, options);
                    if worst(&angles) >= accept {
                        taken(k);
                    }
                    Some(Candidate {
                        meshes,
                        triangles,
                        angles,
                        path: OutlinePath::Mapped,
                        overlay_angles: None,
                        source,
                    })
                })
                .collect();
            for c in tried.into_iter().flatten() {
                if best
                    .as_ref()
                    .is_none_or(|b| worst(&c.angles) > worst(&b.angles))
                {
                    best = Some(c);
                }
                if best
                    .as_ref()
                    .is_some_and(|b| worst(&b.angles) >= accept || pass > 0)
                {
                    break 'passes;
                }
            }
            if best.is_some() {
                break;
            }
        }
    }
    // The overlay only where no mapping gave valid meshes: on unlike
    // drawings its angles are far below a mapped mesh's, and it grows with
    // the square of the points.
    if best.is_none() {
        best = Some(overlay_set(&boundary, &fixed, n, options)?);
    }
    let Some(mut chosen) = best else {
        unreachable!("the overlay either succeeds or returns its error")
    };
    let anchor_vertices = placed.vertices(&boundary, n);
    if options.settle_steps > 0 {
        settle_set(
            &mut chosen,
            &boundary,
            &anchor_vertices,
            n + inside,
            options.settle_steps,
            options.rigid_parts,
        );
    }
    let loops: Vec<Vec<u32>> = boundary
        .loop_start
        .windows(2)
        .map(|w| (w[0] as u32..w[1] as u32).collect())
        .collect();
    // Given points to vertices, drawing by drawing.
    let given: Vec<Vec<Vec<u32>>> = drawings
        .iter()
        .enumerate()
        .map(|(d, drawing)| {
            let mut vertex_at: Vec<Vec<u32>> =
                drawing.loops().iter().map(|l| vec![0; l.len()]).collect();
            for (l, w) in boundary.loop_start.windows(2).enumerate() {
                let own = pairings[d][l];
                for v in w[0]..w[1] {
                    if let Some(f) = boundary.from[d][v] {
                        vertex_at[own][f] = v as u32;
                    }
                }
            }
            drawing
                .stored_of_given()
                .iter()
                .enumerate()
                .map(|(l, s)| s.iter().map(|&i| vertex_at[l][i]).collect())
                .collect()
        })
        .collect();
    let steiner_points = chosen.meshes[0].len() - n - inside;
    let num_triangles = chosen.triangles.len();
    let mut meshes = Vec::with_capacity(count);
    for positions in chosen.meshes {
        meshes.push(Mesh2::new(positions, chosen.triangles.clone())?);
    }
    Ok(CompatibleSet {
        meshes,
        loops,
        given,
        anchors: anchor_vertices,
        report: OutlineReport {
            drawing_points: drawings.iter().map(Drawing::num_points).collect(),
            boundary_points: n,
            inside_anchors: inside,
            steiner_points,
            triangles: num_triangles,
            min_angle_degrees: chosen.angles.iter().map(|a| a.to_degrees()).collect(),
            overlay_min_angle_degrees: chosen
                .overlay_angles
                .map(|o| o.iter().map(|a| a.to_degrees()).collect()),
            path: chosen.path,
            seconds: start.elapsed().as_secs_f64(),
        },
    })
}

/// The chosen meshes' maps made as rigid as they can be ([`settle`]):
/// each other mesh against the source drawing's, and with two drawings
/// then the source's against the other (so that the boundary points of
/// both slide). Each drawing's own points and the anchors
/// (`anchor_vertices`, those below `num_boundary` on the outlines) stay;
/// vertices from `free_from` on move freely. The smallest angles are
/// measured again.
fn settle_set(
    chosen: &mut Candidate,
    boundary: &common::CommonBoundary,
    anchor_vertices: &[u32],
    free_from: usize,
    steps: usize,
    rigid_parts: bool,
) {
    let n = boundary.loop_start[boundary.loop_start.len() - 1];
    let count = chosen.meshes.len();
    let slides: Vec<Vec<settle::Slide>> = (0..count)
        .map(|d| {
            let mut fixed: Vec<bool> = boundary.from[d].iter().map(Option::is_some).collect();
            for &v in anchor_vertices {
                if (v as usize) < n {
                    fixed[v as usize] = true;
                }
            }
            settle::slides(&chosen.meshes[d][..n], &boundary.loop_start, &fixed)
        })
        .collect();
    let source = chosen.source;
    for k in (0..count).filter(|&k| k != source) {
        let (reference, moving) = two_of(&mut chosen.meshes, source, k);
        settle::settle(
            reference,
            &chosen.triangles,
            moving,
            free_from,
            &slides[k],
            steps,
            rigid_parts,
        );
        if count == 2 {
            let (reference, moving) = two_of(&mut chosen.meshes, k, source);
            settle::settle(
                reference,
                &chosen.triangles,
                moving,
                free_from,
                &slides[source],
                steps,
                rigid_parts,
            );
        }
    }
    chosen.angles = improve::smallest_angles(&improve::Pair {
        meshes: &mut chosen.meshes,
        triangles: &mut chosen.triangles,
        fixed: &mut Vec::new(),
    });
}

/// Mesh `r` to read and mesh `m` to change, of `meshes` (`r != m`).
fn two_of(meshes: &mut [Vec<[f64; 2]>], r: usize, m: usize) -> (&[[f64; 2]], &mut [[f64; 2]]) {
    if r < m {
        let (low, high) = meshes.split_at_mut(m);
        (&low[r], &mut high[0])
    } else {
        let (low, high) = meshes.split_at_mut(r);
        (&high[0], &mut low[m])
    }
}

/// The guaranteed way: the first drawing overlaid with each other one,
/// the pairs laid over each other when there are more than two drawings,
/// the anchors inside put in and moved into place, then improved.
fn overlay_set(
    boundary: &common::CommonBoundary,
    fixed: &[Vec<[f64; 2]>],
    n: usize,
    options: &OutlineOptions,
) -> Result<Candidate> {
    let count = fixed.len();
    let inside = fixed[0].len() - n;
    let matched_with = |k: usize| -> Vec<Vec<MatchedPoint>> {
        boundary
            .loop_start
            .windows(2)
            .map(|w| {
                (w[0]..w[1])
                    .map(|v| MatchedPoint {
                        ta: 0.0,
                        a: boundary.points[0][v],
                        b: boundary.points[k][v],
                        from_a: None,
                        from_b: None,
                    })
                    .collect()
            })
            .collect()
    };
    // The first drawing with drawing k: mapped, else overlaid; improved.
    let pair_with = |k: usize| -> Result<Positioned> {
        let two = [boundary.points[0].clone(), boundary.points[k].clone()];
        let (mut m, mut t) = match (count > 2)
            .then(|| {
                mapped::compatible(
                    &two,
                    0,
                    &boundary.loop_start,
                    0,
                    options.mapped_angle_degrees,
                    untangle::Patience::SHORT,
                )
            })
            .flatten()
        {
            Some(found) => found,
            None => overlay_pair(&matched_with(k), &two[0], &two[1])?,
        };
        if count > 2 {
            improve_set(&mut m, &mut t, n, n, options);
        }
        Ok((m, t))
    };
    let (mut meshes, mut triangles) = pair_with(1)?;
    // More drawings: the first pair's mesh mapped into each, and where
    // that turns a triangle over, carried through the first drawing's own
    // pair with that drawing and untangled.
    for k in 2..count {
        let mut b = mapped::map_into(
            &meshes[0],
            &triangles,
            &boundary.points[k],
            untangle::Patience::SHORT,
        );
        if !mapped::all_positive(&b, &triangles) {
            let (mut m, t) = pair_with(k)?;
            let pair = carry::PairMesh {
                other: m.pop().unwrap_or_default(),
                first: m.pop().unwrap_or_default(),
                triangles: t,
            };
            let start = carry::carry_all(&pair, &meshes[0]);
            b = untangle::untangle(&meshes[0], &triangles, start, n, untangle::Patience::LONG);
            if !mapped::all_positive(&b, &triangles) {
                return Err(Error::IncompatibleDrawings(format!(
                    "drawing {} could not be given the mesh of the first two without turning a triangle over: \
                     morph the drawings two at a time, or add anchors on the outlines",
                    k + 1
                )));
            }
        }
        meshes.push(b);
    }
    let overlay_angles = improve::smallest_angles(&improve::Pair {
        meshes: &mut meshes,
        triangles: &mut triangles,
        fixed: &mut Vec::new(),
    });
    if inside > 0 {
        // Better shapes first: the untangling that moves the anchors keeps
        // the triangles close to the first drawing's.
        improve_set(&mut meshes, &mut triangles, n, n, options);
        anchors::insert_inside(&mut meshes, &mut triangles, fixed, n)?;
    }
    let (_, angles) = improve_set(&mut meshes, &mut triangles, n + inside, 2 * n, options);
    if !meshes.iter().all(|m| mapped::all_positive(m, &triangles)) {
        return Err(Error::IncompatibleDrawings(
            "the overlaid meshes came out with a triangle turned over in one drawing; \
             simplify the drawings (fewer, less detailed points) or add anchors on the outlines"
                .into(),
        ));
    }
    Ok(Candidate {
        meshes,
        triangles,
        angles,
        path: OutlinePath::Overlay,
        overlay_angles: Some(overlay_angles),
        source: 0,
    })
}
