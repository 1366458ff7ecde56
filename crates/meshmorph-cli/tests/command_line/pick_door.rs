//! The door of `meshmorph pick`, tested with hostile requests: each refused
//! (or handled) with a 4xx, the server still answering afterwards, nothing
//! read but the files named and nothing written but `-o`.

use std::fs;

use meshmorph::{Markers, VertexNumbering};
use tempfile::TempDir;

use super::pick_session::Pick;

/// Three pairs on the two sheets (a vertex, and points of triangles).
const PAIRS: &str = r#"{"pairs": [
  {"name": "corner", "source": {"vertex": 0}, "target": {"vertex": 0}},
  {"name": "middle", "source": {"triangle": 100, "barycentric": [0.2, 0.3, 0.5]}, "target": {"triangle": 500, "barycentric": [0.6, 0.2, 0.2]}},
  {"source": {"triangle": 400, "barycentric": [1, 0, 0]}, "target": {"vertex": 600}}
]}"#;

fn still_answers(pick: &Pick) {
    let (status, body) = pick.page("GET", "/api/session", "");
    assert_eq!(status, 200, "{body}");
    assert!(body.contains("\"max_markers\""), "{body}");
}

#[test]
fn pick_serves_its_page_meshes_and_session_with_the_token() {
    let dir = TempDir::new().unwrap();
    let pick = Pick::start(dir.path(), &[]);
    for path in [
        "/",
        "/pick.js",
        "/pick.css",
        "/three.module.js",
        "/three.core.js",
        "/OrbitControls.js",
    ] {
        let (status, _) = pick.page("GET", path, "");
        assert_eq!(status, 200, "{path}");
    }
    let (status, body) = pick.page("GET", "/api/mesh/source", "");
    assert_eq!(status, 200);
    // 17 x 17 vertices, 2 x 16 x 16 triangles, as counts then arrays.
    let bytes = body.as_bytes();
    assert!(bytes.len() >= 8);
    assert_eq!(u32::from_le_bytes(bytes[0..4].try_into().unwrap()), 289);
    still_answers(&pick);
}

