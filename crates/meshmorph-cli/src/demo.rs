//! `meshmorph demo`: the main jobs on built-in procedural shapes.

use std::f64::consts::PI;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use meshmorph::io::gltf::SampleCharacter;
use meshmorph::io::picture::{arm_anchors, arm_fold_anchors, arm_sprite, ARM_SPRITE_SIZE};
use meshmorph::io::{write_animated_svg, write_svg_frame, Animation, Canvas, Format, Style};
use meshmorph::outline::{compatible_set, Drawing, OutlineOptions};
use meshmorph::render::{write_gif_2d, Edges, GifOptions, Style2d};
use meshmorph::{shapes, Interpolator, InterpolatorOptions, Mesh3};

use crate::animation::FrameOutputs;
use crate::gltf::GltfArgs;
use crate::interpolate::{animate, FrameArgs, Keys};
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
///   drawing/stem-straight.svg,       two drawings made in code (a tapered stem,
///   drawing/stem-curled.svg,         straight, then curled by 400 degrees at its
///   drawing/anchors.txt              tip) and six points matched on them, made
///                                    into compatible meshes;
///   drawing/frame_*.svg,             the morph: an SVG a frame, one animated
///   drawing/drawing.svg,             SVG, and a GIF of the straight blend of the
///   drawing/drawing.gif              same meshes (left) beside it (right);
///   transfer.gif, transfer.png,      a thin tube's bending poses carried over
///   transfer.glb, transfer/target/*  to a thicker, differently tessellated tube
///   (the inputs are in transfer/input/, to rerun with `meshmorph transfer`);
///   character/character-shapes.glb   two shapes of a rig (character/input/rig.glb)
///                                    carried into a copy of a skinned, textured
///                                    character of other tessellation
///                                    (character/input/character.glb: its
///                                    skeleton, materials, eye and own shape key
///                                    kept), from seven points (markers.txt);
///   sprite/arm-straight.png,         a sprite made in code (an arm, striped
///   sprite/arm-bent.png,             across, its forearm then bent by 150°
///   sprite/anchors.txt,              at the elbow), seven points matched on
///   sprite/frames/frame_*.png,       them (two at the fold of the elbow),
///                                    and its morph: a PNG a frame and
///   sprite/sprite.gif                a GIF;
///   expressions/head-arkit.glb,      the ARKit shapes put on a head made in code
///   expressions/expressions.gif      (expressions/input/head.obj, the template's
///                                    head given other proportions, and its 17
///                                    landmarks, expressions/input/head.txt).
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
    drawing(args)?;
    transfer(args)?;
    character(args)?;
    sprite(args)?;
    expressions(args)
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
        stretch: None,
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
        stretch: None,
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

/// Frames of the drawing morph.
const DRAWING_FRAMES: usize = 48;

/// The outline of a tapered stem 10 long, up from the origin, whose path
/// turns by `curl` radians in all, more and more towards its tip; points
/// about `spacing` apart.
fn stem(curl: f64, spacing: f64) -> Vec<[f64; 2]> {
    const LENGTH: f64 = 10.0;
    const STEPS: usize = 24;
    let steps: Vec<(f64, f64)> = (0..STEPS)
        .map(|k| {
            let s = (k as f64 + 0.5) / STEPS as f64;
            // The turn grows as s^2 towards the tip (the weights sum to about 1).
            (LENGTH / STEPS as f64, curl * 3.0 * s * s / STEPS as f64)
        })
        .collect();
    let width = |s: f64| 0.16 + 0.5 * (1.0 - s).powf(1.5);
    shapes::stroke_outline([0.0, 0.0], PI / 2.0, &steps, &width, spacing)
}

