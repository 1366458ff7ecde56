//! Hostile cases around the outputs that the catalogue's table cannot hold:
//! links planted at staged names, side files (material libraries and
//! textures), stdout closed or full, limits on threads, memory and file
//! size, signals, two runs into one folder, and many frames or markers.
//! Each checks what the run says, its exit status, and that no file of the
//! user's changed and no temporary file remains.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

const BIN: &str = env!("CARGO_BIN_EXE_meshmorph");

/// A triangle and the same turned a quarter: the smallest interpolation.
const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
const TURNED: &str = "v 0 0 0\nv 0 1 0\nv -1 0 0\nf 1 2 3\n";

/// A square of two triangles with texture coordinates and a material.
const TEXTURED: &str = "mtllib look.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl skin\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
const TEXTURED_TURNED: &str = "mtllib look.mtl\nv 0 0 0\nv 0 1 0\nv -1 1 0\nv -1 0 0\n\
                        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl skin\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
const MTL: &str = "newmtl skin\nKd 0.8 0.6 0.5\nmap_Kd tex/skin.png\nmap_Bump normal.png\n";

/// Every file and folder under `dir` (links not followed), with the bytes
/// of the files and the targets of the links.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut all = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let meta = fs::symlink_metadata(&p).unwrap();
            let bytes = if meta.is_dir() {
                stack.push(p.clone());
                b"<folder>".to_vec()
            } else if meta.file_type().is_symlink() {
                fs::read_link(&p)
                    .unwrap()
                    .to_string_lossy()
                    .as_bytes()
                    .to_vec()
            } else {
                fs::read(&p).unwrap_or_default()
            };
            all.insert(p.strip_prefix(dir).unwrap().to_path_buf(), bytes);
        }
    }
    all
}

/// The files of `before` that are not byte for byte the same in `after`.
fn changed(
    before: &BTreeMap<PathBuf, Vec<u8>>,
    after: &BTreeMap<PathBuf, Vec<u8>>,
) -> Vec<PathBuf> {
    before
        .iter()
        .filter(|(p, b)| after.get(*p) != Some(*b))
        .map(|(p, _)| p.clone())
        .collect()
}

/// A folder with `files` (name, text).
fn folder(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        let path = dir.path().join(name);
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, text).unwrap();
    }
    dir
}

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

fn text(out: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// No panic, no temporary name said or left anywhere under `dir`.
fn clean(dir: &Path, out: &Output) {
    let (stdout, stderr) = text(out);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        !stderr.contains(".meshmorph-") && !stdout.contains(".meshmorph-"),
        "{stderr}"
    );
    let left: Vec<_> = snapshot(dir)
        .into_keys()
        .filter(|p| p.to_string_lossy().contains(".meshmorph-"))
        .collect();
    assert!(left.is_empty(), "left {left:?}\n{stderr}");
}

#[cfg(unix)]
#[test]
fn links_planted_at_staged_names_are_never_written_through() {
    // What a local attacker can plant: links at the names staged files had
    // (`.meshmorph-<pid>-<n>.part`, pid 1 in a container), to files of the
    // user's, in the output folder and beside a picture.
    let dir = folder(&[
        ("a.obj", TRIANGLE),
        ("b.obj", TURNED),
        ("victim.txt", "precious"),
    ]);
    let d = dir.path();
    fs::create_dir_all(d.join("out")).unwrap();
    let mut planted = Vec::new();
    for pid in [1u32, 2, 7] {
        for k in 0..4 {
            for folder in ["out", "."] {
                let link = d.join(folder).join(format!(".meshmorph-{pid}-{k}.part"));
                if k % 2 == 0 {
                    std::os::unix::fs::symlink(d.join("victim.txt"), &link).unwrap();
                } else {
                    fs::hard_link(d.join("a.obj"), &link).unwrap();
                }
                planted.push(link);
            }
        }
    }
    let before = snapshot(d);
    let out = run(
        d,
        &[
            "interpolate",
            "a.obj",
            "b.obj",
            "-o",
            "out",
            "--frames",
            "3",
            "--gif",
            "a.gif",
        ],
    );
    assert!(out.status.success(), "{}", text(&out).1);
    let after = snapshot(d);
    assert_eq!(changed(&before, &after), Vec::<PathBuf>::new());
    assert_eq!(
        fs::read_to_string(d.join("victim.txt")).unwrap(),
        "precious"
    );
    assert!(d.join("out/frame_0002.obj").is_file() && d.join("a.gif").is_file());
}

