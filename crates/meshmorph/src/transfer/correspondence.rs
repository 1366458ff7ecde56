//! The triangle map between a source and a target mesh (its file format is
//! in [`crate::io`], `io/correspondence_file.rs`).

use crate::error::{Error, Result};
use crate::linalg::similarity::Similarity;
use crate::mesh::Mesh3;

/// Pairs `(source triangle, target triangle)`, sorted and unique, with the
/// sizes and a connectivity fingerprint of the meshes they were made for,
/// and the similarity that brought the source onto the target before the
/// pairs were found (the identity unless [`correspond`](crate::correspond)
/// aligned them).
#[derive(Clone, Debug, PartialEq)]
pub struct Correspondence {
    pub(crate) pairs: Vec<[u32; 2]>,
    pub(crate) source: MeshSignature,
    pub(crate) target: MeshSignature,
    pub(crate) alignment: Similarity,
}

/// Vertex and triangle counts and a hash of the triangle list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshSignature {
    pub(crate) vertices: usize,
    pub(crate) triangles: usize,
    pub(crate) hash: u64,
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
                     different connectivity: other faces, or polygons split along other diagonals \
                     where the positions differ, as each polygon is split by its shape)"
                )));
            }
        }
        Ok(())
    }
}

fn unmatched(used: impl Iterator<Item = u32>, count: usize) -> usize {
    let mut hit = vec![false; count];
    for t in used {
        hit[t as usize] = true;
    }
    hit.iter().filter(|h| !**h).count()
}
