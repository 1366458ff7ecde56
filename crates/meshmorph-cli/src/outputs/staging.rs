//! Staged outputs: written under temporary names beside their final place,
//! moved there together by [`Staging::commit`], removed if the run fails.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, Result};

use super::interrupt::{self, Cleanup};
use super::plan::{self, Named, Output, Plan};
use super::resolve::Resolved;
use super::stale;
use super::surplus;

/// A prepared plan: write each output with [`Staging::write`], then
/// [`Staging::commit`]. Dropped without a commit (an error, a panic), it
/// removes the staged files and the folders it created.
#[derive(Debug)]
pub struct Staging {
    outputs: Vec<Named>,
    resolved: Vec<Resolved>,
    inputs: Vec<Resolved>,
    frame_folders: Vec<PathBuf>,
    staged: Vec<PathBuf>,
    created: Vec<PathBuf>,
    committed: bool,
    /// What was said of earlier runs' leftovers removed from the folders.
    warnings: Vec<String>,
}

impl Staging {
    pub(super) fn new(plan: Plan, inputs: Vec<Resolved>, resolved: Vec<Resolved>) -> Result<Self> {
        interrupt::install();
        let pid = std::process::id();
        let staged = plan
            .outputs
            .iter()
            .enumerate()
            .map(|(k, o)| sibling(&o.path, &format!(".meshmorph-{pid}-{k}.part")))
            .collect();
        let created = plan::create_folders(&plan::missing_folders(&plan.outputs))?;
        let mut staging = Self {
            outputs: plan.outputs,
            resolved,
            inputs,
            frame_folders: plan.frame_folders,
            staged,
            created,
            committed: false,
            warnings: Vec::new(),
        };
        interrupt::arm(staging.cleanup());
        staging.probe_folders()?;
        let folders: Vec<&Path> = staging.folders().into_iter().map(|(f, _)| f).collect();
        staging.warnings = stale::remove_stale(&folders);
        Ok(staging)
    }

    /// The folders of the outputs, each once (`.` for the current one),
    /// with the first output in each.
    fn folders(&self) -> Vec<(&Path, usize)> {
        let mut folders: Vec<(&Path, usize)> = Vec::new();
        for (k, staged) in self.staged.iter().enumerate() {
            let folder = match staged.parent() {
                Some(d) if !d.as_os_str().is_empty() => d,
                _ => Path::new("."),
            };
            if !folders.iter().any(|(f, _)| *f == folder) {
                folders.push((folder, k));
            }
        }
        folders
    }

    /// Warnings for the report: staged files of runs stopped by force
    /// removed from the output folders.
    pub fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// Refuses a run whose outputs could not be written, before any work:
    /// in each output folder, creates the staged file of its first output
    /// and removes it again.
    ///
    /// # Errors
    /// Naming the user's path and the folder that refused.
    fn probe_folders(&self) -> Result<()> {
        for (folder, k) in self.folders() {
            let (named, staged) = (&self.outputs[k], &self.staged[k]);
            let _writing = interrupt::writing()?;
            // The staged name is this run's own: a file there is replaced.
            let made = std::fs::OpenOptions::new()
                .write(true)
                .create(true)
                .truncate(true)
                .open(staged);
            match made {
                Ok(file) => {
                    drop(file);
                    let _ = std::fs::remove_file(staged);
                }
                Err(e) => {
                    return Err(anyhow!(
                        "cannot write the {} `{}`: the folder `{}` does not take new files ({e}); nothing was computed",
                        named.role,
                        named.path.display(),
                        folder.display()
                    ));
                }
            }
        }
        Ok(())
    }

    /// Writes one output: `write` gets the staged path to write to (any
    /// writer that creates the file at a path will do). Safe to call from
    /// several threads at once. An error names the user's path, never the
    /// staged one.
    ///
    /// # Errors
    /// `write`'s error, with the output named; or the run was interrupted.
    pub fn write(&self, output: Output, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
        let _writing = interrupt::writing()?;
        let named = &self.outputs[output.0];
        let staged = &self.staged[output.0];
        write(staged).map_err(|e| {
            let message = format!("{e:#}").replace(
                &staged.display().to_string(),
                &named.path.display().to_string(),
            );
            anyhow!(
                "writing the {} `{}`: {message}",
                named.role,
                named.path.display()
            )
        })
    }

    /// Moves every staged output into place, then removes the surplus
    /// frames of an earlier run; returns how many of those it removed.
    /// Either every output is in place afterwards, or (on error) none has
    /// changed.
    ///
    /// # Errors
    /// An output that was never written, or a move the system refused.
    pub fn commit(mut self) -> Result<usize> {
        let _exclusive = interrupt::exclusive()?;
        if let Some(k) = (0..self.staged.len()).find(|&k| !self.staged[k].exists()) {
            return Err(anyhow!(
                "the {} `{}` was not written",
                self.outputs[k].role,
                self.outputs[k].path.display()
            ));
        }
        let pid = std::process::id();
        // (final path, backup of the file it replaced)
        let mut placed: Vec<(usize, Option<PathBuf>)> = Vec::new();
        for k in 0..self.staged.len() {
            let target = &self.outputs[k].path;
            let backup = sibling(target, &format!(".meshmorph-{pid}-{k}.old"));
            let had = std::fs::symlink_metadata(target).is_ok();
            let moved = (|| {
                if had {
                    std::fs::rename(target, &backup)?;
                }
                std::fs::rename(&self.staged[k], target).inspect_err(|_| {
                    if had {
                        let _ = std::fs::rename(&backup, target);
                    }
                })
            })();
            if let Err(e) = moved {
                roll_back(&self.outputs, &placed);
                return Err(anyhow!(
                    "moving the {} into place at `{}`: {e}; no output was changed",
                    self.outputs[k].role,
                    target.display()
                ));
            }
            placed.push((k, had.then_some(backup)));
        }
        for (_, backup) in &placed {
            if let Some(b) = backup {
                let _ = std::fs::remove_file(b);
            }
        }
        self.committed = true;
        interrupt::disarm();
        Ok(self.remove_surplus())
    }

    /// Frame files in the frame folders that this run did not write and
    /// that are not inputs.
    fn remove_surplus(&self) -> usize {
        let mut removed = 0;
        for dir in &self.frame_folders {
            let keep = |p: &Path| {
                let r = Resolved::new(p);
                self.resolved.iter().any(|o| o.same_file(&r))
                    || self.inputs.iter().any(|i| i.same_file(&r))
            };
            for p in surplus::surplus_frames(dir, keep) {
                if std::fs::remove_file(&p).is_ok() {
                    removed += 1;
                }
            }
        }
        removed
    }

    fn cleanup(&self) -> Cleanup {
        Cleanup {
            staged: self.staged.clone(),
            created: self.created.clone(),
        }
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            self.cleanup().run();
            interrupt::disarm();
        }
    }
}

/// Undoes the moves done so far, last first.
fn roll_back(outputs: &[Named], placed: &[(usize, Option<PathBuf>)]) {
    for (k, backup) in placed.iter().rev() {
        let target = &outputs[*k].path;
        match backup {
            Some(b) => {
                let _ = std::fs::rename(b, target);
            }
            None => {
                let _ = std::fs::remove_file(target);
            }
        }
    }
}

/// `name` in the folder of `path`.
fn sibling(path: &Path, name: &str) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.join(name),
        _ => PathBuf::from(name),
    }
}
