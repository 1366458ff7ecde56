//! `meshmorph transfer` from and into glTF and VRM rigs: the source's
//! morph targets carried into a copy of the target's own file, name
//! clashes refused, inputs never written over, failed runs leave nothing.

use std::path::{Path, PathBuf};
use std::process::Output;

use super::common::{run, text};

use meshmorph::io::gltf::{read, SampleCharacter, SampleVrm};

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// A GLB rig: the sample character, coarser, with two more morph targets
/// (`Extra_0`, `Extra_1`) beside its `Smile`.
fn small_rig() -> Vec<u8> {
    let mut rig = SampleCharacter::default();
    rig.extra_targets = 2;
    rig.rings = 10;
    rig.segments = 12;
    rig.glb()
}

#[test]
fn morph_targets_of_a_glb_rig_go_into_a_copy_of_a_vrm() {
    let dir = tempfile::tempdir().unwrap();
    let source = write(dir.path(), "rig.glb", &small_rig());
    let mut character = SampleCharacter::default();
    character.vrm = SampleVrm::V1;
    let target_bytes = character.glb();
    let target = write(dir.path(), "char.vrm", &target_bytes);
    let out = dir.path().join("char-shapes.vrm");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let base = [
        "transfer".to_string(),
        "--source-ref".into(),
        s(&source),
        "--target-ref".into(),
        s(&target),
        "--no-markers".into(),
        "--gltf".into(),
        s(&out),
    ];
    let with = |extra: &[&str]| -> Output {
        let mut args: Vec<&str> = base.iter().map(String::as_str).collect();
        args.extend(extra);
        run(&args)
    };
    // Both have a `Smile`: refused, naming it, and nothing written.
    let refused = with(&[]);
    assert!(!refused.status.success());
    let message = text(&refused);
    assert!(
        message.contains("`Smile`") && message.contains("--replace-shapes"),
        "{message}"
    );
    assert!(!message.contains("panicked"), "{message}");
    assert!(!out.exists());
    // Chosen shapes, as VRM expressions.
    let done = with(&["--shapes", "Extra_1,Extra_0", "--vrm-expressions"]);
    assert!(done.status.success(), "{}", text(&done));
    let (doc, mesh) = read(&out, None).unwrap();
    assert_eq!(mesh.target_names(), ["Smile", "Extra_1", "Extra_0"]);
    let custom = &doc.json()["extensions"]["VRMC_vrm"]["expressions"]["custom"];
    assert_eq!(custom["Extra_0"]["morphTargetBinds"][0]["index"], 2);
    // The bulges moved the target's body, and only outwards a little.
    for t in &mesh.targets[1..] {
        let moved = t
            .positions
            .iter()
            .zip(mesh.surface.positions())
            .filter(|(p, q)| p != q)
            .count();
        assert!(moved > 0, "{}", t.name);
    }
    // The input is untouched.
    assert_eq!(std::fs::read(&target).unwrap(), target_bytes);
    // Every target, replacing the character's own Smile.
    std::fs::remove_file(&out).unwrap();
    let replaced = with(&["--replace-shapes"]);
    assert!(replaced.status.success(), "{}", text(&replaced));
    let (_, mesh) = read(&out, None).unwrap();
    assert_eq!(mesh.target_names(), ["Smile", "Extra_0", "Extra_1"]);
    // Writing over an input is refused.
    let over = run(&[
        "transfer",
        "--source-ref",
        &s(&source),
        "--target-ref",
        &s(&target),
        "--no-markers",
        "--gltf",
        &s(&target),
        "--replace-shapes",
    ]);
    assert!(!over.status.success());
    assert_eq!(std::fs::read(&target).unwrap(), target_bytes);
    // A mesh that is not there is named with the file's meshes.
    let missing = with(&["--target-mesh", "Face"]);
    let message = text(&missing);
    assert!(!missing.status.success());
    assert!(
        message.contains("char.vrm") && message.contains("`Face`") && message.contains("`Body`"),
        "{message}"
    );
}

