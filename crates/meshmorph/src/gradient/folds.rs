//! Triangles of a surface turned over relative to its rest shape: the
//! signed dihedral angles of the rest surface, computed once, and each
//! pose's triangles that collapsed or folded back through their
//! neighbours.

use rayon::prelude::*;

use crate::linalg::vector::{cross, dot, norm, sub};
use crate::mesh::topology::TriangleAdjacency;
use crate::mesh::Mesh3;

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
pub(crate) fn turned_over_in_space(
    rest: &Mesh3,
    adjacency: &TriangleAdjacency,
    folds: &RestDihedrals,
    positions: &[[f64; 3]],
) -> Vec<usize> {
    assert_eq!(
        folds.0.len(),
        adjacency.offset(adjacency.len()),
        "rest folds of another adjacency"
    );
    let pose_normals = raw_normals(positions, rest.triangles());
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
            let at_rest = &folds.0[adjacency.offset(t)..];
            for (&u, &at_rest) in adjacency.of(t).iter().zip(at_rest) {
                let u = u as usize;
                let Some([a, b]) = shared_edge(rest.triangles()[t], rest.triangles()[u]) else {
                    continue;
                };
                let w = norm(sub(
                    rest.positions()[b as usize],
                    rest.positions()[a as usize],
                ));
                total += w;
                let change = wrap(dihedral(&pose_normals, positions, [t, u], [a, b]) - at_rest);
                if (at_rest + change).abs() >= limit {
                    through += w;
                }
            }
            through > 0.5 * total
        })
        .collect()
}

/// The signed dihedral angle of every pair of neighbouring triangles of a
/// rest surface, in the order of its [`TriangleAdjacency`] (0 where they
/// share no edge, only a vertex): what [`turned_over_in_space`] compares
/// each pose with, computed once.
#[derive(Clone, Debug)]
pub struct RestDihedrals(Vec<f64>);

impl RestDihedrals {
    pub(crate) fn new(rest: &Mesh3, adjacency: &TriangleAdjacency) -> Self {
        let normals = raw_normals(rest.positions(), rest.triangles());
        let angles = (0..rest.num_triangles())
            .into_par_iter()
            .flat_map_iter(|t| {
                let (normals, tris) = (&normals, rest.triangles());
                adjacency.of(t).iter().map(move |&u| {
                    let u = u as usize;
                    shared_edge(tris[t], tris[u]).map_or(0.0, |edge| {
                        dihedral(normals, rest.positions(), [t, u], edge)
                    })
                })
            })
            .collect();
        Self(angles)
    }
}

/// The signed dihedral angle between triangles `t` and `u` (of the given
/// `normals`, twice their area vectors) across their shared edge `[a, b]`.
#[inline]
fn dihedral(
    normals: &[[f64; 3]],
    positions: &[[f64; 3]],
    [t, u]: [usize; 2],
    [a, b]: [u32; 2],
) -> f64 {
    let e = sub(positions[b as usize], positions[a as usize]);
    let c = cross(normals[t], normals[u]);
    dot(c, e).atan2(dot(normals[t], normals[u]) * norm(e))
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
