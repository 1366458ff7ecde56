//! Faces as read from a file (polygons of any size) and their
//! triangulation.
//!
//! A polygon is projected onto its best-fit plane (the plane through its
//! first vertex orthogonal to the Newell normal, i.e. the polygon's area
//! vector) and triangulated there by ear clipping, preferring the
//! best-shaped ear at each step. The triangles keep the polygon's
//! orientation. A convex quad is simply split along its shorter diagonal.
//! Should ear clipping get stuck (a self-intersecting or degenerate
//! polygon), what is left of the polygon is triangulated as a fan.

use crate::linalg::vector::{cross, dot, norm, scale, sub};

/// Faces of any size, stored flat, with the line each came from.
#[derive(Clone, Debug, Default)]
pub struct Polygons {
    indices: Vec<u32>,
    /// End of each face in `indices`.
    ends: Vec<usize>,
    /// Line (or instance number, for binary files) of each face.
    lines: Vec<usize>,
}

impl Polygons {
    /// An empty list with room for about `faces` triangles.
    pub(super) fn with_capacity(faces: usize) -> Self {
        Polygons {
            indices: Vec::with_capacity(3 * faces),
            ends: Vec::with_capacity(faces),
            lines: Vec::with_capacity(faces),
        }
    }

    /// Adds a face (at least three distinct indices; the caller checks).
    #[inline]
    pub fn push(&mut self, face: &[u32], line: usize) {
        self.indices.extend_from_slice(face);
        self.ends.push(self.indices.len());
        self.lines.push(line);
    }

    /// Number of faces.
    pub(super) fn len(&self) -> usize {
        self.ends.len()
    }

    /// Face `f`'s corners as `start..end` in the flat corner list.
    pub(super) fn range(&self, f: usize) -> std::ops::Range<usize> {
        let start = if f == 0 { 0 } else { self.ends[f - 1] };
        start..self.ends[f]
    }

    /// The vertex of every corner, face after face.
    pub(super) fn corner_vertices(&self) -> &[u32] {
        &self.indices
    }

    /// The line (or instance) face `f` came from.
    pub(super) fn line(&self, f: usize) -> usize {
        self.lines[f]
    }

    /// Triangulates every face once (every index must be in range of
    /// `positions`): the triangles, and for each its face and the flat
    /// corner (index into [`Polygons::corner_vertices`]) of each of its
    /// vertices.
    pub(super) fn triangulate(&self, positions: &[[f64; 3]]) -> Split {
        let capacity = self.indices.len().saturating_sub(2 * self.ends.len());
        let mut split = Split {
            triangles: Vec::with_capacity(capacity),
            face: Vec::with_capacity(capacity),
            corners: Vec::with_capacity(capacity),
        };
        let mut local = Vec::new();
        let mut distinct = Vec::new();
        for f in 0..self.len() {
            let range = self.range(f);
            let face = &self.indices[range.clone()];
            local.clear();
            if repeats_in_a_row(face) {
                without_repeats_in_a_row(face, &mut distinct);
                triangulate_polygon(positions, &distinct, &mut local);
            } else {
                triangulate_polygon(positions, face, &mut local);
            }
            for t in &local {
                // The corners of one face are distinct vertices but for
                // repeats in a row (checked by the readers), so each vertex
                // names its first corner.
                let corner = t.map(|v| {
                    let k = face.iter().position(|&w| w == v).unwrap_or(0);
                    (range.start + k) as u32
                });
                split.triangles.push(*t);
                split.face.push(f as u32);
                split.corners.push(corner);
            }
        }
        split
    }
}

/// The triangles of a split of polygons, with where each came from.
#[derive(Clone, Debug)]
pub(super) struct Split {
    pub(super) triangles: Vec<[u32; 3]>,
    /// The face of each triangle.
    pub(super) face: Vec<u32>,
    /// The flat corner of each triangle vertex.
    pub(super) corners: Vec<[u32; 3]>,
}

/// Whether `face` repeats a vertex in a row, cyclically (`4 5 6 6 7`, or
/// `4 5 6 4`): a corner of no length, which modellers and scan tools leave
/// and readers drop.
#[inline]
pub(super) fn repeats_in_a_row(face: &[u32]) -> bool {
    face.len() > 1 && (face.windows(2).any(|w| w[0] == w[1]) || face.first() == face.last())
}

/// `face` without the vertices that repeat the one before them (cyclically:
/// the last ones that repeat the first too), the first corner kept first.
pub(super) fn without_repeats_in_a_row(face: &[u32], out: &mut Vec<u32>) {
    out.clear();
    for &v in face {
        if out.last() != Some(&v) {
            out.push(v);
        }
    }
    while out.len() > 1 && out.last() == out.first() {
        out.pop();
    }
}

