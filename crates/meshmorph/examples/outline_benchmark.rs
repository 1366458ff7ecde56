//! Drawings morphed by meshmorph against GSAP's MorphSVG and flubber: the
//! same pairs of outlines (drawn here in code), 11 frames each, judged by
//! one set of measures computed here for every method.
//!
//! `tools/bench/outline-morph/run` runs it all: this example writes the
//! pairs (`pairs FILE.json`), the node script beside the run script
//! morphs them with the peers and writes their frames, then this example
//! reads those (`table FILE.json`), morphs the pairs itself (compatible
//! meshes, then as-rigid-as-possible frames) and prints the tables:
//!
//! - **ends**: the Hausdorff distance of the first and last frames to the
//!   two drawings, in per cent of the drawing's diagonal (< 0.1 %);
//! - **crossed**: frames (of 11) whose outline crosses or touches itself,
//!   or whose hole crosses, touches or leaves the outer loop;
//! - **flipped**: triangles turned over, summed over the frames (meshes
//!   only);
//! - **area**: the smallest and largest ratio of a frame's area to the
//!   straight blend of the two drawings' areas (0.85 to 1.2; 0.97 to 1.03
//!   for a shape and its rotation);
//! - **edges**: the mean relative deviation of the outline's edge lengths
//!   from the straight blend of their lengths in the first and last frames
//!   (0 for a rigid turn);
//!
//! then the times of two 500-point outlines to 60 SVG path strings
//! (setup, and per frame), for every method on one thread.
//!
//! meshmorph morphs as the command line does (`--stretch area`, outlines
//! untied, folds mended); `MM_STRETCH=linear` in the environment takes the
//! paper's linear blend of the stretches instead, for comparison.

use std::f64::consts::{PI, TAU};
use std::fmt::Write as _;
use std::time::Instant;

use meshmorph::outline::{compatible_set, CompatibleSet, Drawing, OutlineOptions};
use meshmorph::{shapes, Interpolator, InterpolatorOptions};
use serde_json::{json, Value};

type Point = [f64; 2];
type Loops = Vec<Vec<Point>>;

#[path = "support/outline_edges.rs"]
mod outline_edges;
use outline_edges::edges_off_blend;

const FRAMES: usize = 11;

/// A pair of drawings to morph.
struct Pair {
    name: &'static str,
    /// The second drawing is the first turned (tighter area target).
    rotation: bool,
    a: Loops,
    b: Loops,
}

// ---------------------------------------------------------------- shapes

/// A wavy five-pointed star with one long arm (so that no turn but its own
/// lays it onto itself), `n` points, radius about `r`, centred at `c`.
fn star(n: usize, r: f64, c: Point) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let a = TAU * k as f64 / n as f64;
            let arm = (a - 0.6 + PI).rem_euclid(TAU) - PI;
            let s = r
                * (1.0
                    + 0.25 * (5.0 * a).cos()
                    + 0.08 * (11.0 * a + 1.0).sin()
                    + 0.6 * (-arm * arm / 0.03).exp());
            [c[0] + s * a.cos(), c[1] + s * a.sin()]
        })
        .collect()
}

/// A polygon's edges sampled about `spacing` apart (its corners kept).
fn sampled(corners: &[Point], spacing: f64) -> Vec<Point> {
    let mut out = Vec::new();
    for i in 0..corners.len() {
        let (a, b) = (corners[i], corners[(i + 1) % corners.len()]);
        let n = ((dist(a, b) / spacing).ceil() as usize).max(1);
        out.extend((0..n).map(|k| {
            let s = k as f64 / n as f64;
            [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]
        }));
    }
    out
}

/// An arrow pointing along x, 200 long: long enough that no start offset
/// of the outline passes for its turn.
fn arrow(spacing: f64) -> Vec<Point> {
    let corners = [
        [-100.0, -12.0],
        [40.0, -12.0],
        [40.0, -35.0],
        [100.0, 0.0],
        [40.0, 35.0],
        [40.0, 12.0],
        [-100.0, 12.0],
    ];
    sampled(&corners, spacing)
}

