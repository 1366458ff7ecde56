//! Rotation consistency: choosing the 2π branch of every triangle's angle.
//!
//! `atan2` returns angles in (−π, π]. A part of a shape that turns by more
//! than half a turn gets neighbouring triangles whose principal angles differ
//! by about 2π, and interpolating those angles tears the shape apart. Walking
//! the triangle adjacency from a seed and giving each triangle the branch
//! nearest its neighbour's makes the angle field continuous (Baxter, Barla
//! and Anjyo, "Rigid shape interpolation using normal equations", NPAR 2008,
//! section 4.2).

use std::collections::VecDeque;
use std::f64::consts::TAU;

use crate::topology::TriangleAdjacency;

/// `angle + 2πk` for the integer `k` that brings it nearest to `reference`.
#[inline]
pub fn nearest_branch(angle: f64, reference: f64) -> f64 {
    angle + TAU * ((reference - angle) / TAU).round()
}

/// Makes `angles` continuous over the triangle adjacency, in place.
///
/// Each seed keeps its angle; a breadth-first walk from it over the
/// triangles it reaches gives each one the branch of its angle nearest to the
/// angle of the triangle it was reached from. Give one seed per connected
/// component; triangles no seed reaches keep their angles.
pub fn make_consistent(angles: &mut [f64], adjacency: &TriangleAdjacency, seeds: &[usize]) {
    assert_eq!(angles.len(), adjacency.len(), "one angle per triangle");
    let mut visited = vec![false; angles.len()];
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
                    angles[n] = nearest_branch(angles[n], angles[t]);
                    queue.push_back(n);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn branches() {
        assert!((nearest_branch(-0.9 * PI, 0.95 * PI) - 1.1 * PI).abs() < 1e-12);
        assert!((nearest_branch(0.1, 4.0 * PI) - (0.1 + 4.0 * PI)).abs() < 1e-12);
        assert_eq!(nearest_branch(0.5, 0.4), 0.5);
    }

    #[test]
    fn unwraps_a_chain_of_triangles() {
        // A chain 0-1-2-...-9 whose true angles grow by 0.4π per step.
        let tris: Vec<[u32; 3]> = (0..10).map(|i| [i, i + 1, i + 2]).collect();
        let adj = TriangleAdjacency::new(&tris);
        let truth: Vec<f64> = (0..10).map(|i| 0.4 * PI * i as f64).collect();
        let mut a: Vec<f64> = truth.iter().map(|&x| nearest_branch(x, 0.0)).collect();
        make_consistent(&mut a, &adj, &[0]);
        for (x, y) in a.iter().zip(&truth) {
            assert!((x - y).abs() < 1e-12, "{a:?}");
        }
    }
}
