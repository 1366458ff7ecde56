//! Reading input files: regular files only, each read whole up to a limit.
//!
//! Every file the library reads (meshes, poses, markers, correspondences,
//! material libraries, textures) goes through [`open`] then
//! [`Input::read_to_end`]:
//!
//! - Only regular files are read, links followed: a folder, a FIFO, a
//!   socket or a device (`/dev/zero`, `/dev/urandom`, a terminal) is
//!   refused naming the path and what it is, before anything is read from
//!   it. A FIFO is never waited on: the type is checked before opening, the
//!   file is opened without blocking (`O_NONBLOCK` on Unix) and checked
//!   again once open, so a file swapped for another between the two checks
//!   is caught too.
//! - The size is checked against a limit before reading, and the read
//!   itself stops one byte past the limit, so a file that grows while it
//!   is read (or whose size lies) is refused as well.
//!
//! The limits, each chosen for what the file holds:
//!
//! - **Meshes, markers and correspondences**: what the memory available
//!   allows ([`available_memory`]): a file is read whole and then parsed,
//!   and parsing takes about twice its size again, so a file may take a
//!   third of the memory available ([`MEMORY_PER_FILE_BYTE`], the
//!   estimate the command line makes before reading). Without a figure
//!   (systems other than Linux) there is no limit but the file's size.
//! - **Material libraries**: [`MAX_MATERIAL_LIBRARY_BYTES`], far above any
//!   real one: a library describes looks, a few lines per material.
//! - **Textures**: what the GLB they go into may still take
//!   ([`Appearance::of_file`](super::Appearance::of_file)), as the command
//!   line's `--max-gltf-mb` counts every byte of the file.

use std::fs::{File, Metadata};
use std::io::Read;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Bytes of memory that reading a mesh (or marker, or correspondence) file
/// takes per byte of the file: the bytes, then what is parsed from them
/// (positions, faces and, for a file kept whole, where each number is).
pub const MEMORY_PER_FILE_BYTE: u64 = 3;

/// The most bytes a material library (`.mtl`) may hold: 64 MiB. A library
/// of 100,000 materials of ten statements each is about 50 MB; a larger
/// file is not a material library.
pub const MAX_MATERIAL_LIBRARY_BYTES: u64 = 64 << 20;

/// How many bytes a read may take, and why (for the message refusing a
/// larger file: "more than {why}").
#[derive(Clone, Debug)]
pub struct Limit {
    pub bytes: u64,
    pub why: String,
}

impl Limit {
    /// The limit of a file read whole and parsed in memory: a third of the
    /// memory available ([`MEMORY_PER_FILE_BYTE`]); none when that is not
    /// known.
    pub(crate) fn memory() -> Self {
        match available_memory() {
            Some(free) => Limit {
                bytes: free / MEMORY_PER_FILE_BYTE,
                why: format!(
                    "the {} that reading can take here (reading a file takes about {MEMORY_PER_FILE_BYTE} times its size in memory, and {} is available): free memory or use a smaller file",
                    human_bytes(free / MEMORY_PER_FILE_BYTE),
                    human_bytes(free)
                ),
            },
            None => Limit::none(),
        }
    }

    /// No limit but the file's own size.
    pub fn none() -> Self {
        Limit {
            bytes: u64::MAX,
            why: String::new(),
        }
    }
}

/// A regular file opened for reading, and its size when opened.
pub struct Input {
    path: PathBuf,
    file: File,
    len: u64,
    /// The bytes read so far (by [`Input::head`]).
    read: Vec<u8>,
}

/// Opens `path` for reading when it is a regular file (links followed).
///
/// # Errors
/// [`Error::Io`] when it cannot be opened; [`Error::FileRefused`] naming
/// the path and what it is when it is not a regular file.
pub fn open(path: &Path) -> Result<Input> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    refuse_unless_regular(path, &meta)?;
    let file = open_without_waiting(path).map_err(|e| Error::io(path, e))?;
    // What was opened may not be what was looked at (a swap in between).
    let meta = file.metadata().map_err(|e| Error::io(path, e))?;
    refuse_unless_regular(path, &meta)?;
    Ok(Input {
        path: path.to_path_buf(),
        file,
        len: meta.len(),
        read: Vec::new(),
    })
}

/// Reads the regular file `path` whole, refusing it past `limit` (see the
/// [module documentation](self)).
pub fn read_file(path: &Path, limit: &Limit) -> Result<Vec<u8>> {
    open(path)?.read_to_end(limit)
}

/// `bytes` of the file `path` as text.
///
/// # Errors
/// [`Error::Parse`] naming the line of the first byte that is not UTF-8.
pub(crate) fn utf8(bytes: Vec<u8>, path: &Path) -> Result<String> {
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = 1 + memchr::memchr_iter(b'\n', &e.as_bytes()[..at]).count();
        Error::parse(path, Some(line), "not UTF-8 text (a binary file?)")
    })
}

/// Reads a small text file whole: a regular file only (links followed),
/// refused past `max_bytes` (`what` says what it is: "a batch file"),
/// UTF-8, a leading byte-order mark dropped. For front ends' own files
/// (batch files, settings): bounded as every read of the library is.
///
/// # Errors
/// [`Error::Io`] when it cannot be read; [`Error::FileRefused`] when it is
/// not a regular file or is too large; [`Error::Parse`] naming the line of
/// a byte that is not UTF-8.
pub fn read_text(path: &Path, max_bytes: u64, what: &str) -> Result<String> {
    let limit = Limit {
        bytes: max_bytes,
        why: format!("the {} that {what} may hold", human_bytes(max_bytes)),
    };
    let text = utf8(read_file(path, &limit)?, path)?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    })
}

