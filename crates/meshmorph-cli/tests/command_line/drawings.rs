//! `meshmorph interpolate` on drawings: SVG files, polygons as text and
//! planar meshes with other triangles, through two and three drawings,
//! with anchors; every output the run asks for, and the refusals.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use meshmorph::io::{parse_svg_drawing, read_mesh, DrawingOptions};
use serde_json::Value;

pub(super) fn run(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the meshmorph binary runs")
}

pub(super) fn succeeds(out: &Output) -> String {
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "stdout:\n{text}\nstderr:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

pub(super) fn fails(out: &Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "stderr:\n{err}");
    assert!(
        err.starts_with("error: ") && !err.contains("panicked"),
        "{err}"
    );
    err
}

pub(super) fn mentions(text: &str, parts: &[&str]) {
    for p in parts {
        assert!(text.contains(p), "`{p}` missing from:\n{text}");
    }
}

fn svg(body: &str) -> String {
    format!("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"100\" viewBox=\"0 0 200 100\">{body}</svg>\n")
}

/// A folder with drawings: a bar (`bar.svg`), the bar turned upright with
/// a curved end (`up.svg`), a disc (`disc.svg`), a tall ellipse (`tall.svg`), a turned box
/// (`box.svg`), two squares with a hole
/// as text (`sq.txt`, `wide.txt`).
fn drawings() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let write = |name: &str, text: String| fs::write(d.join(name), text).unwrap();
    write(
        "bar.svg",
        svg(
            r##"<path d="M20 45 H180 V55 H20 Z" fill="#3366cc" stroke="#000000" stroke-width="1"/><circle id="anchor-tip" cx="180" cy="50" r="1" fill="red"/>"##,
        ),
    );
    write(
        "up.svg",
        svg(
            r##"<g transform="translate(100 50) rotate(-90)"><path d="M-40 -5 H30 Q40 0 30 5 H-40 Z"/></g><circle id="anchor-tip" cx="100" cy="15" r="1" fill="red"/>"##,
        ),
    );
    write(
        "disc.svg",
        svg(r#"<ellipse cx="100" cy="50" rx="40" ry="30"/>"#),
    );
    write(
        "tall.svg",
        svg(r#"<ellipse cx="100" cy="50" rx="15" ry="45"/>"#),
    );
    write(
        "box.svg",
        svg(r#"<rect x="30" y="30" width="140" height="40" transform="rotate(20 100 50)"/>"#),
    );
    write(
        "sq.txt",
        "0 0\n10 0\n10 10\n0 10\n\n3 3\n3 7\n7 7\n7 3\n".into(),
    );
    write(
        "wide.txt",
        "# wide\n0 0\n20 0\n20 5\n0 5\n\n8 1\n8 4\n12 4\n12 1\n".into(),
    );
    dir
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .map(|e| {
            e.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn two_svgs_give_svg_frames_and_every_animation() {
    let dir = drawings();
    let d = dir.path();
    let out = run(
        &[
            "interpolate",
            "bar.svg",
            "up.svg",
            "-o",
            "frames",
            "--frames",
            "5",
            "--gif",
            "m.gif",
            "--animated-svg",
            "m.svg",
            "--lottie",
            "m.json",
            "--meshes",
            "meshes",
            "--json",
        ],
        d,
    );
    let report: Value = serde_json::from_str(succeeds(&out).trim()).unwrap();
    assert_eq!(
        names(&d.join("frames")),
        (0..5)
            .map(|k| format!("frame_000{k}.svg"))
            .collect::<Vec<_>>()
    );
    let dr = &report["drawings"];
    assert_eq!(dr["kinds"], serde_json::json!(["svg", "svg"]));
    assert_eq!(dr["anchors"], 1);
    assert!(dr["tolerance"][1].as_f64().unwrap() > 0.0);
    assert!(dr["min_angle_degrees"][0].as_f64().unwrap() > 0.0);
    assert!(report["setup_seconds"].as_f64().unwrap() > 0.0);
    assert!(report["seconds_per_frame"].as_f64().unwrap() > 0.0);
    assert_eq!(report["max_flipped_triangles"], 0);
    // The ends are the drawings: every frame-0 point on the bar's outline,
    // the first drawing's page and colours kept (the page grown downwards
    // only, to hold the bar, which keeps its length as it turns).
    let f0 = fs::read_to_string(d.join("frames/frame_0000.svg")).unwrap();
    mentions(
        &f0,
        &[
            "width=\"200\" height=\"10",
            "viewBox=\"0 0 200 10",
            "fill=\"#3366cc\"",
            "fill-rule=\"evenodd\"",
        ],
    );
    let back =
        parse_svg_drawing(f0.as_bytes(), Path::new("f0"), &DrawingOptions::default()).unwrap();
    for p in &back.drawing.loops()[0] {
        let on = (p[1] - 45.0).abs() < 1e-3
            || (p[1] - 55.0).abs() < 1e-3
            || (p[0] - 20.0).abs() < 1e-3
            || (p[0] - 180.0).abs() < 1e-3;
        assert!(on, "{p:?} off the bar");
    }
    // Every frame has the same number of points, in one path.
    let count = |k: usize| {
        let t = fs::read_to_string(d.join(format!("frames/frame_000{k}.svg"))).unwrap();
        assert_eq!(t.matches("<path").count(), 1);
        t.split(" d=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap()
            .split(['L', ' '])
            .count()
    };
    assert!((1..5).all(|k| count(k) == count(0)));
    let smil = fs::read_to_string(d.join("m.svg")).unwrap();
    // Forward and back: 5 + 3 values and the first again.
    assert_eq!(
        smil.split("values=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap()
            .split(';')
            .count(),
        9
    );
    let lottie: Value =
        serde_json::from_str(&fs::read_to_string(d.join("m.json")).unwrap()).unwrap();
    assert_eq!(lottie["layers"][0]["ty"], 4);
    let a = read_mesh(&d.join("meshes/bar.obj")).unwrap();
    let b = read_mesh(&d.join("meshes/up.obj")).unwrap();
    assert_eq!(a.triangles(), b.triangles());
    assert!(d.join("m.gif").is_file());
    // The compatible meshes are keys for interpolate as it was.
    succeeds(&run(
        &[
            "interpolate",
            "meshes/bar.obj",
            "meshes/up.obj",
            "-o",
            "again",
            "--frames",
            "3",
        ],
        d,
    ));
}

#[test]
fn three_drawings_and_text_polygons() {
    let dir = drawings();
    let d = dir.path();
    let text = succeeds(&run(
        &[
            "interpolate",
            "box.svg",
            "disc.svg",
            "tall.svg",
            "-o",
            "f",
            "--frames",
            "7",
        ],
        d,
    ));
    mentions(
        &text,
        &[
            "wrote 7 frames",
            "3 keys",
            "drawings:       3",
            "flattened:",
            "smallest angle",
        ],
    );
    let text = succeeds(&run(
        &[
            "interpolate",
            "sq.txt",
            "wide.txt",
            "-o",
            "t",
            "--frames",
            "3",
            "--lottie",
            "t.json",
        ],
        d,
    ));
    mentions(&text, &["1 hole each", "Lottie:"]);
    assert_eq!(
        names(&d.join("t")),
        ["frame_0000.txt", "frame_0001.txt", "frame_0002.txt"]
    );
    // The last frame is the second drawing: its points among the frame's.
    let last = fs::read_to_string(d.join("t/frame_0002.txt")).unwrap();
    for want in ["20 0", "20 5", "8 1", "12 4"] {
        assert!(
            last.lines().filter(|l| !l.is_empty()).any(|l| {
                let v: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
                let w: Vec<f64> = want.split(' ').map(|x| x.parse().unwrap()).collect();
                (v[0] - w[0]).abs() < 1e-9 && (v[1] - w[1]).abs() < 1e-9
            }),
            "{want} not in\n{last}"
        );
    }
}

#[test]
fn anchors_from_a_file() {
    let dir = drawings();
    let d = dir.path();
    fs::write(
        d.join("a.txt"),
        "# name  on sq  on wide\ncorner 10 10 20 5\n",
    )
    .unwrap();
    let text = succeeds(&run(
        &[
            "interpolate",
            "sq.txt",
            "wide.txt",
            "--anchors",
            "a.txt",
            "-o",
            "t",
            "--frames",
            "2",
        ],
        d,
    ));
    mentions(&text, &["anchors:        1 kept matched"]);
    fs::write(d.join("bad.txt"), "corner 10 10 20\n").unwrap();
    let err = fails(&run(
        &[
            "interpolate",
            "sq.txt",
            "wide.txt",
            "--anchors",
            "bad.txt",
            "-o",
            "u",
        ],
        d,
    ));
    mentions(&err, &["`bad.txt`, line 1", "expected 4 numbers"]);
    assert!(!d.join("u").exists());
    // An anchor the drawings refuse is named, with its line, counted from 1.
    fs::write(d.join("far.txt"), "corner 10 10 20 5\nfar 500 500 20 5\n").unwrap();
    let err = fails(&run(
        &[
            "interpolate",
            "sq.txt",
            "wide.txt",
            "--anchors",
            "far.txt",
            "-o",
            "u",
        ],
        d,
    ));
    mentions(
        &err,
        &[
            "anchor 2 (`far`, `far.txt`, line 2)",
            "lies outside drawing 1 (`sq.txt`)",
        ],
    );
    assert!(!d.join("u").exists());
}

/// Writes the compatible meshes of `sq.txt` and `wide.txt` as `m/sq.obj`
/// and `m/wide.obj`.
fn write_compatible_meshes(d: &Path) {
    let args = [
        "interpolate",
        "sq.txt",
        "wide.txt",
        "-o",
        "x",
        "--frames",
        "2",
        "--meshes",
        "m",
    ];
    succeeds(&run(&args, d));
}

#[test]
fn planar_meshes_with_other_triangles_are_drawings() {
    let dir = drawings();
    let d = dir.path();
    write_compatible_meshes(d);
    // Meshes with other triangles (and other vertices): their boundaries.
    fs::copy(d.join("m/sq.obj"), d.join("a.obj")).unwrap();
    let square = meshmorph::Mesh2::new(
        vec![
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 4.0],
            [0.0, 4.0],
            [2.0, 2.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [3.0, 3.0],
            [3.0, 1.0],
        ],
        vec![
            [0, 1, 8],
            [0, 8, 5],
            [1, 2, 7],
            [1, 7, 8],
            [2, 3, 6],
            [2, 6, 7],
            [3, 0, 5],
            [3, 5, 6],
        ],
    )
    .unwrap();
    meshmorph::io::write_mesh(
        &d.join("b.obj"),
        &square.to_3d(),
        meshmorph::io::Format::Obj,
    )
    .unwrap();
    let text = succeeds(&run(
        &["interpolate", "a.obj", "b.obj", "-o", "y", "--frames", "3"],
        d,
    ));
    mentions(&text, &["mesh, mesh", "1 hole each"]);
    assert_eq!(
        names(&d.join("y")),
        ["frame_0000.obj", "frame_0001.obj", "frame_0002.obj"]
    );
}

#[test]
fn refusals_name_the_file_and_leave_nothing() {
    let dir = drawings();
    let d = dir.path();
    let write = |name: &str, body: &str| fs::write(d.join(name), svg(body)).unwrap();
    write(
        "two.svg",
        r#"<rect x="0" y="0" width="10" height="10"/><rect x="50" y="0" width="10" height="10"/>"#,
    );
    write(
        "line.svg",
        r#"<path d="M0 0 L50 50" stroke="black" fill="none"/>"#,
    );
    write(
        "cross.svg",
        r#"<path id="bow" d="M0 0 L50 50 L50 0 L0 50 Z"/>"#,
    );
    write(
        "ring.svg",
        r#"<path fill-rule="evenodd" d="M0 0 H50 V50 H0 Z M10 10 H20 V20 H10 Z"/>"#,
    );
    let cases: [(&[&str], &[&str]); 7] = [
        (
            &["bar.svg", "disc.svg", "up.svg"],
            &["anchor `tip`", "not in `disc.svg`"],
        ),
        (
            &["two.svg", "bar.svg"],
            &["`two.svg`", "2 separate filled regions", "file of its own"],
        ),
        (
            &["bar.svg", "line.svg"],
            &["`line.svg`", "no filled shape", "stroke"],
        ),
        (
            &["cross.svg", "bar.svg"],
            &["`cross.svg`", "crosses itself", "element `bow`"],
        ),
        (
            &["ring.svg", "disc.svg"],
            &["ring.svg", "disc.svg", "holes"],
        ),
        (
            &["bar.svg", "up.svg", "--svg"],
            &["--svg", "SVG drawings already"],
        ),
        (
            &[
                "bar.svg",
                "up.svg",
                "--gif",
                "x.gif",
                "--animated-svg",
                "bar.svg",
            ],
            &["would overwrite", "bar.svg"],
        ),
    ];
    for (args, parts) in cases {
        let mut all = vec!["interpolate"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["-o", "out"]);
        let err = fails(&run(&all, d));
        mentions(&err, parts);
        assert!(!d.join("out").exists(), "{args:?} left out/");
        assert!(!d.join("x.gif").exists());
    }
    // Flags for drawings on meshes with the same triangles.
    write_compatible_meshes(d);
    let err = fails(&run(
        &[
            "interpolate",
            "m/sq.obj",
            "m/wide.obj",
            "-o",
            "y",
            "--lottie",
            "l.json",
        ],
        d,
    ));
    mentions(&err, &["--lottie applies to drawings"]);
    // Flags for pictures on drawings and on meshes: refused, nothing
    // written.
    for (keys, flag) in [
        (["bar.svg", "up.svg"], "--apng"),
        (["bar.svg", "up.svg"], "--sprite-sheet"),
        (["m/sq.obj", "m/wide.obj"], "--apng"),
    ] {
        let err = fails(&run(
            &["interpolate", keys[0], keys[1], "-o", "z", flag, "p.png"],
            d,
        ));
        mentions(&err, &[&format!("{flag} applies to pictures")]);
        assert!(!d.join("z").exists() && !d.join("p.png").exists());
    }
}

#[test]
fn no_output_lands_on_an_input() {
    let dir = drawings();
    let d = dir.path();
    // The compatible meshes written over a drawing's own folder with its
    // name: refused before any work.
    fs::write(d.join("bar.obj"), "v 0 0 0\n").unwrap();
    let frames_over_input: PathBuf = d.join("frames");
    fs::create_dir(&frames_over_input).unwrap();
    fs::copy(d.join("bar.svg"), frames_over_input.join("frame_0000.svg")).unwrap();
    let err = fails(&run(
        &[
            "interpolate",
            "frames/frame_0000.svg",
            "up.svg",
            "-o",
            "frames",
            "--frames",
            "2",
        ],
        d,
    ));
    mentions(&err, &["would overwrite", "frame_0000.svg"]);
    let err = fails(&run(
        &[
            "interpolate",
            "bar.svg",
            "up.svg",
            "-o",
            "f",
            "--meshes",
            ".",
            "--anchors",
            "bar.obj",
        ],
        d,
    ));
    mentions(&err, &["would overwrite", "bar.obj"]);
    assert!(!d.join("f").exists());
}

/// SVG's y points down: `--png` and `--gif` draw a drawing the way up it
/// shows in the SVG (a triangle with its apex at the top stays so).
#[test]
fn pictures_of_svg_drawings_keep_their_way_up() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Apex at the top (small y), base at the bottom; the second is the
    // same triangle moved right.
    for (name, dx) in [("a.svg", 0), ("b.svg", 60)] {
        let body = format!(
            r#"<path d="M{} 10 L{} 90 L{} 90 Z"/>"#,
            50 + dx,
            20 + dx,
            80 + dx
        );
        fs::write(d.join(name), svg(&body)).unwrap();
    }
    let out = run(
        &[
            "interpolate",
            "a.svg",
            "b.svg",
            "-o",
            "f",
            "--frames",
            "3",
            "--png",
            "s.png",
            "--gif",
            "m.gif",
        ],
        d,
    );
    succeeds(&out);
    let still = meshmorph::io::picture::read_picture(&d.join("s.png"), u64::MAX).unwrap();
    // The first panel (a third of the width), below its caption: the ink's
    // rows weighed by how much ink each holds lie below the middle when the
    // wide base is at the bottom.
    let (w, h) = (still.width as usize, still.height as usize);
    let (mut ink, mut weighted_row) = (0.0, 0.0);
    for y in 30..h {
        for x in 0..w / 3 {
            let p = &still.rgba[4 * (y * w + x)..4 * (y * w + x) + 4];
            if p[3] > 0 && (p[0] < 200 || p[1] < 200 || p[2] < 200) {
                ink += 1.0;
                weighted_row += y as f64;
            }
        }
    }
    assert!(ink > 100.0, "no ink in the first panel");
    let mean_row = weighted_row / ink;
    let drawn = |y: f64| (y - 30.0) / (h as f64 - 30.0);
    assert!(
        drawn(mean_row) > 0.5,
        "the ink's mean row is at {:.2} of the panel's height: drawn upside down",
        drawn(mean_row)
    );
}

/// A five-armed star (150 points) and a thin band curling along a spiral
/// (90 points a side), as text: an unlike pair whose fit turns a hundred
/// or more triangles over in its middle frames.
fn star_and_curl(d: &Path) {
    let star: String = (0..150)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 150.0;
            let r = 1.0 + 0.45 * (5.0 * a).cos();
            format!("{:.6} {:.6}\n", r * a.cos(), r * a.sin())
        })
        .collect();
    fs::write(d.join("star.txt"), star).unwrap();
    let centre = |s: f64| {
        let (a, r) = (3.5 * s, 1.6 - 0.9 * s);
        let (x, y) = (r * a.cos(), r * a.sin());
        let (dx, dy) = (-3.5 * y - 0.9 * a.cos(), 3.5 * x - 0.9 * a.sin());
        let l = dx.hypot(dy);
        ([x, y], [-dy / l, dx / l])
    };
    let side = |sign: f64| -> Vec<[f64; 2]> {
        (0..90)
            .map(|i| {
                let (p, n) = centre(i as f64 / 89.0);
                [p[0] + sign * 0.125 * n[0], p[1] + sign * 0.125 * n[1]]
            })
            .collect()
    };
    let mut band = side(-1.0);
    band.extend(side(1.0).into_iter().rev());
    let curl: String = band
        .iter()
        .map(|p| format!("{:.6} {:.6}\n", p[0], p[1]))
        .collect();
    fs::write(d.join("curl.txt"), curl).unwrap();
}

/// The number after `flipped triangles: at most` in a report, 0 for none.
fn most_flipped(report: &str) -> usize {
    let line = report
        .lines()
        .find(|l| l.starts_with("flipped triangles:"))
        .expect("the report counts flipped triangles");
    line.split_whitespace()
        .find_map(|w| w.parse().ok())
        .unwrap_or(0)
}

/// Outlines alone do not show a drawing's inside, and the report says so
/// of the triangles the fit turns over. Pictures show it: its frames are
/// mended where the fit turns triangles over (made once, and read by the
/// frame files, the GIF and the PNG alike), and the outlines written are
/// those of a run with no picture.
#[test]
fn pictures_mend_a_drawings_frames_and_keep_its_outlines() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    star_and_curl(d);
    let out = run(
        &[
            "interpolate",
            "star.txt",
            "curl.txt",
            "-o",
            "plain",
            "--frames",
            "11",
        ],
        d,
    );
    let plain = succeeds(&out);
    // Outlines alone show no triangle: those turned over inside are
    // counted, not warned about.
    assert!(most_flipped(&plain) > 50, "{plain}");
    mentions(&plain, &["none in the outputs, which show the outline"]);
    let warnings = String::from_utf8_lossy(&out.stderr);
    assert!(!warnings.contains("reversed"), "{warnings}");
    let pictured = succeeds(&run(
        &[
            "interpolate",
            "star.txt",
            "curl.txt",
            "-o",
            "pictured",
            "--frames",
            "11",
            "--gif",
            "m.gif",
            "--png",
            "m.png",
        ],
        d,
    ));
    assert_eq!(most_flipped(&pictured), 0, "{pictured}");
    assert!(d.join("m.gif").is_file() && d.join("m.png").is_file());
    let frames = names(&d.join("plain"));
    assert_eq!(frames.len(), 11);
    assert_eq!(frames, names(&d.join("pictured")));
    for f in &frames {
        assert_eq!(
            fs::read(d.join("plain").join(f)).unwrap(),
            fs::read(d.join("pictured").join(f)).unwrap(),
            "{f}"
        );
    }
}
