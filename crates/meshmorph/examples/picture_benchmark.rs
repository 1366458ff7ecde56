//! A picture morph against the two baselines a user has: the arm sprite
//! of `meshmorph demo` ([`arm_sprite`]: upper arm and forearm, striped
//! across, a hand) turning its forearm by 150° at the elbow, with the
//! demo's seven anchors ([`arm_anchors`] and [`arm_fold_anchors`]) and
//! with the five on the outlines alone, then the same sprite drawn at
//! 4096 × 4096 (five anchors) for the time and memory of a large morph.
//!
//! `cargo run --release -p meshmorph --features render --example picture_benchmark [-- RUNS]`
//! (RUNS 3 by default: the median of RUNS timings).
//!
//! **Quality**, 11 frames (t = 0, 0.1, ..., 1) of 320 × 240, three
//! methods:
//!
//! - **meshmorph**: the as-rigid-as-possible frames of the compatible
//!   meshes (`PictureMorphOptions`' interpolation: areas kept on their
//!   blend, outlines untied, folds mended; `MM_STRETCH=linear` in the
//!   environment: the paper's linear blend of the stretches), each drawn
//!   with A carried forward and B carried back, blended by t
//!   ([`PictureMorph`]), as `meshmorph interpolate` draws them;
//! - **linear warp**: the same meshes, each vertex moved on a straight
//!   line from A to B, the same drawing;
//! - **cross-dissolve**: no warp, A and B blended by t in premultiplied
//!   alpha.
//!
//! Measures, each over the 11 frames:
//!
//! - **area**: the pixels of alpha above one half against the straight
//!   blend `(1 - t) area(A) + t area(B)`; the smallest and largest ratio;
//! - **ghost**: the pixels of alpha from 0.1 to 0.9 (a half-transparent
//!   picture: the arm shown twice over, faded) against the same straight
//!   blend; the largest share (a sharp sprite has none but at its edge);
//! - **stretch** (warps only): for each triangle, the affine map from its
//!   place in picture A to its place in the frame has singular values
//!   σ1 ≥ σ2, and `s_A = max(σ1, 1/σ2)` is the most that the texture is
//!   stretched or squeezed along any direction (1 for a rigid motion, 2
//!   for twice longer or half as long); likewise `s_B` from picture B.
//!   The frame shows A's texture with weight 1 - t and B's with weight t,
//!   so a triangle's stretch is `(1 - t) s_A + t s_B` (1 at both ends).
//!   Reported: the largest area-weighted mean over the frames (each
//!   triangle weighted by its area in the frame), and the worst triangle
//!   of any frame;
//! - **flipped**: triangles turned over, summed over the frames.
//!
//! Then the stretch away from the elbow, where the forearm folding over
//! the upper arm forces none (the triangles of A whose centroid is more
//! than three half widths from the joint): of the meshes' own map from A
//! to B, and of the frame at t = 0.5 for meshmorph and the linear warp.
//! And how much of the picture keeps its texture as drawn: the share of
//! the area (the frame's) whose stretch is at most 1.1, 1.25 and 1.5, of
//! the map from A to B and of both warps at t = 0.5; and the same share
//! of the pictures' texture (each triangle weighed by `(1 - t)` its area
//! in A plus `t` its area in B, what it shows of them, so that a part
//! the frame shrinks does not count as less of the picture), over the
//! whole arm and over the forearm beyond the fold, for the meshes as
//! pictures make them ([`OutlineOptions::for_pictures`]) and without the
//! rigid parts.
//!
//! **Speed and memory** at 4096 × 4096 (the same arm, scaled 12.8 times):
//! the two pictures' outlines traced and the compatible meshes made (the
//! setup of `meshmorph interpolate`, reading left out), the morph's setup
//! (the factorisation) and the frames' (the mipmaps), then a frame (its
//! positions and its drawing) on every thread and on one (with the cores
//! the frames on every thread kept busy, their CPU seconds over their
//! seconds on the clock, and the CPU time of one on one thread, which the
//! machine's other load does not inflate as it does the clock's); the peak
//! memory
//! of all that (the pictures included) against the two pictures' bytes.
//! Then the compatible meshes made with and without the rigid parts, in
//! turn, for what the rigid parts cost.

