//! Reading and writing meshes: OBJ, OFF, PLY and STL; animations as binary glTF
//! ([`gltf`]).
//!
//! - [`read_mesh`] / [`read_mesh_as`] / [`parse_mesh`] read a triangle mesh
//!   ([`read_planar_mesh`] a planar one)
//!   (polygons are triangulated, see below); every error names the file and,
//!   for text formats, the 1-based line.
//! - [`write_mesh`] / [`write_positions`] write a mesh in any of the four
//!   formats (planar meshes get z = 0), atomically through [`write_atomic`],
//!   which other modules also use for their own outputs;
//!   [`write_positions_to`] and [`MeshFile::write_to`] write into any
//!   writer, such as that of [`write_new`] (a new file made at its own name,
//!   for a folder no one reads before it is complete).
//! - [`MeshFile`] keeps a file whole (polygons, texture coordinates, normals,
//!   groups, materials, other PLY properties and elements, colours) beside
//!   the triangle mesh derived from it, and writes it back with new
//!   positions: what deformation transfer writes for the target.
//! - Drawings ([`read_drawing`]: SVG and polygons as text, a planar mesh's
//!   boundary by [`drawing_of_mesh`]) and the frames of their morphs
//!   ([`write_svg_frame`], [`write_animated_svg`], [`write_lottie`],
//!   [`write_text_frame`]), in `drawing/`.
//! - The files of deformation transfer (`marker_file.rs`, `marker_points.rs`,
//!   `picked_points.rs`, `wrap_points.rs`, `correspondence_file.rs`):
//!   marker pairs ([`Markers::read`](crate::Markers::read),
//!   [`Markers::parse`](crate::Markers::parse), [`Markers::save`](crate::Markers::save)),
//!   one mesh's marker points in twos, as MeshLab's `.pp` and Wrap's `.json`
//!   ([`Markers::read_pair`](crate::Markers::read_pair)), and triangle correspondences
//!   ([`Correspondence::save`](crate::Correspondence::save) and
//!   [`Correspondence::load`](crate::Correspondence::load)).
//!
//! Every file is read whole, from regular files only (links followed): a
//! folder, a FIFO or a device (`/dev/zero`) is refused naming it and what
//! it is, without waiting on it ([`Error::FileRefused`]). Sizes are checked
//! before and while reading: a mesh, marker or correspondence file may take
//! a third of the memory available ([`crate::limits::available_memory`],
//! [`crate::limits::MEMORY_PER_FILE_BYTE`]), a material library
//! [`crate::limits::MAX_MATERIAL_LIBRARY_BYTES`], textures what the GLB may still take
//! ([`Appearance::of_file`]); a mesh file larger than 64 KiB that its first
//! 64 KiB show is not of its format (an STL of neither the binary size nor
//! ASCII text, say) is refused before the rest is read.
//!
//! Reading accepts:
//!
//! - **OBJ**: `v x y [z] [w]` (z is 0 in a planar file, whose vertices all
//!   have 2 coordinates; a file mixing vertices of 2 and of 3 coordinates
//!   is refused, naming the line of the first that differs from those
//!   before it), faces `f a`, `f a/b`,
//!   `f a/b/c`, `f a//c` with absolute (1-based) or relative (negative)
//!   indices, `#` comments, CRLF line ends; `vt` and `vn` (through `f a/b/c`)
//!   are read for [`MeshFile`]; every other statement (`g`, `o`, `s`,
//!   `usemtl`, `mtllib`, `l`, ...) is kept by [`MeshFile`] and not needed
//!   for the mesh; the indices of lines `l` and points `p` are checked as
//!   faces' are (and written back as they were).
//! - **OFF**: the `OFF` keyword (also `COFF`, `NOFF`, `STOFF`, counts on the
//!   same line, or no keyword at all), `nV nF [nE]`, vertex lines (values past
//!   x y z, such as colours, are ignored), face lines `n i0 ... i(n-1)`
//!   (trailing colour values are ignored).
//! - **PLY**: `ascii`, `binary_little_endian` and `binary_big_endian`; element
//!   `vertex` with scalar properties `x`, `y` and optionally `z` of any type,
//!   element `face` with a list property `vertex_indices` or `vertex_index`;
//!   every other element and property is skipped.
//! - **STL**: ASCII (`solid` ... `endsolid`, several solids in a row) and
//!   binary (told by its size: binary files whose header starts with
//!   `solid` are common); corners at the same point are one vertex (see
//!   `stl.rs`).
//!
//! Polygons with more than three vertices are triangulated by ear clipping in
//! the polygon's best-fit plane, keeping the polygon's orientation (a convex
//! quad is split along its shorter diagonal).
//!
//! Writing produces `v x y z` / `f a b c` OBJ, standard OFF,
//! `binary_little_endian` PLY with `double` coordinates, and binary STL
//! (`float` corners, as the format holds them). Coordinates of the text
//! formats and PLY are written with the shortest representation that reads
//! back to the same `f64`, so reading such a written mesh gives back exactly
//! the same mesh.

