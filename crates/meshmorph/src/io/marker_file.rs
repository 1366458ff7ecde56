//! The marker file format: one pair `source target` (vertex indices) or
//! `sx sy sz tx ty tz` (a point on each mesh) per line.

use std::path::Path;

use crate::error::{Error, Result};
use crate::transfer::markers::{Markers, VertexNumbering};

impl Markers {
    /// Reads a marker file: one pair `source target` per line, separated by
    /// white space or a comma; `#` starts a comment; a first line holding
    /// only the number of pairs (as in `.cons` files) is accepted and
    /// checked. Indices count from 0 or from 1 as `numbering` says.
    ///
    /// # Errors
    /// [`Error::Io`] if the file cannot be read, [`Error::FileRefused`] when
    /// it is not a regular file or is larger than a third of the memory
    /// available, [`Error::Parse`] naming the line of the first entry that
    /// does not parse (or of a byte that is not UTF-8).
    pub fn read(path: &Path, numbering: VertexNumbering) -> Result<Self> {
        let bytes = crate::io::read::read_file(path, &crate::io::read::Limit::memory())?;
        let text = crate::io::read::utf8(bytes, path)?;
        Self::parse(&text, path, numbering)
    }

    /// [`Markers::read`] on text already in memory; `path` names it in errors.
    ///
    /// # Errors
    /// [`Error::Parse`] naming the line of the first entry that does not parse.
    pub fn parse(text: &str, path: &Path, numbering: VertexNumbering) -> Result<Self> {
        let one_based = numbering == VertexNumbering::FromOne;
        // A byte-order mark, as some editors write, is not part of the text.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut pairs = Vec::new();
        let mut lines = Vec::new();
        let mut points = Vec::new();
        let mut count: Option<(usize, usize)> = None;
        let mut first = true;
        for (k, raw) in text.lines().enumerate() {
            let line = k + 1;
            let content = raw.split('#').next().unwrap_or("").trim();
            if content.is_empty() {
                continue;
            }
            let fields: Vec<&str> = content
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|f| !f.is_empty())
                .collect();
            let bad = |msg: String| Error::parse(path, Some(line), msg);
            let index = |f: &str| -> Result<u32> {
                let v: i64 = f
                    .parse()
                    .map_err(|_| bad(format!("`{f}` is not a vertex index")))?;
                let v = if one_based {
                    if v < 1 {
                        return Err(bad(format!(
                            "vertex index {v} is not 1-based (1 is the first vertex)"
                        )));
                    }
                    v - 1
                } else {
                    v
                };
                u32::try_from(v).map_err(|_| bad(format!("vertex index {f} is out of range")))
            };
            match fields.len() {
                1 if first => {
                    let n = fields[0].parse::<usize>().map_err(|_| {
                        bad(format!(
                            "`{}` is neither a pair count nor a pair",
                            fields[0]
                        ))
                    })?;
                    count = Some((n, line));
                }
                2 => {
                    pairs.push([index(fields[0])?, index(fields[1])?]);
                    lines.push(line);
                }
                6 => {
                    let mut c = [0.0; 6];
                    for (x, f) in c.iter_mut().zip(&fields) {
                        *x = f
                            .parse::<f64>()
                            .ok()
                            .filter(|x| x.is_finite())
                            .ok_or_else(|| bad(format!("`{f}` is not a coordinate")))?;
                    }
                    points.push(([[c[0], c[1], c[2]], [c[3], c[4], c[5]]], line));
                }
                _ => {
                    return Err(bad(format!(
                        "expected `source target` (two vertex indices) or `sx sy sz tx ty tz` (a point on each mesh), found `{content}`"
                    )))
                }
            }
            first = false;
        }
        if let Some((n, line)) = count {
            if n != pairs.len() + points.len() {
                return Err(Error::parse(
                    path,
                    Some(line),
                    format!(
                        "the count line says {n} pairs but {} follow",
                        pairs.len() + points.len()
                    ),
                ));
            }
        }
        Ok(Self {
            pairs,
            lines,
            points,
            path: Some(path.to_path_buf()),
            first_index: u32::from(one_based),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_usual_layouts() {
        let p = Path::new("m.cons");
        let m = Markers::parse(
            "3\n0, 5\n1 6 # tail\n\n# c\n2\t7\r\n",
            p,
            VertexNumbering::FromZero,
        )
        .unwrap();
        assert_eq!(m.pairs(), &[[0, 5], [1, 6], [2, 7]]);
        let m = Markers::parse("1 1\n2 3\n", p, VertexNumbering::FromOne).unwrap();
        assert_eq!(m.pairs(), &[[0, 0], [1, 2]]);
        assert_eq!(
            Markers::parse("", p, VertexNumbering::FromZero)
                .unwrap()
                .pairs()
                .len(),
            0
        );
    }

    #[test]
    fn reports_lines() {
        let p = Path::new("m.txt");
        let e = Markers::parse("0 1\n2 x\n", p, VertexNumbering::FromZero)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("m.txt") && e.contains("line 2") && e.contains("`x`"),
            "{e}"
        );
        let e = Markers::parse("0 1 2\n", p, VertexNumbering::FromZero)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 1"), "{e}");
        let e = Markers::parse("4\n0 1\n", p, VertexNumbering::FromZero)
            .unwrap_err()
            .to_string();
        assert!(e.contains("says 4 pairs but 1"), "{e}");
        let e = Markers::parse("0 1\n", p, VertexNumbering::FromOne)
            .unwrap_err()
            .to_string();
        assert!(e.contains("1-based"), "{e}");
        let e = Markers::parse("0 -1\n", p, VertexNumbering::FromZero)
            .unwrap_err()
            .to_string();
        assert!(e.contains("out of range"), "{e}");
    }

    #[test]
    fn messages_number_vertices_as_the_file_does() {
        let p = Path::new("m.txt");
        for (one_based, text, shown) in [(false, "0 4\n1 9\n", "9"), (true, "1 5\n2 10\n", "10")] {
            let numbering = if one_based {
                VertexNumbering::FromOne
            } else {
                VertexNumbering::FromZero
            };
            let m = Markers::parse(text, p, numbering).unwrap();
            let e = m.check_ranges(5, 6).unwrap_err().to_string();
            assert!(
                e.contains(&format!("target vertex {shown} is out of range")),
                "{e}"
            );
            assert!(m.describe(0).contains(if one_based {
                "target vertex 5"
            } else {
                "target vertex 4"
            }));
        }
        let m = Markers::parse("1 5\n1 6\n", p, VertexNumbering::FromOne).unwrap();
        let e = m.validate(10, 10).unwrap_err().to_string();
        assert!(
            e.contains("source vertex 1 is paired with target vertex 6 here and with 5"),
            "{e}"
        );
    }
}