#[test]
fn pick_refuses_requests_without_the_token_or_from_elsewhere() {
    let dir = TempDir::new().unwrap();
    let pick = Pick::start(dir.path(), &[]);
    let host = format!("127.0.0.1:{}", pick.port);
    let t = &pick.token;
    let cases: Vec<(String, u16, &str)> = vec![
        (format!("GET / HTTP/1.1\r\nHost: {host}\r\n\r\n"), 403, "no token"),
        (format!("GET /api/session HTTP/1.1\r\nHost: {host}\r\n\r\n"), 403, "no token"),
        (
            format!("GET /{}/ HTTP/1.1\r\nHost: {host}\r\n\r\n", "0".repeat(32)),
            403,
            "wrong token",
        ),
        (
            format!("GET /{}/api/session HTTP/1.1\r\nHost: {host}\r\n\r\n", &t[..31]),
            403,
            "a token one short",
        ),
        (
            format!("GET /{t}/ HTTP/1.1\r\nHost: evil.example:{}\r\n\r\n", pick.port),
            403,
            "a foreign Host (DNS rebinding)",
        ),
        (format!("GET /{t}/ HTTP/1.1\r\n\r\n"), 403, "no Host"),
        (
            format!("GET /{t}/ HTTP/1.1\r\nHost: 127.0.0.1:1\r\n\r\n"),
            403,
            "another port",
        ),
        (
            format!(
                "POST /{t}/api/save HTTP/1.1\r\nHost: {host}\r\nOrigin: http://evil.example\r\nContent-Length: {}\r\n\r\n{PAIRS}",
                PAIRS.len()
            ),
            403,
            "a foreign Origin on a write",
        ),
        (
            format!(
                "POST /{t}/api/done HTTP/1.1\r\nHost: {host}\r\nOrigin: http://127.0.0.1.evil.example:{}\r\nContent-Length: 2\r\n\r\n{{}}",
                pick.port
            ),
            403,
            "an Origin that starts like ours",
        ),
        (format!("GET /{t}/../../etc/passwd HTTP/1.1\r\nHost: {host}\r\n\r\n"), 404, "a path outside"),
        (format!("GET /{t}/vendor/LICENSE HTTP/1.1\r\nHost: {host}\r\n\r\n"), 404, "a file beside the page's"),
        (
            format!("GET /{t}/%2e%2e/Cargo.toml HTTP/1.1\r\nHost: {host}\r\n\r\n"),
            404,
            "an escaped path",
        ),
        (format!("GET /{t}/api/nothing HTTP/1.1\r\nHost: {host}\r\n\r\n"), 404, "no such call"),
        (format!("DELETE /{t}/api/save HTTP/1.1\r\nHost: {host}\r\n\r\n"), 405, "a wrong method"),
        (format!("POST /{t}/pick.js HTTP/1.1\r\nHost: {host}\r\nContent-Length: 0\r\n\r\n"), 405, "a write to a file"),
        (
            format!("POST /{t}/api/save HTTP/1.1\r\nHost: {host}\r\nContent-Length: 99999999\r\n\r\n"),
            413,
            "an oversized body",
        ),
        (
            format!("POST /{t}/api/save HTTP/1.1\r\nHost: {host}\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\n"),
            411,
            "a chunked body",
        ),
        (
            format!("GET /{t}/ HTTP/1.1\r\nHost: {host}\r\nX-Long: {}\r\n\r\n", "a".repeat(40_000)),
            431,
            "headers too long",
        ),
        ("garbage\r\n\r\n".to_string(), 400, "no request line"),
        (format!("GET /{t}/ SPDY/3\r\nHost: {host}\r\n\r\n"), 505, "another protocol"),
        (
            format!("POST /{t}/api/save HTTP/1.1\r\nHost: {host}\r\nContent-Length: x\r\n\r\n"),
            400,
            "a bad length",
        ),
        (
            format!("POST /{t}/api/save HTTP/1.1\r\nHost: {host}\r\nContent-Length: +2\r\n\r\n{{}}"),
            400,
            "a signed length",
        ),
        (
            format!("GET /{t}/ HTTP/1.1\r\nHost: {host}\r\nOrigin : http://evil.example\r\n\r\n"),
            400,
            "a header name with a space",
        ),
        (
            format!("GET /{t}/ HTTP/1.1\r\nHost: {host}\r\nOrigin: http://{host}\r\nOrigin: http://evil.example\r\n\r\n"),
            400,
            "two Origins",
        ),
        (
            format!("GET /{t}/ HTTP/1.1\r\nHost: {host}\r\nX-A: 1\r\n Origin: http://evil.example\r\n\r\n"),
            400,
            "a folded header",
        ),
        (format!("GET /{t} HTTP/1.1\r\nHost: {host}\r\n\r\n"), 308, "the page without its slash"),
        (format!("GET /{t} HTTP/1.1\r\nHost: evil.example\r\n\r\n"), 403, "the same from elsewhere"),
    ];
    for (raw, expected, what) in cases {
        let (status, body) = pick.send(raw.as_bytes());
        assert_eq!(status, expected, "{what}: {body}");
        still_answers(&pick);
    }
    assert!(!pick.output.exists(), "a refused write wrote");
}

#[test]
fn pick_refuses_malformed_and_bad_markers_naming_them() {
    let dir = TempDir::new().unwrap();
    let pick = Pick::start(dir.path(), &[]);
    let cases = [
        ("{not json", "not a list of marker pairs"),
        (r#"{"pairs": 3}"#, "not a list of marker pairs"),
        (
            r#"{"pairs": [{"source": {"vertex": 0}}]}"#,
            "not a list of marker pairs",
        ),
        (
            r#"{"pairs": [{"source": {"vertex": 0}, "target": {"vertex": 99999}}]}"#,
            "99999",
        ),
        (
            r#"{"pairs": [{"source": {"triangle": 99999, "barycentric": [1, 0, 0]}, "target": {"vertex": 0}}]}"#,
            "99999",
        ),
        (
            r#"{"pairs": [{"source": {"triangle": 3, "barycentric": [0.5, 0.5, 0.5]}, "target": {"vertex": 0}}]}"#,
            "sum",
        ),
        (
            r#"{"pairs": [{"source": {"vertex": 1, "triangle": 3}, "target": {"vertex": 0}}]}"#,
            "neither a vertex nor a triangle",
        ),
    ];
    for (body, says) in cases {
        for call in ["/api/save", "/api/fit", "/api/mirror"] {
            let (status, answer) = pick.page("POST", call, body);
            assert_eq!(status, 422, "{call} {body}: {answer}");
            assert!(answer.contains(says), "{call} {body}: {answer}");
        }
        still_answers(&pick);
    }
    let twice = r#"{"pairs": [
      {"name": "nose", "source": {"vertex": 0}, "target": {"vertex": 0}},
      {"name": "nose", "source": {"vertex": 1}, "target": {"vertex": 1}}]}"#;
    let (status, answer) = pick.page("POST", "/api/save", twice);
    assert_eq!(status, 422);
    assert!(answer.contains("both named"), "{answer}");
    let many = format!(
        r#"{{"pairs": [{}]}}"#,
        vec![r#"{"source": {"vertex": 0}, "target": {"vertex": 0}}"#; 10_001].join(",")
    );
    let (status, answer) = pick.page("POST", "/api/save", &many);
    assert_eq!(status, 422);
    assert!(answer.contains("at most 10000"), "{answer}");
    assert!(!pick.output.exists());
}

