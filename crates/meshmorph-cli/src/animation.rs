//! Writing an animation: every frame of an interpolation (planar or in
//! space, two keys or more) through the run's staging, the pictures asked
//! for, and the report.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Result};
use meshmorph::io::gltf::{write_glb_frames, GltfOptions};
use meshmorph::io::Appearance;
use meshmorph::io::Format;

use crate::output::WeldedFile;
use meshmorph::{Dimension, FrameSource, Sequence, Space};
use rayon::prelude::*;
use serde::Serialize;

use crate::interpolate::FrameArgs;
use crate::kept_frames::KeptFrames;
use crate::output;
use crate::outputs::{Output, Plan, Staging};
use crate::pictures;
use crate::progress;

/// The files of an animation: one mesh per frame, and the pictures asked for.
pub struct FrameOutputs {
    dir: PathBuf,
    count: usize,
    format: Format,
    /// The frame files' extension: the mesh format's, or a drawing's
    /// (`svg`, `txt`).
    ext: &'static str,
    meshes: Vec<Output>,
    svgs: Vec<Output>,
    gif: Option<Output>,
    png: Option<Output>,
    gltf: Option<Output>,
}

impl FrameOutputs {
    /// Whether an output shows the meshes' insides (frames written as
    /// meshes, their SVG pictures, the GIF, the PNG, the GLB), not only
    /// their outlines (a drawing's SVG or text frames).
    pub fn shows_inside(&self) -> bool {
        let mesh_frames = !self.meshes.is_empty() && !matches!(self.ext, "svg" | "txt");
        mesh_frames
            || !self.svgs.is_empty()
            || self.gif.is_some()
            || self.png.is_some()
            || self.gltf.is_some()
    }

    /// Adds the frames (and SVGs, GIF, PNG, GLB) of `count` frames in `dir`
    /// to `plan`.
    pub fn plan(
        plan: &mut Plan,
        args: &FrameArgs,
        dir: &Path,
        count: usize,
        format: Format,
    ) -> Self {
        Self::plan_as(plan, args, dir, count, format, format.extension())
    }

    /// [`FrameOutputs::plan`] for frames written as `ext` files (a
    /// drawing's outline, by [`Run::outline`]); `format` for the GLB's and
    /// pictures' sake only.
    pub fn plan_as(
        plan: &mut Plan,
        args: &FrameArgs,
        dir: &Path,
        count: usize,
        format: Format,
        ext: &'static str,
    ) -> Self {
        Self {
            dir: dir.to_path_buf(),
            count,
            format,
            ext,
            meshes: plan.frames(dir, count, ext),
            svgs: if args.svg {
                plan.frames(dir, count, "svg")
            } else {
                Vec::new()
            },
            gif: args
                .pictures
                .gif
                .as_deref()
                .map(|g| plan.file(g, "animation")),
            png: args
                .pictures
                .png
                .as_deref()
                .map(|g| plan.file(g, "picture")),
            gltf: args.gltf.gltf.as_deref().map(|g| plan.file(g, "glTF file")),
        }
    }

    /// The frame files' extension.
    pub fn ext(&self) -> &'static str {
        self.ext
    }

    /// Where frame `k`'s mesh goes.
    fn mesh_path(&self, k: usize) -> PathBuf {
        crate::outputs::frame_path(&self.dir, k, self.count, self.ext)
    }
}

/// What the frames are: how many keys, how the setup went.
pub struct Setup {
    /// Number of keys (2 for an interpolation between two meshes).
    pub keys: usize,
    /// Seconds spent building the interpolation.
    pub seconds: f64,
    /// Triangles given whole turns by rotation consistency, summed over
    /// the segments (keyframe sequences only).
    pub whole_turns: Option<usize>,
    /// Vertices in no triangle.
    pub unused_vertices: usize,
    /// Copies of vertices at seams, welded for the solve.
    pub welded_vertices: usize,
    /// Separate parts placed by the surface they sit in.
    pub parts_following_host: usize,
}

