//! meshmorph's marker file: one marker a line, an optional name, then a
//! point on each mesh.
//!
//! ```text
//! # the two forms other tools write
//! 12 40                       # source vertex 12, target vertex 40
//! 0.1 0.2 0.3 1.5 0.2 0.9     # a position on each mesh, snapped to its surface
//! # the general form: [name] SIDE SIDE
//! nose v 12 t 40 0.2 0.3 0.5  # a vertex, and a triangle's point (barycentric)
//! "left eye" p 0.1 0.2 0.3 v 7
//! ```
//!
//! A side is `v I` (vertex `I`), `t T b0 b1 b2` (the point `b0 A + b1 B +
//! b2 C` of triangle `T` with corners `A B C`, weights in `[0, 1]` summing
//! to 1) or `p x y z` (a position, snapped to the nearest point of the
//! surface). Fields are separated by white space or a comma; `#` starts a
//! comment; a name is a word that is not a number nor `v`, `t` or `p`, or
//! any text in double quotes (with `\"`, `\\`, `\n` and `\r` escapes).
//! Names are unique within a file. A first line holding only the number of
//! markers (as in `.cons` files) is accepted and checked. Indices count
//! from 0 or from 1 as the [`VertexNumbering`] says.
//!
//! The same lines with one side each (`[name] SIDE`, or a bare index, or a
//! bare `x y z`) make a file of one mesh's points, paired with another
//! mesh's file by [`Markers::read_pair`] (`marker_points.rs`).

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::surface_point::SurfacePoint;
use crate::transfer::markers::{Markers, Origin, Pending, Side, VertexNumbering};

/// The most markers a marker file may hold: a million, a hundred times
/// more than any use of markers needs (a fit takes a few dozen to a few
/// thousand). A file past it is refused at its first marker too many, so
/// reading a marker file takes at most [`MEMORY_PER_MARKER`] bytes times
/// this, besides its text.
pub const MAX_MARKERS: usize = 1_000_000;

/// Bytes of memory a marker takes at the peak of reading and checking a
/// marker file (the pair, its name and lines, the checks' tables), measured
/// at about 370 with six million short lines; with a margin.
pub const MEMORY_PER_MARKER: u64 = 512;

/// The first line [`Markers::write`] writes.
const HEADER: &str = "# meshmorph markers: [name] SOURCE TARGET, each a vertex `v I`, a triangle's point `t T b0 b1 b2` or a position `p x y z`; indices from 0";

/// One line of a marker file: its name and sides, as given.
pub(crate) struct Line {
    pub(crate) number: usize,
    pub(crate) name: Option<String>,
    pub(crate) sides: Vec<Side>,
}

impl Markers {
    /// Reads a file of marker pairs in meshmorph's own format (see
    /// `io/marker_file.rs`): one marker a line, `source target` vertex
    /// indices, `sx sy sz tx ty tz` positions, or `[name] SIDE SIDE` with
    /// each side a vertex `v I`, a triangle's point `t T b0 b1 b2` or a
    /// position `p x y z`. Indices count from 0 or from 1 as `numbering`
    /// says. Files of one mesh's points (MeshLab's `.pp`, Wrap's `.json`)
    /// are read in twos by [`Markers::read_pair`].
    ///
    /// # Errors
    /// [`Error::Io`] if the file cannot be read, [`Error::FileRefused`] when
    /// it is not a regular file or is larger than a third of the memory
    /// available, [`Error::Parse`] naming the line of the first entry that
    /// does not parse (or of a byte that is not UTF-8), a name given twice,
    /// barycentric coordinates that do not sum to 1; a file of one mesh's
    /// points is refused, saying how to pair it.
    pub fn read(path: &Path, numbering: VertexNumbering) -> Result<Self> {
        let bytes = crate::io::read::read_file(path, &crate::io::read::Limit::memory())?;
        let text = crate::io::read::utf8(bytes, path)?;
        if let Some(kind) = crate::io::marker_points::one_mesh_format(path, &text) {
            return Err(Error::parse(
                path,
                None,
                format!(
                    "{kind} holds the points of one mesh: give it with the other mesh's file, source first (`--markers SOURCE --markers TARGET` on the command line, Markers::read_pair in the library)"
                ),
            ));
        }
        Self::parse(&text, path, numbering)
    }

