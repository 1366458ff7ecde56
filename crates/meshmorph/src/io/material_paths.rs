//! The material libraries of an OBJ file (`mtllib` paths) as seen from
//! another folder: an OBJ written with new positions in another folder than
//! the file it comes from keeps its materials by pointing at the same `.mtl`
//! files, which are never copied nor changed.

use std::path::{Component, Path, PathBuf};

/// Where relative `mtllib` paths were read from and where they are written.
#[derive(Debug)]
pub(super) struct MaterialPaths {
    /// The source file's folder, resolved (absolute, without links).
    from: PathBuf,
    /// The output file's folder, resolved.
    to: PathBuf,
}

impl MaterialPaths {
    /// The folders of `source` (the file read) and `output` (the file
    /// written); `None` when they are the same folder, when either cannot
    /// be resolved, or when no file is at `source` (a file parsed from
    /// bytes, its path only a name for messages): then `mtllib` paths are
    /// written as they are.
    pub(super) fn new(source: &Path, output: &Path) -> Option<Self> {
        if !source.is_file() {
            return None;
        }
        let from = folder_of(source).canonicalize().ok()?;
        let to = folder_of(output).canonicalize().ok()?;
        (from != to).then_some(MaterialPaths { from, to })
    }

    /// The argument of a `mtllib` statement (the text after the keyword,
    /// without surrounding spaces) with each relative path made to resolve
    /// from the output's folder to the file it named from the source's:
    /// relative when the two folders share a root, else absolute. `None`
    /// when nothing changes (only absolute paths, or text that is not
    /// UTF-8).
    ///
    /// Several libraries may be named, separated by spaces; a name with
    /// spaces is read as one when a file of that name is beside the source.
    pub(super) fn rewrite(&self, argument: &[u8]) -> Option<Vec<u8>> {
        let text = std::str::from_utf8(argument).ok()?;
        let names = library_names(&self.from, text);
        let mut changed = false;
        let rewritten: Vec<String> = names
            .iter()
            .map(|&name| match self.seen_from_output(Path::new(name)) {
                Some(path) => {
                    changed = true;
                    path
                }
                None => name.to_string(),
            })
            .collect();
        changed.then(|| rewritten.join(" ").into_bytes())
    }

    /// A relative `name` (read from the source's folder) as a path from the
    /// output's folder; `None` for an absolute name, or a path that is not
    /// UTF-8.
    fn seen_from_output(&self, name: &Path) -> Option<String> {
        if name.is_absolute() || name.has_root() {
            return None;
        }
        let joined = self.from.join(name);
        let target = joined
            .canonicalize()
            .unwrap_or_else(|_| without_dots(&joined));
        let path = relative_path(&self.to, &target).unwrap_or(target);
        path.to_str().map(str::to_string)
    }
}

/// The library names of a `mtllib` statement's argument `text`, read from
/// the folder `from`: several, separated by spaces, or one name with spaces
/// when a file of that name is there.
pub(super) fn library_names<'t>(from: &Path, text: &'t str) -> Vec<&'t str> {
    if !text.contains(char::is_whitespace) || from.join(text).is_file() {
        vec![text]
    } else {
        text.split_whitespace().collect()
    }
}

/// The folder holding `file` (`.` for a bare file name).
pub(super) fn folder_of(file: &Path) -> &Path {
    match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// An absolute `path` with its `.` and `..` components resolved by name.
pub fn without_dots(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The path from the folder `dir` to `target` (both absolute, without `.`
/// or `..`); `None` when they do not share a root (another drive).
pub fn relative_path(dir: &Path, target: &Path) -> Option<PathBuf> {
    let mut d = dir.components().peekable();
    let mut t = target.components().peekable();
    let mut common = 0;
    while let (Some(a), Some(b)) = (d.peek(), t.peek()) {
        if a != b {
            break;
        }
        d.next();
        t.next();
        common += 1;
    }
    if common == 0 {
        return None;
    }
    let mut path: PathBuf = d.map(|_| Component::ParentDir).collect();
    path.extend(t);
    Some(path)
}
