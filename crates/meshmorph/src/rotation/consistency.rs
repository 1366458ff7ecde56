//! Rotation consistency: choosing the branch (whole turns) of every
//! triangle's rotation.
//!
//! `atan2` returns angles in (−π, π]. A part of a shape that turns by more
//! than half a turn gets neighbouring triangles whose principal angles differ
//! by about 2π, and interpolating those angles tears the shape apart. Walking
//! the triangle adjacency from a seed and giving each triangle the branch
//! nearest its neighbour's makes the angle field continuous (Baxter, Barla
//! and Anjyo, "Rigid shape interpolation using normal equations", NPAR 2008,
//! section 4.2).

use std::collections::VecDeque;

use crate::topology::TriangleAdjacency;

/// Makes the rotations `logs` continuous over the triangle adjacency, in
/// place, with `branch(log, reference)` choosing the branch of a triangle's
/// rotation given the one of the triangle it is reached from (for example
/// [`Rotations::nearest_branch`](super::Rotations::nearest_branch)).
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::planar::nearest_branch;
    use std::f64::consts::PI;

    #[test]
    fn unwraps_a_chain_of_triangles() {
        // A chain 0-1-2-...-9 whose true angles grow by 0.4π per step.
        let tris: Vec<[u32; 3]> = (0..10).map(|i| [i, i + 1, i + 2]).collect();
        let adj = TriangleAdjacency::new(&tris);
        let truth: Vec<f64> = (0..10).map(|i| 0.4 * PI * i as f64).collect();
        let mut a: Vec<f64> = truth.iter().map(|&x| nearest_branch(x, 0.0)).collect();
        make_consistent(&mut a, &adj, &[0], |&a, &r| nearest_branch(a, r));
        for (x, y) in a.iter().zip(&truth) {
            assert!((x - y).abs() < 1e-12, "{a:?}");
        }
    }
}
