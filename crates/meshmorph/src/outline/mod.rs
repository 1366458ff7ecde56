//! From two drawings to two compatible meshes: outlines in, the same
//! triangles out, every one positively oriented in both meshes, ready for
//! [`Interpolator`](crate::Interpolator).
//!
//! The way, one file a step:
//!
//! 1. `drawing`: each drawing checked (loops simple, apart, holes inside)
//!    and oriented (outer loop counter-clockwise, holes clockwise).
//! 2. `boundary`: the outer loops matched by aligning their turning-angle
//!    signatures (dynamic time warping over every start), the union of
//!    both loops' points put on each; `holes` pairs the holes by where
//!    they sit once the outer loops are laid over each other, and each
//!    pair is matched the same way.
//! 3. `cuts`: each hole opened to the outer loop by a straight cut at the
//!    same matched points in both drawings, so both become disks with the
//!    same boundary.
//! 4. `disk`: each disk triangulated with no inside points (constrained
//!    Delaunay, `spade`); `overlay`: the two triangulations laid over
//!    each other as chords of one convex polygon (Aronov, Seidel and
//!    Souvaine 1993), which gives triangles valid in both drawings
//!    whatever the shapes.
//! 5. `improve`: compatible edge flips and smoothing that raise the
//!    smallest angle and keep every triangle positive in both meshes.
//!
//! Before steps 3 and 4, `mapped` tries the fast way: one drawing meshed
//! with good angles (constrained Delaunay refinement), mapped into the
//! other with the matched boundary fixed and untangled (Garanzha et al.
//! 2021); it is kept when every triangle is positive in both meshes and
//! its smallest angle is good enough or beats the overlay's.

mod boundary;
mod cuts;
mod disk;
mod drawing;
mod geometry;
mod holes;
mod improve;
mod mapped;
mod overlay;
#[cfg(test)]
mod tests;

use std::time::Instant;

pub use drawing::Drawing;

use self::boundary::{match_loops, LoopAnchor, MatchedPoint};
use self::geometry::{diagonal, dist, lerp, point_segment_distance, ArcLoop};
use self::overlay::OverlayVertex;
use crate::error::{Error, Result};
use crate::mesh::Mesh2;

/// A pair of points kept matched: `a` on the first drawing's outline, `b`
/// on the second's, each on a loop (the outer loop or a hole; the two
/// loops must pair). Points within 1 % of the drawing's size from its
/// outline are moved onto it.
///
/// Anchors inside the shapes are not supported yet.
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
    /// The smallest angle the first drawing's mesh is refined towards on
    /// the fast way, degrees. Default 25.
    pub mapped_angle_degrees: f64,
    /// The fast way's meshes are kept without making the overlay when
    /// every triangle is positive in both and their smallest angle is at
    /// least this many degrees; below it the overlay is made too and the
    /// better of the two kept. Default 10.
    pub accept_angle_degrees: f64,
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
            mapped_first: true,
            mapped_angle_degrees: 25.0,
            accept_angle_degrees: 10.0,
        }
    }
}

/// What [`compatible_meshes`] made, and how well.
#[derive(Clone, Debug)]
pub struct OutlineReport {
    /// Points of each drawing as stored (repeats removed).
    pub drawing_points: [usize; 2],
    /// Points of the matched boundary (every loop), the same on both
    /// meshes: each drawing's own points and the other's carried over.
    pub boundary_points: usize,
    /// Mesh vertices not on the boundary (Steiner points).
    pub steiner_points: usize,
    /// Triangles of each mesh.
    pub triangles: usize,
    /// Smallest angle of any triangle in each mesh, degrees, after the
    /// improvement.
    pub min_angle_degrees: [f64; 2],
    /// The same straight after the overlay, before the improvement, when
    /// the overlay was made.
    pub overlay_min_angle_degrees: Option<[f64; 2]>,
    /// Which way the meshes were made.
    pub path: OutlinePath,
    /// Wall-clock seconds for the whole call.
    pub seconds: f64,
}

