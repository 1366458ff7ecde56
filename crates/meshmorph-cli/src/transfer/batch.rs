//! `meshmorph transfer --batch FILE`: one source's poses carried to many
//! targets. Each target is an ordinary transfer (its own correspondence,
//! reused from its file when given; its outputs written all or nothing);
//! a target that fails is reported and the others go on, and the exit
//! status says that one failed. The report ends with the totals.
//!
//! A batch file, TOML or JSON, paths relative to it:
//!
//! ```toml
//! source = "horse-reference.obj"
//! poses = ["horse-01.obj", "horse-02.obj"]
//!
//! [[targets]]
//! reference = "camel-reference.obj"
//! markers = "horse-camel.cons"        # or two point files: ["horse.pp", "camel.pp"]
//! # correspondence = "horse-camel.corr"  (instead of markers)
//! # save_correspondence = "horse-camel.corr"
//! # gltf = "camel.glb"
//! output = "camel/"
//! ```
//!
//! With glTF and VRM files, as `--source-ref`, `--target-ref` and `--gltf`
//! take them: a glTF `source` needs no `poses` (its morph targets are the
//! poses: `shapes` chooses some, `source_mesh` its mesh), a target's
//! `mesh` chooses the target's mesh, and a glTF or VRM `reference`'s
//! `gltf` is a copy of that file with the shapes added (`replace_shapes`,
//! `vrm_expressions` as the options of those names); then `output` may be
//! left out.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};

use super::{plan_transfer, run_transfer, Done, Planned, References, TransferArgs};
use crate::output;

/// The batch file's form, at the end of `meshmorph transfer --help`.
pub const FORMAT: &str = r#"A batch file (--batch), TOML or JSON, paths relative to it:

  source = "horse-reference.obj"
  poses = ["horse-01.obj", "horse-02.obj"]

  [[targets]]
  reference = "camel-reference.obj"
  markers = "horse-camel.cons"          # or two point files: ["horse.pp", "camel.pp"]
  save_correspondence = "horse-camel.corr"   # optional
  gltf = "camel.glb"                    # optional
  output = "camel/"

  [[targets]]
  reference = "llama-reference.obj"
  correspondence = "horse-llama.corr"   # instead of markers
  output = "llama/"

With a glTF or VRM source, its morph targets are the poses:

  source = "rig.glb"
  source_mesh = "Face"                  # optional: the mesh's or its node's name
  shapes = ["jawOpen", "eyeBlinkLeft"]  # optional: default every one

  [[targets]]
  reference = "mychar.vrm"
  mesh = "Body"                         # optional
  markers = "rig-mychar.txt"
  gltf = "mychar-shapes.vrm"            # a copy of mychar.vrm with the shapes added
  replace_shapes = false                # optional: as --replace-shapes
  vrm_expressions = true                # optional: as --vrm-expressions"#;

/// A batch file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BatchFile {
    source: PathBuf,
    /// A glTF source's mesh.
    #[serde(default)]
    source_mesh: Option<String>,
    /// None: a glTF source's morph targets.
    #[serde(default)]
    poses: Vec<PathBuf>,
    /// A glTF source's morph targets to carry over (default every one).
    #[serde(default)]
    shapes: Vec<String>,
    targets: Vec<Target>,
}

/// One target of a batch file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Target {
    reference: PathBuf,
    /// A glTF reference's mesh.
    #[serde(default)]
    mesh: Option<String>,
    #[serde(default)]
    markers: Option<MarkerFiles>,
    #[serde(default)]
    correspondence: Option<PathBuf>,
    #[serde(default)]
    save_correspondence: Option<PathBuf>,
    #[serde(default)]
    gltf: Option<PathBuf>,
    #[serde(default)]
    replace_shapes: bool,
    #[serde(default)]
    vrm_expressions: bool,
    /// Needed unless `gltf` is given.
    #[serde(default)]
    output: Option<PathBuf>,
}

/// One file of pairs, or the source's and the target's point files.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum MarkerFiles {
    One(PathBuf),
    Several(Vec<PathBuf>),
}