/// A textured square whose material library names a texture and a bump map.
fn textured() -> tempfile::TempDir {
    folder(&[
        ("a.obj", TEXTURED),
        ("b.obj", TEXTURED_TURNED),
        ("look.mtl", MTL),
        ("tex/skin.png", "not really a picture"),
        ("normal.png", "nor this"),
    ])
}

#[test]
fn side_files_are_inputs_and_never_written() {
    let cases: [(&[&str], &str); 4] = [
        (&["--png", "tex/skin.png"], "tex/skin.png"),
        (&["--png", "normal.png"], "normal.png"),
        (&["--format", "obj", "--gltf", "look.mtl"], "look.mtl"),
        (&["--png", "linked/skin.png"], "linked/skin.png"),
    ];
    for (extra, named) in cases {
        let dir = textured();
        let d = dir.path();
        #[cfg(unix)]
        std::os::unix::fs::symlink(d.join("tex"), d.join("linked")).unwrap();
        if named == "look.mtl" {
            // The GLB is named for its format: rename the case's library.
            fs::rename(d.join("look.mtl"), d.join("look.glb")).unwrap();
            for obj in ["a.obj", "b.obj"] {
                let t = fs::read_to_string(d.join(obj))
                    .unwrap()
                    .replace("look.mtl", "look.glb");
                fs::write(d.join(obj), t).unwrap();
            }
        }
        let named = named.replace("look.mtl", "look.glb");
        let extra: Vec<String> = extra
            .iter()
            .map(|a| a.replace("look.mtl", "look.glb"))
            .collect();
        let before = snapshot(d);
        let mut args = vec![
            "interpolate",
            "a.obj",
            "b.obj",
            "-o",
            "out",
            "--frames",
            "3",
        ];
        args.extend(extra.iter().map(String::as_str));
        let out = run(d, &args);
        let (_, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("would overwrite the material file of the"),
            "{stderr}"
        );
        assert!(stderr.contains(&named), "{stderr}");
        assert_eq!(snapshot(d), before, "{args:?}");
        clean(d, &out);
    }
}

#[cfg(unix)]
#[test]
fn a_closed_or_full_stdout_is_an_error_after_the_outputs_are_written() {
    let dir = folder(&[("a.obj", TRIANGLE), ("b.obj", TURNED)]);
    let d = dir.path();
    // Closed: the reader is gone before the program starts (dropped after
    // it started, a quick run could print into the pipe's buffer first).
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let out = Command::new(BIN)
        .args([
            "interpolate",
            "a.obj",
            "b.obj",
            "-o",
            "closed",
            "--frames",
            "3",
            "--json",
        ])
        .current_dir(d)
        .stdout(Stdio::from(writer))
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    let (_, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("printing on stdout failed"), "{stderr}");
    assert!(
        stderr.contains("every file the run writes was written"),
        "{stderr}"
    );
    assert!(d.join("closed/frame_0002.obj").is_file());
    clean(d, &out);
    // Full, for every command that prints.
    for args in [
        &[
            "interpolate",
            "a.obj",
            "b.obj",
            "-o",
            "full",
            "--frames",
            "3",
        ][..],
        &["completions", "bash"],
        &["man"],
        &["demo", "-o", "demo", "--json"],
    ] {
        let out = Command::new(BIN)
            .args(args)
            .current_dir(d)
            .stdout(fs::File::create("/dev/full").unwrap())
            .output()
            .unwrap();
        let (_, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("No space left on device"),
            "{args:?}: {stderr}"
        );
        clean(d, &out);
    }
}

