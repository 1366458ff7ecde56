//! Files that a run stopped by force (SIGKILL, the out-of-memory killer, a
//! CI timeout) could not remove: its staged outputs
//! `.meshmorph-<pid>-<token>-<n>.part`, the temporary files of atomic
//! writes `.meshmorph-<pid>-<random>.tmp`, and the second names
//! `.meshmorph-<pid>-<token>-<n>.old` of files its outputs were replacing.
//! A later run into the same folder removes those whose process no longer
//! runs. A file moved aside where hard links are not available
//! (`….aside`) may be the only copy of a file: it is reported, never
//! removed.

use std::path::{Path, PathBuf};

/// A leftover of an ended run, by the end of its name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Leftover {
    /// `.part`, `.tmp` or `.old`: safe to remove.
    Removable,
    /// `.aside`: perhaps the only copy of a file.
    Kept,
}

/// The process id in `name` when it is exactly the name of a file a run
/// leaves while it works: `.meshmorph-<process>-<letters, digits and
/// dashes>` then `.part`, `.tmp`, `.old`, `.folder` (a staged folder) or
/// `.aside`.
pub fn staged_by(name: &str) -> Option<(u32, Leftover)> {
    let rest = name.strip_prefix(".meshmorph-")?;
    let (stem, kind) = [
        (".part", Leftover::Removable),
        (".tmp", Leftover::Removable),
        (".old", Leftover::Removable),
        (".folder", Leftover::Removable),
        (".aside", Leftover::Kept),
    ]
    .into_iter()
    .find_map(|(end, kind)| rest.strip_suffix(end).map(|s| (s, kind)))?;
    let (pid, own) = stem.split_once('-')?;
    let digits = !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit());
    let own_ok = !own.is_empty()
        && !own.starts_with('-')
        && own.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-');
    (digits && own_ok)
        .then(|| pid.parse().ok())
        .flatten()
        .map(|pid| (pid, kind))
}

/// This run's part of its staged names: no other user can know a staged
/// name before the run makes the file.
pub fn token() -> String {
    meshmorph::io::random_name(16)
}

/// Whether process `pid` surely no longer runs: on Linux, `/proc` is there
/// and has no entry for it. Elsewhere (and without `/proc`) this cannot be
/// told, and the answer is no.
fn surely_ended(pid: u32) -> bool {
    if !cfg!(target_os = "linux") || pid == std::process::id() {
        return false;
    }
    let proc = Path::new("/proc");
    proc.join("self").exists() && !proc.join(pid.to_string()).exists()
}

/// The regular files in `dir` named as leftovers of processes that no
/// longer run, with their sizes in bytes and what to do with them.
fn stale_in(dir: &Path) -> Vec<(PathBuf, u64, Leftover)> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut found: Vec<(PathBuf, u64, Leftover)> = entries
        .filter_map(Result::ok)
        .filter_map(|e| {
            let (pid, kind) = e.file_name().to_str().and_then(staged_by)?;
            surely_ended(pid).then_some((e, kind))
        })
        // Not followed: a symbolic link is not a staged file. A staged
        // folder (`.folder`) is a folder; every other leftover a file.
        .filter_map(|(e, kind)| {
            let m = std::fs::symlink_metadata(e.path()).ok()?;
            let folder = e.file_name().to_string_lossy().ends_with(".folder");
            let size = if folder {
                m.is_dir().then(|| folder_size(&e.path()))?
            } else {
                m.is_file().then_some(m.len())?
            };
            Some((e.path(), size, kind))
        })
        .collect();
    found.sort_by(|a, b| a.0.cmp(&b.0));
    found
}

/// Removes the leftovers of ended processes in each of `dirs`; returns a
/// warning for each folder where it removed some, and one for each file
/// it keeps.
pub fn remove_stale(dirs: &[&Path]) -> Vec<String> {
    let mut warnings = Vec::new();
    for dir in dirs {
        let (mut files, mut bytes) = (0usize, 0u64);
        for (path, size, kind) in stale_in(dir) {
            if kind == Leftover::Kept {
                warnings.push(format!(
                    "`{}` is a file a stopped run moved aside while replacing it (kill -9 or out of memory during its last step): if a file of yours is missing from `{}`, this is it; meshmorph leaves it there",
                    path.display(),
                    dir.display()
                ));
            } else if std::fs::remove_file(&path)
                .or_else(|_| std::fs::remove_dir_all(&path))
                .is_ok()
            {
                files += 1;
                bytes += size;
            }
        }
        if files > 0 {
            warnings.push(format!(
                "removed {} ({}) from `{}`: hidden `.meshmorph-<process>-…` files of runs that were stopped by force (kill -9, out of memory) and can no longer remove them",
                crate::output::count(files, "unfinished output"),
                human_bytes(bytes),
                dir.display()
            ));
        }
    }
    warnings
}

/// The bytes of the files in `dir` and below (links not followed).
fn folder_size(dir: &Path) -> u64 {
    let mut bytes = 0;
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            match e.file_type() {
                Ok(t) if t.is_dir() => stack.push(e.path()),
                Ok(t) if t.is_file() => bytes += e.metadata().map_or(0, |m| m.len()),
                _ => {}
            }
        }
    }
    bytes
}

/// Bytes as a short human string (powers of 1000, as `du --si`).
fn human_bytes(bytes: u64) -> String {
    match bytes {
        b if b >= 1_000_000_000 => format!("{:.1} GB", b as f64 / 1e9),
        b if b >= 1_000_000 => format!("{:.1} MB", b as f64 / 1e6),
        b if b >= 1_000 => format!("{:.1} kB", b as f64 / 1e3),
        b => format!("{b} bytes"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_exact_staged_names() {
        use Leftover::{Kept, Removable};
        assert_eq!(staged_by(".meshmorph-1234-0.part"), Some((1234, Removable)));
        assert_eq!(staged_by(".meshmorph-7-41.part"), Some((7, Removable)));
        assert_eq!(staged_by(".meshmorph-7-aZ09xY.tmp"), Some((7, Removable)));
        assert_eq!(
            staged_by(".meshmorph-7-aZ09xY-12.part"),
            Some((7, Removable))
        );
        assert_eq!(
            staged_by(".meshmorph-7-aZ09xY-12.old"),
            Some((7, Removable))
        );
        assert_eq!(staged_by(".meshmorph-7-aZ09xY-12.aside"), Some((7, Kept)));
        assert_eq!(
            staged_by(".meshmorph-7-aZ09xY-0.folder"),
            Some((7, Removable))
        );
        for other in [
            ".meshmorph-7kUIk1.tmp",
            ".meshmorph-1234.part",
            ".meshmorph--0.part",
            ".meshmorph-12a-0.part",
            ".meshmorph-1234-0.part.bak",
            ".meshmorph-1234-a.b.tmp",
            ".meshmorph-1234-.tmp",
            ".meshmorph-1234--x.tmp",
            "meshmorph-1234-0.part",
            ".meshmorph-99999999999-0.part",
        ] {
            assert_eq!(staged_by(other), None, "{other}");
        }
    }

    #[test]
    fn tokens_differ_and_fit_the_names() {
        let (a, b) = (token(), token());
        assert_ne!(a, b);
        assert_eq!(a.len(), 16);
        assert!(staged_by(&format!(".meshmorph-5-{a}-3.part")).is_some());
    }
}
