//! `meshmorph expressions`: the built-in template's shapes put on a head
//! (the template's own head, turned, scaled and moved) from its landmarks,
//! written as one mesh per shape, into a new GLB, and into a copy of a
//! glTF head; the refusals, with nothing written.

use std::path::{Path, PathBuf};
use std::process::Output;

use super::common::{run, text};

use meshmorph::io::gltf::{read, write_glb, GltfOptions};
use meshmorph::io::Appearance;
use meshmorph::{landmark_name, ExpressionTemplate, Mesh3, RECOMMENDED_LANDMARKS};

/// `meshmorph expressions HEAD --markers POINTS -o OUT` and `extra`.
fn expressions(head: &Path, points: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["expressions", s(head), "--markers", s(points), "-o", s(out)];
    args.extend(extra);
    run(&args)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The template's head turned a little, scaled by 1.4 and moved; and its
/// recommended landmarks, as a point file of `name x y z` lines (every
/// one but those in `leave_out`).
fn head_and_landmarks(leave_out: &[u8]) -> (Mesh3, String) {
    let t = ExpressionTemplate::arkit();
    let (c, s) = (0.3f64.cos(), 0.3f64.sin());
    let moved: Vec<[f64; 3]> = t
        .head
        .positions()
        .iter()
        .map(|p| {
            let [x, y, z] = [1.4 * p[0], 1.4 * p[1], 1.4 * p[2]];
            [c * x + s * z + 0.5, y - 2.0, -s * x + c * z + 1.0]
        })
        .collect();
    let head = t.head.with_positions(moved).unwrap();
    let mut lines = String::from("# landmarks by iBUG number and alias\n");
    for n in RECOMMENDED_LANDMARKS {
        if leave_out.contains(&n) {
            continue;
        }
        let v = t.landmark(&n.to_string()).unwrap();
        let p = head.positions()[v as usize];
        lines += &format!("{} {} {} {}\n", landmark_name(n), p[0], p[1], p[2]);
    }
    (head, lines)
}

fn write_obj(path: &Path, mesh: &Mesh3) {
    meshmorph::io::write_positions(
        path,
        mesh.positions(),
        mesh.triangles(),
        meshmorph::io::Format::Obj,
    )
    .unwrap();
}

fn json(out: &Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{e}: {}", text(out)))
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

#[test]
fn an_obj_head_gets_one_mesh_per_arkit_shape_and_a_new_glb() {
    let dir = tempfile::tempdir().unwrap();
    let (head, landmarks) = head_and_landmarks(&[]);
    let head_path = dir.path().join("head.obj");
    write_obj(&head_path, &head);
    let points = dir.path().join("head.txt");
    std::fs::write(&points, landmarks).unwrap();
    let shapes = dir.path().join("shapes");
    let gif = dir.path().join("faces.gif");
    let out = expressions(
        &head_path,
        &points,
        &shapes,
        &["--gif", s(&gif), "--size", "64", "--json"],
    );
    assert!(out.status.success(), "{}", text(&out));
    let report = json(&out);
    assert_eq!(report["missing"], serde_json::json!(["tongueOut"]));
    assert_eq!(report["landmarks"], 17);
    let names = files_in(&shapes);
    assert_eq!(names.len(), 51, "{names:?}");
    for expected in [
        "jawOpen.obj",
        "eyeBlinkLeft.obj",
        "browInnerUp.obj",
        "mouthSmileRight.obj",
    ] {
        assert!(names.iter().any(|n| n == expected), "{expected}: {names:?}");
    }
    assert!(gif.exists());
    // jawOpen moves the chin down a good way; eyeBlinkLeft leaves it still.
    let read_shape = |name: &str| {
        meshmorph::io::read_mesh(&shapes.join(name))
            .unwrap()
            .positions()
            .to_vec()
    };
    let chin = ExpressionTemplate::arkit().landmark("9").unwrap() as usize;
    let diagonal = head.bounding_box_diagonal();
    let jaw = read_shape("jawOpen.obj");
    assert_eq!(jaw.len(), head.num_vertices());
    let moved = |p: [f64; 3]| {
        let q = head.positions()[chin];
        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
    };
    assert!(moved(jaw[chin]) > 0.02 * diagonal, "{}", moved(jaw[chin]));
    assert_eq!(read_shape("eyeBlinkLeft.obj")[chin], head.positions()[chin]);

    // The same head into a new GLB: the shapes as its morph targets.
    let glb = dir.path().join("head-arkit.glb");
    let out = expressions(&head_path, &points, &glb, &[]);
    assert!(out.status.success(), "{}", text(&out));
    assert!(text(&out).contains("tongueOut"), "{}", text(&out));
    let (_, mesh) = read(&glb, None).unwrap();
    let targets = mesh.target_names();
    assert_eq!(targets.len(), 51);
    assert!(targets.contains(&"jawOpen"));
}

#[test]
fn a_glb_head_gets_the_shapes_in_a_copy_of_its_own_file() {
    let dir = tempfile::tempdir().unwrap();
    let (head, landmarks) = head_and_landmarks(&[]);
    let head_path = dir.path().join("head.glb");
    let look = Appearance::default();
    let base = look.base(head.positions(), head.triangles());
    let names: Vec<String> = vec!["smile".into()];
    let smile: Vec<[f64; 3]> = head
        .positions()
        .iter()
        .map(|p| [p[0], p[1], p[2] + 1e-3])
        .collect();
    write_glb(
        &head_path,
        &base,
        &[smile],
        &names,
        &GltfOptions::default().with_animation(false),
    )
    .unwrap();
    let before = std::fs::read(&head_path).unwrap();
    let points = dir.path().join("head.txt");
    std::fs::write(&points, landmarks).unwrap();
    let out_path = dir.path().join("head-arkit.glb");
    let out = expressions(&head_path, &points, &out_path, &["--all-shapes"]);
    assert!(out.status.success(), "{}", text(&out));
    assert_eq!(
        std::fs::read(&head_path).unwrap(),
        before,
        "the head was written"
    );
    let (_, mesh) = read(&out_path, None).unwrap();
    let targets = mesh.target_names();
    // Its own target first, then ARKit's 51, then the template's others.
    assert_eq!(targets[0], "smile");
    assert_eq!(targets[1], "eyeBlinkLeft");
    assert!(targets.len() > 52, "{targets:?}");
    assert!(targets.contains(&"jawOpen"));

    // A text glTF output for a binary head is refused, nothing written.
    let wrong = dir.path().join("head-arkit.gltf");
    let out = expressions(&head_path, &points, &wrong, &[]);
    assert!(!out.status.success());
    assert!(text(&out).contains("binary glTF"), "{}", text(&out));
    assert!(!wrong.exists());
}

#[test]
fn too_few_or_unknown_landmarks_are_refused_naming_them_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let (head, landmarks) = head_and_landmarks(&[1, 9, 17, 18, 22, 23]);
    let head_path = dir.path().join("head.obj");
    write_obj(&head_path, &head);
    let points = dir.path().join("few.txt");
    std::fs::write(&points, &landmarks).unwrap();
    let shapes: PathBuf = dir.path().join("shapes");
    let refused = |points: &Path, expected: &str| {
        let out = expressions(&head_path, points, &shapes, &[]);
        assert!(!out.status.success());
        let message = text(&out);
        assert!(message.contains(expected), "{message}");
        assert!(!message.contains("panicked"), "{message}");
        assert!(files_in(&shapes).is_empty(), "{:?}", files_in(&shapes));
    };
    refused(&points, "12");
    let unknown = dir.path().join("unknown.txt");
    std::fs::write(&unknown, format!("{landmarks}earlobeLeft 0 0 0\n")).unwrap();
    refused(&unknown, "earlobeLeft");

    // A template that is not a GLB: named.
    let bad = dir.path().join("rig.glb");
    std::fs::write(&bad, b"not a glb").unwrap();
    let out = expressions(&head_path, &points, &shapes, &["--template", s(&bad)]);
    assert!(!out.status.success());
    assert!(text(&out).contains("rig.glb"), "{}", text(&out));
    assert!(!text(&out).contains("panicked"), "{}", text(&out));

    // -o naming one mesh file (the head itself, or a new one): a folder
    // or a .glb is asked for, and nothing is written.
    let (_, all) = head_and_landmarks(&[]);
    std::fs::write(&points, &all).unwrap();
    let before = std::fs::read(&head_path).unwrap();
    for out_path in [head_path.clone(), dir.path().join("shapes.obj")] {
        let out = expressions(&head_path, &points, &out_path, &[]);
        assert!(!out.status.success());
        assert!(
            text(&out).contains("names one OBJ file") && text(&out).contains("give a folder"),
            "{}",
            text(&out)
        );
    }
    assert_eq!(std::fs::read(&head_path).unwrap(), before);
    assert!(!dir.path().join("shapes.obj").exists());

    // A new GLB past --max-gltf-mb: refused with the count of shapes, the
    // way to make fewer of them and the limit that would do; nothing written.
    let glb = dir.path().join("head-arkit.glb");
    let out = expressions(
        &head_path,
        &points,
        &glb,
        &["--all-shapes", "--max-gltf-mb", "1"],
    );
    assert!(!out.status.success());
    let message = text(&out);
    for expected in [
        "head-arkit.glb",
        "would weigh about",
        "shapes x",
        "leave out --all-shapes",
        "--max-gltf-mb ",
    ] {
        assert!(message.contains(expected), "{expected}: {message}");
    }
    assert!(!glb.exists());
}

#[test]
fn a_batch_puts_the_shapes_on_each_head_and_one_that_fails_leaves_the_others() {
    let dir = tempfile::tempdir().unwrap();
    let (head, landmarks) = head_and_landmarks(&[]);
    let (_, few) = head_and_landmarks(&[1, 9, 17, 18, 22, 23]);
    write_obj(&dir.path().join("alice.obj"), &head);
    write_obj(&dir.path().join("bob.obj"), &head);
    std::fs::write(dir.path().join("alice.txt"), &landmarks).unwrap();
    std::fs::write(dir.path().join("bob.txt"), &few).unwrap();
    let batch = dir.path().join("heads.toml");
    let write_batch = |bob_output: &str| {
        std::fs::write(
            &batch,
            format!(
                "[[heads]]\nhead = \"alice.obj\"\nmarkers = \"alice.txt\"\noutput = \"alice-arkit.glb\"\ngif = \"alice.gif\"\n\n\
                 [[heads]]\nhead = \"bob.obj\"\nmarkers = \"bob.txt\"\noutput = \"{bob_output}\"\n"
            ),
        )
        .unwrap();
    };

    // Two heads writing the same file: refused before any work.
    write_batch("alice-arkit.glb");
    let out = run(&["expressions", "--batch", s(&batch)]);
    assert!(!out.status.success());
    let message = text(&out);
    assert!(
        message.contains("head 0") && message.contains("head 1"),
        "{message}"
    );
    assert!(!message.contains("panicked"), "{message}");
    assert!(!dir.path().join("alice-arkit.glb").exists());

    // Bob's landmarks are too few: Alice's head is written, Bob's named.
    write_batch("bob/");
    let out = run(&["expressions", "--batch", s(&batch), "--size", "48"]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    let message = text(&out);
    assert!(
        message.contains("`bob.obj`") && message.contains("12"),
        "{message}"
    );
    assert!(message.contains("1 of 2 heads written"), "{message}");
    assert!(message.contains("1 of 2 heads failed"), "{message}");
    let (_, mesh) = read(&dir.path().join("alice-arkit.glb"), None).unwrap();
    assert_eq!(mesh.target_names().len(), 51);
    assert!(dir.path().join("alice.gif").exists());
    assert!(files_in(&dir.path().join("bob")).is_empty());

    // One picture for every head: refused, pointing at the batch file.
    let out = run(&["expressions", "--batch", s(&batch), "--gif", "all.gif"]);
    assert!(!out.status.success());
    assert!(
        text(&out).contains("for each head in the batch file"),
        "{}",
        text(&out)
    );
    // A head on the command line as well: refused by the parser.
    let out = run(&["expressions", "--batch", s(&batch), "x.obj"]);
    assert!(!out.status.success());
    assert!(text(&out).contains("--batch"), "{}", text(&out));
}
