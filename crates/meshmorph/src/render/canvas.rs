//! [`Canvas`]: an indexed-colour picture with drawing primitives.

use super::font::{glyph, ADVANCE, GLYPH_HEIGHT, GLYPH_WIDTH};
use super::palette::{slot, Palette};
use super::raster::{self, Clip};
use super::style::Style2d;
use super::Rect;

/// A `width` × `height` picture of palette indices, row by row from the
/// top-left pixel, and the palette they index.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Canvas {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` palette indices, rows top to bottom.
    pub pixels: Vec<u8>,
    /// The colours of the indices.
    pub palette: Palette,
}

impl Canvas {
    /// A canvas filled with [`slot::BACKGROUND`].
    pub fn new(width: u32, height: u32, palette: Palette) -> Self {
        Canvas {
            width,
            height,
            pixels: vec![slot::BACKGROUND; width as usize * height as usize],
            palette,
        }
    }

    /// A canvas with the [`Palette::standard`] palette coloured by `style`,
    /// filled with its background.
    pub fn with_style(width: u32, height: u32, style: &Style2d) -> Self {
        Self::new(width, height, Palette::standard().with_style(style))
    }

    /// The whole canvas as a rectangle.
    pub fn bounds(&self) -> Rect {
        Rect {
            x: 0,
            y: 0,
            width: self.width,
            height: self.height,
        }
    }

    /// Sets every pixel to `index`.
    pub fn clear(&mut self, index: u8) {
        self.pixels.fill(index);
    }

    /// The index at pixel `(x, y)`, `None` outside the canvas.
    pub fn get(&self, x: u32, y: u32) -> Option<u8> {
        (x < self.width && y < self.height)
            .then(|| self.pixels[y as usize * self.width as usize + x as usize])
    }

    /// Sets pixel `(x, y)` if it is inside the canvas.
    pub fn set(&mut self, x: u32, y: u32, index: u8) {
        if x < self.width && y < self.height {
            self.pixels[y as usize * self.width as usize + x as usize] = index;
        }
    }

    /// Fills the part of `rect` inside the canvas.
    pub fn fill_rect(&mut self, rect: Rect, index: u8) {
        let (w, h) = (u64::from(self.width), u64::from(self.height));
        let x0 = u64::from(rect.x).min(w) as usize;
        let y0 = u64::from(rect.y).min(h) as usize;
        let x1 = (u64::from(rect.x) + u64::from(rect.width)).min(w) as usize;
        let y1 = (u64::from(rect.y) + u64::from(rect.height)).min(h) as usize;
        let w = w as usize;
        for y in y0..y1 {
            self.pixels[y * w + x0..y * w + x1].fill(index);
        }
    }

    /// Fills the triangle with corners `p` (pixel coordinates, `(0, 0)` the
    /// top-left corner, either orientation), clipped to `clip` (the whole
    /// canvas when `None`). Pixels whose centre is inside are set; a pixel
    /// centre on an edge shared by two triangles goes to exactly one, so a
    /// tessellation is drawn without holes or overdraw.
    pub fn fill_triangle(&mut self, p: [[f64; 2]; 3], index: u8, clip: Option<Rect>) {
        let clip = self.clip(clip.unwrap_or(self.bounds()));
        let w = self.width as usize;
        let pixels = &mut self.pixels;
        raster::fill_triangle(p, &clip, |y, x0, x1| {
            pixels[y * w + x0..y * w + x1].fill(index)
        });
    }

    /// Draws a 1-pixel line from `a` to `b` (pixel coordinates), clipped
    /// to `clip` (the whole canvas when `None`).
    pub fn draw_line(&mut self, a: [f64; 2], b: [f64; 2], index: u8, clip: Option<Rect>) {
        let clip = self.clip(clip.unwrap_or(self.bounds()));
        let w = self.width as usize;
        let pixels = &mut self.pixels;
        raster::draw_line(a, b, &clip, |x, y, _| pixels[y * w + x] = index);
    }

    /// Writes `text` in the built-in 5 × 7 font with its top-left corner at
    /// `(x, y)`, each font pixel `scale` × `scale` pixels (at least 1), in
    /// palette entry `index`; a character outside printable ASCII is drawn
    /// as `?`. Pixels outside the canvas are skipped.
    pub fn draw_text(&mut self, x: u32, y: u32, text: &str, scale: u32, index: u8) {
        let scale = scale.max(1);
        let mut left = x;
        for c in text.chars() {
            for (r, bits) in glyph(c).iter().enumerate() {
                for col in 0..GLYPH_WIDTH {
                    if bits >> (GLYPH_WIDTH - 1 - col) & 1 == 1 {
                        let square = Rect {
                            x: left.saturating_add(col * scale),
                            y: y.saturating_add(r as u32 * scale),
                            width: scale,
                            height: scale,
                        };
                        self.fill_rect(square, index);
                    }
                }
            }
            left = left.saturating_add(ADVANCE * scale);
        }
    }

    /// The width and height in pixels of `text` written by
    /// [`Canvas::draw_text`] at `scale`.
    pub fn text_size(text: &str, scale: u32) -> (u32, u32) {
        let scale = scale.max(1);
        let n = text.chars().count() as u32;
        (
            (n * ADVANCE).saturating_sub(1) * scale,
            GLYPH_HEIGHT * scale,
        )
    }

    /// The canvas as `r, g, b` bytes, rows top to bottom.
    pub fn to_rgb(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|&i| self.palette.get(i))
            .collect()
    }

    /// How many pixels have index `index`.
    pub fn count(&self, index: u8) -> usize {
        self.pixels.iter().filter(|&&i| i == index).count()
    }

    pub(crate) fn clip(&self, rect: Rect) -> Clip {
        Clip::new(rect, self.width, self.height)
    }
}