#[test]
fn pick_saves_named_surface_points_fits_and_stops_when_done() {
    let dir = TempDir::new().unwrap();
    let mut pick = Pick::start(dir.path(), &[]);
    // Two pages at once: both served.
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| pick.page("GET", "/api/session", ""));
        let b = s.spawn(|| pick.page("GET", "/api/mesh/target", ""));
        (a.join().unwrap(), b.join().unwrap())
    });
    assert_eq!((a.0, b.0), (200, 200));
    let (status, body) = pick.page("POST", "/api/save", PAIRS);
    assert_eq!(status, 200, "{body}");
    let saved = Markers::read(&pick.output, VertexNumbering::FromZero).unwrap();
    assert_eq!(saved.pairs().len(), 3);
    assert_eq!(saved.name(0), Some("corner"));
    assert_eq!(saved.name(1), Some("middle"));
    assert_eq!(saved.name(2), None);
    let text = fs::read_to_string(&pick.output).unwrap();
    assert!(text.contains("t 100 0.2 0.3 0.5"), "{text}");
    // Saved again: replaced, no staged file left beside it.
    let (status, _) = pick.page("POST", "/api/save", PAIRS);
    assert_eq!(status, 200);
    let names: Vec<String> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 3, "{names:?}");
    // A fit: the report first, then the arrays.
    let (status, body) = pick.page("POST", "/api/fit", PAIRS);
    assert_eq!(status, 200, "{body}");
    assert!(
        body.contains("\"mean_distance\""),
        "{}",
        &body[..body.len().min(400)]
    );
    let (status, body) = pick.page("POST", "/api/done", "{}");
    assert_eq!(status, 200, "{body}");
    assert!(pick.wait().success());
}

#[test]
fn done_during_a_large_save_leaves_the_output_whole_or_absent_and_answers_the_save() {
    // 10,000 pairs: a body of about 1 MB, and a save that takes a while.
    let pairs: Vec<String> = (0..10_000)
        .map(|k| {
            // Twenty points on each source triangle, none twice.
            let a = 0.05 + 0.04 * (k / 512) as f64;
            format!(
                r#"{{"name": "m{k}", "source": {{"triangle": {}, "barycentric": [{a}, 0.1, {}]}}, "target": {{"triangle": {}, "barycentric": [0.6, 0.2, 0.2]}}}}"#,
                k % 512,
                0.9 - a,
                k % 1152
            )
        })
        .collect();
    let body = format!(r#"{{"pairs": [{}]}}"#, pairs.join(", "));
    assert!(body.len() > 1_000_000);
    for delay_ms in [0, 2, 5, 20, 60] {
        let dir = TempDir::new().unwrap();
        let mut pick = Pick::start(dir.path(), &[]);
        // The save under way: connected and its first bytes sent, the rest
        // of its body still coming when "done" is sent.
        let (started, go) = std::sync::mpsc::channel();
        let (save, done) = std::thread::scope(|s| {
            let save = s.spawn(|| pick.page_in_parts("POST", "/api/save", &body, started));
            go.recv().unwrap();
            std::thread::sleep(std::time::Duration::from_millis(delay_ms));
            let done = s.spawn(|| pick.page("POST", "/api/done", "{}"));
            (save.join().unwrap(), done.join().unwrap())
        });
        assert_eq!(done.0, 200, "{}", done.1);
        // The save was answered: written whole, or refused once done.
        match save.0 {
            200 => {
                let saved = Markers::read(&pick.output, VertexNumbering::FromZero).unwrap();
                assert_eq!(saved.pairs().len(), 10_000);
            }
            422 => {
                assert!(save.1.contains("ended"), "{}", save.1);
                assert!(!pick.output.exists());
            }
            other => panic!("save after {delay_ms} ms: {other} {}", save.1),
        }
        assert!(pick.wait().success());
        // Nothing but the two meshes and, maybe, the markers.
        let mut names: Vec<String> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.retain(|n| n != "markers.txt");
        names.sort();
        assert_eq!(names, ["source.obj", "target.obj"], "after {delay_ms} ms");
    }
}

/// A small sheet written to `dir/source.obj`.
fn small_sheet(dir: &std::path::Path) -> std::path::PathBuf {
    let source = dir.join("source.obj");
    meshmorph::io::write_mesh(
        &source,
        &super::pick_session::sheet(4, 1.0),
        meshmorph::io::Format::Obj,
    )
    .unwrap();
    source
}

#[cfg(unix)]
#[test]
fn pick_refuses_an_output_that_is_a_device_or_a_fifo() {
    use std::os::unix::fs::FileTypeExt;
    let dir = TempDir::new().unwrap();
    let source = small_sheet(dir.path());
    let null = dir.path().join("null.txt");
    std::os::unix::fs::symlink("/dev/null", &null).unwrap();
    let fifo = dir.path().join("fifo.txt");
    let mut outputs = vec![(null.clone(), "character device")];
    if std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        outputs.push((fifo, "FIFO"));
    }
    for (output, what) in outputs {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_meshmorph"))
            .arg("pick")
            .args([&source, &source])
            .arg("-o")
            .arg(&output)
            .output()
            .unwrap();
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(what) && err.contains("not a regular file"),
            "{err}"
        );
        assert!(err.contains(&*output.to_string_lossy()), "{err}");
    }
    assert!(fs::symlink_metadata(&null)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
}