/// `points` turned by `angle` about `about`, moved by `shift`, started
/// `restart` points later.
fn turned(points: &[Point], angle: f64, about: Point, shift: Point, restart: usize) -> Vec<Point> {
    let (s, c) = angle.sin_cos();
    let mut out: Vec<Point> = points
        .iter()
        .map(|p| {
            let (x, y) = (p[0] - about[0], p[1] - about[1]);
            [
                about[0] + shift[0] + c * x - s * y,
                about[1] + shift[1] + s * x + c * y,
            ]
        })
        .collect();
    out.rotate_left(restart % points.len());
    out
}

/// The outline of a stroke of half-width `w` along a turtle's path
/// ([`shapes::stroke_outline`]).
fn stroke(start: Point, heading: f64, steps: &[(f64, f64)], w: f64, spacing: f64) -> Vec<Point> {
    shapes::stroke_outline(start, heading, steps, &|_| w, spacing)
}

/// A circle (or a superellipse with exponent `e`) of `n` points, radii
/// `rx`, `ry`, turned by `angle`, centred at `c`, clockwise when `hole`.
fn round(n: usize, c: Point, rx: f64, ry: f64, e: f64, angle: f64, hole: bool) -> Vec<Point> {
    let (s, co) = angle.sin_cos();
    let mut out: Vec<Point> = (0..n)
        .map(|k| {
            let a = TAU * k as f64 / n as f64;
            let (ca, sa) = (a.cos(), a.sin());
            let x = rx * ca.signum() * ca.abs().powf(2.0 / e);
            let y = ry * sa.signum() * sa.abs().powf(2.0 / e);
            [c[0] + co * x - s * y, c[1] + s * x + co * y]
        })
        .collect();
    if hole {
        out.reverse();
    }
    out
}

/// A thick curl: a band of half-width `0.15 r` along an inward spiral.
fn curl(n: usize, r: f64, c: Point) -> Vec<Point> {
    let centre = |t: f64| {
        let a = 0.5 + (TAU + 0.7) * t;
        let s = r * (1.0 - 0.45 * t);
        [s * a.cos() + c[0], s * a.sin() + c[1]]
    };
    let side = |t: f64, sign: f64| {
        let (p, q) = (centre((t - 1e-4).max(0.0)), centre((t + 1e-4).min(1.0)));
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let l = dx.hypot(dy);
        let m = centre(t);
        [
            m[0] - sign * 0.15 * r * dy / l,
            m[1] + sign * 0.15 * r * dx / l,
        ]
    };
    let half = n / 2;
    let mut out: Vec<Point> = (0..half)
        .map(|k| side(k as f64 / (half - 1) as f64, -1.0))
        .collect();
    out.extend((0..n - half).map(|k| side(1.0 - k as f64 / (n - half - 1) as f64, 1.0)));
    out.rotate_left(n / 4);
    out
}

/// The letter C as a stroke (unit 100 drawing units).
fn letter_c(spacing: f64) -> Vec<Point> {
    let a0 = 40f64.to_radians();
    stroke(
        [100.0 * a0.cos(), 100.0 * a0.sin()],
        a0 + PI / 2.0,
        &[(100.0 * 280f64.to_radians(), 280f64.to_radians())],
        16.0,
        spacing,
    )
}

/// The letter G as a stroke: the C's arc a little longer, then turning in
/// to a bar.
fn letter_g(spacing: f64, at: Point) -> Vec<Point> {
    let a0 = 40f64.to_radians();
    let turn = 125f64.to_radians();
    stroke(
        [at[0] + 100.0 * a0.cos(), at[1] + 100.0 * a0.sin()],
        a0 + PI / 2.0,
        &[
            (100.0 * 285f64.to_radians(), 285f64.to_radians()),
            (30.0 * turn, turn),
            (30.0, 0.0),
        ],
        16.0,
        spacing,
    )
}

/// A thin arm (upper arm, elbow, forearm), its elbow bent by `bend`.
fn arm(bend: f64, spacing: f64, at: Point, heading: f64) -> Vec<Point> {
    stroke(
        at,
        heading,
        &[(100.0, 0.0), (30.0, bend), (90.0, 0.0)],
        7.0,
        spacing,
    )
}

