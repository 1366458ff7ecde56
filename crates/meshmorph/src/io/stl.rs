//! STL (stereolithography), ASCII and binary.
//!
//! An STL file lists each facet with its own three corners and a normal:
//! there are no shared vertices. Corners at the same point (bit for bit,
//! but 0 and -0 alike: written back, such a corner takes the sign of the
//! vertex's first) are one vertex, numbered in the order they first occur,
//! so a pose exported from the same mesh numbers its vertices alike. A
//! facet whose corners are not three distinct points is refused, naming
//! it; so is, when written, a shape that `float` corners cannot hold
//! (beyond their range, or corners of a facet rounded onto one point).
//!
//! Written back in STL, the file keeps its header or `solid` name, its facet
//! order, and (binary) each facet's attribute bytes; each facet's corners
//! take the new positions and its normal turns with the facet (a zero normal
//! stays zero). Other formats are written as binary STL: facet normals from
//! the triangles, `float` corners.

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use super::mesh_file::{offset_in, Coding, Keep, Parsed, Patch, Slot};
use super::ply::Scalar;
use super::triangulate::Polygons;
use super::{parse_f64, show, tokens, xyz, Lines};
use crate::error::{Error, Result};
use crate::linalg::vector::{cross, norm, sub};

/// Bytes before the first facet of a binary file: an 80-byte header and
/// the facet count.
const HEADER: usize = 84;
/// Bytes of one binary facet: normal, three corners (12 `float`s) and a
/// 2-byte attribute.
const FACET: usize = 50;

/// Parses an STL file's contents (see the [module documentation](self)),
/// keeping what [`MeshFile`](super::MeshFile) needs to write it back.
pub(super) fn parse(bytes: &[u8], path: &Path, keep: Keep) -> Result<Parsed> {
    let count = (bytes.len() >= HEADER)
        .then(|| u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize);
    let sized_as_binary = count.is_some_and(|n| HEADER + FACET * n == bytes.len());
    // Binary files whose header starts with `solid` are common: the size
    // decides first; a file that starts as text but is not (a binary file
    // cut short, say) is judged as binary.
    let mut out = if sized_as_binary || !starts_as_ascii(bytes) {
        parse_binary(bytes, path, keep)?
    } else {
        match parse_ascii(bytes, path, keep) {
            Ok(ascii) if ascii.faces.len() > 0 || is_text(bytes) => ascii,
            Err(e) if is_text(bytes) => return Err(e),
            _ => parse_binary(bytes, path, keep)?,
        }
    };
    if out.faces.len() == 0 {
        return Err(Error::parse(
            path,
            None,
            "no triangles: the file has no facets",
        ));
    }
    out.flat_faces = vec![true; out.faces.len()];
    Ok(out)
}

/// Refuses at once (before the rest is read) a file of `len` bytes that
/// begins with `start` (some kilobytes, less than the whole file) and is
/// no STL: neither of the size of a binary file (84 + 50 bytes per facet
/// the header counts) nor beginning as an ASCII one (`solid`, then `facet`
/// or `endsolid` in `start`). What is refused here is what [`parse`] would
/// refuse once the whole file is read, with the same message.
pub(super) fn check_start(start: &[u8], len: u64, path: &Path) -> Result<()> {
    let count = (start.len() >= HEADER)
        .then(|| u32::from_le_bytes([start[80], start[81], start[82], start[83]]));
    if count.is_some_and(|n| HEADER as u64 + FACET as u64 * u64::from(n) == len) {
        return Ok(());
    }
    let has = |word: &[u8]| {
        start
            .windows(word.len())
            .any(|w| w.eq_ignore_ascii_case(word))
    };
    if starts_as_ascii(start) && (has(b"facet") || has(b"endsolid")) {
        return Ok(());
    }
    Err(binary_size_error(path, count, len))
}

/// The error of a file read as binary STL whose size is not the one its
/// header's facet count gives (`count`, `None` when shorter than the
/// header).
fn binary_size_error(path: &Path, count: Option<u32>, len: u64) -> Error {
    let message = match count {
        None => format!(
            "a binary STL file has an 84-byte header, this file has {len} bytes (and does not start with `solid`)"
        ),
        Some(count) => {
            let expected = HEADER as u64 + FACET as u64 * u64::from(count);
            format!(
                "the header announces {count} facets, which take {expected} bytes, but the file has {len} bytes"
            )
        }
    };
    Error::parse(path, None, message)
}