#[cfg(target_os = "linux")]
#[test]
fn a_name_that_is_not_utf8_is_written_lossily_in_json() {
    use std::os::unix::ffi::OsStrExt as _;
    let dir = folder(&[("a.obj", TRIANGLE), ("b.obj", TURNED)]);
    let d = dir.path();
    let name = std::ffi::OsStr::from_bytes(b"out-\xff\xfe");
    let out = Command::new(BIN)
        .args([
            "interpolate",
            "a.obj",
            "b.obj",
            "--frames",
            "2",
            "--json",
            "-o",
        ])
        .arg(name)
        .current_dir(d)
        .output()
        .unwrap();
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stderr}");
    let report: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(report["output"], "out-\u{fffd}\u{fffd}");
    assert!(d.join(name).join("frame_0001.obj").is_file());
}

/// `args` run by `prlimit` with `limit`, as the user nobody where the
/// limit is on processes (root is exempt from it); `None` when `prlimit`
/// or `setpriv` is missing.
#[cfg(target_os = "linux")]
fn limited(dir: &Path, limit: &str, args: &[&str]) -> Option<Output> {
    let nobody = limit.starts_with("--nproc");
    let mut cmd = if nobody {
        let mut c = Command::new("setpriv");
        c.args([
            "--reuid=65534",
            "--regid=65534",
            "--clear-groups",
            "prlimit",
        ]);
        c
    } else {
        Command::new("prlimit")
    };
    // The user nobody may not reach the build's folder (a clone under
    // /root): a copy of the binary in the test's folder runs instead.
    let bin = if nobody {
        use std::os::unix::fs::PermissionsExt as _;
        let copy = dir.join("meshmorph-for-nobody");
        fs::copy(BIN, &copy).unwrap();
        fs::set_permissions(&copy, fs::Permissions::from_mode(0o755)).unwrap();
        copy
    } else {
        PathBuf::from(BIN)
    };
    let out = cmd
        .arg(limit)
        .arg(&bin)
        .args(args)
        .current_dir(dir)
        .output();
    if nobody {
        let _ = fs::remove_file(&bin);
    }
    match out {
        Ok(out) => Some(out),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => panic!("{e}"),
    }
}

#[cfg(target_os = "linux")]
#[test]
fn limits_on_threads_memory_and_file_size_are_errors_not_crashes() {
    let dir = folder(&[("a.obj", TRIANGLE), ("b.obj", TURNED)]);
    let d = dir.path();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        fs::set_permissions(d, fs::Permissions::from_mode(0o777)).unwrap();
    }
    let missing = "prlimit and setpriv (util-linux) are needed for this test";
    // No second thread: the run uses one.
    let out = limited(
        d,
        "--nproc=1",
        &[
            "interpolate",
            "a.obj",
            "b.obj",
            "-o",
            "one",
            "--frames",
            "40",
            "--gif",
            "one.gif",
        ],
    )
    .expect(missing);
    assert!(out.status.success(), "{}", text(&out).1);
    assert!(d.join("one/frame_0039.obj").is_file() && d.join("one.gif").is_file());
    clean(d, &out);
    // A file past `ulimit -f`: the write fails, nothing stays.
    let before = snapshot(d);
    let out = limited(
        d,
        "--fsize=3000",
        &[
            "interpolate",
            "a.obj",
            "b.obj",
            "-o",
            "big",
            "--frames",
            "5",
            "--gif",
            "big.gif",
        ],
    )
    .expect(missing);
    let (_, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("big.gif") && stderr.contains("too large"),
        "{stderr}"
    );
    assert_eq!(snapshot(d), before);
    clean(d, &out);
    // Address space too small for the run: refused, nothing stays.
    for megabytes in [40, 80, 150] {
        let out = limited(
            d,
            &format!("--as={}", megabytes * 1_000_000),
            &[
                "interpolate",
                "a.obj",
                "b.obj",
                "-o",
                "mem",
                "--frames",
                "400",
                "--gif",
                "mem.gif",
                "--gltf",
                "mem.glb",
            ],
        )
        .expect(missing);
        let (_, stderr) = text(&out);
        if out.status.success() {
            clean(d, &out);
            continue;
        }
        assert_eq!(out.status.code(), Some(1), "{megabytes} MB: {stderr}");
        assert!(stderr.contains("memory"), "{megabytes} MB: {stderr}");
        assert_eq!(snapshot(d), before, "{megabytes} MB");
        clean(d, &out);
    }
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_while_writing_manual_pages_leaves_none() {
    let dir = folder(&[]);
    let d = dir.path();
    // The longest pages go past the limit.
    let out = limited(d, "--fsize=4000", &["man", "--dir", "pages"]).expect("prlimit is needed");
    let (_, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!d.join("pages").exists(), "{stderr}");
    clean(d, &out);
    let out = run(d, &["man", "--dir", "pages"]);
    assert!(out.status.success());
    assert_eq!(fs::read_dir(d.join("pages")).unwrap().count(), 10);
}

