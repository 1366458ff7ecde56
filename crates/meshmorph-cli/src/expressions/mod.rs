//! `meshmorph expressions`: a template's facial expressions (the 52 ARKit
//! shapes of the built-in template) put on a head from a few landmarks,
//! or on many heads from a batch file (`batch`).

mod batch;

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use meshmorph::io::gltf::ShapeKeyOptions;
use meshmorph::io::gltf::{GltfDocument, GltfMesh, GltfOptions};
use meshmorph::io::{Appearance, Format, MeshFile};
use meshmorph::{
    CarryMethod, ExpressionOptions, ExpressionTemplate, FrameSource, HeadExpressions, Mesh3,
};
use serde::Serialize;

use crate::gltf::{is_gltf, GltfArgs};
use crate::memory;
use crate::output::{self, FormatArg, WeldedFile};
use crate::outputs::{Output, Plan};
use crate::pictures::{self, PictureArgs};
use crate::transfer::numbering;

/// Put a template's facial expressions on a head from a few named
/// landmarks: by default the 52 ARKit blendshapes (eyeBlinkLeft, jawOpen,
/// ...) of the built-in template, made from ICT-FaceKit (MIT licence).
///
/// The template head is fitted onto the head from the landmarks (12 or
/// more, by iBUG 300-W number 1 to 68 or by alias: eyeOuterRight,
/// noseTip, mouthCornerLeft, chin, ...; left and right are the head's
/// own), then each shape is carried onto the head. The head's separate
/// parts (eyes, teeth, tongue as separate pieces) move rigidly with the
/// template part nearest to them.
///
/// -o FILE.glb (or .gltf, .vrm) with a glTF or VRM head writes a copy of
/// the head's own file with the shapes added as morph targets of its mesh,
/// everything else kept; with a head of another format, a new GLB of the
/// head with the shapes as morph targets. -o DIR writes one mesh per shape,
/// DIR/<shape name>.<ext>, in the head's format. The head is never written.
///
/// --batch FILE puts them on many heads, each named with its landmarks and
/// output in the file (see the end of this help).
#[derive(Debug, Clone, clap::Args)]
#[command(
    after_long_help = batch::FORMAT,
    mut_arg("png", |a| a.help("Also write a still picture (PNG) of three of the new shapes on the head (jawOpen, eyeBlinkLeft, mouthSmileLeft, those it has)")),
    mut_arg("gif", |a| a.help("Also write an animated GIF of the head making a few of its new shapes (jawOpen, eyeBlinkLeft, mouthSmileLeft, browInnerUp, those it has) one after another")),
)]
pub struct Args {
    /// The head at rest: OBJ, OFF, PLY, STL, or a glTF, GLB or VRM file.
    #[arg(required_unless_present = "batch", conflicts_with = "batch")]
    pub head: Option<PathBuf>,
    /// The landmarks on the head: MeshLab's .pp, Wrap's .json, or lines of
    /// `name x y z` or `name VERTEX`, each named by its landmark.
    #[arg(
        long,
        value_name = "FILE",
        required_unless_present = "batch",
        conflicts_with = "batch"
    )]
    pub markers: Option<PathBuf>,
    /// Vertex indices in the landmark file start at 1 instead of 0.
    #[arg(long)]
    pub one_based: bool,
    /// Where the shapes go: FILE.glb, .gltf or .vrm, or a directory.
    #[arg(
        short,
        long,
        value_name = "OUT",
        required_unless_present = "batch",
        conflicts_with = "batch"
    )]
    pub output: Option<PathBuf>,
    /// Many heads, each with its landmarks and output, from a batch file
    /// (TOML or JSON; see the end of this help); repeat for several files.
    /// The other options apply to every head.
    #[arg(long, value_name = "FILE")]
    pub batch: Vec<PathBuf>,
    /// The template: `arkit` (built in) or a rig's GLB: a mesh named `head`
    /// with named morph targets (`extras.targetNames`) and landmarks
    /// (`extras.landmarks`, a list of {"name", "vertex"}), its other meshes
    /// its parts.
    #[arg(long, default_value = "arkit", value_name = "arkit|FILE.glb")]
    pub template: String,
    /// With a glTF or VRM head: its mesh to read, by the mesh's or its
    /// node's name [default: the only mesh, else the one with the most
    /// vertices].
    #[arg(long, value_name = "NAME", conflicts_with = "batch")]
    pub mesh: Option<String>,
    /// How each shape is carried: `displacements` copies the template's
    /// moves through the fitted correspondence (closest to the template's
    /// own motion; measured the more accurate); `transfer` is deformation
    /// transfer (adapts each shape to the head's proportions).
    #[arg(long, value_enum, default_value_t = MethodArg::Displacements)]
    pub method: MethodArg,
    /// Also carry every shape the other way and report, per shape, where
    /// the two ways differ most.
    #[arg(long)]
    pub compare: bool,
    /// Keep the template's shapes beyond ARKit's 52 under their own names.
    #[arg(long)]
    pub all_shapes: bool,
    /// With a glTF or VRM head: a shape whose name the mesh already has
    /// replaces it (else refused).
    #[arg(long)]
    pub replace_shapes: bool,
    /// With a VRM head: also add each shape as a custom expression of the
    /// same name.
    #[arg(long)]
    pub vrm_expressions: bool,
    /// Store every morph target densely, for tools that do not read glTF's
    /// sparse accessors.
    #[arg(long)]
    pub gltf_dense: bool,
    /// With -o FILE.glb for a head that is not glTF: refuse, before any
    /// work, a GLB that may weigh more than this many megabytes (10^6
    /// bytes; counted as if every shape moved every vertex, so the file
    /// written with sparse storage is often half of it: 1024 is a head of
    /// about 800,000 vertices).
    #[arg(long, default_value_t = 1024.0, value_name = "MB", value_parser = output::positive_number)]
    pub max_gltf_mb: f64,
    /// Output mesh format with -o DIR [default: the head's; OBJ for a glTF
    /// head].
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    #[command(flatten)]
    pub pictures: PictureArgs,
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

