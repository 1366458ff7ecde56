//! Frames' outlines untied where they knot.
//!
//! Where a drawing's maps disagree a great deal (a fat drawing into a thin
//! curled band, a spiky polygon into a curl), the fit can twist a short
//! stretch of the outline into a knot: a few points gathered in a tangle,
//! or the bottom of a notch turned through itself in a small bow, the
//! outline crossing itself there. A knot is cut where the edges entering
//! and leaving its stretch meet: the stretch's points are laid on a short
//! line across that place, from a point of the entering edge to one of the
//! leaving edge, each as far back from the meeting as the tangle was wide
//! (at most half the edge), in their order and spaced as the fit spaced
//! them. What the outline does around the knot (a notch's depth, a
//! spike's length) stays; the rest of the frame is kept to the bit. Where
//! the entering and leaving edges share no place to cut (too short), the
//! stretch is laid straight between the points on either side of it.
//! Where the result still meets the outline, the sweep runs again, a few
//! times.
//!
//! Only knots are untied: two places of a loop that meet with more than
//! [`KNOT_SHARE`] of the loop's points between them both ways round (a
//! thin part laid across another) are left as the fit made them, and so
//! are holes that meet the outer loop. A frame whose outline is simple is
//! unchanged (one sweep over its edges tells).

use std::ops::ControlFlow;

use super::geometry::{diagonal, dist, lerp, near_edge_pairs, nearest_points, segments_meet};
use crate::mesh::topology::boundary_loops;

/// The largest share of a loop's points a knot may hold.
const KNOT_SHARE: f64 = 0.125;

/// Sweeps over a frame's outline per frame: the first cuts the knots
/// found, the others take in what the cut stretches still meet.
const ROUNDS: usize = 4;

/// Edges closer than this share of the frame's size meet (as the
/// drawings' own check has it).
const TOUCH: f64 = 1e-9;

/// What untying a planar sequence's frames needs from its first key: the
/// outline's loops, as vertices in order.
#[derive(Debug)]
pub struct OutlineUntier {
    loops: Vec<Vec<u32>>,
}

/// A stretch of loop `l`: `count` points from its point `start` on
/// (wrapping), moved; the points just before and after it stay. The edge
/// into its first point and the edge out of its last are its entering and
/// leaving edges.
#[derive(Clone, Copy, Debug)]
struct Stretch {
    l: usize,
    start: usize,
    count: usize,
}

impl OutlineUntier {
    /// The untier of frames of the mesh with `triangles`; none when its
    /// boundary is not a set of simple loops (then there is no outline to
    /// keep simple).
    pub fn new(triangles: &[[u32; 3]]) -> Option<Self> {
        let loops = boundary_loops(triangles).ok()?;
        (!loops.is_empty()).then_some(Self { loops })
    }

    /// Unties the knots of `frame`'s outline; returns the number of pairs
    /// of its edges that still meet after [`ROUNDS`] sweeps (0 for an
    /// outline left simple).
    pub fn untie(&self, frame: &mut [[f64; 2]]) -> usize {
        for _ in 0..ROUNDS {
            let pairs = self.meeting_pairs(frame);
            let knots = self.knots(&pairs);
            if knots.is_empty() {
                return pairs.len();
            }
            for s in knots {
                self.cut(frame, s);
            }
        }
        self.meeting_pairs(frame).len()
    }

    /// The loops' points in `frame`.
    fn loop_points(&self, frame: &[[f64; 2]]) -> Vec<Vec<[f64; 2]>> {
        self.loops
            .iter()
            .map(|l| l.iter().map(|&v| frame[v as usize]).collect())
            .collect()
    }

    /// Every pair of edges of the outline that cross or touch (not
    /// counting neighbours along a loop), as `(l, i, m, j)`: edge `i` of
    /// loop `l` and edge `j` of loop `m`.
    pub fn meeting_pairs(&self, frame: &[[f64; 2]]) -> Vec<(usize, usize, usize, usize)> {
        let points = self.loop_points(frame);
        let tol = TOUCH * diagonal(points.iter().flatten());
        let mut pairs = Vec::new();
        near_edge_pairs::<()>(&points, tol, |e, f| {
            let n = points[e.l].len();
            let neighbours = e.l == f.l && ((e.i + 1) % n == f.i || (f.i + 1) % n == e.i);
            if !neighbours && segments_meet(e.a, e.b, f.a, f.b, tol) {
                pairs.push((e.l, e.i, f.l, f.i));
            }
            ControlFlow::Continue(())
        });
        pairs
    }

