use meshmorph::linalg::matrix::*;

#[test]
fn inverse_and_products() {
    let m: Mat3 = [[2.0, 1.0, 0.0], [0.5, 3.0, 1.0], [0.0, -1.0, 1.5]];
    let p = mul(m, inverse3(m).unwrap());
    for i in 0..3 {
        for j in 0..3 {
            assert!((p[i][j] - identity::<3>()[i][j]).abs() < 1e-14);
        }
    }
    assert_eq!(det2([[1.0, 2.0], [3.0, 4.0]]), -2.0);
    assert!(inverse3([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]]).is_none());
    assert_eq!(
        lerp(&identity(), &[[3.0, 1.0], [1.0, 5.0]], 0.5),
        [[2.0, 0.5], [0.5, 3.0]]
    );
}
