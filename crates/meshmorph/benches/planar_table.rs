//! Prints a markdown table of ARAP interpolation timings for each mesh and
//! factor kind: setup, one frame (`at_into`, reused workspace), and the time
//! per frame of 100 frames computed sequentially and with
//! `Interpolator::frames` (rayon). Medians of several runs.
//!
//! `cargo bench -p meshmorph --bench planar_table [-- MESH...]`
//! with MESH among elephant, strip_10k, strip_100k, strip_1000k (default:
//! these four), square_100k, square_1000k (square sheets, a rigid turn). The divan benchmarks (`cargo bench -p meshmorph --bench
//! interpolate`) measure the same things; this table puts them side by side.

#[path = "../examples/support/timing.rs"]
mod timing;
use timing::{fmt, time};

use std::f64::consts::PI;
use std::path::Path;

use meshmorph::FactorKind;
use meshmorph::{io, shapes, Interpolator, InterpolatorOptions, Mesh2};

const ELEPHANT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../../shared/data/2d/elephant"
);
const FRAMES: usize = 100;

fn pair(name: &str) -> Option<(Mesh2, Mesh2)> {
    if name == "elephant" {
        let dir = Path::new(ELEPHANT);
        if !dir.is_dir() {
            return None;
        }
        let read = |f: &str| io::read_mesh(&dir.join(f)).and_then(|m| m.to_2d()).unwrap();
        return Some((read("elephant_s.obj"), read("elephant_t.obj")));
    }
    // Square sheets turned rigidly by 2 rad: the same solver work as a
    // deformation (the system depends on the source only), with the most
    // fill-in a planar mesh of that size has.
    if let Some(n) = match name {
        "square_100k" => Some(224),
        "square_1000k" => Some(707),
        _ => None,
    } {
        let s = shapes::strip(1.0, 1.0, n, n);
        let t = shapes::rigid_motion(&s, 2.0, [0.5, 0.5], [0.0, 0.0]);
        return Some((s, t));
    }
    // Same strips as benches/interpolate.rs: nx = 10 ny, width 0.5 below
    // the curl's tightest radius 10 / (6π) ≈ 0.53.
    let ny = match name {
        "strip_10k" => 22,
        "strip_100k" => 71,
        "strip_1000k" => 224,
        _ => panic!("unknown mesh {name}"),
    };
    let s = shapes::strip(10.0, 0.5, 10 * ny, ny);
    let t = shapes::curl(&s, 3.0 * PI);
    Some((s, t))
}

fn main() {
    let args: Vec<String> = timing::args().into_iter().collect();
    let meshes: Vec<&str> = if args.is_empty() {
        vec!["elephant", "strip_10k", "strip_100k", "strip_1000k"]
    } else {
        args.iter().map(|s| s.as_str()).collect()
    };
    println!(
        "| mesh | triangles | vertices | factor | setup | frame (`at_into`) | per frame, 100 sequential | per frame, 100 in `frames` | speed-up |"
    );
    println!("|---|---:|---:|---|---:|---:|---:|---:|---:|");
    for name in meshes {
        let Some((s, t)) = pair(name) else {
            println!("skipped {name}: data not found");
            continue;
        };
        let big = s.num_triangles() > 500_000;
        for kind in [
            FactorKind::Auto,
            FactorKind::Simplicial,
            FactorKind::Supernodal,
        ] {
            let options = InterpolatorOptions::default().with_factor(kind);
            let setup = time(if big { 5 } else { 21 }, || {
                Interpolator::new(&s, &t, &options).unwrap()
            });
            let morph = Interpolator::new(&s, &t, &options).unwrap();
            let mut ws = morph.workspace();
            let mut out = vec![[0.0; 2]; morph.num_vertices()];
            let frame = time(if big { 21 } else { 201 }, || {
                morph.at_into(0.37, &mut out, &mut ws);
            });
            let times: Vec<f64> = (0..FRAMES)
                .map(|k| k as f64 / (FRAMES - 1) as f64)
                .collect();
            let runs = if big { 3 } else { 11 };
            let mut outs = vec![vec![[0.0; 2]; morph.num_vertices()]; FRAMES];
            let seq = time(runs, || {
                for (&t, o) in times.iter().zip(&mut outs) {
                    morph.at_into(t, o, &mut ws);
                }
            }) / FRAMES as f64;
            let par = time(runs, || morph.frames(&times)) / FRAMES as f64;
            println!(
                "| {name} | {} | {} | {kind:?} | {} | {} | {} | {} | {:.2}x |",
                s.num_triangles(),
                s.num_vertices(),
                fmt(setup),
                fmt(frame),
                fmt(seq),
                fmt(par),
                seq / par
            );
        }
    }
}
