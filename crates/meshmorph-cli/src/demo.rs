//! `meshmorph demo`: the main jobs on built-in procedural shapes.

use std::f64::consts::PI;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use meshmorph::io::Format;
use meshmorph::{shapes, Mesh3};

use crate::animation::FrameOutputs;
use crate::gltf::GltfArgs;
use crate::interpolate::{animate, FrameArgs, Keys, Stretch};
use crate::output;
use crate::outputs::Plan;
use crate::pictures::{DrawArgs, PictureArgs};
use crate::transfer::{run_transfer, CorrespondArgs, References, TransferArgs};

/// Run the main jobs on built-in procedural shapes (no files needed).
///
/// Each step (the spiral, the transfer's inputs, the transfer) is all or
/// nothing, like every other command: its files are moved into place
/// together once it has succeeded.
///
/// Writes, under DIR:
///   spiral.gif, spiral.glb,          a bar curling into a spiral of 540 degrees;
///   spiral/frame_*.obj
///   coil.gif, coil.png, coil.glb,    a tube bending through 540 degrees while
///   coil/frame_*.obj                 twisting by 90, through three keys
///                                    (coil-key0.obj, coil-key1.obj, coil-key2.obj);
///   transfer.gif, transfer.png,      a thin tube's bending poses carried over
///   transfer.glb, transfer/target/*  to a thicker, differently tessellated tube
///   (the inputs are in transfer/input/, to rerun with `meshmorph transfer`).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Where to write everything (created if missing).
    #[arg(short, long, value_name = "DIR", default_value = "meshmorph-demo")]
    pub output: PathBuf,
    /// Print the reports as JSON lines on stdout.
    #[arg(long)]
    pub json: bool,
    /// How the pictures are drawn.
    #[command(flatten)]
    pub draw: DrawArgs,
}

pub fn run(args: &Args) -> Result<()> {
    spiral(args)?;
    coil(args)?;
    transfer(args)
}

/// As-rigid-as-possible interpolation of a bar into a spiral.
fn spiral(args: &Args) -> Result<()> {
    let start = Instant::now();
    let bar = shapes::strip(12.0, 0.6, 60, 3);
    let spiral = shapes::curl(&bar, 3.0 * PI);
    let frames = FrameArgs {
        frames: 60,
        times: None,
        no_consistency: false,
        turns: 0,
        stretch: Stretch::Linear,
        allow_flips: false,
        svg: false,
        pictures: PictureArgs {
            gif: Some(args.output.join("spiral.gif")),
            png: None,
            draw: args.draw.clone(),
        },
        gltf: GltfArgs {
            gltf: Some(args.output.join("spiral.glb")),
            max_gltf_mb: 256.0,
            gltf_quantize: false,
            gltf_dense: false,
        },
    };
    let keys = [bar.to_3d(), spiral.to_3d()];
    animate_demo(
        args,
        (&keys, &["spiral-source.obj", "spiral-target.obj"]),
        true,
        &frames,
        "spiral",
        "== interpolation: a bar curling into a spiral of 540 degrees ==",
        start,
    )
}

/// As-rigid-as-possible interpolation in space through three keys: a tube
/// that bends through 540 degrees while twisting by 90.
fn coil(args: &Args) -> Result<()> {
    let start = Instant::now();
    let straight = shapes::tube(10.0, 0.35, 81, 16);
    let key = |a: f64| shapes::bend(&shapes::twist(&straight, 10.0, a / 6.0), 10.0, a);
    let keys = [straight.clone(), key(1.5 * PI), key(3.0 * PI)];
    let frames = FrameArgs {
        frames: 48,
        times: None,
        no_consistency: false,
        turns: 0,
        stretch: Stretch::Linear,
        allow_flips: false,
        svg: false,
        pictures: PictureArgs {
            gif: Some(args.output.join("coil.gif")),
            png: Some(args.output.join("coil.png")),
            draw: args.draw.clone(),
        },
        gltf: GltfArgs {
            gltf: Some(args.output.join("coil.glb")),
            max_gltf_mb: 256.0,
            gltf_quantize: false,
            gltf_dense: false,
        },
    };
    animate_demo(
        args,
        (&keys, &["coil-key0.obj", "coil-key1.obj", "coil-key2.obj"]),
        false,
        &frames,
        "coil",
        "\n== interpolation in space: a tube bending through 540 degrees while twisting by 90, through 3 keys ==",
        start,
    )
}

