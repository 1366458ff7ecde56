//! `meshmorph transfer` and `meshmorph correspond`.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::output::WeldedFile;
use anyhow::{bail, Context, Result};
use meshmorph::io::gltf::GltfOptions;
use meshmorph::io::Appearance;
use meshmorph::{
    correspond_with_progress, CorrespondOptions, Correspondence, Markers, Mesh3, Transfer,
    TransferOptions, VertexNumbering,
};
use rayon::prelude::*;
use serde::Serialize;

use crate::gltf::GltfArgs;
use crate::memory;
use crate::output::{self, finite_number, FormatArg};
use crate::outputs::{Output, Plan, Staging};
use crate::pictures::PictureArgs;
use crate::progress;

/// How the triangle correspondence is computed (Sumner and Popovic 2004, section 5).
#[derive(Debug, Clone, clap::Args)]
pub struct CorrespondArgs {
    /// Marker file: one `source target` vertex pair per line, or a point on
    /// each mesh `sx sy sz tx ty tz` (snapped to the nearest vertex); white
    /// space or a comma between, `#` comments, an optional first line with
    /// the count.
    #[arg(long, value_name = "FILE")]
    pub markers: Option<PathBuf>,
    /// Vertex indices in the marker file start at 1 instead of 0.
    #[arg(long)]
    pub one_based: bool,
    /// Do not bring the source onto the target by the similarity (rotation,
    /// uniform scale, translation) that best fits the markers: the two
    /// references must then already overlap.
    #[arg(long)]
    pub no_align: bool,
    /// Weight of the smoothness term w_S [default: 1].
    #[arg(long, value_name = "W", allow_negative_numbers = true, value_parser = finite_number)]
    pub smoothness_weight: Option<f64>,
    /// Weight of the identity term w_I, above 0 [default: 0.3]: each
    /// triangle keeps its shape up to a turn and a uniform scale.
    #[arg(long, value_name = "W", allow_negative_numbers = true, value_parser = finite_number)]
    pub identity_weight: Option<f64>,
    /// Weights w_C of the closest-point rounds, comma-separated, after a
    /// first round without closest points, with distances measured in
    /// diagonals of the target's bounding box [default: 1 to 5000 in four
    /// even steps].
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LIST",
        allow_hyphen_values = true,
        value_parser = finite_number
    )]
    pub closest_weights: Option<Vec<f64>>,
    /// Largest distance to a closest point, as a fraction of the target's
    /// bounding-box diagonal [default: 0.02].
    #[arg(long, value_name = "FRACTION", allow_negative_numbers = true, value_parser = finite_number)]
    pub closest_cutoff: Option<f64>,
    /// Largest centroid distance of matched triangles, as a fraction of the
    /// target's bounding-box diagonal, and never less than the mean edge
    /// length of either mesh [default: 0.01].
    #[arg(long, value_name = "FRACTION", allow_negative_numbers = true, value_parser = finite_number)]
    pub match_threshold: Option<f64>,
}

impl CorrespondArgs {
    /// The library's defaults, with the options given on the command line.
    fn options(&self) -> CorrespondOptions {
        let d = CorrespondOptions::default();
        CorrespondOptions::default()
            .with_weights(
                self.smoothness_weight.unwrap_or(d.smoothness_weight),
                self.identity_weight.unwrap_or(d.identity_weight),
            )
            .with_closest_weights(self.closest_weights.clone().unwrap_or(d.closest_weights))
            .with_closest_cutoff(self.closest_cutoff.unwrap_or(d.closest_cutoff))
            .with_match_threshold(self.match_threshold.unwrap_or(d.match_threshold))
            .with_align(!self.no_align)
    }

