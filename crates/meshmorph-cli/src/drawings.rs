//! `meshmorph interpolate` on drawings: SVG files, polygons as text, or
//! planar meshes whose triangles differ. Their outlines are made into
//! meshes with the same triangles ([`meshmorph::outline::compatible_set`]),
//! then interpolated as any keys; the frames are written in the drawings'
//! format, and as one animated SVG, a Lottie JSON and the compatible
//! meshes when asked.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use meshmorph::io::{
    AnchorRow, Animation, Canvas, DrawingFile, DrawingKind, DrawingOptions, Format, Style,
};
use meshmorph::outline::{compatible_set, CompatibleSet, Drawing, OutlineOptions};
use meshmorph::{Interpolator, Mesh2, Sequence, StretchMode};
use serde::Serialize;

use crate::animation::{write_frames, FrameOutputs, Recomputed, Run, Setup, WriteFrame};
use crate::interpolate::Args;
use crate::kept_frames::KeptFrames;
use crate::output;
use crate::outputs::{Output, Plan, Staging};
use crate::pictures::file_named;

/// Options of `interpolate` for drawings.
#[derive(Debug, Clone, clap::Args)]
pub struct DrawingArgs {
    /// Points matched across the drawings, kept exactly (an eye to an
    /// eye; on the outlines or inside): one anchor a line, an optional
    /// name then `x y` on each drawing in order (`eye 120 80 300 95`), `#`
    /// comments. Anchors marked in SVG files (elements whose id starts
    /// with `anchor`, such as `<circle id="anchor-eye" .../>`) are matched
    /// by name and used too (ids `anchor-NAME`).
    #[arg(long, value_name = "FILE")]
    pub anchors: Option<PathBuf>,
    /// How far SVG curves may stray from the chords that replace them, as
    /// a fraction of the drawing's bounding-box diagonal.
    #[arg(long, default_value_t = 0.0005, value_name = "FRACTION", value_parser = tolerance)]
    pub tolerance: f64,
    /// Also write one animated SVG of every frame (the path's outline
    /// animated with SMIL `<animate>`, playing in browsers at --fps, over
    /// and over; forward then back unless --no-boomerang). Drawings only.
    #[arg(long, value_name = "FILE.svg", value_parser = svg_file)]
    pub animated_svg: Option<PathBuf>,
    /// Also write a Lottie animation (JSON: a shape layer with a path
    /// keyframe a frame, at --fps; forward then back unless
    /// --no-boomerang), for After Effects and the web and mobile players.
    /// Drawings only.
    #[arg(long, value_name = "FILE.json", value_parser = json_file)]
    pub lottie: Option<PathBuf>,
    /// Also write the compatible meshes, one OBJ a drawing named after it
    /// (DIR/cat.obj, DIR/dog.obj, ...): the same triangles in each, ready
    /// for `interpolate`, `blend` and Python. Drawings only.
    #[arg(long, value_name = "DIR")]
    pub meshes: Option<PathBuf>,
}

fn tolerance(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x > 0.0 && x <= 0.1 => Ok(x),
        _ => Err(format!(
            "`{text}` is not a fraction of the drawing's size from 0 (excluded) to 0.1, such as 0.0005"
        )),
    }
}

fn svg_file(text: &str) -> Result<PathBuf, String> {
    file_named(text, "svg", "SVG")
}

fn json_file(text: &str) -> Result<PathBuf, String> {
    file_named(text, "json", "Lottie JSON")
}

impl DrawingArgs {
    /// The flags given that apply to drawings only.
    fn given(&self) -> Vec<&'static str> {
        [
            (self.anchors.is_some(), "--anchors"),
            (self.animated_svg.is_some(), "--animated-svg"),
            (self.lottie.is_some(), "--lottie"),
            (self.meshes.is_some(), "--meshes"),
        ]
        .into_iter()
        .filter_map(|(given, flag)| given.then_some(flag))
        .collect()
    }

    /// Refuses flags for drawings on keys that are meshes with the same
    /// triangles.
    pub fn check_meshes(&self) -> Result<()> {
        if let Some(flag) = self.given().first() {
            bail!(
                "{flag} applies to drawings (SVG files, polygons as text, or planar meshes whose triangles differ); these keys are meshes with the same triangles"
            );
        }
        Ok(())
    }
}

