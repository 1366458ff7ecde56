//! Drawings as files: filled outlines read from SVG and from text, a
//! planar mesh's boundary as a drawing, and the frames of a morph written
//! back as SVG, animated SVG, Lottie JSON and text.
//!
//! One concept a file:
//!
//! - `svg_read`: an SVG file to a [`DrawingFile`] (with `usvg`: paths,
//!   `rect`, `circle`, `ellipse`, `polygon`, `polyline`, `line`, transforms,
//!   nested groups, `use`, CSS); `flatten` turns its curves into chords
//!   within a tolerance, `regions` sorts the loops into outer loops and
//!   holes by each path's fill rule; `svg_numbers` refuses a shape whose
//!   numbers do not read, before SVG's own handling would drop it.
//! - `text_read`: polygons as text (`x y` lines, a blank line between
//!   loops, `#` comments).
//! - `mesh_outline`: a planar mesh's boundary loops as a drawing.
//! - `anchors`: named points matched across drawings, from a text file.
//! - `canvas`: the page frames are drawn on (viewBox and size).
//! - `svg_write`, `svg_animate`, `lottie`, `text_write`: the writers.
//!
//! **Coordinates.** A drawing keeps its file's own coordinates: an SVG's
//! user units inside its `viewBox` (y pointing down, as in SVG), a text
//! file's numbers as they are. [`Drawing`] calls counter-clockwise what
//! turns from +x towards +y, so in an SVG's coordinates its outer loop runs
//! clockwise on the screen; nothing depends on it but the sign of areas,
//! the same for every drawing of a morph. Frames are written in the same
//! coordinates, so that an SVG frame laid over its drawing's file covers
//! it exactly. Drawings without a page of their own (text, meshes) are
//! taken as y pointing up, as meshes are drawn, and flipped when written
//! as SVG or Lottie.

pub mod anchors;
pub mod canvas;
pub mod flatten;
pub mod lottie;
pub mod mesh_outline;
pub mod regions;
pub mod svg_animate;
pub mod svg_numbers;
pub mod svg_read;
pub mod svg_write;
pub mod text_read;
pub mod text_write;

pub use anchors::{match_anchors, read_anchor_file, AnchorRow};
pub use canvas::Canvas;
pub use lottie::write_lottie;
pub use mesh_outline::drawing_of_mesh;
pub use svg_animate::write_animated_svg;
pub use svg_read::parse_svg_drawing;
pub use svg_write::{svg_path_data, write_svg_frame};
pub use text_read::parse_text_drawing;
pub use text_write::write_text_frame;

pub use regions::{inside, signed_area2};

use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::frame_source::FrameSource;
use crate::outline::Drawing;

/// How a drawing file is read.
#[derive(Clone, Debug)]
pub struct DrawingOptions {
    /// The largest distance between a curve and the chords that replace
    /// it, as a fraction of the diagonal of the drawing's bounding box.
    /// Default 1/2000 (0.05 %): a circle becomes about 70 chords.
    pub tolerance: f64,
}

impl Default for DrawingOptions {
    fn default() -> Self {
        Self {
            tolerance: 1.0 / 2000.0,
        }
    }
}

/// Colours and lines of a drawing, as its file gave them (SVG: the first
/// filled element's), for the frames written from it.
#[derive(Clone, Debug, PartialEq)]
pub struct Style {
    /// Fill colour, `[r, g, b]` from 0 to 255; `None` for a paint that is
    /// not a plain colour (a gradient, a pattern), drawn as black.
    pub fill: Option<[u8; 3]>,
    /// Fill opacity from 0 to 1 (the element's and its groups' opacity
    /// included).
    pub fill_opacity: f64,
    /// Stroke colour, when the element has a stroke of a plain colour.
    pub stroke: Option<[u8; 3]>,
    /// Stroke width in the drawing's units (0 without a stroke).
    pub stroke_width: f64,
    /// Stroke opacity from 0 to 1.
    pub stroke_opacity: f64,
}

impl Default for Style {
    /// Black fill, no stroke: an SVG shape's defaults.
    fn default() -> Self {
        Self {
            fill: Some([0, 0, 0]),
            fill_opacity: 1.0,
            stroke: None,
            stroke_width: 0.0,
            stroke_opacity: 1.0,
        }
    }
}

