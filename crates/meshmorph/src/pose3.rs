//! The per-triangle maps from a rest surface to its poses, decomposed into
//! rotations and stretches, and the checks a pose must pass.
#![allow(non_snake_case)]

use rayon::prelude::*;

use crate::error::{Error, Result, LIST_LIMIT};
use crate::geometry::{centroid, cross, dot, norm, sub};
use crate::gradient::spatial::{deformation_gradient, frame};
use crate::matrix::{identity, inverse3, Mat3};
use crate::mesh::Mesh3;
use crate::polar3::polar_decomposition3;
use crate::rotation3::{quat_from_matrix, Quat};
use crate::topology::TriangleAdjacency;

/// What every pose of one rest surface shares: the triangle adjacency.
#[derive(Debug)]
pub(crate) struct RestFrames {
    pub adjacency: TriangleAdjacency,
}

/// A pose's rotations (principal quaternions, scalar part ≥ 0) and
/// symmetric stretches `S` with `A = R S`.
#[derive(Debug)]
pub(crate) struct PoseMaps {
    pub rotations: Vec<Quat>,
    pub stretches: Vec<Mat3>,
}

impl RestFrames {
    /// # Errors
    /// [`Error::DegenerateTriangles`] naming zero-area triangles of `rest`
    /// (called `name`).
    pub fn new(rest: &Mesh3, name: &str) -> Result<Self> {
        rest.check_no_degenerate_triangles(name)?;
        Ok(Self {
            adjacency: TriangleAdjacency::new(rest.triangles()),
        })
    }

    /// The maps from `rest` to `pose` (called `name`), decomposed (in
    /// parallel).
    ///
    /// # Errors
    /// [`Error::InvalidTriangle`] for the first triangle whose map is too
    /// large to decompose in floating point (its squares overflow): a pose
    /// far larger than the rest.
    pub fn decompose(&self, rest: &Mesh3, pose: &Mesh3, name: &str) -> Result<PoseMaps> {
        let (rotations, stretches): (Vec<Quat>, Vec<Mat3>) = (0..pose.num_triangles())
            .into_par_iter()
            .map(|t| {
                let inverse = inverse3(frame(rest.corners(t))).unwrap_or(identity());
                let p = polar_decomposition3(deformation_gradient(inverse, pose.corners(t)));
                (quat_from_matrix(&p.rotation), p.stretch)
            })
            .unzip();
        let finite = |t: &usize| {
            rotations[*t]
                .iter()
                .chain(stretches[*t].iter().flatten())
                .all(|x| x.is_finite())
        };
        if let Some(t) = (0..rotations.len()).find(|t| !finite(t)) {
            return Err(Error::InvalidTriangle {
                triangle: t,
                message: format!(
                    "the {name}'s triangle {t} overflows: its map from the first mesh exceeds the range of floating-point numbers; scale the meshes down"
                ),
            });
        }
        let rotations = self.orient_half_turns(rotations);
        Ok(PoseMaps {
            rotations,
            stretches,
        })
    }

    /// A rotation by exactly half a turn has two principal quaternions,
    /// `(0, ±v)`, and which one rounding gives decides on which side of a
    /// half-turn jump the triangle falls (see [`crate::consistency3`]).
    /// Triangles within `1e-12` of a half turn take the sign that agrees
    /// with most of their neighbours (the rotation moves by at most `4e-12`
    /// radians), so that a ring of them turning by exactly half a turn
    /// joins its neighbours rather than splitting at random.
    fn orient_half_turns(&self, mut rotations: Vec<Quat>) -> Vec<Quat> {
        let flips: Vec<usize> = (0..rotations.len())
            .filter(|&t| {
                rotations[t][0].abs() < 1e-12 && {
                    let agree: f64 = self
                        .adjacency
                        .of(t)
                        .iter()
                        .map(|&u| crate::rotation3::quat_dot(rotations[t], rotations[u as usize]))
                        .sum();
                    agree < 0.0
                }
            })
            .collect();
        for t in flips {
            let q = rotations[t];
            rotations[t] = [q[0].abs(), -q[1], -q[2], -q[3]];
        }
        rotations
    }

