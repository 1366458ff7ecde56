//! The plane a surface is its own mirror image about (the bilateral
//! symmetry of most characters), found by iterating closest points.
//!
//! From each principal axis of the surface (its exact second moments of
//! area, which do not depend on how it is tessellated), and from the
//! directions halfway between them, the plane is refined as in iterative
//! closest point: every vertex is mirrored, paired with the vertex nearest
//! to its image, and the plane is fitted again to the pairs (its normal the
//! direction the pairs differ in most, its offset through their midpoints),
//! pairs whose image lands far from any vertex left out. The planes that
//! map the surface onto itself to within [`MIRROR_MISFIT`] of its size (RMS
//! over its area, in RMS distances of its area from its centroid) fit; the
//! best of them is the surface's plane unless another fits about as well:
//! an asymmetric surface has none, and a surface of revolution (a tube)
//! several, so neither gets one. A flat surface is its own mirror image
//! about its own plane. What is measured depends only on the surface:
//! moving, turning or scaling it moves, turns or scales the plane (to
//! rounding, but for near ties between equally near vertices).

use rayon::prelude::*;

use crate::mesh::bvh::{Aabb, Bvh};

use crate::gradient::weights::vertex_weights;
use crate::linalg::polar::SymmetricEigen3;
use crate::linalg::vector::{add, dot, scale, sub};
use crate::mesh::Mesh3;

/// The largest RMS distance, over the area, between a surface mirrored
/// about its plane and the surface itself, as a fraction of its size (the
/// RMS distance of its area from its centroid), for the plane to count.
/// Sumner's horse, camel, face mask and head are their own mirror images to
/// 1.3 %, 2.6 %, 2.2 % and 0.5 %; their next best planes miss by 8 % or
/// more.
pub const MIRROR_MISFIT: f64 = 0.04;

/// Refinements of each plane at most (they settle in a few).
const ROUNDS: usize = 12;

/// Fitting planes whose normals are less than this many degrees apart are
/// one plane, found from two starts.
const SAME_PLANE: f64 = 5.0;

/// Misfits below this are exact mirror images but for rounding and the
/// tessellation: two such planes are two planes of symmetry.
const TIE: f64 = 1e-3;

/// A plane whose normal turns by `θ` and whose offset moves by `δ` (over
/// the size) in a round has settled when `√(1 − cos θ) + δ` (about
/// `θ / √2 + δ`) is below this: far below anything a turn of the transfer
/// could show.
const SETTLED: f64 = 1e-5;

/// The scatter of the pairs' differences is nothing when its largest
/// eigenvalue is below this fraction of the squared size: every vertex is
/// its own image.
const FLAT: f64 = 1e-24;

/// A plane whose misfit is more than this many times [`MIRROR_MISFIT`] is
/// not refined further.
const FAR: f64 = 2.0;

/// Images farther than this many times [`MIRROR_MISFIT`] (of the size)
/// from every vertex are not searched further, and count as that far in the
/// misfit.
const REACH: f64 = 4.0;

/// A pair whose image lands farther from its vertex than this many times
/// the median of those distances is left out of the next fit (the parts of
/// a surface that are not symmetric).
const OUTLIER: f64 = 3.0;

/// A plane `{x : n · x = offset}` with a unit normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MirrorPlane {
    /// The unit normal (either sign).
    pub normal: [f64; 3],
    /// `n · x` on the plane.
    pub offset: f64,
    /// RMS distance over the area between the mirrored surface and the
    /// surface, over the surface's size (a plane is kept below 0.04).
    pub misfit: f64,
}

impl MirrorPlane {
    /// The mirror image of `p`.
    #[inline]
    pub fn mirror(&self, p: [f64; 3]) -> [f64; 3] {
        sub(
            p,
            scale(self.normal, 2.0 * (dot(self.normal, p) - self.offset)),
        )
    }
}

impl Mesh3 {
    /// The plane about which this surface is its own mirror image, if one
    /// plane fits clearly best: where a character's left meets its right.
    /// Deformation transfer keeps the source's and the target's planes
    /// together ([`CorrespondResult::mirror_planes`](crate::CorrespondResult::mirror_planes)).
    pub fn mirror_plane(&self) -> Option<MirrorPlane> {
        mirror_plane(self)
    }
}

