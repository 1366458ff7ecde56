//! `meshmorph expressions --batch FILE`: the shapes put on many heads. The
//! template is read once; each head is an ordinary run (its outputs
//! written all or nothing, its report); a head that fails is reported and
//! the others go on, and the exit status says that one failed. Every
//! head's outputs are checked against every head's files before any work.
//!
//! A batch file, TOML or JSON, paths relative to it:
//!
//! ```toml
//! [[heads]]
//! head = "alice.obj"
//! markers = "alice.txt"
//! output = "alice-arkit.glb"     # or a folder: one mesh per shape
//!
//! [[heads]]
//! head = "bob.vrm"
//! mesh = "Face"                  # optional: a glTF or VRM head's mesh
//! markers = "bob.pp"
//! output = "bob-arkit.vrm"
//! gif = "bob.gif"                # optional, and png
//! ```

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};

use super::{plan_head, read_template, run_head, Args, Planned};
use crate::output;

/// The batch file's form, at the end of `meshmorph expressions --help`.
pub const FORMAT: &str = r#"A batch file (--batch), TOML or JSON, paths relative to it:

  [[heads]]
  head = "alice.obj"
  markers = "alice.txt"
  output = "alice-arkit.glb"            # or a folder: one mesh per shape

  [[heads]]
  head = "bob.vrm"
  mesh = "Face"                         # optional: a glTF or VRM head's mesh
  markers = "bob.pp"
  output = "bob-arkit.vrm"              # a copy of bob.vrm with the shapes added
  gif = "bob.gif"                       # optional, and png

The other options (--template, --method, --all-shapes, --vrm-expressions,
--json, ...) apply to every head."#;

/// A batch file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BatchFile {
    heads: Vec<HeadEntry>,
}

/// One head of a batch file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct HeadEntry {
    head: PathBuf,
    #[serde(default)]
    mesh: Option<String>,
    markers: PathBuf,
    output: PathBuf,
    #[serde(default)]
    png: Option<PathBuf>,
    #[serde(default)]
    gif: Option<PathBuf>,
}

/// The totals printed at the end.
#[derive(Debug, Serialize)]
struct BatchReport {
    heads: usize,
    #[serde(serialize_with = "output::lossy")]
    heads_failed: Vec<PathBuf>,
    shapes_written: usize,
    seconds: f64,
    expressions_seconds: f64,
}

/// One head of the batch: the command line's options with the head's files.
struct Job {
    /// The batch file it comes from and the head's index there, for messages.
    named: String,
    args: Args,
}

pub fn run(args: &Args) -> Result<()> {
    let start = Instant::now();
    if args.pictures.png.is_some() || args.pictures.gif.is_some() {
        bail!("--png and --gif name one picture; with --batch, give `png` and `gif` for each head in the batch file");
    }
    let mut jobs = Vec::new();
    for file in &args.batch {
        jobs.extend(read(file, args)?);
    }
    let template = read_template(args)?;
    let runs = plan(jobs, args, &template.0)?;
    let heads = runs.len();
    let (mut shapes, mut expressions_seconds) = (0, 0.0);
    let mut failed = Vec::new();
    for (k, (job, planned)) in runs.into_iter().enumerate() {
        if !args.json {
            say!("\n== {} of {}: {} ==", k + 1, heads, job.named);
        }
        match run_head(&job.args, &template, planned) {
            Ok(done) => {
                shapes += done.shapes;
                expressions_seconds += done.expressions_seconds;
            }
            Err(e) => {
                let message = format!("{}: {e:#}", job.named);
                tell!("error: {message}");
                if args.json {
                    output::print_json_error(&message, 1);
                }
                failed.push(job.args.output().to_path_buf());
            }
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    if args.json {
        output::print_json(&BatchReport {
            heads,
            heads_failed: failed.clone(),
            shapes_written: shapes,
            seconds,
            expressions_seconds,
        });
    } else {
        say!(
            "\nbatch: {} of {} heads written, {} in {} ({} fitting and carrying)",
            heads - failed.len(),
            heads,
            output::count(shapes, "shape"),
            output::human_seconds(seconds),
            output::human_seconds(expressions_seconds),
        );
    }
    if failed.len() == heads {
        bail!("every head failed (named above): nothing was written");
    }
    if !failed.is_empty() {
        bail!(
            "{} of {} heads failed (named above); the others were written",
            failed.len(),
            heads
        );
    }
    Ok(())
}

/// The heads of one batch file: its paths taken relative to its folder.
fn read(file: &Path, args: &Args) -> Result<Vec<Job>> {
    let batch: BatchFile = crate::batch_file::read(file)?;
    if batch.heads.is_empty() {
        bail!("the batch file `{}` lists no heads", file.display());
    }
    let folder = file.parent().unwrap_or(Path::new(""));
    let at = |p: &Path| folder.join(p);
    Ok(batch
        .heads
        .iter()
        .enumerate()
        .map(|(k, h)| {
            let mut job = args.clone();
            job.batch = Vec::new();
            job.head = Some(at(&h.head));
            job.mesh = h.mesh.clone();
            job.markers = Some(at(&h.markers));
            job.output = Some(at(&h.output));
            job.pictures.png = h.png.as_deref().map(at);
            job.pictures.gif = h.gif.as_deref().map(at);
            Job {
                named: format!("head {k} of `{}` (`{}`)", file.display(), h.head.display()),
                args: job,
            }
        })
        .collect())
}

/// The batch as one run, planned before any work: every head's outputs
/// against every head's inputs and the batch files, and against every
/// other head's outputs. A clash is refused naming both heads; a head
/// reached twice (the same batch file given twice) runs once.
fn plan(
    jobs: Vec<Job>,
    args: &Args,
    template: &meshmorph::ExpressionTemplate,
) -> Result<Vec<(Job, Planned)>> {
    let plans = jobs
        .iter()
        .map(|job| plan_head(&job.args, template).with_context(|| job.named.clone()))
        .collect::<Result<Vec<_>>>()?;
    let runs: Vec<(Job, Planned)> = jobs.into_iter().zip(plans).collect();
    crate::batch_file::runs_once(
        runs,
        |(job, planned)| (job.named.clone(), &planned.plan),
        &args.batch,
        "head",
        args.json,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_form_in_the_help_is_a_batch_file() {
        let toml_text: String = FORMAT
            .lines()
            .skip(1)
            .take_while(|l| !l.starts_with("The other options"))
            .map(|l| l.trim_start().to_string() + "\n")
            .collect();
        let batch: BatchFile = toml::from_str(&toml_text).unwrap();
        assert_eq!(batch.heads.len(), 2);
        assert_eq!(batch.heads[1].mesh.as_deref(), Some("Face"));
        assert_eq!(batch.heads[1].gif.as_deref(), Some(Path::new("bob.gif")));
    }
}
