//! SIGINT, SIGTERM, SIGHUP, SIGQUIT and the other signals that would end
//! the process, during a long run: the run stops (status 128 + the
//! signal's number), removes every
//! staged file and every folder it created, and leaves the files that were
//! there before as they were.

#![cfg(unix)]

use std::fs;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use meshmorph::io::{write_mesh, Format};
use meshmorph::shapes::{curl, strip};

/// Every name under `dir`, recursively.
fn all_names(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = fs::read_dir(&d) else {
            continue;
        };
        for e in entries {
            let p = e.unwrap().path();
            out.push(p.strip_prefix(dir).unwrap().display().to_string());
            if p.is_dir() {
                stack.push(p);
            }
        }
    }
    out.sort();
    out
}

/// Interrupts a long run with `signal`; it must exit with status `code`.
fn interrupt_a_long_run(signal: &str, code: i32) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let bar = strip(8.0, 1.0, 40, 4);
    write_mesh(&d.join("a.obj"), &bar, Format::Obj).unwrap();
    write_mesh(&d.join("b.obj"), &curl(&bar, 2.0), Format::Obj).unwrap();
    // An earlier run's frames in one output folder, a new folder for the GIF.
    fs::create_dir(d.join("old")).unwrap();
    for k in 0..5 {
        fs::write(d.join(format!("old/frame_{k:04}.obj")), format!("old {k}")).unwrap();
    }
    let before = all_names(d);
    let mut child = Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .args([
            "interpolate",
            "a.obj",
            "b.obj",
            "-o",
            "old",
            "--frames",
            "20000",
            "--svg",
            "--gif",
            "new/anim.gif",
            "--json",
        ])
        .current_dir(d)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the run has staged some files.
    let begin = Instant::now();
    loop {
        let staged = all_names(d)
            .iter()
            .filter(|n| n.contains(".meshmorph-"))
            .count();
        if staged >= 3 {
            break;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before it could be interrupted"
        );
        assert!(
            begin.elapsed() < Duration::from_secs(60),
            "nothing was staged"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let status = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "{stderr}");
    // With --json, one JSON error object on stdout.
    let stdout = String::from_utf8_lossy(&out.stdout);
    let report: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    assert!(
        report["error"].as_str().unwrap().contains("interrupted"),
        "{report}"
    );
    assert_eq!(
        report["exit_status"].as_i64(),
        Some(i64::from(code)),
        "{report}"
    );
    assert!(stderr.contains("interrupted"), "{stderr}");
    assert!(!stderr.contains(".meshmorph-"), "{stderr}");
    assert_eq!(all_names(d), before, "the folder is as it was");
    for k in 0..5 {
        let text = fs::read_to_string(d.join(format!("old/frame_{k:04}.obj"))).unwrap();
        assert_eq!(text, format!("old {k}"));
    }
}

#[test]
fn sigint_leaves_the_folders_as_they_were() {
    interrupt_a_long_run("-INT", 130);
}

#[test]
fn sigterm_leaves_the_folders_as_they_were() {
    interrupt_a_long_run("-TERM", 143);
}

#[test]
fn sighup_leaves_the_folders_as_they_were() {
    interrupt_a_long_run("-HUP", 129);
}

#[test]
fn sigquit_leaves_the_folders_as_they_were() {
    interrupt_a_long_run("-QUIT", 131);
}

#[test]
fn sigusr1_and_sigalrm_leave_the_folders_as_they_were() {
    interrupt_a_long_run("-USR1", 138);
    interrupt_a_long_run("-ALRM", 142);
}

#[test]
fn an_interrupt_during_the_final_moves_lets_them_finish_and_says_so() {
    // The moves of many frames take a moment: a signal sent once the
    // first frame is in place waits for the rest, and the run says that
    // every output was written.
    for frames in [20_000usize, 60_000, 150_000] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        fs::write(d.join("a.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        fs::write(d.join("b.obj"), "v 0 0 0\nv 0 1 0\nv -1 0 0\nf 1 2 3\n").unwrap();
        // An existing folder takes the frames one rename each (a new one
        // would be moved into place whole, at once).
        fs::create_dir(d.join("out")).unwrap();
        let mut child = Command::new(env!("CARGO_BIN_EXE_meshmorph"))
            .args(["interpolate", "a.obj", "b.obj", "-o", "out", "--frames"])
            .arg(frames.to_string())
            .current_dir(d)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let first = d.join("out").join(format!(
            "frame_{:0w$}.obj",
            0,
            w = (frames - 1).to_string().len()
        ));
        let caught = loop {
            if first.exists() {
                break child.try_wait().unwrap().is_none();
            }
            if child.try_wait().unwrap().is_some() {
                break false;
            }
            std::thread::sleep(Duration::from_micros(200));
        };
        if !caught {
            let _ = child.wait();
            continue;
        }
        let status = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(status.success());
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        if out.status.success() {
            // The signal came after the run ended.
            continue;
        }
        assert_eq!(out.status.code(), Some(130), "{stderr}");
        assert!(
            stderr.contains("every output of this run had been moved into place"),
            "{stderr}"
        );
        let names = all_names(d);
        assert_eq!(
            names.iter().filter(|n| n.contains("frame_")).count(),
            frames
        );
        assert!(
            !names.iter().any(|n| n.contains(".meshmorph-")),
            "{names:?}"
        );
        return;
    }
    panic!("every run ended before the signal reached its final moves");
}
