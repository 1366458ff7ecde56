use meshmorph::linalg::vector::*;

#[test]
fn turn_takes_from_to_to() {
    let from = [0.0, 0.0, 1.0];
    let to = [0.0, 1.0, 0.0];
    let got = least_turn(from, from, to);
    assert!(norm(sub(got, to)) < 1e-15, "{got:?}");
    let other = least_turn([1.0, 0.0, 0.0], from, to);
    assert!(norm(sub(other, [1.0, 0.0, 0.0])) < 1e-15, "{other:?}");
    let back = least_turn(from, from, [0.0, 0.0, -1.0]);
    assert!(norm(sub(back, [0.0, 0.0, -1.0])) < 1e-15, "{back:?}");
    assert_eq!(least_turn([0.3, 0.1, 0.2], to, to), [0.3, 0.1, 0.2]);
}

#[test]
fn corner_angles_are_atan2_to_1e7() {
    let mut worst: f64 = 0.0;
    for i in 0..=1000 {
        let t = std::f64::consts::PI * i as f64 / 1000.0;
        for r in [1e-6, 1.0, 3e4] {
            worst = worst.max((corner_angle(r * t.sin(), r * t.cos()) - t).abs());
        }
    }
    assert!(worst < 1e-7, "{worst}");
    assert_eq!(corner_angle(0.0, 0.0), 0.0);
}

#[test]
fn angle_weights_do_not_depend_on_the_triangles_sizes() {
    // The apex of a pyramid's three faces. Sliding one base corner along
    // its edge from the apex changes two faces' areas, not their planes
    // nor the angles at the apex: the apex's normal stays (area weights
    // would lean towards the grown faces).
    let apex = [0.0, 0.0, 1.0];
    let t = [[0, 1, 2], [0, 2, 3], [0, 3, 1]];
    let normal = |reach: f64| {
        let corner = add(apex, scale(sub([0.0, 1.0, 0.0], apex), reach));
        let p = vec![apex, [1.0, 0.0, 0.0], corner, [-1.0, -1.0, 0.0]];
        angle_weighted_vertex_normals(&p, &t)[0]
    };
    let (a, b) = (normal(1.0), normal(5.0));
    assert!(norm(sub(a, b)) < 1e-12, "{a:?} {b:?}");
    // A flat fan: the plane's normal.
    let flat = angle_weighted_vertex_normals(
        &[
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 3.0, 0.0],
            [-1.0, -1.0, 0.0],
        ],
        &[[0, 1, 2], [0, 2, 3], [0, 3, 1]],
    )[0];
    assert!(norm(sub(flat, [0.0, 0.0, 1.0])) < 1e-12, "{flat:?}");
}