#[cfg(unix)]
#[test]
fn open_gives_the_browser_a_private_file_not_the_token() {
    use std::io::BufRead;
    use std::os::unix::fs::PermissionsExt;
    let dir = TempDir::new().unwrap();
    let source = small_sheet(dir.path());
    // A browser opener that notes what it was given and what it read.
    let bin = dir.path().join("bin");
    fs::create_dir(&bin).unwrap();
    let log = dir.path().join("opened.txt");
    let opener = bin.join("xdg-open");
    fs::write(
        &opener,
        format!(
            "#!/bin/sh\necho \"$@\" > {0}.tmp\nstat -c %a \"$1\" >> {0}.tmp\ncat \"$1\" >> {0}.tmp\nmv {0}.tmp {0}\n",
            log.display()
        ),
    )
    .unwrap();
    fs::set_permissions(&opener, fs::Permissions::from_mode(0o755)).unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .args(["pick", "--open", "-o"])
        .arg(dir.path().join("m.txt"))
        .args([&source, &source])
        .env("PATH", path)
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    std::io::BufReader::new(child.stdout.as_mut().unwrap())
        .read_line(&mut line)
        .unwrap();
    let token = line.split('/').nth(3).unwrap().to_string();
    assert_eq!(token.len(), 32, "{line}");
    for _ in 0..600 {
        if log.exists() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let _ = child.kill();
    let _ = child.wait();
    let opened = fs::read_to_string(&log).unwrap();
    let mut lines = opened.lines();
    let argument = lines.next().unwrap();
    assert!(!argument.contains(&token), "{opened}");
    assert!(argument.ends_with("open.html"), "{opened}");
    assert_eq!(lines.next(), Some("600"), "{opened}");
    assert!(opened.contains(&format!("/{token}/")), "{opened}");
}

#[test]
fn pick_never_saves_over_an_input() {
    let dir = TempDir::new().unwrap();
    let source = small_sheet(dir.path());
    let before = fs::read(&source).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .arg("pick")
        .args([&source, &source])
        .arg("-o")
        .arg(&source)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("would overwrite"), "{err}");
    assert_eq!(fs::read(&source).unwrap(), before);
}