/// Whether the file begins with the `solid` keyword (after a byte-order
/// mark and blanks; in any case, as some tools write it).
fn starts_as_ascii(bytes: &[u8]) -> bool {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    bytes[start..]
        .get(..5)
        .is_some_and(|w| w.eq_ignore_ascii_case(b"solid"))
}

/// Whether the file holds text only (no control bytes but blanks): an
/// ASCII STL does, a binary one almost never.
fn is_text(bytes: &[u8]) -> bool {
    bytes
        .iter()
        .all(|&b| b >= 0x20 || matches!(b, b'\n' | b'\r' | b'\t' | 0x0c))
}

/// Whether `token` is the keyword `word`, in any case.
fn is(token: &[u8], word: &[u8]) -> bool {
    token.eq_ignore_ascii_case(word)
}

/// Gives corners one vertex per distinct point, in order of first use.
struct Welder<K> {
    vertex_of: HashMap<K, u32>,
}

impl<K: std::hash::Hash + Eq> Welder<K> {
    fn new(capacity: usize) -> Self {
        Welder {
            vertex_of: HashMap::with_capacity(capacity),
        }
    }

    /// The vertex at `key`, added to `positions` at `p` when new.
    fn vertex(&mut self, key: K, p: [f64; 3], positions: &mut Vec<[f64; 3]>) -> u32 {
        *self.vertex_of.entry(key).or_insert_with(|| {
            positions.push(p);
            positions.len() as u32 - 1
        })
    }
}

/// The bits of a coordinate, with `-0` read as `0`.
fn key64(x: f64) -> u64 {
    if x == 0.0 {
        0
    } else {
        x.to_bits()
    }
}

/// Refuses a facet whose corners are not three distinct points.
fn check_facet(
    path: &Path,
    line: Option<usize>,
    f: usize,
    face: [u32; 3],
    positions: &[[f64; 3]],
) -> Result<()> {
    for (a, b) in [(0, 1), (1, 2), (0, 2)] {
        if face[a] == face[b] {
            let p = positions[face[a] as usize];
            return Err(Error::parse(
                path,
                line,
                format!(
                    "facet {} (numbered from 1): corners {} and {} are the same point ({} {} {}): a facet needs three distinct corners",
                    f + 1,
                    a + 1,
                    b + 1,
                    p[0],
                    p[1],
                    p[2]
                ),
            ));
        }
    }
    Ok(())
}

fn parse_binary(bytes: &[u8], path: &Path, keep: Keep) -> Result<Parsed> {
    let len = bytes.len() as u64;
    if bytes.len() < HEADER {
        return Err(binary_size_error(path, None, len));
    }
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]);
    if HEADER as u64 + FACET as u64 * u64::from(count) != len {
        return Err(binary_size_error(path, Some(count), len));
    }
    let count = count as usize;
    let mut out = Parsed::new(keep);
    let mut welder = Welder::new(count / 2 + 3);
    let mut faces = Polygons::with_capacity(count);
    let float =
        |at: usize| f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let mut attributes = false;
    for f in 0..count {
        let at = HEADER + FACET * f;
        // Patches go in file order: the normal, then the corners.
        let normal = [float(at), float(at + 4), float(at + 8)];
        out.normals
            .push(normal.map(|x| if x.is_finite() { f64::from(x) } else { 0.0 }));
        for axis in 0..3 {
            let b = at + 4 * axis;
            out.patch(Patch {
                bytes: b..b + 4,
                slot: Slot::Normal(f as u32, axis as u8),
                coding: Coding::Binary(Scalar::F32, false),
            });
        }
        let mut face = [0u32; 3];
        for (k, corner) in face.iter_mut().enumerate() {
            let c = at + 12 * (k + 1);
            let p = [float(c), float(c + 4), float(c + 8)];
            if let Some(x) = p.iter().find(|x| !x.is_finite()) {
                return Err(Error::parse(
                    path,
                    None,
                    format!(
                        "facet {} (numbered from 1), corner {}: the coordinate {x} is not a finite number",
                        f + 1,
                        k + 1
                    ),
                ));
            }
            let key = p.map(|x| if x == 0.0 { 0 } else { x.to_bits() });
            *corner = welder.vertex(key, p.map(f64::from), &mut out.positions);
            for axis in 0..3 {
                let b = c + 4 * axis;
                out.patch(Patch {
                    bytes: b..b + 4,
                    slot: Slot::Position(*corner, axis as u8),
                    coding: Coding::Binary(Scalar::F32, false),
                });
            }
        }
        check_facet(path, None, f, face, &out.positions)?;
        attributes |= bytes[at + 48] != 0 || bytes[at + 49] != 0;
        faces.push(&face, 0);
    }
    if attributes {
        out.note_extra("facet attribute bytes (colours in some tools)");
    }
    out.corner_normal = (0..count as u32).flat_map(|f| [f; 3]).collect();
    out.faces = faces;
    Ok(out)
}

