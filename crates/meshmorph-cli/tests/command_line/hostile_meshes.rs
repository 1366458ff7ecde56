//! The catalogue of pathological meshes that are tiny on disk: one triangle
//! repeated tens of thousands of times, a book of thousands of triangles on
//! one edge, a million `f 1 2 3` lines. Each once took gigabytes and minutes
//! (every structure over the triangles around an edge held all their
//! pairs); each must now run, or be refused, as any mesh of its size.
//!
//! Every case runs the `meshmorph` binary in a fresh folder holding only its
//! own inputs, under an address-space limit where the command's own needs
//! allow one (so that a return of the quadratic growth fails the case
//! instead of filling the machine), and checks its exit status and message;
//! no panic; every input byte for byte unchanged; a successful run adds
//! files under its outputs only, a failed one adds nothing.

use super::hostile::run_catalogue;
use std::collections::BTreeMap;
use std::f64::consts::TAU;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// One row of the catalogue.
struct Case {
    name: &'static str,
    /// Writes the inputs into the case's folder.
    setup: fn(&Path),
    args: &'static [&'static str],
    /// Exit status: 0 success, 1 refused by meshmorph.
    code: i32,
    /// Fragments of stdout (successes) or stderr (failures).
    says: &'static [&'static str],
    /// Fragments of stderr of a success (its warnings).
    warns: &'static [&'static str],
    /// Where a successful run may add files (a file or a folder).
    outputs: &'static [&'static str],
    /// Address-space limit of the run, in KiB (`ulimit -v`), or none.
    limit_kib: Option<u64>,
}

/// Enough for the runs of the catalogue that allow a limit (they peak
/// below 60 MB of memory), far below what the quadratic growth took.
const LIMIT_KIB: Option<u64> = Some(1_000_000);

/// A successful run under [`LIMIT_KIB`].
const fn runs(
    name: &'static str,
    setup: fn(&Path),
    args: &'static [&'static str],
    says: &'static [&'static str],
    warns: &'static [&'static str],
    outputs: &'static [&'static str],
) -> Case {
    Case {
        name,
        setup,
        args,
        code: 0,
        says,
        warns,
        outputs,
        limit_kib: LIMIT_KIB,
    }
}

/// A refused run under [`LIMIT_KIB`].
const fn refused(
    name: &'static str,
    setup: fn(&Path),
    args: &'static [&'static str],
    says: &'static [&'static str],
) -> Case {
    Case {
        name,
        setup,
        args,
        code: 1,
        says,
        warns: &[],
        outputs: &[],
        limit_kib: LIMIT_KIB,
    }
}

/// The case without an address-space limit: the supernodal Cholesky
/// factorization of the correspondence reserves a large block of address
/// space per thread (faer's matrix products), whatever the mesh.
const fn unlimited(mut c: Case) -> Case {
    c.limit_kib = None;
    c
}

// ---------------------------------------------------------------------------
// The meshes.

/// A turn by 0.3 radians about the y axis and a shift, to make a second key
/// or a pose out of a mesh.
fn moved(p: [f64; 3]) -> [f64; 3] {
    let (s, c) = 0.3f64.sin_cos();
    [c * p[0] - s * p[2] + 0.5, p[1], s * p[0] + c * p[2]]
}

/// A turn by 0.3 radians about the z axis and a shift: [`moved`] that keeps
/// a planar mesh planar.
fn moved_in_plane(p: [f64; 3]) -> [f64; 3] {
    let (s, c) = 0.3f64.sin_cos();
    [c * p[0] - s * p[1] + 0.5, s * p[0] + c * p[1], p[2]]
}

fn obj(positions: &[[f64; 3]], faces: impl Iterator<Item = [usize; 3]>) -> String {
    let mut s = String::new();
    for p in positions {
        writeln!(s, "v {} {} {}", p[0], p[1], p[2]).unwrap();
    }
    for f in faces {
        writeln!(s, "f {} {} {}", f[0], f[1], f[2]).unwrap();
    }
    s
}

