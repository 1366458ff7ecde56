//! Where a file's normals are used, and what each use becomes in a new
//! shape.
//!
//! An OBJ file indexes its normals, and exporters write each distinct normal
//! once: Blender shares one `vn` among every corner that faces the same way,
//! the corners of a flat face, the corners around a smooth vertex, and also
//! parallel faces and vertices far apart (a flat grid has one `vn`,
//! whether shaded flat or smooth). A new shape turns those apart. So the
//! uses of a normal are grouped: in a face the file shades flat (OBJ's
//! `s off` or `s 0`) the corners of the face are a group; elsewhere the
//! corners at one vertex (a smooth fan). Each group is turned with the faces
//! around it; where the groups of one normal no longer agree, the others
//! than the first get normals of their own, written right after it.
//!
//! In the file's own shape every group agrees with its normal, so nothing is
//! added and the file is written back as it was. Formats with one normal per
//! vertex (PLY, OFF) have one group per normal, so they never add any.

use std::collections::HashMap;

use super::mesh_file::NONE;
use super::triangulate::Polygons;
use crate::linalg::matrix::Mat3;
use crate::linalg::similarity::closest_rotation;
use crate::linalg::vector::{add, corner_angle, cross, dot, least_turn, norm, scale, sub};

/// Turned normals whose coordinates agree to this are one normal: far below
/// what shading shows (exporters round normals to 4 to 6 digits), far above
/// the rounding of a solve that gives back the file's own shape.
const AGREE: f64 = 1e-9;

/// The groups of corners that share a normal (see the module
/// documentation).
#[derive(Clone, Debug, Default)]
pub struct NormalGroups {
    /// The group of each flat corner ([`NONE`] for a corner without a
    /// normal); empty when the file has no normals.
    corner_group: Vec<u32>,
    /// The normal each group uses; groups are numbered in the order of their
    /// first corner, so a normal's first group comes before its others.
    normal_of: Vec<u32>,
    /// Each group's direction in the file's shape: the area-weighted mean
    /// normal of the polygons of its corners (unit, or zero).
    rest_directions: Vec<[f64; 3]>,
    /// The file's positions (empty when the file has no normals).
    rest_positions: Vec<[f64; 3]>,
}

/// The normals of a file in a new shape.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeNormals {
    /// One per normal of the file: its first group's.
    pub normals: Vec<[f64; 3]>,
    /// The normals added after each normal of the file, in file order:
    /// `(normal of the file, new normal)`.
    pub added: Vec<(u32, [f64; 3])>,
    /// The 0-based index each corner's normal has in the written file
    /// (counting the added normals where they stand); empty when nothing is
    /// added and every corner keeps its index.
    pub(super) corner_index: Vec<u32>,
}

impl NormalGroups {
    /// Groups the corners of `faces` by the normal each uses
    /// (`corner_normal`, [`NONE`] for none; empty when the file has none):
    /// per face in the faces `flat_faces` marks (empty: none), per vertex
    /// elsewhere.
    pub fn new(
        faces: &Polygons,
        corner_normal: &[u32],
        flat_faces: &[bool],
        positions: &[[f64; 3]],
    ) -> Self {
        if corner_normal.is_empty() {
            return Self::default();
        }
        let corners = faces.corner_vertices();
        let mut corner_group = vec![NONE; corners.len()];
        let mut normal_of = Vec::new();
        // The first (normal, group) at each vertex, for its smooth corners:
        // nearly every corner finds its group there.
        let mut first_at_vertex = vec![(NONE, NONE); positions.len()];
        // Every other (normal, face or vertex, whether a face) -> group.
        let mut group_of: HashMap<(u32, u32, bool), u32> = HashMap::new();
        for f in 0..faces.len() {
            let flat = flat_faces.get(f).copied().unwrap_or(false);
            // The first (normal, group) of this face, when it is flat.
            let mut first_at_face = (NONE, NONE);
            for c in faces.range(f) {
                let n = corner_normal[c];
                if n == NONE {
                    continue;
                }
                let (first, key) = if flat {
                    (&mut first_at_face, (n, f as u32, true))
                } else {
                    let v = corners[c];
                    (&mut first_at_vertex[v as usize], (n, v, false))
                };
                let mut new_group = || {
                    normal_of.push(n);
                    normal_of.len() as u32 - 1
                };
                corner_group[c] = match *first {
                    (m, g) if m == n => g,
                    (NONE, _) => {
                        let g = new_group();
                        *first = (n, g);
                        g
                    }
                    _ => *group_of.entry(key).or_insert_with(new_group),
                };
            }
        }
        let mut groups = NormalGroups {
            corner_group,
            normal_of,
            rest_directions: Vec::new(),
            rest_positions: Vec::new(),
        };
        groups.rest_directions = groups.directions(faces, positions);
        groups.rest_positions = positions.to_vec();
        groups
    }

