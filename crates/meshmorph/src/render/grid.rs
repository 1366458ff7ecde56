//! Several meshes in space side by side: a grid of cells, one row per set
//! of meshes that share a camera (e.g. the source poses, then the target
//! poses of a deformation transfer).

use super::canvas::Canvas;
use super::font::{ADVANCE, GLYPH_HEIGHT};
use super::palette::{slot, Palette, Ramp};
use super::shade3d::{draw_mesh_3d_coloured, Camera3d, Style3d};
use super::Rect;

/// One row of a grid: meshes with the same triangles (the poses of one
/// shape), drawn left to right in one style.
#[derive(Clone, Debug)]
pub struct GridRow<'a> {
    /// The triangles of every pose of the row.
    pub triangles: &'a [[u32; 3]],
    /// The vertex positions of each pose, one cell each.
    pub poses: Vec<&'a [[f64; 3]]>,
    /// How the row looks (e.g. [`Ramp::BLUE`](super::Ramp::BLUE) for the
    /// source, [`Ramp::SAND`](super::Ramp::SAND) for the target).
    pub style: Style3d,
}

/// Size and camera of a grid picture.
#[derive(Clone, Debug, PartialEq)]
pub struct GridOptions {
    /// Width of one cell in pixels (320).
    pub cell_width: u32,
    /// Height of one cell in pixels; `None` (the default) chooses it from
    /// the shape of the tallest row, between a quarter and twice the
    /// width, even.
    pub cell_height: Option<u32>,
    /// The longer side of a cell in pixels, the other following the shape
    /// of the tallest row (between a quarter and twice the width, even):
    /// a tall mesh gets a narrower cell rather than a taller one. When
    /// set, `cell_width` and `cell_height` are not used; `None` (the
    /// default) keeps them.
    pub longest_side: Option<u32>,
    /// Background pixels kept around the mesh inside each cell (12).
    pub margin_px: u32,
    /// The direction every camera looks in ([`Camera3d::orbit`]`(30, 20)`
    /// for y-up meshes).
    pub direction: [f64; 3],
    /// Up on screen.
    pub up: [f64; 3],
    /// The palette of the picture ([`Palette::standard`]).
    pub palette: Palette,
    /// Anti-aliasing: each pixel is the mean of `supersample²` samples (3;
    /// 1 for none).
    pub supersample: u32,
    /// A band above each cell's view for its caption ([`GridLayout::caption`]),
    /// its height following the cell's size (false).
    pub captions: bool,
    /// A grid of one column whose cells are taller than wide lays its rows
    /// side by side instead (false): two tall meshes read better next to
    /// each other than as a tall strip.
    pub tall_rows_side_by_side: bool,
}

impl Default for GridOptions {
    fn default() -> Self {
        let cam = Camera3d::orbit(30.0, 20.0);
        GridOptions {
            cell_width: 320,
            cell_height: None,
            longest_side: None,
            margin_px: 12,
            direction: cam.forward,
            up: cam.up,
            palette: Palette::standard(),
            supersample: 3,
            captions: false,
            tall_rows_side_by_side: false,
        }
    }
}

/// Where the cells of a grid are and the camera of each row: fitted once,
/// then used to draw any number of pictures (the frames of an animation
/// keep still cameras when the layout is fitted over all of them).
#[derive(Clone, Debug, PartialEq)]
pub struct GridLayout {
    /// Cell width in pixels.
    pub cell_width: u32,
    /// Cell height in pixels.
    pub cell_height: u32,
    /// Number of columns (the most poses of any row).
    pub columns: u32,
    /// Background pixels around each mesh inside its cell.
    pub margin_px: u32,
    /// The camera of each row, fitted to all of the row's poses so that
    /// they share a scale.
    pub cameras: Vec<Camera3d>,
    /// The palette of the pictures.
    pub palette: Palette,
    /// Samples per pixel in each direction (anti-aliasing).
    pub supersample: u32,
    /// The band above each cell's view for its caption, in pixels (0 for
    /// none).
    pub caption_px: u32,
    /// See [`GridOptions::tall_rows_side_by_side`].
    pub tall_rows_side_by_side: bool,
}

