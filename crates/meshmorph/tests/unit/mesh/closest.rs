use meshmorph::mesh::closest::*;

#[test]
fn a_surface_turned_beyond_the_angle_is_not_taken() {
    // One triangle tilted 45° about the x axis, a query above it.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, h, h]];
    let s = SurfaceIndex::new(&p, &[[0, 1, 2]]);
    let (q, up) = ([0.2, 0.2, 0.5], [0.0, 0.0, 1.0]);
    for (degrees, found) in [
        (90.0, true),
        (60.0, true),
        (46.0, true),
        (44.0, false),
        (25.0, false),
    ] {
        assert_eq!(
            s.closest_compatible(q, up, 10.0, Angle::degrees(degrees))
                .is_some(),
            found,
            "{degrees}°"
        );
    }
}

#[test]
fn closest_point_regions() {
    let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let inside = closest_point_on_triangle([0.2, 0.2, 1.0], t);
    assert!(
        (0..3).all(|i| (inside[i] - [0.2, 0.2, 0.0][i]).abs() < 1e-15),
        "{inside:?}"
    );
    assert_eq!(
        closest_point_on_triangle([-1.0, -1.0, 0.0], t),
        [0.0, 0.0, 0.0]
    );
    assert_eq!(
        closest_point_on_triangle([2.0, -0.5, 0.0], t),
        [1.0, 0.0, 0.0]
    );
    assert_eq!(
        closest_point_on_triangle([0.5, -1.0, 0.0], t),
        [0.5, 0.0, 0.0]
    );
    let e = closest_point_on_triangle([1.0, 1.0, 0.0], t);
    assert!((e[0] - 0.5).abs() < 1e-15 && (e[1] - 0.5).abs() < 1e-15);
}

#[test]
fn queries_skip_incompatible_normals_and_respect_the_cutoff() {
    // Two parallel squares facing opposite ways, 1 apart.
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    let t = vec![[0, 1, 2], [0, 2, 3], [4, 6, 5], [4, 7, 6]];
    let s = SurfaceIndex::new(&p, &t);
    let q = [0.3, 0.6, 0.9];
    let up = s
        .closest_compatible(q, [0.0, 0.0, 1.0], 10.0, Angle::RIGHT)
        .unwrap();
    assert!(up.triangle < 2 && (up.distance - 0.9).abs() < 1e-12);
    let down = s
        .closest_compatible(q, [0.0, 0.0, -1.0], 10.0, Angle::RIGHT)
        .unwrap();
    assert!(down.triangle >= 2 && (down.distance - 0.1).abs() < 1e-12);
    assert!(s
        .closest_compatible(q, [0.0, 0.0, 1.0], 0.5, Angle::RIGHT)
        .is_none());
    let c = CentroidIndex::new(&p, &t, &[0, 1, 0, 1]);
    assert!(
        c.nearest_compatible(q, [0.0, 0.0, 1.0], 10.0, Angle::RIGHT, None)
            .unwrap()
            < 2
    );
    assert!(
        c.nearest_compatible(q, [0.0, 0.0, -1.0], 10.0, Angle::RIGHT, None)
            .unwrap()
            >= 2
    );
    assert!(c
        .nearest_compatible(q, [0.0, 0.0, 1.0], 0.5, Angle::RIGHT, None)
        .is_none());
    // Within one part only.
    assert_eq!(
        c.nearest_compatible(q, [0.0, 0.0, 1.0], 10.0, Angle::RIGHT, Some(1)),
        Some(1)
    );
    assert_eq!(
        c.nearest_compatible(q, [0.0, 0.0, -1.0], 10.0, Angle::RIGHT, Some(0)),
        Some(2)
    );
}