impl Args {
    /// The head (given unless --batch: then each head of the batch is set).
    fn head(&self) -> &Path {
        self.head.as_deref().unwrap_or(Path::new(""))
    }

    /// The landmark file (as [`Args::head`]).
    fn markers(&self) -> &Path {
        self.markers.as_deref().unwrap_or(Path::new(""))
    }

    /// Where the shapes go (as [`Args::head`]).
    fn output(&self) -> &Path {
        self.output.as_deref().unwrap_or(Path::new(""))
    }
}

/// How the shapes are carried (see [`CarryMethod`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodArg {
    Displacements,
    Transfer,
}

/// The shapes the pictures show, those the head has, in this order.
const SHOWN: [&str; 4] = ["jawOpen", "eyeBlinkLeft", "mouthSmileLeft", "browInnerUp"];

/// Frames of the pictures from rest to a shape.
const STEPS: usize = 10;

/// Where the shapes are written.
enum Destination {
    /// A copy of the glTF head's own file with the shapes added.
    IntoHead,
    /// A new GLB of a head that is not glTF.
    NewGlb,
    /// One mesh per shape in a directory.
    Folder(Format),
}

/// A shape's line of the report.
#[derive(Debug, Serialize)]
pub struct ShapeLine {
    pub name: String,
    /// Vertices that move.
    pub moved_vertices: usize,
    /// The largest move over the head's bounding-box diagonal.
    pub largest_move: f64,
    /// With --compare: the largest distance between the two ways over the
    /// diagonal, and the vertex where it is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub methods_differ: Option<(f64, u32)>,
}

/// A separate part of the head.
#[derive(Debug, Serialize)]
pub struct PartLine {
    pub vertices: usize,
    /// The template part it moves with (none: it stays still).
    pub follows: Option<String>,
}

/// The separate parts grouped by the template part they follow (none: they
/// stay still), in the order the parts come: `(followed, parts, vertices)`.
/// Teeth come as many pieces; the report says one line for them all.
fn by_part_followed(parts: &[PartLine]) -> Vec<(Option<&str>, usize, usize)> {
    let mut followed: Vec<(Option<&str>, usize, usize)> = Vec::new();
    for p in parts {
        let follows = p.follows.as_deref();
        match followed.iter_mut().find(|(f, ..)| *f == follows) {
            Some((_, pieces, vertices)) => {
                *pieces += 1;
                *vertices += p.vertices;
            }
            None => followed.push((follows, 1, p.vertices)),
        }
    }
    followed
}

