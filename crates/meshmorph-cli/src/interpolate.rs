//! `meshmorph interpolate`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use meshmorph::io::gltf::{GltfBase, GltfOptions};
use meshmorph::{Interpolator, InterpolatorOptions, Mesh2, StretchMode};
use rayon::prelude::*;
use serde::Serialize;

use crate::gltf::GltfArgs;
use crate::memory;
use crate::output::{self, positive_number, FormatArg};
use crate::outputs::{Output, Plan, Staging};
use crate::pictures;
use crate::progress;

/// Interpolate between two planar meshes with the same triangles.
///
/// Writes DIR/frame_0000.obj, frame_0001.obj, ... and prints a report.
///
/// Inputs are never written: an output that would land on an input is
/// refused before any work. All or nothing: every file is written under a
/// temporary name and moved into place only when the whole run has
/// succeeded; a failed or interrupted (Ctrl-C) run leaves the output folder
/// as it was. After a successful run, files of an earlier run in DIR named
/// exactly like frames (frame_ + digits + .obj/.off/.ply/.svg) that this
/// run did not write are removed; no other file is touched.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The shape at t = 0 (OBJ, OFF or PLY; planar: every z = 0).
    pub source: PathBuf,
    /// The shape at t = 1: the same vertices and triangles as SOURCE.
    pub target: PathBuf,
    /// Directory for the frames (created if missing).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    #[command(flatten)]
    pub frames: FrameArgs,
    /// Output mesh format [default: the source's].
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Options shared by `interpolate` and `demo`.
#[derive(Debug, Clone, clap::Args)]
pub struct FrameArgs {
    /// Number of frames, t evenly from 0 to 1 inclusive (at most 1000000).
    #[arg(long, default_value_t = 30, value_name = "N", value_parser = frame_count)]
    pub frames: usize,
    /// Explicit times instead, comma-separated, written in this order
    /// (values outside [0, 1] extrapolate), e.g. --t 0,0.5,1.5
    #[arg(
        long = "t",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "LIST",
        conflicts_with = "frames"
    )]
    pub times: Option<Vec<f64>>,
    /// Interpolate each triangle's principal angle (-180..180 degrees) as it
    /// is, without making angles continuous across neighbours: parts that turn
    /// by more than half a turn then tear.
    #[arg(long)]
    pub no_consistency: bool,
    /// Add K whole turns (360 degrees each, counter-clockwise for K > 0) to
    /// every triangle's rotation: the long way round.
    #[arg(
        long,
        default_value_t = 0,
        allow_negative_numbers = true,
        value_name = "K"
    )]
    pub turns: i32,
    /// Stretch interpolation: `linear` is (1-t)I + tS as in Alexa et al.;
    /// `log` is S^t, which never collapses a triangle when extrapolating.
    #[arg(long, value_enum, default_value_t = Stretch::Linear)]
    pub stretch: Stretch,
    /// Go on when triangles are reversed between source and target.
    #[arg(long)]
    pub allow_flips: bool,
    /// Also write an animated GIF of the frames to FILE.
    #[arg(long, value_name = "FILE")]
    pub gif: Option<PathBuf>,
    /// GIF width in pixels.
    #[arg(long, default_value_t = 640, value_name = "PX", value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub gif_width: u32,
    /// GIF height in pixels [default: from the shape's aspect ratio].
    #[arg(long, value_name = "PX", value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub gif_height: Option<u32>,
    /// Frame rate of the GIF and of the glTF animation.
    #[arg(long, default_value_t = 25.0, value_name = "FPS", value_parser = positive_number)]
    pub fps: f64,
    /// Play the GIF forward only, instead of forward then back.
    #[arg(long)]
    pub no_boomerang: bool,
    /// Also write each frame as an SVG beside the mesh files (one view that
    /// holds every frame, --gif-width pixels wide).
    #[arg(long)]
    pub svg: bool,
    #[command(flatten)]
    pub gltf: GltfArgs,
}

/// The most frames a run writes: a million files is already more than a
/// folder comfortably holds.
pub const MAX_FRAMES: usize = 1_000_000;

