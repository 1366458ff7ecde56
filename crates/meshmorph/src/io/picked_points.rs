//! MeshLab's picked points (`.pp`, written by its PickPoints tool): XML,
//!
//! ```xml
//! <!DOCTYPE PickedPoints>
//! <PickedPoints>
//!  <DocumentData>...</DocumentData>
//!  <point x="0.1" y="0.2" z="0.3" active="1" name="nose"/>
//! </PickedPoints>
//! ```
//!
//! Each `point` is a position on one mesh (snapped to its surface like any
//! marker position), named by its `name`. A point with `active="0"` (left
//! unticked in MeshLab's list) is left out, with its partner in the other
//! file: MeshLab's own alignment leaves such points out too, and the file
//! keeps them so that they can be ticked again. Its name still counts for
//! pairing (a name in one file only is refused whether it is active or
//! not). Everything but the `point` elements is ignored.

use std::path::Path;

use crate::error::{Error, Result};
use crate::io::marker_points::{Entry, PointList};
use crate::transfer::markers::Side;

/// The points of a `.pp` file.
pub fn parse(text: &str, path: &Path) -> Result<PointList> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..roxmltree::ParsingOptions::default()
    };
    let doc = roxmltree::Document::parse_with_options(text, options).map_err(|e| {
        Error::parse(
            path,
            Some(e.pos().row as usize),
            format!("not a MeshLab picked-points file (XML): {e}"),
        )
    })?;
    let root = doc.root_element();
    if root.tag_name().name() != "PickedPoints" {
        return Err(Error::parse(
            path,
            Some(doc.text_pos_at(root.range().start).row as usize),
            format!(
                "not a MeshLab picked-points file: its root element is `{}`, not `PickedPoints`",
                root.tag_name().name()
            ),
        ));
    }
    let mut entries = Vec::new();
    // Lines counted as the points come, in order: linear in the file
    // (`text_pos_at` for each point would count from the start each time).
    let (mut counted, mut line) = (0, 1);
    for node in root
        .children()
        .filter(|n| n.is_element() && n.tag_name().name() == "point")
    {
        let at = node.range().start;
        line += memchr::memchr_iter(b'\n', &text.as_bytes()[counted..at]).count();
        counted = at;
        if entries.len() == crate::io::marker_file::MAX_MARKERS {
            return Err(Error::parse(
                path,
                Some(line),
                format!(
                    "more than {} points: a point file holds at most that many (a fit needs a few dozen to a few thousand)",
                    crate::io::marker_file::MAX_MARKERS
                ),
            ));
        }
        let bad = |msg: String| Error::parse(path, Some(line), msg);
        let mut p = [0.0; 3];
        for (c, axis) in p.iter_mut().zip(["x", "y", "z"]) {
            let value = node
                .attribute(axis)
                .ok_or_else(|| bad(format!("the point has no `{axis}`")))?;
            *c = value
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| bad(format!("`{axis}=\"{value}\"` is not a coordinate")))?;
        }
        let active = match node.attribute("active").map(str::trim) {
            None | Some("1") => true,
            Some("0") => false,
            Some(other) => {
                return Err(bad(format!(
                    "`active=\"{other}\"` is neither 1 (used) nor 0 (left out)"
                )))
            }
        };
        entries.push(Entry {
            name: node.attribute("name").map(str::to_string),
            side: Side::At(p),
            place: line,
            active,
        });
    }
    Ok(PointList {
        path: path.to_path_buf(),
        unit: "line",
        first_index: 0,
        entries,
    })
}
