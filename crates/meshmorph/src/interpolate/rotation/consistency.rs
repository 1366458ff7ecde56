//! Rotation consistency: choosing the branch (whole turns) of every
//! triangle's rotation.
//!
//! `atan2` returns angles in (−π, π]. A part of a shape that turns by more
//! than half a turn gets neighbouring triangles whose principal angles differ
//! by about 2π, and interpolating those angles tears the shape apart. Walking
//! the triangle adjacency from a seed and giving each triangle the branch
//! nearest its neighbour's makes the angle field continuous (Baxter, Barla
//! and Anjyo, "Rigid shape interpolation using normal equations", NPAR 2008,
//! section 4.2). That walk is the plane's branch choice; in space, where
//! errors along a walk add up, the choice is made per patch between jumps
//! ([`super::patches`]). [`consistent_rotations`] is the one entry point:
//! it chooses the seeds, the same way in every dimension, and hands them to
//! the dimension's choice ([`Rotations::choose_branches`]).
//!
//! Which whole number of turns a part as a whole takes is a convention: its
//! seed, the triangle that turns least, keeps its principal rotation (or,
//! for a later key of a sequence, the branch nearest to the previous key's).

use std::collections::VecDeque;

use super::{Rotations, Space};
use crate::linalg::vector::{centroid, norm, sub};
use crate::mesh::topology::TriangleAdjacency;
use crate::mesh::Mesh;

/// The logarithms of `rotations` (the principal rotations of the maps from
/// `rest` to one pose, one per triangle) with branches made consistent over
/// `adjacency` (the rest's), by the dimension's branch choice. `previous`:
/// for a later key of a sequence, the previous key's logarithms and the
/// triangles' areas.
pub fn consistent_rotations<const D: usize>(
    rest: &Mesh<D>,
    adjacency: &TriangleAdjacency,
    rotations: &[<Space<D> as Rotations<D>>::Principal],
    previous: Option<(&[<Space<D> as Rotations<D>>::Log], &[f64])>,
) -> Vec<<Space<D> as Rotations<D>>::Log>
where
    Space<D>: Rotations<D>,
{
    let seeds = rotation_seeds(rest, adjacency, rotations);
    Space::<D>::choose_branches(
        rotations,
        adjacency,
        &|a, b| shared_edge_length(rest, a, b),
        &seeds,
        previous,
    )
}

/// One seed triangle per part connected across edges: the one that turns
/// least, ties broken by the position of its rest centroid, so that the
/// choice does not depend on how the triangles are numbered.
fn rotation_seeds<const D: usize>(
    rest: &Mesh<D>,
    adjacency: &TriangleAdjacency,
    rotations: &[<Space<D> as Rotations<D>>::Principal],
) -> Vec<usize>
where
    Space<D>: Rotations<D>,
{
    let (parts, count) = adjacency.edge_components();
    let key = |t: usize| (Space::<D>::angle(&rotations[t]), centroid(rest.corners(t)));
    // The best triangle so far with its key (angle, centroid).
    type Best<const D: usize> = Option<(usize, (f64, [f64; D]))>;
    let mut best: Vec<Best<D>> = vec![None; count];
    for (t, &c) in parts.iter().enumerate() {
        let k = key(t);
        let slot = &mut best[c as usize];
        if slot.is_none_or(|(_, b)| k.partial_cmp(&b) == Some(std::cmp::Ordering::Less)) {
            *slot = Some((t, k));
        }
    }
    best.into_iter().flatten().map(|(t, _)| t).collect()
}

/// Length of the edge that rest triangles `a` and `b` share (0 if none).
fn shared_edge_length<const D: usize>(rest: &Mesh<D>, a: usize, b: usize) -> f64 {
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

/// Makes the rotations `logs` continuous over the triangle adjacency, in
/// place, with `branch(log, reference)` choosing the branch of a triangle's
/// rotation given the one of the triangle it is reached from (in the plane,
/// the angle nearest to the reference).
///
/// Each seed keeps its rotation; a breadth-first walk from it over the
/// triangles it reaches gives each one the branch `branch` chooses from the
/// triangle it was reached from. Give one seed per part connected across
/// edges; triangles no seed reaches keep their rotations.
///
/// # Panics
/// If there is not one rotation per triangle.
pub fn make_consistent<L>(
    logs: &mut [L],
    adjacency: &TriangleAdjacency,
    seeds: &[usize],
    branch: impl Fn(&L, &L) -> L,
) {
    assert_eq!(logs.len(), adjacency.len(), "one rotation per triangle");
    let mut visited = vec![false; logs.len()];
    let mut queue = VecDeque::new();
    for &seed in seeds {
        if visited[seed] {
            continue;
        }
        visited[seed] = true;
        queue.push_back(seed);
        while let Some(t) = queue.pop_front() {
            for &n in adjacency.of(t) {
                let n = n as usize;
                if !visited[n] {
                    visited[n] = true;
                    logs[n] = branch(&logs[n], &logs[t]);
                    queue.push_back(n);
                }
            }
        }
    }
}
