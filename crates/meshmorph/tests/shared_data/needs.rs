//! Checks that need what a fresh clone does not have (the meshes of
//! ../shared/data, the glTF clients), under libtest-mimic's harness, which
//! can tell at run time: a check whose needs are missing is reported as
//! `ignored`, with what is missing; in CI (`CI=true`), which provides them,
//! it fails instead.

use std::path::PathBuf;

use libtest_mimic::{Completion, Trial};

fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// A check that runs on what `found` holds; when `found` says what is
/// missing, it is ignored with that reason, or fails in CI.
pub fn trial<T: Send + 'static>(
    name: &str,
    found: Result<T, String>,
    check: impl FnOnce(T) + Send + 'static,
) -> Trial {
    Trial::ignorable_test(name, move || match found {
        Ok(needs) => {
            check(needs);
            Ok(Completion::Completed)
        }
        Err(missing) if in_ci() => Err(format!("{missing}; CI must run this check").into()),
        Err(missing) => Ok(Completion::ignored_with(missing)),
    })
}

/// The folder `../shared/data/{folder}` beside the workspace, or what to
/// say when it is not there.
pub fn shared_data(folder: &str) -> Result<PathBuf, String> {
    let named = format!("../shared/data/{folder}");
    let path = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join(&named);
    if path.is_dir() {
        Ok(path)
    } else {
        Err(format!("{} not found", named.trim_end_matches('/')))
    }
}
