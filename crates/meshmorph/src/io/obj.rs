//! Wavefront OBJ: `v` and `f` statements.

use std::io::Write;
use std::path::Path;

use super::triangulate::{repeated_index, Polygons};
use super::{
    finish, parse_f64, parse_i64, push_f64, push_uint, show, strip_comment, tokens,
    write_formatted, xyz, Lines,
};
use crate::error::{Error, Result};
use crate::mesh::Mesh3;

/// Parses an OBJ file's contents (see the [module documentation](super)).
pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<Mesh3> {
    let err = |line: usize, msg: String| Error::parse(path, Some(line), msg);
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut faces = Polygons::default();
    let mut face: Vec<u32> = Vec::new();
    // Positive indices are checked once every vertex is known (forward
    // references are legal); the largest one tells whether any is out of
    // range.
    let mut max_index: i64 = 0;

    for (line_no, line) in Lines::new(bytes) {
        let mut toks = tokens(strip_comment(line));
        match toks.next() {
            Some(b"v") => {
                let mut p = [0.0; 3];
                let mut count = 0;
                for tok in toks {
                    let x = parse_f64(tok)
                        .ok_or_else(|| err(line_no, format!("`{}` is not a number", show(tok))))?;
                    if count < 3 {
                        if !x.is_finite() {
                            return Err(err(
                                line_no,
                                format!(
                                    "vertex {} (1-based) has a coordinate that is not a finite number: `{}`",
                                    positions.len() + 1,
                                    show(tok)
                                ),
                            ));
                        }
                        p[count] = x;
                    }
                    count += 1;
                }
                if count < 2 {
                    return Err(err(
                        line_no,
                        format!("a vertex needs at least 2 coordinates (`v x y [z] [w]`), found {count}"),
                    ));
                }
                positions.push(p);
            }
            Some(b"f") => {
                face.clear();
                for tok in toks {
                    let vertex_part = tok.split(|&b| b == b'/').next().unwrap_or(tok);
                    let index = parse_i64(vertex_part).ok_or_else(|| {
                        err(line_no, format!("`{}` is not a vertex index", show(tok)))
                    })?;
                    let resolved = match index {
                        0 => {
                            return Err(err(
                                line_no,
                                "vertex index 0 is invalid: OBJ indices start at 1 (or count back from -1)".into(),
                            ))
                        }
                        i if i > 0 => {
                            max_index = max_index.max(i);
                            i - 1
                        }
                        i => {
                            let r = positions.len() as i64 + i;
                            if r < 0 {
                                return Err(err(
                                    line_no,
                                    format!(
                                        "vertex index {i} is out of range: only {} vertices are defined before this line",
                                        positions.len()
                                    ),
                                ));
                            }
                            r
                        }
                    };
                    let resolved = u32::try_from(resolved).map_err(|_| {
                        err(
                            line_no,
                            format!("vertex index {index} is out of range (too large)"),
                        )
                    })?;
                    face.push(resolved);
                }
                if face.len() < 3 {
                    return Err(err(
                        line_no,
                        format!("a face needs at least 3 vertices, found {}", face.len()),
                    ));
                }
                if let Some(i) = repeated_index(&face) {
                    return Err(err(
                        line_no,
                        format!(
                            "the face uses vertex {} (1-based) more than once",
                            i as u64 + 1
                        ),
                    ));
                }
                faces.push(&face, line_no);
            }
            // vt, vn, vp, g, o, s, usemtl, mtllib, l, p, unknown statements.
            _ => {}
        }
    }

    if max_index as u64 > positions.len() as u64 {
        // Report the first face (in file order) with an index out of range.
        let n = positions.len();
        for (face, line) in faces.iter() {
            if let Some(&i) = face.iter().find(|&&i| i as usize >= n) {
                return Err(err(
                    line,
                    format!(
                        "vertex index {} is out of range: the file has {n} vertices",
                        u64::from(i) + 1
                    ),
                ));
            }
        }
    }
    if faces.iter().next().is_none() {
        return Err(Error::parse(
            path,
            None,
            format!(
                "no triangles: the file has {} vertices and no faces (`f` lines)",
                positions.len()
            ),
        ));
    }
    let triangles = faces.triangulate(&positions);
    finish(path, positions, triangles)
}

/// Writes `v x y z` lines then `f a b c` lines (1-based).
pub(super) fn write<const D: usize>(
    w: &mut dyn Write,
    positions: &[[f64; D]],
    triangles: &[[u32; 3]],
) -> std::io::Result<()> {
    write_formatted(w, positions, |buf, p| {
        buf.push(b'v');
        for x in xyz(p) {
            buf.push(b' ');
            push_f64(buf, x);
        }
        buf.push(b'\n');
    })?;
    write_formatted(w, triangles, |buf, t| {
        buf.push(b'f');
        for &i in t {
            buf.push(b' ');
            push_uint(buf, u64::from(i) + 1);
        }
        buf.push(b'\n');
    })
}
