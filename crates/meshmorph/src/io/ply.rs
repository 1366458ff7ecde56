//! Stanford PLY: ascii, binary little endian and binary big endian.
//!
//! A small parser of its own rather than a PLY library: it gives messages
//! with the file name, the line (ascii) or byte offset (binary) and the
//! element, skips what it does not need, never allocates more than the file
//! could fill and never panics on malformed input.

use std::io::Write;
use std::path::Path;

use super::mesh_file::{offset_in, Coding, Keep, Parsed, Patch, Slot, NONE};
use super::triangulate::{check_corners, Polygons};
use super::vertex_attributes::{channel_byte, VertexAttributes};
use super::{bad_count, parse_f64, parse_i64, show, tokens, xyz, Lines, CHUNK};
use crate::error::{Error, Result};

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn from_name(name: &[u8]) -> Option<Scalar> {
        Some(match name {
            b"char" | b"int8" => Scalar::I8,
            b"uchar" | b"uint8" => Scalar::U8,
            b"short" | b"int16" => Scalar::I16,
            b"ushort" | b"uint16" => Scalar::U16,
            b"int" | b"int32" => Scalar::I32,
            b"uint" | b"uint32" => Scalar::U32,
            b"float" | b"float32" => Scalar::F32,
            b"double" | b"float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// The value of full intensity of a colour stored in this type: the
    /// largest value of an integer type, 1 for floating point.
    fn color_scale(self) -> f64 {
        match self {
            Scalar::I8 => 127.0,
            Scalar::U8 => 255.0,
            Scalar::I16 => 32767.0,
            Scalar::U16 => 65535.0,
            Scalar::I32 => 2147483647.0,
            Scalar::U32 => 4294967295.0,
            Scalar::F32 | Scalar::F64 => 1.0,
        }
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// The value stored in `b` (exactly `size()` bytes); every PLY scalar
    /// converts exactly to `f64`.
    fn decode(self, b: &[u8], big: bool) -> Option<f64> {
        macro_rules! get {
            ($t:ty) => {{
                let a = b.try_into().ok()?;
                f64::from(if big {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                })
            }};
        }
        Some(match self {
            Scalar::I8 => get!(i8),
            Scalar::U8 => get!(u8),
            Scalar::I16 => get!(i16),
            Scalar::U16 => get!(u16),
            Scalar::I32 => get!(i32),
            Scalar::U32 => get!(u32),
            Scalar::F32 => get!(f32),
            Scalar::F64 => get!(f64),
        })
    }

    /// Appends `x` in this type (integers rounded and saturated).
    pub(super) fn encode(self, x: f64, big: bool, out: &mut Vec<u8>) {
        macro_rules! put {
            ($v:expr) => {{
                let v = $v;
                out.extend_from_slice(&if big {
                    v.to_be_bytes()
                } else {
                    v.to_le_bytes()
                });
            }};
        }
        match self {
            Scalar::I8 => put!(x.round() as i8),
            Scalar::U8 => put!(x.round() as u8),
            Scalar::I16 => put!(x.round() as i16),
            Scalar::U16 => put!(x.round() as u16),
            Scalar::I32 => put!(x.round() as i32),
            Scalar::U32 => put!(x.round() as u32),
            Scalar::F32 => put!(x as f32),
            Scalar::F64 => put!(x),
        }
    }
}

/// The names of a vertex colour's properties (red, green, blue, alpha), as
/// tools write them.
const COLOR_NAMES: [[&[u8]; 4]; 3] = [
    [b"red", b"green", b"blue", b"alpha"],
    [b"r", b"g", b"b", b"a"],
    [
        b"diffuse_red",
        b"diffuse_green",
        b"diffuse_blue",
        b"diffuse_alpha",
    ],
];

/// A property: a scalar, or a list with its count and item types.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Scalar(Scalar),
    List(Scalar, Scalar),
}

struct Property {
    name: Vec<u8>,
    kind: Kind,
}

struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

impl Element {
    fn prop(&self, names: &[&[u8]]) -> Option<(usize, Kind)> {
        self.props
            .iter()
            .position(|p| names.contains(&p.name.as_slice()))
            .map(|k| (k, self.props[k].kind))
    }

    /// The fewest bytes one instance takes (binary), or values (ascii).
    fn min_size(&self, binary: bool) -> usize {
        let sizes = self.props.iter().map(|p| match p.kind {
            Kind::Scalar(s) | Kind::List(s, _) if binary => s.size(),
            _ => 1,
        });
        sizes.sum::<usize>().max(1)
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// Parses a PLY file's contents (see the [module documentation](super)),
/// keeping what [`MeshFile`](super::MeshFile) needs to write it back.
pub(super) fn parse(bytes: &[u8], path: &Path, keep: Keep) -> Result<Parsed> {
    let mut lines = Lines::new(bytes);
    let (encoding, elements) = parse_header(&mut lines, path)?;
    let mut body = Body {
        path,
        file: bytes,
        ascii: (encoding == Encoding::Ascii).then_some(lines.clone()),
        tokens: Vec::new(),
        next: 0,
        bytes: lines.rest,
        pos: 0,
        big: encoding == Encoding::Big,
        element: "",
        instance: 0,
        last: 0..0,
    };
    let binary = encoding != Encoding::Ascii;
    let Some(num_vertices) = elements
        .iter()
        .find(|e| e.name == "vertex")
        .map(|e| e.count)
    else {
        return Err(Error::parse(
            path,
            None,
            "no `vertex` element in the header",
        ));
    };
    if !elements.iter().any(|e| e.name == "face") {
        return Err(Error::parse(
            path,
            None,
            "no triangles: no `face` element in the header",
        ));
    }

    let mut out = Parsed::new(keep);
    for element in &elements {
        body.element = &element.name;
        let capacity = element
            .count
            .min(body.bytes.len() / element.min_size(binary));
        match element.name.as_str() {
            "vertex" => {
                out.positions.reserve(capacity);
                read_vertices(&mut body, element, &mut out)?;
            }
            "face" => {
                out.faces = Polygons::with_capacity(capacity);
                read_faces(&mut body, element, num_vertices, &mut out)?;
            }
            other => {
                out.note_extra(&format!("element `{other}`"));
                skip(&mut body, element)?;
            }
        }
    }
    if out.faces.len() == 0 {
        return Err(Error::parse(
            path,
            None,
            format!("no triangles: the file has {num_vertices} vertices and no faces"),
        ));
    }
    out.warnings.extend(body.left_over());
    Ok(out)
}

/// Reads the header up to `end_header`, leaving `lines` at the body.
fn parse_header(lines: &mut Lines<'_>, path: &Path) -> Result<(Encoding, Vec<Element>)> {
    let err = |line: usize, msg: String| Error::parse(path, Some(line), msg);
    match lines.next() {
        Some((_, b"ply")) => {}
        _ => return Err(err(1, "not a PLY file: the first line is not `ply`".into())),
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some((n, line)) = lines.next() else {
            return Err(Error::parse(
                path,
                None,
                "the header has no `end_header` line",
            ));
        };
        let toks: Vec<&[u8]> = tokens(line).collect();
        match toks.as_slice() {
            [] | [b"comment" | b"obj_info", ..] => {}
            [b"end_header"] => break,
            [b"format", enc, _version] => {
                encoding = Some(match *enc {
                    b"ascii" => Encoding::Ascii,
                    b"binary_little_endian" => Encoding::Little,
                    b"binary_big_endian" => Encoding::Big,
                    _ => return Err(err(n, format!("unknown PLY format `{}`", show(enc)))),
                });
            }
            [b"element", name, count] => {
                let count = parse_i64(count)
                    .and_then(|c| usize::try_from(c).ok())
                    .ok_or_else(|| {
                        err(
                            n,
                            format!("element count `{}` {}", show(count), bad_count(count)),
                        )
                    })?;
                if elements.iter().any(|e| e.name.as_bytes() == *name) {
                    return Err(err(
                        n,
                        format!("element `{}` is declared twice", show(name)),
                    ));
                }
                elements.push(Element {
                    name: String::from_utf8_lossy(name).into_owned(),
                    count,
                    props: Vec::new(),
                });
            }
            [b"property", rest @ ..] => {
                let scalar = |t: &[u8]| {
                    Scalar::from_name(t)
                        .ok_or_else(|| err(n, format!("unknown property type `{}`", show(t))))
                };
                let (kind, name) = match rest {
                    [b"list", count, item, name] => {
                        (Kind::List(scalar(count)?, scalar(item)?), name)
                    }
                    [ty, name] if *ty != b"list" => (Kind::Scalar(scalar(ty)?), name),
                    _ => return Err(err(n, "malformed `property` line".into())),
                };
                let Some(element) = elements.last_mut() else {
                    return Err(err(n, "`property` before any `element`".into()));
                };
                element.props.push(Property {
                    name: name.to_vec(),
                    kind,
                });
            }
            _ => return Err(err(n, format!("unexpected header line `{}`", show(line)))),
        }
    }
    let encoding =
        encoding.ok_or_else(|| Error::parse(path, None, "the header has no `format` line"))?;
    Ok((encoding, elements))
}

/// The body being read: ascii lines of tokens, or binary bytes.
struct Body<'a> {
    path: &'a Path,
    /// The whole file, for the byte ranges of values.
    file: &'a [u8],
    /// The remaining lines, for an ascii file.
    ascii: Option<Lines<'a>>,
    /// The current line's tokens and the next one to read (ascii).
    tokens: Vec<&'a [u8]>,
    next: usize,
    /// The body and the read position (binary).
    bytes: &'a [u8],
    pos: usize,
    big: bool,
    /// Where we are, for messages.
    element: &'a str,
    instance: usize,
    /// Where in the file the value read last is.
    last: std::ops::Range<usize>,
}

impl<'a> Body<'a> {
    fn error(&self, msg: impl std::fmt::Display) -> Error {
        match &self.ascii {
            Some(lines) => Error::parse(
                self.path,
                Some(lines.number()),
                format!("{} {}: {msg}", self.element, self.instance),
            ),
            None => Error::parse(
                self.path,
                None,
                format!(
                    "{} {} (body byte {}): {msg}",
                    self.element, self.instance, self.pos
                ),
            ),
        }
    }

    /// Starts instance `i` of the current element.
    fn begin(&mut self, i: usize, count: usize) -> Result<()> {
        self.instance = i;
        if let Some(lines) = &mut self.ascii {
            let line = lines
                .by_ref()
                .map(|(_, l)| l)
                .find(|l| tokens(l).next().is_some());
            let Some(line) = line else {
                return Err(self.error(format_args!(
                    "the file ends here, but the header announces {count} `{}` elements",
                    self.element
                )));
            };
            self.tokens.clear();
            self.tokens.extend(tokens(line));
            self.next = 0;
        }
        Ok(())
    }

    /// What is left past the last element the header announces, as a
    /// warning: lines with values (ascii) or bytes (binary).
    fn left_over(&mut self) -> Option<String> {
        let path = self.path.display();
        match &mut self.ascii {
            Some(lines) => {
                let mut rest = lines.by_ref().filter(|(_, l)| tokens(l).next().is_some());
                let (first, _) = rest.next()?;
                let more = 1 + rest.count();
                Some(format!(
                    "`{path}`, line {first}: {more} more line{} after the elements the header announces: ignored (the counts may be wrong)",
                    if more == 1 { "" } else { "s" }
                ))
            }
            None => {
                let left = self.bytes.len() - self.pos;
                (left > 0).then(|| {
                    format!(
                        "`{path}`: {left} byte{} after the elements the header announces: ignored (the counts may be wrong)",
                        if left == 1 { "" } else { "s" }
                    )
                })
            }
        }
    }

    /// Ends the current instance: an ascii line must hold nothing more.
    fn end(&self) -> Result<()> {
        if self.ascii.is_some() && self.next < self.tokens.len() {
            return Err(self.error(format_args!(
                "the line has {} values, more than the header's properties ({} read)",
                self.tokens.len(),
                self.next
            )));
        }
        Ok(())
    }

    /// Reads one scalar.
    #[inline]
    fn value(&mut self, ty: Scalar) -> Result<f64> {
        if self.ascii.is_some() {
            let Some(&tok) = self.tokens.get(self.next) else {
                return Err(self.error("the line has too few values for the header's properties"));
            };
            self.next += 1;
            let start = offset_in(self.file, tok);
            self.last = start..start + tok.len();
            return parse_f64(tok)
                .ok_or_else(|| self.error(format_args!("`{}` is not a number", show(tok))));
        }
        let end = self.pos + ty.size();
        let value = self
            .bytes
            .get(self.pos..end)
            .and_then(|b| ty.decode(b, self.big));
        let Some(value) = value else {
            return Err(self.error("the file ends in the middle of this element (truncated file)"));
        };
        let base = offset_in(self.file, self.bytes);
        self.last = base + self.pos..base + end;
        self.pos = end;
        Ok(value)
    }

    /// Reads a list's count, checking it against what is left to read.
    fn list_len(&mut self, count: Scalar, item: Scalar) -> Result<usize> {
        let c = self.value(count)?;
        let left = match self.ascii {
            Some(_) => self.tokens.len() - self.next,
            None => (self.bytes.len() - self.pos) / item.size(),
        };
        if !(c >= 0.0 && c.fract() == 0.0) {
            return Err(self.error(format_args!(
                "list length {c} is not a non-negative integer"
            )));
        }
        if c > left as f64 {
            return Err(self.error(format_args!(
                "a list of {c} values, but only {left} are left {}",
                if self.ascii.is_some() {
                    "on the line"
                } else {
                    "in the file"
                }
            )));
        }
        Ok(c as usize)
    }

    /// Reads (and drops) a property's value(s).
    fn skip_property(&mut self, kind: Kind) -> Result<()> {
        match kind {
            Kind::Scalar(s) => {
                self.value(s)?;
            }
            Kind::List(count, item) => {
                for _ in 0..self.list_len(count, item)? {
                    self.value(item)?;
                }
            }
        }
        Ok(())
    }
}

/// Skips every instance of an element the mesh does not need.
fn skip(body: &mut Body<'_>, element: &Element) -> Result<()> {
    if element.props.is_empty() {
        return Ok(());
    }
    let fixed: Option<usize> = element
        .props
        .iter()
        .map(|p| match p.kind {
            Kind::Scalar(s) => Some(s.size()),
            Kind::List(..) => None,
        })
        .sum();
    if let (None, Some(size)) = (&body.ascii, fixed) {
        let total = element
            .count
            .checked_mul(size)
            .filter(|&t| t <= body.bytes.len() - body.pos);
        let Some(total) = total else {
            body.instance = element.count;
            return Err(
                body.error("the file is too short for the header's element count (truncated file)")
            );
        };
        body.pos += total;
        return Ok(());
    }
    for i in 0..element.count {
        body.begin(i, element.count)?;
        for p in &element.props {
            body.skip_property(p.kind)?;
        }
        body.end()?;
    }
    Ok(())
}

/// Names of per-vertex texture coordinates, in the order they are looked for.
const UV_NAMES: [[&[u8]; 2]; 4] = [
    [b"s", b"t"],
    [b"u", b"v"],
    [b"texture_u", b"texture_v"],
    [b"texture_s", b"texture_t"],
];

fn read_vertices(body: &mut Body<'_>, element: &Element, out: &mut Parsed) -> Result<()> {
    let path = body.path;
    let axis = |name: &[u8]| match element.prop(&[name]) {
        Some((k, Kind::Scalar(_))) => Ok(Some(k)),
        Some((_, Kind::List(..))) => Err(Error::parse(
            path,
            None,
            format!("vertex property `{}` is a list, not a number", show(name)),
        )),
        None => Ok(None),
    };
    let (Some(ix), Some(iy)) = (axis(b"x")?, axis(b"y")?) else {
        return Err(Error::parse(
            path,
            None,
            "the `vertex` element has no `x` and `y` properties",
        ));
    };
    let iz = axis(b"z")?;
    let normal_props = [axis(b"nx")?, axis(b"ny")?, axis(b"nz")?];
    let has_normals = normal_props.iter().all(Option::is_some);
    let mut uv_props = [None, None];
    for names in UV_NAMES {
        if let (Some(u), Some(v)) = (axis(names[0])?, axis(names[1])?) {
            uv_props = [Some(u), Some(v)];
            break;
        }
    }
    let has_uvs = uv_props.iter().all(Option::is_some);
    // A colour: red, green, blue and an optional alpha.
    let mut color_props = [None; 4];
    for names in COLOR_NAMES {
        if let (Some(r), Some(g), Some(b)) = (axis(names[0])?, axis(names[1])?, axis(names[2])?) {
            color_props = [Some(r), Some(g), Some(b), axis(names[3])?];
            break;
        }
    }
    let has_colors = color_props[..3].iter().all(Option::is_some);
    // What each property is: 0..3 a coordinate, 3..6 a normal's, 6..8 a
    // texture coordinate, 8..12 a colour's, else kept as it is.
    let role: Vec<Option<usize>> = (0..element.props.len())
        .map(|k| {
            if k == ix {
                Some(0)
            } else if k == iy {
                Some(1)
            } else if Some(k) == iz {
                Some(2)
            } else if has_normals && normal_props.contains(&Some(k)) {
                normal_props
                    .iter()
                    .position(|&p| p == Some(k))
                    .map(|i| 3 + i)
            } else if has_uvs && uv_props.contains(&Some(k)) {
                uv_props.iter().position(|&p| p == Some(k)).map(|i| 6 + i)
            } else if has_colors && color_props.contains(&Some(k)) {
                color_props
                    .iter()
                    .position(|&p| p == Some(k))
                    .map(|i| 8 + i)
            } else {
                None
            }
        })
        .collect();
    for (prop, r) in element.props.iter().zip(&role) {
        if r.is_none() {
            out.note_extra(&format!("vertex property `{}`", show(&prop.name)));
        }
    }
    let (ascii, big) = (body.ascii.is_some(), body.big);
    let coding = |ty: Scalar| match ascii {
        true => Coding::Text,
        false => Coding::Binary(ty, big),
    };
    for i in 0..element.count {
        body.begin(i, element.count)?;
        let mut p = [0.0; 3];
        let mut n = [0.0; 3];
        let mut uv = [0.0; 2];
        let mut color = [1.0f32; 4];
        for (prop, r) in element.props.iter().zip(&role) {
            let (Kind::Scalar(ty), Some(r)) = (prop.kind, *r) else {
                body.skip_property(prop.kind)?;
                continue;
            };
            let v = body.value(ty)?;
            if !v.is_finite() {
                let name = String::from_utf8_lossy(&prop.name).into_owned();
                let what = if r < 3 { "coordinate" } else { "value" };
                return Err(body.error(format_args!("{what} {name} is not a finite number")));
            }
            let slot = match r {
                0..3 => {
                    p[r] = v;
                    Slot::Position(i as u32, r as u8)
                }
                3..6 => {
                    n[r - 3] = v;
                    Slot::Normal(i as u32, (r - 3) as u8)
                }
                6..8 => {
                    uv[r - 6] = v;
                    continue;
                }
                _ => {
                    color[r - 8] = (v / ty.color_scale()).clamp(0.0, 1.0) as f32;
                    continue;
                }
            };
            out.patch(Patch {
                bytes: body.last.clone(),
                slot,
                coding: coding(ty),
            });
        }
        body.end()?;
        out.positions.push(p);
        if has_normals {
            out.normals.push(n);
        }
        if has_uvs {
            out.uvs.push(uv);
        }
        if has_colors && out.keeps_whole() {
            out.colors.push(color);
        }
    }
    if has_colors {
        out.note_extra("vertex colours");
    }
    if has_normals {
        out.note_extra("normals (`nx ny nz`)");
    }
    if has_uvs {
        out.note_extra("texture coordinates");
    }
    Ok(())
}

fn read_faces(
    body: &mut Body<'_>,
    element: &Element,
    num_vertices: usize,
    out: &mut Parsed,
) -> Result<()> {
    let (il, count_ty, item_ty) = match element.prop(&[b"vertex_indices", b"vertex_index"]) {
        Some((k, Kind::List(c, i))) => (k, c, i),
        _ => {
            return Err(Error::parse(
                body.path,
                None,
                "the `face` element has no list property `vertex_indices` (or `vertex_index`)",
            ))
        }
    };
    let texcoord = match element.prop(&[b"texcoord"]) {
        Some((k, Kind::List(..))) => Some(k),
        _ => None,
    };
    for (k, prop) in element.props.iter().enumerate() {
        if k != il && Some(k) != texcoord {
            out.note_extra(&format!("face property `{}`", show(&prop.name)));
        }
    }
    let mut face: Vec<u32> = Vec::new();
    let mut corner_uv: Vec<u32> = Vec::new();
    let mut wedge: Vec<f64> = Vec::new();
    for i in 0..element.count {
        body.begin(i, element.count)?;
        wedge.clear();
        for (k, prop) in element.props.iter().enumerate() {
            if Some(k) == texcoord {
                if let Kind::List(c, item) = prop.kind {
                    for _ in 0..body.list_len(c, item)? {
                        wedge.push(body.value(item)?);
                    }
                }
                continue;
            }
            if k != il {
                body.skip_property(prop.kind)?;
                continue;
            }
            let n = body.list_len(count_ty, item_ty)?;
            if n < 3 {
                return Err(body.error(format_args!("a face needs at least 3 vertices, found {n}")));
            }
            face.clear();
            for _ in 0..n {
                let v = body.value(item_ty)?;
                if !(v >= 0.0
                    && v < num_vertices as f64
                    && v <= f64::from(u32::MAX)
                    && v.fract() == 0.0)
                {
                    return Err(body.error(format_args!(
                        "vertex index {v} is out of range: the file has {num_vertices} vertices (indices start at 0)"
                    )));
                }
                face.push(v as u32);
            }
            let collapsed =
                check_corners(&face, |i| format!("vertex {i}")).map_err(|m| body.error(m))?;
            if collapsed {
                out.repeats_in_a_row.push(i as u32);
            }
        }
        body.end()?;
        if texcoord.is_some() {
            if wedge.len() == 2 * face.len() && wedge.iter().all(|x| x.is_finite()) {
                for c in wedge.chunks_exact(2) {
                    corner_uv.push(out.uvs.len() as u32);
                    out.uvs.push([c[0], c[1]]);
                }
            } else {
                corner_uv.extend(std::iter::repeat_n(NONE, face.len()));
            }
        }
        let line = body.ascii.as_ref().map_or(i, Lines::number);
        out.faces.push(&face, line);
    }
    let corners = out.faces.corner_vertices().to_vec();
    if texcoord.is_some() {
        out.corner_uv = corner_uv;
        out.note_extra("texture coordinates");
    } else if !out.uvs.is_empty() {
        out.corner_uv = corners.clone();
    }
    if !out.normals.is_empty() {
        out.corner_normal = corners;
    }
    Ok(())
}

/// Writes a `binary_little_endian` PLY with `double x, y, z` and
/// `list uchar int vertex_indices`.
pub(super) fn write<'a, const D: usize>(
    w: &mut dyn Write,
    positions: &[[f64; D]],
    faces: impl Iterator<Item = &'a [u32]>,
    num_faces: usize,
    extra: &VertexAttributes,
) -> std::io::Result<()> {
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by meshmorph\n\
         element vertex {}\nproperty double x\nproperty double y\nproperty double z\n",
        positions.len(),
    );
    if extra.normals.is_some() {
        header.push_str("property double nx\nproperty double ny\nproperty double nz\n");
    }
    if extra.uvs.is_some() {
        header.push_str("property double s\nproperty double t\n");
    }
    let alpha = extra.has_alpha();
    if extra.colors.is_some() {
        header.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\n");
        if alpha {
            header.push_str("property uchar alpha\n");
        }
    }
    header.push_str(&format!(
        "element face {num_faces}\nproperty list uchar int vertex_indices\n"
    ));
    // Two numbers per corner: counted in a byte (as MeshLab writes them)
    // while faces have at most 127 corners.
    let faces: Vec<&[u32]> = faces.collect();
    let wide_texcoord = faces.iter().any(|f| f.len() > 127);
    if extra.corner_uvs.is_some() {
        header.push_str(if wide_texcoord {
            "property list int float texcoord\n"
        } else {
            "property list uchar float texcoord\n"
        });
    }
    header.push_str("end_header\n");
    w.write_all(header.as_bytes())?;
    let mut buf = Vec::with_capacity(CHUNK + 64);
    for (v, p) in positions.iter().enumerate() {
        let mut put = |x: f64| buf.extend_from_slice(&x.to_le_bytes());
        xyz(p).into_iter().for_each(&mut put);
        if let Some(n) = &extra.normals {
            n[v].into_iter().for_each(&mut put);
        }
        if let Some(uv) = extra.uvs {
            uv[v].into_iter().for_each(&mut put);
        }
        if let Some(c) = extra.colors {
            let k = if alpha { 4 } else { 3 };
            buf.extend(c[v][..k].iter().map(|&x| channel_byte(x)));
        }
        if buf.len() >= CHUNK {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    let invalid = |msg: String| std::io::Error::new(std::io::ErrorKind::InvalidInput, msg);
    let mut corner = 0;
    for face in faces {
        let n = u8::try_from(face.len()).map_err(|_| {
            invalid(format!(
                "a face of {} vertices does not fit a PLY `uchar` count",
                face.len()
            ))
        })?;
        buf.push(n);
        for &i in face {
            let i = i32::try_from(i)
                .map_err(|_| invalid(format!("vertex index {i} does not fit a PLY `int`")))?;
            buf.extend_from_slice(&i.to_le_bytes());
        }
        if let Some((uvs, of_corner)) = extra.corner_uvs {
            let count = 2 * face.len();
            if wide_texcoord {
                buf.extend_from_slice(&(count as i32).to_le_bytes());
            } else {
                buf.push(count as u8);
            }
            for &k in &of_corner[corner..corner + face.len()] {
                for x in uvs[k as usize] {
                    buf.extend_from_slice(&(x as f32).to_le_bytes());
                }
            }
        }
        corner += face.len();
        if buf.len() >= CHUNK {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    w.write_all(&buf)
}