#[doc(hidden)]
pub mod appearance;
#[doc(hidden)]
pub mod atomic;
#[doc(hidden)]
pub mod correspondence_file;
#[doc(hidden)]
pub mod drawing;
pub mod gltf;
#[doc(hidden)]
pub mod marker_file;
#[doc(hidden)]
pub mod marker_points;
#[doc(hidden)]
pub mod material_paths;
#[doc(hidden)]
pub mod mesh_file;
#[doc(hidden)]
pub mod morph_storage;
pub mod mtl;
#[doc(hidden)]
pub mod normal_groups;
#[doc(hidden)]
pub mod obj;
#[doc(hidden)]
pub mod off;
#[doc(hidden)]
pub mod picked_points;
pub mod picture;
#[doc(hidden)]
pub mod ply;
#[doc(hidden)]
pub mod read;
#[doc(hidden)]
pub mod stl;
#[doc(hidden)]
pub mod surface_issues;
#[doc(hidden)]
pub mod triangulate;
#[doc(hidden)]
pub mod vertex_attributes;
#[doc(hidden)]
pub mod wrap_points;

pub use appearance::Appearance;
pub use atomic::{
    random_name, refuse_unless_replaceable, remove_own_temporaries, write_atomic, write_new,
};
pub use drawing::{
    drawing_of_mesh, match_anchors, parse_svg_drawing, parse_text_drawing, read_anchor_file,
    read_drawing, svg_path_data, write_animated_svg, write_lottie, write_svg_frame,
    write_text_frame, AnchorRow, Animation, Canvas, DrawingFile, DrawingKind, DrawingOptions,
    NamedPoint, Style,
};
pub use mesh_file::MeshFile;
pub use read::read_text;
pub use surface_issues::SurfaceIssues;
use vertex_attributes::VertexAttributes;

use std::fmt;
use std::io::Write;
use std::path::Path;
use std::str::FromStr;

use crate::error::{Error, Result};
use crate::mesh::{Mesh, Mesh2, Mesh3};

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ (`.obj`).
    Obj,
    /// Object File Format (`.off`).
    Off,
    /// Stanford polygon format (`.ply`).
    Ply,
    /// Stereolithography (`.stl`), ASCII or binary.
    Stl,
}

impl Format {
    /// Every format, in the order error messages list them.
    const ALL: [Format; 4] = [Format::Obj, Format::Off, Format::Ply, Format::Stl];

    /// The format a file name's extension names (case-insensitive:
    /// `mesh.OBJ` is OBJ).
    ///
    /// # Errors
    /// [`Error::UnknownFormat`] when the path has no extension or one that
    /// is not `obj`, `off`, `ply` or `stl`.
    pub fn from_path(path: &Path) -> Result<Format> {
        path.extension()
            .and_then(|e| e.to_str())
            .and_then(|e| {
                Format::ALL
                    .into_iter()
                    .find(|f| f.extension().eq_ignore_ascii_case(e))
            })
            .ok_or_else(|| Error::UnknownFormat {
                path: path.to_path_buf(),
            })
    }

    /// The usual file name extension, lower case and without the dot
    /// (`"obj"`, `"off"`, `"ply"` or `"stl"`).
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Off => "off",
            Format::Ply => "ply",
            Format::Stl => "stl",
        }
    }
}

