//! Small planar predicates and measures shared by the outline wing:
//! orientation, segment distances, polygon areas and containment, points
//! at an arc length along a loop or a polyline.

/// Twice the signed area of the triangle `a b c`: positive when the
/// corners turn counter-clockwise.
#[inline]
pub fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

#[inline]
pub(crate) fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

#[inline]
pub fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[inline]
pub fn lerp(a: [f64; 2], b: [f64; 2], s: f64) -> [f64; 2] {
    [a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s]
}

/// The point of the segment `a b` nearest to `p`.
pub(crate) fn nearest_on_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let d = sub(b, a);
    let len2 = d[0] * d[0] + d[1] * d[1];
    let s = if len2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    lerp(a, b, s)
}

/// Distance from `p` to the segment `a b`.
pub fn point_segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    dist(p, nearest_on_segment(p, a, b))
}

/// The nearest points of the segments `a b` and `c d`, one on each: where
/// they cross, their crossing twice.
pub fn nearest_points(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> ([f64; 2], [f64; 2]) {
    if segments_cross(a, b, c, d) {
        // a + s (b - a) on c d: orient(c, d, ·) is affine along a b.
        let (oa, ob) = (orient(c, d, a), orient(c, d, b));
        let x = lerp(a, b, oa / (oa - ob));
        return (x, x);
    }
    [
        (a, nearest_on_segment(a, c, d)),
        (b, nearest_on_segment(b, c, d)),
        (nearest_on_segment(c, a, b), c),
        (nearest_on_segment(d, a, b), d),
    ]
    .into_iter()
    .min_by(|(p, q), (r, s)| dist(*p, *q).total_cmp(&dist(*r, *s)))
    .expect("four candidates")
}

/// Whether the segments `a b` and `c d` cross at a point inside both.
pub fn segments_cross(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
        && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
}

/// Whether the segments `a b` and `c d` cross or come closer than `tol`.
pub fn segments_meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2], tol: f64) -> bool {
    segments_cross(a, b, c, d)
        || point_segment_distance(a, c, d) <= tol
        || point_segment_distance(b, c, d) <= tol
        || point_segment_distance(c, a, b) <= tol
        || point_segment_distance(d, a, b) <= tol
}

/// Edge `i` of loop `l` (from its point `i` to the next), with its x range
/// widened by the sweep's tolerance.
pub struct LoopEdge {
    pub(crate) l: usize,
    pub(crate) i: usize,
    pub(crate) a: [f64; 2],
    pub(crate) b: [f64; 2],
    lo: f64,
    hi: f64,
}

/// Every pair of edges of `loops` whose bounding boxes, widened by `tol`,
/// overlap, given to `visit` (the edge of smaller left end first) until it
/// breaks with a value, which is returned.
///
/// # Performance
/// A sweep along x: `O(n log n)` for the `n` edges plus the pairs whose x
/// ranges overlap.
pub fn near_edge_pairs<B>(
    loops: &[Vec<[f64; 2]>],
    tol: f64,
    mut visit: impl FnMut(&LoopEdge, &LoopEdge) -> std::ops::ControlFlow<B>,
) -> Option<B> {
    let mut edges = Vec::with_capacity(loops.iter().map(Vec::len).sum());
    for (l, pts) in loops.iter().enumerate() {
        let n = pts.len();
        for i in 0..n {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            edges.push(LoopEdge {
                l,
                i,
                a,
                b,
                lo: a[0].min(b[0]) - tol,
                hi: a[0].max(b[0]) + tol,
            });
        }
    }
    edges.sort_by(|e, f| e.lo.total_cmp(&f.lo));
    for x in 0..edges.len() {
        let e = &edges[x];
        let (lo_y, hi_y) = (e.a[1].min(e.b[1]) - tol, e.a[1].max(e.b[1]) + tol);
        for f in &edges[x + 1..] {
            if f.lo > e.hi {
                break;
            }
            if f.a[1].max(f.b[1]) < lo_y || f.a[1].min(f.b[1]) > hi_y {
                continue;
            }
            if let std::ops::ControlFlow::Break(value) = visit(e, f) {
                return Some(value);
            }
        }
    }
    None
}

/// Twice the signed area of a closed loop (shoelace formula): positive
/// when it turns counter-clockwise.
pub fn signed_area2(points: &[[f64; 2]]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| {
            let (p, q) = (points[i], points[(i + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum()
}

/// Whether `p` lies inside the closed loop (even-odd rule).
pub fn inside_loop(p: [f64; 2], points: &[[f64; 2]]) -> bool {
    let n = points.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (points[i], points[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if x > p[0] {
                inside = !inside;
            }
        }
    }
    inside
}

/// Length of the diagonal of the bounding box of `points`.
pub fn diagonal<'a>(points: impl IntoIterator<Item = &'a [f64; 2]>) -> f64 {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if lo[0] > hi[0] {
        return 0.0;
    }
    dist(lo, hi)
}

/// The smallest angle of the triangle `a b c`, in radians (0 for a
/// degenerate one).
pub(crate) fn min_angle(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    let corner = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        let (u, v) = (sub(q, p), sub(r, p));
        (u[0] * v[1] - u[1] * v[0])
            .abs()
            .atan2(u[0] * v[0] + u[1] * v[1])
    };
    corner(a, b, c).min(corner(b, c, a)).min(corner(c, a, b))
}

/// A closed loop measured by arc length: the point at any fraction of
/// its length.
pub struct ArcLoop<'a> {
    pub(crate) points: &'a [[f64; 2]],
    /// `cumulative[i]`: length from point 0 to point `i`, then the whole
    /// length as a last entry.
    pub(crate) cumulative: Vec<f64>,
}

impl<'a> ArcLoop<'a> {
    pub fn new(points: &'a [[f64; 2]]) -> Self {
        let n = points.len();
        let mut cumulative = Vec::with_capacity(n + 1);
        let mut total = 0.0;
        cumulative.push(0.0);
        for i in 0..n {
            total += dist(points[i], points[(i + 1) % n]);
            cumulative.push(total);
        }
        Self { points, cumulative }
    }

    pub fn length(&self) -> f64 {
        self.cumulative[self.points.len()]
    }

    /// The fraction of the length at which point `i` stands, in `[0, 1)`.
    pub(crate) fn param(&self, i: usize) -> f64 {
        self.cumulative[i] / self.length()
    }

    /// The point at fraction `t` of the length (taken modulo 1).
    pub(crate) fn at(&self, t: f64) -> [f64; 2] {
        let n = self.points.len();
        let s = t.rem_euclid(1.0) * self.length();
        let i = match self.cumulative.partition_point(|&c| c <= s) {
            0 => 0,
            k => (k - 1).min(n - 1),
        };
        let len = self.cumulative[i + 1] - self.cumulative[i];
        let f = if len > 0.0 {
            ((s - self.cumulative[i]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        lerp(self.points[i], self.points[(i + 1) % n], f)
    }
}
