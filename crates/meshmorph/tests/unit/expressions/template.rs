use meshmorph::expressions::template::*;

/// `tools/arkit-template/build.py` run on the ICT-FaceKit copy that
/// `MESHMORPH_ICT_FACEKIT` names makes the shipped file byte for byte
/// (`PYTHON` names an interpreter with numpy; default `python3`).
#[test]
#[ignore = "needs MESHMORPH_ICT_FACEKIT (a copy of ICT-FaceKit) and Python with numpy"]
fn the_shipped_template_is_what_the_build_script_makes() {
    let Some(facekit) = std::env::var_os("MESHMORPH_ICT_FACEKIT") else {
        panic!("set MESHMORPH_ICT_FACEKIT to a copy of ICT-FaceKit (github.com/ICT-VGL/ICT-FaceKit) to run this check");
    };
    let python = std::env::var_os("PYTHON").unwrap_or_else(|| "python3".into());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("arkit.glb");
    let status = std::process::Command::new(&python)
        .arg(root.join("../../tools/arkit-template/build.py"))
        .arg(&facekit)
        .arg(&out)
        .status()
        .expect("Python runs");
    assert!(
        status.success(),
        "the build script failed (does {python:?} have numpy?)"
    );
    let built = std::fs::read(&out).unwrap();
    assert!(
        built == ARKIT_TEMPLATE_GLB,
        "the shipped template differs from what the script makes: rebuild it"
    );
}

#[test]
fn the_builtin_template_has_its_head_parts_shapes_and_landmarks() {
    let t = ExpressionTemplate::arkit();
    assert_eq!(t.shape_names.len(), 57);
    assert_eq!(t.landmarks.len(), 68);
    assert_eq!(t.face, 0..9409);
    let names: Vec<&str> = t.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "gumsTongue",
            "teethUpper",
            "teethLower",
            "eyeLeft",
            "eyeRight"
        ]
    );
    // The head's left eye is on +x: eyeBlink_L moves it, not the right.
    let blink = t.shape("eyeBlink_L").unwrap();
    let moved: Vec<[f64; 3]> = (0..t.head.num_vertices())
        .filter(|&v| t.head_deltas[blink][v] != [0.0; 3])
        .map(|v| t.head.positions()[v])
        .collect();
    assert!(!moved.is_empty());
    assert!(moved.iter().all(|p| p[0] > -0.01), "the left eye is on +x");
}

#[test]
fn the_back_of_the_head_is_exactly_still_in_the_eye_shapes() {
    let t = ExpressionTemplate::arkit();
    let back: Vec<usize> = (0..t.head.num_vertices())
        .filter(|&v| t.head.positions()[v][2] < -0.02)
        .collect();
    assert!(back.len() > 100);
    for name in ["eyeBlink_L", "eyeBlink_R", "browDown_L", "eyeLookUp_R"] {
        let k = t.shape(name).unwrap();
        assert!(
            back.iter().all(|&v| t.head_deltas[k][v] == [0.0; 3]),
            "{name}"
        );
    }
}

#[test]
fn upper_teeth_are_still_and_lower_teeth_rigid_in_jaw_open() {
    let t = ExpressionTemplate::arkit();
    let jaw = t.shape("jawOpen").unwrap();
    let part = |n: &str| t.parts.iter().find(|p| p.name == n).unwrap();
    assert!(part("teethUpper").deltas[jaw]
        .iter()
        .all(|d| *d == [0.0; 3]));
    // Lower teeth: every edge keeps its length to the quantisation's step.
    let lower = part("teethLower");
    let posed: Vec<[f64; 3]> = lower
        .mesh
        .positions()
        .iter()
        .zip(&lower.deltas[jaw])
        .map(|(p, d)| std::array::from_fn(|i| p[i] + d[i]))
        .collect();
    assert!(posed != lower.mesh.positions());
    let len = |a: [f64; 3], b: [f64; 3]| (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
    for tri in lower.mesh.triangles() {
        let [a, b, _] = tri.map(|v| v as usize);
        let rest = len(lower.mesh.positions()[a], lower.mesh.positions()[b]);
        assert!((len(posed[a], posed[b]) - rest).abs() < 2e-4, "{rest}");
    }
}
