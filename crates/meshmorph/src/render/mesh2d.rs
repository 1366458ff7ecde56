//! Planar meshes on a [`Canvas`]: filled triangles, flipped ones in the
//! warning colour, edges on top.

use super::canvas::Canvas;
use super::palette::slot;
use super::raster;
use super::style::{valid, EdgeSets, Style2d};
use super::view::View2d;

/// Draws a planar mesh onto `canvas` through `view`.
///
/// Correctly oriented triangles are filled with [`slot::FILL`], then the
/// flipped ones (see [`Style2d::flipped`]) with [`slot::FLIPPED_FILL`] on
/// top, then the edges chosen by [`Style2d::edges`] in [`slot::EDGE`], and
/// the edges of flipped triangles in [`slot::FLIPPED_EDGE`]. The colours
/// are those of the canvas palette (see [`Canvas::with_style`]).
///
/// Triangles with an index out of range, a non-finite coordinate or zero
/// area draw nothing (zero-area ones still get their edges).
pub fn draw_mesh_2d(
    canvas: &mut Canvas,
    positions: &[[f64; 2]],
    triangles: &[[u32; 3]],
    view: &View2d,
    style: &Style2d,
) {
    let mode = style.resolve_edges(super::style::mean_area(positions, triangles), view.scale);
    let edges = match mode {
        Some(_) => EdgeSets::new(triangles, positions.len()),
        None => EdgeSets::default(),
    };
    let mut scratch = Scratch::default();
    draw_prepared(
        canvas,
        positions,
        triangles,
        &edges,
        mode,
        view,
        style,
        &mut scratch,
        1,
    );
}

/// Buffers reused from frame to frame.
#[derive(Debug, Default)]
pub struct Scratch {
    /// Pixel coordinates of the vertices.
    px: Vec<[f64; 2]>,
    /// The same, snapped.
    fixed: Vec<[i64; 2]>,
}

/// [`draw_mesh_2d`] with the edge sets and edge mode computed beforehand
/// (once per animation) and a reusable buffer for the pixel coordinates.
#[allow(clippy::too_many_arguments)]
pub fn draw_prepared(
    canvas: &mut Canvas,
    positions: &[[f64; 2]],
    triangles: &[[u32; 3]],
    edges: &EdgeSets,
    mode: Option<bool>,
    view: &View2d,
    style: &Style2d,
    scratch: &mut Scratch,
    line_width: u32,
) {
    let Scratch { px, fixed } = scratch;
    px.clear();
    px.extend(positions.iter().map(|&p| view.to_pixel(p)));
    fixed.clear();
    fixed.extend(px.iter().map(|&p| raster::snap_point(p)));
    let flipped = style.flipped_mask(positions, triangles);
    let clip = canvas.clip(canvas.bounds());
    let w = canvas.width as usize;
    let n = px.len();
    for (pass, color) in [(false, slot::FILL), (true, slot::FLIPPED_FILL)] {
        let pixels = &mut canvas.pixels;
        for (t, _) in triangles
            .iter()
            .zip(&flipped)
            .filter(|(t, &f)| f == pass && valid(t, n))
        {
            let [a, b, c] = t.map(|i| i as usize);
            raster::fill_snapped(
                [fixed[a], fixed[b], fixed[c]],
                [px[a], px[b], px[c]],
                &clip,
                |y, x0, x1| pixels[y * w + x0..y * w + x1].fill(color),
            );
        }
    }
    let Some(all) = mode else { return };
    let list = if all { &edges.all } else { &edges.boundary };
    for &[a, b] in list {
        if (a as usize) < n && (b as usize) < n {
            draw_wide_line(
                canvas,
                px[a as usize],
                px[b as usize],
                slot::EDGE,
                line_width,
            );
        }
    }
    if all {
        for (t, _) in triangles
            .iter()
            .zip(&flipped)
            .filter(|(t, &f)| f && valid(t, n))
        {
            for k in 0..3 {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                draw_wide_line(canvas, px[a], px[b], slot::FLIPPED_EDGE, line_width);
            }
        }
    }
}

/// A line `width` pixels wide: that many one-pixel lines side by side,
/// offset across the line (the edges of a supersampled picture).
fn draw_wide_line(canvas: &mut Canvas, a: [f64; 2], b: [f64; 2], index: u8, width: u32) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len = dx.hypot(dy);
    if width <= 1 || len.is_nan() || len <= 0.0 {
        canvas.draw_line(a, b, index, None);
        return;
    }
    let n = [-dy / len, dx / len];
    for k in 0..width {
        let o = f64::from(k) - f64::from(width - 1) / 2.0;
        let shift = |p: [f64; 2]| [p[0] + o * n[0], p[1] + o * n[1]];
        canvas.draw_line(shift(a), shift(b), index, None);
    }
}