/// Two drawings made in code, a tapered stem straight and curled at its
/// tip by 400 degrees, made into compatible meshes and morphed as rigidly
/// as possible: SVG frames, an animated SVG and a GIF that shows the
/// straight blend of the same meshes beside it (its tip shrinking and
/// folding through itself; turned-over triangles would be red).
fn drawing(args: &Args) -> Result<()> {
    let start = Instant::now();
    let dir = args.output.join("drawing");
    let (straight, curled) = (stem(-0.25, 0.12), stem(400f64.to_radians(), 0.12));
    // Drawn alike, point i of one is point i of the other: six of them
    // kept matched as anchors, as a user marks a few matching points.
    let anchors: Vec<Vec<[f64; 2]>> = (0..6)
        .map(|k| k * straight.len() / 6)
        .map(|i| vec![straight[i], curled[i]])
        .collect();
    let drawings = [Drawing::new(vec![straight])?, Drawing::new(vec![curled])?];
    let set = compatible_set(&drawings, &anchors, &OutlineOptions::default())?;
    let morph = Interpolator::new(
        &set.meshes[0],
        &set.meshes[1],
        &InterpolatorOptions::default(),
    )?;
    let setup = start.elapsed();
    let (a, b) = (set.meshes[0].positions(), set.meshes[1].positions());
    let times: Vec<f64> = (0..DRAWING_FRAMES)
        .map(|k| k as f64 / (DRAWING_FRAMES - 1) as f64)
        .collect();
    let frames: Vec<Vec<[f64; 2]>> = times.iter().map(|&t| morph.at(t)).collect();
    let computed = start.elapsed() - setup;
    // The straight blend of the same meshes, to the left of the morph.
    let shift = 1.15
        * (0..DRAWING_FRAMES)
            .map(|k| extent(&frames[k]))
            .fold(0.0, f64::max);
    let n = a.len() as u32;
    let both: Vec<Vec<[f64; 2]>> = times
        .iter()
        .zip(&frames)
        .map(|(&t, frame)| {
            let blend = a.iter().zip(b).map(|(p, q)| {
                [
                    (1.0 - t) * p[0] + t * q[0] - shift,
                    (1.0 - t) * p[1] + t * q[1],
                ]
            });
            blend.chain(frame.iter().copied()).collect()
        })
        .collect();
    let triangles = set.meshes[0].triangles();
    let both_triangles: Vec<[u32; 3]> = triangles
        .iter()
        .copied()
        .chain(triangles.iter().map(|t| t.map(|v| v + n)))
        .collect();
    let page = Canvas::for_frames(None, &frames, &set.loops, 0.0);
    let ends = [a, b];
    let style = Style {
        fill: Some([0x3b, 0x6e, 0xa8]),
        stroke: Some([0x1d, 0x2b, 0x45]),
        stroke_width: 0.04,
        ..Style::default()
    };

    let mut plan = Plan::new();
    let input_paths = [dir.join("stem-straight.svg"), dir.join("stem-curled.svg")];
    let inputs = [
        plan.file(&input_paths[0], "demo drawing"),
        plan.file(&input_paths[1], "demo drawing"),
    ];
    let anchors_path = dir.join("anchors.txt");
    let anchors_output = plan.file(&anchors_path, "demo anchors");
    let frame_outputs = plan.frames(&dir, DRAWING_FRAMES, "svg");
    let animated = plan.file(&dir.join("drawing.svg"), "animated SVG");
    let gif_path = dir.join("drawing.gif");
    let gif = plan.file(&gif_path, "GIF");
    let staging = plan.prepare()?;
    output::print_warnings(&staging.warnings());
    for (output, positions) in inputs.into_iter().zip(ends) {
        staging.write_to(output, |_, w| {
            Ok(write_svg_frame(w, positions, &set.loops, &style, &page)?)
        })?;
    }
    // The anchors as `meshmorph interpolate --anchors` reads them: in the
    // written files' coordinates (y down).
    staging.write_to(anchors_output, |_, w| {
        writeln!(
            w,
            "# name, then x y on stem-straight.svg and on stem-curled.svg"
        )?;
        for (k, pair) in anchors.iter().enumerate() {
            let (p, q) = (page.map(pair[0]), page.map(pair[1]));
            writeln!(w, "a{k} {} {} {} {}", p[0], p[1], q[0], q[1])?;
        }
        Ok(())
    })?;
    for (output, frame) in frame_outputs.into_iter().zip(&frames) {
        staging.write_to(output, |_, w| {
            Ok(write_svg_frame(w, frame, &set.loops, &style, &page)?)
        })?;
    }
    staging.write_to(animated, |_, w| {
        Ok(write_animated_svg(
            w,
            &Animation {
                frames: &frames,
                loops: &set.loops,
                style: &style,
                canvas: &page,
                fps: args.draw.fps,
                boomerang: !args.draw.no_boomerang,
            },
        )?)
    })?;
    let options = GifOptions {
        longest_side: Some(args.draw.size),
        fps: args.draw.fps,
        boomerang: !args.draw.no_boomerang,
        ..GifOptions::default()
    };
    let look = Style2d {
        edges: Edges::Boundary,
        ..Style2d::default()
    };
    staging.write(gif, |path| {
        Ok(write_gif_2d(path, &both, &both_triangles, &options, &look)?)
    })?;
    staging.commit()?;
    let report = &set.report;
    if args.json {
        say!(
            "{}",
            serde_json::json!({
                "job": "drawing",
                "frames": DRAWING_FRAMES,
                "vertices": a.len(),
                "triangles": report.triangles,
                "min_angle_degrees": report.min_angle_degrees,
                "setup_seconds": setup.as_secs_f64(),
                "seconds_per_frame": computed.as_secs_f64() / DRAWING_FRAMES as f64,
                "total_seconds": start.elapsed().as_secs_f64(),
                "files_written": DRAWING_FRAMES + 5,
            })
        );
    } else {
        say!(
            "\n== a drawing morph: a stem curling by 400 degrees at its tip, from two outlines =="
        );
        say!("compatible meshes: {report}");
        say!(
            "wrote {DRAWING_FRAMES} SVG frames, drawing.svg (animated) and drawing.gif (the straight blend beside it) to {}",
            dir.display()
        );
        say!(
            "setup {:.1} ms (meshes and interpolator), {:.1} µs a frame, total {:.2} s",
            setup.as_secs_f64() * 1e3,
            computed.as_secs_f64() * 1e6 / DRAWING_FRAMES as f64,
            start.elapsed().as_secs_f64()
        );
        say!(
            "rerun: meshmorph interpolate {} {} --anchors {} -o {} --frames {DRAWING_FRAMES} --gif {}",
            input_paths[0].display(),
            input_paths[1].display(),
            anchors_path.display(),
            dir.join("frames").display(),
            dir.join("morph.gif").display()
        );
    }
    Ok(())
}

