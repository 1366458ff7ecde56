//! `meshmorph demo`: the main jobs on built-in procedural shapes.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use meshmorph::io::Format;
use meshmorph::render::{self, GifOptions, GridOptions, GridRow, Ramp, Style3d};
use meshmorph::shapes;

use crate::interpolate::{animate, FrameArgs, Stretch};
use crate::transfer::{run_transfer, CorrespondArgs, References, TransferArgs};

/// Run the main jobs on built-in procedural shapes (no files needed).
///
/// Writes, under DIR:
///   spiral.gif, spiral/frame_*.obj   a bar curling into a spiral of 540 degrees;
///   transfer.gif, transfer.png,      a thin tube's bending poses carried over
///   transfer/target/*.obj            to a thicker, differently tessellated tube
///   (the inputs are in transfer/input/, to rerun with `meshmorph transfer`).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Where to write everything (created if missing).
    #[arg(short, long, value_name = "DIR", default_value = "meshmorph-demo")]
    pub output: PathBuf,
    /// Print the reports as JSON lines on stdout.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &Args) -> Result<()> {
    spiral(args)?;
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
        gif: Some(args.output.join("spiral.gif")),
        gif_width: 480,
        gif_height: None,
        fps: 25.0,
        no_boomerang: false,
        svg: false,
    };
    crate::output::make_dir(&args.output)?;
    meshmorph::io::write_mesh(&args.output.join("spiral-source.obj"), &bar, Format::Obj)?;
    meshmorph::io::write_mesh(&args.output.join("spiral-target.obj"), &spiral, Format::Obj)?;
    let report = animate(
        &bar,
        &spiral,
        &frames,
        &args.output.join("spiral"),
        Format::Obj,
        start,
    )?;
    if !args.json {
        println!("== interpolation: a bar curling into a spiral of 540 degrees ==");
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
    crate::output::make_dir(&input)?;
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
    meshmorph::io::write_atomic(&markers_path, |w| {
        writeln!(w, "# source-vertex target-vertex (0-based)")?;
        for [s, t] in &markers {
            writeln!(w, "{s} {t}")?;
        }
        Ok(())
    })?;
    let source_ref = input.join("thin-tube.obj");
    let target_ref = input.join("thick-tube.obj");
    meshmorph::io::write_mesh(&source_ref, &source, Format::Obj)?;
    meshmorph::io::write_mesh(&target_ref, &target, Format::Obj)?;
    let mut pose_paths = Vec::new();
    let mut poses = Vec::new();
    for k in 0..POSES {
        let angle = 0.75 * PI * k as f64 / (POSES - 1) as f64;
        let pose = shapes::bend(&source, TUBE_LENGTH, angle);
        let path = input.join(format!("bend-{k:02}.obj"));
        meshmorph::io::write_mesh(&path, &pose, Format::Obj)?;
        pose_paths.push(path);
        poses.push(pose);
    }
    if !args.json {
        println!("\n== deformation transfer: a thin tube's bends onto a thick tube ==");
    }
    let out = dir.join("target");
    run_transfer(&TransferArgs {
        refs: References {
            source_ref: source_ref.clone(),
            target_ref: target_ref.clone(),
        },
        correspond: CorrespondArgs {
            markers: Some(markers_path.clone()),
            one_based: false,
            smoothness_weight: None,
            identity_weight: None,
            closest_weights: None,
            closest_cutoff: None,
            match_threshold: None,
            no_align: false,
        },
        correspondence: None,
        save_correspondence: Some(dir.join("thin-to-thick.corr")),
        pin: Vec::new(),
        output: out.clone(),
        format: None,
        json: args.json,
        poses: pose_paths,
    })?;

    let results: Vec<Vec<[f64; 3]>> = (0..POSES)
        .map(|k| {
            let path = out.join(format!("bend-{k:02}.obj"));
            Ok(crate::output::read_mesh(&path, "transferred pose")?
                .into_parts()
                .0)
        })
        .collect::<Result<_>>()?;
    write_pictures(&dir, &source, &poses, &target, &results)?;
    if !args.json {
        println!(
            "pictures: {}, {}",
            dir.join("transfer.gif").display(),
            dir.join("transfer.png").display()
        );
        println!(
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

/// An animation and a still: source poses above, target poses below.
fn write_pictures(
    dir: &Path,
    source: &meshmorph::Mesh3,
    poses: &[meshmorph::Mesh3],
    target: &meshmorph::Mesh3,
    results: &[Vec<[f64; 3]>],
) -> Result<()> {
    let grid = GridOptions {
        cell_width: 360,
        direction: [-0.25, -0.35, -1.0],
        up: [0.0, 1.0, 0.0],
        ..GridOptions::default()
    };
    let rows = |k: usize| {
        vec![
            GridRow {
                triangles: source.triangles(),
                poses: vec![poses[k].positions()],
                style: Style3d::with_ramp(Ramp::BLUE),
            },
            GridRow {
                triangles: target.triangles(),
                poses: vec![results[k].as_slice()],
                style: Style3d::with_ramp(Ramp::SAND),
            },
        ]
    };
    let frames: Vec<Vec<GridRow<'_>>> = (0..poses.len()).map(rows).collect();
    let options = GifOptions {
        fps: 12.0,
        hold_ends: Duration::from_millis(600),
        ..GifOptions::default()
    };
    render::write_gif_grid(&dir.join("transfer.gif"), &frames, &grid, &options)
        .context("writing transfer.gif")?;
    let picks = [0, poses.len() / 2, poses.len() - 1];
    let still = vec![
        GridRow {
            triangles: source.triangles(),
            poses: picks.iter().map(|&k| poses[k].positions()).collect(),
            style: Style3d::with_ramp(Ramp::BLUE),
        },
        GridRow {
            triangles: target.triangles(),
            poses: picks.iter().map(|&k| results[k].as_slice()).collect(),
            style: Style3d::with_ramp(Ramp::SAND),
        },
    ];
    let canvas = render::render_grid_3d(
        &still,
        &GridOptions {
            cell_width: 240,
            ..grid
        },
    );
    render::write_png(&dir.join("transfer.png"), &canvas).context("writing transfer.png")?;
    Ok(())
}
