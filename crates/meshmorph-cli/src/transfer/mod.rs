//! `meshmorph transfer`: the poses of a source carried over to a target.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use meshmorph::io::gltf::{GltfOptions, ShapeKeyOptions};
use meshmorph::io::Appearance;
use meshmorph::{Correspondence, Mesh3, Transfer, TransferOptions};
use rayon::prelude::*;

use crate::gltf::GltfArgs;
use crate::memory;
use crate::output::{self, FormatArg};
use crate::outputs::{Output, Plan, Staging};
use crate::pictures::PictureArgs;
use crate::progress;
mod batch;
mod correspondence;
mod fit;
mod report;

use correspondence::name_degenerate_faces;
pub(crate) use correspondence::{numbering, print_welded, signed_for, MarkerReport};
pub use correspondence::{CorrespondArgs, References};
pub(crate) use correspondence::{Reference, Rig};
pub use fit::FitSummary;
pub(crate) use report::print_unmatched;
use report::TransferReport;

/// Carry the poses of a source mesh over to a target mesh, or to many
/// targets at once (--batch).
///
/// Writes one mesh per pose: DIR/<the pose file's stem>.<ext>.
#[derive(Debug, Clone, clap::Args)]
#[command(
    after_long_help = batch::FORMAT,
    mut_arg("one_based", |a| a.help("Vertex indices (markers and --pin) start at 1 instead of 0")),
    mut_arg("png", |a| a.help("Also write a still picture (PNG): source poses above, transferred poses below (the first, middle and last)")),
    mut_arg("gif", |a| a.help("Also write an animated GIF: every source pose above its transferred pose")),
    mut_arg("gltf", |a| a.help("Also write one binary glTF (FILE.glb) for Blender, three.js or any glTF viewer: the target reference with every transferred pose as a morph target, and an animation playing the poses in order at --fps (see --gltf-shapes). It weighs about 24 bytes x target vertices x poses: a 10,000-vertex target with 100 poses makes 24 MB")),
)]
pub struct TransferArgs {
    #[command(flatten)]
    pub refs: Option<References>,
    /// A batch file (TOML or JSON): one source and its poses, and any number
    /// of targets, each with its markers or saved correspondence and its
    /// output directory (its form is at the end of `--help`). One
    /// correspondence a target; each target written all or
    /// nothing; a target that fails is reported and the others go on.
    /// Repeat it to run several batches together. The other options here
    /// apply to every target.
    #[arg(
        long,
        value_name = "FILE",
        conflicts_with_all = ["source_ref", "target_ref", "markers", "no_markers", "correspondence", "save_correspondence", "pin", "output", "gltf", "png", "gif", "poses"]
    )]
    pub batch: Vec<PathBuf>,
    #[command(flatten)]
    pub correspond: CorrespondArgs,
    /// Reuse a correspondence saved by --save-correspondence or `meshmorph
    /// correspond` (then no markers are needed).
    #[arg(long, value_name = "FILE", conflicts_with = "markers")]
    pub correspondence: Option<PathBuf>,
    /// Save the correspondence computed from the markers.
    #[arg(long, value_name = "FILE")]
    pub save_correspondence: Option<PathBuf>,
    /// Target vertices (comma-separated, 0-based unless --one-based) held at
    /// their rest positions in every pose: the parts of the target that hold
    /// one are placed by them, instead of by the shift most of their pairs
    /// agree on (the weighted geometric median of the pairs' shifts).
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LIST",
        allow_hyphen_values = true,
        value_parser = vertex_index
    )]
    pub pin: Vec<u32>,
    /// Directory for the transferred poses (created if missing); not
    /// needed when --gltf takes them.
    #[arg(short, long, value_name = "DIR", required_unless_present_any = ["batch", "gltf"])]
    pub output: Option<PathBuf>,
    /// Output mesh format [default: the target reference's].
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub gltf: GltfArgs,
    /// With --gltf: write the poses as shape keys (morph targets at weight
    /// 0), without the animation.
    #[arg(long, requires = "gltf")]
    pub gltf_shapes: bool,
    /// With a glTF or VRM --source-ref and no pose files: the morph targets
    /// to carry over (comma-separated names) [default: every one].
    #[arg(long, value_delimiter = ',', value_name = "LIST")]
    pub shapes: Vec<String>,
    /// With a glTF or VRM --target-ref and --gltf: a pose whose name the
    /// target mesh already has as a shape key replaces it (else refused).
    #[arg(long, requires = "gltf")]
    pub replace_shapes: bool,
    /// With a VRM --target-ref and --gltf: also add each transferred shape
    /// as a custom expression of the same name.
    #[arg(long, requires = "gltf")]
    pub vrm_expressions: bool,
    #[command(flatten)]
    pub pictures: PictureArgs,
    /// Source poses: new positions for the source reference's vertices, with
    /// its faces (listed in any corner order or winding). With a glTF or
    /// VRM --source-ref and none given, its morph targets are the poses.
    #[arg(value_name = "POSE")]
    pub poses: Vec<PathBuf>,
}