    /// The knots among the meeting `pairs` of edges: for each pair of one
    /// loop with few enough points between them the shorter way round,
    /// those points; stretches that overlap or abut made one.
    fn knots(&self, pairs: &[(usize, usize, usize, usize)]) -> Vec<Stretch> {
        let mut moved: Vec<Option<Vec<bool>>> = vec![None; self.loops.len()];
        for &(l, i, m, j) in pairs {
            if l != m {
                continue;
            }
            let n = self.loops[l].len();
            let (a, b) = (i.min(j), i.max(j));
            // Edge a ends at point a + 1, edge b starts at point b: the
            // points a + 1 ..= b lie between them one way, b + 1 ..= a + n
            // the other.
            let (start, count) = if b - a <= n - (b - a) {
                (a + 1, b - a)
            } else {
                (b + 1, n - (b - a))
            };
            if count as f64 > KNOT_SHARE * n as f64 {
                continue;
            }
            let mask = moved[l].get_or_insert_with(|| vec![false; n]);
            for k in 0..count {
                mask[(start + k) % n] = true;
            }
        }
        let mut knots = Vec::new();
        for (l, mask) in moved.iter().enumerate() {
            if let Some(mask) = mask {
                knots.extend(
                    runs(mask)
                        .into_iter()
                        .filter(|&(_, count)| count as f64 <= KNOT_SHARE * mask.len() as f64)
                        .map(|(start, count)| Stretch { l, start, count }),
                );
            }
        }
        knots
    }

    /// Cuts the knot of the stretch `s` of `frame` where its entering and
    /// leaving edges meet (or come nearest), laying its points on a line
    /// across that place; straightens it between its neighbours where
    /// the edges leave no room for that.
    fn cut(&self, frame: &mut [[f64; 2]], s: Stretch) {
        let l = &self.loops[s.l];
        let n = l.len();
        let at = |k: usize| l[(s.start + n + k - 1) % n] as usize;
        // Points 0 and count + 1 of the walk stay.
        let walk: Vec<[f64; 2]> = (0..s.count + 2).map(|k| frame[at(k)]).collect();
        let (before, after) = (walk[0], walk[s.count + 1]);
        let (on_entering, on_leaving) = nearest_points(before, walk[1], walk[s.count], after);
        let middle = lerp(on_entering, on_leaving, 0.5);
        let width = walk[1..=s.count]
            .iter()
            .map(|&p| dist(p, middle))
            .fold(0.0, f64::max);
        let back_in = width.min(0.5 * dist(before, on_entering));
        let back_out = width.min(0.5 * dist(after, on_leaving));
        let room = TOUCH * 1e3 * dist(before, after).max(width);
        let (from, to, first, last) = if s.count >= 2 && back_in > room && back_out > room {
            let from = lerp(on_entering, before, back_in / dist(before, on_entering));
            let to = lerp(on_leaving, after, back_out / dist(after, on_leaving));
            (from, to, 1, s.count)
        } else {
            (before, after, 0, s.count + 1)
        };
        // The fit's spacing along the walk from `first` to `last`.
        let mut along = vec![0.0; walk.len()];
        for k in first + 1..=last {
            along[k] = along[k - 1] + dist(walk[k - 1], walk[k]);
        }
        let total = along[last];
        for k in 1..=s.count {
            let share = if total > 0.0 {
                along[k] / total
            } else {
                (k - first) as f64 / (last - first) as f64
            };
            frame[at(k)] = lerp(from, to, share);
        }
    }
}

/// The runs of `true` in the closed loop `mask`, as `(start, count)`
/// (a run may wrap past the end); none when every point is in one.
pub fn runs(mask: &[bool]) -> Vec<(usize, usize)> {
    let n = mask.len();
    let Some(outside) = mask.iter().position(|&m| !m) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let mut run: Option<(usize, usize)> = None;
    for k in 1..=n {
        let p = (outside + k) % n;
        match (&mut run, mask[p]) {
            (Some((_, count)), true) => *count += 1,
            (None, true) => run = Some((p, 1)),
            (Some(_), false) => out.extend(run.take()),
            (None, false) => {}
        }
    }
    out
}
