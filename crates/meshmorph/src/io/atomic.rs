//! Atomic file output: write a temporary file next to the target, then
//! rename it over the target.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

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
/// An existing `path` that is not a regular file (a device, a FIFO, a
/// socket, a folder, or a link to one) is refused before anything is
/// written ([`refuse_unless_replaceable`]).
///
/// # Errors
/// [`Error::Io`] naming `path` with the operating system's (or `f`'s)
/// error; [`Error::FileRefused`] for a path that is not a regular file.
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
    write_atomic_with(path, |w| f(w).map_err(|e| Error::io(path, e)))
}

/// [`write_atomic`] for a writer `f` that may fail otherwise than the
/// system (a check of what it writes) and returns a value: `f`'s error
/// (any that the crate's errors convert to) as it is.
pub(crate) fn write_atomic_with<T, E: From<Error>>(
    path: &Path,
    f: impl FnOnce(&mut dyn Write) -> std::result::Result<T, E>,
) -> std::result::Result<T, E> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    refuse_unless_replaceable(path)?;
    let temp = Temporary::create(dir).map_err(|e| Error::io(path, e))?;
    // From here on, dropping `temp` (on any early return) removes the file.
    let value = temp.fill(path, f)?;
    std::fs::rename(&temp.path, path).map_err(|e| Error::io(path, e))?;
    temp.kept();
    Ok(value)
}

/// Refuses an output path that exists and is not a regular file (links
/// followed): a rename would replace a device such as `/dev/null`, a FIFO
/// or a socket with a regular file, and a folder cannot be replaced.
///
/// # Errors
/// [`Error::FileRefused`] naming the path and what it is.
pub fn refuse_unless_replaceable(path: &Path) -> Result<()> {
    match std::fs::metadata(path) {
        Ok(meta) => match super::read::not_a_file(&meta) {
            None => Ok(()),
            Some(what) => Err(Error::FileRefused {
                path: path.to_path_buf(),
                message: format!(
                    "{what}, not a regular file: meshmorph writes only to a new path or over a regular file; choose another output"
                ),
            }),
        },
        Err(_) => Ok(()),
    }
}

/// Writes a new file at `path` itself, without a temporary name: `path`
/// is created new (`O_CREAT|O_EXCL`: a file or link already there is an
/// error, never written through nor replaced), `f` writes into it through
/// a buffer, and it is flushed. When anything fails the file is removed:
/// nothing is left at `path`.
///
/// For files that no one reads before they are complete: those made in a
/// folder that is itself not yet in place (a hidden folder moved to its
/// name once everything in it is written). Elsewhere use
/// [`write_atomic`], whose readers never see a partial file. A file made
/// here costs one system call fewer than through [`write_atomic`] (no
/// rename), and the folder no second name: on a disk, creating a million
/// small files takes most of the time of writing them.
///
/// # Errors
/// [`Error::Io`] naming `path` when it cannot be created (`AlreadyExists`
/// when something is there), written or flushed; `f`'s own error as it is.
pub fn write_new<T, E: From<Error>>(
    path: &Path,
    f: impl FnOnce(&mut dyn Write) -> std::result::Result<T, E>,
) -> std::result::Result<T, E> {
    let file = Temporary::new_at(path.to_path_buf()).map_err(|e| Error::io(path, e))?;
    let value = file.fill(path, f)?;
    file.kept();
    Ok(value)
}

/// A temporary file made afresh (never through a file or link already at
/// its name), removed when dropped unless [`Temporary::kept`].
pub struct Temporary {
    pub path: PathBuf,
    file: std::fs::File,
    keep: bool,
}

impl Temporary {
    /// `.meshmorph-<process id>-<random letters><count>.tmp` in `dir`: the
    /// process id tells a later run whether the file's writer still runs (a
    /// writer killed by force cannot remove it); the letters, random for
    /// each process, keep anyone from knowing the names before it starts.
    /// (A count after them rather than new random letters each time: an
    /// ext4 folder takes names that share their beginning about three
    /// times faster, measured over 50,000 files.) The file is created new
    /// whatever its name, so a name guessed and planted is only skipped.
    pub fn create(dir: &Path) -> std::io::Result<Self> {
        let mut last = None;
        for _ in 0..16 {
            let path = dir.join(format!(".meshmorph-{}-{}.tmp", process_id(), next_name()));
            match Self::new_at(path) {
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
                made => return made,
            }
        }
        Err(last.expect("sixteen tries"))
    }