impl TransferArgs {
    /// The two references (clap asks for them unless --batch is given).
    fn references(&self) -> Result<&References> {
        self.refs
            .as_ref()
            .context("--source-ref and --target-ref are needed (or --batch FILE)")
    }

    /// Whether --gltf writes into a copy of a glTF or VRM --target-ref
    /// (else it is a binary glTF made from scratch, named `.glb`).
    pub fn writes_into_gltf_target(&self) -> bool {
        self.refs
            .as_ref()
            .is_some_and(|r| crate::gltf::is_gltf(&r.target_ref))
    }

    /// The output directory, when pose files are written (clap asks for
    /// it unless --batch or --gltf is given).
    fn output_dir(&self) -> Option<&Path> {
        self.output.as_deref()
    }
}

/// The morph targets of a glTF source (those `shapes` names, else every
/// one) as poses of its welded mesh, placed as the mesh is.
fn rig_poses(rig: &Rig, source_ref: &Reference, shapes: &[String]) -> Result<Vec<(String, Mesh3)>> {
    let targets = &rig.mesh.targets;
    if targets.is_empty() {
        bail!(
            "the source reference's mesh `{}` has no morph targets to carry over: give pose files",
            rig.mesh.name
        );
    }
    let chosen: Vec<&meshmorph::io::gltf::MorphTarget> = if shapes.is_empty() {
        targets.iter().collect()
    } else {
        shapes
            .iter()
            .map(|name| {
                targets.iter().find(|t| &t.name == name).with_context(|| {
                    format!(
                        "--shapes {name}: mesh `{}` has no such morph target; it has {}",
                        rig.mesh.name,
                        rig.mesh.target_names().join(", ")
                    )
                })
            })
            .collect::<Result<_>>()?
    };
    let seams = &source_ref.file.seams;
    chosen
        .into_iter()
        .map(|t| {
            let placed = rig.mesh.placed(&t.positions);
            let pose = source_ref
                .mesh
                .with_positions(seams.weld_positions(&placed))?;
            Ok((t.name.clone(), pose))
        })
        .collect()
}

/// A vertex index (0 or more).
fn vertex_index(text: &str) -> Result<u32, String> {
    match text.trim().parse::<i128>() {
        Ok(v) if v < 0 => Err(format!("{v} is not a vertex index: indices count from 0")),
        Ok(v) => u32::try_from(v).map_err(|_| format!("{v} is too large for a vertex index")),
        Err(_) => Err(format!("`{text}` is not a vertex index")),
    }
}

/// One pose done: seconds solving, seconds with reading and writing, what
/// the output format dropped, the positions (kept for the glTF and pictures).
type SolvedPose = (f64, f64, Vec<String>, Option<Vec<[f64; 3]>>);

/// `meshmorph transfer`: one target, or a batch.
pub fn run(args: &TransferArgs) -> Result<()> {
    if args.batch.is_empty() {
        run_transfer(args).map(|_| ())
    } else {
        batch::run(args)
    }
}

