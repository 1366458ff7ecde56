//! Pictures the CLI writes: SVG frames, GIF animations, PNG stills.

use std::path::Path;

use anyhow::Result;
use meshmorph::render::{self, Flipped, GifOptions, Style2d, View2d};

use crate::outputs::{Output, Staging};

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
    staging: &Staging,
    outputs: &[Output],
    frames: &[Vec<[f64; 2]>],
    triangles: &[[u32; 3]],
    width: u32,
) -> Result<()> {
    let view = View2d::fitting(frames.iter().map(Vec::as_slice), width, None, 16);
    let style = style_2d();
    for (&output, frame) in outputs.iter().zip(frames) {
        let svg = render::svg_frame(frame, triangles, &view, &style);
        staging.write(output, |path| {
            Ok(meshmorph::io::write_atomic(path, |w| {
                w.write_all(svg.as_bytes())
            })?)
        })?;
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
    Ok(render::write_gif_2d(
        path,
        frames,
        triangles,
        &options,
        &style_2d(),
    )?)
}
