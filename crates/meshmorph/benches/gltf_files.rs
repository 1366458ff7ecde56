//! Time to write a GLB, and its size: horse→camel (10 transferred poses) and
//! a 1M-triangle strip curling over 30 frames. Then users' rigs (the sample
//! character, skinned and textured, made large): reading a 100k-vertex GLB
//! with 50 morph targets, and adding 50 shape keys to a GLB of about 50 MB
//! beside reading it and writing its bytes as they are, with the memory
//! each step takes at its peak.
//!
//! Run with `cargo bench -p meshmorph --bench gltf_files` (`-- write` or
//! `-- rigs` for one table); the horse→camel row needs
//! ../shared/data/dt/horse-camel beside the workspace (it is skipped
//! otherwise). Each figure is the median of 5.

#[path = "../examples/support/memory.rs"]
mod memory;

use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;

use meshmorph::io::gltf::{
    add_shape_keys, read, write_glb, write_shape_keys, GltfBase, GltfOptions, NewShape,
    SampleCharacter, ShapeKeyOptions,
};
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
    let only = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    if only.as_deref() != Some("rigs") {
        writes()?;
    }
    if only.as_deref() != Some("write") {
        rigs()?;
    }
    Ok(())
}

/// The median of 5 runs of `f`, in seconds, and the most memory one run
/// took above what the process held before it (the peak resident set,
/// reset before each run through /proc/self/clear_refs; 0 where that is
/// not there).
fn median_of_5<T>(
    mut f: impl FnMut() -> Result<T, meshmorph::Error>,
) -> Result<(f64, u64, T), meshmorph::Error> {
    let mut runs = Vec::new();
    let mut last = None;
    for _ in 0..5 {
        memory::reset_peak();
        let before = memory::resident_memory().unwrap_or(0);
        let t = Instant::now();
        let got = f()?;
        let seconds = t.elapsed().as_secs_f64();
        runs.push((
            seconds,
            memory::peak_memory().unwrap_or(0).saturating_sub(before),
        ));
        last = Some(got);
    }
    runs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let peak = runs.iter().map(|r| r.1).max().unwrap_or(0);
    Ok((runs[2].0, peak, last.expect("5 runs")))
}

/// The sample character with `rings × segments` body vertices and
/// `targets` morph targets (its `Smile` and bulges), written to `path`;
/// its size.
fn sample_rig(path: &Path, rings: usize, segments: usize, targets: usize) -> std::io::Result<u64> {
    let mut rig = SampleCharacter::default();
    rig.rings = rings;
    rig.segments = segments;
    rig.extra_targets = targets - 1;
    std::fs::write(path, rig.glb())?;
    Ok(std::fs::metadata(path)?.len())
}

