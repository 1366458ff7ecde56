//! The page frames are drawn on: a viewBox in the drawing's units and a
//! size in pixels.

use crate::mesh::frame_source::FrameSource;

/// Where written frames sit: `view_box` (`[x, y, width, height]` in the
/// drawing's units) shown at `size` (`[width, height]` in pixels), as an
/// SVG's `viewBox`, `width` and `height`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Canvas {
    /// `[x, y, width, height]` in the drawing's units (after `flip_y`).
    pub view_box: [f64; 4],
    /// `[width, height]` in pixels.
    pub size: [f64; 2],
    /// The drawing's y points up (text, meshes): written as `-y`, so that
    /// it shows the right way up where y points down (SVG, Lottie).
    pub flip_y: bool,
}

/// The bounding box `[min x, min y, max x, max y]` of the points of
/// `loops` over every frame of `frames`, y negated when `flip_y`.
pub(super) fn bounds(
    frames: &dyn FrameSource<2>,
    loops: &[Vec<u32>],
    flip_y: bool,
) -> Option<[f64; 4]> {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for k in 0..frames.num_frames() {
        frames.with_frame(k, &mut |positions| {
            for &v in loops.iter().flatten() {
                let p = positions[v as usize];
                let y = if flip_y { -p[1] } else { p[1] };
                b = [b[0].min(p[0]), b[1].min(y), b[2].max(p[0]), b[3].max(y)];
            }
        });
    }
    (b[0] <= b[2] && b[1] <= b[3] && b.iter().all(|x| x.is_finite())).then_some(b)
}

/// Significant digits written for a drawing's coordinates, at the size of
/// its page (or of the drawing, when that is smaller): one more than a
/// 32-bit float holds (SVG readers, `usvg` among them, read coordinates
/// as those), so a drawing read and written back loses nothing, and
/// arithmetic's last bits are not written.
pub const SIGNIFICANT_DIGITS: i32 = 8;

/// Digits after the point that give [`SIGNIFICANT_DIGITS`] at `extent`
/// (17 for an extent that is zero or not finite: written as the shortest
/// text that reads back to the number).
pub fn decimals_at(extent: f64) -> usize {
    decimals_with(SIGNIFICANT_DIGITS, extent)
}

/// Digits after the point that give `significant` digits to numbers up
/// to `extent` across (17 for an extent that is zero or not finite).
fn decimals_with(significant: i32, extent: f64) -> usize {
    let extent = extent.abs();
    if !(extent.is_finite() && extent > 0.0) {
        return 17;
    }
    (significant - extent.log10().ceil() as i32).clamp(0, 17) as usize
}

impl Canvas {
    /// Digits after the point for coordinates on this canvas:
    /// [`SIGNIFICANT_DIGITS`] at the size of its viewBox's longer side.
    pub fn decimals(&self) -> usize {
        decimals_at(self.view_box[2].abs().max(self.view_box[3].abs()))
    }

    /// Digits after the point for a drawing `extent` across (its bounding
    /// box's longer side) whose coordinates reach `magnitude` (the largest
    /// absolute value) on this canvas: [`SIGNIFICANT_DIGITS`] at the
    /// smaller of its size and the page's, so that a small drawing on a
    /// large page keeps its shape, but no more than a double holds at
    /// `magnitude` (15 significant digits), so that a drawing shrunk to a
    /// point is not written with the arithmetic's last bits.
    pub fn decimals_for(&self, extent: f64, magnitude: f64) -> usize {
        let page = self.decimals();
        if !(extent.is_finite() && extent > 0.0) {
            return page;
        }
        page.max(decimals_at(extent).min(decimals_with(15, magnitude)))
    }

    /// The point as written: y negated when the drawing's y points up.
    pub fn map(&self, p: [f64; 2]) -> [f64; 2] {
        if self.flip_y {
            [p[0], -p[1]]
        } else {
            p
        }
    }

    /// The canvas for frames: `page` (the first drawing's, when it has
    /// one) when every frame's outline, widened by `margin` (half the
    /// stroke), fits in its viewBox; else its viewBox grown to hold them,
    /// its size grown at the same pixels per unit. Without a page: the
    /// frames' bounding box with 5 % around, 640 pixels on its longer
    /// side, y flipped (drawings without a page have y up).
    pub fn for_frames(
        page: Option<&Canvas>,
        frames: &dyn FrameSource<2>,
        loops: &[Vec<u32>],
        margin: f64,
    ) -> Canvas {
        let flip_y = page.is_none_or(|p| p.flip_y);
        let b = bounds(frames, loops, flip_y).unwrap_or([0.0, 0.0, 1.0, 1.0]);
        let b = [b[0] - margin, b[1] - margin, b[2] + margin, b[3] + margin];
        match page {
            Some(page) => {
                let v = page.view_box;
                let grown = [
                    v[0].min(b[0]),
                    v[1].min(b[1]),
                    (v[0] + v[2]).max(b[2]),
                    (v[1] + v[3]).max(b[3]),
                ];
                let view_box = [grown[0], grown[1], grown[2] - grown[0], grown[3] - grown[1]];
                Canvas {
                    view_box,
                    size: [
                        page.size[0] * view_box[2] / v[2],
                        page.size[1] * view_box[3] / v[3],
                    ],
                    flip_y,
                }
            }
            None => {
                let (w, h) = ((b[2] - b[0]).max(1e-12), (b[3] - b[1]).max(1e-12));
                let pad = 0.05 * w.max(h);
                let view_box = [b[0] - pad, b[1] - pad, w + 2.0 * pad, h + 2.0 * pad];
                let scale = 640.0 / view_box[2].max(view_box[3]);
                Canvas {
                    view_box,
                    size: [
                        (view_box[2] * scale).round().max(1.0),
                        (view_box[3] * scale).round().max(1.0),
                    ],
                    flip_y,
                }
            }
        }
    }
}
