//! `meshmorph blend`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use meshmorph::io::gltf::{write_glb_frames, GltfOptions};
use meshmorph::io::Appearance;
use meshmorph::io::{Format, MeshFile};

use crate::output::WeldedFile;
use meshmorph::{Blend, Dimension, FrameSource, InterpolatorOptions, Mesh, Mesh2, Mesh3, Space};
use serde::Serialize;

use crate::gltf::GltfArgs;
use crate::memory;
use crate::output::{self, FormatArg};
use crate::outputs::Staging;
use crate::outputs::{Output, Plan};
use crate::pictures::{self, PictureArgs};

/// Blend shapes of a base mesh with weights, as rigidly as possible, in the
/// plane or in space.
///
/// Writes OUT: BASE moved by SHAPE1 x W1 + SHAPE2 x W2 + ... Per triangle
/// the rotations (as rotation vectors) and the logarithms of the stretches
/// from the base to each shape are combined with the weights (Baxter,
/// Barla and Anjyo 2008), then one least-squares solve places the
/// vertices. A weight of 1 on one shape and 0 on the others gives that
/// shape; weights may be negative or above 1 (extrapolation): stretches
/// always combine by their logarithms (the S^t rule of `interpolate
/// --stretch log`), so nothing collapses.
///
/// Inputs are never written, and OUT (with the pictures) is written all or
/// nothing, as for every command.
#[derive(Debug, clap::Args)]
#[command(
    mut_arg("png", |a| a.help("Also write a still picture (PNG) of the base, the blend about halfway and the blend, side by side")),
    mut_arg("gif", |a| a.help("Also write an animated GIF of the base turning into the blend, the weights growing from 0 to theirs")),
    mut_arg("gltf", |a| a.help("Also write one binary glTF (FILE.glb) for Blender, three.js or any glTF viewer: the base with the way to the blend (24 steps) as morph targets and an animation playing them at --fps")),
)]
pub struct Args {
    /// The base mesh (OBJ, OFF, PLY or STL).
    pub base: PathBuf,
    /// A shape and its weight, FILE=WEIGHT (repeat for more shapes; the
    /// weight any finite number); every shape has the base's vertices and
    /// triangles.
    #[arg(long = "shape", required = true, value_name = "FILE=WEIGHT", value_parser = parse_shape, allow_hyphen_values = true)]
    pub shapes: Vec<(PathBuf, f64)>,
    /// The blended mesh to write.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Output mesh format [default: from OUT's extension].
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Planar (2) or in space (3) [default: 2 when every z of every mesh is 0].
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=3), value_name = "2|3")]
    pub dim: Option<u8>,
    /// Combine each triangle's principal rotations as they are, without
    /// making them continuous across neighbours.
    #[arg(long)]
    pub no_consistency: bool,
    /// Go on when a shape has triangles turned over relative to the base.
    #[arg(long)]
    pub allow_flips: bool,
    /// Keep apart vertices that share a place. By default copies at seams
    /// (vertices at exactly one place in the base and every shape whose neighbours coincide too, as
    /// UV seams and edge splits leave them) are welded for the solve, so that
    /// the surface does not crack along them; the files keep their vertices.
    #[arg(long)]
    pub no_weld: bool,
    /// `--png` and `--gif`, with their help for blends (above).
    #[command(flatten)]
    pub pictures: PictureArgs,
    #[command(flatten)]
    pub gltf: GltfArgs,
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Steps of the pictures and of the GLB, from the base to the blend.
const STEPS: usize = 24;

/// `FILE=WEIGHT`, split at the last `=`; the weight a finite number.
fn parse_shape(text: &str) -> Result<(PathBuf, f64), String> {
    let Some((file, weight)) = text.rsplit_once('=') else {
        return Err(format!(
            "`{text}`: expected FILE=WEIGHT, e.g. smile.obj=0.5"
        ));
    };
    if file.is_empty() {
        return Err(format!("`{text}`: no file before `=`"));
    }
    match weight.trim().parse::<f64>() {
        Ok(w) if w.is_finite() => Ok((PathBuf::from(file), w)),
        _ => Err(format!(
            "`{text}`: the weight `{weight}` is not a finite number"
        )),
    }
}

