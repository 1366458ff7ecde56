//! `meshmorph pick A.png B.png`: the page for two pictures behind the same
//! door as the meshes' page: the token, the pictures, previews of the
//! morph the anchors make, anchors refused naming them, saves as the
//! anchor file `interpolate --anchors` reads, never over an input.

use std::fs;
use std::path::Path;

use meshmorph::io::picture::decode_picture;
use tempfile::TempDir;

use super::pick_session::Pick;

/// The demo's five anchors as the page sends them, plus one inside.
fn anchors_json(dir: &Path) -> String {
    let rows = meshmorph::io::read_anchor_file(&dir.join("anchors.txt"), 2).unwrap();
    let mut list: Vec<serde_json::Value> = rows
        .iter()
        .map(|r| serde_json::json!({ "name": r.name, "a": r.points[0], "b": r.points[1] }))
        .collect();
    list.push(
        serde_json::json!({ "name": "inner_elbow", "a": [160.0, 160.0], "b": [140.0, 158.0] }),
    );
    serde_json::json!({ "anchors": list }).to_string()
}

#[test]
fn the_picture_page_serves_previews_and_saves_anchors_interpolate_reads() {
    let dir = TempDir::new().unwrap();
    let mut pick = Pick::start_pictures(dir.path(), &[]);
    // The page and its files, with the token.
    let (status, html) = pick.page("GET", "/", "");
    assert_eq!(status, 200, "{html}");
    assert!(html.contains("pictures.js"), "{html}");
    let (status, session) = pick.page("GET", "/api/session", "");
    assert_eq!(status, 200, "{session}");
    let session: serde_json::Value = serde_json::from_str(&session).unwrap();
    assert_eq!(session["pictures"][0]["width"], 320, "{session}");
    assert_eq!(session["pictures"][1]["height"], 240, "{session}");
    assert_eq!(session["anchors"].as_array().unwrap().len(), 0, "{session}");
    for side in ["a", "b"] {
        let (status, png) = pick.page_bytes("GET", &format!("/api/picture/{side}"), "");
        assert_eq!(status, 200);
        let picture = decode_picture(&png, Path::new("served.png"), u64::MAX).unwrap();
        assert_eq!((picture.width, picture.height), (320, 240));
    }
    // A preview: 12 frames of 256 × 192 side by side, the first the
    // straight arm and the last the bent one.
    let body = anchors_json(dir.path());
    let (status, png) = pick.page_bytes("POST", "/api/preview", &body);
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&png));
    let sheet = decode_picture(&png, Path::new("preview.png"), u64::MAX).unwrap();
    assert_eq!((sheet.width, sheet.height), (12 * 256, 192));
    let opaque = |x0: u32| {
        (0..192)
            .flat_map(|y| (x0..x0 + 256).map(move |x| (x, y)))
            .filter(|&(x, y)| sheet.pixel(x, y)[3] > 127)
            .collect::<Vec<_>>()
    };
    let (first, last) = (opaque(0), opaque(11 * 256));
    assert!(!first.is_empty() && !last.is_empty());
    // The straight arm's hand is at the right (x near 278 of 320); the
    // bent one's at the upper left (57, 111).
    let scale = 256.0 / 320.0;
    let has = |set: &[(u32, u32)], x0: u32, p: [f64; 2]| {
        set.iter().any(|&(x, y)| {
            ((f64::from(x - x0) - p[0] * scale).powi(2) + (f64::from(y) - p[1] * scale).powi(2))
                .sqrt()
                < 3.0
        })
    };
    assert!(
        has(&first, 0, [270.0, 170.0]),
        "the first frame is not the straight arm"
    );
    assert!(
        !has(&last, 11 * 256, [270.0, 170.0]),
        "the last frame still has the straight arm's hand"
    );
    assert!(
        has(&last, 11 * 256, [57.6, 110.9]),
        "the last frame is not the bent arm"
    );
    // Anchors refused, naming them; the server still answers.
    let bad = [
        (
            r#"{"anchors": [{"name": "hand", "a": [400, 10], "b": [5, 5]}]}"#,
            "anchor 1 (\"hand\"): (400, 10) is outside the first picture (320 × 240 pixels)",
        ),
        (
            r#"{"anchors": [{"a": [1, 1], "b": [1, 1]}, {"name": "x y", "a": [1, 1], "b": [1, 1]}]}"#,
            "anchor 2 (\"x y\"): a name is one word",
        ),
        (
            r#"{"anchors": [{"name": "12", "a": [1, 1], "b": [1, 1]}]}"#,
            "not a number",
        ),
        (
            r#"{"anchors": [{"name": "e", "a": [1, 1], "b": [1, 1]}, {"name": "e", "a": [2, 2], "b": [2, 2]}]}"#,
            "anchor 2 (\"e\"): the name is given twice",
        ),
        (
            r#"{"anchors": [{"name": "e", "a": [1, 1], "b": [1, -1]}]}"#,
            "outside the second picture",
        ),
        (
            r#"{"anchors": [{"name": "e", "a": [1, 1]}]}"#,
            "not understood",
        ),
        (
            r#"{"anchors": [{"name": "e", "a": [1, 1], "b": [1, 1], "c": 2}]}"#,
            "not understood",
        ),
        (
            r#"{"anchors": [{"name": "e", "a": [1e999, 1], "b": [1, 1]}]}"#,
            "not understood",
        ),
        ("[", "not understood"),
    ];
    for (body, expected) in bad {
        for call in ["/api/preview", "/api/save"] {
            let (status, answer) = pick.page("POST", call, body);
            assert_eq!(status, 422, "{call} {body}: {answer}");
            let answer: serde_json::Value = serde_json::from_str(&answer).unwrap();
            let answer = answer["error"].as_str().unwrap_or_default();
            assert!(answer.contains(expected), "{call} {body}: {answer}");
        }
    }
    let many = serde_json::json!({ "anchors": (0..1001).map(|k| serde_json::json!({ "name": format!("a{k}"), "a": [1, 1], "b": [1, 1] })).collect::<Vec<_>>() });
    let (status, answer) = pick.page("POST", "/api/preview", &many.to_string());
    assert_eq!(status, 422);
    assert!(answer.contains("at most 1000"), "{answer}");
    assert!(!pick.output.exists(), "a refused save wrote");
    // Without the token, or from elsewhere: refused.
    let host = format!("127.0.0.1:{}", pick.port);
    for raw in [
        format!("GET /api/picture/a HTTP/1.1\r\nHost: {host}\r\n\r\n"),
        format!("GET /{}/api/picture/a HTTP/1.1\r\nHost: evil.example\r\n\r\n", pick.token),
        format!(
            "POST /{}/api/save HTTP/1.1\r\nHost: {host}\r\nOrigin: http://evil.example\r\nContent-Length: {}\r\n\r\n{body}",
            pick.token,
            body.len()
        ),
    ] {
        assert_eq!(pick.send(raw.as_bytes()).0, 403, "{raw}");
    }
    assert!(!pick.output.exists(), "a refused save wrote");
    // Saved: the file `interpolate --anchors` reads, the anchors as sent.
    let (status, answer) = pick.page("POST", "/api/save", &body);
    assert_eq!(status, 200, "{answer}");
    let saved = meshmorph::io::read_anchor_file(&pick.output, 2).unwrap();
    assert_eq!(saved.len(), 6);
    assert_eq!(saved[5].name, "inner_elbow");
    assert_eq!(saved[5].points, vec![[160.0, 160.0], [140.0, 158.0]]);
    let given = meshmorph::io::read_anchor_file(&dir.path().join("anchors.txt"), 2).unwrap();
    for (s, g) in saved.iter().zip(&given) {
        assert_eq!((&s.name, &s.points), (&g.name, &g.points));
    }
    let (status, _) = pick.page("POST", "/api/done", "{}");
    assert_eq!(status, 200);
    assert!(pick.wait().success());
    // interpolate takes the saved file.
    let frames = dir.path().join("frames");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .arg("interpolate")
        .arg(&pick.source)
        .arg(&pick.target)
        .arg("--anchors")
        .arg(&pick.output)
        .args(["--frames", "3", "-o"])
        .arg(&frames)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(fs::read_dir(&frames).unwrap().count(), 3);
}

