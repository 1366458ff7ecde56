//! Gradient operators of triangles in space through their edge bases and
//! fourth vertices (Sumner and Popović 2004, section 3).
//!
//! Each triangle `v1 v2 v3` gets a fourth vertex off its plane,
//! `v4 = v1 + (v2−v1)×(v3−v1) / √|(v2−v1)×(v3−v1)|`, and the frame
//! `V = [v2−v1, v3−v1, v4−v1]`. The deformation gradient of a deformed
//! triangle `ṽ1..ṽ4` is `Q = Ṽ V⁻¹`, an affine map's linear part.
//!
//! With the deformed corners as unknowns, `Q = X G` where `X = [ṽ1 ṽ2 ṽ3 ṽ4]`
//! (3×4) and `G = D V⁻¹` (4×3) with `D` the difference operator: every row
//! of `Q` is a linear function of one coordinate of the four corners, with
//! the same coefficients `G` for x, y and z.
#![allow(non_snake_case)]

use super::GradientOperators;
use crate::error::{Error, Result};
use crate::linalg::matrix::{inverse3, mul, Mat3};
use crate::linalg::vector::{add, cross, norm, scale, sub};
use crate::mesh::Mesh3;

/// The fourth vertex of a triangle: `v1 + n / √|n|` with `n` the (unnormalised)
/// normal. A degenerate triangle (`n = 0`) gets `v1`, which keeps every
/// later quantity finite.
#[inline]
pub fn fourth_vertex(p: [[f64; 3]; 3]) -> [f64; 3] {
    let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    let len = norm(n);
    if len > 0.0 {
        add(p[0], scale(n, 1.0 / len.sqrt()))
    } else {
        p[0]
    }
}

/// The frame `V = [v2−v1, v3−v1, v4−v1]` (columns).
#[inline]
pub fn frame(p: [[f64; 3]; 3]) -> Mat3 {
    let v4 = fourth_vertex(p);
    let (a, b, c) = (sub(p[1], p[0]), sub(p[2], p[0]), sub(v4, p[0]));
    [[a[0], b[0], c[0]], [a[1], b[1], c[1]], [a[2], b[2], c[2]]]
}

/// The gradient operator `G = D V⁻¹` (4×3, row `k` for corner `k`, the
/// fourth vertex last) of a rest triangle with frame inverse `V⁻¹`:
/// `Q[i][j] = Σ_k X[i][k] G[k][j]`.
#[inline]
pub fn gradient_operator(V_inv: Mat3) -> [[f64; 3]; 4] {
    let r = V_inv;
    [
        std::array::from_fn(|j| -(r[0][j] + r[1][j] + r[2][j])),
        r[0],
        r[1],
        r[2],
    ]
}

/// Deformation gradient `Q = Ṽ V⁻¹` of a triangle whose rest frame has
/// inverse `V_inv` and whose deformed corners are `p`.
#[inline]
pub fn deformation_gradient(V_inv: Mat3, p: [[f64; 3]; 3]) -> Mat3 {
    mul(frame(p), V_inv)
}

impl GradientOperators<3, 4> {
    /// The operators `G = D V⁻¹` of every triangle of `mesh` over its
    /// vertices and one fourth vertex per triangle; `name` says which mesh it
    /// is in errors.
    ///
    /// # Errors
    /// As [`frame_inverses`].
    pub fn spatial(mesh: &Mesh3, name: &str) -> Result<Self> {
        let operators = frame_inverses(mesh, name)?
            .into_iter()
            .map(gradient_operator)
            .collect();
        Ok(Self::from_parts(
            mesh.num_vertices(),
            mesh.triangles().to_vec(),
            operators,
        ))
    }
}

/// `V⁻¹` of every triangle of `mesh`.
///
/// # Errors
/// [`Error::InvalidTriangle`] naming the first
/// triangle whose frame cannot be inverted: a zero-area triangle, or
/// coordinates so large or small that the determinant leaves the range of
/// `f64`.
pub(crate) fn frame_inverses(mesh: &Mesh3, name: &str) -> Result<Vec<Mat3>> {
    (0..mesh.num_triangles())
        .map(|t| {
            inverse3(frame(mesh.corners(t))).ok_or_else(|| Error::InvalidTriangle {
                triangle: t,
                message: format!(
                    "triangle {t} of the {name} has no invertible frame (zero area, or \
                         coordinates too large or too small: rescale the mesh)"
                ),
            })
        })
        .collect()
}
