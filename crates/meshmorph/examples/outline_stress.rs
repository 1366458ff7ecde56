//! Many pairs of drawings made at random, morphed as the command line
//! morphs drawings, every measure of the drawings' benchmark taken on each:
//! how often the compatible meshes fail, frames cross, triangles turn over
//! or the area leaves its target, on pairs nobody chose.
//!
//! ```sh
//! cargo run --release -p meshmorph --example outline_stress [-- PAIRS [SEED]]
//! ```
//!
//! Three families, a third of the pairs each: random star-shaped polygons
//! (20 to 200 points, radii 0.2 to 1 of the largest); bands along random
//! smooth curves turning up to one and a half turns (a thin part that
//! curls); star-shaped polygons with one or two round holes. Each pair is
//! two members of one family, the second turned by a random angle.

use std::f64::consts::TAU;
use std::time::Instant;

use meshmorph::outline::{compatible_set, Drawing, OutlineOptions};
use meshmorph::{Interpolator, InterpolatorOptions, StretchMode};

type Point = [f64; 2];
type Loops = Vec<Vec<Point>>;

#[path = "support/outline_edges.rs"]
mod outline_edges;
use outline_edges::edges_off_blend;

const FRAMES: usize = 11;

/// xorshift64*: the same pairs for the same seed.
struct Random(u64);
impl Random {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// A star-shaped polygon: `n` points at sorted random angles, radii
/// smoothed from random ones so that neighbours do not jump too far.
fn star_shaped(r: &mut Random, n: usize, low: f64) -> Vec<Point> {
    let mut angles: Vec<f64> = (0..n).map(|_| r.range(0.0, TAU)).collect();
    angles.sort_by(f64::total_cmp);
    angles.dedup_by(|a, b| (*a - *b).abs() < 1e-3);
    let raw: Vec<f64> = angles.iter().map(|_| r.range(low, 1.0)).collect();
    let k = raw.len();
    angles
        .iter()
        .enumerate()
        .map(|(i, &a)| {
            let radius = (raw[(i + k - 1) % k] + 2.0 * raw[i] + raw[(i + 1) % k]) / 4.0;
            [radius * a.cos(), radius * a.sin()]
        })
        .collect()
}

/// A band of `width` along a smooth random curve of unit length turning
/// by up to `turn` radians, `n` points a side, counter-clockwise.
fn band(r: &mut Random, n: usize, width: f64, turn: f64) -> Vec<Point> {
    let (c1, c2, c3) = (r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0));
    let heading = |s: f64| turn * (c1 * s + c2 * s * s + c3 * (3.0 * s).sin() / 3.0);
    let steps = 4 * n;
    let mut centre = vec![[0.0, 0.0]];
    for i in 0..steps {
        let h = heading((i as f64 + 0.5) / steps as f64);
        let p = centre[i];
        centre.push([p[0] + h.cos() / steps as f64, p[1] + h.sin() / steps as f64]);
    }
    let side = |s: f64, sign: f64| {
        let i = ((s * steps as f64).round() as usize).min(steps);
        let h = heading(s);
        let p = centre[i];
        [
            p[0] - sign * 0.5 * width * h.sin(),
            p[1] + sign * 0.5 * width * h.cos(),
        ]
    };
    let mut out: Vec<Point> = (0..n)
        .map(|k| side(k as f64 / (n - 1) as f64, -1.0))
        .collect();
    out.extend((0..n).rev().map(|k| side(k as f64 / (n - 1) as f64, 1.0)));
    out
}

fn circle(c: Point, radius: f64, n: usize, clockwise: bool) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let a = TAU * k as f64 / n as f64 * if clockwise { -1.0 } else { 1.0 };
            [c[0] + radius * a.cos(), c[1] + radius * a.sin()]
        })
        .collect()
}

fn turned(loops: &Loops, angle: f64, shift: Point) -> Loops {
    let (s, c) = angle.sin_cos();
    loops
        .iter()
        .map(|l| {
            l.iter()
                .map(|p| {
                    [
                        c * p[0] - s * p[1] + shift[0],
                        s * p[0] + c * p[1] + shift[1],
                    ]
                })
                .collect()
        })
        .collect()
}

/// A drawing of `family` (with `holes` holes in the third), its loops;
/// drawn again until its loops are simple (a band may curl into itself).
fn drawing(r: &mut Random, family: usize, holes: usize) -> Loops {
    loop {
        let loops = draw(r, family, holes);
        if Drawing::new(loops.clone()).is_ok() {
            return loops;
        }
    }
}

