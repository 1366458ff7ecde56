//! The maps of single triangles from a rest shape to a deformed one, in a
//! form that does not depend on the dimension.

use std::fmt::Debug;

use crate::linalg::matrix::Mat;
use crate::mesh::topology::TriangleAdjacency;
use crate::mesh::Mesh;

/// The per-triangle geometry of `D`-dimensional meshes that interpolation
/// needs (implemented by [`Space<2>`](crate::linalg::Space) and [`Space<3>`](crate::linalg::Space)).
pub trait TriangleMaps<const D: usize> {
    /// The area of a triangle: in the plane signed, positive when
    /// counter-clockwise; in space at least 0.
    fn area(corners: &[[f64; D]; 3]) -> f64;
    /// Gradients (one row per corner) of the three hat functions of a rest
    /// triangle of the given (non-zero) `area`, within its plane.
    fn hat_gradients(rest: &[[f64; D]; 3], area: f64) -> [[f64; D]; 3];
    /// The linear part (`D × D`) of the affine map that takes a rest
    /// triangle, whose hat gradients are `gradients`, to `corners`.
    fn linear_map(
        rest: &[[f64; D]; 3],
        gradients: &[[f64; D]; 3],
        corners: &[[f64; D]; 3],
    ) -> Mat<D>;
    /// What [`TriangleMaps::turned_over`] needs of the rest mesh, computed
    /// once for any number of poses: in space the signed dihedral angle of
    /// each pair of neighbours, in the plane nothing.
    type RestFolds: Debug + Send + Sync + 'static;
    /// [`TriangleMaps::RestFolds`] of `rest` (`adjacency`, its triangle
    /// adjacency).
    fn rest_folds(rest: &Mesh<D>, adjacency: &TriangleAdjacency) -> Self::RestFolds;
    /// The triangles of `positions` (a pose of `rest`) turned over relative
    /// to `rest`: in the plane those reversed or collapsed; in space those
    /// collapsed or folded back through their neighbours (`adjacency`, the
    /// rest's triangle adjacency; `folds`, its [`TriangleMaps::rest_folds`]).
    fn turned_over(
        rest: &Mesh<D>,
        adjacency: &TriangleAdjacency,
        folds: &Self::RestFolds,
        positions: &[[f64; D]],
    ) -> Vec<usize>;
}
