//! Still pictures as PNG.

use std::io;
use std::path::Path;

use super::canvas::Canvas;
use crate::error::{Error, Result};

/// Writes `canvas` as an 8-bit indexed PNG (the palette trimmed to the
/// entries used), which keeps the files small and the colours exact.
///
/// # Errors
/// [`Error::InvalidArgument`] for an empty canvas or one whose pixels do not
/// match its size, [`Error::Io`] when writing fails.
pub fn write_png(path: &Path, canvas: &Canvas) -> Result<()> {
    if canvas.width == 0 || canvas.height == 0 {
        return Err(Error::InvalidArgument(format!(
            "cannot write an empty {} × {} picture",
            canvas.width, canvas.height
        )));
    }
    if canvas.pixels.len() != canvas.width as usize * canvas.height as usize {
        return Err(Error::InvalidArgument(format!(
            "a {} × {} canvas with {} pixels",
            canvas.width,
            canvas.height,
            canvas.pixels.len()
        )));
    }
    let used = canvas.pixels.iter().copied().max().unwrap_or(0) as usize + 1;
    let palette = &canvas.palette.to_bytes()[..3 * used];
    crate::io::write_atomic(path, |out| {
        let mut enc = ::png::Encoder::new(out, canvas.width, canvas.height);
        enc.set_color(::png::ColorType::Indexed);
        enc.set_depth(::png::BitDepth::Eight);
        enc.set_palette(palette);
        let mut writer = enc.write_header().map_err(png_error)?;
        writer.write_image_data(&canvas.pixels).map_err(png_error)?;
        writer.finish().map_err(png_error)
    })
}

pub fn png_error(e: ::png::EncodingError) -> io::Error {
    match e {
        ::png::EncodingError::IoError(e) => e,
        e => io::Error::other(e),
    }
}
