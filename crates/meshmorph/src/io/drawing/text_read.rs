//! Polygons as text: a drawing's loops as lines of `x y`.

use std::path::Path;

use super::{drawing_error, parse_error, DrawingFile, DrawingKind, NamedPoint, Style};
use crate::error::Result;
use crate::outline::Drawing;

/// Reads a drawing from text: each loop is lines of `x y` (two numbers,
/// separated by spaces, tabs or a comma), loops separated by one or more
/// blank lines, the outer loop first, then the holes; `#` starts a comment
/// (to the end of the line; a line holding only a comment is not blank).
/// A line `anchor NAME x y` marks an anchor (not a point of a loop).
/// Loops may run either way and need not repeat their first point. The
/// numbers are taken with y pointing up.
///
/// ```text
/// # a square with a square hole
/// 0 0
/// 10 0
/// 10 10
/// 0 10
///
/// 4 4
/// 4 6
/// 6 6
/// 6 4
/// anchor corner 10 10
/// ```
///
/// # Errors
/// [`Error::Parse`](crate::Error::Parse) naming `path` and the 1-based line
/// of a line that is not two numbers, a number that is not finite, no
/// loop at all; the drawing's own checks ([`Drawing::new`]) naming the
/// loop and the line it starts on.
pub fn parse_text_drawing(text: &str, path: &Path) -> Result<DrawingFile> {
    let mut loops: Vec<Vec<[f64; 2]>> = Vec::new();
    let mut starts: Vec<usize> = Vec::new();
    let mut anchors = Vec::new();
    let mut open = false;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        if raw.trim().is_empty() {
            open = false;
            continue;
        }
        if content.is_empty() {
            continue;
        }
        let words: Vec<&str> = content
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|w| !w.is_empty())
            .collect();
        let number = |w: &str| -> Result<f64> {
            match w.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                Ok(_) => Err(parse_error(
                    path,
                    Some(line),
                    format!("`{w}` is not a finite number"),
                )),
                Err(_) => Err(parse_error(
                    path,
                    Some(line),
                    format!("`{w}` is not a number: expected a point `x y`, a blank line between loops, or `anchor NAME x y`"),
                )),
            }
        };
        if words[0] == "anchor" {
            let (name, xy) = match words.len() {
                3 => ("", &words[1..]),
                4 => (words[1], &words[2..]),
                _ => {
                    return Err(parse_error(
                        path,
                        Some(line),
                        format!(
                            "an anchor line is `anchor NAME x y`; found {} words",
                            words.len()
                        ),
                    ))
                }
            };
            anchors.push(NamedPoint {
                name: name.to_string(),
                point: [number(xy[0])?, number(xy[1])?],
            });
            continue;
        }
        if words.len() != 2 {
            return Err(parse_error(
                path,
                Some(line),
                format!(
                    "expected a point `x y` (two numbers), found {} value{}: `{content}`",
                    words.len(),
                    if words.len() == 1 { "" } else { "s" }
                ),
            ));
        }
        let p = [number(words[0])?, number(words[1])?];
        if !open {
            loops.push(Vec::new());
            starts.push(line);
            open = true;
        }
        loops.last_mut().expect("a loop was opened").push(p);
    }
    if loops.is_empty() {
        return Err(parse_error(
            path,
            None,
            "no points: give the outer loop as lines `x y`, then each hole after a blank line"
                .into(),
        ));
    }
    let drawing = Drawing::new(loops).map_err(|e| {
        let at = match &e {
            crate::Error::InvalidDrawing { loop_index, .. } => starts
                .get(*loop_index)
                .map(|l| format!("that loop starts on line {l}"))
                .unwrap_or_default(),
            _ => String::new(),
        };
        drawing_error(
            e,
            path,
            &format!("loops are separated by blank lines, points numbered from 0 in each; {at}"),
        )
    })?;
    Ok(DrawingFile {
        drawing,
        style: Style::default(),
        canvas: None,
        anchors,
        tolerance: 0.0,
        curves: 0,
        kind: DrawingKind::Text,
    })
}
