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
pub(crate) enum Region {
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
pub(crate) fn closest_region(q: [f64; 3], p: [[f64; 3]; 3]) -> Region {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_surface_turned_beyond_the_angle_is_not_taken() {
        // One triangle tilted 45° about the x axis, a query above it.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, h, h]];
        let s = SurfaceIndex::new(&p, &[[0, 1, 2]]);
        let (q, up) = ([0.2, 0.2, 0.5], [0.0, 0.0, 1.0]);
        for (degrees, found) in [
            (90.0, true),
            (60.0, true),
            (46.0, true),
            (44.0, false),
            (25.0, false),
        ] {
            assert_eq!(
                s.closest_compatible(q, up, 10.0, Angle::degrees(degrees))
                    .is_some(),
                found,
                "{degrees}°"
            );
        }
    }

    #[test]
    fn closest_point_regions() {
        let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let inside = closest_point_on_triangle([0.2, 0.2, 1.0], t);
        assert!(
            (0..3).all(|i| (inside[i] - [0.2, 0.2, 0.0][i]).abs() < 1e-15),
            "{inside:?}"
        );
        assert_eq!(
            closest_point_on_triangle([-1.0, -1.0, 0.0], t),
            [0.0, 0.0, 0.0]
        );
        assert_eq!(
            closest_point_on_triangle([2.0, -0.5, 0.0], t),
            [1.0, 0.0, 0.0]
        );
        assert_eq!(
            closest_point_on_triangle([0.5, -1.0, 0.0], t),
            [0.5, 0.0, 0.0]
        );
        let e = closest_point_on_triangle([1.0, 1.0, 0.0], t);
        assert!((e[0] - 0.5).abs() < 1e-15 && (e[1] - 0.5).abs() < 1e-15);
    }

    #[test]
    fn queries_skip_incompatible_normals_and_respect_the_cutoff() {
        // Two parallel squares facing opposite ways, 1 apart.
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ];
        let t = vec![[0, 1, 2], [0, 2, 3], [4, 6, 5], [4, 7, 6]];
        let s = SurfaceIndex::new(&p, &t);
        let q = [0.3, 0.6, 0.9];
        let up = s
            .closest_compatible(q, [0.0, 0.0, 1.0], 10.0, Angle::RIGHT)
            .unwrap();
        assert!(up.triangle < 2 && (up.distance - 0.9).abs() < 1e-12);
        let down = s
            .closest_compatible(q, [0.0, 0.0, -1.0], 10.0, Angle::RIGHT)
            .unwrap();
        assert!(down.triangle >= 2 && (down.distance - 0.1).abs() < 1e-12);
        assert!(s
            .closest_compatible(q, [0.0, 0.0, 1.0], 0.5, Angle::RIGHT)
            .is_none());
        let c = CentroidIndex::new(&p, &t, &[0, 1, 0, 1]);
        assert!(
            c.nearest_compatible(q, [0.0, 0.0, 1.0], 10.0, Angle::RIGHT, None)
                .unwrap()
                < 2
        );
        assert!(
            c.nearest_compatible(q, [0.0, 0.0, -1.0], 10.0, Angle::RIGHT, None)
                .unwrap()
                >= 2
        );
        assert!(c
            .nearest_compatible(q, [0.0, 0.0, 1.0], 0.5, Angle::RIGHT, None)
            .is_none());
        // Within one part only.
        assert_eq!(
            c.nearest_compatible(q, [0.0, 0.0, 1.0], 10.0, Angle::RIGHT, Some(1)),
            Some(1)
        );
        assert_eq!(
            c.nearest_compatible(q, [0.0, 0.0, -1.0], 10.0, Angle::RIGHT, Some(0)),
            Some(2)
        );
    }
}
