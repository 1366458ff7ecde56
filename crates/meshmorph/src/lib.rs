//! # meshmorph
//!
//! Gradient-domain shape animation on triangle meshes: as-rigid-as-possible
//! shape interpolation and deformation transfer.
//!
//! ```no_run
//! use std::path::Path;
//! use meshmorph::io::{read_mesh, MeshFile};
//! use meshmorph::{correspond, CorrespondOptions, Interpolator, InterpolatorOptions};
//! use meshmorph::{Markers, Transfer, TransferOptions, VertexNumbering};
//!
//! // Interpolate between two keys with the same triangles; write the frame
//! // at t = 0.5 keeping the first key's quads, UVs and materials.
//! let first = MeshFile::read(Path::new("horse-01.obj"))?;
//! let last = read_mesh(Path::new("horse-07.obj"))?;
//! let morph = Interpolator::new(first.mesh(), &last, &InterpolatorOptions::default())?;
//! first.save(Path::new("halfway.obj"), &morph.at(0.5))?;
//!
//! // Carry a pose of the horse over to the camel through marker pairs.
//! let (horse, camel) = (read_mesh(Path::new("horse.obj"))?, MeshFile::read(Path::new("camel.obj"))?);
//! let markers = Markers::read(Path::new("horse-camel.cons"), VertexNumbering::FromZero)?;
//! let found = correspond(&horse, camel.mesh(), &markers, &CorrespondOptions::default())?;
//! let transfer = Transfer::new(&horse, camel.mesh(), &found.correspondence, &TransferOptions::default())?;
//! camel.save(Path::new("camel-gallop.obj"), &transfer.apply(&read_mesh(Path::new("horse-gallop.obj"))?)?)?;
//! # Ok::<(), meshmorph::Error>(())
//! ```
//!
//! - [`Interpolator`], [`Sequence`] and [`Blend`]: as-rigid-as-possible
//!   shape interpolation (Alexa, Cohen-Or and Levin, SIGGRAPH 2000) between
//!   two keys, through any number of keys, and blends of shapes with
//!   weights, with rotation consistency and a system factored once
//!   (Baxter, Barla and Anjyo, NPAR 2008). The dimension `D` (2 for planar
//!   meshes, 3 for surfaces in space) comes from the meshes given:
//!   [`io::read_planar_mesh`] reads a planar file as a [`Mesh2`],
//!   [`io::read_mesh`] any file as a [`Mesh3`].
//! - [`correspond()`] and [`Transfer`]: deformation transfer (Sumner and
//!   Popović, SIGGRAPH 2004): a triangle correspondence from a few marker
//!   pairs of surface points ([`Markers`], [`SurfacePoint`]), then any number of source poses carried
//!   over to a target, one back-substitution each.
//! - [`outline::compatible_set`] (and [`outline::compatible_meshes`] for
//!   two): drawings (planar regions given as loops of points, with holes)
//!   to meshes with the same triangles, for [`Interpolator`] and
//!   [`Sequence`]: the outlines matched automatically, anchors kept on
//!   the outlines or inside, the triangles from one drawing's refined mesh
//!   mapped into the others and untangled, else from the overlay of
//!   Aronov, Seidel and Souvaine (1993), improved by compatible flips,
//!   splits, smoothing and relaxation.
//! - [`io`]: OBJ, OFF, PLY and STL read and written back whole
//!   ([`io::MeshFile`]), animations and shape keys as binary glTF
//!   ([`io::gltf`]), marker and correspondence files.
//! - `render` (with the `render` feature): pictures, SVG, GIF and PNG,
//!   drawn by the crate itself.
//! - [`shapes`]: procedural meshes for tests, examples and benchmarks;
//!   [`limits`]: what the work costs, for front ends that check first.
//!
//! What the command line warns about is data here:
//! [`io::MeshFile::surface_issues`] (faces repeated, edges shared by more
//! than two faces), [`Mesh::surface_counts`], [`CorrespondResult::far_markers`],
//! [`CorrespondResult::fit`] (a [`FitReport`]: how well the deformed source
//! lies on the target), [`Markers::fit`], [`Interpolator::count_flipped`]
//! and [`Blend::count_turned_over`].
//!
//! Positions are plain `[f64; D]` arrays and triangles `[u32; 3]` index
//! triples; small matrices are row-major `[[f64; D]; D]` ([`Mat`]). The
//! sparse linear algebra stays inside the crate. Everything that does not
//! depend on the frame or pose is computed in `new`; `at_into` and
//! `apply_into` cannot fail.
//!
//! ## Inside
//!
//! The source reads from the bottom up, each folder using only those
//! before it: `linalg/` (small dense algebra: vectors, 2×2 and 3×3
//! matrices, polar decompositions, quaternions, similarity fits), `mesh/`
//! (the mesh and its queries: topology, seams, bounding volumes, closest
//! points, procedural shapes), `outline/` (drawings to compatible meshes:
//! boundary correspondence, compatible triangulation), `gradient/` (the least-squares core shared
//! by interpolation, transfer and the correspondence: per-triangle gradient
//! operators, area weights, pins, placement, and `solve/`, the sparse
//! Cholesky factorization with pinned unknowns eliminated),
//! `interpolate/` (keys, sequences, blends; `rotation/`, the rotations'
//! logarithms and their consistent branches), `transfer/` (markers,
//! mirror planes, the correspondence, carried parts, the transfer), `io/`
//! (files) and `render/` (pictures). The dimension-dependent algebra is
//! behind two traits implemented by [`Space`]: [`Rotations`] and
//! [`TriangleMaps`].
#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Numeric kernels index small fixed-size arrays by position, as the papers do.
#![allow(clippy::needless_range_loop)]
// The modules behind the re-exports below are public but hidden from the
// documentation, for the unit tests (tests/unit/); their own documentation
// links the private helpers it explains.
#![allow(rustdoc::private_intra_doc_links)]