/// `a.obj` and `b.obj` (`a` turned): one triangle, with corners `corners`,
/// listed `n` times.
fn repeated(d: &Path, n: usize, corners: [[f64; 3]; 3]) {
    let faces = || std::iter::repeat_n([1, 2, 3], n);
    let turn = if corners.iter().all(|p| p[2] == 0.0) {
        moved_in_plane
    } else {
        moved
    };
    fs::write(d.join("a.obj"), obj(&corners, faces())).unwrap();
    fs::write(d.join("b.obj"), obj(&corners.map(turn), faces())).unwrap();
    fs::write(d.join("markers.txt"), "0 0\n1 1\n2 2\n").unwrap();
}

const IN_SPACE: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.2], [0.0, 1.0, 0.5]];
const FLAT: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// `a.obj` and `b.obj` (`a` turned): a book of `n` pages, every triangle on
/// the edge from vertex 1 to vertex 2 (its spine), each with its own third
/// vertex on a circle around the spine.
fn book(d: &Path, n: usize) {
    let mut p = vec![[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
    p.extend((0..n).map(|k| {
        let t = TAU * k as f64 / n as f64;
        [t.cos(), t.sin(), 0.5]
    }));
    let faces = || (0..n).map(|k| [1, 2, k + 3]);
    fs::write(d.join("a.obj"), obj(&p, faces())).unwrap();
    let turned: Vec<[f64; 3]> = p.iter().map(|&q| moved(q)).collect();
    fs::write(d.join("b.obj"), obj(&turned, faces())).unwrap();
    fs::write(d.join("markers.txt"), "0 0\n1 1\n2 2\n3 3\n7 7\n").unwrap();
}

fn copies_30000(d: &Path) {
    repeated(d, 30_000, IN_SPACE)
}

fn flat_copies_30000(d: &Path) {
    repeated(d, 30_000, FLAT)
}

fn copies_12000(d: &Path) {
    repeated(d, 12_000, IN_SPACE)
}

fn a_million_lines(d: &Path) {
    repeated(d, 1_000_000, IN_SPACE)
}

const ON_A_LINE: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];

/// A million `f 1 2 3` lines over three points on a line.
fn a_million_degenerate_lines(d: &Path) {
    repeated(d, 1_000_000, ON_A_LINE)
}

fn degenerate_copies_30000(d: &Path) {
    repeated(d, 30_000, ON_A_LINE)
}

fn book_20000(d: &Path) {
    book(d, 20_000)
}

// ---------------------------------------------------------------------------
// Running a case.

/// Every file under `dir`, with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut all = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).unwrap().to_path_buf();
                all.insert(rel, fs::read(&p).unwrap());
            }
        }
    }
    all
}

fn meshmorph(dir: &Path, args: &[&str], limit_kib: Option<u64>) -> std::process::Output {
    let bin = env!("CARGO_BIN_EXE_meshmorph");
    let mut command = match limit_kib {
        #[cfg(unix)]
        Some(kib) => {
            let mut c = Command::new("sh");
            c.arg("-c")
                .arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\""))
                .arg(bin);
            c
        }
        _ => Command::new(bin),
    };
    command
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the meshmorph binary runs")
}

