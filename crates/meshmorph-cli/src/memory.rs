//! Memory estimates before large allocations: a run that would not fit
//! stops with a message giving the estimate, instead of being killed (or
//! aborting) half way. And one allocator heap shared by every thread.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use meshmorph::limits::{
    FRAMES_IN_FLIGHT_PER_THREAD, MAX_MARKERS, MEMORY_PER_FILE_BYTE, MEMORY_PER_MARKER,
};

/// Makes every thread allocate from one heap (glibc's `M_ARENA_MAX` of 1).
/// By default each thread that allocates gets an arena of its own, and
/// memory one thread frees (the correspondence's matrices) stays in its
/// arena while another thread allocates afresh (the transfer's): the peak
/// then depends on which thread ran what. Face -> head peaked at 218 to 264
/// MiB over runs, and at 211 to 235 MiB with one heap, as fast. Call it
/// before any other thread starts.
pub fn share_one_heap() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only sets a tunable of the C allocator; called
    // first thing in `main`, before any other thread exists.
    unsafe {
        libc::mallopt(libc::M_ARENA_MAX, 1);
    }
}

/// Bytes a run may still allocate: the smaller of the memory the system
/// reports available (`MemAvailable` on Linux) and what the address-space
/// limit (`ulimit -v`) leaves; `None` where neither is known (the figure
/// the library bounds its reads by: [`meshmorph::limits::available_memory`]).
pub fn available() -> Option<u64> {
    meshmorph::limits::available_memory()
}

/// Refuses to go on when `bytes` (what `what` needs) exceeds [`available`].
///
/// # Errors
/// Giving the estimate and what is available.
pub fn check(bytes: u64, what: &str) -> Result<()> {
    if let Some(free) = available() {
        if bytes > free {
            bail!(
                "{what} needs about {} of memory, but only {} is available: use a smaller input or free memory",
                human_bytes(bytes),
                human_bytes(free)
            );
        }
    }
    Ok(())
}

/// Reading meshes: the file's bytes, then the parsed positions and
/// triangles (smaller than the text; a binary PLY's are about its size),
/// [`MEMORY_PER_FILE_BYTE`] times the bytes of the regular files among
/// `paths` (the library refuses the others when it reads them, and bounds
/// each read by the same figure).
pub fn check_reading(paths: &[&Path]) -> Result<()> {
    let bytes = sum_of_regular_files(paths, |len| len);
    check(
        bytes.saturating_mul(MEMORY_PER_FILE_BYTE),
        "reading the meshes",
    )
}

/// The sum of `cost(size)` over the regular files among `paths` (the
/// library refuses the others when it reads them).
fn sum_of_regular_files(paths: &[impl AsRef<Path>], cost: impl Fn(u64) -> u64) -> u64 {
    paths
        .iter()
        .filter_map(|p| std::fs::metadata(p).ok())
        .filter(std::fs::Metadata::is_file)
        .map(|m| cost(m.len()))
        .fold(0, u64::saturating_add)
}

/// Reading marker files: each file's text, and [`MEMORY_PER_MARKER`] bytes
/// for each marker it can hold (a line takes at least 4 bytes, `0 1` and its
/// end; at most [`MAX_MARKERS`] are read).
pub fn check_markers(paths: &[PathBuf]) -> Result<()> {
    let bytes = sum_of_regular_files(paths, |len| {
        let markers = (len / 4).min(MAX_MARKERS as u64);
        len.saturating_add(markers.saturating_mul(MEMORY_PER_MARKER))
    });
    check(bytes, "reading the markers")
}

/// Bytes per triangle of a solver setup (interpolation or transfer),
/// measured on planar strips from 10^4 to 10^7 triangles, with a margin:
/// per-triangle data, the sparse system and its Cholesky factor.
const SETUP_BYTES_PER_TRIANGLE: u64 = 700;

/// A solver setup over `triangles` triangles.
pub fn check_setup(triangles: usize, what: &str) -> Result<()> {
    check(
        (triangles as u64).saturating_mul(SETUP_BYTES_PER_TRIANGLE),
        what,
    )
}

/// Bytes per triangle and segment of a keyframe sequence or per shape of a
/// blend, counted from what is kept (a segment's rotation: 12 numbers; its
/// stretches: 18) and what is built beside it (the key's polar
/// decompositions and whole turns), with a margin.
const SEGMENT_BYTES_PER_TRIANGLE: u64 = 480;

/// The per-triangle data of `segments` segments (or blend shapes) over
/// `triangles` triangles.
pub fn check_sequence(triangles: usize, segments: usize) -> Result<()> {
    check(
        (triangles as u64)
            .saturating_mul(segments as u64)
            .saturating_mul(SEGMENT_BYTES_PER_TRIANGLE),
        "the rotations and stretches of the keys",
    )
}

/// What an animation holds of its frames: with frames streamed to their
/// files (and recomputed for the pictures and the GLB), each thread holds
/// the positions of the frames it solves together
/// ([`meshmorph::limits::FRAMES_PER_SOLVE`]), its solver scratch (as large again)
/// and, writing a GLB, the bytes of [`FRAMES_IN_FLIGHT_PER_THREAD`] frames
/// (24 per vertex); the run also keeps about a kilobyte per frame file
/// (names, timings, the report).
pub fn check_frames_in_flight(
    vertices: usize,
    dim: usize,
    threads: usize,
    frames: usize,
) -> Result<()> {
    let per_thread = (vertices as u64).saturating_mul(
        8 * dim as u64 * 2 * meshmorph::limits::FRAMES_PER_SOLVE as u64
            + 24 * FRAMES_IN_FLIGHT_PER_THREAD as u64,
    );
    let bookkeeping = (frames as u64).saturating_mul(FRAME_FILE_BYTES);
    check(
        per_thread
            .saturating_mul(threads.max(1) as u64)
            .saturating_add(bookkeeping),
        "the frames in flight",
    )
}

/// What a run keeps per frame file: its path (planned, staged, resolved),
/// its timings and its line of the report.
const FRAME_FILE_BYTES: u64 = 1024;

pub fn human_bytes(b: u64) -> String {
    let b = b as f64;
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else {
        format!("{:.0} MB", (b / 1e6).max(1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimates_beyond_any_machine_are_refused() {
        if available().is_none() {
            eprintln!("skipped: no memory figure on this system");
            return;
        }
        let e = check(u64::MAX, "a test").unwrap_err().to_string();
        assert!(e.contains("a test needs about"), "{e}");
        assert!(check(1, "a test").is_ok());
    }
}
