//! Pictures the CLI writes: SVG frames, GIF animations, PNG stills.

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{Context, Result};
use meshmorph::render::{
    self, Flipped, GifOptions, GridOptions, GridRow, Ramp, Style2d, Style3d, View2d,
};
use meshmorph::FrameSource;
use rayon::prelude::*;

use crate::outputs::{Output, Staging};

/// The look of planar frames: triangles turned against the majority of
/// the mesh are drawn in the warning colour.
pub fn style_2d() -> Style2d {
    Style2d {
        flipped: Flipped::AgainstMajority,
        ..Style2d::default()
    }
}

/// Writes each frame as an SVG, all through one view that holds every
/// frame. Frames are asked for twice (for the view, then to draw), in
/// parallel; each is held only while it is drawn.
pub fn write_svgs(
    staging: &Staging,
    outputs: &[Output],
    frames: &dyn FrameSource<2>,
    triangles: &[[u32; 3]],
    width: u32,
) -> Result<()> {
    let corners: Vec<[[f64; 2]; 2]> = (0..frames.num_frames())
        .into_par_iter()
        .map(|k| {
            let mut bounds = [[0.0; 2]; 2];
            frames.with_frame(k, &mut |f| bounds = View2d::bounds([f]));
            bounds
        })
        .collect();
    let view = View2d::fitting(corners.iter().map(|c| c.as_slice()), width, None, 16);
    let style = style_2d();
    outputs.par_iter().enumerate().try_for_each(|(k, &output)| {
        let mut svg = String::new();
        frames.with_frame(k, &mut |f| {
            svg = render::svg_frame(f, triangles, &view, &style)
        });
        staging.write_to(output, |_, w| Ok(w.write_all(svg.as_bytes())?))
    })
}

/// Options of an animation of frames.
pub struct GifArgs {
    pub width: u32,
    pub height: Option<u32>,
    pub fps: f64,
    pub boomerang: bool,
}

/// The frames of a source of `D`-dimensional frames with `E` coordinates:
/// planar frames lifted to z = 0, or frames in space seen from above.
pub struct InDim<'a, const D: usize>(pub &'a dyn FrameSource<D>);

impl<const D: usize, const E: usize> FrameSource<E> for InDim<'_, D> {
    fn num_frames(&self) -> usize {
        self.0.num_frames()
    }

    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; E]])) {
        self.0.with_frame(k, &mut |f| use_frame(&in_dim(f)))
    }
}

/// Positions with `D` coordinates given `E`: z = 0 added, or z dropped.
pub fn in_dim<const D: usize, const E: usize>(positions: &[[f64; D]]) -> Vec<[f64; E]> {
    positions
        .iter()
        .map(|p| std::array::from_fn(|c| if c < D { p[c] } else { 0.0 }))
        .collect()
}

/// Writes the frames as an animated GIF: planar frames through one view
/// that holds them all, frames in space flat-shaded through one camera.
/// Each frame is held only while it is drawn.
pub fn write_gif<const D: usize>(
    path: &Path,
    frames: &dyn FrameSource<D>,
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
    let counted = crate::progress::Counted::new(frames, "GIF");
    let frames = InDim(&counted);
    if D == 2 {
        render::write_gif_2d_frames(path, &frames, triangles, &options, &style_2d())?;
    } else {
        let style = Style3d::with_ramp(Ramp::BLUE);
        let grid = grid_options(args.width);
        render::write_gif_3d_frames(path, &frames, triangles, style, &grid, &options)?;
    }
    Ok(())
}

/// A still picture (PNG) of the first, middle and last frames side by
/// side, each `cell_width` pixels wide (planar frames seen from above).
pub fn write_png<const D: usize>(
    path: &Path,
    frames: &dyn FrameSource<D>,
    triangles: &[[u32; 3]],
    cell_width: u32,
) -> Result<()> {
    let lifted = InDim(frames);
    let poses: Vec<Vec<[f64; 3]>> = picks(frames.num_frames())
        .into_iter()
        .map(|k| {
            let mut pose = Vec::new();
            lifted.with_frame(k, &mut |f: &[[f64; 3]]| pose = f.to_vec());
            pose
        })
        .collect();
    let mut options = grid_options(cell_width);
    if D == 2 {
        options.direction = [0.0, 0.0, -1.0];
    }
    let row = space_row(triangles, poses.iter().map(Vec::as_slice).collect());
    let canvas = render::render_grid_3d(&[row], &options);
    Ok(render::write_png(path, &canvas)?)
}

/// The first, middle and last of `n` frames (fewer when they coincide).
fn picks(n: usize) -> Vec<usize> {
    let mut picks = vec![0, n / 2, n.saturating_sub(1)];
    picks.dedup();
    picks
}

/// One row of poses in space, in the interpolation's colour.
fn space_row<'a>(triangles: &'a [[u32; 3]], poses: Vec<&'a [[f64; 3]]>) -> GridRow<'a> {
    GridRow {
        triangles,
        poses,
        style: Style3d::with_ramp(Ramp::BLUE),
    }
}

/// A path ending in `.ext` (any case), for a file written as `what` (a
/// clap value parser's body): a file named otherwise would not open as
/// what it is.
pub fn file_named(text: &str, ext: &str, what: &str) -> Result<PathBuf, String> {
    let path = PathBuf::from(text);
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
    {
        Ok(path)
    } else {
        Err(format!(
            "`{text}`: the file is written as {what}; name it with the extension .{ext}"
        ))
    }
}