impl fmt::Display for Format {
    /// The extension: `obj`, `off`, `ply` or `stl`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.extension())
    }
}

impl FromStr for Format {
    type Err = Error;

    /// Parses `obj`, `off`, `ply` or `stl` (case-insensitive, an optional leading
    /// dot is allowed).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] listing the choices.
    fn from_str(s: &str) -> Result<Format> {
        let name = s.strip_prefix('.').unwrap_or(s);
        Format::ALL
            .into_iter()
            .find(|f| f.extension().eq_ignore_ascii_case(name))
            .ok_or_else(|| {
                Error::InvalidArgument(format!(
                    "unknown mesh format `{s}`: expected one of obj, off, ply, stl"
                ))
            })
    }
}

/// Reads a triangle mesh, choosing the format by the file's extension.
///
/// # Errors
/// [`Error::UnknownFormat`] for an unknown extension, [`Error::Io`] when the
/// file cannot be read, [`Error::FileRefused`] when it is not a regular
/// file or is larger than a third of the memory available (see
/// [`crate::limits::available_memory`]), [`Error::Parse`] naming the file (and the line, for
/// text formats) when its contents are not a valid mesh.
pub fn read_mesh(path: &Path) -> Result<Mesh3> {
    read_mesh_as(path, Format::from_path(path)?)
}

/// Reads a planar mesh: a mesh file whose vertices all have z = 0 (as
/// OBJ, OFF, PLY and STL files of 2D shapes store them), choosing the
/// format by the file's extension.
///
/// # Errors
/// As [`read_mesh`], and [`Error::InvalidVertex`] naming the first vertex
/// off the plane (read a surface in space with [`read_mesh`]).
pub fn read_planar_mesh(path: &Path) -> Result<Mesh2> {
    read_mesh(path)?.to_2d()
}

/// Reads a triangle mesh in the given format, whatever the file's extension.
///
/// # Errors
/// [`Error::Io`] when the file cannot be read, [`Error::FileRefused`] as
/// for [`read_mesh`], [`Error::Parse`] naming the
/// file (and the line, for text formats) when its contents are not a valid
/// mesh.
pub fn read_mesh_as(path: &Path, format: Format) -> Result<Mesh3> {
    let bytes = read_mesh_bytes(path, format)?;
    parse_mesh(&bytes, format, path)
}

/// The bytes of the mesh file `path` in `format`: a regular file, at most
/// a third of the memory available (see [`read`]). A file larger than its
/// first [`START`] bytes is refused at once, before the rest is read, when
/// they show it is not of its format: an STL file neither of the size its
/// header gives nor beginning as an ASCII one ([`stl::check_start`]), a
/// PLY file without `ply` on its first line, an OBJ or OFF file with a NUL
/// byte (they are text).
fn read_mesh_bytes(path: &Path, format: Format) -> Result<Vec<u8>> {
    let mut input = read::open(path)?;
    let len = input.len();
    let start = input.head(START)?;
    if (start.len() as u64) < len {
        match format {
            Format::Stl => stl::check_start(start, len, path)?,
            Format::Ply if Lines::new(start).next().is_none_or(|(_, l)| l != b"ply") => {
                return Err(Error::parse(
                    path,
                    Some(1),
                    "not a PLY file: the first line is not `ply`",
                ));
            }
            Format::Obj | Format::Off => {
                if let Some(at) = memchr::memchr(0, start) {
                    return Err(Error::parse(
                        path,
                        Some(1 + memchr::memchr_iter(b'\n', &start[..at]).count()),
                        format!("not a text file: byte {at} is 0 (an {format} file is text)"),
                    ));
                }
            }
            Format::Ply => {}
        }
    }
    input.read_to_end(&read::Limit::memory())
}

/// How many first bytes of a mesh file [`read_mesh_bytes`] looks at before
/// reading the rest.
const START: usize = 64 << 10;

