//! Which hole of the second drawing goes with which hole of the first:
//! the second drawing is laid over the first by the least-squares
//! similarity of their matched outer loops (`Similarity`, which also
//! breaks ties when a hole is matched), and the holes are paired so
//! that their centroids are as close as they can be (every pairing tried
//! for up to 7 holes, the closest pairs first beyond).

use super::boundary::MatchedPoint;
use super::geometry::signed_area2;

/// Area centroid of a loop.
fn centroid(points: &[[f64; 2]]) -> [f64; 2] {
    let n = points.len();
    let (mut cx, mut cy) = (0.0, 0.0);
    for i in 0..n {
        let (p, q) = (points[i], points[(i + 1) % n]);
        let w = p[0] * q[1] - q[0] * p[1];
        cx += (p[0] + q[0]) * w;
        cy += (p[1] + q[1]) * w;
    }
    let a = 3.0 * signed_area2(points);
    [cx / a, cy / a]
}

/// The similarity that best lays the second drawing's matched outer loop
/// onto the first's (least squares, in complex numbers `z_a = s z_b +
/// t`): where a point of the second drawing sits in the first's frame.
#[derive(Clone, Copy, Debug)]
pub struct Similarity {
    ma: [f64; 2],
    mb: [f64; 2],
    sr: f64,
    si: f64,
}

impl Similarity {
    pub(crate) fn of_outer(outer: &[MatchedPoint]) -> Self {
        let (a, b): (Vec<[f64; 2]>, Vec<[f64; 2]>) = outer.iter().map(|p| (p.a, p.b)).unzip();
        Self::of_points(&a, &b)
    }

    /// The similarity that best lays points `b` onto points `a`.
    pub(crate) fn of_points(pa: &[[f64; 2]], pb: &[[f64; 2]]) -> Self {
        let n = pa.len() as f64;
        let ma = pa
            .iter()
            .fold([0.0, 0.0], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n]);
        let mb = pb
            .iter()
            .fold([0.0, 0.0], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n]);
        let (mut re, mut im, mut norm) = (0.0, 0.0, 0.0);
        for (p, q) in pa.iter().zip(pb) {
            let (a, b) = ([p[0] - ma[0], p[1] - ma[1]], [q[0] - mb[0], q[1] - mb[1]]);
            re += b[0] * a[0] + b[1] * a[1];
            im += b[0] * a[1] - b[1] * a[0];
            norm += b[0] * b[0] + b[1] * b[1];
        }
        let (sr, si) = if norm > 0.0 {
            (re / norm, im / norm)
        } else {
            (1.0, 0.0)
        };
        Self { ma, mb, sr, si }
    }

    /// A point of the second drawing in the first's frame.
    pub(crate) fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        let d = [p[0] - self.mb[0], p[1] - self.mb[1]];
        [
            self.sr * d[0] - self.si * d[1] + self.ma[0],
            self.si * d[0] + self.sr * d[1] + self.ma[1],
        ]
    }
}

/// Distances between the first drawing's hole centroids and the second's,
/// laid onto the first by `frame`: `[i][j]` for hole `i` of the first and
/// `j` of the second.
fn hole_distances(
    holes_a: &[Vec<[f64; 2]>],
    holes_b: &[Vec<[f64; 2]>],
    frame: &Similarity,
) -> Vec<Vec<f64>> {
    let ca: Vec<[f64; 2]> = holes_a.iter().map(|l| centroid(l)).collect();
    let cb: Vec<[f64; 2]> = holes_b.iter().map(|l| frame.apply(centroid(l))).collect();
    ca.iter()
        .map(|p| {
            cb.iter()
                .map(|q| (p[0] - q[0]).hypot(p[1] - q[1]))
                .collect()
        })
        .collect()
}

/// How far the holes land from each other when the second drawing is laid
/// onto the first by `frame`: for each hole of the first, the distance to
/// the closest hole of the second, summed.
pub fn holes_misplaced(
    holes_a: &[Vec<[f64; 2]>],
    holes_b: &[Vec<[f64; 2]>],
    frame: &Similarity,
) -> f64 {
    hole_distances(holes_a, holes_b, frame)
        .iter()
        .map(|row| row.iter().copied().fold(f64::INFINITY, f64::min))
        .sum()
}

/// For each hole of the first drawing (0-based among the holes), the hole
/// of the second it pairs with: the pairing that puts the holes' centres
/// closest once the second drawing is laid onto the first by `frame`.
pub(crate) fn pair_holes(
    holes_a: &[Vec<[f64; 2]>],
    holes_b: &[Vec<[f64; 2]>],
    frame: &Similarity,
) -> Vec<usize> {
    let h = holes_a.len();
    if h <= 1 {
        return (0..h).collect();
    }
    let cost = hole_distances(holes_a, holes_b, frame);
    let cost = |i: usize, j: usize| cost[i][j];
    if h <= 7 {
        let mut perm: Vec<usize> = (0..h).collect();
        let mut best = (f64::INFINITY, perm.clone());
        permutations(&mut perm, 0, &mut |p| {
            let c: f64 = p.iter().enumerate().map(|(i, &j)| cost(i, j)).sum();
            if c < best.0 {
                best = (c, p.to_vec());
            }
        });
        return best.1;
    }
    let mut pairs: Vec<(f64, usize, usize)> = (0..h)
        .flat_map(|i| (0..h).map(move |j| (i, j)))
        .map(|(i, j)| (cost(i, j), i, j))
        .collect();
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut out = vec![usize::MAX; h];
    let mut used = vec![false; h];
    for (_, i, j) in pairs {
        if out[i] == usize::MAX && !used[j] {
            out[i] = j;
            used[j] = true;
        }
    }
    out
}

fn permutations(p: &mut [usize], k: usize, f: &mut impl FnMut(&[usize])) {
    if k == p.len() {
        f(p);
        return;
    }
    for i in k..p.len() {
        p.swap(k, i);
        permutations(p, k + 1, f);
        p.swap(k, i);
    }
}