fn draw(r: &mut Random, family: usize, holes: usize) -> Loops {
    match family {
        0 => {
            let n = r.range(20.0, 200.0) as usize;
            let low = r.range(0.2, 0.8);
            vec![star_shaped(r, n, low)]
        }
        1 => {
            let n = r.range(30.0, 120.0) as usize;
            let width = r.range(0.04, 0.2);
            let turn = r.range(0.0, 1.5 * TAU);
            vec![band(r, n, width, turn)]
        }
        _ => {
            let n = r.range(30.0, 150.0) as usize;
            let low = r.range(0.5, 0.9);
            let mut loops = vec![star_shaped(r, n, low)];
            for h in 0..holes {
                let side = if holes == 1 {
                    0.0
                } else {
                    0.22 * if h == 0 { -1.0 } else { 1.0 }
                };
                let radius = r.range(0.05, 0.15);
                let m = r.range(8.0, 40.0) as usize;
                loops.push(circle([side, r.range(-0.05, 0.05)], radius, m, true));
            }
            loops
        }
    }
}

fn dist(a: Point, b: Point) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

fn area(loops: &Loops) -> f64 {
    let signed = |l: &Vec<Point>| {
        (0..l.len())
            .map(|i| {
                let (a, b) = (l[i], l[(i + 1) % l.len()]);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum::<f64>()
            / 2.0
    };
    let areas: Vec<f64> = loops.iter().map(|l| signed(l).abs()).collect();
    2.0 * areas.iter().copied().fold(0.0, f64::max) - areas.iter().sum::<f64>()
}

fn diagonal(loops: &Loops) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in loops.iter().flatten() {
        for i in 0..2 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    dist(lo, hi)
}

/// Whether the frame's outline crosses or touches itself or a hole leaves
/// the outer loop: by the drawings' own check, which refuses such loops.
fn crossed(loops: &Loops) -> bool {
    Drawing::new(loops.clone()).is_err()
}

#[derive(Default)]
struct Tally {
    pairs: usize,
    failed: Vec<String>,
    crossed_pairs: usize,
    crossed_frames: usize,
    flipped_pairs: usize,
    flipped: usize,
    area_out: usize,
    area: [f64; 2],
    ends: f64,
    min_angle: f64,
    /// Each pair's mean deviation of its outline's edge lengths from the
    /// straight blend of their lengths in the two drawings' meshes, over
    /// the frames between them (as the drawings' benchmark measures it).
    edges: Vec<f64>,
    seconds: Vec<f64>,
    /// Triangles turned over by how many of their corners are on the
    /// outline.
    corners_held: [usize; 4],
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let pairs: usize = args.first().and_then(|s| s.parse().ok()).unwrap_or(60);
    let seed: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    let names = ["star-shaped", "curling bands", "with holes"];
    let mut tallies: Vec<Tally> = (0..3)
        .map(|_| Tally {
            area: [f64::INFINITY, 0.0],
            min_angle: f64::INFINITY,
            ..Tally::default()
        })
        .collect();
    let mut r = Random(0x9E37_79B9_7F4A_7C15 ^ seed);
    let options = InterpolatorOptions::default()
        .with_mend_folds(true)
        .with_untie_outlines(true)
        .with_outline_lengths(std::env::var("MM_OUTLINE").as_deref() != Ok("fit"))
        .with_stretch(StretchMode::AreaBlend);
    for k in 0..pairs {
        let family = k % 3;
        let holes = 1 + usize::from(r.next() < 0.5);
        let a = drawing(&mut r, family, holes);
        let b0 = drawing(&mut r, family, holes);
        let b = turned(
            &b0,
            r.range(-3.1, 3.1),
            [r.range(-1.0, 1.0), r.range(-1.0, 1.0)],
        );
        let tally = &mut tallies[family];
        tally.pairs += 1;
        let start = Instant::now();
        let result = (|| -> meshmorph::Result<_> {
            let drawings = [Drawing::new(a.clone())?, Drawing::new(b.clone())?];
            let set = compatible_set(&drawings, &[], &OutlineOptions::default())?;
            let morph = Interpolator::new(&set.meshes[0], &set.meshes[1], &options)?;
            Ok((set, morph))
        })();
        let (set, morph) = match result {
            Ok(x) => x,
            Err(e) => {
                tally.failed.push(format!("pair {k}: {e}"));
                continue;
            }
        };
        tally.seconds.push(start.elapsed().as_secs_f64());
        tally.min_angle = set
            .report
            .min_angle_degrees
            .iter()
            .copied()
            .fold(tally.min_angle, f64::min);
        let triangles = set.meshes[0].triangles();
        let mut on_outline = vec![false; set.meshes[0].num_vertices()];
        for &v in set.loops.iter().flatten() {
            on_outline[v as usize] = true;
        }
        let (area_a, area_b) = (area(&a), area(&b));
        let (mut crossed_frames, mut flipped) = (0, 0);
        let mut out = false;
        let mut outlines = Vec::with_capacity(FRAMES);
        for f in 0..FRAMES {
            let t = f as f64 / (FRAMES - 1) as f64;
            let x = morph.at(t);
            let loops: Loops = set
                .loops
                .iter()
                .map(|l| l.iter().map(|&v| x[v as usize]).collect())
                .collect();
            if crossed(&loops) {
                crossed_frames += 1;
            }
            for tr in triangles {
                let [p, q, s] = tr.map(|v| x[v as usize]);
                if (q[0] - p[0]) * (s[1] - p[1]) - (q[1] - p[1]) * (s[0] - p[0]) <= 0.0 {
                    flipped += 1;
                    let held = tr.iter().filter(|v| on_outline[**v as usize]).count();
                    tally.corners_held[held] += 1;
                }
            }
            let ratio = area(&loops) / ((1.0 - t) * area_a + t * area_b);
            tally.area = [tally.area[0].min(ratio), tally.area[1].max(ratio)];
            out |= !(0.85..=1.2).contains(&ratio);
            if f == 0 || f == FRAMES - 1 {
                let given = if f == 0 { &a } else { &b };
                // Every given point is a point of the frame's outline.
                let worst = given
                    .iter()
                    .flatten()
                    .map(|p| {
                        loops
                            .iter()
                            .flatten()
                            .map(|q| dist(*p, *q))
                            .fold(f64::INFINITY, f64::min)
                    })
                    .fold(0.0, f64::max);
                tally.ends = tally.ends.max(worst / diagonal(given));
            }
            outlines.push(loops);
        }
        if crossed_frames > 0 {
            tally.crossed_pairs += 1;
            tally.crossed_frames += crossed_frames;
            eprintln!(
                "pair {k} ({}): {crossed_frames} frames crossed",
                names[family]
            );
        }
        if flipped > 0 {
            tally.flipped_pairs += 1;
            tally.flipped += flipped;
            eprintln!(
                "pair {k} ({}): {flipped} triangles turned over",
                names[family]
            );
        }
        tally.area_out += usize::from(out);
        tally
            .edges
            .push(edges_off_blend(&outlines, 1e-7 * diagonal(&a)));
    }
    println!("| family | pairs | failed | pairs with a frame crossed (frames) | pairs with a triangle turned over (triangles) | pairs with the area outside 0.85 to 1.2 | area, min to max | ends, largest | smallest angle | edges against their blend, median and worst pair | setup, median and slowest |");
    println!("|---|---:|---:|---:|---:|---:|---|---:|---:|---|---|");
    for (name, t) in names.iter().zip(&mut tallies) {
        t.seconds.sort_by(f64::total_cmp);
        let median = t
            .seconds
            .get(t.seconds.len() / 2)
            .copied()
            .unwrap_or(f64::NAN);
        let slowest = t.seconds.last().copied().unwrap_or(f64::NAN);
        t.edges.sort_by(f64::total_cmp);
        let edges_median = t.edges.get(t.edges.len() / 2).copied().unwrap_or(f64::NAN);
        let edges_worst = t.edges.last().copied().unwrap_or(f64::NAN);
        println!(
            "| {name} | {} | {} | {} ({}) | {} ({}) | {} | {:.3} to {:.3} | {:.1e} % | {:.2}° | {:.2} %, {:.2} % | {:.0} ms, {:.0} ms |",
            t.pairs,
            t.failed.len(),
            t.crossed_pairs,
            t.crossed_frames,
            t.flipped_pairs,
            t.flipped,
            t.area_out,
            t.area[0],
            t.area[1],
            100.0 * t.ends,
            t.min_angle,
            100.0 * edges_median,
            100.0 * edges_worst,
            1e3 * median,
            1e3 * slowest
        );
    }
    for (name, t) in names.iter().zip(&tallies) {
        if t.flipped > 0 {
            println!(
                "- {name}: triangles turned over with 0, 1, 2, 3 corners on the outline: {:?}",
                t.corners_held
            );
        }
    }
    for t in &tallies {
        for f in &t.failed {
            println!("- failed: {f}");
        }
    }
}
