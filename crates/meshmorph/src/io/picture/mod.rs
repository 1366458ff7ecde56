//! Pictures as drawings: a sprite's outline traced where its alpha crosses
//! one half, or a photo's whole rectangle, ready for
//! [`compatible_set`](crate::outline::compatible_set); and the compatible
//! meshes of two or more pictures, with where each mesh lies in its own
//! picture, for the textured frames of [`render`](crate::render).
//!
//! One concept a file:
//!
//! - `decode` (with the `render` feature): PNG (any colour type and depth,
//!   the first frame of an APNG) and baseline or progressive JPEG to 8-bit
//!   RGBA.
//! - `trace`: marching squares on the alpha channel, every loop (outer
//!   loops and holes) closed and oriented.
//! - `simplify`: a closed loop's points thinned within a tolerance in
//!   pixels (Douglas and Peucker).
//! - `outline`: the drawing of a picture: its largest traced region, or
//!   its rectangle (photo mode), and what was left out.
//! - `meshes`: the pictures brought to one frame size and made compatible.
//! - `arm`: a sprite made in code (an arm bending at the elbow) and points
//!   matched on it, for demos, tests and benchmarks.
//!
//! **Coordinates** are pixels: `(0, 0)` the top-left corner of the
//! top-left pixel, x to the right, y down; pixel `(i, j)` has its centre
//! at `(i + ½, j + ½)`. Anchors are given so, in each picture's own pixels.

#[doc(hidden)]
pub mod arm;
#[cfg(feature = "render")]
#[doc(hidden)]
pub mod decode;
#[doc(hidden)]
pub mod meshes;
#[doc(hidden)]
pub mod outline;
#[doc(hidden)]
pub mod simplify;
#[doc(hidden)]
pub mod trace;

pub use arm::{arm_anchors, arm_fold_anchors, arm_sprite, ARM_SPRITE_SIZE};
#[cfg(feature = "render")]
pub use decode::{decode_picture, read_picture, PictureFormat};
pub use meshes::{picture_meshes, PictureMeshes};
pub use outline::{picture_drawing, LeftOut, PictureDrawing, PictureShape};
pub use simplify::simplify_loop;
pub use trace::trace_alpha;

use crate::error::{Error, Result};

/// A picture in memory: 8-bit RGBA, straight (not premultiplied) alpha,
/// rows from top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Picture {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `4 × width × height` bytes: red, green, blue, alpha of each pixel.
    pub rgba: Vec<u8>,
}

impl Picture {
    /// A picture from its pixels.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when a side is 0 or `rgba` does not hold
    /// `4 × width × height` bytes.
    pub fn new(width: u32, height: u32, rgba: Vec<u8>) -> Result<Self> {
        if width == 0 || height == 0 {
            return Err(Error::InvalidArgument(format!(
                "an empty {width} × {height} picture: a picture needs at least one pixel"
            )));
        }
        let expected = 4 * width as u64 * height as u64;
        if rgba.len() as u64 != expected {
            return Err(Error::InvalidArgument(format!(
                "a {width} × {height} picture needs {expected} bytes of RGBA, {} given",
                rgba.len()
            )));
        }
        Ok(Self {
            width,
            height,
            rgba,
        })
    }

    /// A picture of `width × height` pixels, each `f(x, y)` (a procedural
    /// picture).
    pub fn from_fn(width: u32, height: u32, mut f: impl FnMut(u32, u32) -> [u8; 4]) -> Self {
        let mut rgba = Vec::with_capacity(4 * width as usize * height as usize);
        for y in 0..height {
            for x in 0..width {
                rgba.extend_from_slice(&f(x, y));
            }
        }
        Self {
            width,
            height,
            rgba,
        }
    }

    /// The pixel at column `x`, row `y`.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = 4 * (y as usize * self.width as usize + x as usize);
        [
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ]
    }

    /// Whether any pixel is less than fully opaque.
    pub fn has_transparency(&self) -> bool {
        self.rgba.chunks_exact(4).any(|p| p[3] < 255)
    }

    /// Whether every pixel is fully transparent.
    pub fn is_fully_transparent(&self) -> bool {
        self.rgba.chunks_exact(4).all(|p| p[3] == 0)
    }
}

/// Bytes of memory a morph of two pictures of `pixels` pixels each (the
/// larger, if they differ) into frames of `frame_pixels` pixels takes at
/// its peak, for front ends that refuse a run before it starts: both
/// pictures as read (4 bytes a pixel) and their mipmaps (8 bytes a pixel
/// over a third of the pixels), the decoder's buffer of one picture (4 bytes
/// a pixel), the tracing's row of marks (1 byte a pixel), and `frames_held`
/// frames of 4 bytes a pixel being drawn or written.
pub fn picture_morph_memory(pixels: u64, frame_pixels: u64, frames_held: u64) -> u64 {
    let picture = 4 * pixels + 8 * pixels / 3;
    2 * picture + 4 * pixels + pixels + frames_held * 4 * frame_pixels
}
