//! End-to-end tests: run the `meshmorph` binary on small files in temporary
//! directories and check its outputs, its reports and its error messages.
//!
//! The rule for bad input: a clear message naming the file and the element
//! (line, vertex or triangle), a non-zero exit status, no panic, and no
//! partial output (no frame or pose file, no leftover temporary file).

use std::f64::consts::PI;
use std::ffi::OsStr;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use meshmorph::io::{read_mesh, write_mesh, write_positions, Format};
use meshmorph::shapes::{bend, curl, nearest_vertex_pairs, strip, tube};
use meshmorph::{Mesh2, Mesh3};
use serde_json::Value;
use tempfile::TempDir;

// ---------------------------------------------------------------------------
// Helpers.

/// Runs the binary with `args`.
fn run<I, S>(args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .args(args)
        .output()
        .expect("the meshmorph binary runs")
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts a successful run and returns its stdout.
fn succeeds(out: &Output) -> String {
    assert!(
        out.status.success(),
        "expected success, got {:?}\nstdout:\n{}\nstderr:\n{}",
        out.status,
        stdout(out),
        stderr(out)
    );
    stdout(out)
}

/// Asserts a clean failure (non-zero status, no panic) and returns stderr.
fn fails(out: &Output) -> String {
    let err = stderr(out);
    assert!(
        !out.status.success(),
        "expected failure\nstdout:\n{}\nstderr:\n{err}",
        stdout(out)
    );
    assert_eq!(out.status.code(), Some(1), "stderr:\n{err}");
    assert!(!err.contains("panicked"), "panic:\n{err}");
    assert!(err.starts_with("error: "), "stderr:\n{err}");
    err
}

/// Asserts that `text` contains every one of `parts`.
fn assert_mentions(text: &str, parts: &[&str]) {
    for p in parts {
        assert!(text.contains(p), "`{p}` missing from:\n{text}");
    }
}

/// A path as it appears in messages.
fn shown(path: &Path) -> String {
    path.display().to_string()
}

/// The names in `dir` (sorted), or nothing when it does not exist.
fn names(dir: &Path) -> Vec<String> {
    let Ok(entries) = fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut v: Vec<String> = entries
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Asserts that `dir` is missing or empty: no output, no temporary file.
fn assert_empty(dir: &Path) {
    let left = names(dir);
    assert!(left.is_empty(), "{} holds {left:?}", dir.display());
}

/// Parses stdout as exactly one JSON object.
fn json(out: &str) -> Value {
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 1, "expected one line of JSON:\n{out}");
    let v: Value = serde_json::from_str(lines[0]).expect("valid JSON");
    assert!(v.is_object(), "{v}");
    v
}

fn uint(v: &Value, key: &str) -> u64 {
    v[key]
        .as_u64()
        .unwrap_or_else(|| panic!("`{key}` is not an integer in {v}"))
}

fn seconds(v: &Value, key: &str) -> f64 {
    let s = v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("`{key}` is not a number in {v}"));
    assert!(s.is_finite() && s >= 0.0, "{key} = {s}");
    s
}

/// Largest coordinate difference between two position lists of equal length.
fn max_diff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |k| (p[k] - q[k]).abs()))
        .fold(0.0, f64::max)
}

fn read(path: &Path) -> Mesh3 {
    read_mesh(path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()))
}

fn write<const D: usize>(path: &Path, mesh: &meshmorph::Mesh<D>) {
    write_mesh(path, mesh, Format::from_path(path).unwrap()).unwrap();
}

/// Rewrites a text file line by line (1-based line numbers).
fn edit_lines(path: &Path, f: impl FnOnce(&mut Vec<String>)) {
    let mut lines: Vec<String> = fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(str::to_owned)
        .collect();
    f(&mut lines);
    fs::write(path, lines.join("\n") + "\n").unwrap();
}

/// 1-based number of the first line of `path` that starts with `prefix`.
fn line_starting(path: &Path, prefix: &str) -> usize {
    fs::read_to_string(path)
        .unwrap()
        .lines()
        .position(|l| l.starts_with(prefix))
        .expect("such a line")
        + 1
}

// ---------------------------------------------------------------------------
// Help.

#[test]
fn help_lists_commands_and_flags() {
    let top = succeeds(&run(["--help"]));
    assert_mentions(
        &top,
        &["interpolate", "blend", "transfer", "correspond", "demo"],
    );
    let cases: [(&str, &[&str]); 5] = [
        (
            "interpolate",
            &[
                "--output",
                "--frames",
                "--t",
                "--format",
                "--json",
                "--gif",
                "--svg",
                "--allow-flips",
                "--no-consistency",
                "--turns",
                "--stretch",
                "--dim",
                "--png",
                "--gltf",
                "Inputs are never written",
                "files of an earlier run",
            ],
        ),
        (
            "blend",
            &[
                "--shape",
                "--output",
                "--dim",
                "--allow-flips",
                "--png",
                "--gif",
                "--gltf",
                "--json",
            ],
        ),
        (
            "transfer",
            &[
                "--source-ref",
                "--target-ref",
                "--markers",
                "--one-based",
                "--correspondence",
                "--save-correspondence",
                "--output",
                "--format",
                "--json",
                "--pin",
            ],
        ),
        (
            "correspond",
            &[
                "--source-ref",
                "--target-ref",
                "--markers",
                "--output",
                "--deformed-source",
                "--json",
            ],
        ),
        ("demo", &["--output", "--json"]),
    ];
    for (command, flags) in cases {
        let text = succeeds(&run([command, "--help"]));
        assert_mentions(&text, flags);
    }
}

#[test]
fn help_of_shared_options_fits_each_command() {
    // The help as words: clap wraps it at the terminal's width.
    let help = |command: &str| {
        let text = succeeds(&run([command, "--help"]));
        text.split_whitespace().collect::<Vec<_>>().join(" ")
    };
    let correspond = help("correspond");
    assert_mentions(
        &correspond,
        &["--one-based", "the deformed source above the target"],
    );
    assert!(!correspond.contains("--pin"), "{correspond}");
    let transfer = help("transfer");
    assert_mentions(&transfer, &["markers and --pin", "transferred poses below"]);
    let pin = transfer
        .split("--pin <LIST>")
        .nth(1)
        .and_then(|rest| rest.split(" -o, --output").next())
        .unwrap_or_else(|| panic!("no --pin in:\n{transfer}"));
    assert_mentions(pin, &["geometric median"]);
    assert!(!pin.contains("centroid"), "{pin}");
    assert_mentions(
        &help("blend"),
        &["the base, the blend about halfway and the blend"],
    );
}

/// A planar mesh of one triangle, and the same triangle turned and stretched.
fn one_triangle() -> (Mesh2, Mesh2) {
    let a = Mesh2::new(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], vec![[0, 1, 2]]).unwrap();
    let b = Mesh2::new(vec![[0.0, 0.0], [0.0, 2.0], [-1.0, 0.0]], vec![[0, 1, 2]]).unwrap();
    (a, b)
}

#[test]
fn reports_count_one_triangle_in_the_singular() {
    let (a, b) = one_triangle();
    let p = Pair::new(&a, &b);
    let text = succeeds(&p.interpolate(&["--frames", "3"]));
    assert_mentions(
        &text,
        &["wrote 3 frames (3 vertices, 1 triangle, planar, 2 keys)"],
    );
    let out = p.out.join("blend.obj");
    let text = succeeds(&blend(&p.src, &[(&p.tgt, "0.5")], &out, &[]));
    assert_mentions(&text, &["(3 vertices, 1 triangle, 1 shape, planar)"]);
}

// ---------------------------------------------------------------------------
// interpolate: happy paths.

/// A small bar and the same bar curled by half a turn.
fn bar_and_curl() -> (Mesh2, Mesh2) {
    let bar = strip(4.0, 1.0, 8, 2);
    let curled = curl(&bar, PI);
    (bar, curled)
}

/// A temporary directory with `src.obj` and `tgt.obj` written from the meshes.
struct Pair {
    /// Kept for its lifetime: the directory goes when the test ends.
    _dir: TempDir,
    src: PathBuf,
    tgt: PathBuf,
    out: PathBuf,
}

impl Pair {
    fn new(source: &Mesh2, target: &Mesh2) -> Self {
        Self::with_ext(source, target, "obj")
    }

    fn with_ext(source: &Mesh2, target: &Mesh2, ext: &str) -> Self {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in");
        fs::create_dir(&input).unwrap();
        let src = input.join(format!("src.{ext}"));
        let tgt = input.join(format!("tgt.{ext}"));
        write(&src, source);
        write(&tgt, target);
        let out = dir.path().join("out");
        Self {
            _dir: dir,
            src,
            tgt,
            out,
        }
    }

    fn bar() -> Self {
        let (a, b) = bar_and_curl();
        Self::new(&a, &b)
    }

    /// `interpolate SRC TGT -o OUT` followed by `extra`.
    fn interpolate(&self, extra: &[&str]) -> Output {
        let mut args: Vec<&OsStr> = vec![
            "interpolate".as_ref(),
            self.src.as_os_str(),
            self.tgt.as_os_str(),
            "-o".as_ref(),
            self.out.as_os_str(),
        ];
        args.extend(extra.iter().map(OsStr::new));
        run(args)
    }

    /// Runs, expects a clean failure with no output, returns stderr.
    fn interpolate_fails(&self, extra: &[&str]) -> String {
        let err = fails(&self.interpolate(extra));
        assert_empty(&self.out);
        err
    }
}

#[test]
fn interpolate_writes_frames_svgs_gif_and_a_json_report() {
    let (bar, curled) = bar_and_curl();
    let p = Pair::new(&bar, &curled);
    let gif = p.out.join("a.gif");
    let out = p.interpolate(&[
        "--frames",
        "5",
        "--json",
        "--gif",
        gif.to_str().unwrap(),
        "--svg",
    ]);
    let report = json(&succeeds(&out));
    assert_eq!(uint(&report, "frames_written"), 5);
    assert_eq!(uint(&report, "max_flipped_triangles"), 0);
    assert_eq!(uint(&report, "vertices"), bar.num_vertices() as u64);
    assert_eq!(uint(&report, "triangles"), bar.num_triangles() as u64);
    seconds(&report, "setup_seconds");
    seconds(&report, "seconds_per_frame");
    seconds(&report, "total_seconds");

    let mut expected: Vec<String> = (0..5)
        .flat_map(|k| [format!("frame_{k:04}.obj"), format!("frame_{k:04}.svg")])
        .collect();
    expected.push("a.gif".into());
    expected.sort();
    assert_eq!(names(&p.out), expected);
    assert!(fs::read(&gif).unwrap().starts_with(b"GIF89a"));
    let svg = fs::read_to_string(p.out.join("frame_0002.svg")).unwrap();
    assert!(svg.contains("<svg"), "{svg}");

    let first = read(&p.out.join("frame_0000.obj"));
    let last = read(&p.out.join("frame_0004.obj"));
    assert_eq!(first.triangles(), bar.triangles());
    assert_eq!(last.triangles(), bar.triangles());
    assert!(max_diff(first.positions(), bar.to_3d().positions()) < 1e-12);
    assert!(max_diff(last.positions(), curled.to_3d().positions()) < 1e-12);
    // The middle frame is neither end.
    let middle = read(&p.out.join("frame_0002.obj"));
    assert!(max_diff(middle.positions(), bar.to_3d().positions()) > 0.1);
    assert!(max_diff(middle.positions(), curled.to_3d().positions()) > 0.1);
}

#[test]
fn interpolate_explicit_times_in_order_and_extrapolated() {
    let (bar, curled) = bar_and_curl();
    let p = Pair::new(&bar, &curled);
    let report = json(&succeeds(&p.interpolate(&["--t", "0,0.5,1.5", "--json"])));
    assert_eq!(uint(&report, "frames_written"), 3);
    assert_eq!(
        names(&p.out),
        ["frame_0000.obj", "frame_0001.obj", "frame_0002.obj"]
    );
    let frame = |k: usize| read(&p.out.join(format!("frame_{k:04}.obj")));
    assert!(max_diff(frame(0).positions(), bar.to_3d().positions()) < 1e-12);
    // 1.5 goes past the target.
    assert!(max_diff(frame(2).positions(), curled.to_3d().positions()) > 0.1);

    // The same times in the reverse order give the same frames reversed.
    let q = Pair::new(&bar, &curled);
    succeeds(&q.interpolate(&["--t", "1.5,0.5,0"]));
    for k in 0..3 {
        let a = fs::read(p.out.join(format!("frame_{k:04}.obj"))).unwrap();
        let b = fs::read(q.out.join(format!("frame_{:04}.obj", 2 - k))).unwrap();
        assert!(a == b, "frame {k}");
    }
}

#[test]
fn interpolate_format_ply() {
    let (bar, curled) = bar_and_curl();
    let p = Pair::new(&bar, &curled);
    succeeds(&p.interpolate(&["--frames", "3", "--format", "ply"]));
    assert_eq!(
        names(&p.out),
        ["frame_0000.ply", "frame_0001.ply", "frame_0002.ply"]
    );
    let bytes = fs::read(p.out.join("frame_0000.ply")).unwrap();
    assert!(bytes.starts_with(b"ply"));
    let first = read(&p.out.join("frame_0000.ply"));
    assert!(max_diff(first.positions(), bar.to_3d().positions()) < 1e-12);
    let last = read(&p.out.join("frame_0002.ply"));
    assert!(max_diff(last.positions(), curled.to_3d().positions()) < 1e-12);
}

#[test]
fn interpolate_format_follows_the_source() {
    let (bar, curled) = bar_and_curl();
    let p = Pair::with_ext(&bar, &curled, "off");
    succeeds(&p.interpolate(&["--frames", "2"]));
    assert_eq!(names(&p.out), ["frame_0000.off", "frame_0001.off"]);
}

#[test]
fn interpolate_spiral_tears_only_without_consistency() {
    let bar = strip(10.0, 0.5, 100, 4);
    let spiral = curl(&bar, 3.0 * PI);
    let p = Pair::new(&bar, &spiral);
    let report = json(&succeeds(&p.interpolate(&["--frames", "9", "--json"])));
    assert_eq!(uint(&report, "max_flipped_triangles"), 0, "{report}");
    // No frame to name: not frame 0.
    assert!(report["max_flipped_frame"].is_null(), "{report}");

    let q = Pair::new(&bar, &spiral);
    let report = json(&succeeds(&q.interpolate(&[
        "--frames",
        "9",
        "--json",
        "--no-consistency",
    ])));
    assert!(uint(&report, "max_flipped_triangles") > 0, "{report}");
    // The report names a frame strictly inside the animation.
    let frame = uint(&report, "max_flipped_frame");
    assert!(0 < frame && frame < 8, "{report}");
}

// ---------------------------------------------------------------------------
// interpolate: bad input.

#[test]
fn interpolate_malformed_obj_names_file_and_line() {
    let p = Pair::bar();
    edit_lines(&p.src, |l| l[2] = "v 0.5 abc 0".into());
    let err = p.interpolate_fails(&[]);
    assert_mentions(&err, &[&shown(&p.src), "line 3", "`abc` is not a number"]);
}

#[test]
fn interpolate_face_index_out_of_range() {
    let p = Pair::bar();
    let line = line_starting(&p.src, "f ") + 1;
    edit_lines(&p.src, |l| {
        let k = line - 1;
        l[k] = "f 1 2 999".into();
    });
    let err = p.interpolate_fails(&[]);
    assert_mentions(
        &err,
        &[
            &shown(&p.src),
            &format!("line {line}"),
            "999",
            "out of range",
        ],
    );
}

#[test]
fn interpolate_face_repeating_a_vertex() {
    let p = Pair::bar();
    edit_lines(&p.tgt, |l| l.push("f 4 5 4".into()));
    let line = fs::read_to_string(&p.tgt).unwrap().lines().count();
    let err = p.interpolate_fails(&[]);
    assert_mentions(
        &err,
        &[
            &shown(&p.tgt),
            &format!("line {line}"),
            "vertex 4",
            "more than once",
        ],
    );
}

#[test]
fn a_file_that_cannot_be_read_is_named_once_with_its_role() {
    let p = Pair::bar();
    edit_lines(&p.tgt, |l| l[4] = "v 1.0 NaN 0".into());
    let err = p.interpolate_fails(&[]);
    let named = format!("`{}`", shown(&p.tgt));
    assert_mentions(&err, &[&format!("reading key 1 {named}, line 5: ")]);
    assert_eq!(err.matches(&named).count(), 1, "{err}");

    let rig = Rig::new();
    let bad = rig.path("bad.obj");
    fs::copy(&rig.poses[1], &bad).unwrap();
    edit_lines(&bad, |l| l[2] = "v 1.0 NaN 0".into());
    let named = format!("`{}`", shown(&bad));
    let out = rig.path("out");
    let pose = fails(&rig.transfer(
        &out,
        &[os("--markers"), rig.markers.as_os_str()],
        std::slice::from_ref(&bad),
    ));
    let target = fails(&transfer_between(
        [&rig.source_ref, &bad, &rig.markers],
        &out,
        &[],
        &rig.poses,
    ));
    for (err, role) in [(pose, "source pose"), (target, "target reference")] {
        assert_mentions(&err, &[&format!("reading {role} {named}, line 3: ")]);
        assert_eq!(err.matches(&named).count(), 1, "{err}");
    }
    assert_empty(&out);
}

