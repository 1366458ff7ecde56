//! Two or more pictures brought to one frame size and made into compatible
//! meshes, each mesh also placed in its own picture for the textures.

use super::{Picture, PictureDrawing};
use crate::error::{Error, Result};
use crate::outline::{compatible_set, CompatibleSet, Drawing, OutlineOptions};

/// The compatible meshes of pictures, in frame pixels, and where each lies
/// in its own picture.
#[derive(Clone, Debug)]
pub struct PictureMeshes {
    /// The compatible meshes in frame pixels (each picture scaled onto the
    /// frame: a picture of another size than the frame's is stretched to
    /// it), with their boundary loops and anchors.
    pub set: CompatibleSet,
    /// Each mesh's vertices in its own picture's pixels: where each frame
    /// takes that picture's colours from.
    pub sources: Vec<Vec<[f64; 2]>>,
    /// The frames' width in pixels.
    pub width: u32,
    /// The frames' height in pixels.
    pub height: u32,
}

/// The compatible meshes of `pictures` (their `drawings`, from
/// [`picture_drawing`](super::picture_drawing)) for frames of `width ×
/// height` pixels: each picture's drawing scaled from its own pixels onto
/// the frame, made compatible with `anchors` (one point a picture each, in
/// that picture's pixels; exact vertices of every mesh), and each mesh
/// scaled back into its picture for [`PictureMeshes::sources`]. `names`
/// name the pictures in messages.
///
/// # Errors
/// [`Error::InvalidArgument`] for an anchor outside its picture, or a
/// frame size of 0; the errors of
/// [`compatible_set`](crate::outline::compatible_set).
pub fn picture_meshes(
    pictures: &[&Picture],
    drawings: &[&PictureDrawing],
    anchors: &[Vec<[f64; 2]>],
    (width, height): (u32, u32),
    options: &OutlineOptions,
    names: &[String],
) -> Result<PictureMeshes> {
    if width == 0 || height == 0 {
        return Err(Error::InvalidArgument(format!(
            "frames of {width} × {height} pixels: give a frame size of at least 1 × 1"
        )));
    }
    let name = |k: usize| {
        names
            .get(k)
            .cloned()
            .unwrap_or_else(|| format!("picture {}", k + 1))
    };
    for (a, row) in anchors.iter().enumerate() {
        for (k, (p, picture)) in row.iter().zip(pictures).enumerate() {
            let (w, h) = (f64::from(picture.width), f64::from(picture.height));
            if !(p[0] >= 0.0 && p[0] <= w && p[1] >= 0.0 && p[1] <= h) {
                return Err(Error::InvalidArgument(format!(
                    "anchor {} is at ({}, {}) on {}, outside the picture (0 to {w} across, 0 to {h} down, in pixels from its top-left corner)",
                    a + 1,
                    p[0],
                    p[1],
                    name(k)
                )));
            }
        }
    }
    let scale: Vec<[f64; 2]> = pictures
        .iter()
        .map(|p| {
            [
                f64::from(width) / f64::from(p.width),
                f64::from(height) / f64::from(p.height),
            ]
        })
        .collect();
    let on_frame = |p: [f64; 2], s: [f64; 2]| [p[0] * s[0], p[1] * s[1]];
    let scaled = drawings
        .iter()
        .zip(&scale)
        .map(|(d, &s)| {
            Drawing::new(
                d.drawing
                    .loops()
                    .iter()
                    .map(|l| l.iter().map(|&p| on_frame(p, s)).collect())
                    .collect(),
            )
        })
        .collect::<Result<Vec<Drawing>>>()?;
    let anchors: Vec<Vec<[f64; 2]>> = anchors
        .iter()
        .map(|row| {
            row.iter()
                .zip(&scale)
                .map(|(&p, &s)| on_frame(p, s))
                .collect()
        })
        .collect();
    let set = compatible_set(&scaled, &anchors, options)?;
    let sources = set
        .meshes
        .iter()
        .zip(&scale)
        .map(|(m, s)| {
            m.positions()
                .iter()
                .map(|p| [p[0] / s[0], p[1] / s[1]])
                .collect()
        })
        .collect();
    Ok(PictureMeshes {
        set,
        sources,
        width,
        height,
    })
}
