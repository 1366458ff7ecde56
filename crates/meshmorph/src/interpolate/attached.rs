//! Separate parts that sit in or next to a larger part (eyes in a head,
//! teeth behind lips, a button on a coat): where they go between keys.
//!
//! The least squares fix each connected part only up to a translation, and
//! each part's centroid moves on a straight line between the keys. For a
//! part that sits in another and moves with it, a straight line is wrong as
//! soon as the other part turns: with a head turned by 90 degrees, the eyes'
//! centroids cut the chords of their arcs and sink into the head halfway.
//!
//! Such a part is *attached* to its *anchors*: the vertices nearest to its
//! own in the first key (the eyelids around an eye) of its *host*, the
//! larger part that holds most of its nearest vertices. At each
//! frame its centroid is the anchors' centroid plus its offset from them,
//! turned by the anchors' best-fit rotation from the first key (Horn); the
//! offset, expressed in the anchors' frame of the first key, is interpolated
//! (or blended) between the keys' offsets. Every key is reproduced exactly,
//! and where the anchors turn rigidly the part turns with them.
//!
//! Which parts are attached follows from the keys, without a threshold of
//! distance: a part is attached when its offsets in the anchors' frame vary
//! no more across the keys than its offsets in the world do (each summed as
//! distances from the first key's; equal up to rounding, `TIE`, when the
//! anchors do not turn, and then the part goes with the surface around
//! it). Eyes in a turning head keep their offset in the head's frame and
//! are attached; a part that stays where it is while the part next to it
//! turns keeps its offset in the world and its straight line. A part whose
//! anchors lie on one line (which does not say how they turn about it)
//! keeps its straight line too.
#![allow(non_snake_case)]

use rstar::primitives::GeomWithData;
use rstar::RTree;

use crate::linalg::matrix::Mat;
use crate::linalg::similarity::rigid_fit;
use crate::linalg::vector::{cross, norm, sub};
use crate::mesh::nearest_vertices::{nearest_with_ties, VertexTree};
use crate::mesh::topology::Components;

/// How many nearest vertices of larger parts each vertex of a part adds to
/// its anchors (more where several are as near: `nearest_vertices.rs`).
const ANCHORS_PER_VERTEX: usize = 4;

/// How many nearest vertices of the larger parts are searched for each
/// vertex's anchors in its host: the search stays local, and a host with
/// fewer vertices than asked for does not make it walk the whole tree.
const ANCHOR_SEARCH: usize = 16 * ANCHORS_PER_VERTEX;

/// Differences of offsets below this, relative to the size of the
/// coordinates they come from, are rounding: a part whose offsets vary as
/// much in the anchors' frame as in the world follows its anchors.
const TIE: f64 = 1e-9;

/// The anchors of every part but the largest (rest geometry only).
#[derive(Clone, Debug, Default)]
pub struct PartAnchors {
    /// Number of parts.
    pub count: usize,
    /// `(part, anchor vertices)`, in decreasing order of the parts' areas:
    /// a part's anchors lie in parts that come before it.
    pub parts: Vec<(u32, Vec<u32>)>,
}

/// A part's offset from its anchors in one key: in the world, and in the
/// anchors' frame of the first key; with the size of the coordinates it
/// was computed from (what its rounding is relative to).
#[derive(Clone, Copy, Debug)]
pub struct KeyOffset<const D: usize> {
    pub world: [f64; D],
    pub local: [f64; D],
    pub size: f64,
}

/// Which anchored parts of a sequence or blend follow their anchors.
#[derive(Clone, Debug, Default)]
pub struct Attached {
    /// One flag per part.
    parts: Vec<bool>,
}

impl Attached {
    /// No part attached (every centroid on its own path).
    pub(crate) fn none() -> Self {
        Self::default()
    }

    /// Whether part `p` follows its anchors.
    pub fn holds(&self, p: usize) -> bool {
        self.parts.get(p).copied().unwrap_or(false)
    }

    /// Number of parts that follow their anchors.
    pub(crate) fn count(&self) -> usize {
        self.parts.iter().filter(|&&f| f).count()
    }
}