/// What a run did.
#[derive(Debug, Serialize)]
pub struct Report {
    /// The file written.
    #[serde(serialize_with = "output::lossy")]
    pub output: PathBuf,
    /// 2 for planar meshes, 3 for meshes in space.
    pub dimension: usize,
    /// Vertices of the mesh.
    pub vertices: usize,
    /// Triangles of the mesh.
    pub triangles: usize,
    /// Number of shapes blended.
    pub shapes: usize,
    /// Preparing the blend: decompositions, factorization.
    pub setup_seconds: f64,
    /// Computing the blend.
    pub blend_seconds: f64,
    /// Wall time of the whole command.
    pub total_seconds: f64,
    /// Triangles of the result turned over relative to the base.
    pub turned_over_triangles: usize,
    /// Separate parts (eyes, teeth) placed by the surface they sit in.
    pub parts_following_host: usize,
    /// The PNG written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub png: Option<PathBuf>,
    /// The GIF written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub gif: Option<PathBuf>,
    /// The GLB written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub gltf: Option<PathBuf>,
    /// Every file written.
    #[serde(serialize_with = "output::lossy")]
    pub files_written: Vec<PathBuf>,
    /// The warnings given (also printed on stderr).
    pub warnings: Vec<String>,
    /// Vertices at the same place as another in the base and every shape
    /// (copies at seams), welded for the solve; the result keeps them.
    pub welded_vertices: usize,
}

impl Report {
    fn print(&self, json: bool) {
        if json {
            output::print_json(self);
            return;
        }
        say!(
            "wrote {} ({}, {}, {}, {})",
            self.output.display(),
            output::vertices(self.vertices),
            output::count(self.triangles, "triangle"),
            output::count(self.shapes, "shape"),
            if self.dimension == 3 {
                "in space"
            } else {
                "planar"
            }
        );
        say!("setup: {}", output::human_seconds(self.setup_seconds));
        say!("blend: {}", output::human_seconds(self.blend_seconds));
        say!("total: {}", output::human_seconds(self.total_seconds));
        say!("turned-over triangles: {}", self.turned_over_triangles);
        if let Some(line) = output::following_line(self.parts_following_host) {
            say!("parts: {line}");
        }
        if let Some(line) = output::welded_line(self.welded_vertices) {
            say!("welded: {line}");
        }
        output::print_files(
            &[
                ("picture:", self.png.as_deref()),
                ("animation:", self.gif.as_deref()),
                ("glTF:", self.gltf.as_deref()),
            ],
            11,
        );
    }
}

/// The outputs of a blend.
struct Outputs {
    mesh: Output,
    png: Option<Output>,
    gif: Option<Output>,
    gltf: Option<Output>,
}

