//! Small dense algebra on fixed-size arrays: vectors and 2×2/3×3
//! matrices, four-wide lanes, angles, polar decompositions, quaternions and
//! similarity fits. Everything above it (meshes, the gradient-domain core,
//! interpolation, transfer) computes with these.

pub mod block_chain;
pub mod lanes;
pub mod matrix;
pub mod polar;
pub mod quaternion;
pub mod similarity;
pub mod trig;
pub mod vector;

/// `D`-dimensional space, the type that carries the dimension-dependent
/// algebra: [`Rotations`](crate::Rotations) for interpolation and
/// [`TriangleMaps`](crate::TriangleMaps) for the gradient operators.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Space<const D: usize>;
