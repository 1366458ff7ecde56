use meshmorph::linalg::matrix::{inverse3, mul, Mat3};
use meshmorph::linalg::vector::add;

use meshmorph::gradient::spatial::*;
use meshmorph::linalg::matrix::det3;

#[test]
fn frames_of_a_rotated_triangle_give_the_rotation() {
    let p = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.5, 1.0, 0.0]];
    let (s, c) = 0.7f64.sin_cos();
    let R: Mat3 = [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]];
    let q = p.map(|v| {
        add(
            std::array::from_fn(|i| (0..3).map(|k| R[i][k] * v[k]).sum()),
            [1.0, 2.0, 3.0],
        )
    });
    let V_inv = inverse3(frame(p)).unwrap();
    let Q = deformation_gradient(V_inv, q);
    for i in 0..3 {
        for j in 0..3 {
            assert!((Q[i][j] - R[i][j]).abs() < 1e-12, "{Q:?}");
        }
    }
    // The same through the operator G.
    let v4 = fourth_vertex(q);
    let X = [q[0], q[1], q[2], v4];
    let G = gradient_operator(V_inv);
    for i in 0..3 {
        for j in 0..3 {
            let qij: f64 = (0..4).map(|k| X[k][i] * G[k][j]).sum();
            assert!((qij - R[i][j]).abs() < 1e-12);
        }
    }
    let I = mul(frame(p), V_inv);
    assert!((det3(I) - 1.0).abs() < 1e-12);
}

#[test]
fn degenerate_triangles_stay_finite() {
    let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    assert_eq!(fourth_vertex(p), p[0]);
    assert!(inverse3(frame(p)).is_none());
}
