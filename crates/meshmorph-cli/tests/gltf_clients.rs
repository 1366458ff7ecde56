//! The GLB files meshmorph writes, checked in real clients: the Khronos glTF
//! validator (no error, no warning) and three.js's GLTFLoader in headless
//! Chromium (the mesh is drawn and moves).
//!
//! Both need `npm ci` in tools/gltf-check (and Debian's `chromium` for the
//! second). Without them the tests say they were skipped; in CI
//! (`CI=true`) a missing tool fails them instead.

use std::path::{Path, PathBuf};
use std::process::Command;

use meshmorph::io::gltf::{write_glb, GltfBase, GltfOptions};
use meshmorph::shapes::{bend, tube};

fn tools() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tools/gltf-check")
}

fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// Whether `program --version` runs.
fn runs(program: &str) -> bool {
    Command::new(program)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Whether the check can run; prints why not, and panics in CI.
fn available(what: &str, needs: &[(&str, bool)]) -> bool {
    let missing: Vec<&str> = needs
        .iter()
        .filter(|(_, ok)| !ok)
        .map(|(name, _)| *name)
        .collect();
    if missing.is_empty() {
        return true;
    }
    let message = format!(
        "{what}: skipped, missing {} (install: apt-get install nodejs chromium; npm ci in tools/gltf-check)",
        missing.join(", ")
    );
    assert!(!in_ci(), "{message}: CI must run this check");
    eprintln!("{message}");
    false
}

fn node_packages() -> bool {
    tools().join("node_modules/gltf-validator").is_dir()
        && tools().join("node_modules/three").is_dir()
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

    // Texture coordinates: u around the tube (0 to 1 across the seam), v along.
    let rest = tube(4.0, 0.5, 9, 16);
    let p = rest.positions();
    let uvs: Vec<[[f64; 2]; 3]> = rest
        .triangles()
        .iter()
        .map(|t| {
            let mut u = t.map(|v| {
                let q = p[v as usize];
                q[2].atan2(q[1]).rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU
            });
            if u.iter().any(|&x| x > 0.75) {
                u = u.map(|x| if x < 0.25 { x + 1.0 } else { x });
            }
            std::array::from_fn(|k| [u[k], p[t[k] as usize][0] / 4.0])
        })
        .collect();
    let poses: Vec<Vec<[f64; 3]>> = (0..6)
        .map(|k| bend(&rest, 4.0, 0.3 * k as f64).positions().to_vec())
        .collect();
    let names: Vec<String> = (0..6).map(|k| format!("bend-{k}")).collect();
    let uv_glb = dir.join("transfer-uvs.glb");
    let base = GltfBase::new(rest.positions(), rest.triangles()).with_corner_uvs(&uvs);
    write_glb(&uv_glb, &base, &poses, &names, &GltfOptions::default()).unwrap();

    vec![
        demo.join("spiral.glb"),
        demo.join("transfer/transfer.glb"),
        shapes,
        uv_glb,
    ]
}

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn every_glb_passes_the_khronos_validator() {
    if !available(
        "glTF validator",
        &[("node", runs("node")), ("npm packages", node_packages())],
    ) {
        return;
    }
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

#[test]
fn three_js_in_chromium_draws_the_animation_moving() {
    let chromium = std::env::var("CHROMIUM").unwrap_or_else(|_| "chromium".into());
    if !available(
        "three.js in Chromium",
        &[
            ("node", runs("node")),
            ("npm packages", node_packages()),
            ("chromium", runs(&chromium)),
        ],
    ) {
        return;
    }
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

/// The full path of a program on the PATH (puppeteer wants one).
fn which(program: &str) -> String {
    if program.contains('/') {
        return program.to_string();
    }
    std::env::var_os("PATH")
        .and_then(|paths| {
            std::env::split_paths(&paths)
                .map(|d| d.join(program))
                .find(|p| p.is_file())
        })
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| program.to_string())
}
