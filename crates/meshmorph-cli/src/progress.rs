//! Progress bars on stderr, shown only when stderr is a terminal.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use meshmorph::FrameSource;
use std::io::IsTerminal;

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

/// Frames read through a counter shown as `what: R reads of N frames`: a
/// writer that reads every frame (a GIF, a GLB), perhaps twice (once to fit
/// its view or bounds, once to draw or write), is seen at work. Hidden when stderr is not a terminal.
pub struct Counted<'a, const D: usize> {
    frames: &'a dyn FrameSource<D>,
    counter: ProgressBar,
}

impl<'a, const D: usize> Counted<'a, D> {
    pub fn new(frames: &'a dyn FrameSource<D>, what: &str) -> Self {
        let counter = if std::io::stderr().is_terminal() {
            let c = ProgressBar::new_spinner();
            c.set_style(
                ProgressStyle::with_template(
                    "{msg:>12} {spinner} {pos} reads of {prefix} frames {elapsed_precise}",
                )
                .expect("valid template"),
            );
            c.set_message(what.to_string());
            c.set_prefix(frames.num_frames().to_string());
            // Alive between frames too: drawing one may take a while.
            c.enable_steady_tick(std::time::Duration::from_millis(120));
            c
        } else {
            ProgressBar::hidden()
        };
        Counted { frames, counter }
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
        self.counter.inc(1);
    }
}