    /// Reads the markers (snapping marker points to vertices) and computes
    /// the correspondence, with a progress bar. `refs` name the meshes in
    /// error messages; warnings about the markers go to `warnings`.
    fn compute(
        &self,
        refs: &References,
        source_ref: &Reference,
        target_ref: &Reference,
        warnings: &mut Vec<String>,
    ) -> Result<(meshmorph::CorrespondResult, MarkerReport)> {
        let (source, target) = (&source_ref.mesh, &target_ref.mesh);
        let Some(path) = &self.markers else {
            bail!(
                "--markers is required to compute a correspondence (or pass --correspondence FILE)"
            );
        };
        let markers =
            Markers::read(path, numbering(self.one_based)).context("reading the markers")?;
        let (markers, snap) = markers
            .snap(source_ref.file_mesh(), target_ref.file_mesh())
            .context("snapping the marker points to vertices")?;
        markers.check_ranges(
            source_ref.file_mesh().num_vertices(),
            target_ref.file_mesh().num_vertices(),
        )?;
        let welded = markers.welded(&source_ref.file.seams, &target_ref.file.seams);
        let options = self.options();
        let bar = progress::bar(options.steps() as u64, "correspond");
        let result = correspond_with_progress(source, target, &welded, &options, &mut |done| {
            bar.set_position(done as u64)
        })
        .map_err(|e| name_degenerate_faces(e, source_ref, target_ref))
        .with_context(|| {
            format!(
                "computing the correspondence {} with the markers `{}`",
                refs.describe(),
                path.display()
            )
        })?;
        bar.finish_and_clear();
        let diagonal = target.bounding_box_diagonal();
        let r = &result.marker_residuals;
        let rms = (r.iter().map(|x| x * x).sum::<f64>() / r.len().max(1) as f64).sqrt();
        let suspicious: Vec<String> = result
            .far_markers()
            .into_iter()
            .map(|k| welded.describe(k))
            .collect();
        if !suspicious.is_empty() {
            warnings.push(format!(
                "after the alignment, {} far from {} target vertex ({}): {} may be on the wrong feature",
                if suspicious.len() == 1 { "a marker lies" } else { "markers lie" },
                if suspicious.len() == 1 { "its" } else { "their" },
                suspicious.join("; "),
                if suspicious.len() == 1 { "it" } else { "they" },
            ));
        }
        // Apart by more than the closest-point cut-off, the references' parts
        // go unmatched.
        if !options.align && rms > options.closest_cutoff * diagonal {
            warnings.extend(misplaced_warning(source, target, &welded, rms / diagonal));
        }
        let report = MarkerReport {
            markers: markers.pairs().len(),
            snapped_points: snap.points,
            largest_snap_source: snap.largest_source,
            largest_snap_target: snap.largest_target,
            aligned: options.align,
            alignment_scale: result.correspondence.alignment().scale,
            marker_residual_rms: rms / diagonal,
            marker_residual_max: r.iter().copied().fold(0.0, f64::max) / diagonal,
            suspicious_markers: suspicious,
            turn_from_marker_fit: result
                .marker_fit
                .angle_to(result.correspondence.alignment())
                .to_degrees(),
            mirror_plane_misfits: result.mirror_planes.map(|p| p.map(|p| p.misfit)),
        };
        Ok((result, report))
    }
}

/// With `--no-align`, the warning that the references stand apart: the
/// markers' similarity would bring them at least twice as close as they
/// stand (`rms`, the markers' RMS distance over the target's diagonal). A
/// pair aligned by hand, whose markers differ only as the shapes do, gets
/// none.
fn misplaced_warning(
    source: &Mesh3,
    target: &Mesh3,
    markers: &Markers,
    rms: f64,
) -> Option<String> {
    let r = markers.fit(source, target).ok()?.1;
    let fitted = (r.iter().map(|x| x * x).sum::<f64>() / r.len().max(1) as f64).sqrt()
        / target.bounding_box_diagonal();
    (rms > 2.0 * fitted).then(|| {
        format!(
            "with --no-align the markers lie {:.1} % of the target's diagonal from their partners (RMS), where the similarity that fits them would leave {:.1} %: the references stand apart, and much of the target may stay unmatched; leave out --no-align to bring the source onto the target",
            100.0 * rms,
            100.0 * fitted
        )
    })
}