    /// Triangles of `positions` turned over relative to the rest: collapsed
    /// to (numerically) zero area, or folded back through their neighbours.
    /// A triangle has folded through a neighbour when the signed dihedral
    /// angle of their shared edge has passed a half turn on the shortest way
    /// from its rest value (the two triangles went through each other); it
    /// is turned over when that holds for more than half of its shared edges
    /// (weighted by their rest lengths). In the plane this is a triangle
    /// whose orientation reversed (its normal opposite to its neighbours');
    /// in space it is the same thing relative to its surroundings (a single
    /// triangle in space can always be turned rigidly, so only its
    /// neighbours tell whether it was turned over). A hinge that closes, even
    /// to a sharp fold, is not turned over.
    pub fn turned_over(&self, rest: &Mesh3, positions: &[[f64; 3]]) -> Vec<usize> {
        let pose_normals = raw_normals(positions, rest.triangles());
        let rest_normals = raw_normals(rest.positions(), rest.triangles());
        let diagonal = crate::mesh::bounding_box_diagonal(positions);
        let tiny = 2e-14 * diagonal * diagonal;
        let limit = std::f64::consts::PI * (1.0 - 1e-9);
        (0..pose_normals.len())
            .into_par_iter()
            .filter(|&t| {
                let area2 = norm(pose_normals[t]);
                if area2.is_nan() || area2 <= tiny {
                    return true;
                }
                let (mut through, mut total) = (0.0, 0.0);
                for &u in self.adjacency.of(t) {
                    let u = u as usize;
                    let Some([a, b]) = shared_edge(rest.triangles()[t], rest.triangles()[u]) else {
                        continue;
                    };
                    let w = norm(sub(
                        rest.positions()[b as usize],
                        rest.positions()[a as usize],
                    ));
                    total += w;
                    let dihedral = |n: &[[f64; 3]], p: &[[f64; 3]]| {
                        let e = sub(p[b as usize], p[a as usize]);
                        let c = cross(n[t], n[u]);
                        dot(c, e).atan2(dot(n[t], n[u]) * norm(e))
                    };
                    let at_rest = dihedral(&rest_normals, rest.positions());
                    let change = wrap(dihedral(&pose_normals, positions) - at_rest);
                    if (at_rest + change).abs() >= limit {
                        through += w;
                    }
                }
                through > 0.5 * total
            })
            .collect()
    }

    /// Fails when `pose` has triangles turned over relative to the rest.
    pub fn check_pose(&self, rest: &Mesh3, pose: &Mesh3, name: &str) -> Result<()> {
        let bad = self.turned_over(rest, pose.positions());
        if bad.is_empty() {
            return Ok(());
        }
        Err(Error::ReflectedTriangles {
            mesh: name.into(),
            count: bad.len(),
            first: bad.into_iter().take(LIST_LIMIT).collect(),
        })
    }

    /// One seed triangle per part connected across edges: the one whose
    /// rotation is the smallest, ties broken by the position of its rest
    /// centroid, so that the choice does not depend on numbering.
    pub fn seeds(&self, rest: &Mesh3, rotations: &[Quat]) -> Vec<usize> {
        let (parts, count) = self.adjacency.edge_components();
        let key = |t: usize| {
            let c = centroid(rest.corners(t));
            // A smaller angle is a larger scalar part.
            (-rotations[t][0].abs(), c[0], c[1], c[2])
        };
        type Best = Option<(usize, (f64, f64, f64, f64))>;
        let mut best: Vec<Best> = vec![None; count];
        for (t, &c) in parts.iter().enumerate() {
            let k = key(t);
            let slot = &mut best[c as usize];
            if slot.is_none_or(|(_, b)| k.partial_cmp(&b) == Some(std::cmp::Ordering::Less)) {
                *slot = Some((t, k));
            }
        }
        best.into_iter().flatten().map(|(t, _)| t).collect()
    }
}

/// Twice the area vector of every triangle.
fn raw_normals(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<[f64; 3]> {
    triangles
        .iter()
        .map(|&[a, b, c]| {
            let (a, b, c) = (
                positions[a as usize],
                positions[b as usize],
                positions[c as usize],
            );
            cross(sub(b, a), sub(c, a))
        })
        .collect()
}

/// An angle moved into (−π, π].
fn wrap(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let w = a - TAU * (a / TAU).round();
    if w <= -PI {
        w + TAU
    } else {
        w
    }
}

/// The edge triangles `ta` and `tb` share, in `ta`'s winding order.
fn shared_edge(ta: [u32; 3], tb: [u32; 3]) -> Option<[u32; 2]> {
    (0..3)
        .map(|k| [ta[k], ta[(k + 1) % 3]])
        .find(|[a, b]| tb.contains(a) && tb.contains(b))
}

/// Length of the edge that rest triangles `a` and `b` share (0 if none).
pub(crate) fn shared_edge_length(rest: &Mesh3, a: usize, b: usize) -> f64 {
    let (ta, tb) = (rest.triangles()[a], rest.triangles()[b]);
    let mut shared = ta.iter().filter(|v| tb.contains(v));
    match (shared.next(), shared.next()) {
        (Some(&u), Some(&v)) => norm(sub(
            rest.positions()[u as usize],
            rest.positions()[v as usize],
        )),
        _ => 0.0,
    }
}
