//! Polar decompositions `A = R S` (a rotation times a stretch) of 2×2 and
//! 3×3 matrices, and powers of symmetric matrices.
//!
//! Matrices are row-major `[[a00, a01], [a10, a11]]`. In the plane the
//! decomposition is closed-form: `R` is the rotation by an angle. In space
//! it goes through the symmetric eigen decomposition of `AᵀA` (cyclic Jacobi
//! rotations, which are accurate to the last bits for any symmetric matrix),
//! i.e. through the singular value decomposition `A = U Σ Vᵀ`; the rotation is
//! `R = U Vᵀ` with `U` and `V` made proper, so that `R` is a rotation even
//! when `A` is singular or reverses orientation.
#![allow(non_snake_case)]

use crate::linalg::matrix::{det2, det3, mul_tn, mul_vec, Mat2, Mat3};
use crate::linalg::vector::{cross, dot, norm, scale, sub};

/// `A = R(θ) S` with `R(θ)` the rotation by `angle` (radians,
/// counter-clockwise) and `S` the remaining factor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polar2 {
    /// θ in (-π, π], counter-clockwise.
    pub angle: f64,
    /// `S = R(θ)ᵀ A`: symmetric positive semi-definite when `det A ≥ 0`.
    pub stretch: Mat2,
}

/// The rotation matrix `R(θ)`.
#[inline]
pub fn rotation(angle: f64) -> Mat2 {
    let (s, c) = crate::linalg::trig::sin_cos(angle);
    [[c, -s], [s, c]]
}

/// Polar decomposition `A = R(θ) S` (Alexa et al. 2000, section 3).
///
/// The rotation is the one closest to `A` in the Frobenius norm:
/// `θ = atan2(a10 − a01, a00 + a11)`. For `det A > 0`, `S` is symmetric
/// positive definite. For `det A < 0` (a reflected triangle) no rotation
/// makes `S` symmetric; the closest rotation is still returned and `S` is
/// `R(θ)ᵀ A`, which keeps `A = R S` exact.
pub fn polar_decomposition(A: Mat2) -> Polar2 {
    let angle = (A[1][0] - A[0][1]).atan2(A[0][0] + A[1][1]);
    let (s, c) = angle.sin_cos();
    // Rᵀ A with Rᵀ = [[c, s], [-s, c]].
    let mut S = [
        [c * A[0][0] + s * A[1][0], c * A[0][1] + s * A[1][1]],
        [-s * A[0][0] + c * A[1][0], -s * A[0][1] + c * A[1][1]],
    ];
    if det2(A) >= 0.0 {
        // Symmetric up to rounding: make it exactly so.
        let off = 0.5 * (S[0][1] + S[1][0]);
        S[0][1] = off;
        S[1][0] = off;
    }
    Polar2 { angle, stretch: S }
}

/// Eigen decomposition of a symmetric 2×2 matrix `S = λ₁ u uᵀ + λ₂ w wᵀ`
/// with `u = (cos φ, sin φ)`, `w = (−sin φ, cos φ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SymmetricEigen2 {
    /// `λ₁, λ₂`.
    pub values: [f64; 2],
    /// `φ`, radians.
    pub angle: f64,
}

impl SymmetricEigen2 {
    /// Decomposes the symmetric part of `S`.
    pub fn new(S: Mat2) -> Self {
        let (p, q, r) = (S[0][0], 0.5 * (S[0][1] + S[1][0]), S[1][1]);
        let mean = 0.5 * (p + r);
        let radius = (0.25 * (p - r) * (p - r) + q * q).sqrt();
        let angle = 0.5 * (2.0 * q).atan2(p - r);
        Self {
            values: [mean + radius, mean - radius],
            angle,
        }
    }

    /// `f(λ₁) u uᵀ + f(λ₂) w wᵀ`.
    pub fn map_values(&self, f: impl Fn(f64) -> f64) -> Mat2 {
        let (l1, l2) = (f(self.values[0]), f(self.values[1]));
        let (s, c) = self.angle.sin_cos();
        let (cc, ss, cs) = (c * c, s * s, c * s);
        let off = (l1 - l2) * cs;
        [[l1 * cc + l2 * ss, off], [off, l1 * ss + l2 * cc]]
    }

    /// `S^t = λ₁ᵗ u uᵀ + λ₂ᵗ w wᵀ`, with eigenvalues below `floor` raised to
    /// it first so that every power is defined and positive definite.
    pub fn power(&self, t: f64, floor: f64) -> Mat2 {
        let l1 = self.values[0].max(floor).powf(t);
        let l2 = self.values[1].max(floor).powf(t);
        let (s, c) = self.angle.sin_cos();
        let (cc, ss, cs) = (c * c, s * s, c * s);
        let off = (l1 - l2) * cs;
        [[l1 * cc + l2 * ss, off], [off, l1 * ss + l2 * cc]]
    }
}

/// The identity matrix.
pub const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// Eigen decomposition of a symmetric 3×3 matrix,
/// `S = Σ_k λ_k v_k v_kᵀ`, eigenvalues in decreasing order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SymmetricEigen3 {
    /// `λ₁ ≥ λ₂ ≥ λ₃`.
    pub values: [f64; 3],
    /// The eigenvectors as the columns `v_k` (`vectors[i][k]` is component `i`
    /// of `v_k`), orthonormal, with determinant +1.
    pub vectors: Mat3,
}