#[path = "support/memory.rs"]
mod memory;
#[path = "support/timing.rs"]
#[allow(dead_code)]
mod timing;

use std::time::Instant;

use meshmorph::io::picture::{
    arm_anchors, arm_fold_anchors, arm_sprite, picture_drawing, picture_meshes, Picture,
    PictureMeshes, PictureShape, ARM_SPRITE_SIZE,
};
use meshmorph::mesh::map_stretch;
use meshmorph::outline::OutlineOptions;
use meshmorph::render::{PictureMorph, PictureMorphOptions};
use meshmorph::Interpolator;
use timing::{fmt, median};

const FRAMES: usize = 11;
const BEND_DEGREES: f64 = 150.0;
/// `meshmorph interpolate`'s default `--trace-tolerance`, pixels.
const TRACE_TOLERANCE: f64 = 0.5;
/// Regions and holes under this many square pixels are dropped, as the
/// command line drops them.
const MIN_AREA: f64 = 16.0;
/// The large pictures' side.
const LARGE: u32 = 4096;

/// A morph of two sprites set up as `meshmorph interpolate` sets it up.
struct Morph<'a> {
    meshes: PictureMeshes,
    arap: Interpolator<2>,
    frames: PictureMorph<'a>,
}

impl Morph<'_> {
    /// The linear warp's positions at `t`: each vertex on a straight line
    /// from A to B.
    fn linear_at(&self, t: f64) -> Vec<[f64; 2]> {
        let [pa, pb] = [0, 1].map(|k| self.meshes.set.meshes[k].positions());
        pa.iter()
            .zip(pb)
            .map(|(p, q)| [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])])
            .collect()
    }
}

/// The straight arm and the arm bent by 150°, `size` pixels, and their
/// anchors: the five on the outlines, and with `fold` the two at the
/// elbow's fold (the demo's seven).
fn arm_pair(size: (u32, u32), fold: bool) -> (Picture, Picture, Vec<Vec<[f64; 2]>>) {
    let bend = BEND_DEGREES.to_radians();
    let mut named = arm_anchors(bend, size).to_vec();
    if fold {
        named.extend(arm_fold_anchors(bend, size));
    }
    let anchors = named.iter().map(|(_, a, b)| vec![*a, *b]).collect();
    (arm_sprite(0.0, size), arm_sprite(bend, size), anchors)
}

/// The compatible meshes of `a` and `b`, with the seconds their outlines
/// took to trace and the meshes to make.
fn meshes(
    a: &Picture,
    b: &Picture,
    anchors: &[Vec<[f64; 2]>],
    options: &OutlineOptions,
) -> (PictureMeshes, [f64; 2]) {
    let start = Instant::now();
    let names = ["A".to_string(), "B".to_string()];
    let da = picture_drawing(a, false, TRACE_TOLERANCE, MIN_AREA, &names[0]).unwrap();
    let db = picture_drawing(b, false, TRACE_TOLERANCE, MIN_AREA, &names[1]).unwrap();
    let trace = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let meshes = picture_meshes(
        &[a, b],
        &[&da, &db],
        anchors,
        (a.width, a.height),
        options,
        &names,
    )
    .unwrap();
    (meshes, [trace, start.elapsed().as_secs_f64()])
}