/// A point of a drawing named to be matched with the points of the same
/// name on the other drawings (an anchor).
#[derive(Clone, Debug, PartialEq)]
pub struct NamedPoint {
    /// Its name (empty for an unnamed anchor: those are matched in order).
    pub name: String,
    /// Where it is, in the drawing's coordinates.
    pub point: [f64; 2],
}

/// The frames of a morph to write as one animation
/// ([`write_animated_svg`], [`write_lottie`]).
#[derive(Clone, Copy)]
pub struct Animation<'a> {
    /// Every frame's vertex positions.
    pub frames: &'a dyn FrameSource<2>,
    /// The loops drawn, as vertex indices: the outer loop first.
    pub loops: &'a [Vec<u32>],
    /// Colours and lines.
    pub style: &'a Style,
    /// The page ([`Canvas::for_frames`]).
    pub canvas: &'a Canvas,
    /// Frames a second.
    pub fps: f64,
    /// Forward, then back (the ends not repeated), over and over; else
    /// forward over and over.
    pub boomerang: bool,
}

/// What kind of file a drawing came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawingKind {
    /// An SVG file (`.svg`).
    Svg,
    /// Polygons as text (`.txt`).
    Text,
    /// A planar mesh's boundary.
    Mesh,
}

impl DrawingKind {
    /// The kind a path's extension names (`.svg`, `.txt`;
    /// case-insensitive), if any.
    pub fn of_path(path: &Path) -> Option<DrawingKind> {
        let ext = path.extension()?.to_str()?;
        if ext.eq_ignore_ascii_case("svg") {
            Some(DrawingKind::Svg)
        } else if ext.eq_ignore_ascii_case("txt") {
            Some(DrawingKind::Text)
        } else {
            None
        }
    }
}

/// A drawing read from a file, with what the file says about how it looks.
#[derive(Clone, Debug)]
pub struct DrawingFile {
    /// The region: outer loop and holes, checked.
    pub drawing: Drawing,
    /// Colours and lines (SVG: the first filled element's; others: the
    /// defaults).
    pub style: Style,
    /// The page: an SVG's viewBox and size; `None` for text and meshes.
    pub canvas: Option<Canvas>,
    /// Marked anchors, in the file's order.
    pub anchors: Vec<NamedPoint>,
    /// The largest distance between a curve and its chords, in the
    /// drawing's units (0 when the file has no curves, as text).
    pub tolerance: f64,
    /// Curves flattened, counted.
    pub curves: usize,
    /// What kind of file it came from.
    pub kind: DrawingKind,
}

/// Reads a drawing, choosing the format by the file's extension: `.svg`
/// ([`parse_svg_drawing`]) or `.txt` ([`parse_text_drawing`]).
///
/// # Errors
/// [`Error::UnknownFormat`] for another extension; [`Error::Io`] and
/// [`Error::FileRefused`] as for meshes; [`Error::Parse`] naming the file
/// (and line, for text) for anything that is not one valid drawing.
pub fn read_drawing(path: &Path, options: &DrawingOptions) -> Result<DrawingFile> {
    let kind = DrawingKind::of_path(path).ok_or_else(|| Error::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    let bytes = super::read::read_file(path, &super::read::Limit::memory())?;
    match kind {
        DrawingKind::Svg => parse_svg_drawing(&bytes, path, options),
        _ => {
            let text = super::read::utf8(bytes, path)?;
            let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
            parse_text_drawing(text, path)
        }
    }
}

/// A drawing's own error said about its file: the loop's problem, naming
/// the file, with what the loops are in that file.
pub(crate) fn drawing_error(e: Error, path: &Path, loops_are: &str) -> Error {
    match e {
        Error::InvalidDrawing { message, .. } => Error::Parse {
            path: path.to_path_buf(),
            line: None,
            message: format!("{message} ({loops_are})"),
        },
        e => e,
    }
}

/// A parse error naming `path`.
pub(crate) fn parse_error(path: &Path, line: Option<usize>, message: String) -> Error {
    Error::Parse {
        path: path.to_path_buf(),
        line,
        message,
    }
}