/// What a run did.
#[derive(Debug, Serialize)]
pub struct Report {
    #[serde(serialize_with = "output::lossy")]
    pub head: PathBuf,
    /// The mesh read from a glTF head.
    pub mesh: Option<String>,
    pub vertices: usize,
    pub triangles: usize,
    pub template: String,
    pub landmarks: usize,
    pub method: &'static str,
    pub shapes: Vec<ShapeLine>,
    /// ARKit names the template has no shape for.
    pub missing: Vec<String>,
    pub parts: Vec<PartLine>,
    /// Fitting the template and carrying the shapes.
    pub expressions_seconds: f64,
    pub total_seconds: f64,
    #[serde(serialize_with = "output::lossy")]
    pub output: PathBuf,
    #[serde(serialize_with = "output::lossy")]
    pub files_written: Vec<PathBuf>,
    pub warnings: Vec<String>,
}

impl Report {
    fn print(&self, json: bool) {
        if json {
            output::print_json(self);
            return;
        }
        say!(
            "wrote {} ({} on a head of {}, {})",
            self.output.display(),
            output::count(self.shapes.len(), "shape"),
            output::vertices(self.vertices),
            output::count(self.triangles, "triangle"),
        );
        say!(
            "template: {}, fitted from {} ({})",
            self.template,
            output::count(self.landmarks, "landmark"),
            self.method
        );
        if !self.missing.is_empty() {
            say!(
                "missing: {} (the template has no shape for {})",
                self.missing.join(", "),
                if self.missing.len() == 1 {
                    "it"
                } else {
                    "them"
                }
            );
        }
        for (follows, pieces, vertices) in by_part_followed(&self.parts) {
            let what = if pieces == 1 {
                format!("part: {}", output::vertices(vertices))
            } else {
                format!("parts: {pieces} of {} in all", output::vertices(vertices))
            };
            match follows {
                Some(name) => say!("{what} moving with {name}"),
                None if pieces == 1 => say!("{what} with no template part near: it stays still"),
                None => say!("{what} with no template part near: they stay still"),
            }
        }
        let mut largest: Vec<&ShapeLine> = self.shapes.iter().collect();
        largest.sort_by(|a, b| b.largest_move.total_cmp(&a.largest_move));
        let list = |lines: &[&ShapeLine], value: &dyn Fn(&ShapeLine) -> String| {
            lines
                .iter()
                .take(5)
                .map(|l| format!("{} {}", l.name, value(l)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        say!(
            "largest moves (of the diagonal): {}",
            list(&largest, &|l| format!("{:.2} %", 100.0 * l.largest_move))
        );
        let mut differ: Vec<&ShapeLine> = self
            .shapes
            .iter()
            .filter(|l| l.methods_differ.is_some())
            .collect();
        if !differ.is_empty() {
            differ.sort_by(|a, b| {
                let d = |l: &ShapeLine| l.methods_differ.map_or(0.0, |(d, _)| d);
                d(b).total_cmp(&d(a))
            });
            say!(
                "the two ways differ most (of the diagonal): {}",
                list(&differ, &|l| {
                    let (d, v) = l.methods_differ.unwrap_or_default();
                    format!("{:.2} % at vertex {v}", 100.0 * d)
                })
            );
        }
        say!(
            "time: {} ({} fitting and carrying)",
            output::human_seconds(self.total_seconds),
            output::human_seconds(self.expressions_seconds)
        );
    }
}

/// A head as read: its mesh (placed in its scene, for a glTF head), and
/// what writing the outputs needs of its file.
struct Head {
    mesh: Mesh3,
    file: HeadFile,
}

enum HeadFile {
    Mesh(Box<WeldedFile>),
    Gltf(GltfDocument, Box<GltfMesh>),
}

impl Head {
    fn read(args: &Args) -> Result<Self> {
        let path = args.head();
        if is_gltf(path) {
            let (doc, mesh) = meshmorph::io::gltf::read(path, args.mesh.as_deref())
                .map_err(|e| output::reading_error(e, "head", path))?;
            let placed = mesh.placed(mesh.surface.positions());
            let head = mesh.surface.with_positions(placed)?;
            return Ok(Head {
                mesh: head,
                file: HeadFile::Gltf(doc, Box::new(mesh)),
            });
        }
        if args.mesh.is_some() {
            bail!(
                "--mesh chooses a mesh of a glTF or VRM head; `{}` is not one",
                path.display()
            );
        }
        let file: MeshFile = output::read_mesh_file(path, "head")?;
        // The library welds the copies at seams itself.
        let (file, mesh) = WeldedFile::new(file, false);
        Ok(Head {
            mesh,
            file: HeadFile::Mesh(Box::new(file)),
        })
    }
}

/// The template asked for, and what the report calls it.
fn read_template(args: &Args) -> Result<(ExpressionTemplate, String)> {
    if args.template == "arkit" {
        return Ok((
            ExpressionTemplate::arkit(),
            "arkit (ICT-FaceKit, MIT licence)".to_string(),
        ));
    }
    let path = Path::new(&args.template);
    let bytes = std::fs::read(path)
        .with_context(|| format!("reading the template `{}`", path.display()))?;
    let template = ExpressionTemplate::from_glb(&bytes, &path.display().to_string())?;
    Ok((template, format!("`{}`", path.display())))
}

/// Whether `path` names a text glTF (`.gltf`), which holds its data apart.
fn is_text_gltf(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf"))
}

/// Where the shapes go, refusing a glTF output that does not fit the head.
fn destination(args: &Args) -> Result<Destination> {
    let out = args.output();
    if !is_gltf(out) {
        if args.replace_shapes || args.vrm_expressions || args.gltf_dense {
            bail!("--replace-shapes, --vrm-expressions and --gltf-dense are for a glTF output (-o FILE.glb, .gltf or .vrm); `{}` is a directory", out.display());
        }
        if let Ok(format) = meshmorph::io::Format::from_path(out) {
            bail!(
                "-o `{}` names one {} file, but the shapes are one mesh each: give a folder (-o shapes/) for a mesh per shape, or a .glb for one file with every shape as a morph target",
                out.display(),
                format.extension().to_uppercase()
            );
        }
        let format = output::format_or_like(args.format, args.head())?;
        return Ok(Destination::Folder(format));
    }
    if args.format.is_some() {
        bail!(
            "--format is for -o DIR (one mesh per shape); `{}` is a glTF file",
            out.display()
        );
    }
    if is_gltf(args.head()) {
        if is_text_gltf(out) != is_text_gltf(args.head()) {
            bail!(
                "`{}` would hold a copy of `{}`, which is {}: name it as the head is named (.gltf for a text glTF; .glb or .vrm for a binary one)",
                out.display(),
                args.head().display(),
                if is_text_gltf(args.head()) { "a text glTF" } else { "a binary glTF" }
            );
        }
        return Ok(Destination::IntoHead);
    }
    if args.replace_shapes || args.vrm_expressions {
        bail!("--replace-shapes and --vrm-expressions add to a glTF or VRM head's own file; `{}` is not one", args.head().display());
    }
    pictures::file_named(&out.to_string_lossy(), "glb", "binary glTF")
        .map_err(anyhow::Error::msg)?;
    Ok(Destination::NewGlb)
}

/// `DIR/<name>.<ext>` for each shape, refusing a name that is not a plain
/// file name, or two names the same but for case.
fn shape_paths(dir: &Path, names: &[String], ext: &str) -> Result<Vec<PathBuf>> {
    let mut seen = HashSet::new();
    names
        .iter()
        .map(|name| {
            let plain = !name.is_empty()
                && name != "."
                && name != ".."
                && !name.chars().any(|c| {
                    matches!(c, '/' | '\\' | ':' | '*' | '?' | '"' | '<' | '>' | '|') || c.is_control()
                });
            if !plain {
                bail!("the template's shape `{name}` cannot be a file name: write the shapes into a glTF (-o FILE.glb) instead");
            }
            if !seen.insert(name.to_lowercase()) {
                bail!("two of the template's shapes are named `{name}` (but for case): their files would overwrite each other on some systems; write them into a glTF (-o FILE.glb) instead");
            }
            Ok(dir.join(format!("{name}.{ext}")))
        })
        .collect()
}

/// The head making a few of its shapes one after another, each from rest
/// to full and back.
struct ShapeTour<'a> {
    rest: &'a [[f64; 3]],
    shapes: Vec<&'a [[f64; 3]]>,
}

impl FrameSource<3> for ShapeTour<'_> {
    fn num_frames(&self) -> usize {
        self.shapes.len().max(1) * 2 * STEPS
    }

    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; 3]])) {
        let Some(delta) = self.shapes.get(k / (2 * STEPS)) else {
            return use_frame(self.rest);
        };
        let step = k % (2 * STEPS);
        let up = if step < STEPS {
            step
        } else {
            2 * STEPS - 1 - step
        };
        let w = up as f64 / (STEPS - 1) as f64;
        let posed: Vec<[f64; 3]> = self
            .rest
            .iter()
            .zip(delta.iter())
            .map(|(p, d)| std::array::from_fn(|i| p[i] + w * d[i]))
            .collect();
        use_frame(&posed)
    }
}