/// The mirror plane of `mesh`, if one plane fits clearly best (see the
/// module documentation).
pub fn mirror_plane(mesh: &Mesh3) -> Option<MirrorPlane> {
    let areas = mesh.triangle_areas();
    let weights = vertex_weights(mesh.num_vertices(), mesh.triangles(), &areas);
    let used: Vec<([f64; 3], f64)> = mesh
        .positions()
        .iter()
        .zip(&weights)
        .filter(|(_, &w)| w > 0.0)
        .map(|(&p, &w)| (p, w))
        .collect();
    // Worked on in units of the bounding box, about its centre, with the
    // weights summing to 1: every sum below stays in range whatever the
    // units of the file.
    let positions: Vec<[f64; 3]> = used.iter().map(|p| p.0).collect();
    let bounds = Aabb::around(positions.iter().copied());
    let origin = scale(add(bounds.lo, bounds.hi), 0.5);
    let unit = bounds.diagonal();
    let total: f64 = used.iter().map(|p| p.1).sum();
    let area_total: f64 = areas.iter().sum();
    if used.len() < 4 || !(unit > 0.0 && unit.is_finite() && total > 0.0 && area_total > 0.0) {
        return None;
    }
    let points: Vec<([f64; 3], f64)> = used
        .iter()
        .map(|&(p, w)| (scale(sub(p, origin), 1.0 / unit), w / total))
        .collect();
    // The centroid and the second moments of the surface itself, each
    // triangle integrated exactly: the same for any tessellation of the
    // same surface (a cap split into a fan from one corner, or into a
    // strip), so a symmetric surface has its plane's normal among the axes.
    let corner = |v: u32| scale(sub(mesh.positions()[v as usize], origin), 1.0 / unit);
    let mut centre = [0.0; 3];
    let mut moments = [[0.0; 3]; 3];
    for (tri, &a) in mesh.triangles().iter().zip(&areas) {
        let (a, p) = (a / area_total, tri.map(corner));
        let sum = add(p[0], add(p[1], p[2]));
        centre = add(centre, scale(sum, a / 3.0));
        for i in 0..3 {
            for j in 0..3 {
                let own: f64 = p.iter().map(|v| v[i] * v[j]).sum();
                moments[i][j] += a / 12.0 * (own + sum[i] * sum[j]);
            }
        }
    }
    let spread: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| moments[i][j] - centre[i] * centre[j]));
    // The RMS distance from the centre: the size misfits are measured in,
    // the same however the surface is turned.
    let size = (spread[0][0] + spread[1][1] + spread[2][2]).sqrt();
    if !(size.is_finite() && size > 0.0) {
        return None;
    }
    let axes = SymmetricEigen3::new(spread).vectors;
    let tree = Bvh::new(
        points.iter().map(|p| p.0).collect(),
        |p| Aabb::around([*p]),
        |p| p.map(f64::to_bits),
    );
    // The planes that fit, each once: a start that comes within
    // [`SAME_PLANE`] of a plane already found stops there, and two planes
    // that both fit to within [`TIE`] end the search (a surface of
    // revolution would otherwise refine every start to the full).
    let mut fitting: Vec<MirrorPlane> = Vec::new();
    for normal in starts(axes) {
        let start = MirrorPlane {
            normal,
            offset: dot(normal, centre),
            misfit: f64::INFINITY,
        };
        let Some(plane) = refine(&points, &tree, size, start, &fitting) else {
            continue;
        };
        if plane.misfit <= MIRROR_MISFIT {
            fitting.push(plane);
            if fitting.iter().filter(|p| p.misfit <= TIE).count() > 1 {
                return None;
            }
        }
    }
    // The best plane, unless another fits about as well: then neither is
    // the surface's (a coarse ring of a tube mirrors itself between its
    // vertices as well as through them, but a bent body only one way).
    fitting.sort_by(|a, b| a.misfit.total_cmp(&b.misfit));
    let (&best, others) = fitting.split_first()?;
    if others
        .iter()
        .any(|p| p.misfit <= (2.0 * best.misfit).max(TIE))
    {
        return None;
    }
    let found = Some(best);
    // Back in the file's units.
    found.map(|plane| MirrorPlane {
        offset: plane.offset * unit + dot(plane.normal, origin),
        ..plane
    })
}

