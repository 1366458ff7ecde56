//! Marker vertex pairs that tie a source mesh to a target mesh.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Pairs `(source vertex, target vertex)`, 0-based, with where they came from
/// so that errors can name the file and line.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Markers {
    pairs: Vec<[u32; 2]>,
    /// 1-based line of each pair, when read from a file.
    lines: Vec<usize>,
    path: Option<PathBuf>,
}

impl Markers {
    /// Markers from 0-based pairs in memory.
    pub fn new(pairs: Vec<[u32; 2]>) -> Self {
        Self {
            pairs,
            lines: Vec::new(),
            path: None,
        }
    }

    /// The pairs, 0-based.
    pub fn pairs(&self) -> &[[u32; 2]] {
        &self.pairs
    }

    /// Reads a marker file: one pair `source target` per line, separated by
    /// white space or a comma; `#` starts a comment; a first line holding
    /// only the number of pairs (as in `.cons` files) is accepted and
    /// checked. Indices are 0-based unless `one_based`.
    ///
    /// # Errors
    /// [`Error::Io`] if the file cannot be read, [`Error::Parse`] naming the
    /// line of the first entry that does not parse.
    pub fn read(path: &Path, one_based: bool) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        Self::parse(&text, path, one_based)
    }

    /// [`Markers::read`] on text already in memory; `path` names it in errors.
    ///
    /// # Errors
    /// [`Error::Parse`] naming the line of the first entry that does not parse.
    pub fn parse(text: &str, path: &Path, one_based: bool) -> Result<Self> {
        // A byte-order mark, as some editors write, is not part of the text.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut pairs = Vec::new();
        let mut lines = Vec::new();
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
                _ => {
                    return Err(bad(format!(
                        "expected `source target` (two vertex indices), found `{content}`"
                    )))
                }
            }
            first = false;
        }
        if let Some((n, line)) = count {
            if n != pairs.len() {
                return Err(Error::parse(
                    path,
                    Some(line),
                    format!("the count line says {n} pairs but {} follow", pairs.len()),
                ));
            }
        }
        Ok(Self {
            pairs,
            lines,
            path: Some(path.to_path_buf()),
        })
    }

    /// Checks every pair against meshes of `source_vertices` and
    /// `target_vertices` vertices: indices in range, no pair repeated, no
    /// source vertex paired with two targets.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] naming the marker (and file and line, when
    /// read from a file).
    pub fn validate(&self, source_vertices: usize, target_vertices: usize) -> Result<()> {
        let mut seen: HashMap<u32, usize> = HashMap::with_capacity(self.pairs.len());
        for (k, &[s, t]) in self.pairs.iter().enumerate() {
            let fail =
                |msg: String| Err(Error::InvalidArgument(format!("{}: {msg}", self.name(k))));
            if s as usize >= source_vertices {
                return fail(format!(
                    "source vertex {s} is out of range (the source has {source_vertices} vertices)"
                ));
            }
            if t as usize >= target_vertices {
                return fail(format!(
                    "target vertex {t} is out of range (the target has {target_vertices} vertices)"
                ));
            }
            if let Some(&j) = seen.get(&s) {
                let other = self.pairs[j][1];
                return if other == t {
                    fail(format!("the pair {s} {t} repeats {}", self.name(j)))
                } else {
                    fail(format!(
                        "source vertex {s} is paired with target vertex {t} here and with {other} in {}",
                        self.name(j)
                    ))
                };
            }
            seen.insert(s, k);
        }
        Ok(())
    }

    /// "marker 3" or "`file.cons`, line 5".
    fn name(&self, k: usize) -> String {
        match (&self.path, self.lines.get(k)) {
            (Some(p), Some(l)) => format!("`{}`, line {l}", p.display()),
            _ => format!("marker {k}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_usual_layouts() {
        let p = Path::new("m.cons");
        let m = Markers::parse("3\n0, 5\n1 6 # tail\n\n# c\n2\t7\r\n", p, false).unwrap();
        assert_eq!(m.pairs(), &[[0, 5], [1, 6], [2, 7]]);
        let m = Markers::parse("1 1\n2 3\n", p, true).unwrap();
        assert_eq!(m.pairs(), &[[0, 0], [1, 2]]);
        assert_eq!(Markers::parse("", p, false).unwrap().pairs().len(), 0);
    }

    #[test]
    fn reports_lines() {
        let p = Path::new("m.txt");
        let e = Markers::parse("0 1\n2 x\n", p, false)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("m.txt") && e.contains("line 2") && e.contains("`x`"),
            "{e}"
        );
        let e = Markers::parse("0 1 2\n", p, false).unwrap_err().to_string();
        assert!(e.contains("line 1"), "{e}");
        let e = Markers::parse("4\n0 1\n", p, false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("says 4 pairs but 1"), "{e}");
        let e = Markers::parse("0 1\n", p, true).unwrap_err().to_string();
        assert!(e.contains("1-based"), "{e}");
        let e = Markers::parse("0 -1\n", p, false).unwrap_err().to_string();
        assert!(e.contains("out of range"), "{e}");
    }

    #[test]
    fn validation() {
        let p = Path::new("m.txt");
        let m = Markers::parse("0 1\n5 2\n", p, false).unwrap();
        assert!(m.validate(6, 3).is_ok());
        let e = m.validate(5, 3).unwrap_err().to_string();
        assert!(e.contains("line 2") && e.contains("source vertex 5"), "{e}");
        let e = m.validate(6, 2).unwrap_err().to_string();
        assert!(e.contains("target vertex 2"), "{e}");
        let e = Markers::new(vec![[0, 1], [0, 1]])
            .validate(6, 6)
            .unwrap_err()
            .to_string();
        assert!(e.contains("repeats marker 0"), "{e}");
        let e = Markers::new(vec![[0, 1], [0, 2]])
            .validate(6, 6)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("paired with target vertex 2 here and with 1"),
            "{e}"
        );
    }
}
