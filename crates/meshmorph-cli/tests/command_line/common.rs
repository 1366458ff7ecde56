//! What the command-line tests share: running the program and reading
//! what it said.

use std::process::{Command, Output};

/// Runs `meshmorph` with `args`.
pub fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_meshmorph"))
        .args(args)
        .output()
        .expect("the meshmorph binary runs")
}

/// What the program printed, stdout then stderr.
pub fn text(out: &Output) -> String {
    format!(
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}
