//! `meshmorph transfer` and `meshmorph correspond`.

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use meshmorph::{
    correspond, CorrespondOptions, Correspondence, Markers, Mesh3, Transfer, TransferOptions,
};
use rayon::prelude::*;
use serde::Serialize;

use crate::memory;
use crate::output::{self, FormatArg};
use crate::outputs::Plan;
use crate::progress;

/// How the triangle correspondence is computed (Sumner and Popovic 2004, section 5).
#[derive(Debug, Clone, clap::Args)]
pub struct CorrespondArgs {
    /// Marker file: one `source target` vertex pair per line (white space or
    /// a comma between), `#` comments, an optional first line with the count.
    #[arg(long, value_name = "FILE")]
    pub markers: Option<PathBuf>,
    /// Marker indices start at 1 instead of 0.
    #[arg(long)]
    pub one_based: bool,
    /// Weight of the smoothness term w_S [default: 1].
    #[arg(long, value_name = "W", allow_negative_numbers = true)]
    pub smoothness_weight: Option<f64>,
    /// Weight of the identity term w_I, above 0 [default: 0.001].
    #[arg(long, value_name = "W", allow_negative_numbers = true)]
    pub identity_weight: Option<f64>,
    /// Weights w_C of the closest-point rounds, comma-separated, after a
    /// first round without closest points [default: 1 to 5000 in four
    /// even steps].
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LIST",
        allow_hyphen_values = true
    )]
    pub closest_weights: Option<Vec<f64>>,
    /// Largest distance to a closest point, as a fraction of the target's
    /// bounding-box diagonal [default: 0.02].
    #[arg(long, value_name = "FRACTION", allow_negative_numbers = true)]
    pub closest_cutoff: Option<f64>,
    /// Largest centroid distance of matched triangles, as a fraction of the
    /// target's bounding-box diagonal, and never less than the mean edge
    /// length of either mesh [default: 0.01].
    #[arg(long, value_name = "FRACTION", allow_negative_numbers = true)]
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
    }

    /// Reads the markers and computes the correspondence, with a progress bar.
    /// `refs` name the meshes in error messages.
    fn compute(
        &self,
        refs: &References,
        source: &Mesh3,
        target: &Mesh3,
    ) -> Result<meshmorph::CorrespondResult> {
        let Some(path) = &self.markers else {
            bail!(
                "--markers is required to compute a correspondence (or pass --correspondence FILE)"
            );
        };
        let markers = Markers::read(path, self.one_based).context("reading the markers")?;
        let options = self.options();
        let bar = progress::bar(
            meshmorph::correspond::correspond_steps(&options) as u64,
            "correspond",
        );
        let result = correspond(source, target, &markers, &options, &mut |done| {
            bar.set_position(done as u64)
        })
        .with_context(|| {
            format!(
                "computing the correspondence {} with the markers `{}`",
                refs.describe(),
                path.display()
            )
        })?;
        bar.finish_and_clear();
        Ok(result)
    }
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
}

impl References {
    /// Both meshes as inputs of a plan.
    fn plan(&self, plan: &mut Plan) {
        plan.input(&self.source_ref, "source reference");
        plan.input(&self.target_ref, "target reference");
    }

