//! The frames of an animation, produced on demand, so that writers of
//! animations (GLB, GIF) need not hold them all: a list of frames in
//! memory is one source, an interpolation recomputing each frame (one
//! back-substitution) is another.

use std::ops::RangeInclusive;

/// The frame rates an animation may be written at, in frames per second:
/// from one frame in 100 seconds (a GIF shows a picture for at most 655 s)
/// to 1000 (glTF's `float` times then keep a million frames apart).
pub const FRAME_RATES: RangeInclusive<f64> = 0.01..=1000.0;

/// Frames of `D`-dimensional vertex positions, numbered from 0, each
/// available as often as a writer asks (a writer may ask twice: once to fit
/// a view or find bounds, once to write).
///
/// ```
/// use meshmorph::FrameSource;
///
/// let frames = vec![vec![[0.0, 0.0], [1.0, 0.0]], vec![[0.0, 1.0], [1.0, 1.0]]];
/// let mut ys = Vec::new();
/// frames.with_frame(1, &mut |f| ys.push(f[0][1]));
/// assert_eq!((frames.num_frames(), ys), (2, vec![1.0]));
/// ```
pub trait FrameSource<const D: usize>: Sync {
    /// Number of frames.
    fn num_frames(&self) -> usize;

    /// Calls `use_frame` with the positions of frame `k` (`k <
    /// num_frames()`).
    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; D]]));
}

impl<const D: usize, F: AsRef<[[f64; D]]> + Sync> FrameSource<D> for [F] {
    fn num_frames(&self) -> usize {
        self.len()
    }

    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; D]])) {
        use_frame(self[k].as_ref())
    }
}

impl<const D: usize, F: AsRef<[[f64; D]]> + Sync> FrameSource<D> for Vec<F> {
    fn num_frames(&self) -> usize {
        self.len()
    }

    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; D]])) {
        use_frame(self[k].as_ref())
    }
}

/// `f` applied to frame `k` of `frames`, returning its result.
pub fn map_frame<const D: usize, S: FrameSource<D> + ?Sized, R>(
    frames: &S,
    k: usize,
    f: impl FnOnce(&[[f64; D]]) -> R,
) -> R {
    let mut f = Some(f);
    let mut result = None;
    frames.with_frame(k, &mut |p| result = f.take().map(|f| f(p)));
    result.expect("a frame source calls back once")
}
