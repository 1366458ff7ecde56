//! Progress bars on stderr, shown only when stderr is a terminal.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use meshmorph::FrameSource;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU8, AtomicUsize, Ordering};

/// A bar over `len` steps labelled `what`; hidden when stderr is not a terminal.
pub fn bar(len: u64, what: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden());
    }
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template(
            "{msg:>12} [{bar:40}] {pos}/{len} {elapsed_precise} (eta {eta})",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar
}

/// Frames read through a counter shown as `what K of N frames`: a writer
/// that reads every frame (a GIF, a GLB), perhaps twice (once to fit its
/// view or bounds, then once to draw or write), is seen at work. The first
/// reading of every frame is counted as `what (fitting) K of N frames`,
/// the second as `what K of N frames`. Hidden when stderr is not a
/// terminal.
pub struct Counted<'a, const D: usize> {
    frames: &'a dyn FrameSource<D>,
    counter: ProgressBar,
    what: String,
    /// How often each frame has been read.
    reads: Vec<AtomicU8>,
    /// Frames read once or more, and twice or more.
    first: AtomicUsize,
    second: AtomicUsize,
}

impl<'a, const D: usize> Counted<'a, D> {
    pub fn new(frames: &'a dyn FrameSource<D>, what: &str) -> Self {
        let n = frames.num_frames();
        let counter = if std::io::stderr().is_terminal() {
            let c = ProgressBar::new(n as u64);
            c.set_style(
                ProgressStyle::with_template("{msg:>12} {pos} of {len} frames {elapsed_precise}")
                    .expect("valid template"),
            );
            c.set_message(what.to_string());
            // Alive between frames too: drawing one may take a while.
            c.enable_steady_tick(std::time::Duration::from_millis(120));
            c
        } else {
            ProgressBar::hidden()
        };
        Counted {
            frames,
            counter,
            what: what.to_string(),
            reads: (0..n).map(|_| AtomicU8::new(0)).collect(),
            first: AtomicUsize::new(0),
            second: AtomicUsize::new(0),
        }
    }

    /// Counts a frame's `read`th reading; returns the progress line's new
    /// text and count, if it changes: `(what, frames done)`.
    fn line(&self, read: u8) -> Option<(String, u64)> {
        match read {
            1 => {
                let done = self.first.fetch_add(1, Ordering::Relaxed) as u64 + 1;
                (self.second.load(Ordering::Relaxed) == 0)
                    .then(|| (format!("{} (fitting)", self.what), done))
            }
            2 => Some((
                self.what.clone(),
                self.second.fetch_add(1, Ordering::Relaxed) as u64 + 1,
            )),
            _ => None,
        }
    }
}

impl<const D: usize> Drop for Counted<'_, D> {
    fn drop(&mut self) {
        self.counter.finish_and_clear();
    }
}

impl<const D: usize> FrameSource<D> for Counted<'_, D> {
    fn num_frames(&self) -> usize {
        self.frames.num_frames()
    }

    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; D]])) {
        self.frames.with_frame(k, use_frame);
        let read = self.reads[k]
            .fetch_add(1, Ordering::Relaxed)
            .saturating_add(1);
        if let Some((message, done)) = self.line(read) {
            self.counter.set_message(message);
            self.counter.set_position(done);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_counted_against_their_total_in_each_pass() {
        let frames = vec![vec![[0.0; 2]]; 4];
        let counted = Counted::new(&frames, "GIF");
        let mut seen = Vec::new();
        for read in [1, 1, 1, 1, 2, 2, 2, 2] {
            seen.push(counted.line(read));
        }
        let texts: Vec<String> = seen
            .into_iter()
            .map(|l| {
                let (what, done) = l.unwrap();
                format!("{what} {done} of {} frames", frames.len())
            })
            .collect();
        assert_eq!(texts[0], "GIF (fitting) 1 of 4 frames");
        assert_eq!(texts[3], "GIF (fitting) 4 of 4 frames");
        assert_eq!(texts[4], "GIF 1 of 4 frames");
        assert_eq!(texts[7], "GIF 4 of 4 frames");
        // A late first reading does not take the line back to fitting.
        assert_eq!(counted.line(1), None);
        assert_eq!(counted.line(3), None);
    }
}
