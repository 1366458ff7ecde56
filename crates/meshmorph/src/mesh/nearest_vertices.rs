//! The vertices nearest to a point, ties included: what the anchors of a
//! separate part (the vertices around an eye) are made of.
//!
//! Taking "the 4 nearest" splits a tie by rounding: a ball centred in a
//! pipe is equally near a whole ring of the pipe's vertices, and which 4 of
//! them come first depends on the last bits of the coordinates (a file in
//! single precision and the same file in decimal pick different ones, and
//! the ball then follows a different part of a bending pipe). So every
//! vertex as near as the last one taken, to a millionth of the
//! coordinates, is taken too.

use rstar::primitives::GeomWithData;
use rstar::RTree;

use crate::linalg::vector::{norm, sub};

/// Vertices in space, by index.
pub(crate) type VertexTree = RTree<GeomWithData<[f64; 3], u32>>;

/// Distances within this, relative to the size of the coordinates, are
/// equal: far above the rounding of single precision (6e-8), far below any
/// spacing of vertices that matters.
const TIE: f64 = 1e-6;

/// The `count` vertices of `tree` nearest to `p` that `keep` accepts, among
/// its `search` nearest, and every further accepted one as near as the last
/// of them, however many (see the module documentation).
pub(crate) fn nearest_with_ties(
    tree: &VertexTree,
    p: [f64; 3],
    count: usize,
    search: usize,
    keep: impl Fn(u32) -> bool,
) -> Vec<u32> {
    let mut out = Vec::with_capacity(count);
    let mut last = f64::INFINITY;
    for (seen, item) in tree.nearest_neighbor_iter(p).enumerate() {
        let d = norm(sub(*item.geom(), p));
        let full = out.len() >= count;
        // Past `search` only to finish a tie: a whole ring, however many.
        if (full && d - last > TIE * (norm(p) + last)) || (!full && seen >= search) {
            break;
        }
        if !keep(item.data) {
            continue;
        }
        if !full {
            last = d;
        }
        out.push(item.data);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ring_around_the_point_is_taken_whole() {
        // 16 vertices on a circle about the point, one nearer, one farther;
        // single-precision rounding on the circle's.
        let mut items: Vec<GeomWithData<[f64; 3], u32>> = (0..16)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 16.0;
                let p = [3.5, 0.6 * a.cos(), 0.6 * a.sin()].map(|x| f64::from(x as f32));
                GeomWithData::new(p, k)
            })
            .collect();
        items.push(GeomWithData::new([3.5, 0.1, 0.0], 16));
        items.push(GeomWithData::new([3.5, 0.9, 0.0], 17));
        let tree = RTree::bulk_load(items);
        let mut got = nearest_with_ties(&tree, [3.5, 0.0, 0.0], 4, 64, |_| true);
        got.sort_unstable();
        assert_eq!(got, (0..17).collect::<Vec<u32>>());
        // Without the nearest one, the ring alone; filtered, what is kept.
        let got = nearest_with_ties(&tree, [3.5, 0.0, 0.0], 4, 64, |v| v != 16);
        assert_eq!(got.len(), 16);
        let got = nearest_with_ties(&tree, [3.5, 0.0, 0.0], 2, 64, |v| v >= 16);
        assert_eq!(got, vec![16, 17]);
        // A tie is finished past the search: 4 asked among the 5 nearest.
        let got = nearest_with_ties(&tree, [3.5, 0.0, 0.0], 4, 5, |v| v != 16);
        assert_eq!(got.len(), 16);
    }
}
