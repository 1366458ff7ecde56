use crate::linalg::polar::{max_diff, rng};
use meshmorph::linalg::quaternion::*;
use std::f64::consts::PI;

fn norm(w: [f64; 3]) -> f64 {
    meshmorph::linalg::vector::norm(w)
}

#[test]
fn log_inverts_exp_inside_the_principal_ball() {
    let mut r = rng(5);
    for i in 0..3000 {
        let mut w = [r(), r(), r()];
        let len = norm(w);
        // Lengths spread over (0, π), with many near 0 and near π.
        let target = match i % 3 {
            0 => PI * (0.5 + 0.5 * r()),
            1 => 10f64.powf(-12.0 * (0.5 + 0.5 * r())),
            _ => PI - 10f64.powf(-10.0 * (0.5 + 0.5 * r())),
        };
        w = w.map(|x| x * target / len);
        let R = exp_rotation(w);
        let back = log_rotation(&R);
        let err = norm(meshmorph::linalg::vector::sub(back, w));
        // Near a half turn the rotation itself only determines the axis
        // to about √ε relative to the distance from π.
        let tol = if PI - target < 1e-6 {
            1e-7
        } else {
            1e-12 * target.max(1e-3)
        };
        assert!(err <= tol.max(1e-15 * target), "{w:?} {back:?} {err}");
        assert!(max_diff(exp_rotation(back), R) < 1e-13);
    }
}

#[test]
fn exp_of_a_long_vector_wraps() {
    // Rotations by θ and θ − 2π about the same axis are the same matrix.
    let axis = [0.6, 0.0, 0.8];
    for theta in [0.5, 3.0, PI, 4.0, 2.0 * PI, 7.0] {
        let a = exp_rotation(axis.map(|x| x * theta));
        let b = exp_rotation(axis.map(|x| x * (theta - 2.0 * PI)));
        assert!(max_diff(a, b) < 1e-13);
        let l = log_rotation(&a);
        assert!(norm(l) <= PI + 1e-12);
    }
    // Exactly the identity and exactly a half turn.
    assert_eq!(log_rotation(&exp_rotation([0.0; 3])), [0.0; 3]);
    let half = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]];
    let l = log_rotation(&half);
    assert!((norm(l) - PI).abs() < 1e-15 && (l[0].abs() - PI).abs() < 1e-15);
}

#[test]
fn quaternion_products_compose_rotations() {
    let (a, b) = ([0.3, -1.0, 2.0], [1.5, 0.2, -0.4]);
    let ab = quat_to_matrix(quat_mul(quat_exp(a), quat_exp(b)));
    let m = meshmorph::linalg::matrix::mul(exp_rotation(a), exp_rotation(b));
    assert!(max_diff(ab, m) < 1e-14);
    let q = quat_axis_angle([0.0, 0.0, 1.0], 0.5);
    assert!(max_diff(quat_to_matrix(q), exp_rotation([0.0, 0.0, 0.5])) < 1e-15);
}
