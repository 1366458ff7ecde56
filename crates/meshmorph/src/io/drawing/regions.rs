//! Filled regions from the loops of filled paths: which loops bound the
//! fill from outside (outer loops), which from inside (holes), by each
//! path's fill rule.

use crate::outline::geometry::point_segment_distance;

/// How a path decides what is inside.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// Inside where the loops wind around a point a non-zero number of
    /// times (SVG's default).
    NonZero,
    /// Inside where a ray from the point crosses the loops an odd number
    /// of times.
    EvenOdd,
}

/// A loop of a filled path.
pub struct FilledLoop {
    /// The path it belongs to (an index into the caller's list).
    pub element: usize,
    pub points: Vec<[f64; 2]>,
}

/// One filled region: an outer loop and the holes just inside it, as
/// indices into the loops given.
#[derive(Debug, PartialEq)]
pub struct Region {
    pub outer: usize,
    pub holes: Vec<usize>,
}

/// Twice the signed area (positive when the loop turns from +x towards +y).
pub fn signed_area2(points: &[[f64; 2]]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| {
            let (a, b) = (points[i], points[(i + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum()
}

/// How many times `points` winds around `p` (positive when it turns from
/// +x towards +y).
fn winding(points: &[[f64; 2]], p: [f64; 2]) -> i32 {
    let n = points.len();
    let mut w = 0;
    for i in 0..n {
        let (a, b) = (points[i], points[(i + 1) % n]);
        let side = (b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1]);
        if a[1] <= p[1] {
            if b[1] > p[1] && side > 0.0 {
                w += 1;
            }
        } else if b[1] <= p[1] && side < 0.0 {
            w -= 1;
        }
    }
    w
}

/// Whether `p` is inside the loop `points`.
pub fn inside(points: &[[f64; 2]], p: [f64; 2]) -> bool {
    winding(points, p) != 0
}

/// A point of loop `i` of `loops` to ask which side the fill is on: the
/// midpoint of its first edge that lies on no other loop (a vertex may be
/// shared, as where two loops of a figure eight touch); its first edge's
/// midpoint where every one does.
fn probe(loops: &[FilledLoop], i: usize) -> [f64; 2] {
    let points = &loops[i].points;
    let n = points.len();
    let midpoint = |k: usize| {
        let (a, b) = (points[k], points[(k + 1) % n]);
        [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
    };
    let size = points
        .iter()
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(0.0, f64::max);
    let tol = 1e-9 * size.max(f64::MIN_POSITIVE);
    let on_another = |p: [f64; 2]| {
        loops.iter().enumerate().any(|(j, m)| {
            j != i
                && (0..m.points.len()).any(|k| {
                    let (a, b) = (m.points[k], m.points[(k + 1) % m.points.len()]);
                    point_segment_distance(p, a, b) <= tol
                })
        })
    };
    (0..n)
        .map(midpoint)
        .find(|&p| !on_another(p))
        .unwrap_or_else(|| midpoint(0))
}

/// Sorts `loops` into regions: each loop is an outer loop when the fill is
/// on its inside only, a hole when on its outside only (by its path's
/// `rules[element]`, counting the other loops of the same path); a loop
/// with fill on both sides (a loop drawn within the fill) bounds nothing
/// and is left out. Each hole goes to the smallest outer loop around it.
pub fn regions(loops: &[FilledLoop], rules: &[Rule]) -> Vec<Region> {
    let mut outers = Vec::new();
    let mut holes = Vec::new();
    for (i, l) in loops.iter().enumerate() {
        let p = probe(loops, i);
        let others: i32 = loops
            .iter()
            .enumerate()
            .filter(|&(j, m)| j != i && m.element == l.element)
            .map(|(_, m)| winding(&m.points, p))
            .sum();
        let own = if signed_area2(&l.points) > 0.0 { 1 } else { -1 };
        let filled = |w: i32| match rules[l.element] {
            Rule::NonZero => w != 0,
            Rule::EvenOdd => w % 2 != 0,
        };
        // Crossing counts of even-odd are windings' parities.
        match (filled(others), filled(others + own)) {
            (false, true) => outers.push(i),
            (true, false) => holes.push(i),
            _ => {}
        }
    }
    let area = |i: usize| signed_area2(&loops[i].points).abs();
    let mut found: Vec<Region> = outers
        .iter()
        .map(|&o| Region {
            outer: o,
            holes: Vec::new(),
        })
        .collect();
    for h in holes {
        let p = probe(loops, h);
        let around = found
            .iter_mut()
            .filter(|r| inside(&loops[r.outer].points, p))
            .min_by(|a, b| area(a.outer).total_cmp(&area(b.outer)));
        if let Some(r) = around {
            r.holes.push(h);
        }
    }
    found
}