#[test]
fn interpolate_nan_coordinate() {
    let p = Pair::bar();
    edit_lines(&p.src, |l| l[4] = "v 1.0 NaN 0".into());
    let err = p.interpolate_fails(&[]);
    assert_mentions(
        &err,
        &[&shown(&p.src), "line 5", "vertex 5", "not a finite number"],
    );
}

#[test]
fn interpolate_planar_keys_with_other_vertices_are_drawings() {
    // Planar meshes whose vertices and triangles differ: their outlines
    // are made compatible, and the frames are meshes.
    let bar = strip(4.0, 1.0, 8, 2);
    let other = curl(&strip(4.0, 1.0, 9, 2), PI);
    let p = Pair::new(&bar, &other);
    let out = succeeds(&p.interpolate(&["--frames", "3"]));
    assert_mentions(
        &out,
        &["wrote 3 frames", "drawings:", "mesh, mesh", "compatible:"],
    );
    assert_eq!(
        names(&p.out),
        ["frame_0000.obj", "frame_0001.obj", "frame_0002.obj"]
    );
}

#[test]
fn interpolate_accepts_a_face_listed_from_another_corner() {
    let (bar, curled) = bar_and_curl();
    let mut triangles = curled.triangles().to_vec();
    // Same orientation, another starting corner: the same face, read as
    // the source's (with a warning).
    let [a, b, c] = triangles[7];
    triangles[7] = [b, c, a];
    let target = Mesh2::new(curled.positions().to_vec(), triangles).unwrap();
    let p = Pair::new(&bar, &target);
    let out = p.interpolate(&["--frames", "3"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_mentions(
        &stderr,
        &[
            &shown(&p.tgt),
            "1 face lists its corners",
            "read as the same face",
        ],
    );
    // The last frame is the target.
    let last = meshmorph::io::read_mesh(&p.out.join("frame_0002.obj")).unwrap();
    assert!(max_diff(last.positions(), curled.to_3d().positions()) < 1e-9);
}

#[test]
fn interpolate_zero_area_source_triangle() {
    let (bar, curled) = bar_and_curl();
    let mut positions = bar.positions().to_vec();
    // Vertex 1 onto vertex 0: triangle 0 = [0, 1, 10] collapses.
    positions[1] = positions[0];
    let source = Mesh2::new(positions, bar.triangles().to_vec()).unwrap();
    let p = Pair::new(&source, &curled);
    let err = p.interpolate_fails(&[]);
    assert_mentions(
        &err,
        &[
            &shown(&p.src),
            "degenerate",
            "source",
            "face 1 (numbered from 1",
        ],
    );
}

#[test]
fn interpolate_mirrored_target_needs_allow_flips() {
    let (bar, curled) = bar_and_curl();
    let mirrored: Vec<[f64; 2]> = curled.positions().iter().map(|p| [-p[0], p[1]]).collect();
    let target = curled.with_positions(mirrored).unwrap();
    let p = Pair::new(&bar, &target);
    let err = p.interpolate_fails(&[]);
    assert_mentions(
        &err,
        &[
            &shown(&p.tgt),
            &format!("{} triangles reversed", bar.num_triangles()),
            "--allow-flips",
        ],
    );
    let report = json(&succeeds(&p.interpolate(&[
        "--allow-flips",
        "--frames",
        "3",
        "--json",
    ])));
    assert_eq!(uint(&report, "frames_written"), 3);
    assert_eq!(names(&p.out).len(), 3);
}

#[test]
fn interpolate_empty_file_and_file_without_triangles() {
    let p = Pair::bar();
    fs::write(&p.src, "").unwrap();
    let err = p.interpolate_fails(&[]);
    assert_mentions(&err, &[&shown(&p.src), "no triangles"]);

    fs::write(&p.src, "# only vertices\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    let err = p.interpolate_fails(&[]);
    assert_mentions(&err, &[&shown(&p.src), "no triangles", "3 vertices"]);
}

#[test]
fn interpolate_non_planar_mesh_names_the_vertex() {
    let (bar, curled) = bar_and_curl();
    let p = Pair::new(&bar, &curled);
    let mut lifted: Vec<[f64; 3]> = curled.to_3d().positions().to_vec();
    lifted[6][2] = 0.25;
    let target = Mesh3::new(lifted, curled.triangles().to_vec()).unwrap();
    write(&p.tgt, &target);
    let err = p.interpolate_fails(&["--dim", "2"]);
    assert_mentions(
        &err,
        &[&shown(&p.tgt), "not planar", "vertex 6", "z = 0.25"],
    );
}

#[test]
fn interpolate_unknown_extension() {
    let p = Pair::bar();
    let fbx = p.src.with_extension("fbx");
    fs::copy(&p.src, &fbx).unwrap();
    let out = run([
        "interpolate".as_ref(),
        fbx.as_os_str(),
        p.tgt.as_os_str(),
        "-o".as_ref(),
        p.out.as_os_str(),
    ]);
    let err = fails(&out);
    assert_empty(&p.out);
    assert_mentions(&err, &[&shown(&fbx), "unknown format", ".png"]);
}

#[test]
fn interpolate_missing_file() {
    let p = Pair::bar();
    fs::remove_file(&p.tgt).unwrap();
    let err = p.interpolate_fails(&[]);
    assert_mentions(&err, &[&shown(&p.tgt), "key 1"]);
    // The operating system's message once, not repeated by the error chain.
    assert_eq!(err.matches("os error").count(), 1, "{err}");
}

#[test]
fn interpolate_gif_that_cannot_be_written_leaves_no_frames() {
    let p = Pair::bar();
    let blocker = p.out.parent().unwrap().join("blocker");
    fs::write(&blocker, "a file, not a folder").unwrap();
    let gif = blocker.join("a.gif");
    let err = p.interpolate_fails(&["--frames", "3", "--svg", "--gif", gif.to_str().unwrap()]);
    assert_mentions(
        &err,
        &[&shown(&gif), "animation", "is a file, not a folder"],
    );
}

#[test]
fn interpolate_bad_frame_options() {
    let p = Pair::bar();
    let out = p.interpolate(&["--frames", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert_mentions(&stderr(&out), &["--frames", "at least 1 frame"]);
    assert_empty(&p.out);
    // Not a number, like a mistyped option: a usage error.
    for t in ["0,nan", "inf", "0,,1"] {
        let out = p.interpolate(&["--t", t]);
        assert_eq!(out.status.code(), Some(2), "--t {t}");
        assert_mentions(&stderr(&out), &["--t", "not a finite number"]);
        assert_empty(&p.out);
    }
}

// ---------------------------------------------------------------------------
// interpolate: keys, surfaces in space; blend.

/// Three keys of a tube in space: straight, bent by 270 and by 540 degrees.
fn tube_keys(dir: &Path) -> (Vec<PathBuf>, Vec<Mesh3>) {
    let t = tube(4.0, 0.2, 21, 8);
    let meshes = vec![t.clone(), bend(&t, 4.0, 1.5 * PI), bend(&t, 4.0, 3.0 * PI)];
    let paths: Vec<PathBuf> = (0..3).map(|k| dir.join(format!("key{k}.obj"))).collect();
    for (p, m) in paths.iter().zip(&meshes) {
        write(p, m);
    }
    (paths, meshes)
}

/// `interpolate KEYS... -o OUT` followed by `extra`.
fn interpolate_keys(keys: &[PathBuf], out: &Path, extra: &[&str]) -> Output {
    let mut args: Vec<&OsStr> = vec!["interpolate".as_ref()];
    args.extend(keys.iter().map(|p| p.as_os_str()));
    args.extend(["-o".as_ref(), out.as_os_str()]);
    args.extend(extra.iter().map(OsStr::new));
    run(args)
}

#[test]
fn stl_keys_give_stl_frames_that_keep_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (objs, _) = tube_keys(dir.path());
    let keys: Vec<PathBuf> = objs[..2]
        .iter()
        .map(|p| {
            let stl = p.with_extension("stl");
            write_positions(&stl, read(p).positions(), read(p).triangles(), Format::Stl).unwrap();
            stl
        })
        .collect();
    let out = dir.path().join("out");
    let glb = dir.path().join("tube.glb");
    succeeds(&interpolate_keys(
        &keys,
        &out,
        &["--frames", "3", "--gltf", glb.to_str().unwrap()],
    ));
    assert_eq!(
        names(&out),
        ["frame_0000.stl", "frame_0001.stl", "frame_0002.stl"]
    );
    // The first frame is the first key, byte for byte; the last has the
    // last key's corners (its normals are the first key's, turned).
    assert_eq!(
        fs::read(out.join("frame_0000.stl")).unwrap(),
        fs::read(&keys[0]).unwrap()
    );
    let last = read(&out.join("frame_0002.stl"));
    assert!(max_diff(last.positions(), read(&keys[1]).positions()) == 0.0);
    // Flat facets give the GLB three vertices per triangle: its size limit
    // counts them (it counted the mesh's vertices, a sixth of them).
    let bytes = fs::metadata(&glb).unwrap().len() as f64;
    let limit = format!("{}", 0.8 * bytes / 1e6);
    let refused = dir.path().join("refused.glb");
    let err = fails(&interpolate_keys(
        &keys,
        &dir.path().join("refused"),
        &[
            "--frames",
            "3",
            "--gltf",
            refused.to_str().unwrap(),
            "--max-gltf-mb",
            &limit,
        ],
    ));
    assert_mentions(&err, &["would weigh about", "--max-gltf-mb"]);
    assert!(!refused.exists());
}

#[test]
fn interpolate_keys_in_space_pass_through_every_key() {
    let dir = tempfile::tempdir().unwrap();
    let (paths, meshes) = tube_keys(dir.path());
    let out = dir.path().join("out");
    let gif = dir.path().join("tube.gif");
    let png = dir.path().join("tube.png");
    let glb = dir.path().join("tube.glb");
    let report = json(&succeeds(&interpolate_keys(
        &paths,
        &out,
        &[
            "--t",
            "0,0.5,1,1.5,2",
            "--json",
            "--gif",
            gif.to_str().unwrap(),
            "--png",
            png.to_str().unwrap(),
            "--gltf",
            glb.to_str().unwrap(),
        ],
    )));
    assert_eq!(uint(&report, "dimension"), 3);
    assert_eq!(uint(&report, "keys"), 3);
    assert_eq!(uint(&report, "frames_written"), 5);
    assert_eq!(uint(&report, "max_flipped_triangles"), 0);
    assert!(uint(&report, "triangles_with_whole_turns") > 0);
    assert!(seconds(&report, "throughput_seconds_per_frame") > 0.0);
    assert!(seconds(&report, "seconds_per_frame") > 0.0);
    assert!(uint(&report, "threads") >= 1);
    let diagonal = meshes[0].bounding_box_diagonal();
    for (k, key) in [(0, &meshes[0]), (2, &meshes[1]), (4, &meshes[2])] {
        let frame = read(&out.join(format!("frame_{k:04}.obj")));
        let d = max_diff(frame.positions(), key.positions());
        assert!(d < 1e-9 * diagonal, "frame {k}: {d}");
    }
    assert!(fs::read(&gif).unwrap().starts_with(b"GIF89a"));
    assert!(fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    assert!(fs::read(&glb).unwrap().starts_with(b"glTF"));
    // --frames spreads over the whole sequence: 5 frames hit the keys.
    let out5 = dir.path().join("out5");
    succeeds(&interpolate_keys(&paths, &out5, &["--frames", "5"]));
    for k in 0..5 {
        assert_eq!(
            fs::read(out5.join(format!("frame_{k:04}.obj"))).unwrap(),
            fs::read(out.join(format!("frame_{k:04}.obj"))).unwrap(),
            "frame {k}"
        );
    }
    let text = succeeds(&interpolate_keys(&paths, &out5, &["--frames", "3"]));
    assert_mentions(
        &text,
        &[
            "in space, 3 keys",
            "time per frame:",
            "computing, on one thread",
            "throughput:",
            "wall time of all frames / frames",
        ],
    );
}

#[test]
fn interpolate_keys_that_cannot_be_used_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (paths, meshes) = tube_keys(dir.path());
    let out = dir.path().join("out");
    // A key whose triangles differ: the file and the triangle are named.
    let other = dir.path().join("other.obj");
    let mut tris = meshes[1].triangles().to_vec();
    tris.swap(3, 4);
    write(
        &other,
        &Mesh3::new(meshes[1].positions().to_vec(), tris).unwrap(),
    );
    let keys = [paths[0].clone(), paths[1].clone(), other.clone()];
    let err = fails(&interpolate_keys(&keys, &out, &[]));
    assert_mentions(
        &err,
        &[&shown(&other), &shown(&paths[0]), "face 4", "key 2"],
    );
    assert_empty(&out);
    // A key with fewer vertices.
    let short = dir.path().join("short.obj");
    write(&short, &tube(4.0, 0.2, 20, 8));
    let err = fails(&interpolate_keys(
        &[paths[0].clone(), short.clone()],
        &out,
        &[],
    ));
    assert_mentions(&err, &[&shown(&short), "vertices"]);
    assert_empty(&out);
    // --turns has no axis in space, nor in a sequence of planar keys.
    let err = fails(&interpolate_keys(&paths[..2], &out, &["--turns", "1"]));
    assert_mentions(&err, &["--turns", "two planar keys only"]);
    assert_empty(&out);
    // --svg draws planar frames only.
    let err = fails(&interpolate_keys(&paths[..2], &out, &["--svg"]));
    assert_mentions(&err, &["--svg", "planar frames only"]);
    assert_empty(&out);
    // A degenerate triangle in the first key: the file is named.
    let mut p = meshes[0].positions().to_vec();
    p[1] = p[0];
    let flat = dir.path().join("flat.obj");
    write(&flat, &meshes[0].with_positions(p).unwrap());
    let err = fails(&interpolate_keys(
        &[flat.clone(), paths[1].clone()],
        &out,
        &[],
    ));
    assert_mentions(&err, &[&shown(&flat), "degenerate", "faces 1,"]);
    assert_empty(&out);
}

/// A planar sheet, and the same sheet with one vertex pushed past its
/// neighbour: in space, the triangles between them are folded back.
fn sheet_and_fold(dir: &Path) -> [PathBuf; 2] {
    let sheet = strip(4.0, 1.0, 8, 4);
    let mut p = sheet.positions().to_vec();
    p[2 * 9 + 4][0] += 0.8;
    let folded = sheet.with_positions(p).unwrap();
    let paths = [dir.join("sheet.obj"), dir.join("folded.obj")];
    write(&paths[0], &sheet);
    write(&paths[1], &folded);
    paths
}

#[test]
fn interpolate_a_key_turned_over_in_space_needs_allow_flips() {
    let dir = tempfile::tempdir().unwrap();
    let paths = sheet_and_fold(dir.path());
    let out = dir.path().join("out");
    let err = fails(&interpolate_keys(&paths, &out, &["--dim", "3"]));
    assert_mentions(&err, &[&shown(&paths[1]), "turned over", "--allow-flips"]);
    assert_empty(&out);
    let report = json(&succeeds(&interpolate_keys(
        &paths,
        &out,
        &["--dim", "3", "--allow-flips", "--frames", "3", "--json"],
    )));
    assert_eq!(uint(&report, "dimension"), 3);
    assert!(uint(&report, "max_flipped_triangles") > 0);
}

#[test]
fn interpolate_planar_keys_through_a_sequence() {
    let (bar, curled) = bar_and_curl();
    let halfway = Mesh2::new(
        meshmorph::Interpolator::new(&bar, &curled, &Default::default())
            .unwrap()
            .at(0.5),
        bar.triangles().to_vec(),
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let paths: Vec<PathBuf> = (0..3)
        .map(|k| dir.path().join(format!("k{k}.obj")))
        .collect();
    for (p, m) in paths.iter().zip([&bar, &halfway, &curled]) {
        write(p, m);
    }
    let out = dir.path().join("out");
    let svg_gif = dir.path().join("a.gif");
    let report = json(&succeeds(&interpolate_keys(
        &paths,
        &out,
        &[
            "--t",
            "0,1,2",
            "--svg",
            "--gif",
            svg_gif.to_str().unwrap(),
            "--json",
        ],
    )));
    assert_eq!(uint(&report, "dimension"), 2);
    assert_eq!(uint(&report, "keys"), 3);
    for (k, key) in [&bar, &halfway, &curled].into_iter().enumerate() {
        let frame = read(&out.join(format!("frame_{k:04}.obj")));
        assert!(
            max_diff(frame.positions(), key.to_3d().positions()) < 1e-9,
            "key {k}"
        );
        assert!(out.join(format!("frame_{k:04}.svg")).is_file());
    }
    // A sequence has no common number of extra turns.
    let err = fails(&interpolate_keys(
        &paths,
        &dir.path().join("o2"),
        &["--turns", "1"],
    ));
    assert_mentions(&err, &["--turns"]);
}

/// `blend BASE --shape ... -o OUT` with `extra`.
fn blend(base: &Path, shapes: &[(&Path, &str)], out: &Path, extra: &[&str]) -> Output {
    let mut args: Vec<String> = vec!["blend".into(), shown(base)];
    for (p, w) in shapes {
        args.push("--shape".into());
        args.push(format!("{}={w}", p.display()));
    }
    args.extend(["-o".into(), shown(out)]);
    args.extend(extra.iter().map(|s| s.to_string()));
    run(args)
}

#[test]
fn blend_reproduces_a_shape_and_extrapolates() {
    let dir = tempfile::tempdir().unwrap();
    let (paths, meshes) = tube_keys(dir.path());
    let out = dir.path().join("blend.obj");
    let report = json(&succeeds(&blend(
        &paths[0],
        &[(&paths[1], "0"), (&paths[2], "1")],
        &out,
        &["--json"],
    )));
    assert_eq!(uint(&report, "dimension"), 3);
    assert_eq!(uint(&report, "shapes"), 2);
    let diagonal = meshes[0].bounding_box_diagonal();
    assert!(max_diff(read(&out).positions(), meshes[2].positions()) < 1e-9 * diagonal);
    // Negative weights and weights above 1, with every picture.
    let out2 = dir.path().join("b/extra.ply");
    let (png, gif, glb) = (
        dir.path().join("p/b.png"),
        dir.path().join("p/b.gif"),
        dir.path().join("p/b.glb"),
    );
    let report = json(&succeeds(&blend(
        &paths[0],
        &[(&paths[1], "1.4"), (&paths[2], "-0.3")],
        &out2,
        &[
            "--json",
            "--png",
            png.to_str().unwrap(),
            "--gif",
            gif.to_str().unwrap(),
            "--gltf",
            glb.to_str().unwrap(),
        ],
    )));
    assert_eq!(uint(&report, "turned_over_triangles"), 0);
    assert!(read(&out2)
        .positions()
        .iter()
        .all(|p| p.iter().all(|x| x.is_finite())));
    assert!(fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    assert!(fs::read(&gif).unwrap().starts_with(b"GIF89a"));
    assert!(fs::read(&glb).unwrap().starts_with(b"glTF"));
    // Planar: weight 1 reproduces the curled bar.
    let (bar, curled) = bar_and_curl();
    let p = Pair::new(&bar, &curled);
    let flat_out = dir.path().join("flat.obj");
    let report = json(&succeeds(&blend(
        &p.src,
        &[(&p.tgt, "1")],
        &flat_out,
        &["--json"],
    )));
    assert_eq!(uint(&report, "dimension"), 2);
    assert!(max_diff(read(&flat_out).positions(), curled.to_3d().positions()) < 1e-9);
}

#[test]
fn blend_refuses_bad_shapes_and_weights() {
    let dir = tempfile::tempdir().unwrap();
    let (paths, meshes) = tube_keys(dir.path());
    let out = dir.path().join("blend.obj");
    for w in ["nan", "inf", "x"] {
        let o = blend(&paths[0], &[(&paths[1], w)], &out, &[]);
        assert_eq!(o.status.code(), Some(2), "{w}");
        assert_mentions(&stderr(&o), &[w, "not a finite number"]);
    }
    let err = fails(&blend(&paths[0], &[(&paths[1], "0.5")], &paths[1], &[]));
    assert_mentions(
        &err,
        &["would overwrite the blend shape", &shown(&paths[1])],
    );
    let other = dir.path().join("other.obj");
    let mut tris = meshes[1].triangles().to_vec();
    tris.swap(3, 4);
    write(
        &other,
        &Mesh3::new(meshes[1].positions().to_vec(), tris).unwrap(),
    );
    let err = fails(&blend(
        &paths[0],
        &[(&paths[1], "0.5"), (&other, "0.5")],
        &out,
        &[],
    ));
    assert_mentions(&err, &[&shown(&other), "face 4"]);
    assert!(!out.exists());
    let folded = sheet_and_fold(dir.path());
    let err = fails(&blend(
        &folded[0],
        &[(&folded[1], "1")],
        &out,
        &["--dim", "3"],
    ));
    assert_mentions(&err, &[&shown(&folded[1]), "turned over", "--allow-flips"]);
    assert!(!out.exists());
    succeeds(&blend(
        &folded[0],
        &[(&folded[1], "1")],
        &out,
        &["--dim", "3", "--allow-flips"],
    ));
}

/// The key times of a GLB's animation.
fn animation_times(glb: &Path) -> Vec<f32> {
    let file = gltf::Gltf::open(glb).unwrap();
    let blob = file.blob.as_deref().unwrap();
    let animation = file.document.animations().next().expect("an animation");
    let channel = animation.channels().next().unwrap();
    let reader = channel.reader(|_| Some(blob));
    reader.read_inputs().unwrap().collect()
}

/// `blend --fps` sets the frame rate of the GLB's animation (and of the
/// GIF), as `interpolate --fps` does; 25 frames a second without it, as
/// for every command.
#[test]
fn blend_plays_its_animation_at_fps() {
    let dir = tempfile::tempdir().unwrap();
    let (paths, _) = tube_keys(dir.path());
    let out = dir.path().join("blend.obj");
    for (fps, extra) in [(25.0, None), (6.0, Some("6")), (30.0, Some("30"))] {
        let glb = dir.path().join(format!("blend{fps}.glb"));
        let gif = dir.path().join(format!("blend{fps}.gif"));
        let mut args = vec![
            "--gltf",
            glb.to_str().unwrap(),
            "--gif",
            gif.to_str().unwrap(),
        ];
        if let Some(fps) = extra {
            args.extend(["--fps", fps]);
        }
        succeeds(&blend(&paths[0], &[(&paths[1], "1")], &out, &args));
        let times = animation_times(&glb);
        assert!(times.len() >= 2, "{times:?}");
        for (k, t) in times.iter().enumerate() {
            assert!(
                (f64::from(*t) - k as f64 / fps).abs() < 1e-5,
                "{fps}: {times:?}"
            );
        }
        assert!(fs::read(&gif).unwrap().starts_with(b"GIF89a"));
    }
    for fps in ["0", "-1", "nan", "inf", "1e-20", "1e50"] {
        let glb = dir.path().join("refused.glb");
        let o = blend(
            &paths[0],
            &[(&paths[1], "1")],
            &dir.path().join("refused.obj"),
            &["--gltf", glb.to_str().unwrap(), &format!("--fps={fps}")],
        );
        let err = usage_error(&o);
        assert_mentions(&err, &["--fps", "not a frame rate from 0.01 to 1000"]);
        assert!(!glb.exists());
    }
    let help = succeeds(&run(["blend", "--help"]));
    assert_mentions(&help, &["--fps", "glTF animation"]);
}

// ---------------------------------------------------------------------------
// transfer and correspond.

const LENGTH: f64 = 4.0;
const THIN_RINGS: usize = 17;
const THIN_SEGMENTS: usize = 12;

fn thin_tube() -> Mesh3 {
    tube(LENGTH, 0.25, THIN_RINGS, THIN_SEGMENTS)
}

fn thick_tube() -> Mesh3 {
    tube(LENGTH, 0.5, 11, 16)
}

/// Marker pairs as the demo builds them: rings along the thin tube at four
/// angles, each paired with the nearest vertex of the thick tube once the
/// thin one is widened to its radius.
fn marker_pairs(source: &Mesh3, target: &Mesh3) -> Vec<[u32; 2]> {
    let ring = |r: usize, s: usize| (r * THIN_SEGMENTS + s) as u32;
    let chosen: Vec<u32> = [0, 4, 8, 12, 16]
        .iter()
        .flat_map(|&r| [0, 3, 6, 9].map(|s| ring(r, s)))
        .collect();
    let widened: Vec<[f64; 3]> = source
        .positions()
        .iter()
        .map(|p| [p[0], 2.0 * p[1], 2.0 * p[2]])
        .collect();
    nearest_vertex_pairs(&widened, target.positions(), &chosen)
}

fn write_markers(path: &Path, pairs: &[[u32; 2]], offset: u32) {
    let mut text = String::from("# source target\n");
    for [s, t] in pairs {
        text.push_str(&format!("{} {}\n", s + offset, t + offset));
    }
    fs::write(path, text).unwrap();
}

/// Reference meshes, markers and bent poses of the thin tube, in files.
struct Rig {
    dir: TempDir,
    source_ref: PathBuf,
    target_ref: PathBuf,
    markers: PathBuf,
    poses: Vec<PathBuf>,
    target_vertices: usize,
}

impl Rig {
    fn new() -> Self {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in");
        fs::create_dir(&input).unwrap();
        let source = thin_tube();
        let target = thick_tube();
        let source_ref = input.join("thin.obj");
        let target_ref = input.join("thick.obj");
        write(&source_ref, &source);
        write(&target_ref, &target);
        let markers = input.join("markers.txt");
        write_markers(&markers, &marker_pairs(&source, &target), 0);
        let poses = [0.0, 0.3, 0.6]
            .iter()
            .enumerate()
            .map(|(k, &turn)| {
                let path = input.join(format!("bend-{k}.obj"));
                write(&path, &bend(&source, LENGTH, turn * PI));
                path
            })
            .collect();
        Self {
            dir,
            source_ref,
            target_ref,
            markers,
            poses,
            target_vertices: target.num_vertices(),
        }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// `COMMAND --source-ref .. --target-ref .. -o OUT`.
    fn between_references<'a>(&'a self, command: &'a str, out: &'a Path) -> Vec<&'a OsStr> {
        vec![
            command.as_ref(),
            "--source-ref".as_ref(),
            self.source_ref.as_os_str(),
            "--target-ref".as_ref(),
            self.target_ref.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ]
    }

    /// `transfer --source-ref .. --target-ref .. -o OUT EXTRA.. POSES..`.
    fn transfer(&self, out: &Path, extra: &[&OsStr], poses: &[PathBuf]) -> Output {
        let mut args = self.between_references("transfer", out);
        args.extend_from_slice(extra);
        args.extend(poses.iter().map(|p| p.as_os_str()));
        run(args)
    }

    /// `correspond` between the rig's references with its markers, saving
    /// to `corr`, with `extra` options.
    fn correspond(&self, corr: &Path, extra: &[&OsStr]) -> Output {
        let mut args = self.between_references("correspond", corr);
        args.extend(["--markers".as_ref(), self.markers.as_os_str()]);
        args.extend_from_slice(extra);
        run(args)
    }

    /// A transfer with the rig's markers and `extra` options on every pose.
    fn transfer_with_markers(&self, out: &Path, extra: &[&OsStr]) -> Output {
        let mut args: Vec<&OsStr> = vec!["--markers".as_ref(), self.markers.as_os_str()];
        args.extend_from_slice(extra);
        self.transfer(out, &args, &self.poses)
    }

    /// Runs `transfer` with these markers; expects a clean failure with no
    /// output; returns stderr.
    fn transfer_fails_with_markers(&self, markers: &Path) -> String {
        let out = self.path("out");
        let err = fails(&self.transfer(
            &out,
            &["--markers".as_ref(), markers.as_os_str()],
            &self.poses,
        ));
        assert_empty(&out);
        err
    }

    /// The bytes of every pose output in `dir`, by file name.
    fn outputs(&self, dir: &Path) -> Vec<(String, Vec<u8>)> {
        names(dir)
            .into_iter()
            .map(|n| {
                let bytes = fs::read(dir.join(&n)).unwrap();
                (n, bytes)
            })
            .collect()
    }
}

fn os(s: &str) -> &OsStr {
    OsStr::new(s)
}

/// A batch file in the rig's folder: the rig's source and poses, and a
/// target per entry of `targets` (TOML lines of its table), each with the
/// rig's target reference.
fn batch_file(rig: &Rig, name: &str, targets: &[String]) -> PathBuf {
    let entries: Vec<String> = targets
        .iter()
        .map(|t| format!("reference = {:?}\n{t}", rig.target_ref.to_str().unwrap()))
        .collect();
    batch_file_of(rig, name, &entries)
}

/// A batch file in the rig's folder: the rig's source and poses, and a
/// target per entry of `targets` (the whole TOML of its table).
fn batch_file_of(rig: &Rig, name: &str, targets: &[String]) -> PathBuf {
    let quoted = |p: &Path| format!("{:?}", p.to_str().unwrap());
    let mut text = format!(
        "source = {}\nposes = [{}]\n",
        quoted(&rig.source_ref),
        rig.poses
            .iter()
            .map(|p| quoted(p))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for t in targets {
        text += &format!("\n[[targets]]\n{t}\n");
    }
    let path = rig.path(name);
    fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_batch_with_a_bad_marker_file_writes_the_other_targets_and_names_it() {
    let rig = Rig::new();
    let bad = rig.path("bad-markers.txt");
    fs::write(&bad, "0 0\n1 999999\n").unwrap();
    let target = |markers: &Path, out: &str| {
        format!(
            "markers = {:?}\noutput = {out:?}",
            markers.to_str().unwrap()
        )
    };
    let batch = batch_file(
        &rig,
        "batch.toml",
        &[
            target(&rig.markers, "a"),
            target(&bad, "b"),
            target(&rig.markers, "c"),
        ],
    );
    let out = run([os("transfer"), os("--batch"), batch.as_os_str()]);
    let err = fails(&out);
    assert_mentions(
        &err,
        &["target 1 of", "bad-markers.txt", "1 of 3 targets failed"],
    );
    assert!(
        stdout(&out).contains("batch: 2 of 3 targets written, 6 shapes"),
        "{}",
        stdout(&out)
    );
    assert_eq!(names(&rig.path("a")).len(), 3);
    assert_eq!(names(&rig.path("c")).len(), 3);
    assert!(!rig.path("b").exists() || names(&rig.path("b")).is_empty());
    // The good targets are what the single command writes.
    let single = rig.path("single");
    succeeds(&rig.transfer_with_markers(&single, &[]));
    assert_eq!(rig.outputs(&rig.path("a")), rig.outputs(&single));
}

#[test]
fn a_batch_reusing_its_saved_correspondence_writes_the_same_bytes() {
    let rig = Rig::new();
    let corr = rig.path("kept.corr");
    let first = batch_file(
        &rig,
        "first.toml",
        &[format!(
            "markers = {:?}\nsave_correspondence = {:?}\noutput = \"fitted\"",
            rig.markers.to_str().unwrap(),
            corr.to_str().unwrap()
        )],
    );
    let report = succeeds(&run([
        os("transfer"),
        os("--json"),
        os("--batch"),
        first.as_os_str(),
    ]));
    let totals = json(report.lines().last().unwrap());
    assert_eq!(uint(&totals, "shapes_written"), 3);
    assert!(
        seconds(&totals, "correspondence_seconds") > 0.0
            && seconds(&totals, "transfer_seconds") > 0.0
    );
    assert!(corr.exists());
    // The same batch as JSON, from the saved correspondence.
    let again = rig.path("again.json");
    let quoted = |p: &Path| serde_json::Value::from(p.to_str().unwrap());
    fs::write(
        &again,
        serde_json::json!({
            "source": quoted(&rig.source_ref),
            "poses": rig.poses.iter().map(|p| quoted(p)).collect::<Vec<_>>(),
            "targets": [{"reference": quoted(&rig.target_ref), "correspondence": "kept.corr", "output": "reused"}],
        })
        .to_string(),
    )
    .unwrap();
    succeeds(&run([os("transfer"), os("--batch"), again.as_os_str()]));
    let fitted = rig.outputs(&rig.path("fitted"));
    assert_eq!(fitted.len(), 3);
    assert_eq!(rig.outputs(&rig.path("reused")), fitted);
}

/// Runs a batch that must be refused before any work: the message names
/// `parts`, and nothing in the rig's folder changed.
fn batch_refused(rig: &Rig, batches: &[&Path], parts: &[&str]) {
    let before = tree(rig.dir.path());
    let mut args = vec![os("transfer")];
    for b in batches {
        args.extend([os("--batch"), b.as_os_str()]);
    }
    let err = fails(&run(args));
    assert_mentions(&err, parts);
    assert_eq!(tree(rig.dir.path()), before, "{err}");
}

/// Every file under `dir` with its bytes (links as their targets).
fn tree(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let meta = fs::symlink_metadata(&path).unwrap();
        if meta.file_type().is_symlink() {
            out.push((
                path.clone(),
                fs::read_link(&path)
                    .unwrap()
                    .into_os_string()
                    .into_encoded_bytes(),
            ));
        } else if meta.is_dir() {
            out.push((path.clone(), Vec::new()));
            out.extend(tree(&path));
        } else {
            out.push((path.clone(), fs::read(&path).unwrap()));
        }
    }
    out.sort();
    out
}

#[test]
fn a_batchs_targets_never_write_over_each_other_or_each_others_inputs() {
    let rig = Rig::new();
    let m = rig.markers.to_str().unwrap();
    // Target 0 keeps its own reference, named like a pose output, in `t0/`.
    fs::create_dir(rig.path("t0")).unwrap();
    let own_ref = rig.path("t0/bend-1.obj");
    fs::copy(&rig.target_ref, &own_ref).unwrap();
    let corr = rig.path("t0/kept.corr");
    succeeds(&rig.correspond(&corr, &[]));
    fs::create_dir(rig.path("x")).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(rig.path("real"), rig.path("linked")).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(rig.path("later"), rig.path("ahead")).unwrap();
    fs::create_dir(rig.path("real")).unwrap();
    let theirs = |rest: &str| format!("reference = {:?}\n{rest}", rig.target_ref.to_str().unwrap());
    let own = |rest: &str| format!("reference = {:?}\n{rest}", own_ref.to_str().unwrap());
    let t0 = own(&format!(
        "correspondence = {:?}\noutput = \"out0\"",
        corr.to_str().unwrap()
    ));
    let other = batch_file_of(&rig, "other.toml", std::slice::from_ref(&t0));
    let (ps, pt) = (rig.path("ps.txt"), rig.path("pt.txt"));
    fs::write(&ps, "0\n1\n2\n").unwrap();
    fs::write(&pt, "0\n1\n2\n").unwrap();
    let (ps, pt) = (ps.to_str().unwrap(), pt.to_str().unwrap());
    // (file name, its targets, what the refusal names), each refused
    // before any work; `other.toml` is given as a batch too.
    let cases: Vec<(&str, Vec<String>, Vec<&str>)> = vec![
        // Target 1's poses into target 0's folder: over its reference.
        (
            "into-reference.toml",
            vec![
                t0.clone(),
                theirs(&format!("markers = {m:?}\noutput = \"t0\"")),
            ],
            vec![
                "target 1 of",
                "target 0 of",
                "would overwrite",
                "bend-1.obj",
            ],
        ),
        // Target 1 saving its correspondence over target 0's.
        (
            "over-correspondence.toml",
            vec![
                t0.clone(),
                theirs(&format!(
                    "markers = {m:?}\nsave_correspondence = \"t0/kept.corr\"\noutput = \"out1\""
                )),
            ],
            vec!["target 1 of", "target 0 of", "kept.corr"],
        ),
        // Two targets, one output folder by two spellings; one GLB.
        (
            "one-folder.toml",
            vec![
                theirs(&format!("markers = {m:?}\noutput = \"out\"")),
                own(&format!("markers = {m:?}\noutput = \"x/../out\"")),
            ],
            vec!["target 0 of", "target 1 of", "are one file"],
        ),
        (
            "one-glb.toml",
            vec![
                theirs(&format!(
                    "markers = {m:?}\ngltf = \"same.glb\"\noutput = \"g0\""
                )),
                own(&format!(
                    "markers = {m:?}\ngltf = \"same.glb\"\noutput = \"g1\""
                )),
            ],
            vec!["target 0 of", "target 1 of", "same.glb"],
        ),
        // An output over the batch file itself, or over another batch's.
        (
            "self.toml",
            vec![theirs(&format!(
                "markers = {m:?}\ngltf = \"self.toml\"\noutput = \"s\""
            ))],
            vec!["would overwrite", "batch file", "self.toml"],
        ),
        (
            "over-other.toml",
            vec![theirs(&format!(
                "markers = {m:?}\ngltf = \"other.toml\"\noutput = \"s\""
            ))],
            vec!["would overwrite", "batch file", "other.toml"],
        ),
        // The same files in other roles: two transfers, one folder.
        (
            "swapped.toml",
            vec![
                theirs(&format!("markers = [{ps:?}, {pt:?}]\noutput = \"sw\"")),
                theirs(&format!("markers = [{pt:?}, {ps:?}]\noutput = \"sw\"")),
            ],
            vec!["target 0 of", "target 1 of", "are one file"],
        ),
        // A target's output folder inside another's pose file.
        (
            "inside.toml",
            vec![
                theirs(&format!("markers = {m:?}\noutput = \"in0\"")),
                own(&format!("markers = {m:?}\noutput = \"in0/bend-0.obj\"")),
            ],
            vec!["target 1 of", "target 0 of", "inside", "bend-0.obj"],
        ),
    ];
    #[cfg(unix)]
    let cases = {
        let mut cases = cases;
        // A link to a folder no run has made yet.
        cases.push((
            "ahead.toml",
            vec![
                theirs(&format!("markers = {m:?}\noutput = \"later\"")),
                own(&format!("markers = {m:?}\noutput = \"ahead\"")),
            ],
            vec!["target 1 of", "ahead", "does not exist"],
        ));
        // One output folder through a link.
        cases.push((
            "linked.toml",
            vec![
                theirs(&format!("markers = {m:?}\noutput = \"real\"")),
                own(&format!("markers = {m:?}\noutput = \"linked\"")),
            ],
            vec!["target 0 of", "target 1 of", "are one file"],
        ));
        cases
    };
    for (name, targets, parts) in cases {
        let b = batch_file_of(&rig, name, &targets);
        batch_refused(&rig, &[&other, &b], &parts);
    }
    // One batch file given twice, by two spellings: each target runs once.
    fs::create_dir(rig.path("sub")).unwrap();
    let again = rig.path("sub/../other.toml");
    let out = run([
        os("transfer"),
        os("--batch"),
        other.as_os_str(),
        os("--batch"),
        again.as_os_str(),
    ]);
    succeeds(&out);
    assert_mentions(&stdout(&out), &["run once", "1 of 1 targets written"]);
    assert_eq!(names(&rig.path("out0")).len(), 3);
    assert_eq!(
        fs::read(&own_ref).unwrap(),
        fs::read(&rig.target_ref).unwrap()
    );
}

#[test]
fn batch_files_are_read_as_regular_files_within_bounds_with_or_without_a_byte_order_mark() {
    let rig = Rig::new();
    #[cfg(unix)]
    {
        let fifo = rig.path("batch.toml");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let err = fails(&run([os("transfer"), os("--batch"), fifo.as_os_str()]));
            assert_mentions(&err, &["batch.toml", "FIFO"]);
        }
        let err = fails(&run([os("transfer"), os("--batch"), os("/dev/zero")]));
        assert_mentions(&err, &["/dev/zero", "character device"]);
    }
    // A sparse file far beyond any batch: refused by its size, unread.
    let huge = rig.path("huge.toml");
    let f = fs::File::create(&huge).unwrap();
    f.set_len(8 << 30).unwrap();
    let err = fails(&run([os("transfer"), os("--batch"), huge.as_os_str()]));
    assert_mentions(&err, &["huge.toml", "a batch file may hold"]);
    // JSON and TOML with a byte-order mark, as some editors write them.
    let quoted = |p: &Path| serde_json::Value::from(p.to_str().unwrap());
    let json_text = serde_json::json!({
        "source": quoted(&rig.source_ref),
        "poses": rig.poses.iter().map(|p| quoted(p)).collect::<Vec<_>>(),
        "targets": [{"reference": quoted(&rig.target_ref), "markers": quoted(&rig.markers), "output": "from-json"}],
    })
    .to_string();
    let bom = rig.path("bom.json");
    fs::write(&bom, format!("\u{feff}{json_text}")).unwrap();
    succeeds(&run([os("transfer"), os("--batch"), bom.as_os_str()]));
    assert_eq!(names(&rig.path("from-json")).len(), 3);
    let toml_bom = batch_file(
        &rig,
        "bom.toml",
        &[format!(
            "markers = {:?}\noutput = \"from-toml\"",
            rig.markers.to_str().unwrap()
        )],
    );
    let text = fs::read_to_string(&toml_bom).unwrap();
    fs::write(&toml_bom, format!("\u{feff}{text}")).unwrap();
    succeeds(&run([os("transfer"), os("--batch"), toml_bom.as_os_str()]));
    assert_eq!(
        rig.outputs(&rig.path("from-toml")),
        rig.outputs(&rig.path("from-json"))
    );
}

#[test]
fn a_batch_file_that_does_not_parse_is_named_before_anything_is_written() {
    let rig = Rig::new();
    let batch = rig.path("broken.toml");
    fs::write(&batch, "source = \"s.obj\"\nposes = [\"p.obj\"]\n[[targets]]\nreference = \"t.obj\"\nmarkers = \"m.txt\"\nouptut = \"o\"\n").unwrap();
    let err = fails(&run([os("transfer"), os("--batch"), batch.as_os_str()]));
    assert_mentions(&err, &["broken.toml", "ouptut"]);
    let twice = batch_file(
        &rig,
        "twice.toml",
        &[
            format!(
                "markers = {:?}\noutput = \"same\"",
                rig.markers.to_str().unwrap()
            ),
            format!(
                "markers = {:?}\noutput = \"same\"",
                rig.markers.to_str().unwrap()
            ),
        ],
    );
    // The same target twice: run once.
    let out = run([os("transfer"), os("--batch"), twice.as_os_str()]);
    succeeds(&out);
    assert_mentions(
        &stdout(&out),
        &["target 1 of", "run once", "1 of 1 targets written"],
    );
    assert_eq!(names(&rig.path("same")).len(), 3);
    // A usage error (status 2), as clap gives them.
    let mixed = run([
        os("transfer"),
        os("--batch"),
        twice.as_os_str(),
        os("--source-ref"),
        rig.source_ref.as_os_str(),
    ]);
    assert_eq!(mixed.status.code(), Some(2));
    assert_mentions(&stderr(&mixed), &["--batch", "--source-ref"]);
}

#[test]
fn transfer_happy_path_then_reuse_the_saved_correspondence() {
    let rig = Rig::new();
    let out = rig.path("out");
    let corr = rig.path("thin-thick.corr");
    let report = json(&succeeds(&rig.transfer_with_markers(
        &out,
        &[os("--json"), os("--save-correspondence"), corr.as_os_str()],
    )));
    assert_eq!(uint(&report, "poses_written"), 3);
    assert!(uint(&report, "matched_pairs") > 0, "{report}");
    assert_eq!(report["correspondence_loaded"], Value::Bool(false));
    for key in [
        "correspondence_seconds",
        "setup_seconds",
        "seconds_per_pose",
        "seconds_per_pose_with_io",
        "total_seconds",
    ] {
        seconds(&report, key);
    }
    assert_eq!(names(&out), ["bend-0.obj", "bend-1.obj", "bend-2.obj"]);
    let thick = thick_tube();
    for name in names(&out) {
        let mesh = read(&out.join(&name));
        assert_eq!(mesh.num_vertices(), rig.target_vertices, "{name}");
        assert_eq!(mesh.triangles(), thick.triangles(), "{name}");
    }
    // The unbent pose gives back the thick tube, nearly.
    let rest = read(&out.join("bend-0.obj"));
    assert!(max_diff(rest.positions(), thick.positions()) < 0.05);
    // The bent ones bend it: the far end moves off the x axis.
    let bent = read(&out.join("bend-2.obj"));
    let end = bent.positions()[rig.target_vertices - 1];
    assert!(end[1] > 0.5, "{end:?}");

    // Second run from the saved correspondence, without markers.
    assert!(fs::read_to_string(&corr)
        .unwrap()
        .starts_with("meshmorph-correspondence"));
    let again = rig.path("again");
    let report = json(&succeeds(&rig.transfer(
        &again,
        &[os("--json"), os("--correspondence"), corr.as_os_str()],
        &rig.poses,
    )));
    assert_eq!(report["correspondence_loaded"], Value::Bool(true));
    assert_eq!(rig.outputs(&out), rig.outputs(&again));
}

#[test]
fn correspond_writes_the_map_and_the_deformed_source() {
    let rig = Rig::new();
    let corr = rig.path("map.corr");
    let deformed = rig.path("deformed.ply");
    let out = rig.correspond(
        &corr,
        &[os("--deformed-source"), deformed.as_os_str(), os("--json")],
    );
    let report = json(&succeeds(&out));
    let pairs = uint(&report, "matched_pairs");
    assert!(pairs > 0, "{report}");
    seconds(&report, "seconds");
    let text = fs::read_to_string(&corr).unwrap();
    assert!(text.starts_with("meshmorph-correspondence"), "{text}");
    assert!(text.contains(&format!("pairs {pairs}\n")), "{text}");
    let mesh = read(&deformed);
    assert_eq!(mesh.num_vertices(), thin_tube().num_vertices());
    assert_eq!(mesh.triangles(), thin_tube().triangles());
    // Deformed onto the thick tube: about twice as wide as the thin one.
    let radius = mesh
        .positions()
        .iter()
        .map(|p| p[1].hypot(p[2]))
        .fold(0.0, f64::max);
    assert!(radius > 0.4, "{radius}");

    // The map transfers the same as the one computed from the markers.
    let (a, b) = (rig.path("a"), rig.path("b"));
    succeeds(&rig.transfer_with_markers(&a, &[]));
    succeeds(&rig.transfer(&b, &[os("--correspondence"), corr.as_os_str()], &rig.poses));
    assert_eq!(rig.outputs(&a), rig.outputs(&b));
}

/// `transfer --source-ref SOURCE --target-ref TARGET --markers MARKERS -o
/// OUT EXTRA.. POSES..`.
fn transfer_between(
    [source, target, markers]: [&Path; 3],
    out: &Path,
    extra: &[&OsStr],
    poses: &[PathBuf],
) -> Output {
    let mut args: Vec<&OsStr> = vec![
        os("transfer"),
        os("--source-ref"),
        source.as_os_str(),
        os("--target-ref"),
        target.as_os_str(),
        os("--markers"),
        markers.as_os_str(),
        os("-o"),
        out.as_os_str(),
    ];
    args.extend_from_slice(extra);
    args.extend(poses.iter().map(|p| p.as_os_str()));
    run(args)
}

/// `mesh` cut along the boundary between its first and second half of
/// triangles, as files split at UV seams are: the second half's corners
/// that the first half also uses become copies (same position), appended
/// after the other vertices. Returns the cut mesh and, for each copy, the
/// vertex it copies.
fn split_at_seam(mesh: &Mesh3) -> (Mesh3, Vec<u32>) {
    let half = mesh.num_triangles() / 2;
    let mut in_first = vec![false; mesh.num_vertices()];
    for t in &mesh.triangles()[..half] {
        t.iter().for_each(|&v| in_first[v as usize] = true);
    }
    let mut positions = mesh.positions().to_vec();
    let mut copy_of: Vec<u32> = Vec::new();
    let mut copy = std::collections::HashMap::new();
    let mut triangles = mesh.triangles().to_vec();
    for t in &mut triangles[half..] {
        for v in t.iter_mut() {
            if in_first[*v as usize] {
                *v = *copy.entry(*v).or_insert_with(|| {
                    positions.push(mesh.positions()[*v as usize]);
                    copy_of.push(*v);
                    (positions.len() - 1) as u32
                });
            }
        }
    }
    (Mesh3::new(positions, triangles).unwrap(), copy_of)
}

/// Asserts that `cut` (a result on a mesh split by [`split_at_seam`]) has
/// every copy where its vertex is, and is `whole` (the result on the mesh
/// before the split) on the other vertices.
fn assert_welded_result(cut: &Mesh3, copy_of: &[u32], whole: &Mesh3, what: &str) {
    let n = whole.num_vertices();
    for (c, &v) in copy_of.iter().enumerate() {
        assert_eq!(
            cut.positions()[n + c],
            cut.positions()[v as usize],
            "{what}"
        );
    }
    assert!(
        max_diff(whole.positions(), &cut.positions()[..n]) < 1e-6,
        "{what}"
    );
}

#[test]
fn interpolation_of_a_mesh_split_at_seams_does_not_crack() {
    let dir = tempfile::tempdir().unwrap();
    let rest = tube(LENGTH, 0.25, 13, 12);
    let bent = bend(&rest, LENGTH, 0.8 * PI);
    let (split_rest, copy_of) = split_at_seam(&rest);
    let (split_bent, _) = split_at_seam(&bent);
    assert!(copy_of.len() >= 12, "{}", copy_of.len());
    let path = |name: &str| dir.path().join(name);
    write(&path("rest.obj"), &rest);
    write(&path("bent.obj"), &bent);
    write(&path("split-rest.ply"), &split_rest);
    write(&path("split-bent.ply"), &split_bent);
    let frames_with = |a: &str, b: &str, out: &str, extra: &[&str]| {
        let mut args: Vec<std::ffi::OsString> = vec![
            "interpolate".into(),
            path(a).into(),
            path(b).into(),
            "-o".into(),
            path(out).into(),
            "--frames".into(),
            "4".into(),
            "--json".into(),
        ];
        args.extend(extra.iter().map(|e| e.into()));
        json(&succeeds(&run(args)))
    };
    let frames = |a: &str, b: &str, out: &str| frames_with(a, b, out, &[]);
    let whole = frames("rest.obj", "bent.obj", "whole");
    assert_eq!(uint(&whole, "welded_vertices"), 0);
    // With --no-weld the copies stay apart, and the two halves of the cut
    // tube part between the keys.
    let apart = frames_with("split-rest.ply", "split-bent.ply", "apart", &["--no-weld"]);
    assert_eq!(uint(&apart, "welded_vertices"), 0);
    let halfway = read(&path("apart").join("frame_0002.ply"));
    let n = rest.num_vertices();
    let gap = copy_of
        .iter()
        .enumerate()
        .map(|(c, &v)| {
            let (a, b) = (halfway.positions()[n + c], halfway.positions()[v as usize]);
            (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
        })
        .fold(0.0, f64::max);
    assert!(gap > 1e-3, "{gap}");
    let cut = frames("split-rest.ply", "split-bent.ply", "cut");
    assert_eq!(uint(&cut, "welded_vertices"), copy_of.len() as u64);
    assert_eq!(uint(&cut, "vertices"), split_rest.num_vertices() as u64);
    for k in 0..4 {
        assert_welded_result(
            &read(&path("cut").join(format!("frame_{k:04}.ply"))),
            &copy_of,
            &read(&path("whole").join(format!("frame_{k:04}.obj"))),
            &format!("frame {k}"),
        );
    }
}

#[test]
fn transfer_onto_a_target_split_at_seams_does_not_crack() {
    let rig = Rig::new();
    let (split, copy_of) = split_at_seam(&thick_tube());
    let split_ref = rig.path("in/thick-split.ply");
    write(&split_ref, &split);
    let whole = rig.path("whole");
    succeeds(&rig.transfer_with_markers(&whole, &[]));
    let transfer = |source: &Path, poses: &[PathBuf], out: &Path| {
        let files = [source, split_ref.as_path(), rig.markers.as_path()];
        json(&succeeds(&transfer_between(
            files,
            out,
            &[os("--json")],
            poses,
        )))
    };
    let cut = rig.path("cut");
    let report = transfer(&rig.source_ref, &rig.poses, &cut);
    assert_eq!(
        uint(&report, "welded_target_vertices"),
        copy_of.len() as u64
    );
    // A marker given twice, to a vertex and to its copy, is one marker; the
    // correspondence saved names the file's own mesh and is read back.
    let mut pairs = marker_pairs(&thin_tube(), &thick_tube());
    let [s, _] = pairs[0];
    pairs.extend([[s, copy_of[0]], [s, rig.target_vertices as u32]]);
    pairs.remove(0);
    let twice = rig.path("in/twice.txt");
    write_markers(&twice, &pairs, 0);
    let saved = rig.path("split.corr");
    let (first, again) = (rig.path("first"), rig.path("again"));
    succeeds(&transfer_between(
        [&rig.source_ref, &split_ref, &twice],
        &first,
        &[os("--save-correspondence"), saved.as_os_str()],
        &rig.poses,
    ));
    let mut args: Vec<&OsStr> = vec![
        os("transfer"),
        os("--source-ref"),
        rig.source_ref.as_os_str(),
    ];
    args.extend([
        os("--target-ref"),
        split_ref.as_os_str(),
        os("--correspondence"),
        saved.as_os_str(),
    ]);
    args.extend([os("-o"), again.as_os_str()]);
    args.extend(rig.poses.iter().map(|p| p.as_os_str()));
    succeeds(&run(args));
    assert_eq!(rig.outputs(&first), rig.outputs(&again));
    assert!(fs::read_to_string(&saved)
        .unwrap()
        .contains(&format!("target {} ", split.num_vertices())));
    // The source and its poses split as well: the same again.
    let (split_source, source_copies) = split_at_seam(&thin_tube());
    let split_source_ref = rig.path("in/thin-split.obj");
    write(&split_source_ref, &split_source);
    let split_poses: Vec<PathBuf> = rig
        .poses
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let path = rig.path(&format!("in/split-bend-{k}.obj"));
            write(&path, &split_at_seam(&read(p)).0);
            path
        })
        .collect();
    let both = rig.path("both");
    let report = transfer(&split_source_ref, &split_poses, &both);
    assert_eq!(
        uint(&report, "welded_source_vertices"),
        source_copies.len() as u64
    );
    // A vertex and its copy pinned: one pin, held at rest.
    let pinned = rig.path("pinned");
    let (v, copy) = (copy_of[0], rig.target_vertices.to_string());
    let v_text = v.to_string();
    succeeds(&transfer_between(
        [&rig.source_ref, &split_ref, &rig.markers],
        &pinned,
        &[os("--pin"), os(&v_text), os("--pin"), os(&copy)],
        &rig.poses[2..],
    ));
    let held = read(&pinned.join("bend-2.ply"));
    assert_eq!(held.positions()[v as usize], split.positions()[v as usize]);
    assert_eq!(
        held.positions()[rig.target_vertices],
        split.positions()[v as usize]
    );
    for k in 0..rig.poses.len() {
        let whole = read(&whole.join(format!("bend-{k}.obj")));
        for cut in [
            read(&cut.join(format!("bend-{k}.ply"))),
            read(&both.join(format!("split-bend-{k}.ply"))),
        ] {
            assert_welded_result(&cut, &copy_of, &whole, &format!("pose {k}"));
        }
    }
}

#[test]
fn no_align_on_references_that_stand_apart_warns() {
    let rig = Rig::new();
    // As they are the tubes overlap: no warning.
    let report = json(&succeeds(&rig.transfer_with_markers(
        &rig.path("as-is"),
        &[os("--no-align"), os("--json")],
    )));
    assert!(
        !report["warnings"].to_string().contains("stand apart"),
        "{report}"
    );
    // The source moved away: --no-align says so.
    let moved = rig.path("in/moved.obj");
    let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    write(
        &moved,
        &meshmorph::shapes::rigid_motion3(&thin_tube(), identity, [0.0, 20.0, 0.0]),
    );
    let report = json(&succeeds(&transfer_between(
        [&moved, &rig.target_ref, &rig.markers],
        &rig.path("moved-out"),
        &[os("--no-align"), os("--json")],
        &rig.poses[..1],
    )));
    assert_mentions(
        &report["warnings"].to_string(),
        &["--no-align", "stand apart", "leave out --no-align"],
    );
}

#[test]
fn transfer_one_based_markers_match_zero_based() {
    let rig = Rig::new();
    let one = rig.path("one.txt");
    write_markers(&one, &marker_pairs(&thin_tube(), &thick_tube()), 1);
    let (a, b) = (rig.path("a"), rig.path("b"));
    succeeds(&rig.transfer_with_markers(&a, &[]));
    succeeds(&rig.transfer(
        &b,
        &[os("--markers"), one.as_os_str(), os("--one-based")],
        &rig.poses,
    ));
    assert_eq!(names(&a).len(), 3);
    assert_eq!(rig.outputs(&a), rig.outputs(&b));
}

#[test]
fn transfer_format_option() {
    let rig = Rig::new();
    let out = rig.path("out");
    succeeds(&rig.transfer_with_markers(&out, &[os("--format"), os("off")]));
    assert_eq!(names(&out), ["bend-0.off", "bend-1.off", "bend-2.off"]);
}

// ---------------------------------------------------------------------------
// transfer: bad input.

#[test]
fn transfer_pose_with_other_vertex_count_writes_nothing() {
    let rig = Rig::new();
    let bad = rig.path("odd-pose.obj");
    write(&bad, &tube(LENGTH, 0.25, THIN_RINGS + 1, THIN_SEGMENTS));
    let poses = vec![rig.poses[0].clone(), bad.clone(), rig.poses[2].clone()];
    let out = rig.path("out");
    let corr = rig.path("map.corr");
    let err = fails(&rig.transfer(
        &out,
        &[
            os("--markers"),
            rig.markers.as_os_str(),
            os("--save-correspondence"),
            corr.as_os_str(),
        ],
        &poses,
    ));
    assert_empty(&out);
    assert!(!corr.exists(), "the correspondence was saved");
    assert_mentions(&err, &[&shown(&bad), "vertices"]);
    // Not the good poses.
    assert!(!err.contains(&shown(&rig.poses[0])), "{err}");
}

#[test]
fn transfer_markers_out_of_range() {
    let rig = Rig::new();
    let m = rig.path("m.txt");
    fs::write(&m, "0 0\n12 16\n# comment\n24 99999\n36 48\n").unwrap();
    let err = rig.transfer_fails_with_markers(&m);
    assert_mentions(&err, &[&shown(&m), "line 4", "99999", "out of range"]);

    fs::write(&m, "0 0\n12 16\n9999 5\n").unwrap();
    let err = rig.transfer_fails_with_markers(&m);
    assert_mentions(&err, &[&shown(&m), "line 3", "source vertex 9999"]);
}

#[test]
fn transfer_markers_repeated() {
    let rig = Rig::new();
    let m = rig.path("m.txt");
    fs::write(&m, "0 0\n12 16\n24 32\n12 16\n").unwrap();
    let err = rig.transfer_fails_with_markers(&m);
    assert_mentions(&err, &[&shown(&m), "line 4", "repeats", "line 2"]);
}

#[test]
fn transfer_marker_source_vertex_with_two_targets() {
    let rig = Rig::new();
    let m = rig.path("m.txt");
    fs::write(&m, "0 0\n12 16\n24 32\n\n12 17\n").unwrap();
    let err = rig.transfer_fails_with_markers(&m);
    assert_mentions(
        &err,
        &[
            &shown(&m),
            "line 5",
            "source vertex 12",
            "target vertex 17",
            "16",
        ],
    );
}

#[test]
fn transfer_markers_that_do_not_parse() {
    let rig = Rig::new();
    let m = rig.path("m.txt");
    fs::write(&m, "0 0\n12 16\n24 x32\n").unwrap();
    let err = rig.transfer_fails_with_markers(&m);
    assert_mentions(&err, &[&shown(&m), "line 3", "x32"]);

    fs::write(&m, "0 0\n12 16 3\n").unwrap();
    let err = rig.transfer_fails_with_markers(&m);
    assert_mentions(&err, &[&shown(&m), "line 2"]);

    // Zero is not a 1-based index.
    fs::write(&m, "1 1\n0 2\n").unwrap();
    let out = rig.path("out");
    let err = fails(&rig.transfer(
        &out,
        &[os("--markers"), m.as_os_str(), os("--one-based")],
        &rig.poses,
    ));
    assert_empty(&out);
    assert_mentions(&err, &[&shown(&m), "line 2", "1-based"]);
}

#[test]
fn transfer_fewer_than_three_markers() {
    let rig = Rig::new();
    let m = rig.path("m.txt");
    fs::write(&m, "0 0\n12 16\n").unwrap();
    let err = rig.transfer_fails_with_markers(&m);
    assert_mentions(&err, &[&shown(&m), "2 marker pairs", "at least 3"]);
}

#[test]
fn transfer_without_markers_or_correspondence() {
    let rig = Rig::new();
    let out = rig.path("out");
    let err = fails(&rig.transfer(&out, &[], &rig.poses));
    assert_empty(&out);
    assert_mentions(&err, &["--markers", "--correspondence"]);
}

#[test]
fn transfer_saved_correspondence_with_other_meshes() {
    let rig = Rig::new();
    let corr = rig.path("map.corr");
    succeeds(&rig.correspond(&corr, &[]));
    // Another thick tube, more finely tessellated.
    let other = rig.path("other.obj");
    write(&other, &tube(LENGTH, 0.5, 13, 16));
    let out = rig.path("out");
    let output = run([
        os("transfer"),
        os("--source-ref"),
        rig.source_ref.as_os_str(),
        os("--target-ref"),
        other.as_os_str(),
        os("--correspondence"),
        corr.as_os_str(),
        os("-o"),
        out.as_os_str(),
        rig.poses[1].as_os_str(),
    ]);
    let err = fails(&output);
    assert_empty(&out);
    assert_mentions(
        &err,
        &[
            &shown(&corr),
            "does not fit",
            "target reference",
            "vertices",
        ],
    );
}

#[test]
fn transfer_corrupted_correspondence() {
    let rig = Rig::new();
    let corr = rig.path("map.corr");
    let first = rig.path("first");
    succeeds(&rig.transfer_with_markers(&first, &[os("--save-correspondence"), corr.as_os_str()]));
    let line = line_starting(&corr, "pairs ") + 3;
    edit_lines(&corr, |l| l[line - 1] = "12 abc".into());
    let out = rig.path("out");
    let err = fails(&rig.transfer(
        &out,
        &[os("--correspondence"), corr.as_os_str()],
        &rig.poses,
    ));
    assert_empty(&out);
    assert_mentions(&err, &[&shown(&corr), &format!("line {line}"), "12 abc"]);

    // Truncated.
    edit_lines(&corr, |l| l.truncate(line - 1));
    let err = fails(&rig.transfer(
        &out,
        &[os("--correspondence"), corr.as_os_str()],
        &rig.poses,
    ));
    assert_empty(&out);
    assert_mentions(&err, &[&shown(&corr), "ends before"]);

    // Not a correspondence at all.
    let err = fails(&rig.transfer(
        &out,
        &[os("--correspondence"), rig.markers.as_os_str()],
        &rig.poses,
    ));
    assert_empty(&out);
    assert_mentions(
        &err,
        &[
            &shown(&rig.markers),
            "line 2",
            "not a meshmorph correspondence",
        ],
    );
}

#[test]
fn transfer_degenerate_target_triangle() {
    let rig = Rig::new();
    let corr = rig.path("map.corr");
    succeeds(&rig.correspond(&corr, &[]));
    let thick = thick_tube();
    let mut positions = thick.positions().to_vec();
    // Vertex 1 onto vertex 0: triangle 0 = [0, 1, 17] and the cap triangle
    // [cap, 1, 0] collapse.
    positions[1] = positions[0];
    write(&rig.target_ref, &thick.with_positions(positions).unwrap());
    let out = rig.path("out");
    let err = fails(&rig.transfer_with_markers(&out, &[]));
    assert_empty(&out);
    assert_mentions(
        &err,
        &[
            &shown(&rig.target_ref),
            "2 degenerate (zero-area) triangles",
            "target reference",
            "faces 1, 321 (numbered from 1",
        ],
    );
    // The same from a saved correspondence (it fits: same connectivity).
    let err = fails(&rig.transfer(
        &out,
        &[os("--correspondence"), corr.as_os_str()],
        &rig.poses,
    ));
    assert_empty(&out);
    assert_mentions(
        &err,
        &[
            &shown(&rig.target_ref),
            "2 degenerate (zero-area) triangles",
            "target reference",
            "faces 1, 321 (numbered from 1",
        ],
    );
}

#[test]
fn transfer_two_poses_with_the_same_stem() {
    let rig = Rig::new();
    let (a, b) = (rig.path("a"), rig.path("b"));
    fs::create_dir(&a).unwrap();
    fs::create_dir(&b).unwrap();
    fs::copy(&rig.poses[0], a.join("bend.obj")).unwrap();
    fs::copy(&rig.poses[1], b.join("bend.ply")).unwrap();
    let out = rig.path("out");
    let err = fails(&rig.transfer(
        &out,
        &[os("--markers"), rig.markers.as_os_str()],
        &[a.join("bend.obj"), b.join("bend.ply")],
    ));
    assert_empty(&out);
    assert_mentions(&err, &["are both named `bend`"]);
}

#[test]
fn transfer_poses_with_dots_in_their_names_keep_them() {
    // `walk.01.obj` and `walk.02.obj` are two outputs, not one `walk.obj`.
    let rig = Rig::new();
    let poses: Vec<PathBuf> = (0..2)
        .map(|k| {
            let p = rig.path(&format!("walk.0{k}.obj"));
            fs::copy(&rig.poses[k], &p).unwrap();
            p
        })
        .collect();
    let out = rig.path("out");
    succeeds(&rig.transfer(&out, &[os("--markers"), rig.markers.as_os_str()], &poses));
    assert_eq!(names(&out), ["walk.00.obj", "walk.01.obj"]);
}

#[test]
fn correspond_bad_deformed_source_name_writes_nothing() {
    let rig = Rig::new();
    let corr = rig.path("map.corr");
    let deformed = rig.path("deformed.fbx");
    let err = fails(&rig.correspond(&corr, &[os("--deformed-source"), deformed.as_os_str()]));
    assert_mentions(&err, &[&shown(&deformed), "unknown mesh format"]);
    assert!(!corr.exists() && !deformed.exists());
}

// ---------------------------------------------------------------------------
// demo.

#[test]
fn demo_writes_everything_and_json_lines() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    let text = succeeds(&run([os("demo"), os("-o"), out.as_os_str(), os("--json")]));
    let lines: Vec<&str> = text.lines().collect();
    assert!(!lines.is_empty());
    for line in &lines {
        let v: Value =
            serde_json::from_str(line).unwrap_or_else(|e| panic!("not JSON ({e}): {line}"));
        assert!(v.is_object(), "{line}");
    }
    let reports: Vec<Value> = lines
        .iter()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert!(reports
        .iter()
        .any(|r| r["frames_written"].as_u64() > Some(0)));
    assert!(reports
        .iter()
        .any(|r| r["poses_written"].as_u64() > Some(0)));

    let gif = fs::read(out.join("spiral.gif")).unwrap();
    assert!(gif.starts_with(b"GIF89a"));
    for file in ["coil.gif", "coil.png", "coil.glb", "coil-key2.obj"] {
        assert!(out.join(file).is_file(), "{file}");
    }
    assert_eq!(names(&out.join("coil")).len(), 48);
    assert!(reports.iter().any(|r| r["dimension"].as_u64() == Some(3)
        && r["keys"].as_u64() == Some(3)
        && r["max_flipped_triangles"].as_u64() == Some(0)));
    assert!(out.join("spiral").join("frame_0000.obj").is_file());
    // The sprite morph: its two pictures and anchors, 24 PNG frames, the
    // GIF, and its report.
    let sprite = out.join("sprite");
    for file in [
        "arm-straight.png",
        "arm-bent.png",
        "anchors.txt",
        "sprite.gif",
    ] {
        assert!(sprite.join(file).is_file(), "{file}");
    }
    assert_eq!(names(&sprite.join("frames")).len(), 24);
    // The rig's two shapes in a copy of the character: its own shape key
    // first, then theirs; its other mesh (the eye), skin and animation
    // kept; the character's file as it was made.
    let character = out.join("character");
    let (doc, mesh) =
        meshmorph::io::gltf::read(&character.join("character-shapes.glb"), Some("Body")).unwrap();
    assert_eq!(mesh.target_names(), ["Smile", "Extra_0", "Extra_1"]);
    let (input, _) =
        meshmorph::io::gltf::read(&character.join("input/character.glb"), Some("Body")).unwrap();
    for kept in ["skins", "animations", "materials", "images", "nodes"] {
        assert_eq!(doc.json()[kept], input.json()[kept], "{kept}");
    }
    assert_eq!(
        doc.json()["meshes"].as_array().unwrap().len(),
        input.json()["meshes"].as_array().unwrap().len()
    );
    // The expressions on the demo's head: its GLB with the 51 shapes, the
    // GIF, and its report (parts found: eyes, teeth, tongue).
    let expressions = out.join("expressions");
    for file in [
        "input/head.obj",
        "input/head.txt",
        "head-arkit.glb",
        "expressions.gif",
    ] {
        assert!(expressions.join(file).is_file(), "{file}");
    }
    assert!(reports
        .iter()
        .any(|r| r["shapes"].as_array().map(Vec::len) == Some(51)
            && r["missing"] == serde_json::json!(["tongueOut"])
            && r["parts"].as_array().is_some_and(|p| !p.is_empty())));
    assert!(reports.iter().any(|r| r["shape"] == "sprite"
        && r["frames_written"].as_u64() == Some(24)
        && r["anchors"].as_u64() == Some(7)));
    // The drawing morph: its two drawings and their anchors, 48 SVG frames,
    // the animated SVG and the GIF, and its report.
    let drawing = out.join("drawing");
    for file in [
        "stem-straight.svg",
        "stem-curled.svg",
        "anchors.txt",
        "drawing.svg",
        "drawing.gif",
    ] {
        assert!(drawing.join(file).is_file(), "{file}");
    }
    let frames: Vec<String> = names(&drawing)
        .into_iter()
        .filter(|n| n.starts_with("frame_"))
        .collect();
    assert_eq!(frames.len(), 48);
    assert!(frames.iter().all(|n| n.ends_with(".svg")));
    let first = fs::read_to_string(drawing.join("frame_0000.svg")).unwrap();
    assert!(
        first.contains("<path") && first.contains("evenodd"),
        "{first}"
    );
    assert!(reports
        .iter()
        .any(|r| r["job"] == "drawing" && r["triangles"].as_u64() > Some(0)));
    let transfer = out.join("transfer");
    let gif = fs::read(transfer.join("transfer.gif")).unwrap();
    assert!(gif.starts_with(b"GIF89a"));
    let png = fs::read(transfer.join("transfer.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
    let targets = names(&transfer.join("target"));
    assert!(!targets.is_empty());
    for name in &targets {
        assert!(name.ends_with(".obj"), "{name}");
        read(&transfer.join("target").join(name));
    }
    // No temporary file left anywhere.
    for d in [
        out.clone(),
        out.join("spiral"),
        drawing.clone(),
        transfer.clone(),
        transfer.join("target"),
    ] {
        for name in names(&d) {
            assert!(!name.ends_with(".tmp"), "{}", d.join(name).display());
        }
    }
}

#[test]
fn transfer_refuses_to_overwrite_its_inputs() {
    let rig = Rig::new();
    let dir = rig.poses[0].parent().unwrap().to_path_buf();
    let before = fs::read(&rig.poses[0]).unwrap();
    let err = fails(&rig.transfer(
        &dir,
        &[os("--markers"), rig.markers.as_os_str()],
        &rig.poses[..1],
    ));
    assert_mentions(&err, &["would overwrite the source pose"]);
    assert_eq!(fs::read(&rig.poses[0]).unwrap(), before);
}

// ---------------------------------------------------------------------------
// glTF, pictures, reports, completions and manual pages.

/// Asserts a command-line usage error (clap's exit status 2, no panic) and
/// returns stderr.
fn usage_error(out: &Output) -> String {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(2), "stderr:\n{err}");
    assert!(!err.contains("panicked"), "panic:\n{err}");
    err
}

#[test]
fn interpolate_gltf_and_its_report_list_every_file() {
    let p = Pair::bar();
    let glb = p.out.join("a.glb");
    let report = json(&succeeds(&p.interpolate(&[
        "--frames",
        "4",
        "--json",
        "--gltf",
        glb.to_str().unwrap(),
        "--fps",
        "10",
    ])));
    assert!(fs::read(&glb).unwrap().starts_with(b"glTF"));
    let files: Vec<String> = report["files_written"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    let mut want: Vec<String> = (0..4)
        .map(|k| shown(&p.out.join(format!("frame_{k:04}.obj"))))
        .collect();
    want.push(shown(&glb));
    assert_eq!(files, want);
    assert_eq!(report["warnings"], Value::Array(Vec::new()));
    assert_eq!(report["gltf"].as_str().unwrap(), shown(&glb));
}

#[test]
fn a_gltf_says_what_of_the_file_it_does_not_hold() {
    let dir = tempfile::tempdir().unwrap();
    let rest = tube(LENGTH, 0.25, 5, 6);
    let bent = bend(&rest, LENGTH, 0.5 * PI);
    let (a, b) = (dir.path().join("a.obj"), dir.path().join("b.obj"));
    write(&a, &rest);
    write(&b, &bent);
    // An object name and a material in the first key.
    edit_lines(&a, |lines| {
        lines.insert(0, "o arm".to_string());
        lines.insert(1, "usemtl skin".to_string());
    });
    let glb = dir.path().join("a.glb");
    let report = json(&succeeds(&run([
        os("interpolate"),
        a.as_os_str(),
        b.as_os_str(),
        os("-o"),
        dir.path().join("out").as_os_str(),
        os("--frames"),
        os("3"),
        os("--gltf"),
        glb.as_os_str(),
        os("--json"),
    ])));
    let warnings = report["warnings"].to_string();
    assert_mentions(
        &warnings,
        &["GLB", "objects (`o`)", "a.obj", "material `skin`"],
    );
    // The frames keep them.
    let frame = fs::read_to_string(dir.path().join("out/frame_0001.obj")).unwrap();
    assert!(frame.starts_with("o arm\nusemtl skin\n"), "{frame}");
}

#[test]
fn a_gltf_keeps_the_materials_and_textures_of_an_obj() {
    let dir = tempfile::tempdir().unwrap();
    let rest = tube(LENGTH, 0.25, 5, 6);
    let bent = bend(&rest, LENGTH, 0.5 * PI);
    let (a, b) = (dir.path().join("a.obj"), dir.path().join("b.obj"));
    write(&a, &rest);
    write(&b, &bent);
    // Texture coordinates, a textured material on the first half of the
    // faces and a plain one on the rest.
    let mut png_bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut png_bytes, 1, 1);
        encoder.set_color(png::ColorType::Rgb);
        let mut w = encoder.write_header().unwrap();
        w.write_image_data(&[200, 100, 50]).unwrap();
    }
    fs::write(dir.path().join("skin.png"), &png_bytes).unwrap();
    fs::write(
        dir.path().join("a.mtl"),
        "newmtl skin\nmap_Kd skin.png\nnewmtl cloth\nKd 0.1 0.2 0.3\n",
    )
    .unwrap();
    edit_lines(&a, |lines| {
        let faces: Vec<usize> = (0..lines.len())
            .filter(|&i| lines[i].starts_with("f "))
            .collect();
        let half = faces[faces.len() / 2];
        for &i in &faces {
            let corners: Vec<String> = lines[i][2..]
                .split_whitespace()
                .map(|c| format!("{c}/1"))
                .collect();
            lines[i] = format!("f {}", corners.join(" "));
        }
        lines.insert(half, "usemtl cloth".to_string());
        lines.insert(faces[0], "usemtl skin".to_string());
        lines.insert(faces[0], "vt 0.5 0.5".to_string());
        lines.insert(0, "mtllib a.mtl".to_string());
    });
    let glb = dir.path().join("a.glb");
    let report = json(&succeeds(&run([
        os("interpolate"),
        a.as_os_str(),
        b.as_os_str(),
        os("-o"),
        dir.path().join("out").as_os_str(),
        os("--frames"),
        os("3"),
        os("--gltf"),
        glb.as_os_str(),
        os("--json"),
    ])));
    assert_eq!(report["warnings"], Value::Array(Vec::new()));
    let file = gltf::Gltf::open(&glb).unwrap();
    let names: Vec<&str> = file.materials().filter_map(|m| m.name()).collect();
    assert_eq!(names, ["skin", "cloth"]);
    let mesh = file.meshes().next().unwrap();
    assert_eq!(mesh.primitives().count(), 2);
    let image = file.images().next().expect("the texture is embedded");
    let gltf::image::Source::View { view, mime_type } = image.source() else {
        panic!("an embedded image");
    };
    assert_eq!((mime_type, view.length()), ("image/png", png_bytes.len()));
}

#[test]
fn a_face_that_repeats_a_vertex_in_a_row_is_read_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let rest = tube(LENGTH, 0.25, 5, 6);
    let bent = bend(&rest, LENGTH, 0.5 * PI);
    let (a, b) = (dir.path().join("a.obj"), dir.path().join("b.obj"));
    write(&a, &rest);
    write(&b, &bent);
    // The third face lists its last vertex twice, in both keys.
    for path in [&a, &b] {
        edit_lines(path, |lines| {
            let i = (0..lines.len())
                .filter(|&i| lines[i].starts_with("f "))
                .nth(2)
                .unwrap();
            let last = lines[i].split_whitespace().last().unwrap().to_string();
            lines[i] = format!("{} {last}", lines[i]);
        });
    }
    let report = json(&succeeds(&run([
        os("interpolate"),
        a.as_os_str(),
        b.as_os_str(),
        os("-o"),
        dir.path().join("out").as_os_str(),
        os("--frames"),
        os("3"),
        os("--json"),
    ])));
    assert_mentions(
        &report["warnings"].to_string(),
        &["a.obj", "1 face lists a vertex twice in a row", "face 3"],
    );
}

#[test]
fn faces_of_a_ply_are_numbered_from_0() {
    let dir = tempfile::tempdir().unwrap();
    let ply = |name: &str, x: f64| {
        let path = dir.path().join(name);
        fs::write(
            &path,
            format!(
                "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
                 element face 2\nproperty list uchar int vertex_indices\nend_header\n\
                 0 0 0\n{x} 0 0\n1 1 0\n0 1 0\n3 0 1 2\n4 0 2 3 3\n"
            ),
        )
        .unwrap();
        path
    };
    let (a, b) = (ply("a.ply", 1.0), ply("b.ply", 1.5));
    let report = json(&succeeds(&run([
        os("interpolate"),
        a.as_os_str(),
        b.as_os_str(),
        os("-o"),
        dir.path().join("out").as_os_str(),
        os("--frames"),
        os("2"),
        os("--json"),
    ])));
    assert_mentions(
        &report["warnings"].to_string(),
        &["a.ply", "face 1, numbered from 0"],
    );
}

#[test]
fn a_gif_faster_than_50_frames_per_second_is_said_to_play_at_50() {
    let p = Pair::bar();
    let gif = p.out.join("a.gif");
    let warned = |fps: &str| {
        let out = p.interpolate(&[
            "--frames",
            "2",
            "--gif",
            gif.to_str().unwrap(),
            "--fps",
            fps,
        ]);
        succeeds(&out);
        stderr(&out).contains("GIF plays at 50 frames per second, not")
    };
    assert!(warned("60"));
    assert!(!warned("50"));
}

#[test]
fn interpolate_bad_gltf_options_are_refused_before_any_output() {
    let p = Pair::bar();
    let glb = p.out.join("a.glb");
    let g = glb.to_str().unwrap();
    for fps in ["0", "-1", "nan", "inf", "1e-20", "1e50"] {
        let err = usage_error(&p.interpolate(&["--gltf", g, &format!("--fps={fps}")]));
        assert_mentions(&err, &["--fps", "not a frame rate from 0.01 to 1000"]);
        assert!(!p.out.exists());
    }
    let err = usage_error(&p.interpolate(&["--gltf", p.out.join("a.gltf").to_str().unwrap()]));
    assert_mentions(&err, &["a.gltf", ".glb"]);
    let err = p.interpolate_fails(&["--gltf", g, "--frames", "100", "--max-gltf-mb", "0.01"]);
    assert_mentions(&err, &["a.glb", "MB", "100 frames", "--max-gltf-mb"]);
    // A GLB that cannot be written (its folder is a file): no frame files
    // left either. (Missing folders are created.)
    let blocker = p.out.parent().unwrap().join("blocker");
    fs::write(&blocker, "a file").unwrap();
    let blocked = blocker.join("a.glb");
    let err = p.interpolate_fails(&["--gltf", blocked.to_str().unwrap()]);
    assert_mentions(&err, &[&shown(&blocked), "glTF", "is a file, not a folder"]);
}

#[test]
fn transfer_writes_a_gltf_pictures_and_lists_them() {
    let rig = Rig::new();
    let out = rig.path("out");
    let glb = rig.path("poses.glb");
    let png = rig.path("poses.png");
    let gif = rig.path("poses.gif");
    let report = json(&succeeds(&rig.transfer_with_markers(
        &out,
        &[
            "--json".as_ref(),
            "--gltf".as_ref(),
            glb.as_os_str(),
            "--gltf-shapes".as_ref(),
            "--png".as_ref(),
            png.as_os_str(),
            "--gif".as_ref(),
            gif.as_os_str(),
        ],
    )));
    assert!(fs::read(&glb).unwrap().starts_with(b"glTF"));
    assert!(fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    assert!(fs::read(&gif).unwrap().starts_with(b"GIF89a"));
    let files = report["files_written"].as_array().unwrap();
    assert_eq!(files.len(), rig.poses.len() + 3);
    for f in [&glb, &gif, &png] {
        assert!(files.iter().any(|v| v.as_str() == Some(&shown(f))), "{f:?}");
    }
    assert!(report["warnings"].is_array());
}

#[test]
fn transfer_gltf_shapes_needs_gltf_and_the_gltf_never_overwrites_an_input() {
    let rig = Rig::new();
    let out = rig.path("out");
    let err = usage_error(&rig.transfer_with_markers(&out, &["--gltf-shapes".as_ref()]));
    assert_mentions(&err, &["--gltf"]);
    // A picture named as the target's file is refused by its name (outputs
    // onto inputs by other names: tests/command_line/hostile.rs).
    let err = usage_error(
        &rig.transfer_with_markers(&out, &["--png".as_ref(), rig.target_ref.as_os_str()]),
    );
    assert_mentions(&err, &[&shown(&rig.target_ref), "extension .png"]);
    assert!(!out.exists());
}

#[test]
fn correspond_draws_the_deformed_source_over_the_target() {
    let rig = Rig::new();
    let png = rig.path("fit.png");
    let gif = rig.path("fit.gif");
    let corr = rig.path("c.corr");
    let report = json(&succeeds(&rig.correspond(
        &corr,
        &[
            os("--png"),
            png.as_os_str(),
            os("--gif"),
            gif.as_os_str(),
            os("--json"),
        ],
    )));
    assert!(fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    assert!(fs::read(&gif).unwrap().starts_with(b"GIF89a"));
    let files = report["files_written"].as_array().unwrap();
    assert_eq!(files.len(), 3, "{files:?}");
}

/// The length of a PNG's palette in entries.
fn png_palette_len(bytes: &[u8]) -> usize {
    let at = bytes
        .windows(4)
        .position(|w| w == b"PLTE")
        .expect("an indexed PNG");
    let len = u32::from_be_bytes(bytes[at - 4..at].try_into().unwrap());
    len as usize / 3
}

#[test]
fn correspond_colours_the_target_by_its_distance_to_the_deformed_source() {
    let rig = Rig::new();
    let png = rig.path("fit.png");
    succeeds(&rig.correspond(&rig.path("c.corr"), &[os("--png"), png.as_os_str()]));
    let bytes = fs::read(&png).unwrap();
    assert!(bytes.starts_with(b"\x89PNG"));
    // The colour scale's entries (from 192 on) are in use.
    assert!(png_palette_len(&bytes) > 192, "{}", png_palette_len(&bytes));
}

/// The fields of the fit in a report, checked for range.
fn assert_fit_fields(fit: &Value) {
    for key in [
        "mean_distance",
        "distance_95th_percentile",
        "distance_limit",
        "uncovered_area",
        "poor_threshold",
        "poor_area",
    ] {
        let v = fit[key]
            .as_f64()
            .unwrap_or_else(|| panic!("`{key}` is not a number in {fit}"));
        assert!((0.0..=1.0).contains(&v), "{key} = {v}");
    }
    assert!(fit["poor_regions"].is_array(), "{fit}");
}

#[test]
fn correspond_and_transfer_report_the_fit_in_the_same_words() {
    let rig = Rig::new();
    let corr = rig.path("c.corr");
    let text = succeeds(&rig.correspond(&corr, &[]));
    let lines = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| l.starts_with("fit:") || l.starts_with("coverage:"))
            .map(|l| {
                l.split_whitespace()
                    .filter(|w| w.parse::<f64>().is_err())
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .collect()
    };
    let from_correspond = lines(&text);
    assert_eq!(from_correspond.len(), 2, "{text}");
    assert_mentions(
        &text,
        &[
            "target to deformed source",
            "(95th percentile)",
            "has no source partner",
        ],
    );
    let report = json(&succeeds(&rig.correspond(&corr, &[os("--json")])));
    assert_fit_fields(&report["fit"]);
    let out = rig.path("out");
    let text = succeeds(&rig.transfer_with_markers(&out, &[]));
    assert_eq!(lines(&text), from_correspond, "{text}");
    let again = rig.path("again");
    let report = json(&succeeds(
        &rig.transfer_with_markers(&again, &[os("--json")]),
    ));
    assert_fit_fields(&report["fit"]);
    // A loaded correspondence has no deformed source to measure.
    let loaded = rig.path("loaded");
    let report = json(&succeeds(&rig.transfer(
        &loaded,
        &[os("--json"), os("--correspondence"), corr.as_os_str()],
        &rig.poses,
    )));
    assert_eq!(report["fit"], Value::Null);
}

#[test]
fn correspond_warns_where_the_source_does_not_reach_the_target_naming_the_markers_there() {
    // A source tube 4 long on a target 6 long, markers on rings at x = 0,
    // 2 and 4 (lines 2 to 13 of the file, four a ring).
    let dir = tempfile::tempdir().unwrap();
    let (source, target) = (tube(4.0, 0.5, 17, 16), tube(6.0, 0.5, 25, 16));
    let (source_ref, target_ref) = (dir.path().join("short.obj"), dir.path().join("long.obj"));
    write(&source_ref, &source);
    write(&target_ref, &target);
    let pairs: Vec<[u32; 2]> = [0, 8, 16]
        .iter()
        .flat_map(|&r| [0, 4, 8, 12].map(|s| [r * 16 + s; 2]))
        .collect();
    let markers = dir.path().join("markers.txt");
    write_markers(&markers, &pairs, 0);
    let corr = dir.path().join("c.corr");
    let run_with = |extra: &[&str]| {
        let mut args: Vec<&OsStr> = vec![
            os("correspond"),
            os("--source-ref"),
            source_ref.as_os_str(),
            os("--target-ref"),
            target_ref.as_os_str(),
            os("--markers"),
            markers.as_os_str(),
            os("-o"),
            corr.as_os_str(),
        ];
        args.extend(extra.iter().map(|a| os(a)));
        run(args)
    };
    let out = run_with(&[]);
    succeeds(&out);
    let err = stderr(&out);
    let warning = err
        .lines()
        .find(|l| l.contains("the deformed source lies farther than"))
        .unwrap_or_else(|| panic!("no warning about the fit in:\n{err}"));
    // The nearest markers: those at the source's end, lines 10 to 13.
    let named = format!("`{}`, line 1", shown(&markers));
    assert!(warning.contains(&named), "{warning}");
    assert_mentions(warning, &["add a marker pair there"]);
    let report = json(&succeeds(&run_with(&["--json"])));
    let regions = report["fit"]["poor_regions"].as_array().unwrap();
    assert_eq!(regions.len(), 1, "{report}");
    let area = regions[0]["area"].as_f64().unwrap();
    assert!((0.2..0.4).contains(&area), "{area}");
    for near in regions[0]["nearest_markers"].as_array().unwrap() {
        let k = near["marker"].as_u64().unwrap();
        assert!((8..12).contains(&k), "{near}");
        let line = format!("line {}", k + 2);
        assert!(
            near["description"].as_str().unwrap().contains(&line),
            "{near}"
        );
    }
    let warnings = report["warnings"].as_array().unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.as_str().unwrap().contains(&named)),
        "{report}"
    );
}

/// Runs a command with `files` (each `--flag path`) and checks that its
/// report names each: as a line `label path` in text, as the key's value
/// with `--json`.
fn assert_reports_name(command: impl Fn(&[&OsStr]) -> Output, files: &[(&str, &Path, &str, &str)]) {
    let mut args: Vec<&OsStr> = Vec::new();
    for (flag, path, _, _) in files {
        args.extend([os(flag), path.as_os_str()]);
    }
    let text = succeeds(&command(&args));
    args.push(os("--json"));
    let report = json(&succeeds(&command(&args)));
    for (_, path, label, key) in files {
        let named = text.lines().any(|l| {
            l.strip_prefix(label)
                .is_some_and(|rest| rest.trim_start() == shown(path))
        });
        assert!(named, "no `{label} {}` in:\n{text}", shown(path));
        assert_eq!(report[key].as_str(), Some(shown(path).as_str()), "{report}");
    }
}

#[test]
fn transfer_and_correspond_reports_name_every_file_they_write() {
    let rig = Rig::new();
    let out = rig.path("out");
    let [glb, png, gif, corr, deformed] =
        ["poses.glb", "poses.png", "poses.gif", "map.corr", "fit.obj"].map(|n| rig.path(n));
    // Both draw pictures; each writes one more file of its own.
    let pictures = [
        ("--png", png.as_path(), "picture:", "png"),
        ("--gif", gif.as_path(), "animation:", "gif"),
    ];
    let transfer_files = [
        (
            "--save-correspondence",
            corr.as_path(),
            "saved:",
            "saved_correspondence",
        ),
        ("--gltf", glb.as_path(), "glTF:", "gltf"),
    ];
    assert_reports_name(
        |args| rig.transfer_with_markers(&out, args),
        &[&pictures[..], &transfer_files[..]].concat(),
    );
    let deformed_file = (
        "--deformed-source",
        deformed.as_path(),
        "deformed:",
        "deformed_source",
    );
    assert_reports_name(
        |args| rig.correspond(&corr, args),
        &[&pictures[..], &[deformed_file]].concat(),
    );
}

#[test]
fn transfer_report_splits_the_unmatched_target_triangles() {
    let rig = Rig::new();
    // A target twice as long as the source: its far half lies beyond it,
    // and a few triangles near the middle are holes of the match.
    let long = tube(2.0 * LENGTH, 0.5, 21, 16);
    let target = rig.path("long.obj");
    write(&target, &long);
    let markers = rig.path("long-markers.txt");
    write_markers(&markers, &marker_pairs(&thin_tube(), &long), 0);
    let out = rig.path("out");
    let transfer = |extra: &[&OsStr]| {
        let files = [rig.source_ref.as_path(), &target, &markers];
        transfer_between(files, &out, extra, &rig.poses[1..2])
    };
    let report = json(&succeeds(&transfer(&[os("--json")])));
    let unmatched = uint(&report, "unmatched_target_triangles");
    // The source's end caps, turned across the long tube's side, have no
    // partner there.
    let unmatched_source = uint(&report, "unmatched_source_triangles");
    let gaps = uint(&report, "gap_target_triangles");
    let rest = uint(&report, "unpaired_target_triangles");
    assert!(gaps > 1 && rest > 1, "{report}");
    assert_eq!(gaps + rest, unmatched, "{report}");
    assert_mentions(
        &report["warnings"].to_string(),
        &[&format!(
            "{rest} of the {unmatched} unmatched target triangles lie beyond the source"
        )],
    );
    let out = transfer(&[]);
    assert_mentions(
        &succeeds(&out),
        &[
            &format!(
                "unmatched:      {unmatched_source} source triangles, {unmatched} target triangles\n"
            ),
            &format!("in gaps:      {gaps} target triangles ("),
            &format!("kept at rest: {rest} target triangles ("),
        ],
    );
    assert_mentions(&stderr(&out), &[&format!("the other {gaps} fill gaps")]);
}

#[test]
fn completions_and_manual_pages_come_from_the_command_line_definitions() {
    for shell in ["bash", "zsh", "fish", "elvish", "powershell"] {
        let out = succeeds(&run(["completions", shell]));
        assert!(out.contains("transfer"), "{shell}: {out}");
        assert!(out.contains("gltf"), "{shell}");
    }
    let page = succeeds(&run(["man"]));
    assert!(
        page.starts_with(".ie") || page.contains(".TH meshmorph"),
        "{page}"
    );
    assert_mentions(&page, &["interpolate", "transfer", "correspond"]);
    let dir = tempfile::tempdir().unwrap();
    succeeds(&run([
        "man".as_ref(),
        "--dir".as_ref(),
        dir.path().as_os_str(),
    ]));
    let pages = names(dir.path());
    for want in [
        "meshmorph.1",
        "meshmorph-transfer.1",
        "meshmorph-interpolate.1",
    ] {
        assert!(pages.iter().any(|p| p == want), "{pages:?}");
    }
    let transfer = fs::read_to_string(dir.path().join("meshmorph-transfer.1")).unwrap();
    assert_mentions(&transfer, &["gltf\\-shapes", "max\\-gltf\\-mb"]);
}

/// A quad sheet with texture coordinates, an object and a material, and a
/// key of it bent out of the plane whose first face starts at another
/// corner.
fn textured_quad_keys(dir: &Path) -> [PathBuf; 2] {
    let head = "# a quad sheet\nmtllib sheet.mtl\no sheet\n";
    let tail = "vt 0 0\nvt 0.5 0\nvt 1 0\nvt 0 1\nvt 0.5 1\nvt 1 1\nusemtl skin\n";
    let flat = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n";
    let bent = "v 0 0 0\nv 1 0 0\nv 1.8 0 0.6\nv 0 1 0\nv 1 1 0\nv 1.8 1 0.6\n";
    let k0 = dir.join("k0.obj");
    let k1 = dir.join("k1.obj");
    fs::write(
        &k0,
        format!("{head}{flat}{tail}f 1/1 2/2 5/5 4/4\nf 2/2 3/3 6/6 5/5\n"),
    )
    .unwrap();
    fs::write(
        &k1,
        format!("{head}{bent}{tail}f 2/2 5/5 4/4 1/1\nf 2/2 3/3 6/6 5/5\n"),
    )
    .unwrap();
    [k0, k1]
}

/// The lines of an OBJ file other than its positions.
fn all_but_positions(path: &Path) -> Vec<String> {
    fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with("v "))
        .map(String::from)
        .collect()
}

#[test]
fn interpolation_and_blend_keep_the_first_file() {
    let dir = tempfile::tempdir().unwrap();
    let keys = textured_quad_keys(dir.path());
    let out = dir.path().join("out");
    succeeds(&interpolate_keys(&keys, &out, &["--frames", "3"]));
    let expected = all_but_positions(&keys[0]);
    // In another folder the material library is found from there.
    let from_out: Vec<String> = expected
        .iter()
        .map(|l| l.replace("mtllib sheet.mtl", "mtllib ../sheet.mtl"))
        .collect();
    assert_ne!(from_out, expected);
    for k in 0..3 {
        let frame = out.join(format!("frame_000{k}.obj"));
        // Quads, texture coordinates, the object and the material stay.
        assert_eq!(all_but_positions(&frame), from_out, "frame {k}");
    }
    assert!(!out.join("sheet.mtl").exists());
    let last = meshmorph::io::read_mesh(&out.join("frame_0002.obj")).unwrap();
    let k1 = meshmorph::io::read_mesh(&keys[1]).unwrap();
    assert!(max_diff(last.positions(), k1.positions()) < 1e-9);
    // The GLBs carry the first file's texture coordinates.
    let glb = dir.path().join("frames.glb");
    let with_glb = interpolate_keys(
        &keys,
        &dir.path().join("o2"),
        &["--frames", "3", "--gltf", &shown(&glb)],
    );
    succeeds(&with_glb);
    let blend_glb = dir.path().join("blend.glb");
    let blended = dir.path().join("blend.obj");
    succeeds(&blend(
        &keys[0],
        &[(&keys[1], "1")],
        &blended,
        &["--gltf", &shown(&blend_glb)],
    ));
    for g in [&glb, &blend_glb] {
        let bytes = fs::read(g).unwrap();
        assert!(
            bytes.windows(10).any(|w| w == b"TEXCOORD_0"),
            "{}",
            g.display()
        );
    }
    assert_eq!(all_but_positions(&blended), expected);
    let b = meshmorph::io::read_mesh(&blended).unwrap();
    assert!(max_diff(b.positions(), k1.positions()) < 1e-9);
    // Into another format, what it cannot hold is said, once; the texture
    // coordinates go along.
    let ply = dir.path().join("ply");
    let run = interpolate_keys(&keys, &ply, &["--frames", "3", "--format", "ply"]);
    let stderr = String::from_utf8_lossy(&run.stderr).to_string();
    assert!(run.status.success(), "{stderr}");
    assert_eq!(stderr.matches("materials").count(), 1, "{stderr}");
    assert!(!stderr.contains("texture coordinates"), "{stderr}");
    assert_mentions(
        &stderr,
        &[
            &shown(&ply),
            "cannot be carried over to ply",
            "1 face lists its corners",
        ],
    );
    let frame = meshmorph::io::MeshFile::read(&ply.join("frame_0001.ply")).unwrap();
    assert!(frame.has_corner_uvs());
}

/// A tube with a small tube ("an eye") just off its surface, and the whole
/// turned by 90 degrees about z.
fn head_with_an_eye(dir: &Path) -> (PathBuf, PathBuf) {
    let head = tube(2.0, 0.5, 9, 10);
    let eye = tube(0.2, 0.1, 3, 6);
    let mut positions = head.positions().to_vec();
    positions.extend(
        eye.positions()
            .iter()
            .map(|p| [p[0] + 1.2, p[1] + 0.55, p[2]]),
    );
    let n = head.num_vertices() as u32;
    let mut triangles = head.triangles().to_vec();
    triangles.extend(eye.triangles().iter().map(|t| t.map(|v| v + n)));
    let rest = Mesh3::new(positions, triangles).unwrap();
    let turned = rest
        .with_positions(
            rest.positions()
                .iter()
                .map(|p| [-p[1], p[0], p[2]])
                .collect(),
        )
        .unwrap();
    let (a, b) = (dir.join("rest.obj"), dir.join("turned.obj"));
    write(&a, &rest);
    write(&b, &turned);
    (a, b)
}

#[test]
fn separate_parts_turn_with_the_part_they_sit_in() {
    let dir = tempfile::tempdir().unwrap();
    let (rest, turned) = head_with_an_eye(dir.path());
    let out = dir.path().join("frames");
    let report = json(&succeeds(&run([
        "interpolate",
        &shown(&rest),
        &shown(&turned),
        "-o",
        &shown(&out),
        "--frames",
        "3",
        "--json",
    ])));
    assert_eq!(uint(&report, "parts_following_host"), 1);
    // Halfway the eye's centre is as far from the head's axis as at rest
    // (0.55): on a straight line it would be 0.55 cos 45° from it.
    let halfway = read(&out.join("frame_0001.obj"));
    let eye = &halfway.positions()[92..];
    let head = &halfway.positions()[..92];
    let mean = |p: &[[f64; 3]]| -> [f64; 3] {
        let s = p
            .iter()
            .fold([0.0; 3], |s, q| [s[0] + q[0], s[1] + q[1], s[2] + q[2]]);
        s.map(|x| x / p.len() as f64)
    };
    let (e, h) = (mean(eye), mean(head));
    // The head's axis at 45 degrees: (1, 1, 0) / √2 through its centroid.
    let d = [e[0] - h[0], e[1] - h[1]];
    let off_axis = (d[0] - d[1]).abs() / 2f64.sqrt();
    assert!((off_axis - 0.55).abs() < 1e-6, "{off_axis}");
    let blended = dir.path().join("blend.obj");
    let report = json(&succeeds(&blend(
        &rest,
        &[(&turned, "0.5")],
        &blended,
        &["--json"],
    )));
    assert_eq!(uint(&report, "parts_following_host"), 1);
}

#[test]
fn faces_given_twice_or_edges_shared_by_three_faces_are_said() {
    let dir = tempfile::tempdir().unwrap();
    let rest = tube(2.0, 0.5, 5, 8);
    let bent = bend(&rest, 2.0, 1.0);
    let twice = |m: &Mesh3| {
        let mut triangles = m.triangles().to_vec();
        triangles.push(triangles[3]);
        Mesh3::new(m.positions().to_vec(), triangles).unwrap()
    };
    let (a, b) = (dir.path().join("a.obj"), dir.path().join("b.obj"));
    write(&a, &twice(&rest));
    write(&b, &twice(&bent));
    let out = dir.path().join("frames");
    let report = json(&succeeds(&run([
        "interpolate",
        &shown(&a),
        &shown(&b),
        "-o",
        &shown(&out),
        "--frames",
        "3",
        "--json",
    ])));
    let warnings = report["warnings"].to_string();
    let last = rest.num_triangles() + 1;
    assert!(
        warnings.contains(&format!("face {last} repeats face 4")) && warnings.contains("a.obj"),
        "{warnings}"
    );
}

/// A planar grid of `n` × `n` quads as OBJ text, vertex `moved` (0-based)
/// shifted by `shift`.
fn quad_grid_obj(n: usize, moved: usize, shift: [f64; 2]) -> String {
    let mut text = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let k = j * (n + 1) + i;
            let d = if k == moved { shift } else { [0.0, 0.0] };
            text.push_str(&format!("v {} {} 0\n", i as f64 + d[0], j as f64 + d[1]));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            let b = a + n + 1;
            text.push_str(&format!("f {a} {} {} {b}\n", a + 1, b + 1));
        }
    }
    text
}

