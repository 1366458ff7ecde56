//! The numbers of an SVG's shapes, checked before the drawing is read.
//!
//! SVG's own error handling draws a path up to its first malformed number
//! and leaves out a shape whose number is malformed (`NaN`, `1e400`, a
//! typing slip): what would be morphed is then not the drawing the user
//! made, with no word said. So every path's data, every polygon's and
//! polyline's points, the numbers of rectangles, circles, ellipses and
//! lines, and every transform are read first with `svgtypes` (the parser
//! `usvg` itself reads them with), and the first that does not read is
//! refused, naming the element, its line and the attribute.

use std::path::Path;
use std::str::FromStr;

use usvg::roxmltree;

use super::parse_error;
use crate::error::Result;

/// The attributes of the basic shapes that hold a length.
const SHAPE_LENGTHS: [(&str, &[&str]); 4] = [
    ("rect", &["x", "y", "width", "height", "rx", "ry"]),
    ("circle", &["cx", "cy", "r"]),
    ("ellipse", &["cx", "cy", "rx", "ry"]),
    ("line", &["x1", "y1", "x2", "y2"]),
];

/// Checks the numbers of every shape and transform of `doc` (read from
/// `path`): an error names the first element, its line, the attribute
/// and what in it does not read as a finite number.
pub fn check_shape_numbers(doc: &roxmltree::Document, path: &Path) -> Result<()> {
    for node in doc.descendants().filter(|n| n.is_element()) {
        let tag = node.tag_name().name();
        let refuse = |attribute: &str, why: String| {
            let line = doc.text_pos_at(node.range().start).row as usize;
            let id = node
                .attribute("id")
                .map_or(String::new(), |id| format!(" id=\"{id}\""));
            Err(parse_error(
                path,
                Some(line),
                format!(
                    "the `{attribute}` attribute of `<{tag}{id}>` {why}: SVG would leave that shape out or cut it short there, so the drawing is not read; correct the number"
                ),
            ))
        };
        // `d="none"` is a path with no data.
        if let Some(d) = node
            .attribute("d")
            .filter(|d| tag == "path" && d.trim() != "none")
        {
            for segment in svgtypes::SimplifyingPathParser::from(d) {
                if let Err(e) = segment {
                    return refuse("d", format!("does not read as path data ({e})"));
                }
            }
        }
        if let Some(points) = node
            .attribute("points")
            .filter(|_| tag == "polygon" || tag == "polyline")
        {
            for number in svgtypes::NumberListParser::from(points) {
                if let Err(e) = number {
                    return refuse("points", format!("does not read as numbers ({e})"));
                }
            }
        }
        if let Some((_, attributes)) = SHAPE_LENGTHS.iter().find(|(shape, _)| *shape == tag) {
            for &attribute in *attributes {
                let Some(value) = node.attribute(attribute) else {
                    continue;
                };
                // `auto` is a value of `rx` and `ry`.
                if value.trim() == "auto" {
                    continue;
                }
                if let Err(e) = svgtypes::Length::from_str(value) {
                    return refuse(attribute, format!("`{value}` is not a length ({e})"));
                }
            }
        }
        if let Some(transform) = node.attribute("transform") {
            if let Err(e) = svgtypes::Transform::from_str(transform) {
                return refuse("transform", format!("does not read as a transform ({e})"));
            }
        }
    }
    Ok(())
}