/// `c` for the meshes `source` and `target` (the files' own, or welded at
/// seams: welding keeps the triangles, which the pairs name). A saved
/// correspondence names the files' meshes, the solvers take welded ones.
fn signed_for(c: &Correspondence, source: &Mesh3, target: &Mesh3) -> Correspondence {
    Correspondence::new(c.pairs().to_vec(), source, target).with_alignment(*c.alignment())
}

/// The report's lines for the copies of vertices welded at seams in each
/// reference, if any.
fn print_welded(source: usize, target: usize) {
    for (mesh, welded) in [("source", source), ("target", target)] {
        if let Some(line) = output::welded_line(welded) {
            say!("welded in the {mesh}: {line}");
        }
    }
}

/// How the markers fitted (distances as fractions of the target's diagonal).
#[derive(Debug, Default, Serialize)]
pub struct MarkerReport {
    pub markers: usize,
    /// Markers given as points and snapped to the nearest vertex.
    pub snapped_points: usize,
    pub largest_snap_source: f64,
    pub largest_snap_target: f64,
    /// Whether the source was aligned to the target (not --no-align).
    pub aligned: bool,
    /// The scale of the alignment (target size over source size).
    pub alignment_scale: f64,
    pub marker_residual_rms: f64,
    pub marker_residual_max: f64,
    pub suspicious_markers: Vec<String>,
    /// How far (degrees) the orientation the deformations are transferred
    /// in turns from the markers' fit: that of the matched surface.
    pub turn_from_marker_fit: f64,
    /// When the source's and the target's planes of symmetry were kept
    /// together: how far each mesh is from its mirror image (RMS, over the
    /// RMS distance of its surface from its centroid).
    pub mirror_plane_misfits: Option<[f64; 2]>,
}

impl MarkerReport {
    fn print(&self) {
        let mut line = format!("markers:        {}", self.markers);
        if self.snapped_points > 0 {
            line += &format!(
                " ({} snapped to vertices, at most {:.3} % of the source's and {:.3} % of the target's diagonal away)",
                output::count(self.snapped_points, "point"),
                100.0 * self.largest_snap_source,
                100.0 * self.largest_snap_target
            );
        }
        say!("{line}");
        if self.aligned {
            say!(
                "alignment:      scale {:.6}, marker residual {:.3} % of the target's diagonal (RMS), {:.3} % at most",
                self.alignment_scale,
                100.0 * self.marker_residual_rms,
                100.0 * self.marker_residual_max
            );
            let mut line = format!(
                "orientation:    the matched surface's, {:.2} degrees from the markers' fit",
                self.turn_from_marker_fit
            );
            if let Some([source, target]) = self.mirror_plane_misfits {
                line += &format!(
                    ", the planes of symmetry kept together (each mesh its own mirror image to {:.2} % and {:.2} % of its size)",
                    100.0 * source,
                    100.0 * target
                );
            }
            say!("{line}");
        } else {
            say!(
                "alignment:      off, marker distance {:.3} % of the target's diagonal (RMS)",
                100.0 * self.marker_residual_rms
            );
        }
    }
}

/// `e` with degenerate triangles of either reference named as its file's
/// faces.
fn name_degenerate_faces(
    e: meshmorph::Error,
    source_ref: &Reference,
    target_ref: &Reference,
) -> meshmorph::Error {
    let e = output::degenerate_faces(e, &source_ref.file.file, "source reference");
    output::degenerate_faces(e, &target_ref.file.file, "target reference")
}

/// The two reference meshes.
#[derive(Debug, Clone, clap::Args)]
pub struct References {
    /// The source character at rest (S0); its poses have its vertices and triangles.
    #[arg(long, value_name = "MESH")]
    pub source_ref: PathBuf,
    /// The target character at rest (T0).
    #[arg(long, value_name = "MESH")]
    pub target_ref: PathBuf,
    /// Keep apart vertices that share a place. By default copies at seams
    /// (vertices at exactly one place in a reference whose neighbours coincide too, as
    /// UV seams and edge splits leave them) are welded for the solve, so that
    /// the surface does not crack along them; the files keep their vertices.
    #[arg(long)]
    pub no_weld: bool,
}