fn parse_ascii(bytes: &[u8], path: &Path, keep: Keep) -> Result<Parsed> {
    let err = |line: usize, msg: String| Error::parse(path, Some(line), msg);
    let mut out = Parsed::new(keep);
    let mut welder = Welder::new(bytes.len() / 200);
    let mut faces = Polygons::with_capacity(bytes.len() / 250);
    let mut lines = Lines::new(bytes).filter(|(_, l)| tokens(l).next().is_some());
    // What comes next: `solid`, then facets until `endsolid`, then
    // perhaps another solid (files of several parts).
    let mut in_solid = false;
    let mut last_line = 0;
    while let Some((no, line)) = lines.next() {
        last_line = no;
        let mut toks = tokens(line);
        let keyword = toks.next().unwrap_or_default();
        match (in_solid, keyword) {
            (false, k) if is(k, b"solid") => in_solid = true,
            (true, k) if is(k, b"endsolid") => in_solid = false,
            (true, k) if is(k, b"facet") => {
                let f = faces.len();
                if !toks.next().is_some_and(|t| is(t, b"normal")) {
                    return Err(err(no, "expected `facet normal nx ny nz`".into()));
                }
                let normal: Vec<&[u8]> = toks.collect();
                if normal.len() != 3 {
                    return Err(err(
                        no,
                        format!(
                            "facet {} (numbered from 1): expected 3 numbers after `facet normal`, found {}",
                            f + 1,
                            normal.len()
                        ),
                    ));
                }
                let mut n = [0.0; 3];
                for (axis, tok) in normal.iter().enumerate() {
                    // Normals are recomputed by every reader: one that is
                    // not a number (`-1.#IND00e+000` of old exporters) is 0.
                    let x = parse_f64(tok).filter(|x| x.is_finite()).unwrap_or(0.0);
                    n[axis] = x;
                    let start = offset_in(bytes, tok);
                    out.patch(Patch::text(
                        start..start + tok.len(),
                        Slot::Normal(f as u32, axis as u8),
                    ));
                }
                out.normals.push(n);
                let mut expect = |word: &[u8]| -> Result<(usize, &[u8])> {
                    match lines.next() {
                        Some((no, line)) if tokens(line).next().is_some_and(|t| is(t, word)) => {
                            Ok((no, line))
                        }
                        Some((no, line)) => Err(err(
                            no,
                            format!(
                                "facet {} (numbered from 1): expected `{}`, found `{}`",
                                f + 1,
                                show(word),
                                show(line.trim_ascii())
                            ),
                        )),
                        None => Err(Error::parse(
                            path,
                            None,
                            format!("the file ends inside facet {} (numbered from 1)", f + 1),
                        )),
                    }
                };
                expect(b"outer")?;
                let mut face = [0u32; 3];
                for (k, corner) in face.iter_mut().enumerate() {
                    let (no, line) = expect(b"vertex")?;
                    let coords: Vec<&[u8]> = tokens(line).skip(1).collect();
                    if coords.len() != 3 {
                        return Err(err(
                            no,
                            format!(
                                "facet {} (numbered from 1), corner {}: expected `vertex x y z`, found {} numbers",
                                f + 1,
                                k + 1,
                                coords.len()
                            ),
                        ));
                    }
                    let mut p = [0.0; 3];
                    for (axis, tok) in coords.iter().enumerate() {
                        let x = parse_f64(tok)
                            .ok_or_else(|| err(no, format!("`{}` is not a number", show(tok))))?;
                        if !x.is_finite() {
                            return Err(err(
                                no,
                                format!(
                                    "facet {} (numbered from 1), corner {}: the coordinate `{}` is not a finite number",
                                    f + 1,
                                    k + 1,
                                    show(tok)
                                ),
                            ));
                        }
                        p[axis] = x;
                    }
                    *corner = welder.vertex(p.map(key64), p, &mut out.positions);
                    for (axis, tok) in coords.iter().enumerate() {
                        let start = offset_in(bytes, tok);
                        out.patch(Patch::text(
                            start..start + tok.len(),
                            Slot::Position(*corner, axis as u8),
                        ));
                    }
                }
                check_facet(path, Some(no), f, face, &out.positions)?;
                expect(b"endloop")?;
                expect(b"endfacet")?;
                faces.push(&face, no);
            }
            _ => {
                let expected = if in_solid {
                    "`facet normal` or `endsolid`"
                } else {
                    "`solid`"
                };
                return Err(err(
                    no,
                    format!("expected {expected}, found `{}`", show(keyword)),
                ));
            }
        }
    }
    if in_solid && faces.len() > 0 {
        return Err(Error::parse(
            path,
            Some(last_line),
            "the file ends without `endsolid`: it may have been cut short",
        ));
    }
    out.corner_normal = (0..faces.len() as u32).flat_map(|f| [f; 3]).collect();
    out.faces = faces;
    Ok(out)
}