/// What a run did, for people and (with --json) for programs.
#[derive(Debug, Serialize)]
pub struct Report {
    /// Where the frames went.
    #[serde(serialize_with = "output::lossy")]
    pub output: PathBuf,
    /// Number of frame files written.
    pub frames_written: usize,
    /// Vertices of the mesh.
    pub vertices: usize,
    /// Triangles of the mesh.
    pub triangles: usize,
    /// 2 for planar meshes, 3 for meshes in space.
    pub dimension: usize,
    /// Number of keys.
    pub keys: usize,
    /// Triangles given whole turns by rotation consistency (beyond their
    /// principal rotation), summed over the segments between keys; absent
    /// for two planar keys.
    pub triangles_with_whole_turns: Option<usize>,
    /// Building the interpolator: decompositions, factorization.
    pub setup_seconds: f64,
    /// Time per frame: the computing time of a frame on one thread (each
    /// thread solves its frames up to [`meshmorph::limits::FRAMES_PER_SOLVE`] at a
    /// time, one substitution for them, and counts each its share),
    /// averaged over the frames. Frames run in parallel, so this is not the
    /// throughput.
    pub seconds_per_frame: f64,
    /// Throughput: the wall time of computing and writing all frames,
    /// divided by the number of frames (with `threads` threads).
    pub throughput_seconds_per_frame: f64,
    /// Threads computing frames.
    pub threads: usize,
    /// Writing one frame's files, averaged.
    pub write_seconds_per_frame: f64,
    /// Wall time of the whole command.
    pub total_seconds: f64,
    /// The largest number of triangles reversed (planar) or turned over (in
    /// space) relative to the first key in any frame.
    pub max_flipped_triangles: usize,
    /// The first frame (index, from 0) where that happened; null when no
    /// frame has such triangles.
    pub max_flipped_frame: Option<usize>,
    /// Whether an output shows the triangles: false for a drawing morph
    /// written as outlines only (its SVG or text frames, animated SVG,
    /// Lottie), whose inside is not mended, and where triangles turned over
    /// inside are in no output.
    pub inside_shown: bool,
    /// The GIF written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub gif: Option<PathBuf>,
    /// The PNG written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub png: Option<PathBuf>,
    /// The GLB written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub gltf: Option<PathBuf>,
    /// Every file written, in order.
    #[serde(serialize_with = "output::lossy")]
    pub files_written: Vec<PathBuf>,
    /// The warnings given (also printed on stderr).
    pub warnings: Vec<String>,
    /// Frame files of an earlier run removed from the output folder.
    pub surplus_frames_removed: usize,
    /// Vertices no triangle uses: they move on straight lines between
    /// their positions in the keys and count in no scale.
    pub unused_vertices: usize,
    /// Vertices at the same place as another in every key (copies at
    /// seams), welded for the solve; the frames keep them.
    pub welded_vertices: usize,
    /// Separate parts (eyes, teeth) that keep their place in the part
    /// around them and turn with it between keys, rather than moving their
    /// centroids on straight lines.
    pub parts_following_host: usize,
    /// When the keys were drawings: how they were read and made
    /// compatible, and the files written from them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drawings: Option<crate::drawings::DrawingsReport>,
}

impl Report {
    pub fn print(&self, json: bool) {
        if json {
            output::print_json(self);
            return;
        }
        let space = if self.dimension == 3 {
            "in space"
        } else {
            "planar"
        };
        say!(
            "wrote {} ({}, {}, {space}, {}) to {}",
            output::count(self.frames_written, "frame"),
            output::vertices(self.vertices),
            output::count(self.triangles, "triangle"),
            output::count(self.keys, "key"),
            self.output.display()
        );
        say!(
            "setup:          {}",
            output::human_seconds(self.setup_seconds)
        );
        say!(
            "time per frame: {} (computing, on one thread; + {} writing)",
            output::human_seconds(self.seconds_per_frame),
            output::human_seconds(self.write_seconds_per_frame)
        );
        say!(
            "throughput:     {} a frame (wall time of all frames / frames, {} threads)",
            output::human_seconds(self.throughput_seconds_per_frame),
            self.threads
        );
        if let Some(n) = self.triangles_with_whole_turns {
            say!(
                "whole turns:    {} (rotation consistency)",
                output::count(n, "triangle")
            );
        }
        say!(
            "total:          {}",
            output::human_seconds(self.total_seconds)
        );
        let what = if self.dimension == 3 {
            "turned-over"
        } else {
            "flipped"
        };
        match self.max_flipped_frame {
            Some(frame) if !self.inside_shown => say!(
                "{what} triangles: none in the outputs, which show the outline (inside, at most {} in frame {frame}, not mended)",
                self.max_flipped_triangles
            ),
            Some(frame) => say!(
                "{what} triangles: at most {} (frame {frame})",
                self.max_flipped_triangles
            ),
            None => say!("{what} triangles: none in any frame"),
        }
        output::print_files(
            &[
                ("animation:", self.gif.as_deref()),
                ("picture:", self.png.as_deref()),
                ("glTF:", self.gltf.as_deref()),
            ],
            11,
        );
        if self.unused_vertices > 0 {
            say!(
                "unused vertices: {} (in no triangle; carried along unchanged)",
                self.unused_vertices
            );
        }
        if let Some(line) = crate::output::welded_line(self.welded_vertices) {
            say!("welded:   {line}");
        }
        if let Some(line) = crate::output::following_line(self.parts_following_host) {
            say!("parts:    {line}");
        }
        if let Some(d) = &self.drawings {
            d.print();
        }
        if self.surplus_frames_removed > 0 {
            say!(
                "removed {} of an earlier run",
                output::count(self.surplus_frames_removed, "frame file")
            );
        }
    }
}

