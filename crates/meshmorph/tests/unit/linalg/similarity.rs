use meshmorph::linalg::matrix::det3;
use meshmorph::linalg::vector::{dot, norm, scale, sub};

use meshmorph::linalg::similarity::*;

#[test]
fn the_geometric_median_follows_the_majority() {
    // 60 % of the weight at one point, the rest scattered to one side:
    // the mean moves, the median stays on the point.
    let at = [0.3, -1.0, 2.0];
    let mut points = vec![(at, 0.2), (at, 0.4)];
    for k in 0..8 {
        let k = k as f64;
        points.push(([at[0] + 1.0 + 0.1 * k, at[1] + 0.3 * k, at[2] - 0.2], 0.05));
    }
    let median = geometric_median(&points);
    assert!(norm(sub(median, at)) < 1e-8, "{median:?}");
    // Equivariant under a rigid motion and a scale.
    let (R, shift, s) = (turn([1.0, 2.0, -0.5], 0.7), [10.0, -3.0, 4.0], 2.5);
    let moved = |p: [f64; 3]| -> [f64; 3] {
        std::array::from_fn(|i| s * (0..3).map(|k| R[i][k] * p[k]).sum::<f64>() + shift[i])
    };
    let spread: Vec<([f64; 3], f64)> = (0..9)
        .map(|k| {
            let k = k as f64;
            ([k.sin(), (1.3 * k).cos(), 0.1 * k * k], 1.0 + 0.1 * k)
        })
        .collect();
    let a = moved(geometric_median(&spread));
    let b = geometric_median(
        &spread
            .iter()
            .map(|&(p, w)| (moved(p), w))
            .collect::<Vec<_>>(),
    );
    assert!(norm(sub(a, b)) < 1e-8, "{a:?} {b:?}");
    // Three points of equal weight at the corners of an equilateral
    // triangle: its centre.
    let c = geometric_median(&[
        ([1.0, 0.0, 0.0], 1.0),
        ([-0.5, 0.75f64.sqrt(), 0.0], 1.0),
        ([-0.5, -(0.75f64.sqrt()), 0.0], 1.0),
    ]);
    assert!(norm(c) < 1e-9, "{c:?}");
}

fn turn(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let a = scale(axis, 1.0 / norm(axis));
    let (c, s) = (angle.cos(), angle.sin());
    let [x, y, z] = a;
    [
        [
            c + x * x * (1.0 - c),
            x * y * (1.0 - c) - z * s,
            x * z * (1.0 - c) + y * s,
        ],
        [
            y * x * (1.0 - c) + z * s,
            c + y * y * (1.0 - c),
            y * z * (1.0 - c) - x * s,
        ],
        [
            z * x * (1.0 - c) - y * s,
            z * y * (1.0 - c) + x * s,
            c + z * z * (1.0 - c),
        ],
    ]
}

/// Both ways to the nearest rotation agree: Newton's iteration where it
/// applies, Horn's quaternion everywhere; and the result is a rotation
/// that fits `A` at least as well as any other tried.
#[test]
fn the_closest_rotation_is_the_polar_factor_and_a_proper_rotation() {
    let mut next = crate::linalg::polar::rng(12345);
    let horn = |A: &[[f64; 3]; 3]| {
        let At: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| A[j][i]));
        best_rotation(&At)
    };
    let fit = |R: &[[f64; 3]; 3], A: &[[f64; 3]; 3]| -> f64 {
        (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| (R[i][j] - A[i][j]).powi(2))
            .sum()
    };
    let (mut newton, mut flipped) = (0, 0);
    for k in 0..2000 {
        // Near-similarities, general matrices, flattened and mirrored ones.
        let spread = [0.05, 1.0, 3.0][k % 3];
        let mut A: [[f64; 3]; 3] = turn([next(), next(), next() + 0.01], 3.0 * next());
        for row in A.iter_mut() {
            for x in row.iter_mut() {
                *x = *x * 1.5 + spread * next();
            }
        }
        if k % 7 == 0 {
            A[2] = A[2].map(|x| -x);
        }
        if k % 11 == 0 {
            A[1] = scale(A[0], 0.5);
        }
        let R = closest_rotation(&A);
        assert!((det3(R) - 1.0).abs() < 1e-12, "{A:?}: det {}", det3(R));
        let RtR: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..3).map(|m| R[m][i] * R[m][j]).sum())
        });
        for i in 0..3 {
            for j in 0..3 {
                let e = RtR[i][j] - if i == j { 1.0 } else { 0.0 };
                assert!(e.abs() < 1e-12, "{A:?}: not orthogonal");
            }
        }
        let H = horn(&A);
        assert!(
            fit(&R, &A) <= fit(&H, &A) + 1e-10,
            "{A:?}: {R:?} against {H:?}"
        );
        if polar_rotation(&A).is_some() {
            newton += 1;
            let d = crate::linalg::polar::max_diff(R, H);
            assert!(d < 1e-9, "{A:?}: Newton and Horn differ by {d}");
        } else {
            flipped += 1;
        }
    }
    assert!(
        newton > 1000 && flipped > 200,
        "{newton} by Newton, {flipped} not"
    );
}

