//! Per-triangle frames and deformation gradients in space (Sumner and
//! Popović 2004, section 3).
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

use crate::geometry::{add, cross, norm, scale, sub};
use crate::solve::SymmetricBuilder;

/// A 3×3 matrix, row-major.
pub type Mat3 = [[f64; 3]; 3];

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

/// Determinant.
#[inline]
pub fn det3(m: Mat3) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// Inverse, or `None` when the determinant is zero.
pub fn inverse3(m: Mat3) -> Option<Mat3> {
    let d = det3(m);
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let inv = 1.0 / d;
    let c =
        |r0: usize, r1: usize, c0: usize, c1: usize| m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
    Some([
        [
            c(1, 2, 1, 2) * inv,
            -c(0, 2, 1, 2) * inv,
            c(0, 1, 1, 2) * inv,
        ],
        [
            -c(1, 2, 0, 2) * inv,
            c(0, 2, 0, 2) * inv,
            -c(0, 1, 0, 2) * inv,
        ],
        [
            c(1, 2, 0, 1) * inv,
            -c(0, 2, 0, 1) * inv,
            c(0, 1, 0, 1) * inv,
        ],
    ])
}

/// `A B`.
#[inline]
pub fn mul3(A: Mat3, B: Mat3) -> Mat3 {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| A[i][k] * B[k][j]).sum()))
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
    mul3(frame(p), V_inv)
}

/// The gradient operators of every triangle of a rest mesh, and the
/// least-squares terms built from them. The unknowns are the `#V` vertices
/// followed by one fourth vertex per triangle; every coordinate has the same
/// matrix, so a term is added once and its right-hand side has three columns.
#[derive(Clone, Debug)]
pub struct GradientOperators {
    num_vertices: usize,
    triangles: Vec<[u32; 3]>,
    operators: Vec<[[f64; 3]; 4]>,
}

impl GradientOperators {
    /// The operators of `mesh`; `name` says which mesh it is in errors.
    ///
    /// # Errors
    /// As [`frame_inverses`].
    pub fn new(mesh: &crate::mesh::Mesh3, name: &str) -> crate::Result<Self> {
        let operators = frame_inverses(mesh, name)?
            .into_iter()
            .map(gradient_operator)
            .collect();
        Ok(Self {
            num_vertices: mesh.num_vertices(),
            triangles: mesh.triangles().to_vec(),
            operators,
        })
    }

    /// Number of unknowns: vertices and fourth vertices.
    pub fn num_unknowns(&self) -> usize {
        self.num_vertices + self.triangles.len()
    }

    /// The operator `G` (4×3) of triangle `t`.
    #[inline]
    pub fn operator(&self, t: usize) -> &[[f64; 3]; 4] {
        &self.operators[t]
    }

    /// The unknowns of triangle `t`: its corners, then its fourth vertex.
    #[inline]
    pub fn unknowns(&self, t: usize) -> [usize; 4] {
        let [a, b, c] = self.triangles[t];
        [a as usize, b as usize, c as usize, self.num_vertices + t]
    }

    /// `weight · ‖T_t − Q‖²_F`: adds the matrix part to `builder` and
    /// `weight · G Qᵀ` to the column-major `#unknowns × 3` right-hand side.
    pub fn add_target(
        &self,
        builder: &mut SymmetricBuilder,
        rhs: &mut [f64],
        t: usize,
        Q: &Mat3,
        weight: f64,
    ) {
        builder.add_gram(&self.unknowns(t), &self.operators[t], weight);
        self.add_target_rhs(rhs, t, Q, weight);
    }

    /// The right-hand side part of [`GradientOperators::add_target`] alone.
    #[inline]
    pub fn add_target_rhs(&self, rhs: &mut [f64], t: usize, Q: &Mat3, weight: f64) {
        let m = self.num_unknowns();
        let G = &self.operators[t];
        for (k, u) in self.unknowns(t).into_iter().enumerate() {
            for i in 0..3 {
                rhs[i * m + u] +=
                    weight * (G[k][0] * Q[i][0] + G[k][1] * Q[i][1] + G[k][2] * Q[i][2]);
            }
        }
    }

    /// `weight · ‖T_a − T_b‖²_F` (no right-hand side).
    pub fn add_difference(&self, builder: &mut SymmetricBuilder, a: usize, b: usize, weight: f64) {
        let (ua, ub) = (self.unknowns(a), self.unknowns(b));
        let idx: [usize; 8] = std::array::from_fn(|k| if k < 4 { ua[k] } else { ub[k - 4] });
        let coef: [[f64; 3]; 8] = std::array::from_fn(|k| {
            if k < 4 {
                self.operators[a][k]
            } else {
                self.operators[b][k - 4].map(|x| -x)
            }
        });
        builder.add_gram(&idx, &coef, weight);
    }
}

/// `V⁻¹` of every triangle of `mesh`.
///
/// # Errors
/// [`Error::InvalidMesh`](crate::Error::InvalidMesh) naming the first
/// triangle whose frame cannot be inverted: a zero-area triangle, or
/// coordinates so large or small that the determinant leaves the range of
/// `f64`.
pub fn frame_inverses(mesh: &crate::mesh::Mesh3, name: &str) -> crate::Result<Vec<Mat3>> {
    (0..mesh.num_triangles())
        .map(|t| {
            inverse3(frame(mesh.corners(t))).ok_or_else(|| {
                crate::Error::InvalidMesh(format!(
                    "triangle {t} of the {name} has no invertible frame (zero area, or \
                     coordinates too large or too small: rescale the mesh)"
                ))
            })
        })
        .collect()
}

/// The identity matrix.
pub const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_of_a_rotated_triangle_give_the_rotation() {
        let p = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.5, 1.0, 0.0]];
        let (s, c) = 0.7f64.sin_cos();
        let R: Mat3 = [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]];
        let q = p.map(|v| {
            add(
                std::array::from_fn(|i| (0..3).map(|k| R[i][k] * v[k]).sum()),
                [1.0, 2.0, 3.0],
            )
        });
        let V_inv = inverse3(frame(p)).unwrap();
        let Q = deformation_gradient(V_inv, q);
        for i in 0..3 {
            for j in 0..3 {
                assert!((Q[i][j] - R[i][j]).abs() < 1e-12, "{Q:?}");
            }
        }
        // The same through the operator G.
        let v4 = fourth_vertex(q);
        let X = [q[0], q[1], q[2], v4];
        let G = gradient_operator(V_inv);
        for i in 0..3 {
            for j in 0..3 {
                let qij: f64 = (0..4).map(|k| X[k][i] * G[k][j]).sum();
                assert!((qij - R[i][j]).abs() < 1e-12);
            }
        }
        let I = mul3(frame(p), V_inv);
        assert!((det3(I) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn degenerate_triangles_stay_finite() {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        assert_eq!(fourth_vertex(p), p[0]);
        assert!(inverse3(frame(p)).is_none());
    }
}
