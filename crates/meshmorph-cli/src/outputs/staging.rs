//! Staged outputs: written under temporary names beside their final place,
//! moved there together by [`Staging::commit`], removed if the run fails.

use std::collections::HashSet;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{anyhow, bail, Result};

use super::interrupt::{self, Cleanup};
use super::plan::{self, Inputs, Named, Output, Plan};
use super::resolve::{Resolved, Resolver};
use super::stale;
use super::surplus;

/// A prepared plan: write each output with [`Staging::write`], then
/// [`Staging::commit`]. Dropped without a commit (an error, a panic), it
/// removes the staged files and the folders it created.
#[derive(Debug)]
pub struct Staging {
    outputs: Vec<Named>,
    resolved: Vec<Resolved>,
    /// Every file the run reads: those of the plan, then side files
    /// ([`Staging::also_reads`]), with their names and roles.
    inputs: Mutex<(Vec<Resolved>, Vec<Named>)>,
    frame_folders: Vec<PathBuf>,
    /// This run's own part of every staged name: unpredictable, so that
    /// nothing can be planted at a staged path before the run makes it.
    token: String,
    /// This process's id, the first part of every staged name.
    pid: u32,
    /// Folders the run creates, each staged whole under a hidden name
    /// beside its final place and moved there by one rename: (final,
    /// staged). Only the outermost of the missing folders.
    folders: Vec<(PathBuf, PathBuf)>,
    /// For each output, the staged folder it is in, if any.
    in_folder: Vec<Option<usize>>,
    committed: bool,
    /// What was said of earlier runs' leftovers removed from the folders.
    warnings: Vec<String>,
}

impl Staging {
    pub(super) fn new(plan: Plan, inputs: Vec<Resolved>, resolved: Vec<Resolved>) -> Result<Self> {
        interrupt::install();
        let pid = std::process::id();
        let token = stale::token();
        let missing = plan::missing_folders(&plan.outputs);
        // The outermost missing folders, each staged whole.
        let roots: Vec<&PathBuf> = missing
            .iter()
            .filter(|m| !missing.iter().any(|o| o != *m && m.starts_with(o)))
            .collect();
        let folders: Vec<(PathBuf, PathBuf)> = roots
            .iter()
            .enumerate()
            .map(|(j, r)| {
                (
                    (*r).clone(),
                    sibling(r, &format!(".meshmorph-{pid}-{token}-{j}.folder")),
                )
            })
            .collect();
        let in_folder = plan
            .outputs
            .iter()
            .map(|o| folders.iter().position(|(r, _)| o.path.starts_with(r)))
            .collect();
        create_staged_folders(&missing, &folders, &plan.outputs)?;
        let mut staging = Self {
            inputs: Mutex::new((inputs, plan.inputs)),
            outputs: plan.outputs,
            resolved,
            frame_folders: plan.frame_folders,
            token,
            pid,
            folders,
            in_folder,
            committed: false,
            warnings: Vec::new(),
        };
        interrupt::arm(staging.cleanup());
        staging.probe_folders()?;
        let mut scanned: Vec<PathBuf> = staging.folders().into_iter().map(|(f, _)| f).collect();
        scanned.extend(
            staging
                .folders
                .iter()
                .map(|(r, _)| parent_of(r).to_path_buf()),
        );
        scanned.dedup();
        let scanned: Vec<&Path> = scanned.iter().map(PathBuf::as_path).collect();
        staging.warnings = stale::remove_stale(&scanned);
        Ok(staging)
    }

    /// Files the run reads that the plan could not name before the meshes
    /// were read: an OBJ's material libraries and the textures they name.
    /// Call it before writing anything.
    ///
    /// # Errors
    /// An output that is one of `paths`, naming both.
    pub fn also_reads(&self, paths: &[PathBuf], role: &str) -> Result<()> {
        let mut resolver = Resolver::default();
        let mut inputs = self.inputs.lock().unwrap_or_else(|e| e.into_inner());
        for path in paths {
            let r = resolver.resolve(path);
            if let Some(k) = self.resolved.iter().position(|o| o.same_file(&r)) {
                bail!(
                    "{}",
                    plan::overwrite_message(
                        &self.outputs[k].role,
                        &self.outputs[k].path,
                        role,
                        path
                    )
                );
            }
            inputs.0.push(r);
            inputs.1.push(Named {
                path: path.clone(),
                role: role.to_string(),
            });
        }
        Ok(())
    }

