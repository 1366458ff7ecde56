//! What the checks in real clients need (node with the npm packages of
//! tools/browser-checks, and Chromium), and their trials: without what a
//! check needs it is reported as ignored, naming what is missing; in CI
//! (`CI=true`), which installs them, it fails instead.

use std::path::{Path, PathBuf};
use std::process::Command;

use libtest_mimic::Trial;

use crate::needs::trial;

/// What a check needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Needs {
    /// node and the npm packages.
    Node,
    /// Those and Chromium.
    Chromium,
    /// Those, Chromium and a folder of ../shared/data.
    ChromiumAndSharedData(&'static str),
    /// Those and Blender (Debian's `blender`), run in the background.
    Blender,
}

/// A check: its name, its body and what it needs.
pub type Check = (&'static str, fn(), Needs);

pub fn tools() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tools/browser-checks")
}

pub fn chromium() -> String {
    std::env::var("CHROMIUM").unwrap_or_else(|_| "chromium".into())
}

/// The full path of `program` on the PATH (itself when it has a `/` or is
/// not found).
pub fn which(program: &str) -> String {
    if program.contains('/') {
        return program.to_string();
    }
    std::env::var_os("PATH")
        .and_then(|paths| {
            std::env::split_paths(&paths)
                .map(|d| d.join(program))
                .find(|p| p.is_file())
        })
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| program.to_string())
}

/// Whether `program --version` runs.
fn runs(program: &str) -> bool {
    Command::new(program)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

fn node_packages() -> bool {
    ["gltf-validator", "three", "puppeteer-core", "lottie-web"]
        .iter()
        .all(|p| tools().join("node_modules").join(p).is_dir())
}

/// The checks as trials, each ignored (or failed in CI) with what it misses.
pub fn trials(checks: Vec<Check>) -> Vec<Trial> {
    let node = runs("node");
    let packages = node_packages();
    let browser = runs(&chromium());
    checks
        .into_iter()
        .map(|(name, check, needs)| {
            let mut missing: Vec<&str> = Vec::new();
            for (what, there) in [("node", node), ("npm packages", packages)] {
                if !there {
                    missing.push(what);
                }
            }
            if matches!(needs, Needs::Chromium | Needs::ChromiumAndSharedData(_)) && !browser {
                missing.push("chromium");
            }
            if needs == Needs::Blender && !runs("blender") {
                missing.push("blender");
            }
            let found = if missing.is_empty() {
                match needs {
                    Needs::ChromiumAndSharedData(folder) => {
                        crate::needs::shared_data(folder).map(|_| ())
                    }
                    _ => Ok(()),
                }
            } else {
                Err(format!(
                    "missing {}: apt-get install nodejs chromium blender, npm ci in tools/browser-checks",
                    missing.join(", ")
                ))
            };
            trial(name, found, move |()| check())
        })
        .collect()
}
