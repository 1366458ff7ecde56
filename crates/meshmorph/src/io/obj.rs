//! Wavefront OBJ: `v`, `vt`, `vn` and `f` statements; the others are kept
//! as they are when the file is written back (lines `l` and points `p` with
//! their indices checked as faces' are).

use std::io::Write;
use std::path::Path;

use super::mesh_file::{offset_in, Keep, Parsed, Patch, Slot, NONE};
use super::triangulate::{check_corners, Polygons};
use super::{
    continued_tokens, parse_f64, parse_i64, push_f64, push_uint, show, tokens, write_formatted,
    xyz, UncommentedLines,
};
use crate::error::{Error, Result};

/// Resolves an OBJ index (1-based, or negative: counted back from the last
/// element defined so far) to 0-based; `None` for 0 or before the start.
fn resolve(index: i64, defined: usize) -> Option<u32> {
    let r = match index {
        0 => return None,
        i if i > 0 => i - 1,
        i => defined as i64 + i,
    };
    u32::try_from(r).ok()
}

/// The texture coordinate or normal index of a face corner (`b` or `c` of
/// the corner `token`, `a/b/c`), 0-based, or [`NONE`] when the corner has
/// none; `defined` are defined before the line, `max` is the largest
/// positive index so far.
///
/// # Errors
/// The message when the index does not parse or is out of range.
#[inline]
fn corner_index(
    part: Option<&[u8]>,
    defined: usize,
    max: &mut i64,
    what: &str,
    token: &[u8],
) -> std::result::Result<u32, String> {
    let Some(part) = part.filter(|p| !p.is_empty()) else {
        return Ok(NONE);
    };
    let i = parse_i64(part).ok_or_else(|| format!("`{}` is not a {what} index", show(token)))?;
    if i > 0 {
        *max = (*max).max(i);
    }
    resolve(i, defined).ok_or_else(|| {
        format!("{what} index {i} is out of range: {defined} are defined before this line")
    })
}

/// The vertex of an element's corner (`part`, the vertex part of the corner
/// `token`), 0-based; `defined` vertices are defined before the line, `max`
/// is the largest positive index so far (checked once every vertex is
/// known: forward references are legal).
///
/// # Errors
/// The message when the index does not parse, is 0 or counts back past the
/// first vertex.
#[inline]
fn vertex_index(
    part: &[u8],
    token: &[u8],
    defined: usize,
    max: &mut i64,
) -> std::result::Result<u32, String> {
    let index =
        parse_i64(part).ok_or_else(|| format!("`{}` is not a vertex index", show(token)))?;
    if index > 0 {
        *max = (*max).max(index);
    }
    resolve(index, defined).ok_or_else(|| {
        if index == 0 {
            "vertex index 0 is invalid: OBJ indices start at 1 (or count back from -1)".into()
        } else {
            format!(
                "vertex index {index} is out of range: only {defined} vertices are defined before this line"
            )
        }
    })
}

/// OBJ's logical lines: a line that ends with `\` (before its comment and
/// line end) goes on on the next one. A logical line is the file's bytes
/// from its first line to its last, numbered by the first; the `\` and
/// line ends inside separate tokens as white space does.
pub(super) struct ContinuedLines<'a> {
    bytes: &'a [u8],
    lines: UncommentedLines<'a>,
}

impl<'a> ContinuedLines<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        ContinuedLines {
            bytes,
            lines: UncommentedLines::new(bytes),
        }
    }
}

impl<'a> Iterator for ContinuedLines<'a> {
    /// The first line's number, the logical line, and whether it goes over
    /// several.
    type Item = (usize, &'a [u8], bool);

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        let (number, mut line) = self.lines.next()?;
        // Each physical line that ends with `\` takes in the next one.
        let mut last = line;
        while last.trim_ascii_end().ends_with(b"\\") {
            let Some((_, more)) = self.lines.next() else {
                break;
            };
            let start = offset_in(self.bytes, line);
            line = &self.bytes[start..offset_in(self.bytes, more) + more.len()];
            last = more;
        }
        Some((number, line, last.as_ptr() != line.as_ptr()))
    }
}

/// The text of `line` after its keyword `keyword`, trimmed.
fn rest_of_line(line: &[u8], keyword: &[u8]) -> String {
    let after = offset_in(line, keyword) + keyword.len();
    String::from_utf8_lossy(line[after..].trim_ascii()).into_owned()
}