impl GridLayout {
    /// Fits a camera to the poses of each row and sizes the cells.
    ///
    /// To animate, fit with rows holding every pose of every frame, then
    /// [`render`](GridLayout::render) each frame's rows.
    pub fn fit(rows: &[GridRow<'_>], options: &GridOptions) -> Self {
        let base = Camera3d::looking(options.direction, options.up);
        let cameras: Vec<Camera3d> = rows
            .iter()
            .map(|r| base.fitted(r.poses.iter().copied()))
            .collect();
        let tallest = cameras
            .iter()
            .map(|c| 1.0 / c.aspect())
            .fold(0.0f64, f64::max);
        let tallest = if tallest > 0.0 && tallest.is_finite() {
            tallest
        } else {
            1.0
        };
        // The height of a cell `width` wide that holds the tallest row.
        let fitted_height = |width: u32| {
            let margin = options.margin_px.min(width.saturating_sub(1) / 2);
            let inner = f64::from(width - 2 * margin);
            let lo = (width / 4).max(2 * margin + 2);
            let hi = width.saturating_mul(2).max(lo);
            let h = (inner * tallest + f64::from(2 * margin))
                .ceil()
                .clamp(f64::from(lo), f64::from(hi)) as u32;
            h + h % 2
        };
        let (cell_width, cell_height) = match options.longest_side {
            Some(side) => {
                let side = side.max(1);
                let height = fitted_height(side);
                if height <= side {
                    (side, height)
                } else {
                    // Tall: the height is the side, the width what holds
                    // the row at that height (at least half of it).
                    let margin = options.margin_px.min(side.saturating_sub(1) / 2);
                    let inner = f64::from(side - 2 * margin) / tallest;
                    let w = ((inner + f64::from(2 * margin)).ceil() as u32).clamp(side / 2, side);
                    (w.max(1), side)
                }
            }
            None => {
                let width = options.cell_width.max(1);
                (
                    width,
                    options
                        .cell_height
                        .map_or_else(|| fitted_height(width), |h| h.max(1)),
                )
            }
        };
        let caption_px = if options.captions {
            caption_scale(cell_width.max(cell_height)) * (GLYPH_HEIGHT + 6)
        } else {
            0
        };
        GridLayout {
            cell_width,
            cell_height: cell_height.saturating_add(caption_px),
            columns: rows
                .iter()
                .map(|r| r.poses.len() as u32)
                .max()
                .unwrap_or(0)
                .max(1),
            margin_px: options.margin_px,
            cameras,
            palette: options.palette.clone(),
            supersample: options.supersample.clamp(1, 8),
            caption_px,
            tall_rows_side_by_side: options.tall_rows_side_by_side,
        }
    }

    /// Whether the rows are laid side by side (see
    /// [`GridOptions::tall_rows_side_by_side`]).
    pub fn transposed(&self) -> bool {
        self.tall_rows_side_by_side
            && self.columns == 1
            && self.cameras.len() > 1
            && self.cell_height > self.cell_width
    }

    /// Writes `text` in the caption band of the cell of pose `column` of
    /// row `row` (dark grey on the background, shortened with `...` to the
    /// cell's width); nothing without captions.
    pub fn caption(&self, canvas: &mut Canvas, row: u32, column: u32, text: &str) {
        if self.caption_px == 0 {
            return;
        }
        let cell = self.cell(row, column);
        let scale = caption_scale(self.cell_width.max(self.cell_height - self.caption_px));
        let pad = 3 * scale;
        let room = (cell.width.saturating_sub(2 * pad) / (ADVANCE * scale)) as usize;
        let shown: String = if text.chars().count() <= room {
            text.to_string()
        } else {
            let kept: String = text.chars().take(room.saturating_sub(3)).collect();
            kept + "..."
        };
        canvas.draw_text(cell.x + pad, cell.y + pad, &shown, scale, slot::EDGE_3D);
    }

    /// Picture width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        let (mut across, mut down) = (self.columns, self.cameras.len().max(1) as u32);
        if self.transposed() {
            std::mem::swap(&mut across, &mut down);
        }
        (
            self.cell_width.saturating_mul(across),
            self.cell_height.saturating_mul(down),
        )
    }

    /// The pixels of the cell of pose `column` of row `row`, margins
    /// included.
    pub fn cell(&self, row: u32, column: u32) -> Rect {
        let (across, down) = if self.transposed() {
            (row, column)
        } else {
            (column, row)
        };
        Rect {
            x: across.saturating_mul(self.cell_width),
            y: down.saturating_mul(self.cell_height),
            width: self.cell_width,
            height: self.cell_height,
        }
    }

    /// Draws pose `k` of row `r` into cell `(r, k)` with the row's camera.
    /// Rows beyond those the layout was fitted with are left empty.
    pub fn render(&self, rows: &[GridRow<'_>]) -> Canvas {
        self.render_coloured(rows, &[])
    }

    /// [`GridLayout::render`] with the triangles of row `r` shaded in the
    /// ramps `ramps[r]` ([`draw_mesh_3d_coloured`]), rows past the end of
    /// `ramps` in their style's ramp.
    pub fn render_coloured(&self, rows: &[GridRow<'_>], ramps: &[&[Ramp]]) -> Canvas {
        let (w, h) = self.size();
        let s = self.supersample.max(1);
        let mut canvas = Canvas::new(w * s, h * s, self.palette.clone());
        for ((r, row), camera) in rows.iter().enumerate().zip(&self.cameras) {
            for (k, pose) in row.poses.iter().enumerate() {
                let cell = self.cell(r as u32, k as u32);
                let m = self
                    .margin_px
                    .min(cell.width.min(cell.height).saturating_sub(1) / 2);
                let band = self.caption_px.min(cell.height - 2 * m);
                let inner = Rect {
                    x: (cell.x + m) * s,
                    y: (cell.y + band + m) * s,
                    width: (cell.width - 2 * m) * s,
                    height: (cell.height - band - 2 * m) * s,
                };
                let style = Style3d {
                    dither_px: s,
                    ..row.style
                };
                let ramps = ramps.get(r).copied().unwrap_or(&[]);
                draw_mesh_3d_coloured(
                    &mut canvas,
                    pose,
                    row.triangles,
                    camera,
                    inner,
                    &style,
                    ramps,
                );
            }
        }
        if s == 1 {
            canvas
        } else {
            super::resample::downsample(&canvas, s, w, h)
        }
    }
}

/// The scale of the caption font over a view whose longer side is `side`
/// pixels: 2 from 360 pixels on, else 1.
fn caption_scale(side: u32) -> u32 {
    if side >= 360 {
        2
    } else {
        1
    }
}

/// A picture of several meshes in space in a grid: row `r`, column `k`
/// shows pose `k` of `rows[r]`, every row seen through its own camera fitted
/// to all its poses (so they share a scale). Save it with
/// [`write_png`](super::write_png).
pub fn render_grid_3d(rows: &[GridRow<'_>], options: &GridOptions) -> Canvas {
    GridLayout::fit(rows, options).render(rows)
}
