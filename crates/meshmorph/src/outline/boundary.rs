//! Boundary correspondence: which point of one loop goes where on the
//! other, and both loops given the same points in matched order.
//!
//! Each loop is measured by arc length as a fraction of its length and
//! sampled evenly; a sample's signature is its turning angle at two
//! scales, which no translation, rotation or scale changes. Dynamic time
//! warping (Sakoe and Chiba 1978, with a band around the diagonal) aligns
//! the two signatures for every cyclic start on the second loop, first
//! coarsely over all starts, then finely around the best few, the start
//! refined to a fraction of a sample by golden-section search. The warp
//! is a monotone map between the two loops' arc-length fractions. Every
//! point of each loop is carried to the other by it; a point that lands
//! within 0.3 of the local spacing of a point of the other loop is merged
//! with it (so a shape and a turned, restarted copy match point for
//! point), and the union of the rest is the matched boundary.
//!
//! Anchors hold the warp: between each two in turn round the loops the
//! two stretches' signatures are aligned alike, their ends at the
//! anchors, so that one anchor matches the rest of the outlines by their
//! features as no anchor does (by arc length from a single anchor, a
//! feature that sits elsewhere along the two loops, a tooth, a raised
//! arm, lands on a flat stretch, and the head is matched to the
//! shoulder).

use super::geometry::{diagonal, dist, ArcLoop};
use super::holes::{holes_misplaced, Similarity};
use crate::error::{Error, Result};

/// A point of the matched boundary: where it is on each drawing, and
/// which given point of each it is, if any.
#[derive(Clone, Copy, Debug)]
pub struct MatchedPoint {
    /// Where it is on the first loop, as a fraction of its length from
    /// its first point, in [0, 1).
    pub(crate) ta: f64,
    pub(crate) a: [f64; 2],
    pub(crate) b: [f64; 2],
    /// The loop point of the first drawing it is, else a point on one of
    /// its edges.
    pub from_a: Option<usize>,
    /// The loop point of the second drawing it is.
    pub from_b: Option<usize>,
}

/// A pair of points kept matched, as arc-length fractions on each loop
/// with their positions.
#[derive(Clone, Copy, Debug)]
pub struct LoopAnchor {
    pub(crate) ta: f64,
    pub(crate) tb: f64,
    pub(crate) a: [f64; 2],
    pub(crate) b: [f64; 2],
}

/// A monotone map from the first loop's arc-length fraction to the
/// second's: knots `(ta, tb)` increasing in both, spanning one turn.
struct Warp {
    knots: Vec<(f64, f64)>,
    /// The same before the blend with the diagonal (`warp_from`), or the
    /// least step (`anchored_warp`), that keeps it strictly increasing:
    /// how far that moved a point is how far from its partner it may be
    /// and still be merged with it.
    unblended: Vec<(f64, f64)>,
}

impl Warp {
    fn eval(knots: &[(f64, f64)], t: f64, forward: bool) -> f64 {
        let key = |k: &(f64, f64)| if forward { k.0 } else { k.1 };
        let val = |k: &(f64, f64)| if forward { k.1 } else { k.0 };
        let start = key(&knots[0]);
        let t = start + (t - start).rem_euclid(1.0);
        let i = knots
            .partition_point(|k| key(k) <= t)
            .saturating_sub(1)
            .min(knots.len() - 2);
        let (k0, k1) = (&knots[i], &knots[i + 1]);
        let span = key(k1) - key(k0);
        let f = if span > 0.0 {
            (t - key(k0)) / span
        } else {
            0.0
        };
        (val(k0) + f * (val(k1) - val(k0))).rem_euclid(1.0)
    }
    fn forward(&self, ta: f64) -> f64 {
        Self::eval(&self.knots, ta, true)
    }
    fn inverse(&self, tb: f64) -> f64 {
        Self::eval(&self.knots, tb, false)
    }
    /// Where `ta`'s partner on the second loop would be without the blend.
    fn unblended_forward(&self, ta: f64) -> f64 {
        Self::eval(&self.unblended, ta, true)
    }
    /// Where `tb`'s partner on the first loop would be without the blend.
    fn unblended_inverse(&self, tb: f64) -> f64 {
        Self::eval(&self.unblended, tb, false)
    }
}