/// Checks the corners of a face as readers take it: a vertex repeated in a
/// row is dropped (`Ok(true)`), any other repeat is refused with its
/// message, as is a face of fewer than 3 distinct vertices; `vertex`
/// names a vertex in messages (`vertex 15 (1-based)` in OBJ).
pub(super) fn check_corners(face: &[u32], vertex: impl Fn(u32) -> String) -> Result<bool, String> {
    let collapsed = repeats_in_a_row(face);
    let mut distinct = Vec::new();
    let corners = if collapsed {
        without_repeats_in_a_row(face, &mut distinct);
        &distinct[..]
    } else {
        face
    };
    if let Some(i) = repeated_index(corners) {
        return Err(format!(
            "the face uses {} more than once, not in a row",
            vertex(i)
        ));
    }
    if corners.len() < 3 {
        let repeated = (0..face.len())
            .find(|&k| face[k] == face[(k + 1) % face.len()])
            .map_or(face[0], |k| face[k]);
        return Err(format!(
            "the face uses {} more than once: it has {} distinct vertices, and a face needs at least 3",
            vertex(repeated),
            corners.len()
        ));
    }
    Ok(collapsed)
}

/// The first index that occurs twice in `face`, if any.
pub fn repeated_index(face: &[u32]) -> Option<u32> {
    if face.len() <= 16 {
        (1..face.len()).find_map(|i| face[..i].contains(&face[i]).then_some(face[i]))
    } else {
        let mut sorted = face.to_vec();
        sorted.sort_unstable();
        sorted.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
    }
}

/// A quad split into two triangles one way and into two the other way:
/// when `reference` and `other` are each two triangles over the same four
/// vertices, sharing different diagonals, the quad's corners in order
/// around it (starting so that `reference[0]`'s corners keep their order).
/// `None` for anything else (other vertices, the same split, or faces that
/// are not triangles).
pub(super) fn quad_split_the_other_way(
    reference: [&[u32]; 2],
    other: [&[u32]; 2],
) -> Option<[u32; 4]> {
    let triangle = |f: &[u32]| <[u32; 3]>::try_from(f).ok();
    let [a, b] = reference.map(triangle);
    let [c, d] = other.map(triangle);
    let (a, b, c, d) = (a?, b?, c?, d?);
    // The diagonal `a` shares with `b`: its edge from `a[i]` to `a[i + 1]`.
    let i = (0..3).find(|&i| b.contains(&a[i]) && b.contains(&a[(i + 1) % 3]))?;
    let opposite = *b.iter().find(|v| !a.contains(v))?;
    let quad = [a[(i + 1) % 3], a[(i + 2) % 3], a[i], opposite];
    // `a` and `b` share the diagonal `quad[0]`-`quad[2]`; the other split is
    // two triangles sharing `quad[1]`-`quad[3]`, one with `quad[0]`, one
    // with `quad[2]`.
    let in_quad = |t: [u32; 3]| t.iter().all(|v| quad.contains(v));
    let other_diagonal = |t: [u32; 3]| t.contains(&quad[1]) && t.contains(&quad[3]);
    let distinct = |t: [u32; 3]| t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
    let splits_other_way = [c, d]
        .iter()
        .all(|&t| in_quad(t) && distinct(t) && other_diagonal(t))
        && (c.contains(&quad[0]) != d.contains(&quad[0]));
    splits_other_way.then_some(quad)
}

/// Above this many vertices ear clipping takes the first ear it finds
/// instead of the best-shaped one (which costs `O(n^3)`).
const BEST_EAR_LIMIT: usize = 64;

/// Above this many vertices a polygon is triangulated as a fan: ear clipping
/// costs `O(n^2)` or worse, and no real mesh has such faces (a malformed
/// file must not hang the reader).
pub const EAR_CLIPPING_LIMIT: usize = 2048;

