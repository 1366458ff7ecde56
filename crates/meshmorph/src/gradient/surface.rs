//! Triangles in space: unsigned areas and the gradients of the three hat
//! functions of each triangle, within its plane; the map between two
//! triangles is Sumner and Popović's, through a fourth vertex off the plane
//! ([`super::spatial`]).
//!
//! With these, the normal matrix of a surface's fit
//! `Σ_T area_T ‖J_T(x) − A_T P_T‖²_F` (`J_T` the surface gradient, `P_T`
//! the projection onto the rest triangle's plane) is the cotangent Laplacian
//! of the rest mesh, the same for x, y and z: one factorization, three
//! right-hand sides.

use super::folds::{turned_over_in_space, RestDihedrals};
use super::spatial::{deformation_gradient, frame};
use super::TriangleMaps;
use crate::linalg::matrix::{identity, inverse3, Mat3};
use crate::linalg::vector::{cross, norm, scale, sub};
use crate::linalg::Space;
use crate::mesh::topology::TriangleAdjacency;
use crate::mesh::Mesh3;

impl TriangleMaps<3> for Space<3> {
    #[inline]
    fn area(p: &[[f64; 3]; 3]) -> f64 {
        0.5 * norm(cross(sub(p[1], p[0]), sub(p[2], p[0])))
    }

    /// `∇φ_i = n̂ × (p_{i+2} − p_{i+1}) / (2 area)`, `n̂` the unit normal.
    #[inline]
    fn hat_gradients(p: &[[f64; 3]; 3], area: f64) -> [[f64; 3]; 3] {
        let normal = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        let unit = scale(normal, 1.0 / norm(normal));
        let inv = 0.5 / area;
        std::array::from_fn(|i| scale(cross(unit, sub(p[(i + 2) % 3], p[(i + 1) % 3])), inv))
    }

    /// The 3×3 map between the triangles' frames (two edges and the scaled
    /// normal).
    #[inline]
    fn linear_map(rest: &[[f64; 3]; 3], _: &[[f64; 3]; 3], q: &[[f64; 3]; 3]) -> Mat3 {
        deformation_gradient(inverse3(frame(*rest)).unwrap_or(identity()), *q)
    }

    /// Collapsed, or folded back through their neighbours (the signed
    /// dihedral angles of their shared edges).
    type RestFolds = RestDihedrals;

    fn rest_folds(rest: &Mesh3, adjacency: &TriangleAdjacency) -> RestDihedrals {
        RestDihedrals::new(rest, adjacency)
    }

    fn turned_over(
        rest: &Mesh3,
        adjacency: &TriangleAdjacency,
        folds: &RestDihedrals,
        positions: &[[f64; 3]],
    ) -> Vec<usize> {
        turned_over_in_space(rest, adjacency, folds, positions)
    }
}
