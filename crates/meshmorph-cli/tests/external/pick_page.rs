//! The page of `meshmorph pick` in headless Chromium, driven as a user
//! drives it (`tools/browser-checks/pick.mjs`): three pairs clicked at
//! known points of two procedural sheets, one deleted, the deletion undone,
//! the markers saved and fitted; the saved file must hold the three pairs
//! at the points clicked. A screenshot is kept in `target/pick-check/`.
//! Also: the three.js files built into the page are those the lock file
//! pins.

use std::path::Path;
use std::process::Command;

use meshmorph::io::read_mesh;
use meshmorph::{Markers, SurfacePoint, VertexNumbering};
use serde_json::Value;

#[path = "../command_line/pick_session.rs"]
mod pick_session;
use pick_session::{height, Pick};

use crate::browser::{chromium, tools, which, Check, Needs};

/// The checks (see `browser.rs`).
pub fn checks() -> Vec<Check> {
    vec![
        (
            "pick_page::the_page_makes_deletes_undoes_saves_and_fits_pairs",
            the_page_makes_deletes_undoes_saves_and_fits_pairs,
            Needs::Chromium,
        ),
        (
            "pick_page::horse_camel_fits_on_the_page_as_correspond_fits",
            horse_camel_fits_on_the_page_as_correspond_fits,
            Needs::ChromiumAndSharedData("dt/horse-camel"),
        ),
        (
            "pick_page::guided_by_the_template_the_landmarks_are_placed_and_previewed",
            guided_by_the_template_the_landmarks_are_placed_and_previewed,
            Needs::Chromium,
        ),
        (
            "pick_page::on_two_pictures_anchors_are_clicked_previewed_and_saved",
            on_two_pictures_anchors_are_clicked_previewed_and_saved,
            Needs::Chromium,
        ),
        (
            "pick_page::the_page_carries_the_pinned_three_js",
            the_page_carries_the_pinned_three_js,
            Needs::Node,
        ),
    ]
}

/// The points clicked: on the source sheet (scale 1) and the target (1.5).
fn points() -> Vec<[[f64; 3]; 2]> {
    [(-0.5, -0.4), (0.45, -0.3), (0.0, 0.5)]
        .iter()
        .map(|&(x, y)| {
            let at = |s: f64| [s * x, s * y, height(s * x, s * y, s)];
            [at(1.0), at(1.5)]
        })
        .collect()
}