/// Carries the poses to the target and prints the report; returns how many
/// poses were written and the seconds in the correspondence and in the
/// transfer.
pub fn run_transfer(args: &TransferArgs) -> Result<Done> {
    let start = Instant::now();
    let refs = args.references()?;
    let output_dir = args.output_dir();
    let from_rig = args.poses.is_empty();
    if from_rig {
        if !crate::gltf::is_gltf(&refs.source_ref) {
            bail!("no source poses: give pose files, or a glTF or VRM --source-ref whose morph targets are the poses");
        }
        if output_dir.is_some() {
            bail!("--output writes pose files for pose files given; the morph targets of a glTF source go into --gltf");
        }
    } else if !args.shapes.is_empty() {
        bail!("--shapes chooses morph targets of a glTF source; with pose files, list the files instead");
    }
    // Every output is checked against every input (by resolved path) before
    // anything is read or computed.
    let Planned {
        plan,
        format,
        outputs,
        pose_outputs,
        save,
        gltf_output,
        pictures,
    } = plan_transfer(args)?;
    let staging = plan.prepare()?;
    let mut read: Vec<&Path> = args.poses.iter().map(PathBuf::as_path).collect();
    read.extend([refs.source_ref.as_path(), refs.target_ref.as_path()]);
    memory::check_reading(&read)?;
    let (source_ref, target_ref) = refs.read()?;
    output::protect_side_files(&staging, &source_ref.file.file, "source reference")?;
    output::protect_side_files(&staging, &target_ref.file.file, "target reference")?;
    let (source, target) = (&source_ref.mesh, &target_ref.mesh);
    let rig_poses = match (from_rig, &source_ref.rig) {
        (true, Some(rig)) => rig_poses(rig, &source_ref, &args.shapes)?,
        _ => Vec::new(),
    };
    let pose_names: Vec<String> = if from_rig {
        rig_poses.iter().map(|(name, _)| name.clone()).collect()
    } else {
        args.poses
            .iter()
            .map(|p| crate::gltf::mesh_name(p))
            .collect()
    };
    let image_budget = if target_ref.rig.is_some() {
        0
    } else {
        args.gltf
            .check::<3>(Some(&target_ref.file.file), target, pose_names.len())?
    };
    let pins = pin_positions(&args.pin, args.correspond.one_based, &target_ref)?;

    // Each pose is new positions for the reference's faces, split as the
    // reference is. The first pose is read and checked at once (a pose of
    // another mesh is reported before the slow correspondence), the others
    // while the correspondence and the setup run (they leave a core mostly
    // idle). A bad pose is reported, ahead of any error of theirs, before
    // anything is written.
    let (first, others) = args.poses.split_at(args.poses.len().min(1));
    let mut read = read_poses(first, &source_ref)?;
    read.poses
        .extend(rig_poses.into_iter().map(|(_, pose)| (pose, 0, 0.0)));
    let (others, prepared) = rayon::join(
        || read_poses(others, &source_ref),
        || prepare(args, refs, &source_ref, &target_ref, pins),
    );
    read.append(others?);
    let ReadPoses {
        poses,
        warnings: read_warnings,
    } = read;
    let mut warnings = staging.warnings();
    warnings.extend(read_warnings);
    warnings.extend(output::gif_rate_warning(
        args.pictures.gif.is_some(),
        args.pictures.draw.fps,
    ));
    let reordered_pose_faces = poses.iter().map(|(_, reordered, _)| reordered).sum();
    let Prepared {
        correspondence,
        marker_report,
        fit,
        transfer,
        correspondence_seconds,
        setup_seconds,
        warnings: preparation_warnings,
    } = prepared?;
    warnings.extend(preparation_warnings);

    let bar = progress::bar(poses.len() as u64, "poses");
    if let Some(save) = save {
        let on_file = signed_for(
            &correspondence,
            source_ref.file_mesh(),
            target_ref.file_mesh(),
        );
        staging.write(save, |path| Ok(on_file.save(path)?))?;
    }
    let keep = args.gltf.gltf.is_some() || args.pictures.any();
    let solved: Vec<SolvedPose> = poses
        .par_iter()
        .enumerate()
        .map_init(
            || transfer.workspace(),
            |ws, (k, (pose, _, read))| {
                let begin = Instant::now();
                let mut out = vec![[0.0; 3]; target.num_vertices()];
                transfer.apply_into(pose.positions(), &mut out, ws);
                let solve = begin.elapsed().as_secs_f64();
                let mut dropped = Vec::new();
                if let Some(v) = out.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
                    bail!("vertex {v} overflows (its coordinates exceed the range of floating-point numbers); scale the meshes down");
                }
                if let Some(&output) = pose_outputs.get(k) {
                    staging.write_to(output, |path, w| {
                        dropped = target_ref.file.write_to(w, path, &out, format)?;
                        Ok(())
                    })?;
                }
                bar.inc(1);
                Ok((
                    solve,
                    read + begin.elapsed().as_secs_f64(),
                    dropped,
                    keep.then_some(out),
                ))
            },
        )
        .collect::<Result<_>>()?;
    bar.finish_and_clear();
    if let (Some((_, _, dropped, _)), Some(dir)) = (solved.first(), output_dir) {
        // The same for every pose: said once, for the directory.
        warnings.extend(output::dropped_for(dir, dropped));
    }
    let mut timings = Vec::with_capacity(solved.len());
    let mut results = Vec::new();
    for (solve, with_io, _, result) in solved {
        timings.push((solve, with_io));
        results.extend(result);
    }
    let mut files_written: Vec<PathBuf> = args.save_correspondence.iter().cloned().collect();
    files_written.extend(outputs.iter().cloned());
    let names = &pose_names;
    let options = GltfOptions::default()
        .with_fps(args.pictures.draw.fps)
        .with_animation(!args.gltf_shapes)
        .with_name(crate::gltf::mesh_name(&refs.target_ref));
    let mut gltf = None;
    if let (Some(output), Some(rig)) = (gltf_output, &target_ref.rig) {
        let placed: Vec<Vec<[f64; 3]>> = results
            .iter()
            .map(|welded| target_ref.file.seams.unweld(welded))
            .collect();
        let options = ShapeKeyOptions::default()
            .with_replace(args.replace_shapes)
            .with_vrm_expressions(args.vrm_expressions)
            .with_sparse(!args.gltf.gltf_dense);
        crate::gltf::write_shapes_into(
            &staging,
            output,
            (&refs.target_ref, &rig.doc, &rig.mesh),
            names,
            &placed,
            &options,
        )?;
        gltf = args.gltf.gltf.clone();
        files_written.extend(gltf.clone());
    } else if let Some(output) = gltf_output {
        if args.replace_shapes || args.vrm_expressions {
            bail!("--replace-shapes and --vrm-expressions add to a glTF or VRM --target-ref's own file; `{}` is not one", refs.target_ref.display());
        }
        let look = Appearance::of_file(&target_ref.file.file, image_budget)?;
        let base = look.base(target.positions(), target.triangles());
        staging.write(output, |path| {
            let mut staged = args.gltf.clone();
            staged.gltf = Some(path.to_path_buf());
            staged.write(&base, &results, names, &options)?;
            Ok(())
        })?;
        gltf = args.gltf.gltf.clone();
        files_written.extend(gltf.clone());
        warnings.extend(look.warnings);
    }
    if args.pictures.any() {
        let source_poses: Vec<&[[f64; 3]]> = poses.iter().map(|(p, _, _)| p.positions()).collect();
        let target_poses: Vec<&[[f64; 3]]> = results.iter().map(Vec::as_slice).collect();
        let target_name = crate::gltf::mesh_name(&refs.target_ref);
        files_written.extend(pictures.write(&staging, &args.pictures, |staged| {
            crate::pictures::write_transfer_pictures(
                staged,
                (source.triangles(), &source_poses),
                (target.triangles(), &target_poses),
                (&pose_names, &target_name),
            )
            .map(|_| ())
        })?);
    }
    let unpaired = transfer.unpaired_triangles();
    if unpaired > 0 {
        let (lie, keep) = if unpaired == 1 {
            ("lies", "it keeps its rest shape and turns")
        } else {
            ("lie", "they keep their rest shape and turn")
        };
        let gaps = match transfer.gap_triangles() {
            0 => String::new(),
            1 => "; the other one fills a gap and takes its neighbours' deformation".to_string(),
            n => format!("; the other {n} fill gaps and take their neighbours' deformation"),
        };
        warnings.push(format!(
            "{unpaired} of the {} {lie} beyond the source, with no source partner nearby: {keep} with the paired surface{gaps}",
            output::count(correspondence.unmatched_target(), "unmatched target triangle"),
        ));
    }
    if transfer.carried_parts() > 0 {
        warnings.push(format!(
            "{} of the target with few source partners {} carried rigidly by the surface around {}",
            output::count(transfer.carried_parts(), "separate part"),
            if transfer.carried_parts() == 1 {
                "is"
            } else {
                "are"
            },
            if transfer.carried_parts() == 1 {
                "it"
            } else {
                "them"
            },
        ));
    }
    output::print_warnings(&warnings);
    staging.commit()?;
    let n = timings.len() as f64;
    let done = Done {
        poses: timings.len(),
        correspondence_seconds,
        transfer_seconds: start.elapsed().as_secs_f64() - correspondence_seconds,
    };
    for r in [&source_ref, &target_ref] {
        if let Some(rig) = &r.rig {
            warnings.extend(rig.mesh.notes.iter().cloned());
        }
    }
    TransferReport {
        output: output_dir.map(Path::to_path_buf).unwrap_or_default(),
        poses_written: timings.len(),
        correspondence_seconds,
        correspondence_loaded: args.correspondence.is_some(),
        setup_seconds,
        seconds_per_pose: timings.iter().map(|t| t.0).sum::<f64>() / n,
        seconds_per_pose_with_io: timings.iter().map(|t| t.1).sum::<f64>() / n,
        matched_pairs: correspondence.pairs().len(),
        unmatched_source_triangles: correspondence.unmatched_source(),
        unmatched_target_triangles: correspondence.unmatched_target(),
        gap_target_triangles: transfer.gap_triangles(),
        unpaired_target_triangles: transfer.unpaired_triangles(),
        markers: marker_report,
        fit,
        reordered_pose_faces,
        carried_parts: transfer.carried_parts(),
        following_parts: transfer.following_parts(),
        unused_target_vertices: target.num_unused_vertices(),
        welded_source_vertices: source_ref.file.seams.num_welded(),
        welded_target_vertices: target_ref.file.seams.num_welded(),
        total_seconds: start.elapsed().as_secs_f64(),
        saved_correspondence: args.save_correspondence.clone(),
        gif: args.pictures.gif.clone(),
        png: args.pictures.png.clone(),
        gltf,
        files_written,
        warnings,
    }
    .print(args.json);
    Ok(done)
}

