//! The stretch of [`StretchMode::AreaBlend`](crate::StretchMode::AreaBlend):
//! the straight blend of two symmetric stretches, its area held to the
//! straight blend of theirs.
//!
//! A triangle stretched along one direction and squeezed along the other
//! (a fat drawing's part becoming a thin band) keeps each principal length
//! on its straight blend under `(1 − u) S₀ + u S₁`, so its area, their
//! product, runs above the straight blend of its two areas: at `u = ½`, a
//! threefold stretch along and a threefold squeeze across give lengths 2
//! and ⅔, area 1⅓ where the blend is 1. Here the smaller principal length
//! alone gives way, `λ₂ = A / λ₁` with `A` the blended area: the longer
//! direction, the one along a band and its outline, stays on its straight
//! blend; the squeezed one thins sooner. Where the blend's area is not
//! above the blended area (both lengths grow, or both shrink, or a turn),
//! the straight blend is kept as it is.

use crate::linalg::matrix::{det2, lerp, Mat2};

/// `(1 − u) a + u b`, its smaller principal stretch shrunk where its
/// determinant exceeds `(1 − u) det a + u det b`.
///
/// # Performance
/// One square root, no angle: with `S` the blend, `λ₁ > λ₂` its principal
/// stretches and `w` the direction of `λ₂`, the result is `S + (A/λ₁ − λ₂)
/// w wᵀ`, and `w wᵀ = (λ₁ I − S) / (λ₁ − λ₂)`. A blend stretched the same
/// both ways (`λ₁ = λ₂`) gives way along y.
pub fn area_blend(a: &Mat2, b: &Mat2, u: f64) -> Mat2 {
    let blend = lerp(a, b, u);
    let area = (1.0 - u) * det2(*a) + u * det2(*b);
    let (p, q, r) = (blend[0][0], 0.5 * (blend[0][1] + blend[1][0]), blend[1][1]);
    let half = 0.5 * (p - r);
    let radius = (half * half + q * q).sqrt();
    let mean = 0.5 * (p + r);
    let (large, small) = (mean + radius, mean - radius);
    if large <= 0.0 || area <= 0.0 || large * small <= area {
        return blend;
    }
    let shrink = area / large - small;
    if radius == 0.0 {
        return [[p, q], [q, r + shrink]];
    }
    // (λ₁ I − S) / (λ₁ − λ₂), scaled by the shrink.
    let k = shrink / (2.0 * radius);
    let off = q - k * q;
    [
        [p + k * (radius - half), off],
        [off, r + k * (radius + half)],
    ]
}