    /// The file at `path`, created new (`O_CREAT|O_EXCL`, which never
    /// follows a link) with the usual permissions of a new file (`0o666`
    /// minus the umask on Unix).
    fn new_at(path: PathBuf) -> std::io::Result<Self> {
        let mut options = std::fs::OpenOptions::new();
        options.write(true).create_new(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt as _;
            options.mode(0o666);
        }
        let file = options.open(&path)?;
        Ok(Temporary {
            path,
            file,
            keep: false,
        })
    }

    /// `f` writes into the file through a buffer, which is then flushed;
    /// the system's errors name `path` (the file asked for).
    fn fill<T, E: From<Error>>(
        &self,
        path: &Path,
        f: impl FnOnce(&mut dyn Write) -> std::result::Result<T, E>,
    ) -> std::result::Result<T, E> {
        let mut writer = BufWriter::with_capacity(1 << 16, &self.file);
        let value = f(&mut writer)?;
        writer
            .into_inner()
            .map_err(|e| Error::io(path, e.into_error()))?;
        Ok(value)
    }

    /// The file was moved into place: nothing to remove.
    fn kept(mut self) {
        self.keep = true;
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if !self.keep {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// This process's random letters, then the next count.
fn next_name() -> String {
    static COUNT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let count = COUNT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    format!("{}{count}", own_letters())
}

/// The random letters of this process's temporary files.
fn own_letters() -> &'static str {
    static LETTERS: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    LETTERS.get_or_init(|| random_name(10))
}

/// Removes this process's temporary files in `dir` (those [`write_atomic`]
/// was writing there): for a process that abandons its run without
/// unwinding (out of memory, a signal), whose writers cannot remove their
/// own. Files of other processes and of other runs are left alone: their
/// names carry another process id or other random letters. Returns how
/// many were removed.
pub fn remove_own_temporaries(dir: &Path) -> usize {
    let prefix = format!(".meshmorph-{}-{}", process_id(), own_letters());
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    entries
        .filter_map(|e| e.ok())
        .filter(|e| {
            let name = e.file_name();
            let name = name.to_string_lossy();
            name.starts_with(&prefix) && name.ends_with(".tmp")
        })
        .filter(|e| std::fs::remove_file(e.path()).is_ok())
        .count()
}

/// This process's id, asked once (a system call each time otherwise).
pub fn process_id() -> u32 {
    static ID: std::sync::OnceLock<u32> = std::sync::OnceLock::new();
    *ID.get_or_init(std::process::id)
}

/// `len` letters and digits that no one can know in advance: for the
/// names of files made beside a user's (temporary and staged files), so
/// that nothing can be planted at a name before it is made. From a
/// generator per thread (xorshift64*) seeded by the system's randomness
/// (the keys of std's `RandomState`).
pub fn random_name(len: usize) -> String {
    use std::cell::Cell;
    use std::hash::{BuildHasher as _, Hasher as _};
    thread_local! {
        static STATE: Cell<u64> = Cell::new({
            let mut h = std::collections::hash_map::RandomState::new().build_hasher();
            h.write_u32(process_id());
            h.finish() | 1
        });
    }
    const LETTERS: &[u8] = b"abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    // Ten letters from each 64 random bits (62^10 < 2^64).
    let mut name = String::with_capacity(len);
    while name.len() < len {
        let mut bits = STATE.with(|state| {
            let mut x = state.get();
            x ^= x >> 12;
            x ^= x << 25;
            x ^= x >> 27;
            state.set(x);
            x.wrapping_mul(0x2545_F491_4F6C_DD1D)
        });
        for _ in 0..10.min(len - name.len()) {
            name.push(LETTERS[(bits % LETTERS.len() as u64) as usize] as char);
            bits /= LETTERS.len() as u64;
        }
    }
    name
}
