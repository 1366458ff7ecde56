//! Spatial queries with a normal-compatibility filter: the closest point of
//! a surface, the nearest triangle centroid.
//!
//! Both answer "the nearest thing whose normal is less than 90° from mine,
//! within a distance", as deformation transfer needs (Sumner and Popović
//! 2004, sections 5.1 and 5.2), from a bounding volume hierarchy
//! (`bvh.rs`) that skips whatever lies beyond the cut-off or beyond the
//! nearest compatible candidate found so far.

use crate::linalg::vector::{add, cross, dot, norm, scale, sub};
use crate::mesh::bvh::{Aabb, Bvh};

/// Cosines of the angle between two normals up to this count as a right
/// angle: such faces are not compatible. Faces at exactly 90° (a tube's
/// side and its cap, as procedural and CAD meshes have them) would
/// otherwise be compatible or not by the rounding of their coordinates, and
/// moving the same mesh elsewhere could change the result.
const PERPENDICULAR: f64 = 1e-9;

/// Unit normal of a triangle (zero for a degenerate one).
#[inline]
pub fn unit_normal(p: [[f64; 3]; 3]) -> [f64; 3] {
    let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    let len = norm(n);
    if len > 0.0 {
        scale(n, 1.0 / len)
    } else {
        [0.0; 3]
    }
}

/// Area-weighted unit vertex normals of a mesh (zero for unused vertices).
pub fn vertex_normals(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<[f64; 3]> {
    let mut normals = vec![[0.0; 3]; positions.len()];
    for t in triangles {
        let p = t.map(|v| positions[v as usize]);
        let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        for &v in t {
            normals[v as usize] = add(normals[v as usize], n);
        }
    }
    for n in &mut normals {
        let len = norm(*n);
        if len > 0.0 {
            *n = scale(*n, 1.0 / len);
        }
    }
    normals
}

/// The point of triangle `p` closest to `q` (Ericson, "Real-Time Collision
/// Detection", 5.1.5).
#[inline]
pub fn closest_point_on_triangle(q: [f64; 3], p: [[f64; 3]; 3]) -> [f64; 3] {
    let [a, b, c] = p;
    match closest_region(q, p) {
        Region::Corner(k) => p[k],
        Region::Edge { from, to, t } => add(p[from], scale(sub(p[to], p[from]), t)),
        Region::Inside { v, w } => add(a, add(scale(sub(b, a), v), scale(sub(c, a), w))),
    }
}

/// Where on a triangle the point closest to a query lies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Region {
    /// At corner `k` (also for a degenerate triangle: its nearest corner).
    Corner(usize),
    /// On the edge from corner `from` to corner `to`, at `t` along it.
    Edge { from: usize, to: usize, t: f64 },
    /// Inside: `a + v (b - a) + w (c - a)`.
    Inside { v: f64, w: f64 },
}

impl Region {
    /// The barycentric coordinates of the point, in the triangle's order.
    pub(crate) fn barycentric(self) -> [f64; 3] {
        let mut b = [0.0; 3];
        match self {
            Region::Corner(k) => b[k] = 1.0,
            Region::Edge { from, to, t } => {
                b[from] = 1.0 - t;
                b[to] = t;
            }
            Region::Inside { v, w } => b = [1.0 - v - w, v, w],
        }
        b
    }
}

/// The region of triangle `p` holding the point closest to `q` (Ericson,
/// "Real-Time Collision Detection", 5.1.5).
#[inline]
pub fn closest_region(q: [f64; 3], p: [[f64; 3]; 3]) -> Region {
    let [a, b, c] = p;
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(q, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return Region::Corner(0);
    }
    let bp = sub(q, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return Region::Corner(1);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let t = d1 / (d1 - d3);
        return Region::Edge { from: 0, to: 1, t };
    }
    let cp = sub(q, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return Region::Corner(2);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let t = d2 / (d2 - d6);
        return Region::Edge { from: 0, to: 2, t };
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return Region::Edge { from: 1, to: 2, t };
    }
    let denom = va + vb + vc;
    if denom == 0.0 {
        // Degenerate triangle: fall back to the nearest corner (the first
        // of equally near ones).
        let d = |x: [f64; 3]| dot(sub(q, x), sub(q, x));
        return Region::Corner(
            (0..3)
                .min_by(|&i, &j| d(p[i]).total_cmp(&d(p[j])))
                .expect("three corners"),
        );
    }
    Region::Inside {
        v: vb / denom,
        w: vc / denom,
    }
}

/// A triangle of an indexed surface.
struct Triangle {
    corners: [[f64; 3]; 3],
    normal: [f64; 3],
}

/// The largest angle between two unit normals that still face the same
/// way, kept as its cosine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Angle {
    cos: f64,
}

impl Angle {
    /// Less than 90°: any two normals on the same side.
    pub const RIGHT: Angle = Angle { cos: PERPENDICULAR };