#[test]
fn flipped_triangles_are_named_by_the_files_faces_and_the_flag() {
    // 5 × 5 quads (25 faces, 50 triangles); vertex 22 (1-based) pushed past
    // its neighbours folds the quads around it, the last of them face 19.
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("grid.obj"), dir.path().join("folded.obj"));
    fs::write(&a, quad_grid_obj(5, 21, [0.0, 0.0])).unwrap();
    fs::write(&b, quad_grid_obj(5, 21, [1.6, 1.6])).unwrap();
    let out = dir.path().join("out");
    for extra in [&[][..], &["--dim", "3"][..]] {
        let err = fails(&interpolate_keys(&[a.clone(), b.clone()], &out, extra));
        let (a, b) = (shown(&a), shown(&b));
        assert_mentions(
            &err,
            &[&a, &b, "face 19", "numbered from 1", "--allow-flips"],
        );
        assert!(!err.contains("allow_flips"), "library wording: {err}");
        // Face numbers of a 25-face file, not triangle numbers after splitting.
        let numbers = err
            .split("in face")
            .nth(1)
            .unwrap()
            .split('(')
            .next()
            .unwrap();
        for n in numbers.trim_start_matches('s').split(',') {
            let n: usize = n.trim().parse().unwrap_or_else(|_| panic!("{err}"));
            assert!((1..=25).contains(&n), "{err}");
        }
        assert_empty(&out);
    }
    let blended = dir.path().join("blend.obj");
    let err = fails(&blend(&a, &[(&b, "1")], &blended, &["--dim", "3"]));
    assert_mentions(&err, &[&shown(&a), &shown(&b), "face 19", "--allow-flips"]);
    assert!(!err.contains("allow_flips"), "library wording: {err}");
    assert!(!blended.exists());
}