/// Appends triangles covering the polygon `poly` (indices into `positions`,
/// at least three, distinct and in range) with the polygon's orientation.
pub fn triangulate_polygon(positions: &[[f64; 3]], poly: &[u32], out: &mut Vec<[u32; 3]>) {
    let n = poly.len();
    if n < 3 {
        return;
    }
    if n == 3 {
        out.push([poly[0], poly[1], poly[2]]);
        return;
    }
    if n > EAR_CLIPPING_LIMIT {
        fan(poly, &(0..n).collect::<Vec<_>>(), out);
        return;
    }
    let origin = positions[poly[0] as usize];
    let p3: Vec<[f64; 3]> = poly
        .iter()
        .map(|&i| sub(positions[i as usize], origin))
        .collect();
    let Some((u, v)) = plane_basis(&p3) else {
        fan(poly, &(0..n).collect::<Vec<_>>(), out);
        return;
    };
    let p: Vec<[f64; 2]> = p3.iter().map(|&q| [dot(q, u), dot(q, v)]).collect();

    if n == 4 && (0..4).all(|k| turn(p[(k + 3) % 4], p[k], p[(k + 1) % 4]) > 0.0) {
        // Convex quad: the shorter diagonal.
        if norm(sub(p3[2], p3[0])) <= norm(sub(p3[3], p3[1])) {
            out.extend([[poly[0], poly[1], poly[2]], [poly[0], poly[2], poly[3]]]);
        } else {
            out.extend([[poly[1], poly[2], poly[3]], [poly[1], poly[3], poly[0]]]);
        }
        return;
    }

    let mut left: Vec<usize> = (0..n).collect();
    // Where the search for the first ear starts (large polygons): just
    // before the last ear clipped, so that a pass costs O(n) typically.
    let mut start = 0;
    while left.len() > 3 {
        let m = left.len();
        let mut best: Option<(usize, f64)> = None;
        for k in (0..m).map(|k| (k + start) % m) {
            let (a, b, c) = (left[(k + m - 1) % m], left[k], left[(k + 1) % m]);
            if turn(p[a], p[b], p[c]) <= 0.0 {
                continue; // reflex or flat
            }
            let blocked = left
                .iter()
                .any(|&j| j != a && j != b && j != c && in_triangle(p[j], p[a], p[b], p[c]));
            if blocked {
                continue;
            }
            let q = shape_quality(p[a], p[b], p[c]);
            if best.is_none_or(|(_, bq)| q > bq) {
                best = Some((k, q));
            }
            if m > BEST_EAR_LIMIT {
                break;
            }
        }
        let Some((k, _)) = best else {
            fan(poly, &left, out);
            return;
        };
        out.push([
            poly[left[(k + m - 1) % m]],
            poly[left[k]],
            poly[left[(k + 1) % m]],
        ]);
        left.remove(k);
        start = k.saturating_sub(1);
    }
    out.push([poly[left[0]], poly[left[1]], poly[left[2]]]);
}

/// An orthonormal basis `(u, v)` of the plane orthogonal to the polygon's
/// Newell normal, with `u × v` along the normal (so the polygon winds
/// counter-clockwise in `(u, v)` coordinates); `None` for a polygon of zero
/// area.
fn plane_basis(p: &[[f64; 3]]) -> Option<([f64; 3], [f64; 3])> {
    let mut normal = [0.0; 3];
    for k in 0..p.len() {
        let c = cross(p[k], p[(k + 1) % p.len()]);
        normal = [normal[0] + c[0], normal[1] + c[1], normal[2] + c[2]];
    }
    let len = norm(normal);
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    let nrm = scale(normal, 1.0 / len);
    // The coordinate axis least aligned with the normal.
    let axis = (0..3)
        .min_by(|&i, &j| nrm[i].abs().total_cmp(&nrm[j].abs()))
        .unwrap_or(0);
    let mut e = [0.0; 3];
    e[axis] = 1.0;
    let u = cross(nrm, e);
    let u = scale(u, 1.0 / norm(u));
    let v = cross(nrm, u);
    Some((u, v))
}

/// Twice the signed area of `abc`: positive for a left turn.
#[inline]
pub fn turn(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether `q` lies inside or on the counter-clockwise triangle `abc`.
#[inline]
fn in_triangle(q: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    turn(a, b, q) >= 0.0 && turn(b, c, q) >= 0.0 && turn(c, a, q) >= 0.0
}

/// Area over the sum of squared edge lengths, scaled to 1 for an
/// equilateral triangle.
fn shape_quality(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    let sq = |x: [f64; 2], y: [f64; 2]| (x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2);
    2.0 * 3f64.sqrt() * turn(a, b, c) / (sq(a, b) + sq(b, c) + sq(c, a))
}

/// A fan over the polygon vertices `left` (positions in `poly`).
fn fan(poly: &[u32], left: &[usize], out: &mut Vec<[u32; 3]>) {
    for k in 1..left.len().saturating_sub(1) {
        out.push([poly[left[0]], poly[left[k]], poly[left[k + 1]]]);
    }
}
