//! Files of one mesh's marker points, read in twos (the source's, the
//! target's) and paired into [`Markers`]: MeshLab's picked points (`.pp`,
//! `picked_points.rs`), Wrap's points on triangles (`.json`,
//! `wrap_points.rs`) and meshmorph's own lines with one side each
//! (`marker_file.rs`).
//!
//! Two files whose points are all named pair by name, whatever their
//! order; otherwise they pair in order, and must hold as many points.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::transfer::markers::{Markers, Origin, Side, VertexNumbering};

/// One point of a file of one mesh's points.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    pub name: Option<String>,
    pub side: Side,
    /// 1-based line, or place in the list for files without lines.
    pub place: usize,
    /// MeshLab's `active="0"`: a point left out.
    pub active: bool,
}

/// The points of one mesh's file.
#[derive(Clone, Debug)]
pub struct PointList {
    pub(crate) path: PathBuf,
    /// "line", or "point" for files without lines.
    pub(crate) unit: &'static str,
    pub(crate) first_index: u32,
    pub entries: Vec<Entry>,
}

/// The formats of one mesh's points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    PickedPoints,
    Wrap,
    Lines,
}

/// The format of one mesh's points `path` holds: by extension (`.pp`,
/// `.json`), else by its first character (`<` XML, `[` or `{` JSON).
fn format(path: &Path, text: &str) -> Format {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("pp") => return Format::PickedPoints,
        Some("json") => return Format::Wrap,
        _ => {}
    }
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    match text.trim_start().chars().next() {
        Some('<') => Format::PickedPoints,
        Some('[' | '{') => Format::Wrap,
        _ => Format::Lines,
    }
}

/// What kind of file of one mesh's points `path` is, for messages, if it
/// is one (`None` for meshmorph's own lines).
pub(crate) fn one_mesh_format(path: &Path, text: &str) -> Option<&'static str> {
    match format(path, text) {
        Format::PickedPoints => Some("a MeshLab picked-points file"),
        Format::Wrap => Some("a Wrap point file"),
        Format::Lines => None,
    }
}

impl Markers {
    /// Reads the marker points of the source (`source`) and of the target
    /// (`target`), one file for each mesh, and pairs them: MeshLab's
    /// picked points (`.pp`: `x y z` positions, names; see
    /// `io/picked_points.rs`), Wrap's points on triangles (`.json`: lists of
    /// `[triangle, u, v]` or objects of named ones; see `io/wrap_points.rs`),
    /// or meshmorph's own lines with one point each (`[name] SIDE`, a bare
    /// vertex index, or `x y z`), told apart by extension or content. Two
    /// files whose points are all named pair by name; otherwise they pair in
    /// order. `numbering` applies to meshmorph's own files (`.pp` files
    /// hold no indices, and Wrap's count from 0). Wrap numbers the
    /// triangles of a fan over each polygon from its first vertex: the same
    /// numbers as meshmorph's on a mesh of triangles only (meshmorph splits
    /// quads along their shorter diagonal and larger polygons by ear
    /// clipping), so give Wrap files for meshes exported as triangles.
    ///
    /// # Errors
    /// As [`Markers::read`], and [`Error::Parse`] naming the file (and
    /// line or point) for a name in one file only, a name given twice in
    /// one file, a point without a name in a file of named points, or
    /// unnamed files of different lengths.
    pub fn read_pair(source: &Path, target: &Path, numbering: VertexNumbering) -> Result<Self> {
        let (s, t) = (
            read_points(source, numbering)?,
            read_points(target, numbering)?,
        );
        pair(&s, &t)
    }
}

/// Reads one mesh's points.
pub(crate) fn read_points(path: &Path, numbering: VertexNumbering) -> Result<PointList> {
    let bytes = crate::io::read::read_file(path, &crate::io::read::Limit::memory())?;
    let text = crate::io::read::utf8(bytes, path)?;
    parse_points(&text, path, numbering)
}

