//! The GLB files meshmorph writes, checked in real clients: the Khronos glTF
//! validator (no error, no warning), three.js's GLTFLoader in headless
//! Chromium (the mesh is drawn and moves) and Blender's importer; and the
//! users' own files with shape keys written back into them (a GLB
//! character, a `.gltf` with its buffer and image beside it, a VRM 0.x and
//! a VRM 1.0), in the validator (no error, no warning the input did not
//! have), in Blender (the new keys on the same object, all else as the
//! input imports) and in three.js (drawn, moving, the new targets named).
//!
//! All need `npm ci` in tools/browser-checks, and Debian's `chromium` or
//! `blender` for theirs: see `browser.rs`.

use std::path::{Path, PathBuf};
use std::process::Command;

use std::fs;

use meshmorph::io::gltf::{write_glb, GltfBase, GltfOptions, SampleCharacter, SampleVrm};
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
        (
            "gltf_clients::written_back_files_pass_the_khronos_validator_as_their_inputs_do",
            written_back_files_pass_the_khronos_validator_as_their_inputs_do,
            Needs::Node,
        ),
        (
            "gltf_clients::blender_finds_written_back_shape_keys_on_the_same_objects",
            blender_finds_written_back_shape_keys_on_the_same_objects,
            Needs::Blender,
        ),
        (
            "gltf_clients::three_js_in_chromium_reads_written_back_glb_and_vrm",
            three_js_in_chromium_reads_written_back_glb_and_vrm,
            Needs::Chromium,
        ),
    ]
}

/// Blender's own glTF importer, in the background: every GLB gives a mesh
/// with one shape key per morph target, named as the targets, and the
/// sparse file's keys move only where its frames do.
fn blenders_importer_reads_every_glb() {
    let dir = out_dir("gltf-blender");
    let glbs = write_glbs(&dir);
    let imported = blender_import(&dir, &glbs);
    for (glb, got) in glbs.iter().zip(&imported) {
        // The names as the file gives them (read as JSON: the gltf crate
        // refuses files that require KHR_mesh_quantization).
        let bytes = fs::read(glb).unwrap();
        let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + length]).unwrap();
        let names = &doc["meshes"][0]["extras"]["targetNames"];
        let meshes = mesh_objects(got);
        assert_eq!(meshes.len(), 1, "{}", glb.display());
        let moved = moves(meshes[0]);
        println!(
            "{}: {} shape keys, largest moves {:.3?}",
            glb.display(),
            moved.len(),
            &moved[..moved.len().min(4)]
        );
        assert_eq!(&meshes[0]["keys"], names, "{}", glb.display());
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
    assert_eq!(moves(mesh_objects(sparse)[0])[0], 0.0);
}

/// What Blender's glTF importer makes of each file, read in the background
/// (a factory scene for each): for every object its name, type and
/// parent, and for a mesh its vertices, materials, their textures (name
/// and size in pixels), shape keys (the basis left out), how far each key
/// moves a vertex at most and its armature modifiers' objects, for an
/// armature its bones.
fn blender_import(dir: &Path, files: &[PathBuf]) -> Vec<serde_json::Value> {
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
    objects = []
    for o in sorted(bpy.data.objects, key=lambda o: o.name):
        got = {"name": o.name, "type": o.type, "parent": o.parent.name if o.parent else None}
        if o.type == "MESH":
            keys = o.data.shape_keys
            blocks = list(keys.key_blocks) if keys else []
            basis = [v.co.copy() for v in blocks[0].data] if blocks else []
            got["vertices"] = len(o.data.vertices)
            got["materials"] = [m.name if m else None for m in o.data.materials]
            got["textures"] = sorted(f"{n.image.name} {n.image.size[0]}x{n.image.size[1]}" for m in o.data.materials if m and m.use_nodes for n in m.node_tree.nodes if n.type == "TEX_IMAGE" and n.image)
            got["keys"] = [k.name for k in blocks[1:]]
            got["moved"] = [max(((a - b).length for a, b in zip((v.co for v in k.data), basis)), default=0.0) for k in blocks[1:]]
            got["armatures"] = [m.object.name for m in o.modifiers if m.type == "ARMATURE" and m.object]
        if o.type == "ARMATURE":
            got["bones"] = [b.name for b in o.data.bones]
        objects.append(got)
    print("IMPORTED " + json.dumps({"path": path, "objects": objects}))
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
        .args(files)
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
    assert_eq!(imported.len(), files.len(), "{text}");
    imported
}

