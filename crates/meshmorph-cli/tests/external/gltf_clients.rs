//! The GLB files meshmorph writes, checked in real clients: the Khronos glTF
//! validator (no error, no warning) and three.js's GLTFLoader in headless
//! Chromium (the mesh is drawn and moves).
//!
//! Both need `npm ci` in tools/browser-checks (and Debian's `chromium` for the
//! second): see `browser.rs`.

use std::path::{Path, PathBuf};
use std::process::Command;

use std::fs;

use meshmorph::io::gltf::{write_glb, GltfBase, GltfOptions};
use meshmorph::io::read_mesh;
use meshmorph::Mesh3;

use crate::browser::{chromium, tools, which, Check, Needs};

/// The two checks (see `browser.rs`).
pub fn checks() -> Vec<Check> {
    vec![
        (
            "gltf_clients::every_glb_passes_the_khronos_validator",
            every_glb_passes_the_khronos_validator,
            Needs::Node,
        ),
        (
            "gltf_clients::three_js_in_chromium_draws_the_animation_moving",
            three_js_in_chromium_draws_the_animation_moving,
            Needs::Chromium,
        ),
        (
            "gltf_clients::blenders_importer_reads_every_glb",
            blenders_importer_reads_every_glb,
            Needs::Blender,
        ),
    ]
}

/// Blender's own glTF importer, in the background: every GLB gives a mesh
/// with one shape key per morph target, named as the targets, and the
/// sparse file's keys move only where its frames do.
fn blenders_importer_reads_every_glb() {
    let dir = out_dir("gltf-blender");
    let glbs = write_glbs(&dir);
    let script = r#"
import json, sys
import bpy, addon_utils
import numpy
# Debian's Blender 3.4 importer still says numpy.bool, which Debian's numpy
# 1.24 no longer has (Blender's own builds ship an older numpy).
if not hasattr(numpy, "bool"):
    numpy.bool = bool
addon_utils.enable("io_scene_gltf2", default_set=True)
for path in sys.argv[sys.argv.index("--") + 1:]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    keys = meshes[0].data.shape_keys
    blocks = keys.key_blocks if keys else []
    basis = [v.co.copy() for v in blocks[0].data] if blocks else []
    moved = [max(((a - b).length for a, b in zip((v.co for v in k.data), basis)), default=0.0) for k in list(blocks)[1:]]
    print("IMPORTED " + json.dumps({"path": path, "meshes": len(meshes), "vertices": len(meshes[0].data.vertices), "keys": [k.name for k in list(blocks)[1:]], "moved": moved}))
"#;
    let script_path = dir.join("import.py");
    fs::write(&script_path, script).unwrap();
    let out = Command::new("blender")
        .args([
            "-b",
            "--factory-startup",
            "--python-exit-code",
            "1",
            "--python",
        ])
        .arg(&script_path)
        .arg("--")
        .args(&glbs)
        .output()
        .expect("blender runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "blender failed:\n{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let imported: Vec<serde_json::Value> = text
        .lines()
        .filter_map(|l| l.strip_prefix("IMPORTED "))
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(imported.len(), glbs.len(), "{text}");
    for (glb, got) in glbs.iter().zip(&imported) {
        // The names as the file gives them (read as JSON: the gltf crate
        // refuses files that require KHR_mesh_quantization).
        let bytes = fs::read(glb).unwrap();
        let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + length]).unwrap();
        let names = &doc["meshes"][0]["extras"]["targetNames"];
        let moved: Vec<f64> = got["moved"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m.as_f64().unwrap())
            .collect();
        println!(
            "{}: {} shape keys, largest moves {:.3?}",
            glb.display(),
            moved.len(),
            &moved[..moved.len().min(4)]
        );
        assert_eq!(got["meshes"], 1, "{}", glb.display());
        assert_eq!(&got["keys"], names, "{}", glb.display());
        assert!(
            moved.iter().any(|&m| m > 0.01),
            "{}: no key moves",
            glb.display()
        );
    }
    // The sparse file's first frame is the rest itself.
    let sparse = &imported[glbs
        .iter()
        .position(|g| g.ends_with("bent-sparse.glb"))
        .unwrap()];
    assert_eq!(sparse["moved"][0].as_f64().unwrap(), 0.0);
}

