//! `meshmorph interpolate`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use meshmorph::io::MeshFile;
use meshmorph::{
    Dimension, Interpolator, InterpolatorOptions, Mesh, Mesh2, Mesh3, Sequence, Space, StretchMode,
};

use crate::animation::{write_frames, FrameOutputs, Report, Run, Setup};
use crate::gltf::GltfArgs;
use crate::memory;
use crate::output::WeldedFile;
use crate::output::{self, finite_number, FormatArg};
use crate::outputs::{Plan, Staging};
use crate::pictures::PictureArgs;

/// Interpolate through two or more meshes with the same triangles (keys),
/// planar or surfaces in space, or through drawings.
///
/// Writes DIR/frame_0000.obj, frame_0001.obj, ... and prints a report. Key
/// i is at time t = i; the frames pass through every key in order, with one
/// factorization for all of them. Planar when every z of every key is 0
/// (--dim forces it): planar keys are interpolated in the plane.
///
/// Inputs are never written: an output that would land on an input is
/// refused before any work. All or nothing: every file is written under a
/// temporary name and moved into place only when the whole run has
/// succeeded; a failed or interrupted (Ctrl-C) run leaves the output folder
/// as it was. After a successful run, files of an earlier run in DIR named
/// exactly like frames (frame_ + digits + .obj/.off/.ply/.stl/.svg/.txt)
/// that this run did not write are removed; no other file is touched.
///
/// Drawings: SVG files (.svg), polygons as text (.txt), or planar meshes
/// whose triangles differ. Each is one filled region (an outer loop and
/// any holes); their outlines are matched and made into meshes with the
/// same triangles, which are then interpolated. Frames are written in the
/// first drawing's format (SVG: frame_0000.svg, ... in its coordinates and
/// page, one path a frame, each point the same point of the drawing in
/// every frame; text: frame_0000.txt, ...; meshes: meshes).
#[derive(Debug, clap::Args)]
#[command(
    mut_arg("png", |a| a.help("Also write a still picture (PNG) of the first, middle and last frames side by side, each captioned with its time (and its key's name at a key)")),
    mut_arg("gif", |a| a.help("Also write an animated GIF of the frames")),
)]
pub struct Args {
    /// The keys, in order (OBJ, OFF, PLY or STL): the first at t = 0, the
    /// others at t = 1, 2, ...; every key has the first's vertices and
    /// triangles. Or drawings: SVG (.svg), polygons as text (.txt) or
    /// planar meshes with other triangles.
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
    /// Output mesh format [default: the first key's].
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Keep apart vertices that share a place. By default copies at seams
    /// (vertices at exactly one place in every key whose neighbours coincide too, as
    /// UV seams and edge splits leave them) are welded for the solve, so that
    /// the surface does not crack along them; the files keep their vertices.
    #[arg(long)]
    pub no_weld: bool,
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub drawing: crate::drawings::DrawingArgs,
    #[command(flatten)]
    pub picture: crate::picture_morph::PictureMorphArgs,
}

/// Options shared by `interpolate` and `demo`.
#[derive(Debug, Clone, clap::Args)]
pub struct FrameArgs {
    /// Number of frames, t evenly from the first key (0) to the last (the
    /// number of keys - 1) inclusive (at most 1000000).
    #[arg(long, default_value_t = 30, value_name = "N", value_parser = frame_count)]
    pub frames: usize,
    /// Explicit times instead, comma-separated, written in this order (key
    /// i at t = i; values outside extrapolate), e.g. --t 0,0.5,1.5
    #[arg(
        long = "t",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "LIST",
        value_parser = finite_number,
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
    /// in space there is no common axis to turn about, and a sequence's
    /// turns come from its keys).
    #[arg(
        long,
        default_value_t = 0,
        allow_negative_numbers = true,
        value_name = "K"
    )]
    pub turns: i32,
    /// Stretch interpolation: `linear` is (1-t)I + tS as in Alexa et al.
    /// (the default for meshes); `log` is S^t, which never collapses a
    /// triangle when extrapolating; `area` is `linear` with each triangle's
    /// area held to the straight blend of its keys' areas (planar; the
    /// default for drawings and pictures, whose unlike pairs `linear`
    /// swells by a quarter or more).
    #[arg(long, value_enum)]
    pub stretch: Option<Stretch>,
    /// Go on when triangles are reversed between the keys (in space: turned
    /// over relative to their neighbours in the first key).
    #[arg(long)]
    pub allow_flips: bool,
    /// Also write each frame as an SVG beside the mesh files (one view that
    /// holds every frame, --size pixels on its longer side; planar frames
    /// only).
    #[arg(long)]
    pub svg: bool,
    /// `--png`, `--gif` and how pictures are drawn.
    #[command(flatten)]
    pub pictures: PictureArgs,
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
    /// (1-t) I + t S, its area held to the blend of the keys' areas.
    Area,
}

