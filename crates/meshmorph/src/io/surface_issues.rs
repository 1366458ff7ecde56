//! What is odd about a file's surface without making it unusable: faces
//! that repeat another face's corners, edges shared by more than two faces
//! (a fin, a face given twice, two surfaces glued along an edge), faces
//! that list a vertex twice in a row. The solvers take such surfaces as
//! they are; results may crease there, so front ends warn.

use super::MeshFile;
use crate::mesh::topology::edges;

/// The odd places of a file's surface ([`MeshFile::surface_issues`]).
/// Faces are the file's own (0-based, before triangulation), vertices the
/// mesh's (0-based).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct SurfaceIssues {
    /// `[later, earlier]`: each face whose triangle has the corners of a
    /// triangle of an earlier face, once, in increasing order of `later`.
    pub repeated_faces: Vec<[u32; 2]>,
    /// The vertices of each edge shared by more than two triangles.
    pub crowded_edges: Vec<[u32; 2]>,
    /// Faces that listed a vertex twice in a row (read without the repeat).
    pub faces_repeating_a_vertex: Vec<u32>,
}

impl SurfaceIssues {
    /// Whether the surface has none of these.
    pub fn is_empty(&self) -> bool {
        self.repeated_faces.is_empty()
            && self.crowded_edges.is_empty()
            && self.faces_repeating_a_vertex.is_empty()
    }
}

impl MeshFile {
    /// The odd places of this file's surface, in time `n log n` in its
    /// triangles.
    pub fn surface_issues(&self) -> SurfaceIssues {
        let mesh = self.mesh();
        let faces = self.triangle_faces();
        let mut corners: Vec<([u32; 3], usize)> = mesh
            .triangles()
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                let mut c = *tri;
                c.sort_unstable();
                (c, t)
            })
            .collect();
        corners.sort_unstable();
        // Pairs of faces (the later one first) with a triangle of the same
        // corners: each repeating face counted once.
        let mut repeated: Vec<[u32; 2]> = corners
            .windows(2)
            .filter(|w| w[0].0 == w[1].0 && faces[w[0].1] != faces[w[1].1])
            .map(|w| {
                let (a, b) = (faces[w[0].1], faces[w[1].1]);
                [a.max(b), a.min(b)]
            })
            .collect();
        repeated.sort_unstable();
        repeated.dedup_by_key(|p| p[0]);
        let crowded = edges(mesh.triangles())
            .into_iter()
            .filter(|e| e.triangles.len() > 2)
            .map(|e| e.vertices)
            .collect();
        SurfaceIssues {
            repeated_faces: repeated,
            crowded_edges: crowded,
            faces_repeating_a_vertex: self.faces_repeating_a_vertex().to_vec(),
        }
    }
}
