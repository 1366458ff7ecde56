//! Object File Format (OFF), text variant.

use std::io::Write;
use std::path::Path;

use super::mesh_file::{offset_in, Keep, Parsed, Patch, Slot};
use super::triangulate::{check_corners, Polygons};
use super::vertex_attributes::{channel_byte, VertexAttributes};
use super::{
    bad_count, parse_f64, parse_i64, push_f64, push_uint, show, tokens, write_formatted, xyz,
    UncommentedLines,
};
use crate::error::{Error, Result};

/// Parses an OFF file's contents (see the [module documentation](super)),
/// keeping what [`MeshFile`](super::MeshFile) needs to write it back.
pub(super) fn parse(bytes: &[u8], path: &Path, keep: Keep) -> Result<Parsed> {
    let err = |line: usize, msg: String| Error::parse(path, Some(line), msg);
    let mut out = Parsed::new(keep);
    // Non-blank lines without comments.
    let mut lines = UncommentedLines::new(bytes).filter(|(_, l)| tokens(l).next().is_some());

    let Some((first_no, first)) = lines.next() else {
        return Err(Error::parse(path, None, "no triangles: the file is empty"));
    };
    let mut first_tokens = tokens(first);
    let keyword = first_tokens.next().unwrap_or_default();
    let mut counts: Vec<&[u8]> = Vec::new();
    let mut counts_line = first_no;
    // `NOFF`: a normal follows each vertex's x y z; `ST`: texture
    // coordinates end each vertex line.
    let mut has_normals = false;
    let mut has_uvs = false;
    let mut colour_scale = ColourScale::default();
    if let Some(at) = keyword.windows(3).position(|w| w == b"OFF") {
        let (prefix, suffix) = (&keyword[..at], &keyword[at + 3..]);
        has_normals = prefix.contains(&b'N');
        has_uvs = prefix.starts_with(b"ST");
        if !prefix.iter().all(|b| b"CNST".contains(b)) {
            return Err(err(
                first_no,
                format!(
                    "`{}` files are not supported (only 3D OFF is)",
                    show(keyword)
                ),
            ));
        }
        if !suffix.is_empty() {
            if !suffix.iter().all(u8::is_ascii_digit) {
                return Err(err(
                    first_no,
                    format!("unexpected header keyword `{}`", show(keyword)),
                ));
            }
            counts.push(suffix); // "OFF8 6 0"
        }
        counts.extend(first_tokens);
        if counts.first() == Some(&&b"BINARY"[..]) {
            return Err(err(first_no, "binary OFF files are not supported".into()));
        }
        if counts.is_empty() {
            let Some((n, l)) = lines.next() else {
                return Err(err(
                    first_no,
                    "the file ends after the `OFF` keyword: no counts `nV nF nE`".into(),
                ));
            };
            counts_line = n;
            counts.extend(tokens(l));
        }
    } else if parse_i64(keyword).is_some() {
        // No keyword: the first line holds the counts.
        counts.push(keyword);
        counts.extend(first_tokens);
    } else {
        return Err(err(
            first_no,
            format!("expected the `OFF` keyword, found `{}`", show(keyword)),
        ));
    }

    let count = |tok: &[u8], what: &str| {
        parse_i64(tok)
            .and_then(|n| usize::try_from(n).ok())
            .ok_or_else(|| {
                err(
                    counts_line,
                    format!("the {what} count `{}` {}", show(tok), bad_count(tok)),
                )
            })
    };
    if !(2..=3).contains(&counts.len()) {
        return Err(err(
            counts_line,
            format!(
                "expected the counts `nV nF nE`, found {} values",
                counts.len()
            ),
        ));
    }
    let num_vertices = count(counts[0], "vertex")?;
    let num_faces = count(counts[1], "face")?;
    if let Some(e) = counts.get(2) {
        count(e, "edge")?;
    }

    // Never trust the counts for more memory than the file could fill.
    out.positions.reserve(num_vertices.min(bytes.len() / 6));
    if out.keeps_whole() {
        out.patches.reserve(3 * num_vertices.min(bytes.len() / 6));
    }
    for v in 0..num_vertices {
        let Some((line_no, line)) = lines.next() else {
            return Err(Error::parse(
                path,
                None,
                format!("the file ends after {v} of the {num_vertices} vertices announced on line {counts_line}"),
            ));
        };
        let mut p = [0.0; 3];
        let mut toks = tokens(line);
        for (k, slot) in p.iter_mut().enumerate() {
            let Some(tok) = toks.next() else {
                return Err(err(
                    line_no,
                    format!("vertex {v} has {k} coordinates, expected 3 (x y z)"),
                ));
            };
            let x = parse_f64(tok)
                .ok_or_else(|| err(line_no, format!("`{}` is not a number", show(tok))))?;
            if !x.is_finite() {
                return Err(err(
                    line_no,
                    format!(
                        "vertex {v} has a coordinate that is not a finite number: `{}`",
                        show(tok)
                    ),
                ));
            }
            *slot = x;
            let start = offset_in(bytes, tok);
            out.patch(Patch::text(
                start..start + tok.len(),
                Slot::Position(v as u32, k as u8),
            ));
        }
        let rest: Vec<&[u8]> = toks.collect();
        if has_normals {
            let mut n = [0.0; 3];
            for k in 0..3 {
                let x = rest
                    .get(k)
                    .and_then(|t| parse_f64(t))
                    .filter(|x| x.is_finite());
                let Some(x) = x else {
                    return Err(err(
                        line_no,
                        format!(
                            "vertex {v} has no normal (`nx ny nz` after x y z, as `NOFF` says)"
                        ),
                    ));
                };
                n[k] = x;
                let start = offset_in(bytes, rest[k]);
                out.patch(Patch::text(
                    start..start + rest[k].len(),
                    Slot::Normal(v as u32, k as u8),
                ));
            }
            out.normals.push(n);
        }
        if has_uvs && rest.len() >= 2 {
            let uv = [rest.len() - 2, rest.len() - 1].map(|k| parse_f64(rest[k]));
            if let [Some(u), Some(w)] = uv {
                out.uvs.push([u, w]);
            }
        }
        let used = if has_normals { 3 } else { 0 } + if has_uvs { 2 } else { 0 };
        if rest.len() > used {
            out.note_extra("vertex colours");
            // `r g b [a]` after the normal, scaled once every vertex is read.
            let start = if has_normals { 3 } else { 0 };
            let values = &rest[start..rest.len() - if has_uvs { 2 } else { 0 }];
            if out.keeps_whole() && (3..=4).contains(&values.len()) {
                let mut color = [f32::NAN; 4];
                for (c, t) in color.iter_mut().zip(values) {
                    let x = parse_f64(t).filter(|x| x.is_finite() && *x >= 0.0);
                    *c = x.map_or(0.0, |x| x as f32);
                    colour_scale.see(t, *c);
                }
                out.colors.resize(v, [f32::NAN; 4]);
                out.colors.push(color);
            }
        }
        out.positions.push(p);
    }

    let mut faces = Polygons::with_capacity(num_faces.min(bytes.len() / 8));
    let mut face: Vec<u32> = Vec::new();
    for f in 0..num_faces {
        let Some((line_no, line)) = lines.next() else {
            return Err(Error::parse(
                path,
                None,
                format!("the file ends after {f} of the {num_faces} faces announced on line {counts_line}"),
            ));
        };
        let mut toks = tokens(line);
        let size_tok = toks.next().unwrap_or_default();
        let size = parse_i64(size_tok).ok_or_else(|| {
            err(
                line_no,
                format!("`{}` is not a vertex count", show(size_tok)),
            )
        })?;
        if size < 3 {
            return Err(err(
                line_no,
                format!("face {f} has {size} vertices, a face needs at least 3"),
            ));
        }
        face.clear();
        for k in 0..size {
            let Some(tok) = toks.next() else {
                return Err(err(
                    line_no,
                    format!("face {f} announces {size} vertices but lists {k}"),
                ));
            };
            let index = parse_i64(tok)
                .ok_or_else(|| err(line_no, format!("`{}` is not a vertex index", show(tok))))?;
            match u32::try_from(index) {
                Ok(i) if (i as usize) < num_vertices => face.push(i),
                _ => {
                    return Err(err(
                        line_no,
                        format!(
                            "face {f}: vertex index {index} is out of range: the file has {num_vertices} vertices (indices start at 0)"
                        ),
                    ))
                }
            }
        }
        if toks.next().is_some() {
            out.note_extra("face colours");
        }
        let collapsed = check_corners(&face, |i| format!("vertex {i}"))
            .map_err(|m| err(line_no, format!("face {f}: {m}")))?;
        if collapsed {
            out.repeats_in_a_row.push(faces.len() as u32);
        }
        faces.push(&face, line_no);
    }

    if faces.len() == 0 {
        return Err(Error::parse(
            path,
            None,
            format!("no triangles: the file has {num_vertices} vertices and no faces"),
        ));
    }
    if let Some((line_no, _)) = lines.next() {
        let more = 1 + lines.count();
        out.warnings.push(format!(
            "`{}`, line {line_no}: {more} more line{} after the {num_vertices} vertices and {num_faces} faces that line {counts_line} announces: ignored (the counts may be wrong)",
            path.display(),
            if more == 1 { "" } else { "s" }
        ));
    }
    let corners = faces.corner_vertices().to_vec();
    if has_normals {
        out.corner_normal = corners.clone();
        out.note_extra("normals (`NOFF`)");
    }
    if has_uvs && out.uvs.len() == num_vertices {
        out.corner_uv = corners;
        out.note_extra("texture coordinates (`STOFF`)");
    }
    out.faces = faces;
    if !out.colors.is_empty() {
        // Vertices without a colour are white (NaN: not given).
        out.colors.resize(out.positions.len(), [f32::NAN; 4]);
        let scale = colour_scale.scale();
        for c in out.colors.iter_mut().flatten() {
            *c = if c.is_nan() {
                1.0
            } else {
                (*c / scale).clamp(0.0, 1.0)
            };
        }
    }
    Ok(out)
}