impl FrameArgs {
    /// The times asked for, over keys at `0..=last`.
    pub fn times(&self, last: usize) -> Result<Vec<f64>> {
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
            n => Ok((0..n)
                .map(|k| last as f64 * k as f64 / (n - 1) as f64)
                .collect()),
        }
    }

    /// The options asked for, `--stretch` linear unless given.
    pub fn options(&self) -> InterpolatorOptions {
        self.options_or(StretchMode::Linear)
    }

    /// The options asked for, `--stretch` `stretch` unless given.
    pub fn options_or(&self, stretch: StretchMode) -> InterpolatorOptions {
        InterpolatorOptions::default()
            .with_consistency(!self.no_consistency)
            .with_turns(self.turns)
            .with_stretch(match self.stretch {
                None => stretch,
                Some(Stretch::Linear) => StretchMode::Linear,
                Some(Stretch::Log) => StretchMode::Log,
                Some(Stretch::Area) => StretchMode::AreaBlend,
            })
            .with_allow_flips(self.allow_flips)
    }
}

pub fn run(args: &Args) -> Result<()> {
    if crate::picture_morph::named_as_pictures(&args.keys)? {
        return crate::picture_morph::run(args);
    }
    args.picture.check_not_pictures()?;
    if crate::drawings::named_as_drawings(&args.keys) {
        return crate::drawings::run(args, None);
    }
    if let Some(key) = args
        .keys
        .iter()
        .find(|k| (k.is_file() || !k.exists()) && meshmorph::io::Format::from_path(k).is_err())
    {
        bail!(
            "`{}`: unknown format: interpolate takes meshes (.obj, .off, .ply, .stl), drawings (.svg, or polygons as .txt) or pictures (.png, .jpg, .jpeg), told apart by the file's extension",
            key.display()
        );
    }
    match run_meshes(args) {
        // Planar meshes whose triangles differ are drawings.
        Err(e) if crate::drawings::is_mismatch(&e) && args.dim != Some(3) => {
            crate::drawings::run(args, Some(e))
        }
        done => done,
    }
}

/// `interpolate` on meshes with the same triangles.
fn run_meshes(args: &Args) -> Result<()> {
    let start = Instant::now();
    let last = args.keys.len() - 1;
    let times = args.frames.times(last)?;
    let format = output::format_or_like(args.format, &args.keys[0])?;
    let roles = key_roles(args.keys.len());
    let mut plan = Plan::new();
    for (path, role) in args.keys.iter().zip(&roles) {
        plan.input(path, role);
    }
    let outputs = FrameOutputs::plan(&mut plan, &args.frames, &args.output, times.len(), format);
    let staging = plan.prepare()?;
    let paths: Vec<&Path> = args.keys.iter().map(PathBuf::as_path).collect();
    memory::check_reading(&paths)?;
    // Read as "key 0", "key 1", ... however many keys: a file that cannot
    // be read is named the same way in every run.
    let key_words: Vec<String> = (0..args.keys.len()).map(|i| format!("key {i}")).collect();
    let reading: Vec<&str> = key_words.iter().map(String::as_str).collect();
    let mut warnings = staging.warnings();
    let (first_file, keys) = output::read_poses(&paths, &reading, !args.no_weld, &mut warnings)?;
    args.drawing.check_meshes()?;
    output::protect_side_files(&staging, &first_file.file, &roles[0])?;
    let key_refs: Vec<&Mesh3> = keys.iter().collect();
    let planar = output::is_planar(args.dim, &key_refs, |k| {
        format!("the {} `{}`", roles[k], args.keys[k].display())
    })?;
    let context = || {
        let names: Vec<String> = args
            .keys
            .iter()
            .map(|p| format!("`{}`", p.display()))
            .collect();
        format!("interpolating {}", names.join(" to "))
    };
    let names: Vec<String> = args
        .keys
        .iter()
        .map(|p| crate::gltf::mesh_name(p))
        .collect();
    let keys = Keys {
        meshes: &keys,
        names: &names,
        file: Some(&first_file),
        warnings: &warnings,
    };
    let mut report = animate(
        keys,
        planar,
        &args.frames,
        &times,
        &outputs,
        &staging,
        start,
    )
    .map_err(|e| name_key_files(e, &args.keys, &first_file.file))
    .with_context(context)?;
    report.surplus_frames_removed = staging.commit()?;
    report.print(args.json);
    Ok(())
}

/// What the keys are called in messages: source and target when there are
/// two (as for any interpolation), else key 0, key 1, ...
fn key_roles(count: usize) -> Vec<String> {
    (0..count)
        .map(|i| match (count, i) {
            (2, 0) => "source mesh".to_string(),
            (2, _) => "target mesh".to_string(),
            _ => format!("key {i}"),
        })
        .collect()
}