/// Parses an OBJ file's contents (see the [module documentation](super)),
/// keeping what [`MeshFile`](super::MeshFile) needs to write it back.
pub(super) fn parse(bytes: &[u8], path: &Path, keep: Keep) -> Result<Parsed> {
    let err = |line: usize, msg: String| Error::parse(path, Some(line), msg);
    let mut out = Parsed::new(keep);
    let mut face: Vec<u32> = Vec::new();
    let mut corner_uv: Vec<u32> = Vec::new();
    let mut corner_normal: Vec<u32> = Vec::new();
    // Positive indices are checked once every vertex is known (forward
    // references are legal); the largest one tells whether any is out of
    // range.
    let mut max_index: i64 = 0;
    let mut max_uv: i64 = 0;
    let mut max_normal: i64 = 0;
    // Whether each face is shaded flat (`s off` or `s 0` before it).
    let mut flat = false;
    let mut flat_faces: Vec<bool> = Vec::new();
    // The material of the faces that follow (`usemtl`), an index into
    // `out.materials.names`.
    let mut material = NONE;
    // The line of the first vertex with 2 coordinates and of the first with
    // 3 or more: a file is planar (`v x y`) or in space, never both.
    let mut first_planar: Option<usize> = None;
    // Normals with a coordinate that is not a finite number: how many, and
    // the first with its line.
    let mut not_finite_normals = 0usize;
    let mut first_not_finite: Option<(u32, usize)> = None;
    let mut first_spatial: Option<usize> = None;
    // Lines and points (`l`, `p`) with an index past what was defined before
    // them: their line, largest vertex and texture coordinate indices.
    let mut forward_elements: Vec<(usize, i64, i64)> = Vec::new();

    for (line_no, line, continued) in ContinuedLines::new(bytes) {
        let mut toks = if continued {
            continued_tokens(line)
        } else {
            tokens(line)
        };
        let keyword = toks.next();
        match keyword {
            Some(b"v") => {
                let vertex = out.positions.len() as u32;
                let mut p = [0.0; 3];
                let mut count = 0;
                let mut last_end = 0;
                // `v x y z r g b`: the values after x y z, a colour when
                // there are three.
                let mut after = [0.0f32; 4];
                for tok in toks {
                    let x = parse_f64(tok)
                        .ok_or_else(|| err(line_no, format!("`{}` is not a number", show(tok))))?;
                    if count < 3 {
                        if !x.is_finite() {
                            return Err(err(
                                line_no,
                                format!(
                                    "vertex {} (1-based) has a coordinate that is not a finite number: `{}`",
                                    out.positions.len() + 1,
                                    show(tok)
                                ),
                            ));
                        }
                        p[count] = x;
                        let start = offset_in(bytes, tok);
                        last_end = start + tok.len();
                        out.patch(Patch::text(
                            start..last_end,
                            Slot::Position(vertex, count as u8),
                        ));
                    }
                    if (3..7).contains(&count) {
                        after[count - 3] = x as f32;
                    }
                    count += 1;
                }
                if count == 6 && out.keeps_whole() {
                    let [r, g, b, _] = after.map(|c| {
                        if c.is_finite() {
                            c.clamp(0.0, 1.0)
                        } else {
                            0.0
                        }
                    });
                    // Vertices without a colour are white.
                    out.colors.resize(vertex as usize, [1.0; 4]);
                    out.colors.push([r, g, b, 1.0]);
                }
                if count < 2 {
                    return Err(err(
                        line_no,
                        format!("a vertex needs at least 2 coordinates (`v x y [z] [w]`), found {count}"),
                    ));
                }
                let (mine, other, have, other_have) = if count == 2 {
                    (&mut first_planar, first_spatial, 2, 3)
                } else {
                    (&mut first_spatial, first_planar, 3, 2)
                };
                if let Some(first) = other {
                    return Err(err(
                        line_no,
                        format!(
                            "vertex {} (1-based) has {have} coordinates where the vertices before it have {other_have} (the first at line {first}): give every vertex x y z, or every vertex x y for a planar mesh",
                            vertex as u64 + 1
                        ),
                    ));
                }
                mine.get_or_insert(line_no);
                if count == 2 {
                    // `v x y`: z is written after y.
                    out.patch(Patch::appended(last_end, Slot::Position(vertex, 2)));
                }
                out.positions.push(p);
            }
            Some(b"vt") => {
                let mut uv = [0.0; 2];
                for (k, tok) in toks.take(2).enumerate() {
                    uv[k] = parse_f64(tok).filter(|x| x.is_finite()).ok_or_else(|| {
                        err(
                            line_no,
                            format!("`{}` is not a texture coordinate", show(tok)),
                        )
                    })?;
                }
                out.uvs.push(uv);
            }
            Some(b"vn") => {
                let normal = out.normals.len() as u32;
                let mut n = [0.0; 3];
                let mut count = 0;
                for tok in toks.take(3) {
                    n[count] = parse_f64(tok).ok_or_else(|| {
                        err(
                            line_no,
                            format!("`{}` is not a normal coordinate", show(tok)),
                        )
                    })?;
                    let start = offset_in(bytes, tok);
                    out.patch(Patch::text(
                        start..start + tok.len(),
                        Slot::Normal(normal, count as u8),
                    ));
                    count += 1;
                }
                if count < 3 {
                    return Err(err(
                        line_no,
                        format!("a normal needs 3 coordinates (`vn x y z`), found {count}"),
                    ));
                }
                // Where normals of the new shape that this one splits into
                // are written: at the start of the next line (`line` is
                // without its line end, `\n` or `\r\n`), or at the end of a
                // file whose last line this is.
                if out.keeps_whole() {
                    let end = offset_in(bytes, line) + line.len();
                    let crlf = bytes.get(end) == Some(&b'\r');
                    let next = match memchr::memchr(b'\n', &bytes[end..]) {
                        Some(i) => end + i + 1,
                        None => bytes.len(),
                    };
                    out.patch(Patch::text(next..next, Slot::NormalsAfter(normal, crlf)));
                }
                // Read, and said: exporters write them for faces of no
                // area (Sumner's camel poses hold some).
                if n.iter().any(|x| !x.is_finite()) {
                    not_finite_normals += 1;
                    first_not_finite.get_or_insert((normal, line_no));
                }
                out.normals.push(n);
            }
            Some(b"f") => {
                face.clear();
                let first_corner = corner_uv.len();
                for tok in toks {
                    let mut parts = tok.split(|&b| b == b'/');
                    let vertex_part = parts.next().unwrap_or(tok);
                    let resolved =
                        vertex_index(vertex_part, tok, out.positions.len(), &mut max_index)
                            .map_err(|m| err(line_no, m))?;
                    face.push(resolved);
                    // Texture and normal indices: `a/b`, `a/b/c`, `a//c`.
                    let uv_part = parts.next();
                    let uv = corner_index(
                        uv_part,
                        out.uvs.len(),
                        &mut max_uv,
                        "texture coordinate",
                        tok,
                    )
                    .map_err(|m| err(line_no, m))?;
                    let normal_part = parts.next();
                    let normal = corner_index(
                        normal_part,
                        out.normals.len(),
                        &mut max_normal,
                        "normal",
                        tok,
                    )
                    .map_err(|m| err(line_no, m))?;
                    if let Some(t) = normal_part.filter(|t| !t.is_empty()) {
                        let start = offset_in(bytes, t);
                        out.patch(Patch::text(
                            start..start + t.len(),
                            Slot::CornerNormal(corner_normal.len() as u32),
                        ));
                    }
                    corner_uv.push(uv);
                    corner_normal.push(normal);
                }
                if face.len() < 3 {
                    return Err(err(
                        line_no,
                        format!("a face needs at least 3 vertices, found {}", face.len()),
                    ));
                }
                let collapsed =
                    check_corners(&face, |i| format!("vertex {} (1-based)", u64::from(i) + 1))
                        .map_err(|m| err(line_no, m))?;
                if collapsed {
                    out.repeats_in_a_row.push(out.faces.len() as u32);
                }
                debug_assert_eq!(corner_uv.len() - first_corner, face.len());
                out.faces.push(&face, line_no);
                flat_faces.push(flat);
                if out.keeps_whole() {
                    out.materials.of_face.push(material);
                }
            }
            Some(b"g") => out.note_extra("groups (`g`)"),
            Some(b"o") => out.note_extra("objects (`o`)"),
            Some(b"s") => {
                out.note_extra("smoothing groups (`s`)");
                flat = matches!(toks.next(), Some(b"off" | b"0"));
            }
            Some(b"mtllib") => {
                out.note_extra("materials (`mtllib`, `usemtl`)");
                // The library paths, from the first to the end of the last:
                // rewritten when the file is written to another folder.
                if let Some(first) = toks.next() {
                    let last = toks.last().unwrap_or(first);
                    let start = offset_in(bytes, first);
                    let end = offset_in(bytes, last) + last.len();
                    out.patch(Patch::text(start..end, Slot::MaterialLibrary));
                    if out.keeps_whole() {
                        let text = String::from_utf8_lossy(&bytes[start..end]).into_owned();
                        out.materials.libraries.push(text);
                    }
                }
            }
            Some(b"usemtl") => {
                out.note_extra("materials (`mtllib`, `usemtl`)");
                if out.keeps_whole() {
                    let name = rest_of_line(line, keyword.unwrap_or_default());
                    material = out.materials.index_of(&name);
                }
            }
            Some(kind @ (b"l" | b"p")) => {
                out.note_extra("lines and points (`l`, `p`)");
                // Checked as faces are, kept as written: `l v` or `l v/vt`,
                // `p v`.
                let line_element = kind == b"l";
                let (mut vertex_max, mut uv_max) = (0, 0);
                let mut count = 0;
                for tok in toks {
                    let mut parts = tok.split(|&b| b == b'/');
                    let vertex_part = parts.next().unwrap_or(tok);
                    let uv_part = parts.next();
                    if parts.next().is_some() || (!line_element && uv_part.is_some()) {
                        let form = if line_element { "`v` or `v/vt`" } else { "`v`" };
                        return Err(err(
                            line_no,
                            format!("`{}` is not a vertex index ({form})", show(tok)),
                        ));
                    }
                    vertex_index(vertex_part, tok, out.positions.len(), &mut vertex_max)
                        .map_err(|m| err(line_no, m))?;
                    corner_index(
                        uv_part,
                        out.uvs.len(),
                        &mut uv_max,
                        "texture coordinate",
                        tok,
                    )
                    .map_err(|m| err(line_no, m))?;
                    count += 1;
                }
                let least = if line_element {
                    "a line (`l`) needs at least 2 vertices"
                } else {
                    "a point (`p`) needs at least 1 vertex"
                };
                if count < 1 + usize::from(line_element) {
                    return Err(err(line_no, format!("{least}, found {count}")));
                }
                // Forward references, checked at the end.
                if vertex_max as u64 > out.positions.len() as u64
                    || uv_max as u64 > out.uvs.len() as u64
                {
                    forward_elements.push((line_no, vertex_max, uv_max));
                }
            }
            // vp, curves, unknown statements, comments: kept when written
            // back as OBJ, never needed elsewhere.
            _ => {}
        }
    }

    for (max, defined, what, plural, corners) in [
        (max_index, out.positions.len(), "vertex", "vertices", None),
        (
            max_uv,
            out.uvs.len(),
            "texture coordinate",
            "texture coordinates",
            Some(&corner_uv),
        ),
        (
            max_normal,
            out.normals.len(),
            "normal",
            "normals",
            Some(&corner_normal),
        ),
    ] {
        if max as u64 <= defined as u64 {
            continue;
        }
        // Report the first face (in file order) with an index out of range.
        for f in 0..out.faces.len() {
            let range = out.faces.range(f);
            let bad = match corners {
                None => out.faces.corner_vertices()[range]
                    .iter()
                    .find(|&&i| i as usize >= defined),
                Some(c) => c[range]
                    .iter()
                    .find(|&&i| i != NONE && i as usize >= defined),
            };
            if let Some(&i) = bad {
                return Err(err(
                    out.faces.line(f),
                    format!(
                        "{what} index {} is out of range: the file has {defined} {plural}",
                        u64::from(i) + 1
                    ),
                ));
            }
        }
    }
    let (vertices, uvs) = (out.positions.len() as u64, out.uvs.len() as u64);
    for &(line_no, vertex, uv) in &forward_elements {
        let (index, defined, what, plural) = if vertex as u64 > vertices {
            (vertex, vertices, "vertex", "vertices")
        } else if uv as u64 > uvs {
            (uv, uvs, "texture coordinate", "texture coordinates")
        } else {
            continue;
        };
        return Err(err(
            line_no,
            format!("{what} index {index} is out of range: the file has {defined} {plural}"),
        ));
    }
    if out.faces.len() == 0 {
        return Err(Error::parse(
            path,
            None,
            format!(
                "no triangles: the file has {} vertices and no faces (`f` lines)",
                out.positions.len()
            ),
        ));
    }
    if !out.uvs.is_empty() && corner_uv.iter().any(|&i| i != NONE) {
        out.corner_uv = corner_uv;
        out.note_extra("texture coordinates (`vt`)");
    }
    if !out.normals.is_empty() && corner_normal.iter().any(|&i| i != NONE) {
        out.corner_normal = corner_normal;
        out.flat_faces = flat_faces;
        out.note_extra("normals (`vn`)");
    }
    if !out.colors.is_empty() {
        // Vertices after the last coloured one are white.
        out.colors.resize(out.positions.len(), [1.0; 4]);
        out.note_extra("vertex colours");
    }
    if let Some((normal, line)) = first_not_finite {
        out.warnings.push(format!(
            "`{}`, line {line}: {} (`vn`) with a coordinate that is not a finite number (the first is normal {}, numbered from 1): copied as written into outputs in OBJ; a GLB's normals come from the shape",
            path.display(),
            if not_finite_normals == 1 { "1 normal".to_string() } else { format!("{not_finite_normals} normals") },
            normal + 1
        ));
    }
    Ok(out)
}