/// What one run asks for: the frame options, the times, where the files
/// go, and when the command began.
pub struct Run<'a> {
    pub args: &'a FrameArgs,
    pub times: &'a [f64],
    pub outputs: &'a FrameOutputs,
    pub staging: &'a Staging,
    pub start: Instant,
    /// The first key's file: each frame is written as that file with new
    /// positions (in its format; in another, what that format holds).
    pub file: Option<&'a WeldedFile>,
    /// Warnings of reading the keys, reported with the run's.
    pub read_warnings: &'a [String],
    /// The bytes the GLB's textures may take (see
    /// [`GltfArgs::check`](crate::gltf::GltfArgs::check)).
    pub image_budget: u64,
    /// The keys' names (their files' stems), for the captions of the PNG.
    pub key_names: &'a [String],
    /// Writes each planar frame itself (a drawing's outline) instead of
    /// as a mesh.
    pub outline: Option<&'a dyn WriteFrame>,
    /// The keys' y axis points down (SVG drawings): the pictures (`--png`,
    /// `--gif`, `--svg`) are drawn with it down, as the drawings show.
    pub y_down: bool,
    /// Whether an output shows the triangles (see
    /// [`Report::inside_shown`]): else triangles turned over inside are
    /// reported as such, without a warning.
    pub inside_shown: bool,
}

/// A frame written otherwise than as a mesh: a drawing's outline.
pub trait WriteFrame: Sync {
    /// Writes the frame whose vertices are at `positions` into `w`.
    fn write(&self, w: &mut dyn std::io::Write, positions: &[[f64; 2]]) -> std::io::Result<()>;
}

