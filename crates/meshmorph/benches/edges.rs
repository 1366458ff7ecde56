//! The structures over edges (the edge list and connected parts, and the
//! triangle adjacency inside an interpolation's setup) and an
//! interpolation setup in space on meshes whose edges are shared by many
//! triangles, beside an ordinary mesh of the same size.
//!
//! Run with `cargo bench -p meshmorph --bench edges`. Results are in
//! BENCHMARKS.md at the workspace root.
//!
//! Meshes, of about 100,000 triangles each:
//! - `book_100k`: 100,000 triangles on one edge (a book's spine), each with
//!   its own third vertex on a circle around it;
//! - `repeated_100k`: one triangle listed 100,000 times;
//! - `strip_100k`: an ordinary surface, `shapes::strip(10, 0.5, 710, 71)`
//!   (100,820 triangles) lifted into space and bent.
//!
//! Past eight triangles on one edge, each is the neighbour of the next only
//! (`topology::linked_pairs`): the book and the repeated triangle must cost
//! about what the strip costs, not the square of their triangles.

use std::f64::consts::{PI, TAU};

use divan::counter::ItemsCount;
use divan::{black_box, Bencher};
use meshmorph::{shapes, Interpolator, InterpolatorOptions, Mesh3};

const MESHES: [&str; 3] = ["book_100k", "repeated_100k", "strip_100k"];
const PAGES: usize = 100_000;

fn main() {
    for name in MESHES {
        let m = mesh(name);
        println!(
            "{name}: {} triangles, {} vertices",
            m.num_triangles(),
            m.num_vertices()
        );
    }
    divan::main();
}

/// The named mesh at rest.
fn mesh(name: &str) -> Mesh3 {
    match name {
        "book_100k" => {
            let mut p = vec![[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
            p.extend((0..PAGES).map(|k| {
                let t = TAU * k as f64 / PAGES as f64;
                [t.cos(), t.sin(), 0.5]
            }));
            let tris = (0..PAGES as u32).map(|k| [0, 1, k + 2]).collect();
            Mesh3::new(p, tris).unwrap()
        }
        "repeated_100k" => {
            let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.2], [0.0, 1.0, 0.5]];
            Mesh3::new(p, vec![[0, 1, 2]; PAGES]).unwrap()
        }
        "strip_100k" => {
            let strip = shapes::strip(10.0, 0.5, 710, 71).to_3d();
            shapes::bend(&strip, 10.0, 0.5 * PI)
        }
        _ => panic!("unknown mesh {name}"),
    }
}

/// The mesh turned by 0.3 radians about the y axis and shifted: a second
/// key for the interpolation.
fn turned(m: &Mesh3) -> Mesh3 {
    let (s, c) = 0.3f64.sin_cos();
    let p = m
        .positions()
        .iter()
        .map(|p| [c * p[0] - s * p[2] + 0.5, p[1], s * p[0] + c * p[2]])
        .collect();
    m.with_positions(p).unwrap()
}

/// The edge list and the connected parts ([`Mesh3::surface_counts`]).
#[divan::bench(args = MESHES)]
fn surface_counts(bencher: Bencher, name: &str) {
    let m = mesh(name);
    bencher
        .counter(ItemsCount::new(m.num_triangles()))
        .bench_local(|| black_box(&m).surface_counts());
}

/// Everything an interpolation between two keys in space builds once:
/// adjacency, rest folds, rotations made consistent, the factored system.
#[divan::bench(args = MESHES, sample_count = 10)]
fn interpolation_setup(bencher: Bencher, name: &str) {
    let m = mesh(name);
    let t = turned(&m);
    let options = InterpolatorOptions::default();
    bencher
        .counter(ItemsCount::new(m.num_triangles()))
        .bench_local(|| Interpolator::new(black_box(&m), black_box(&t), &options).unwrap());
}