/// Whether `keys` are drawings by their names: any SVG or text file.
pub fn named_as_drawings(keys: &[PathBuf]) -> bool {
    keys.iter().any(|k| DrawingKind::of_path(k).is_some())
}

/// Whether `e`, an error of reading keys as meshes with the same
/// triangles, says their vertices or faces differ: planar ones are then
/// taken as drawings.
pub fn is_mismatch(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        matches!(
            c.downcast_ref::<meshmorph::Error>(),
            Some(meshmorph::Error::Mismatch(_) | meshmorph::Error::FaceMismatch { .. })
        )
    })
}

/// What the drawings were and how they were made compatible.
#[derive(Debug, Serialize)]
pub struct DrawingsReport {
    /// Each drawing's file.
    #[serde(serialize_with = "output::lossy")]
    pub files: Vec<PathBuf>,
    /// Each drawing's kind: `svg`, `text` or `mesh`.
    pub kinds: Vec<&'static str>,
    /// Points of each drawing's outline (every loop), as read.
    pub points: Vec<usize>,
    /// Loops of each drawing (1 + holes).
    pub loops: usize,
    /// Curves flattened in each drawing.
    pub curves: Vec<usize>,
    /// The flattening tolerance asked for, a fraction of each drawing's
    /// bounding-box diagonal.
    pub tolerance_fraction: f64,
    /// The same in each drawing's units (0 for drawings without curves
    /// to flatten: text and meshes).
    pub tolerance: Vec<f64>,
    /// Anchors kept matched.
    pub anchors: usize,
    /// Points of the matched outline, the same on every mesh.
    pub boundary_points: usize,
    /// Mesh vertices inside (Steiner points).
    pub steiner_points: usize,
    /// Triangles of the compatible meshes.
    pub triangles: usize,
    /// Smallest angle of any triangle in each mesh, degrees.
    pub min_angle_degrees: Vec<f64>,
    /// How the meshes were made, as the library names the way
    /// (`mapped`: one drawing's mesh mapped into the others; `overlay`:
    /// the drawings' triangulations laid over each other; ...).
    pub path: String,
    /// The library's account of it, one line.
    pub summary: String,
    /// Seconds spent reading the drawings.
    pub read_seconds: f64,
    /// Seconds spent matching the outlines and making the compatible
    /// meshes (part of `setup_seconds`).
    pub compatible_seconds: f64,
    /// The animated SVG written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub animated_svg: Option<PathBuf>,
    /// The Lottie file written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub lottie: Option<PathBuf>,
    /// The compatible meshes written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub meshes: Vec<PathBuf>,
}

impl DrawingsReport {
    pub fn print(&self) {
        let list = |v: &[usize]| {
            v.iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(" + ")
        };
        say!(
            "drawings:       {} ({} points{}; {})",
            self.files.len(),
            list(&self.points),
            match self.loops {
                1 => String::new(),
                2 => ", 1 hole each".to_string(),
                n => format!(", {} holes each", n - 1),
            },
            self.kinds.join(", ")
        );
        if self.curves.iter().any(|&c| c > 0) {
            // Three significant digits, whatever the drawing's size (0 for
            // a drawing with no curve).
            let units: Vec<String> = self
                .tolerance
                .iter()
                .map(|&t| {
                    if t > 0.0 && t.is_finite() {
                        let decimals = (2.0 - t.log10().floor()).clamp(0.0, 17.0) as usize;
                        format!("{t:.decimals$}")
                    } else {
                        format!("{t}")
                    }
                })
                .collect();
            say!(
                "flattened:      {} curves within {} of each drawing's diagonal ({} in its units)",
                list(&self.curves),
                self.tolerance_fraction,
                units.join(", ")
            );
        }
        let angles: Vec<String> = self
            .min_angle_degrees
            .iter()
            .map(|a| format!("{a:.1}"))
            .collect();
        say!(
            "compatible:     {} triangles, {} on the outline, {} Steiner points, smallest angle {}° ({}), {}",
            self.triangles,
            self.boundary_points,
            self.steiner_points,
            angles.join("/"),
            self.path,
            output::human_seconds(self.compatible_seconds)
        );
        if self.anchors > 0 {
            say!("anchors:        {} kept matched", self.anchors);
        }
        output::print_files(
            &[
                ("animated SVG:", self.animated_svg.as_deref()),
                ("Lottie:", self.lottie.as_deref()),
            ],
            16,
        );
        if let (Some(first), n) = (self.meshes.first(), self.meshes.len()) {
            say!(
                "meshes:         {n} OBJ in {}",
                first.parent().unwrap_or(Path::new("")).display()
            );
        }
    }
}