#[test]
fn a_degenerate_first_key_is_named_once() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("grid.obj"), dir.path().join("same.obj"));
    // Face 26 joins three vertices of the grid's first row: zero area.
    let mut text = quad_grid_obj(5, 0, [0.0, 0.0]);
    text.push_str("f 1 2 3\n");
    fs::write(&a, &text).unwrap();
    fs::write(&b, &text).unwrap();
    let out = dir.path().join("out");
    let (a_, b_, o) = (shown(&a), shown(&b), shown(&out));
    let named = format!("`{a_}`");
    for keys in [vec![&a_, &b_], vec![&a_, &b_, &b_]] {
        let mut args: Vec<&str> = vec!["interpolate", "-o", &o];
        args.extend(keys.iter().map(|k| k.as_str()));
        let err = fails(&run(&args));
        assert_mentions(&err, &["degenerate", "face 26"]);
        // Once in "interpolating ...", once where the face is.
        assert_eq!(err.matches(&named).count(), 2, "{err}");
        assert_empty(&out);
    }
    let err = fails(&blend(&a, &[(&b, "1")], &dir.path().join("blend.obj"), &[]));
    assert_mentions(&err, &["degenerate", "face 26"]);
    assert_eq!(err.matches(&named).count(), 2, "{err}");
}