/// Writes every frame of `morph` at the run's times (and the pictures
/// asked for) through its staging, and reports. `base` is the first key
/// (the glTF base mesh). The frames are `kept` where they were computed
/// already, else computed as they are written.
pub fn write_frames<const D: usize>(
    morph: &Sequence<D>,
    base: &[[f64; D]],
    run: &Run<'_>,
    setup: &Setup,
    kept: Option<&KeptFrames<D>>,
) -> Result<Report>
where
    Space<D>: Dimension<D>,
{
    let Run {
        args,
        times,
        outputs,
        staging,
        start,
        file,
        read_warnings,
        image_budget,
        key_names: _,
        outline,
        y_down,
        inside_shown,
    } = *run;
    crate::memory::check_frames_in_flight(
        morph.num_vertices(),
        D,
        rayon::current_num_threads(),
        times.len(),
    )?;
    let bar = progress::bar(times.len() as u64, "frames");
    let wall = Instant::now();
    // Frame `k` at time `t`, computed in `compute` seconds: checked, written.
    let write_frame = |k: usize, t: f64, positions: &[[f64; D]], compute: f64| -> Result<Frame> {
        let flipped = morph.count_turned_over(positions);
        let begin = Instant::now();
        let mut dropped = Vec::new();
        staging.write_to(outputs.meshes[k], |path, w| {
            check_finite(positions, k, t, morph.num_keys() - 1)?;
            match (outline, file) {
                (Some(outline), _) => {
                    let planar: Vec<[f64; 2]> = positions.iter().map(|p| [p[0], p[1]]).collect();
                    outline.write(w, &planar)?;
                }
                (None, Some(file)) => {
                    let lifted: Vec<[f64; 3]> = positions
                        .iter()
                        .map(|p| std::array::from_fn(|i| if i < D { p[i] } else { 0.0 }))
                        .collect();
                    dropped = file.write_to(w, path, &lifted, outputs.format)?;
                }
                (None, None) => meshmorph::io::write_positions_to(
                    w,
                    path,
                    positions,
                    morph.triangles(),
                    outputs.format,
                )?,
            }
            Ok(())
        })?;
        let write = begin.elapsed().as_secs_f64();
        bar.inc(1);
        Ok(Frame {
            compute,
            write,
            flipped,
            dropped,
        })
    };
    // Frames `first..` at `chunk_times`, each computed in `compute` seconds:
    // written, and what they come to summed as they go (a million frames
    // keep no list of their own).
    let write_chunk = |first: usize, chunk_times: &[f64], solved: &[&[[f64; D]]], compute: f64| {
        solved.iter().zip(chunk_times).enumerate().fold(
            Frames::default(),
            |frames, (i, (positions, &t))| {
                let k = first + i;
                frames.merge(Frames::one(k, write_frame(k, t, positions, compute)))
            },
        )
    };
    let frames = match kept {
        // Read where they are kept, in chunks as they would be solved.
        Some(kept) => {
            let together = meshmorph::limits::frames_per_solve(times.len());
            times
                .par_chunks(together)
                .enumerate()
                .map(|(chunk, chunk_times)| {
                    let first = chunk * together;
                    let solved: Vec<&[[f64; D]]> = (first..first + chunk_times.len())
                        .map(|k| kept.frame(k))
                        .collect();
                    write_chunk(first, chunk_times, &solved, kept.seconds_per_frame())
                })
                .reduce(Frames::default, Frames::merge)
        }
        // Each thread solves a few frames together (one substitution for
        // all), then writes them.
        None => crate::frame_chunks::solve(
            morph,
            times,
            Frames::default,
            |first, chunk_times, computed, compute| {
                let solved: Vec<&[[f64; D]]> = computed.iter().map(Vec::as_slice).collect();
                write_chunk(first, chunk_times, &solved, compute)
            },
            Frames::merge,
        ),
    };
    // (The frames kept were computed before: their time counts too.)
    let wall_seconds = wall.elapsed().as_secs_f64() + kept.map_or(0.0, KeptFrames::wall_seconds);
    bar.finish_and_clear();
    if let Some((_, e)) = frames.error {
        return Err(e);
    }
    let (max_flipped, max_flipped_frame) = frames.most_flipped;
    let mut files_written: Vec<PathBuf> = (0..times.len()).map(|k| outputs.mesh_path(k)).collect();
    // Pictures and the GLB recompute the frames they draw or write (or
    // read them where they are kept).
    let recomputed = Recomputed {
        morph,
        times,
        y_down: false,
        kept,
    };
    files_written.extend(write_pictures(
        args,
        outputs,
        staging,
        &Recomputed {
            y_down,
            ..recomputed
        },
        (morph.triangles(), run.key_names),
    )?);
    // The first key's looks for the GLB, when it comes from a file.
    let look = match (outputs.gltf, file) {
        (Some(_), Some(file)) => Appearance::of_file(&file.file, image_budget)?,
        _ => Appearance::default(),
    };
    if let Some(output) = outputs.gltf {
        let names: Vec<String> = (0..times.len())
            .map(|k| crate::gltf::mesh_name(&outputs.mesh_path(k)))
            .collect();
        // Named after the first key's file, as a transfer's after the
        // target's; keys made in memory have none.
        let name = file.map_or_else(
            || "interpolation".to_string(),
            |f| crate::gltf::mesh_name(f.file.path()),
        );
        let options = args.gltf.options(
            GltfOptions::default()
                .with_fps(args.pictures.draw.fps)
                .with_name(name),
        );
        let base = look.base(base, morph.triangles());
        staging.write(output, |path| {
            let counted = crate::progress::Counted::new(&recomputed, "glTF");
            Ok(write_glb_frames(path, &base, &counted, &names, &options)?)
        })?;
        files_written.extend(args.gltf.gltf.clone());
    }
    let mut warnings = read_warnings.to_vec();
    warnings.extend(output::gif_rate_warning(
        args.pictures.gif.is_some(),
        args.pictures.draw.fps,
    ));
    if args.gltf.gltf.is_some() {
        warnings.extend(look.warnings.iter().cloned());
    }
    // What the output format cannot hold of the first key's file is the
    // same for every frame: said once, for the first.
    warnings.extend(output::dropped_for(&outputs.dir, &frames.dropped));
    if max_flipped > 0 && inside_shown {
        let what = if D == 3 { "turned over" } else { "reversed" };
        warnings.push(format!(
            "frame {max_flipped_frame} has {} {what} relative to the first key",
            output::count(max_flipped, "triangle")
        ));
    }
    output::print_warnings(&warnings);
    let n = times.len() as f64;
    Ok(Report {
        output: outputs.dir.clone(),
        frames_written: times.len(),
        vertices: morph.num_vertices() + setup.welded_vertices,
        triangles: morph.triangles().len(),
        dimension: D,
        keys: setup.keys,
        triangles_with_whole_turns: setup.whole_turns,
        setup_seconds: setup.seconds,
        seconds_per_frame: frames.compute / n,
        throughput_seconds_per_frame: wall_seconds / n,
        threads: rayon::current_num_threads(),
        write_seconds_per_frame: frames.write / n,
        total_seconds: start.elapsed().as_secs_f64(),
        max_flipped_triangles: max_flipped,
        max_flipped_frame: (max_flipped > 0).then_some(max_flipped_frame),
        inside_shown,
        gif: args.pictures.gif.clone(),
        png: args.pictures.png.clone(),
        gltf: args.gltf.gltf.clone(),
        files_written,
        warnings,
        surplus_frames_removed: 0,
        unused_vertices: setup.unused_vertices,
        welded_vertices: setup.welded_vertices,
        parts_following_host: setup.parts_following_host,
        drawings: None,
    })
}

