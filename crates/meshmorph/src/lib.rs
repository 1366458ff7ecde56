//! # meshmorph
//!
//! Gradient-domain shape animation on triangle meshes:
//!
//! - [`Interpolator`], [`Sequence`] and [`Blend`]: as-rigid-as-possible
//!   shape interpolation of planar meshes and of surfaces in space (Alexa,
//!   Cohen-Or and Levin, SIGGRAPH 2000), between two keys, through any
//!   number of keys, and blends of shapes with weights, with rotation
//!   consistency and a system factored once (Baxter, Barla and Anjyo, NPAR
//!   2008); one machinery for both dimensions.
//! - [`correspond()`] and [`Transfer`]: deformation transfer (Sumner and
//!   Popović, SIGGRAPH 2004): a triangle correspondence from a few marker
//!   vertex pairs, then any number of source poses carried over to a target.
//! - mesh reading and writing ([`io`]), pictures ([`render`]); [`Seams`]
//!   welds the copies of vertices that files split at texture seams, so
//!   that the solvers see one surface.
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
//! triples; small matrices are row-major `[[f64; D]; D]` ([`Mat`]). The
//! sparse linear algebra stays inside the crate.
//!
//! ## Inside
//!
//! Interpolation, transfer and the correspondence share one gradient-domain
//! least-squares core: per-triangle gradient operators of a rest mesh, area
//! weights, the normal matrix factored once with pinned unknowns
//! eliminated, and the placement of each connected part. What depends on
//! the rest mesh alone is a value of its own ([`RestSystem`] for
//! interpolation), shared between targets, sequences and blends. The
//! dimension-dependent algebra of interpolation is behind two traits
//! implemented by [`Space`]: [`Rotations`] (polar decomposition, rotation
//! logarithm and exponential, a rotation's path between two keys, the choice
//! of rotation branches over the triangle adjacency) and [`TriangleMaps`]
//! (areas, hat-function gradients, per-triangle maps, turned-over
//! triangles).
#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Numeric kernels index small fixed-size arrays by position, as the papers do.
#![allow(clippy::needless_range_loop)]

mod error;
mod gradient;
mod interpolate;
pub mod io;
mod linalg;
mod mesh;
pub mod render;
mod transfer;

pub use error::{Error, Result, DEGENERATE_FIX};
pub use gradient::solve::FactorKind;
pub use gradient::TriangleMaps;
pub use interpolate::rotation::{RotationLog3, Rotations};
pub use interpolate::{
    frames_per_solve, Blend, Blend3, FrameWorkspace, Interpolator, InterpolatorOptions,
    PreparedSurface, RestSystem, Sequence, Sequence3, SequenceWorkspace, StretchMode,
    FRAMES_PER_SOLVE,
};
pub use linalg::matrix::Mat;
pub use linalg::Space;
pub use linalg::{polar as polar3, quaternion as rotation3, similarity};
pub use mesh::frame_source::{FrameSource, FRAME_RATES};
pub use mesh::seams::Seams;
pub use mesh::{shapes, topology};
pub use mesh::{Mesh, Mesh2, Mesh3};
pub use similarity::Similarity;
pub use transfer::correspondence::Correspondence;
pub use transfer::markers::{Markers, Snap, SNAP_LIMIT};
pub use transfer::matching::{
    correspond, correspond_steps, CorrespondOptions, CorrespondResult, MIN_MARKERS,
};
pub use transfer::pose_transfer::{PoseWorkspace, Transfer, TransferOptions};
pub use transfer::{carried_parts, mirror_plane, rotation_field};

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
