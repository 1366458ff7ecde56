//! What the library's work costs, for front ends that check before they
//! start (the command line, Python, the Blender add-on): a run refused at
//! once is better than one that fills the memory or the disk after minutes
//! of work.
//!
//! - Reading: [`available_memory`], and [`MEMORY_PER_FILE_BYTE`] bytes of
//!   memory per byte of a mesh file at its peak; material libraries larger
//!   than [`MAX_MATERIAL_LIBRARY_BYTES`] are refused. A marker file holds
//!   at most [`MAX_MARKERS`] markers, each taking [`MEMORY_PER_MARKER`]
//!   bytes at the peak of reading it.
//! - Solving: a sequence solves up to [`FRAMES_PER_SOLVE`] frames at once
//!   ([`frames_per_solve`] for a given count), each thread with its own
//!   right-hand sides.
//! - Writing a GLB: up to [`FRAMES_IN_FLIGHT_PER_THREAD`] frames per thread
//!   are held at once; frame rates are in [`FRAME_RATES`].

pub use crate::interpolate::{frames_per_solve, FRAMES_PER_SOLVE};
pub use crate::io::marker_file::{MAX_MARKERS, MEMORY_PER_MARKER};
pub use crate::io::read::{available_memory, MAX_MATERIAL_LIBRARY_BYTES, MEMORY_PER_FILE_BYTE};
pub use crate::mesh::frame_source::FRAME_RATES;

/// Frames a GLB writer prepares at once, per thread: their bytes (24 per
/// vertex in space, 12 in the plane) are all it holds of the frames.
pub const FRAMES_IN_FLIGHT_PER_THREAD: usize = 2;
