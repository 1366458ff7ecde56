//! The plan of a run: every file it reads and every file it will write,
//! checked against each other before any work.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use anyhow::{bail, Result};

use super::resolve::{Resolved, Resolver};
use super::staging::Staging;
use super::surplus::frame_path;

/// One output of a plan, to hand to [`Staging::write`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Output(pub(super) usize);

/// A file of the plan: where the user asked for it and what it is, for
/// messages ("source mesh", "frame", "animation", ...).
#[derive(Clone, Debug)]
pub(super) struct Named {
    pub path: PathBuf,
    pub role: String,
}

/// Every input and output of one run. Build it first, then
/// [`Plan::prepare`] it before reading large files or computing anything.
#[derive(Debug, Default)]
pub struct Plan {
    pub(super) inputs: Vec<Named>,
    pub(super) outputs: Vec<Named>,
    /// Folders of frame sets: their surplus frames go after a successful run.
    pub(super) frame_folders: Vec<PathBuf>,
}

impl Plan {
    pub fn new() -> Self {
        Self::default()
    }

    /// A file the run reads (it is never written, replaced or removed).
    pub fn input(&mut self, path: &Path, role: &str) {
        self.inputs.push(Named {
            path: path.to_path_buf(),
            role: role.to_string(),
        });
    }

    /// A file the run writes.
    pub fn file(&mut self, path: &Path, role: &str) -> Output {
        self.outputs.push(Named {
            path: path.to_path_buf(),
            role: role.to_string(),
        });
        Output(self.outputs.len() - 1)
    }

    /// `count` frames `dir/frame_0000.ext`, ... (see [`frame_path`]). Frame
    /// files of an earlier run left in `dir` are removed once this run has
    /// committed.
    pub fn frames(&mut self, dir: &Path, count: usize, ext: &str) -> Vec<Output> {
        if !self.frame_folders.iter().any(|d| d == dir) {
            self.frame_folders.push(dir.to_path_buf());
        }
        (0..count)
            .map(|k| self.file(&frame_path(dir, k, count, ext), "frame"))
            .collect()
    }

    /// Checks the plan and gets ready to write: refuses an output that is
    /// an input or another output (by resolved path and by device and
    /// inode), an output slot holding a folder or anything else that is not
    /// a regular file (a device, a FIFO, a socket, links followed), and an
    /// output folder that is a file; then creates the missing folders, arms the interrupt
    /// clean-up and refuses a folder that does not take new files.
    ///
    /// # Errors
    /// Naming both paths of a clash, or the path that cannot be used.
    pub fn prepare(self) -> Result<Staging> {
        let mut resolver = Resolver::default();
        let inputs: Vec<Resolved> = self
            .inputs
            .iter()
            .map(|i| resolver.resolve(&i.path))
            .collect();
        let read = Inputs::new(&inputs);
        let mut outputs: Vec<Resolved> = Vec::with_capacity(self.outputs.len());
        let mut checked = HashSet::new();
        for out in &self.outputs {
            let r = check_slot(out, &mut resolver, &mut checked)?;
            if let Some(k) = read.find(&r) {
                bail!(
                    "{}",
                    overwrite_message(
                        &out.role,
                        &out.path,
                        &self.inputs[k].role,
                        &self.inputs[k].path
                    )
                );
            }
            outputs.push(r);
        }
        check_distinct(&self.outputs, &outputs)?;
        Staging::new(self, inputs, outputs)
    }
}

