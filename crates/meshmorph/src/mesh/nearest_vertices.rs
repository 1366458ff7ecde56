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
pub type VertexTree = RTree<GeomWithData<[f64; 3], u32>>;

/// Distances within this, relative to the size of the coordinates, are
/// equal: far above the rounding of single precision (6e-8), far below any
/// spacing of vertices that matters.
const TIE: f64 = 1e-6;

/// The `count` vertices of `tree` nearest to `p` that `keep` accepts, among
/// its `search` nearest, and every further accepted one as near as the last
/// of them, however many (see the module documentation).
pub fn nearest_with_ties(
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