/// Writes the demo's `keys` (as the files named beside them in the demo
/// folder) and the interpolation through them (frames in the folder `name`,
/// with the pictures and GLB `frames` asks for), all or nothing, then prints
/// `heading` and the report.
fn animate_demo(
    args: &Args,
    (keys, files): (&[Mesh3], &[&str]),
    planar: bool,
    frames: &FrameArgs,
    name: &str,
    heading: &str,
    start: Instant,
) -> Result<()> {
    let times = frames.times(keys.len() - 1)?;
    let dir = args.output.join(name);
    let mut plan = Plan::new();
    let key_outputs: Vec<_> = files
        .iter()
        .map(|file| plan.file(&args.output.join(file), "demo mesh"))
        .collect();
    let outputs = FrameOutputs::plan(&mut plan, frames, &dir, times.len(), Format::Obj);
    let staging = plan.prepare()?;
    output::print_warnings(&staging.warnings());
    for (output, mesh) in key_outputs.into_iter().zip(keys) {
        staging.write(output, |path| {
            Ok(meshmorph::io::write_mesh(path, mesh, Format::Obj)?)
        })?;
    }
    let names: Vec<String> = files
        .iter()
        .map(|f| crate::gltf::mesh_name(f.as_ref()))
        .collect();
    let mut report = animate(
        Keys::made(keys, &names),
        planar,
        frames,
        &times,
        &outputs,
        &staging,
        start,
    )?;
    report.surplus_frames_removed = staging.commit()?;
    if !args.json {
        say!("{heading}");
    }
    report.print(args.json);
    Ok(())
}

const TUBE_LENGTH: f64 = 4.0;
const POSES: usize = 24;

/// Deformation transfer from a thin tube to a thick one, through files, as
/// a user would run it.
fn transfer(args: &Args) -> Result<()> {
    let dir = args.output.join("transfer");
    let input = dir.join("input");
    let source = shapes::tube(TUBE_LENGTH, 0.25, 33, 12);
    let target = shapes::tube(TUBE_LENGTH, 0.5, 21, 20);

    // Markers: rings at x = 0, 1, 2, 3, 4 at four angles each, paired with the
    // target vertex at the same place on the thicker tube.
    let ring = |r: u32, s: u32| r * 12 + s;
    let chosen: Vec<u32> = [0, 8, 16, 24, 32]
        .iter()
        .flat_map(|&r| [0, 3, 6, 9].map(|s| ring(r, s)))
        .collect();
    let widened: Vec<[f64; 3]> = source
        .positions()
        .iter()
        .map(|p| [p[0], 2.0 * p[1], 2.0 * p[2]])
        .collect();
    let markers = shapes::nearest_vertex_pairs(&widened, target.positions(), &chosen);
    let markers_path = input.join("markers.txt");
    let source_ref = input.join("thin-tube.obj");
    let target_ref = input.join("thick-tube.obj");
    let poses: Vec<meshmorph::Mesh3> = (0..POSES)
        .map(|k| {
            let angle = 0.75 * PI * k as f64 / (POSES - 1) as f64;
            shapes::bend(&source, TUBE_LENGTH, angle)
        })
        .collect();
    let pose_paths: Vec<PathBuf> = (0..POSES)
        .map(|k| input.join(format!("bend-{k:02}.obj")))
        .collect();
    let mut plan = Plan::new();
    let marker_output = plan.file(&markers_path, "demo markers");
    let meshes: Vec<_> = [(&source_ref, &source), (&target_ref, &target)]
        .into_iter()
        .chain(pose_paths.iter().zip(&poses))
        .map(|(path, mesh)| (plan.file(path, "demo mesh"), mesh))
        .collect();
    let staging = plan.prepare()?;
    output::print_warnings(&staging.warnings());
    staging.write(marker_output, |path| {
        Ok(meshmorph::io::write_atomic(path, |w| {
            writeln!(w, "# source-vertex target-vertex (0-based)")?;
            for [s, t] in &markers {
                writeln!(w, "{s} {t}")?;
            }
            Ok(())
        })?)
    })?;
    for (output, mesh) in meshes {
        staging.write(output, |path| {
            Ok(meshmorph::io::write_mesh(path, mesh, Format::Obj)?)
        })?;
    }
    staging.commit()?;
    if !args.json {
        say!("\n== deformation transfer: a thin tube's bends onto a thick tube ==");
    }
    let out = dir.join("target");
    run_transfer(&TransferArgs {
        refs: Some(References {
            source_ref: source_ref.clone(),
            target_ref: target_ref.clone(),
            no_weld: false,
        }),
        batch: Vec::new(),
        correspond: CorrespondArgs {
            markers: vec![markers_path.clone()],
            no_markers: false,
            one_based: false,
            smoothness_weight: None,
            identity_weight: None,
            closest_weights: None,
            closest_cutoff: None,
            match_threshold: None,
            closest_normal_angle: None,
            match_normal_angle: None,
            no_align: false,
        },
        correspondence: None,
        save_correspondence: Some(dir.join("thin-to-thick.corr")),
        pin: Vec::new(),
        output: Some(out.clone()),
        format: None,
        json: args.json,
        gltf: GltfArgs {
            gltf: Some(dir.join("transfer.glb")),
            max_gltf_mb: 256.0,
            gltf_quantize: false,
            gltf_dense: false,
        },
        gltf_shapes: false,
        pictures: PictureArgs {
            png: Some(dir.join("transfer.png")),
            gif: Some(dir.join("transfer.gif")),
            draw: args.draw.clone(),
        },
        poses: pose_paths,
    })?;
    // The transfer's report names its pictures.
    if !args.json {
        say!(
            "rerun: meshmorph transfer --source-ref {} --target-ref {} --markers {} -o {} {}",
            source_ref.display(),
            target_ref.display(),
            markers_path.display(),
            out.display(),
            input.join("bend-*.obj").display()
        );
    }
    Ok(())
}
