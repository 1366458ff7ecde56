//! Frames mended where triangles turn over.
//!
//! The as-rigid-as-possible frame is the least-squares fit of each
//! triangle's own map; where neighbouring maps disagree a great deal (a
//! fat drawing into a thin curled band, whose maps stretch eight times
//! more one way than the other) the fit can turn a few triangles over
//! while the outline stays whole. Such a frame is mended where it folds:
//! the inner vertices within a few rings of the turned-over triangles are
//! moved by the untangling that makes the compatible meshes
//! ([`untangle`]: the foldover-free energy of Garanzha et al. 2021,
//! against the first key's triangles), everything else of the frame kept
//! as the fit made it, the outline to the bit. Set up once per sequence
//! (which vertices are inner, which triangles meet at each); a frame with
//! nothing turned over costs one pass over its triangles.

use super::geometry::orient;
use super::mapped::{all_positive, untangle, Patience};

/// Rings of inner vertices around the turned-over triangles moved in each
/// try: a fold is mended with as little of the frame as it needs.
const RINGS: [usize; 4] = [2, 4, 8, 16];

/// What mending a planar sequence's frames needs from its first key.
#[derive(Debug)]
pub(crate) struct FrameMender {
    /// The first key's positions: each triangle's own shape.
    rest: Vec<[f64; 2]>,
    triangles: Vec<[u32; 3]>,
    /// Whether a vertex is on the outline (or used by no triangle): it is
    /// never moved.
    kept: Vec<bool>,
    /// The triangles at each vertex (`at[v]` in `corners[at[v]..at[v + 1]]`).
    at: Vec<usize>,
    corners: Vec<u32>,
}

impl FrameMender {
    /// The mender of frames of the mesh `rest` with `triangles`.
    pub(crate) fn new(rest: &[[f64; 2]], triangles: &[[u32; 3]]) -> Self {
        let n = rest.len();
        // An edge used once is on the outline.
        let mut edges: Vec<(u32, u32)> = triangles
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
            .collect();
        edges.sort_unstable();
        let mut kept = vec![true; n];
        for t in triangles {
            for &v in t {
                kept[v as usize] = false;
            }
        }
        let mut k = 0;
        while k < edges.len() {
            let mut j = k + 1;
            while j < edges.len() && edges[j] == edges[k] {
                j += 1;
            }
            if j - k == 1 {
                kept[edges[k].0 as usize] = true;
                kept[edges[k].1 as usize] = true;
            }
            k = j;
        }
        let mut at = vec![0usize; n + 1];
        for t in triangles {
            for &v in t {
                at[v as usize + 1] += 1;
            }
        }
        for v in 0..n {
            at[v + 1] += at[v];
        }
        let mut fill = at.clone();
        let mut corners = vec![0u32; at[n]];
        for (i, t) in triangles.iter().enumerate() {
            for &v in t {
                corners[fill[v as usize]] = i as u32;
                fill[v as usize] += 1;
            }
        }
        Self {
            rest: rest.to_vec(),
            triangles: triangles.to_vec(),
            kept,
            at,
            corners,
        }
    }

    fn triangles_at(&self, v: usize) -> &[u32] {
        &self.corners[self.at[v]..self.at[v + 1]]
    }

    /// Mends `frame` where triangles are turned over (not positive): the
    /// inner vertices within two rings of them moved until every triangle
    /// is positive, with four, eight, sixteen rings where two are too few.
    /// The number of triangles left turned over: 0 unless the outline
    /// itself folds or no ring gave a valid patch (then the frame is as
    /// the fit made it).
    pub(crate) fn mend(&self, frame: &mut [[f64; 2]]) -> usize {
        let turned: Vec<usize> = (0..self.triangles.len())
            .filter(|&t| {
                let [a, b, c] = self.triangles[t].map(|v| frame[v as usize]);
                orient(a, b, c).is_nan() || orient(a, b, c) <= 0.0
            })
            .collect();
        if turned.is_empty() {
            return 0;
        }
        for rings in RINGS {
            if let Some(mended) = self.try_rings(frame, &turned, rings) {
                for (v, p) in mended {
                    frame[v] = p;
                }
                return 0;
            }
        }
        turned.len()
    }

    /// The new positions of the inner vertices within `rings` rings of the
    /// triangles `turned`, when moving them makes every triangle around
    /// them positive.
    fn try_rings(
        &self,
        frame: &[[f64; 2]],
        turned: &[usize],
        rings: usize,
    ) -> Option<Vec<(usize, [f64; 2])>> {
        let n = self.rest.len();
        let mut free = vec![false; n];
        let mut front: Vec<usize> = Vec::new();
        for &t in turned {
            for v in self.triangles[t] {
                let v = v as usize;
                if !self.kept[v] && !free[v] {
                    free[v] = true;
                    front.push(v);
                }
            }
        }
        for _ in 1..rings {
            let mut next = Vec::new();
            for &v in &front {
                for &t in self.triangles_at(v) {
                    for w in self.triangles[t as usize] {
                        let w = w as usize;
                        if !self.kept[w] && !free[w] {
                            free[w] = true;
                            next.push(w);
                        }
                    }
                }
            }
            front = next;
        }
        // The patch: every triangle at a moved vertex, its other vertices
        // held, numbered first.
        let mut patch: Vec<u32> = Vec::new();
        let mut in_patch = vec![false; self.triangles.len()];
        let moved: Vec<usize> = (0..n).filter(|&v| free[v]).collect();
        if moved.is_empty() {
            return None;
        }
        for &v in &moved {
            for &t in self.triangles_at(v) {
                if !in_patch[t as usize] {
                    in_patch[t as usize] = true;
                    patch.push(t);
                }
            }
        }
        let mut local = vec![u32::MAX; n];
        let mut order: Vec<usize> = Vec::new();
        for &t in &patch {
            for v in self.triangles[t as usize] {
                let v = v as usize;
                if !free[v] && local[v] == u32::MAX {
                    local[v] = order.len() as u32;
                    order.push(v);
                }
            }
        }
        let held = order.len();
        for &v in &moved {
            local[v] = order.len() as u32;
            order.push(v);
        }
        let triangles: Vec<[u32; 3]> = patch
            .iter()
            .map(|&t| self.triangles[t as usize].map(|v| local[v as usize]))
            .collect();
        let reference: Vec<[f64; 2]> = order.iter().map(|&v| self.rest[v]).collect();
        let start: Vec<[f64; 2]> = order.iter().map(|&v| frame[v]).collect();
        // The smallest patch is given up on quickly: the next is bigger.
        let patience = if rings == RINGS[0] {
            Patience::SHORT
        } else {
            Patience::LONG
        };
        let mended = untangle(&reference, &triangles, start, held, patience);
        all_positive(&mended, &triangles).then(|| {
            order[held..]
                .iter()
                .copied()
                .zip(mended[held..].iter().copied())
                .collect()
        })
    }
}