/// Every file a transfer reads and writes, planned before any work.
pub(crate) struct Planned {
    pub plan: Plan,
    format: meshmorph::io::Format,
    /// The transferred poses' paths, one a pose.
    outputs: Vec<PathBuf>,
    pose_outputs: Vec<Output>,
    save: Option<Output>,
    gltf_output: Option<Output>,
    pictures: PictureOutputs,
}

/// The plan of one transfer: the poses, references, markers and
/// correspondence it reads; the poses, correspondence, GLB and pictures it
/// writes.
pub(crate) fn plan_transfer(args: &TransferArgs) -> Result<Planned> {
    let refs = args.references()?;
    let format = output::format_or_like(args.format, &refs.target_ref)?;
    let outputs = match args.output_dir() {
        Some(dir) => output_paths(&args.poses, dir, format.extension())?,
        None => Vec::new(),
    };
    let mut plan = Plan::new();
    for pose in &args.poses {
        plan.input(pose, "source pose");
    }
    plan.input(&refs.source_ref, "source reference");
    plan.input(&refs.target_ref, "target reference");
    for m in &args.correspond.markers {
        plan.input(m, "marker file");
    }
    if let Some(c) = &args.correspondence {
        plan.input(c, "correspondence");
    }
    let pose_outputs: Vec<Output> = outputs
        .iter()
        .map(|p| plan.file(p, "transferred pose"))
        .collect();
    let save = args
        .save_correspondence
        .as_deref()
        .map(|p| plan.file(p, "correspondence to save"));
    let gltf_output = args.gltf.gltf.as_deref().map(|p| plan.file(p, "glTF file"));
    let pictures = PictureOutputs::plan(&mut plan, &args.pictures);
    Ok(Planned {
        plan,
        format,
        outputs,
        pose_outputs,
        save,
        gltf_output,
        pictures,
    })
}

