//! Pictures the CLI writes: SVG frames, GIF animations, PNG stills.

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{Context, Result};
use meshmorph::render::{
    self, Flipped, GifOptions, GridLayout, GridOptions, GridRow, Ramp, Style2d, Style3d, View2d,
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
/// frame, `size` pixels on its longer side. Frames are asked for twice (for the view, then to draw), in
/// parallel; each is held only while it is drawn.
pub fn write_svgs(
    staging: &Staging,
    outputs: &[Output],
    frames: &dyn FrameSource<2>,
    triangles: &[[u32; 3]],
    size: u32,
) -> Result<()> {
    let corners: Vec<[[f64; 2]; 2]> = (0..frames.num_frames())
        .into_par_iter()
        .map(|k| {
            let mut bounds = [[0.0; 2]; 2];
            frames.with_frame(k, &mut |f| bounds = View2d::bounds([f]));
            bounds
        })
        .collect();
    let view = View2d::fitting_longest(corners.iter().map(|c| c.as_slice()), size, 16);
    let style = style_2d();
    outputs.par_iter().enumerate().try_for_each(|(k, &output)| {
        let mut svg = String::new();
        frames.with_frame(k, &mut |f| {
            svg = render::svg_frame(f, triangles, &view, &style)
        });
        staging.write_to(output, |_, w| Ok(w.write_all(svg.as_bytes())?))
    })
}

/// The longer side of a picture's views in pixels without `--size`.
pub const DEFAULT_SIZE: u32 = 640;

/// The frame rate of the animations without `--fps`.
pub const DEFAULT_FPS: f64 = 25.0;

/// How pictures are drawn: the options every command that draws takes,
/// meaning the same on each, with one default each.
#[derive(Debug, Clone, clap::Args)]
pub struct DrawArgs {
    /// The size of the pictures in pixels: each view (a GIF's frame, each
    /// pose of a PNG, each SVG frame) fits in PX x PX, its other side
    /// following the mesh's shape.
    #[arg(long, default_value_t = DEFAULT_SIZE, value_name = "PX", value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub size: u32,
    /// The GIF's width in pixels instead of --size [default: from --size].
    #[arg(long, value_name = "PX", value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub gif_width: Option<u32>,
    /// The GIF's height in pixels instead of --size [default: from --size,
    /// or from --gif-width and the shape].
    #[arg(long, value_name = "PX", value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub gif_height: Option<u32>,
    /// Frame rate of the GIF and of the glTF animation.
    #[arg(long, default_value_t = DEFAULT_FPS, value_name = "FPS", value_parser = crate::output::frame_rate)]
    pub fps: f64,
    /// Play the GIF (and a picture morph's APNG) forward only, instead of
    /// forward then back.
    #[arg(long)]
    pub no_boomerang: bool,
}

impl Default for DrawArgs {
    fn default() -> Self {
        DrawArgs {
            size: DEFAULT_SIZE,
            gif_width: None,
            gif_height: None,
            fps: DEFAULT_FPS,
            no_boomerang: false,
        }
    }
}

impl DrawArgs {
    /// Size and timing of a GIF.
    fn gif_options(&self) -> GifOptions {
        let exact = self.gif_width.is_some() || self.gif_height.is_some();
        GifOptions {
            width: self.gif_width.unwrap_or(self.size),
            height: self.gif_height,
            longest_side: (!exact).then_some(self.size),
            fps: self.fps,
            boomerang: !self.no_boomerang,
            ..GifOptions::default()
        }
    }

    /// The cells of a GIF of meshes in space, looking along `direction`:
    /// supersampled twice (each frame is a small part of the animation).
    fn gif_grid(&self, direction: [f64; 3]) -> GridOptions {
        let exact = self.gif_width.is_some() || self.gif_height.is_some();
        GridOptions {
            cell_width: self.gif_width.unwrap_or(self.size),
            cell_height: self.gif_height,
            longest_side: (!exact).then_some(self.size),
            supersample: 2,
            tall_rows_side_by_side: true,
            ..grid_options(direction)
        }
    }

    /// The cells of a still picture, looking along `direction`: each view
    /// --size on its longer side, with a caption above it.
    fn still_grid(&self, direction: [f64; 3]) -> GridOptions {
        GridOptions {
            longest_side: Some(self.size),
            captions: true,
            tall_rows_side_by_side: true,
            ..grid_options(direction)
        }
    }
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
/// that holds them all, frames in space smooth-shaded through one camera.
/// Each frame is held only while it is drawn.
pub fn write_gif<const D: usize>(
    path: &Path,
    frames: &dyn FrameSource<D>,
    triangles: &[[u32; 3]],
    args: &DrawArgs,
) -> Result<()> {
    let options = args.gif_options();
    let counted = crate::progress::Counted::new(frames, "GIF");
    let frames = InDim(&counted);
    if D == 2 {
        render::write_gif_2d_frames(path, &frames, triangles, &options, &style_2d())?;
    } else {
        let style = Style3d::with_ramp(Ramp::BLUE);
        let grid = args.gif_grid(FROM_FRONT);
        render::write_gif_3d_frames(path, &frames, triangles, style, &grid, &options)?;
    }
    Ok(())
}

/// A still picture (PNG) of the first, middle and last frames side by
/// side (planar frames seen from above), each captioned by `caption` of
/// its frame's index.
pub fn write_png<const D: usize>(
    path: &Path,
    frames: &dyn FrameSource<D>,
    triangles: &[[u32; 3]],
    args: &DrawArgs,
    caption: impl Fn(usize) -> String,
) -> Result<()> {
    let lifted = InDim(frames);
    let picked = picks(frames.num_frames());
    let poses: Vec<Vec<[f64; 3]>> = picked
        .iter()
        .map(|&k| {
            let mut pose = Vec::new();
            lifted.with_frame(k, &mut |f: &[[f64; 3]]| pose = f.to_vec());
            pose
        })
        .collect();
    let direction = if D == 2 { FROM_ABOVE } else { FROM_FRONT };
    let row = space_row(triangles, poses.iter().map(Vec::as_slice).collect());
    let captions: Vec<Vec<String>> = vec![picked.iter().map(|&k| caption(k)).collect()];
    write_still(path, &[row], &captions, &args.still_grid(direction))
}

/// Draws `rows` (each pose captioned by its entry of `captions`) and
/// writes the picture as a PNG.
fn write_still(
    path: &Path,
    rows: &[GridRow<'_>],
    captions: &[Vec<String>],
    options: &GridOptions,
) -> Result<()> {
    let layout = GridLayout::fit(rows, options);
    let mut canvas = layout.render(rows);
    for (r, row) in captions.iter().enumerate() {
        for (k, text) in row.iter().enumerate() {
            layout.caption(&mut canvas, r as u32, k as u32, text);
        }
    }
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

/// `--png` and `--gif`, and how pictures are drawn: the same on every
/// command that draws (their help for `--png` and `--gif` says what each
/// shows).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct PictureArgs {
    /// Also write a still picture (PNG) of the result.
    #[arg(long, value_name = "FILE.png", value_parser = png_file)]
    pub png: Option<PathBuf>,
    /// Also write an animated GIF of the result.
    #[arg(long, value_name = "FILE.gif", value_parser = gif_file)]
    pub gif: Option<PathBuf>,
    #[command(flatten)]
    pub draw: DrawArgs,
}

impl PictureArgs {
    /// Whether any picture is asked for.
    pub fn any(&self) -> bool {
        self.png.is_some() || self.gif.is_some()
    }
}

/// Meshes in space with one set of triangles: the triangles and the poses.
pub type Poses<'a> = (&'a [[u32; 3]], &'a [&'a [[f64; 3]]]);

/// A view from the front, a little from the left and from above, y up.
const FROM_FRONT: [f64; 3] = [-0.25, -0.35, -1.0];

/// Planar meshes seen from above.
const FROM_ABOVE: [f64; 3] = [0.0, 0.0, -1.0];

/// The look of grid pictures: looking along `direction`, y up.
fn grid_options(direction: [f64; 3]) -> GridOptions {
    GridOptions {
        direction,
        up: [0.0, 1.0, 0.0],
        ..GridOptions::default()
    }
}

/// Pictures of a transfer, as `meshmorph demo` draws them: source poses
/// above, target poses below (side by side when there is one pose of tall
/// meshes). The PNG shows the first, the middle and the last pose, each
/// captioned by its name in `names` (the target's with `target` too); the
/// GIF every pose. Returns the files written.
pub fn write_transfer_pictures(
    args: &PictureArgs,
    source: Poses<'_>,
    target: Poses<'_>,
    (names, target_name): (&[String], &str),
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
            hold_ends: Duration::from_millis(600),
            ..args.draw.gif_options()
        };
        render::write_gif_grid(path, &frames, &args.draw.gif_grid(FROM_FRONT), &options)
            .with_context(|| format!("writing the animation `{}`", path.display()))?;
        written.push(path.clone());
    }
    if let Some(path) = &args.png {
        let picked = picks(n);
        let name = |k: usize| names.get(k).map_or("", String::as_str);
        let captions = vec![
            picked.iter().map(|&k| name(k).to_string()).collect(),
            picked
                .iter()
                .map(|&k| format!("{} on {target_name}", name(k)))
                .collect(),
        ];
        write_still(
            path,
            &rows(&picked),
            &captions,
            &args.draw.still_grid(FROM_FRONT),
        )
        .with_context(|| format!("writing the picture `{}`", path.display()))?;
        written.push(path.clone());
    }
    Ok(written)
}