/// The morph of `meshes` and the frames' setup, with the seconds each
/// took.
fn morph<'a>(a: &'a Picture, b: &'a Picture, meshes: PictureMeshes) -> (Morph<'a>, [f64; 2]) {
    let start = Instant::now();
    let set = &meshes.set;
    // As `meshmorph interpolate` and `PictureFrames` morph pictures.
    let mut options = PictureMorphOptions::default().interpolation;
    if std::env::var("MM_STRETCH").as_deref() == Ok("linear") {
        options = options.with_stretch(meshmorph::StretchMode::Linear);
    }
    let arap = Interpolator::new(&set.meshes[0], &set.meshes[1], &options).unwrap();
    let solve = start.elapsed().as_secs_f64();
    let start = Instant::now();
    // The command line's fringe: the tracing's tolerance and a pixel and a
    // half for the pictures' soft edges.
    let fringe = TRACE_TOLERANCE + 1.5;
    let frames = PictureMorph::new(
        [a, b],
        &meshes.sources,
        set.meshes[0].triangles(),
        &set.loops,
        (a.width, a.height),
        fringe,
        PictureShape::Sprite,
    )
    .unwrap();
    let textures = start.elapsed().as_secs_f64();
    (
        Morph {
            meshes,
            arap,
            frames,
        },
        [solve, textures],
    )
}

/// Pixels of `picture` whose alpha is above one half.
fn opaque_area(picture: &Picture) -> f64 {
    picture.rgba.chunks_exact(4).filter(|p| p[3] > 127).count() as f64
}

/// Pixels of `picture` whose alpha is from 0.1 to 0.9.
fn ghost_area(picture: &Picture) -> f64 {
    picture
        .rgba
        .chunks_exact(4)
        .filter(|p| (26..=229).contains(&p[3]))
        .count() as f64
}

/// The cross-dissolve's alpha at `t` as a picture (its colour is not
/// measured, left black), ties rounded down.
fn cross_dissolve(a: &Picture, b: &Picture, t: f64) -> Picture {
    let rgba = a
        .rgba
        .chunks_exact(4)
        .zip(b.rgba.chunks_exact(4))
        .flat_map(|(p, q)| {
            // Ties rounded down: a pixel half opaque is not above one half.
            let alpha = (1.0 - t) * f64::from(p[3]) + t * f64::from(q[3]);
            [0, 0, 0, (alpha - 1e-9).round() as u8]
        })
        .collect();
    Picture::new(a.width, a.height, rgba).unwrap()
}

/// `max(σ1, 1/σ2)` of the affine map taking triangle `from` onto `to`
/// ([`map_stretch`]), and whether it turns the triangle over.
fn stretch(from: [[f64; 2]; 3], to: [[f64; 2]; 3]) -> (f64, bool) {
    let turned = signed_area(from) * signed_area(to) < 0.0;
    (map_stretch(from, to), turned)
}

fn signed_area(p: [[f64; 2]; 3]) -> f64 {
    0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]))
}

fn triangle_area(p: [[f64; 2]; 3]) -> f64 {
    signed_area(p).abs()
}

/// Each triangle's texture stretch in the frame at `positions`, time `t`
/// (`(1 - t) s_A + t s_B`), its area in the frame, whether it is turned
/// over from A or B, and its centroid in picture A.
fn triangle_stretches(
    meshes: &PictureMeshes,
    positions: &[[f64; 2]],
    t: f64,
) -> Vec<(f64, f64, bool, [f64; 2])> {
    let [a, b] = [0, 1].map(|k| meshes.set.meshes[k].positions());
    meshes.set.meshes[0]
        .triangles()
        .iter()
        .map(|tri| {
            let at = |p: &[[f64; 2]]| tri.map(|v| p[v as usize]);
            let c = at(a);
            let frame = at(positions);
            let (sa, fa) = stretch(at(a), frame);
            let (sb, fb) = stretch(at(b), frame);
            let centroid = [
                (c[0][0] + c[1][0] + c[2][0]) / 3.0,
                (c[0][1] + c[1][1] + c[2][1]) / 3.0,
            ];
            (
                (1.0 - t) * sa + t * sb,
                triangle_area(frame),
                fa || fb,
                centroid,
            )
        })
        .collect()
}

