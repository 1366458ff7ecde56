//! A colour scale explained below a picture: a title, a swatch of each
//! step, and labels under the swatches' edges.

use super::canvas::Canvas;
use super::font::GLYPH_HEIGHT;
use super::palette::{slot, Ramp};
use super::Rect;

/// What a [`with_legend`] strip says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Legend<'a> {
    /// The line above the swatches (what the colours measure, in what unit).
    pub title: &'a str,
    /// One swatch per ramp, left to right, each in a lit shade of its ramp.
    pub ramps: &'a [Ramp],
    /// Labels `(k, text)`, each centred under the left edge of swatch `k`
    /// (`k = ramps.len()`: the right edge of the last).
    pub ticks: &'a [(usize, &'a str)],
}

/// `canvas` with a strip below it holding `legend`, as wide as the canvas
/// (text at twice the font's size from 480 pixels on). Whatever does not
/// fit is clipped, never wrapped.
pub fn with_legend(canvas: &Canvas, legend: &Legend<'_>) -> Canvas {
    let s = if canvas.width >= 480 { 2 } else { 1 };
    let pad = 4 * s;
    let text = GLYPH_HEIGHT * s;
    let swatch_height = 8 * s;
    let strip = pad + text + 3 * s + swatch_height + 2 * s + text + pad;
    let mut out = Canvas::new(
        canvas.width,
        canvas.height.saturating_add(strip),
        canvas.palette.clone(),
    );
    let n = canvas.pixels.len().min(out.pixels.len());
    out.pixels[..n].copy_from_slice(&canvas.pixels[..n]);
    let top = canvas.height;
    out.draw_text(pad, top + pad, legend.title, s, slot::EDGE_3D);
    let count = legend.ramps.len().max(1) as u32;
    let swatch = (canvas.width.saturating_sub(2 * pad) / count).min(48 * s);
    // Room for half a label at either end.
    let left = pad + 2 * 6 * s;
    let swatch = swatch.min(canvas.width.saturating_sub(2 * left) / count);
    let y = top + pad + text + 3 * s;
    for (k, ramp) in legend.ramps.iter().enumerate() {
        out.fill_rect(
            Rect {
                x: left + k as u32 * swatch,
                y,
                width: swatch,
                height: swatch_height,
            },
            ramp.index(0.6),
        );
    }
    for &(k, label) in legend.ticks {
        let centre = left + k as u32 * swatch;
        let (width, _) = Canvas::text_size(label, s);
        let x = centre
            .saturating_sub(width / 2)
            .min(canvas.width.saturating_sub(width));
        out.draw_text(x, y + swatch_height + 2 * s, label, s, slot::EDGE_3D);
    }
    out
}