/// One step of the colour scale of a correspondence's picture, as a
/// fraction of the target's bounding-box diagonal: seven steps from green
/// to red cover 0 to 1.75 %, farther is purple. Fixed, so that pictures of
/// different correspondences compare; the default match threshold (1 %)
/// falls where orange begins.
pub const FIT_STEP: f64 = 0.0025;

/// Pictures of a correspondence: the source deformed onto the target above
/// the target (side by side when they are tall), captioned with `names`
/// (the source's and the target's). In the PNG, each target triangle is
/// coloured by `distances` (its distance to the deformed source over the
/// target's diagonal) on a scale of [`FIT_STEP`] per colour, explained
/// below the picture. The GIF shows the source reference turning into the
/// deformed source. Returns the files written.
pub fn write_correspondence_pictures(
    args: &PictureArgs,
    source: Poses<'_>,
    deformed: &[[f64; 3]],
    target: Poses<'_>,
    distances: &[f64],
    (source_name, target_name): (&str, &str),
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
            draw: args.draw.clone(),
        };
        written.extend(write_transfer_pictures(
            &only_gif,
            (source.0, &sources),
            (target.0, &targets),
            (&[], target_name),
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
        let captions = [
            format!("{source_name} deformed"),
            format!("{target_name} by distance"),
        ];
        let steps = (Ramp::SCALE.len() - 1) as f64;
        let ramps: Vec<Ramp> = distances
            .iter()
            .map(|d| Ramp::on_scale(d / (steps * FIT_STEP)))
            .collect();
        let options = args.draw.still_grid(FROM_FRONT);
        let layout = GridLayout::fit(&rows, &options);
        let mut canvas = layout.render_coloured(&rows, &[&[], &ramps]);
        for (r, caption) in captions.iter().enumerate() {
            layout.caption(&mut canvas, r as u32, 0, caption);
        }
        // "0.5", "1", "1.75": two decimals at most, trailing zeros dropped.
        let label = |k: usize| {
            let text = format!("{:.2}", 100.0 * FIT_STEP * k as f64);
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        };
        let labels: Vec<(usize, String)> = [0, 2, 4, 6, 7].map(|k| (k, label(k))).to_vec();
        let ticks: Vec<(usize, &str)> = labels.iter().map(|(k, t)| (*k, t.as_str())).collect();
        let legend = render::Legend {
            title: "distance, % of target diagonal (purple: farther)",
            ramps: &Ramp::SCALE,
            ticks: &ticks,
        };
        render::write_png(path, &render::with_legend(&canvas, &legend))
            .with_context(|| format!("writing the picture `{}`", path.display()))?;
        written.push(path.clone());
    }
    Ok(written)
}
