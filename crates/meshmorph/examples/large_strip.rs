//! Writes a planar strip and its curled target as binary PLY, to measure the
//! command line on large inputs (RELIABILITY.md):
//!
//! `cargo run --release -p meshmorph --example large_strip -- TRIANGLES DIR`
//!
//! writes DIR/strip.ply and DIR/curled.ply with about TRIANGLES triangles
//! (a strip 2 cells wide per 5 along, curled by half a turn).

use std::f64::consts::PI;
use std::path::PathBuf;

use meshmorph::io::{write_mesh, Format};
use meshmorph::shapes::{curl, strip};

fn main() -> Result<(), meshmorph::Error> {
    let mut args = std::env::args().skip(1);
    let triangles: usize = args
        .next()
        .and_then(|a| a.parse().ok())
        .expect("usage: large_strip TRIANGLES DIR");
    let dir = PathBuf::from(args.next().expect("usage: large_strip TRIANGLES DIR"));
    std::fs::create_dir_all(&dir).map_err(|e| meshmorph::Error::InvalidArgument(e.to_string()))?;
    // 2 nx ny triangles with nx = 5 ny / 2.
    let ny = ((triangles as f64 / 5.0).sqrt().round() as usize).max(1);
    let nx = (triangles / (2 * ny)).max(1);
    let source = strip(5.0, 2.0, nx, ny);
    let target = curl(&source, PI);
    write_mesh(&dir.join("strip.ply"), &source, Format::Ply)?;
    write_mesh(&dir.join("curled.ply"), &target, Format::Ply)?;
    println!(
        "{} vertices, {} triangles",
        source.num_vertices(),
        source.num_triangles()
    );
    Ok(())
}