impl References {
    /// Both files, kept whole, and their meshes welded at seams.
    fn read(&self) -> Result<(Reference, Reference)> {
        let read = |path: &Path, role: &str| -> Result<Reference> {
            let (file, mesh) = WeldedFile::new(output::read_mesh_file(path, role)?, !self.no_weld);
            Ok(Reference { file, mesh })
        };
        let (s, t) = rayon::join(
            || read(&self.source_ref, "source reference"),
            || read(&self.target_ref, "target reference"),
        );
        Ok((s?, t?))
    }

    /// "from `source.obj` to `target.obj`", for messages.
    fn describe(&self) -> String {
        format!(
            "from `{}` to `{}`",
            self.source_ref.display(),
            self.target_ref.display()
        )
    }
}

/// A reference mesh: its file, and its mesh with the copies of vertices at
/// seams welded ([`meshmorph::Seams`]), which the solvers take.
struct Reference {
    file: WeldedFile,
    mesh: Mesh3,
}

impl Reference {
    /// The mesh as the file has it (marker and pin indices refer to it).
    fn file_mesh(&self) -> &Mesh3 {
        self.file.file.mesh()
    }
}

/// Carry the poses of a source mesh over to a target mesh.
///
/// Writes one mesh per pose: DIR/<the pose file's stem>.<ext>.
#[derive(Debug, clap::Args)]
#[command(
    mut_arg("one_based", |a| a.help("Vertex indices (markers and --pin) start at 1 instead of 0")),
    mut_arg("png", |a| a.help("Also write a still picture (PNG): source poses above, transferred poses below (the first, middle and last)")),
    mut_arg("gif", |a| a.help("Also write an animated GIF: every source pose above its transferred pose")),
    mut_arg("gltf", |a| a.help("Also write one binary glTF (FILE.glb) for Blender, three.js or any glTF viewer: the target reference with every transferred pose as a morph target, and an animation playing the poses in order at --fps (see --gltf-shapes). It weighs about 24 bytes x target vertices x poses: a 10,000-vertex target with 100 poses makes 24 MB")),
)]
pub struct TransferArgs {
    #[command(flatten)]
    pub refs: References,
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
    /// Directory for the transferred poses (created if missing).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
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
    #[command(flatten)]
    pub pictures: PictureArgs,
    /// Source poses: new positions for the source reference's vertices, with
    /// its faces (listed in any corner order or winding).
    #[arg(required = true, value_name = "POSE")]
    pub poses: Vec<PathBuf>,
}

/// A vertex index (0 or more).
fn vertex_index(text: &str) -> Result<u32, String> {
    match text.trim().parse::<i128>() {
        Ok(v) if v < 0 => Err(format!("{v} is not a vertex index: indices count from 0")),
        Ok(v) => u32::try_from(v).map_err(|_| format!("{v} is too large for a vertex index")),
        Err(_) => Err(format!("`{text}` is not a vertex index")),
    }
}