/// Writes `keyword x y ...` lines, one per item.
fn write_numbers<const D: usize>(
    w: &mut dyn Write,
    keyword: &[u8],
    items: &[[f64; D]],
) -> std::io::Result<()> {
    write_formatted(w, items, |buf, p| {
        buf.extend_from_slice(keyword);
        for x in xyz(p) {
            buf.push(b' ');
            push_f64(buf, x);
        }
        buf.push(b'\n');
    })
}

/// Writes `v` lines (`v x y z r g b` with `colors`, each 0 to 1), `vt` and
/// `vn` lines, then `f` lines of `faces` whose corners index them
/// (`v/vt/vn`, `v/vt`, `v//vn` or `v`, 1-based): `uvs` and `normals` are
/// each the values and the index of each flat corner ([`NONE`] for none;
/// empty for none at all).
pub(super) fn write_with_corners(
    w: &mut dyn Write,
    positions: &[[f64; 3]],
    colors: Option<&[[f32; 4]]>,
    faces: &Polygons,
    uvs: (&[[f64; 2]], &[u32]),
    normals: (&[[f64; 3]], &[u32]),
) -> std::io::Result<()> {
    match colors {
        None => write_numbers(w, b"v", positions)?,
        // `v x y z r g b`.
        Some(colors) => write_formatted(w, positions.iter().zip(colors), |buf, (p, c)| {
            buf.push(b'v');
            let rgb = [c[0], c[1], c[2]].map(f64::from);
            for x in p.iter().chain(&rgb) {
                buf.push(b' ');
                push_f64(buf, *x);
            }
            buf.push(b'\n');
        })?,
    }
    write_formatted(w, uvs.0, |buf, uv| {
        buf.extend_from_slice(b"vt");
        for x in uv {
            buf.push(b' ');
            push_f64(buf, *x);
        }
        buf.push(b'\n');
    })?;
    write_numbers(w, b"vn", normals.0)?;
    let corners = faces.corner_vertices();
    write_formatted(w, 0..faces.len(), |buf, f| {
        buf.push(b'f');
        for c in faces.range(f) {
            buf.push(b' ');
            push_uint(buf, u64::from(corners[c]) + 1);
            let uv = uvs.1.get(c).copied().unwrap_or(NONE);
            let normal = normals.1.get(c).copied().unwrap_or(NONE);
            if uv != NONE || normal != NONE {
                buf.push(b'/');
            }
            if uv != NONE {
                push_uint(buf, u64::from(uv) + 1);
            }
            if normal != NONE {
                buf.push(b'/');
                push_uint(buf, u64::from(normal) + 1);
            }
        }
        buf.push(b'\n');
    })
}

/// Writes `v x y z` lines then `f a b c ...` lines (1-based).
pub(super) fn write<'a, const D: usize>(
    w: &mut dyn Write,
    positions: &[[f64; D]],
    faces: impl Iterator<Item = &'a [u32]>,
) -> std::io::Result<()> {
    write_numbers(w, b"v", positions)?;
    write_formatted(w, faces, |buf, face| {
        buf.push(b'f');
        for &i in face {
            buf.push(b' ');
            push_uint(buf, u64::from(i) + 1);
        }
        buf.push(b'\n');
    })
}