/// What one transfer did, for a batch's totals.
#[derive(Debug, Clone, Copy, Default)]
pub struct Done {
    pub poses: usize,
    /// Computing (or loading) the correspondence.
    pub correspondence_seconds: f64,
    /// The rest: reading, setting up, solving and writing.
    pub transfer_seconds: f64,
}

/// The source poses, read and checked against the source reference.
struct ReadPoses {
    /// Each pose, with its count of reordered faces and its reading time.
    poses: Vec<(Mesh3, usize, f64)>,
    warnings: Vec<String>,
}

fn read_poses(paths: &[PathBuf], source_ref: &Reference) -> Result<ReadPoses> {
    let source_file = &source_ref.file.file;
    let seams = &source_ref.file.seams;
    let source_size = output::size(&source_ref.mesh);
    let poses: Vec<(Mesh3, usize, usize, f64)> = paths
        .par_iter()
        .map(|path| {
            let begin = Instant::now();
            let (pose, reordered) =
                output::read_pose(source_file, "source reference", path, "source pose")?;
            let apart = seams.num_apart(pose.positions());
            let pose = if seams.is_empty() {
                pose
            } else {
                source_ref
                    .mesh
                    .with_positions(seams.weld_positions(pose.positions()))?
            };
            Ok((pose, reordered, apart, begin.elapsed().as_secs_f64()))
        })
        .collect::<Result<_>>()?;
    let mut warnings = Vec::new();
    for ((pose, reordered, apart, _), path) in poses.iter().zip(paths) {
        if *apart > 0 {
            warnings.push(format!(
                "`{}`: {} that coincide in the source reference (copies at seams) {} apart in this pose: each taken at the mean of its copies",
                path.display(),
                output::count(*apart, "vertex group"),
                if *apart == 1 { "is" } else { "are" }
            ));
        }
        warnings.extend(output::reordered_faces_warning(
            path,
            source_file.path(),
            *reordered,
        ));
        warnings.extend(output::size_warning(
            path,
            output::size(pose) / source_size,
            "the source reference",
        ));
    }
    let poses = poses
        .into_iter()
        .map(|(pose, reordered, _, read)| (pose, reordered, read))
        .collect();
    Ok(ReadPoses { poses, warnings })
}