/// A frame count from 1 to [`MAX_FRAMES`].
fn frame_count(text: &str) -> Result<usize, String> {
    match text.parse::<u128>() {
        Ok(0) => Err("at least 1 frame is needed".into()),
        Ok(n) if n <= MAX_FRAMES as u128 => Ok(n as usize),
        Ok(_) => Err(format!("{text} frames is too many (at most {MAX_FRAMES})")),
        Err(_) => Err(format!("`{text}` is not a whole number of frames")),
    }
}

/// `--stretch` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Stretch {
    /// (1-t) I + t S.
    Linear,
    /// S^t.
    Log,
}

impl FrameArgs {
    pub fn times(&self) -> Result<Vec<f64>> {
        if let Some(t) = &self.times {
            if t.is_empty() {
                bail!("--t needs at least one time");
            }
            if let Some(x) = t.iter().find(|x| !x.is_finite()) {
                bail!("--t: {x} is not a finite number");
            }
            if t.len() > MAX_FRAMES {
                bail!("--t lists {} times: at most {MAX_FRAMES}", t.len());
            }
            return Ok(t.clone());
        }
        match self.frames {
            0 => bail!("--frames must be at least 1"),
            n if n > MAX_FRAMES => bail!("--frames {n} is too many (at most {MAX_FRAMES})"),
            1 => Ok(vec![0.0]),
            n => Ok((0..n).map(|k| k as f64 / (n - 1) as f64).collect()),
        }
    }

    fn options(&self) -> InterpolatorOptions {
        InterpolatorOptions::default()
            .with_consistency(!self.no_consistency)
            .with_turns(self.turns)
            .with_stretch(match self.stretch {
                Stretch::Linear => StretchMode::Linear,
                Stretch::Log => StretchMode::Log,
            })
            .with_allow_flips(self.allow_flips)
    }
}

/// What a run did, for people and (with --json) for programs.
#[derive(Debug, Serialize)]
pub struct Report {
    /// Where the frames went.
    pub output: PathBuf,
    /// Number of frame files written.
    pub frames_written: usize,
    /// Vertices and triangles of the mesh.
    pub vertices: usize,
    /// Triangles of the mesh.
    pub triangles: usize,
    /// Building the interpolator: polar decompositions, factorization.
    pub setup_seconds: f64,
    /// Computing one frame, averaged (frames run in parallel).
    pub seconds_per_frame: f64,
    /// Writing one frame's files, averaged.
    pub write_seconds_per_frame: f64,
    /// Wall time of the whole command.
    pub total_seconds: f64,
    /// The largest number of triangles reversed relative to the source in any frame.
    pub max_flipped_triangles: usize,
    /// The frame (index) where that happened.
    pub max_flipped_frame: usize,
    /// The GIF written, if any.
    pub gif: Option<PathBuf>,
    /// The GLB written, if any.
    pub gltf: Option<PathBuf>,
    /// Every file written, in order.
    pub files_written: Vec<PathBuf>,
    /// The warnings given (also printed on stderr).
    pub warnings: Vec<String>,
    /// Frame files of an earlier run removed from the output folder.
    pub surplus_frames_removed: usize,
    /// Vertices no triangle uses: they move on the straight line from their
    /// source to their target position and count in no scale.
    pub unused_vertices: usize,
}

impl Report {
    pub fn print(&self, json: bool) {
        if json {
            output::print_json(self);
            return;
        }
        println!(
            "wrote {} frames ({} vertices, {} triangles) to {}",
            self.frames_written,
            self.vertices,
            self.triangles,
            self.output.display()
        );
        println!(
            "setup:          {}",
            output::human_seconds(self.setup_seconds)
        );
        println!(
            "time per frame: {} (+ {} writing)",
            output::human_seconds(self.seconds_per_frame),
            output::human_seconds(self.write_seconds_per_frame)
        );
        println!(
            "total:          {}",
            output::human_seconds(self.total_seconds)
        );
        if self.max_flipped_triangles == 0 {
            println!("flipped triangles: none in any frame");
        } else {
            println!(
                "flipped triangles: at most {} (frame {})",
                self.max_flipped_triangles, self.max_flipped_frame
            );
        }
        if let Some(g) = &self.gif {
            println!("animation: {}", g.display());
        }
        if let Some(g) = &self.gltf {
            println!("glTF:      {}", g.display());
        }
        if self.unused_vertices > 0 {
            println!(
                "unused vertices: {} (in no triangle; carried along unchanged)",
                self.unused_vertices
            );
        }
        if self.surplus_frames_removed > 0 {
            println!(
                "removed {} frame files of an earlier run",
                self.surplus_frames_removed
            );
        }
    }
}

