//! Pictures the CLI writes: SVG frames, GIF animations, PNG stills.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use meshmorph::render::{self, Flipped, GifOptions, Style2d, View2d};

/// The look of planar frames: triangles turned against the majority of
/// the mesh are drawn in the warning colour.
pub fn style_2d() -> Style2d {
    Style2d {
        flipped: Flipped::AgainstMajority,
        ..Style2d::default()
    }
}

/// Writes each frame as an SVG, all through one view that holds every frame.
pub fn write_svgs(
    paths: &[PathBuf],
    frames: &[Vec<[f64; 2]>],
    triangles: &[[u32; 3]],
    width: u32,
) -> Result<()> {
    let view = View2d::fitting(frames.iter().map(Vec::as_slice), width, None, 16);
    let style = style_2d();
    for (path, frame) in paths.iter().zip(frames) {
        let svg = render::svg_frame(frame, triangles, &view, &style);
        meshmorph::io::write_atomic(path, |w| w.write_all(svg.as_bytes()))
            .with_context(|| format!("writing `{}`", path.display()))?;
    }
    Ok(())
}

/// Options of an animation of planar frames.
pub struct GifArgs {
    pub width: u32,
    pub height: Option<u32>,
    pub fps: f64,
    pub boomerang: bool,
}

/// Writes the frames as an animated GIF with one view that holds them all.
pub fn write_gif(
    path: &Path,
    frames: &[Vec<[f64; 2]>],
    triangles: &[[u32; 3]],
    args: &GifArgs,
) -> Result<()> {
    let options = GifOptions {
        width: args.width,
        height: args.height,
        fps: args.fps,
        boomerang: args.boomerang,
        ..GifOptions::default()
    };
    render::write_gif_2d(path, frames, triangles, &options, &style_2d())
        .with_context(|| format!("writing the animation `{}`", path.display()))
}