/// The plans of several runs made as one (a batch's targets), checked
/// together before any of them starts: an output of any run that is an
/// input of any run (or one of `shared`, such as the batch files), or an
/// output of another run, or that cannot take a file, is refused naming
/// both runs (`runs[k].0` names run `k`). A run whose inputs and outputs are
/// all those of an earlier run (the same target reached twice) is that run:
/// the indices of such repeats are returned, to be left out.
///
/// # Errors
/// The first clash, naming both runs and both paths.
pub fn check_runs(
    runs: &[(String, &Plan)],
    shared: &[(PathBuf, String)],
) -> Result<HashSet<usize>> {
    let mut resolver = Resolver::default();
    let resolve_all = |resolver: &mut Resolver, files: &[Named]| -> Vec<Resolved> {
        files.iter().map(|f| resolver.resolve(&f.path)).collect()
    };
    let resolved: Vec<(Vec<Resolved>, Vec<Resolved>)> = runs
        .iter()
        .map(|(_, plan)| {
            (
                resolve_all(&mut resolver, &plan.inputs),
                resolve_all(&mut resolver, &plan.outputs),
            )
        })
        .collect();
    // The same run twice: the same files read and written, each in the
    // same role and place (a source and a target swapped are two runs).
    type Signature = Vec<(String, PathBuf)>;
    let mut seen: HashMap<(Signature, Signature), usize> = HashMap::new();
    let mut repeats = HashSet::new();
    for (k, ((_, plan), (inputs, outputs))) in runs.iter().zip(&resolved).enumerate() {
        let signature = |named: &[Named], files: &[Resolved]| -> Signature {
            named
                .iter()
                .zip(files)
                .map(|(n, f)| (n.role.clone(), f.path.clone()))
                .collect()
        };
        let key = (
            signature(&plan.inputs, inputs),
            signature(&plan.outputs, outputs),
        );
        if seen.insert(key, k).is_some() {
            repeats.insert(k);
        }
    }
    // Every input of every run, then the shared ones (owner `None`).
    let mut owners: Vec<(Option<usize>, &Path, &str)> = Vec::new();
    let mut read = Inputs::default();
    for (k, (_, plan)) in runs.iter().enumerate() {
        if repeats.contains(&k) {
            continue;
        }
        for (named, r) in plan.inputs.iter().zip(&resolved[k].0) {
            read.insert(r, owners.len());
            owners.push((Some(k), &named.path, &named.role));
        }
    }
    for (path, role) in shared {
        read.insert(&resolver.resolve(path), owners.len());
        owners.push((None, path, role));
    }
    let mut written: HashMap<PathBuf, (usize, usize)> = HashMap::new();
    let mut written_ids: HashMap<(u64, u64), (usize, usize)> = HashMap::new();
    let mut checked = HashSet::new();
    for (k, (name, plan)) in runs.iter().enumerate() {
        if repeats.contains(&k) {
            continue;
        }
        for (j, out) in plan.outputs.iter().enumerate() {
            let r = check_slot(out, &mut resolver, &mut checked)
                .map_err(|e| anyhow::anyhow!("{name}: {e:#}"))?;
            if let Some(i) = read.find(&r) {
                let (owner, input, role) = owners[i];
                let whose = match owner {
                    Some(o) if o != k => format!(" of {}", runs[o].0),
                    _ => String::new(),
                };
                bail!(
                    "{name}: the {} `{}` would overwrite the {role} `{}`{whose}: meshmorph never writes over its inputs; choose another output path",
                    out.role,
                    out.path.display(),
                    input.display()
                );
            }
            let earlier = written
                .get(&r.path)
                .or_else(|| r.id.and_then(|id| written_ids.get(&id)))
                .copied();
            if let Some((o, i)) = earlier {
                let other = &runs[o].1.outputs[i];
                let whose = if o == k {
                    String::new()
                } else {
                    format!(" of {}", runs[o].0)
                };
                bail!(
                    "{name}: the {} `{}` and the {} `{}`{whose} are one file: give each output its own path",
                    out.role,
                    out.path.display(),
                    other.role,
                    other.path.display()
                );
            }
            written.insert(r.path.clone(), (k, j));
            if let Some(id) = r.id {
                written_ids.insert(id, (k, j));
            }
        }
    }
    // A folder one run writes into that is a file another run writes.
    for (k, (name, plan)) in runs.iter().enumerate() {
        if repeats.contains(&k) {
            continue;
        }
        for (out, r) in plan.outputs.iter().zip(&resolved[k].1) {
            let Some((o, i)) = r.path.ancestors().skip(1).find_map(|a| written.get(a)) else {
                continue;
            };
            let other = &runs[*o].1.outputs[*i];
            bail!(
                "{name}: the {} `{}` would be written inside the {} `{}` of {}, a file: give each output its own path",
                out.role,
                out.path.display(),
                other.role,
                other.path.display(),
                runs[*o].0
            );
        }
    }
    Ok(repeats)
}

/// The message refusing an output that is an input.
pub(super) fn overwrite_message(role: &str, path: &Path, input_role: &str, input: &Path) -> String {
    format!(
        "the {role} `{}` would overwrite the {input_role} `{}`: meshmorph never writes over its inputs; choose another output path",
        path.display(),
        input.display()
    )
}

/// Resolved files looked up by path and by device and inode, in constant
/// time: a million frames are checked in time proportional to a million.
#[derive(Debug, Default)]
pub(super) struct Inputs {
    paths: HashMap<PathBuf, usize>,
    ids: HashMap<(u64, u64), usize>,
}

impl Inputs {
    pub fn new(files: &[Resolved]) -> Self {
        let mut found = Self::default();
        for (k, f) in files.iter().enumerate() {
            found.insert(f, k);
        }
        found
    }

