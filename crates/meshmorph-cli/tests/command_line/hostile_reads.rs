//! The catalogue of hostile inputs to read: devices, FIFOs and folders
//! where files are expected (directly or through links, as meshes,
//! markers, correspondences, material libraries and textures), files far
//! larger than what they hold, textures past `--max-gltf-mb`, and files
//! that say more or other than their format allows.
//!
//! Every case runs the `meshmorph` binary in a fresh copy of one folder of
//! small inputs and checks, besides its own exit status and message: it
//! ends (a run that would wait on a FIFO or read a device for ever is
//! killed and reported); no panic; every file that was there before is
//! unchanged; a failed run adds no file or folder; no temporary file
//! remains. Nothing here reads a device or a FIFO itself: the folder is
//! compared without following links, and large (sparse) files by size.

#![cfg(unix)]

use super::hostile::run_catalogue;
use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// One row of the catalogue.
struct Case {
    name: &'static str,
    /// Changes to the standard folder before the run.
    setup: fn(&Path),
    args: &'static [&'static str],
    /// Exit status: 0 success, 1 refused by meshmorph.
    code: i32,
    /// Fragments of the output (stdout and stderr: warnings go to stderr
    /// on success too).
    says: &'static [&'static str],
}

const fn case(
    name: &'static str,
    setup: fn(&Path),
    args: &'static [&'static str],
    code: i32,
    says: &'static [&'static str],
) -> Case {
    Case {
        name,
        setup,
        args,
        code,
        says,
    }
}

/// How long a case may run before it is taken to hang (a debug build, two
/// cases at a time on a busy machine: generous; a run that waits on a
/// FIFO never ends).
const HANG: Duration = Duration::from_secs(120);

// ---------------------------------------------------------------------------
// The standard folder.

/// The inputs every case starts from, made once.
fn template() -> &'static Path {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        super::hostile::base_files(d);
        fs::copy(d.join("thin.obj"), d.join("pose.obj")).unwrap();
        // A textured quad and a bent copy, with a material library and
        // its texture (a PNG signature is all a GLB checks).
        let quad = |z: f64| {
            format!(
                "mtllib tex.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 {z}\nv 0 1 0\n\
                 vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl skin\nf 1/1 2/2 3/3 4/4\n"
            )
        };
        fs::write(d.join("tex.obj"), quad(0.0)).unwrap();
        fs::write(d.join("tex2.obj"), quad(0.25)).unwrap();
        fs::write(
            d.join("tex.mtl"),
            "newmtl skin\nKd 1 1 1\nmap_Kd skin.png\n",
        )
        .unwrap();
        fs::write(d.join("skin.png"), b"\x89PNG\r\n\x1a\nnot really").unwrap();
        dir
    })
    .path()
}

/// What is at a path, compared before and after a run without reading a
/// device, a FIFO or a large (sparse) file.
#[derive(Debug, PartialEq)]
enum Entry {
    Folder,
    Link(PathBuf),
    Fifo,
    Bytes(Vec<u8>),
    Large(u64),
    Other,
}

/// Every entry under `dir`, links not followed.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Entry> {
    use std::os::unix::fs::FileTypeExt;
    let mut all = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let rel = p.strip_prefix(dir).unwrap().to_path_buf();
            let meta = fs::symlink_metadata(&p).unwrap();
            let kind = meta.file_type();
            let entry = if kind.is_dir() {
                stack.push(p.clone());
                Entry::Folder
            } else if kind.is_symlink() {
                Entry::Link(fs::read_link(&p).unwrap())
            } else if kind.is_fifo() {
                Entry::Fifo
            } else if kind.is_file() && meta.len() > 1 << 20 {
                Entry::Large(meta.len())
            } else if kind.is_file() {
                Entry::Bytes(fs::read(&p).unwrap())
            } else {
                Entry::Other
            };
            all.insert(rel, entry);
        }
    }
    all
}