    /// The mean polygon normal of each group in `positions`, each corner's
    /// polygon weighing its angle at the corner (unit length, or zero): the
    /// normals Blender and most modellers compute for a shape, so that
    /// normals computed from the file's shape are computed again for the
    /// new one, and the shape of a later key gives back that key's own.
    /// Zero also where the polygons cancel out (to [`AGREE`] of their
    /// weight: the two faces of a double-sided sheet, listed in both
    /// windings), whose direction rounding alone would choose: such a
    /// group's normal turns with its polygons instead
    /// ([`NormalGroups::turns_of_cancelled`]).
    fn directions(&self, faces: &Polygons, positions: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut sums = vec![[0.0; 3]; self.normal_of.len()];
        let mut weights = vec![0.0; self.normal_of.len()];
        if sums.is_empty() {
            return sums;
        }
        for f in 0..faces.len() {
            let range = faces.range(f);
            let vertices = &faces.corner_vertices()[range.clone()];
            let n = newell_normal(vertices, positions);
            let len = norm(n);
            if len == 0.0 {
                continue;
            }
            let unit = scale(n, 1.0 / len);
            let last = vertices.len() - 1;
            for (k, &g) in self.corner_group[range].iter().enumerate() {
                if g != NONE {
                    let [before, after] = beside(k, last);
                    let at = positions[vertices[k] as usize];
                    let (a, b) = (
                        sub(positions[vertices[before] as usize], at),
                        sub(positions[vertices[after] as usize], at),
                    );
                    // In a triangle |a × b| is twice its area at every corner.
                    let sine = if last == 2 { len } else { norm(cross(a, b)) };
                    let angle = corner_angle(sine, dot(a, b));
                    sums[g as usize] = add(sums[g as usize], scale(unit, angle));
                    weights[g as usize] += angle;
                }
            }
        }
        for (s, w) in sums.iter_mut().zip(weights) {
            let len = norm(*s);
            *s = if len > AGREE * w {
                scale(*s, 1.0 / len)
            } else {
                [0.0; 3]
            };
        }
        sums
    }

