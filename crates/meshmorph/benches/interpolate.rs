//! ARAP interpolation benchmarks: setup (`Interpolator::new`) and time per
//! frame (`Interpolator::at_into` with a reused workspace).
//!
//! Run with `cargo bench -p meshmorph --bench interpolate`; add a filter to
//! run a part, e.g. `-- strip` or `-- factor`. Results and the machine they
//! were measured on are in BENCHMARKS.md at the workspace root.
//!
//! Meshes:
//! - the elephant of ../shared/data/2d/elephant (1796 triangles), skipped
//!   with a message when the data is absent;
//! - procedural strips `shapes::strip(10, 0.5, 10·ny, ny)` curled by 3π into
//!   an Euler spiral, of about 10k, 100k and 1M triangles. The curl's
//!   tightest radius is `length / (2 · 3π) ≈ 0.53`, above the width 0.5, so
//!   no triangle flips.

use std::f64::consts::PI;
use std::path::Path;

use divan::counter::ItemsCount;
use divan::{black_box, Bencher};
use meshmorph::FactorKind;
use meshmorph::{io, shapes, Interpolator, InterpolatorOptions, Mesh2};

const ELEPHANT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../../shared/data/2d/elephant"
);

const STRIP_LENGTH: f64 = 10.0;
const STRIP_WIDTH: f64 = 0.5;
const CURL: f64 = 3.0 * PI;

/// Frames per run in the parallel-frames comparison.
const FRAMES: usize = 100;

/// Mesh names used as benchmark arguments.
const STRIPS: [&str; 3] = ["strip_10k", "strip_100k", "strip_1000k"];

fn main() {
    if let Some((s, _)) = elephant() {
        println!(
            "elephant: {} triangles, {} vertices",
            s.num_triangles(),
            s.num_vertices()
        );
    } else {
        println!("skipped elephant benchmarks: {ELEPHANT} not found");
    }
    for name in STRIPS {
        let ny = strip_rows(name);
        println!(
            "{name}: strip({STRIP_LENGTH}, {STRIP_WIDTH}, {}, {ny}) curled by 3π: {} triangles, {} vertices",
            10 * ny,
            2 * 10 * ny * ny,
            (10 * ny + 1) * (ny + 1)
        );
    }
    divan::main();
}

/// `ny` of each strip; `nx = 10 ny`, so `2 nx ny = 20 ny²` triangles.
fn strip_rows(name: &str) -> usize {
    match name {
        "strip_10k" => 22,    // 9,680 triangles
        "strip_100k" => 71,   // 100,820 triangles
        "strip_1000k" => 224, // 1,003,520 triangles
        _ => panic!("unknown mesh {name}"),
    }
}

fn elephant() -> Option<(Mesh2, Mesh2)> {
    let dir = Path::new(ELEPHANT);
    if !dir.is_dir() {
        return None;
    }
    let read = |f: &str| {
        io::read_mesh(&dir.join(f))
            .and_then(|m| m.to_2d())
            .unwrap_or_else(|e| panic!("{f}: {e}"))
    };
    Some((read("elephant_s.obj"), read("elephant_t.obj")))
}

/// Source and target of the named mesh (`"elephant"` or a strip name).
fn pair(name: &str) -> Option<(Mesh2, Mesh2)> {
    if name == "elephant" {
        return elephant();
    }
    let ny = strip_rows(name);
    let source = shapes::strip(STRIP_LENGTH, STRIP_WIDTH, 10 * ny, ny);
    let target = shapes::curl(&source, CURL);
    Some((source, target))
}

fn interpolator(name: &str, kind: FactorKind) -> Option<Interpolator<2>> {
    let (s, t) = pair(name)?;
    let options = InterpolatorOptions::default().with_factor(kind);
    Some(Interpolator::new(&s, &t, &options).expect("interpolator"))
}

fn bench_setup(bencher: Bencher, name: &str, kind: FactorKind) {
    let Some((s, t)) = pair(name) else {
        println!("skipped {name}: data not found");
        return;
    };
    let options = InterpolatorOptions::default().with_factor(kind);
    bencher.bench_local(|| Interpolator::new(black_box(&s), black_box(&t), &options).unwrap());
}