impl SymmetricEigen3 {
    /// Decomposes the symmetric part of `S` by cyclic Jacobi rotations.
    pub fn new(S: Mat3) -> Self {
        let mut a: Mat3 =
            std::array::from_fn(|i| std::array::from_fn(|j| 0.5 * (S[i][j] + S[j][i])));
        let mut v = IDENTITY;
        for _sweep in 0..64 {
            let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
            let diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
            if off <= 1e-32 * diag || off == 0.0 {
                break;
            }
            for (p, q) in [(0, 1), (0, 2), (1, 2)] {
                if a[p][q] == 0.0 {
                    continue;
                }
                // The rotation in the (p, q) plane that zeroes a[p][q]
                // (Golub and Van Loan, algorithm 8.4.1, the small root).
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                // (θ² overflows only for |θ| > 1e154, where t ≈ 1/(2θ).)
                let t = if theta.abs() < 1e150 {
                    theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt())
                } else {
                    0.5 / theta
                };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                // a ← Jᵀ a J, v ← v J, J the identity with J[p][p] = J[q][q] = c,
                // J[p][q] = s, J[q][p] = −s.
                for k in 0..3 {
                    let (akp, akq) = (a[k][p], a[k][q]);
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for k in 0..3 {
                    let (apk, aqk) = (a[p][k], a[q][k]);
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                a[p][q] = 0.0;
                a[q][p] = 0.0;
                for k in 0..3 {
                    let (vkp, vkq) = (v[k][p], v[k][q]);
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
        }
        let mut order = [0, 1, 2];
        order.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
        let values = order.map(|k| a[k][k]);
        let mut vectors: Mat3 = std::array::from_fn(|i| order.map(|k| v[i][k]));
        if det3(vectors) < 0.0 {
            for row in &mut vectors {
                row[2] = -row[2];
            }
        }
        Self { values, vectors }
    }

    /// Eigenvector `k` (a column of [`SymmetricEigen3::vectors`]).
    #[inline]
    pub fn vector(&self, k: usize) -> [f64; 3] {
        [self.vectors[0][k], self.vectors[1][k], self.vectors[2][k]]
    }

    /// `Σ_k f(λ_k) v_k v_kᵀ`.
    #[inline]
    pub fn map_values(&self, f: impl Fn(f64) -> f64) -> Mat3 {
        let l = self.values.map(f);
        let V = &self.vectors;
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                l[0] * V[i][0] * V[j][0] + l[1] * V[i][1] * V[j][1] + l[2] * V[i][2] * V[j][2]
            })
        })
    }

    /// `Sᵗ = Σ_k λ_kᵗ v_k v_kᵀ`, with eigenvalues below `floor` raised to it
    /// first so that every power is defined and positive definite.
    #[inline]
    pub fn power(&self, t: f64, floor: f64) -> Mat3 {
        self.map_values(|l| l.max(floor).powf(t))
    }
}

/// `A = R S` with `R` a proper rotation (`RᵀR = I`, `det R = +1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polar3 {
    /// The proper rotation nearest to `A` in the Frobenius norm among those
    /// that make `S` symmetric.
    pub rotation: Mat3,
    /// `S = Rᵀ A`, symmetric; positive semi-definite when `det A ≥ 0`, with
    /// one negative eigenvalue (the direction `A` reverses) when `det A < 0`.
    pub stretch: Mat3,
}

/// Polar decomposition `A = R S` with `R` a proper rotation.
///
/// From the eigen decomposition `AᵀA = V Σ² Vᵀ` (with `det V = +1`):
/// `u₁ = A v₁ / σ₁`, `u₂` the unit part of `A v₂` orthogonal to `u₁`,
/// `u₃ = u₁ × u₂`, and `R = U Vᵀ`. The third column never divides by the
/// smallest singular value, so a matrix that flattens a direction (rank 2)
/// still gets an exact rotation; for `det A < 0` the rotation is the
/// nearest proper one and `S` carries the reflection as a negative
/// eigenvalue. Rank 0 and rank 1 get any rotation that satisfies `A = R S`
/// with `S` symmetric (the identity for `A = 0`).
pub fn polar_decomposition3(A: Mat3) -> Polar3 {
    let eig = SymmetricEigen3::new(mul_tn(&A, &A));
    let (v1, v2) = (eig.vector(0), eig.vector(1));
    let a1 = mul_vec(&A, v1);
    let n1 = norm(a1);
    let scale_a = A.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let tiny = 1e-300f64.max(scale_a * 1e-15);
    if n1 <= tiny {
        return Polar3 {
            rotation: IDENTITY,
            stretch: A,
        };
    }
    let u1 = scale(a1, 1.0 / n1);
    let a2 = mul_vec(&A, v2);
    let mut w2 = sub(a2, scale(u1, dot(u1, a2)));
    if norm(w2) <= tiny {
        // Rank 1: any unit vector orthogonal to u₁.
        let e = if u1[0].abs() < 0.6 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        w2 = cross(u1, e);
    }
    let u2 = scale(w2, 1.0 / norm(w2));
    let u3 = cross(u1, u2);
    let v3 = eig.vector(2);
    // R = u₁v₁ᵀ + u₂v₂ᵀ + u₃v₃ᵀ.
    let R: Mat3 = std::array::from_fn(|i| {
        std::array::from_fn(|j| u1[i] * v1[j] + u2[i] * v2[j] + u3[i] * v3[j])
    });
    let mut S = mul_tn(&R, &A);
    for i in 0..3 {
        for j in i + 1..3 {
            let m = 0.5 * (S[i][j] + S[j][i]);
            S[i][j] = m;
            S[j][i] = m;
        }
    }
    Polar3 {
        rotation: R,
        stretch: S,
    }
}
