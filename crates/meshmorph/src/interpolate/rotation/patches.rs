//! The branch choice in space ([`Rotations::choose_branches`] of
//! [`Space<3>`](crate::linalg::Space)): which whole turns each triangle's rotation
//! takes, so that parts turning by more than half a turn do not tear.
//!
//! [`Rotations::choose_branches`]: super::Rotations::choose_branches
//!
//! Every triangle's rotation `R_i` has a principal rotation vector `e_i`
//! (angle in `[0, π]`). Interpolating `exp(t e_i)` is right as long as the
//! rotations of neighbouring triangles stay on the same side of a half turn.
//! Where a part turns further, the principal vectors of two neighbours jump:
//! the shortest rotation from one to the other passes through a half turn.
//! With principal quaternions (scalar part `≥ 0`) that is exactly the case
//! `q_i · q_j < 0`: the quaternion of `R_j` continued from `q_i` along the
//! shortest path is `−q_j`, whose scalar part is negative, i.e. whose angle is
//! beyond π. For planar rotations this is the familiar `|θ_i − θ_j| > π`.
//!
//! The method:
//!
//! 1. Mark the edges across which the principal rotation jumps. Triangles
//!    connected without crossing such an edge form a *patch*; within a patch
//!    the principal vectors are continuous, and the patch keeps them.
//! 2. Each patch `P` gets one *whole-turn vector* `c_P = 2πk u` (`k ≥ 0`
//!    whole turns about the unit axis `u`), so each of its triangles turns
//!    along `R_i(t) = exp(t c_P) exp(t e_i)`: at `t = 1` the whole turns
//!    vanish (`exp(c_P) = I`) and the key is reproduced exactly. When `u` is
//!    the triangle's own axis this is `exp(t (e_i + 2πk u))`, the rotation
//!    interpolated along its axis by an angle with `k` extra turns.
//! 3. The patch of each part's seed (the triangle that turns least, so the
//!    part as a whole takes the principal angle there, the same convention
//!    as in 2D) has `c = 0`. Other patches are decided in layers of the patch
//!    graph from the seed: across a jump edge from triangle `i` of a decided
//!    patch `Q` to triangle `j` of `P`, continuing `R_j` from `e_i` through
//!    the half turn gives `c_Q + π(â_i − â_j)` (`â` the unit axes, which
//!    point nearly opposite ways at a jump); `c_P` is the mean of these over
//!    the jump edges between `P` and the earlier layers, weighted by the
//!    edges' lengths, rounded to the nearest whole number of turns along
//!    its own direction. The patch takes these turns only if they remove a
//!    tear: halfway (`t = 1/2`, where a tear of a whole turn is widest, half
//!    a turn) its rotations must agree with its decided neighbours' across
//!    those edges better by more than a quarter turn on average than with
//!    no turns; otherwise it keeps its principal rotations.
//!
//! The same choice, applied to the rotations of a key relative to the
//! previous one (without `previous`), gives the whole turns of a
//! sequence's segment between later keys (see [`super::spatial`]).
//!
//! Why patches rather than a walk from triangle to triangle: in 3D the axes
//! of neighbours differ, non-rigid regions rotate a lot relative to each
//! other, and a walk that lets every triangle pick the branch nearest to the
//! one it came from adds up errors along the way and carries a wrong branch
//! into whole regions that need none. Here a whole turn is only ever added
//! where the principal rotation actually jumps, one decision for each
//! connected region between jumps, from all its boundary at once. A mesh
//! whose neighbouring rotations never straddle a half turn has one patch per
//! part and is interpolated exactly as without consistency. (In the plane
//! all axes are one and a turn's neighbours agree on it, so the walk of
//! [`super::make_consistent`] is the plane's choice.)
//!
//! And why a whole-turn vector of the patch rather than whole turns along
//! each triangle's own axis: where a part has turned by about a full turn
//! its triangles' principal rotations are small and their axes are whatever
//! the small non-rigid part of the deformation says (a twisted tube's
//! shear); a whole turn about any axis is the identity, so the patch's
//! common axis carries the turn through such regions without a tear.

use std::f64::consts::{PI, TAU};

use crate::linalg::quaternion::{quat_dot, quat_exp, quat_log, quat_mul, Quat};
use crate::linalg::vector::{add, norm, scale, sub};
use crate::mesh::topology::TriangleAdjacency;

