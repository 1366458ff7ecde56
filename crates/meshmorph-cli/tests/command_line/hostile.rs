//! The catalogue of hostile inputs and argument combinations: every
//! command and format, each case with its expected outcome.
//!
//! Every case runs the `meshmorph` binary in a fresh copy of one folder of
//! small inputs (planar strips, two tubes, markers, poses, a saved
//! correspondence) and checks, besides its own exit status and message:
//! no panic; no message naming a temporary file; every file that was there
//! before is byte for byte unchanged (unless the case expects it to be
//! replaced or removed); a failed run adds no file or folder; no temporary
//! file remains anywhere.

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use meshmorph::io::{read_mesh, write_mesh, Format};
use meshmorph::shapes::{bend, curl, nearest_vertex_pairs, strip, tube};

/// One row of the catalogue.
struct Case {
    name: &'static str,
    /// Changes to the standard folder before the run.
    setup: fn(&Path),
    args: &'static [&'static str],
    /// Exit status: 0 success, 1 refused by meshmorph, 2 refused by the
    /// argument parser.
    code: i32,
    /// Fragments of stderr (failures) or stdout (successes).
    says: &'static [&'static str],
    /// Files (relative) a successful run may replace or remove.
    may_change: &'static [&'static str],
    /// More checks after the run.
    after: fn(&Path),
}

const NONE: fn(&Path) = |_| {};

/// A case with no setup, nothing that may change and no extra check.
const fn case(
    name: &'static str,
    args: &'static [&'static str],
    code: i32,
    says: &'static [&'static str],
) -> Case {
    Case {
        name,
        setup: NONE,
        args,
        code,
        says,
        may_change: &[],
        after: NONE,
    }
}

const fn with_setup(mut c: Case, setup: fn(&Path)) -> Case {
    c.setup = setup;
    c
}

const fn with_after(mut c: Case, after: fn(&Path)) -> Case {
    c.after = after;
    c
}

const fn may_change(mut c: Case, files: &'static [&'static str]) -> Case {
    c.may_change = files;
    c
}

// ---------------------------------------------------------------------------
// The standard folder.

/// The inputs every case starts from, made once.
fn template() -> &'static Path {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        base_files(d);
        let thin = read_mesh(&d.join("thin.obj")).unwrap();
        for (k, turn) in [0.2, 0.5].iter().enumerate() {
            let pose = bend(&thin, 2.0, turn * PI);
            write_mesh(&d.join(format!("pose{}.obj", k + 1)), &pose, Format::Obj).unwrap();
        }
        dir
    })
    .path()
}

