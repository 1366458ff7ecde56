//! The correspondence file format: a header, the signatures of the meshes
//! the map was made for, the alignment, then one triangle pair per line.

use std::path::Path;

use crate::error::{Error, Result};
use crate::linalg::similarity::Similarity;
use crate::transfer::correspondence::{Correspondence, MeshSignature};

pub const MAGIC: &str = "meshmorph-correspondence 1";

/// The range of an alignment's scale: nine orders of magnitude either
/// way, past any change of units between two models of one thing
/// (nanometres to metres), while the squares of lengths (areas) stay
/// twelve orders of magnitude or more inside what an `f64` holds, so the
/// aligned source keeps its triangles.
const SCALES: std::ops::RangeInclusive<f64> = 1e-9..=1e9;

/// How far from orthonormal a rotation may be (the largest entry of
/// $R R^T - I$): rotations written with 6 significant digits pass, a
/// matrix that stretches or shears does not.
const ORTHONORMAL_TOLERANCE: f64 = 1e-5;

/// Why `a` is not an alignment a transfer can apply: a scale out of
/// [`SCALES`], a rotation that is not orthonormal (within
/// [`ORTHONORMAL_TOLERANCE`]) or that mirrors.
fn check_alignment(a: &Similarity) -> std::result::Result<(), String> {
    if !SCALES.contains(&a.scale) {
        return Err(format!(
            "the alignment's scale {:e} is out of the range {:e} to {:e}: this file was not written by `meshmorph correspond` (or was edited); make it again",
            a.scale,
            SCALES.start(),
            SCALES.end()
        ));
    }
    let r = &a.rotation;
    let off = (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .map(|(i, j)| {
            let dot: f64 = (0..3).map(|k| r[i][k] * r[j][k]).sum();
            (dot - if i == j { 1.0 } else { 0.0 }).abs()
        })
        .fold(0.0, f64::max);
    if off > ORTHONORMAL_TOLERANCE {
        return Err(format!(
            "the alignment's rotation is not a rotation (its rows are {off:.2e} from orthonormal, more than {ORTHONORMAL_TOLERANCE:e}): this file was not written by `meshmorph correspond` (or was edited); make it again"
        ));
    }
    if crate::linalg::matrix::det3(*r) < 0.0 {
        return Err(
            "the alignment's rotation mirrors (its determinant is -1): this file was not written by `meshmorph correspond` (or was edited); make it again".into(),
        );
    }
    Ok(())
}

impl Correspondence {
    /// Writes the map as text, atomically.
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be written.
    pub fn save(&self, path: &Path) -> Result<()> {
        crate::io::write_atomic(path, |w| {
            writeln!(w, "{MAGIC}")?;
            writeln!(w, "# pairs of (source triangle, target triangle), 0-based")?;
            for (name, s) in [("source", self.source), ("target", self.target)] {
                writeln!(w, "{name} {} {} {:016x}", s.vertices, s.triangles, s.hash)?;
            }
            let a = &self.alignment;
            write!(w, "alignment {:?}", a.scale)?;
            for x in a.rotation.iter().flatten().chain(&a.translation) {
                write!(w, " {x:?}")?;
            }
            writeln!(w)?;
            writeln!(w, "pairs {}", self.pairs.len())?;
            for [s, t] in &self.pairs {
                writeln!(w, "{s} {t}")?;
            }
            Ok(())
        })
    }

    /// Reads a map written by [`Correspondence::save`].
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be read, [`Error::FileRefused`]
    /// when it is not a regular file or is larger than a third of the
    /// memory available, [`Error::Parse`] naming the line that does not
    /// parse or whose alignment is not a similarity.
    pub fn load(path: &Path) -> Result<Self> {
        let bytes = crate::io::read::read_file(path, &crate::io::read::Limit::memory())?;
        let text = crate::io::read::utf8(bytes, path)?;
        Self::parse(&text, path)
    }

    /// [`Correspondence::load`] on text already in memory; `path` names it
    /// in errors. A leading UTF-8 byte-order mark is skipped.
    ///
    /// # Errors
    /// [`Error::Parse`] naming the line that does not parse.
    pub fn parse(text: &str, path: &Path) -> Result<Self> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(k, l)| (k + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let mut next = |what: &str| {
            lines
                .next()
                .ok_or_else(|| Error::parse(path, None, format!("the file ends before {what}")))
        };
        let (line, magic) = next("the header")?;
        if magic != MAGIC {
            return Err(Error::parse(
                path,
                Some(line),
                format!("not a meshmorph correspondence (expected `{MAGIC}`)"),
            ));
        }
        let mut signature = |name: &str| -> Result<MeshSignature> {
            let (line, l) = next(name)?;
            let f: Vec<&str> = l.split_whitespace().collect();
            let bad = || {
                Error::parse(
                    path,
                    Some(line),
                    format!("expected `{name} VERTICES TRIANGLES HASH`"),
                )
            };
            if f.len() != 4 || f[0] != name {
                return Err(bad());
            }
            Ok(MeshSignature {
                vertices: f[1].parse().map_err(|_| bad())?,
                triangles: f[2].parse().map_err(|_| bad())?,
                hash: u64::from_str_radix(f[3], 16).map_err(|_| bad())?,
            })
        };
        let source = signature("source")?;
        let target = signature("target")?;
        let (mut line, mut l) = next("the pair count")?;
        let mut alignment = Similarity::IDENTITY;
        if let Some(values) = l.strip_prefix("alignment ") {
            let v: Vec<f64> = values
                .split_whitespace()
                .map(str::parse)
                .collect::<std::result::Result<_, _>>()
                .ok()
                .filter(|v: &Vec<f64>| v.len() == 13 && v.iter().all(|x| x.is_finite()) && v[0] > 0.0)
                .ok_or_else(|| {
                    Error::parse(
                        path,
                        Some(line),
                        "expected `alignment SCALE R00 R01 ... R22 T0 T1 T2` (13 finite numbers, scale above 0)",
                    )
                })?;
            alignment = Similarity {
                scale: v[0],
                rotation: [[v[1], v[2], v[3]], [v[4], v[5], v[6]], [v[7], v[8], v[9]]],
                translation: [v[10], v[11], v[12]],
            };
            check_alignment(&alignment).map_err(|m| Error::parse(path, Some(line), m))?;
            (line, l) = next("the pair count")?;
        }
        let count: usize = l
            .strip_prefix("pairs ")
            .and_then(|c| c.trim().parse().ok())
            .ok_or_else(|| Error::parse(path, Some(line), "expected `pairs COUNT`"))?;
        let mut pairs = Vec::with_capacity(count.min(1 << 24));
        for _ in 0..count {
            let (line, l) = next("all pairs are listed")?;
            let mut f = l.split_whitespace().map(|x| x.parse::<u32>());
            let pair = match (f.next(), f.next(), f.next()) {
                (Some(Ok(s)), Some(Ok(t)), None) => [s, t],
                _ => {
                    return Err(Error::parse(
                        path,
                        Some(line),
                        format!("expected `SOURCE TARGET`, found `{l}`"),
                    ))
                }
            };
            if pair[0] as usize >= source.triangles || pair[1] as usize >= target.triangles {
                return Err(Error::parse(
                    path,
                    Some(line),
                    format!("triangle pair {} {} is out of range", pair[0], pair[1]),
                ));
            }
            pairs.push(pair);
        }
        if let Some((line, _)) = lines.next() {
            return Err(Error::parse(
                path,
                Some(line),
                format!("more lines than the {count} pairs announced"),
            ));
        }
        pairs.sort_unstable();
        pairs.dedup();
        Ok(Self {
            pairs,
            source,
            target,
            alignment,
        })
    }
}