    fn read(&self) -> Result<(Mesh3, Mesh3)> {
        let (s, t) = rayon::join(
            || output::read_mesh(&self.source_ref, "source reference"),
            || output::read_mesh(&self.target_ref, "target reference"),
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

/// Carry the poses of a source mesh over to a target mesh.
///
/// Writes one mesh per pose: DIR/<the pose file's stem>.<ext>.
///
/// Inputs are never written: an output that would land on an input is
/// refused before any work. All or nothing: every file is written under a
/// temporary name and moved into place only when the whole run has
/// succeeded; a failed or interrupted (Ctrl-C) run leaves every output
/// folder as it was.
#[derive(Debug, clap::Args)]
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
    /// Target vertices (comma-separated, 0-based) held at their rest
    /// positions in every pose, instead of placing the result by its centroid.
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
    /// Source poses: meshes with the source reference's vertices and triangles.
    #[arg(required = true, value_name = "POSE")]
    pub poses: Vec<PathBuf>,
}

/// A 0-based vertex index.
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
    pub unmatched_source_triangles: usize,
    pub unmatched_target_triangles: usize,
    /// Target vertices no triangle uses: written at their rest positions.
    pub unused_target_vertices: usize,
    pub total_seconds: f64,
}

impl TransferReport {
    fn print(&self, json: bool) {
        if json {
            output::print_json(self);
            return;
        }
        println!(
            "wrote {} poses to {}",
            self.poses_written,
            self.output.display()
        );
        println!(
            "correspondence: {} ({} pairs; unmatched: {} source, {} target triangles){}",
            output::human_seconds(self.correspondence_seconds),
            self.matched_pairs,
            self.unmatched_source_triangles,
            self.unmatched_target_triangles,
            if self.correspondence_loaded {
                ", loaded"
            } else {
                ""
            }
        );
        if self.unused_target_vertices > 0 {
            println!(
                "unused target vertices: {} (in no triangle; kept at rest)",
                self.unused_target_vertices
            );
        }
        println!(
            "setup:          {}",
            output::human_seconds(self.setup_seconds)
        );
        println!(
            "time per pose:  {} solving, {} with reading and writing",
            output::human_seconds(self.seconds_per_pose),
            output::human_seconds(self.seconds_per_pose_with_io)
        );
        println!(
            "total:          {}",
            output::human_seconds(self.total_seconds)
        );
    }
}

pub fn run_transfer(args: &TransferArgs) -> Result<()> {
    let start = Instant::now();
    let format = output::format_or_like(args.format, &args.refs.target_ref)?;
    let mut plan = Plan::new();
    for pose in &args.poses {
        plan.input(pose, "source pose");
    }
    args.refs.plan(&mut plan);
    if let Some(m) = &args.correspond.markers {
        plan.input(m, "marker file");
    }
    if let Some(c) = &args.correspondence {
        plan.input(c, "correspondence");
    }
    let pose_outputs: Vec<_> = pose_paths(&args.poses, &args.output, format.extension())?
        .iter()
        .map(|p| plan.file(p, "transferred pose"))
        .collect();
    let save = args
        .save_correspondence
        .as_deref()
        .map(|p| plan.file(p, "correspondence to save"));
    let staging = plan.prepare()?;
    let mut read: Vec<&Path> = args.poses.iter().map(PathBuf::as_path).collect();
    read.extend([
        args.refs.source_ref.as_path(),
        args.refs.target_ref.as_path(),
    ]);
    memory::check_reading(&read)?;
    let (source, target) = args.refs.read()?;

    // Read and check every pose first: a bad pose is reported before the
    // slow correspondence, and nothing is written.
    let poses: Vec<(Mesh3, f64)> = args
        .poses
        .par_iter()
        .map(|path| {
            let begin = Instant::now();
            let pose = output::read_mesh(path, "source pose")?;
            pose.check_same_connectivity(&source, ["the pose", "the source reference"])
                .with_context(|| {
                    format!(
                        "source pose `{}` does not fit the source reference",
                        path.display()
                    )
                })?;
            Ok((pose, begin.elapsed().as_secs_f64()))
        })
        .collect::<Result<_>>()?;

    let begin = Instant::now();
    let correspondence = match &args.correspondence {
        Some(path) => {
            let c = Correspondence::load(path).context("reading the correspondence")?;
            c.check_fits(&source, &target).with_context(|| {
                format!(
                    "correspondence `{}` does not fit these meshes",
                    path.display()
                )
            })?;
            c
        }
        None => {
            args.correspond
                .compute(&args.refs, &source, &target)?
                .correspondence
        }
    };
    let correspondence_seconds = begin.elapsed().as_secs_f64();

    let begin = Instant::now();
    memory::check_setup(
        source.num_triangles() + target.num_triangles(),
        "the transfer",
    )?;
    let pins = args
        .pin
        .iter()
        .map(|&v| {
            let p = target.positions().get(v as usize).with_context(|| {
                format!(
                    "--pin {v}: the target has {} vertices",
                    target.num_vertices()
                )
            })?;
            Ok((v, *p))
        })
        .collect::<Result<Vec<_>>>()?;
    let transfer = Transfer::new(
        &source,
        &target,
        &correspondence,
        &TransferOptions::default().with_pins(pins),
    )
    .with_context(|| format!("setting up the transfer {}", args.refs.describe()))?;
    let setup_seconds = begin.elapsed().as_secs_f64();

    let bar = progress::bar(poses.len() as u64, "poses");
    if let Some(save) = save {
        staging.write(save, |path| Ok(correspondence.save(path)?))?;
    }
    let timings: Vec<(f64, f64)> = poses
        .par_iter()
        .zip(&pose_outputs)
        .map_init(
            || transfer.workspace(),
            |ws, ((pose, read), &output)| {
                let begin = Instant::now();
                let mut out = vec![[0.0; 3]; target.num_vertices()];
                transfer.apply_into(pose.positions(), &mut out, ws);
                let solve = begin.elapsed().as_secs_f64();
                staging.write(output, |path| {
                    if let Some(v) = out.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
                        bail!("vertex {v} overflows (its coordinates exceed the range of floating-point numbers); scale the meshes down");
                    }
                    Ok(meshmorph::io::write_positions(
                        path,
                        &out,
                        target.triangles(),
                        format,
                    )?)
                })?;
                bar.inc(1);
                Ok((solve, read + begin.elapsed().as_secs_f64()))
            },
        )
        .collect::<Result<_>>()?;
    bar.finish_and_clear();
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
        unused_target_vertices: target.num_unused_vertices(),
        total_seconds: start.elapsed().as_secs_f64(),
    }
    .print(args.json);
    Ok(())
}