pub fn run(args: &Args) -> Result<()> {
    let start = Instant::now();
    let times = args.frames.times()?;
    let format = output::format_or_like(args.format, &args.source)?;
    let mut plan = Plan::new();
    plan.input(&args.source, "source mesh");
    plan.input(&args.target, "target mesh");
    let outputs = FrameOutputs::plan(&mut plan, &args.frames, &args.output, times.len(), format);
    let staging = plan.prepare()?;
    memory::check_reading(&[&args.source, &args.target])?;
    let source = output::read_mesh_2d(&args.source, "source mesh")?;
    let target = output::read_mesh_2d(&args.target, "target mesh")?;
    let context = || {
        format!(
            "interpolating `{}` to `{}`",
            args.source.display(),
            args.target.display()
        )
    };
    let mut report = animate(
        &source,
        &target,
        &args.frames,
        &times,
        &outputs,
        &staging,
        format,
        start,
    )
    .with_context(context)?;
    report.surplus_frames_removed = staging.commit()?;
    report.print(args.json);
    Ok(())
}

/// The files of an animation: one mesh per frame, and the pictures asked for.
pub struct FrameOutputs {
    dir: PathBuf,
    meshes: Vec<Output>,
    svgs: Vec<Output>,
    gif: Option<Output>,
    gltf: Option<Output>,
}

impl FrameOutputs {
    /// Adds the frames (and SVGs, GIF, GLB) of `count` frames in `dir` to `plan`.
    pub fn plan(
        plan: &mut Plan,
        args: &FrameArgs,
        dir: &Path,
        count: usize,
        format: meshmorph::io::Format,
    ) -> Self {
        Self {
            dir: dir.to_path_buf(),
            meshes: plan.frames(dir, count, format.extension()),
            svgs: if args.svg {
                plan.frames(dir, count, "svg")
            } else {
                Vec::new()
            },
            gif: args.gif.as_deref().map(|g| plan.file(g, "animation")),
            gltf: args.gltf.gltf.as_deref().map(|g| plan.file(g, "glTF file")),
        }
    }
}

