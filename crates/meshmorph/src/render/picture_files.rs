//! Full-colour pictures (straight RGBA) as files: a PNG still, an
//! animated PNG, an animated GIF, and a sprite sheet with its JSON.

use std::io::{self, Write};
use std::time::Duration;

use super::gif::gif_error;
use super::png::png_error;
use crate::io::picture::Picture;

/// Writes `picture` as an 8-bit RGBA PNG.
///
/// # Errors
/// The writer's errors.
pub fn write_picture_png(w: &mut dyn Write, picture: &Picture) -> io::Result<()> {
    let mut writer = rgba_encoder(w, picture.width, picture.height)
        .write_header()
        .map_err(png_error)?;
    writer.write_image_data(&picture.rgba).map_err(png_error)?;
    writer.finish().map_err(png_error)
}

/// A PNG encoder of 8-bit RGBA pixels.
fn rgba_encoder(w: &mut dyn Write, width: u32, height: u32) -> ::png::Encoder<'_, &mut dyn Write> {
    let mut enc = ::png::Encoder::new(w, width, height);
    enc.set_color(::png::ColorType::Rgba);
    enc.set_depth(::png::BitDepth::Eight);
    enc
}

/// Writes frames of `width × height` pixels as an animated PNG (APNG:
/// plays in every browser; viewers without APNG show the first frame), as
/// `schedule` shows them (frame and how long, in order: as
/// [`GifOptions::schedule`](super::GifOptions::schedule) gives them),
/// played over and over. `frame(k)` gives frame `k`, asked for once each
/// time it is shown.
///
/// # Errors
/// The writer's errors; [`io::ErrorKind::InvalidInput`] for no frame or a
/// frame of another size.
pub fn write_apng(
    w: &mut dyn Write,
    (width, height): (u32, u32),
    schedule: &[(usize, Duration)],
    frame: &mut dyn FnMut(usize) -> Picture,
) -> io::Result<()> {
    if schedule.is_empty() {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, "no frame"));
    }
    let mut enc = rgba_encoder(w, width, height);
    enc.set_animated(schedule.len() as u32, 0)
        .map_err(png_error)?;
    let mut writer = enc.write_header().map_err(png_error)?;
    for &(k, shown) in schedule {
        let ms = shown.as_millis().clamp(1, u128::from(u16::MAX)) as u16;
        writer.set_frame_delay(ms, 1000).map_err(png_error)?;
        let picture = frame(k);
        check_size(&picture, width, height)?;
        writer.write_image_data(&picture.rgba).map_err(png_error)?;
    }
    writer.finish().map_err(png_error)
}

/// Writes frames as an animated GIF as `schedule` shows them (frame and
/// how long, in hundredths of a second, at least 2), played over and
/// over: each frame's own 255 colours (NeuQuant), pixels under half alpha
/// transparent, every frame drawn on a cleared page.
/// Each frame is drawn and quantised once; one shown again later (on the
/// way back of a boomerang) is kept compressed until its last showing.
///
/// # Errors
/// As [`write_apng`].
pub fn write_picture_gif(
    w: &mut dyn Write,
    (width, height): (u32, u32),
    schedule: &[(usize, Duration)],
    frame: &mut dyn FnMut(usize) -> Picture,
) -> io::Result<()> {
    let (gw, gh) = (
        u16::try_from(width).map_err(|_| too_large(width))?,
        u16::try_from(height).map_err(|_| too_large(height))?,
    );
    let mut enc = ::gif::Encoder::new(w, gw, gh, &[]).map_err(gif_error)?;
    enc.set_repeat(::gif::Repeat::Infinite).map_err(gif_error)?;
    let count = schedule.iter().map(|s| s.0).max().map_or(0, |k| k + 1);
    let mut last_shown = vec![0; count];
    for (j, &(k, _)) in schedule.iter().enumerate() {
        last_shown[k] = j;
    }
    let mut kept: Vec<Option<::gif::Frame<'static>>> = vec![None; count];
    for (j, &(k, shown)) in schedule.iter().enumerate() {
        let mut f = match kept[k].take() {
            Some(f) => f,
            None => {
                let mut picture = frame(k);
                check_size(&picture, width, height)?;
                for p in picture.rgba.chunks_exact_mut(4) {
                    p[3] = if p[3] >= 128 { 255 } else { 0 };
                }
                let mut f = ::gif::Frame::from_rgba_speed(gw, gh, &mut picture.rgba, 10);
                f.dispose = ::gif::DisposalMethod::Background;
                f
            }
        };
        f.delay = (shown.as_millis() / 10).clamp(2, u128::from(u16::MAX)) as u16;
        enc.write_frame(&f).map_err(gif_error)?;
        if last_shown[k] > j {
            kept[k] = Some(f);
        }
    }
    Ok(())
}

/// Frames laid side by side in rows, `columns` a row, as one picture,
/// with the JSON that game engines' sprite-sheet importers read (the
/// "hash" layout of TexturePacker, read by Phaser, PixiJS, Cocos and
/// Unity's importers): `frames` named `name(k)`, each with its rectangle,
/// untrimmed and unrotated, and `duration` in milliseconds; `meta` with
/// the sheet's file name `image` and size.
pub fn sprite_sheet(
    frames: &[Picture],
    columns: usize,
    duration: Duration,
    image: &str,
    name: &dyn Fn(usize) -> String,
) -> (Picture, String) {
    let columns = columns.clamp(1, frames.len().max(1));
    let (fw, fh) = frames
        .first()
        .map_or((1, 1), |f| (f.width as usize, f.height as usize));
    let rows = frames.len().div_ceil(columns).max(1);
    let (sw, sh) = (fw * columns, fh * rows);
    let mut rgba = vec![0u8; 4 * sw * sh];
    let mut entries = serde_json::Map::new();
    for (k, f) in frames.iter().enumerate() {
        let (x0, y0) = ((k % columns) * fw, (k / columns) * fh);
        for y in 0..fh.min(f.height as usize) {
            let src = &f.rgba[4 * y * f.width as usize..][..4 * fw.min(f.width as usize)];
            let at = 4 * ((y0 + y) * sw + x0);
            rgba[at..at + src.len()].copy_from_slice(src);
        }
        entries.insert(
            name(k),
            serde_json::json!({
                "frame": {"x": x0, "y": y0, "w": fw, "h": fh},
                "rotated": false,
                "trimmed": false,
                "spriteSourceSize": {"x": 0, "y": 0, "w": fw, "h": fh},
                "sourceSize": {"w": fw, "h": fh},
                "duration": duration.as_millis() as u64,
            }),
        );
    }
    let json = serde_json::json!({
        "frames": entries,
        "meta": {
            "app": "meshmorph",
            "version": env!("CARGO_PKG_VERSION"),
            "image": image,
            "format": "RGBA8888",
            "size": {"w": sw, "h": sh},
            "scale": "1",
        },
    });
    let sheet = Picture {
        width: sw as u32,
        height: sh as u32,
        rgba,
    };
    (
        sheet,
        serde_json::to_string_pretty(&json).unwrap_or_default(),
    )
}

fn check_size(p: &Picture, width: u32, height: u32) -> io::Result<()> {
    if (p.width, p.height) != (width, height) {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "a frame of {} × {} among frames of {width} × {height}",
                p.width, p.height
            ),
        ));
    }
    Ok(())
}

fn too_large(side: u32) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("a GIF's sides are at most 65535 pixels, not {side}"),
    )
}
