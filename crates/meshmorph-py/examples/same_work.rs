//! The work `bench/overhead.py` times through Python, timed here through
//! the Rust library: horse -> camel's correspondence, its ten poses
//! transferred together, 100 frames of a horse interpolation, 10 frames of
//! a 1M-triangle strip curling, and `at` on two triangles. Prints one JSON
//! object of the fastest of `runs` seconds per case; writes the strip and
//! its curl to DIR for the Python side.
//!
//!   cargo run --release -p meshmorph-py --example same_work -- SHARED_DT DIR

use std::path::PathBuf;
use std::time::Instant;

use meshmorph::io::{write_mesh, Format, MeshFile};
use meshmorph::{
    correspond, shapes, CorrespondOptions, Interpolator, InterpolatorOptions, Markers, Transfer,
    TransferOptions, VertexNumbering,
};

fn fastest(runs: usize, mut f: impl FnMut()) -> f64 {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let [dt, dir] = &args[..] else {
        return Err("usage: same_work SHARED_DT DIR".into());
    };
    let d = dt.join("horse-camel");
    let horse = MeshFile::read(&d.join("horse-poses/horse-reference.obj"))?.into_mesh();
    let camel = MeshFile::read(&d.join("camel-poses/camel-reference.obj"))?.into_mesh();
    let markers = Markers::read(
        &d.join("markers/horse-camel-107.cons"),
        VertexNumbering::FromZero,
    )?;
    let poses: Vec<_> = (1..=10)
        .map(|k| {
            MeshFile::read(&d.join(format!("horse-poses/horse-{k:02}.obj")))
                .map(MeshFile::into_mesh)
        })
        .collect::<Result<_, _>>()?;
    let options = CorrespondOptions::default();
    let mut found = None;
    let correspondence = fastest(3, || {
        found = Some(correspond(&horse, &camel, &markers, &options).unwrap());
    });
    let c = found.unwrap().correspondence;
    let transfer = Transfer::new(&horse, &camel, &c, &TransferOptions::default())?;
    let apply_all = fastest(15, || {
        transfer.apply_all(&poses).unwrap();
    });
    let walk = Interpolator::new(&horse, &poses[4], &InterpolatorOptions::default())?;
    let times: Vec<f64> = (0..100).map(|k| k as f64 / 99.0).collect();
    let frames_100 = fastest(15, || {
        walk.frames(&times);
    });
    let strip = shapes::strip(10.0, 0.5, 2240, 224);
    let curl = shapes::curl(&strip, 3.0 * std::f64::consts::PI);
    std::fs::create_dir_all(dir)?;
    write_mesh(&dir.join("strip.obj"), &strip, Format::Obj)?;
    write_mesh(&dir.join("curl.obj"), &curl, Format::Obj)?;
    let big = Interpolator::new(&strip, &curl, &InterpolatorOptions::default())?;
    let ten: Vec<f64> = (0..10).map(|k| k as f64 / 9.0).collect();
    // The first call, whose frames are new memory (later calls reuse what
    // the earlier ones freed).
    let strip_first = fastest(1, || {
        big.frames(&ten);
    });
    let strip_frames = fastest(10, || {
        big.frames(&ten);
    });
    let one = shapes::strip(1.0, 1.0, 1, 1);
    let small = Interpolator::new(
        &one,
        &shapes::curl(&one, 1.0),
        &InterpolatorOptions::default(),
    )?;
    let calls = 100_000;
    let small_at = fastest(3, || {
        for k in 0..calls {
            std::hint::black_box(small.at(k as f64 / calls as f64));
        }
    }) / calls as f64;
    println!(
        "{{\"correspond\": {correspondence}, \"apply_all\": {apply_all}, \"frames_100\": {frames_100}, \"strip_frames\": {strip_frames}, \"strip_first\": {strip_first}, \"small_at\": {small_at}, \"strip_triangles\": {}}}",
        strip.num_triangles()
    );
    Ok(())
}
