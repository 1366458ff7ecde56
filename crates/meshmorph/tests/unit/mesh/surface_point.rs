use meshmorph::mesh::closest::SurfaceIndex;
use meshmorph::mesh::Mesh3;

use meshmorph::mesh::surface_point::*;

#[test]
fn positions_terms_and_corners() {
    let mesh = Mesh3::new(
        vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let p = SurfacePoint::Triangle {
        triangle: 0,
        barycentric: [0.5, 0.25, 0.25],
    };
    assert_eq!(p.position(&mesh), [0.5, 0.5, 0.0]);
    assert_eq!(p.terms(mesh.triangles()).count(), 3);
    assert_eq!(p.as_vertex(mesh.triangles()), None);
    let corner = SurfacePoint::Triangle {
        triangle: 0,
        barycentric: [0.0, 1.0, 0.0],
    };
    assert_eq!(corner.as_vertex(mesh.triangles()), Some(1));
    assert_eq!(corner.position(&mesh), [2.0, 0.0, 0.0]);
    assert_eq!(SurfacePoint::Vertex(2).position(&mesh), [0.0, 2.0, 0.0]);
    let bad = SurfacePoint::Triangle {
        triangle: 0,
        barycentric: [0.5, 0.5, 0.5],
    };
    assert!(bad.barycentric_problem().unwrap().contains("sum to 1.5"));
    let outside = SurfacePoint::Triangle {
        triangle: 0,
        barycentric: [1.5, -0.5, 0.0],
    };
    assert!(outside
        .barycentric_problem()
        .unwrap()
        .contains("outside its triangle"));
    assert!(p.barycentric_problem().is_none());
}

#[test]
fn coordinates_rounded_to_nine_decimals_are_taken_and_made_exact() {
    for (b, sum) in [
        ([0.333333334, 0.333333334, 0.333333333], 1.000000001),
        ([0.1, 0.2, 0.7000009], 1.0000009),
        ([1.0000005, -0.0000005, 0.0], 1.0),
        ([0.25, 0.25, 0.4999991], 0.9999991),
    ] {
        let p = SurfacePoint::Triangle {
            triangle: 3,
            barycentric: b,
        };
        assert!((b.iter().sum::<f64>() - sum).abs() < 1e-12);
        let SurfacePoint::Triangle {
            triangle,
            barycentric: n,
        } = p.normalized().unwrap()
        else {
            panic!()
        };
        assert_eq!(triangle, 3);
        assert!(
            (n.iter().sum::<f64>() - 1.0).abs() <= 2.0 * f64::EPSILON,
            "{n:?}"
        );
        assert!(n.iter().all(|x| (0.0..=1.0).contains(x)), "{n:?}");
    }
    for b in [
        [0.5, 0.5, 0.000002],
        [0.4, 0.4, 0.199998],
        [1.00001, 0.0, -0.00001],
    ] {
        let p = SurfacePoint::Triangle {
            triangle: 0,
            barycentric: b,
        };
        assert!(p.normalized().is_err(), "{b:?}");
    }
    assert_eq!(
        SurfacePoint::Vertex(4).normalized(),
        Ok(SurfacePoint::Vertex(4))
    );
}

#[test]
fn the_nearest_point_is_on_the_surface_or_a_corner() {
    let mesh = Mesh3::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let index = SurfaceIndex::new(mesh.positions(), mesh.triangles());
    let (p, d) = nearest_surface_point(&index, &mesh, [0.25, 0.5, 2.0]).unwrap();
    assert_eq!(d, 2.0);
    let SurfacePoint::Triangle { barycentric: b, .. } = p else {
        panic!("{p:?}")
    };
    assert!((b[0] - 0.25).abs() < 1e-15 && (b[1] - 0.25).abs() < 1e-15);
    assert!((b[2] - 0.5).abs() < 1e-15);
    let (p, d) = nearest_surface_point(&index, &mesh, [2.0, -1.0, 0.0]).unwrap();
    assert_eq!((p, d), (SurfacePoint::Vertex(1), 2f64.sqrt()));
    // On an edge: two weights.
    let (p, _) = nearest_surface_point(&index, &mesh, [0.5, -1.0, 0.0]).unwrap();
    assert_eq!(p.terms(mesh.triangles()).count(), 2);
    assert_eq!(p.position(&mesh), [0.5, 0.0, 0.0]);
}