pub fn run(args: &Args) -> Result<()> {
    if !args.batch.is_empty() {
        return batch::run(args);
    }
    // The shapes' names are known only once the template is read; the
    // built-in template is read before any output is planned.
    let template = read_template(args)?;
    let planned = plan_head(args, &template.0)?;
    run_head(args, &template, planned).map(|_| ())
}

/// The files one head's run reads and writes, planned before any work.
struct Planned {
    destination: Destination,
    plan: Plan,
    /// The shapes the template will give.
    names: Vec<String>,
    /// The shapes' files (-o DIR), or the one glTF file.
    shape_outputs: Vec<Output>,
    shape_paths: Vec<PathBuf>,
    png: Option<Output>,
    gif: Option<Output>,
}

/// The plan of the head `args` names, with `template` (read already).
fn plan_head(args: &Args, template: &ExpressionTemplate) -> Result<Planned> {
    let destination = destination(args)?;
    let mut plan = Plan::new();
    plan.input(args.head(), "head");
    plan.input(args.markers(), "landmark file");
    if args.template != "arkit" {
        plan.input(Path::new(&args.template), "template");
    }
    let names = planned_names(template, args.all_shapes);
    let (shape_outputs, shape_paths) = match &destination {
        Destination::Folder(format) => {
            let paths = shape_paths(args.output(), &names, format.extension())?;
            let outputs: Vec<Output> = paths.iter().map(|p| plan.file(p, "shape")).collect();
            (outputs, paths)
        }
        _ => (
            vec![plan.file(args.output(), "glTF file")],
            vec![args.output().to_path_buf()],
        ),
    };
    let png = args
        .pictures
        .png
        .as_deref()
        .map(|p| plan.file(p, "picture"));
    let gif = args
        .pictures
        .gif
        .as_deref()
        .map(|p| plan.file(p, "animation"));
    Ok(Planned {
        destination,
        plan,
        names,
        shape_outputs,
        shape_paths,
        png,
        gif,
    })
}