fn the_page_makes_deletes_undoes_saves_and_fits_pairs() {
    let dir = tempfile::TempDir::new().unwrap();
    let mut pick = Pick::start(dir.path(), &[]);
    let plan = serde_json::json!({
        "pairs": points(),
        "delete": 1,
        "undo": true,
        "redo": true,
        "mirror": 0,
        "overlay": "pick-overlay.png",
        "drag": { "pair": 1, "side": "source", "to": [0.3, 0.4, height(0.3, 0.4, 1.0)] },
        "save": true,
        "fit": true,
        "screenshot": "pick-page.png",
        "size": [1280, 720],
        "done": true,
    });
    let report = drive(&pick.url, &plan, dir.path());
    assert_eq!(report["after_clicks"], 3, "{report}");
    assert_eq!(report["after_delete"], 2, "{report}");
    assert_eq!(report["after_undo"], 3, "{report}");
    assert_eq!(report["after_redo"], 2, "{report}");
    // The first pair mirrored across both sheets' planes (y = 0): at the
    // mirror images of its points, on the surfaces.
    let mirrored = &report["mirrored"];
    let sheets = [
        read_mesh(&pick.source).unwrap(),
        read_mesh(&pick.target).unwrap(),
    ];
    for (side, key) in ["source", "target"].iter().enumerate() {
        let p = &mirrored[key];
        let at = match (p["vertex"].as_u64(), p["triangle"].as_u64()) {
            (Some(v), _) => SurfacePoint::Vertex(v as u32),
            (None, Some(t)) => SurfacePoint::Triangle {
                triangle: t as u32,
                barycentric: std::array::from_fn(|i| p["barycentric"][i].as_f64().unwrap()),
            },
            _ => panic!("{mirrored}"),
        }
        .position(&sheets[side]);
        let [x, y, z] = points()[0][side];
        let off = ((at[0] - x).powi(2) + (at[1] + y).powi(2) + (at[2] - z).powi(2)).sqrt();
        assert!(
            off < 0.01 * sheets[side].bounding_box_diagonal(),
            "{key}: {at:?} against {:?}",
            [x, -y, z]
        );
    }
    // The second pair's source marker dragged along the sheet ends where
    // it was dropped; undone, it is back.
    let point = |v: &Value| -> [f64; 3] { std::array::from_fn(|i| v[i].as_f64().unwrap()) };
    let near = |a: [f64; 3], b: [f64; 3]| {
        (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
            < 0.01 * sheets[0].bounding_box_diagonal()
    };
    assert!(
        near(point(&report["dragged"]), [0.3, 0.4, height(0.3, 0.4, 1.0)]),
        "{report}"
    );
    assert!(
        near(point(&report["after_drag_undone"]), points()[1][0]),
        "{report}"
    );
    assert_eq!(report["saved"], "3", "{report}");
    assert_eq!(report["fit_state"], "done", "{report}");
    let mean = report["fit"]["fit"]["mean_distance"].as_f64().unwrap();
    assert!(mean.is_finite() && mean >= 0.0, "{report}");
    assert!(
        report["fit_text"]
            .as_str()
            .unwrap()
            .contains("mean distance"),
        "{report}"
    );
    assert!(Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../target/pick-check/pick-page.png")
        .is_file());
    // The file holds the three pairs where they were clicked, as points of
    // triangles (no vertex snapping without Alt).
    let saved = Markers::read(&pick.output, VertexNumbering::FromZero).unwrap();
    let meshes = [
        read_mesh(&pick.source).unwrap(),
        read_mesh(&pick.target).unwrap(),
    ];
    assert_eq!(saved.pairs().len(), 3);
    for (pair, wanted) in saved.pairs().iter().zip(points()) {
        for side in 0..2 {
            assert!(matches!(pair[side], SurfacePoint::Triangle { .. }));
            let at = pair[side].position(&meshes[side]);
            let off = (0..3)
                .map(|i| (at[i] - wanted[side][i]).powi(2))
                .sum::<f64>()
                .sqrt();
            let tolerance = 0.01 * meshes[side].bounding_box_diagonal();
            assert!(
                off < tolerance,
                "side {side}: {at:?} is {off} from {:?}",
                wanted[side]
            );
        }
    }
    assert!(pick.wait().success(), "pick did not stop on done");
}

/// Runs `pick.mjs` on the page at `url` with `plan`, keeping its
/// screenshots in `target/pick-check/`; the page's report.
/// Waits for `meshmorph pick` to end after the page said "done": within a
/// minute, else it is ended and the test fails (instead of waiting for
/// ever).
fn ends_after_done(child: &mut std::process::Child) {
    let start = std::time::Instant::now();
    while start.elapsed() < std::time::Duration::from_secs(60) {
        if let Some(status) = child.try_wait().unwrap() {
            assert!(status.success(), "meshmorph pick ended with {status}");
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let _ = child.kill();
    let _ = child.wait();
    panic!("meshmorph pick did not end within a minute of the page's \"done\"");
}

/// `meshmorph pick ARGS`, and the page's address from its first line.
fn spawn_pick(args: &[&std::ffi::OsStr]) -> (std::process::Child, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .arg("pick")
        .args(args)
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    std::io::BufRead::read_line(
        &mut std::io::BufReader::new(child.stdout.as_mut().unwrap()),
        &mut line,
    )
    .unwrap();
    let url = line
        .split_whitespace()
        .find(|w| w.starts_with("http://"))
        .unwrap()
        .to_string();
    (child, url)
}

fn drive(url: &str, plan: &Value, dir: &Path) -> Value {
    drive_with("pick.mjs", url, plan, dir)
}

/// Runs `script` (in `tools/browser-checks`) on the page at `url` with
/// `plan`; its one line of JSON.
fn drive_with(script: &str, url: &str, plan: &Value, dir: &Path) -> Value {
    let artifacts = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/pick-check");
    let plan_path = dir.join("plan.json");
    std::fs::write(&plan_path, plan.to_string()).unwrap();
    let out = Command::new("node")
        .arg(tools().join(script))
        .arg(url)
        .arg(&artifacts)
        .arg(&plan_path)
        .arg("--chromium")
        .arg(which(&chromium()))
        .output()
        .expect("node runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "the page check failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(stdout.trim()).expect("one JSON line")
}

/// `pick A.png B.png --anchors`: the demo's arm sprites and anchors, one
/// anchor clicked on both pictures, one dragged (then undone), one deleted
/// (then undone), a preview of the morph after each change, the anchors
/// saved as `interpolate --anchors` reads them. Its screenshot is kept as
/// `target/pick-check/pick-pictures.png`.
fn on_two_pictures_anchors_are_clicked_previewed_and_saved() {
    let dir = tempfile::TempDir::new().unwrap();
    let anchors = dir.path().join("anchors.txt");
    let mut pick = Pick::start_pictures(dir.path(), &["--anchors", anchors.to_str().unwrap()]);
    let clicked = [[160.0, 160.0], [140.0, 158.0]];
    let plan = serde_json::json!({
        "anchors": [clicked],
        "drag": { "anchor": 5, "side": "b", "to": [134.0, 154.0] },
        "delete": 0,
        "save": true,
        "screenshot": "pick-pictures.png",
        "size": [1280, 640],
        "done": true,
    });
    let report = drive_with("pick-pictures.mjs", &pick.url, &plan, dir.path());
    let point = |v: &Value| [v[0].as_f64().unwrap(), v[1].as_f64().unwrap()];
    let near = |p: [f64; 2], q: [f64; 2], tol: f64| (p[0] - q[0]).hypot(p[1] - q[1]) <= tol;
    assert_eq!(report["start"].as_array().unwrap().len(), 5, "{report}");
    let after = report["after_clicks"].as_array().unwrap();
    assert_eq!(after.len(), 6, "{report}");
    // A click lands within a screen pixel (under a picture pixel here).
    assert!(near(point(&after[5]["a"]), clicked[0], 1.0), "{report}");
    assert!(near(point(&after[5]["b"]), clicked[1], 1.0), "{report}");
    assert!(
        near(point(&report["dragged"]), [134.0, 154.0], 1.0),
        "{report}"
    );
    assert!(
        near(point(&report["drag_undone"]), clicked[1], 1.0),
        "{report}"
    );
    assert_eq!(report["after_delete"], 5, "{report}");
    assert_eq!(report["after_undo"], 6, "{report}");
    // The first preview, one after the click, two for the drag and its
    // undoing, two for the deletion and its undoing.
    assert!(report["previews"].as_u64().unwrap() >= 6, "{report}");
    assert!(report["preview_error"].is_null(), "{report}");
    assert_eq!(report["saved"], "6", "{report}");
    assert!(pick.wait().success());
    let saved = meshmorph::io::read_anchor_file(&pick.output, 2).unwrap();
    assert_eq!(saved.len(), 6);
    let given = meshmorph::io::read_anchor_file(&anchors, 2).unwrap();
    for (s, g) in saved.iter().zip(&given) {
        assert_eq!((&s.name, &s.points), (&g.name, &g.points));
    }
    assert!(near(saved[5].points[0], clicked[0], 1.0) && near(saved[5].points[1], clicked[1], 1.0));
}

/// Horse to camel with the shared 107 markers and a pose: the page's fit
/// reports what `correspond` reports for the same markers, and shows the
/// pose transferred. Its screenshot is the README's picture of the page
/// (`docs/pick.png`, copied from `target/pick-check/pick-horse-camel.png`).
fn horse_camel_fits_on_the_page_as_correspond_fits() {
    let data = crate::needs::shared_data("dt/horse-camel").unwrap();
    let dir = tempfile::TempDir::new().unwrap();
    let (horse, camel, markers, pose) = (
        data.join("horse-poses/horse-reference.obj"),
        data.join("camel-poses/camel-reference.obj"),
        data.join("markers/horse-camel-107.cons"),
        data.join("horse-poses/horse-09.obj"),
    );
    let output = dir.path().join("picked.txt");
    let (mut child, url) = spawn_pick(&[
        horse.as_os_str(),
        camel.as_os_str(),
        "-o".as_ref(),
        output.as_os_str(),
        "--markers".as_ref(),
        markers.as_os_str(),
        "--pose".as_ref(),
        pose.as_os_str(),
    ]);
    let url = url.as_str();
    let plan = serde_json::json!({
        "fit": true, "pose": false, "save": true,
        "screenshot": "pick-horse-camel.png", "size": [1280, 720], "done": true,
    });
    let page = drive(url, &plan, dir.path());
    ends_after_done(&mut child);
    let corr = Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .args(["correspond", "--json", "--source-ref"])
        .arg(&horse)
        .arg("--target-ref")
        .arg(&camel)
        .arg("--markers")
        .arg(&markers)
        .arg("-o")
        .arg(dir.path().join("c.corr"))
        .output()
        .unwrap();
    assert!(corr.status.success());
    let corr: Value = serde_json::from_slice(&corr.stdout).unwrap();
    for key in [
        "mean_distance",
        "distance_95th_percentile",
        "uncovered_area",
        "poor_area",
    ] {
        let (a, b) = (
            page["fit"]["fit"][key].as_f64().unwrap(),
            corr["fit"][key].as_f64().unwrap(),
        );
        assert!(
            (a - b).abs() <= 1e-12,
            "{key}: the page's {a}, correspond's {b}"
        );
    }
    assert_eq!(page["fit"]["matched_pairs"], corr["matched_pairs"]);
    assert_eq!(page["fit"]["pose"], true);
    // Saved from the page, the markers read back as the file's.
    let saved = Markers::read(&output, VertexNumbering::FromZero).unwrap();
    let given = Markers::read(&markers, VertexNumbering::FromZero).unwrap();
    assert_eq!(saved.pairs(), given.pairs());
}

/// The page's three.js is byte for byte the pinned package's.
fn the_page_carries_the_pinned_three_js() {
    let vendored = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/pick/page/vendor");
    let package = tools().join("node_modules/three");
    for (ours, theirs) in [
        ("three.module.js", "build/three.module.js"),
        ("three.core.js", "build/three.core.js"),
        ("OrbitControls.js", "examples/jsm/controls/OrbitControls.js"),
        ("LICENSE", "LICENSE"),
    ] {
        let a = std::fs::read(vendored.join(ours)).unwrap();
        let b = std::fs::read(package.join(theirs)).unwrap();
        assert!(a == b, "{ours} differs from the pinned three's {theirs}: copy it again after changing the version");
    }
}

/// `pick --template arkit` on the template's own head, scaled and moved:
/// the page asks for the recommended landmarks first; each is clicked on
/// the head where the template has it (one skipped at first, asked for
/// again at the end), the fit after the last click previews the shapes,
/// and the saved landmark file puts every landmark where it was clicked
/// and is what `expressions --markers` reads.
fn guided_by_the_template_the_landmarks_are_placed_and_previewed() {
    use meshmorph::{landmark_name, ExpressionTemplate, RECOMMENDED_LANDMARKS};
    let dir = tempfile::TempDir::new().unwrap();
    let t = ExpressionTemplate::arkit();
    let head_mesh = t
        .head
        .with_positions(
            t.head
                .positions()
                .iter()
                .map(|p| [10.0 * p[0] + 1.0, 10.0 * p[1], 10.0 * p[2] - 2.0])
                .collect(),
        )
        .unwrap();
    let head = dir.path().join("head.obj");
    meshmorph::io::write_mesh(&head, &head_mesh, meshmorph::io::Format::Obj).unwrap();
    let output = dir.path().join("head.txt");
    let (mut child, url) = spawn_pick(&[
        "--template".as_ref(),
        "arkit".as_ref(),
        head.as_os_str(),
        "-o".as_ref(),
        output.as_os_str(),
    ]);
    let url = url.as_str();
    let wanted: Vec<(String, [f64; 3])> = RECOMMENDED_LANDMARKS
        .iter()
        .map(|&n| {
            let v = t.landmark(&n.to_string()).unwrap() as usize;
            (landmark_name(n), head_mesh.positions()[v])
        })
        .collect();
    let points: serde_json::Map<String, Value> = wanted
        .iter()
        .map(|(n, p)| (n.clone(), serde_json::json!(p)))
        .collect();
    let plan = serde_json::json!({
        "guided": { "points": points, "skip": "noseTip" },
        "save": true,
        "screenshot": "pick-guided.png", "size": [800, 450], "done": true,
    });
    let page = drive(url, &plan, dir.path());
    ends_after_done(&mut child);
    let asked: Vec<&str> = page["asked"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.as_str().unwrap())
        .collect();
    // The recommended ones first, in order; noseTip again once the others
    // are placed.
    let names: Vec<&str> = wanted.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(asked[..names.len()], names[..], "{page}");
    assert!(asked[names.len()..].contains(&"noseTip"), "{page}");
    assert_eq!(page["fit"]["pose"], true, "{page}");
    assert_eq!(page["saved"], "17", "{page}");
    let placed = meshmorph::read_landmarks(&output, &head_mesh, VertexNumbering::FromZero).unwrap();
    assert_eq!(placed.len(), 17);
    let diagonal = head_mesh.bounding_box_diagonal();
    for (name, p) in &placed {
        let (_, q) = wanted.iter().find(|(n, _)| n == name).unwrap();
        let off = (0..3).map(|i| (p[i] - q[i]).powi(2)).sum::<f64>().sqrt();
        assert!(off < 0.01 * diagonal, "{name}: {p:?} against {q:?}");
    }
}