/// The whole-turn vector `c_i = 2πk u` of every triangle (see the module
/// documentation), zero for triangles of their part's seed patch.
///
/// `rotations` are principal unit quaternions (scalar part `≥ 0`), one per
/// triangle; `edge_weight(i, j)` is the weight of the edge between
/// neighbours `i` and `j` (their shared edge's length); `seeds` holds one
/// triangle per part connected across edges. Triangles no seed reaches keep
/// a zero vector.
///
/// For a later key of a sequence, `previous` continues the previous
/// key: each seed's patch takes, instead of no turns, the whole turns
/// nearest to the previous key's lifted rotation vectors over the patch
/// (`previous.0[i]`, whole-turn vector plus principal vector), weighted by
/// `previous.1` (the triangles' areas); the other patches follow from it as
/// above. A part that keeps turning from key to key keeps
/// turning the same way, as long as the seeds' patches turn by less than
/// half a turn between two keys.
pub fn whole_turns(
    rotations: &[Quat],
    adjacency: &TriangleAdjacency,
    edge_weight: impl Fn(usize, usize) -> f64,
    seeds: &[usize],
    previous: Option<(&[[f64; 3]], &[f64])>,
) -> Vec<[f64; 3]> {
    assert_eq!(
        rotations.len(),
        adjacency.len(),
        "one rotation per triangle"
    );
    let jumps = |i: usize, j: usize| quat_dot(rotations[i], rotations[j]) < 0.0;
    // Patches: triangles connected across edges that do not jump.
    let (patch, count) = adjacency.edge_components_where(|t, u| !jumps(t, u));
    // The seeds' patches: no turns for the first key (the convention), the
    // previous key's nearest whole turns for later ones.
    let mut decided: Vec<Option<[f64; 3]>> = vec![None; count];
    let mut layer: Vec<usize> = Vec::new();
    for &s in seeds {
        let p = patch[s] as usize;
        if decided[p].is_none() {
            decided[p] = Some([0.0; 3]);
            layer.push(p);
        }
    }
    if let Some((lifted, weights)) = previous {
        let mut sums = vec![([0.0; 3], 0.0); count];
        for (t, &p) in patch.iter().enumerate() {
            if decided[p as usize].is_some() {
                let d = sub(lifted[t], quat_log(rotations[t]));
                let s = &mut sums[p as usize];
                s.0 = add(s.0, scale(d, weights[t]));
                s.1 += weights[t];
            }
        }
        for &p in &layer {
            let (sum, total) = sums[p];
            if total > 0.0 {
                decided[p] = Some(nearest_whole_turns(scale(sum, 1.0 / total)));
            }
        }
    }
    let mut turns = vec![[0.0; 3]; rotations.len()];
    if count == layer.len() {
        // No jump separates anything: every patch is a seed's.
        for (t, c) in turns.iter_mut().enumerate() {
            *c = decided[patch[t] as usize].unwrap_or([0.0; 3]);
        }
        return turns;
    }

    // Jump edges between different patches, listed from both sides.
    let mut boundary: Vec<(u32, u32, u32)> = Vec::new(); // (patch, i, j): i in patch
    for i in 0..rotations.len() {
        for &j in adjacency.of(i) {
            let j = j as usize;
            if patch[i] != patch[j] && jumps(i, j) {
                boundary.push((patch[i], i as u32, j as u32));
            }
        }
    }
    boundary.sort_unstable();
    let mut start = vec![0usize; count + 1];
    for &(p, _, _) in &boundary {
        start[p as usize + 1] += 1;
    }
    for p in 0..count {
        start[p + 1] += start[p];
    }

    let axis = |i: usize| {
        let v = [rotations[i][1], rotations[i][2], rotations[i][3]];
        let n = norm(v);
        if n > 0.0 {
            scale(v, 1.0 / n)
        } else {
            [0.0; 3]
        }
    };
    while !layer.is_empty() {
        // The next layer: undecided patches next to this one, each decided
        // from every decided neighbour (all in earlier layers).
        let mut next: Vec<usize> = layer
            .iter()
            .flat_map(|&p| boundary[start[p]..start[p + 1]].iter())
            .map(|&(_, _, j)| patch[j as usize] as usize)
            .filter(|&q| decided[q].is_none())
            .collect();
        next.sort_unstable();
        next.dedup();
        let mut choices = Vec::with_capacity(next.len());
        for &p in &next {
            let (mut sum, mut total) = ([0.0; 3], 0.0);
            for &(_, j, i) in &boundary[start[p]..start[p + 1]] {
                let (i, j) = (i as usize, j as usize);
                if let Some(c) = decided[patch[i] as usize] {
                    let w = edge_weight(i, j);
                    let d = add(c, scale(sub(axis(i), axis(j)), PI));
                    sum = add(sum, scale(d, w));
                    total += w;
                }
            }
            let mean = if total > 0.0 {
                scale(sum, 1.0 / total)
            } else {
                [0.0; 3]
            };
            let candidate = nearest_whole_turns(mean);
            // Adopt the turns only where they remove a tear: halfway (where
            // a tear of a whole turn is widest, half a turn) the patch's
            // rotations must agree with its decided neighbours' better by
            // more than a quarter turn on average over the jump edges. A
            // real wrap gains nearly half a turn; where neighbours disagree
            // anyway (non-rigid regions, where the jump is an accident of
            // large relative rotations), neither choice is better and the
            // principal rotations stay.
            let disagreement = |c: [f64; 3]| -> f64 {
                boundary[start[p]..start[p + 1]]
                    .iter()
                    .filter_map(|&(_, j, i)| {
                        let (i, j) = (i as usize, j as usize);
                        let ci = decided[patch[i] as usize]?;
                        let half = |c: [f64; 3], t: usize| {
                            quat_mul(
                                quat_exp(scale(c, 0.5)),
                                quat_exp(scale(quat_log(rotations[t]), 0.5)),
                            )
                        };
                        let d = quat_dot(half(ci, i), half(c, j)).abs().min(1.0);
                        Some(edge_weight(i, j) * d.acos())
                    })
                    .sum()
            };
            let candidate =
                if candidate != [0.0; 3] && disagreement(candidate) < disagreement([0.0; 3]) {
                    candidate
                } else {
                    [0.0; 3]
                };
            choices.push(candidate);
        }
        for (&p, c) in next.iter().zip(choices) {
            decided[p] = Some(c);
        }
        layer = next;
    }
    for (t, c) in turns.iter_mut().enumerate() {
        *c = decided[patch[t] as usize].unwrap_or([0.0; 3]);
    }
    turns
}

/// The vector `2πk v/|v|` with the whole number `k ≥ 0` nearest to
/// `|v| / 2π`: the whole turns nearest to the rotation vector `v`.
pub fn nearest_whole_turns(v: [f64; 3]) -> [f64; 3] {
    let len = norm(v);
    let k = (len / TAU).round();
    if k == 0.0 {
        [0.0; 3]
    } else {
        scale(v, TAU * k / len)
    }
}