/// The texture's stretch in the frame at `positions`, time `t`: the
/// area-weighted mean and the worst triangle's, and the triangles turned
/// over; over the triangles whose centroid in picture A is `kept`.
fn frame_stretch(
    meshes: &PictureMeshes,
    positions: &[[f64; 2]],
    t: f64,
    kept: &dyn Fn([f64; 2]) -> bool,
) -> (f64, f64, usize) {
    let (mut sum, mut weight, mut worst, mut flipped) = (0.0, 0.0, 1.0f64, 0);
    for (s, w, turned, _) in triangle_stretches(meshes, positions, t)
        .into_iter()
        .filter(|x| kept(x.3))
    {
        sum += w * s;
        weight += w;
        worst = worst.max(s);
        flipped += usize::from(turned);
    }
    (sum / weight, worst, flipped)
}

/// The share of the frame's area (at `positions`, time `t`) whose texture
/// stretches by at most `limit`.
fn share_within(meshes: &PictureMeshes, positions: &[[f64; 2]], t: f64, limit: f64) -> f64 {
    let all = triangle_stretches(meshes, positions, t);
    let total: f64 = all.iter().map(|x| x.1).sum();
    all.iter()
        .filter(|x| x.0 <= limit)
        .map(|x| x.1)
        .sum::<f64>()
        / total
}

/// The share of the pictures' texture shown in the frame at `positions`,
/// time `t` (each triangle weighed by `(1 - t)` its area in A plus `t` its
/// area in B, what it shows of them, whatever its size in the frame),
/// over the triangles whose centroid in A is `kept`, that stretches by at
/// most `limit`. Unlike the share of the frame's area it does not count a
/// part that shrinks as less of the picture.
fn texture_within(
    meshes: &PictureMeshes,
    positions: &[[f64; 2]],
    t: f64,
    limit: f64,
    kept: &dyn Fn([f64; 2]) -> bool,
) -> f64 {
    let [a, b] = [0, 1].map(|k| meshes.set.meshes[k].positions());
    let (mut within, mut total) = (0.0, 0.0);
    for (tri, (s, _, _, centroid)) in meshes.set.meshes[0]
        .triangles()
        .iter()
        .zip(triangle_stretches(meshes, positions, t))
    {
        if !kept(centroid) {
            continue;
        }
        let at = |p: &[[f64; 2]]| tri.map(|v| p[v as usize]);
        let w = (1.0 - t) * triangle_area(at(a)) + t * triangle_area(at(b));
        total += w;
        if s <= limit {
            within += w;
        }
    }
    within / total
}

/// The smallest and largest of `v`.
fn range(v: &[f64]) -> [f64; 2] {
    v.iter()
        .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], &x| {
            [lo.min(x), hi.max(x)]
        })
}

/// One method's measures at each frame.
#[derive(Default)]
struct Quality {
    /// Area against the straight blend.
    areas: Vec<f64>,
    /// Area against the arm drawn in code at the frame's bend.
    true_areas: Vec<f64>,
    ghosts: Vec<f64>,
    /// Mean and worst stretch, and triangles turned over (warps only).
    stretches: Vec<(f64, f64, usize)>,
}

impl Quality {
    fn add(&mut self, frame: &Picture, [straight, truth]: [f64; 2]) {
        let area = opaque_area(frame);
        self.areas.push(area / straight);
        self.true_areas.push(area / truth);
        self.ghosts.push(ghost_area(frame) / straight);
    }
}

