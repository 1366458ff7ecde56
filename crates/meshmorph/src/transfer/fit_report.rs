//! How well the source, deformed onto the target by the correspondence,
//! lies on the target: the figures a user judges a correspondence by before
//! transferring anything.
//!
//! Distances are measured from the target to the deformed source, not the
//! other way: the transfer deforms the target, and a target triangle far
//! from every source triangle is one whose deformation comes from no source
//! triangle of its own (a source that reaches beyond the target only leaves
//! some of its triangles unused). At each target vertex `v`,
//!
//! $$d_v = \min\left(\frac{\lVert x_v - \pi(x_v) \rVert}{L},\ d_{\max}\right),$$
//!
//! with $x_v$ its position, $\pi(x_v)$ the closest point of the deformed
//! source on a triangle whose normal is less than 90° from the vertex's
//! (area-weighted) normal (the same test as the matching: a surface facing
//! the other way covers nothing), $L$ the target's bounding-box diagonal,
//! and $d_{\max}$ the farthest the search looks
//! ([`FitReport::distance_limit`]): a vertex with no compatible source
//! surface that near counts as that far. Each target triangle's distance is
//! the mean of its corners', $d_t = (d_a + d_b + d_c) / 3$, so that the
//! area-weighted mean $\bar d = \sum_t a_t d_t / \sum_t a_t$ is the mean of
//! the distance interpolated linearly over the surface. The 95th percentile
//! is the smallest $d$ such that the triangles with $d_t \le d$ cover 95 %
//! of the area.

use rayon::prelude::*;

use crate::linalg::vector::{centroid, dot, sub};
use crate::mesh::closest::{
    closest_point_on_triangle, unit_normal, vertex_normals, Angle, SurfaceIndex,
};
use crate::mesh::surface_point::SurfacePoint;
use crate::mesh::Mesh3;
use crate::transfer::correspondence::Correspondence;
use crate::transfer::markers::Markers;

/// The farthest [`FitReport`] measures, as a fraction of the target's
/// bounding-box diagonal, unless twice the poor threshold is farther: 5 %,
/// well past any fit worth transferring through, and near enough for the
/// search to stay cheap where the source does not reach at all.
pub const FIT_DISTANCE_LIMIT: f64 = 0.05;

/// The smallest poor region [`FitReport::poor_regions`] lists, as a share of
/// the target's area (0.1 %): smaller ones are a triangle or two where the
/// two tessellations differ, and count only in [`FitReport::poor_area`].
pub const MIN_POOR_REGION: f64 = 0.001;

/// How many markers each [`PoorRegion`] names.
pub const NEAREST_MARKERS: usize = 3;

/// How well the deformed source lies on the target (see the module's
/// formula). Distances are fractions of the target's bounding-box diagonal,
/// areas shares of the target's area, so that moving or scaling both meshes
/// together changes nothing (turning them changes the box, and with it the
/// unit, as it changes the correspondence's thresholds).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct FitReport {
    /// `d_t` of each target triangle (`#T` of the target): the mean of its
    /// corners' distances, in `[0, distance_limit]`.
    pub distances: Vec<f64>,
    /// The area-weighted mean distance.
    pub mean_distance: f64,
    /// The area-weighted 95th percentile of the distance.
    pub distance_95: f64,
    /// The share of the target's area in triangles paired with no source
    /// triangle in the correspondence: what the transfer deforms only
    /// through its neighbours (or not at all).
    pub uncovered_area: f64,
    /// The distance beyond which a target triangle counts as poorly fitted:
    /// the matching's own threshold (the match threshold, never less than
    /// the mean edge length of either mesh), beyond which a triangle finds
    /// no partner.
    pub poor_threshold: f64,
    /// The farthest distance measured: [`FIT_DISTANCE_LIMIT`], or twice
    /// `poor_threshold` if that is farther (but never past 10 diagonals).
    pub distance_limit: f64,
    /// The share of the target's area in triangles farther than
    /// `poor_threshold`.
    pub poor_area: f64,
    /// The connected patches (across edges) of poorly fitted triangles that
    /// cover at least [`MIN_POOR_REGION`] of the target's area, largest
    /// first.
    pub poor_regions: Vec<PoorRegion>,
}

/// A connected patch of target triangles the deformed source lies far
/// from.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct PoorRegion {
    /// Its target triangles, in increasing order.
    pub triangles: Vec<u32>,
    /// Its share of the target's area.
    pub area: f64,
    /// Its largest distance `d_t`.
    pub largest_distance: f64,
    /// The triangle of the largest distance (the lowest index among equals).
    pub farthest_triangle: u32,
    /// That triangle's centroid, in the target's coordinates: where the fit
    /// is worst.
    pub point: [f64; 3],
    /// The [`NEAREST_MARKERS`] markers nearest to the region (fewer when
    /// there are fewer markers): each marker's index and the distance from
    /// its target vertex to the nearest vertex of the region (0 for a
    /// marker inside it), nearest first.
    pub nearest_markers: Vec<(usize, f64)>,
}