/// Raises each knot's second fraction to the one before it, where the
/// alignment's path stepped back.
fn non_decreasing(knots: &mut [(f64, f64)]) {
    for k in 1..knots.len() {
        knots[k].1 = knots[k].1.max(knots[k - 1].1);
    }
}

/// The distance between two arc-length fractions round the loop.
fn cyclic_distance(x: f64, y: f64) -> f64 {
    let d = (x - y).rem_euclid(1.0);
    d.min(1.0 - d)
}

/// The angle the path from `p` through `q` to `r` turns by at `q`
/// (positive to the left).
fn turning(p: [f64; 2], q: [f64; 2], r: [f64; 2]) -> f64 {
    let (u, v) = ([q[0] - p[0], q[1] - p[1]], [r[0] - q[0], r[1] - q[1]]);
    (u[0] * v[1] - u[1] * v[0]).atan2(u[0] * v[0] + u[1] * v[1])
}

/// Turning angles of `n` samples of `arc` from fraction `start` on, at
/// scales of 1 and 4 samples.
fn signature(arc: &ArcLoop, start: f64, n: usize) -> Vec<[f64; 2]> {
    let pts: Vec<[f64; 2]> = (0..n)
        .map(|k| arc.at(start + k as f64 / n as f64))
        .collect();
    let turn = |k: usize, h: usize| turning(pts[(k + n - h) % n], pts[k], pts[(k + h) % n]);
    (0..n).map(|k| [turn(k, 1), 0.5 * turn(k, 4)]).collect()
}

/// Dynamic time warping of two equally long signatures within a band of
/// half-width `band`; a step off the diagonal costs `skip` more. Returns
/// the cost and, when asked, for each row the middle of the columns the
/// path visits.
fn warp(fa: &[[f64; 2]], fb: &[[f64; 2]], band: usize, skip: f64, path: bool) -> (f64, Vec<f64>) {
    let n = fa.len();
    let width = 2 * band + 1;
    let mut cost = vec![f64::INFINITY; n * width];
    // Cell (i, j) is stored at i * width + (j + band - i).
    let at = |i: usize, j: usize| i * width + (j + band - i);
    let inb = |i: usize, j: usize| j + band >= i && j <= i + band;
    for i in 0..n {
        let lo = i.saturating_sub(band);
        let hi = (i + band).min(n - 1);
        for j in lo..=hi {
            let d0 = fa[i][0] - fb[j][0];
            let d1 = fa[i][1] - fb[j][1];
            let c = d0 * d0 + d1 * d1;
            let best = if i == 0 && j == 0 {
                0.0
            } else {
                let mut b = f64::INFINITY;
                if i > 0 && j > 0 && inb(i - 1, j - 1) {
                    b = b.min(cost[at(i - 1, j - 1)]);
                }
                if i > 0 && inb(i - 1, j) {
                    b = b.min(cost[at(i - 1, j)] + skip);
                }
                if j > lo {
                    b = b.min(cost[at(i, j - 1)] + skip);
                }
                b
            };
            cost[at(i, j)] = best + c;
        }
    }
    let total = cost[at(n - 1, n - 1)];
    if !path {
        return (total, Vec::new());
    }
    let mut lo = vec![usize::MAX; n];
    let mut hi = vec![0usize; n];
    let (mut i, mut j) = (n - 1, n - 1);
    loop {
        lo[i] = lo[i].min(j);
        hi[i] = hi[i].max(j);
        if i == 0 && j == 0 {
            break;
        }
        let diag = if i > 0 && j > 0 && inb(i - 1, j - 1) {
            cost[at(i - 1, j - 1)]
        } else {
            f64::INFINITY
        };
        let up = if i > 0 && inb(i - 1, j) {
            cost[at(i - 1, j)] + skip
        } else {
            f64::INFINITY
        };
        let left = if j > 0 && inb(i, j - 1) {
            cost[at(i, j - 1)] + skip
        } else {
            f64::INFINITY
        };
        if diag <= up && diag <= left {
            i -= 1;
            j -= 1;
        } else if up <= left {
            i -= 1;
        } else {
            j -= 1;
        }
    }
    let mid = (0..n).map(|i| 0.5 * (lo[i] + hi[i]) as f64).collect();
    (total, mid)
}