impl std::fmt::Display for OutlineReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} + {} points, {} on the matched boundary, {} Steiner, {} triangles; smallest angle {:.2}/{:.2} degrees by the {}",
            self.drawing_points[0],
            self.drawing_points[1],
            self.boundary_points,
            self.steiner_points,
            self.triangles,
            self.min_angle_degrees[0],
            self.min_angle_degrees[1],
            match self.path {
                OutlinePath::Mapped => "mapped mesh",
                OutlinePath::Overlay => "overlay",
            },
        )?;
        if let Some(o) = self.overlay_min_angle_degrees {
            write!(f, " (overlay before improvement {:.2}/{:.2})", o[0], o[1])?;
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
fn snap(loops: &[Vec<[f64; 2]>], p: [f64; 2]) -> (usize, f64, [f64; 2], f64) {
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

/// The guaranteed way: the overlay of both drawings' triangulations in a
/// common convex domain, then the compatible improvement. Returns the
/// meshes, the overlay's smallest angles and the improved ones (radians).
#[allow(clippy::type_complexity)]
fn overlay_pair(
    matched: &[Vec<MatchedPoint>],
    points_a: &[[f64; 2]],
    points_b: &[[f64; 2]],
    options: &OutlineOptions,
) -> Result<(
    Vec<[f64; 2]>,
    Vec<[f64; 2]>,
    Vec<[u32; 3]>,
    [f64; 2],
    [f64; 2],
)> {
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
    let num_points = points_a.len();
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
    let mut triangles: Vec<[u32; 3]> = over
        .triangles
        .iter()
        .map(|t| t.map(|v| vertex_of[v as usize]))
        .collect();
    let (overlay_angles, angles) = improve_pair(
        &mut pos_a,
        &mut pos_b,
        &mut triangles,
        num_points,
        2 * num_points,
        options,
    );
    Ok((pos_a, pos_b, triangles, overlay_angles, angles))
}

/// The compatible improvement of two meshes whose first `num_points`
/// vertices (the outline points) stay where they are, adding at most
/// `extra` vertices: the smallest angles (radians) before and after.
fn improve_pair(
    pos_a: &mut Vec<[f64; 2]>,
    pos_b: &mut Vec<[f64; 2]>,
    triangles: &mut Vec<[u32; 3]>,
    num_points: usize,
    extra: usize,
    options: &OutlineOptions,
) -> ([f64; 2], [f64; 2]) {
    let mut fixed: Vec<bool> = (0..pos_a.len()).map(|v| v < num_points).collect();
    let mut pair = improve::Pair {
        a: pos_a,
        b: pos_b,
        triangles,
        fixed: &mut fixed,
    };
    let before = improve::smallest_angles(&pair);
    improve::improve(
        &mut pair,
        options.improvement_rounds,
        options.target_angle_degrees.to_radians(),
        extra,
    );
    (before, improve::smallest_angles(&pair))
}

/// Two compatible meshes, one inside each drawing: the same triangles,
/// every one positively oriented in both, every given outline point a
/// vertex at exactly its position, each mesh's boundary its drawing's
/// loops. The boundary correspondence is found automatically
/// (invariant to where each loop starts, its direction, and the drawings'
/// position, scale and rotation); `anchors` are kept matched exactly.
///
/// The triangles come first from a refined mesh of one drawing mapped
/// into the other and untangled ([`OutlinePath::Mapped`]), kept when every
/// triangle is positive in both and the smallest angle reaches
/// [`OutlineOptions::accept_angle_degrees`]; otherwise from the overlay of
/// Aronov, Seidel and Souvaine (1993) ([`OutlinePath::Overlay`]), which
/// cannot fail on drawings that pass [`Drawing::new`] and whose holes can
/// be cut straight to the outer loop at matched points in both, the
/// better of the two kept. Compatible flips and smoothing then raise the
/// smallest angle (reported in [`OutlineReport::min_angle_degrees`], the
/// way taken in [`OutlineReport::path`]).
///
/// # Errors
/// [`Error::IncompatibleDrawings`] when the drawings have different
/// numbers of loops, an anchor is off the outlines, on loops that do not
/// pair, or anchors come in different orders on the two outlines, or a
/// hole cannot be cut straight to the outer loop in both drawings.
///
/// # Performance
/// Two like 500-point outlines take tens of milliseconds on the mapped
/// way; the overlay grows with how differently the two shapes'
/// triangulations run (up to quadratically in the points: seconds for
/// two unlike 500-point outlines).
pub fn compatible_meshes(
    a: &Drawing,
    b: &Drawing,
    anchors: &[Anchor],
    options: &OutlineOptions,
) -> Result<CompatibleMeshes> {
    let start = Instant::now();
    if a.num_loops() != b.num_loops() {
        let holes = |d: &Drawing| match d.num_loops() - 1 {
            0 => "no hole".to_string(),
            1 => "1 hole".to_string(),
            h => format!("{h} holes"),
        };
        return Err(Error::IncompatibleDrawings(format!(
            "the first drawing has {} loop{} ({}) but the second has {} ({}): both need the same number of holes",
            a.num_loops(),
            if a.num_loops() == 1 { "" } else { "s" },
            holes(a),
            b.num_loops(),
            holes(b)
        )));
    }
    let (la, lb) = (a.loops(), b.loops());
    // Anchors snapped onto the loops, sorted by loop of the first drawing.
    let (size_a, size_b) = (diagonal(la.iter().flatten()), diagonal(lb.iter().flatten()));
    let mut snapped: Vec<(usize, usize, LoopAnchor)> = Vec::with_capacity(anchors.len());
    for (k, anchor) in anchors.iter().enumerate() {
        let (l, ta, pa, da) = snap(la, anchor.a);
        let (m, tb, pb, db) = snap(lb, anchor.b);
        for (d, size, which, p) in [
            (da, size_a, "first", anchor.a),
            (db, size_b, "second", anchor.b),
        ] {
            if d.is_nan() || d > 0.01 * size {
                return Err(Error::IncompatibleDrawings(format!(
                    "anchor {k} is {d:.4} from the {which} drawing's outline at {p:?}, more than 1 % of its size: put it on the outline (anchors inside the shapes are not supported yet)"
                )));
            }
        }
        snapped.push((
            l,
            m,
            LoopAnchor {
                ta,
                tb,
                a: pa,
                b: pb,
            },
        ));
    }
    let for_loop = |l: usize, m: usize| -> Result<Vec<LoopAnchor>> {
        let mut out = Vec::new();
        for (k, &(x, y, s)) in snapped.iter().enumerate() {
            if (x == l) != (y == m) {
                return Err(Error::IncompatibleDrawings(format!(
                    "anchor {k} is on loop {x} of the first drawing and loop {y} of the second, which do not pair (loop {l} pairs with loop {m}): put both ends on loops that pair, outer with outer"
                )));
            }
            if x == l {
                out.push(s);
            }
        }
        Ok(out)
    };
    let outer = match_loops(&la[0], &lb[0], &for_loop(0, 0)?, options.samples)?;
    let pairing = holes::pair_holes(&la[1..], &lb[1..], &outer);
    let mut matched: Vec<Vec<MatchedPoint>> = vec![outer];
    for (h, &g) in pairing.iter().enumerate() {
        matched.push(match_loops(
            &la[h + 1],
            &lb[g + 1],
            &for_loop(h + 1, g + 1)?,
            options.samples,
        )?);
    }
    let points_a: Vec<[f64; 2]> = matched.iter().flatten().map(|p| p.a).collect();
    let points_b: Vec<[f64; 2]> = matched.iter().flatten().map(|p| p.b).collect();
    let num_points = points_a.len();
    let mut loop_start = vec![0usize];
    for l in &matched {
        loop_start.push(loop_start[loop_start.len() - 1] + l.len());
    }
    let worst = |angles: [f64; 2]| angles[0].min(angles[1]);
    // The fast first try: the first drawing's refined mesh mapped into
    // the second, kept when every triangle is positive in both.
    let try_mapped = |from: &[[f64; 2]], to: &[[f64; 2]], swap: bool| {
        mapped::compatible(from, to, &loop_start, options.mapped_angle_degrees).map(
            |(pos_from, pos_to, mut triangles)| {
                let (mut pos_a, mut pos_b) = if swap {
                    (pos_to, pos_from)
                } else {
                    (pos_from, pos_to)
                };
                let (_, angles) = improve_pair(
                    &mut pos_a,
                    &mut pos_b,
                    &mut triangles,
                    num_points,
                    num_points,
                    options,
                );
                (pos_a, pos_b, triangles, angles)
            },
        )
    };
    // The first drawing's mesh mapped into the second, else (or when its
    // angles fall short) the second's mapped into the first: the better.
    let mut mapped = None;
    if options.mapped_first {
        mapped = try_mapped(&points_a, &points_b, false);
        let short = |m: &Option<(_, _, _, [f64; 2])>| {
            m.as_ref()
                .is_none_or(|m| worst(m.3) < options.accept_angle_degrees.to_radians())
        };
        if short(&mapped) {
            if let Some(other) = try_mapped(&points_b, &points_a, true) {
                if mapped.as_ref().is_none_or(|m| worst(other.3) > worst(m.3)) {
                    mapped = Some(other);
                }
            }
        }
    }
    let mapped_angles = mapped.as_ref().map(|m| m.3);
    let accept_fast =
        mapped_angles.is_some_and(|a| worst(a) >= options.accept_angle_degrees.to_radians());
    let (path, pos_a, pos_b, triangles, angles, overlay_angles) = match mapped {
        Some((pa, pb, t, angles)) if accept_fast => (OutlinePath::Mapped, pa, pb, t, angles, None),
        mapped => match overlay_pair(&matched, &points_a, &points_b, options) {
            Ok((pa, pb, t, over, angles)) => match mapped {
                Some((ma, mb, mt, m_angles)) if worst(m_angles) > worst(angles) => {
                    (OutlinePath::Mapped, ma, mb, mt, m_angles, Some(over))
                }
                _ => (OutlinePath::Overlay, pa, pb, t, angles, Some(over)),
            },
            Err(e) => match mapped {
                Some((ma, mb, mt, m_angles)) => (OutlinePath::Mapped, ma, mb, mt, m_angles, None),
                None => return Err(e),
            },
        },
    };
    let mut loops = Vec::with_capacity(matched.len());
    let mut first = 0u32;
    for l in &matched {
        loops.push((first..first + l.len() as u32).collect());
        first += l.len() as u32;
    }
    // Given points to vertices.
    let given = |d: &Drawing, side: usize| -> Vec<Vec<u32>> {
        let stored = d.stored_of_given();
        let mut vertex_at: Vec<Vec<u32>> = d.loops().iter().map(|l| vec![0; l.len()]).collect();
        let mut offset = 0u32;
        for (k, l) in matched.iter().enumerate() {
            let loop_index = if side == 0 || k == 0 {
                k
            } else {
                pairing[k - 1] + 1
            };
            for (i, p) in l.iter().enumerate() {
                let from = if side == 0 { p.from_a } else { p.from_b };
                if let Some(f) = from {
                    vertex_at[loop_index][f] = offset + i as u32;
                }
            }
            offset += l.len() as u32;
        }
        stored
            .iter()
            .enumerate()
            .map(|(l, s)| s.iter().map(|&i| vertex_at[l][i]).collect())
            .collect()
    };
    let given_a = given(a, 0);
    let given_b = given(b, 1);
    let steiner_points = pos_a.len() - num_points;
    let num_triangles = triangles.len();
    let mesh_a = Mesh2::new(pos_a, triangles.clone())?;
    let mesh_b = Mesh2::new(pos_b, triangles)?;
    Ok(CompatibleMeshes {
        a: mesh_a,
        b: mesh_b,
        loops,
        given_a,
        given_b,
        report: OutlineReport {
            drawing_points: [a.num_points(), b.num_points()],
            boundary_points: num_points,
            steiner_points,
            triangles: num_triangles,
            min_angle_degrees: angles.map(f64::to_degrees),
            overlay_min_angle_degrees: overlay_angles.map(|o| o.map(f64::to_degrees)),
            path,
            seconds: start.elapsed().as_secs_f64(),
        },
    })
}
