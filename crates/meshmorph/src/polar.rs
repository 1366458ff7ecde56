//! Closed-form polar decomposition of 2×2 matrices and powers of symmetric
//! 2×2 matrices.
//!
//! Matrices are row-major `[[a00, a01], [a10, a11]]`.
#![allow(non_snake_case)]

use crate::matrix::{det2, Mat2};

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
    let (s, c) = crate::trig::sin_cos(angle);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::matrix::mul;

    fn close(A: Mat2, B: Mat2, tol: f64) -> bool {
        (0..2).all(|i| (0..2).all(|j| (A[i][j] - B[i][j]).abs() <= tol))
    }

    #[test]
    fn reconstructs_and_is_symmetric() {
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
        };
        for _ in 0..1000 {
            let A = [[rnd(), rnd()], [rnd(), rnd()]];
            let p = polar_decomposition(A);
            assert!(close(mul(rotation(p.angle), p.stretch), A, 1e-12));
            assert!(p.angle > -std::f64::consts::PI && p.angle <= std::f64::consts::PI);
            if det2(A) > 0.0 {
                let S = p.stretch;
                assert_eq!(S[0][1], S[1][0]);
                let e = SymmetricEigen2::new(S);
                assert!(e.values[1] > -1e-12, "{e:?}");
                assert!(close(e.power(1.0, 0.0), S, 1e-12));
                assert!(close(e.power(0.0, 0.0), [[1.0, 0.0], [0.0, 1.0]], 1e-12));
                let half = e.power(0.5, 0.0);
                assert!(close(mul(half, half), S, 1e-9));
            }
        }
    }

    #[test]
    fn rotation_by_150_degrees() {
        let theta = 150f64.to_radians();
        let A = mul(rotation(theta), [[2.0, 0.3], [0.3, 0.5]]);
        let p = polar_decomposition(A);
        assert!((p.angle - theta).abs() < 1e-12);
        assert!(close(p.stretch, [[2.0, 0.3], [0.3, 0.5]], 1e-12));
    }
}
