//! Where the examples find `../shared/data` (beside the workspace).

use std::path::PathBuf;

/// `../shared/data/<sub>` beside the workspace, or `None` (after saying
/// that it was skipped) when it is absent.
pub fn dir(sub: &str) -> Option<PathBuf> {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data")).join(sub);
    if dir.is_dir() {
        Some(dir)
    } else {
        println!("skipped: {} not found", dir.display());
        None
    }
}