/// What a transfer did.
#[derive(Debug, Serialize)]
pub struct TransferReport {
    #[serde(serialize_with = "output::lossy")]
    pub output: PathBuf,
    pub poses_written: usize,
    /// Computing (or loading) the correspondence.
    pub correspondence_seconds: f64,
    pub correspondence_loaded: bool,
    /// Factoring the transfer system.
    pub setup_seconds: f64,
    /// Solving one pose, averaged.
    pub seconds_per_pose: f64,
    /// One pose with reading and writing, averaged over the poses run in parallel.
    pub seconds_per_pose_with_io: f64,
    pub matched_pairs: usize,
    /// Source triangles in no pair: their deformation is carried to no
    /// target triangle.
    pub unmatched_source_triangles: usize,
    /// Target triangles in no pair: `gap_target_triangles` +
    /// `unpaired_target_triangles`.
    pub unmatched_target_triangles: usize,
    /// Unmatched target triangles in gaps of the matching (enclosed by the
    /// paired surface, or near a paired triangle): deformed as their
    /// neighbours.
    pub gap_target_triangles: usize,
    /// Unmatched target triangles beyond the source (no source partner
    /// nearby): kept in their rest shape, turned with the paired surface.
    pub unpaired_target_triangles: usize,
    /// How the markers fitted (absent when the correspondence was loaded).
    pub markers: Option<MarkerReport>,
    /// Pose faces that list the reference's corners in another order or winding.
    pub reordered_pose_faces: usize,
    /// Separate parts of the target carried rigidly by the surface around them.
    pub carried_parts: usize,
    /// Separate parts of the target with their own partners, placed by the
    /// main part around them (their shape follows their partners).
    pub following_parts: usize,
    /// Target vertices no triangle uses: written at their rest positions.
    pub unused_target_vertices: usize,
    /// Vertices at the same place as another (copies at seams), welded for
    /// the solve, in the source and in the target; the files keep them.
    pub welded_source_vertices: usize,
    pub welded_target_vertices: usize,
    pub total_seconds: f64,
    /// The correspondence saved, if any.
    #[serde(serialize_with = "output::lossy")]
    pub saved_correspondence: Option<PathBuf>,
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
}

impl TransferReport {
    fn print(&self, json: bool) {
        if json {
            output::print_json(self);
            return;
        }
        if let Some(m) = &self.markers {
            m.print();
        }
        say!(
            "wrote {} to {}",
            output::count(self.poses_written, "pose"),
            self.output.display()
        );
        say!(
            "correspondence: {} ({}){}",
            output::human_seconds(self.correspondence_seconds),
            output::count(self.matched_pairs, "pair"),
            if self.correspondence_loaded {
                ", loaded"
            } else {
                ""
            }
        );
        print_unmatched(
            self.unmatched_source_triangles,
            self.unmatched_target_triangles,
        );
        if self.unmatched_target_triangles > 0 {
            say!(
                "  in gaps:      {} (holes in the match: deformed as their neighbours)",
                output::count(self.gap_target_triangles, "target triangle")
            );
            say!(
                "  kept at rest: {} (beyond the source: rest shape, turned with the paired surface)",
                output::count(self.unpaired_target_triangles, "target triangle")
            );
        }
        if self.carried_parts + self.following_parts > 0 {
            say!(
                "separate parts: {} with partners (shaped by them, placed by the main part around them), {} carried rigidly",
                self.following_parts, self.carried_parts
            );
        }
        print_welded(self.welded_source_vertices, self.welded_target_vertices);
        if self.unused_target_vertices > 0 {
            say!(
                "unused target vertices: {} (in no triangle; kept at rest)",
                self.unused_target_vertices
            );
        }
        say!(
            "setup:          {}",
            output::human_seconds(self.setup_seconds)
        );
        say!(
            "time per pose:  {} solving, {} with reading and writing",
            output::human_seconds(self.seconds_per_pose),
            output::human_seconds(self.seconds_per_pose_with_io)
        );
        say!(
            "total:          {}",
            output::human_seconds(self.total_seconds)
        );
        output::print_files(
            &[
                ("saved:", self.saved_correspondence.as_deref()),
                ("picture:", self.png.as_deref()),
                ("animation:", self.gif.as_deref()),
                ("glTF:", self.gltf.as_deref()),
            ],
            16,
        );
    }
}

/// The report's line for the triangles of either reference in no pair.
fn print_unmatched(source: usize, target: usize) {
    say!(
        "unmatched:      {}, {}",
        output::count(source, "source triangle"),
        output::count(target, "target triangle")
    );
}

/// One pose done: seconds solving, seconds with reading and writing, what
/// the output format dropped, the positions (kept for the glTF and pictures).
type SolvedPose = (f64, f64, Vec<String>, Option<Vec<[f64; 3]>>);