/// How a loop's near-best starts are told apart: by where they put the
/// points in a frame the drawings already share (a hole, once the outer
/// loops are matched), by how well they lay the other loops (the holes)
/// over each other (an outer loop with holes), then by how little they
/// turn the drawing (every outer loop).
pub enum TieBreak<'a> {
    /// The second drawing's points in the first's frame.
    Frame(&'a Similarity),
    /// The first and second drawings' holes, laid over each other by the
    /// similarity of the outer loops as matched from a start; of starts
    /// that lay them equally well, the one that turns least.
    Holes(&'a [Vec<[f64; 2]>], &'a [Vec<[f64; 2]>]),
    /// The start that turns the drawing least: a round outline, whose
    /// every start matches alike, is not spun.
    Turn,
}

/// `n` points of `a` from its start and of `b` from `start`, evenly
/// spaced by arc length, pair by pair.
fn sampled(a: &ArcLoop, b: &ArcLoop, start: f64, n: usize) -> (Vec<[f64; 2]>, Vec<[f64; 2]>) {
    (0..n)
        .map(|k| {
            let t = k as f64 / n as f64;
            (a.at(t), b.at(start + t))
        })
        .unzip()
}

/// How far points `pa` lie from points `pb` once `pb` are laid onto them
/// by a shift and a scale but no turn: the sum of squares over `pa`'s
/// squared spread about its centre.
fn turned_away(pa: &[[f64; 2]], pb: &[[f64; 2]]) -> f64 {
    let n = pa.len() as f64;
    let mean = |p: &[[f64; 2]]| {
        let s = p.iter().fold([0.0, 0.0], |m, q| [m[0] + q[0], m[1] + q[1]]);
        [s[0] / n, s[1] / n]
    };
    let (ma, mb) = (mean(pa), mean(pb));
    let spread = |p: &[[f64; 2]], m: [f64; 2]| -> f64 {
        p.iter()
            .map(|q| (q[0] - m[0]).powi(2) + (q[1] - m[1]).powi(2))
            .sum()
    };
    let (sa, sb) = (spread(pa, ma), spread(pb, mb));
    if sa <= 0.0 || sb <= 0.0 {
        return 0.0;
    }
    let k = (sa / sb).sqrt();
    pa.iter()
        .zip(pb)
        .map(|(p, q)| {
            let r = [ma[0] + k * (q[0] - mb[0]), ma[1] + k * (q[1] - mb[1])];
            (p[0] - r[0]).powi(2) + (p[1] - r[1]).powi(2)
        })
        .sum::<f64>()
        / sa
}