/// `mesh` turned by 40° about (1, 2, 2)/3 and scaled 7.5 times about the
/// origin.
fn turned_and_scaled(mesh: &Mesh3) -> Mesh3 {
    let (c, s) = (40f64.to_radians().cos(), 40f64.to_radians().sin());
    let k = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
    let turn = |p: &[f64; 3]| -> [f64; 3] {
        // Rodrigues: p cos + (k × p) sin + k (k · p)(1 - cos).
        let kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
        let cross = [
            k[1] * p[2] - k[2] * p[1],
            k[2] * p[0] - k[0] * p[2],
            k[0] * p[1] - k[1] * p[0],
        ];
        [0, 1, 2].map(|i| 7.5 * (p[i] * c + cross[i] * s + k[i] * kp * (1.0 - c)))
    };
    mesh.with_positions(mesh.positions().iter().map(turn).collect())
        .unwrap()
}

#[test]
fn a_turned_and_scaled_key_or_pose_is_said_at_its_true_size() {
    // Its bounding box grows by another factor than 7.5, its size not.
    let dir = tempfile::tempdir().unwrap();
    let rest = tube(3.0, 0.5, 6, 10);
    let big = turned_and_scaled(&rest);
    let box_ratio = big.bounding_box_diagonal() / rest.bounding_box_diagonal();
    assert!(
        (box_ratio - 7.5).abs() > 0.1,
        "the box changes: {box_ratio}"
    );
    let (a, b) = (dir.path().join("a.obj"), dir.path().join("b.obj"));
    write(&a, &rest);
    write(&b, &big);
    let out = dir.path().join("out");
    let report = json(&succeeds(&interpolate_keys(
        &[a, b],
        &out,
        &["--frames", "2", "--json"],
    )));
    let said = "is 7.500 times the size of";
    let warnings = report["warnings"].to_string();
    assert!(warnings.contains(said), "{warnings}");
    // A transfer's pose against the source reference.
    let rig = Rig::new();
    let pose = rig.path("big-pose.obj");
    write(&pose, &turned_and_scaled(&read(&rig.source_ref)));
    let out = rig.path("out");
    let markers = [os("--markers"), rig.markers.as_os_str(), os("--json")];
    let report = json(&succeeds(&rig.transfer(&out, &markers, &[pose])));
    let warnings = report["warnings"].to_string();
    assert!(warnings.contains(said), "{warnings}");
}

