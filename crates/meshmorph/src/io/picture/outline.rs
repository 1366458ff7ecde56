//! The drawing of a picture: the outline of its largest opaque region
//! (a sprite), or its whole rectangle (a photo).

use super::simplify::simplify_loop;
use super::trace::trace_alpha;
use super::Picture;
use crate::error::{Error, Result};
use crate::outline::Drawing;

/// How a picture's region was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PictureShape {
    /// Traced where alpha crosses one half.
    Sprite,
    /// The whole picture rectangle (no transparency, or asked for).
    Photo,
}

/// A region of a picture left out of its drawing (only the largest is
/// morphed).
#[derive(Clone, Debug, PartialEq)]
pub struct LeftOut {
    /// Its area in square pixels (holes taken out).
    pub area: f64,
    /// Its bounding box, `[[x_min, y_min], [x_max, y_max]]` in pixels.
    pub bounds: [[f64; 2]; 2],
}

/// A picture's drawing and how it was made.
#[derive(Clone, Debug)]
pub struct PictureDrawing {
    /// The region: an outer loop and its holes, in pixels.
    pub drawing: Drawing,
    /// Traced or the whole rectangle.
    pub shape: PictureShape,
    /// Regions traced besides the one kept, largest first (specks under
    /// `min_area` not counted).
    pub left_out: Vec<LeftOut>,
    /// Specks (regions and holes) under `min_area` ignored.
    pub specks: usize,
    /// Points traced before simplifying (every loop kept).
    pub traced_points: usize,
    /// The simplification's tolerance used, pixels.
    pub tolerance: f64,
    /// Pixels less than half opaque but not transparent beyond what an
    /// anti-aliased edge has (a glow or a soft shadow): the traced shape
    /// leaves them out of every frame. Zero for a photo.
    pub faint_left_out: usize,
}

/// Points a side of a photo's rectangle is cut into: the frame warps
/// smoothly instead of as a few large triangles.
const PHOTO_SIDE_POINTS: usize = 8;

/// The drawing of `picture`: with `photo`, or when no pixel is less than
/// fully opaque, its rectangle (each side cut into 8 equal edges);
/// otherwise its outline traced where alpha crosses one half
/// ([`trace_alpha`]), each loop simplified within `tolerance` pixels
/// ([`simplify_loop`]; halved until the loops are simple again, should
/// thinning make them touch), regions and holes under `min_area` square
/// pixels dropped, and of the regions left the largest kept (the others
/// listed in [`PictureDrawing::left_out`]).
///
/// # Errors
/// [`Error::InvalidArgument`] naming `name` for a fully transparent
/// picture or one whose opaque parts are all specks.
pub fn picture_drawing(
    picture: &Picture,
    photo: bool,
    tolerance: f64,
    min_area: f64,
    name: &str,
) -> Result<PictureDrawing> {
    if photo || !picture.has_transparency() {
        let (w, h) = (f64::from(picture.width), f64::from(picture.height));
        let corners = [[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]];
        let mut outer = Vec::with_capacity(4 * PHOTO_SIDE_POINTS);
        for c in 0..4 {
            let (a, b) = (corners[c], corners[(c + 1) % 4]);
            for k in 0..PHOTO_SIDE_POINTS {
                let s = k as f64 / PHOTO_SIDE_POINTS as f64;
                outer.push([a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]);
            }
        }
        return Ok(PictureDrawing {
            drawing: Drawing::new(vec![outer])?,
            shape: PictureShape::Photo,
            left_out: Vec::new(),
            specks: 0,
            traced_points: 0,
            tolerance: 0.0,
            faint_left_out: 0,
        });
    }
    if picture.is_fully_transparent() {
        return Err(Error::InvalidArgument(format!(
            "{name} is fully transparent (every pixel's alpha is 0): there is nothing to morph; give a picture with an opaque part, or morph the whole rectangle (--frame-only on the command line, frame_only=True in Python)"
        )));
    }
    let loops = trace_alpha(picture, 0.5);
    let faint_left_out = faint_beyond_edges(picture, &loops);
    let area = |l: &[[f64; 2]]| crate::io::drawing::signed_area2(l) / 2.0;
    let mut specks = 0;
    // Each outer loop, its area less its holes', and its holes.
    type Region = (Vec<[f64; 2]>, f64, Vec<Vec<[f64; 2]>>);
    let mut outers: Vec<Region> = Vec::new();
    let mut holes = Vec::new();
    for l in loops {
        let a = area(&l);
        if a.abs() < min_area {
            specks += 1;
        } else if a > 0.0 {
            outers.push((l, a, Vec::new()));
        } else {
            holes.push(l);
        }
    }
    for h in holes {
        let p = h[0];
        let around = outers
            .iter_mut()
            .filter(|o| crate::io::drawing::inside(&o.0, p))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match around {
            Some(o) => {
                o.1 -= area(&h).abs();
                o.2.push(h);
            }
            None => specks += 1,
        }
    }
    if outers.is_empty() {
        return Err(Error::InvalidArgument(format!(
            "{name} has no opaque region of {min_area} square pixels or more (alpha at or above one half): only {}; give a picture with an opaque part, or morph the whole rectangle (--frame-only on the command line, frame_only=True in Python)",
            if specks == 1 { "1 speck".to_string() } else { format!("{specks} specks") }
        )));
    }
    outers.sort_by(|a, b| b.1.total_cmp(&a.1));
    let (outer, _, holes) = outers.remove(0);
    let left_out = outers
        .iter()
        .map(|(l, a, _)| {
            let mut bounds = [[f64::INFINITY; 2], [f64::NEG_INFINITY; 2]];
            for p in l {
                for k in 0..2 {
                    bounds[0][k] = bounds[0][k].min(p[k]);
                    bounds[1][k] = bounds[1][k].max(p[k]);
                }
            }
            LeftOut { area: *a, bounds }
        })
        .collect();
    let mut all = vec![outer];
    all.extend(holes);
    let traced_points = all.iter().map(Vec::len).sum();
    let mut tol = tolerance;
    // Thinner where thinning makes the loops touch; the traced loops
    // themselves where no tolerance keeps them apart (the thinned error
    // reported where those fail too).
    let (drawing, tolerance) = loop {
        let thinned: Vec<Vec<[f64; 2]>> = all.iter().map(|l| simplify_loop(l, tol)).collect();
        match Drawing::new(thinned) {
            Ok(drawing) => break (drawing, tol),
            Err(_) if tol > 1e-3 => tol /= 2.0,
            Err(e) => break (Drawing::new(all).map_err(|_| e)?, 0.0),
        }
    };
    Ok(PictureDrawing {
        drawing,
        shape: PictureShape::Sprite,
        left_out,
        specks,
        traced_points,
        tolerance,
        faint_left_out,
    })
}

/// The pixels of `picture` with an alpha above 0 and under one half, less
/// two for each pixel of length of the traced `loops`: an anti-aliased
/// edge has about one such pixel along each pixel of outline, a glow or a
/// soft shadow many more.
fn faint_beyond_edges(picture: &Picture, loops: &[Vec<[f64; 2]>]) -> usize {
    let faint = picture
        .rgba
        .chunks_exact(4)
        .filter(|p| p[3] > 0 && p[3] < 128)
        .count();
    let length: f64 = loops
        .iter()
        .map(|l| {
            (0..l.len())
                .map(|i| {
                    let (a, b) = (l[i], l[(i + 1) % l.len()]);
                    (b[0] - a[0]).hypot(b[1] - a[1])
                })
                .sum::<f64>()
        })
        .sum();
    faint.saturating_sub((2.0 * length).ceil() as usize)
}