/// A drawing's frames as files: the outline as an SVG path or as text.
struct OutlineFrame<'a> {
    loops: &'a [Vec<u32>],
    style: &'a Style,
    canvas: &'a Canvas,
    svg: bool,
}

impl WriteFrame for OutlineFrame<'_> {
    fn write(&self, w: &mut dyn std::io::Write, positions: &[[f64; 2]]) -> std::io::Result<()> {
        if self.svg {
            meshmorph::io::write_svg_frame(w, positions, self.loops, self.style, self.canvas)
        } else {
            meshmorph::io::write_text_frame(w, positions, self.loops)
        }
    }
}

/// What the keys are called: source and target drawing for two, else
/// drawing 0, 1, ...
fn roles(count: usize) -> Vec<String> {
    (0..count)
        .map(|i| match (count, i) {
            (2, 0) => "source drawing".to_string(),
            (2, _) => "target drawing".to_string(),
            _ => format!("drawing {i}"),
        })
        .collect()
}

/// `role` in a sentence: "the source drawing", "drawing 2".
fn the(role: &str) -> String {
    if role.starts_with("drawing ") {
        role.to_string()
    } else {
        format!("the {role}")
    }
}

/// Reads key `path` (called `role`) as a drawing: an SVG or text file,
/// or a planar mesh's boundary. `mismatch`, when the keys were first read
/// as meshes with the same triangles, is said instead when a mesh is not
/// planar.
fn read_key(
    path: &Path,
    role: &str,
    options: &DrawingOptions,
    mismatch: Option<&anyhow::Error>,
) -> Result<DrawingFile> {
    if DrawingKind::of_path(path).is_some() {
        return meshmorph::io::read_drawing(path, options)
            .map_err(|e| anyhow::anyhow!("reading {} {e}", the(role)));
    }
    let mesh = match meshmorph::io::read_planar_mesh(path) {
        Ok(m) => m,
        Err(e @ meshmorph::Error::InvalidVertex { .. }) => {
            // In space: meshes with other triangles cannot be drawings.
            return Err(match mismatch {
                Some(m) => anyhow::anyhow!("{m:#}"),
                None => anyhow::anyhow!("reading {} `{}`: {e}", the(role), path.display()),
            });
        }
        Err(e) => return Err(anyhow::anyhow!("reading {} {e}", the(role))),
    };
    let drawing =
        meshmorph::io::drawing_of_mesh(&mesh, &format!("{} `{}`", the(role), path.display()))?;
    Ok(DrawingFile {
        drawing,
        style: Style::default(),
        canvas: None,
        anchors: Vec::new(),
        tolerance: 0.0,
        curves: 0,
        kind: DrawingKind::Mesh,
    })
}

/// The OBJ paths of the compatible meshes in `dir`: each drawing's stem,
/// numbered in front when two drawings share one.
fn mesh_paths(dir: &Path, keys: &[PathBuf]) -> Vec<PathBuf> {
    let stems: Vec<String> = keys.iter().map(|k| crate::gltf::mesh_name(k)).collect();
    stems
        .iter()
        .enumerate()
        .map(|(i, s)| {
            if stems.iter().filter(|t| *t == s).count() > 1 {
                dir.join(format!("{i}-{s}.obj"))
            } else {
                dir.join(format!("{s}.obj"))
            }
        })
        .collect()
}