    /// [`Markers::read`] on text already in memory; `path` names it in errors.
    ///
    /// # Errors
    /// [`Error::Parse`] naming the line of the first entry that does not parse.
    pub fn parse(text: &str, path: &Path, numbering: VertexNumbering) -> Result<Self> {
        let mut markers = Markers {
            origin: Origin {
                files: [Some(path.to_path_buf()), Some(path.to_path_buf())],
                units: ["line"; 2],
                first_index: [u32::from(numbering == VertexNumbering::FromOne); 2],
            },
            ..Markers::default()
        };
        let mut order = 0;
        parse_lines(text, path, numbering, 2, |line| {
            markers.push(
                order,
                [line.sides[0], line.sides[1]],
                line.name,
                [line.number; 2],
            );
            order += 1;
        })?;
        Ok(markers)
    }

    /// Adds marker `order` (its place among all the markers).
    pub(crate) fn push(
        &mut self,
        order: usize,
        sides: [Side; 2],
        name: Option<String>,
        lines: [usize; 2],
    ) {
        match sides {
            [Side::On(s), Side::On(t)] => {
                self.pairs.push([s, t]);
                self.names.push(name);
                self.lines.push(lines);
            }
            sides => self.points.push(Pending {
                order,
                sides,
                name,
                lines,
            }),
        }
    }

    /// Writes the markers in meshmorph's own format, the general form with
    /// 0-based indices, every marker in the order given (positions not yet
    /// snapped as `p x y z`), numbers printed so that they read back the
    /// same: [`Markers::read`] with [`VertexNumbering::FromZero`] gives back
    /// the same pairs, positions and names.
    ///
    /// # Errors
    /// What `w` returns.
    pub fn write(&self, w: &mut dyn Write) -> std::io::Result<()> {
        writeln!(w, "{HEADER}")?;
        for (name, sides) in self.entries() {
            if let Some(name) = name {
                write!(w, "{} ", quoted(name))?;
            }
            writeln!(w, "{} {}", side_text(&sides[0]), side_text(&sides[1]))?;
        }
        Ok(())
    }

    /// Every marker in the order given, with its name and its two sides
    /// (source, target) as given: points of the surfaces, and positions
    /// not yet snapped onto them.
    pub fn entries(&self) -> Vec<(Option<&str>, [Side; 2])> {
        let mut located = 0..self.pairs.len();
        let mut pending = self.points.iter().peekable();
        (0..self.len())
            .map(|order| match pending.peek() {
                Some(p) if p.order == order => {
                    let p = pending.next().expect("peeked");
                    (p.name.as_deref(), p.sides)
                }
                _ => {
                    let k = located.next().expect("counted");
                    (self.names[k].as_deref(), self.pairs[k].map(Side::On))
                }
            })
            .collect()
    }

    /// [`Markers::write`] into the file `path`, atomically.
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be written.
    pub fn save(&self, path: &Path) -> Result<()> {
        crate::io::write_atomic(path, |w| self.write(w))
    }
}

/// A side as [`Markers::write`] writes it.
fn side_text(side: &Side) -> String {
    match side {
        Side::On(SurfacePoint::Vertex(v)) => format!("v {v}"),
        Side::On(SurfacePoint::Triangle {
            triangle,
            barycentric: b,
        }) => format!("t {triangle} {:?} {:?} {:?}", b[0], b[1], b[2]),
        Side::At(p) => format!("p {:?} {:?} {:?}", p[0], p[1], p[2]),
    }
}