/// What one head's run made, for a batch's totals.
struct Done {
    shapes: usize,
    expressions_seconds: f64,
}

/// Puts the shapes of `template` (read, with what the report calls it) on
/// the head `args` names, as `planned`.
fn run_head(
    args: &Args,
    (template, template_name): &(ExpressionTemplate, String),
    planned: Planned,
) -> Result<Done> {
    let start = Instant::now();
    let Planned {
        destination,
        plan,
        names,
        shape_outputs,
        shape_paths,
        png,
        gif,
    } = planned;
    let options = ExpressionOptions::default()
        .with_method(match args.method {
            MethodArg::Displacements => CarryMethod::Displacements,
            MethodArg::Transfer => CarryMethod::Transfer,
        })
        .with_compare(args.compare)
        .with_all_shapes(args.all_shapes);
    let staging = plan.prepare()?;
    memory::check_reading(&[args.head()])?;
    let head = Head::read(args)?;
    if let HeadFile::Mesh(file) = &head.file {
        output::protect_side_files(&staging, &file.file, "head")?;
    }
    let points = meshmorph::read_landmarks(args.markers(), &head.mesh, numbering(args.one_based))
        .map_err(|e| output::reading_error(e, "landmark file", args.markers()))?;
    memory::check_setup(head.mesh.num_triangles(), "the expressions")?;
    // A new GLB too heavy is refused before the work.
    let new_glb = GltfArgs {
        gltf: Some(args.output().to_path_buf()),
        max_gltf_mb: args.max_gltf_mb,
        gltf_quantize: false,
        gltf_dense: args.gltf_dense,
    };
    let texture_budget = match (&destination, &head.file) {
        (Destination::NewGlb, HeadFile::Mesh(file)) => new_glb.check_targets::<3>(
            Some(&file.file),
            &head.mesh,
            names.len(),
            "shapes",
            if args.all_shapes {
                "leave out --all-shapes, "
            } else {
                ""
            },
        )?,
        _ => 0,
    };

    let begin = Instant::now();
    let made = meshmorph::expressions(template, &head.mesh, &points, &options)
        .with_context(|| format!("putting the expressions on `{}`", args.head().display()))?;
    let expressions_seconds = begin.elapsed().as_secs_f64();
    if made.names != names {
        bail!(
            "the shapes made ({}) are not those planned ({})",
            made.names.join(", "),
            names.join(", ")
        );
    }
    let mut warnings = staging.warnings();
    warnings.extend(made.warnings.iter().cloned());
    let rest = head.mesh.positions();
    let posed: Vec<Vec<[f64; 3]>> = made
        .deltas
        .iter()
        .map(|d| {
            rest.iter()
                .zip(d)
                .map(|(p, d)| std::array::from_fn(|i| p[i] + d[i]))
                .collect()
        })
        .collect();
    if let Some(k) = posed
        .iter()
        .position(|p| p.iter().any(|x| x.iter().any(|c| !c.is_finite())))
    {
        bail!(
            "shape `{}` overflows (its coordinates exceed the range of floating-point numbers); scale the head down",
            made.names[k]
        );
    }

    let mut files_written = Vec::new();
    match (&destination, &head.file) {
        (Destination::Folder(format), HeadFile::Mesh(file)) => {
            for ((output, path), positions) in shape_outputs.iter().zip(&shape_paths).zip(&posed) {
                staging.write_to(*output, |to, w| {
                    let dropped = file.write_to(w, to, positions, *format)?;
                    if files_written.is_empty() {
                        warnings.extend(output::dropped_for(args.output(), &dropped));
                    }
                    Ok(())
                })?;
                files_written.push(path.clone());
            }
        }
        (Destination::Folder(format), HeadFile::Gltf(..)) => {
            for ((output, path), positions) in shape_outputs.iter().zip(&shape_paths).zip(&posed) {
                staging.write_to(*output, |to, w| {
                    meshmorph::io::write_positions_to(
                        w,
                        to,
                        positions,
                        head.mesh.triangles(),
                        *format,
                    )?;
                    Ok(())
                })?;
                files_written.push(path.clone());
            }
        }
        (Destination::IntoHead, HeadFile::Gltf(doc, mesh)) => {
            let options = ShapeKeyOptions::default()
                .with_replace(args.replace_shapes)
                .with_vrm_expressions(args.vrm_expressions)
                .with_sparse(!args.gltf_dense);
            crate::gltf::write_shapes_into(
                &staging,
                shape_outputs[0],
                (args.head(), doc, mesh),
                &made.names,
                &posed,
                &options,
            )?;
            files_written.push(args.output().to_path_buf());
        }
        (Destination::NewGlb, HeadFile::Mesh(file)) => {
            let look = Appearance::of_file(&file.file, texture_budget)?;
            let base = look.base(rest, head.mesh.triangles());
            let options = GltfOptions::default()
                .with_animation(false)
                .with_name(crate::gltf::mesh_name(args.head()));
            staging.write(shape_outputs[0], |path| {
                let mut staged = new_glb.clone();
                staged.gltf = Some(path.to_path_buf());
                staged.write(&base, &posed, &made.names, &options)?;
                Ok(())
            })?;
            warnings.extend(look.warnings);
            files_written.push(args.output().to_path_buf());
        }
        _ => unreachable!("a glTF destination is chosen by the head's kind"),
    }

    let tour = ShapeTour {
        rest,
        shapes: SHOWN
            .iter()
            .filter_map(|s| made.names.iter().position(|n| n == s))
            .map(|k| made.deltas[k].as_slice())
            .collect(),
    };
    let triangles = head.mesh.triangles();
    let draw = &args.pictures.draw;
    if let (Some(output), Some(path)) = (png, &args.pictures.png) {
        // The first three shapes shown, each at full.
        let mut stills: Vec<(String, Vec<[f64; 3]>)> = SHOWN
            .iter()
            .filter_map(|s| made.names.iter().position(|n| n == s))
            .take(3)
            .map(|k| (made.names[k].clone(), posed[k].clone()))
            .collect();
        if stills.is_empty() {
            stills.push(("rest".to_string(), rest.to_vec()));
        }
        let frames: Vec<&[[f64; 3]]> = stills.iter().map(|(_, p)| p.as_slice()).collect();
        staging.write(output, |p| {
            pictures::write_png::<3>(p, &frames, triangles, draw, |k| stills[k].0.clone())
        })?;
        files_written.push(path.clone());
    }
    if let (Some(output), Some(path)) = (gif, &args.pictures.gif) {
        // Each shape already goes from rest to full and back.
        let mut once = draw.clone();
        once.no_boomerang = true;
        staging.write(output, |p| {
            pictures::write_gif::<3>(p, &tour, triangles, &once)
        })?;
        files_written.push(path.clone());
    }
    output::print_warnings(&warnings);
    staging.commit()?;
    let shapes = made.names.len();
    report(
        args,
        &head,
        made,
        template_name.clone(),
        points.len(),
        expressions_seconds,
    )
    .with_files(files_written, warnings, start)
    .print(args.json);
    Ok(Done {
        shapes,
        expressions_seconds,
    })
}