#[test]
fn a_failed_run_with_json_prints_one_json_error() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.obj");
    let out = dir.path().join("out");
    let (m, o, b) = (
        shown(&missing),
        shown(&out),
        shown(&dir.path().join("b.obj")),
    );
    let runs: [Vec<&str>; 3] = [
        vec!["interpolate", &m, &m, "-o", &o, "--json"],
        vec!["blend", &m, "--shape", "x.obj=1", "-o", &b, "--json"],
        vec!["interpolate", &m, &m, "-o", &o],
    ];
    for (k, args) in runs.iter().enumerate() {
        let result = run(args);
        let err = fails(&result);
        assert_mentions(&err, &[&m]);
        if k < 2 {
            let report = json(&stdout(&result));
            let message = report["error"].as_str().unwrap();
            assert_eq!(format!("error: {message}\n"), err);
            assert_eq!(uint(&report, "exit_status"), 1);
        } else {
            assert_eq!(stdout(&result), "", "no JSON without --json");
        }
    }
}

/// A folder no file can be created in: a read-only one, or where the tests
/// run as root (who may write anywhere) on Linux, `/proc`. None elsewhere.
fn unwritable_folder(dir: &Path) -> Option<PathBuf> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        let ro = dir.join("ro");
        fs::create_dir(&ro).unwrap();
        fs::set_permissions(&ro, fs::Permissions::from_mode(0o555)).unwrap();
        if fs::write(ro.join("probe"), "").is_err() {
            return Some(ro);
        }
        fs::remove_file(ro.join("probe")).unwrap();
    }
    let proc = Path::new("/proc");
    (proc.is_dir() && fs::write(proc.join("meshmorph-probe"), "").is_err())
        .then(|| proc.to_path_buf())
}