/// The warp found by aligning the signatures over every start. With a
/// `tie`, the starts whose signature scores are near the best are told
/// apart by it, so that a loop with few features of its own (a round
/// outline or hole) follows the rest of its drawing.
fn aligned_warp(a: &ArcLoop, b: &ArcLoop, samples: usize, tie: Option<&TieBreak>) -> Warp {
    let coarse = 64.min(samples);
    let fa = signature(a, 0.0, coarse);
    let skip = 0.02;
    let mut scored: Vec<(f64, f64)> = (0..coarse)
        .map(|o| {
            let start = o as f64 / coarse as f64;
            let fb = signature(b, start, coarse);
            (warp(&fa, &fb, coarse / 6, skip, false).0, start)
        })
        .collect();
    scored.sort_by(|x, y| x.0.total_cmp(&y.0));
    // Where a tie-break is given: among the starts scored near the best
    // (`pick` says how near), the one it prefers: how far a start moves the
    // drawing by the tie-break first, then how much it turns it.
    let moved = |start: f64| -> (f64, f64) {
        let Some(tie) = tie else {
            return (0.0, 0.0);
        };
        let (pa, pb) = sampled(a, b, start, coarse);
        match tie {
            TieBreak::Frame(frame) => (
                pa.iter()
                    .zip(&pb)
                    .map(|(p, &q)| {
                        let q = frame.apply(q);
                        (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)
                    })
                    .sum(),
                0.0,
            ),
            TieBreak::Holes(holes_a, holes_b) => (
                holes_misplaced(holes_a, holes_b, &Similarity::of_points(&pa, &pb)),
                turned_away(&pa, &pb),
            ),
            TieBreak::Turn => (0.0, turned_away(&pa, &pb)),
        }
    };
    // Holes misplaced by less than a hundredth of the drawing's size each
    // are as good as in place (a round hole in the middle lies there from
    // every start).
    let alike = match tie {
        Some(TieBreak::Holes(holes_a, _)) => {
            0.01 * diagonal(a.points.iter()) * holes_a.len() as f64
        }
        _ => 0.0,
    };
    let pick = |scored: &mut Vec<(f64, f64)>| -> (f64, f64) {
        scored.sort_by(|x, y| x.0.total_cmp(&y.0));
        let (best, median) = (scored[0].0, scored[scored.len() / 2].0);
        // (Turning angles in radians summed over the samples: differences
        // under 1 % of a loop's whole turn are how the samples happen to
        // fall between a round loop's points, not features.)
        let floor = 0.01 * std::f64::consts::TAU;
        // A frame or holes to go by: within a quarter of the way to the
        // median score, or half the best score again, whichever is more (a
        // loop with no features scores every start alike, up to where the
        // samples fall). The turn alone is weak evidence: it only picks among starts that
        // score alike but for how the samples fall. Where the median start
        // scores within 5 % of the best, no feature tells the starts apart
        // (a round loop's spread is about 1 %): any start up to twice that
        // spread. Else within 2 % of the best: a start one sample off a
        // feature scores 5 % or more worse.
        let near = match tie {
            Some(TieBreak::Turn) if median - best < 0.05 * best => best + 2.0 * (median - best),
            Some(TieBreak::Turn) => best + 0.02 * best + 0.1 * floor,
            _ => best + (0.25 * (median - best)).max(0.5 * best).max(floor),
        };
        let candidates: Vec<((f64, f64), (f64, f64))> = scored
            .iter()
            .take_while(|x| x.0 <= near)
            .map(|&c| (moved(c.1), c))
            .collect();
        let least = candidates
            .iter()
            .map(|c| c.0 .0)
            .fold(f64::INFINITY, f64::min);
        candidates
            .iter()
            .filter(|c| c.0 .0 <= least + alike)
            .min_by(|x, y| x.0 .1.total_cmp(&y.0 .1))
            .map_or(scored[0], |c| c.1)
    };
    if tie.is_some() {
        scored = vec![pick(&mut scored)];
    }
    let n = samples;
    let band = n / 6;
    let fa = signature(a, 0.0, n);
    let score = |start: f64| warp(&fa, &signature(b, start, n), band, skip, false).0;
    let mut best = (f64::INFINITY, 0.0);
    let step = 1.0 / n as f64;
    let reach = (n / coarse) as i64;
    let mut fine = Vec::new();
    for &(_, start) in scored.iter().take(3) {
        for d in -reach..=reach {
            let s = start + d as f64 * step;
            let c = score(s);
            fine.push((c, s));
            if c < best.0 {
                best = (c, s);
            }
        }
    }
    // Golden-section search for the start within a sample either side
    // (half a sample about the tie-break's choice, which a loop without
    // features would otherwise drift from).
    let mut window = step;
    if tie.is_some() {
        best = pick(&mut fine);
        window = 0.5 * step;
    }
    let (mut lo, mut hi) = (best.1 - window, best.1 + window);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut c1, mut c2) = (score(x1), score(x2));
    for _ in 0..16 {
        if c1 < c2 {
            hi = x2;
            x2 = x1;
            c2 = c1;
            x1 = hi - g * (hi - lo);
            c1 = score(x1);
        } else {
            lo = x1;
            x1 = x2;
            c1 = c2;
            x2 = lo + g * (hi - lo);
            c2 = score(x2);
        }
    }
    let start = if c1.min(c2) < best.0 {
        if c1 < c2 {
            x1
        } else {
            x2
        }
    } else {
        best.1
    };
    warp_from(&fa, b, start, n, band, skip)
}