/// Every anchor: those marked in the drawings, matched by name (or in
/// order), then those of `--anchors`.
fn anchors(args: &DrawingArgs, files: &[DrawingFile], keys: &[PathBuf]) -> Result<Vec<AnchorRow>> {
    let names: Vec<String> = keys.iter().map(|k| format!("`{}`", k.display())).collect();
    let marked: Vec<Vec<meshmorph::io::NamedPoint>> =
        files.iter().map(|f| f.anchors.clone()).collect();
    let mut rows = meshmorph::io::match_anchors(&marked, &names)?;
    if let Some(path) = &args.anchors {
        for row in meshmorph::io::read_anchor_file(path, files.len())? {
            if !row.name.is_empty() {
                if let Some(r) = rows.iter().find(|r| r.name == row.name) {
                    bail!(
                        "the anchor `{}` of {} is also {}: give it once",
                        row.name,
                        row.origin,
                        r.origin
                    );
                }
            }
            rows.push(row);
        }
    }
    Ok(rows)
}

/// The outputs of a run on drawings.
struct Outputs {
    frames: FrameOutputs,
    animated_svg: Option<Output>,
    lottie: Option<Output>,
    meshes: Vec<(Output, PathBuf)>,
}

/// `meshmorph interpolate` on drawings. `mismatch` is the error of reading
/// the keys as meshes with the same triangles, when they were first read
/// so.
pub fn run(args: &Args, mismatch: Option<anyhow::Error>) -> Result<()> {
    let start = Instant::now();
    let d = &args.drawing;
    let keys = &args.keys;
    let times = args.frames.times(keys.len() - 1)?;
    let kind = DrawingKind::of_path(&keys[0]).unwrap_or(DrawingKind::Mesh);
    // Frames in the first drawing's format, or the mesh format asked for.
    let (format, ext) = match (args.format, kind) {
        (Some(f), _) => (f.into(), Format::from(f).extension()),
        (None, DrawingKind::Svg) => (Format::Obj, "svg"),
        (None, DrawingKind::Text) => (Format::Obj, "txt"),
        (None, _) => {
            let f = Format::from_path(&keys[0])?;
            (f, f.extension())
        }
    };
    if ext == "svg" && args.frames.svg {
        bail!("--svg draws the triangles of each frame beside the mesh files; these frames are SVG drawings already: leave out --svg, or ask for meshes with --format");
    }
    let roles = roles(keys.len());
    let mut plan = Plan::new();
    for (path, role) in keys.iter().zip(&roles) {
        plan.input(path, role);
    }
    if let Some(a) = &d.anchors {
        plan.input(a, "anchor file");
    }
    let mesh_files = d
        .meshes
        .as_deref()
        .map(|dir| mesh_paths(dir, keys))
        .unwrap_or_default();
    let outputs = Outputs {
        frames: FrameOutputs::plan_as(
            &mut plan,
            &args.frames,
            &args.output,
            times.len(),
            format,
            ext,
        ),
        animated_svg: d
            .animated_svg
            .as_deref()
            .map(|p| plan.file(p, "animated SVG")),
        lottie: d.lottie.as_deref().map(|p| plan.file(p, "Lottie file")),
        meshes: mesh_files
            .iter()
            .map(|p| (plan.file(p, "compatible mesh"), p.clone()))
            .collect(),
    };
    let staging = plan.prepare()?;
    let paths: Vec<&Path> = keys.iter().map(PathBuf::as_path).collect();
    crate::memory::check_reading(&paths)?;
    let read_begin = Instant::now();
    let options = DrawingOptions {
        tolerance: d.tolerance,
    };
    let files = keys
        .iter()
        .zip(&roles)
        .map(|(k, role)| read_key(k, role, &options, mismatch.as_ref()))
        .collect::<Result<Vec<DrawingFile>>>()?;
    let read_seconds = read_begin.elapsed().as_secs_f64();
    let anchor_rows = anchors(d, &files, keys)?;
    let begin = Instant::now();
    let drawings: Vec<Drawing> = files.iter().map(|f| f.drawing.clone()).collect();
    let anchor_points: Vec<Vec<[f64; 2]>> = anchor_rows.iter().map(|r| r.points.clone()).collect();
    let names: Vec<String> = keys.iter().map(|k| format!("`{}`", k.display())).collect();
    let set = compatible_set(&drawings, &anchor_points, &OutlineOptions::default())
        .map_err(|e| anyhow::anyhow!(name_anchors(&name_drawings(e, &names), &anchor_rows)))
        .with_context(|| format!("making {} compatible", names.join(", ")))?;
    let compatible_seconds = begin.elapsed().as_secs_f64();
    let report = animate(
        args,
        &files,
        &set,
        &times,
        &outputs,
        &staging,
        (start, begin),
    )
    .with_context(|| format!("interpolating {}", names.join(" to ")))?;
    let mut report = report;
    let r = &set.report;
    report.drawings = Some(DrawingsReport {
        files: keys.clone(),
        kinds: files
            .iter()
            .map(|f| match f.kind {
                DrawingKind::Svg => "svg",
                DrawingKind::Text => "text",
                _ => "mesh",
            })
            .collect(),
        points: files.iter().map(|f| f.drawing.num_points()).collect(),
        loops: files[0].drawing.num_loops(),
        curves: files.iter().map(|f| f.curves).collect(),
        tolerance_fraction: d.tolerance,
        tolerance: files.iter().map(|f| f.tolerance).collect(),
        anchors: anchor_rows.len(),
        boundary_points: r.boundary_points,
        steiner_points: r.steiner_points,
        triangles: r.triangles,
        min_angle_degrees: r.min_angle_degrees.clone(),
        path: format!("{:?}", r.path).to_lowercase(),
        summary: r.to_string(),
        read_seconds,
        compatible_seconds,
        animated_svg: d.animated_svg.clone(),
        lottie: d.lottie.clone(),
        meshes: mesh_files,
    });
    report.surplus_frames_removed = staging.commit()?;
    report.print(args.json);
    Ok(())
}