fn run_case(c: &Case) -> Result<(), String> {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("case");
    fs::create_dir(&d).unwrap();
    for e in fs::read_dir(template()).unwrap() {
        let e = e.unwrap();
        fs::copy(e.path(), d.join(e.file_name())).unwrap();
    }
    (c.setup)(&d);
    let before = snapshot(&d);
    // The output goes to files beside the folder, not into pipes that a
    // killed run could leave half read.
    let (out_path, err_path) = (dir.path().join("stdout"), dir.path().join("stderr"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .args(c.args)
        .current_dir(&d)
        .stdin(Stdio::null())
        .stdout(fs::File::create(&out_path).unwrap())
        .stderr(fs::File::create(&err_path).unwrap())
        .spawn()
        .expect("the meshmorph binary runs");
    let begin = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break Some(status);
        }
        if begin.elapsed() > HANG {
            child.kill().unwrap();
            child.wait().unwrap();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stdout = fs::read_to_string(&out_path).unwrap_or_default();
    let stderr = fs::read_to_string(&err_path).unwrap_or_default();
    let fail = |what: String| {
        Err(format!(
            "{}: {what}\nargs: {:?}\nstatus: {status:?}\nstdout:\n{stdout}\nstderr:\n{stderr}",
            c.name, c.args
        ))
    };
    let Some(status) = status else {
        return fail(format!("still running after {} s: killed", HANG.as_secs()));
    };
    if status.code() != Some(c.code) {
        return fail(format!("expected exit status {}", c.code));
    }
    if stderr.contains("panicked")
        || stderr.contains(".meshmorph-")
        || stdout.contains(".meshmorph-")
    {
        return fail("a panic or a temporary file's name in the output".into());
    }
    let text = format!("{stdout}\n{stderr}");
    for s in c.says {
        if !text.contains(s) {
            return fail(format!("`{s}` missing"));
        }
    }
    let after = snapshot(&d);
    for (path, entry) in &before {
        if after.get(path) != Some(entry) {
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
    Ok(())
}

// ---------------------------------------------------------------------------
// Setups.

fn nothing(_: &Path) {}

fn symlink(d: &Path, target: &str, link: &str) {
    std::os::unix::fs::symlink(target, d.join(link)).unwrap();
}

fn fifo(d: &Path, name: &str) {
    let status = Command::new("mkfifo").arg(d.join(name)).status().unwrap();
    assert!(status.success(), "mkfifo {name}");
}

/// A sparse file of `len` bytes (no disk used) beginning with `start`.
fn sparse(d: &Path, name: &str, start: &[u8], len: u64) {
    fs::write(d.join(name), start).unwrap();
    fs::OpenOptions::new()
        .write(true)
        .open(d.join(name))
        .unwrap()
        .set_len(len)
        .unwrap();
}

/// `to`: the correspondence `c.corr` with its alignment line's numbers
/// changed by `change`.
fn corr_with_alignment(d: &Path, to: &str, change: fn(&mut Vec<String>)) {
    let text = fs::read_to_string(d.join("c.corr")).unwrap();
    let lines: Vec<String> = text
        .lines()
        .map(|l| match l.strip_prefix("alignment ") {
            Some(values) => {
                let mut v: Vec<String> = values.split_whitespace().map(String::from).collect();
                change(&mut v);
                format!("alignment {}", v.join(" "))
            }
            None => l.to_string(),
        })
        .collect();
    assert!(lines.iter().any(|l| l.starts_with("alignment ")));
    fs::write(d.join(to), lines.join("\n") + "\n").unwrap();
}

fn append_bytes(d: &Path, from: &str, to: &str, extra: &[u8]) {
    let mut bytes = fs::read(d.join(from)).unwrap();
    bytes.extend_from_slice(extra);
    fs::write(d.join(to), bytes).unwrap();
}

// ---------------------------------------------------------------------------
// The catalogue.

const I: &str = "interpolate";
const T: &str = "transfer";

#[rustfmt::skip]
fn catalogue() -> Vec<Case> {
    vec![
        // Devices, FIFOs and folders as meshes.
        case("/dev/zero as a key", nothing, &[I, "/dev/zero", "src.obj", "-o", "out"], 1, &["`/dev/zero`", "a character device"]),
        case("/dev/urandom as a key", nothing, &[I, "src.obj", "/dev/urandom", "-o", "out"], 1, &["`/dev/urandom`", "a character device"]),
        case("/dev/zero through a link named .obj", |d| symlink(d, "/dev/zero", "zero.obj"), &[I, "zero.obj", "src.obj", "-o", "out"], 1, &["`zero.obj`", "a character device, not a regular file"]),
        case("/dev/urandom through a link named .stl", |d| symlink(d, "/dev/urandom", "noise.stl"), &[I, "noise.stl", "src.obj", "-o", "out"], 1, &["`noise.stl`", "a character device, not a regular file"]),
        case("/dev/zero through a link as a later key", |d| symlink(d, "/dev/zero", "zero.obj"), &[I, "src.obj", "zero.obj", "-o", "out"], 1, &["`zero.obj`", "a character device, not a regular file"]),
        case("/dev/zero through a link as a source pose", |d| symlink(d, "/dev/zero", "zero.obj"), &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "-o", "out", "zero.obj"], 1, &["`zero.obj`", "a character device"]),
        case("a FIFO as a key", |d| fifo(d, "pipe.obj"), &[I, "pipe.obj", "src.obj", "-o", "out"], 1, &["`pipe.obj`", "a FIFO (named pipe), not a regular file"]),
        case("a FIFO as a pose", |d| fifo(d, "pipe.obj"), &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "c.corr", "-o", "out", "pose.obj", "pipe.obj"], 1, &["`pipe.obj`", "a FIFO"]),
        case("a folder named like a mesh", |d| fs::create_dir(d.join("dir.obj")).unwrap(), &[I, "dir.obj", "src.obj", "-o", "out"], 1, &["`dir.obj`", "a folder, not a regular file"]),
        // Devices and FIFOs as the other inputs.
        case("a FIFO as the markers", |d| fifo(d, "pipe.txt"), &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "pipe.txt", "-o", "out", "pose.obj"], 1, &["`pipe.txt`", "a FIFO"]),
        case("/dev/zero through a link as the markers", |d| symlink(d, "/dev/zero", "zero.txt"), &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--markers", "zero.txt", "-o", "out", "pose.obj"], 1, &["`zero.txt`", "a character device"]),
        case("a FIFO as the correspondence", |d| fifo(d, "pipe.corr"), &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "pipe.corr", "-o", "out", "pose.obj"], 1, &["`pipe.corr`", "a FIFO"]),
        case("/dev/urandom as the correspondence", nothing, &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "/dev/urandom", "-o", "out", "pose.obj"], 1, &["`/dev/urandom`", "a character device"]),
        case("a FIFO as the material library", |d| { fs::remove_file(d.join("tex.mtl")).unwrap(); fifo(d, "tex.mtl"); }, &[I, "tex.obj", "tex2.obj", "-o", "out", "--frames", "2", "--gltf", "a.glb"], 0, &["wrote 2 frames", "tex.mtl`: ", "a FIFO", "not in the GLB"]),
        case("/dev/zero as the material library", |d| { fs::remove_file(d.join("tex.mtl")).unwrap(); symlink(d, "/dev/zero", "tex.mtl"); }, &[I, "tex.obj", "tex2.obj", "-o", "out", "--frames", "2", "--gltf", "a.glb"], 0, &["wrote 2 frames", "tex.mtl`: ", "a character device"]),
        case("a FIFO as a texture", |d| { fs::remove_file(d.join("skin.png")).unwrap(); fifo(d, "skin.png"); }, &[I, "tex.obj", "tex2.obj", "-o", "out", "--frames", "2", "--gltf", "a.glb"], 0, &["wrote 2 frames", "skin.png` of material `skin` is not in the GLB: a FIFO"]),
        case("/dev/zero as a texture", |d| { fs::remove_file(d.join("skin.png")).unwrap(); symlink(d, "/dev/zero", "skin.png"); }, &[I, "tex.obj", "tex2.obj", "-o", "out", "--frames", "2", "--gltf", "a.glb"], 0, &["wrote 2 frames", "skin.png` of material `skin` is not in the GLB: a character device"]),
        // Files far larger than what they hold (sparse: no disk used).
        case("a 5 GB STL of zeros", |d| sparse(d, "big.stl", b"", 5_000_000_000), &[I, "big.stl", "src.obj", "-o", "out"], 1, &["`big.stl`", "the header announces 0 facets, which take 84 bytes, but the file has 5000000000 bytes"]),
        case("a 5 GB STL that begins as ASCII", |d| sparse(d, "big.stl", b"solid big\n", 5_000_000_000), &[I, "big.stl", "src.obj", "-o", "out"], 1, &["`big.stl`", "but the file has 5000000000 bytes"]),
        case("a 200 MB OBJ of zeros", |d| sparse(d, "big.obj", b"v 0 0 0\n", 200_000_000), &[I, "big.obj", "src.obj", "-o", "out"], 1, &["`big.obj`", "line 2", "not a text file"]),
        case("a 200 MB PLY of zeros", |d| sparse(d, "big.ply", b"", 200_000_000), &[I, "big.ply", "src.obj", "-o", "out"], 1, &["`big.ply`", "not a PLY file"]),
        // Textures count against --max-gltf-mb before they are read.
        case("a texture larger than --max-gltf-mb", |d| sparse(d, "skin.png", b"\x89PNG\r\n\x1a\n", 300_000_000), &[I, "tex.obj", "tex2.obj", "-o", "out", "--frames", "2", "--gltf", "a.glb"], 1, &["`a.glb`", "300 MB of textures", "over the limit of 256 MB", "--max-gltf-mb 301"]),
        case("a texture past a small --max-gltf-mb", |d| sparse(d, "skin.png", b"\x89PNG\r\n\x1a\n", 2_000_000), &[I, "tex.obj", "tex2.obj", "-o", "out", "--frames", "2", "--gltf", "a.glb", "--max-gltf-mb", "1"], 1, &["MB of textures", "over the limit of 1 MB"]),
        case("a texture within the limit is embedded", nothing, &[I, "tex.obj", "tex2.obj", "-o", "out", "--frames", "2", "--gltf", "a.glb"], 0, &["wrote 2 frames"]),
        // Correspondences whose alignment is no similarity.
        case("a correspondence scaled by 1e308", |d| corr_with_alignment(d, "big.corr", |v| v[0] = "1e308".into()), &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "big.corr", "-o", "out", "pose.obj"], 1, &["`big.corr`, line 5", "scale 1e308 is out of the range"]),
        case("a correspondence whose rotation shears", |d| corr_with_alignment(d, "shear.corr", |v| v[2] = "0.5".into()), &[T, "--source-ref", "thin.obj", "--target-ref", "thick.obj", "--correspondence", "shear.corr", "-o", "out", "pose.obj"], 1, &["`shear.corr`, line 5", "is not a rotation"]),
        // Normals that are not numbers; more than the header announces.
        case("an OBJ normal that is NaN is said", |d| fs::write(d.join("nan.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn nan 0 1\nf 1//1 2//2 3//1\n").unwrap(), &[I, "nan.obj", "nan.obj", "-o", "out", "--frames", "2"], 0, &["wrote 2 frames", "`nan.obj`, line 5: 1 normal (`vn`) with a coordinate that is not a finite number"]),
        case("an OFF file with more faces than its header says", |d| append_bytes(d, "dst.off", "extra.off", b"3 0 1 2\n"), &[I, "extra.off", "dst.off", "-o", "out", "--frames", "2"], 0, &["wrote 2 frames", "`extra.off`", "1 more line after the", "ignored"]),
        case("a binary PLY file with bytes past its elements", |d| append_bytes(d, "src.ply", "extra.ply", &[0; 7]), &[I, "extra.ply", "src.ply", "-o", "out", "--frames", "2"], 0, &["wrote 2 frames", "`extra.ply`: 7 bytes after the elements the header announces"]),
    ]
}

#[test]
fn hostile_reads_catalogue() {
    let cases = catalogue();
    run_catalogue(&cases, run_case, "hostile read");
}
