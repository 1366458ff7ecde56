//! A point of a mesh's surface: a vertex, or a point of a triangle given by
//! barycentric coordinates; and the nearest point of a surface to a point
//! in space.

use crate::linalg::vector::{add, scale};
use crate::mesh::closest::{closest_region, Region, SurfaceIndex};
use crate::mesh::Mesh3;

/// How far from 1 the barycentric coordinates of a point may sum, and how
/// far below 0 or above 1 each may lie: coordinates written with 7 or more
/// decimals pass (three numbers rounded to 9 decimals may sum to
/// 1.000000001), and are then renormalised ([`SurfacePoint::normalized`]).
pub const BARYCENTRIC_TOLERANCE: f64 = 1e-6;

/// A point of a mesh's surface.
///
/// A point of triangle `t` with corners $A, B, C$ (in the order the mesh
/// lists them) and barycentric coordinates $(b_0, b_1, b_2)$ is
/// $b_0 A + b_1 B + b_2 C$, with $b_0 + b_1 + b_2 = 1$ and every $b_i$ in
/// $[0, 1]$ (Wrap's `[t, u, v]` is $(u, v, 1 - u - v)$). A point of a
/// triangle that lies on one of its corners (weight 1 there) is that
/// vertex wherever it matters ([`SurfacePoint::terms`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfacePoint {
    /// A vertex, 0-based.
    Vertex(u32),
    /// A point of a triangle.
    Triangle {
        /// The triangle, 0-based.
        triangle: u32,
        /// The weights of its corners, in the triangle's order.
        barycentric: [f64; 3],
    },
}

impl SurfacePoint {
    /// The vertices the point is made of with their weights: `(v, 1)` for a
    /// vertex, the corners of a triangle with non-zero weight otherwise. A
    /// point is $\sum_i w_i x_{v_i}$.
    ///
    /// # Panics
    /// If the triangle is out of range of `triangles`.
    pub fn terms(&self, triangles: &[[u32; 3]]) -> impl Iterator<Item = (u32, f64)> {
        let (vertices, weights) = match *self {
            SurfacePoint::Vertex(v) => ([v, 0, 0], [1.0, 0.0, 0.0]),
            SurfacePoint::Triangle {
                triangle,
                barycentric,
            } => (triangles[triangle as usize], barycentric),
        };
        vertices.into_iter().zip(weights).filter(|&(_, w)| w != 0.0)
    }

    /// The point's position on `mesh`: a vertex's own position (bit for
    /// bit, also for a corner of a triangle), or $\sum_i b_i x_i$ over the
    /// triangle's corners.
    ///
    /// # Panics
    /// If the vertex or triangle is out of range of `mesh`.
    pub fn position(&self, mesh: &Mesh3) -> [f64; 3] {
        match self.as_vertex(mesh.triangles()) {
            Some(v) => mesh.positions()[v as usize],
            None => self.terms(mesh.triangles()).fold([0.0; 3], |sum, (v, w)| {
                add(sum, scale(mesh.positions()[v as usize], w))
            }),
        }
    }

    /// The vertex the point is, if it is one: a vertex, or a corner of its
    /// triangle (weight exactly 1 there).
    ///
    /// # Panics
    /// If the triangle is out of range of `triangles`.
    pub fn as_vertex(&self, triangles: &[[u32; 3]]) -> Option<u32> {
        let mut terms = self.terms(triangles);
        match (terms.next(), terms.next()) {
            (Some((v, w)), None) => (w == 1.0).then_some(v),
            _ => None,
        }
    }

    /// The point with its barycentric coordinates made exact: each clamped to
    /// `[0, 1]`, then divided by their sum; or why they are no point of the
    /// triangle ([`SurfacePoint::barycentric_problem`]). A vertex is itself.
    ///
    /// # Errors
    /// The sentence of [`SurfacePoint::barycentric_problem`].
    pub fn normalized(self) -> std::result::Result<Self, String> {
        if let Some(problem) = self.barycentric_problem() {
            return Err(problem);
        }
        Ok(match self {
            SurfacePoint::Triangle {
                triangle,
                barycentric,
            } => {
                let b = barycentric.map(|x| x.clamp(0.0, 1.0));
                let sum: f64 = b.iter().sum();
                SurfacePoint::Triangle {
                    triangle,
                    barycentric: b.map(|x| x / sum),
                }
            }
            vertex => vertex,
        })
    }

    /// Why the barycentric coordinates of a triangle point are no point of
    /// the triangle (not finite, outside `[0, 1]`, or not summing to 1,
    /// within [`BARYCENTRIC_TOLERANCE`]); `None` for a vertex or a good
    /// triangle point.
    pub fn barycentric_problem(&self) -> Option<String> {
        let SurfacePoint::Triangle { barycentric: b, .. } = *self else {
            return None;
        };
        let sum: f64 = b.iter().sum();
        if !b.iter().all(|x| x.is_finite()) {
            Some(format!(
                "the barycentric coordinates {b:?} are not all finite"
            ))
        } else if (sum - 1.0).abs() > BARYCENTRIC_TOLERANCE {
            Some(format!(
                "the barycentric coordinates {} {} {} sum to {sum}, not 1",
                b[0], b[1], b[2]
            ))
        } else if b
            .iter()
            .any(|&x| !(-BARYCENTRIC_TOLERANCE..=1.0 + BARYCENTRIC_TOLERANCE).contains(&x))
        {
            Some(format!(
                "the barycentric coordinates {} {} {} are not all between 0 and 1: the point lies outside its triangle",
                b[0], b[1], b[2]
            ))
        } else {
            None
        }
    }
}

/// The point of `mesh`'s surface nearest to `q` (of equally near
/// triangles, the first in the index's order), and its distance from `q`:
/// a vertex when the nearest point is a corner, else a triangle with its
/// barycentric coordinates. `None` when the mesh has no triangle.
pub fn nearest_surface_point(
    index: &SurfaceIndex,
    mesh: &Mesh3,
    q: [f64; 3],
) -> Option<(SurfacePoint, f64)> {
    let closest = index.closest(q)?;
    let t = closest.triangle;
    let corners = mesh.triangles()[t as usize];
    let point = match closest_region(q, mesh.corners(t as usize)) {
        Region::Corner(k) => SurfacePoint::Vertex(corners[k]),
        region => SurfacePoint::Triangle {
            triangle: t,
            barycentric: region.barycentric(),
        },
    };
    Some((point, closest.distance))
}