/// Points along an arc of radius `r` about `c` from angle `a0` to `a1`
/// (radians), `n` of them, the last left out.
fn arc(c: Point, r: f64, a0: f64, a1: f64, n: usize) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let a = a0 + (a1 - a0) * k as f64 / n as f64;
            [c[0] + r * a.cos(), c[1] + r * a.sin()]
        })
        .collect()
}

/// A hand, fingers up and the thumb out to its side, about 150 tall.
fn hand(spacing: f64) -> Vec<Point> {
    let corners = [
        [-25.0, -30.0],
        [25.0, -30.0],
        [30.0, 0.0],
        [45.0, 20.0],
        [62.0, 44.0],
        [54.0, 52.0],
        [34.0, 36.0],
        [30.0, 60.0],
        [30.0, 100.0],
        [20.0, 100.0],
        [18.5, 60.0],
        [16.0, 60.0],
        [16.0, 112.0],
        [4.0, 112.0],
        [3.0, 60.0],
        [0.5, 60.0],
        [0.5, 115.0],
        [-11.0, 115.0],
        [-12.0, 60.0],
        [-14.5, 60.0],
        [-15.0, 104.0],
        [-26.0, 104.0],
        [-28.0, 60.0],
        [-31.0, 0.0],
    ];
    sampled(&corners, spacing)
}

/// A claw hammer standing on its handle, about 150 tall.
fn hammer(spacing: f64) -> Vec<Point> {
    let corners = [
        [-8.0, -60.0],
        [8.0, -60.0],
        [8.0, 60.0],
        [45.0, 60.0],
        [50.0, 75.0],
        [45.0, 90.0],
        [-45.0, 90.0],
        [-62.0, 74.0],
        [-42.0, 76.0],
        [-8.0, 60.0],
    ];
    sampled(&corners, spacing)
}

/// A horse's silhouette, facing right: thin legs, a neck and a head.
fn horse(spacing: f64) -> Vec<Point> {
    let corners = [
        [-60.0, 40.0],
        [-82.0, 8.0],
        [-76.0, 6.0],
        [-62.0, 26.0],
        [-60.0, 0.0],
        [-58.0, -50.0],
        [-49.0, -50.0],
        [-46.0, 0.0],
        [-35.0, 0.0],
        [-33.0, -50.0],
        [-24.0, -50.0],
        [-21.0, 0.0],
        [30.0, 0.0],
        [32.0, -50.0],
        [41.0, -50.0],
        [43.0, 0.0],
        [50.0, 0.0],
        [52.0, -50.0],
        [61.0, -50.0],
        [62.0, 5.0],
        [66.0, 22.0],
        [86.0, 52.0],
        [110.0, 48.0],
        [113.0, 60.0],
        [96.0, 76.0],
        [90.0, 90.0],
        [84.0, 78.0],
        [60.0, 46.0],
    ];
    sampled(&corners, spacing)
}

/// An elephant's silhouette, facing right: thick legs, a trunk, big
/// ears over the neck.
fn elephant(spacing: f64) -> Vec<Point> {
    let corners = [
        [-70.0, 55.0],
        [-84.0, 14.0],
        [-79.0, 12.0],
        [-72.0, 30.0],
        [-70.0, -5.0],
        [-68.0, -50.0],
        [-47.0, -50.0],
        [-44.0, -5.0],
        [-30.0, -5.0],
        [-28.0, -50.0],
        [-7.0, -50.0],
        [-4.0, -5.0],
        [25.0, -5.0],
        [27.0, -50.0],
        [48.0, -50.0],
        [50.0, -5.0],
        [55.0, -5.0],
        [57.0, -50.0],
        [78.0, -50.0],
        [80.0, 0.0],
        [84.0, 8.0],
        [92.0, -40.0],
        [101.0, -38.0],
        [97.0, 12.0],
        [102.0, 42.0],
        [90.0, 72.0],
        [66.0, 78.0],
        [46.0, 66.0],
        [40.0, 30.0],
        [30.0, 60.0],
    ];
    sampled(&corners, spacing)
}

