//! Prints markdown tables of 3D as-rigid-as-possible interpolation timings:
//! setup, one frame (`at_into`, reused workspace), and the time per frame of
//! many frames computed in parallel (`frames`, wall time / frames); and, for
//! the largest 2D and 3D meshes, the frame time against its floor: the bytes
//! of the Cholesky factor read twice (forward and back substitution)
//! divided by this machine's single-thread read bandwidth, measured by a
//! streaming loop in the same run. Medians of several runs.
//!
//! `cargo bench -p meshmorph --bench surface_table [-- MESH...]`
//! with MESH among horse (../shared/data), tube_100k, tube_1000k,
//! fat_tube_100k and strip_1000k (the 2D strip of `planar_table`, setup split into its
//! steps); default: all.

#[path = "../examples/support/timing.rs"]
mod timing;
use timing::{fmt, time};

use std::f64::consts::PI;
use std::path::Path;

use meshmorph::{io, shapes, Interpolator, InterpolatorOptions, Mesh3, Sequence};

const HORSE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../../shared/data/dt/horse-camel/horse-poses"
);

/// Single-thread read bandwidth, bytes per second: the median of summing a
/// 256 MB array (far larger than any cache) several times.
fn read_bandwidth() -> f64 {
    let v: Vec<f64> = (0..32 << 20).map(|i| i as f64).collect();
    let bytes = (v.len() * 8) as f64;
    let s = time(7, || {
        // Four accumulators so that the adds do not serialise.
        let mut acc = [0.0f64; 4];
        for c in v.chunks_exact(4) {
            for k in 0..4 {
                acc[k] += c[k];
            }
        }
        acc.iter().sum::<f64>()
    });
    bytes / s
}

fn pair(name: &str) -> Option<(Mesh3, Mesh3)> {
    match name {
        "horse" => {
            let dir = Path::new(HORSE);
            if !dir.is_dir() {
                return None;
            }
            let read = |f: &str| io::read_mesh(&dir.join(f)).unwrap();
            Some((read("horse-reference.obj"), read("horse-05.obj")))
        }
        "tube_100k" | "tube_1000k" | "fat_tube_100k" => {
            // A long tube of radius 0.5 with 32 vertices around (square
            // cells), the surface counterpart of the 2D strips, bent through
            // 540 degrees and twisted by 180; and a fatter tube, 100 around,
            // whose factor has more fill-in.
            let (rings, around) = match name {
                "tube_100k" => (1563, 32),
                "tube_1000k" => (15626, 32),
                _ => (501, 100),
            };
            let length = (rings - 1) as f64 * 2.0 * PI * 0.5 / around as f64;
            let t = shapes::tube(length, 0.5, rings, around);
            let b = shapes::bend(&shapes::twist(&t, length, PI), length, 3.0 * PI);
            Some((t, b))
        }
        _ => panic!("unknown mesh {name}"),
    }
}

fn main() {
    let args: Vec<String> = timing::args().into_iter().collect();
    let meshes: Vec<&str> = if args.is_empty() {
        vec!["horse", "tube_100k", "tube_1000k", "strip_1000k"]
    } else {
        args.iter().map(|s| s.as_str()).collect()
    };
    let threads = rayon::current_num_threads();
    let bandwidth = read_bandwidth();
    println!(
        "single-thread read bandwidth: {:.2} GB/s; {threads} threads",
        bandwidth / 1e9
    );
    println!();
    println!("| mesh | triangles | vertices | setup | frame (`at_into`) | per frame, {threads} threads (`frames`, wall / frames) | factor bytes | floor (factor read twice) | frame / floor |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for name in meshes {
        let big = name.ends_with("1000k");
        let runs = if big { 3 } else { 11 };
        let frames_n = if big { 20 } else { 100 };
        let times: Vec<f64> = (0..frames_n)
            .map(|k| k as f64 / (frames_n - 1) as f64)
            .collect();
        let (triangles, vertices, setup, frame, par, len) = if name == "strip_1000k" {
            let s = shapes::strip(10.0, 0.5, 2240, 224);
            let t = shapes::curl(&s, 3.0 * PI);
            let o = InterpolatorOptions::default();
            let setup = time(runs, || Interpolator::new(&s, &t, &o).unwrap());
            let m = Interpolator::new(&s, &t, &o).unwrap();
            let mut ws = m.workspace();
            let mut out = vec![[0.0; 2]; m.num_vertices()];
            let frame = time(if big { 11 } else { 101 }, || {
                m.at_into(0.37, &mut out, &mut ws)
            });
            let par = time(runs, || m.frames(&times)) / frames_n as f64;
            (
                s.num_triangles(),
                s.num_vertices(),
                setup,
                frame,
                par,
                m.rest().factor_bytes(),
            )
        } else {
            let Some((s, t)) = pair(name) else {
                println!("skipped {name}: data not found");
                continue;
            };
            let o = InterpolatorOptions::default();
            let keys = [s.clone(), t.clone()];
            let setup = time(runs, || Sequence::<3>::new(&keys, &o).unwrap());
            let prepare = time(runs, || {
                meshmorph::RestSystem::<3>::new(&s, o.factor).unwrap()
            });
            println!("{name}: setup {}, of which the prepared surface (gradients, Laplacian, factorization) {}", fmt(setup), fmt(prepare));
            let m = Sequence::<3>::new(&keys, &o).unwrap();
            let mut ws = m.workspace();
            let mut out = vec![[0.0; 3]; m.num_vertices()];
            let frame = time(if big { 11 } else { 101 }, || {
                m.at_into(0.37, &mut out, &mut ws)
            });
            let par = time(runs, || m.frames(&times)) / frames_n as f64;
            (
                s.num_triangles(),
                s.num_vertices(),
                setup,
                frame,
                par,
                m.surface().factor_bytes(),
            )
        };
        let floor = 2.0 * len as f64 / bandwidth;
        println!(
            "| {name} | {triangles} | {vertices} | {} | {} | {} | {len} | {} | {:.2}x |",
            fmt(setup),
            fmt(frame),
            fmt(par),
            fmt(floor),
            frame / floor
        );
    }
}
