//! Atomic file output: write a temporary file next to the target, then
//! rename it over the target.

use std::io::{BufWriter, Write};
use std::path::Path;

use crate::error::{Error, Result};

/// Writes a file atomically: `f` writes into a buffered temporary file in
/// the same directory as `path` (named `.meshmorph-<process id>-<random>.tmp`),
/// which is flushed and then renamed to `path`.
///
/// Readers of `path` see either the old file or the complete new one, never
/// a partial one. When anything fails (creating the temporary file, `f`
/// returning an error, flushing, renaming) the temporary file is removed and
/// `path` is left as it was: no file appears there. The new file gets the
/// usual permissions for a new file (`0o666` minus the umask on Unix).
///
/// The data is not `fsync`ed: atomicity is guaranteed against other
/// processes and failed writes, durability across a power loss is not.
///
/// The mesh writers and the other modules' outputs (SVG, GIF, JSON) all go
/// through this function.
///
/// # Errors
/// [`Error::Io`] naming `path` with the operating system's (or `f`'s) error.
///
/// # Example
/// ```no_run
/// use std::io::Write;
/// meshmorph::io::write_atomic("out.txt".as_ref(), |w| writeln!(w, "hello"))?;
/// # Ok::<(), meshmorph::Error>(())
/// ```
pub fn write_atomic(
    path: &Path,
    f: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let err = |e| Error::io(path, e);
    // `.meshmorph-<process>-<random>.tmp`: the process id tells a later
    // run whether the file's writer still runs (a writer killed by force
    // cannot remove it).
    let prefix = format!(".meshmorph-{}-", std::process::id());
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        // The default 0o600 of temporary files would stick to the output;
        // the umask still applies to this.
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let temp = builder
        .tempfile_in(dir)
        .map_err(|e| err(without_temporary_path(e)))?;
    // From here on, dropping `temp` (on any early return) removes the file.
    // Written through the plain file: `NamedTempFile`'s own writes add the
    // temporary path to their errors (a full disk), and messages name the
    // file asked for.
    let mut writer = BufWriter::with_capacity(1 << 16, temp.as_file());
    f(&mut writer).map_err(err)?;
    writer.into_inner().map_err(|e| err(e.into_error()))?;
    temp.persist(path).map_err(|e| err(e.error))?;
    Ok(())
}

/// `e`, an error of creating the temporary file, without the temporary
/// file's name that `tempfile` adds to it (` at path "…"`): the message
/// names the file asked for, never a name of ours.
fn without_temporary_path(e: std::io::Error) -> std::io::Error {
    let text = e.to_string();
    match text.find(" at path \"") {
        Some(i) => std::io::Error::new(e.kind(), &text[..i]),
        None => e,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failure_names_the_file_asked_for_not_the_temporary_one() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing/out.obj");
        let e = write_atomic(&path, |w| w.write_all(b"x")).unwrap_err();
        let message = e.to_string();
        assert!(message.contains("out.obj"), "{message}");
        assert!(!message.contains(".meshmorph-"), "{message}");
    }
}