/// The totals printed at the end.
#[derive(Debug, Serialize)]
struct BatchReport {
    targets: usize,
    #[serde(serialize_with = "output::lossy")]
    targets_failed: Vec<PathBuf>,
    shapes_written: usize,
    seconds: f64,
    shapes_per_second: f64,
    correspondence_seconds: f64,
    transfer_seconds: f64,
}

/// One transfer of the batch: the command line's options with the target's
/// files.
struct Job {
    /// The batch file it comes from and the target's index there, for messages.
    named: String,
    args: TransferArgs,
}

pub fn run(args: &TransferArgs) -> Result<()> {
    let start = Instant::now();
    let mut jobs = Vec::new();
    for file in &args.batch {
        jobs.extend(read(file, args)?);
    }
    let jobs = plan(jobs, args)?;
    let mut done = Done::default();
    let mut failed = Vec::new();
    for (k, job) in jobs.iter().enumerate() {
        if !args.json {
            say!("\n== {} of {}: {} ==", k + 1, jobs.len(), job.named);
        }
        match run_transfer(&job.args) {
            Ok(d) => {
                done.poses += d.poses;
                done.correspondence_seconds += d.correspondence_seconds;
                done.transfer_seconds += d.transfer_seconds;
            }
            Err(e) => {
                let message = format!("{}: {e:#}", job.named);
                tell!("error: {message}");
                if args.json {
                    output::print_json_error(&message, 1);
                }
                let written = job.args.output.as_ref().or(job.args.gltf.gltf.as_ref());
                failed.push(written.cloned().unwrap_or_default());
            }
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    let report = BatchReport {
        targets: jobs.len(),
        targets_failed: failed.clone(),
        shapes_written: done.poses,
        seconds,
        shapes_per_second: done.poses as f64 / seconds,
        correspondence_seconds: done.correspondence_seconds,
        transfer_seconds: done.transfer_seconds,
    };
    if args.json {
        output::print_json(&report);
    } else {
        say!(
            "\nbatch: {} of {} targets written, {} in {} ({:.1} shapes a second): {} in correspondences, {} in transfers",
            jobs.len() - failed.len(),
            jobs.len(),
            output::count(done.poses, "shape"),
            output::human_seconds(seconds),
            report.shapes_per_second,
            output::human_seconds(done.correspondence_seconds),
            output::human_seconds(done.transfer_seconds),
        );
    }
    if !failed.is_empty() {
        bail!(
            "{} of {} targets failed (named above); the others were written",
            failed.len(),
            jobs.len()
        );
    }
    Ok(())
}

/// The jobs of one batch file: its paths taken relative to its folder.
fn read(file: &Path, args: &TransferArgs) -> Result<Vec<Job>> {
    let batch: BatchFile = crate::batch_file::read(file)?;
    if batch.poses.is_empty() && !crate::gltf::is_gltf(&batch.source) {
        bail!(
            "the batch file `{}` lists no poses (a glTF or VRM source's morph targets would be them; `{}` is not one)",
            file.display(),
            batch.source.display()
        );
    }
    if !batch.poses.is_empty() && !batch.shapes.is_empty() {
        bail!(
            "the batch file `{}`: `shapes` chooses morph targets of a glTF source when no `poses` are listed; give one of them",
            file.display()
        );
    }
    if batch.targets.is_empty() {
        bail!("the batch file `{}` lists no targets", file.display());
    }
    let folder = file.parent().unwrap_or(Path::new(""));
    let at = |p: &Path| folder.join(p);
    batch
        .targets
        .iter()
        .enumerate()
        .map(|(k, t)| {
            let named = format!(
                "target {k} of `{}` (`{}`)",
                file.display(),
                t.reference.display()
            );
            let markers = match &t.markers {
                None => Vec::new(),
                Some(MarkerFiles::One(m)) => vec![at(m)],
                Some(MarkerFiles::Several(m)) if (1..=2).contains(&m.len()) => {
                    m.iter().map(|p| at(p)).collect()
                }
                Some(MarkerFiles::Several(_)) => {
                    bail!("{named}: `markers` is one file of pairs or two files of points")
                }
            };
            if markers.is_empty() == t.correspondence.is_none() {
                bail!("{named}: give `markers` or `correspondence` (one of them)");
            }
            if t.output.is_none() && t.gltf.is_none() {
                bail!("{named}: give `output` (a folder for the poses), `gltf` or both");
            }
            if t.output.is_some() && batch.poses.is_empty() {
                bail!("{named}: `output` is a folder for the poses listed in `poses`; a glTF source's morph targets go into `gltf`");
            }
            let into_gltf = crate::gltf::is_gltf(&t.reference);
            if (t.replace_shapes || t.vrm_expressions) && !(into_gltf && t.gltf.is_some()) {
                bail!("{named}: `replace_shapes` and `vrm_expressions` add to a glTF or VRM `reference`'s own file, written as `gltf`");
            }
            let mut job = args.clone();
            job.batch = Vec::new();
            job.refs = Some(References {
                source_ref: at(&batch.source),
                target_ref: at(&t.reference),
                no_weld: args.refs.as_ref().is_some_and(|r| r.no_weld),
                source_mesh: batch.source_mesh.clone(),
                target_mesh: t.mesh.clone(),
            });
            job.correspond.markers = markers;
            job.correspondence = t.correspondence.as_deref().map(at);
            job.save_correspondence = t.save_correspondence.as_deref().map(at);
            job.gltf.gltf = t.gltf.as_deref().map(at);
            job.replace_shapes = t.replace_shapes;
            job.vrm_expressions = t.vrm_expressions;
            job.output = t.output.as_deref().map(at);
            job.poses = batch.poses.iter().map(|p| at(p)).collect();
            if !batch.shapes.is_empty() {
                job.shapes = batch.shapes.clone();
            }
            Ok(Job { named, args: job })
        })
        .collect()
}

/// The batch as one run, planned before any work: every output of every
/// target against every input of every target and the batch files (paths
/// resolved, links followed), and against every other target's outputs. A
/// clash is refused naming both targets; a target reached twice (the same
/// batch file given twice, by any path) runs once.
fn plan(jobs: Vec<Job>, args: &TransferArgs) -> Result<Vec<Job>> {
    let plans = jobs
        .iter()
        .map(|job| plan_transfer(&job.args).with_context(|| job.named.clone()))
        .collect::<Result<Vec<_>>>()?;
    let runs: Vec<(Job, Planned)> = jobs.into_iter().zip(plans).collect();
    let runs = crate::batch_file::runs_once(
        runs,
        |(job, planned)| (job.named.clone(), &planned.plan),
        &args.batch,
        "target",
        args.json,
    )?;
    // A glTF made from scratch (the target is not glTF) is a .glb, as
    // --gltf's own check says on the command line.
    for (job, _) in &runs {
        if let Some(g) = job.args.gltf.gltf.as_deref() {
            if !job.args.writes_into_gltf_target() {
                crate::pictures::file_named(&g.to_string_lossy(), "glb", "binary glTF")
                    .map_err(|e| anyhow::anyhow!("{}: `gltf` {e}", job.named))?;
            }
        }
    }
    Ok(runs.into_iter().map(|(job, _)| job).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_forms_in_the_help_are_batch_files() {
        let (meshes, rigs) = FORMAT.split_once("\nWith a glTF").unwrap();
        let toml_of = |form: &str| -> BatchFile {
            let text: String = form
                .lines()
                .skip(1)
                .map(|l| format!("{}\n", l.trim_start()))
                .collect();
            toml::from_str(&text).unwrap()
        };
        let batch = toml_of(meshes);
        assert_eq!(batch.poses.len(), 2);
        assert_eq!(batch.targets.len(), 2);
        assert!(batch.targets[0].markers.is_some() && batch.targets[1].correspondence.is_some());
        let batch = toml_of(rigs);
        assert!(batch.poses.is_empty());
        assert_eq!(batch.shapes, ["jawOpen", "eyeBlinkLeft"]);
        assert_eq!(batch.source_mesh.as_deref(), Some("Face"));
        let target = &batch.targets[0];
        assert_eq!(target.mesh.as_deref(), Some("Body"));
        assert!(target.output.is_none() && target.gltf.is_some() && target.vrm_expressions);
    }
}