pub fn run_transfer(args: &TransferArgs) -> Result<()> {
    let start = Instant::now();
    let format = output::format_or_like(args.format, &args.refs.target_ref)?;
    // Every output is checked against every input (by resolved path) before
    // anything is read or computed.
    let outputs = output_paths(&args.poses, &args.output, format.extension())?;
    let mut plan = Plan::new();
    for pose in &args.poses {
        plan.input(pose, "source pose");
    }
    plan.input(&args.refs.source_ref, "source reference");
    plan.input(&args.refs.target_ref, "target reference");
    if let Some(m) = &args.correspond.markers {
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
    let staging = plan.prepare()?;
    let mut read: Vec<&Path> = args.poses.iter().map(PathBuf::as_path).collect();
    read.extend([
        args.refs.source_ref.as_path(),
        args.refs.target_ref.as_path(),
    ]);
    memory::check_reading(&read)?;
    let (source_ref, target_ref) = args.refs.read()?;
    output::protect_side_files(&staging, &source_ref.file.file, "source reference")?;
    output::protect_side_files(&staging, &target_ref.file.file, "target reference")?;
    let (source, target) = (&source_ref.mesh, &target_ref.mesh);
    let image_budget =
        args.gltf
            .check::<3>(Some(&target_ref.file.file), target, args.poses.len())?;
    let pins = pin_positions(&args.pin, args.correspond.one_based, &target_ref)?;

    // Each pose is new positions for the reference's faces, split as the
    // reference is. The first pose is read and checked at once (a pose of
    // another mesh is reported before the slow correspondence), the others
    // while the correspondence and the setup run (they leave a core mostly
    // idle). A bad pose is reported, ahead of any error of theirs, before
    // anything is written.
    let (first, others) = args.poses.split_at(args.poses.len().min(1));
    let mut read = read_poses(first, &source_ref)?;
    let (others, prepared) = rayon::join(
        || read_poses(others, &source_ref),
        || prepare(args, &source_ref, &target_ref, pins),
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
        .zip(&pose_outputs)
        .map_init(
            || transfer.workspace(),
            |ws, ((pose, _, read), &output)| {
                let begin = Instant::now();
                let mut out = vec![[0.0; 3]; target.num_vertices()];
                transfer.apply_into(pose.positions(), &mut out, ws);
                let solve = begin.elapsed().as_secs_f64();
                let mut dropped = Vec::new();
                staging.write_to(output, |path, w| {
                    if let Some(v) = out.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
                        bail!("vertex {v} overflows (its coordinates exceed the range of floating-point numbers); scale the meshes down");
                    }
                    dropped = target_ref.file.write_to(w, path, &out, format)?;
                    Ok(())
                })?;
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
    if let Some((_, _, dropped, _)) = solved.first() {
        // The same for every pose: said once, for the directory.
        warnings.extend(output::dropped_for(&args.output, dropped));
    }
    let mut timings = Vec::with_capacity(solved.len());
    let mut results = Vec::new();
    for (solve, with_io, _, result) in solved {
        timings.push((solve, with_io));
        results.extend(result);
    }
    let mut files_written: Vec<PathBuf> = args.save_correspondence.iter().cloned().collect();
    files_written.extend(outputs.iter().cloned());
    let names: Vec<String> = outputs.iter().map(|p| crate::gltf::mesh_name(p)).collect();
    let options = GltfOptions::default()
        .with_fps(args.pictures.draw.fps)
        .with_animation(!args.gltf_shapes)
        .with_name(crate::gltf::mesh_name(&args.refs.target_ref));
    let mut gltf = None;
    if let Some(output) = gltf_output {
        let look = Appearance::of_file(&target_ref.file.file, image_budget)?;
        let base = look.base(target.positions(), target.triangles());
        staging.write(output, |path| {
            let mut staged = args.gltf.clone();
            staged.gltf = Some(path.to_path_buf());
            staged.write(&base, &results, &names, &options)?;
            Ok(())
        })?;
        gltf = args.gltf.gltf.clone();
        files_written.extend(gltf.clone());
        warnings.extend(look.warnings);
    }
    if args.pictures.any() {
        let source_poses: Vec<&[[f64; 3]]> = poses.iter().map(|(p, _, _)| p.positions()).collect();
        let target_poses: Vec<&[[f64; 3]]> = results.iter().map(Vec::as_slice).collect();
        let pose_names: Vec<String> = args
            .poses
            .iter()
            .map(|p| crate::gltf::mesh_name(p))
            .collect();
        let target_name = crate::gltf::mesh_name(&args.refs.target_ref);
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
    TransferReport {
        output: args.output.clone(),
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
    Ok(())
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
    transfer: Transfer,
    correspondence_seconds: f64,
    setup_seconds: f64,
    warnings: Vec<String>,
}

fn prepare(
    args: &TransferArgs,
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
    let mut marker_report = None;
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
            let (result, report) =
                args.correspond
                    .compute(&args.refs, source_ref, target_ref, &mut warnings)?;
            marker_report = Some(report);
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
    .with_context(|| format!("setting up the transfer {}", args.refs.describe()))?;
    Ok(Prepared {
        correspondence,
        marker_report,
        transfer,
        correspondence_seconds,
        setup_seconds: begin.elapsed().as_secs_f64(),
        warnings,
    })
}

/// The pictures of a plan (`--png`, `--gif`), each written through the
/// staging on its own.
struct PictureOutputs {
    png: Option<Output>,
    gif: Option<Output>,
}

impl PictureOutputs {
    fn plan(plan: &mut Plan, args: &crate::pictures::PictureArgs) -> Self {
        Self {
            png: args.png.as_deref().map(|p| plan.file(p, "picture")),
            gif: args.gif.as_deref().map(|p| plan.file(p, "animation")),
        }
    }

    /// Calls `draw` once per picture with the staged path in place of the
    /// user's; returns the user's paths.
    fn write(
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

/// Compute the triangle correspondence between two meshes and save it.
#[derive(Debug, clap::Args)]
#[command(
    mut_arg("png", |a| a.help("Also write a still picture (PNG): the deformed source above the target")),
    mut_arg("gif", |a| a.help("Also write an animated GIF: the source reference turning into the deformed source, above the target")),
)]
pub struct CorrespondCommand {
    #[command(flatten)]
    pub refs: References,
    #[command(flatten)]
    pub correspond: CorrespondArgs,
    /// Where to save the correspondence.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Also write the source reference deformed onto the target, to see how
    /// well it fits.
    #[arg(long, value_name = "MESH")]
    pub deformed_source: Option<PathBuf>,
    /// `--png` and `--gif`, with their help for correspondences (above).
    #[command(flatten)]
    pub pictures: PictureArgs,
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// What `correspond` did.
#[derive(Debug, Serialize)]
pub struct CorrespondReport {
    #[serde(serialize_with = "output::lossy")]
    pub output: PathBuf,
    pub seconds: f64,
    pub matched_pairs: usize,
    pub unmatched_source_triangles: usize,
    pub unmatched_target_triangles: usize,
    /// Copies of vertices at seams welded for the solve, in the source and
    /// in the target.
    pub welded_source_vertices: usize,
    pub welded_target_vertices: usize,
    /// The source reference deformed onto the target, if written.
    #[serde(serialize_with = "output::lossy")]
    pub deformed_source: Option<PathBuf>,
    /// The GIF written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub gif: Option<PathBuf>,
    /// The PNG written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub png: Option<PathBuf>,
    /// Every file written, in order.
    #[serde(serialize_with = "output::lossy")]
    pub files_written: Vec<PathBuf>,
    /// How the markers fitted.
    pub markers: MarkerReport,
    /// The warnings given (also printed on stderr).
    pub warnings: Vec<String>,
}

pub fn run_correspond(args: &CorrespondCommand) -> Result<()> {
    let Some(markers_path) = &args.correspond.markers else {
        bail!("--markers is required");
    };
    // Checked before any work, so that a bad name leaves no output behind.
    let deformed_format = args
        .deformed_source
        .as_deref()
        .map(meshmorph::io::Format::from_path)
        .transpose()?;
    let mut plan = Plan::new();
    plan.input(&args.refs.source_ref, "source reference");
    plan.input(&args.refs.target_ref, "target reference");
    plan.input(markers_path, "marker file");
    let saved = plan.file(&args.output, "correspondence");
    let deformed = args
        .deformed_source
        .as_deref()
        .map(|p| plan.file(p, "deformed source"));
    let pictures = PictureOutputs::plan(&mut plan, &args.pictures);
    let staging = plan.prepare()?;
    memory::check_reading(&[&args.refs.source_ref, &args.refs.target_ref])?;
    let (source_ref, target_ref) = args.refs.read()?;
    output::protect_side_files(&staging, &source_ref.file.file, "source reference")?;
    output::protect_side_files(&staging, &target_ref.file.file, "target reference")?;
    let (source, target) = (&source_ref.mesh, &target_ref.mesh);
    memory::check_setup(
        source.num_triangles() + target.num_triangles(),
        "the correspondence",
    )?;
    let begin = Instant::now();
    let mut warnings = staging.warnings();
    warnings.extend(
        [&source_ref, &target_ref]
            .iter()
            .flat_map(|r| output::surface_warnings(&r.file.file)),
    );
    let (result, markers) =
        args.correspond
            .compute(&args.refs, &source_ref, &target_ref, &mut warnings)?;
    let seconds = begin.elapsed().as_secs_f64();
    let c = &result.correspondence;
    let on_file = signed_for(c, source_ref.file_mesh(), target_ref.file_mesh());
    staging.write(saved, |path| Ok(on_file.save(path)?))?;
    let mut files_written = vec![args.output.clone()];
    if let (Some(output), Some(path), Some(format)) =
        (deformed, &args.deformed_source, deformed_format)
    {
        staging.write_to(output, |staged, w| {
            let dropped =
                source_ref
                    .file
                    .write_to(w, staged, result.deformed_source.positions(), format)?;
            warnings.extend(output::dropped_for(path, &dropped));
            Ok(())
        })?;
        files_written.push(path.clone());
    }
    let names = (
        crate::gltf::mesh_name(&args.refs.source_ref),
        crate::gltf::mesh_name(&args.refs.target_ref),
    );
    files_written.extend(pictures.write(&staging, &args.pictures, |staged| {
        crate::pictures::write_correspondence_pictures(
            staged,
            (source.triangles(), &[source.positions()]),
            result.deformed_source.positions(),
            (target.triangles(), &[target.positions()]),
            (&names.0, &names.1),
        )
        .map(|_| ())
    })?);
    if c.unmatched_target() > 0 {
        warnings.push(format!(
            "{} no source partner",
            output::count_doing(c.unmatched_target(), "target triangle", "has", "have")
        ));
    }
    output::print_warnings(&warnings);
    staging.commit()?;
    let report = CorrespondReport {
        output: args.output.clone(),
        seconds,
        matched_pairs: c.pairs().len(),
        unmatched_source_triangles: c.unmatched_source(),
        unmatched_target_triangles: c.unmatched_target(),
        welded_source_vertices: source_ref.file.seams.num_welded(),
        welded_target_vertices: target_ref.file.seams.num_welded(),
        deformed_source: args.deformed_source.clone(),
        gif: args.pictures.gif.clone(),
        png: args.pictures.png.clone(),
        files_written,
        markers,
        warnings,
    };
    if args.json {
        output::print_json(&report);
    } else {
        report.markers.print();
        say!(
            "correspondence: {} in {}, saved to {}",
            output::count(report.matched_pairs, "pair"),
            output::human_seconds(seconds),
            args.output.display()
        );
        print_unmatched(
            report.unmatched_source_triangles,
            report.unmatched_target_triangles,
        );
        print_welded(report.welded_source_vertices, report.welded_target_vertices);
        output::print_files(
            &[
                ("deformed:", report.deformed_source.as_deref()),
                ("picture:", report.png.as_deref()),
                ("animation:", report.gif.as_deref()),
            ],
            16,
        );
    }
    Ok(())
}

/// How `--one-based` numbers the markers' vertices.
fn numbering(one_based: bool) -> VertexNumbering {
    if one_based {
        VertexNumbering::FromOne
    } else {
        VertexNumbering::FromZero
    }
}