    /// Where output `k` is written: `.meshmorph-<pid>-<token>-<k>.part`
    /// beside its final place, or its final name inside a staged folder.
    /// (Made when asked: a million frames keep no second list of paths.)
    fn staged(&self, k: usize) -> PathBuf {
        let path = &self.outputs[k].path;
        match self.in_folder[k] {
            Some(j) => rebase(path, &self.folders[j]),
            None => sibling(
                path,
                &format!(".meshmorph-{}-{}-{k}.part", self.pid, self.token),
            ),
        }
    }

    /// The folders the outputs are staged in, each once (`.` for the
    /// current one), with the first output in each.
    fn folders(&self) -> Vec<(PathBuf, usize)> {
        let mut folders: Vec<(PathBuf, usize)> = Vec::new();
        let mut last: Option<&Path> = None;
        for (k, output) in self.outputs.iter().enumerate() {
            // An output's staged folder follows from its folder, which the
            // frames share.
            let folder = parent_of(&output.path);
            if last == Some(folder) {
                continue;
            }
            last = Some(folder);
            let staged = parent_of(&self.staged(k)).to_path_buf();
            if !folders.iter().any(|(f, _)| *f == staged) {
                folders.push((staged, k));
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
            if self.in_folder[k].is_some() {
                // Made by this run: it took its first entry already.
                continue;
            }
            let (named, staged) = (&self.outputs[k], self.staged(k));
            let _writing = interrupt::writing()?;
            // Created afresh (never through a file or link already there).
            let made = std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&staged);
            match made {
                Ok(file) => {
                    drop(file);
                    let _ = std::fs::remove_file(&staged);
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
        let staged = self.staged(output.0);
        write(&staged).map_err(|e| {
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

    /// Writes one output through a writer: [`Staging::write`] with the
    /// staged file made by the staging itself, new (`O_CREAT|O_EXCL`: what
    /// is at the name is never written through), at the staged path, where
    /// `write` writes its bytes into `w` (`path`, the staged path, only
    /// for what the bytes depend on, such as relative paths). No temporary
    /// name then a rename: inside a folder the run created the file is
    /// made at its final name in the hidden staged folder, which nothing
    /// reads before the commit moves it into place; elsewhere at its
    /// `.part` name, which only this run knows. A file whose write fails
    /// is removed.
    ///
    /// # Errors
    /// As [`Staging::write`].
    pub fn write_to(
        &self,
        output: Output,
        write: impl FnOnce(&Path, &mut dyn Write) -> Result<()>,
    ) -> Result<()> {
        self.write(output, |staged| {
            meshmorph::io::write_new(staged, |w| write(staged, w))
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
        // Another run moving outputs into one of these folders finishes
        // first: two runs' frames never mix. Taken before the interrupt's
        // hold, so that Ctrl-C while waiting still cleans up at once.
        let _locks = self.lock_folders();
        let _exclusive = interrupt::exclusive()?;
        // (output, where the file it replaced is kept until every move is
        // done); the outputs in staged folders move with their folder.
        let mut placed: Vec<(usize, Option<Aside>)> = Vec::new();
        let loose: Vec<usize> = (0..self.outputs.len())
            .filter(|&k| self.in_folder[k].is_none())
            .collect();
        if let Err(e) = self.move_files(&loose, &mut placed) {
            roll_back(&self.outputs, &placed, &[]);
            return Err(e);
        }
        let mut moved_folders = 0;
        // The staged folders whose outputs moved in one by one.
        let mut merged = Vec::new();
        for (j, (folder, staged)) in self.folders.iter().enumerate() {
            if std::fs::rename(staged, folder).is_ok() {
                moved_folders = j + 1;
                continue;
            }
            merged.push(j);
            // The folder was made meanwhile (another run into it, which
            // committed before this one took its locks, so that this one
            // holds that folder's lock too): its outputs move in one by one,
            // as into any existing folder.
            let inside: Vec<usize> = (0..self.outputs.len())
                .filter(|&k| self.in_folder[k] == Some(j))
                .collect();
            let made = inside.iter().try_for_each(|&k| {
                std::fs::create_dir_all(parent_of(&self.outputs[k].path)).map_err(|e| {
                    anyhow!(
                        "creating the folder `{}`: {e}",
                        parent_of(&self.outputs[k].path).display()
                    )
                })
            });
            if let Err(e) = made.and_then(|()| self.move_files(&inside, &mut placed)) {
                roll_back(&self.outputs, &placed, &self.folders[..moved_folders]);
                return Err(e);
            }
            let _ = std::fs::remove_dir_all(staged);
        }
        for (_, aside) in &placed {
            if let Some(a) = aside {
                let _ = std::fs::remove_file(a.path());
            }
        }
        self.committed = true;
        interrupt::committed();
        Ok(self.remove_surplus(&merged))
    }

    /// Moves the staged files of `outputs` into place, each file it
    /// replaces kept aside (see [`Aside`]), adding each to `placed`.
    ///
    /// # Errors
    /// The output that could not be moved (those in `placed` are to be
    /// rolled back).
    fn move_files(
        &self,
        outputs: &[usize],
        placed: &mut Vec<(usize, Option<Aside>)>,
    ) -> Result<()> {
        for &k in outputs {
            let target = &self.outputs[k].path;
            let moved = (|| {
                let aside = if std::fs::symlink_metadata(target).is_ok() {
                    Some(set_aside(
                        target,
                        &format!(".meshmorph-{}-{}-{k}", self.pid, self.token),
                    )?)
                } else {
                    None
                };
                match std::fs::rename(self.staged(k), target) {
                    Ok(()) => Ok(aside),
                    Err(e) => {
                        if let Some(a) = &aside {
                            a.put_back(target);
                        }
                        Err(e)
                    }
                }
            })();
            match moved {
                Ok(aside) => placed.push((k, aside)),
                Err(e) => {
                    let (role, path) = (&self.outputs[k].role, target.display());
                    if e.kind() == std::io::ErrorKind::NotFound && !self.staged(k).exists() {
                        bail!("the {role} `{path}` was not written; no output was changed");
                    }
                    bail!("moving the {role} into place at `{path}`: {e}; no output was changed");
                }
            }
        }
        Ok(())
    }

    /// Holds every output folder against other runs' commits (an advisory
    /// lock on the folder itself: no file is made for it) until dropped.
    /// A folder that cannot be locked (a file system without locks) is
    /// written without.
    fn lock_folders(&self) -> Vec<std::fs::File> {
        // The folders the outputs go to, and the folders the staged
        // folders are moved into.
        let mut finals: std::collections::BTreeSet<&Path> =
            self.outputs.iter().map(|o| parent_of(&o.path)).collect();
        finals.extend(self.folders.iter().map(|(r, _)| parent_of(r)));
        lock(finals.into_iter())
    }

    /// Frame files in the frame folders that this run did not write and
    /// that are not inputs. A frame folder the run made and moved into
    /// place whole (in a staged folder not `merged`) holds only what the
    /// run wrote: it is not read. Elsewhere the run's own frames are known
    /// by their names; only the other frame files are looked at.
    fn remove_surplus(&self, merged: &[usize]) -> usize {
        let made_whole = |dir: &Path| {
            self.folders
                .iter()
                .position(|(root, _)| dir.starts_with(root))
                .is_some_and(|j| !merged.contains(&j))
        };
        let mut swept = self
            .frame_folders
            .iter()
            .filter(|d| !made_whole(d))
            .peekable();
        if swept.peek().is_none() {
            return 0;
        }
        let written: HashSet<&Path> = self.outputs.iter().map(|o| o.path.as_path()).collect();
        let mut keep = Inputs::new(&self.resolved);
        {
            let inputs = self.inputs.lock().unwrap_or_else(|e| e.into_inner());
            for r in &inputs.0 {
                keep.insert(r, 0);
            }
        }
        let mut resolver = Resolver::default();
        let mut removed = 0;
        for dir in swept {
            let keep = |p: &Path| written.contains(p) || keep.find(&resolver.resolve(p)).is_some();
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
            staged: (0..self.outputs.len())
                .filter(|&k| self.in_folder[k].is_none())
                .map(|k| self.staged(k))
                .collect(),
            folders: self
                .folders
                .iter()
                .map(|(_, staged)| staged.clone())
                .collect(),
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

/// Advisory locks on `folders` (those that exist), taken in one order for
/// every run (by canonical path), so that two runs never wait for each
/// other; held until the files are dropped. A folder that cannot be
/// locked (a file system without locks) is written without.
fn lock<'a>(folders: impl Iterator<Item = &'a Path>) -> Vec<std::fs::File> {
    let mut canonical: Vec<PathBuf> = folders.filter_map(|f| f.canonicalize().ok()).collect();
    canonical.sort();
    canonical.dedup();
    canonical
        .iter()
        .filter_map(|f| {
            let folder = std::fs::File::open(f).ok()?;
            folder.lock().ok()?;
            Some(folder)
        })
        .collect()
}

/// A file an output replaces, kept aside until every move is done.
#[derive(Debug)]
enum Aside {
    /// A second name of the file (a hard link): the output's path is
    /// never empty, and the link may be removed whatever happens.
    Linked(PathBuf),
    /// The file itself, moved (where the file system has no hard links):
    /// until it is moved back or the output replaces it, it is the only
    /// copy, so a later run reports it and never removes it.
    Moved(PathBuf),
}

impl Aside {
    fn path(&self) -> &Path {
        match self {
            Aside::Linked(p) | Aside::Moved(p) => p,
        }
    }

    /// Restores the file at `target`.
    fn put_back(&self, target: &Path) {
        let _ = std::fs::rename(self.path(), target);
    }
}

/// Keeps the file at `target` under `name` (`.old` for a link, `.aside`
/// when moved) in its folder.
fn set_aside(target: &Path, name: &str) -> std::io::Result<Aside> {
    let linked = sibling(target, &format!("{name}.old"));
    if std::fs::hard_link(target, &linked).is_ok() {
        return Ok(Aside::Linked(linked));
    }
    let moved = sibling(target, &format!("{name}.aside"));
    std::fs::rename(target, &moved)?;
    Ok(Aside::Moved(moved))
}

/// Undoes the moves done so far, last first: the staged folders moved
/// into place (`folders`), then the files.
fn roll_back(outputs: &[Named], placed: &[(usize, Option<Aside>)], folders: &[(PathBuf, PathBuf)]) {
    for (folder, staged) in folders.iter().rev() {
        let _ = std::fs::rename(folder, staged);
    }
    for (k, aside) in placed.iter().rev() {
        let target = &outputs[*k].path;
        match aside {
            Some(a) => a.put_back(target),
            None => {
                let _ = std::fs::remove_file(target);
            }
        }
    }
}

/// Creates the staged folders (`folders`: final and staged path of each
/// outermost missing folder) and, inside them, the other `missing` ones.
/// Each is created new: nothing planted at a staged name is followed.
///
/// # Errors
/// Naming the user's folder that could not be made, and the first output
/// in it; whatever was made is removed.
fn create_staged_folders(
    missing: &[PathBuf],
    folders: &[(PathBuf, PathBuf)],
    outputs: &[Named],
) -> Result<()> {
    for dir in missing {
        let Some(j) = folders.iter().position(|(r, _)| dir.starts_with(r)) else {
            continue;
        };
        let staged = rebase(dir, &folders[j]);
        if let Err(e) = std::fs::create_dir(&staged) {
            for (_, root) in &folders[..=j] {
                let _ = std::fs::remove_dir_all(root);
            }
            let first = outputs.iter().find(|o| o.path.starts_with(dir));
            let what = first.map_or(String::new(), |o| {
                format!("the {} `{}`: ", o.role, o.path.display())
            });
            bail!(
                "cannot write {what}the folder `{}` cannot be made in `{}` ({e}); nothing was computed",
                dir.display(),
                parent_of(dir).display()
            );
        }
    }
    Ok(())
}

/// `path` (inside the folder `root.0`) at its place inside the staged
/// folder `root.1`.
fn rebase(path: &Path, root: &(PathBuf, PathBuf)) -> PathBuf {
    match path.strip_prefix(&root.0) {
        Ok(rest) if !rest.as_os_str().is_empty() => root.1.join(rest),
        _ => root.1.clone(),
    }
}

/// The folder of `path` (`.` for a bare name).
fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// `name` in the folder of `path`.
fn sibling(path: &Path, name: &str) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.join(name),
        _ => PathBuf::from(name),
    }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn a_link_planted_at_a_staged_name_is_replaced_not_followed() {
        let dir = tempfile::tempdir().unwrap();
        let victim = dir.path().join("victim.txt");
        std::fs::write(&victim, "precious").unwrap();
        let mut plan = Plan::new();
        let out = plan.file(&dir.path().join("out/a.txt"), "test output");
        let staging = plan.prepare().unwrap();
        staging
            .write(out, |staged| {
                assert!(staged.to_string_lossy().contains(&staging.token));
                // Planted between the plan and the write: the writer's
                // rename replaces the link.
                std::os::unix::fs::symlink(&victim, staged).unwrap();
                Ok(meshmorph::io::write_atomic(staged, |w| {
                    w.write_all(b"new")
                })?)
            })
            .unwrap();
        staging.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
        assert_eq!(
            std::fs::read_to_string(dir.path().join("out/a.txt")).unwrap(),
            "new"
        );
    }

    #[test]
    fn writers_make_their_files_new_at_the_staged_paths() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("old")).unwrap();
        let mut plan = Plan::new();
        let fresh = plan.file(&dir.path().join("new/a.txt"), "test output");
        let existing = plan.file(&dir.path().join("old/b.txt"), "test output");
        let staging = plan.prepare().unwrap();
        staging
            .write_to(fresh, |path, w| {
                // In a folder the run makes: its final name, in the hidden
                // staged folder.
                assert_eq!(path.file_name().unwrap(), "a.txt");
                assert!(path
                    .parent()
                    .unwrap()
                    .to_string_lossy()
                    .ends_with(".folder"));
                Ok(w.write_all(b"a")?)
            })
            .unwrap();
        staging
            .write_to(existing, |path, w| {
                assert!(path.to_string_lossy().ends_with(".part"));
                Ok(w.write_all(b"b")?)
            })
            .unwrap();
        // Made new: a file already at the name is refused, not written
        // through, and the message names the user's path.
        let again = staging
            .write_to(fresh, |_, w| Ok(w.write_all(b"x")?))
            .unwrap_err()
            .to_string();
        assert!(again.contains("new/a.txt"), "{again}");
        assert!(!again.contains(".meshmorph-"), "{again}");
        staging.commit().unwrap();
        let read = |p: &str| std::fs::read_to_string(dir.path().join(p)).unwrap();
        assert_eq!(
            (read("new/a.txt"), read("old/b.txt")),
            ("a".into(), "b".into())
        );
        let mut names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .chain(std::fs::read_dir(dir.path().join("old")).unwrap())
            .map(|e| e.unwrap().file_name())
            .collect();
        names.sort();
        assert_eq!(names, ["b.txt", "new", "old"]);
    }

    #[test]
    fn a_replaced_file_keeps_its_path_during_the_moves() {
        // Kept aside as a second name: the user's path is never empty, and
        // a failed move puts every earlier output back.
        let dir = tempfile::tempdir().unwrap();
        let old = dir.path().join("a.txt");
        std::fs::write(&old, "old").unwrap();
        let aside = set_aside(&old, ".meshmorph-1-x-0").unwrap();
        assert!(matches!(aside, Aside::Linked(_)));
        assert_eq!(std::fs::read_to_string(&old).unwrap(), "old");
        assert_eq!(std::fs::read_to_string(aside.path()).unwrap(), "old");
        std::fs::write(dir.path().join("new"), "new").unwrap();
        std::fs::rename(dir.path().join("new"), &old).unwrap();
        aside.put_back(&old);
        assert_eq!(std::fs::read_to_string(&old).unwrap(), "old");
        assert!(!aside.path().exists());
    }
}
