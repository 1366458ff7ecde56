//! `meshmorph interpolate`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use meshmorph::io::gltf::{GltfBase, GltfOptions};
use meshmorph::{Interpolator, InterpolatorOptions, Mesh2, Mesh3, Sequence3, StretchMode};
use rayon::prelude::*;
use serde::Serialize;

use crate::gltf::GltfArgs;
use crate::output::{self, positive_number, FormatArg};
use crate::pictures;
use crate::progress;

/// Interpolate through two or more meshes with the same triangles (keys), in
/// the plane or in space.
///
/// Writes DIR/frame_0000.obj, frame_0001.obj, ... and prints a report. Key i
/// is at time t = i; frames pass through every key in order.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The keys, in order (OBJ, OFF or PLY): the first at t = 0, the others
    /// at t = 1, 2, ...; every key has the first's vertices and triangles.
    #[arg(num_args = 2.., required = true, value_name = "KEY")]
    pub keys: Vec<PathBuf>,
    /// Planar (2) or in space (3) [default: 2 when every z of every key is 0].
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=3), value_name = "2|3")]
    pub dim: Option<u8>,
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
    /// Number of frames, t evenly from the first key (0) to the last (number
    /// of keys - 1) inclusive.
    #[arg(long, default_value_t = 30, value_name = "N")]
    pub frames: usize,
    /// Explicit times instead, comma-separated, written in this order (key i
    /// at t = i; values outside extrapolate), e.g. --t 0,0.5,1.5
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
    /// every triangle's rotation: the long way round (two planar keys only:
    /// in space there is no common axis to turn about).
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
    /// Go on when triangles are reversed between source and target (in
    /// space: turned over relative to their neighbours).
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
    /// The times asked for, over keys `0..=last`.
    fn times(&self, last: f64) -> Result<Vec<f64>> {
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
            n => Ok((0..n).map(|k| last * k as f64 / (n - 1) as f64).collect()),
        }
    }

    pub(crate) fn options(&self) -> InterpolatorOptions {
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
    /// 2 for planar meshes, 3 for meshes in space.
    pub dimension: usize,
    /// Number of keys.
    pub keys: usize,
    /// Triangles given whole turns by rotation consistency (beyond their
    /// principal rotation), summed over the segments between keys; `None`
    /// for two planar keys.
    pub triangles_with_whole_turns: Option<usize>,
    /// Building the interpolator: polar decompositions, factorization.
    pub setup_seconds: f64,
    /// Computing one frame on its thread, averaged over the frames (frames
    /// run in parallel, so this is not the throughput).
    pub seconds_per_frame: f64,
    /// Wall time of computing and writing all frames, divided by the number
    /// of frames: the throughput with `threads` threads.
    pub wall_seconds_per_frame: f64,
    /// Threads computing frames.
    pub threads: usize,
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
            "time per frame: {} on its thread (+ {} writing)",
            output::human_seconds(self.seconds_per_frame),
            output::human_seconds(self.write_seconds_per_frame)
        );
        println!(
            "throughput:     {} a frame, computed and written (wall time / frames, {} threads)",
            output::human_seconds(self.wall_seconds_per_frame),
            self.threads
        );
        if let Some(n) = self.triangles_with_whole_turns {
            println!("whole turns:    {n} triangles (rotation consistency)");
        }
        println!(
            "total:          {}",
            output::human_seconds(self.total_seconds)
        );
        let what = if self.dimension == 3 {
            "turned-over"
        } else {
            "flipped"
        };
        if self.max_flipped_triangles == 0 {
            println!("{what} triangles: none in any frame");
        } else {
            println!(
                "{what} triangles: at most {} (frame {})",
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
    let format = output::format_or_like(args.format, &args.keys[0])?;
    let mut keys: Vec<Mesh3> = Vec::with_capacity(args.keys.len());
    for (i, path) in args.keys.iter().enumerate() {
        let role = match (args.keys.len(), i) {
            (2, 0) => "source mesh".to_string(),
            (2, _) => "target mesh".to_string(),
            _ => format!("key {i}"),
        };
        let key = output::read_mesh(path, &role)?;
        if let Some(first) = keys.first() {
            first.check_same_connectivity(
                &key,
                [
                    &format!("the first key `{}`", args.keys[0].display()),
                    &format!("`{}`", path.display()),
                ],
            )?;
        }
        keys.push(key);
    }
    let planar = match args.dim {
        Some(2) => {
            for (key, path) in keys.iter().zip(&args.keys) {
                key.to_2d()
                    .with_context(|| format!("--dim 2: `{}` is not planar", path.display()))?;
            }
            true
        }
        Some(_) => false,
        None => keys
            .iter()
            .all(|k| k.positions().iter().all(|p| p[2] == 0.0)),
    };
    let context = || {
        let names: Vec<String> = args
            .keys
            .iter()
            .map(|p| format!("`{}`", p.display()))
            .collect();
        format!("interpolating {}", names.join(" to "))
    };
    let report = if planar && keys.len() == 2 {
        let source = keys[0].to_2d()?;
        let target = keys[1].to_2d()?;
        animate(&source, &target, &args.frames, &args.output, format, start)
    } else {
        animate_sequence(&keys, planar, &args.frames, &args.output, format, start).map_err(|e| {
            match e.downcast::<meshmorph::Error>() {
                Ok(e) => crate::blend::name_numbered(e, "key", &args.keys[1..]),
                Err(e) => e,
            }
        })
    }
    .with_context(context)?;
    report.print(args.json);
    Ok(())
}

/// Builds the interpolator of two planar keys, writes every frame (and the
/// pictures asked for), and reports. `start` is when the command began.
pub fn animate(
    source: &Mesh2,
    target: &Mesh2,
    args: &FrameArgs,
    dir: &Path,
    format: meshmorph::io::Format,
    start: Instant,
) -> Result<Report> {
    let times = args.times(1.0)?;
    args.gltf.check::<2>(
        source.num_vertices(),
        source.num_triangles(),
        times.len(),
        false,
    )?;
    let setup = Instant::now();
    let morph = Interpolator::new(source, target, &args.options())?;
    let setup_seconds = setup.elapsed().as_secs_f64();
    let run = Run {
        args,
        dir,
        format,
        start,
        times: &times,
        setup_seconds,
        keys: 2,
        whole_turns: None,
    };
    write_frames(&morph, source.positions(), &run)
}

/// The keyframe sequence through `keys` (planar: computed in space and
/// written in the plane), written and reported as [`animate`] does.
pub fn animate_sequence(
    keys: &[Mesh3],
    planar: bool,
    args: &FrameArgs,
    dir: &Path,
    format: meshmorph::io::Format,
    start: Instant,
) -> Result<Report> {
    if args.turns != 0 {
        bail!("--turns applies to two planar keys only (in space there is no common axis, and a sequence's turns come from its keys)");
    }
    if !planar && args.svg {
        bail!("--svg draws planar frames only: use --gif or --gltf for meshes in space");
    }
    let times = args.times((keys.len() - 1) as f64)?;
    let (vertices, triangles) = (keys[0].num_vertices(), keys[0].num_triangles());
    if planar {
        args.gltf
            .check::<2>(vertices, triangles, times.len(), false)?;
    } else {
        args.gltf
            .check::<3>(vertices, triangles, times.len(), false)?;
    }
    let setup = Instant::now();
    let morph = Sequence3::new(keys, &args.options())?;
    let setup_seconds = setup.elapsed().as_secs_f64();
    let whole_turns = Some(morph.triangles_with_whole_turns().iter().sum());
    let run = Run {
        args,
        dir,
        format,
        start,
        times: &times,
        setup_seconds,
        keys: keys.len(),
        whole_turns,
    };
    if planar {
        let base: Vec<[f64; 2]> = keys[0].positions().iter().map(|p| [p[0], p[1]]).collect();
        write_frames(&Planar(morph), &base, &run)
    } else {
        write_frames(&morph, keys[0].positions(), &run)
    }
}

/// What [`write_frames`] needs of an interpolation of `D`-dimensional meshes.
trait Frames<const D: usize>: Sync {
    type Workspace: Send;
    fn workspace(&self) -> Self::Workspace;
    fn num_vertices(&self) -> usize;
    fn triangles(&self) -> &[[u32; 3]];
    fn frame_into(&self, t: f64, out: &mut [[f64; D]], ws: &mut Self::Workspace);
    fn count_flipped(&self, positions: &[[f64; D]]) -> usize;
}

impl Frames<2> for Interpolator {
    type Workspace = meshmorph::interpolate::FrameWorkspace;
    fn workspace(&self) -> Self::Workspace {
        Interpolator::workspace(self)
    }
    fn num_vertices(&self) -> usize {
        Interpolator::num_vertices(self)
    }
    fn triangles(&self) -> &[[u32; 3]] {
        Interpolator::triangles(self)
    }
    fn frame_into(&self, t: f64, out: &mut [[f64; 2]], ws: &mut Self::Workspace) {
        self.at_into(t, out, ws)
    }
    fn count_flipped(&self, positions: &[[f64; 2]]) -> usize {
        Interpolator::count_flipped(self, positions)
    }
}

impl Frames<3> for Sequence3 {
    type Workspace = meshmorph::sequence3::SequenceWorkspace;
    fn workspace(&self) -> Self::Workspace {
        Sequence3::workspace(self)
    }
    fn num_vertices(&self) -> usize {
        Sequence3::num_vertices(self)
    }
    fn triangles(&self) -> &[[u32; 3]] {
        Sequence3::triangles(self)
    }
    fn frame_into(&self, t: f64, out: &mut [[f64; 3]], ws: &mut Self::Workspace) {
        self.at_into(t, out, ws)
    }
    fn count_flipped(&self, positions: &[[f64; 3]]) -> usize {
        self.count_turned_over(positions)
    }
}

/// A sequence of planar keys, computed in space (z stays 0) and written in
/// the plane.
struct Planar(Sequence3);

impl Frames<2> for Planar {
    type Workspace = (meshmorph::sequence3::SequenceWorkspace, Vec<[f64; 3]>);
    fn workspace(&self) -> Self::Workspace {
        (self.0.workspace(), vec![[0.0; 3]; self.0.num_vertices()])
    }
    fn num_vertices(&self) -> usize {
        self.0.num_vertices()
    }
    fn triangles(&self) -> &[[u32; 3]] {
        self.0.triangles()
    }
    fn frame_into(&self, t: f64, out: &mut [[f64; 2]], ws: &mut Self::Workspace) {
        self.0.at_into(t, &mut ws.1, &mut ws.0);
        for (o, p) in out.iter_mut().zip(&ws.1) {
            *o = [p[0], p[1]];
        }
    }
    fn count_flipped(&self, positions: &[[f64; 2]]) -> usize {
        let p: Vec<[f64; 3]> = positions.iter().map(|q| [q[0], q[1], 0.0]).collect();
        self.0.count_turned_over(&p)
    }
}

/// What one run of [`write_frames`] is asked to do.
struct Run<'a> {
    args: &'a FrameArgs,
    dir: &'a Path,
    format: meshmorph::io::Format,
    start: Instant,
    times: &'a [f64],
    setup_seconds: f64,
    keys: usize,
    whole_turns: Option<usize>,
}