fn quality(fold: bool) {
    println!(
        "\n### With {}\n",
        if fold {
            "the demo's seven anchors: five on the outlines, two at the elbow's fold"
        } else {
            "the five anchors on the outlines"
        }
    );
    let (a, b, anchors) = arm_pair(ARM_SPRITE_SIZE, fold);
    let (made, _) = meshes(&a, &b, &anchors, &OutlineOptions::for_pictures());
    let (m, _) = morph(&a, &b, made);
    let (area_a, area_b) = (opaque_area(&a), opaque_area(&b));
    let mut truths = Vec::new();
    let pb = m.meshes.set.meshes[1].positions();
    let mut methods: [(&str, Quality); 3] = [
        ("meshmorph (as rigid as possible)", Quality::default()),
        ("linear warp of the same meshes", Quality::default()),
        ("cross-dissolve", Quality::default()),
    ];
    for k in 0..FRAMES {
        let t = k as f64 / (FRAMES - 1) as f64;
        let straight = (1.0 - t) * area_a + t * area_b;
        // The arm drawn in code at the frame's bend: what a rigid turn
        // about the elbow shows (where the forearm lies over the upper
        // arm, less than the straight blend).
        let truth = opaque_area(&arm_sprite(t * BEND_DEGREES.to_radians(), ARM_SPRITE_SIZE));
        truths.push(truth / straight);
        for (positions, (_, q)) in [m.arap.at(t), m.linear_at(t)].iter().zip(&mut methods) {
            q.add(&m.frames.draw(positions, t), [straight, truth]);
            q.stretches
                .push(frame_stretch(&m.meshes, positions, t, &|_| true));
        }
        methods[2]
            .1
            .add(&cross_dissolve(&a, &b, t), [straight, truth]);
    }
    let report = &m.meshes.set.report;
    // The stretch of the meshes' own correspondence: each triangle's map
    // from its place in A to its place in B, which every frame shares out.
    let (between, between_worst, _) = frame_stretch(&m.meshes, pb, 0.0, &|_| true);
    println!(
        "Quality: the arm sprite of `meshmorph demo` ({} × {}), its forearm turning {BEND_DEGREES}° at the elbow, {} anchors, {FRAMES} frames; compatible meshes of {} triangles, whose map from A to B stretches {between:.3} on average, {between_worst:.2} at worst.\n",
        a.width, a.height, anchors.len(), report.triangles
    );
    println!("| method | area / straight blend | area / true arm | ghost, max | stretch, mean (max over frames) | stretch, worst | flipped |");
    println!("|---|---|---|---|---|---|---|");
    for (name, q) in &methods {
        let stretch = if q.stretches.is_empty() {
            ["—".to_string(), "—".to_string(), "—".to_string()]
        } else {
            let means: Vec<f64> = q.stretches.iter().map(|s| s.0).collect();
            let worsts: Vec<f64> = q.stretches.iter().map(|s| s.1).collect();
            let flipped: usize = q.stretches.iter().map(|s| s.2).sum();
            [
                format!("{:.3}", range(&means)[1]),
                format!("{:.2}", range(&worsts)[1]),
                flipped.to_string(),
            ]
        };
        let [lo, hi] = range(&q.areas);
        let [true_lo, true_hi] = range(&q.true_areas);
        println!(
            "| {name} | {lo:.3} to {hi:.3} | {true_lo:.3} to {true_hi:.3} | {:.1} % | {} | {} | {} |",
            100.0 * range(&q.ghosts)[1],
            stretch[0],
            stretch[1],
            stretch[2]
        );
    }
    println!("\nAt each frame (t = 0, 0.1, ..., 1): area against the straight blend, and the stretch's mean:\n");
    println!(
        "| method | {} |",
        (0..FRAMES)
            .map(|k| format!("{:.1}", k as f64 / (FRAMES - 1) as f64))
            .collect::<Vec<_>>()
            .join(" | ")
    );
    println!("|---|{}", "---|".repeat(FRAMES));
    let row = |name: &str, v: &[f64]| {
        let cells: Vec<String> = v.iter().map(|r| format!("{r:.3}")).collect();
        println!("| {name} | {} |", cells.join(" | "));
    };
    row("true arm (drawn at t · 150°): area", &truths);
    for (name, q) in &methods {
        row(&format!("{name}: area"), &q.areas);
    }
    for (name, q) in methods.iter().filter(|(_, q)| !q.stretches.is_empty()) {
        let means: Vec<f64> = q.stretches.iter().map(|s| s.0).collect();
        row(&format!("{name}: stretch"), &means);
    }
    // Away from the elbow, where the forearm folding over the upper arm
    // forces no stretch: triangles of A whose centroid is more than three
    // half widths from the joint.
    let demo_anchors = arm_anchors(BEND_DEGREES.to_radians(), ARM_SPRITE_SIZE);
    let named = |n: &str| demo_anchors.iter().find(|a| a.0 == n).map(|a| a.1).unwrap();
    let (elbow, shoulder) = (named("elbow"), named("shoulder"));
    let half_width = elbow[1] - shoulder[1];
    let joint = [elbow[0], shoulder[1]];
    let away = move |c: [f64; 2]| (c[0] - joint[0]).hypot(c[1] - joint[1]) > 3.0 * half_width;
    let (mid, linear_mid) = (m.arap.at(0.5), m.linear_at(0.5));
    let (between_away, _, _) = frame_stretch(&m.meshes, pb, 0.0, &away);
    let (arap_away, _, _) = frame_stretch(&m.meshes, &mid, 0.5, &away);
    let (linear_away, _, _) = frame_stretch(&m.meshes, &linear_mid, 0.5, &away);
    println!(
        "\nAway from the elbow (the triangles of A more than three half widths from the joint): the map from A to B stretches {between_away:.3} on average; at t = 0.5 the texture stretches {arap_away:.3} (meshmorph) and {linear_away:.3} (linear warp)."
    );
    // How much of the picture shows its texture as drawn: the share of the
    // frame's area stretched by at most 10, 25 and 50 %.
    let limits = [1.1, 1.25, 1.5];
    let shares = |positions: &[[f64; 2]], t: f64| {
        limits
            .map(|l| format!("{:.0} %", 100.0 * share_within(&m.meshes, positions, t, l)))
            .join(" / ")
    };
    println!(
        "\nThe share of the area whose texture stretches by at most 10 / 25 / 50 %: the map from A to B {}; at t = 0.5 meshmorph {}, the linear warp {}.",
        shares(pb, 0.0),
        shares(&mid, 0.5),
        shares(&linear_mid, 0.5)
    );
    texture_shares(
        &m,
        joint,
        half_width,
        "the compatible meshes as pictures make them",
    );
    // The same pair meshed without the rigid parts, for comparison.
    let (plain, _) = meshes(&a, &b, &anchors, &OutlineOptions::default());
    let (plain, _) = morph(&a, &b, plain);
    texture_shares(
        &plain,
        joint,
        half_width,
        "meshes made without the rigid parts (`OutlineOptions::default()`)",
    );
}

