//! # meshmorph
//!
//! Gradient-domain shape animation on triangle meshes:
//!
//! - [`Interpolator`]: as-rigid-as-possible shape interpolation of planar
//!   meshes (Alexa, Cohen-Or and Levin, SIGGRAPH 2000) with rotation
//!   consistency and a system factored once (Baxter, Barla and Anjyo,
//!   NPAR 2008).
//! - [`correspond()`] and [`Transfer`]: deformation transfer (Sumner and
//!   Popović, SIGGRAPH 2004): a triangle correspondence from a few marker
//!   vertex pairs, then any number of source poses carried over to a target.
//! - mesh reading and writing ([`io`]), pictures ([`render`]).
//!
//! ## glTF
//!
//! [`io::gltf::write_glb`] writes frames or poses as one binary glTF 2.0
//! file that Blender, three.js and other viewers open: the base mesh (with
//! texture coordinates per triangle corner, when given), one morph target
//! per frame (position and normal deltas, named in `mesh.extras.targetNames`)
//! and an animation of the morph weights at a frame rate, or shape keys at
//! weight 0 without it. [`io::gltf::estimate_glb_bytes`] says what a file
//! will weigh before any work.
//!
//! Positions are plain `[f64; D]` arrays and triangles `[u32; 3]` index
//! triples; the sparse linear algebra stays behind the [`solve`] module.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Numeric kernels index small fixed-size arrays by position, as the papers do.
#![allow(clippy::needless_range_loop)]

pub mod blend3;
pub mod carried_parts;
pub mod closest;
pub mod consistency3;
pub mod correspond;
pub mod correspondence;
pub mod error;
pub mod geometry;
mod gradient;
pub mod interpolate;
pub mod io;
pub mod markers;
mod matrix;
pub mod mesh;
pub mod polar;
pub mod polar3;
pub mod pose3;
pub mod prepared3;
pub mod render;
pub mod rotation;
pub mod rotation3;
pub mod rotation_field;
pub mod sequence3;
pub mod shapes;
pub mod similarity;
pub mod solve;
pub mod topology;
pub mod transfer;

pub use blend3::Blend3;
pub use correspond::{correspond, CorrespondOptions, CorrespondResult};
pub use correspondence::Correspondence;
pub use error::{Error, Result};
pub use prepared3::PreparedSurface;
pub use sequence3::Sequence3;

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
pub use gradient::TriangleMaps;
pub use interpolate::{Interpolator, InterpolatorOptions, RestSystem, StretchMode};
pub use markers::Markers;
pub use mesh::{Mesh, Mesh2, Mesh3};
pub use rotation::{Rotations, Space};
pub use similarity::Similarity;
pub use solve::FactorKind;
pub use transfer::{Transfer, TransferOptions};