/// The larger side of the bounding box of `points`.
fn extent(points: &[[f64; 2]]) -> f64 {
    let b = meshmorph::render::View2d::bounds(std::iter::once(points));
    (b[1][0] - b[0][0]).max(b[1][1] - b[0][1])
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
            source_mesh: None,
            target_mesh: None,
        }),
        batch: Vec::new(),
        correspond: markers_only(&markers_path),
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
        shapes: Vec::new(),
        replace_shapes: false,
        vrm_expressions: false,
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

/// A correspondence fitted from the markers in `path`, every other
/// setting its default.
fn markers_only(path: &std::path::Path) -> CorrespondArgs {
    CorrespondArgs {
        markers: vec![path.to_path_buf()],
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
    }
}

/// Marker pairs on the sample character's body, as positions (the rig and
/// the character are the same body, made of fewer or more vertices).
const BODY_MARKERS: &str = "# name, a point on the rig, the same point on the character
top 0 1.6 0 0 1.6 0
bottom 0 0 0 0 0 0
right 0.25 0.8 0 0.25 0.8 0
left -0.25 0.8 0 -0.25 0.8 0
front 0 0.8 0.25 0 0.8 0.25
back 0 0.8 -0.25 0 0.8 -0.25
chin 0 1.2 0.25 0 1.2 0.25
";

