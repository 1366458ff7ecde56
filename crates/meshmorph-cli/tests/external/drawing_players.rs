//! A drawing morph in its players (`tools/browser-checks/drawing.mjs`):
//! the Lottie file of `interpolate --lottie` in lottie-web, and the
//! animated SVG of `--animated-svg` in Chromium, from two SVG drawings
//! with a hole each.

use std::process::Command;

use serde_json::Value;

use crate::browser::{chromium, tools, which, Check, Needs};

/// The check (see `browser.rs`).
pub fn checks() -> Vec<Check> {
    vec![(
        "drawing_players::lottie_web_and_chromium_play_a_drawing_morph",
        lottie_web_and_chromium_play_a_drawing_morph,
        Needs::Chromium,
    )]
}

fn lottie_web_and_chromium_play_a_drawing_morph() {
    let dir = tempfile::TempDir::new().unwrap();
    let d = dir.path();
    let svg = |body: &str| {
        format!("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"300\" height=\"200\" viewBox=\"0 0 300 200\">{body}</svg>\n")
    };
    std::fs::write(
        d.join("ring.svg"),
        svg(r##"<path fill="#2266aa" fill-rule="evenodd" d="M50 100 A50 50 0 1 1 150 100 A50 50 0 1 1 50 100 Z M80 100 A20 20 0 1 0 120 100 A20 20 0 1 0 80 100 Z"/>"##),
    )
    .unwrap();
    std::fs::write(
        d.join("frame.svg"),
        svg(r#"<g transform="rotate(120 200 100)"><path fill-rule="evenodd" d="M130 80 H270 V120 H130 Z M150 90 H250 V110 H150 Z"/></g>"#),
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .args([
            "interpolate",
            "ring.svg",
            "frame.svg",
            "-o",
            "frames",
            "--frames",
            "11",
        ])
        .args(["--lottie", "m.json", "--animated-svg", "m.svg"])
        .current_dir(d)
        .output()
        .expect("meshmorph runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = Command::new("node")
        .arg(tools().join("drawing.mjs"))
        .arg(which(&chromium()))
        .arg(d.join("m.json"))
        .arg(d.join("m.svg"))
        .output()
        .expect("node runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value = serde_json::from_str(text.trim()).expect("one JSON object");
    assert_eq!(report["errors"], serde_json::json!([]), "{report}");
    // 11 frames forward, 9 back.
    assert_eq!(report["lottie"]["totalFrames"], 20, "{report}");
    let frames = report["lottie"]["frames"].as_array().unwrap();
    for f in frames {
        assert_eq!(
            (f["paths"].as_u64(), f["fillRule"].as_str()),
            (Some(1), Some("evenodd")),
            "{f}"
        );
        // The outer loop and the hole.
        assert_eq!(f["d"].as_str().unwrap().matches('M').count(), 2, "{f}");
    }
    assert_ne!(frames[0]["d"], frames[1]["d"]);
    // 20 values and the first again, and it plays.
    assert_eq!(report["svg"]["values"], 21, "{report}");
    assert_eq!(report["svg"]["moves"], true, "{report}");
}
