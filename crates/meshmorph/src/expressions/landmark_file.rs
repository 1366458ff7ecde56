//! A file of named landmarks on a head: any point file meshmorph reads
//! for one mesh (MeshLab's `.pp`, Wrap's `.json`, meshmorph's own lines of
//! `name x y z` or `name VERTEX`), every point named by a template landmark
//! name ([`landmark_number`](super::landmarks::landmark_number)).

use std::path::Path;

use crate::error::{Error, Result};
use crate::io::marker_points::read_points;
use crate::mesh::{Mesh3, SurfacePoint};
use crate::transfer::markers::{Side, VertexNumbering};

/// The named points of `path` on `head`: `(name, position)`, in the file's
/// order (MeshLab's points marked inactive left out).
///
/// # Errors
/// The reading errors of the point file; [`Error::Parse`] naming the file
/// for a point without a name, or one that names a vertex or triangle the
/// head does not have.
pub fn read_landmarks(
    path: &Path,
    head: &Mesh3,
    numbering: VertexNumbering,
) -> Result<Vec<(String, [f64; 3])>> {
    let list = read_points(path, numbering)?;
    let mut out = Vec::with_capacity(list.entries.len());
    for e in list.entries.iter().filter(|e| e.active) {
        let at = || format!("{} {}", list.unit, e.place);
        let name = e.name.clone().ok_or_else(|| {
            Error::parse(
                path,
                None,
                format!("{}: a landmark without a name: name every point by its landmark (iBUG number 1 to 68, or an alias such as noseTip)", at()),
            )
        })?;
        let p = match e.side {
            Side::At(p) => p,
            Side::On(point) => {
                let (n, t) = (head.num_vertices() as u32, head.num_triangles() as u32);
                let problem = match point {
                    SurfacePoint::Vertex(v) if v >= n => {
                        Some(format!("vertex {v} is past the head's {n} vertices"))
                    }
                    SurfacePoint::Triangle { triangle, .. } if triangle >= t => Some(format!(
                        "triangle {triangle} is past the head's {t} triangles"
                    )),
                    _ => point.barycentric_problem(),
                };
                if let Some(problem) = problem {
                    return Err(Error::parse(
                        path,
                        None,
                        format!("{} ({name}): {problem}", at()),
                    ));
                }
                point.position(head)
            }
        };
        out.push((name, p));
    }
    Ok(out)
}