/// [`read_points`] on text in memory.
pub fn parse_points(text: &str, path: &Path, numbering: VertexNumbering) -> Result<PointList> {
    let list = match format(path, text) {
        Format::PickedPoints => crate::io::picked_points::parse(text, path)?,
        Format::Wrap => crate::io::wrap_points::parse(text, path)?,
        Format::Lines => {
            let mut entries = Vec::new();
            crate::io::marker_file::parse_lines(text, path, numbering, 1, |line| {
                entries.push(Entry {
                    name: line.name,
                    side: line.sides[0],
                    place: line.number,
                    active: true,
                });
            })?;
            PointList {
                path: path.to_path_buf(),
                unit: "line",
                first_index: u32::from(numbering == VertexNumbering::FromOne),
                entries,
            }
        }
    };
    if list.entries.len() > crate::io::marker_file::MAX_MARKERS {
        return Err(Error::parse(
            path,
            None,
            format!(
                "{} points: a point file holds at most {} (a fit needs a few dozen to a few thousand)",
                list.entries.len(),
                crate::io::marker_file::MAX_MARKERS
            ),
        ));
    }
    list.check_names()?;
    Ok(list)
}

impl PointList {
    /// The error at entry `e`.
    fn error(&self, e: &Entry, message: String) -> Error {
        if self.unit == "line" {
            Error::parse(&self.path, Some(e.place), message)
        } else {
            Error::parse(
                &self.path,
                None,
                format!("{} {}: {message}", self.unit, e.place),
            )
        }
    }

    /// Whether the points are named (all of them: see
    /// [`PointList::check_names`]).
    fn named(&self) -> bool {
        self.entries.iter().any(|e| e.name.is_some())
    }

    /// Names unique, and on every point or on none.
    fn check_names(&self) -> Result<()> {
        let mut seen: HashMap<&str, &Entry> = HashMap::new();
        let named = self.named();
        for e in &self.entries {
            match &e.name {
                None if named => {
                    return Err(self.error(
                        e,
                        "a point without a name among named points: name every point, or none (then the files pair in order)".into(),
                    ))
                }
                None => {}
                Some(name) => {
                    if let Some(before) = seen.insert(name, e) {
                        return Err(self.error(
                            e,
                            format!(
                                "the name `{name}` is given twice ({} {} and here): names must be unique within a file",
                                self.unit, before.place
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}

/// The markers of two files of points: by name when both are named, else
/// in order. A pair with a point left out (inactive) on either side is left
/// out.
pub fn pair(source: &PointList, target: &PointList) -> Result<Markers> {
    let mut markers = Markers {
        origin: Origin {
            files: [Some(source.path.clone()), Some(target.path.clone())],
            units: [source.unit, target.unit],
            first_index: [source.first_index, target.first_index],
        },
        ..Markers::default()
    };
    let pairs: Vec<(&Entry, &Entry)> = if source.named() && target.named() {
        fn by_name(list: &PointList) -> HashMap<&str, &Entry> {
            list.entries
                .iter()
                .filter_map(|e| Some((e.name.as_deref()?, e)))
                .collect()
        }
        let (in_source, in_target) = (by_name(source), by_name(target));
        let alone = |list: &PointList, other: &PointList, others: &HashMap<&str, &Entry>| {
            let e = list
                .entries
                .iter()
                .find(|e| !others.contains_key(e.name.as_deref().unwrap_or_default()))?;
            Some(list.error(
                e,
                format!(
                    "the point `{}` has no point of that name in `{}`: named points pair by name, and every name must be in both files",
                    e.name.as_deref().unwrap_or_default(),
                    other.path.display()
                ),
            ))
        };
        if let Some(e) =
            alone(source, target, &in_target).or_else(|| alone(target, source, &in_source))
        {
            return Err(e);
        }
        source
            .entries
            .iter()
            .map(|e| (e, in_target[e.name.as_deref().unwrap_or_default()]))
            .collect()
    } else {
        if source.entries.len() != target.entries.len() {
            return Err(Error::parse(
                &source.path,
                None,
                format!(
                    "{} point{} here and {} in `{}`: files without names on both sides pair in order, and must hold as many points",
                    source.entries.len(),
                    if source.entries.len() == 1 { "" } else { "s" },
                    target.entries.len(),
                    target.path.display()
                ),
            ));
        }
        source.entries.iter().zip(&target.entries).collect()
    };
    let mut order = 0;
    for (s, t) in pairs {
        if s.active && t.active {
            let name = s.name.clone().or_else(|| t.name.clone());
            markers.push(order, [s.side, t.side], name, [s.place, t.place]);
            order += 1;
        }
    }
    Ok(markers)
}
