use meshmorph::linalg::matrix::{det2, lerp, Mat2};

use meshmorph::interpolate::area_blend::*;
use meshmorph::linalg::polar::SymmetricEigen2;
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

#[test]
fn the_same_as_shrinking_the_smaller_eigenvalue() {
    // Random pairs of stretches, against the eigen decomposition with
    // the smaller eigenvalue replaced.
    let mut seed = 11u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut stretch = || {
        SymmetricEigen2 {
            values: [0.1 + 4.0 * next(), 0.1 + 4.0 * next()],
            angle: 7.0 * next(),
        }
        .map_values(|l| l)
    };
    let mut shrunk = 0;
    for _ in 0..1000 {
        let (a, b) = (stretch(), stretch());
        for u in [0.1, 0.5, 0.77] {
            let blend = lerp(&a, &b, u);
            let area = (1.0 - u) * det2(a) + u * det2(b);
            let e = SymmetricEigen2::new(blend);
            let expected = if e.values[0] * e.values[1] > area {
                shrunk += 1;
                SymmetricEigen2 {
                    values: [e.values[0], area / e.values[0]],
                    angle: e.angle,
                }
                .map_values(|l| l)
            } else {
                blend
            };
            let got = area_blend(&a, &b, u);
            for i in 0..2 {
                for j in 0..2 {
                    assert!(
                        (got[i][j] - expected[i][j]).abs() < 1e-12 * (1.0 + expected[i][j].abs()),
                        "{a:?} {b:?} at {u}: {got:?} against {expected:?}"
                    );
                }
            }
        }
    }
    assert!(shrunk > 300, "{shrunk} shrunk");
    // Stretched the same both ways yet above the blended area: y gives way.
    let (a, b) = ([[2.0, 0.0], [0.0, 0.5]], [[0.5, 0.0], [0.0, 2.0]]);
    let got = area_blend(&a, &b, 0.5);
    assert!(
        (got[0][0] - 1.25).abs() < 1e-15 && (det2(got) - 1.0).abs() < 1e-12,
        "{got:?}"
    );
}
