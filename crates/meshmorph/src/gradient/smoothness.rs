//! Smoothness across edges: neighbouring triangles asked to deform alike.

use super::GradientOperators;
use crate::gradient::solve::SymmetricBuilder;
use crate::mesh::topology::{linked_pairs, Edge};

impl<const D: usize, const K: usize> GradientOperators<D, K> {
    /// `Σ scale · ½ (w_a + w_b) ‖X G_a − X G_b‖²_F` over every pair of
    /// triangles `a`, `b` sharing one of `edges` (as
    /// [`linked_pairs`] links them) for which `include(a, b)`: each pair
    /// counts in proportion to the mean weight `w` (area) of its two
    /// triangles.
    pub(crate) fn add_smoothness(
        &self,
        builder: &mut SymmetricBuilder,
        edges: &[Edge],
        triangle_weights: &[f64],
        scale: f64,
        include: impl Fn(usize, usize) -> bool,
    ) {
        for e in edges {
            for (a, b) in linked_pairs(&e.triangles) {
                let (a, b) = (a as usize, b as usize);
                if include(a, b) {
                    let w = scale * 0.5 * (triangle_weights[a] + triangle_weights[b]);
                    self.add_difference(builder, a, b, w);
                }
            }
        }
    }
}