#[test]
fn pick_mirrors_a_pair_across_both_planes_of_symmetry() {
    // Both sheets are their own mirror images across y = 0.
    let dir = TempDir::new().unwrap();
    let pick = Pick::start(dir.path(), &[]);
    let (status, session) = pick.page("GET", "/api/session", "");
    assert_eq!(status, 200);
    let session: serde_json::Value = serde_json::from_str(&session).unwrap();
    for plane in session["mirror_planes"].as_array().unwrap() {
        let n = plane["normal"].as_array().unwrap();
        assert!(n[1].as_f64().unwrap().abs() > 0.999, "{plane}");
    }
    // Source vertex (4, 2) and target vertex (6, 3): both at y = -0.75.
    let (s, t) = (2 * 17 + 4, 3 * 25 + 6);
    let body =
        format!(r#"{{"pairs": [{{"source": {{"vertex": {s}}}, "target": {{"vertex": {t}}}}}]}}"#);
    let (status, answer) = pick.page("POST", "/api/mirror", &body);
    assert_eq!(status, 200, "{answer}");
    let answer: serde_json::Value = serde_json::from_str(&answer).unwrap();
    let pair = &answer["pairs"][0];
    // The mirror images are vertices (4, 14) and (6, 21), at y = +0.75.
    assert_eq!(pair["source"]["vertex"], 14 * 17 + 4, "{pair}");
    assert_eq!(pair["target"]["vertex"], 21 * 25 + 6, "{pair}");
}

#[cfg(unix)]
#[test]
fn pick_stops_on_ctrl_c_leaving_nothing() {
    for (signal, status, stderr_closed) in [("-INT", 130, false), ("-TERM", 143, true)] {
        let dir = TempDir::new().unwrap();
        let mut pick = Pick::start(dir.path(), &[]);
        if stderr_closed {
            // `pick ... 2>&1 | head -1`: saying why it stops must not keep it running.
            drop(pick.child.stderr.take());
        }
        still_answers(&pick);
        let killed = std::process::Command::new("kill")
            .args([signal, &pick.child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let stopped = pick.wait();
        assert_eq!(stopped.code(), Some(status), "{signal}: {stopped:?}");
        assert!(!pick.output.exists());
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 2);
    }
}

/// `pick --template arkit HEAD`: the session lists the template's
/// landmarks (the recommended first); a save writes the head's points as a
/// landmark file `expressions --markers` reads; pairs that are not the
/// template's landmarks are refused, naming them; a fit with twelve
/// landmarks previews the expressions.
#[test]
fn pick_with_a_template_saves_landmarks_and_refuses_pairs_that_are_not_its_landmarks() {
    use meshmorph::{landmark_name, ExpressionTemplate, RECOMMENDED_LANDMARKS};
    let dir = tempfile::TempDir::new().unwrap();
    let t = ExpressionTemplate::arkit();
    let head = dir.path().join("head.obj");
    meshmorph::io::write_mesh(&head, &t.head, meshmorph::io::Format::Obj).unwrap();
    let mut pick = Pick::start_guided(dir.path(), "arkit", &head);
    let (status, body) = pick.page("GET", "/api/session", "");
    assert_eq!(status, 200, "{body}");
    let session: serde_json::Value = serde_json::from_str(&body).unwrap();
    let guide = &session["guide"]["landmarks"];
    assert_eq!(guide.as_array().unwrap().len(), 68);
    assert_eq!(guide[0]["name"], "jawRight");
    assert_eq!(guide[1]["name"], "chin");
    let pair = |name: &str, source: u32, target: u32| {
        format!(
            r#"{{"name":"{name}","source":{{"vertex":{source}}},"target":{{"vertex":{target}}}}}"#
        )
    };
    let landmarks: Vec<(String, u32)> = RECOMMENDED_LANDMARKS
        .iter()
        .map(|&n| (landmark_name(n), t.landmark(&n.to_string()).unwrap()))
        .collect();
    let body = |pairs: &[String]| format!(r#"{{"pairs":[{}]}}"#, pairs.join(","));
    // Not a landmark, a wrong template point, no name: refused, naming it.
    for (bad, words) in [
        (pair("earlobe", 0, 0), "earlobe"),
        (pair("chin", 5, 5), "chin"),
        (
            r#"{"source":{"vertex":966},"target":{"vertex":966}}"#.to_string(),
            "name",
        ),
    ] {
        let (status, answer) = pick.page("POST", "/api/save", &body(&[bad]));
        assert_eq!(status, 422, "{answer}");
        assert!(answer.contains(words), "{answer}");
    }
    assert!(!pick.output.exists());
    // Twelve landmarks: the fit previews the expressions.
    let twelve: Vec<String> = landmarks[..12]
        .iter()
        .map(|(n, v)| pair(n, *v, *v))
        .collect();
    let (status, fit) = pick.page("POST", "/api/fit", &body(&twelve));
    assert_eq!(status, 200);
    assert!(
        fit.contains(r#""pose":true"#),
        "{}",
        &fit[..fit.len().min(400)]
    );
    let (status, answer) = pick.page("POST", "/api/save", &body(&twelve));
    assert_eq!(status, 200, "{answer}");
    let read =
        meshmorph::read_landmarks(&pick.output, &t.head, meshmorph::VertexNumbering::FromZero)
            .unwrap();
    assert_eq!(read.len(), 12);
    for ((name, p), (n, v)) in read.iter().zip(&landmarks) {
        assert_eq!(name, n);
        assert_eq!(*p, t.head.positions()[*v as usize]);
    }
    let (status, _) = pick.page("POST", "/api/done", "{}");
    assert_eq!(status, 200);
    assert!(pick.wait().success());
}