pub fn run(args: &Args) -> Result<()> {
    let start = Instant::now();
    let format = output::format_or_like(args.format, &args.output)?;
    if let Ok(named) = Format::from_path(&args.output) {
        if named != format {
            bail!(
                "the output `{}` is named as {named} but --format asks for {format}: name it .{format}, or leave --format out",
                args.output.display()
            );
        }
    }
    let mut plan = Plan::new();
    plan.input(&args.base, "base mesh");
    for (path, _) in &args.shapes {
        plan.input(path, "blend shape");
    }
    let outputs = Outputs {
        mesh: plan.file(&args.output, "blend"),
        png: args
            .pictures
            .png
            .as_deref()
            .map(|p| plan.file(p, "picture")),
        gif: args
            .pictures
            .gif
            .as_deref()
            .map(|p| plan.file(p, "animation")),
        gltf: args.gltf.gltf.as_deref().map(|p| plan.file(p, "glTF file")),
    };
    let staging = plan.prepare()?;
    let mut paths: Vec<&Path> = vec![&args.base];
    paths.extend(args.shapes.iter().map(|(p, _)| p.as_path()));
    memory::check_reading(&paths)?;
    let mut roles = vec!["base mesh"];
    roles.extend(args.shapes.iter().map(|_| "blend shape"));
    let mut warnings = staging.warnings();
    warnings.extend(output::gif_rate_warning(
        args.pictures.gif.is_some(),
        args.pictures.draw.fps,
    ));
    let (base_file, mut shapes) = output::read_poses(&paths, &roles, !args.no_weld, &mut warnings)?;
    output::protect_side_files(&staging, &base_file.file, "base mesh")?;
    let base = shapes.remove(0);
    let meshes: Vec<&Mesh3> = std::iter::once(&base).chain(&shapes).collect();
    let paths: Vec<&PathBuf> = std::iter::once(&args.base)
        .chain(args.shapes.iter().map(|(p, _)| p))
        .collect();
    let planar = output::is_planar(args.dim, &meshes, |k| format!("`{}`", paths[k].display()))?;
    let triangles = base.num_triangles();
    let image_budget = if planar {
        args.gltf.check::<2>(Some(&base_file.file), &base, STEPS)?
    } else {
        args.gltf.check::<3>(Some(&base_file.file), &base, STEPS)?
    };
    memory::check_setup(triangles, "the blend")?;
    memory::check_sequence(triangles, shapes.len())?;
    let options = InterpolatorOptions::default()
        .with_consistency(!args.no_consistency)
        .with_allow_flips(args.allow_flips);
    let run = BlendRun {
        args,
        outputs: &outputs,
        staging: &staging,
        options: &options,
        file: (&base_file, format),
        image_budget,
    };
    let blended = if planar {
        let base = base.to_2d()?;
        let shapes = shapes
            .iter()
            .map(Mesh3::to_2d)
            .collect::<meshmorph::Result<Vec<Mesh2>>>()?;
        blend_and_write(&run, &base, &shapes, &mut warnings)
    } else {
        blend_and_write(&run, &base, &shapes, &mut warnings)
    }?;
    let Blended {
        turned_over,
        parts_following_host,
        files_written,
        setup_seconds,
        blend_seconds,
    } = blended;
    if turned_over > 0 {
        warnings.push(format!(
            "the blend has {} turned over relative to the base",
            output::count(turned_over, "triangle")
        ));
    }
    output::print_warnings(&warnings);
    staging.commit()?;
    Report {
        output: args.output.clone(),
        dimension: if planar { 2 } else { 3 },
        vertices: base.num_vertices() + base_file.seams.num_welded(),
        triangles,
        shapes: shapes.len(),
        setup_seconds,
        blend_seconds,
        total_seconds: start.elapsed().as_secs_f64(),
        turned_over_triangles: turned_over,
        parts_following_host,
        png: args.pictures.png.clone(),
        gif: args.pictures.gif.clone(),
        gltf: args.gltf.gltf.clone(),
        files_written,
        warnings,
        welded_vertices: base_file.seams.num_welded(),
    }
    .print(args.json);
    Ok(())
}

/// What writing a blend needs besides its meshes.
struct BlendRun<'a> {
    args: &'a Args,
    outputs: &'a Outputs,
    staging: &'a Staging,
    options: &'a InterpolatorOptions,
    /// The base's file, and the format of the output.
    file: (&'a WeldedFile, Format),
    /// The bytes the GLB's textures may take (see
    /// [`GltfArgs::check`](crate::gltf::GltfArgs::check)).
    image_budget: u64,
}

/// What the report says of a blend written.
struct Blended {
    turned_over: usize,
    parts_following_host: usize,
    files_written: Vec<PathBuf>,
    setup_seconds: f64,
    blend_seconds: f64,
}

