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

#[test]
fn morph_targets_of_a_glb_rig_go_into_a_copy_of_a_vrm() {
    let dir = tempfile::tempdir().unwrap();
    let mut rig = SampleCharacter::default();
    rig.extra_targets = 2;
    rig.rings = 10;
    rig.segments = 12;
    let source = write(dir.path(), "rig.glb", &rig.glb());
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