/// The mesh objects of one file's import.
fn mesh_objects(imported: &serde_json::Value) -> Vec<&serde_json::Value> {
    imported["objects"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|o| o["type"] == "MESH")
        .collect()
}

/// How far each shape key of a mesh object moves a vertex at most.
fn moves(object: &serde_json::Value) -> Vec<f64> {
    object["moved"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m.as_f64().unwrap())
        .collect()
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
    let reports = validate(&glbs);
    for (glb, report) in glbs.iter().zip(&reports) {
        assert!(
            report.errors == 0 && report.warnings == 0,
            "{}: {report:?}",
            glb.display()
        );
    }
}

/// One file's report from the Khronos validator (`validate.mjs`).
#[derive(Debug)]
struct Validated {
    errors: usize,
    warnings: usize,
    /// Each error and warning: its severity, code and JSON pointer.
    issues: Vec<String>,
}

/// Runs the Khronos validator on `files` (in one node) and reads its
/// report of each, in order.
fn validate(files: &[PathBuf]) -> Vec<Validated> {
    let out = Command::new("node")
        .arg(tools().join("validate.mjs"))
        .args(files)
        .output()
        .expect("node runs");
    let report = String::from_utf8_lossy(&out.stdout);
    println!("{report}{}", String::from_utf8_lossy(&out.stderr));
    // 1 is a file with an error or a warning, read below; 2 is a file
    // that could not be read.
    assert!(
        matches!(out.status.code(), Some(0 | 1)),
        "validation failed:\n{report}"
    );
    let mut reports: Vec<Validated> = Vec::new();
    for line in report.lines() {
        if let Some(issue) = line.strip_prefix("  ") {
            let (issue, _message) = issue.split_once(": ").unwrap_or((issue, ""));
            reports.last_mut().unwrap().issues.push(issue.to_string());
            continue;
        }
        let file = &files[reports.len()];
        let counts = line
            .strip_prefix(&format!("{}: ", file.display()))
            .unwrap_or_else(|| panic!("no report of {}:\n{report}", file.display()));
        let count = |what: &str| -> usize {
            let words: Vec<&str> = counts.split([' ', ',']).collect();
            let at = words.iter().position(|w| *w == what).unwrap();
            words[at - 1].parse().unwrap()
        };
        reports.push(Validated {
            errors: count("errors"),
            warnings: count("warnings"),
            issues: Vec::new(),
        });
    }
    assert_eq!(reports.len(), files.len(), "{report}");
    for (file, r) in files.iter().zip(&reports) {
        assert_eq!(
            r.issues.len(),
            r.errors + r.warnings,
            "{}: every error and warning listed:\n{report}",
            file.display()
        );
    }
    reports
}

fn three_js_in_chromium_draws_the_animation_moving() {
    let dir = out_dir("gltf-chromium");
    let glbs = write_glbs(&dir);
    let shots = dir.join("screenshots");
    // The planar interpolation and the transfer, both animated, and the
    // quantised and sparse variants.
    let animated: Vec<&Path> = glbs
        .iter()
        .filter(|g| !g.ends_with("transfer-shapes.glb") && !g.ends_with("transfer-uvs.glb"))
        .map(PathBuf::as_path)
        .collect();
    render(&animated, &shots);
    println!("screenshots in {}", shots.display());
}

