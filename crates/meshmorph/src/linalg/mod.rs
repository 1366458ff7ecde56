//! Small dense algebra on fixed-size arrays: vectors and 2×2/3×3
//! matrices, four-wide lanes, angles, polar decompositions, quaternions and
//! similarity fits. Everything above it (meshes, the gradient-domain core,
//! interpolation, transfer) computes with these.

pub(crate) mod block_chain;
pub(crate) mod lanes;
pub(crate) mod matrix;
pub(crate) mod polar;
pub(crate) mod quaternion;
pub(crate) mod similarity;
pub(crate) mod trig;
pub(crate) mod vector;

/// `D`-dimensional space, the type that carries the dimension-dependent
/// algebra: [`Rotations`](crate::Rotations) for interpolation and
/// [`TriangleMaps`](crate::TriangleMaps) for the gradient operators.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Space<const D: usize>;
