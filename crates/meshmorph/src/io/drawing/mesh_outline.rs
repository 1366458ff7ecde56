//! A planar mesh's boundary as a drawing: its outer boundary loop and the
//! loops around its holes.

use super::regions::signed_area2;
use crate::error::{Error, Result};
use crate::mesh::topology::{boundary_loops, connected_components, BoundaryBreak};
use crate::mesh::Mesh2;
use crate::outline::Drawing;

/// The drawing a planar mesh fills: its boundary loops (edges of one
/// triangle only), the one of largest area as the outer loop and the
/// others as holes. `name` says which mesh in messages ("the mesh
/// `a.obj`").
///
/// # Errors
/// [`Error::InvalidMesh`] when the mesh is in several parts, has no
/// boundary (closed), or a vertex where the boundary meets itself (two
/// boundary edges leaving it); the drawing's own checks
/// ([`Drawing::new`]) as [`Error::InvalidDrawing`].
pub fn drawing_of_mesh(mesh: &Mesh2, name: &str) -> Result<Drawing> {
    let triangles = mesh.triangles();
    let parts = connected_components(mesh.num_vertices(), triangles).count;
    if parts > 1 {
        return Err(Error::InvalidMesh(format!(
            "{name} is in {parts} separate parts: a drawing is one region; give each part as a mesh of its own"
        )));
    }
    let loops = boundary_loops(triangles).map_err(|e| {
        Error::InvalidMesh(match e {
            BoundaryBreak::PassesTwice(a) => format!(
                "{name}'s boundary passes twice through vertex {a} (numbered from 0): its outline touches itself there; separate the parts that meet at that vertex"
            ),
            BoundaryBreak::Stops(v) => format!(
                "{name}'s boundary stops at vertex {v} (numbered from 0): triangles on either side of an edge list it the same way round; orient them alike"
            ),
        })
    })?;
    if loops.is_empty() {
        return Err(Error::InvalidMesh(format!(
            "{name} has no boundary (it is closed): a drawing is a region with an outline"
        )));
    }
    let mut loops: Vec<Vec<[f64; 2]>> = loops
        .iter()
        .map(|l| l.iter().map(|&v| mesh.positions()[v as usize]).collect())
        .collect();
    let outer = (0..loops.len())
        .max_by(|&a, &b| {
            signed_area2(&loops[a])
                .abs()
                .total_cmp(&signed_area2(&loops[b]).abs())
        })
        .expect("a boundary was found");
    loops.swap(0, outer);
    Drawing::new(loops).map_err(|e| match e {
        Error::InvalidDrawing {
            loop_index,
            message,
        } => Error::InvalidDrawing {
            loop_index,
            message: format!("{name}'s boundary: {message}"),
        },
        e => e,
    })
}
