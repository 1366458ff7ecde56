use meshmorph::error::{Error, Result};
use std::io::Write;

use meshmorph::io::atomic::*;

#[test]
fn only_this_process_own_temporaries_are_removed() {
    let dir = tempfile::tempdir().unwrap();
    // One left by a writer that could not remove it, as a process
    // abandoning its run leaves it; and others' files.
    let own = Temporary::create(dir.path()).unwrap();
    let own_path = own.path.clone();
    std::mem::forget(own);
    let others = [
        format!(".meshmorph-{}-otherletters0.tmp", process_id()),
        ".meshmorph-1-abcdefghij0.tmp".to_string(),
        "user.obj".to_string(),
    ];
    for name in &others {
        std::fs::write(dir.path().join(name), b"x").unwrap();
    }
    assert_eq!(remove_own_temporaries(dir.path()), 1);
    assert!(!own_path.exists());
    for name in &others {
        assert!(dir.path().join(name).exists(), "{name}");
    }
}

#[cfg(unix)]
#[test]
fn an_output_that_is_a_device_a_fifo_or_a_folder_is_refused_and_left_alone() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let null = dir.path().join("null");
    std::os::unix::fs::symlink("/dev/null", &null).unwrap();
    let fifo = dir.path().join("fifo");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    let folder = dir.path().join("folder");
    std::fs::create_dir(&folder).unwrap();
    let mut paths = vec![(null.clone(), "character device"), (folder, "folder")];
    if made.is_ok_and(|s| s.success()) {
        paths.push((fifo, "FIFO"));
    }
    for (path, what) in paths {
        let e = write_atomic(&path, |w| w.write_all(b"x"))
            .unwrap_err()
            .to_string();
        assert!(e.contains(what) && e.contains("not a regular file"), "{e}");
        assert!(e.contains(&*path.to_string_lossy()), "{e}");
    }
    assert!(std::fs::symlink_metadata(&null)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
    // Nothing staged is left beside them.
    for entry in std::fs::read_dir(dir.path()).unwrap() {
        let name = entry.unwrap().file_name();
        assert!(
            !name.to_string_lossy().starts_with(".meshmorph"),
            "{name:?}"
        );
    }
    let file = dir.path().join("file.txt");
    write_atomic(&file, |w| w.write_all(b"x")).unwrap();
    assert_eq!(std::fs::read(&file).unwrap(), b"x");
}

#[test]
fn a_failure_names_the_file_asked_for_not_the_temporary_one() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing/out.obj");
    let e = write_atomic(&path, |w| w.write_all(b"x")).unwrap_err();
    let message = e.to_string();
    assert!(message.contains("out.obj"), "{message}");
    assert!(!message.contains(".meshmorph-"), "{message}");
}

#[test]
fn a_new_file_is_made_at_its_name_never_through_what_is_there() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.obj");
    let put = |bytes: &'static [u8]| {
        move |w: &mut dyn Write| w.write_all(bytes).map_err(|e| Error::io("out.obj", e))
    };
    let written: Result<()> = write_new(&path, put(b"new"));
    written.unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
    // Something at the name: refused, left as it was.
    let again: Result<()> = write_new(&path, put(b"other"));
    assert!(again.unwrap_err().to_string().contains("out.obj"));
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
    #[cfg(unix)]
    {
        let victim = dir.path().join("victim.txt");
        std::fs::write(&victim, "precious").unwrap();
        let link = dir.path().join("link.obj");
        std::os::unix::fs::symlink(&victim, &link).unwrap();
        let through: Result<()> = write_new(&link, put(b"x"));
        assert!(through.is_err());
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    }
    // A writer that fails leaves nothing.
    let failed = dir.path().join("failed.obj");
    let e: Result<()> = write_new(&failed, |w| {
        put(b"half")(w)?;
        Err(Error::InvalidArgument("no".into()))
    });
    assert!(e.is_err());
    assert!(!failed.exists());
}