/// Opens for reading without waiting for a writer, should `path` have
/// become a FIFO since it was looked at.
#[cfg(unix)]
pub fn open_without_waiting(path: &Path) -> std::io::Result<File> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
}

#[cfg(not(unix))]
fn open_without_waiting(path: &Path) -> std::io::Result<File> {
    File::open(path)
}

impl Input {
    /// The file's size when it was opened, in bytes.
    pub fn len(&self) -> u64 {
        self.len
    }

    /// Whether the file was empty when it was opened.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The first `n` bytes of the file (fewer when it is shorter), read
    /// once: [`Input::read_to_end`] goes on from there.
    pub fn head(&mut self, n: usize) -> Result<&[u8]> {
        if self.read.len() < n {
            let wanted = (n - self.read.len()) as u64;
            (&self.file)
                .take(wanted)
                .read_to_end(&mut self.read)
                .map_err(|e| Error::io(&self.path, e))?;
        }
        Ok(&self.read[..n.min(self.read.len())])
    }

    /// The whole file, refused when it holds more than `limit` bytes:
    /// before reading when its size says so, else as soon as it is read
    /// past the limit (a file that grows).
    pub fn read_to_end(mut self, limit: &Limit) -> Result<Vec<u8>> {
        if self.len > limit.bytes {
            return Err(self.too_large(self.len, limit));
        }
        let mut bytes = std::mem::take(&mut self.read);
        bytes.reserve((self.len as usize).saturating_sub(bytes.len()));
        let left = limit.bytes.saturating_sub(bytes.len() as u64);
        (&self.file)
            .take(left.saturating_add(1))
            .read_to_end(&mut bytes)
            .map_err(|e| Error::io(&self.path, e))?;
        if bytes.len() as u64 > limit.bytes {
            return Err(self.too_large(bytes.len() as u64, limit));
        }
        Ok(bytes)
    }

    fn too_large(&self, size: u64, limit: &Limit) -> Error {
        let grew = if size > self.len {
            format!(
                " (it held {} when opened and grew while it was read)",
                human_bytes(self.len)
            )
        } else {
            String::new()
        };
        Error::FileRefused {
            path: self.path.clone(),
            message: format!(
                "{}{grew}, more than {}",
                if size > self.len {
                    format!("over {}", human_bytes(size - 1))
                } else {
                    human_bytes(size)
                },
                limit.why
            ),
        }
    }
}

/// Refuses what is not a regular file, saying what it is.
fn refuse_unless_regular(path: &Path, meta: &Metadata) -> Result<()> {
    match not_a_file(meta) {
        None => Ok(()),
        Some(what) => Err(Error::FileRefused {
            path: path.to_path_buf(),
            message: format!(
                "{what}, not a regular file: only regular files are read (a device or a FIFO may never end, or wait for a writer)"
            ),
        }),
    }
}

/// What `meta` describes when it is not a regular file ("a folder", "a
/// FIFO (named pipe)", "a character device", ...); `None` for a regular
/// file.
pub(crate) fn not_a_file(meta: &Metadata) -> Option<&'static str> {
    let kind = meta.file_type();
    if kind.is_file() {
        return None;
    }
    if kind.is_dir() {
        return Some("a folder");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return Some("a FIFO (named pipe)");
        }
        if kind.is_char_device() {
            return Some("a character device");
        }
        if kind.is_block_device() {
            return Some("a block device (a disk)");
        }
        if kind.is_socket() {
            return Some("a socket");
        }
    }
    Some("not a regular file")
}

/// The memory this process may still allocate: the smaller of what the
/// system reports available (`MemAvailable` on Linux) and what the
/// address-space limit (`ulimit -v`) leaves; `None` where neither is
/// known.
pub fn available_memory() -> Option<u64> {
    let system = read_kib("/proc/meminfo", "MemAvailable:");
    let limit = address_space_limit().map(|limit| {
        let used = read_kib("/proc/self/status", "VmSize:").unwrap_or(0);
        limit.saturating_sub(used)
    });
    match (system, limit) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// A `Key: N kB` line of a /proc file, in bytes.
fn read_kib(file: &str, key: &str) -> Option<u64> {
    let text = std::fs::read_to_string(file).ok()?;
    let line = text.lines().find(|l| l.starts_with(key))?;
    let kib: u64 = line[key.len()..].split_whitespace().next()?.parse().ok()?;
    Some(kib * 1024)
}

/// The soft `Max address space` of /proc/self/limits, when not unlimited.
fn address_space_limit() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = text.lines().find(|l| l.starts_with("Max address space"))?;
    line["Max address space".len()..]
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// "2.1 GB", "256 MB", "12 kB" or "80 bytes" (powers of 10, as
/// `--max-gltf-mb` counts).
pub fn human_bytes(b: u64) -> String {
    let x = b as f64;
    if x >= 1e9 {
        format!("{:.1} GB", x / 1e9)
    } else if x >= 1e6 {
        format!("{:.0} MB", x / 1e6)
    } else if x >= 1e3 {
        format!("{:.0} kB", x / 1e3)
    } else {
        format!("{b} bytes")
    }
}
