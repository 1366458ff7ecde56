//! The triangle mesh type shared by every algorithm.

use crate::error::{Error, Result};

/// A triangle mesh with `D`-dimensional vertex positions (`D` is 2 or 3).
///
/// Construction validates the mesh: it has at least one triangle, every
/// coordinate is finite, every index is in range and no triangle repeats a
/// vertex. Every algorithm may rely on these invariants. Triangles are
/// counter-clockwise when seen from the side their normal points to.
///
/// Vertices that no triangle uses are allowed (OBJ files often have them);
/// the algorithms move them along with the nearest sensible rule (see each
/// algorithm's documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh<const D: usize> {
    positions: Vec<[f64; D]>,
    triangles: Vec<[u32; 3]>,
}

/// A planar mesh: `#V × 2` positions.
pub type Mesh2 = Mesh<2>;
/// A mesh in space: `#V × 3` positions.
pub type Mesh3 = Mesh<3>;

impl<const D: usize> Mesh<D> {
    /// Builds a mesh from `#V × D` positions and `#T × 3` vertex indices.
    ///
    /// # Errors
    /// [`Error::InvalidMesh`] when the mesh is empty,
    /// [`Error::InvalidVertex`] naming the first vertex with a coordinate
    /// that is NaN or infinite, [`Error::InvalidTriangle`] the first
    /// triangle with an index out of range or a repeated vertex.
    pub fn new(positions: Vec<[f64; D]>, triangles: Vec<[u32; 3]>) -> Result<Self> {
        if triangles.is_empty() {
            return Err(Error::InvalidMesh("the mesh has no triangles".into()));
        }
        check_finite(&positions, "")?;
        check_indices(positions.len(), &triangles)?;
        Ok(Self {
            positions,
            triangles,
        })
    }

    /// `#V × D` vertex positions.
    pub fn positions(&self) -> &[[f64; D]] {
        &self.positions
    }

    /// `#T × 3` vertex indices.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.triangles.len()
    }

    /// The same connectivity with new positions.
    ///
    /// # Errors
    /// [`Error::InvalidMesh`] if the count differs, [`Error::InvalidVertex`]
    /// if a coordinate is not finite.
    pub fn with_positions(&self, positions: Vec<[f64; D]>) -> Result<Self> {
        if positions.len() != self.positions.len() {
            return Err(Error::InvalidMesh(format!(
                "{} positions given for a mesh of {} vertices",
                positions.len(),
                self.positions.len()
            )));
        }
        check_finite(&positions, "")?;
        Ok(Self {
            positions,
            triangles: self.triangles.clone(),
        })
    }

    /// Checks that `other` has this mesh's vertex count and triangles (the
    /// same connectivity: another pose of the same shape). `names` say what
    /// the two meshes are, for the message ("the source", "the target").
    ///
    /// # Errors
    /// [`Error::Mismatch`] naming the counts, or [`Error::TriangleMismatch`]
    /// the first triangle that differs.
    pub fn check_same_connectivity<const E: usize>(
        &self,
        other: &Mesh<E>,
        names: [&str; 2],
    ) -> Result<()> {
        let [mine, theirs] = names;
        if self.num_vertices() != other.num_vertices() {
            return Err(Error::Mismatch(format!(
                "{mine} has {} vertices but {theirs} has {}",
                self.num_vertices(),
                other.num_vertices()
            )));
        }
        if self.num_triangles() != other.num_triangles() {
            return Err(Error::Mismatch(format!(
                "{mine} has {} triangles but {theirs} has {}",
                self.num_triangles(),
                other.num_triangles()
            )));
        }
        match (0..self.num_triangles()).find(|&t| self.triangles[t] != other.triangles()[t]) {
            Some(t) => Err(Error::TriangleMismatch {
                triangle: t,
                message: format!(
                    "triangle {t} is {:?} in {mine} but {:?} in {theirs}: they must have the same triangles",
                    self.triangles[t],
                    other.triangles()[t]
                ),
            }),
            None => Ok(()),
        }
    }

    /// Takes the mesh apart into positions and triangles.
    pub fn into_parts(self) -> (Vec<[f64; D]>, Vec<[u32; 3]>) {
        (self.positions, self.triangles)
    }

    /// Length of the diagonal of the axis-aligned bounding box of the
    /// vertices that triangles use: a stray unused vertex changes no scale.
    pub fn bounding_box_diagonal(&self) -> f64 {
        used_bounding_box_diagonal(&self.positions, &self.triangles)
    }

    /// How many vertices no triangle uses (they are carried through every
    /// operation unchanged).
    pub fn num_unused_vertices(&self) -> usize {
        let used = used_vertices(self.positions.len(), &self.triangles);
        used.iter().filter(|u| !**u).count()
    }

    /// The vertices of triangle `t`.
    #[inline]
    pub fn corners(&self, t: usize) -> [[f64; D]; 3] {
        let [a, b, c] = self.triangles[t];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }
}

