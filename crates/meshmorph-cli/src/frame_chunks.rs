//! Frames solved a few together on every thread: one back-substitution
//! for a chunk of frames, and each chunk handed on as soon as it is solved.

use std::time::Instant;

use meshmorph::{Dimension, Sequence, Space};
use rayon::prelude::*;

/// The frames of `morph` at `times`, solved in chunks of
/// [`meshmorph::limits::frames_per_solve`] on every thread, each with one
/// workspace per thread. Each chunk is handed to `each` with the index of
/// its first frame, its times, its frames and the seconds a frame took to
/// solve (on one thread); what `each` returns is combined with `merge`,
/// in the frames' order, starting from `empty`.
pub fn solve<const D: usize, R: Send>(
    morph: &Sequence<D>,
    times: &[f64],
    empty: impl Fn() -> R + Sync + Send,
    each: impl Fn(usize, &[f64], Vec<Vec<[f64; D]>>, f64) -> R + Sync + Send,
    merge: impl Fn(R, R) -> R + Sync + Send,
) -> R
where
    Space<D>: Dimension<D>,
{
    let together = meshmorph::limits::frames_per_solve(times.len());
    times
        .par_chunks(together)
        .enumerate()
        .map_init(
            || morph.workspace(),
            |ws, (chunk, chunk_times)| {
                let begin = Instant::now();
                let frames = morph.frames_with(chunk_times, ws);
                let seconds = begin.elapsed().as_secs_f64() / chunk_times.len() as f64;
                each(chunk * together, chunk_times, frames, seconds)
            },
        )
        .reduce(empty, merge)
}