/// `tools/browser-checks/render.mjs` on `glbs` (one browser for them all),
/// screenshots into `shots`: three.js's GLTFLoader in headless Chromium
/// draws each at the start, the middle and the end of its animation, and
/// it moves. Its report on each, in their order.
fn render(glbs: &[&Path], shots: &Path) -> Vec<String> {
    let out = Command::new("node")
        .arg(tools().join("render.mjs"))
        .args(glbs)
        .arg(shots)
        .env("CHROMIUM", which(&chromium()))
        .output()
        .expect("node runs");
    let report = String::from_utf8_lossy(&out.stdout).into_owned();
    println!("{report}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "three.js check failed:\n{report}");
    // A paragraph a file, each starting with the file's name.
    let reports: Vec<String> = report
        .split("\n\n")
        .filter(|p| !p.trim().is_empty())
        .map(str::to_string)
        .collect();
    assert_eq!(reports.len(), glbs.len(), "{report}");
    for (glb, paragraph) in glbs.iter().zip(&reports) {
        let name = glb.file_name().unwrap().to_string_lossy();
        assert!(paragraph.starts_with(&format!("{name}: ")), "{report}");
    }
    reports
}

/// three.js in headless Chromium on the written-back GLB and VRMs (a
/// `.gltf` needs its files served beside it, which render.mjs does not):
/// drawn, its animation (the head nodding) moving it, and the body's
/// morph targets its own followed by the new ones, by name.
fn three_js_in_chromium_reads_written_back_glb_and_vrm() {
    let dir = out_dir("gltf-written-back-chromium");
    let (pairs, _) = write_backs(&dir);
    let shots = dir.join("screenshots");
    let drawn: Vec<&WrittenBack> = pairs
        .iter()
        .filter(|p| p.output.extension().is_some_and(|e| e != "gltf"))
        .collect();
    let outputs: Vec<&Path> = drawn.iter().map(|p| p.output.as_path()).collect();
    for (pair, report) in drawn.iter().zip(render(&outputs, &shots)) {
        let names = format!("3 morph targets (Smile, {})", pair.added.join(", "));
        assert!(
            report.contains(&names),
            "{}: {report}",
            pair.output.display()
        );
    }
    println!("screenshots in {}", shots.display());
}

/// A user's file and the copy of it a transfer wrote shape keys into.
struct WrittenBack {
    input: PathBuf,
    output: PathBuf,
    /// The shapes the transfer added.
    added: Vec<String>,
}

/// Transfers two morph targets of a GLB rig (`Extra_0`, `Extra_1`) into
/// each kind of user's file the sample character comes as: a GLB, a
/// `.gltf` whose buffer and texture are files beside it, a VRM 0.x and a
/// VRM 1.0 (these two with `--vrm-expressions`), each written back
/// beside its input. Also every input and output, input first.
fn write_backs(dir: &Path) -> (Vec<WrittenBack>, Vec<PathBuf>) {
    let mut rig = SampleCharacter::default();
    rig.extra_targets = 2;
    rig.rings = 10;
    rig.segments = 12;
    let source = dir.join("rig.glb");
    fs::write(&source, rig.glb()).unwrap();
    let sample = |vrm: SampleVrm| {
        let mut c = SampleCharacter::default();
        c.vrm = vrm;
        c.glb()
    };
    let character = dir.join("character.glb");
    fs::write(&character, sample(SampleVrm::None)).unwrap();
    let (vrm0, vrm1) = (dir.join("vrm0.vrm"), dir.join("vrm1.vrm"));
    fs::write(&vrm0, sample(SampleVrm::V0)).unwrap();
    fs::write(&vrm1, sample(SampleVrm::V1)).unwrap();
    // The GLB as a .gltf in a folder of its own: the binary chunk as
    // `character.bin`, the texture as `skin.png`.
    let separate = dir.join("separate");
    fs::create_dir_all(&separate).unwrap();
    let gltf = separate.join("character.gltf");
    {
        let bytes = sample(SampleVrm::None);
        let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        let json_length = word(12);
        let mut json: serde_json::Value =
            serde_json::from_slice(&bytes[20..20 + json_length]).unwrap();
        let bin = &bytes[28 + json_length..28 + json_length + word(20 + json_length)];
        fs::write(separate.join("character.bin"), bin).unwrap();
        json["buffers"][0]["uri"] = "character.bin".into();
        let view = &json_view(&json["images"][0], &json);
        let (start, length) = (
            view["byteOffset"].as_u64().unwrap_or(0) as usize,
            view["byteLength"].as_u64().unwrap() as usize,
        );
        fs::write(separate.join("skin.png"), &bin[start..start + length]).unwrap();
        let image = json["images"][0].as_object_mut().unwrap();
        image.remove("bufferView");
        image.remove("mimeType");
        image.insert("uri".into(), "skin.png".into());
        fs::write(&gltf, serde_json::to_vec_pretty(&json).unwrap()).unwrap();
    }
    let added = vec!["Extra_0".to_string(), "Extra_1".to_string()];
    let pairs: Vec<WrittenBack> = [character, gltf, vrm0, vrm1]
        .into_iter()
        .map(|input| {
            let name = input.file_name().unwrap().to_str().unwrap();
            let (stem, ext) = name.rsplit_once('.').unwrap();
            let output = input.with_file_name(format!("{stem}-shapes.{ext}"));
            let mut args = vec![
                "transfer",
                "--source-ref",
                source.to_str().unwrap(),
                "--target-ref",
                input.to_str().unwrap(),
                "--no-markers",
                "--shapes",
                "Extra_0,Extra_1",
                "--gltf",
                output.to_str().unwrap(),
            ];
            if ext == "vrm" {
                args.push("--vrm-expressions");
            }
            meshmorph(&args);
            WrittenBack {
                input,
                output,
                added: added.clone(),
            }
        })
        .collect();
    let files = pairs
        .iter()
        .flat_map(|p| [p.input.clone(), p.output.clone()])
        .collect();
    (pairs, files)
}

/// The buffer view an image of `json` is stored in.
fn json_view(image: &serde_json::Value, json: &serde_json::Value) -> serde_json::Value {
    json["bufferViews"][image["bufferView"].as_u64().unwrap() as usize].clone()
}

/// The Khronos validator on every kind of written-back file: no error,
/// and no warning (code and place) that its input did not have already.
fn written_back_files_pass_the_khronos_validator_as_their_inputs_do() {
    let dir = out_dir("gltf-written-back-validator");
    let (pairs, files) = write_backs(&dir);
    let reports = validate(&files);
    for (pair, reports) in pairs.iter().zip(reports.chunks(2)) {
        let (before, after) = (&reports[0], &reports[1]);
        assert_eq!(before.errors, 0, "{}: {before:?}", pair.input.display());
        assert_eq!(after.errors, 0, "{}: {after:?}", pair.output.display());
        let new: Vec<&String> = after
            .issues
            .iter()
            .filter(|i| !before.issues.contains(i))
            .collect();
        assert!(
            new.is_empty(),
            "{}: warnings that {} does not have: {new:?}",
            pair.output.display(),
            pair.input.display()
        );
    }
}

/// Blender's importer on every kind of written-back file and on its
/// input: the same objects (names, types, parents), the same armature and
/// bones, the same materials and textures (with their pixels) on every
/// mesh and the same vertices; the
/// body's shape keys are its own followed by the new ones, on the same
/// object, and each new one moves it; every other mesh's keys as they
/// were.
fn blender_finds_written_back_shape_keys_on_the_same_objects() {
    let dir = out_dir("gltf-written-back-blender");
    let (pairs, files) = write_backs(&dir);
    let imported = blender_import(&dir, &files);
    for (pair, got) in pairs.iter().zip(imported.chunks(2)) {
        let (before, after) = (&got[0]["objects"], &got[1]["objects"]);
        let out = pair.output.display();
        let objects = before.as_array().unwrap();
        assert_eq!(
            objects.len(),
            after.as_array().unwrap().len(),
            "{out}: {after}"
        );
        assert!(
            objects
                .iter()
                .any(|o| o["type"] == "ARMATURE" && !o["bones"].as_array().unwrap().is_empty()),
            "{}: no armature imported: {before}",
            pair.input.display()
        );
        let mut grown = 0;
        for (b, a) in objects.iter().zip(after.as_array().unwrap()) {
            for what in [
                "name",
                "type",
                "parent",
                "bones",
                "vertices",
                "materials",
                "textures",
                "armatures",
            ] {
                assert_eq!(b[what], a[what], "{out}: `{what}` of {b} became {a}");
            }
            if b["type"] != "MESH" || b["keys"] == a["keys"] {
                continue;
            }
            // The body: its own keys first, then the new ones, each moving.
            grown += 1;
            let mut keys: Vec<serde_json::Value> = b["keys"].as_array().unwrap().clone();
            keys.extend(
                pair.added
                    .iter()
                    .map(|n| serde_json::Value::from(n.as_str())),
            );
            assert_eq!(a["keys"], serde_json::Value::from(keys), "{out}");
            for what in ["materials", "textures", "armatures"] {
                assert!(
                    !a[what].as_array().unwrap().is_empty(),
                    "{out}: no {what}: {a}"
                );
            }
            // The texture's pixels were found (beside a .gltf, in a GLB).
            assert!(
                a["textures"].as_array().unwrap().iter().all(|t| {
                    let size = t.as_str().unwrap().rsplit(' ').next().unwrap();
                    size != "0x0"
                }),
                "{out}: a texture without pixels: {a}"
            );
            let moved = moves(a);
            println!(
                "{out}: `{}` has keys {}, moving at most {moved:.3?}",
                a["name"], a["keys"]
            );
            assert!(
                moved[moved.len() - pair.added.len()..]
                    .iter()
                    .all(|&m| m > 1e-4),
                "{out}: a new key does not move: {a}"
            );
        }
        assert_eq!(grown, 1, "{out}: the new keys on one object: {after}");
    }
}