impl Mesh3 {
    /// The planar mesh, if every z coordinate is exactly 0.
    ///
    /// # Errors
    /// [`Error::InvalidVertex`] naming the first vertex with a non-zero z.
    pub fn to_2d(&self) -> Result<Mesh2> {
        if let Some(v) = self.positions.iter().position(|p| p[2] != 0.0) {
            return Err(Error::InvalidVertex {
                vertex: v,
                message: format!(
                    "vertex {v} has z = {} but a planar mesh (every z = 0) is required",
                    self.positions[v][2]
                ),
            });
        }
        Ok(Mesh2 {
            positions: self.positions.iter().map(|p| [p[0], p[1]]).collect(),
            triangles: self.triangles.clone(),
        })
    }

    /// Twice the area vector (cross product of two edges) of each triangle.
    pub fn triangle_normals_unnormalized(&self) -> Vec<[f64; 3]> {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                crate::linalg::vector::cross(
                    crate::linalg::vector::sub(b, a),
                    crate::linalg::vector::sub(c, a),
                )
            })
            .collect()
    }
}

impl Mesh3 {
    /// Area of each triangle.
    pub fn triangle_areas(&self) -> Vec<f64> {
        self.triangle_normals_unnormalized()
            .iter()
            .map(|n| 0.5 * crate::linalg::vector::norm(*n))
            .collect()
    }

    /// Fails on triangles of (numerically) zero area; `name` says which mesh
    /// it is in the message.
    ///
    /// # Errors
    /// [`Error::DegenerateTriangles`] naming the first few.
    pub fn check_no_degenerate_triangles(&self, name: &str) -> Result<()> {
        check_areas(&self.triangle_areas(), self.bounding_box_diagonal(), name)
    }
}

/// Fails on triangles whose (absolute) area is at most `1e-14 · diagonal²`
/// or not a number, where `diagonal` is that of the used vertices' box.
/// Coordinates so large that the box or an area is not a finite number
/// are named as overflow, not as degenerate triangles.
pub fn check_areas(areas: &[f64], diagonal: f64, name: &str) -> Result<()> {
    check_overflow(areas, diagonal, name)?;
    let tiny = 1e-14 * diagonal * diagonal;
    let bad: Vec<usize> = (0..areas.len())
        .filter(|&t| areas[t].abs() <= tiny || areas[t].is_nan())
        .collect();
    if bad.is_empty() {
        return Ok(());
    }
    Err(Error::DegenerateTriangles {
        mesh: name.into(),
        count: bad.len(),
        first: bad.into_iter().take(crate::error::LIST_LIMIT).collect(),
    })
}

/// Fails when the used vertices' box (its `diagonal`) or a triangle's area
/// is not a finite number: coordinates so large that products of them
/// overflow.
pub fn check_overflow(areas: &[f64], diagonal: f64, name: &str) -> Result<()> {
    if !diagonal.is_finite() {
        return Err(Error::InvalidMesh(format!(
            "the {name}'s coordinates overflow: its extent exceeds the range of floating-point numbers (about 1.8e308); scale it down"
        )));
    }
    // Coordinates are finite (checked by `Mesh::new`): an area that is not
    // comes from overflow in its products.
    if let Some(t) = areas.iter().position(|a| !a.is_finite()) {
        return Err(Error::InvalidTriangle {
            triangle: t,
            message: format!(
                "the {name}'s triangle {t} overflows: its area exceeds the range of floating-point numbers; scale the mesh down"
            ),
        });
    }
    Ok(())
}