#[test]
fn the_picture_page_starts_from_an_anchor_file_and_never_saves_over_an_input() {
    let dir = TempDir::new().unwrap();
    let anchors = dir.path().join("anchors.txt");
    let anchors = anchors.to_str().unwrap();
    let pick = Pick::start_pictures(dir.path(), &["--anchors", anchors]);
    let (status, session) = pick.page("GET", "/api/session", "");
    assert_eq!(status, 200, "{session}");
    let session: serde_json::Value = serde_json::from_str(&session).unwrap();
    assert_eq!(session["anchors"].as_array().unwrap().len(), 5, "{session}");
    assert_eq!(session["anchors"][3]["name"], "forearm", "{session}");
    drop(pick);
    // -o naming an input (a picture or the anchor file): refused before
    // anything is served, the input untouched.
    for input in ["arm-straight.png", "anchors.txt"] {
        let path = dir.path().join(input);
        let before = fs::read(&path).unwrap();
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_meshmorph"))
            .arg("pick")
            .arg(dir.path().join("arm-straight.png"))
            .arg(dir.path().join("arm-bent.png"))
            .arg("--anchors")
            .arg(dir.path().join("anchors.txt"))
            .arg("-o")
            .arg(&path)
            .output()
            .unwrap();
        assert!(!run.status.success());
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(stderr.contains(input), "{stderr}");
        assert_eq!(fs::read(&path).unwrap(), before);
    }
    // An anchor file with a point outside a picture: refused naming it.
    let outside = dir.path().join("outside.txt");
    fs::write(&outside, "hand 500 10 1 1\n").unwrap();
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .arg("pick")
        .arg(dir.path().join("arm-straight.png"))
        .arg(dir.path().join("arm-bent.png"))
        .arg("--anchors")
        .arg(&outside)
        .arg("-o")
        .arg(dir.path().join("out.txt"))
        .output()
        .unwrap();
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.contains("outside.txt")
            && stderr.contains("anchor 1 (\"hand\")")
            && stderr.contains("outside the first picture"),
        "{stderr}"
    );
    assert!(!dir.path().join("out.txt").exists());
}