/// The normals the planes start from, in the frame of the principal axes
/// (`axes`, columns): the three axes, the six halfway between two of them
/// and the four halfway between all three. A symmetric surface has its
/// plane's normal among its principal axes, but where two of them spread
/// alike (a face mask about as tall as wide) they are any two directions in
/// their plane, and the normal may lie between them.
fn starts(axes: [[f64; 3]; 3]) -> Vec<[f64; 3]> {
    let column = |k: usize| [axes[0][k], axes[1][k], axes[2][k]];
    let (a, b, c) = (column(0), column(1), column(2));
    let unit = |v: [f64; 3]| scale(v, 1.0 / dot(v, v).sqrt());
    let mut out = vec![a, b, c];
    for (u, v) in [(a, b), (a, c), (b, c)] {
        out.push(unit(add(u, v)));
        out.push(unit(sub(u, v)));
    }
    for (sb, sc) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
        out.push(unit(add(a, add(scale(b, sb), scale(c, sc)))));
    }
    out
}

/// Iterates closest points from `plane` (see the module documentation).
///
/// `None` once it comes within [`SAME_PLANE`] of a plane of `found`.
fn refine(
    points: &[([f64; 3], f64)],
    tree: &Bvh<[f64; 3]>,
    size: f64,
    mut plane: MirrorPlane,
    found: &[MirrorPlane],
) -> Option<MirrorPlane> {
    let same = SAME_PLANE.to_radians().cos();
    let mut settled = false;
    // For each vertex, the vertex nearest to its image and that distance:
    // the last round's partner bounds the search, and an image farther than
    // `reach` from every vertex has none and counts as that far.
    const NONE: usize = usize::MAX;
    let reach = REACH * MIRROR_MISFIT * size;
    let mut partners: Vec<(usize, f64)> = vec![(NONE, reach); points.len()];
    for round in 0..=ROUNDS {
        partners
            .par_iter_mut()
            .zip(points)
            .for_each(|(partner, &(p, _))| {
                let image = plane.mirror(p);
                let bound = match partner.0 {
                    NONE => reach * reach,
                    q => {
                        let d = sub(points[q].0, image);
                        (dot(d, d) * (1.0 + 1e-12)).min(reach * reach)
                    }
                };
                let found = tree.nearest(
                    image,
                    bound,
                    |_| true,
                    |q| {
                        let d = sub(*q, image);
                        dot(d, d)
                    },
                );
                *partner = match found {
                    Some((q, _, d2)) => (q as usize, d2.sqrt()),
                    None => (NONE, reach),
                };
            });
        let squares: f64 = points
            .iter()
            .zip(&partners)
            .map(|(&(_, w), &(_, d))| w * d * d)
            .sum();
        // (The weights sum to 1.)
        plane.misfit = squares.sqrt() / size;
        // A principal axis of a symmetric surface is its plane's normal, so
        // a mirror plane starts near the limit; a plane that does not is
        // not one, and would only drift.
        if settled || round == ROUNDS || plane.misfit > FAR * MIRROR_MISFIT {
            break;
        }
        let mut distances: Vec<f64> = partners.iter().map(|p| p.1).collect();
        let middle = distances.len() / 2;
        let limit = OUTLIER * *distances.select_nth_unstable_by(middle, f64::total_cmp).1;
        // The direction the kept pairs differ in most, and their midpoints.
        let mut differ = [[0.0; 3]; 3];
        let (mut mid, mut kept) = ([0.0; 3], 0.0);
        for (&(p, w), &(q, d)) in points.iter().zip(&partners) {
            if d > limit || q == NONE {
                continue;
            }
            let q = points[q].0;
            let e = sub(p, q);
            for i in 0..3 {
                for j in 0..3 {
                    differ[i][j] += w * e[i] * e[j];
                }
            }
            mid = add(mid, scale(add(p, q), 0.5 * w));
            kept += w;
        }
        let eigen = SymmetricEigen3::new(differ);
        if !(kept.is_finite() && kept > 0.0) || eigen.values[0] <= FLAT * kept * size * size {
            // Every pair is a vertex and itself: the plane of a flat surface
            // (or of a flat part of one), which no pair turns.
            settled = true;
            continue;
        }
        let v = eigen.vectors;
        let mut normal = [v[0][0], v[1][0], v[2][0]];
        if dot(normal, plane.normal) < 0.0 {
            normal = scale(normal, -1.0);
        }
        if !normal.iter().all(|c| c.is_finite()) {
            break;
        }
        let offset = dot(normal, scale(mid, 1.0 / kept));
        // (√(1 − cos θ) is about θ / √2.)
        settled = (1.0 - dot(normal, plane.normal)).max(0.0).sqrt()
            + (offset - plane.offset).abs() / size
            < SETTLED;
        plane.normal = normal;
        plane.offset = offset;
        if found.iter().any(|f| dot(f.normal, normal).abs() >= same) {
            return None;
        }
    }
    Some(plane)
}
