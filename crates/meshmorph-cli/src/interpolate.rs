//! `meshmorph interpolate`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use meshmorph::io::gltf::{GltfBase, GltfOptions};
use meshmorph::{Interpolator, InterpolatorOptions, Mesh2, StretchMode};
use rayon::prelude::*;
use serde::Serialize;

use crate::gltf::GltfArgs;
use crate::output::{self, positive_number, FormatArg};
use crate::pictures;
use crate::progress;

/// Interpolate between two planar meshes with the same triangles.
///
/// Writes DIR/frame_0000.obj, frame_0001.obj, ... and prints a report.
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
    /// Number of frames, t evenly from 0 to 1 inclusive.
    #[arg(long, default_value_t = 30, value_name = "N")]
    pub frames: usize,
    /// Explicit times instead, comma-separated, written in this order
    /// (values outside [0, 1] extrapolate), e.g. --t 0,0.5,1.5
    #[arg(
        long = "t",
        value_delimiter = ',',
        allow_negative_numbers = true,
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

/// `--stretch` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Stretch {
    /// (1-t) I + t S.
    Linear,
    /// S^t.
    Log,
}

impl FrameArgs {
    fn times(&self) -> Result<Vec<f64>> {
        if let Some(t) = &self.times {
            if t.is_empty() {
                bail!("--t needs at least one time");
            }
            if let Some(x) = t.iter().find(|x| !x.is_finite()) {
                bail!("--t: {x} is not a finite number");
            }
            return Ok(t.clone());
        }
        match self.frames {
            0 => bail!("--frames must be at least 1"),
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
    }
}

pub fn run(args: &Args) -> Result<()> {
    let start = Instant::now();
    let source = output::read_mesh_2d(&args.source, "source mesh")?;
    let target = output::read_mesh_2d(&args.target, "target mesh")?;
    let format = output::format_or_like(args.format, &args.source)?;
    let context = || {
        format!(
            "interpolating `{}` to `{}`",
            args.source.display(),
            args.target.display()
        )
    };
    let report = animate(&source, &target, &args.frames, &args.output, format, start)
        .with_context(context)?;
    report.print(args.json);
    Ok(())
}

/// Builds the interpolator, writes every frame (and the pictures asked for),
/// and reports. `start` is when the command began.
pub fn animate(
    source: &Mesh2,
    target: &Mesh2,
    args: &FrameArgs,
    dir: &Path,
    format: meshmorph::io::Format,
    start: Instant,
) -> Result<Report> {
    let times = args.times()?;
    args.gltf.check(
        source.num_vertices(),
        source.num_triangles(),
        times.len(),
        false,
    )?;
    let setup = Instant::now();
    let morph = Interpolator::new(source, target, &args.options())?;
    let setup_seconds = setup.elapsed().as_secs_f64();
    output::make_dir(dir)?;

    let bar = progress::bar(times.len() as u64, "frames");
    let keep = args.gif.is_some() || args.svg || args.gltf.gltf.is_some();
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
                let path = output::frame_path(dir, k, times.len(), format.extension());
                meshmorph::io::write_positions(&path, &positions, morph.triangles(), format)
                    .with_context(|| format!("writing `{}`", path.display()))?;
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
    // A run that fails once writing has begun (a frame that cannot be
    // written, an SVG or GIF path that cannot be) removes the frames and
    // SVGs it names, so that it leaves no partial animation behind.
    let remove_frames = |e: anyhow::Error| {
        for k in 0..times.len() {
            let _ =
                std::fs::remove_file(output::frame_path(dir, k, times.len(), format.extension()));
            if args.svg {
                let _ = std::fs::remove_file(output::frame_path(dir, k, times.len(), "svg"));
            }
        }
        if let Some(gif) = &args.gif {
            let _ = std::fs::remove_file(gif);
        }
        e
    };
    let mut frames = results
        .into_iter()
        .collect::<Result<Vec<_>>>()
        .map_err(remove_frames)?;
    let (max_flipped_frame, max_flipped) = frames
        .iter()
        .enumerate()
        .map(|(k, f)| (k, f.flipped))
        .max_by_key(|&(k, f)| (f, std::cmp::Reverse(k)))
        .unwrap_or((0, 0));
    let mut files_written: Vec<PathBuf> = (0..times.len())
        .map(|k| output::frame_path(dir, k, times.len(), format.extension()))
        .collect();
    let mut gltf = None;
    if keep {
        let positions: Vec<Vec<[f64; 2]>> = frames
            .iter_mut()
            .filter_map(|f| f.positions.take())
            .collect();
        files_written.extend(
            write_pictures(args, dir, &positions, morph.triangles()).map_err(remove_frames)?,
        );
        let names: Vec<String> = (0..times.len())
            .map(|k| {
                let path = output::frame_path(dir, k, times.len(), format.extension());
                crate::gltf::mesh_name(&path)
            })
            .collect();
        let options = GltfOptions::default()
            .with_fps(args.fps)
            .with_name("interpolation");
        let base = GltfBase::new(source.positions(), source.triangles());
        gltf = args
            .gltf
            .write(&base, &positions, &names, &options)
            .map_err(remove_frames)?;
        files_written.extend(gltf.clone());
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
    })
}

/// The SVGs and the GIF asked for, of the frames' positions; returns the
/// files written.
fn write_pictures(
    args: &FrameArgs,
    dir: &Path,
    positions: &[Vec<[f64; 2]>],
    triangles: &[[u32; 3]],
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    if args.svg {
        let paths: Vec<PathBuf> = (0..positions.len())
            .map(|k| output::frame_path(dir, k, positions.len(), "svg"))
            .collect();
        pictures::write_svgs(&paths, positions, triangles, args.gif_width)?;
        written.extend(paths);
    }
    if let Some(gif) = &args.gif {
        let gif_args = pictures::GifArgs {
            width: args.gif_width,
            height: args.gif_height,
            fps: args.fps,
            boomerang: !args.no_boomerang,
        };
        pictures::write_gif(gif, positions, triangles, &gif_args)?;
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
