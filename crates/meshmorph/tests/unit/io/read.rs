use meshmorph::error::Error;
use std::fs::File;
use std::path::Path;

use meshmorph::io::read::*;
use std::io::Write;

fn limit(bytes: u64) -> Limit {
    Limit {
        bytes,
        why: format!("the {bytes} bytes of the test"),
    }
}

#[test]
fn reads_a_regular_file_within_its_limit() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.txt");
    std::fs::write(&path, b"0123456789").unwrap();
    assert_eq!(read_file(&path, &limit(10)).unwrap(), b"0123456789");
    let mut input = open(&path).unwrap();
    assert_eq!(input.len(), 10);
    assert_eq!(input.head(4).unwrap(), b"0123");
    assert_eq!(input.head(20).unwrap(), b"0123456789");
    assert_eq!(input.read_to_end(&limit(10)).unwrap(), b"0123456789");
}

#[test]
fn a_file_over_its_limit_is_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.stl");
    // Sparse: no disk is used.
    File::create(&path).unwrap().set_len(5_000_000_000).unwrap();
    let e = read_file(&path, &limit(1000)).unwrap_err();
    assert!(matches!(e, Error::FileRefused { .. }), "{e:?}");
    let m = e.to_string();
    assert!(
        m.contains("big.stl") && m.contains("5.0 GB") && m.contains("the 1000 bytes"),
        "{m}"
    );
}

#[test]
fn a_folder_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let m = read_file(dir.path(), &Limit::none())
        .unwrap_err()
        .to_string();
    assert!(m.contains("a folder, not a regular file"), "{m}");
}

#[cfg(unix)]
#[test]
fn devices_are_refused_directly_and_through_links() {
    let dir = tempfile::tempdir().unwrap();
    let link = dir.path().join("zero.obj");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    for path in [Path::new("/dev/zero"), Path::new("/dev/urandom"), &link] {
        let e = read_file(path, &Limit::none()).unwrap_err();
        let m = e.to_string();
        assert!(
            m.contains(&format!("`{}`", path.display())) && m.contains("a character device"),
            "{m}"
        );
    }
}

/// A FIFO without a writer: refused at once (a read would wait for a
/// writer for ever).
#[cfg(unix)]
#[test]
fn a_fifo_is_refused_without_waiting() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pipe.obj");
    let made = std::process::Command::new("mkfifo")
        .arg(&path)
        .status()
        .is_ok_and(|s| s.success());
    if !made {
        eprintln!("skipped: mkfifo is not available");
        return;
    }
    let m = read_file(&path, &Limit::none()).unwrap_err().to_string();
    assert!(m.contains("pipe.obj") && m.contains("a FIFO"), "{m}");
    // Opened without waiting for a writer, had the check been passed.
    assert!(open_without_waiting(&path).is_ok());
}

#[test]
fn a_file_that_grows_past_its_limit_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.txt");
    std::fs::write(&path, b"0123").unwrap();
    let input = open(&path).unwrap();
    std::fs::OpenOptions::new()
        .append(true)
        .open(&path)
        .unwrap()
        .write_all(b"456789")
        .unwrap();
    let m = input.read_to_end(&limit(5)).unwrap_err().to_string();
    assert!(m.contains("grew while it was read"), "{m}");
}

#[test]
fn sizes_read_as_people_do() {
    assert_eq!(human_bytes(80), "80 bytes");
    assert_eq!(human_bytes(12_000), "12 kB");
    assert_eq!(human_bytes(256_000_000), "256 MB");
    assert_eq!(human_bytes(2_147_483_648), "2.1 GB");
}