/// Refuses what binary STL, which holds `float` corners, cannot hold so that
/// it reads back: a coordinate beyond the range of `float`, a facet whose
/// corners fall on one point once rounded to `float`.
///
/// # Errors
/// [`Error::InvalidMesh`] naming `path` and the vertex or facet (from 1).
pub(super) fn check_float_corners<const D: usize>(
    path: &Path,
    positions: &[[f64; D]],
    triangles: &[[u32; 3]],
) -> Result<()> {
    let float = |v: u32| xyz(&positions[v as usize]).map(|x| x as f32);
    for (f, t) in triangles.iter().enumerate() {
        let corners = t.map(float);
        if let Some(k) = (0..3).find(|&k| corners[k].iter().any(|x| !x.is_finite())) {
            return Err(Error::InvalidMesh(format!(
                "cannot write `{}`: STL holds single-precision numbers, and vertex {} of facet {} ({:?}) lies beyond their range; scale the mesh down or write another format",
                path.display(),
                t[k] + 1,
                f + 1,
                xyz(&positions[t[k] as usize])
            )));
        }
        for (a, b) in [(0, 1), (1, 2), (0, 2)] {
            if corners[a] == corners[b] {
                return Err(Error::InvalidMesh(format!(
                    "cannot write `{}`: STL holds single-precision numbers, and in them corners {} and {} of facet {} (vertices {} and {}, numbered from 1) fall on one point, which no reader takes back; write another format",
                    path.display(),
                    a + 1,
                    b + 1,
                    f + 1,
                    t[a] + 1,
                    t[b] + 1
                )));
            }
        }
    }
    Ok(())
}

/// Writes binary STL: an 80-byte header, the facet count, and per
/// triangle its unit normal (zero for a degenerate one), its corners as
/// `float`s and a zero attribute.
pub(super) fn write<const D: usize>(
    w: &mut dyn Write,
    positions: &[[f64; D]],
    triangles: &[[u32; 3]],
) -> std::io::Result<()> {
    let count = u32::try_from(triangles.len())
        .map_err(|_| std::io::Error::other("binary STL holds at most 4294967295 facets"))?;
    let mut header = [b' '; 80];
    let text = b"binary STL written by meshmorph";
    header[..text.len()].copy_from_slice(text);
    let mut buf: Vec<u8> = Vec::with_capacity(super::CHUNK + FACET);
    buf.extend_from_slice(&header);
    buf.extend_from_slice(&count.to_le_bytes());
    for t in triangles {
        if buf.len() >= super::CHUNK {
            w.write_all(&buf)?;
            buf.clear();
        }
        let [a, b, c] = t.map(|v| xyz(&positions[v as usize]));
        let n = cross(sub(b, a), sub(c, a));
        let len = norm(n);
        let n = if len > 0.0 {
            n.map(|x| x / len)
        } else {
            [0.0; 3]
        };
        for p in [n, a, b, c] {
            for x in p {
                buf.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        buf.extend_from_slice(&[0, 0]);
    }
    w.write_all(&buf)
}
