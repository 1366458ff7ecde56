//! The README's commands checked against ../shared/data.

use std::fs;
use std::path::{Path, PathBuf};

/// The README's commands run as written from the repository root: the
/// files of `../shared/data` they name are given by their path there, and
/// exist.
pub fn readme_commands_name_the_shared_data_by_its_paths(data: PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut data_files = Vec::new();
    file_names(&data, &mut data_files);
    let readme = fs::read_to_string(root.join("README.md")).unwrap();
    let (mut in_shell, mut variables) = (false, Vec::<(String, String)>::new());
    let mut named = 0;
    for line in readme.lines() {
        if line.starts_with("```") {
            in_shell = line == "```sh";
            variables.clear();
            continue;
        }
        if !in_shell {
            continue;
        }
        for word in line.split_whitespace() {
            if let Some((name, value)) = word.split_once('=') {
                if !name.is_empty() && name.chars().all(|c| c.is_ascii_uppercase()) {
                    variables.push((name.to_string(), value.to_string()));
                    continue;
                }
            }
            let mut word = word.to_string();
            for (name, value) in &variables {
                word = word.replace(&format!("${name}"), value);
            }
            if word.starts_with("../shared/data/") {
                assert!(root.join(&word).exists(), "README: `{word}` does not exist");
                named += 1;
            } else {
                assert!(
                    !data_files.contains(&word),
                    "README: `{word}` is in ../shared/data: give its path there"
                );
            }
        }
    }
    assert!(
        named > 0,
        "the README's commands name no file of ../shared/data"
    );
}

/// The names of the files under `dir`, at any depth.
fn file_names(dir: &Path, into: &mut Vec<String>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            file_names(&path, into);
        } else {
            into.push(path.file_name().unwrap().to_string_lossy().into_owned());
        }
    }
}
