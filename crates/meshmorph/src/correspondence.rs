//! The triangle map between a source and a target mesh, and its file format.

use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::Mesh3;
use crate::similarity::Similarity;

/// Pairs `(source triangle, target triangle)`, sorted and unique, with the
/// sizes and a connectivity fingerprint of the meshes they were made for,
/// and the similarity that brought the source onto the target before the
/// pairs were found (the identity unless [`correspond`](crate::correspond)
/// aligned them).
#[derive(Clone, Debug, PartialEq)]
pub struct Correspondence {
    pairs: Vec<[u32; 2]>,
    source: MeshSignature,
    target: MeshSignature,
    alignment: Similarity,
}

/// Vertex and triangle counts and a hash of the triangle list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct MeshSignature {
    vertices: usize,
    triangles: usize,
    hash: u64,
}

impl MeshSignature {
    fn of(mesh: &Mesh3) -> Self {
        // FNV-1a over the indices: stable across runs and platforms.
        let mut h: u64 = 0xcbf29ce484222325;
        for t in mesh.triangles() {
            for v in t {
                for b in v.to_le_bytes() {
                    h ^= b as u64;
                    h = h.wrapping_mul(0x100000001b3);
                }
            }
        }
        Self {
            vertices: mesh.num_vertices(),
            triangles: mesh.num_triangles(),
            hash: h,
        }
    }
}

const MAGIC: &str = "meshmorph-correspondence 1";

impl Correspondence {
    /// A map from `pairs` between `source` and `target` (sorted and
    /// deduplicated here).
    ///
    /// # Panics
    /// If a pair names a triangle out of range.
    pub fn new(mut pairs: Vec<[u32; 2]>, source: &Mesh3, target: &Mesh3) -> Self {
        pairs.sort_unstable();
        pairs.dedup();
        assert!(
            pairs
                .iter()
                .all(|p| (p[0] as usize) < source.num_triangles()
                    && (p[1] as usize) < target.num_triangles()),
            "triangle index out of range"
        );
        Self {
            pairs,
            source: MeshSignature::of(source),
            target: MeshSignature::of(target),
            alignment: Similarity::IDENTITY,
        }
    }

    /// The same pairs, made with the source brought onto the target by
    /// `alignment`: [`Transfer`](crate::Transfer) applies it to the source
    /// reference and to every pose.
    pub fn with_alignment(mut self, alignment: Similarity) -> Self {
        self.alignment = alignment;
        self
    }

    /// The similarity that brings the source onto the target.
    pub fn alignment(&self) -> &Similarity {
        &self.alignment
    }

    /// Every triangle of `mesh` paired with itself: the map between a mesh
    /// and another with the same triangles.
    pub fn identity(mesh: &Mesh3) -> Self {
        Self::new(
            (0..mesh.num_triangles() as u32).map(|t| [t, t]).collect(),
            mesh,
            mesh,
        )
    }

    /// The pairs `(source triangle, target triangle)`, sorted.
    pub fn pairs(&self) -> &[[u32; 2]] {
        &self.pairs
    }

    /// Number of source triangles in no pair.
    pub fn unmatched_source(&self) -> usize {
        unmatched(self.pairs.iter().map(|p| p[0]), self.source.triangles)
    }

    /// Number of target triangles in no pair.
    pub fn unmatched_target(&self) -> usize {
        unmatched(self.pairs.iter().map(|p| p[1]), self.target.triangles)
    }

    /// Checks that the map was made for these meshes.
    ///
    /// # Errors
    /// [`Error::Mismatch`] saying which mesh differs and how.
    pub fn check_fits(&self, source: &Mesh3, target: &Mesh3) -> Result<()> {
        for (name, made, given) in [
            ("source reference", self.source, MeshSignature::of(source)),
            ("target reference", self.target, MeshSignature::of(target)),
        ] {
            if made.vertices != given.vertices || made.triangles != given.triangles {
                return Err(Error::Mismatch(format!(
                    "the correspondence was made for a {name} of {} vertices and {} triangles, \
                     but this one has {} vertices and {} triangles",
                    made.vertices, made.triangles, given.vertices, given.triangles
                )));
            }
            if made.hash != given.hash {
                return Err(Error::Mismatch(format!(
                    "the correspondence was made for a {name} with other triangles (same counts, \
                     different connectivity)"
                )));
            }
        }
        Ok(())
    }

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
    /// [`Error::Io`] when the file cannot be read, [`Error::Parse`] naming
    /// the line that does not parse.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
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

fn unmatched(used: impl Iterator<Item = u32>, count: usize) -> usize {
    let mut hit = vec![false; count];
    for t in used {
        hit[t as usize] = true;
    }
    hit.iter().filter(|h| !**h).count()
}