/// Runs the batch file `text`, written as `dir/name`, after making the
/// folders its `gltf` outputs are in.
fn batch(dir: &Path, name: &str, text: &str) -> Output {
    for line in text.lines() {
        if let Some(gltf) = line.strip_prefix("gltf = \"") {
            let path = dir.join(gltf.trim_end_matches('"'));
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        }
    }
    let path = write(dir, name, text.as_bytes());
    run(&["transfer", "--batch", path.to_str().unwrap()])
}

/// Marker pairs on the sample character's body, as positions (both rigs
/// are the same body, made of more or fewer vertices).
const BODY_MARKERS: &str = "top 0 1.6 0 0 1.6 0
bottom 0 0 0 0 0 0
right 0.25 0.8 0 0.25 0.8 0
left -0.25 0.8 0 -0.25 0.8 0
front 0 0.8 0.25 0 0.8 0.25
back 0 0.8 -0.25 0 0.8 -0.25
chin 0 1.2 0.25 0 1.2 0.25
";

#[test]
fn a_batch_carries_a_rigs_morph_targets_into_copies_of_glb_and_vrm_characters() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "rig.glb", &small_rig());
    let glb_bytes = SampleCharacter::default().glb();
    let glb = write(dir.path(), "char.glb", &glb_bytes);
    let mut vrm0 = SampleCharacter::default();
    vrm0.vrm = SampleVrm::V0;
    let vrm_bytes = vrm0.glb();
    let vrm = write(dir.path(), "char.vrm", &vrm_bytes);
    write(dir.path(), "body.txt", BODY_MARKERS.as_bytes());
    let done = batch(
        dir.path(),
        "batch.toml",
        r#"
source = "rig.glb"
source_mesh = "Body"
shapes = ["Extra_1", "Extra_0"]

[[targets]]
reference = "char.glb"
markers = "body.txt"
gltf = "out/char-shapes.glb"

[[targets]]
reference = "char.vrm"
mesh = "Body"
markers = "body.txt"
gltf = "out/char-shapes.vrm"
vrm_expressions = true
"#,
    );
    assert!(done.status.success(), "{}", text(&done));
    let (_, mesh) = read(&dir.path().join("out/char-shapes.glb"), None).unwrap();
    assert_eq!(mesh.target_names(), ["Smile", "Extra_1", "Extra_0"]);
    let (doc, mesh) = read(&dir.path().join("out/char-shapes.vrm"), None).unwrap();
    assert_eq!(mesh.target_names(), ["Smile", "Extra_1", "Extra_0"]);
    let groups = &doc.json()["extensions"]["VRM"]["blendShapeMaster"]["blendShapeGroups"];
    let names: Vec<&str> = groups
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g["name"].as_str().unwrap())
        .collect();
    assert!(
        names.contains(&"Extra_0") && names.contains(&"Extra_1"),
        "{groups}"
    );
    assert!(
        !text(&done).contains("wrote 2 poses to \n"),
        "{}",
        text(&done)
    );
    // The inputs are untouched.
    assert_eq!(std::fs::read(&glb).unwrap(), glb_bytes);
    assert_eq!(std::fs::read(&vrm).unwrap(), vrm_bytes);

    // Every shape of the rig into the GLB clashes on `Smile`: that target
    // fails naming it, the other is written, the run says one failed.
    let failed = batch(
        dir.path(),
        "clash.toml",
        r#"
source = "rig.glb"

[[targets]]
reference = "char.glb"
markers = "body.txt"
gltf = "clash/char-smile.glb"

[[targets]]
reference = "char.vrm"
markers = "body.txt"
gltf = "clash/char-smile.vrm"
replace_shapes = true
"#,
    );
    let message = text(&failed);
    assert!(!failed.status.success(), "{message}");
    assert!(
        message.contains("`Smile`") && message.contains("target 0 of"),
        "{message}"
    );
    assert!(!message.contains("panicked"), "{message}");
    assert!(!dir.path().join("clash/char-smile.glb").exists());
    let (_, mesh) = read(&dir.path().join("clash/char-smile.vrm"), None).unwrap();
    assert_eq!(mesh.target_names(), ["Smile", "Extra_0", "Extra_1"]);
}