fn run_case(c: &Case) -> Result<(), String> {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    (c.setup)(d);
    let before = snapshot(d);
    let out = meshmorph(d, c.args, c.limit_kib);
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
    if stderr.contains("panicked") {
        return fail("a panic".into());
    }
    let (text, other) = if c.code == 0 {
        (&stdout, &stderr)
    } else {
        (&stderr, &stdout)
    };
    for s in c.says {
        if !text.contains(s) {
            return fail(format!("`{s}` missing"));
        }
    }
    for s in c.warns {
        if !other.contains(s) {
            return fail(format!("warning `{s}` missing"));
        }
    }
    for (path, bytes) in &before {
        if after.get(path) != Some(bytes) {
            return fail(format!("input `{}` was changed or removed", path.display()));
        }
    }
    let is_output = |p: &Path| c.outputs.iter().any(|o| p.starts_with(o));
    if let Some(p) = after
        .keys()
        .find(|p| !before.contains_key(*p) && (c.code != 0 || !is_output(p)))
    {
        return fail(format!("the run added `{}`", p.display()));
    }
    if c.code == 0 && !c.outputs.iter().all(|o| d.join(o).exists()) {
        return fail("an output is missing".into());
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// The catalogue.

const I: &str = "interpolate";
const T: &str = "transfer";
const C: &str = "correspond";
const REPEATS: &str = "faces repeat the corners of another";
const SHARED: &str = "shared by more than two faces";

#[rustfmt::skip]
fn catalogue() -> Vec<Case> {
    vec![
        runs("12,000 copies of a triangle, interpolated", copies_12000, &[I, "a.obj", "b.obj", "-o", "out"],
            &["wrote 30 frames (3 vertices, 12000 triangles, in space"], &["11999 faces repeat"], &["out"]),
        runs("30,000 copies of a triangle, interpolated", copies_30000, &[I, "a.obj", "b.obj", "-o", "out"],
            &["wrote 30 frames (3 vertices, 30000 triangles, in space"], &["29999 faces repeat", SHARED], &["out"]),
        runs("30,000 copies of a triangle in the plane, interpolated", flat_copies_30000, &[I, "a.obj", "b.obj", "-o", "out"],
            &["wrote 30 frames (3 vertices, 30000 triangles, planar"], &[REPEATS], &["out"]),
        unlimited(runs("30,000 copies of a triangle, transferred onto themselves", copies_30000,
            &[T, "--source-ref", "a.obj", "--target-ref", "a.obj", "--markers", "markers.txt", "-o", "out", "b.obj"],
            &["wrote 1 pose", "unmatched:      0 source triangles, 0 target triangles"], &[REPEATS], &["out"])),
        unlimited(runs("30,000 copies of a triangle, corresponded", copies_30000,
            &[C, "--source-ref", "a.obj", "--target-ref", "a.obj", "--markers", "markers.txt", "-o", "c.corr"],
            &["saved to c.corr"], &[REPEATS], &["c.corr"])),
        runs("a book of 20,000 pages, interpolated", book_20000, &[I, "a.obj", "b.obj", "-o", "out"],
            &["wrote 30 frames (20002 vertices, 20000 triangles, in space"], &["1 edge is shared by more than two faces"], &["out"]),
        unlimited(runs("a book of 20,000 pages, transferred onto itself", book_20000,
            &[T, "--source-ref", "a.obj", "--target-ref", "a.obj", "--markers", "markers.txt", "-o", "out", "b.obj"],
            &["wrote 1 pose", "unmatched:      0 source triangles, 0 target triangles"], &[SHARED], &["out"])),
        unlimited(runs("a book of 20,000 pages, corresponded", book_20000,
            &[C, "--source-ref", "a.obj", "--target-ref", "a.obj", "--markers", "markers.txt", "-o", "c.corr"],
            &["saved to c.corr"], &[SHARED], &["c.corr"])),
        // As much memory as a million triangles of any mesh.
        unlimited(runs("a million `f 1 2 3` lines, interpolated", a_million_lines, &[I, "a.obj", "b.obj", "-o", "out", "--frames", "2"],
            &["wrote 2 frames (3 vertices, 1000000 triangles, in space"], &["999999 faces repeat"], &["out"])),
        refused("a million `f 1 2 3` lines on a line", a_million_degenerate_lines, &[I, "a.obj", "b.obj", "-o", "out"],
            &["1000000 degenerate (zero-area) triangles", "a.obj", "faces 1, 2, 3"]),
        refused("30,000 copies of a triangle on a line, corresponded", degenerate_copies_30000,
            &[C, "--source-ref", "a.obj", "--target-ref", "a.obj", "--markers", "markers.txt", "-o", "c.corr"],
            &["30000 degenerate (zero-area) triangles", "a.obj"]),
    ]
}

#[test]
fn hostile_mesh_catalogue() {
    let cases = catalogue();
    run_catalogue(&cases, run_case, "hostile mesh");
}
