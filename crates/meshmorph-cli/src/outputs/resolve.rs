//! What a path names on disk, so that two spellings of one file compare
//! equal: the canonical path (symbolic links and `..` resolved; for a file
//! that does not exist yet, its nearest existing folder made canonical and
//! the rest appended) and, for an existing file, its device and inode.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};

/// A path as the file system sees it.
#[derive(Clone, Debug)]
pub struct Resolved {
    /// Canonical where it exists, else canonical parent plus the rest.
    pub path: PathBuf,
    /// Device and inode of the existing file (following symbolic links).
    pub id: Option<(u64, u64)>,
}

impl Resolved {
    pub fn new(path: &Path) -> Self {
        Self {
            path: canonical(path),
            id: file_id(path),
        }
    }

    /// The same file: same canonical path, or same device and inode.
    pub fn same_file(&self, other: &Resolved) -> bool {
        self.path == other.path || (self.id.is_some() && self.id == other.id)
    }
}

/// `path` made absolute with every existing part canonical: symbolic
/// links and `..` resolved as the system would, links that lead nowhere
/// yet (to a folder a run will create) followed too, the missing rest
/// appended.
pub fn canonical(path: &Path) -> PathBuf {
    if let Ok(p) = path.canonicalize() {
        return p;
    }
    let mut out = if path.is_absolute() {
        PathBuf::new()
    } else {
        let cwd = std::env::current_dir().unwrap_or_else(|_| PathBuf::from("."));
        cwd.canonicalize().unwrap_or(cwd)
    };
    // The parts still to walk, the next last; a link's target is pushed in
    // its place. `out` stays canonical while it exists, so `..` may drop
    // its last part.
    let mut parts: Vec<std::ffi::OsString> = Vec::new();
    let push = |parts: &mut Vec<std::ffi::OsString>, p: &Path| {
        let before = parts.len();
        for part in p.components() {
            parts.insert(before, part.as_os_str().to_os_string());
        }
    };
    push(&mut parts, path);
    // As the system does, give up following links after 40.
    let mut links = 0;
    while let Some(part) = parts.pop() {
        match Path::new(&part).components().next() {
            Some(Component::CurDir) | None => {}
            Some(Component::ParentDir) => {
                out.pop();
            }
            Some(Component::Normal(name)) => {
                out.push(name);
                if let Ok(c) = out.canonicalize() {
                    out = c;
                } else if let Ok(target) = std::fs::read_link(&out) {
                    links += 1;
                    if links <= 40 {
                        out.pop();
                        push(&mut parts, &target);
                    }
                }
            }
            Some(other) => out.push(other),
        }
    }
    out
}

/// Resolves many paths, most of them in a few folders (a run's frames):
/// each folder is made canonical once, and a path that is not a symbolic
/// link costs one `lstat`, none in a folder that does not exist.
#[derive(Debug, Default)]
pub struct Resolver {
    /// Each folder's canonical path, and whether it exists.
    folders: HashMap<PathBuf, (PathBuf, bool)>,
}

impl Resolver {
    /// As [`Resolved::new`].
    pub fn resolve(&mut self, path: &Path) -> Resolved {
        let (Some(name), Some(parent)) = (path.file_name(), path.parent()) else {
            return Resolved::new(path);
        };
        if name == ".." {
            return Resolved::new(path);
        }
        let (folder, exists) = self.folders.entry(parent.to_path_buf()).or_insert_with(|| {
            let parent = if parent.as_os_str().is_empty() {
                Path::new(".")
            } else {
                parent
            };
            (canonical(parent), parent.is_dir())
        });
        // Nothing is in a folder that does not exist (until the run makes it).
        let meta = match exists.then(|| std::fs::symlink_metadata(path)) {
            Some(Ok(m)) if m.file_type().is_symlink() => return Resolved::new(path),
            Some(Ok(m)) => Some(m),
            _ => None,
        };
        Resolved {
            path: folder.join(name),
            id: meta.as_ref().and_then(metadata_id),
        }
    }
}

#[cfg(unix)]
fn metadata_id(m: &std::fs::Metadata) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt as _;
    Some((m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn metadata_id(_m: &std::fs::Metadata) -> Option<(u64, u64)> {
    None
}

/// Device and inode of the file at `path`, links followed.
fn file_id(path: &Path) -> Option<(u64, u64)> {
    std::fs::metadata(path).ok().as_ref().and_then(metadata_id)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spellings_of_one_file_resolve_alike() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.obj");
        std::fs::write(&a, "x").unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let dotted = dir.path().join("sub/../a.obj");
        assert!(Resolved::new(&a).same_file(&Resolved::new(&dotted)));
        let missing = dir.path().join("new/../b.obj");
        assert_eq!(
            canonical(&dir.path().join("new/../sub/../a.obj")),
            a.canonicalize().unwrap()
        );
        assert_eq!(canonical(&missing), canonical(&dir.path().join("b.obj")));
        #[cfg(unix)]
        {
            let link = dir.path().join("link.obj");
            std::os::unix::fs::symlink(&a, &link).unwrap();
            assert!(Resolved::new(&a).same_file(&Resolved::new(&link)));
            let hard = dir.path().join("hard.obj");
            std::fs::hard_link(&a, &hard).unwrap();
            assert!(Resolved::new(&a).same_file(&Resolved::new(&hard)));
            assert!(!Resolved::new(&a).same_file(&Resolved::new(&missing)));
        }
        // The resolver that caches folders agrees with the one-off form.
        let mut resolver = Resolver::default();
        for p in [
            &a,
            &dotted,
            &missing,
            &dir.path().join("sub"),
            &dir.path().join("sub/x"),
        ] {
            let (one, many) = (Resolved::new(p), resolver.resolve(p));
            assert_eq!((one.path, one.id), (many.path, many.id), "{}", p.display());
        }
        #[cfg(unix)]
        for p in [dir.path().join("link.obj"), dir.path().join("hard.obj")] {
            let (one, many) = (Resolved::new(&p), resolver.resolve(&p));
            assert_eq!((one.path, one.id), (many.path, many.id), "{}", p.display());
        }
    }
}
