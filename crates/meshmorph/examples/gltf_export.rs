//! Writes an interpolation and a set of shape keys as binary glTF files that
//! Blender, three.js or any glTF viewer open.
//!
//! Run with `cargo run --release --example gltf_export [-- DIR]` (DIR
//! defaults to the current folder): writes DIR/curl.glb (a bar curling into
//! a spiral, animated at 25 frames per second) and DIR/bends.glb (a tube's
//! bends as shape keys, no animation, with texture coordinates).

use std::f64::consts::{PI, TAU};
use std::path::PathBuf;

use meshmorph::io::gltf::{write_glb, GltfBase, GltfOptions};
use meshmorph::{shapes, Interpolator, InterpolatorOptions};

fn main() -> Result<(), meshmorph::Error> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));

    // An interpolation: the base mesh is the source, frame k is morph target k,
    // and the animation plays them in order.
    let bar = shapes::strip(12.0, 0.6, 60, 3);
    let spiral = shapes::curl(&bar, 3.0 * PI);
    let morph = Interpolator::new(&bar, &spiral, &InterpolatorOptions::default())?;
    let times: Vec<f64> = (0..50).map(|k| k as f64 / 49.0).collect();
    let frames = morph.frames(&times);
    let names: Vec<String> = (0..frames.len()).map(|k| format!("frame_{k:04}")).collect();
    let path = dir.join("curl.glb");
    write_glb(
        &path,
        &GltfBase::new(bar.positions(), bar.triangles()),
        &frames,
        &names,
        &GltfOptions::default().with_name("curl"),
    )?;
    println!("{}: {} frames", path.display(), frames.len());

    // Shape keys with texture coordinates per triangle corner: u around the
    // tube, v along it. The seam, where u jumps from 1 to 0, splits vertices.
    let tube = shapes::tube(4.0, 0.5, 17, 24);
    let p = tube.positions();
    let uvs: Vec<[[f32; 2]; 3]> = tube
        .triangles()
        .iter()
        .map(|t| {
            let mut u = t.map(|v| p[v as usize][2].atan2(p[v as usize][1]).rem_euclid(TAU) / TAU);
            if u.iter().any(|&x| x > 0.75) {
                u = u.map(|x| if x < 0.25 { x + 1.0 } else { x });
            }
            std::array::from_fn(|k| [u[k] as f32, (p[t[k] as usize][0] / 4.0) as f32])
        })
        .collect();
    let bends: Vec<Vec<[f64; 3]>> = [0.5, 1.0, 1.5]
        .iter()
        .map(|&a| shapes::bend(&tube, 4.0, a).positions().to_vec())
        .collect();
    let names = ["bend-30deg", "bend-60deg", "bend-90deg"].map(String::from);
    let path = dir.join("bends.glb");
    write_glb(
        &path,
        &GltfBase::new(tube.positions(), tube.triangles()).with_corner_uvs(&uvs),
        &bends,
        &names,
        &GltfOptions::default()
            .with_animation(false)
            .with_name("tube"),
    )?;
    println!("{}: {} shape keys", path.display(), bends.len());
    Ok(())
}
