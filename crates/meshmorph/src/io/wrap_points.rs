//! Wrap's (Faceform's) points on triangles, `.json`: a list
//! `[[42, 0.3, 0.5], [1337, 0.0, 1.0]]` ("Point On Triangle") or an object
//! of named points `{"Point01": [0, 0.3, 0.5], ...}` ("Named Point On
//! Triangle"), one file for each mesh. `[t, u, v]` is the point
//! `u A + v B + (1 - u - v) C` of triangle `t` (0-based) with corners
//! `A B C`, that is barycentric coordinates `(u, v, 1 - u - v)`.
//!
//! Wrap numbers the triangles of a fan over each polygon from its first
//! vertex, in the order of the faces. meshmorph numbers a triangle mesh's
//! triangles as the file lists its faces, the same numbers on a mesh of
//! triangles only; but it splits a quad along its shorter diagonal and a
//! larger polygon by ear clipping, so on a mesh with quads or polygons the
//! numbers differ: export such a mesh as triangles for Wrap and meshmorph
//! alike (the command line refuses a Wrap file for a mesh with polygons).
//! Names, as every JSON object's keys, are kept in the file's order.

use std::fmt;
use std::path::Path;

use serde::de::{Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};

use crate::error::{Error, Result};
use crate::io::marker_points::{Entry, PointList};
use crate::mesh::surface_point::SurfacePoint;
use crate::transfer::markers::Side;

/// A Wrap file as it is: its points in order, named or not.
struct WrapPoints(Vec<(Option<String>, Vec<f64>)>);

impl<'de> Deserialize<'de> for WrapPoints {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Points;
        impl<'de> Visitor<'de> for Points {
            type Value = WrapPoints;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a list of [triangle, u, v] or an object of named [triangle, u, v]")
            }
            fn visit_seq<A: SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> std::result::Result<WrapPoints, A::Error> {
                let mut out = Vec::new();
                while let Some(p) = seq.next_element::<Vec<f64>>()? {
                    out.push((None, p));
                }
                Ok(WrapPoints(out))
            }
            fn visit_map<A: MapAccess<'de>>(
                self,
                mut map: A,
            ) -> std::result::Result<WrapPoints, A::Error> {
                let mut out = Vec::new();
                while let Some((name, p)) = map.next_entry::<String, Vec<f64>>()? {
                    out.push((Some(name), p));
                }
                Ok(WrapPoints(out))
            }
        }
        d.deserialize_any(Points)
    }
}

/// The points of a Wrap file; each is named in messages by its place in
/// the file (1-based) and its name.
pub fn parse(text: &str, path: &Path) -> Result<PointList> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let points: WrapPoints = serde_json::from_str(text).map_err(|e| {
        Error::parse(
            path,
            Some(e.line()),
            format!("not a Wrap point file (JSON of [triangle, u, v]): {e}"),
        )
    })?;
    let mut entries = Vec::with_capacity(points.0.len());
    for (k, (name, p)) in points.0.into_iter().enumerate() {
        let place = k + 1;
        let bad = |msg: String| {
            let which = match &name {
                Some(n) => format!("point {place} (`{n}`)"),
                None => format!("point {place}"),
            };
            Error::parse(path, None, format!("{which}: {msg}"))
        };
        let &[t, u, v] = p.as_slice() else {
            return Err(bad(format!(
                "expected [triangle, u, v], found {} number{}",
                p.len(),
                if p.len() == 1 { "" } else { "s" }
            )));
        };
        if !(t >= 0.0 && t.fract() == 0.0 && t < f64::from(u32::MAX)) {
            return Err(bad(format!("`{t}` is not a triangle index")));
        }
        let point = SurfacePoint::Triangle {
            triangle: t as u32,
            barycentric: [u, v, 1.0 - u - v],
        };
        let point = point
            .normalized()
            .map_err(|problem| bad(format!("u {u} and v {v}: {problem}")))?;
        entries.push(Entry {
            name,
            side: Side::On(point),
            place,
            active: true,
        });
    }
    Ok(PointList {
        path: path.to_path_buf(),
        unit: "point",
        first_index: 0,
        entries,
    })
}