/// DIR/<stem>.<ext> for each pose, refusing two poses with the same stem.
fn pose_paths(poses: &[PathBuf], dir: &Path, ext: &str) -> Result<Vec<PathBuf>> {
    let mut seen = HashSet::new();
    poses
        .iter()
        .map(|p| {
            let stem = p
                .file_stem()
                .with_context(|| format!("pose `{}` has no file name", p.display()))?;
            if !seen.insert(stem.to_os_string()) {
                bail!(
                    "two poses are named `{}`: their outputs would overwrite each other",
                    stem.to_string_lossy()
                );
            }
            Ok(dir.join(stem).with_extension(ext))
        })
        .collect()
}

/// Compute the triangle correspondence between two meshes and save it.
#[derive(Debug, clap::Args)]
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
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// What `correspond` did.
#[derive(Debug, Serialize)]
pub struct CorrespondReport {
    pub output: PathBuf,
    pub seconds: f64,
    pub matched_pairs: usize,
    pub unmatched_source_triangles: usize,
    pub unmatched_target_triangles: usize,
}

pub fn run_correspond(args: &CorrespondCommand) -> Result<()> {
    let Some(markers) = &args.correspond.markers else {
        bail!("--markers is required");
    };
    // Checked before any work, so that a bad name leaves no output behind.
    let deformed_format = args
        .deformed_source
        .as_deref()
        .map(meshmorph::io::Format::from_path)
        .transpose()?;
    let mut plan = Plan::new();
    args.refs.plan(&mut plan);
    plan.input(markers, "marker file");
    let saved = plan.file(&args.output, "correspondence");
    let deformed = args
        .deformed_source
        .as_deref()
        .map(|p| plan.file(p, "deformed source"));
    let staging = plan.prepare()?;
    memory::check_reading(&[&args.refs.source_ref, &args.refs.target_ref])?;
    let (source, target) = args.refs.read()?;
    memory::check_setup(
        source.num_triangles() + target.num_triangles(),
        "the correspondence",
    )?;
    let begin = Instant::now();
    let result = args.correspond.compute(&args.refs, &source, &target)?;
    let seconds = begin.elapsed().as_secs_f64();
    let c = &result.correspondence;
    staging.write(saved, |path| Ok(c.save(path)?))?;
    if let (Some(output), Some(format)) = (deformed, deformed_format) {
        staging.write(output, |path| {
            Ok(meshmorph::io::write_mesh(
                path,
                &result.deformed_source,
                format,
            )?)
        })?;
    }
    staging.commit()?;
    let report = CorrespondReport {
        output: args.output.clone(),
        seconds,
        matched_pairs: c.pairs().len(),
        unmatched_source_triangles: c.unmatched_source(),
        unmatched_target_triangles: c.unmatched_target(),
    };
    if args.json {
        output::print_json(&report);
    } else {
        println!(
            "correspondence: {} pairs in {} (unmatched: {} source, {} target triangles), saved to {}",
            report.matched_pairs,
            output::human_seconds(seconds),
            report.unmatched_source_triangles,
            report.unmatched_target_triangles,
            args.output.display()
        );
    }
    Ok(())
}