/// Parses a triangle mesh from a file's contents; `path_for_messages` only
/// names the source in error messages.
///
/// Polygons are triangulated (see the [module documentation](self)).
///
/// # Errors
/// [`Error::Parse`] naming `path_for_messages` and, for text formats, the
/// 1-based line: a number that does not parse, a coordinate that is NaN or
/// infinite, a face with fewer than three vertices, a vertex index out of
/// range, a face that repeats a vertex, a truncated file, a file without
/// triangles, ...
pub fn parse_mesh(bytes: &[u8], format: Format, path_for_messages: &Path) -> Result<Mesh3> {
    let path = path_for_messages;
    let parsed = mesh_file::parse_parts(bytes, format, path, mesh_file::Keep::Mesh)?;
    let triangles = parsed.faces.triangulate(&parsed.positions).triangles;
    finish(path, parsed.positions, triangles)
}

/// Writes a mesh atomically (see [`write_atomic`]); a planar mesh (`D = 2`)
/// is written with z = 0.
///
/// # Errors
/// [`Error::Io`] naming the file when it cannot be written; no file (and no
/// temporary file) is left behind then.
pub fn write_mesh<const D: usize>(path: &Path, mesh: &Mesh<D>, format: Format) -> Result<()> {
    write_positions(path, mesh.positions(), mesh.triangles(), format)
}

/// Writes positions and triangles as a mesh file, atomically (see
/// [`write_atomic`]), without building a [`Mesh`]: the per-frame output path
/// of the animation commands. Positions with `D < 3` are padded with zeros.
///
/// The input is checked (finite coordinates, indices in range) so that the
/// file written can always be read back.
///
/// # Errors
/// [`Error::InvalidArgument`] when `D > 3`; [`Error::InvalidMesh`] naming the
/// file and the first offending vertex or triangle when a coordinate is not
/// finite or an index is out of range; [`Error::Io`] naming the file when it
/// cannot be written. Nothing is left at `path` when an error occurs.
pub fn write_positions<const D: usize>(
    path: &Path,
    positions: &[[f64; D]],
    triangles: &[[u32; 3]],
    format: Format,
) -> Result<()> {
    atomic::write_atomic_with(path, |w| {
        write_positions_to(w, path, positions, triangles, format)
    })
}

/// [`write_positions`] into `w`, for a file made otherwise (see
/// [`write_new`]): `path` is the file's name in messages. The same checks
/// come before any byte is written.
///
/// # Errors
/// Those of [`write_positions`]; `w`'s errors as [`Error::Io`] naming
/// `path`.
pub fn write_positions_to<const D: usize>(
    w: &mut dyn Write,
    path: &Path,
    positions: &[[f64; D]],
    triangles: &[[u32; 3]],
    format: Format,
) -> Result<()> {
    check_writable(path, positions, triangles)?;
    if format == Format::Stl {
        stl::check_float_corners(path, positions, triangles)?;
    }
    let faces = || triangles.iter().map(|t| &t[..]);
    match format {
        Format::Obj => obj::write(w, positions, faces()),
        Format::Off => off::write(
            w,
            positions,
            faces(),
            triangles.len(),
            &VertexAttributes::default(),
        ),
        Format::Ply => ply::write(
            w,
            positions,
            faces(),
            triangles.len(),
            &VertexAttributes::default(),
        ),
        Format::Stl => stl::write(w, positions, triangles),
    }
    .map_err(|e| Error::io(path, e))
}

/// Refuses what could not be read back: `D > 3`, non-finite coordinates,
/// out-of-range indices.
fn check_writable<const D: usize>(
    path: &Path,
    positions: &[[f64; D]],
    triangles: &[[u32; 3]],
) -> Result<()> {
    if D > 3 {
        return Err(Error::InvalidArgument(format!(
            "cannot write `{}`: mesh files hold at most 3 coordinates per vertex, not {D}",
            path.display()
        )));
    }
    if let Some(v) = positions
        .iter()
        .position(|p| p.iter().any(|x| !x.is_finite()))
    {
        return Err(Error::InvalidVertex {
            vertex: v,
            message: format!(
                "cannot write `{}`: vertex {v} has a coordinate that is not a finite number: {:?}",
                path.display(),
                positions[v]
            ),
        });
    }
    let n = positions.len();
    if let Some(t) = triangles
        .iter()
        .position(|tri| tri.iter().any(|&i| i as usize >= n))
    {
        return Err(Error::InvalidTriangle {
            triangle: t,
            message: format!(
                "cannot write `{}`: triangle {t} {:?} uses a vertex index out of range (the mesh has {n} vertices)",
                path.display(),
                triangles[t]
            ),
        });
    }
    Ok(())
}