#[test]
fn an_output_folder_that_cannot_be_written_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let Some(ro) = unwritable_folder(dir.path()) else {
        eprintln!("skipped: no folder here refuses new files");
        return;
    };
    // Keys that do not parse: a run that read them would say so instead.
    let (a, b) = (dir.path().join("a.obj"), dir.path().join("b.obj"));
    fs::write(&a, "v 0 0 0\nv 1 0 0\nv x 1 0\nf 1 2 3\n").unwrap();
    fs::write(&b, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = dir.path().join("frames");
    let gif = ro.join("a.gif");
    let (a_, b_, o, g) = (shown(&a), shown(&b), shown(&out), shown(&gif));
    for extra in [
        ["--gif", &g],
        ["--png", &g.replace(".gif", ".png")],
        ["--gltf", &g.replace(".gif", ".glb")],
    ] {
        let mut args = vec!["interpolate", &a_, &b_, "-o", &o];
        args.extend(extra);
        let err = fails(&run(&args));
        assert_mentions(&err, &[extra[1], &shown(&ro), "does not take new files"]);
        assert!(!err.contains(".meshmorph-"), "a temporary name: {err}");
        assert!(!err.contains("line 3"), "the keys were read first: {err}");
        assert!(!out.exists(), "the frame folder it created stays");
    }
    // The frames' own folder, and transfer's saved correspondence.
    let err = fails(&run([
        "interpolate",
        &a_,
        &b_,
        "-o",
        &shown(&ro.join("sub")),
    ]));
    assert!(
        err.contains(&shown(&ro)) && !err.contains(".meshmorph-"),
        "{err}"
    );
    let save = ro.join("saved.corr");
    let err = fails(&run([
        "transfer",
        "--source-ref",
        &a_,
        "--target-ref",
        &b_,
        "--markers",
        &b_,
        "-o",
        &o,
        "--save-correspondence",
        &shown(&save),
        &a_,
    ]));
    assert_mentions(&err, &[&shown(&save), "does not take new files"]);
    assert!(!out.exists());
}

