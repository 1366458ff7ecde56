//! Planar triangles: signed areas and the gradients of the three hat
//! functions (piecewise-linear interpolation) of each triangle.

use super::TriangleMaps;
use crate::linalg::matrix::Mat2;
use crate::linalg::vector::signed_area2;
use crate::linalg::Space;
use crate::mesh::topology::TriangleAdjacency;
use crate::mesh::Mesh2;

impl TriangleMaps<2> for Space<2> {
    #[inline]
    fn area(p: &[[f64; 2]; 3]) -> f64 {
        signed_area2(p[0], p[1], p[2])
    }

    /// `∇φ_i = rot90(p_{i+2} − p_{i+1}) / (2 area)`.
    #[inline]
    fn hat_gradients(p: &[[f64; 2]; 3], signed_area: f64) -> [[f64; 2]; 3] {
        let inv = 0.5 / signed_area;
        std::array::from_fn(|i| {
            let (a, b) = (p[(i + 1) % 3], p[(i + 2) % 3]);
            [-(b[1] - a[1]) * inv, (b[0] - a[0]) * inv]
        })
    }

    /// `A = Σ_k q_k ∇φ_kᵀ`.
    #[inline]
    fn linear_map(_: &[[f64; 2]; 3], gradients: &[[f64; 2]; 3], q: &[[f64; 2]; 3]) -> Mat2 {
        let mut a = [[0.0; 2]; 2];
        for (g, qk) in gradients.iter().zip(q) {
            for i in 0..2 {
                for j in 0..2 {
                    a[i][j] += qk[i] * g[j];
                }
            }
        }
        a
    }

    /// Reversed or collapsed: the signed area changed sign or vanished.
    type RestFolds = ();

    fn rest_folds(_: &Mesh2, _: &TriangleAdjacency) {}

    fn turned_over(
        rest: &Mesh2,
        _: &TriangleAdjacency,
        _: &(),
        positions: &[[f64; 2]],
    ) -> Vec<usize> {
        (0..rest.num_triangles())
            .filter(|&t| {
                let corners = rest.triangles()[t].map(|v| positions[v as usize]);
                Self::area(&rest.corners(t)) * Self::area(&corners) <= 0.0
            })
            .collect()
    }
}