impl ReadPoses {
    /// Adds the poses of `other`, read after these.
    fn append(&mut self, other: ReadPoses) {
        self.poses.extend(other.poses);
        self.warnings.extend(other.warnings);
    }
}

/// The correspondence (computed or loaded) and the transfer set up on it.
struct Prepared {
    correspondence: Correspondence,
    marker_report: Option<MarkerReport>,
    /// How well the deformed source fits (absent when the correspondence
    /// was loaded).
    fit: Option<FitSummary>,
    transfer: Transfer,
    correspondence_seconds: f64,
    setup_seconds: f64,
    warnings: Vec<String>,
}

fn prepare(
    args: &TransferArgs,
    refs: &References,
    source_ref: &Reference,
    target_ref: &Reference,
    pins: Vec<(u32, [f64; 3])>,
) -> Result<Prepared> {
    let (source, target) = (&source_ref.mesh, &target_ref.mesh);
    let mut warnings: Vec<String> = [source_ref, target_ref]
        .iter()
        .flat_map(|r| output::surface_warnings(&r.file.file))
        .collect();
    let begin = Instant::now();
    let (mut marker_report, mut fit) = (None, None);
    let correspondence = match &args.correspondence {
        Some(path) => {
            let c = Correspondence::load(path).context("reading the correspondence")?;
            c.check_fits(source_ref.file_mesh(), target_ref.file_mesh())
                .with_context(|| {
                    format!(
                        "correspondence `{}` does not fit these meshes",
                        path.display()
                    )
                })?;
            signed_for(&c, source, target)
        }
        None => {
            let (result, report, summary) =
                args.correspond
                    .compute(refs, source_ref, target_ref, &mut warnings)?;
            marker_report = Some(report);
            fit = Some(summary);
            result.correspondence
        }
    };
    let correspondence_seconds = begin.elapsed().as_secs_f64();

    let begin = Instant::now();
    memory::check_setup(
        source.num_triangles() + target.num_triangles(),
        "the transfer",
    )?;
    let transfer = Transfer::new(
        source,
        target,
        &correspondence,
        &TransferOptions::default().with_pins(pins),
    )
    .map_err(|e| name_degenerate_faces(e, source_ref, target_ref))
    .with_context(|| format!("setting up the transfer {}", refs.describe()))?;
    Ok(Prepared {
        correspondence,
        marker_report,
        fit,
        transfer,
        correspondence_seconds,
        setup_seconds: begin.elapsed().as_secs_f64(),
        warnings,
    })
}

