//! What the commands' batches share (`transfer --batch`, `expressions
//! --batch`): a batch file read as TOML or JSON, and its runs planned as
//! one before any of them starts.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde::de::DeserializeOwned;

use crate::outputs::{check_runs, Plan};

/// The most bytes a batch file may hold: 16 MiB, some 80,000 entries.
const MAX_BATCH_FILE_BYTES: u64 = 16 << 20;

/// A batch file: JSON when its name ends in `.json`, else TOML.
pub fn read<T: DeserializeOwned>(file: &Path) -> Result<T> {
    let text = meshmorph::io::read_text(file, MAX_BATCH_FILE_BYTES, "a batch file")
        .with_context(|| format!("cannot read the batch file `{}`", file.display()))?;
    let is_json = file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    if is_json {
        serde_json::from_str(&text).map_err(anyhow::Error::from)
    } else {
        toml::from_str(&text).map_err(anyhow::Error::from)
    }
    .with_context(|| format!("the batch file `{}`", file.display()))
}

/// The runs of `batch_files` (each named, with its plan) checked as one
/// ([`check_runs`], the batch files themselves read by all): a clash is
/// refused naming both runs; a run that reads and writes the same files as
/// one before it (the same entry reached twice) is left out, with a note
/// unless `quiet`. `what` names an entry (target, head).
pub fn runs_once<T>(
    runs: Vec<T>,
    named_plan: impl Fn(&T) -> (String, &Plan),
    batch_files: &[PathBuf],
    what: &str,
    quiet: bool,
) -> Result<Vec<T>> {
    let shared: Vec<(PathBuf, String)> = batch_files
        .iter()
        .map(|b| (b.clone(), "batch file".to_string()))
        .collect();
    let planned: Vec<(String, &Plan)> = runs.iter().map(&named_plan).collect();
    let repeats = check_runs(&planned, &shared)?;
    let mut kept = Vec::with_capacity(runs.len() - repeats.len());
    for (k, run) in runs.into_iter().enumerate() {
        if !repeats.contains(&k) {
            kept.push(run);
        } else if !quiet {
            say!(
                "note: {} reads and writes the same files as a {what} before it: run once",
                named_plan(&run).0
            );
        }
    }
    Ok(kept)
}