/// Points from `a` (included) towards `b` (left out), about `spacing`
/// apart.
fn line(a: Point, b: Point, spacing: f64) -> Vec<Point> {
    let n = ((dist(a, b) / spacing).ceil() as usize).max(1);
    (0..n)
        .map(|k| {
            let s = k as f64 / n as f64;
            [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]
        })
        .collect()
}

/// The letter B: a straight back and two bowls, with two holes.
fn letter_b(spacing: f64) -> Loops {
    let per = |r: f64, turn: f64| ((r * turn / spacing).ceil() as usize).max(8);
    let mut outer = line([-50.0, 100.0], [-50.0, -100.0], spacing);
    outer.extend(line([-50.0, -100.0], [20.0, -100.0], spacing));
    outer.extend(arc([20.0, -50.0], 50.0, -PI / 2.0, PI / 2.0, per(50.0, PI)));
    outer.extend(line([20.0, 0.0], [15.0, 0.0], spacing));
    outer.extend(arc([15.0, 50.0], 50.0, -PI / 2.0, PI / 2.0, per(50.0, PI)));
    outer.extend(line([15.0, 100.0], [-50.0, 100.0], spacing));
    let hole = |c: Point| {
        let mut h = arc(c, 24.0, 0.0, TAU, per(24.0, TAU));
        h.reverse();
        h
    };
    vec![outer, hole([-5.0, -50.0]), hole([-8.0, 50.0])]
}

/// The digit 8: a tall loop pinched at its waist, two round holes.
fn digit_8(spacing: f64, at: Point) -> Loops {
    let n = (600.0 / spacing) as usize;
    let outer: Vec<Point> = (0..n)
        .map(|k| {
            let a = TAU * k as f64 / n as f64;
            let pinch = 1.0 - 0.5 * (-(a.sin() * a.sin()) / 0.02).exp();
            [at[0] + 55.0 * a.cos() * pinch, at[1] + 100.0 * a.sin()]
        })
        .collect();
    let hole = |c: Point| {
        let mut h = round(
            ((TAU * 27.0 / spacing) as usize).max(12),
            c,
            25.0,
            30.0,
            2.0,
            0.0,
            false,
        );
        h.reverse();
        h
    };
    vec![
        outer,
        hole([at[0], at[1] - 48.0]),
        hole([at[0], at[1] + 48.0]),
    ]
}

/// The benchmark's pairs, in drawing units (about 200 across, as an SVG).
fn pairs() -> Vec<Pair> {
    let s = arrow(5.0);
    let ring = vec![
        round(120, [0.0, 0.0], 80.0, 80.0, 2.0, 0.0, false),
        round(60, [15.0, 10.0], 35.0, 35.0, 2.0, 0.0, true),
    ];
    vec![
        Pair {
            name: "arrow, turned 120°",
            rotation: true,
            b: vec![turned(
                &s,
                120f64.to_radians(),
                [0.0, 0.0],
                [40.0, 10.0],
                37,
            )],
            a: vec![s.clone()],
        },
        Pair {
            name: "arrow, turned 180°",
            rotation: true,
            b: vec![turned(&s, PI, [0.0, 0.0], [40.0, 10.0], 61)],
            a: vec![s.clone()],
        },
        Pair {
            name: "thin arm, elbow bent 150°",
            rotation: false,
            a: vec![arm(0.0, 4.0, [0.0, 0.0], 0.0)],
            b: vec![arm(150f64.to_radians(), 3.0, [0.0, 0.0], 0.0)],
        },
        Pair {
            name: "ring (a hole), turned 150°",
            rotation: true,
            a: ring.clone(),
            b: ring
                .iter()
                .map(|l| turned(l, 150f64.to_radians(), [0.0, 0.0], [30.0, -20.0], 11))
                .collect(),
        },
        Pair {
            name: "ring (a hole), to a squarer ring turned 90°",
            rotation: false,
            a: ring.clone(),
            b: vec![
                round(140, [30.0, 0.0], 75.0, 90.0, 4.0, PI / 2.0, false),
                round(50, [15.0, 15.0], 45.0, 25.0, 2.0, PI / 2.0, true),
            ],
        },
        Pair {
            name: "C to G",
            rotation: false,
            a: vec![letter_c(6.0)],
            b: vec![letter_g(5.0, [0.0, 0.0])],
        },
        Pair {
            name: "hand to hammer",
            rotation: false,
            a: vec![hand(5.0)],
            b: vec![hammer(5.0)],
        },
        Pair {
            name: "horse to elephant",
            rotation: false,
            a: vec![horse(4.0)],
            b: vec![elephant(4.0)],
        },
        Pair {
            name: "B to 8 (two holes)",
            rotation: false,
            a: letter_b(5.0),
            b: digit_8(5.0, [10.0, 0.0]),
        },
        Pair {
            name: "star to curl",
            rotation: false,
            a: vec![star(150, 80.0, [0.0, 0.0])],
            b: vec![curl(180, 90.0, [0.0, 0.0])],
        },
    ]
}

