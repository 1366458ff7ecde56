use meshmorph::linalg::matrix::{det2, det3, mul_tn, Mat2, Mat3};

use meshmorph::linalg::matrix::mul as mul3;
use meshmorph::linalg::polar::*;

pub(crate) fn rng(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

pub(crate) fn max_diff(A: Mat3, B: Mat3) -> f64 {
    (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .map(|(i, j)| (A[i][j] - B[i][j]).abs())
        .fold(0.0, f64::max)
}

fn assert_rotation(R: Mat3) {
    assert!(max_diff(mul_tn(&R, &R), IDENTITY) < 1e-13, "{R:?}");
    assert!((det3(R) - 1.0).abs() < 1e-13);
}

#[test]
fn eigen_decomposition_reconstructs() {
    let mut r = rng(3);
    for _ in 0..1000 {
        let B: Mat3 = std::array::from_fn(|_| std::array::from_fn(|_| r()));
        let S = mul_tn(&B, &B);
        let e = SymmetricEigen3::new(S);
        assert!(e.values[0] >= e.values[1] && e.values[1] >= e.values[2]);
        assert!(max_diff(e.map_values(|l| l), S) < 1e-13);
        assert!(max_diff(mul_tn(&e.vectors, &e.vectors), IDENTITY) < 1e-13);
        assert!((det3(e.vectors) - 1.0).abs() < 1e-13);
        assert!(max_diff(e.power(1.0, 0.0), S) < 1e-12);
        assert!(max_diff(e.power(0.0, 0.0), IDENTITY) < 1e-12);
        let h = e.power(0.5, 0.0);
        assert!(max_diff(mul3(h, h), S) < 1e-9);
    }
    // Repeated eigenvalues.
    let e = SymmetricEigen3::new([[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]]);
    assert_eq!(e.values, [2.0, 2.0, 1.0]);
}

#[test]
fn polar_reconstructs_with_proper_rotations() {
    let mut r = rng(11);
    for _ in 0..2000 {
        let A: Mat3 = std::array::from_fn(|_| std::array::from_fn(|_| 2.0 * r()));
        let p = polar_decomposition3(A);
        assert_rotation(p.rotation);
        assert!(max_diff(mul3(p.rotation, p.stretch), A) < 1e-12);
        let e = SymmetricEigen3::new(p.stretch);
        if det3(A) > 0.0 {
            assert!(e.values[2] > -1e-12, "{e:?}");
        } else {
            assert!(e.values[2] < 1e-12, "{e:?}");
            assert!(e.values[1] > -1e-12, "{e:?}");
        }
    }
}

#[test]
fn polar_of_a_rotation_times_a_stretch() {
    let R = meshmorph::linalg::quaternion::exp_rotation([0.3, -2.0, 1.1]);
    let S = [[2.0, 0.3, 0.1], [0.3, 0.5, 0.0], [0.1, 0.0, 1.5]];
    let p = polar_decomposition3(mul3(R, S));
    assert!(max_diff(p.rotation, R) < 1e-13);
    assert!(max_diff(p.stretch, S) < 1e-13);
}

#[test]
fn near_singular_and_degenerate_matrices() {
    // A triangle flattened onto a line in one direction: rank 2 and
    // nearly rank 2.
    let R = meshmorph::linalg::quaternion::exp_rotation([1.0, 2.0, -0.5]);
    for eps in [0.0, 1e-300, 1e-14, 1e-8] {
        let A = mul3(R, [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, eps]]);
        let p = polar_decomposition3(A);
        assert_rotation(p.rotation);
        assert!(max_diff(mul3(p.rotation, p.stretch), A) < 1e-14);
        assert!(max_diff(p.rotation, R) < 1e-12, "{eps}");
    }
    // Rank 1 and zero.
    let A = [[1.0, 2.0, 3.0], [0.0; 3], [0.0; 3]];
    let p = polar_decomposition3(A);
    assert_rotation(p.rotation);
    assert!(max_diff(mul3(p.rotation, p.stretch), A) < 1e-14);
    let p = polar_decomposition3([[0.0; 3]; 3]);
    assert_eq!(p.rotation, IDENTITY);
}

#[test]
fn reflections_keep_a_proper_rotation() {
    let R = meshmorph::linalg::quaternion::exp_rotation([0.2, 0.1, 0.4]);
    let A = mul3(R, [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, -0.5]]);
    let p = polar_decomposition3(A);
    assert_rotation(p.rotation);
    assert!(max_diff(p.rotation, R) < 1e-13);
    let e = SymmetricEigen3::new(p.stretch);
    assert!((e.values[2] + 0.5).abs() < 1e-13);
}

mod planar_tests {
    use super::*;
    use meshmorph::linalg::matrix::mul;

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
