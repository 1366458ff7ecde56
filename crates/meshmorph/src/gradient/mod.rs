//! The gradient-domain least squares shared by interpolation, deformation
//! transfer and the correspondence.
//!
//! Each of them asks for positions `X` of a rest mesh's unknowns whose
//! per-triangle gradients `X G_t` come as close as they can to given
//! `D × D` matrices:
//!
//! `E(X) = Σ_t w_t ‖X G_t − Q_t‖²_F + Σ_(a,b) w_ab ‖X G_a − X G_b‖²_F (+ terms on single vertices)`
//!
//! with `w` area weights, some unknowns pinned, and each connected part
//! placed afterwards. The normal matrix depends only on the rest mesh and
//! the weights, so it is factored once and every new set of targets `Q` is
//! a right-hand side and a back-substitution. The pieces:
//!
//! - [`GradientOperators`]: `G_t` of every triangle (hat-function gradients
//!   through [`TriangleMaps`], in the plane or within each triangle's plane
//!   in space, or Sumner and Popović's fourth vertex, [`spatial`]), and the
//!   fit and difference terms built from them;
//! - [`smoothness`]: the difference terms across every edge;
//! - [`weights`]: area weights of triangles and vertices;
//! - [`Pins`]: pinned vertices, one held vertex in every otherwise free part;
//! - [`FactoredSystem`]: the normal matrix, pins eliminated, factored once;
//! - [`Placement`]: each connected part's area-weighted centroid and shift.

pub mod folds;
pub mod operators;
pub mod pins;
pub mod placement;
pub mod planar;
pub mod smoothness;
pub mod solve;
pub mod spatial;
pub mod surface;
pub mod system;
pub mod triangle_maps;
pub mod weights;

pub use operators::GradientOperators;
pub use pins::Pins;
pub use placement::Placement;
pub use system::{FactoredSystem, SolveWorkspace};
pub use triangle_maps::TriangleMaps;