/// Refuses a frame at time `t` (keys at `0..=last`) with a coordinate
/// that overflowed: far outside the keys the times are the cause, else the
/// meshes' size.
fn check_finite<const D: usize>(
    positions: &[[f64; D]],
    frame: usize,
    t: f64,
    last: usize,
) -> Result<()> {
    if let Some(v) = positions
        .iter()
        .position(|p| !p.iter().all(|x| x.is_finite()))
    {
        let advice = if (0.0..=last as f64).contains(&t) {
            "scale the meshes down".to_string()
        } else {
            format!("extrapolate less far: use times nearer the keys' (0 to {last})")
        };
        bail!(
            "frame {frame} (t = {}): vertex {v} overflows (its coordinates exceed the range of floating-point numbers); {advice}",
            compact(t)
        );
    }
    Ok(())
}

/// `t` as written by hand: `0.25`, or `1e308` rather than 309 digits.
fn compact(t: f64) -> String {
    if t != 0.0 && !(1e-4..1e6).contains(&t.abs()) {
        format!("{t:e}")
    } else {
        t.to_string()
    }
}

/// The frames of an interpolation at `times`, recomputed (one
/// back-substitution each) whenever a writer of pictures or of the GLB
/// asks: memory for frames stays that of the few being drawn or written.
/// Where they are `kept`, read from there instead.
pub struct Recomputed<'a, const D: usize>
where
    Space<D>: Dimension<D>,
{
    pub morph: &'a Sequence<D>,
    pub times: &'a [f64],
    /// Each frame's second coordinate negated: a drawing whose y points
    /// down, handed to the pictures, which take y as pointing up.
    pub y_down: bool,
    /// The frames, where they were computed once already (mended frames
    /// of drawings): read from there instead.
    pub kept: Option<&'a KeptFrames<D>>,
}

impl<const D: usize> FrameSource<D> for Recomputed<'_, D>
where
    Space<D>: Dimension<D>,
{
    fn num_frames(&self) -> usize {
        self.times.len()
    }

    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; D]])) {
        let mut positions = match self.kept {
            Some(kept) if !self.y_down => return use_frame(kept.frame(k)),
            Some(kept) => kept.frame(k).to_vec(),
            None => {
                let mut positions = vec![[0.0; D]; self.morph.num_vertices()];
                self.morph
                    .at_into(self.times[k], &mut positions, &mut self.morph.workspace());
                positions
            }
        };
        if self.y_down {
            for p in &mut positions {
                p[1] = -p[1];
            }
        }
        use_frame(&positions)
    }
}