impl FitReport {
    /// Measures how well `deformed_source` lies on `target`, with the
    /// `correspondence` between them (pairs naming triangles out of range
    /// are ignored), the `markers` (for the markers nearest each poor
    /// region; target vertices out of range are ignored) and the
    /// `poor_threshold` (a fraction of the target's diagonal).
    ///
    /// # Performance
    /// One bounding volume hierarchy over the deformed source's triangles,
    /// one closest-point query per target vertex (in parallel), one sort
    /// of the target's triangles by distance, and per poor region a pass
    /// over its vertices per marker.
    pub fn new(
        deformed_source: &Mesh3,
        target: &Mesh3,
        correspondence: &Correspondence,
        markers: &Markers,
        poor_threshold: f64,
    ) -> Self {
        let diagonal = target.bounding_box_diagonal();
        let unit = if diagonal > 0.0 && diagonal.is_finite() {
            diagonal
        } else {
            1.0
        };
        let poor_threshold = if poor_threshold.is_finite() && poor_threshold >= 0.0 {
            poor_threshold
        } else {
            0.0
        };
        let distance_limit = FIT_DISTANCE_LIMIT.max(2.0 * poor_threshold).min(10.0);
        let distances = distances_to(
            deformed_source,
            target,
            correspondence,
            distance_limit * unit,
        )
        .into_iter()
        .map(|d| (d / unit).min(distance_limit))
        .collect::<Vec<f64>>();
        let areas = target.triangle_areas();
        let total: f64 = areas.iter().filter(|a| a.is_finite()).sum();
        let share = |a: f64| if total > 0.0 { a / total } else { 0.0 };
        let area_where = |keep: &dyn Fn(usize) -> bool| -> f64 {
            share(
                (0..areas.len())
                    .filter(|&t| keep(t) && areas[t].is_finite())
                    .map(|t| areas[t])
                    // From +0: an empty `sum` of floats is -0, printed "-0.00 %".
                    .fold(0.0, |a, b| a + b),
            )
        };
        let mut paired = vec![false; target.num_triangles()];
        for &[_, t] in correspondence.pairs() {
            if let Some(p) = paired.get_mut(t as usize) {
                *p = true;
            }
        }
        let poor: Vec<bool> = distances.iter().map(|&d| d > poor_threshold).collect();
        let mut poor_regions: Vec<PoorRegion> = patches(target.triangles(), &poor)
            .into_iter()
            .map(|triangles| {
                let area = share(triangles.iter().map(|&t| areas[t as usize]).sum());
                (triangles, area)
            })
            .filter(|(_, area)| *area >= MIN_POOR_REGION)
            .map(|(triangles, area)| region(target, &distances, markers, triangles, area, unit))
            .collect();
        poor_regions.sort_by(|a, b| {
            b.area
                .total_cmp(&a.area)
                .then(a.triangles[0].cmp(&b.triangles[0]))
        });
        FitReport {
            mean_distance: share(
                distances
                    .iter()
                    .zip(&areas)
                    .filter(|(_, a)| a.is_finite())
                    .map(|(d, a)| d * a)
                    .sum(),
            ),
            distance_95: weighted_percentile(&distances, &areas, 0.95),
            uncovered_area: area_where(&|t| !paired[t]),
            poor_area: area_where(&|t| poor[t]),
            distances,
            poor_threshold,
            distance_limit,
            poor_regions,
        }
    }
}

/// `d_t` of each target triangle in the target's units: the mean of its
/// corners' distances to the closest compatible point of
/// `deformed_source`, each `limit` where none lies within `limit`.
///
/// A vertex's triangles' partners in `correspondence` (those facing its
/// way) give its search an upper bound to start from: most of a good fit's
/// target lies within a hair of its partners, and the search then opens a
/// few leaves instead of every box within `limit`. The answer is the same.
fn distances_to(
    deformed_source: &Mesh3,
    target: &Mesh3,
    correspondence: &Correspondence,
    limit: f64,
) -> Vec<f64> {
    let normals = vertex_normals(target.positions(), target.triangles());
    let (surface, mut bound) = rayon::join(
        || SurfaceIndex::new(deformed_source.positions(), deformed_source.triangles()),
        || {
            let mut bound = vec![f64::INFINITY; target.num_vertices()];
            for &[s, t] in correspondence.pairs() {
                let (s, t) = (s as usize, t as usize);
                if s >= deformed_source.num_triangles() || t >= target.num_triangles() {
                    continue;
                }
                let q = deformed_source.corners(s);
                let n = unit_normal(q);
                for v in target.triangles()[t] {
                    let v = v as usize;
                    // The same test as the search below: the same answer.
                    if Angle::RIGHT.admits(dot(normals[v], n)) {
                        let x = target.positions()[v];
                        let d = sub(closest_point_on_triangle(x, q), x);
                        bound[v] = bound[v].min(dot(d, d).sqrt());
                    }
                }
            }
            bound
        },
    );
    bound.par_iter_mut().enumerate().for_each(|(v, bound)| {
        let reach = bound.min(limit);
        let d = surface
            .closest_compatible(target.positions()[v], normals[v], reach, Angle::RIGHT)
            .map_or(reach, |c| c.distance.min(reach));
        *bound = if d.is_finite() { d } else { limit };
    });
    target
        .triangles()
        .par_iter()
        .map(|t| t.iter().map(|&v| bound[v as usize]).sum::<f64>() / 3.0)
        .collect()
}