impl Mesh2 {
    /// The same mesh in the plane z = 0.
    pub fn to_3d(&self) -> Mesh3 {
        Mesh3 {
            positions: self.positions.iter().map(|p| [p[0], p[1], 0.0]).collect(),
            triangles: self.triangles.clone(),
        }
    }

    /// Signed area of each triangle: positive when counter-clockwise.
    pub fn signed_areas(&self) -> Vec<f64> {
        signed_areas(&self.positions, &self.triangles)
    }
}

/// Signed area of each triangle of a planar mesh: positive when counter-clockwise.
pub fn signed_areas(positions: &[[f64; 2]], triangles: &[[u32; 3]]) -> Vec<f64> {
    triangles
        .iter()
        .map(|&[a, b, c]| {
            crate::linalg::vector::signed_area2(
                positions[a as usize],
                positions[b as usize],
                positions[c as usize],
            )
        })
        .collect()
}

/// Which of `num_vertices` vertices some triangle uses.
pub fn used_vertices(num_vertices: usize, triangles: &[[u32; 3]]) -> Vec<bool> {
    let mut used = vec![false; num_vertices];
    for t in triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    used
}

/// [`bounding_box_diagonal`] of the vertices that `triangles` use.
pub fn used_bounding_box_diagonal<const D: usize>(
    positions: &[[f64; D]],
    triangles: &[[u32; 3]],
) -> f64 {
    let used = used_vertices(positions.len(), triangles);
    let points: Vec<[f64; D]> = positions
        .iter()
        .zip(&used)
        .filter(|(_, u)| **u)
        .map(|(p, _)| *p)
        .collect();
    bounding_box_diagonal(&points)
}

/// Length of the diagonal of the axis-aligned bounding box of `points`
/// (0 for an empty slice).
pub fn bounding_box_diagonal<const D: usize>(points: &[[f64; D]]) -> f64 {
    let mut lo = [f64::INFINITY; D];
    let mut hi = [f64::NEG_INFINITY; D];
    for p in points {
        for k in 0..D {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if points.is_empty() {
        return 0.0;
    }
    // Scaled by the largest extent, so that a box wider than 1e154 does not
    // overflow when squared; infinite only when an extent is.
    let extents: [f64; D] = std::array::from_fn(|k| hi[k] - lo[k]);
    let largest = extents.iter().fold(0.0f64, |m, e| m.max(*e));
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    largest
        * extents
            .iter()
            .map(|e| (e / largest).powi(2))
            .sum::<f64>()
            .sqrt()
}

/// The first vertex of `positions` with a coordinate that is not finite, as
/// an error; `what` (when not empty) says whose positions they are.
pub fn check_finite<const D: usize>(positions: &[[f64; D]], what: &str) -> Result<()> {
    match positions
        .iter()
        .position(|p| p.iter().any(|x| !x.is_finite()))
    {
        Some(v) => Err(Error::InvalidVertex {
            vertex: v,
            message: format!(
                "{what}{}vertex {v} has a coordinate that is not a finite number: {:?}",
                if what.is_empty() { "" } else { ": " },
                positions[v]
            ),
        }),
        None => Ok(()),
    }
}

fn check_indices(num_vertices: usize, triangles: &[[u32; 3]]) -> Result<()> {
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(&i) = tri.iter().find(|&&i| i as usize >= num_vertices) {
            return Err(Error::InvalidTriangle {
                triangle: t,
                message: format!(
                    "triangle {t} uses vertex {i} but the mesh has {num_vertices} vertices"
                ),
            });
        }
        if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
            return Err(Error::InvalidTriangle {
                triangle: t,
                message: format!("triangle {t} repeats a vertex: {tri:?}"),
            });
        }
    }
    Ok(())
}
