//! Two 500-point outlines to compatible meshes, timed: a wavy star and a
//! thick spiral-like curl, turned and restarted, with the report of
//! `outline::compatible_meshes` and a morph's frame time.
//!
//! `cargo run --release -p meshmorph --example outline_pair`

use std::f64::consts::TAU;
use std::time::Instant;

use meshmorph::outline::{compatible_meshes, Drawing, OutlineOptions};
use meshmorph::{Interpolator, InterpolatorOptions, StretchMode};

fn star(n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|k| {
            let a = TAU * k as f64 / n as f64;
            let r = 1.0 + 0.25 * (5.0 * a).cos() + 0.08 * (11.0 * a + 1.0).sin();
            [r * a.cos(), r * a.sin()]
        })
        .collect()
}

/// A thick curl: a band of half-width 0.15 along an inward spiral.
fn curl(n: usize) -> Vec<[f64; 2]> {
    let centre = |t: f64| {
        let a = 0.5 + (TAU + 0.7) * t;
        let r = 1.0 - 0.45 * t;
        [r * a.cos() + 4.0, r * a.sin() - 2.0]
    };
    let side = |t: f64, sign: f64| {
        let (p, q) = (centre((t - 1e-4).max(0.0)), centre((t + 1e-4).min(1.0)));
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let l = dx.hypot(dy);
        let c = centre(t);
        [c[0] - sign * 0.15 * dy / l, c[1] + sign * 0.15 * dx / l]
    };
    let half = n / 2;
    let mut out: Vec<[f64; 2]> = (0..half)
        .map(|k| side(k as f64 / (half - 1) as f64, -1.0))
        .collect();
    out.extend((0..n - half).map(|k| side(1.0 - k as f64 / (n - half - 1) as f64, 1.0)));
    out.rotate_left(123);
    out
}

fn main() -> meshmorph::Result<()> {
    let pairs = [
        ("star vs curl", star(500), curl(500)),
        ("star vs itself turned", star(500), {
            let (s, c) = (2.1f64).sin_cos();
            let mut b: Vec<[f64; 2]> = star(500)
                .iter()
                .map(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]])
                .collect();
            b.rotate_left(77);
            b
        }),
    ];
    for (name, a, b) in pairs {
        let start = Instant::now();
        let (a, b) = (Drawing::new(vec![a])?, Drawing::new(vec![b])?);
        let meshes = compatible_meshes(&a, &b, &[], &OutlineOptions::default())?;
        let setup = start.elapsed().as_secs_f64();
        println!("{name}: {}; setup {:.1} ms", meshes.report, setup * 1e3);
        // The published frames, then the frames' outlines as the command
        // line morphs drawings to SVG (area kept, outline lengths, knots
        // untied; mending only where an output shows the inside).
        let drawn = InterpolatorOptions::default()
            .with_stretch(StretchMode::AreaBlend)
            .with_outline_lengths(true)
            .with_untie_outlines(true);
        for (way, options) in [
            ("published", InterpolatorOptions::default()),
            ("drawings", drawn),
        ] {
            let start = Instant::now();
            let morph = Interpolator::new(&meshes.a, &meshes.b, &options)?;
            let interp = start.elapsed().as_secs_f64();
            let mut out = vec![[0.0; 2]; morph.num_vertices()];
            let mut ws = morph.workspace();
            let frames = Instant::now();
            for f in 0..60 {
                morph.at_into(f as f64 / 59.0, &mut out, &mut ws);
            }
            let per_frame = frames.elapsed().as_secs_f64() / 60.0;
            println!(
                "  {way} frames: interpolator {:.1} ms, {:.1} us a frame",
                interp * 1e3,
                per_frame * 1e6,
            );
        }
    }
    Ok(())
}