/// Writes `OFF`, the counts, `x y z` lines and `n i0 ... i(n-1)` face
/// lines (0-based).
/// How a file's colours are written: integers from 0 to 255, or numbers
/// from 0 to 1. Told once per file, from every colour in it (a file of
/// numbers writes full red as `1 0 0`): numbers when any has a fraction or
/// an exponent, or when none is above 1.
#[derive(Default)]
struct ColourScale {
    fraction: bool,
    largest: f32,
}

impl ColourScale {
    fn see(&mut self, token: &[u8], value: f32) {
        self.fraction |= token.iter().any(|b| matches!(b, b'.' | b'e' | b'E'));
        self.largest = self.largest.max(value);
    }

    /// What full intensity is written as.
    fn scale(&self) -> f32 {
        if self.fraction || self.largest <= 1.0 {
            1.0
        } else {
            255.0
        }
    }
}

pub(super) fn write<'a, const D: usize>(
    w: &mut dyn Write,
    positions: &[[f64; D]],
    faces: impl Iterator<Item = &'a [u32]>,
    num_faces: usize,
    extra: &VertexAttributes,
) -> std::io::Result<()> {
    // `[ST][C][N]OFF`: each vertex is x y z [nx ny nz] [r g b a] [s t].
    let keyword = format!(
        "{}{}{}OFF",
        if extra.uvs.is_some() { "ST" } else { "" },
        if extra.colors.is_some() { "C" } else { "" },
        if extra.normals.is_some() { "N" } else { "" },
    );
    writeln!(w, "{keyword}\n{} {num_faces} 0", positions.len())?;
    write_formatted(w, positions.iter().enumerate(), |buf, (v, p)| {
        let [x, y, z] = xyz(p);
        push_f64(buf, x);
        let numbers = |buf: &mut Vec<u8>, values: &[f64]| {
            for &x in values {
                buf.push(b' ');
                push_f64(buf, x);
            }
        };
        numbers(buf, &[y, z]);
        if let Some(n) = &extra.normals {
            numbers(buf, &n[v]);
        }
        if let Some(c) = extra.colors {
            for x in c[v] {
                buf.push(b' ');
                push_uint(buf, u64::from(channel_byte(x)));
            }
        }
        if let Some(uv) = extra.uvs {
            numbers(buf, &uv[v]);
        }
        buf.push(b'\n');
    })?;
    write_formatted(w, faces, |buf, face| {
        push_uint(buf, face.len() as u64);
        for &i in face {
            buf.push(b' ');
            push_uint(buf, u64::from(i));
        }
        buf.push(b'\n');
    })
}