/// The SVGs, GIF and PNG asked for, of the frames (at the times of
/// `frames`, through keys named `key_names`); returns the files (as the
/// user will find them).
fn write_pictures<const D: usize>(
    args: &FrameArgs,
    outputs: &FrameOutputs,
    staging: &Staging,
    frames: &Recomputed<'_, D>,
    (triangles, key_names): (&[[u32; 3]], &[String]),
) -> Result<Vec<PathBuf>>
where
    Space<D>: Dimension<D>,
{
    let mut written = Vec::new();
    let draw = &args.pictures.draw;
    let count = frames.num_frames();
    if !outputs.svgs.is_empty() {
        if D != 2 {
            bail!("--svg draws planar frames only: use --gif, --png or --gltf for meshes in space");
        }
        let planar = pictures::InDim(frames);
        pictures::write_svgs(staging, &outputs.svgs, &planar, triangles, draw.size)?;
        written
            .extend((0..count).map(|k| crate::outputs::frame_path(&outputs.dir, k, count, "svg")));
    }
    if let (Some(output), Some(gif)) = (outputs.gif, &args.pictures.gif) {
        staging.write(output, |path| {
            pictures::write_gif(path, frames, triangles, draw)
        })?;
        written.push(gif.clone());
    }
    if let (Some(output), Some(png)) = (outputs.png, &args.pictures.png) {
        let caption = |k: usize| {
            let t = frames.times[k];
            let key = (t.fract() == 0.0 && t >= 0.0)
                .then(|| key_names.get(t as usize))
                .flatten();
            match key {
                Some(name) => format!("{name}, t = {}", compact(t)),
                None => format!("t = {}", short_time(t)),
            }
        };
        staging.write(output, |path| {
            pictures::write_png(path, frames, triangles, draw, caption)
        })?;
        written.push(png.clone());
    }
    Ok(written)
}

/// `t` for a caption: at most three decimals, no trailing zeros.
fn short_time(t: f64) -> String {
    if !(1e-3..1e6).contains(&t.abs()) {
        return compact(t);
    }
    let text = format!("{t:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

struct Frame {
    compute: f64,
    write: f64,
    flipped: usize,
    /// What the output format could not hold of the first key's file.
    dropped: Vec<String>,
}

/// What frames came to, summed as they are written, in any order.
#[derive(Default)]
struct Frames {
    /// Seconds computing and writing them.
    compute: f64,
    write: f64,
    /// The most triangles turned over in one frame, and the first frame
    /// with that many.
    most_flipped: (usize, usize),
    /// What the output format could not hold of the first key's file, as
    /// frame 0 said it (the same for every frame).
    dropped: Vec<String>,
    /// The first frame that failed, and its error.
    error: Option<(usize, anyhow::Error)>,
}

impl Frames {
    /// Frame `k`, written or not.
    fn one(k: usize, frame: Result<Frame>) -> Self {
        match frame {
            Ok(f) => Self {
                compute: f.compute,
                write: f.write,
                most_flipped: (f.flipped, k),
                dropped: if k == 0 { f.dropped } else { Vec::new() },
                error: None,
            },
            Err(e) => Self {
                error: Some((k, e)),
                ..Self::default()
            },
        }
    }

    /// Both: the first frame of the most turned over, the first error.
    fn merge(self, other: Self) -> Self {
        let rank = |(flipped, k): (usize, usize)| (flipped, std::cmp::Reverse(k));
        let most_flipped = if rank(other.most_flipped) > rank(self.most_flipped) {
            other.most_flipped
        } else {
            self.most_flipped
        };
        let error = match (self.error, other.error) {
            (Some(a), Some(b)) => Some(if b.0 < a.0 { b } else { a }),
            (a, b) => a.or(b),
        };
        let dropped = if self.dropped.is_empty() {
            other.dropped
        } else {
            self.dropped
        };
        Self {
            compute: self.compute + other.compute,
            write: self.write + other.write,
            most_flipped,
            dropped,
            error,
        }
    }
}