/// The share of the pictures' texture that stretches by at most 10, 25
/// and 50 % under `m`'s map from A to B and its frame half-way, and the
/// linear warp's, over the whole arm and over the forearm beyond the fold
/// (the part that turns, past a half width from the `joint`).
fn texture_shares(m: &Morph, joint: [f64; 2], half_width: f64, which: &str) {
    let pb = m.meshes.set.meshes[1].positions();
    let (mid, linear_mid) = (m.arap.at(0.5), m.linear_at(0.5));
    let forearm = move |c: [f64; 2]| c[0] > joint[0] + half_width;
    let everywhere = |_: [f64; 2]| true;
    let textures = |positions: &[[f64; 2]], t: f64, kept: &dyn Fn([f64; 2]) -> bool| {
        [1.1, 1.25, 1.5]
            .map(|l| {
                format!(
                    "{:.0} %",
                    100.0 * texture_within(&m.meshes, positions, t, l, kept)
                )
            })
            .join(" / ")
    };
    for (what, kept) in [
        ("the whole arm", &everywhere as &dyn Fn([f64; 2]) -> bool),
        ("the forearm beyond the fold", &forearm),
    ] {
        println!(
            "\nThe share of the pictures' texture ({what}; {which}) that stretches by at most 10 / 25 / 50 %: the map from A to B {}; at t = 0.5 meshmorph {}, the linear warp {}.",
            textures(pb, 0.0, kept),
            textures(&mid, 0.5, kept),
            textures(&linear_mid, 0.5, kept)
        );
    }
}

