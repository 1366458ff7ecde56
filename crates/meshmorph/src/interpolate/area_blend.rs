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
use crate::linalg::polar::SymmetricEigen2;

/// `(1 − u) a + u b`, its smaller principal stretch shrunk where its
/// determinant exceeds `(1 − u) det a + u det b`.
pub(crate) fn area_blend(a: &Mat2, b: &Mat2, u: f64) -> Mat2 {
    let blend = lerp(a, b, u);
    let area = (1.0 - u) * det2(*a) + u * det2(*b);
    let eigen = SymmetricEigen2::new(blend);
    let [large, small] = eigen.values;
    if large <= 0.0 || area <= 0.0 || large * small <= area {
        return blend;
    }
    SymmetricEigen2 {
        values: [large, area / large],
        angle: eigen.angle,
    }
    .map_values(|l| l)
}

#[cfg(test)]
mod tests {
    use super::*;
    const IDENTITY2: Mat2 = [[1.0, 0.0], [0.0, 1.0]];

    fn close(a: Mat2, b: Mat2) -> bool {
        (0..2).all(|i| (0..2).all(|j| (a[i][j] - b[i][j]).abs() < 1e-12))
    }

    #[test]
    fn area_kept_where_one_stretch_grows_and_the_other_shrinks() {
        // A threefold stretch along a direction at 30°, a threefold
        // squeeze across it.
        let s = SymmetricEigen2 {
            values: [3.0, 1.0 / 3.0],
            angle: 30f64.to_radians(),
        }
        .map_values(|l| l);
        for k in 0..=10 {
            let u = k as f64 / 10.0;
            let m = area_blend(&IDENTITY2, &s, u);
            let e = SymmetricEigen2::new(m);
            assert!((det2(m) - 1.0).abs() < 1e-12, "area {} at {u}", det2(m));
            // The longer direction on its straight blend, the same axis.
            assert!((e.values[0] - (1.0 + 2.0 * u)).abs() < 1e-12);
            if k > 0 {
                assert!((e.angle - 30f64.to_radians()).abs() < 1e-9, "{e:?}");
            }
        }
        assert!(close(area_blend(&IDENTITY2, &s, 0.0), IDENTITY2));
        assert!(close(area_blend(&IDENTITY2, &s, 1.0), s));
    }

    #[test]
    fn straight_blend_kept_where_it_does_not_swell() {
        // Both grow (a uniform scale, an uneven one), both shrink.
        for s in [
            [[3.0, 0.0], [0.0, 3.0]],
            [[2.0, 0.4], [0.4, 1.5]],
            [[0.5, 0.1], [0.1, 0.6]],
        ] {
            for u in [0.0, 0.3, 0.5, 1.0] {
                assert!(close(
                    area_blend(&IDENTITY2, &s, u),
                    lerp(&IDENTITY2, &s, u)
                ));
            }
        }
    }
}