    /// The file's `normals` for the shape `positions`: each group's normal
    /// turned by the smallest rotation that takes the group's direction from
    /// the file's shape to the new one, then about the new direction by the
    /// turn of the edges around it ([`NormalGroups::twists`]). Authored
    /// normals and hard edges stay as they were relative to the surface, a
    /// rigid motion turns every normal with it, and the file's own shape
    /// gives back its own normals with nothing added.
    pub fn for_shape(
        &self,
        normals: &[[f64; 3]],
        faces: &Polygons,
        positions: &[[f64; 3]],
    ) -> ShapeNormals {
        let now = self.directions(faces, positions);
        let cancelled = self.turns_of_cancelled(faces, positions);
        let twists = self.twists(faces, positions, &now);
        let turned: Vec<[f64; 3]> = (0..self.normal_of.len())
            .map(|g| {
                let normal = normals[self.normal_of[g] as usize];
                match cancelled[g] {
                    Some(turn) => {
                        let t = std::array::from_fn(|i| dot(turn[i], normal));
                        // The file's own shape keeps the file's normal.
                        if norm(sub(t, normal)) <= AGREE * norm(normal) {
                            normal
                        } else {
                            t
                        }
                    }
                    None => about(
                        least_turn(normal, self.rest_directions[g], now[g]),
                        now[g],
                        twists[g],
                    ),
                }
            })
            .collect();
        let mut out = ShapeNormals {
            normals: normals.to_vec(),
            added: Vec::new(),
            corner_index: Vec::new(),
        };
        // Each group's place: the file's normal for a normal's first group
        // and for the groups that still agree with it, else an added one.
        // Groups of one normal that turn alike (to `AGREE` of its length)
        // share it; the others share one added normal per value (to the
        // grid of `AGREE`: at worst one more `vn` line).
        let alike = |a: [f64; 3], b: [f64; 3]| {
            let (d, len) = (norm(sub(a, b)), norm(a).max(norm(b)));
            d <= AGREE * len
        };
        let cell = |v: [f64; 3]| {
            let len = norm(v);
            v.map(|x| {
                if len > 0.0 {
                    (x / (len * AGREE)).round() as i64
                } else {
                    0
                }
            })
        };
        let mut first_group = vec![NONE; normals.len()];
        let mut slot_of_group = vec![None; turned.len()];
        let mut slot_of_value: HashMap<(u32, [i64; 3]), usize> = HashMap::new();
        for (g, &n) in self.normal_of.iter().enumerate() {
            let first = &mut first_group[n as usize];
            if *first == NONE {
                *first = g as u32;
                out.normals[n as usize] = turned[g];
            } else if !alike(turned[g], turned[*first as usize]) {
                let key = (n, cell(turned[g]));
                slot_of_group[g] = Some(*slot_of_value.entry(key).or_insert_with(|| {
                    out.added.push((n, turned[g]));
                    out.added.len() - 1
                }));
            }
        }
        if out.added.is_empty() {
            return out;
        }
        // The added normals stand right after their own, in group order, so
        // the numbers of the file's later normals move up by the count
        // added before them.
        let mut order: Vec<usize> = (0..out.added.len()).collect();
        order.sort_by_key(|&a| out.added[a].0);
        let mut index_of_normal = vec![0u32; normals.len()];
        let mut index_of_added = vec![0u32; out.added.len()];
        let (mut next, mut k) = (0u32, 0);
        for (n, index) in index_of_normal.iter_mut().enumerate() {
            *index = next;
            next += 1;
            while k < order.len() && out.added[order[k]].0 as usize == n {
                index_of_added[order[k]] = next;
                next += 1;
                k += 1;
            }
        }
        out.corner_index = self
            .corner_group
            .iter()
            .map(|&g| match g {
                NONE => NONE,
                g => match slot_of_group[g as usize] {
                    Some(a) => index_of_added[a],
                    None => index_of_normal[self.normal_of[g as usize] as usize],
                },
            })
            .collect();
        out.added = order.iter().map(|&a| out.added[a]).collect();
        out
    }
}

impl NormalGroups {
    /// For each group, the turn (cosine and sine, not normalised) about its
    /// direction in `positions` (`now`) that the edges at its corners make
    /// beyond the smallest rotation of the group's direction: the sum over
    /// its corners of the angle from the file's edge to the corner's next
    /// vertex, turned by that smallest rotation, to the same edge now, both
    /// seen along the new direction. The smallest rotation alone does not
    /// turn about the direction, so an authored normal that leans off it
    /// (a weighted normal, a hard edge's) would turn differently from the
    /// surface under a rigid motion; with the twist it turns with it. For
    /// the file's own shape every twist is exactly none.
    fn twists(&self, faces: &Polygons, positions: &[[f64; 3]], now: &[[f64; 3]]) -> Vec<[f64; 2]> {
        let mut sums = vec![[0.0; 2]; self.normal_of.len()];
        let rest = &self.rest_positions;
        if sums.is_empty() {
            return sums;
        }
        for f in 0..faces.len() {
            let range = faces.range(f);
            let vertices = &faces.corner_vertices()[range.clone()];
            let last = vertices.len() - 1;
            for (k, &g) in self.corner_group[range].iter().enumerate() {
                if g == NONE {
                    continue;
                }
                let (g, d) = (g as usize, now[g as usize]);
                if norm(d) == 0.0 || self.rest_directions[g] == [0.0; 3] {
                    continue;
                }
                let (at, next) = (vertices[k] as usize, vertices[beside(k, last)[1]] as usize);
                let on_plane = |v: [f64; 3]| sub(v, scale(d, dot(v, d)));
                let was = on_plane(least_turn(
                    sub(rest[next], rest[at]),
                    self.rest_directions[g],
                    d,
                ));
                let is = on_plane(sub(positions[next], positions[at]));
                sums[g][0] += dot(was, is);
                sums[g][1] += dot(d, cross(was, is));
            }
        }
        sums
    }

