//! Scan conversion shared by the 2D and 3D pictures: filled triangles with
//! an exact fill rule, and 1-pixel lines.
//!
//! Coordinates are pixels, `(0, 0)` the top-left corner of the top-left
//! pixel, y down; pixel `(x, y)` is sampled at its centre `(x + ½, y + ½)`.
//! Triangle corners are snapped to 1/256 pixel and the edge functions are
//! evaluated exactly in integers, with a tie rule that gives every pixel
//! centre on an edge or a vertex shared by triangles of a tessellation to
//! exactly one of them: no holes, no double-drawn pixels.

use super::Rect;

/// Sub-pixel bits of the snapped coordinates.
const SUB_BITS: u32 = 8;
const SUB: i64 = 1 << SUB_BITS;
const HALF: i64 = SUB / 2;
/// Triangles reaching further than this (in pixels) from the origin are
/// first clipped to this square, so that the edge functions of the rest fit
/// easily in `i64`: coordinates below 2^(18 + 8), products below 2^54.
const GUARD: f64 = (1u64 << 18) as f64;

/// A pixel rectangle in signed arithmetic: `x0 <= x < x1`, `y0 <= y < y1`.
#[derive(Clone, Copy, Debug)]
pub struct Clip {
    x0: i64,
    y0: i64,
    x1: i64,
    y1: i64,
}

impl Clip {
    /// The pixels of `rect` that are also inside a `width` × `height` image.
    pub fn new(rect: Rect, width: u32, height: u32) -> Self {
        let x1 = (u64::from(rect.x) + u64::from(rect.width)).min(u64::from(width));
        let y1 = (u64::from(rect.y) + u64::from(rect.height)).min(u64::from(height));
        Clip {
            x0: i64::from(rect.x),
            y0: i64::from(rect.y),
            x1: x1 as i64,
            y1: y1 as i64,
        }
    }

    fn is_empty(&self) -> bool {
        self.x0 >= self.x1 || self.y0 >= self.y1
    }
}

/// `v` pixels in 1/256 pixel, rounded (halves up); `v` within the guard.
#[inline]
fn snap(v: f64) -> i64 {
    // Truncating a positive number is `floor` in one instruction, where
    // `round` may be a library call; the offset keeps the number positive.
    const OFFSET: i64 = 1 << 40;
    ((v * SUB as f64 + 0.5) + OFFSET as f64) as i64 - OFFSET
}

/// The marker of [`snap_point`] for points the fast path cannot take.
const FAR: i64 = i64::MIN;

/// A point snapped once for all the triangles using it (see
/// [`fill_snapped`]).
#[inline]
pub(crate) fn snap_point(p: [f64; 2]) -> [i64; 2] {
    if p[0].abs() <= GUARD && p[1].abs() <= GUARD {
        [snap(p[0]), snap(p[1])]
    } else {
        [FAR, FAR]
    }
}

/// [`fill_triangle`] for corners `p` already snapped to `v` by
/// [`snap_point`].
#[inline]
pub(crate) fn fill_snapped(
    v: [[i64; 2]; 3],
    p: [[f64; 2]; 3],
    clip: &Clip,
    mut span: impl FnMut(usize, usize, usize),
) {
    if v[0][0] == FAR || v[1][0] == FAR || v[2][0] == FAR {
        fill_triangle(p, clip, span);
    } else if !clip.is_empty() {
        fill_fixed(v, clip, &mut span);
    }
}

