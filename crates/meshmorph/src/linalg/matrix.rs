//! Small dense matrices: `D × D` arrays, row-major (`m[row][column]`).
//!
//! The per-triangle maps of every algorithm are 2×2 or 3×3; this module
//! holds their algebra once, generic over the size where it can be.
#![allow(non_snake_case)]

/// A `D × D` matrix, row-major.
pub type Mat<const D: usize> = [[f64; D]; D];
/// A 2×2 matrix, row-major.
pub type Mat2 = Mat<2>;
/// A 3×3 matrix, row-major.
pub type Mat3 = Mat<3>;

/// The identity matrix.
#[inline]
pub fn identity<const D: usize>() -> Mat<D> {
    std::array::from_fn(|i| std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 }))
}

/// `A B`.
#[inline]
pub fn mul<const D: usize>(A: Mat<D>, B: Mat<D>) -> Mat<D> {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..D).map(|k| A[i][k] * B[k][j]).sum()))
}

/// `Aᵀ B`.
#[inline]
pub fn mul_tn<const D: usize>(A: &Mat<D>, B: &Mat<D>) -> Mat<D> {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..D).map(|k| A[k][i] * B[k][j]).sum()))
}

/// `A x`.
#[inline]
pub fn mul_vec<const D: usize>(A: &Mat<D>, x: [f64; D]) -> [f64; D] {
    std::array::from_fn(|i| (0..D).map(|k| A[i][k] * x[k]).sum())
}

/// Determinant of a 2×2 matrix.
#[inline]
pub fn det2(A: Mat2) -> f64 {
    A[0][0] * A[1][1] - A[0][1] * A[1][0]
}

/// Determinant of a 3×3 matrix.
#[inline]
pub fn det3(m: Mat3) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// Inverse of a 3×3 matrix, or `None` when the determinant is zero or not finite.
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

/// `(1 − t) A + t B`.
#[inline]
pub fn lerp<const D: usize>(A: &Mat<D>, B: &Mat<D>, t: f64) -> Mat<D> {
    std::array::from_fn(|i| std::array::from_fn(|j| (1.0 - t) * A[i][j] + t * B[i][j]))
}
