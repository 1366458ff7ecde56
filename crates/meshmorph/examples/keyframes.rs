//! Surfaces in space: a keyframe sequence and a blend sharing one
//! factorization, written as OBJ frames and a picture.
//!
//! Run with `cargo run --release --example keyframes [-- DIR]` (DIR defaults
//! to the current folder): writes DIR/keyframes.png (a tube bending through
//! 270, then 540 degrees, through three keys: the keys and the frames
//! between them) and DIR/blend.obj (the two bent keys blended with weights
//! 0.7 and -0.2).

use std::path::PathBuf;
use std::sync::Arc;

use meshmorph::io::{write_positions, Format};
use meshmorph::render::{render_grid_3d, write_png, GridOptions, GridRow, Ramp, Style3d};
use meshmorph::{shapes, Blend, InterpolatorOptions, RestSystem, Sequence};

fn main() -> Result<(), meshmorph::Error> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    let options = InterpolatorOptions::default();
    let tube = shapes::tube(10.0, 0.3, 61, 12);
    let keys = [
        tube.clone(),
        shapes::bend(&tube, 10.0, 1.5 * std::f64::consts::PI),
        shapes::bend(&tube, 10.0, 3.0 * std::f64::consts::PI),
    ];

    // What depends on the first key alone is factored once and shared.
    // (The same types serve planar meshes: `Sequence<2>`, `Blend<2>`.)
    let surface = Arc::new(RestSystem::new(&keys[0], options.factor)?);
    let sequence = Sequence::with_surface(surface.clone(), &keys[1..], &options)?;
    let blend = Blend::with_surface(surface, &keys[1..], &options)?;

    // The keys (s = 0, 1, 2) and the frames halfway between them.
    let times = [0.0, 0.5, 1.0, 1.5, 2.0];
    let frames = sequence.frames(&times);
    println!(
        "triangles with whole turns, per segment: {:?} of {}",
        sequence.triangles_with_whole_turns(),
        sequence.triangles().len()
    );
    for (s, f) in times.iter().zip(&frames) {
        println!(
            "s = {s}: {} triangles turned over",
            sequence.count_turned_over(f)
        );
    }
    let row = GridRow {
        triangles: sequence.triangles(),
        poses: frames.iter().map(Vec::as_slice).collect(),
        style: Style3d::with_ramp(Ramp::BLUE),
    };
    let picture = dir.join("keyframes.png");
    write_png(&picture, &render_grid_3d(&[row], &GridOptions::default()))?;
    println!("{}", picture.display());

    // Weights need not add up to 1, and may be negative.
    let mixed = blend.at(&[0.7, -0.2]);
    let path = dir.join("blend.obj");
    write_positions(&path, &mixed, blend.triangles(), Format::Obj)?;
    println!(
        "{}: {} triangles turned over",
        path.display(),
        blend.count_turned_over(&mixed)
    );
    Ok(())
}