#[test]
fn recovers_a_similarity_exactly() {
    let from = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.2, 0.0],
        [0.3, 1.0, 0.1],
        [0.2, 0.1, 1.0],
        [0.7, 0.7, 0.7],
    ];
    for (axis, angle) in [
        ([0.0, 0.0, 1.0], 0.0),
        ([1.0, 2.0, 3.0], 2.5),
        ([0.0, 1.0, 0.0], std::f64::consts::PI),
    ] {
        let want = Similarity {
            rotation: turn(axis, angle),
            scale: 7.5,
            translation: [3.0, -2.0, 10.0],
        };
        let to = want.apply_all(&from);
        let got = Similarity::fit(&from, &to).unwrap();
        assert!((got.scale - 7.5).abs() < 1e-12, "{got:?}");
        for i in 0..3 {
            for j in 0..3 {
                assert!(
                    (got.rotation[i][j] - want.rotation[i][j]).abs() < 1e-12,
                    "{got:?}"
                );
            }
        }
        assert!(residuals(&got, &from, &to).iter().all(|r| *r < 1e-11));
    }
}

#[test]
fn a_mirror_image_gives_a_rotation() {
    let from = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let to: Vec<[f64; 3]> = from.iter().map(|p| [-p[0], p[1], p[2]]).collect();
    let got = Similarity::fit(&from, &to).unwrap();
    let R = got.rotation;
    let det = R[0][0] * (R[1][1] * R[2][2] - R[1][2] * R[2][1])
        - R[0][1] * (R[1][0] * R[2][2] - R[1][2] * R[2][0])
        + R[0][2] * (R[1][0] * R[2][1] - R[1][1] * R[2][0]);
    assert!((det - 1.0).abs() < 1e-12);
}

#[test]
fn too_few_or_collinear_markers_are_refused() {
    let e = Similarity::fit(&[[0.0; 3], [1.0; 3]], &[[0.0; 3], [1.0; 3]])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("2 marker pairs") && e.contains("at least 3"),
        "{e}"
    );
    let line = [
        [0.0, 0.0, 0.0],
        [1.0, 1.0, 1.0],
        [2.0, 2.0, 2.0],
        [5.0, 5.0, 5.0],
    ];
    let ok = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let e = Similarity::fit(&line, &ok).unwrap_err().to_string();
    assert!(e.contains("source markers lie on one line"), "{e}");
    let e = Similarity::fit(&ok, &line).unwrap_err().to_string();
    assert!(e.contains("target markers lie on one line"), "{e}");
}

#[test]
fn the_robust_rotation_follows_the_majority() {
    let want = turn([1.0, -2.0, 0.5], 0.7);
    let fit = Similarity {
        rotation: want,
        scale: 1.0,
        translation: [0.0; 3],
    };
    let mut rng = crate::linalg::polar::rng(5);
    let from: Vec<[f64; 3]> = (0..200)
        .map(|_| {
            let v = [rng() - 0.5, rng() - 0.5, rng() - 0.5];
            scale(v, 1.0 / norm(v))
        })
        .collect();
    // A fifth of the directions turned another way as well.
    let other = turn([0.0, 0.0, 1.0], 0.5);
    let to: Vec<[f64; 3]> = from
        .iter()
        .enumerate()
        .map(|(k, &x)| {
            let y = fit.rotate(x);
            if k % 5 == 0 {
                std::array::from_fn(|i| dot(other[i], y))
            } else {
                y
            }
        })
        .collect();
    let got = robust_rotation(&from, &to, &vec![1.0; from.len()]);
    for i in 0..3 {
        for j in 0..3 {
            assert!((got[i][j] - want[i][j]).abs() < 1e-6, "{got:?}");
        }
    }
    // Parallel directions leave the turn about them free: none is taken.
    let up = vec![[0.0, 0.0, 1.0]; 4];
    let got = robust_rotation(&up, &up, &[1.0; 4]);
    for i in 0..3 {
        for j in 0..3 {
            let id = if i == j { 1.0 } else { 0.0 };
            assert!((got[i][j] - id).abs() < 1e-9, "{got:?}");
        }
    }
}

#[test]
fn outliers_stand_far_above_the_median() {
    let mut r = vec![0.010, 0.012, 0.011, 0.009, 0.013, 0.010, 0.011];
    assert!(outliers(&r).is_empty());
    r.push(0.2);
    assert_eq!(outliers(&r), vec![7]);
}
