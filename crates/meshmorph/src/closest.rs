//! Spatial queries with a normal-compatibility filter: the closest point of
//! a surface, the nearest triangle centroid.
//!
//! Both answer "the nearest thing whose normal is less than 90° from mine,
//! within a distance", as deformation transfer needs (Sumner and Popović
//! 2004, sections 5.1 and 5.2). They walk an R-tree ([`rstar`]) in order of
//! distance and stop at the first compatible candidate or at the cut-off.

use rstar::primitives::GeomWithData;
use rstar::{PointDistance, RTree, RTreeObject, AABB};

use crate::geometry::{add, cross, dot, norm, scale, sub};

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
pub fn closest_point_on_triangle(q: [f64; 3], p: [[f64; 3]; 3]) -> [f64; 3] {
    let [a, b, c] = p;
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(q, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(q, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return add(a, scale(ab, d1 / (d1 - d3)));
    }
    let cp = sub(q, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return add(a, scale(ac, d2 / (d2 - d6)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return add(b, scale(sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
    }
    let denom = va + vb + vc;
    if denom == 0.0 {
        // Degenerate triangle: fall back to the nearest corner.
        return *[a, b, c]
            .iter()
            .min_by(|x, y| dot(sub(q, **x), sub(q, **x)).total_cmp(&dot(sub(q, **y), sub(q, **y))))
            .expect("three corners");
    }
    let (v, w) = (vb / denom, vc / denom);
    add(a, add(scale(ab, v), scale(ac, w)))
}

struct Triangle {
    index: u32,
    corners: [[f64; 3]; 3],
    envelope: AABB<[f64; 3]>,
}

impl RTreeObject for Triangle {
    type Envelope = AABB<[f64; 3]>;
    fn envelope(&self) -> Self::Envelope {
        self.envelope
    }
}

impl PointDistance for Triangle {
    fn distance_2(&self, point: &[f64; 3]) -> f64 {
        let d = sub(closest_point_on_triangle(*point, self.corners), *point);
        dot(d, d)
    }
}

/// The triangles of a surface, for closest-point queries.
pub struct SurfaceIndex {
    tree: RTree<Triangle>,
    normals: Vec<[f64; 3]>,
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
            .enumerate()
            .map(|(t, tri)| {
                let corners = tri.map(|v| positions[v as usize]);
                Triangle {
                    index: t as u32,
                    corners,
                    envelope: AABB::from_points(corners.iter()),
                }
            })
            .collect();
        let normals = triangles
            .iter()
            .map(|t| unit_normal(t.map(|v| positions[v as usize])))
            .collect();
        Self {
            tree: RTree::bulk_load(items),
            normals,
        }
    }

    /// The closest point to `q` on a triangle whose normal is less than 90°
    /// from `normal`, if one lies within `max_distance`.
    pub fn closest_compatible(
        &self,
        q: [f64; 3],
        normal: [f64; 3],
        max_distance: f64,
    ) -> Option<ClosestPoint> {
        let candidates = self.tree.nearest_neighbor_iter_with_distance_2(q);
        let (tri, d2) = first_compatible(
            candidates,
            |t| self.normals[t.index as usize],
            normal,
            max_distance,
        )?;
        Some(ClosestPoint {
            triangle: tri.index,
            point: closest_point_on_triangle(q, tri.corners),
            distance: d2.sqrt(),
        })
    }
}

/// The first of `candidates` (in order of squared distance) whose normal is
/// less than 90° from `normal`, unless the walk passes `max_distance` first.
fn first_compatible<'a, T: 'a>(
    candidates: impl Iterator<Item = (&'a T, f64)>,
    normal_of: impl Fn(&T) -> [f64; 3],
    normal: [f64; 3],
    max_distance: f64,
) -> Option<(&'a T, f64)> {
    let max2 = max_distance * max_distance;
    candidates
        .take_while(|&(_, d2)| d2 <= max2)
        .find(|&(item, _)| dot(normal_of(item), normal) > 0.0)
}

/// Triangle centroids with their unit normals, for nearest-triangle queries.
pub struct CentroidIndex {
    tree: RTree<GeomWithData<[f64; 3], u32>>,
    normals: Vec<[f64; 3]>,
}

impl CentroidIndex {
    /// Indexes the centroids of the triangles of a mesh.
    pub fn new(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Self {
        let mut normals = Vec::with_capacity(triangles.len());
        let items = triangles
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                let p = tri.map(|v| positions[v as usize]);
                normals.push(unit_normal(p));
                GeomWithData::new(crate::geometry::centroid(p), t as u32)
            })
            .collect();
        Self {
            tree: RTree::bulk_load(items),
            normals,
        }
    }

    /// The triangle whose centroid is nearest to `q` among those whose normal
    /// is less than 90° from `normal`, if one lies within `max_distance`.
    pub fn nearest_compatible(
        &self,
        q: [f64; 3],
        normal: [f64; 3],
        max_distance: f64,
    ) -> Option<u32> {
        let candidates = self.tree.nearest_neighbor_iter_with_distance_2(q);
        first_compatible(
            candidates,
            |item| self.normals[item.data as usize],
            normal,
            max_distance,
        )
        .map(|(item, _)| item.data)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let up = s.closest_compatible(q, [0.0, 0.0, 1.0], 10.0).unwrap();
        assert!(up.triangle < 2 && (up.distance - 0.9).abs() < 1e-12);
        let down = s.closest_compatible(q, [0.0, 0.0, -1.0], 10.0).unwrap();
        assert!(down.triangle >= 2 && (down.distance - 0.1).abs() < 1e-12);
        assert!(s.closest_compatible(q, [0.0, 0.0, 1.0], 0.5).is_none());
        let c = CentroidIndex::new(&p, &t);
        assert!(c.nearest_compatible(q, [0.0, 0.0, 1.0], 10.0).unwrap() < 2);
        assert!(c.nearest_compatible(q, [0.0, 0.0, -1.0], 10.0).unwrap() >= 2);
        assert!(c.nearest_compatible(q, [0.0, 0.0, 1.0], 0.5).is_none());
    }
}