/// The timed pairs: 500 points an outline.
fn timed_pairs() -> Vec<Pair> {
    let s = star(500, 80.0, [0.0, 0.0]);
    vec![
        Pair {
            name: "500-point star, turned 120°",
            rotation: true,
            b: vec![turned(&s, 2.1, [0.0, 0.0], [40.0, 10.0], 77)],
            a: vec![s.clone()],
        },
        Pair {
            name: "500-point star to curl",
            rotation: false,
            a: vec![s],
            b: vec![curl(500, 90.0, [0.0, 0.0])],
        },
    ]
}

// -------------------------------------------------------------- measures

fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1]]
}

fn cross(a: Point, b: Point) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn dist(a: Point, b: Point) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn point_segment(p: Point, a: Point, b: Point) -> f64 {
    let e = sub(b, a);
    let l2 = e[0] * e[0] + e[1] * e[1];
    let s = if l2 > 0.0 {
        (((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, [a[0] + s * e[0], a[1] + s * e[1]])
}

/// Distance between segments `ab` and `cd` (0 when they cross).
fn segment_segment(a: Point, b: Point, c: Point, d: Point) -> f64 {
    let (d1, d2) = (cross(sub(b, a), sub(c, a)), cross(sub(b, a), sub(d, a)));
    let (d3, d4) = (cross(sub(d, c), sub(a, c)), cross(sub(d, c), sub(b, c)));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return 0.0;
    }
    point_segment(a, c, d)
        .min(point_segment(b, c, d))
        .min(point_segment(c, a, b))
        .min(point_segment(d, a, b))
}

fn diagonal(loops: &Loops) -> f64 {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in loops.iter().flatten() {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    dist(lo, hi)
}

/// Symmetric Hausdorff distance between two sets of closed polylines
/// (points of each to the segments of the other).
fn hausdorff(p: &Loops, q: &Loops) -> f64 {
    let one_way = |p: &Loops, q: &Loops| {
        p.iter()
            .flatten()
            .map(|&x| {
                q.iter()
                    .flat_map(|l| {
                        (0..l.len()).map(move |i| point_segment(x, l[i], l[(i + 1) % l.len()]))
                    })
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    };
    one_way(p, q).max(one_way(q, p))
}

fn signed_area(l: &[Point]) -> f64 {
    (0..l.len())
        .map(|i| cross(l[i], l[(i + 1) % l.len()]))
        .sum::<f64>()
        / 2.0
}

/// The area of a region: its largest loop's less the others'.
fn region_area(loops: &Loops) -> f64 {
    let areas: Vec<f64> = loops.iter().map(|l| signed_area(l).abs()).collect();
    let outer = areas.iter().copied().fold(0.0, f64::max);
    2.0 * outer - areas.iter().sum::<f64>()
}

fn inside(p: Point, l: &[Point]) -> bool {
    let mut odd = false;
    for i in 0..l.len() {
        let (a, b) = (l[i], l[(i + 1) % l.len()]);
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0])
        {
            odd = !odd;
        }
    }
    odd
}

/// A frame's outline crosses or touches itself (closer than `eps`), or a
/// hole is outside its outer loop (the loop of largest area).
fn crossed(loops: &Loops, eps: f64) -> bool {
    // Repeated points (a peer's degenerate curve pieces) are one point.
    let loops: Loops = loops
        .iter()
        .map(|l| {
            let mut out: Vec<Point> = Vec::with_capacity(l.len());
            for &p in l {
                if out.last().is_none_or(|&q| dist(p, q) > eps) {
                    out.push(p);
                }
            }
            while out.len() > 1 && dist(out[0], out[out.len() - 1]) <= eps {
                out.pop();
            }
            out
        })
        .collect();
    let mut segments: Vec<(usize, usize, Point, Point)> = Vec::new();
    for (l, pts) in loops.iter().enumerate() {
        for i in 0..pts.len() {
            segments.push((l, i, pts[i], pts[(i + 1) % pts.len()]));
        }
    }
    // Sweep along x: only segments whose x ranges overlap are compared.
    let lo = |s: &(usize, usize, Point, Point)| s.2[0].min(s.3[0]);
    segments.sort_by(|x, y| lo(x).total_cmp(&lo(y)));
    for i in 0..segments.len() {
        let (l, a, p, q) = segments[i];
        let hi = p[0].max(q[0]) + eps;
        for &(m, b, r, s) in &segments[i + 1..] {
            if lo(&(m, b, r, s)) > hi {
                break;
            }
            if l == m {
                let n = loops[l].len();
                if (a + 1) % n == b || (b + 1) % n == a {
                    continue;
                }
            }
            if segment_segment(p, q, r, s) <= eps {
                return true;
            }
        }
    }
    let outer = (0..loops.len())
        .max_by(|&x, &y| {
            signed_area(&loops[x])
                .abs()
                .total_cmp(&signed_area(&loops[y]).abs())
        })
        .unwrap_or(0);
    (0..loops.len())
        .any(|h| h != outer && !loops[h].is_empty() && !inside(loops[h][0], &loops[outer]))
}

/// One method's measures on one pair.
#[derive(Default)]
struct Measures {
    ends: f64,
    crossed: usize,
    flipped: Option<usize>,
    area: [f64; 2],
    edges: f64,
    points: usize,
}

fn measure(frames: &[Loops], pair: &Pair) -> Measures {
    let n = frames.len();
    let ends = (hausdorff(&frames[0], &pair.a) / diagonal(&pair.a))
        .max(hausdorff(&frames[n - 1], &pair.b) / diagonal(&pair.b));
    let eps = 1e-7 * diagonal(&pair.a);
    let (area_a, area_b) = (region_area(&pair.a), region_area(&pair.b));
    let mut area = [f64::INFINITY, 0.0f64];
    for (k, frame) in frames.iter().enumerate() {
        let t = k as f64 / (n - 1) as f64;
        let ratio = region_area(frame) / ((1.0 - t) * area_a + t * area_b);
        area = [area[0].min(ratio), area[1].max(ratio)];
    }
    Measures {
        ends,
        crossed: frames.iter().filter(|f| crossed(f, eps)).count(),
        flipped: None,
        area,
        edges: edges_off_blend(frames, eps),
        points: frames[0].iter().map(Vec::len).sum(),
    }
}

// ------------------------------------------------------------ meshmorph

/// The pair's compatible meshes and the as-rigid-as-possible
/// interpolation between them.
fn morph(pair: &Pair) -> meshmorph::Result<(CompatibleSet, Interpolator<2>)> {
    let drawings = [Drawing::new(pair.a.clone())?, Drawing::new(pair.b.clone())?];
    let set = compatible_set(&drawings, &[], &OutlineOptions::default())?;
    // As the command line morphs drawings: the triangles' areas kept on
    // their blend, outlines untied, folds mended (`MM_STRETCH=linear`: the
    // published linear blend of the stretches instead, for comparison).
    let morph = Interpolator::new(
        &set.meshes[0],
        &set.meshes[1],
        &InterpolatorOptions::default()
            .with_mend_folds(true)
            .with_untie_outlines(true)
            .with_outline_lengths(std::env::var("MM_OUTLINE").as_deref() != Ok("fit"))
            .with_stretch(if std::env::var("MM_STRETCH").as_deref() == Ok("linear") {
                meshmorph::StretchMode::Linear
            } else {
                meshmorph::StretchMode::AreaBlend
            }),
    )?;
    Ok((set, morph))
}

/// The pair's frames by meshmorph: compatible meshes, then
/// as-rigid-as-possible frames; the outline from the meshes' loops.
fn ours(pair: &Pair) -> meshmorph::Result<(Vec<Loops>, usize, String)> {
    let (meshes, morph) = morph(pair)?;
    let triangles = meshes.meshes[0].triangles();
    let mut flipped = 0;
    let mut frames = Vec::with_capacity(FRAMES);
    for k in 0..FRAMES {
        let x = morph.at(k as f64 / (FRAMES - 1) as f64);
        flipped += triangles
            .iter()
            .filter(|t| {
                cross(
                    sub(x[t[1] as usize], x[t[0] as usize]),
                    sub(x[t[2] as usize], x[t[0] as usize]),
                ) <= 0.0
            })
            .count();
        frames.push(
            meshes
                .loops
                .iter()
                .map(|l| l.iter().map(|&v| x[v as usize]).collect())
                .collect(),
        );
    }
    Ok((frames, flipped, meshes.report.to_string()))
}

/// An SVG path of `loops` (two decimals, as the peers write theirs).
fn path_string(loops: &[Vec<u32>], x: &[Point], out: &mut String) {
    out.clear();
    for l in loops {
        for (i, &v) in l.iter().enumerate() {
            let p = x[v as usize];
            let _ = write!(
                out,
                "{}{:.2} {:.2} ",
                if i == 0 { 'M' } else { 'L' },
                p[0],
                p[1]
            );
        }
        out.push('Z');
    }
}

/// Setup (drawings to an interpolator) and per-frame (a frame and its SVG
/// path string) times of meshmorph on `pair`, seconds: the median of three.
fn time_ours(pair: &Pair) -> meshmorph::Result<(f64, f64)> {
    let mut runs = Vec::new();
    for _ in 0..3 {
        let start = Instant::now();
        let (meshes, morph) = morph(pair)?;
        let setup = start.elapsed().as_secs_f64();
        let mut x = vec![[0.0; 2]; morph.num_vertices()];
        let mut ws = morph.workspace();
        let mut path = String::new();
        let mut total = 0usize;
        let frames = Instant::now();
        for f in 0..60 {
            morph.at_into(f as f64 / 59.0, &mut x, &mut ws);
            path_string(&meshes.loops, &x, &mut path);
            total += path.len();
        }
        let per_frame = frames.elapsed().as_secs_f64() / 60.0;
        assert!(total > 0);
        runs.push((setup, per_frame));
    }
    let median = |k: usize| {
        let mut v: Vec<f64> = runs
            .iter()
            .map(|r| if k == 0 { r.0 } else { r.1 })
            .collect();
        v.sort_by(f64::total_cmp);
        v[1]
    };
    Ok((median(0), median(1)))
}

// ------------------------------------------------------------------ files

fn loops_json(loops: &Loops) -> Value {
    json!(loops)
}

fn write_pairs(path: &str) {
    let to_json =
        |p: &Pair| json!({ "name": p.name, "a": loops_json(&p.a), "b": loops_json(&p.b) });
    let value = json!({
        "frames": FRAMES,
        "pairs": pairs().iter().map(to_json).collect::<Vec<_>>(),
        "timed": timed_pairs().iter().map(to_json).collect::<Vec<_>>(),
    });
    std::fs::write(path, serde_json::to_string(&value).unwrap()).expect("writing the pairs");
    println!("wrote {path}");
}

fn parse_frames(v: &Value) -> Option<Vec<Loops>> {
    serde_json::from_value(v.clone()).ok()
}

fn pct(x: f64) -> String {
    if x < 0.001 {
        format!("{x:.1e} %")
    } else {
        format!("{x:.3} %")
    }
}

fn table(peers_path: &str, only: Option<&str>) {
    let peers: Value = match only {
        Some(_) => json!({}),
        None => serde_json::from_str(
            &std::fs::read_to_string(peers_path)
                .expect("reading the peers' frames (run the node script first)"),
        )
        .expect("the peers' frames as JSON"),
    };
    let methods = peers["methods"].as_array().cloned().unwrap_or_default();
    println!(
        "| pair | method | points | ends (Hausdorff / diagonal) | frames crossed or touching (of {FRAMES}) | triangles turned over | area / blend of the ends, min to max | edge lengths against their blend (mean deviation) |"
    );
    println!("|---|---|---:|---:|---:|---:|---|---:|");
    let mut reports = Vec::new();
    for pair in pairs().into_iter().chain(timed_pairs()) {
        if only.is_some_and(|name| name != pair.name)
            || (only.is_none() && pair.name.starts_with("500"))
        {
            continue;
        }
        let row = |method: &str, m: &Measures, note: &str| {
            let target = if pair.rotation {
                [0.97, 1.03]
            } else {
                [0.85, 1.2]
            };
            let ok_area = m.area[0] >= target[0] && m.area[1] <= target[1];
            println!(
                "| {} | {} | {} | {}{} | {}{} | {} | {:.3} to {:.3}{} | {:.2} %{} |",
                pair.name,
                method,
                m.points,
                pct(100.0 * m.ends),
                if m.ends < 1e-3 { "" } else { " ✗" },
                m.crossed,
                if m.crossed == 0 { "" } else { " ✗" },
                m.flipped.map_or("–".to_string(), |f| f.to_string()),
                m.area[0],
                m.area[1],
                if ok_area { "" } else { " ✗" },
                100.0 * m.edges,
                note
            );
        };
        match ours(&pair) {
            Ok((frames, flipped, report)) => {
                let mut m = measure(&frames, &pair);
                m.flipped = Some(flipped);
                row("meshmorph", &m, "");
                reports.push(format!("{}: {report}", pair.name));
            }
            Err(e) => println!("| {} | meshmorph | failed: {e} | | | | | |", pair.name),
        }
        for method in &methods {
            let name = method["name"].as_str().unwrap_or("?");
            let entry = &method["pairs"][pair.name];
            if let Some(why) = entry["unsupported"].as_str() {
                println!(
                    "| {} | {name} | – | not supported: {why} | | | | |",
                    pair.name
                );
            } else if let Some(frames) = parse_frames(&entry["frames"]) {
                row(name, &measure(&frames, &pair), "");
            } else {
                println!(
                    "| {} | {name} | – | no frames in {peers_path} | | | | |",
                    pair.name
                );
            }
        }
    }
    println!("\n(✗: outside the target: ends < 0.1 %, no frame crossed, area 0.85 to 1.2 and 0.97 to 1.03 for a rotation.)");
    println!("\nmeshmorph's compatible meshes:");
    for r in reports {
        println!("- {r}");
    }
    println!("\n| 60 frames as SVG path strings, one thread | method | setup | per frame |");
    println!("|---|---|---:|---:|");
    for pair in timed_pairs() {
        if only.is_some() {
            break;
        }
        match time_ours(&pair) {
            Ok((setup, frame)) => println!(
                "| {} | meshmorph | {:.1} ms | {:.1} µs |",
                pair.name,
                setup * 1e3,
                frame * 1e6
            ),
            Err(e) => println!("| {} | meshmorph | failed: {e} | |", pair.name),
        }
        for t in peers["timed"].as_array().into_iter().flatten() {
            if t["pair"].as_str() == Some(pair.name) {
                println!(
                    "| {} | {} | {:.1} ms | {:.1} µs |",
                    pair.name,
                    t["method"].as_str().unwrap_or("?"),
                    t["setup_ms"].as_f64().unwrap_or(f64::NAN),
                    t["frame_us"].as_f64().unwrap_or(f64::NAN)
                );
            }
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["pairs", path] => write_pairs(path),
        ["table", path] => table(path, None),
        ["only", name] => table("", Some(name)),
        _ => {
            eprintln!(
                "usage: outline_benchmark pairs FILE.json | table PEERS.json (tools/bench/outline-morph/run does both) | only PAIR (meshmorph alone on one pair, by name)"
            );
            std::process::exit(2);
        }
    }
}