fn bench_frame(bencher: Bencher, name: &str, kind: FactorKind) {
    let Some(morph) = interpolator(name, kind) else {
        println!("skipped {name}: data not found");
        return;
    };
    let mut ws = morph.workspace();
    let mut out = vec![[0.0; 2]; morph.num_vertices()];
    bencher.bench_local(|| {
        morph.at_into(black_box(0.37), &mut out, &mut ws);
        black_box(&out);
    });
}

/// Setup and per-frame time with the default options (`FactorKind::Auto`).
mod arap {
    use super::*;

    #[divan::bench(args = ["elephant"])]
    fn setup(bencher: Bencher, name: &str) {
        bench_setup(bencher, name, FactorKind::Auto);
    }

    #[divan::bench(args = ["elephant"])]
    fn frame(bencher: Bencher, name: &str) {
        bench_frame(bencher, name, FactorKind::Auto);
    }

    #[divan::bench(args = STRIPS, max_time = 12)]
    fn setup_strip(bencher: Bencher, name: &str) {
        bench_setup(bencher, name, FactorKind::Auto);
    }

    #[divan::bench(args = STRIPS, max_time = 6)]
    fn frame_strip(bencher: Bencher, name: &str) {
        bench_frame(bencher, name, FactorKind::Auto);
    }
}

/// 100 frames at once: `Interpolator::frames` (rayon over frames, one
/// workspace per worker) against 100 sequential `at_into` calls into
/// preallocated buffers. Throughput is frames per second.
mod frames100 {
    use super::*;

    fn times() -> Vec<f64> {
        (0..FRAMES)
            .map(|k| k as f64 / (FRAMES - 1) as f64)
            .collect()
    }

    #[divan::bench(args = ["elephant", "strip_10k", "strip_100k", "strip_1000k"], max_time = 15)]
    fn parallel(bencher: Bencher, name: &str) {
        let Some(morph) = interpolator(name, FactorKind::Auto) else {
            println!("skipped {name}: data not found");
            return;
        };
        let times = times();
        bencher
            .counter(ItemsCount::new(FRAMES))
            .bench_local(|| morph.frames(black_box(&times)));
    }

    #[divan::bench(args = ["elephant", "strip_10k", "strip_100k", "strip_1000k"], max_time = 15)]
    fn sequential(bencher: Bencher, name: &str) {
        let Some(morph) = interpolator(name, FactorKind::Auto) else {
            println!("skipped {name}: data not found");
            return;
        };
        let times = times();
        let mut ws = morph.workspace();
        let mut out = vec![vec![[0.0; 2]; morph.num_vertices()]; FRAMES];
        bencher.counter(ItemsCount::new(FRAMES)).bench_local(|| {
            for (&t, o) in times.iter().zip(&mut out) {
                morph.at_into(t, o, &mut ws);
            }
            black_box(&out);
        });
    }
}

/// Simplicial against supernodal Cholesky on either side of
/// `FactorKind::SIMPLICIAL_LIMIT` (150k unknowns): the 100k-triangle strip
/// has 51k vertices, the 1M-triangle strip 504k.
mod factor {
    use super::*;

    const SIZES: [&str; 2] = ["strip_100k", "strip_1000k"];

    #[divan::bench(args = SIZES, max_time = 15)]
    fn simplicial_setup(bencher: Bencher, name: &str) {
        bench_setup(bencher, name, FactorKind::Simplicial);
    }

    #[divan::bench(args = SIZES, max_time = 15)]
    fn supernodal_setup(bencher: Bencher, name: &str) {
        bench_setup(bencher, name, FactorKind::Supernodal);
    }

    #[divan::bench(args = SIZES, max_time = 6)]
    fn simplicial_frame(bencher: Bencher, name: &str) {
        bench_frame(bencher, name, FactorKind::Simplicial);
    }

    #[divan::bench(args = SIZES, max_time = 6)]
    fn supernodal_frame(bencher: Bencher, name: &str) {
        bench_frame(bencher, name, FactorKind::Supernodal);
    }
}
