//! Cuts that open every hole to the outer loop, the same in both
//! drawings, so that each drawing becomes one topological disk whose
//! boundary runs round the outer loop and, at each cut, along the cut,
//! round the hole and back.
//!
//! A cut joins a matched point of the hole to a matched point of the
//! outer loop (each outer point ends at most one cut). The pairs are tried
//! from the shortest (the sum of both drawings' lengths, each relative to
//! its drawing's size) on; the first whose straight segment lies inside
//! both drawings, touching no loop and no earlier cut, is taken.

use super::boundary::MatchedPoint;
use super::geometry::{diagonal, dist, inside_loop, point_segment_distance, segments_meet};
use crate::error::{Error, Result};

/// A cut from point `outer` of the matched outer loop to point `hole`
/// of matched hole loop `loop_index - 1`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cut {
    pub(crate) outer: usize,
    pub(crate) hole: usize,
}

/// How many candidate pairs are tried for each hole before giving up.
const TRIES: usize = 4096;

/// Whether the open segment from loop point `from` to loop point `to`
/// lies inside the region given by `loops` (outer first) and keeps clear
/// of every loop and of the segments in `taken`.
pub(crate) fn clear(
    loops: &[Vec<[f64; 2]>],
    taken: &[([f64; 2], [f64; 2])],
    from: (usize, usize),
    to: (usize, usize),
    tol: f64,
) -> bool {
    let (p, q) = (loops[from.0][from.1], loops[to.0][to.1]);
    if dist(p, q) <= tol {
        return false;
    }
    for (l, pts) in loops.iter().enumerate() {
        let n = pts.len();
        for i in 0..n {
            let j = (i + 1) % n;
            let (a, b) = (pts[i], pts[j]);
            let at = |e: (usize, usize)| e.0 == l && (e.1 == i || e.1 == j);
            if at(from) || at(to) {
                // An edge at an end may meet the segment only there.
                let (shared, other) = if (l, i) == from || (l, i) == to {
                    (a, b)
                } else {
                    (b, a)
                };
                let far = if shared == p { q } else { p };
                if point_segment_distance(other, p, q) <= tol
                    || point_segment_distance(far, a, b) <= tol
                {
                    return false;
                }
                continue;
            }
            if segments_meet(p, q, a, b, tol) {
                return false;
            }
        }
    }
    if taken.iter().any(|&(a, b)| segments_meet(p, q, a, b, tol)) {
        return false;
    }
    let mid = [(p[0] + q[0]) * 0.5, (p[1] + q[1]) * 0.5];
    inside_loop(mid, &loops[0]) && !loops[1..].iter().any(|h| inside_loop(mid, h))
}

/// One cut for each hole, straight in both drawings.
///
/// # Errors
/// [`Error::IncompatibleDrawings`] when no pair of matched points gives a
/// straight cut inside both drawings for some hole.
pub(crate) fn find_cuts(outer: &[MatchedPoint], holes: &[Vec<MatchedPoint>]) -> Result<Vec<Cut>> {
    if holes.is_empty() {
        return Ok(Vec::new());
    }
    let loops_of = |side: usize| -> Vec<Vec<[f64; 2]>> {
        std::iter::once(outer)
            .chain(holes.iter().map(Vec::as_slice))
            .map(|l| {
                l.iter()
                    .map(|p| if side == 0 { p.a } else { p.b })
                    .collect()
            })
            .collect()
    };
    let loops = [loops_of(0), loops_of(1)];
    let size = [
        diagonal(loops[0].iter().flatten()),
        diagonal(loops[1].iter().flatten()),
    ];
    let tol = [1e-9 * size[0], 1e-9 * size[1]];
    let mut taken: [Vec<([f64; 2], [f64; 2])>; 2] = [Vec::new(), Vec::new()];
    let mut used_outer = vec![false; outer.len()];
    let mut cuts = Vec::with_capacity(holes.len());
    for (h, hole) in holes.iter().enumerate() {
        let mut pairs: Vec<(f64, usize, usize)> = Vec::with_capacity(hole.len() * outer.len());
        for (i, hp) in hole.iter().enumerate() {
            for (j, op) in outer.iter().enumerate() {
                if !used_outer[j] {
                    let c = dist(hp.a, op.a) / size[0] + dist(hp.b, op.b) / size[1];
                    pairs.push((c, i, j));
                }
            }
        }
        let tries = TRIES.min(pairs.len());
        if tries == 0 {
            break;
        }
        pairs.select_nth_unstable_by(tries - 1, |x, y| x.0.total_cmp(&y.0));
        pairs.truncate(tries);
        pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
        let found = pairs.iter().find(|&&(_, i, j)| {
            (0..2).all(|s| clear(&loops[s], &taken[s], (h + 1, i), (0, j), tol[s]))
        });
        let Some(&(_, i, j)) = found else {
            return Err(Error::IncompatibleDrawings(format!(
                "no straight cut joins loop {} (a hole) to the outer loop inside both drawings at matched points: the hole sits too differently in the two drawings; an anchor near the hole on both outer loops may help",
                h + 1
            )));
        };
        used_outer[j] = true;
        for s in 0..2 {
            taken[s].push((loops[s][h + 1][i], loops[s][0][j]));
        }
        cuts.push(Cut { outer: j, hole: i });
    }
    Ok(cuts)
}
