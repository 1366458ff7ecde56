//! Staged files that a run stopped by force (SIGKILL, the out-of-memory
//! killer, a CI timeout) could not remove: `.meshmorph-<pid>-<n>.part`, and
//! the temporary files of atomic writes, `.meshmorph-<pid>-<random>.tmp`,
//! whose process no longer runs. A later run into the same folder removes
//! them.

use std::path::{Path, PathBuf};

/// The process id in `name` when it is exactly a staged file's name,
/// `.meshmorph-<process>-<output>.part` (decimal digits each), or the name
/// of the library's temporary file of an atomic write,
/// `.meshmorph-<process>-<letters and digits>.tmp`.
pub fn staged_by(name: &str) -> Option<u32> {
    let rest = name.strip_prefix(".meshmorph-")?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let alphanumeric = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_alphanumeric());
    let (pid, ok) = if let Some(part) = rest.strip_suffix(".part") {
        let (pid, n) = part.split_once('-')?;
        (pid, digits(n))
    } else {
        let (pid, random) = rest.strip_suffix(".tmp")?.split_once('-')?;
        (pid, alphanumeric(random))
    };
    (ok && digits(pid)).then(|| pid.parse().ok()).flatten()
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

/// The regular files in `dir` named as staged files of processes that no
/// longer run, with their sizes in bytes.
fn stale_in(dir: &Path) -> Vec<(PathBuf, u64)> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut found: Vec<(PathBuf, u64)> = entries
        .filter_map(Result::ok)
        .filter(|e| {
            e.file_name()
                .to_str()
                .and_then(staged_by)
                .is_some_and(surely_ended)
        })
        // Not followed: a symbolic link is not a staged file.
        .filter_map(|e| {
            let m = std::fs::symlink_metadata(e.path()).ok()?;
            m.is_file().then(|| (e.path(), m.len()))
        })
        .collect();
    found.sort();
    found
}

/// Removes the staged files of ended processes in each of `dirs`; returns
/// a warning for each folder where it removed some.
pub fn remove_stale(dirs: &[&Path]) -> Vec<String> {
    let mut warnings = Vec::new();
    for dir in dirs {
        let (mut files, mut bytes) = (0usize, 0u64);
        for (path, size) in stale_in(dir) {
            if std::fs::remove_file(&path).is_ok() {
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
        assert_eq!(staged_by(".meshmorph-1234-0.part"), Some(1234));
        assert_eq!(staged_by(".meshmorph-7-41.part"), Some(7));
        assert_eq!(staged_by(".meshmorph-7-aZ09xY.tmp"), Some(7));
        for other in [
            ".meshmorph-1234-0.old",
            ".meshmorph-7kUIk1.tmp",
            ".meshmorph-1234.part",
            ".meshmorph--0.part",
            ".meshmorph-12a-0.part",
            ".meshmorph-1234-0.part.bak",
            ".meshmorph-1234-a.b.tmp",
            ".meshmorph-1234-.tmp",
            "meshmorph-1234-0.part",
            ".meshmorph-99999999999-0.part",
        ] {
            assert_eq!(staged_by(other), None, "{other}");
        }
    }
}