/// The library numbers the keys after the first ("key 1", ...), calls the
/// first "the first key" and numbers triangles after splitting polygons;
/// say the files and their faces instead.
fn name_key_files(e: anyhow::Error, paths: &[PathBuf], first: &MeshFile) -> anyhow::Error {
    let lib = match e.downcast::<meshmorph::Error>() {
        Ok(lib) => lib,
        Err(e) => return e,
    };
    let flips = if paths.len() == 2 {
        output::PoseFiles {
            first,
            first_role: "source mesh",
            label: "key",
            poses: vec![("target mesh", &paths[1])],
        }
    } else {
        output::PoseFiles {
            first,
            first_role: "first key",
            label: "key",
            poses: paths[1..].iter().map(|p| ("key", p.as_path())).collect(),
        }
    };
    let e = output::turned_over_faces(lib, &flips);
    let Some(lib) = e.downcast_ref::<meshmorph::Error>() else {
        return e;
    };
    let mut text = lib.to_string();
    for (k, path) in paths.iter().enumerate().skip(1) {
        text = output::name_label(&text, &format!("key {k}"), path);
    }
    anyhow::anyhow!(output::name_label(&text, "the first key", &paths[0]))
}

/// The keys of an interpolation, and where they came from.
pub struct Keys<'a> {
    pub meshes: &'a [Mesh3],
    /// Their names (the stems of their files), for captions.
    pub names: &'a [String],
    /// The first key's file, when the keys were read: each frame is that
    /// file with new positions.
    pub file: Option<&'a WeldedFile>,
    /// Warnings of reading the keys.
    pub warnings: &'a [String],
}

impl<'a> Keys<'a> {
    /// Keys made in memory (the demo's), called `names`.
    pub fn made(meshes: &'a [Mesh3], names: &'a [String]) -> Self {
        Self {
            meshes,
            names,
            file: None,
            warnings: &[],
        }
    }
}

/// Builds the interpolation through `keys`, in the plane when `planar`
/// (two keys: an interpolation; more: a keyframe sequence), and writes its
/// frames through `staging`.
pub fn animate(
    keys: Keys<'_>,
    planar: bool,
    args: &FrameArgs,
    times: &[f64],
    outputs: &FrameOutputs,
    staging: &Staging,
    start: Instant,
) -> Result<Report> {
    let (file, read_warnings, key_names, keys) =
        (keys.file, keys.warnings, keys.names, keys.meshes);
    let first = &keys[0];
    let look_of = file.map(|f| &f.file);
    let image_budget = if planar {
        args.gltf.check::<2>(look_of, first, times.len())?
    } else {
        if args.svg {
            bail!("--svg draws planar frames only: use --gif, --png or --gltf for meshes in space");
        }
        args.gltf.check::<3>(look_of, first, times.len())?
    };
    if args.turns != 0 && !(planar && keys.len() == 2) {
        bail!(
            "--turns applies to two planar keys only: in space there is no common axis to turn about, and a sequence's whole turns come from its keys"
        );
    }
    memory::check_setup(first.num_triangles(), "the interpolation")?;
    let run = Run {
        args,
        times,
        outputs,
        staging,
        start,
        file,
        read_warnings,
        image_budget,
        key_names,
        outline: None,
        y_down: false,
        inside_shown: true,
    };
    let begin = Instant::now();
    let unused_vertices = first.num_unused_vertices();
    let welded_vertices = file.map_or(0, |f| f.seams.num_welded());
    if planar {
        let keys = keys
            .iter()
            .map(Mesh3::to_2d)
            .collect::<meshmorph::Result<Vec<Mesh2>>>()?;
        if keys.len() == 2 {
            let morph = Interpolator::new(&keys[0], &keys[1], &args.options())
                .map_err(|e| first_key_faces(e, file))?;
            let setup = Setup {
                keys: 2,
                seconds: begin.elapsed().as_secs_f64(),
                whole_turns: None,
                unused_vertices,
                welded_vertices,
                parts_following_host: morph.sequence().parts_following_host(),
            };
            return write_frames(morph.sequence(), keys[0].positions(), &run, &setup, None);
        }
        return animate_sequence(&keys, args, &run, begin, (unused_vertices, welded_vertices));
    }
    animate_sequence(keys, args, &run, begin, (unused_vertices, welded_vertices))
}

/// `e` with the first key's degenerate triangles named as its file's faces
/// (the library calls that key "source" between two keys, "first key" in
/// a sequence).
fn first_key_faces(e: meshmorph::Error, file: Option<&WeldedFile>) -> meshmorph::Error {
    match file {
        Some(f) => ["source", "first key"]
            .iter()
            .fold(e, |e, label| output::degenerate_faces(e, &f.file, label)),
        None => e,
    }
}

/// Builds the keyframe sequence through `keys` and writes its frames.
fn animate_sequence<const D: usize>(
    keys: &[Mesh<D>],
    args: &FrameArgs,
    run: &Run<'_>,
    begin: Instant,
    (unused_vertices, welded_vertices): (usize, usize),
) -> Result<Report>
where
    Space<D>: Dimension<D>,
{
    memory::check_sequence(keys[0].num_triangles(), keys.len() - 1)?;
    let morph = Sequence::new(keys, &args.options()).map_err(|e| first_key_faces(e, run.file))?;
    let setup = Setup {
        keys: keys.len(),
        seconds: begin.elapsed().as_secs_f64(),
        whole_turns: Some(morph.triangles_with_whole_turns().iter().sum()),
        unused_vertices,
        welded_vertices,
        parts_following_host: morph.parts_following_host(),
    };
    write_frames(&morph, keys[0].positions(), run, &setup, None)
}