    /// An angle of `degrees` (in (0, 90]; 90 is [`Angle::RIGHT`]).
    pub fn degrees(degrees: f64) -> Angle {
        if degrees >= 90.0 {
            Angle::RIGHT
        } else {
            Angle {
                cos: degrees.to_radians().cos(),
            }
        }
    }

    /// Whether two unit normals whose dot product is `dot` are less than
    /// this angle apart.
    pub(crate) fn admits(self, dot: f64) -> bool {
        dot > self.cos
    }
}

/// The triangles of a surface, for closest-point queries.
pub struct SurfaceIndex {
    tree: Bvh<Triangle>,
}

/// A closest-point answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestPoint {
    /// The triangle it lies on.
    pub triangle: u32,
    /// The point.
    pub point: [f64; 3],
    /// Its distance from the query.
    pub distance: f64,
}

impl SurfaceIndex {
    /// Indexes the triangles of a surface.
    pub fn new(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Self {
        let items = triangles
            .iter()
            .map(|tri| {
                let corners = tri.map(|v| positions[v as usize]);
                Triangle {
                    corners,
                    normal: unit_normal(corners),
                }
            })
            .collect();
        Self {
            // The normal follows from the corners.
            tree: Bvh::new(
                items,
                |t| Aabb::around(t.corners),
                |t| t.corners.map(|c| c.map(f64::to_bits)),
            ),
        }
    }

    /// The closest point of the surface to `q`, whatever the normals (of
    /// equally close triangles, the first); `None` without triangles.
    pub fn closest(&self, q: [f64; 3]) -> Option<ClosestPoint> {
        self.closest_where(q, f64::INFINITY, |_| true)
    }

    /// The closest point to `q` on a triangle whose unit normal is less
    /// than `max_angle` from `normal` (a unit vector), if one lies within
    /// `max_distance` (of equally close triangles, the first).
    pub fn closest_compatible(
        &self,
        q: [f64; 3],
        normal: [f64; 3],
        max_distance: f64,
        max_angle: Angle,
    ) -> Option<ClosestPoint> {
        self.closest_where(q, max_distance * max_distance, |t| {
            max_angle.admits(dot(t.normal, normal))
        })
    }

    /// The closest point to `q` on a triangle that `accept`s, within the
    /// squared distance `max_distance_2`.
    #[inline]
    fn closest_where(
        &self,
        q: [f64; 3],
        max_distance_2: f64,
        accept: impl Fn(&Triangle) -> bool,
    ) -> Option<ClosestPoint> {
        let (triangle, tri, d2) = self.tree.nearest(q, max_distance_2, accept, |t| {
            let d = sub(closest_point_on_triangle(q, t.corners), q);
            dot(d, d)
        })?;
        Some(ClosestPoint {
            triangle,
            point: closest_point_on_triangle(q, tri.corners),
            distance: d2.sqrt(),
        })
    }
}

/// A triangle's centroid and unit normal, and the part it belongs to.
struct Centroid {
    point: [f64; 3],
    normal: [f64; 3],
    part: u32,
}

/// Triangle centroids with their unit normals, for nearest-triangle queries.
pub struct CentroidIndex {
    tree: Bvh<Centroid>,
}

impl CentroidIndex {
    /// Indexes the centroids of the triangles of a mesh, each in the part
    /// `parts[t]`.
    pub fn new(positions: &[[f64; 3]], triangles: &[[u32; 3]], parts: &[u32]) -> Self {
        let items = triangles
            .iter()
            .zip(parts)
            .map(|(tri, &part)| {
                let p = tri.map(|v| positions[v as usize]);
                Centroid {
                    point: crate::linalg::vector::centroid(p),
                    normal: unit_normal(p),
                    part,
                }
            })
            .collect();
        Self {
            tree: Bvh::new(
                items,
                |c| Aabb::around([c.point]),
                |c| {
                    (
                        c.point.map(f64::to_bits),
                        c.normal.map(f64::to_bits),
                        c.part,
                    )
                },
            ),
        }
    }

    /// The triangle whose centroid is nearest to `q` among those whose normal
    /// is less than `max_angle` from `normal` (and in part `part`, if
    /// given), if one lies within `max_distance` (of equally near ones, the
    /// first).
    pub fn nearest_compatible(
        &self,
        q: [f64; 3],
        normal: [f64; 3],
        max_distance: f64,
        max_angle: Angle,
        part: Option<u32>,
    ) -> Option<u32> {
        self.tree
            .nearest(
                q,
                max_distance * max_distance,
                |c| max_angle.admits(dot(c.normal, normal)) && part.is_none_or(|p| c.part == p),
                |c| {
                    let d = sub(c.point, q);
                    dot(d, d)
                },
            )
            .map(|(t, _, _)| t)
    }
}
