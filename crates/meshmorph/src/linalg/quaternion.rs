//! Rotations in space: unit quaternions, the rotation logarithm (rotation
//! vector, axis times angle) and exponential.
//!
//! A rotation vector `w` stands for the rotation by `|w|` radians about
//! `w / |w|`, counter-clockwise when seen from the tip of the axis. The
//! principal logarithm has `|w| ≤ π`. Quaternions are `[w, x, y, z]`, scalar
//! first; `q` and `−q` are the same rotation, and the principal one has
//! `w ≥ 0`.
#![allow(non_snake_case)]

use crate::linalg::lanes::Real;
use crate::linalg::matrix::Mat3;

/// A unit quaternion `[w, x, y, z]`, scalar first.
pub type Quat = [f64; 4];

/// The quaternion of a rotation matrix, with `w ≥ 0`.
///
/// Shepperd's method: the largest of `|w|, |x|, |y|, |z|` is taken from the
/// diagonal, the others from off-diagonal sums, so it is accurate near a
/// half turn (`w` near 0) as well as near the identity.
pub fn quat_from_matrix(R: &Mat3) -> Quat {
    let (m00, m11, m22) = (R[0][0], R[1][1], R[2][2]);
    let trace = m00 + m11 + m22;
    let mut q = if trace >= m00 && trace >= m11 && trace >= m22 {
        let r = (1.0 + trace).max(0.0).sqrt();
        let s = 0.5 / r;
        [
            0.5 * r,
            (R[2][1] - R[1][2]) * s,
            (R[0][2] - R[2][0]) * s,
            (R[1][0] - R[0][1]) * s,
        ]
    } else if m00 >= m11 && m00 >= m22 {
        let r = (1.0 + m00 - m11 - m22).max(0.0).sqrt();
        let s = 0.5 / r;
        [
            (R[2][1] - R[1][2]) * s,
            0.5 * r,
            (R[0][1] + R[1][0]) * s,
            (R[0][2] + R[2][0]) * s,
        ]
    } else if m11 >= m22 {
        let r = (1.0 - m00 + m11 - m22).max(0.0).sqrt();
        let s = 0.5 / r;
        [
            (R[0][2] - R[2][0]) * s,
            (R[0][1] + R[1][0]) * s,
            0.5 * r,
            (R[1][2] + R[2][1]) * s,
        ]
    } else {
        let r = (1.0 - m00 - m11 + m22).max(0.0).sqrt();
        let s = 0.5 / r;
        [
            (R[1][0] - R[0][1]) * s,
            (R[0][2] + R[2][0]) * s,
            (R[1][2] + R[2][1]) * s,
            0.5 * r,
        ]
    };
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let sign = if q[0] < 0.0 { -1.0 } else { 1.0 };
    q.iter_mut().for_each(|x| *x *= sign / n);
    q
}

/// The rotation matrix of a unit quaternion.
#[inline]
pub fn quat_to_matrix(q: Quat) -> Mat3 {
    matrix_of(q)
}

/// The product `a b` (the rotation `b` first, then `a`).
#[inline]
pub fn quat_mul(a: Quat, b: Quat) -> Quat {
    product(a, b)
}

/// [`quat_to_matrix`] in any [`Real`] arithmetic.
#[inline(always)]
pub fn matrix_of<T: Real>(q: [T; 4]) -> [[T; 3]; 3] {
    let [w, x, y, z] = q;
    let (xx, yy, zz) = (x * x, y * y, z * z);
    let (xy, xz, yz) = (x * y, x * z, y * z);
    let (wx, wy, wz) = (w * x, w * y, w * z);
    let (one, two) = (T::splat(1.0), T::splat(2.0));
    [
        [one - two * (yy + zz), two * (xy - wz), two * (xz + wy)],
        [two * (xy + wz), one - two * (xx + zz), two * (yz - wx)],
        [two * (xz - wy), two * (yz + wx), one - two * (xx + yy)],
    ]
}

/// [`quat_mul`] in any [`Real`] arithmetic.
#[inline(always)]
pub fn product<T: Real>(a: [T; 4], b: [T; 4]) -> [T; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// The conjugate of a unit quaternion: the inverse rotation.
#[inline]
pub fn quat_conj(q: Quat) -> Quat {
    [q[0], -q[1], -q[2], -q[3]]
}

/// The principal one of `q` and `−q` (the same rotation): `w ≥ 0`.
#[inline]
pub fn quat_principal(q: Quat) -> Quat {
    if q[0] < 0.0 {
        q.map(|x| -x)
    } else {
        q
    }
}

/// The 4D dot product: `cos(φ/2)` up to sign, `φ` the angle of the rotation
/// between `a` and `b`.
#[inline]
pub fn quat_dot(a: Quat, b: Quat) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

/// The quaternion of the rotation by `angle` radians about the unit `axis`.
#[inline]
pub fn quat_axis_angle(axis: [f64; 3], angle: f64) -> Quat {
    let (s, c) = crate::linalg::trig::sin_cos(0.5 * angle);
    [c, s * axis[0], s * axis[1], s * axis[2]]
}

/// The principal rotation vector of a unit quaternion: `|w| ∈ [0, π]`.
/// Accurate near the identity (`atan2` of the small vector part) and near a
/// half turn.
#[inline]
pub fn quat_log(q: Quat) -> [f64; 3] {
    let (w, v) = if q[0] < 0.0 {
        (-q[0], [-q[1], -q[2], -q[3]])
    } else {
        (q[0], [q[1], q[2], q[3]])
    };
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if n == 0.0 {
        return [0.0; 3];
    }
    let f = 2.0 * n.atan2(w) / n;
    v.map(|x| x * f)
}

/// The unit quaternion of the rotation vector `w` (any length).
#[inline]
pub fn quat_exp(w: [f64; 3]) -> Quat {
    let theta = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    let half = 0.5 * theta;
    let (s, c) = half.sin_cos();
    // sin(θ/2)/θ, by its series where the quotient loses digits.
    let f = if theta < 1e-4 {
        0.5 - theta * theta / 48.0
    } else {
        s / theta
    };
    [c, w[0] * f, w[1] * f, w[2] * f]
}

/// The principal logarithm of a rotation matrix: the rotation vector `w`
/// with `|w| ∈ [0, π]` and `exp(w) = R`. At exactly a half turn both `±w`
/// qualify; one of them is returned.
pub fn log_rotation(R: &Mat3) -> [f64; 3] {
    quat_log(quat_from_matrix(R))
}

/// The rotation matrix `exp([w]×)` of a rotation vector (Rodrigues).
pub fn exp_rotation(w: [f64; 3]) -> Mat3 {
    quat_to_matrix(quat_exp(w))
}