/// The names of the shapes `template` will give (as
/// [`meshmorph::arkit_recipes`] makes them).
fn planned_names(template: &ExpressionTemplate, all_shapes: bool) -> Vec<String> {
    let (recipes, _) = meshmorph::arkit_recipes(&template.shape_names, all_shapes);
    recipes.into_iter().map(|r| r.name).collect()
}

fn report(
    args: &Args,
    head: &Head,
    made: HeadExpressions,
    template: String,
    landmarks: usize,
    expressions_seconds: f64,
) -> Report {
    Report {
        head: args.head().to_path_buf(),
        mesh: match &head.file {
            HeadFile::Gltf(_, mesh) => Some(mesh.name.clone()),
            HeadFile::Mesh(_) => None,
        },
        vertices: head.mesh.num_vertices(),
        triangles: head.mesh.num_triangles(),
        template,
        landmarks,
        method: match args.method {
            MethodArg::Displacements => "displacements",
            MethodArg::Transfer => "deformation transfer",
        },
        shapes: made
            .report
            .into_iter()
            .map(|r| ShapeLine {
                name: r.name,
                moved_vertices: r.moved,
                largest_move: r.largest,
                methods_differ: r.methods_differ,
            })
            .collect(),
        missing: made.missing,
        parts: made
            .parts
            .into_iter()
            .map(|p| PartLine {
                vertices: p.vertices,
                follows: p.follows,
            })
            .collect(),
        expressions_seconds,
        total_seconds: 0.0,
        output: args.output().to_path_buf(),
        files_written: Vec::new(),
        warnings: Vec::new(),
    }
}

impl Report {
    fn with_files(mut self, files: Vec<PathBuf>, warnings: Vec<String>, start: Instant) -> Self {
        self.files_written = files;
        self.warnings = warnings;
        self.total_seconds = start.elapsed().as_secs_f64();
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_are_told_once_for_each_template_part_they_follow() {
        let part = |vertices, follows: Option<&str>| PartLine {
            vertices,
            follows: follows.map(str::to_string),
        };
        let parts = [
            part(100, Some("gumsTongue")),
            part(10, Some("teethUpper")),
            part(12, None),
            part(11, Some("teethUpper")),
            part(3, None),
            part(7, Some("eyeLeft")),
        ];
        assert_eq!(
            by_part_followed(&parts),
            [
                (Some("gumsTongue"), 1, 100),
                (Some("teethUpper"), 2, 21),
                (None, 2, 15),
                (Some("eyeLeft"), 1, 7),
            ]
        );
    }
}