/// Deformation transfer into a user's own GLB: a coarse rig's two shape
/// keys carried into a copy of a skinned, textured character (the
/// library's sample character: two materials, a skeleton, an eye mesh, an
/// animation and a shape key of its own), everything else of it kept.
fn character(args: &Args) -> Result<()> {
    let dir = args.output.join("character");
    let input = dir.join("input");
    let mut rig = SampleCharacter::default();
    (rig.rings, rig.segments, rig.extra_targets) = (10, 12, 2);
    let rig_path = input.join("rig.glb");
    let character_path = input.join("character.glb");
    let markers_path = input.join("markers.txt");
    let files = [
        (&rig_path, rig.glb()),
        (&character_path, SampleCharacter::default().glb()),
        (&markers_path, BODY_MARKERS.as_bytes().to_vec()),
    ];
    let mut plan = Plan::new();
    let outputs: Vec<_> = files
        .iter()
        .map(|(path, bytes)| (plan.file(path, "demo character file"), bytes))
        .collect();
    let staging = plan.prepare()?;
    output::print_warnings(&staging.warnings());
    for (output, bytes) in outputs {
        staging.write(output, |path| {
            Ok(meshmorph::io::write_atomic(path, |w| w.write_all(bytes))?)
        })?;
    }
    staging.commit()?;
    if !args.json {
        say!("\n== deformation transfer into a GLB character: a rig's shape keys, the rest of the file kept ==");
    }
    let glb = dir.join("character-shapes.glb");
    let shapes = vec!["Extra_0".to_string(), "Extra_1".to_string()];
    run_transfer(&TransferArgs {
        refs: Some(References {
            source_ref: rig_path.clone(),
            target_ref: character_path.clone(),
            no_weld: false,
            source_mesh: Some("Body".to_string()),
            target_mesh: Some("Body".to_string()),
        }),
        batch: Vec::new(),
        correspond: markers_only(&markers_path),
        correspondence: None,
        save_correspondence: None,
        pin: Vec::new(),
        output: None,
        format: None,
        json: args.json,
        gltf: GltfArgs {
            gltf: Some(glb.clone()),
            max_gltf_mb: 256.0,
            gltf_quantize: false,
            gltf_dense: false,
        },
        gltf_shapes: false,
        shapes: shapes.clone(),
        replace_shapes: false,
        vrm_expressions: false,
        pictures: PictureArgs {
            png: None,
            gif: None,
            draw: args.draw.clone(),
        },
        poses: Vec::new(),
    })?;
    if !args.json {
        say!(
            "rerun: meshmorph transfer --source-ref {} --source-mesh Body --target-ref {} --target-mesh Body --markers {} --shapes {} --gltf {}",
            rig_path.display(),
            character_path.display(),
            markers_path.display(),
            shapes.join(","),
            glb.display()
        );
    }
    Ok(())
}

/// The ARKit expressions put on a head made in code: the built-in
/// template's head and its parts (eyeballs, teeth, tongue) given other
/// proportions (a wider jaw, a longer and flatter face, fuller cheeks),
/// with its 17 recommended landmarks placed where the template's went.
fn expressions(args: &Args) -> Result<()> {
    let dir = args.output.join("expressions");
    let input = dir.join("input");
    let template = meshmorph::ExpressionTemplate::arkit();
    // The head with the template's eyeballs, teeth and tongue as separate
    // pieces of the same mesh, as many heads are modelled.
    let mut positions = template.head.positions().to_vec();
    let mut triangles = template.head.triangles().to_vec();
    for part in &template.parts {
        let offset = positions.len() as u32;
        positions.extend_from_slice(part.mesh.positions());
        triangles.extend(part.mesh.triangles().iter().map(|t| t.map(|v| v + offset)));
    }
    let head = other_proportions(&Mesh3::new(positions, triangles)?);
    let head_path = input.join("head.obj");
    let landmarks_path = input.join("head.txt");
    let mut plan = Plan::new();
    let head_output = plan.file(&head_path, "demo head");
    let landmarks_output = plan.file(&landmarks_path, "demo landmarks");
    let staging = plan.prepare()?;
    output::print_warnings(&staging.warnings());
    staging.write(head_output, |path| {
        Ok(meshmorph::io::write_mesh(path, &head, Format::Obj)?)
    })?;
    staging.write(landmarks_output, |path| {
        Ok(meshmorph::io::write_atomic(path, |w| {
            writeln!(w, "# landmark x y z (the iBUG 300-W scheme, by alias)")?;
            for n in meshmorph::RECOMMENDED_LANDMARKS {
                let v = template
                    .landmark(&n.to_string())
                    .expect("the template has every iBUG landmark");
                let [x, y, z] = head.positions()[v as usize];
                writeln!(w, "{} {x} {y} {z}", meshmorph::landmark_name(n))?;
            }
            Ok(())
        })?)
    })?;
    staging.commit()?;
    if !args.json {
        say!("\n== the ARKit expressions on a head made in code, from 17 landmarks ==");
    }
    let glb = dir.join("head-arkit.glb");
    let gif = dir.join("expressions.gif");
    crate::expressions::run(&crate::expressions::Args {
        head: Some(head_path.clone()),
        markers: Some(landmarks_path.clone()),
        one_based: false,
        output: Some(glb.clone()),
        batch: Vec::new(),
        template: "arkit".to_string(),
        mesh: None,
        method: crate::expressions::MethodArg::Displacements,
        compare: false,
        all_shapes: false,
        replace_shapes: false,
        vrm_expressions: false,
        gltf_dense: false,
        max_gltf_mb: 1024.0,
        format: None,
        pictures: PictureArgs {
            png: None,
            gif: Some(gif.clone()),
            draw: args.draw.clone(),
        },
        json: args.json,
    })?;
    if !args.json {
        say!(
            "rerun: meshmorph expressions {} --markers {} -o {} --gif {}",
            head_path.display(),
            landmarks_path.display(),
            glb.display(),
            gif.display()
        );
    }
    Ok(())
}

