//! Anchors: points matched across drawings (an eye to an eye), from a
//! text file or marked in the drawings themselves.

use std::path::Path;

use super::{parse_error, NamedPoint};
use crate::error::{Error, Result};

/// One anchor: a point on each drawing, in the drawings' order.
#[derive(Clone, Debug, PartialEq)]
pub struct AnchorRow {
    /// Its name (may be empty).
    pub name: String,
    /// One point a drawing, each in its drawing's coordinates.
    pub points: Vec<[f64; 2]>,
    /// Where it was given: `file, line N`, or the drawings that marked it.
    pub origin: String,
}

impl AnchorRow {
    /// Its name and origin, for messages: `` `elbow`, `a.txt`, line 3 ``.
    pub fn label(&self) -> String {
        if self.name.is_empty() {
            self.origin.clone()
        } else {
            format!("`{}`, {}", self.name, self.origin)
        }
    }
}

/// Reads an anchor file for `drawings` drawings: one anchor a line, an
/// optional name (a first word that is not a number) then `x y` for each
/// drawing in order, all on the line (spaces, tabs or commas between);
/// `#` starts a comment; blank lines are skipped.
///
/// ```text
/// # name   on a.svg    on b.svg
/// eye      120 80      300 95
/// tail     10 200      40 260
/// ```
///
/// # Errors
/// [`Error::Parse`] naming the file and the 1-based line of a line with
/// another count of numbers than `2 × drawings`, a value that is not a
/// finite number, or a name given twice.
pub fn read_anchor_file(path: &Path, drawings: usize) -> Result<Vec<AnchorRow>> {
    let text = super::super::read_text(path, 64 << 20, "an anchor file")?;
    parse_anchor_text(&text, path, drawings)
}

/// [`read_anchor_file`] on text already read from `path`.
pub fn parse_anchor_text(text: &str, path: &Path, drawings: usize) -> Result<Vec<AnchorRow>> {
    let mut rows: Vec<AnchorRow> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let mut words: Vec<&str> = content
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|w| !w.is_empty())
            .collect();
        let name = if words[0].parse::<f64>().is_err() {
            words.remove(0).to_string()
        } else {
            String::new()
        };
        if words.len() != 2 * drawings {
            return Err(parse_error(
                path,
                Some(line),
                format!(
                    "expected {} numbers (x y on each of the {drawings} drawings, in order){}, found {}",
                    2 * drawings,
                    if name.is_empty() { ", after an optional name" } else { " after the name" },
                    words.len()
                ),
            ));
        }
        let mut numbers = Vec::with_capacity(words.len());
        for w in &words {
            match w.parse::<f64>() {
                Ok(x) if x.is_finite() => numbers.push(x),
                _ => {
                    return Err(parse_error(
                        path,
                        Some(line),
                        format!("`{w}` is not a finite number"),
                    ))
                }
            }
        }
        if !name.is_empty() {
            if let Some(r) = rows.iter().find(|r| r.name == name) {
                return Err(parse_error(
                    path,
                    Some(line),
                    format!("the anchor `{name}` is given twice (first at {}): give each anchor its own name", r.origin),
                ));
            }
        }
        rows.push(AnchorRow {
            name,
            points: numbers.chunks(2).map(|c| [c[0], c[1]]).collect(),
            origin: format!("`{}`, line {line}", path.display()),
        });
    }
    Ok(rows)
}

/// Anchors marked in the drawings themselves (`marked[d]`, drawing `d`
/// called `names[d]` in messages) matched across them: named ones by
/// name, unnamed ones in order.
///
/// # Errors
/// [`Error::IncompatibleDrawings`] when a name is marked twice in one
/// drawing, or marked in some drawings and not in others, or the drawings
/// mark different numbers of unnamed anchors.
pub fn match_anchors(marked: &[Vec<NamedPoint>], names: &[String]) -> Result<Vec<AnchorRow>> {
    let mut rows: Vec<AnchorRow> = Vec::new();
    let Some(first) = marked.first() else {
        return Ok(rows);
    };
    for (d, points) in marked.iter().enumerate() {
        for (i, p) in points.iter().enumerate() {
            if !p.name.is_empty() && points[..i].iter().any(|q| q.name == p.name) {
                return Err(Error::IncompatibleDrawings(format!(
                    "{} marks the anchor `{}` twice: give each anchor its own name",
                    names[d], p.name
                )));
            }
        }
    }
    let mut all_names: Vec<&str> = Vec::new();
    for points in marked {
        for p in points {
            if !p.name.is_empty() && !all_names.contains(&p.name.as_str()) {
                all_names.push(&p.name);
            }
        }
    }
    for name in all_names {
        let mut points = Vec::with_capacity(marked.len());
        for (d, drawing) in marked.iter().enumerate() {
            match drawing.iter().find(|p| p.name == name) {
                Some(p) => points.push(p.point),
                None => {
                    let has: Vec<&str> = names
                        .iter()
                        .zip(marked)
                        .filter(|(_, m)| m.iter().any(|p| p.name == name))
                        .map(|(n, _)| n.as_str())
                        .collect();
                    return Err(Error::IncompatibleDrawings(format!(
                        "the anchor `{name}` is marked in {} but not in {}: mark it in every drawing (an element with id `anchor-{name}`), or remove it",
                        has.join(" and "),
                        names[d]
                    )));
                }
            }
        }
        rows.push(AnchorRow {
            name: name.to_string(),
            points,
            origin: "marked in the drawings".into(),
        });
    }
    let unnamed: Vec<Vec<[f64; 2]>> = marked
        .iter()
        .map(|m| {
            m.iter()
                .filter(|p| p.name.is_empty())
                .map(|p| p.point)
                .collect()
        })
        .collect();
    if let Some(d) = (1..marked.len()).find(|&d| unnamed[d].len() != unnamed[0].len()) {
        return Err(Error::IncompatibleDrawings(format!(
            "{} marks {} unnamed anchor{} and {} marks {}: unnamed anchors pair in order, so mark as many in each (or name them, `anchor-NAME`)",
            names[0],
            unnamed[0].len(),
            if unnamed[0].len() == 1 { "" } else { "s" },
            names[d],
            unnamed[d].len()
        )));
    }
    for k in 0..first.iter().filter(|p| p.name.is_empty()).count() {
        rows.push(AnchorRow {
            name: String::new(),
            points: unnamed.iter().map(|u| u[k]).collect(),
            origin: format!("unnamed anchor {} marked in the drawings", k + 1),
        });
    }
    Ok(rows)
}