/// The warp of signature `fa` onto loop `b` read from `start`.
fn warp_from(fa: &[[f64; 2]], b: &ArcLoop, start: f64, n: usize, band: usize, skip: f64) -> Warp {
    let (_, mid) = warp(fa, &signature(b, start, n), band, skip, true);
    let mut knots = Vec::with_capacity(n + 1);
    let mut unblended = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let g = match i {
            0 => 0.0,
            i if i == n => n as f64,
            i => mid[i],
        };
        unblended.push((i as f64 / n as f64, start + g / n as f64));
        // A blend with the diagonal keeps the map strictly increasing.
        let g = 0.8 * g + 0.2 * i as f64;
        knots.push((i as f64 / n as f64, start + g / n as f64));
    }
    non_decreasing(&mut knots);
    non_decreasing(&mut unblended);
    Warp { knots, unblended }
}

/// Turning angles of `n` samples of `arc` spread evenly over the `span`
/// (a fraction of its length) from fraction `start` on, at scales of 1
/// and 4 samples (the samples about either end reach past it, round the
/// loop).
fn span_signature(arc: &ArcLoop, start: f64, span: f64, n: usize) -> Vec<[f64; 2]> {
    let step = span / n as f64;
    // The samples and four more on either side, each found once.
    let pts: Vec<[f64; 2]> = (0..n + 8)
        .map(|j| arc.at(start + (j as f64 - 4.0) * step))
        .collect();
    let turn = |k: usize, h: usize| turning(pts[k + 4 - h], pts[k + 4], pts[k + 4 + h]);
    (0..n).map(|k| [turn(k, 1), 0.5 * turn(k, 4)]).collect()
}

/// The warp through the anchors: between each two in turn round the
/// loops, the signatures' alignment of that stretch of each (as
/// [`aligned_warp`] aligns whole loops, its ends held at the anchors),
/// with as many samples as its share of the first loop's `samples`.
fn anchored_warp(a: &ArcLoop, b: &ArcLoop, anchors: &[LoopAnchor], samples: usize) -> Result<Warp> {
    let mut sorted: Vec<LoopAnchor> = anchors.to_vec();
    sorted.sort_by(|x, y| x.ta.total_cmp(&y.ta));
    let (a0, b0) = (sorted[0].ta, sorted[0].tb);
    // Each anchor's fractions, the second made to increase round the loop
    // from the first anchor's, and the first anchor again a turn on.
    let mut ends = Vec::with_capacity(sorted.len() + 1);
    let mut last = b0;
    for (k, s) in sorted.iter().enumerate() {
        let tb = b0 + (s.tb - b0).rem_euclid(1.0);
        if k > 0 && tb <= last {
            return Err(Error::IncompatibleDrawings(
                "anchors on a pair of loops come in different orders along the two outlines: \
                 give them so that going round both loops meets them in the same order"
                    .into(),
            ));
        }
        last = tb;
        ends.push((s.ta, tb));
    }
    ends.push((a0 + 1.0, b0 + 1.0));
    let skip = 0.02;
    let mut knots = vec![ends[0]];
    let mut unblended = vec![ends[0]];
    for w in ends.windows(2) {
        let ((sa, sb), (ea, eb)) = (w[0], w[1]);
        let (span_a, span_b) = (ea - sa, eb - sb);
        // As finely as the longer of the two stretches (each loop's share
        // of `samples`), so that a long stretch between two anchors close
        // on the other loop keeps its features.
        let n = ((span_a.max(span_b) * samples as f64).round() as usize).max(8);
        let (_, mid) = warp(
            &span_signature(a, sa, span_a, n),
            &span_signature(b, sb, span_b, n),
            (n / 6).max(1),
            skip,
            true,
        );
        // The path kept strictly increasing by a fifth of a sample a step
        // at least, where it is flatter (both ways, so that it still ends
        // at the next anchor). Unlike a whole loop's alignment, whose start
        // is chosen first, a stretch between anchors may lie far from its
        // diagonal: a blend with it would pull features off each other.
        let mut g: Vec<f64> = (0..=n)
            .map(|i| {
                if i == 0 {
                    0.0
                } else if i == n {
                    n as f64
                } else {
                    mid[i]
                }
            })
            .collect();
        for i in 1..=n {
            g[i] = g[i].max(g[i - 1] + 0.2);
        }
        g[n] = n as f64;
        for i in (0..n).rev() {
            g[i] = g[i].min(g[i + 1] - 0.2);
        }
        for i in 1..n {
            let ta = sa + span_a * i as f64 / n as f64;
            unblended.push((ta, sb + span_b * mid[i] / n as f64));
            knots.push((ta, sb + span_b * g[i] / n as f64));
        }
        // The stretch ends exactly at the next anchor.
        unblended.push((ea, eb));
        knots.push((ea, eb));
    }
    non_decreasing(&mut knots);
    non_decreasing(&mut unblended);
    Ok(Warp { knots, unblended })
}