#[cfg(target_os = "linux")]
#[test]
fn staged_files_of_runs_killed_by_force_are_removed_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let p = Pair::bar();
    fs::create_dir_all(&p.out).unwrap();
    // A process that has ended, and one that runs (this test).
    let mut child = Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .arg("--version")
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let dead = child.id();
    child.wait().unwrap();
    let alive = std::process::id();
    // Staged outputs (named as before and with a run's random token), and
    // the second name of a file an output was replacing.
    let stale = [
        format!(".meshmorph-{dead}-0.part"),
        format!(".meshmorph-{dead}-x3kQ9ae2LmZp01Tb-17.part"),
        format!(".meshmorph-{dead}-x3kQ9ae2LmZp01Tb-3.old"),
    ];
    fs::write(p.out.join(&stale[0]), vec![0u8; 1500]).unwrap();
    fs::write(p.out.join(&stale[1]), vec![0u8; 500]).unwrap();
    fs::write(p.out.join(&stale[2]), b"").unwrap();
    let kept = [
        format!(".meshmorph-{alive}-0.part"),
        // Moved aside without a second name: perhaps the only copy.
        format!(".meshmorph-{dead}-x3kQ9ae2LmZp01Tb-4.aside"),
        ".meshmorph-7kUIk1.tmp".to_string(),
        format!(".meshmorph-{dead}-0.part.bak"),
        format!("meshmorph-{dead}-0.part"),
        "notes.txt".to_string(),
    ];
    for name in &kept {
        fs::write(p.out.join(name), "keep").unwrap();
    }
    // Named like a staged file but a folder, or a link: not a staged file.
    fs::create_dir(p.out.join(format!(".meshmorph-{dead}-1.part"))).unwrap();
    let target = dir.path().join("elsewhere.txt");
    fs::write(&target, "keep").unwrap();
    std::os::unix::fs::symlink(&target, p.out.join(format!(".meshmorph-{dead}-2.part"))).unwrap();
    let report = json(&succeeds(&p.interpolate(&["--frames", "2", "--json"])));
    let warnings = report["warnings"].to_string();
    assert_mentions(
        &warnings,
        &[
            "removed 3 unfinished outputs (2.0 kB)",
            &shown(&p.out),
            &format!(".meshmorph-{dead}-x3kQ9ae2LmZp01Tb-4.aside"),
            "moved aside",
        ],
    );
    let left = names(&p.out);
    for name in &stale {
        assert!(!left.contains(name), "{name} stays: {left:?}");
    }
    for name in &kept {
        assert_eq!(
            fs::read_to_string(p.out.join(name)).unwrap(),
            "keep",
            "{name}"
        );
    }
    assert!(p.out.join(format!(".meshmorph-{dead}-1.part")).is_dir());
    assert_eq!(fs::read_to_string(&target).unwrap(), "keep");
    assert!(fs::symlink_metadata(p.out.join(format!(".meshmorph-{dead}-2.part"))).is_ok());
    // A second run finds nothing to remove.
    let report = json(&succeeds(&p.interpolate(&["--frames", "2", "--json"])));
    assert!(
        !report["warnings"].to_string().contains("removed"),
        "{report}"
    );
}

#[test]
fn interpolation_and_blend_glbs_are_named_after_the_first_key() {
    let dir = tempfile::tempdir().unwrap();
    let rest = tube(2.0, 0.5, 5, 8);
    let (a, b) = (
        dir.path().join("Körper rest.obj"),
        dir.path().join("bent.obj"),
    );
    write(&a, &rest);
    write(&b, &bend(&rest, 2.0, 1.0));
    let (frames_glb, blend_glb) = (dir.path().join("frames.glb"), dir.path().join("blend.glb"));
    let out = dir.path().join("out");
    succeeds(&interpolate_keys(
        &[a.clone(), b.clone()],
        &out,
        &["--frames", "3", "--gltf", &shown(&frames_glb)],
    ));
    succeeds(&blend(
        &a,
        &[(&b, "0.5")],
        &dir.path().join("blend.obj"),
        &["--gltf", &shown(&blend_glb)],
    ));
    for glb in [&frames_glb, &blend_glb] {
        let file = gltf::Gltf::open(glb).unwrap();
        let meshes: Vec<_> = file
            .meshes()
            .map(|m| m.name().map(str::to_string))
            .collect();
        let nodes: Vec<_> = file.nodes().map(|n| n.name().map(str::to_string)).collect();
        assert_eq!(
            meshes,
            [Some("Körper rest".to_string())],
            "{}",
            glb.display()
        );
        assert_eq!(
            nodes,
            [Some("Körper rest".to_string())],
            "{}",
            glb.display()
        );
    }
}

#[test]
fn correspond_without_markers_fits_references_that_stand_alike_and_refuses_others() {
    let rig = Rig::new();
    let no_markers = |corr: &Path, target: &Path| {
        run([
            os("correspond"),
            os("--source-ref"),
            rig.source_ref.as_os_str(),
            os("--target-ref"),
            target.as_os_str(),
            os("-o"),
            corr.as_os_str(),
            os("--no-markers"),
            os("--json"),
        ])
    };
    // A larger, moved copy of the source, denser: the same way up.
    let alike_mesh = thin_tube();
    let alike: Vec<[f64; 3]> = alike_mesh
        .positions()
        .iter()
        .map(|p| [3.0 * p[0] + 1.0, 3.0 * p[1] - 2.0, 3.0 * p[2]])
        .collect();
    let alike_path = rig.path("alike.obj");
    write(
        &alike_path,
        &alike_mesh.with_positions(alike.clone()).unwrap(),
    );
    let corr = rig.path("alike.corr");
    let report = json(&succeeds(&no_markers(&corr, &alike_path)));
    assert!(uint(&report, "matched_pairs") > 0, "{report}");
    assert!(fs::read_to_string(&corr)
        .unwrap()
        .starts_with("meshmorph-correspondence"));
    // The same copy lying across the source: refused, nothing written.
    let across: Vec<[f64; 3]> = alike.iter().map(|p| [-p[1], p[0], p[2]]).collect();
    let across_path = rig.path("across.obj");
    write(&across_path, &alike_mesh.with_positions(across).unwrap());
    let refused = rig.path("across.corr");
    let out = no_markers(&refused, &across_path);
    fails(&out);
    assert_mentions(
        &stderr(&out),
        &[
            "without markers",
            "found no partner",
            "give at least 3 markers",
        ],
    );
    assert!(!refused.exists());
    // --no-markers with --markers is a usage error.
    let out = rig.correspond(&rig.path("both.corr"), &[os("--no-markers")]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_mentions(&stderr(&out), &["--no-markers", "--markers"]);
}
