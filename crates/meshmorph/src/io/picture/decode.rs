//! Pictures read from PNG and JPEG files into 8-bit RGBA.

use std::io::Cursor;
use std::path::Path;

use super::Picture;
use crate::error::{Error, Result};

/// The file formats pictures are read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PictureFormat {
    /// PNG (any colour type and bit depth; an APNG's first frame).
    Png,
    /// JPEG (baseline or progressive; greyscale, YCbCr or CMYK).
    Jpeg,
}

impl PictureFormat {
    /// The format a path's extension names (`.png`, `.jpg`, `.jpeg`;
    /// case-insensitive), if any.
    pub fn of_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "png" => Some(Self::Png),
            "jpg" | "jpeg" => Some(Self::Jpeg),
            _ => None,
        }
    }

    /// The format the first bytes of a file say, if any.
    fn of_bytes(bytes: &[u8]) -> Option<Self> {
        if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
            Some(Self::Png)
        } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
            Some(Self::Jpeg)
        } else {
            None
        }
    }
}

/// Reads the picture at `path` (PNG or JPEG, told by its first bytes),
/// refusing one of more than `max_pixels` pixels before decoding it.
///
/// # Errors
/// [`Error::Io`] and [`Error::FileRefused`] as for meshes;
/// [`Error::Parse`] naming the file for one that is neither PNG nor JPEG,
/// is damaged, or is larger than `max_pixels`.
pub fn read_picture(path: &Path, max_pixels: u64) -> Result<Picture> {
    let bytes = super::super::read::read_file(path, &super::super::read::Limit::memory())?;
    decode_picture(&bytes, path, max_pixels)
}

/// [`read_picture`] on a file's bytes already read (`path` names it in
/// messages).
///
/// # Errors
/// As [`read_picture`].
pub fn decode_picture(bytes: &[u8], path: &Path, max_pixels: u64) -> Result<Picture> {
    let refuse = |message: String| Error::parse(path, None, message);
    let too_large = |w: u64, h: u64| {
        refuse(format!(
            "{w} × {h} pixels is more than the {max_pixels} pixels a picture may have here (the memory a morph takes grows with its pictures' pixels): use a smaller picture"
        ))
    };
    match PictureFormat::of_bytes(bytes) {
        Some(PictureFormat::Png) => {
            let mut decoder = ::png::Decoder::new(Cursor::new(bytes));
            decoder.set_transformations(::png::Transformations::normalize_to_color8());
            let mut reader = decoder
                .read_info()
                .map_err(|e| refuse(format!("not a readable PNG: {e}")))?;
            let (w, h) = {
                let info = reader.info();
                (info.width, info.height)
            };
            if u64::from(w) * u64::from(h) > max_pixels {
                return Err(too_large(w.into(), h.into()));
            }
            let size = reader
                .output_buffer_size()
                .ok_or_else(|| refuse("a PNG too large to decode".into()))?;
            let mut buf = vec![0; size];
            let info = reader
                .next_frame(&mut buf)
                .map_err(|e| refuse(format!("a damaged PNG: {e}")))?;
            let pixels = w as usize * h as usize;
            let channels = info.color_type.samples();
            let mut rgba = Vec::with_capacity(4 * pixels);
            for row in buf.chunks(info.line_size).take(h as usize) {
                for p in row[..w as usize * channels].chunks_exact(channels) {
                    rgba.extend_from_slice(&match channels {
                        1 => [p[0], p[0], p[0], 255],
                        2 => [p[0], p[0], p[0], p[1]],
                        3 => [p[0], p[1], p[2], 255],
                        _ => [p[0], p[1], p[2], p[3]],
                    });
                }
            }
            Picture::new(w, h, rgba).map_err(|e| refuse(e.to_string()))
        }
        Some(PictureFormat::Jpeg) => {
            use zune_jpeg::zune_core::colorspace::ColorSpace;
            use zune_jpeg::zune_core::options::DecoderOptions;
            let options = DecoderOptions::default()
                .jpeg_set_out_colorspace(ColorSpace::RGBA)
                .set_max_width(usize::MAX)
                .set_max_height(usize::MAX);
            let mut decoder = zune_jpeg::JpegDecoder::new_with_options(Cursor::new(bytes), options);
            decoder
                .decode_headers()
                .map_err(|e| refuse(format!("not a readable JPEG: {e:?}")))?;
            let info = decoder
                .info()
                .ok_or_else(|| refuse("a JPEG without a frame header".into()))?;
            let (w, h) = (u32::from(info.width), u32::from(info.height));
            if u64::from(w) * u64::from(h) > max_pixels {
                return Err(too_large(w.into(), h.into()));
            }
            let rgba = decoder
                .decode()
                .map_err(|e| refuse(format!("a damaged JPEG: {e:?}")))?;
            Picture::new(w, h, rgba).map_err(|e| refuse(e.to_string()))
        }
        None => Err(refuse(
            "neither a PNG nor a JPEG (by its first bytes): give pictures as .png or .jpg".into(),
        )),
    }
}