fn meshmorph(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .args(args)
        .output()
        .expect("meshmorph runs");
    assert!(
        out.status.success(),
        "meshmorph {args:?} failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Writes the GLBs the checks use into `dir`: the demo's interpolation
/// (planar) and transfer (animated), a shapes-only transfer of the same
/// poses, and a tube with texture coordinates across a seam.
fn write_glbs(dir: &Path) -> Vec<PathBuf> {
    let demo = dir.join("demo");
    meshmorph(&["demo", "-o", demo.to_str().unwrap(), "--json"]);
    let input = demo.join("transfer/input");
    let shapes = dir.join("transfer-shapes.glb");
    let mut args: Vec<String> = [
        "transfer",
        "--source-ref",
        input.join("thin-tube.obj").to_str().unwrap(),
        "--target-ref",
        input.join("thick-tube.obj").to_str().unwrap(),
        "--correspondence",
        demo.join("transfer/thin-to-thick.corr").to_str().unwrap(),
        "-o",
        dir.join("shapes").to_str().unwrap(),
        "--gltf",
        shapes.to_str().unwrap(),
        "--gltf-shapes",
    ]
    .map(String::from)
    .to_vec();
    for k in [0, 8, 16, 23] {
        args.push(
            input
                .join(format!("bend-{k:02}.obj"))
                .to_str()
                .unwrap()
                .into(),
        );
    }
    meshmorph(&args.iter().map(String::as_str).collect::<Vec<_>>());

    // The same transfer onto a copy of the target with texture coordinates
    // (u around the tube, 0 to 1 across a seam, v along it).
    let textured = dir.join("thick-tube-textured.obj");
    let thick = read_mesh(&input.join("thick-tube.obj")).unwrap();
    fs::write(&textured, textured_obj(&thick)).unwrap();
    let uv_glb = dir.join("transfer-uvs.glb");
    args[4] = textured.to_str().unwrap().into();
    args[8] = dir.join("uvs").to_str().unwrap().into();
    args[10] = uv_glb.to_str().unwrap().into();
    args.retain(|a| a != "--gltf-shapes");
    meshmorph(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let glb = gltf::Gltf::open(&uv_glb).unwrap();
    let mesh = glb.document.meshes().next().unwrap();
    let prim = mesh.primitives().next().unwrap();
    let blob = glb.blob.as_deref().unwrap();
    let uvs: Vec<[f32; 2]> = prim
        .reader(|_| Some(blob))
        .read_tex_coords(0)
        .expect("TEXCOORD_0 from the target's file")
        .into_f32()
        .collect();
    assert!(uvs.len() > thick.num_vertices(), "the seam splits vertices");

    // The demo's transfer again, quantised (KHR_mesh_quantization).
    let quantised = dir.join("transfer-quantised.glb");
    args[8] = dir.join("quantised").to_str().unwrap().into();
    args[10] = quantised.to_str().unwrap().into();
    args[4] = input.join("thick-tube.obj").to_str().unwrap().into();
    args.push("--gltf-quantize".into());
    meshmorph(&args.iter().map(String::as_str).collect::<Vec<_>>());

    // Frames that leave most vertices where they are: sparse targets, as
    // they are and quantised.
    let (sparse, sparse_quantised) = (
        dir.join("bent-sparse.glb"),
        dir.join("bent-sparse-quantised.glb"),
    );
    let rest = meshmorph::shapes::tube(4.0, 0.5, 17, 12);
    let frames: Vec<Vec<[f64; 3]>> = [0.0f64, 0.5, 1.0]
        .iter()
        .map(|&angle| {
            rest.positions()
                .iter()
                .map(|&[x, y, z]| {
                    let a = angle * (x - 2.5);
                    if x <= 2.5 {
                        [x, y, z]
                    } else {
                        [
                            2.5 + (x - 2.5) * a.cos() - z * a.sin(),
                            y,
                            (x - 2.5) * a.sin() + z * a.cos(),
                        ]
                    }
                })
                .collect()
        })
        .collect();
    let base = GltfBase::new(rest.positions(), rest.triangles());
    let names: Vec<String> = (0..frames.len()).map(|k| format!("bend-{k}")).collect();
    for (path, quantise) in [(&sparse, false), (&sparse_quantised, true)] {
        let options = GltfOptions::default().with_fps(2.0).with_quantize(quantise);
        write_glb(path, &base, &frames, &names, &options).unwrap();
    }

    vec![
        demo.join("spiral.glb"),
        demo.join("transfer/transfer.glb"),
        shapes,
        uv_glb,
        quantised,
        sparse,
        sparse_quantised,
    ]
}

/// An OBJ of a tube along x with a `vt` for every triangle corner: u around
/// (a seam where it runs from 1 back to 0), v along.
fn textured_obj(tube: &Mesh3) -> String {
    use std::f64::consts::TAU;
    let p = tube.positions();
    let length = p.iter().map(|q| q[0]).fold(0.0, f64::max);
    let mut text = String::new();
    for q in p {
        text += &format!("v {} {} {}\n", q[0], q[1], q[2]);
    }
    for (t, tri) in tube.triangles().iter().enumerate() {
        let mut u = tri.map(|v| {
            let q = p[v as usize];
            q[2].atan2(q[1]).rem_euclid(TAU) / TAU
        });
        if u.iter().any(|&x| x > 0.75) {
            u = u.map(|x| if x < 0.25 { x + 1.0 } else { x });
        }
        for k in 0..3 {
            text += &format!("vt {} {}\n", u[k], p[tri[k] as usize][0] / length);
        }
        let c = |k: usize| format!("{}/{}", tri[k] + 1, 3 * t + k + 1);
        text += &format!("f {} {} {}\n", c(0), c(1), c(2));
    }
    text
}

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn every_glb_passes_the_khronos_validator() {
    let dir = out_dir("gltf-validator");
    let glbs = write_glbs(&dir);
    let out = Command::new("node")
        .arg(tools().join("validate.mjs"))
        .args(&glbs)
        .output()
        .expect("node runs");
    let report = String::from_utf8_lossy(&out.stdout);
    println!("{report}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "validation failed:\n{report}");
    for glb in &glbs {
        assert!(
            report.contains(&format!("{}: 0 errors, 0 warnings", glb.display())),
            "{report}"
        );
    }
}

fn three_js_in_chromium_draws_the_animation_moving() {
    let chromium = chromium();
    let dir = out_dir("gltf-chromium");
    let glbs = write_glbs(&dir);
    let shots = dir.join("screenshots");
    // The planar interpolation and the transfer, both animated, and the
    // quantised and sparse variants.
    for glb in glbs
        .iter()
        .filter(|g| !g.ends_with("transfer-shapes.glb") && !g.ends_with("transfer-uvs.glb"))
    {
        let out = Command::new("node")
            .arg(tools().join("render.mjs"))
            .arg(glb)
            .arg(&shots)
            .env("CHROMIUM", which(&chromium))
            .output()
            .expect("node runs");
        let report = String::from_utf8_lossy(&out.stdout);
        println!("{report}{}", String::from_utf8_lossy(&out.stderr));
        assert!(out.status.success(), "three.js check failed:\n{report}");
    }
    println!("screenshots in {}", shots.display());
}