/// The library says "drawing k" (from 1) and "the first drawing": say the
/// files.
fn name_drawings(e: meshmorph::Error, names: &[String]) -> String {
    let mut text = e.to_string();
    for (k, name) in names.iter().enumerate().rev() {
        text = text.replace(
            &format!("drawing {}", k + 1),
            &format!("drawing {} ({name})", k + 1),
        );
    }
    text = text.replace(
        "the first drawing",
        &format!("the first drawing ({})", names[0]),
    );
    text
}

/// `text` with each `anchor K` (counted from 1) followed by the anchor's
/// name and where it was given: `anchor 3 (`elbow`, `a.txt`, line 5)`.
pub(crate) fn name_anchors(text: &str, rows: &[AnchorRow]) -> String {
    const WORD: &str = "anchor ";
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(WORD) {
        let after = &rest[at + WORD.len()..];
        let digits = after.bytes().take_while(u8::is_ascii_digit).count();
        out.push_str(&rest[..at + WORD.len() + digits]);
        let row = after[..digits]
            .parse::<usize>()
            .ok()
            .and_then(|k| k.checked_sub(1))
            .and_then(|k| rows.get(k));
        if let Some(row) = row {
            out.push_str(&format!(" ({})", row.label()));
        }
        rest = &after[digits..];
    }
    out.push_str(rest);
    out
}