/// `name` in double quotes, escaped.
fn quoted(name: &str) -> String {
    let mut out = String::with_capacity(name.len() + 2);
    out.push('"');
    for c in name.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A field of a line: its text, and whether it was quoted (a name).
struct Field {
    text: String,
    quoted: bool,
}

/// The fields of a line, split at white space and commas outside quotes,
/// up to a `#` outside quotes.
fn fields(line: &str) -> std::result::Result<Vec<Field>, String> {
    let mut out = Vec::new();
    let mut chars = line.chars().peekable();
    while let Some(&c) = chars.peek() {
        if c == ',' || c.is_whitespace() {
            chars.next();
        } else if c == '#' {
            break;
        } else if c == '"' {
            chars.next();
            let mut text = String::new();
            loop {
                match chars.next() {
                    None => return Err("a name in quotes has no closing quote".into()),
                    Some('"') => break,
                    Some('\\') => match chars.next() {
                        Some('n') => text.push('\n'),
                        Some('r') => text.push('\r'),
                        Some(c @ ('"' | '\\')) => text.push(c),
                        Some(c) => {
                            return Err(format!(
                                "`\\{c}` is no escape (`\\\"`, `\\\\`, `\\n`, `\\r`)"
                            ))
                        }
                        None => return Err("a name in quotes has no closing quote".into()),
                    },
                    Some(c) => text.push(c),
                }
            }
            out.push(Field { text, quoted: true });
        } else {
            let mut text = String::new();
            while let Some(&c) = chars.peek() {
                if c == ',' || c == '#' || c == '"' || c.is_whitespace() {
                    break;
                }
                text.push(c);
                chars.next();
            }
            out.push(Field {
                text,
                quoted: false,
            });
        }
    }
    Ok(out)
}

/// Whether an unquoted field starts a side.
fn is_tag(f: &Field) -> bool {
    !f.quoted && matches!(f.text.as_str(), "v" | "t" | "p")
}

/// Reads the marker lines of `text`, each with `per_line` sides (2 for a
/// file of pairs, 1 for a file of one mesh's points), handing each to
/// `each` as it is read (nothing of a line is kept here but its name, to
/// refuse it twice): the memory a marker file takes is what `each` keeps.
pub(crate) fn parse_lines(
    text: &str,
    path: &Path,
    numbering: VertexNumbering,
    per_line: usize,
    mut each: impl FnMut(Line),
) -> Result<()> {
    // A byte-order mark, as some editors write, is not part of the text.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = 0usize;
    let mut count: Option<(usize, usize)> = None;
    let mut first = true;
    let mut names: HashMap<String, usize> = HashMap::new();
    for (k, raw) in text.lines().enumerate() {
        let number = k + 1;
        let bad = |msg: String| Error::parse(path, Some(number), msg);
        let fields = fields(raw).map_err(bad)?;
        if fields.is_empty() {
            continue;
        }
        if first && per_line == 2 && fields.len() == 1 && !fields[0].quoted {
            let n = fields[0].text.parse::<usize>().map_err(|_| {
                bad(format!(
                    "`{}` is neither a marker count nor a marker",
                    fields[0].text
                ))
            })?;
            count = Some((n, number));
            first = false;
            continue;
        }
        first = false;
        let named =
            fields[0].quoted || (!is_tag(&fields[0]) && fields[0].text.parse::<f64>().is_err());
        let (name, rest) = if named {
            (Some(fields[0].text.clone()), &fields[1..])
        } else {
            (None, &fields[..])
        };
        let sides = sides(rest, per_line, numbering).map_err(|msg| {
            let found = raw.split('#').next().unwrap_or("").trim();
            bad(format!("{msg}, in `{found}`"))
        })?;
        if let Some(name) = &name {
            if let Some(before) = names.insert(name.clone(), number) {
                return Err(bad(format!(
                    "the name `{name}` is given twice (line {before} and here): names must be unique within a file"
                )));
            }
        }
        lines += 1;
        if lines > MAX_MARKERS {
            return Err(bad(format!(
                "more than {MAX_MARKERS} markers: a marker file holds at most that many (a fit needs a few dozen to a few thousand)"
            )));
        }
        each(Line {
            number,
            name,
            sides,
        });
    }
    if let Some((n, line)) = count {
        if n != lines {
            return Err(Error::parse(
                path,
                Some(line),
                format!("the count line says {n} pairs but {lines} follow"),
            ));
        }
    }
    Ok(())
}

/// The `per_line` sides in `fields`, or what is wrong with them.
fn sides(
    fields: &[Field],
    per_line: usize,
    numbering: VertexNumbering,
) -> std::result::Result<Vec<Side>, String> {
    let one_based = numbering == VertexNumbering::FromOne;
    let index = |f: &Field, what: &str| -> std::result::Result<u32, String> {
        let v: i64 = f
            .text
            .parse()
            .map_err(|_| format!("`{}` is not a {what} index", f.text))?;
        let v = if one_based {
            if v < 1 {
                return Err(format!(
                    "{what} index {v} is not 1-based (1 is the first {what})"
                ));
            }
            v - 1
        } else {
            v
        };
        u32::try_from(v).map_err(|_| format!("{what} index {} is out of range", f.text))
    };
    let number = |f: &Field, what: &str| -> std::result::Result<f64, String> {
        f.text
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("`{}` is not a {what}", f.text))
    };
    let expected = if per_line == 2 {
        "expected `source target` (two vertex indices), `sx sy sz tx ty tz` (a position on each mesh) or `[name] SIDE SIDE` with each side `v I`, `t T b0 b1 b2` or `p x y z`"
    } else {
        "expected a vertex index, `x y z` (a position) or `[name] SIDE` with the side `v I`, `t T b0 b1 b2` or `p x y z`"
    };
    if fields.first().is_some_and(is_tag) {
        let mut out = Vec::with_capacity(per_line);
        let mut rest = fields;
        while let Some(tag) = rest.first() {
            let arity = match tag.text.as_str() {
                "v" if !tag.quoted => 1,
                "t" if !tag.quoted => 4,
                "p" if !tag.quoted => 3,
                _ => return Err(format!("{expected}; `{}` starts no side", tag.text)),
            };
            if rest.len() < 1 + arity {
                return Err(format!(
                    "{expected}; `{}` needs {arity} number{}",
                    tag.text,
                    if arity == 1 { "" } else { "s" }
                ));
            }
            let f = &rest[1..=arity];
            out.push(match tag.text.as_str() {
                "v" => Side::On(SurfacePoint::Vertex(index(&f[0], "vertex")?)),
                "t" => {
                    let point = SurfacePoint::Triangle {
                        triangle: index(&f[0], "triangle")?,
                        barycentric: [
                            number(&f[1], "barycentric coordinate")?,
                            number(&f[2], "barycentric coordinate")?,
                            number(&f[3], "barycentric coordinate")?,
                        ],
                    };
                    Side::On(point.normalized()?)
                }
                _ => Side::At([
                    number(&f[0], "coordinate")?,
                    number(&f[1], "coordinate")?,
                    number(&f[2], "coordinate")?,
                ]),
            });
            rest = &rest[1 + arity..];
        }
        if out.len() != per_line {
            return Err(format!(
                "{expected}; found {} side{}",
                out.len(),
                if out.len() == 1 { "" } else { "s" }
            ));
        }
        return Ok(out);
    }
    if fields.len() == per_line {
        fields
            .iter()
            .map(|f| Ok(Side::On(SurfacePoint::Vertex(index(f, "vertex")?))))
            .collect()
    } else if fields.len() == 3 * per_line {
        let c = fields
            .iter()
            .map(|f| number(f, "coordinate"))
            .collect::<std::result::Result<Vec<f64>, String>>()?;
        Ok(c.chunks(3).map(|p| Side::At([p[0], p[1], p[2]])).collect())
    } else {
        Err(expected.into())
    }
}