/// Frames of a run in `dir`, and which of two runs (by the last vertex's
/// x, which differs) wrote each.
fn frames_by_run(dir: &Path) -> Vec<(String, String)> {
    let mut frames: Vec<(String, String)> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .map(|e| {
            let text = fs::read_to_string(e.path()).unwrap();
            let third = text
                .lines()
                .filter(|l| l.starts_with("v "))
                .nth(2)
                .unwrap()
                .to_string();
            (e.file_name().to_string_lossy().into_owned(), third)
        })
        .collect();
    frames.sort();
    frames
}

#[cfg(unix)]
#[test]
fn two_runs_into_one_folder_leave_one_whole_animation() {
    let dir = folder(&[
        ("a.obj", TRIANGLE),
        ("b.obj", TURNED),
        ("c.obj", "v 0 0 0\nv 2 0 0\nv 0 2 0\nf 1 2 3\n"),
    ]);
    let d = dir.path();
    // The one run alone, to know its frames.
    for (key, count, name) in [("b.obj", "400", "alone-b"), ("c.obj", "300", "alone-c")] {
        assert!(run(
            d,
            &["interpolate", "a.obj", key, "-o", name, "--frames", count]
        )
        .status
        .success());
    }
    let alone = [
        frames_by_run(&d.join("alone-b")),
        frames_by_run(&d.join("alone-c")),
    ];
    for _ in 0..3 {
        let start = |key: &str, count: &str| {
            Command::new(BIN)
                .args(["interpolate", "a.obj", key, "-o", "both", "--frames", count])
                .current_dir(d)
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        };
        let (first, second) = (start("b.obj", "400"), start("c.obj", "300"));
        for child in [first, second] {
            let out = child.wait_with_output().unwrap();
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        let both = frames_by_run(&d.join("both"));
        assert!(
            both == alone[0] || both == alone[1],
            "a mixed animation of {} frames",
            both.len()
        );
        let left: Vec<_> = snapshot(d)
            .into_keys()
            .filter(|p| p.to_string_lossy().contains(".meshmorph-"))
            .collect();
        assert!(left.is_empty(), "{left:?}");
    }
}

#[test]
fn many_frames_and_marker_lines_are_linear_work() {
    // Not timed here (see BENCHMARKS.md): a run whose plan, sweep or
    // marker checks were quadratic would not end within the test's time.
    let dir = folder(&[("a.obj", TRIANGLE), ("b.obj", TURNED)]);
    let d = dir.path();
    let out = run(
        d,
        &[
            "interpolate",
            "a.obj",
            "b.obj",
            "-o",
            "many",
            "--frames",
            "8000",
        ],
    );
    assert!(out.status.success(), "{}", text(&out).1);
    assert_eq!(fs::read_dir(d.join("many")).unwrap().count(), 8_000);
    // Again, fewer: the surplus of the first run is swept.
    let out = run(
        d,
        &[
            "interpolate",
            "a.obj",
            "b.obj",
            "-o",
            "many",
            "--frames",
            "6000",
        ],
    );
    assert!(text(&out).0.contains("removed 2000 "), "{}", text(&out).0);
    assert_eq!(fs::read_dir(d.join("many")).unwrap().count(), 6_000);
    clean(d, &out);
    // A marker file of a hundred thousand lines, every one the same pair.
    fs::write(d.join("m.txt"), "0 0\n".repeat(100_000)).unwrap();
    let out = run(
        d,
        &[
            "correspond",
            "--source-ref",
            "a.obj",
            "--target-ref",
            "b.obj",
            "--markers",
            "m.txt",
            "-o",
            "c.corr",
        ],
    );
    let (_, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("m.txt") && stderr.contains("repeats"),
        "{stderr}"
    );
    clean(d, &out);
}