/// The files every hostile catalogue starts from: a bar and its curl
/// (`src`/`dst` in OBJ, PLY and OFF), a thin and a thick tube with markers
/// between them, and their correspondence `c.corr`.
pub(super) fn base_files(d: &Path) {
    let bar = strip(4.0, 0.5, 8, 2);
    let curled = curl(&bar, PI);
    write_mesh(&d.join("src.obj"), &bar, Format::Obj).unwrap();
    write_mesh(&d.join("dst.obj"), &curled, Format::Obj).unwrap();
    write_mesh(&d.join("src.ply"), &bar, Format::Ply).unwrap();
    write_mesh(&d.join("dst.off"), &curled, Format::Off).unwrap();
    let thin = tube(2.0, 0.25, 7, 8);
    let thick = tube(2.0, 0.5, 5, 10);
    write_mesh(&d.join("thin.obj"), &thin, Format::Obj).unwrap();
    write_mesh(&d.join("thick.obj"), &thick, Format::Obj).unwrap();
    let widened: Vec<[f64; 3]> = thin
        .positions()
        .iter()
        .map(|p| [p[0], 2.0 * p[1], 2.0 * p[2]])
        .collect();
    let chosen: Vec<u32> = [0u32, 3, 6]
        .iter()
        .flat_map(|&r| [0, 2, 4, 6].map(|s| r * 8 + s))
        .collect();
    let pairs = nearest_vertex_pairs(&widened, thick.positions(), &chosen);
    let text: String = pairs.iter().map(|[s, t]| format!("{s} {t}\n")).collect();
    fs::write(d.join("markers.txt"), text).unwrap();
    let out = meshmorph(
        d,
        &[
            "correspond",
            "--source-ref",
            "thin.obj",
            "--target-ref",
            "thick.obj",
            "--markers",
            "markers.txt",
            "-o",
            "c.corr",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs every case of a catalogue on two threads (`run` gives each
/// failure's description) and fails with all the failures at once.
pub(super) fn run_catalogue<C: Sync>(cases: &[C], run: fn(&C) -> Result<(), String>, what: &str) {
    let failures: Vec<String> = std::thread::scope(|s| {
        let chunks: Vec<_> = cases
            .chunks(cases.len().div_ceil(2))
            .map(|chunk| {
                s.spawn(move || {
                    chunk
                        .iter()
                        .filter_map(|c| run(c).err())
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        chunks.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n\n")
    );
    println!("{} {what} cases passed", cases.len());
}

fn meshmorph(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the meshmorph binary runs")
}

/// Every file and folder under `dir`, with the bytes of the files.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Option<Vec<u8>>> {
    let mut all = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let rel = p.strip_prefix(dir).unwrap().to_path_buf();
            let meta = fs::symlink_metadata(&p).unwrap();
            if meta.is_dir() {
                all.insert(rel, None);
                stack.push(p);
            } else {
                all.insert(rel, Some(fs::read(&p).unwrap_or_default()));
            }
        }
    }
    all
}

fn copy_dir(from: &Path, to: &Path) {
    for e in fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

fn run_case(c: &Case) -> Result<(), String> {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    copy_dir(template(), d);
    (c.setup)(d);
    let before = snapshot(d);
    let out = meshmorph(d, c.args);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let after = snapshot(d);
    let fail = |what: String| {
        Err(format!(
            "{}: {what}\nargs: {:?}\nstatus: {:?}\nstdout:\n{stdout}\nstderr:\n{stderr}",
            c.name, c.args, out.status
        ))
    };
    if out.status.code() != Some(c.code) {
        return fail(format!("expected exit status {}", c.code));
    }
    if stderr.contains("panicked")
        || stderr.contains(".meshmorph-")
        || stdout.contains(".meshmorph-")
    {
        return fail("a panic or a temporary file's name in the output".into());
    }
    let text = if c.code == 0 { &stdout } else { &stderr };
    for s in c.says {
        if !text.contains(s) {
            return fail(format!("`{s}` missing"));
        }
    }
    for (path, bytes) in &before {
        let allowed = c.may_change.iter().any(|m| Path::new(m) == path);
        if !allowed && after.get(path) != Some(bytes) {
            return fail(format!("`{}` was changed or removed", path.display()));
        }
    }
    if let Some(p) = after
        .keys()
        .find(|p| p.to_string_lossy().contains(".meshmorph-"))
    {
        return fail(format!("temporary file `{}` remains", p.display()));
    }
    if c.code != 0 {
        if let Some(p) = after.keys().find(|p| !before.contains_key(*p)) {
            return fail(format!("a failed run left `{}`", p.display()));
        }
    }
    (c.after)(d);
    Ok(())
}

// ---------------------------------------------------------------------------
// Setups.

fn obj_with(d: &Path, name: &str, text: &str) {
    fs::write(d.join(name), text).unwrap();
}

fn append(d: &Path, name: &str, text: &str) {
    let mut s = fs::read_to_string(d.join(name)).unwrap();
    s.push_str(text);
    fs::write(d.join(name), s).unwrap();
}

fn prepend(d: &Path, name: &str, text: &str) {
    let s = fs::read(d.join(name)).unwrap();
    let mut v = text.as_bytes().to_vec();
    v.extend(s);
    fs::write(d.join(name), v).unwrap();
}

fn old_frames(d: &Path) {
    fs::create_dir(d.join("out")).unwrap();
    for k in 0..10 {
        fs::write(d.join(format!("out/frame_{k:04}.obj")), "old").unwrap();
    }
    fs::write(d.join("out/frame_0007.svg"), "old").unwrap();
    fs::write(d.join("out/notes.txt"), "mine").unwrap();
    fs::write(d.join("out/frame_0008.obj.bak"), "mine").unwrap();
    fs::write(d.join("out/frame_12.obj"), "mine").unwrap();
}

#[cfg(unix)]
fn symlink(d: &Path, target: &str, link: &str) {
    std::os::unix::fs::symlink(d.join(target), d.join(link)).unwrap();
}

fn hard_link(d: &Path, target: &str, link: &str) {
    fs::hard_link(d.join(target), d.join(link)).unwrap();
}

fn mkdir(d: &Path, name: &str) {
    fs::create_dir_all(d.join(name)).unwrap();
}

/// `to`: `from` with its first two faces swapped.
fn swap_faces(d: &Path, from: &str, to: &str) {
    let text = fs::read_to_string(d.join(from)).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    let faces: Vec<usize> = (0..lines.len())
        .filter(|&k| lines[k].starts_with("f "))
        .collect();
    lines.swap(faces[0], faces[1]);
    fs::write(d.join(to), lines.join("\n")).unwrap();
}

/// A planar sheet and the same sheet with one vertex pushed past its
/// neighbour (in space, the triangles between them fold back).
fn sheet_and_fold(d: &Path) {
    let sheet = strip(4.0, 1.0, 8, 4);
    let mut p = sheet.positions().to_vec();
    p[2 * 9 + 4][0] += 0.8;
    write_mesh(&d.join("sheet.obj"), &sheet, Format::Obj).unwrap();
    write_mesh(
        &d.join("folded.obj"),
        &sheet.with_positions(p).unwrap(),
        Format::Obj,
    )
    .unwrap();
}

/// The markers of `markers.txt` as points: MeshLab's picked points
/// `s.pp` and `t.pp` (named `m0`, `m1`, ...) and Wrap's `s.json` and
/// `t.json` (a corner of a triangle at each vertex).
fn point_files(d: &Path) {
    let pairs: Vec<[u32; 2]> = fs::read_to_string(d.join("markers.txt"))
        .unwrap()
        .lines()
        .map(|l| {
            let mut f = l.split_whitespace().map(|x| x.parse().unwrap());
            [f.next().unwrap(), f.next().unwrap()]
        })
        .collect();
    for (side, mesh, name) in [(0, "thin.obj", "s"), (1, "thick.obj", "t")] {
        let mesh = read_mesh(&d.join(mesh)).unwrap();
        let mut pp = String::from("<!DOCTYPE PickedPoints>\n<PickedPoints>\n <DocumentData/>\n");
        let mut wrap = Vec::new();
        for (k, pair) in pairs.iter().enumerate() {
            let v = pair[side];
            let p = mesh.positions()[v as usize];
            pp += &format!(
                " <point x=\"{:?}\" y=\"{:?}\" z=\"{:?}\" active=\"1\" name=\"m{k}\"/>\n",
                p[0], p[1], p[2]
            );
            let (t, tri) = mesh
                .triangles()
                .iter()
                .enumerate()
                .find(|(_, tri)| tri.contains(&v))
                .unwrap();
            let corner = tri.iter().position(|&c| c == v).unwrap();
            wrap.push(format!(
                "[{t}, {}, {}]",
                u32::from(corner == 0),
                u32::from(corner == 1)
            ));
        }
        fs::write(d.join(format!("{name}.pp")), pp + "</PickedPoints>\n").unwrap();
        fs::write(
            d.join(format!("{name}.json")),
            format!("[{}]", wrap.join(", ")),
        )
        .unwrap();
    }
}

/// [`point_files`], then `text` in place of `from` in `file`.
fn point_files_with(d: &Path, file: &str, from: &str, text: &str) {
    point_files(d);
    let s = fs::read_to_string(d.join(file)).unwrap();
    assert!(s.contains(from), "{from} not in {s}");
    fs::write(d.join(file), s.replacen(from, text, 1)).unwrap();
}

fn exists(d: &Path, name: &str) -> bool {
    d.join(name).exists()
}

// ---------------------------------------------------------------------------
// The catalogue.

const I: &str = "interpolate";
const B: &str = "blend";
const T: &str = "transfer";

#[rustfmt::skip]
fn catalogue() -> Vec<Case> {
    vec![
        // interpolate: outputs against inputs
        with_after(case("interpolate writes frames", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "3"], 0, &["wrote 3 frames"]),
            |d| assert!(exists(d, "out/frame_0002.obj") && !exists(d, "out/frame_0003.obj"))),
        case("--gif onto the source", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "src.obj"], 2, &["extension .gif"]),
        case("--gif onto the target", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "dst.obj"], 2, &["extension .gif"]),
        case("--gif onto a frame", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "3", "--gif", "out/frame_0001.obj"], 2, &["extension .gif"]),
        case("--gif onto a frame through ..", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "3", "--gif", "out/../out/frame_0002.obj"], 2, &["extension .gif"]),
        case("--gif onto the source through ..", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "out/../src.obj"], 2, &["extension .gif"]),
        with_setup(case("inputs in the output folder under frame names", &[I, "frame_0000.obj", "frame_0001.obj", "-o", ".", "--frames", "2"], 1, &["would overwrite the source mesh `frame_0000.obj`"]),
            |d| { fs::copy(d.join("src.obj"), d.join("frame_0000.obj")).unwrap(); fs::copy(d.join("dst.obj"), d.join("frame_0001.obj")).unwrap(); }),
        with_setup(case("an input is frame 1 of the output folder", &[I, "src.obj", "out/frame_0001.obj", "-o", "out", "--frames", "3"], 1, &["would overwrite the target mesh `out/frame_0001.obj`"]),
            |d| { mkdir(d, "out"); fs::copy(d.join("dst.obj"), d.join("out/frame_0001.obj")).unwrap(); }),
        #[cfg(unix)]
        with_setup(case("--gif onto a symbolic link to the source", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "link.gif"], 1, &["would overwrite the source mesh `src.obj`", "link.gif"]),
            |d| symlink(d, "src.obj", "link.gif")),
        #[cfg(unix)]
        with_setup(case("source through a symbolic link, frame onto it", &[I, "lnk/frame_0000.obj", "dst.obj", "-o", "out", "--frames", "2"], 1, &["would overwrite the source mesh"]),
            |d| { mkdir(d, "out"); fs::copy(d.join("src.obj"), d.join("out/frame_0000.obj")).unwrap(); std::os::unix::fs::symlink(d.join("out"), d.join("lnk")).unwrap(); }),
        with_setup(case("--gif onto a hard link of the source", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "hard.gif"], 1, &["would overwrite the source mesh `src.obj`", "hard.gif"]),
            |d| hard_link(d, "src.obj", "hard.gif")),
        with_setup(case("a frame slot is a hard link of the target", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "3"], 1, &["would overwrite the target mesh `dst.obj`"]),
            |d| { mkdir(d, "out"); hard_link(d, "dst.obj", "out/frame_0002.obj"); }),
        with_setup(case("a folder where a frame goes", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "3"], 1, &["`out/frame_0001.obj` is a folder"]),
            |d| mkdir(d, "out/frame_0001.obj")),
        with_setup(case("a folder where an SVG goes", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "3", "--svg"], 1, &["`out/frame_0002.svg` is a folder"]),
            |d| mkdir(d, "out/frame_0002.svg")),
        with_setup(case("a folder where the GIF goes", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "anim.gif"], 1, &["`anim.gif` is a folder"]),
            |d| mkdir(d, "anim.gif")),
        case("-o is a file", &[I, "src.obj", "dst.obj", "-o", "thin.obj"], 1, &["`thin.obj` is a file, not a folder"]),
        case("--gif inside a file", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "thin.obj/a.gif"], 1, &["`thin.obj` is a file, not a folder"]),
        case("a late failure (overflow at t = 1e308) leaves nothing", &[I, "src.obj", "dst.obj", "-o", "out", "--t", "0,1e308", "--svg"], 1, &["overflow"]),
        with_setup(case("a late failure keeps an earlier run's frames", &[I, "src.obj", "dst.obj", "-o", "out", "--t", "0,0.5,1e308"], 1, &["overflow"]),
            old_frames),
        // interpolate: reruns and surplus frames
        may_change(with_setup(with_after(case("a rerun with fewer frames removes the surplus", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "3"], 0, &["removed 8 frame files of an earlier run"]),
            |d| {
                assert!(exists(d, "out/frame_0002.obj") && !exists(d, "out/frame_0003.obj") && !exists(d, "out/frame_0007.svg"));
                assert!(exists(d, "out/notes.txt") && exists(d, "out/frame_0008.obj.bak") && exists(d, "out/frame_12.obj"));
                assert_ne!(fs::read(d.join("out/frame_0001.obj")).unwrap(), b"old");
            }), old_frames),
            &["out/frame_0000.obj", "out/frame_0001.obj", "out/frame_0002.obj", "out/frame_0003.obj", "out/frame_0004.obj", "out/frame_0005.obj", "out/frame_0006.obj", "out/frame_0007.obj", "out/frame_0008.obj", "out/frame_0009.obj", "out/frame_0007.svg"]),
        with_setup(with_after(case("surplus removal spares an input named like a frame", &[I, "out/frame_0005.obj", "dst.obj", "-o", "out", "--frames", "3"], 0, &["wrote 3 frames"]),
            |d| assert!(exists(d, "out/frame_0005.obj"))),
            |d| { mkdir(d, "out"); fs::copy(d.join("src.obj"), d.join("out/frame_0005.obj")).unwrap(); }),
        with_after(case("outputs into folders that do not exist yet", &[I, "src.obj", "dst.obj", "-o", "a/b/out", "--frames", "2", "--gif", "c/d/anim.gif"], 0, &["wrote 2 frames"]),
            |d| assert!(exists(d, "a/b/out/frame_0001.obj") && exists(d, "c/d/anim.gif"))),
        case("a failure removes the folders it created", &[I, "src.obj", "dst.obj", "-o", "a/b/out", "--t", "0,1e308"], 1, &["overflow"]),
        case("the same file as source and target", &[I, "src.obj", "src.obj", "-o", "out", "--frames", "2"], 0, &["wrote 2 frames"]),
        // interpolate: arguments
        case("--frames 0", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "0"], 2, &["at least 1 frame"]),
        case("--frames 100000000000", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "100000000000"], 2, &["too many"]),
        case("--frames u64::MAX", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "18446744073709551615"], 2, &["too many"]),
        case("--frames 1e40", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "1e40"], 2, &["not a whole number"]),
        case("--frames -3", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "-3"], 2, &[]),
        case("--t -0.5,0.5 extrapolates", &[I, "src.obj", "dst.obj", "-o", "out", "--t", "-0.5,0.5"], 0, &["wrote 2 frames"]),
        case("--t -1,-0.5 starts with a minus", &[I, "src.obj", "dst.obj", "-o", "out", "--t", "-1,-0.5"], 0, &["wrote 2 frames"]),
        case("--closest-weights nan", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "--closest-weights", "1,nan", "-o", "out", "pose1.obj"], 2, &["not a finite number"]),
        case("--identity-weight inf", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "--identity-weight", "inf", "-o", "out", "pose1.obj"], 2, &["not a finite number"]),
        case("--fps 1e-20 in a transfer", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "--gif", "a.gif", "--fps", "1e-20", "-o", "out", "pose1.obj"], 2, &["frame rate"]),
        case("--closest-weights -5,1", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "--closest-weights", "-5,1", "-o", "out", "pose1.obj"], 1, &["weight"]),
        case("--t -0 is a time", &[I, "src.obj", "dst.obj", "-o", "out", "--t", "-0"], 0, &["wrote 1 frame "]),
        case("--t with NaN", &[I, "src.obj", "dst.obj", "-o", "out", "--t", "0,NaN"], 2, &["not a finite number"]),
        case("--t with inf", &[I, "src.obj", "dst.obj", "-o", "out", "--t", "inf"], 2, &["not a finite number"]),
        case("--gif named .png", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "a.png"], 2, &["a.png", "extension .gif"]),
        case("--png named .gif", &[I, "src.obj", "dst.obj", "-o", "out", "--png", "a.gif"], 2, &["a.gif", "extension .png"]),
        case("--t 1e308 overflows", &[I, "src.obj", "dst.obj", "-o", "out", "--t", "1e308"], 1, &["(t = 1e308)", "extrapolate less far", "0 to 1"]),
        case("--t and --frames together", &[I, "src.obj", "dst.obj", "-o", "out", "--t", "0", "--frames", "3"], 2, &["cannot be used with"]),
        case("--turns -1", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "2", "--turns", "-1"], 0, &["wrote 2 frames"]),
        case("--gif-width 100000", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "a.gif", "--gif-width", "100000"], 2, &["100000"]),
        case("--gif-height 0", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "a.gif", "--gif-height", "0"], 2, &[]),
        case("--fps 0", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "a.gif", "--fps", "0"], 2, &["not a frame rate from 0.01 to 1000"]),
        case("--fps -5", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "a.gif", "--fps", "-5"], 2, &[]),
        case("--fps 1e-20", &[I, "src.obj", "dst.obj", "-o", "out", "--gif", "a.gif", "--fps", "1e-20"], 2, &["1e-20"]),
        case("--fps 1e50", &[I, "src.obj", "dst.obj", "-o", "out", "--gltf", "a.glb", "--fps", "1e50"], 2, &["1e50"]),
        case("--format xyz", &[I, "src.obj", "dst.obj", "-o", "out", "--format", "xyz"], 2, &["xyz"]),
        case("--stretch cubic", &[I, "src.obj", "dst.obj", "-o", "out", "--stretch", "cubic"], 2, &["cubic"]),
        // interpolate: bad files
        case("missing source", &[I, "nosuch.obj", "dst.obj", "-o", "out"], 1, &["nosuch.obj"]),
        case("a marker file is no drawing", &[I, "markers.txt", "dst.obj", "-o", "out"], 1, &["reading the source drawing `markers.txt`"]),
        case("unknown extension", &[I, "markers.cons", "dst.obj", "-o", "out"], 1, &["markers.cons", "unknown format", ".svg"]),
        with_setup(case("malformed OBJ line", &[I, "bad.obj", "dst.obj", "-o", "out"], 1, &["bad.obj", "line 2"]),
            |d| obj_with(d, "bad.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n")),
        with_setup(case("OBJ with a byte-order mark", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "2"], 0, &["wrote 2 frames"]),
            |d| { prepend(d, "src.obj", "\u{feff}"); prepend(d, "dst.obj", "\u{feff}"); }),
        with_setup(case("NaN coordinate", &[I, "nan.obj", "nan.obj", "-o", "out"], 1, &["nan.obj", "line 1", "not a finite number"]),
            |d| obj_with(d, "nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")),
        with_setup(case("coordinates near the largest number overflow", &[I, "big.obj", "big.obj", "-o", "out"], 1, &["overflow"]),
            |d| obj_with(d, "big.obj", "v 1e307 0 0\nv -1e307 0 0\nv 0 1e307 0\nf 1 2 3\n")),
        with_setup(case("an unused vertex far away changes nothing", &[I, "src.obj", "dst.obj", "-o", "out", "--frames", "2"], 0, &["wrote 2 frames", "unused vertices: 1"]),
            |d| { append(d, "src.obj", "v 1000000 1000000 0\n"); append(d, "dst.obj", "v 1000000 1000000 0\n"); }),
        with_setup(case("zero-area triangle", &[I, "flat.obj", "flat.obj", "-o", "out"], 1, &["degenerate", "face 1 (numbered from 1"]),
            |d| obj_with(d, "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")),
        case("different meshes", &[I, "src.obj", "thin.obj", "-o", "out"], 1, &["thin.obj"]),
        case("--dim 2 with a mesh that is not planar", &[I, "thin.obj", "thin.obj", "-o", "out", "--dim", "2"], 1, &["not planar", "vertex", "thin.obj"]),
        with_setup(case("empty file", &[I, "empty.obj", "dst.obj", "-o", "out"], 1, &["empty.obj"]),
            |d| obj_with(d, "empty.obj", "")),
        with_setup(case("PLY with an absurd element count", &[I, "huge.ply", "dst.obj", "-o", "out"], 1, &["huge.ply", "too large"]),
            |d| obj_with(d, "huge.ply", "ply\nformat ascii 1.0\nelement vertex 18446744073709551615\nproperty float x\nproperty float y\nend_header\n")),
        with_setup(case("OFF with an absurd count", &[I, "huge.off", "dst.obj", "-o", "out"], 1, &["huge.off"]),
            |d| obj_with(d, "huge.off", "OFF\n18446744073709551615 1 0\n0 0 0\n")),
        with_setup(case("truncated binary PLY", &[I, "cut.ply", "dst.off", "-o", "out"], 1, &["cut.ply"]),
            |d| { let b = fs::read(d.join("src.ply")).unwrap(); fs::write(d.join("cut.ply"), &b[..b.len() - 7]).unwrap(); }),
        case("PLY source and OFF target", &[I, "src.ply", "dst.off", "-o", "out", "--frames", "2"], 0, &["wrote 2 frames"]),
        // transfer
        with_after(case("transfer with a saved correspondence", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "-o", "out", "pose1.obj", "pose2.obj"], 0, &["wrote 2 poses"]),
            |d| assert!(exists(d, "out/pose1.obj") && exists(d, "out/pose2.obj"))),
        case("pose outputs onto the poses", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "-o", ".", "pose1.obj"], 1, &["would overwrite the source pose `pose1.obj`"]),
        case("--save-correspondence onto the source reference", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "--save-correspondence", "thin.obj", "-o", "out", "pose1.obj"], 1, &["would overwrite the source reference `thin.obj`"]),
        case("--save-correspondence onto the markers", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "--save-correspondence", "markers.txt", "-o", "out", "pose1.obj"], 1, &["would overwrite the marker file `markers.txt`"]),
        case("--save-correspondence onto a pose output", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "--save-correspondence", "out/pose1.obj", "-o", "out", "pose1.obj"], 1, &["are the same file", "out/pose1.obj"]),
        with_setup(case("a folder where a pose goes", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "--save-correspondence", "new.corr", "-o", "out", "pose1.obj", "pose2.obj"], 1, &["`out/pose2.obj` is a folder"]),
            |d| mkdir(d, "out/pose2.obj")),
        with_setup(case("a pose slot hard-linked to the target reference", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "-o", "out", "pose1.obj"], 1, &["would overwrite the target reference `thick.obj`"]),
            |d| { mkdir(d, "out"); hard_link(d, "thick.obj", "out/pose1.obj"); }),
        #[cfg(unix)]
        with_setup(case("a pose slot linked to the source reference", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "-o", "out", "pose1.obj"], 1, &["would overwrite the source reference `thin.obj`"]),
            |d| { mkdir(d, "out"); symlink(d, "thin.obj", "out/pose1.obj"); }),
        with_setup(case("a folder given as a pose", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "-o", "out", "poses"], 1, &["`poses`", "a folder, not a mesh file"]),
            |d| mkdir(d, "poses")),
        with_setup(case("two poses with one name", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "-o", "out", "pose1.obj", "b/pose1.obj"], 1, &["are both named `pose1`", "pose1.obj", "b/pose1.obj"]),
            |d| { mkdir(d, "b"); fs::copy(d.join("pose1.obj"), d.join("b/pose1.obj")).unwrap(); }),
        case("--pin 3,-1", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "--pin", "3,-1", "-o", "out", "pose1.obj"], 2, &["-1 is not a vertex index"]),
        case("--pin beyond the target", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "--pin", "99999", "-o", "out", "pose1.obj"], 1, &["--pin 99999"]),
        case("--pin 0 holds a vertex", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "--pin", "0", "-o", "out", "pose1.obj"], 0, &["wrote 1 pose "]),
        case("--smoothness-weight -1", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "--smoothness-weight", "-1", "-o", "out", "pose1.obj"], 1, &["weight"]),
        case("--closest-weights with a negative weight", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "--closest-weights", "1,-5", "-o", "out", "pose1.obj"], 1, &["weight"]),
        case("--markers and --correspondence together", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "--correspondence", "c.corr", "-o", "out", "pose1.obj"], 2, &["cannot be used with"]),
        case("neither markers nor a correspondence", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "-o", "out", "pose1.obj"], 1, &["--markers is required"]),
        with_setup(case("markers with a byte-order mark", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "-o", "out", "pose1.obj"], 0, &["wrote 1 pose "]),
            |d| prepend(d, "markers.txt", "\u{feff}")),
        with_setup(case("markers out of range", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "m.txt", "-o", "out", "pose1.obj"], 1, &["m.txt", "line 2"]),
            |d| obj_with(d, "m.txt", "0 0\n5000 1\n")),
        with_setup(case("a malformed marker line", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "m.txt", "-o", "out", "pose1.obj"], 1, &["m.txt", "line 1"]),
            |d| obj_with(d, "m.txt", "0 zero\n")),
        with_setup(case("a negative marker index", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "m.txt", "-o", "out", "pose1.obj"], 1, &["m.txt", "line 1"]),
            |d| obj_with(d, "m.txt", "-1 3\n")),
        with_setup(case("a correspondence with a byte-order mark", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "-o", "out", "pose1.obj"], 0, &["wrote 1 pose "]),
            |d| prepend(d, "c.corr", "\u{feff}")),
        with_setup(case("a truncated correspondence", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "cut.corr", "-o", "out", "pose1.obj"], 1, &["cut.corr"]),
            |d| { let s = fs::read_to_string(d.join("c.corr")).unwrap(); fs::write(d.join("cut.corr"), &s[..s.len() / 2]).unwrap(); }),
        case("a correspondence of other meshes", &[T, "--source-ref", "thin.obj", "--target-ref", "src.obj", "--correspondence", "c.corr", "-o", "out", "pose1.obj"], 1, &["c.corr"]),
        case("a pose of another mesh", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "-o", "out", "pose1.obj", "thick.obj"], 1, &["thick.obj", "does not fit"]),
        case("a missing pose", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "-o", "out", "pose1.obj", "nosuch.obj"], 1, &["nosuch.obj"]),
        case("--format ply", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "--format", "ply", "-o", "out", "pose1.obj"], 0, &["wrote 1 pose "]),
        // correspond
        case("correspond -o onto the source reference", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "-o", "thin.obj"], 1, &["would overwrite the source reference `thin.obj`"]),
        case("correspond -o onto the markers", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "-o", "markers.txt"], 1, &["would overwrite the marker file"]),
        case("--deformed-source equal to -o", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "-o", "x.obj", "--deformed-source", "x.obj"], 1, &["are the same file"]),
        case("--deformed-source onto the target", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "-o", "x.corr", "--deformed-source", "thick.obj"], 1, &["would overwrite the target reference"]),
        case("--deformed-source with an unknown extension", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "-o", "x.corr", "--deformed-source", "fit.xyz"], 1, &["fit.xyz"]),
        with_after(case("--deformed-source into a missing folder", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "-o", "x.corr", "--deformed-source", "new/fit.obj"], 0, &["saved to x.corr"]),
            |d| assert!(exists(d, "new/fit.obj") && exists(d, "x.corr"))),
        case("correspond without markers", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "-o", "x.corr"], 1, &["--markers is required"]),
        may_change(case("correspond replaces its own earlier output", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "-o", "c.corr"], 0, &["saved to c.corr"]), &["c.corr"]),
        with_setup(case("target with an unused vertex", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "-o", "x.corr"], 0, &["saved to x.corr"]),
            |d| append(d, "thick.obj", "v 10 10 10\n")),
        with_setup(case("transfer onto a target with an unused vertex", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "-o", "out", "pose1.obj"], 0, &["wrote 1 pose ", "unused target vertices: 1"]),
            |d| append(d, "thick.obj", "v 10 10 10\n")),
        case("--gltf onto the source", &[I, "src.obj", "dst.obj", "-o", "out", "--gltf", "src.obj"], 2, &["extension .glb"]),
        case("--gltf equal to --gif", &[I, "src.obj", "dst.obj", "-o", "out", "--gltf", "a.glb", "--gif", "a.glb"], 2, &["extension .gif"]),
        case("transfer --png onto the target reference", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "--png", "thick.obj", "-o", "out", "pose1.obj"], 2, &["extension .png"]),
        case("transfer --gif onto a pose output", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "--gif", "out/pose1.obj", "-o", "out", "pose1.obj"], 2, &["extension .gif"]),
        case("correspond --png onto the markers", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "-o", "x.corr", "--png", "markers.txt"], 2, &["extension .png"]),
        with_after(case("transfer writes its GLB and pictures", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "--gltf", "p/poses.glb", "--png", "p/poses.png", "--gif", "p/poses.gif", "-o", "out", "pose1.obj", "pose2.obj"], 0, &["wrote 2 poses"]),
            |d| assert!(exists(d, "p/poses.glb") && exists(d, "p/poses.png") && exists(d, "p/poses.gif"))),
        // markers as points of the surfaces
        with_setup(case("markers as MeshLab picked points", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "s.pp", "--markers", "t.pp", "-o", "x.corr"], 0, &["saved to x.corr", "snapped to the surface, moved at most 0.000 %"]),
            point_files),
        with_setup(case("markers as Wrap points", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "s.json", "--markers", "t.json", "-o", "out", "pose1.obj"], 0, &["wrote 1 pose "]),
            point_files),
        with_setup(case("a picked point named on one side only", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "s.pp", "--markers", "t.pp", "-o", "x.corr"], 1, &["`s.pp`, line 6", "`m2`", "no point of that name in `t.pp`"]),
            |d| point_files_with(d, "t.pp", "name=\"m2\"", "name=\"nose\"")),
        with_setup(case("a name given twice", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "s.pp", "--markers", "t.pp", "-o", "x.corr"], 1, &["`s.pp`, line 6", "`m0` is given twice"]),
            |d| point_files_with(d, "s.pp", "name=\"m2\"", "name=\"m0\"")),
        with_setup(case("a picked point far from the surface", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "s.pp", "--markers", "t.pp", "-o", "out", "pose1.obj"], 1, &["`s.pp`, line 4 (`m0`)", "from the source mesh's surface", "within 2 %"]),
            |d| point_files_with(d, "s.pp", "point x=\"", "point x=\"9")),
        with_setup(case("unnamed point files of other lengths", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "s.json", "--markers", "t.json", "-o", "x.corr"], 1, &["`s.json`", "12 points here and 11 in `t.json`"]),
            |d| point_files_with(d, "t.json", "[[0, 1, 0], ", "[")),
        with_setup(case("a Wrap triangle out of range", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "s.json", "--markers", "t.json", "-o", "x.corr"], 1, &["`t.json`, point 1", "target triangle 999990 is out of range (the target has 100 triangles)"]),
            |d| point_files_with(d, "t.json", "[[", "[[99999")),
        with_setup(case("Wrap barycentrics outside the triangle", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "s.json", "--markers", "t.json", "-o", "x.corr"], 1, &["`s.json`", "point 1", "outside its triangle"]),
            |d| point_files_with(d, "s.json", "[[0, ", "[[0, 3")),
        with_setup(case("barycentrics that do not sum to 1", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "m.txt", "-o", "out", "pose1.obj"], 1, &["`m.txt`, line 2", "sum to 1.5, not 1"]),
            |d| obj_with(d, "m.txt", "0 0\nv 1 t 2 0.5 0.5 0.5\n")),
        with_setup(case("two markers on one point with different partners", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "m.txt", "-o", "x.corr"], 1, &["`m.txt`, line 3", "two markers on one source point with different partners"]),
            |d| obj_with(d, "m.txt", "0 0\n8 3\nv 0 t 0 0.5 0.25 0.25\n16 20\n")),
        with_setup(case("a picked-points file alone", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "s.pp", "-o", "x.corr"], 1, &["s.pp", "holds the points of one mesh"]),
            point_files),
        case("a mesh given to --markers", &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "-o", "out", "--markers", "markers.txt", "--markers", "pose1.obj", "pose2.obj"], 1, &["`pose1.obj` given to --markers is a mesh"]),
        case("three marker files", &["correspond", "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "markers.txt", "--markers", "markers.txt", "--markers", "markers.txt", "-o", "x.corr"], 1, &["--markers is given 3 times"]),
        // interpolate: keys, surfaces in space
        with_after(case("three keys in space", &[I, "thin.obj", "pose1.obj", "pose2.obj", "-o", "out", "--frames", "3"], 0, &["wrote 3 frames", "in space, 3 keys", "throughput:"]),
            |d| assert!(exists(d, "out/frame_0002.obj"))),
        case("a key of another mesh", &[I, "thin.obj", "pose1.obj", "thick.obj", "-o", "out"], 1, &["thick.obj", "thin.obj", "vertices"]),
        with_setup(case("a key with other triangles", &[I, "thin.obj", "pose1.obj", "swapped.obj", "-o", "out"], 1, &["swapped.obj", "face"]),
            |d| swap_faces(d, "pose2.obj", "swapped.obj")),
        case("--turns with keys in space", &[I, "thin.obj", "pose1.obj", "-o", "out", "--turns", "1"], 1, &["--turns", "two planar keys only"]),
        case("--turns with three planar keys", &[I, "src.obj", "dst.obj", "src.obj", "-o", "out", "--turns", "1"], 1, &["--turns"]),
        case("--svg with keys in space", &[I, "thin.obj", "pose1.obj", "-o", "out", "--svg"], 1, &["planar frames only"]),
        case("--dim 4", &[I, "thin.obj", "pose1.obj", "-o", "out", "--dim", "4"], 2, &["4"]),
        case("a single key", &[I, "thin.obj", "-o", "out"], 2, &[]),
        case("--gif onto a key", &[I, "thin.obj", "pose1.obj", "pose2.obj", "-o", "out", "--gif", "pose2.obj"], 2, &["extension .gif"]),
        case("--png onto a key", &[I, "thin.obj", "pose1.obj", "-o", "out", "--png", "thin.obj"], 2, &["extension .png"]),
        with_setup(case("a key turned over in space", &[I, "sheet.obj", "folded.obj", "-o", "out", "--dim", "3"], 1, &["folded.obj", "turned over", "--allow-flips"]),
            sheet_and_fold),
        with_setup(case("a key turned over in space, --allow-flips", &[I, "sheet.obj", "folded.obj", "-o", "out", "--dim", "3", "--allow-flips", "--frames", "2"], 0, &["wrote 2 frames"]),
            sheet_and_fold),
        with_setup(case("degenerate first key in space", &[I, "flat3.obj", "flat3.obj", "-o", "out"], 1, &["degenerate", "flat3.obj"]),
            |d| obj_with(d, "flat3.obj", "v 0 0 0\nv 1 0 1\nv 2 0 2\nv 0 1 1\nf 1 2 3\nf 1 2 4\n")),
        case("--t with NaN over keys in space", &[I, "thin.obj", "pose1.obj", "pose2.obj", "-o", "out", "--t", "0,NaN"], 2, &["not a finite number"]),
        with_after(case("three keys in space with every picture", &[I, "thin.obj", "pose1.obj", "pose2.obj", "-o", "out", "--frames", "3", "--gif", "p/a.gif", "--png", "p/a.png", "--gltf", "p/a.glb"], 0, &["wrote 3 frames"]),
            |d| assert!(exists(d, "p/a.gif") && exists(d, "p/a.png") && exists(d, "p/a.glb"))),
        // blend
        with_after(case("blend with negative weights", &[B, "thin.obj", "--shape", "pose1.obj=1.3", "--shape", "pose2.obj=-0.2", "-o", "b.obj"], 0, &["wrote b.obj"]),
            |d| assert!(exists(d, "b.obj"))),
        case("blend onto the base", &[B, "thin.obj", "--shape", "pose1.obj=0.5", "-o", "thin.obj"], 1, &["would overwrite the base mesh `thin.obj`"]),
        case("blend --png onto a shape", &[B, "thin.obj", "--shape", "pose1.obj=0.5", "-o", "b.obj", "--png", "pose1.obj"], 2, &["extension .png"]),
        case("blend --gltf equal to --gif", &[B, "thin.obj", "--shape", "pose1.obj=0.5", "-o", "b.obj", "--gif", "a.glb", "--gltf", "a.glb"], 2, &["extension .gif"]),
        case("blend output named for another format", &[B, "thin.obj", "--shape", "pose1.obj=0.5", "-o", "b.ply", "--format", "off"], 1, &["b.ply", "named as ply", "--format asks for off"]),
        case("blend --gif named .png", &[B, "thin.obj", "--shape", "pose1.obj=0.5", "-o", "b.obj", "--gif", "b.png"], 2, &["extension .gif"]),
        case("blend weight NaN", &[B, "thin.obj", "--shape", "pose1.obj=NaN", "-o", "b.obj"], 2, &["not a finite number"]),
        case("blend weight inf", &[B, "thin.obj", "--shape", "pose1.obj=inf", "-o", "b.obj"], 2, &["not a finite number"]),
        case("blend shape without a weight", &[B, "thin.obj", "--shape", "pose1.obj", "-o", "b.obj"], 2, &["FILE=WEIGHT"]),
        case("blend without shapes", &[B, "thin.obj", "-o", "b.obj"], 2, &["--shape"]),
        case("blend a shape of another mesh", &[B, "thin.obj", "--shape", "thick.obj=1", "-o", "b.obj"], 1, &["thick.obj", "vertices"]),
        with_setup(case("blend a shape with other triangles", &[B, "thin.obj", "--shape", "pose1.obj=0.5", "--shape", "swapped.obj=0.5", "-o", "b.obj"], 1, &["swapped.obj", "face"]),
            |d| swap_faces(d, "pose2.obj", "swapped.obj")),
        with_setup(case("blend a shape turned over", &[B, "sheet.obj", "--shape", "folded.obj=1", "-o", "b.obj", "--dim", "3"], 1, &["folded.obj", "turned over", "--allow-flips"]),
            sheet_and_fold),
        case("blend an overflowing weight", &[B, "thin.obj", "--shape", "pose2.obj=1e300", "-o", "b.obj"], 1, &["overflow"]),
        case("blend a missing shape", &[B, "thin.obj", "--shape", "nosuch.obj=1", "-o", "b.obj"], 1, &["nosuch.obj"]),
        // demo
        case("demo -o onto a file", &["demo", "-o", "thin.obj"], 1, &["is a file, not a folder"]),
        case("an unknown command", &["morph"], 2, &["morph"]),
    ]
}

#[test]
fn hostile_catalogue() {
    let cases = catalogue();
    assert!(
        cases.len() >= 60,
        "the catalogue holds {} cases",
        cases.len()
    );
    run_catalogue(&cases, run_case, "hostile");
}
