//! The GLB files meshmorph writes, checked in real clients: the Khronos glTF
//! validator (no error, no warning) and three.js's GLTFLoader in headless
//! Chromium (the mesh is drawn and moves).
//!
//! Both need `npm ci` in tools/browser-checks (and Debian's `chromium` for the
//! second): see `browser.rs`.

use std::path::{Path, PathBuf};
use std::process::Command;

use std::fs;

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
    ]
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

    vec![
        demo.join("spiral.glb"),
        demo.join("transfer/transfer.glb"),
        shapes,
        uv_glb,
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
    // The planar interpolation and the transfer, both animated.
    for glb in &glbs[..2] {
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
