use std::path::{Path, PathBuf};

use meshmorph::io::material_paths::*;

#[test]
fn relative_paths_between_folders() {
    let rel = |d: &str, t: &str| relative_path(Path::new(d), Path::new(t));
    assert_eq!(rel("/a/b/out", "/a/b/x.mtl"), Some("../x.mtl".into()));
    assert_eq!(
        rel("/a/out/r2", "/a/assets/x.mtl"),
        Some("../../assets/x.mtl".into())
    );
    assert_eq!(rel("/a", "/a/m/x.mtl"), Some("m/x.mtl".into()));
    assert_eq!(rel("/", "/x.mtl"), Some("x.mtl".into()));
    assert_eq!(
        without_dots(Path::new("/a/b/../c/./x.mtl")),
        PathBuf::from("/a/c/x.mtl")
    );
}
