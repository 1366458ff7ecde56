//! What every subcommand shares: output paths, formats, reports.

use std::path::Path;

use anyhow::{Context, Result};
use meshmorph::io::Format;

/// `--format` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FormatArg {
    /// Wavefront OBJ.
    Obj,
    /// Object File Format.
    Off,
    /// Stanford PLY (binary).
    Ply,
}

impl From<FormatArg> for Format {
    fn from(f: FormatArg) -> Self {
        match f {
            FormatArg::Obj => Format::Obj,
            FormatArg::Off => Format::Off,
            FormatArg::Ply => Format::Ply,
        }
    }
}

/// The format asked for, else the one of `like`'s extension.
pub fn format_or_like(asked: Option<FormatArg>, like: &Path) -> Result<Format> {
    match asked {
        Some(f) => Ok(f.into()),
        None => Format::from_path(like).map_err(Into::into),
    }
}

/// Reads a mesh, saying which file and what role on failure.
pub fn read_mesh(path: &Path, role: &str) -> Result<meshmorph::Mesh3> {
    meshmorph::io::read_mesh(path).with_context(|| format!("reading {role} `{}`", path.display()))
}

/// Reads a mesh file kept whole, saying which file and what role on failure.
pub fn read_mesh_file(path: &Path, role: &str) -> Result<meshmorph::io::MeshFile> {
    meshmorph::io::MeshFile::read(path)
        .with_context(|| format!("reading {role} `{}`", path.display()))
}

/// Seconds as a short human string.
pub fn human_seconds(s: f64) -> String {
    if s >= 1.0 {
        format!("{s:.2} s")
    } else if s >= 1e-3 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{:.1} µs", s * 1e6)
    }
}

/// Prints a report as one line of JSON on stdout.
pub fn print_json(report: &impl serde::Serialize) {
    println!(
        "{}",
        serde_json::to_string(report).expect("a report serialises")
    );
}

/// A finite number above zero (a clap value parser).
pub fn positive_number(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err(format!("`{text}` is not a finite number above 0")),
    }
}

/// Prints each warning on stderr.
pub fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}