#[test]
fn a_batch_refuses_what_a_glb_rig_cannot_do_naming_the_file_and_target() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "rig.glb", &SampleCharacter::default().glb());
    write(dir.path(), "char.glb", &SampleCharacter::default().glb());
    let tube = meshmorph::shapes::tube(1.6, 0.25, 8, 8);
    let obj = dir.path().join("tube.obj");
    meshmorph::io::write_mesh(&obj, &tube, meshmorph::io::Format::Obj).unwrap();
    write(dir.path(), "body.txt", BODY_MARKERS.as_bytes());
    let refused = |name: &str, file: &str, expected: &[&str]| {
        let out = batch(dir.path(), name, file);
        let message = text(&out);
        assert!(!out.status.success(), "{name}: {message}");
        assert!(!message.contains("panicked"), "{name}: {message}");
        for e in expected {
            assert!(message.contains(e), "{name}: no {e:?} in {message}");
        }
    };
    // An OBJ source has no morph targets to stand for the poses.
    refused(
        "no-poses.toml",
        "source = \"tube.obj\"\n[[targets]]\nreference = \"char.glb\"\nmarkers = \"body.txt\"\ngltf = \"a.glb\"\n",
        &["no-poses.toml", "lists no poses", "tube.obj"],
    );
    // Neither a folder nor a glTF to write.
    refused(
        "nothing.toml",
        "source = \"rig.glb\"\n[[targets]]\nreference = \"char.glb\"\nmarkers = \"body.txt\"\n",
        &["target 0 of", "nothing.toml", "`output`"],
    );
    // A folder of poses without pose files.
    refused(
        "folder.toml",
        "source = \"rig.glb\"\n[[targets]]\nreference = \"char.glb\"\nmarkers = \"body.txt\"\ngltf = \"a.glb\"\noutput = \"poses/\"\n",
        &["target 0 of", "folder.toml", "`output`", "`gltf`"],
    );
    // A glTF made from scratch (an OBJ target) is a .glb.
    refused(
        "vrm-of-obj.toml",
        "source = \"rig.glb\"\n[[targets]]\nreference = \"tube.obj\"\nmarkers = \"body.txt\"\ngltf = \"tube.vrm\"\n",
        &["target 0 of", "tube.vrm", ".glb"],
    );
    // VRM expressions need a VRM (or glTF) reference written back.
    refused(
        "expressions-of-obj.toml",
        "source = \"rig.glb\"\n[[targets]]\nreference = \"tube.obj\"\nmarkers = \"body.txt\"\ngltf = \"tube.glb\"\nvrm_expressions = true\n",
        &["target 0 of", "vrm_expressions"],
    );
    // A mesh the target does not have, named with the ones it has.
    refused(
        "no-face.toml",
        "source = \"rig.glb\"\n[[targets]]\nreference = \"char.glb\"\nmesh = \"Face\"\nmarkers = \"body.txt\"\ngltf = \"a.glb\"\n",
        &["char.glb", "`Face`", "`Body`"],
    );
    // Shapes and pose files both.
    refused(
        "both.toml",
        "source = \"rig.glb\"\nposes = [\"tube.obj\"]\nshapes = [\"Smile\"]\n[[targets]]\nreference = \"char.glb\"\nmarkers = \"body.txt\"\ngltf = \"a.glb\"\n",
        &["both.toml", "`shapes`"],
    );
    // A shape the source does not have.
    refused(
        "no-shape.toml",
        "source = \"rig.glb\"\nshapes = [\"Frown\"]\n[[targets]]\nreference = \"char.glb\"\nmarkers = \"body.txt\"\ngltf = \"a.glb\"\n",
        &["Frown", "Smile"],
    );
    assert!(!dir.path().join("a.glb").exists());
}