/// Builds the mesh at the end of every reader, so that an invariant the
/// reader did not check itself still gives a message naming the file.
fn finish(path: &Path, positions: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Result<Mesh3> {
    check_has_faces(path, positions.len(), triangles.len())?;
    Mesh3::new(positions, triangles).map_err(|e| match e {
        Error::InvalidMesh(message)
        | Error::InvalidVertex { message, .. }
        | Error::InvalidTriangle { message, .. } => Error::parse(path, None, message),
        other => other,
    })
}

/// Refuses a file without faces (`faces`: its faces, or the triangles they
/// split into).
fn check_has_faces(path: &Path, vertices: usize, faces: usize) -> Result<()> {
    if faces == 0 {
        return Err(Error::parse(
            path,
            None,
            format!("no triangles: the file has {vertices} vertices and no faces"),
        ));
    }
    Ok(())
}

/// `x y z` of a position with `D <= 3` coordinates, zero-padded.
#[inline]
pub fn xyz<const D: usize>(p: &[f64; D]) -> [f64; 3] {
    std::array::from_fn(|k| if k < D { p[k] } else { 0.0 })
}

/// Appends the shortest decimal representation of `x` (finite) that parses
/// back to exactly `x`: `0.1`, `1e-7`, `2.5e+20`, and integers without `.0`.
///
/// `zmij` is about five times faster than `{}` formatting, which matters for
/// per-frame output.
#[inline]
pub fn push_f64(buf: &mut Vec<u8>, x: f64) {
    let mut digits = zmij::Buffer::new();
    let s = digits.format_finite(x);
    buf.extend_from_slice(s.strip_suffix(".0").unwrap_or(s).as_bytes());
}

/// Appends the decimal representation of `n`.
#[inline]
pub fn push_uint(buf: &mut Vec<u8>, n: u64) {
    /// "00", "01", ..., "99".
    const PAIRS: [u8; 200] = {
        let mut pairs = [0u8; 200];
        let mut i = 0;
        while i < 100 {
            pairs[2 * i] = b'0' + (i / 10) as u8;
            pairs[2 * i + 1] = b'0' + (i % 10) as u8;
            i += 1;
        }
        pairs
    };
    let mut digits = [0u8; 20];
    let mut i = digits.len();
    // 32-bit division is faster, and indices fit.
    let mut small = match u32::try_from(n) {
        Ok(small) => small,
        Err(_) => {
            let mut big = n;
            while big > u64::from(u32::MAX) {
                i -= 1;
                digits[i] = b'0' + (big % 10) as u8;
                big /= 10;
            }
            big as u32
        }
    };
    while small >= 100 {
        let r = (small % 100) as usize * 2;
        small /= 100;
        i -= 2;
        digits[i..i + 2].copy_from_slice(&PAIRS[r..r + 2]);
    }
    if small >= 10 {
        let r = small as usize * 2;
        i -= 2;
        digits[i..i + 2].copy_from_slice(&PAIRS[r..r + 2]);
    } else {
        i -= 1;
        digits[i] = b'0' + small as u8;
    }
    buf.extend_from_slice(&digits[i..]);
}

/// Size at which writers hand their buffer on.
const CHUNK: usize = 1 << 16;

/// Writes `format(item)` for every item, in order, through a reused
/// buffer handed on every [`CHUNK`] bytes.
///
/// (Formatting chunks in parallel was measured: no faster on two cores busy
/// with other work, so output stays sequential.)
fn write_formatted<T>(
    w: &mut dyn Write,
    items: impl IntoIterator<Item = T>,
    format: impl Fn(&mut Vec<u8>, T),
) -> std::io::Result<()> {
    let mut buf = Vec::with_capacity(CHUNK + 1024);
    for item in items {
        format(&mut buf, item);
        if buf.len() >= CHUNK {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    w.write_all(&buf)
}

/// Lines of a text file as `(1-based number, bytes without the line end)`;
/// a final line without a line end counts, a `\r` before the `\n` is dropped
/// and a UTF-8 byte order mark at the start is skipped.
#[derive(Clone)]
pub struct Lines<'a> {
    rest: &'a [u8],
    number: usize,
}

impl<'a> Lines<'a> {
    /// The lines of a file's bytes.
    pub fn new(bytes: &'a [u8]) -> Self {
        Lines {
            rest: bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes),
            number: 0,
        }
    }

    /// The number of the line returned last (0 before the first).
    fn number(&self) -> usize {
        self.number
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        if self.rest.is_empty() {
            return None;
        }
        let (line, rest) = match memchr::memchr(b'\n', self.rest) {
            Some(i) => (&self.rest[..i], &self.rest[i + 1..]),
            None => (self.rest, &self.rest[..0]),
        };
        self.rest = rest;
        self.number += 1;
        Some((self.number, line.strip_suffix(b"\r").unwrap_or(line)))
    }
}

/// Lines of a text file as [`Lines`] gives them, each up to a `#` comment.
pub struct UncommentedLines<'a> {
    lines: Lines<'a>,
    /// How many bytes of the file are left from its next `#` on (`None`
    /// when no `#` is left): found once for the lines up to it.
    mark_left: Option<usize>,
}

