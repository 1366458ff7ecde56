//! One boundary for two or more drawings: each drawing after the first
//! matched to the first (`boundary`, `holes`), and the matched points of
//! every pair put together along the first drawing's loops, so that every
//! drawing gets the same points in the same order.
//!
//! A point that one pair's matching placed and another pair's did not is
//! carried to the other drawing along that pair's matching: between its
//! two neighbours there, linearly in the first drawing's arc length.
//! Consecutive matched points of a pair lie on one edge of each drawing
//! (every given point is among them), so the carried point lies on the
//! drawing's outline. Points of different pairs closer than 0.3 of the
//! first drawing's local spacing are merged (as `boundary` does within a
//! pair), so a point given in several drawings at one place is one point.

use super::boundary::MatchedPoint;
use super::geometry::{lerp, ArcLoop};

/// The boundary shared by every drawing.
pub(crate) struct CommonBoundary {
    /// For each drawing, every loop's points (the first drawing's loop
    /// order), one after the other.
    pub(crate) points: Vec<Vec<[f64; 2]>>,
    /// First point of each loop, then the total.
    pub(crate) loop_start: Vec<usize>,
    /// For each drawing and point, the stored point of that drawing's
    /// (paired) loop it is, when it is one.
    pub(crate) from: Vec<Vec<Option<usize>>>,
}

/// A point of the first drawing's loop with where each other drawing
/// has it, if its pair placed it.
struct Entry {
    t: f64,
    a: [f64; 2],
    from_a: Option<usize>,
    others: Vec<Option<([f64; 2], Option<usize>)>>,
}

/// Puts together, loop by loop, the matchings `matched[k][l]` of the
/// first drawing's loop `l` (whose points are `first[l]`) with drawing
/// `k + 1`'s paired loop.
pub(crate) fn common_boundary(
    first: &[Vec<[f64; 2]>],
    matched: &[Vec<Vec<MatchedPoint>>],
) -> CommonBoundary {
    let others = matched.len();
    let mut points: Vec<Vec<[f64; 2]>> = vec![Vec::new(); others + 1];
    let mut from: Vec<Vec<Option<usize>>> = vec![Vec::new(); others + 1];
    let mut loop_start = vec![0];
    for (l, loop_points) in first.iter().enumerate() {
        let arc = ArcLoop::new(loop_points);
        let mut entries: Vec<Entry> = Vec::new();
        for (k, pair) in matched.iter().enumerate() {
            for p in &pair[l] {
                let mut e = Entry {
                    t: p.from_a.map_or(p.ta, |i| arc.param(i)),
                    a: p.a,
                    from_a: p.from_a,
                    others: vec![None; others],
                };
                e.others[k] = Some((p.b, p.from_b));
                entries.push(e);
            }
        }
        entries.sort_by(|x, y| x.t.total_cmp(&y.t));
        // The same given point first, then near points.
        let entries = merge(entries, &arc, false);
        let entries = merge(entries, &arc, true);
        let count = entries.len();
        points[0].extend(entries.iter().map(|e| e.a));
        from[0].extend(entries.iter().map(|e| e.from_a));
        for k in 0..others {
            let placed: Vec<usize> = (0..count)
                .filter(|&i| entries[i].others[k].is_some())
                .collect();
            for i in 0..count {
                if let Some((b, f)) = entries[i].others[k] {
                    points[k + 1].push(b);
                    from[k + 1].push(f);
                    continue;
                }
                // The neighbours this pair placed, before and after (cyclic).
                let after = placed.partition_point(|&j| j < i);
                let (p, q) = (
                    placed[(after + placed.len() - 1) % placed.len()],
                    placed[after % placed.len()],
                );
                let span = (entries[q].t - entries[p].t).rem_euclid(1.0);
                let s = if span > 0.0 {
                    ((entries[i].t - entries[p].t).rem_euclid(1.0) / span).clamp(0.0, 1.0)
                } else {
                    0.5
                };
                let (bp, bq) = (
                    entries[p].others[k].map_or([0.0; 2], |x| x.0),
                    entries[q].others[k].map_or([0.0; 2], |x| x.0),
                );
                points[k + 1].push(lerp(bp, bq, s));
                from[k + 1].push(None);
            }
        }
        loop_start.push(loop_start[loop_start.len() - 1] + count);
    }
    CommonBoundary {
        points,
        loop_start,
        from,
    }
}

/// Merges neighbours that are one point: the same given point of the
/// first drawing, or (`near`) points of different pairs (no drawing placed
/// by both) closer than 0.3 of the first drawing's edge they lie on.
fn merge(entries: Vec<Entry>, arc: &ArcLoop, near: bool) -> Vec<Entry> {
    let length = arc.length();
    // The fraction of the loop taken by the edge at fraction t.
    let edge_at = |t: f64| {
        let s = t.rem_euclid(1.0) * length;
        let i = arc
            .cumulative
            .partition_point(|&c| c <= s)
            .saturating_sub(1)
            .min(arc.points.len() - 1);
        (arc.cumulative[i + 1] - arc.cumulative[i]) / length
    };
    // Whether `e`, `gap` after `last` along the loop, is the same point.
    let joins = |last: &Entry, e: &Entry, gap: f64| {
        let disjoint = last
            .others
            .iter()
            .zip(&e.others)
            .all(|(x, y)| x.is_none() || y.is_none());
        let same_given = last.from_a.is_some() && last.from_a == e.from_a;
        let close = near
            && gap.abs() < 0.3 * edge_at(last.t + 0.5 * gap)
            && !(last.from_a.is_some() && e.from_a.is_some());
        disjoint && (same_given || close)
    };
    let mut out: Vec<Entry> = Vec::with_capacity(entries.len());
    for e in entries {
        if let Some(last) = out.last_mut() {
            if joins(last, &e, e.t - last.t) {
                last.absorb(e, 0.0);
                continue;
            }
        }
        out.push(e);
    }
    // The last and the first may be one point too (across t = 0).
    if out.len() > 1 {
        let (first, last) = (&out[0], &out[out.len() - 1]);
        if joins(last, first, first.t + 1.0 - last.t) {
            let last = out.pop().unwrap_or_else(|| unreachable!());
            out[0].absorb(last, -1.0);
        }
    }
    out
}

impl Entry {
    /// Takes in `other`, the same point: its given point of the first
    /// drawing (its place shifted by `shift` turns) when this has none,
    /// and every drawing's point it has.
    fn absorb(&mut self, other: Entry, shift: f64) {
        if self.from_a.is_none() && other.from_a.is_some() {
            self.t = other.t + shift;
            self.a = other.a;
            self.from_a = other.from_a;
        }
        for (x, y) in self.others.iter_mut().zip(other.others) {
            if y.is_some() {
                *x = y;
            }
        }
    }
}
