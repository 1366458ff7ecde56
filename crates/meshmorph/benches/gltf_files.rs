//! Time to write a GLB, and its size: horse→camel (10 transferred poses) and
//! a 1M-triangle strip curling over 30 frames.
//!
//! Run with `cargo bench -p meshmorph --bench gltf_files`; the horse→camel row
//! needs ../shared/data/dt/horse-camel beside the workspace (it is skipped
//! otherwise). Each figure is the median of 5 writes.

use std::path::{Path, PathBuf};
use std::time::Instant;

use meshmorph::io::gltf::{write_glb, GltfBase, GltfOptions};
use meshmorph::{
    correspond, io, shapes, CorrespondOptions, Markers, Transfer, TransferOptions, VertexNumbering,
};

/// Median seconds of 5 writes, and the file's size.
fn time_write<const D: usize>(
    path: &Path,
    base: &GltfBase<'_, D>,
    frames: &[Vec<[f64; D]>],
) -> Result<(f64, u64), Box<dyn std::error::Error>> {
    let names: Vec<String> = (0..frames.len()).map(|k| format!("frame_{k:04}")).collect();
    let mut seconds: Vec<f64> = (0..5)
        .map(|_| {
            let t = Instant::now();
            write_glb(path, base, frames, &names, &GltfOptions::default())?;
            Ok(t.elapsed().as_secs_f64())
        })
        .collect::<Result<_, meshmorph::Error>>()?;
    seconds.sort_by(f64::total_cmp);
    let size = std::fs::metadata(path)?.len();
    std::fs::remove_file(path)?;
    Ok((seconds[2], size))
}

fn row(name: &str, vertices: usize, frames: usize, (seconds, size): (f64, u64)) {
    println!(
        "| {name} | {vertices} | {frames} | {:.0} ms | {:.1} MB | {:.0} MB/s |",
        seconds * 1e3,
        size as f64 / 1e6,
        size as f64 / 1e6 / seconds
    );
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::temp_dir().join(format!("meshmorph-bench-{}.glb", std::process::id()));
    println!("| GLB | vertices | frames | write (median of 5) | size | rate |");
    println!("|---|---|---|---|---|---|");

    let dir = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/data/dt/horse-camel"
    ));
    if dir.is_dir() {
        let horse = io::read_mesh(&dir.join("horse-poses/horse-reference.obj"))?;
        let camel = io::read_mesh(&dir.join("camel-poses/camel-reference.obj"))?;
        let markers = Markers::read(
            &dir.join("markers/horse-camel-107.cons"),
            VertexNumbering::FromZero,
        )?;
        let found = correspond(&horse, &camel, &markers, &CorrespondOptions::default())?;
        let transfer = Transfer::new(
            &horse,
            &camel,
            &found.correspondence,
            &TransferOptions::default(),
        )?;
        let poses: Vec<Vec<[f64; 3]>> = (1..=10)
            .map(|k| {
                let pose = io::read_mesh(&dir.join(format!("horse-poses/horse-{k:02}.obj")))?;
                transfer.apply(&pose)
            })
            .collect::<Result<_, meshmorph::Error>>()?;
        let base = GltfBase::new(camel.positions(), camel.triangles());
        row(
            "horse→camel",
            camel.num_vertices(),
            poses.len(),
            time_write(&out, &base, &poses)?,
        );
    } else {
        println!("(horse→camel skipped: {} not found)", dir.display());
    }

    // 1000 x 500 quads: 1,000,000 triangles, 501,501 vertices.
    let bar = shapes::strip(20.0, 10.0, 1000, 500);
    let frames: Vec<Vec<[f64; 2]>> = (0..30)
        .map(|k| {
            shapes::curl(&bar, std::f64::consts::PI * k as f64 / 29.0)
                .positions()
                .to_vec()
        })
        .collect();
    let base = GltfBase::new(bar.positions(), bar.triangles());
    row(
        "1M-triangle strip",
        bar.num_vertices(),
        frames.len(),
        time_write(&out, &base, &frames)?,
    );
    Ok(())
}