impl<'a> UncommentedLines<'a> {
    /// The lines of a file's bytes, each up to a `#` comment.
    pub fn new(bytes: &'a [u8]) -> Self {
        let lines = Lines::new(bytes);
        let rest = lines.rest;
        UncommentedLines {
            lines,
            mark_left: memchr::memchr(b'#', rest).map(|i| rest.len() - i),
        }
    }
}

impl<'a> Iterator for UncommentedLines<'a> {
    type Item = (usize, &'a [u8]);

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        let rest = self.lines.rest;
        let (number, line) = self.lines.next()?;
        let left = rest.len();
        if self.mark_left.is_some_and(|m| m > left) {
            // The last `#` found is behind: look for the next one.
            self.mark_left = memchr::memchr(b'#', rest).map(|i| left - i);
        }
        Some(match self.mark_left {
            Some(m) if left - m < line.len() => (number, &line[..left - m]),
            _ => (number, line),
        })
    }
}

/// Whether byte `i` of `text` separates tokens: white space, or a `\` that
/// ends a line (OBJ's line continuation, see
/// [`obj::ContinuedLines`]).
#[inline]
fn separates(text: &[u8], i: usize) -> bool {
    let b = text[i];
    b.is_ascii_whitespace()
        || (b == b'\\'
            && text[i + 1..]
                .iter()
                .find(|&&c| !matches!(c, b' ' | b'\t' | b'\r'))
                .is_some_and(|&c| c == b'\n' || c == b'#'))
}

/// Whitespace-separated tokens of a line.
#[inline]
fn tokens(line: &[u8]) -> Tokens<'_> {
    Tokens {
        rest: line,
        continued: false,
    }
}

/// Tokens of a line continued with `\` over several lines (OBJ): the `\`
/// and line ends separate tokens as white space does.
#[inline]
fn continued_tokens(line: &[u8]) -> Tokens<'_> {
    Tokens {
        rest: line,
        continued: true,
    }
}

/// The iterator of [`tokens`] and [`continued_tokens`].
#[derive(Clone)]
struct Tokens<'a> {
    rest: &'a [u8],
    continued: bool,
}

impl<'a> Tokens<'a> {
    /// The next token of a continued line.
    #[cold]
    fn next_continued(&mut self) -> Option<&'a [u8]> {
        let mut rest = self.rest;
        // Separators, and comments to the end of their physical line.
        let start = loop {
            let start = (0..rest.len()).find(|&i| !separates(rest, i))?;
            if rest[start] != b'#' {
                break start;
            }
            let end = memchr::memchr(b'\n', &rest[start..])?;
            rest = &rest[start + end..];
        };
        let token = &rest[start..];
        let end = (1..token.len())
            .find(|&i| separates(token, i))
            .unwrap_or(token.len());
        self.rest = &token[end..];
        Some(&token[..end])
    }
}