/// Blends `shapes` onto `base` with the weights asked for, and writes the
/// blend (with `D` coordinates) and the PNG, GIF and GLB asked for, of the
/// way from the base to it; adds to `warnings` what the output format could
/// not hold of the base's file.
fn blend_and_write<const D: usize>(
    run: &BlendRun<'_>,
    base: &Mesh<D>,
    shapes: &[Mesh<D>],
    warnings: &mut Vec<String>,
) -> Result<Blended>
where
    Space<D>: Dimension<D>,
{
    let BlendRun {
        args,
        outputs,
        staging,
        options,
        file: (file, format),
        image_budget,
    } = *run;
    let context = || format!("blending `{}`", args.base.display());
    let setup = Instant::now();
    let blend = Blend::new(base, shapes, options)
        .map_err(|e| output::degenerate_faces(e, &file.file, "base"))
        .map_err(|e| name_shape_files(e, &file.file, &args.shapes))
        .with_context(context)?;
    let setup_seconds = setup.elapsed().as_secs_f64();
    let weights: Vec<f64> = args.shapes.iter().map(|(_, w)| *w).collect();
    let begin = Instant::now();
    let result = blend.at(&weights);
    let blend_seconds = begin.elapsed().as_secs_f64();
    if let Some(v) = result.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
        bail!("the blend's vertex {v} overflows (its coordinates exceed the range of floating-point numbers): use smaller weights");
    }
    let turned_over = blend.count_turned_over(&result);
    let triangles = blend.triangles();
    // The base's file with the blend's positions (z = 0 in the plane).
    staging.write_to(outputs.mesh, |path, w| {
        let dropped = file.write_to(w, path, &pictures::in_dim::<D, 3>(&result), format)?;
        warnings.extend(output::dropped_for(&args.output, &dropped));
        Ok(())
    })?;
    let mut written = vec![args.output.clone()];
    let steps = Steps {
        blend: &blend,
        weights: &weights,
    };
    let draw = &args.pictures.draw;
    if let (Some(output), Some(path)) = (outputs.png, &args.pictures.png) {
        let caption = |k: usize| match k {
            0 => "base".to_string(),
            k if k + 1 == STEPS => "blend".to_string(),
            k => format!("weights x {:.2}", k as f64 / (STEPS - 1) as f64),
        };
        staging.write(output, |p| {
            pictures::write_png::<D>(p, &steps, triangles, draw, caption)
        })?;
        written.push(path.clone());
    }
    if let (Some(output), Some(path)) = (outputs.gif, &args.pictures.gif) {
        staging.write(output, |p| {
            pictures::write_gif::<D>(p, &steps, triangles, draw)
        })?;
        written.push(path.clone());
    }
    if let (Some(output), Some(path)) = (outputs.gltf, &args.gltf.gltf) {
        let names: Vec<String> = (0..STEPS).map(|k| format!("blend_{k:02}")).collect();
        let options = args.gltf.options(
            GltfOptions::default()
                .with_fps(draw.fps)
                .with_name(crate::gltf::mesh_name(&args.base)),
        );
        let look = Appearance::of_file(&file.file, image_budget)?;
        warnings.extend(look.warnings.iter().cloned());
        let gltf_base = look.base(base.positions(), triangles);
        staging.write(output, |p| {
            Ok(write_glb_frames(p, &gltf_base, &steps, &names, &options)?)
        })?;
        written.push(path.clone());
    }
    Ok(Blended {
        turned_over,
        parts_following_host: blend.parts_following_host(),
        files_written: written,
        setup_seconds,
        blend_seconds,
    })
}

/// The way from the base to the blend in [`STEPS`] frames (weights `s ·
/// weights` for `s` from 0 to 1), each computed when a picture or the GLB
/// asks for it.
struct Steps<'a, const D: usize>
where
    Space<D>: Dimension<D>,
{
    blend: &'a Blend<D>,
    weights: &'a [f64],
}

impl<const D: usize> FrameSource<D> for Steps<'_, D>
where
    Space<D>: Dimension<D>,
{
    fn num_frames(&self) -> usize {
        STEPS
    }

    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; D]])) {
        let s = k as f64 / (STEPS - 1) as f64;
        let scaled: Vec<f64> = self.weights.iter().map(|w| s * w).collect();
        use_frame(&self.blend.at(&scaled))
    }
}

/// The library numbers the shapes ("blend shape 1", ...), calls the base
/// "the base" and numbers triangles after splitting polygons; say the files
/// and their faces instead.
fn name_shape_files(
    e: meshmorph::Error,
    base: &MeshFile,
    shapes: &[(PathBuf, f64)],
) -> anyhow::Error {
    let flips = output::PoseFiles {
        first: base,
        first_role: "base",
        label: "blend shape",
        poses: shapes
            .iter()
            .map(|(p, _)| ("blend shape", p.as_path()))
            .collect(),
    };
    let e = output::turned_over_faces(e, &flips);
    let Some(lib) = e.downcast_ref::<meshmorph::Error>() else {
        return e;
    };
    let mut text = lib.to_string();
    for (k, (path, _)) in shapes.iter().enumerate() {
        text = output::name_label(&text, &format!("blend shape {}", k + 1), path);
    }
    anyhow::anyhow!(output::name_label(&text, "the base", base.path()))
}
