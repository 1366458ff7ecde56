//! Frames computed once and kept, for a run whose frames are read by
//! several writers and are dear to compute: a drawing's frames mended
//! where the fit turns triangles over (tens of milliseconds each on an
//! unlike pair), which the page, the frame files, the pictures, the
//! animated SVG and the Lottie each read in turn. Other runs recompute a
//! frame whenever a writer asks (one back-substitution), and keep no more
//! than the frames in flight.

use std::time::Instant;

use meshmorph::{Dimension, Sequence, Space};

/// The most the kept frames may take: beyond it the writers recompute
/// them, as for any other run.
const BUDGET_BYTES: u64 = 256 << 20;

/// Every frame of an interpolation at the run's times, computed on every
/// thread.
pub struct KeptFrames<const D: usize> {
    frames: Vec<Vec<[f64; D]>>,
    /// Seconds of computing a frame, on average (on one thread).
    seconds_per_frame: f64,
    /// Seconds of the clock computing them all.
    wall_seconds: f64,
}

impl<const D: usize> KeptFrames<D>
where
    Space<D>: Dimension<D>,
{
    /// The frames of `morph` at `times`, when they take no more than
    /// [`BUDGET_BYTES`] and, with the memory the system reports, no more
    /// than a quarter of what is available; `None` otherwise (the writers
    /// then recompute them).
    pub fn compute(morph: &Sequence<D>, times: &[f64]) -> Option<Self> {
        // Each frame's positions, and its list's header and the
        // allocator's share.
        let bytes = (times.len() as u64)
            .saturating_mul((morph.num_vertices() as u64).saturating_mul(8 * D as u64) + 64);
        let room = crate::memory::available().map_or(BUDGET_BYTES, |free| free / 4);
        if bytes > BUDGET_BYTES.min(room) {
            return None;
        }
        let wall = Instant::now();
        let bar = crate::progress::bar(times.len() as u64, "computing frames");
        let (frames, seconds) = crate::frame_chunks::solve(
            morph,
            times,
            || (Vec::new(), 0.0),
            |_, chunk_times, frames, seconds| {
                bar.inc(frames.len() as u64);
                (frames, seconds * chunk_times.len() as f64)
            },
            |(mut frames, seconds), (more, more_seconds)| {
                frames.extend(more);
                (frames, seconds + more_seconds)
            },
        );
        bar.finish_and_clear();
        Some(Self {
            frames,
            seconds_per_frame: seconds / times.len().max(1) as f64,
            wall_seconds: wall.elapsed().as_secs_f64(),
        })
    }

    /// Frame `k`.
    pub fn frame(&self, k: usize) -> &[[f64; D]] {
        &self.frames[k]
    }

    /// Seconds of computing a frame, on average (on one thread).
    pub fn seconds_per_frame(&self) -> f64 {
        self.seconds_per_frame
    }

    /// Seconds of the clock computing them all.
    pub fn wall_seconds(&self) -> f64 {
        self.wall_seconds
    }
}
