//! What interpolation from one source mesh needs whatever the target.

use crate::error::Result;
use crate::gradient::weights::vertex_weights;
use crate::gradient::{FactoredSystem, GradientOperators, Pins, Placement, TriangleMaps};
use crate::mesh::{check_areas, Mesh};
use crate::solve::{FactorKind, SymmetricBuilder};
use crate::topology::connected_components;
use crate::Space;

/// The gradient operators and area weights of a source mesh, its normal
/// matrix (the cotangent Laplacian) factored once, and the placement of its
/// connected parts: everything an interpolation from it needs whatever the
/// target. Build it once and share it behind an [`Arc`](std::sync::Arc)
/// between any number of interpolations from the same source
/// ([`Interpolator::with_rest`](crate::Interpolator::with_rest)).
#[derive(Debug)]
pub struct RestSystem<const D: usize = 2> {
    pub(super) source: Mesh<D>,
    /// `|area|` of each source triangle: the weight of its fit.
    pub(super) weights: Vec<f64>,
    pub(super) operators: GradientOperators<D, 3>,
    pub(super) system: FactoredSystem<D>,
    /// Every connected part, placed by its area-weighted centroid.
    pub(super) placement: Placement<D>,
    /// Vertices no triangle uses: they move on straight lines.
    pub(super) loose: Vec<u32>,
}

impl<const D: usize> RestSystem<D>
where
    Space<D>: TriangleMaps<D>,
{
    /// Prepares and factors the system of `source`; `factor` chooses the
    /// Cholesky variant.
    ///
    /// # Errors
    /// - [`Error::DegenerateTriangles`](crate::Error::DegenerateTriangles)
    ///   for zero-area source triangles;
    /// - [`Error::Solver`](crate::Error::Solver) if the system cannot be
    ///   factored.
    ///
    /// # Performance
    /// Linear in the number of triangles apart from one sparse Cholesky
    /// factorization of a `#V × #V` matrix.
    pub fn new(source: &Mesh<D>, factor: FactorKind) -> Result<Self> {
        let (n, tris) = (source.num_vertices(), source.triangles());
        let areas: Vec<f64> = (0..tris.len())
            .map(|t| Space::<D>::area(&source.corners(t)))
            .collect();
        check_areas(&areas, source.bounding_box_diagonal(), "source")?;
        let operators = GradientOperators::from_parts(
            n,
            tris.to_vec(),
            (0..tris.len())
                .map(|t| Space::<D>::hat_gradients(&source.corners(t), areas[t]))
                .collect(),
        );
        let weights: Vec<f64> = areas.iter().map(|a| a.abs()).collect();
        // The normal matrix: the area-weighted cotangent Laplacian.
        let mut builder = SymmetricBuilder::new(n, 6 * tris.len());
        for (t, &w) in weights.iter().enumerate() {
            operators.add_fit(&mut builder, t, w);
        }
        let components = connected_components(n, tris);
        let mut pins = Pins::new(n);
        pins.hold_free_parts(&components, |_| [0.0; D]);
        let system = FactoredSystem::new(&builder.build(), &pins, factor)?;
        let placement = Placement::new(&components, |_| true, vertex_weights(n, tris, &weights));
        let loose = (0..n as u32)
            .filter(|&v| components.of_vertex[v as usize].is_none())
            .collect();
        Ok(Self {
            source: source.clone(),
            weights,
            operators,
            system,
            placement,
            loose,
        })
    }

    /// Number of stored values of the Cholesky factor (for measuring a
    /// frame against the memory traffic of its back-substitution).
    pub fn factor_len(&self) -> usize {
        self.system.factor_len()
    }

    /// The source mesh.
    pub fn source(&self) -> &Mesh<D> {
        &self.source
    }

    /// The linear map of triangle `t` from the source to `corners`.
    pub(super) fn linear_map(&self, t: usize, corners: &[[f64; D]; 3]) -> crate::matrix::Mat<D> {
        Space::<D>::linear_map(&self.source.corners(t), self.operators.operator(t), corners)
    }
}