/// The smallest value of `values` such that those at most it carry the
/// share `q` of the total weight (weights that are not finite count 0).
pub fn weighted_percentile(values: &[f64], weights: &[f64], q: f64) -> f64 {
    let mut order: Vec<(f64, f64)> = values
        .iter()
        .zip(weights)
        .map(|(&v, &w)| (v, if w.is_finite() { w } else { 0.0 }))
        .collect();
    order.par_sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let total: f64 = order.iter().map(|(_, w)| w).sum();
    let mut sum = 0.0;
    for &(v, w) in &order {
        sum += w;
        if sum >= q * total {
            return v;
        }
    }
    order.last().map_or(0.0, |(v, _)| *v)
}

/// The connected patches of the triangles marked in `inside`, neighbours
/// across an edge (at a non-manifold edge, every triangle on it), each in
/// increasing order, in the order of their lowest triangle.
pub fn patches(triangles: &[[u32; 3]], inside: &[bool]) -> Vec<Vec<u32>> {
    let mut half: Vec<(u64, u32)> = triangles
        .iter()
        .enumerate()
        .filter(|&(t, _)| inside.get(t).copied().unwrap_or(false))
        .flat_map(|(t, tri)| {
            (0..3).map(move |k| {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                ((u64::from(a.min(b)) << 32) | u64::from(a.max(b)), t as u32)
            })
        })
        .collect();
    half.par_sort_unstable();
    // Union-find over triangle indices, the lower root kept.
    let mut parent: Vec<u32> = (0..triangles.len() as u32).collect();
    fn root(parent: &mut [u32], mut t: u32) -> u32 {
        while parent[t as usize] != t {
            let up = parent[parent[t as usize] as usize];
            parent[t as usize] = up;
            t = up;
        }
        t
    }
    for run in half.chunk_by(|x, y| x.0 == y.0) {
        for pair in run.windows(2) {
            let (a, b) = (root(&mut parent, pair[0].1), root(&mut parent, pair[1].1));
            let (lo, hi) = (a.min(b), a.max(b));
            parent[hi as usize] = lo;
        }
    }
    let mut slot = vec![u32::MAX; triangles.len()];
    let mut out: Vec<Vec<u32>> = Vec::new();
    for t in 0..triangles.len() as u32 {
        if !inside.get(t as usize).copied().unwrap_or(false) {
            continue;
        }
        let r = root(&mut parent, t) as usize;
        if slot[r] == u32::MAX {
            slot[r] = out.len() as u32;
            out.push(Vec::new());
        }
        out[slot[r] as usize].push(t);
    }
    out
}

/// The [`PoorRegion`] of `triangles` (a patch of `area`).
fn region(
    target: &Mesh3,
    distances: &[f64],
    markers: &Markers,
    triangles: Vec<u32>,
    area: f64,
    unit: f64,
) -> PoorRegion {
    let farthest_triangle = triangles
        .iter()
        .copied()
        .reduce(|a, b| {
            if distances[b as usize] > distances[a as usize] {
                b
            } else {
                a
            }
        })
        .unwrap_or(0);
    let mut vertices: Vec<u32> = triangles
        .iter()
        .flat_map(|&t| target.triangles()[t as usize])
        .collect();
    vertices.sort_unstable();
    vertices.dedup();
    let positions = target.positions();
    let mut nearest: Vec<(usize, f64)> = markers
        .pairs()
        .par_iter()
        .enumerate()
        .filter_map(|(k, &[_, point])| {
            // Markers made for another mesh are left out, not a panic.
            let in_range = match point {
                SurfacePoint::Vertex(v) => (v as usize) < positions.len(),
                SurfacePoint::Triangle { triangle, .. } => target
                    .triangles()
                    .get(triangle as usize)
                    .is_some_and(|t| t.iter().all(|&v| (v as usize) < positions.len())),
            };
            if !in_range {
                return None;
            }
            let m = point.position(target);
            let d2 = vertices
                .iter()
                .map(|&w| {
                    let d = sub(positions[w as usize], m);
                    dot(d, d)
                })
                .fold(f64::INFINITY, f64::min);
            Some((k, d2.sqrt() / unit))
        })
        .collect();
    nearest.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    nearest.truncate(NEAREST_MARKERS);
    PoorRegion {
        largest_distance: distances[farthest_triangle as usize],
        point: centroid(target.corners(farthest_triangle as usize)),
        farthest_triangle,
        triangles,
        area,
        nearest_markers: nearest,
    }
}