/// Writes every frame (and the pictures asked for) and reports.
fn write_frames<const D: usize, M: Frames<D>>(
    morph: &M,
    base: &[[f64; D]],
    run: &Run<'_>,
) -> Result<Report> {
    let Run {
        args,
        dir,
        format,
        start,
        times,
        setup_seconds,
        ..
    } = *run;
    output::make_dir(dir)?;

    let bar = progress::bar(times.len() as u64, "frames");
    let wall = Instant::now();
    let keep = args.gif.is_some() || args.svg || args.gltf.gltf.is_some();
    let results: Vec<Result<Frame<D>>> = times
        .par_iter()
        .enumerate()
        .map_init(
            || morph.workspace(),
            |ws, (k, &t)| {
                let begin = Instant::now();
                let mut positions = vec![[0.0; D]; morph.num_vertices()];
                morph.frame_into(t, &mut positions, ws);
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
    let wall_seconds = wall.elapsed().as_secs_f64();
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
        let positions: Vec<Vec<[f64; D]>> = frames
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
        let base = GltfBase::new(base, morph.triangles());
        gltf = args
            .gltf
            .write(&base, &positions, &names, &options)
            .map_err(remove_frames)?;
        files_written.extend(gltf.clone());
    }
    let mut warnings = Vec::new();
    if max_flipped > 0 {
        let what = if D == 3 { "turned over" } else { "reversed" };
        warnings.push(format!(
            "frame {max_flipped_frame} has {max_flipped} triangles {what} relative to the source"
        ));
    }
    output::print_warnings(&warnings);
    let n = frames.len() as f64;
    Ok(Report {
        output: dir.to_path_buf(),
        frames_written: frames.len(),
        vertices: morph.num_vertices(),
        triangles: morph.triangles().len(),
        dimension: D,
        keys: run.keys,
        triangles_with_whole_turns: run.whole_turns,
        setup_seconds,
        seconds_per_frame: frames.iter().map(|f| f.compute).sum::<f64>() / n,
        wall_seconds_per_frame: wall_seconds / n,
        threads: rayon::current_num_threads(),
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
fn write_pictures<const D: usize>(
    args: &FrameArgs,
    dir: &Path,
    positions: &[Vec<[f64; D]>],
    triangles: &[[u32; 3]],
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let gif_args = pictures::GifArgs {
        width: args.gif_width,
        height: args.gif_height,
        fps: args.fps,
        boomerang: !args.no_boomerang,
    };
    if D == 3 {
        if let Some(gif) = &args.gif {
            let frames: Vec<Vec<[f64; 3]>> = positions
                .iter()
                .map(|f| f.iter().map(|p| [p[0], p[1], p[2]]).collect())
                .collect();
            pictures::write_gif_3d(gif, &frames, triangles, &gif_args)?;
            written.push(gif.clone());
        }
        return Ok(written);
    }
    let positions: Vec<Vec<[f64; 2]>> = positions
        .iter()
        .map(|f| f.iter().map(|p| [p[0], p[1]]).collect())
        .collect();
    let positions = positions.as_slice();
    if args.svg {
        let paths: Vec<PathBuf> = (0..positions.len())
            .map(|k| output::frame_path(dir, k, positions.len(), "svg"))
            .collect();
        pictures::write_svgs(&paths, positions, triangles, args.gif_width)?;
        written.extend(paths);
    }
    if let Some(gif) = &args.gif {
        pictures::write_gif(gif, positions, triangles, &gif_args)?;
        written.push(gif.clone());
    }
    Ok(written)
}

struct Frame<const D: usize> {
    compute: f64,
    write: f64,
    flipped: usize,
    positions: Option<Vec<[f64; D]>>,
}