struct Event {
    ta: f64,
    tb: f64,
    a: Option<[f64; 2]>,
    b: Option<[f64; 2]>,
    from_a: Option<usize>,
    from_b: Option<usize>,
    /// Spacing of the given points about this one, as fractions.
    gap_a: f64,
    gap_b: f64,
    /// How far the warp's blend with the diagonal moved this point's
    /// partner on each loop, as fractions.
    moved_a: f64,
    moved_b: f64,
}

/// Matches two loops (both in the same orientation): the same number of
/// points on each, in matched order, with every point of each loop among
/// them. `anchors` are kept matched exactly; with none the warp comes
/// from the signatures' alignment at `samples` samples.
pub fn match_loops(
    a: &[[f64; 2]],
    b: &[[f64; 2]],
    anchors: &[LoopAnchor],
    samples: usize,
    tie: Option<&TieBreak>,
) -> Result<Vec<MatchedPoint>> {
    let (arc_a, arc_b) = (ArcLoop::new(a), ArcLoop::new(b));
    let map = if anchors.is_empty() {
        aligned_warp(&arc_a, &arc_b, samples.max(16), tie)
    } else {
        anchored_warp(&arc_a, &arc_b, anchors, samples.max(16))?
    };
    let gaps = |arc: &ArcLoop, i: usize| {
        let n = arc.points.len();
        let next = arc.cumulative[i + 1] - arc.cumulative[i];
        let prev = arc.cumulative[(i + n - 1) % n + 1] - arc.cumulative[(i + n - 1) % n];
        next.min(prev) / arc.length()
    };
    let mut events: Vec<Event> = Vec::with_capacity(a.len() + b.len() + anchors.len());
    for i in 0..a.len() {
        let ta = arc_a.param(i);
        let tb = map.forward(ta);
        events.push(Event {
            ta,
            tb,
            a: Some(a[i]),
            b: None,
            from_a: Some(i),
            from_b: None,
            gap_a: gaps(&arc_a, i),
            gap_b: f64::INFINITY,
            moved_a: 0.0,
            moved_b: cyclic_distance(tb, map.unblended_forward(ta)),
        });
    }
    for j in 0..b.len() {
        let tb = arc_b.param(j);
        let ta = map.inverse(tb);
        events.push(Event {
            ta,
            tb,
            a: None,
            b: Some(b[j]),
            from_a: None,
            from_b: Some(j),
            gap_a: f64::INFINITY,
            gap_b: gaps(&arc_b, j),
            moved_a: cyclic_distance(ta, map.unblended_inverse(tb)),
            moved_b: 0.0,
        });
    }
    for s in anchors {
        events.push(Event {
            ta: s.ta,
            tb: s.tb,
            a: Some(s.a),
            b: Some(s.b),
            from_a: None,
            from_b: None,
            gap_a: f64::INFINITY,
            gap_b: f64::INFINITY,
            moved_a: 0.0,
            moved_b: 0.0,
        });
    }
    events.sort_by(|x, y| x.ta.total_cmp(&y.ta));
    // Merge neighbours that are the same point, closest first, a few
    // rounds: within 0.3 of the given points' spacing, and as much again
    // where the warp's blend with the diagonal moved them apart (a
    // square's corner and a 4:1 bar's, whose sides are 0.25 and 0.4 of
    // their loops, are matched by the alignment and 0.03 apart after the
    // blend, 0.3 of the bar's spacing there).
    for _ in 0..3 {
        let n = events.len();
        if n < 2 {
            break;
        }
        let mut pairs: Vec<(f64, usize)> = (0..n)
            .filter_map(|i| {
                let (e, f) = (&events[i], &events[(i + 1) % n]);
                let clash = (e.from_a.is_some() && f.from_a.is_some())
                    || (e.from_b.is_some() && f.from_b.is_some())
                    || (e.a.is_some() && f.a.is_some() && e.from_a.is_none() && f.from_a.is_none())
                    || (e.b.is_some() && f.b.is_some() && e.from_b.is_none() && f.from_b.is_none());
                let da = cyclic_distance(e.ta, f.ta);
                let db = cyclic_distance(e.tb, f.tb);
                let (near_a, near_b) = (0.3 * e.gap_a.min(f.gap_a), 0.3 * e.gap_b.min(f.gap_b));
                let ok = !clash
                    && da < near_a + (e.moved_a + f.moved_a).min(near_a)
                    && db < near_b + (e.moved_b + f.moved_b).min(near_b);
                ok.then_some((da + db, i))
            })
            .collect();
        if pairs.is_empty() {
            break;
        }
        pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut taken = vec![false; n];
        let mut remove = vec![false; n];
        for &(_, i) in &pairs {
            let j = (i + 1) % n;
            if taken[i] || taken[j] {
                continue;
            }
            taken[i] = true;
            taken[j] = true;
            let f = std::mem::replace(
                &mut events[j],
                Event {
                    ta: 0.0,
                    tb: 0.0,
                    a: None,
                    b: None,
                    from_a: None,
                    from_b: None,
                    gap_a: 0.0,
                    gap_b: 0.0,
                    moved_a: 0.0,
                    moved_b: 0.0,
                },
            );
            let e = &mut events[i];
            if f.from_a.is_some() || (e.from_a.is_none() && f.a.is_some()) {
                e.a = f.a;
                e.ta = f.ta;
                e.from_a = f.from_a.or(e.from_a);
            }
            if f.from_b.is_some() || (e.from_b.is_none() && f.b.is_some()) {
                e.b = f.b;
                e.tb = f.tb;
                e.from_b = f.from_b.or(e.from_b);
            }
            e.gap_a = e.gap_a.min(f.gap_a);
            e.gap_b = e.gap_b.min(f.gap_b);
            e.moved_a = 0.0;
            e.moved_b = 0.0;
            remove[j] = true;
        }
        let mut k = 0;
        events.retain(|_| {
            k += 1;
            !remove[k - 1]
        });
    }
    let out: Vec<MatchedPoint> = events
        .iter()
        .map(|e| MatchedPoint {
            ta: e.ta.rem_euclid(1.0),
            a: e.a.unwrap_or_else(|| arc_a.at(e.ta)),
            b: e.b.unwrap_or_else(|| arc_b.at(e.tb)),
            from_a: e.from_a,
            from_b: e.from_b,
        })
        .collect();
    let tol_a = 1e-12 * diagonal(a.iter());
    let tol_b = 1e-12 * diagonal(b.iter());
    let n = out.len();
    for i in 0..n {
        let (p, q) = (&out[i], &out[(i + 1) % n]);
        if dist(p.a, q.a) <= tol_a || dist(p.b, q.b) <= tol_b {
            return Err(Error::IncompatibleDrawings(format!(
                "the outlines' correspondence put two points at one place (near {:?} on the first drawing, {:?} on the second): anchors closer than the outlines' point spacing cause this; move them apart",
                p.a, p.b
            )));
        }
    }
    Ok(out)
}