/// Interpolates the compatible meshes of `set` and writes the frames and
/// the outputs of drawings.
fn animate(
    args: &Args,
    files: &[DrawingFile],
    set: &CompatibleSet,
    times: &[f64],
    outputs: &Outputs,
    staging: &Staging,
    (start, begin): (Instant, Instant),
) -> Result<crate::animation::Report> {
    let first = &set.meshes[0];
    let mesh3 = first.to_3d();
    let image_budget = args.frames.gltf.check::<2>(None, &mesh3, times.len())?;
    if args.frames.turns != 0 && set.meshes.len() != 2 {
        bail!("--turns applies to two keys only: a sequence's whole turns come from its keys");
    }
    crate::memory::check_setup(first.num_triangles(), "the interpolation")?;
    // A drawing's triangles keep their areas on the straight blend of the
    // keys' (`--stretch area`, unless another is asked for): unlike pairs
    // swell by a quarter or more with the published linear blend.
    // Their outlines' edges take the blend of their lengths (the fit alone
    // shortens an unlike pair's by 10 to 17 %), the area as the fit has it.
    // A drawing's frames' outlines are untied where the fit knots them
    // (microseconds where it does not). They are mended where the fit
    // turns triangles over (the outline stays as it is) when an output
    // shows the inside: outlines alone (SVG and text frames, the animated
    // SVG, Lottie) are the same either way, and mending an unlike pair's
    // frame can take a tenth of a second (so mended frames are made once,
    // for every writer, where they fit in memory).
    let options = args
        .frames
        .options_or(StretchMode::AreaBlend)
        .with_outline_lengths(true)
        .with_untie_outlines(true)
        .with_mend_folds(outputs.frames.shows_inside());
    let (interpolator, sequence);
    let morph: &Sequence<2> = if set.meshes.len() == 2 {
        interpolator = Interpolator::new(&set.meshes[0], &set.meshes[1], &options)?;
        interpolator.sequence()
    } else {
        crate::memory::check_sequence(first.num_triangles(), set.meshes.len() - 1)?;
        sequence = Sequence::new(&set.meshes, &options)?;
        &sequence
    };
    let setup = Setup {
        keys: set.meshes.len(),
        seconds: begin.elapsed().as_secs_f64(),
        whole_turns: (set.meshes.len() > 2)
            .then(|| morph.triangles_with_whole_turns().iter().sum()),
        unused_vertices: first.num_unused_vertices(),
        welded_vertices: 0,
        parts_following_host: morph.parts_following_host(),
    };
    // Mended frames are computed once, for every writer.
    let kept = options
        .mend_folds
        .then(|| KeptFrames::compute(morph, times))
        .flatten();
    let recomputed = Recomputed {
        morph,
        times,
        y_down: false,
        kept: kept.as_ref(),
    };
    let style = &files[0].style;
    let canvas = Canvas::for_frames(
        files[0].canvas.as_ref(),
        &recomputed,
        &set.loops,
        style.stroke_width / 2.0,
    );
    let outline = OutlineFrame {
        loops: &set.loops,
        style,
        canvas: &canvas,
        svg: outputs.frames_ext() == "svg",
    };
    let key_names: Vec<String> = args
        .keys
        .iter()
        .map(|k| crate::gltf::mesh_name(k))
        .collect();
    let is_drawing_frame = matches!(outputs.frames_ext(), "svg" | "txt");
    let run = Run {
        args: &args.frames,
        times,
        outputs: &outputs.frames,
        staging,
        start,
        file: None,
        read_warnings: &[],
        image_budget,
        key_names: &key_names,
        outline: is_drawing_frame.then_some(&outline as &dyn WriteFrame),
        y_down: files[0].kind == DrawingKind::Svg,
        inside_shown: outputs.frames.shows_inside(),
    };
    let mut report = write_frames(morph, first.positions(), &run, &setup, kept.as_ref())?;
    let draw = &args.frames.pictures.draw;
    let animation = Animation {
        frames: &recomputed,
        loops: &set.loops,
        style,
        canvas: &canvas,
        fps: draw.fps,
        boomerang: !draw.no_boomerang,
    };
    if let Some(out) = outputs.animated_svg {
        staging.write_to(out, |_, w| {
            Ok(meshmorph::io::write_animated_svg(w, &animation)?)
        })?;
        report
            .files_written
            .extend(args.drawing.animated_svg.clone());
    }
    if let Some(out) = outputs.lottie {
        staging.write_to(out, |_, w| Ok(meshmorph::io::write_lottie(w, &animation)?))?;
        report.files_written.extend(args.drawing.lottie.clone());
    }
    for ((out, path), mesh) in outputs.meshes.iter().zip(&set.meshes) {
        write_mesh(staging, *out, mesh)?;
        report.files_written.push(path.clone());
    }
    report.total_seconds = start.elapsed().as_secs_f64();
    Ok(report)
}

/// Writes one compatible mesh as OBJ.
fn write_mesh(staging: &Staging, out: Output, mesh: &Mesh2) -> Result<()> {
    staging.write_to(out, |path, w| {
        Ok(meshmorph::io::write_positions_to(
            w,
            path,
            mesh.positions(),
            mesh.triangles(),
            Format::Obj,
        )?)
    })
}

impl Outputs {
    fn frames_ext(&self) -> &'static str {
        self.frames.ext()
    }
}