/// Builds the interpolator, writes every frame (and the pictures asked for)
/// through `staging`, and reports. `start` is when the command began.
#[allow(clippy::too_many_arguments)]
pub fn animate(
    source: &Mesh2,
    target: &Mesh2,
    args: &FrameArgs,
    times: &[f64],
    outputs: &FrameOutputs,
    staging: &Staging,
    format: meshmorph::io::Format,
    start: Instant,
) -> Result<Report> {
    let dir = outputs.dir.as_path();
    args.gltf.check::<2>(
        source.num_vertices(),
        source.num_triangles(),
        times.len(),
        false,
    )?;
    memory::check_setup(source.num_triangles(), "the interpolation")?;
    let setup = Instant::now();
    let morph = Interpolator::new(source, target, &args.options())?;
    let setup_seconds = setup.elapsed().as_secs_f64();

    let bar = progress::bar(times.len() as u64, "frames");
    let keep = outputs.gif.is_some() || !outputs.svgs.is_empty() || outputs.gltf.is_some();
    if keep {
        memory::check_held(
            times.len(),
            morph.num_vertices() * std::mem::size_of::<[f64; 2]>(),
            "holding every frame for the pictures",
        )?;
    }
    let results: Vec<Result<Frame>> = times
        .par_iter()
        .enumerate()
        .map_init(
            || morph.workspace(),
            |ws, (k, &t)| {
                let begin = Instant::now();
                let mut positions = vec![[0.0; 2]; morph.num_vertices()];
                morph.at_into(t, &mut positions, ws);
                let compute = begin.elapsed().as_secs_f64();
                let flipped = morph.count_flipped(&positions);
                let begin = Instant::now();
                staging.write(outputs.meshes[k], |path| {
                    check_finite(&positions, k, t)?;
                    Ok(meshmorph::io::write_positions(
                        path,
                        &positions,
                        morph.triangles(),
                        format,
                    )?)
                })?;
                let write = begin.elapsed().as_secs_f64();
                bar.inc(1);
                Ok(Frame {
                    compute,
                    write,
                    flipped,
                    positions: keep.then_some(positions),
                })
            },
        )
        .collect();
    bar.finish_and_clear();
    let mut frames = results.into_iter().collect::<Result<Vec<_>>>()?;
    let (max_flipped_frame, max_flipped) = frames
        .iter()
        .enumerate()
        .map(|(k, f)| (k, f.flipped))
        .max_by_key(|&(k, f)| (f, std::cmp::Reverse(k)))
        .unwrap_or((0, 0));
    let mut files_written: Vec<PathBuf> = (0..times.len())
        .map(|k| crate::outputs::frame_path(dir, k, times.len(), format.extension()))
        .collect();
    let mut gltf = None;
    if keep {
        let positions: Vec<Vec<[f64; 2]>> = frames
            .iter_mut()
            .filter_map(|f| f.positions.take())
            .collect();
        files_written.extend(write_pictures(
            args,
            outputs,
            staging,
            &positions,
            morph.triangles(),
        )?);
        if let Some(output) = outputs.gltf {
            let names: Vec<String> = (0..times.len())
                .map(|k| {
                    let path = crate::outputs::frame_path(dir, k, times.len(), format.extension());
                    crate::gltf::mesh_name(&path)
                })
                .collect();
            let options = GltfOptions::default()
                .with_fps(args.fps)
                .with_name("interpolation");
            let base = GltfBase::new(source.positions(), source.triangles());
            staging.write(output, |path| {
                let mut staged = args.gltf.clone();
                staged.gltf = Some(path.to_path_buf());
                staged.write(&base, &positions, &names, &options)?;
                Ok(())
            })?;
            gltf = args.gltf.gltf.clone();
            files_written.extend(gltf.clone());
        }
    }
    let mut warnings = Vec::new();
    if max_flipped > 0 {
        warnings.push(format!(
            "frame {max_flipped_frame} has {max_flipped} triangles reversed relative to the source"
        ));
    }
    output::print_warnings(&warnings);
    let n = frames.len() as f64;
    Ok(Report {
        output: dir.to_path_buf(),
        frames_written: frames.len(),
        vertices: morph.num_vertices(),
        triangles: morph.triangles().len(),
        setup_seconds,
        seconds_per_frame: frames.iter().map(|f| f.compute).sum::<f64>() / n,
        write_seconds_per_frame: frames.iter().map(|f| f.write).sum::<f64>() / n,
        total_seconds: start.elapsed().as_secs_f64(),
        max_flipped_triangles: max_flipped,
        max_flipped_frame,
        gif: args.gif.clone(),
        gltf,
        files_written,
        warnings,
        surplus_frames_removed: 0,
        unused_vertices: source.num_unused_vertices(),
    })
}

/// Refuses a frame whose coordinates overflowed (inputs near the largest
/// representable number, or far extrapolation).
fn check_finite(positions: &[[f64; 2]], frame: usize, t: f64) -> Result<()> {
    if let Some(v) = positions
        .iter()
        .position(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        bail!(
            "frame {frame} (t = {t}): vertex {v} overflows (its coordinates exceed the range of floating-point numbers); scale the meshes down"
        );
    }
    Ok(())
}

/// The SVGs and the GIF asked for, of the frames' positions; returns the
/// files (as the user will find them).
fn write_pictures(
    args: &FrameArgs,
    outputs: &FrameOutputs,
    staging: &Staging,
    positions: &[Vec<[f64; 2]>],
    triangles: &[[u32; 3]],
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    if !outputs.svgs.is_empty() {
        pictures::write_svgs(staging, &outputs.svgs, positions, triangles, args.gif_width)?;
        written.extend(
            (0..positions.len())
                .map(|k| crate::outputs::frame_path(&outputs.dir, k, positions.len(), "svg")),
        );
    }
    if let (Some(output), Some(gif)) = (outputs.gif, &args.gif) {
        let gif_args = pictures::GifArgs {
            width: args.gif_width,
            height: args.gif_height,
            fps: args.fps,
            boomerang: !args.no_boomerang,
        };
        staging.write(output, |path| {
            pictures::write_gif(path, positions, triangles, &gif_args)
        })?;
        written.push(gif.clone());
    }
    Ok(written)
}

struct Frame {
    compute: f64,
    write: f64,
    flipped: usize,
    positions: Option<Vec<[f64; 2]>>,
}