fn speed(runs: usize) {
    let base = memory::resident_memory().unwrap_or(0);
    let (a, b, anchors) = arm_pair((LARGE, LARGE), false);
    let bytes = (a.rgba.len() + b.rgba.len()) as f64;
    memory::reset_peak();
    let (made, [trace, compatible]) = meshes(&a, &b, &anchors, &OutlineOptions::for_pictures());
    let report = made.set.report.clone();
    let (m, [solve, textures]) = morph(&a, &b, made);
    let mut out = vec![0u8; 4 * LARGE as usize * LARGE as usize];
    let mut frame = || {
        let positions = m.arap.at(0.5);
        m.frames.draw_into(&positions, 0.5, &mut out);
    };
    let cpu_start = memory::cpu_seconds();
    let all_samples = timing::samples(runs, &mut frame);
    // How many cores the frames on all threads kept busy: their CPU
    // seconds over their seconds on the clock.
    let busy = cpu_start
        .zip(memory::cpu_seconds())
        .map(|(before, after)| (after - before) / all_samples.iter().sum::<f64>());
    let all = median(all_samples);
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let cpu_before = memory::cpu_seconds();
    let one = one_thread.install(|| median(timing::samples(runs, &mut frame)));
    // A frame's work on one thread in CPU seconds (the clock's time grows
    // with the machine's other load, this does not).
    let cpu = cpu_before
        .zip(memory::cpu_seconds())
        .map(|(before, after)| (after - before) / runs as f64);
    let peak = memory::peak_memory().map(|p| p.saturating_sub(base) as f64 / bytes);
    println!(
        "\nSpeed and memory: the arm sprite at {LARGE} × {LARGE} (two pictures of {:.0} MB), compatible meshes of {} triangles, the frame at t = 0.5; {} threads, median of {runs}.\n",
        bytes / 2.0 / 1e6,
        report.triangles,
        rayon::current_num_threads()
    );
    println!("| outlines traced | compatible meshes | morph's setup | mipmaps | a frame, all threads | cores busy | a frame, one thread | ratio | a frame, CPU time | peak memory / pictures |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    println!(
        "| {} | {} | {} | {} | {} | {} | {} | {:.2} | {} | {} |",
        fmt(trace),
        fmt(compatible),
        fmt(solve),
        fmt(textures),
        fmt(all),
        busy.map_or("—".to_string(), |b| format!("{b:.2}")),
        fmt(one),
        one / all,
        cpu.map_or("—".to_string(), fmt),
        peak.map_or("—".to_string(), |p| format!("{p:.2} ×"))
    );
    // What the rigid parts cost: the compatible meshes made both ways, in
    // turn, `runs` times each.
    let (mut with, mut without) = (Vec::new(), Vec::new());
    for _ in 0..runs {
        for (options, times) in [
            (OutlineOptions::for_pictures(), &mut with),
            (OutlineOptions::default(), &mut without),
        ] {
            let (_, [_, compatible]) = meshes(&a, &b, &anchors, &options);
            times.push(compatible);
        }
    }
    println!(
        "\nThe compatible meshes, {runs} times each way in turn: {} with the rigid parts (as pictures make them), {} without (medians).",
        fmt(timing::median(with)),
        fmt(timing::median(without))
    );
}

fn main() {
    let runs: usize = timing::args()
        .first()
        .map(|a| a.parse().expect("RUNS: a number of runs"))
        .unwrap_or(3)
        .max(1);
    quality(true);
    quality(false);
    speed(runs);
}