/// The pictures of a plan (`--png`, `--gif`), each written through the
/// staging on its own.
pub(crate) struct PictureOutputs {
    png: Option<Output>,
    gif: Option<Output>,
}

impl PictureOutputs {
    pub(crate) fn plan(plan: &mut Plan, args: &crate::pictures::PictureArgs) -> Self {
        Self {
            png: args.png.as_deref().map(|p| plan.file(p, "picture")),
            gif: args.gif.as_deref().map(|p| plan.file(p, "animation")),
        }
    }

    /// Calls `draw` once per picture with the staged path in place of the
    /// user's; returns the user's paths.
    pub(crate) fn write(
        &self,
        staging: &Staging,
        args: &crate::pictures::PictureArgs,
        draw: impl Fn(&crate::pictures::PictureArgs) -> Result<()>,
    ) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        if let (Some(output), Some(png)) = (self.png, &args.png) {
            staging.write(output, |path| {
                draw(&crate::pictures::PictureArgs {
                    png: Some(path.to_path_buf()),
                    gif: None,
                    draw: args.draw.clone(),
                })
            })?;
            written.push(png.clone());
        }
        if let (Some(output), Some(gif)) = (self.gif, &args.gif) {
            staging.write(output, |path| {
                draw(&crate::pictures::PictureArgs {
                    png: None,
                    gif: Some(path.to_path_buf()),
                    draw: args.draw.clone(),
                })
            })?;
            written.push(gif.clone());
        }
        Ok(written)
    }
}

/// `--pin` vertices (1-based with `--one-based`) at their rest positions.
/// The target vertices held by `--pin` (numbered as in the target's file),
/// on the welded target, at their rest positions.
fn pin_positions(
    pins: &[u32],
    one_based: bool,
    target_ref: &Reference,
) -> Result<Vec<(u32, [f64; 3])>> {
    let target = target_ref.file_mesh();
    pins.iter()
        .map(|&given| {
            let v = if one_based {
                given.checked_sub(1).with_context(|| {
                    format!("--pin {given}: with --one-based, 1 is the first vertex")
                })?
            } else {
                given
            };
            let p = target.positions().get(v as usize).with_context(|| {
                format!(
                    "--pin {given}: the target has {}",
                    output::vertices(target.num_vertices())
                )
            })?;
            Ok((v, *p))
        })
        .collect::<Result<Vec<_>>>()
        .and_then(|pins| {
            let mut given = HashSet::new();
            if let Some(&(v, _)) = pins.iter().find(|(v, _)| !given.insert(*v)) {
                bail!(
                    "--pin {}: the vertex is pinned twice",
                    v + u32::from(one_based)
                );
            }
            // Copies of one vertex at a seam are one pin.
            let mut seen = HashSet::new();
            Ok(pins
                .into_iter()
                .map(|(v, p)| (target_ref.file.seams.welded(v), p))
                .filter(|(w, _)| seen.insert(*w))
                .collect())
        })
}

/// DIR/<stem>.<ext> for each pose, refusing two poses with the same stem.
/// (Clashes with inputs are the output plan's to refuse.)
fn output_paths(poses: &[PathBuf], dir: &Path, ext: &str) -> Result<Vec<PathBuf>> {
    let mut seen = HashMap::new();
    poses
        .iter()
        .map(|p| {
            let stem = p
                .file_stem()
                .with_context(|| format!("pose `{}` has no file name", p.display()))?;
            if let Some(first) = seen.insert(stem.to_os_string(), p) {
                bail!(
                    "poses `{}` and `{}` are both named `{}`: their outputs would overwrite each other",
                    first.display(),
                    p.display(),
                    stem.to_string_lossy()
                );
            }
            // `pose.01.obj` -> `pose.01.ply`: the stem whole, dots and all.
            let mut name = stem.to_os_string();
            name.push(".");
            name.push(ext);
            Ok(dir.join(name))
        })
        .collect()
}