impl PartAnchors {
    /// The anchors of the parts of `components` in `positions`; `part_area`
    /// orders them (ties by number).
    pub(crate) fn new<const D: usize>(
        positions: &[[f64; D]],
        components: &Components,
        part_area: &[f64],
    ) -> Self {
        if components.count < 2 {
            return Self::default();
        }
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); components.count];
        for (v, part) in components.of_vertex.iter().enumerate() {
            if let Some(p) = part {
                members[*p as usize].push(v as u32);
            }
        }
        let mut order: Vec<usize> = (0..components.count).collect();
        order.sort_by(|&a, &b| part_area[b].total_cmp(&part_area[a]).then(a.cmp(&b)));
        let mut rank = vec![0; components.count];
        for (r, &p) in order.iter().enumerate() {
            rank[p] = r;
        }
        let point = |v: u32| -> [f64; 3] {
            let p = positions[v as usize];
            std::array::from_fn(|i| if i < D { p[i] } else { 0.0 })
        };
        let mut tree: VertexTree = RTree::bulk_load(
            members[order[0]]
                .iter()
                .map(|&v| GeomWithData::new(point(v), v))
                .collect(),
        );
        let mut parts = Vec::with_capacity(order.len() - 1);
        for &p in &order[1..] {
            let nearest = |v: u32| tree.nearest_neighbor_iter(point(v)).map(|a| a.data);
            // The host: the larger part that holds most of the part's
            // nearest vertices (the larger one on a tie).
            let mut votes: Vec<(usize, usize)> = Vec::new();
            for &v in &members[p] {
                for a in nearest(v).take(ANCHORS_PER_VERTEX) {
                    let host = rank[components.of_vertex[a as usize].unwrap_or(0) as usize];
                    match votes.iter_mut().find(|(h, _)| *h == host) {
                        Some((_, n)) => *n += 1,
                        None => votes.push((host, 1)),
                    }
                }
            }
            let host = votes
                .iter()
                .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
                .map_or(0, |h| h.0);
            let in_host =
                |a: &u32| rank[components.of_vertex[*a as usize].unwrap_or(0) as usize] == host;
            let mut anchors: Vec<u32> = members[p]
                .iter()
                .flat_map(|&v| {
                    nearest_with_ties(&tree, point(v), ANCHORS_PER_VERTEX, ANCHOR_SEARCH, |a| {
                        in_host(&a)
                    })
                })
                .collect();
            anchors.sort_unstable();
            anchors.dedup();
            for &v in &members[p] {
                tree.insert(GeomWithData::new(point(v), v));
            }
            // Anchors on one line do not say how they turn about it.
            if !on_a_line(&anchors.iter().map(|&a| point(a)).collect::<Vec<_>>()) {
                parts.push((p as u32, anchors));
            }
        }
        Self {
            count: components.count,
            parts,
        }
    }

    /// Each anchored part's offset from its anchors in `key` (positions of
    /// the first key's vertices, `centroids` its parts' centroids).
    pub(crate) fn offsets<const D: usize>(
        &self,
        first: &[[f64; D]],
        key: &[[f64; D]],
        centroids: &[[f64; D]],
    ) -> Vec<KeyOffset<D>> {
        self.parts
            .iter()
            .map(|(p, anchors)| {
                let (_, b, R) = rigid_fit(anchors, |v| first[v], |v| key[v]);
                let centroid = centroids[*p as usize];
                let world = sub(centroid, b);
                // Rᵀ world: the offset in the anchors' frame of the first key.
                let local = std::array::from_fn(|i| (0..D).map(|k| R[k][i] * world[k]).sum());
                let size = anchors
                    .iter()
                    .map(|&v| norm(key[v as usize]))
                    .fold(norm(centroid), f64::max);
                KeyOffset { world, local, size }
            })
            .collect()
    }

    /// Which parts follow their anchors, from their offsets in every key
    /// (`keys[0]` the first key's).
    pub fn attached<const D: usize>(&self, keys: &[Vec<KeyOffset<D>>]) -> Attached {
        let mut parts = vec![false; self.count];
        for (i, (p, _)) in self.parts.iter().enumerate() {
            parts[*p as usize] = {
                let spread = |of: &dyn Fn(&KeyOffset<D>) -> [f64; D]| -> f64 {
                    keys.iter()
                        .map(|k| norm(sub(of(&k[i]), of(&keys[0][i]))))
                        .sum()
                };
                // A tie (anchors that do not turn between the keys, or a
                // part centred on its anchors, whose offset is rounding
                // whichever way they turn) goes to the anchors: in between
                // the keys the surface around the part may still move, and
                // the part goes with it. Rounding is relative to the
                // coordinates the offsets come from, not to the offsets.
                let scale: f64 = keys.iter().map(|k| k[i].size).sum();
                spread(&|o| o.local) <= spread(&|o| o.world) + TIE * scale
            };
        }
        Attached { parts }
    }

    /// Moves every attached part: `shifts[p]` holds, for each part `p`, its
    /// shift (decided for the parts not attached) or, for attached parts,
    /// the centroid of its vertices `position(v)` before the shift; these
    /// become the shifts that put the part at its anchors' centroid plus
    /// `offset(i)` (the `i`-th anchored part's offset in the first key's
    /// frame of its anchors) turned by the anchors' rotation from `first`.
    pub(crate) fn place<const D: usize>(
        &self,
        attached: &Attached,
        first: &[[f64; D]],
        position: impl Fn(usize) -> [f64; D],
        part_of: impl Fn(usize) -> usize,
        offset: impl Fn(usize) -> [f64; D],
        shifts: &mut [[f64; D]],
    ) {
        for (i, (p, anchors)) in self.parts.iter().enumerate() {
            if !attached.holds(*p as usize) {
                continue;
            }
            let placed = |v: usize| {
                let (x, s) = (position(v), shifts[part_of(v)]);
                std::array::from_fn(|k| x[k] + s[k])
            };
            let (_, b, R): (_, _, Mat<D>) = rigid_fit(anchors, |v| first[v], placed);
            let o = offset(i);
            let solved = shifts[*p as usize];
            shifts[*p as usize] = std::array::from_fn(|k| {
                b[k] + (0..D).map(|m| R[k][m] * o[m]).sum::<f64>() - solved[k]
            });
        }
    }
}

/// Whether `points` lie on one line (or at one point), to a millionth of
/// their extent: then a rigid fit cannot tell how they turn about it, and
/// a part with such anchors keeps its straight path.
fn on_a_line(points: &[[f64; 3]]) -> bool {
    let Some(&first) = points.first() else {
        return true;
    };
    let Some(far) = points
        .iter()
        .copied()
        .max_by(|a, b| norm(sub(*a, first)).total_cmp(&norm(sub(*b, first))))
    else {
        return true;
    };
    let axis = sub(far, first);
    let length = norm(axis);
    if length == 0.0 {
        return true;
    }
    points.iter().all(|&p| {
        let d = sub(p, first);
        norm(cross(d, axis)) / length <= 1e-6 * length
    })
}