/// A `.png` path (a clap value parser).
pub fn png_file(text: &str) -> Result<PathBuf, String> {
    file_named(text, "png", "PNG")
}

/// A `.gif` path (a clap value parser).
pub fn gif_file(text: &str) -> Result<PathBuf, String> {
    file_named(text, "gif", "GIF")
}

/// `--png` and `--gif` of the commands on meshes in space.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct PictureArgs {
    /// Also write a still picture (PNG) of the result.
    #[arg(long, value_name = "FILE.png", value_parser = png_file)]
    pub png: Option<PathBuf>,
    /// Also write an animated GIF of the result.
    #[arg(long, value_name = "FILE.gif", value_parser = gif_file)]
    pub gif: Option<PathBuf>,
}

impl PictureArgs {
    /// Whether any picture is asked for.
    pub fn any(&self) -> bool {
        self.png.is_some() || self.gif.is_some()
    }
}

/// Meshes in space with one set of triangles: the triangles and the poses.
pub type Poses<'a> = (&'a [[u32; 3]], &'a [&'a [[f64; 3]]]);

/// The look of grid pictures: a view from the front, a little from the
/// left and from above, y up.
fn grid_options(cell_width: u32) -> GridOptions {
    GridOptions {
        cell_width,
        direction: [-0.25, -0.35, -1.0],
        up: [0.0, 1.0, 0.0],
        ..GridOptions::default()
    }
}

/// Pictures of a transfer, as `meshmorph demo` draws them: source poses
/// above, target poses below. The PNG shows the first, the middle and the
/// last pose; the GIF every pose at `fps`. Returns the files written.
pub fn write_transfer_pictures(
    args: &PictureArgs,
    fps: f64,
    source: Poses<'_>,
    target: Poses<'_>,
) -> Result<Vec<PathBuf>> {
    let rows = |picks: &[usize]| {
        vec![
            GridRow {
                triangles: source.0,
                poses: picks.iter().map(|&k| source.1[k]).collect(),
                style: Style3d::with_ramp(Ramp::BLUE),
            },
            GridRow {
                triangles: target.0,
                poses: picks.iter().map(|&k| target.1[k]).collect(),
                style: Style3d::with_ramp(Ramp::SAND),
            },
        ]
    };
    let n = source.1.len();
    let mut written = Vec::new();
    if let Some(path) = &args.gif {
        let frames: Vec<Vec<GridRow<'_>>> = (0..n).map(|k| rows(&[k])).collect();
        let options = GifOptions {
            fps,
            hold_ends: Duration::from_millis(600),
            ..GifOptions::default()
        };
        render::write_gif_grid(path, &frames, &grid_options(360), &options)
            .with_context(|| format!("writing the animation `{}`", path.display()))?;
        written.push(path.clone());
    }
    if let Some(path) = &args.png {
        let mut picks = vec![0, n / 2, n - 1];
        picks.dedup();
        let canvas = render::render_grid_3d(&rows(&picks), &grid_options(240));
        render::write_png(path, &canvas)
            .with_context(|| format!("writing the picture `{}`", path.display()))?;
        written.push(path.clone());
    }
    Ok(written)
}

/// Pictures of a correspondence: the source deformed onto the target above,
/// the target below. The GIF shows the source reference turning into the
/// deformed source. Returns the files written.
pub fn write_correspondence_pictures(
    args: &PictureArgs,
    source: Poses<'_>,
    deformed: &[[f64; 3]],
    target: Poses<'_>,
) -> Result<Vec<PathBuf>> {
    /// Steps of the GIF from the reference to the deformed source.
    const STEPS: usize = 24;
    let blends: Vec<Vec<[f64; 3]>> = (0..STEPS)
        .map(|k| {
            let s = k as f64 / (STEPS - 1) as f64;
            source.1[0]
                .iter()
                .zip(deformed)
                .map(|(a, b)| std::array::from_fn(|c| (1.0 - s) * a[c] + s * b[c]))
                .collect()
        })
        .collect();
    let sources: Vec<&[[f64; 3]]> = blends.iter().map(Vec::as_slice).collect();
    let targets: Vec<&[[f64; 3]]> = vec![target.1[0]; STEPS];
    let mut written = Vec::new();
    if let Some(path) = &args.gif {
        let only_gif = PictureArgs {
            png: None,
            gif: Some(path.clone()),
        };
        written.extend(write_transfer_pictures(
            &only_gif,
            12.0,
            (source.0, &sources),
            (target.0, &targets),
        )?);
    }
    if let Some(path) = &args.png {
        let rows = vec![
            GridRow {
                triangles: source.0,
                poses: vec![deformed],
                style: Style3d::with_ramp(Ramp::BLUE),
            },
            GridRow {
                triangles: target.0,
                poses: vec![target.1[0]],
                style: Style3d::with_ramp(Ramp::SAND),
            },
        ];
        let canvas = render::render_grid_3d(&rows, &grid_options(360));
        render::write_png(path, &canvas)
            .with_context(|| format!("writing the picture `{}`", path.display()))?;
        written.push(path.clone());
    }
    Ok(written)
}