    /// For each group whose polygons cancel out in the file's shape (no
    /// direction to turn from), the rotation that best takes its polygons
    /// from the file's shape to `positions`: the nearest rotation to the sum
    /// over its corners of `e' eᵀ` for the two edges at the corner (divided
    /// by their length in the file) and of `n' nᵀ` for the unit normal of the
    /// corner's polygon. `None` for the other groups. A rigid motion turns
    /// such a normal with everything else.
    fn turns_of_cancelled(&self, faces: &Polygons, positions: &[[f64; 3]]) -> Vec<Option<Mat3>> {
        let mut sums: Vec<Option<Mat3>> = vec![None; self.normal_of.len()];
        let rest = &self.rest_positions;
        if !self.rest_directions.contains(&[0.0; 3]) {
            return sums;
        }
        let unit = |n: [f64; 3]| {
            let len = norm(n);
            if len > 0.0 {
                scale(n, 1.0 / len)
            } else {
                n
            }
        };
        let cancelled = |g: u32| g != NONE && self.rest_directions[g as usize] == [0.0; 3];
        for f in 0..faces.len() {
            let range = faces.range(f);
            // Only the few polygons around such groups are looked at.
            if !self.corner_group[range.clone()]
                .iter()
                .any(|&g| cancelled(g))
            {
                continue;
            }
            let vertices = &faces.corner_vertices()[range.clone()];
            let (n0, n1) = (
                unit(newell_normal(vertices, rest)),
                unit(newell_normal(vertices, positions)),
            );
            let last = vertices.len() - 1;
            for (k, &g) in self.corner_group[range].iter().enumerate() {
                if !cancelled(g) {
                    continue;
                }
                let sum = sums[g as usize].get_or_insert([[0.0; 3]; 3]);
                let mut add_outer = |a: [f64; 3], b: [f64; 3]| {
                    for i in 0..3 {
                        for j in 0..3 {
                            sum[i][j] += a[i] * b[j];
                        }
                    }
                };
                let at = vertices[k] as usize;
                for other in beside(k, last) {
                    // Each edge in units of its length in the file, as the
                    // unit normals: the same sum in any units.
                    let other = vertices[other] as usize;
                    let e = sub(rest[other], rest[at]);
                    let len = norm(e);
                    if len > 0.0 {
                        add_outer(
                            scale(sub(positions[other], positions[at]), 1.0 / len),
                            scale(e, 1.0 / len),
                        );
                    }
                }
                add_outer(n1, n0);
            }
        }
        sums.into_iter()
            .map(|s| s.map(|s| closest_rotation(&s)))
            .collect()
    }
}

/// `v` turned about the unit `axis` by the angle whose cosine and sine are
/// proportional to `turn` (unchanged for no turn, or an undefined one).
fn about(v: [f64; 3], axis: [f64; 3], turn: [f64; 2]) -> [f64; 3] {
    let r = turn[0].hypot(turn[1]);
    if turn[1] == 0.0 || !(r > 0.0 && r.is_finite()) {
        return v;
    }
    let (c, s) = (turn[0] / r, turn[1] / r);
    // Rodrigues: v c + (a × v) s + a (a·v)(1 − c).
    add(
        add(scale(v, c), scale(cross(axis, v), s)),
        scale(axis, dot(axis, v) * (1.0 - c)),
    )
}

/// The corners before and after corner `k` of a polygon whose last corner
/// is `last`.
fn beside(k: usize, last: usize) -> [usize; 2] {
    [
        if k == 0 { last } else { k - 1 },
        if k == last { 0 } else { k + 1 },
    ]
}

/// Twice the area vector of a polygon (Newell's formula).
fn newell_normal(vertices: &[u32], positions: &[[f64; 3]]) -> [f64; 3] {
    let mut n = [0.0; 3];
    let origin = positions[vertices[0] as usize];
    for k in 1..vertices.len().saturating_sub(1) {
        let a = sub(positions[vertices[k] as usize], origin);
        let b = sub(positions[vertices[k + 1] as usize], origin);
        n = add(n, cross(a, b));
    }
    n
}