#[doc(hidden)]
pub mod error;
#[doc(hidden)]
pub mod expressions;
#[doc(hidden)]
pub mod gradient;
#[doc(hidden)]
pub mod interpolate;
pub mod io;
pub mod limits;
#[doc(hidden)]
pub mod linalg;
#[doc(hidden)]
pub mod mesh;
pub mod outline;
pub mod playback;
#[cfg(feature = "render")]
pub mod render;
#[doc(hidden)]
pub mod transfer;

pub use error::{Error, Result};
pub use expressions::arkit_names::{arkit_recipes, ShapeRecipe, ARKIT_NAMES};
pub use expressions::carry::{
    expressions, CarryMethod, ExpressionOptions, FoundPart, HeadExpressions, ShapeReport,
};
pub use expressions::landmark_file::read_landmarks;
pub use expressions::landmarks::{
    check_landmarks, landmark_name, landmark_number, ALIASES as LANDMARK_ALIASES, MIN_LANDMARKS,
    RECOMMENDED as RECOMMENDED_LANDMARKS,
};
pub use expressions::places::{FOLD_SLACK, ISLAND_SHARE, LOOKUP_ANGLE, PATH_STRETCH};
pub use expressions::template::{ExpressionTemplate, TemplatePart, ARKIT_TEMPLATE_GLB};
pub use gradient::solve::FactorKind;
pub use gradient::TriangleMaps;
pub use interpolate::rotation::{RotationLog3, Rotations};
pub use interpolate::{
    Blend, Dimension, FrameWorkspace, Interpolator, InterpolatorOptions, RestSystem, Sequence,
    StretchMode,
};
pub use linalg::matrix::Mat;
pub use linalg::similarity::Similarity;
pub use linalg::Space;
pub use mesh::frame_source::FrameSource;
pub use mesh::seams::Seams;
pub use mesh::shapes;
pub use mesh::topology::SurfaceCounts;
pub use mesh::{Mesh, Mesh2, Mesh3, SurfacePoint};
pub use transfer::correspondence::Correspondence;
pub use transfer::fit_report::{
    FitReport, PoorRegion, FIT_DISTANCE_LIMIT, MIN_POOR_REGION, NEAREST_MARKERS,
};
pub use transfer::markers::{Markers, Side as MarkerSide, Snap, VertexNumbering, SNAP_LIMIT};
pub use transfer::matching::{
    correspond, correspond_with_progress, CorrespondOptions, CorrespondResult, MIN_MARKERS,
};
pub use transfer::mirror_plane::MirrorPlane;
pub use transfer::pose_transfer::{PoseWorkspace, Transfer, TransferOptions};

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