    /// Adds `file` as the `k`-th (an earlier one of the same file stays).
    pub fn insert(&mut self, file: &Resolved, k: usize) {
        self.paths.entry(file.path.clone()).or_insert(k);
        if let Some(id) = file.id {
            self.ids.entry(id).or_insert(k);
        }
    }

    /// The index of the file `r` is, if any (see [`Resolved::same_file`]).
    pub fn find(&self, r: &Resolved) -> Option<usize> {
        self.paths
            .get(&r.path)
            .or_else(|| r.id.and_then(|id| self.ids.get(&id)))
            .copied()
    }
}

/// The output's resolved path, after refusing a slot that cannot take a
/// file. The folders above it are looked at once per folder (`checked`):
/// a million frames in one folder cost a million `lstat`s, no more.
fn check_slot(
    out: &Named,
    resolver: &mut Resolver,
    checked: &mut HashSet<PathBuf>,
) -> Result<Resolved> {
    let path = &out.path;
    if path.file_name().is_none() || path.as_os_str().to_string_lossy().ends_with('/') {
        bail!("the {} `{}` is not a file name", out.role, path.display());
    }
    let resolved = resolver.resolve(path);
    // An existing file or link (with an id): is it, or does it lead to, a
    // folder, a device, a FIFO or a socket? A rename would replace it.
    if resolved.id.is_some() {
        if std::fs::metadata(path).is_ok_and(|m| m.is_dir()) {
            bail!(
                "the {} `{}` is a folder: meshmorph writes a file there; move the folder or choose another output",
                out.role,
                path.display()
            );
        }
        if let Err(e) = meshmorph::io::refuse_unless_replaceable(path) {
            bail!("the {} {e}", out.role);
        }
    }
    let parent = path.parent().unwrap_or(Path::new(""));
    if !checked.contains(parent) {
        let mut ancestor = Some(parent);
        while let Some(dir) = ancestor {
            if std::fs::metadata(dir).is_err() {
                if let Ok(target) = std::fs::read_link(dir) {
                    bail!(
                        "cannot write the {} `{}`: `{}` is a link to `{}`, which does not exist; create the folder or choose another output",
                        out.role,
                        path.display(),
                        dir.display(),
                        target.display()
                    );
                }
            }
            if let Ok(m) = std::fs::metadata(dir) {
                if !m.is_dir() {
                    bail!(
                        "cannot write the {} `{}`: `{}` is a file, not a folder",
                        out.role,
                        path.display(),
                        dir.display()
                    );
                }
                break;
            }
            ancestor = dir.parent();
        }
        checked.insert(parent.to_path_buf());
    }
    Ok(resolved)
}

/// Refuses two outputs that are one file.
fn check_distinct(named: &[Named], resolved: &[Resolved]) -> Result<()> {
    let mut order: Vec<usize> = (0..resolved.len()).collect();
    order.sort_by(|&a, &b| resolved[a].path.cmp(&resolved[b].path));
    let same_path = order
        .windows(2)
        .find(|w| resolved[w[0]].path == resolved[w[1]].path)
        .map(|w| (w[0].min(w[1]), w[0].max(w[1])));
    // Existing files reached by two different paths (hard links).
    let mut ids: Vec<(u64, u64, usize)> = resolved
        .iter()
        .enumerate()
        .filter_map(|(k, r)| r.id.map(|(d, i)| (d, i, k)))
        .collect();
    ids.sort_unstable();
    let same_id = ids
        .windows(2)
        .find(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1))
        .map(|w| (w[0].2.min(w[1].2), w[0].2.max(w[1].2)));
    if let Some((a, b)) = same_path.or(same_id) {
        bail!(
            "the {} `{}` and the {} `{}` are the same file: give each output its own path",
            named[a].role,
            named[a].path.display(),
            named[b].role,
            named[b].path.display()
        );
    }
    Ok(())
}

/// The folders to create for `paths` (missing ancestors, outermost first).
pub(super) fn missing_folders(paths: &[Named]) -> Vec<PathBuf> {
    let mut missing: Vec<PathBuf> = Vec::new();
    let mut seen: std::collections::HashSet<&Path> = std::collections::HashSet::new();
    for p in paths {
        // Frames share their folder: each folder is looked at once.
        if !seen.insert(p.path.parent().unwrap_or(Path::new(""))) {
            continue;
        }
        let mut chain = Vec::new();
        let mut dir = p.path.parent();
        while let Some(d) = dir.filter(|d| !d.as_os_str().is_empty()) {
            if d.exists() || missing.iter().any(|m| m == d) {
                break;
            }
            chain.push(d.to_path_buf());
            dir = d.parent();
        }
        missing.extend(chain.into_iter().rev());
    }
    missing
}