/// `head` given other proportions by a smooth warp of its bounding box:
/// wider at the jaw, a longer face, a flatter front and fuller cheeks.
fn other_proportions(head: &Mesh3) -> Mesh3 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in head.positions() {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    let centre: [f64; 3] = std::array::from_fn(|i| 0.5 * (lo[i] + hi[i]));
    let half: [f64; 3] = std::array::from_fn(|i| 0.5 * (hi[i] - lo[i]));
    let warped = head
        .positions()
        .iter()
        .map(|p| {
            let [x, y, z]: [f64; 3] = std::array::from_fn(|i| (p[i] - centre[i]) / half[i]);
            let u = [
                x * (1.08 - 0.1 * y),
                1.1 * y + 0.04 * x * x,
                0.9 * z + 0.05 * (1.0 - x * x).max(0.0) * (1.0 - y * y).max(0.0),
            ];
            std::array::from_fn(|i| centre[i] + half[i] * u[i])
        })
        .collect();
    head.with_positions(warped)
        .expect("the same number of positions")
}

/// A sprite made in code, morphed as a user's would be: an arm (upper arm
/// and forearm, striped across, a hand at the end), straight, then with
/// its forearm bent by 150° at the elbow; `meshmorph interpolate` on the
/// two PNGs, as the command line runs it.
fn sprite(args: &Args) -> Result<()> {
    let dir = args.output.join("sprite");
    let bend = 150f64.to_radians();
    let pictures = [
        (dir.join("arm-straight.png"), 0.0),
        (dir.join("arm-bent.png"), bend),
    ];
    let anchors_path = dir.join("anchors.txt");
    let size = ARM_SPRITE_SIZE;
    let mut anchors = arm_anchors(bend, size).to_vec();
    anchors.extend(arm_fold_anchors(bend, size));
    let mut plan = Plan::new();
    let anchors_output = plan.file(&anchors_path, "demo anchors");
    let outputs: Vec<_> = pictures
        .iter()
        .map(|(path, _)| plan.file(path, "demo sprite"))
        .collect();
    let staging = plan.prepare()?;
    output::print_warnings(&staging.warnings());
    for (output, (_, bend)) in outputs.into_iter().zip(&pictures) {
        let picture = arm_sprite(*bend, size);
        staging.write(output, |path| {
            Ok(meshmorph::io::write_atomic(path, |w| {
                meshmorph::render::write_picture_png(w, &picture)
            })?)
        })?;
    }
    staging.write(anchors_output, |path| {
        Ok(meshmorph::io::write_atomic(path, |w| {
            writeln!(
                w,
                "# name, then x y (pixels, y down) on the straight arm and on the bent one"
            )?;
            for (name, a, b) in &anchors {
                writeln!(w, "{name} {} {} {} {}", a[0], a[1], b[0], b[1])?;
            }
            Ok(())
        })?)
    })?;
    staging.commit()?;
    if !args.json {
        say!("\n== a sprite morph: an arm bending by 150° at the elbow, from two pictures ==");
    }
    let frames = dir.join("frames");
    let gif = dir.join("sprite.gif");
    let mut words: Vec<std::ffi::OsString> = vec!["meshmorph".into(), "interpolate".into()];
    words.extend(pictures.iter().map(|(p, _)| p.clone().into_os_string()));
    words.extend(["-o".into(), frames.clone().into_os_string()]);
    words.extend(["--anchors".into(), anchors_path.clone().into_os_string()]);
    words.extend(["--frames".into(), "24".into()]);
    words.extend(["--gif".into(), gif.clone().into_os_string()]);
    words.extend(["--fps".into(), args.draw.fps.to_string().into()]);
    if args.json {
        words.push("--json".into());
    }
    crate::run_words(words)?;
    if !args.json {
        say!(
            "rerun: meshmorph interpolate {} {} --anchors {} -o {} --frames 24 --gif {}",
            pictures[0].0.display(),
            pictures[1].0.display(),
            anchors_path.display(),
            frames.display(),
            gif.display()
        );
    }
    Ok(())
}