/// Calls `span(y, x_start, x_end)` for every row `y` of pixels inside the
/// triangle `p` (pixel coordinates, either orientation) and `clip`, with
/// the covered pixels `x_start..x_end` of that row (never empty). Triangles
/// of zero area or with a non-finite coordinate cover nothing.
#[inline]
pub fn fill_triangle(p: [[f64; 2]; 3], clip: &Clip, mut span: impl FnMut(usize, usize, usize)) {
    if clip.is_empty() {
        return;
    }
    // Bounding box rejection; also rejects NaN (comparisons fail).
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in &p {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    if !(hi[0] >= clip.x0 as f64
        && lo[0] <= clip.x1 as f64
        && hi[1] >= clip.y0 as f64
        && lo[1] <= clip.y1 as f64)
    {
        return;
    }
    if p.iter().flatten().any(|v| !v.is_finite()) {
        return;
    }
    if lo[0] >= -GUARD && lo[1] >= -GUARD && hi[0] <= GUARD && hi[1] <= GUARD {
        fill_fixed(p.map(snap_point), clip, &mut span);
    } else {
        let poly = clip_to_guard(&p);
        for k in 2..poly.len() {
            let v = [poly[0], poly[k - 1], poly[k]].map(snap_point);
            fill_fixed(v, clip, &mut span);
        }
    }
}

/// The edge function of the directed edge `a -> b` as `(A, B, bias)` with
/// `E(p) = A (p.x - a.x) + B (p.y - a.y)`, positive inside a positively
/// oriented triangle. `bias` is 0 when a sample exactly on the edge belongs
/// to this side and -1 otherwise; the rule (the sample is nudged by
/// `(ε, ε²)`) is antisymmetric, so exactly one of two triangles sharing the
/// edge gets it, and it is consistent at shared vertices too.
#[inline(always)]
fn edge(a: [i64; 2], b: [i64; 2]) -> (i64, i64, i64) {
    let (ea, eb) = (a[1] - b[1], b[0] - a[0]);
    let owns = ea > 0 || (ea == 0 && eb > 0);
    (ea, eb, if owns { 0 } else { -1 })
}

#[inline(always)]
fn fill_fixed(v: [[i64; 2]; 3], clip: &Clip, span: &mut impl FnMut(usize, usize, usize)) {
    let [a, mut b, mut c] = v;
    let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if area == 0 {
        return;
    }
    if area < 0 {
        std::mem::swap(&mut b, &mut c);
    }
    // Pixels whose centres x * SUB + HALF lie in the bounding box.
    let min_x = a[0].min(b[0]).min(c[0]);
    let max_x = a[0].max(b[0]).max(c[0]);
    let min_y = a[1].min(b[1]).min(c[1]);
    let max_y = a[1].max(b[1]).max(c[1]);
    // (Arithmetic shifts are floor divisions by SUB.)
    let x0 = ((min_x - HALF + SUB - 1) >> SUB_BITS).max(clip.x0);
    let x1 = ((max_x - HALF) >> SUB_BITS).min(clip.x1 - 1);
    let y0 = ((min_y - HALF + SUB - 1) >> SUB_BITS).max(clip.y0);
    let y1 = ((max_y - HALF) >> SUB_BITS).min(clip.y1 - 1);
    if x0 > x1 || y0 > y1 {
        return;
    }
    // Edge functions (plus bias) at the centre of pixel (x0, y0), and their
    // steps per pixel; scalars, so that even a lightly optimised build
    // keeps them in registers.
    let (px, py) = (x0 * SUB + HALF, y0 * SUB + HALF);
    let (a0, b0, c0) = edge(b, c);
    let (a1, b1, c1) = edge(c, a);
    let (a2, b2, c2) = edge(a, b);
    let mut r0 = a0 * (px - b[0]) + b0 * (py - b[1]) + c0;
    let mut r1 = a1 * (px - c[0]) + b1 * (py - c[1]) + c1;
    let mut r2 = a2 * (px - a[0]) + b2 * (py - a[1]) + c2;
    let (sx0, sx1, sx2) = (a0 * SUB, a1 * SUB, a2 * SUB);
    let (sy0, sy1, sy2) = (b0 * SUB, b1 * SUB, b2 * SUB);
    for y in y0..=y1 {
        let (mut w0, mut w1, mut w2) = (r0, r1, r2);
        let mut x = x0;
        // Skip to the first covered pixel, then run to the end of the span
        // (a triangle's row is one span).
        while x <= x1 && (w0 | w1 | w2) < 0 {
            w0 += sx0;
            w1 += sx1;
            w2 += sx2;
            x += 1;
        }
        let start = x;
        while x <= x1 && (w0 | w1 | w2) >= 0 {
            w0 += sx0;
            w1 += sx1;
            w2 += sx2;
            x += 1;
        }
        if x > start {
            span(y as usize, start as usize, x as usize);
        }
        r0 += sy0;
        r1 += sy1;
        r2 += sy2;
    }
}

/// The triangle `p` clipped to the guard square, as a convex polygon.
/// Intersections are computed from the edge's endpoints in a fixed order so
/// that two triangles sharing an edge get the same points.
fn clip_to_guard(p: &[[f64; 2]; 3]) -> Vec<[f64; 2]> {
    let mut poly: Vec<[f64; 2]> = p.to_vec();
    for (axis, sign) in [(0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0)] {
        // Keep sign * q[axis] <= GUARD.
        let inside = |q: &[f64; 2]| sign * q[axis] <= GUARD;
        let mut out = Vec::with_capacity(poly.len() + 1);
        for i in 0..poly.len() {
            let (s, e) = (poly[i], poly[(i + 1) % poly.len()]);
            if inside(&s) {
                out.push(s);
            }
            if inside(&s) != inside(&e) {
                let (u, w) = if (s[0], s[1]) < (e[0], e[1]) {
                    (s, e)
                } else {
                    (e, s)
                };
                let t = (sign * GUARD - u[axis]) / (w[axis] - u[axis]);
                let mut q = [u[0] + t * (w[0] - u[0]), u[1] + t * (w[1] - u[1])];
                q[axis] = sign * GUARD;
                out.push(q);
            }
        }
        poly = out;
        if poly.len() < 3 {
            return Vec::new();
        }
    }
    poly
}

/// Calls `plot(x, y, t)` for the pixels of a 1-pixel line from `a` to `b`
/// (pixel coordinates; `t` goes from 0 at `a` to 1 at `b`) that are inside
/// `clip`: Bresenham between the pixels containing the (clipped) endpoints.
pub fn draw_line(a: [f64; 2], b: [f64; 2], clip: &Clip, mut plot: impl FnMut(usize, usize, f32)) {
    if clip.is_empty() || a.iter().chain(&b).any(|v| !v.is_finite()) {
        return;
    }
    // Liang-Barsky against the clip rectangle, slightly shrunk so that the
    // endpoint pixels are inside it.
    let (lo, hi) = (
        [clip.x0 as f64, clip.y0 as f64],
        [clip.x1 as f64 - 1e-6, clip.y1 as f64 - 1e-6],
    );
    let d = [b[0] - a[0], b[1] - a[1]];
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for k in 0..2 {
        for (q, r) in [(-d[k], a[k] - lo[k]), (d[k], hi[k] - a[k])] {
            if q == 0.0 {
                if r < 0.0 {
                    return;
                }
            } else {
                let t = r / q;
                if q < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
    }
    if t0 > t1 || !t0.is_finite() || !t1.is_finite() {
        return;
    }
    let at = |t: f64, k: usize| {
        ((a[k] + t * d[k]).floor() as i64).clamp([clip.x0, clip.y0][k], [clip.x1, clip.y1][k] - 1)
    };
    let (mut x, mut y) = (at(t0, 0), at(t0, 1));
    let (xe, ye) = (at(t1, 0), at(t1, 1));
    let (dx, dy) = ((xe - x).abs(), -(ye - y).abs());
    let (sx, sy) = (if x < xe { 1 } else { -1 }, if y < ye { 1 } else { -1 });
    let n = dx.max(-dy).max(1) as f32;
    let (t0f, span) = (t0 as f32, (t1 - t0) as f32);
    let mut err = dx + dy;
    let mut i = 0.0f32;
    loop {
        plot(x as usize, y as usize, t0f + span * (i / n));
        if x == xe && y == ye {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
        i += 1.0;
    }
}