fn rigs() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::temp_dir().join(format!("meshmorph-bench-rigs-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    println!();
    println!("| users' rigs | vertices | morph targets | file | step | time (median of 5) | memory at peak |");
    println!("|---|---|---|---|---|---|---|");
    let mb = |bytes: u64| format!("{:.1} MB", bytes as f64 / 1e6);
    let row = |name: &str, v: usize, t: usize, size: u64, step: &str, (s, peak): (f64, u64)| {
        println!(
            "| {name} | {v} | {t} | {} | {step} | {:.0} ms | {} |",
            mb(size),
            s * 1e3,
            mb(peak)
        );
    };

    // 400 rings of 250: 100,250 vertices with the seam's copies.
    let small = dir.join("rig-100k.glb");
    let size = sample_rig(&small, 400, 250, 50)?;
    let (s, peak, (_, mesh)) = median_of_5(|| read(&small, None))?;
    let v = mesh.surface.num_vertices();
    row(
        "100k-vertex GLB",
        v,
        mesh.targets.len(),
        size,
        "read (every target's positions)",
        (s, peak),
    );

    // 1,200 rings of 250: about 300,000 vertices, about 50 MB.
    let large = dir.join("rig-50mb.glb");
    let size = sample_rig(&large, 1200, 250, 50)?;
    let bytes = std::fs::read(&large)?;
    let copy = dir.join("copy.glb");
    let (s, peak, ()) =
        median_of_5(|| meshmorph::io::write_atomic(&copy, |w| w.write_all(&bytes)))?;
    let (doc, mesh) = read(&large, None)?;
    let v = mesh.surface.num_vertices();
    let t = mesh.targets.len();
    row(
        "~50 MB GLB",
        v,
        t,
        size,
        "its bytes written as they are",
        (s, peak),
    );
    let (s, peak, _) = median_of_5(|| read(&large, None))?;
    row("~50 MB GLB", v, t, size, "read", (s, peak));
    // 50 shapes, each moving a band of a quarter of the body.
    let rest = mesh.surface.positions();
    let (low, high) = rest
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p[1]), b.max(p[1])));
    let shapes: Vec<(String, Vec<[f64; 3]>)> = (0..50)
        .map(|k| {
            let centre = low + (high - low) * (k as f64 + 0.5) / 50.0;
            let positions = rest
                .iter()
                .map(|&[x, y, z]| {
                    let w = (1.0 - ((y - centre) / (0.125 * (high - low))).powi(2)).max(0.0);
                    [x * (1.0 + 0.05 * w), y, z * (1.0 + 0.05 * w)]
                })
                .collect();
            (format!("new_{k:02}"), positions)
        })
        .collect();
    let new: Vec<NewShape<'_>> = shapes
        .iter()
        .map(|(name, positions)| NewShape { name, positions })
        .collect();
    // What no writer can skip: every shape's positions read once, their
    // deltas from the rest made `f32` (summed, so that nothing is kept).
    let (s, peak, _) = median_of_5(|| {
        let sum: f32 = shapes
            .par_iter()
            .map(|(_, positions)| {
                positions
                    .iter()
                    .zip(rest)
                    .map(|(p, b)| (0..3).map(|c| (p[c] - b[c]) as f32).sum::<f32>())
                    .sum::<f32>()
            })
            .sum();
        Ok(std::hint::black_box(sum))
    })?;
    row(
        "~50 MB GLB",
        v,
        t,
        size,
        "the 50 shapes' deltas computed once, nothing kept (a floor)",
        (s, peak),
    );
    let out = dir.join("with-shapes.glb");
    let options = ShapeKeyOptions::default();
    let (s, peak, added) = median_of_5(|| add_shape_keys(&doc, &mesh, &new, &options))?;
    let written = mb(added.len() as u64);
    row(
        "~50 MB GLB",
        v,
        t,
        size,
        &format!("50 shape keys added, in memory ({written})"),
        (s, peak),
    );
    let (s, peak, ()) = median_of_5(|| write_shape_keys(&out, &doc, &mesh, &new, &options))?;
    row(
        "~50 MB GLB",
        v,
        t,
        size,
        &format!("50 shape keys added and written ({written})"),
        (s, peak),
    );
    let (s, peak, ()) =
        median_of_5(|| meshmorph::io::write_atomic(&copy, |w| w.write_all(&added)))?;
    row(
        "~50 MB GLB",
        v,
        t,
        size,
        &format!("the written file's bytes ({written}) written as they are"),
        (s, peak),
    );
    // The two interleaved, five times: the ratio of each pair, which the
    // machine's drift from minute to minute moves less than either time.
    let mut ratios: Vec<f64> = (0..5)
        .map(|_| {
            let t = Instant::now();
            meshmorph::io::write_atomic(&copy, |w| w.write_all(&added))?;
            let plain = t.elapsed().as_secs_f64();
            let t = Instant::now();
            write_shape_keys(&out, &doc, &mesh, &new, &options)?;
            Ok(t.elapsed().as_secs_f64() / plain)
        })
        .collect::<Result<_, meshmorph::Error>>()?;
    ratios.sort_by(f64::total_cmp);
    println!(
        "| ~50 MB GLB | {v} | {t} | {} | 50 shape keys added and written, over its bytes written as they are (interleaved pairs) | {:.2}x (median; {:.2}x to {:.2}x) | |",
        mb(size),
        ratios[2],
        ratios[0],
        ratios[4]
    );
    // The same mesh and 50 shapes as a new GLB, as `--gltf` writes one
    // for a target that is not glTF (positions, normals and their deltas,
    // no skin, textures or animation).
    let base = GltfBase::new(mesh.surface.positions(), mesh.surface.triangles());
    let frames: Vec<Vec<[f64; 3]>> = shapes.iter().map(|(_, p)| p.clone()).collect();
    let names: Vec<String> = shapes.iter().map(|(name, _)| name.clone()).collect();
    let fresh = GltfOptions::default().with_animation(false);
    let (s, peak, ()) = median_of_5(|| write_glb(&copy, &base, &frames, &names, &fresh))?;
    let made = mb(std::fs::metadata(&copy)?.len());
    row(
        "~50 MB GLB",
        v,
        t,
        size,
        &format!("its mesh and the 50 shapes written as a new GLB ({made})"),
        (s, peak),
    );
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

/// The table of GLBs written from scratch.
fn writes() -> Result<(), Box<dyn std::error::Error>> {
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