impl<'a> Iterator for Tokens<'a> {
    type Item = &'a [u8];

    #[inline]
    fn next(&mut self) -> Option<&'a [u8]> {
        if self.continued {
            return self.next_continued();
        }
        let start = self.rest.iter().position(|b| !b.is_ascii_whitespace())?;
        let token = &self.rest[start..];
        let end = token
            .iter()
            .position(u8::is_ascii_whitespace)
            .unwrap_or(token.len());
        self.rest = &token[end..];
        Some(&token[..end])
    }
}

/// A token as a number (anything `str::parse::<f64>` accepts, including
/// `nan` and `inf`: callers check finiteness where it matters).
#[inline]
pub fn parse_f64(token: &[u8]) -> Option<f64> {
    plain_decimal(token).or_else(|| std::str::from_utf8(token).ok()?.parse().ok())
}

/// Powers of ten that are exact in an `f64`: `10^0` to `10^22`.
const EXACT_POWERS_OF_TEN: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// A number written as mesh files usually write them, `[+-]digits[.digits]`
/// with at most 19 digits, whose digits as an integer are exact in an `f64`
/// (below `2^53`) and with at most 22 of them after the point; `None` for
/// anything else.
///
/// The value is then that integer divided by a power of ten, both exact, so
/// the one division rounds correctly (Clinger's fast path): the same `f64`
/// as the standard library's correctly rounded parser gives, at a fraction
/// of its cost.
#[inline]
fn plain_decimal(token: &[u8]) -> Option<f64> {
    let (negative, digits) = match token.first()? {
        b'-' => (true, &token[1..]),
        b'+' => (false, &token[1..]),
        _ => (false, token),
    };
    // The digits as one integer (wrapping past 19 digits, refused below).
    let mut n: u64 = 0;
    let mut i = 0;
    let mut run = |i: &mut usize| {
        let start = *i;
        while let Some(d) = digits
            .get(*i)
            .map(|d| d.wrapping_sub(b'0'))
            .filter(|&d| d <= 9)
        {
            n = n.wrapping_mul(10).wrapping_add(u64::from(d));
            *i += 1;
        }
        *i - start
    };
    let whole = run(&mut i);
    let fraction = match digits.get(i) {
        Some(b'.') => {
            i += 1;
            run(&mut i)
        }
        _ => 0,
    };
    let plain = whole > 0 && (fraction > 0 || i == whole) && i == digits.len();
    if !plain || whole + fraction > 19 || n > 1 << 53 {
        return None;
    }
    let x = n as f64 / EXACT_POWERS_OF_TEN[fraction];
    Some(if negative { -x } else { x })
}

/// Why `token` is not a usable count: "is too large", "is negative" or "is
/// not a whole number", for messages.
fn bad_count(token: &[u8]) -> &'static str {
    let digits = token.strip_prefix(b"+").unwrap_or(token);
    if let Some(rest) = token.strip_prefix(b"-") {
        if !rest.is_empty() && rest.iter().all(u8::is_ascii_digit) {
            return "is negative";
        }
    }
    if !digits.is_empty() && digits.iter().all(u8::is_ascii_digit) {
        "is too large"
    } else {
        "is not a whole number"
    }
}

/// A token as an integer (optional sign, decimal digits only).
#[inline]
pub fn parse_i64(token: &[u8]) -> Option<i64> {
    let (negative, digits) = match token.first()? {
        b'-' => (true, &token[1..]),
        b'+' => (false, &token[1..]),
        _ => (false, token),
    };
    if digits.is_empty() {
        return None;
    }
    let mut n: i64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        n = n.checked_mul(10)?.checked_add(i64::from(d - b'0'))?;
    }
    Some(if negative { -n } else { n })
}

/// A token for an error message: lossily decoded, shortened if long.
fn show(token: &[u8]) -> String {
    const MAX: usize = 40;
    let s = String::from_utf8_lossy(&token[..token.len().min(MAX)]).into_owned();
    if token.len() > MAX {
        s + "..."
    } else {
        s
    }
}
