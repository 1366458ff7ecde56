//! Transfers the ten horse poses of Sumner and Popović's data to the camel
//! and scores each against Sumner's own camel poses; prints timings.
//!
//! Run with `cargo run --release --example horse_camel [-- MARKERS]`; needs
//! ../shared/data/dt/horse-camel beside the workspace.

use std::path::{Path, PathBuf};
use std::time::Instant;

use meshmorph::{correspond, io, CorrespondOptions, Markers, Mesh3, Transfer, TransferOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/data/dt/horse-camel"
    ));
    if !dir.is_dir() {
        println!("skipped: {} not found", dir.display());
        return Ok(());
    }
    let markers_file = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or(dir.join("markers/horse-camel-107.cons"));
    let horse = io::read_mesh(&dir.join("horse-poses/horse-reference.obj"))?;
    let camel = io::read_mesh(&dir.join("camel-poses/camel-reference.obj"))?;
    let markers = Markers::read(&markers_file, false)?;

    let mut opts = CorrespondOptions::default();
    if let Ok(v) = std::env::var("CUTOFF") {
        opts = opts.with_closest_cutoff(v.parse()?);
    }
    if let Ok(v) = std::env::var("MATCH") {
        opts = opts.with_match_threshold(v.parse()?);
    }
    if let Ok(v) = std::env::var("WC") {
        opts = opts.with_closest_weights(v.split(',').map(|x| x.parse().unwrap()).collect());
    }
    if let Ok(v) = std::env::var("WI") {
        opts = opts.with_weights(1.0, v.parse()?);
    }
    let t = Instant::now();
    let result = correspond(&horse, &camel, &markers, &opts, &mut |_| {})?;
    let t_corr = t.elapsed().as_secs_f64();
    let c = &result.correspondence;
    println!(
        "correspondence: {:.3} s, {} pairs, unmatched source {}, target {}",
        t_corr,
        c.pairs().len(),
        c.unmatched_source(),
        c.unmatched_target()
    );

    if let Ok(d) = std::env::var("OUT") {
        io::write_mesh(
            &Path::new(&d).join("deformed-horse.obj"),
            &result.deformed_source,
            io::Format::Obj,
        )?;
    }
    let t = Instant::now();
    let transfer = Transfer::new(&horse, &camel, c, &TransferOptions::default())?;
    println!("transfer setup: {:.3} s", t.elapsed().as_secs_f64());
    let diag = camel.bounding_box_diagonal();
    let mut scores = Vec::new();
    let mut ws = transfer.workspace();
    for k in 1..=10 {
        let pose = io::read_mesh(&dir.join(format!("horse-poses/horse-{k:02}.obj")))?;
        let reference = io::read_mesh(&dir.join(format!("camel-poses/camel-{k:02}.obj")))?;
        let t = Instant::now();
        let mut out = vec![[0.0; 3]; camel.num_vertices()];
        transfer.apply_into(pose.positions(), &mut out, &mut ws);
        let solve = t.elapsed().as_secs_f64();
        let score = rms_centred(&out, reference.positions()) / diag;
        println!("pose {k:02}: score {score:.5}  solve {:.2} ms", solve * 1e3);
        if let Ok(d) = std::env::var("OUT") {
            io::write_positions(
                &Path::new(&d).join(format!("camel-{k:02}.obj")),
                &out,
                camel.triangles(),
                io::Format::Obj,
            )?;
        }
        scores.push(score);
    }
    let mean = scores.iter().sum::<f64>() / scores.len() as f64;
    let worst = scores.iter().cloned().fold(0.0, f64::max);
    println!("mean {mean:.5} worst {worst:.5}");
    let _ = write_if_asked(&camel, &transfer);
    Ok(())
}

fn write_if_asked(_camel: &Mesh3, _t: &Transfer) -> Option<()> {
    let _ = Path::new(".");
    None
}

fn rms_centred(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let ca = mean(a);
    let cb = mean(b);
    let s: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| {
            (0..3)
                .map(|i| ((p[i] - ca[i]) - (q[i] - cb[i])).powi(2))
                .sum::<f64>()
        })
        .sum();
    (s / a.len() as f64).sqrt()
}

fn mean(p: &[[f64; 3]]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for q in p {
        for i in 0..3 {
            c[i] += q[i];
        }
    }
    c.map(|x| x / p.len() as f64)
}
