use meshmorph::error::Error;

use meshmorph::mesh::triangle_mesh::*;

#[test]
fn rejects_bad_meshes() {
    let p = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    assert!(Mesh2::new(p.clone(), vec![[0, 1, 2]]).is_ok());
    let e = Mesh2::new(p.clone(), vec![]).unwrap_err().to_string();
    assert!(e.contains("no triangles"), "{e}");
    let e = Mesh2::new(p.clone(), vec![[0, 1, 3]])
        .unwrap_err()
        .to_string();
    assert!(e.contains("triangle 0 uses vertex 3"), "{e}");
    let e = Mesh2::new(p.clone(), vec![[0, 1, 2], [1, 1, 2]]).unwrap_err();
    assert!(matches!(e, Error::InvalidTriangle { triangle: 1, .. }));
    let e = e.to_string();
    assert!(e.contains("triangle 1 repeats"), "{e}");
    let mut q = p.clone();
    q[2][1] = f64::NAN;
    let e = Mesh2::new(q, vec![[0, 1, 2]]).unwrap_err();
    assert!(matches!(e, Error::InvalidVertex { vertex: 2, .. }));
    let e = e.to_string();
    assert!(e.contains("vertex 2"), "{e}");
    let m = Mesh2::new(p.clone(), vec![[0, 1, 2]]).unwrap();
    let other = Mesh2::new(p, vec![[0, 2, 1]]).unwrap();
    let e = m.check_same_connectivity(&other, ["a", "b"]).unwrap_err();
    assert!(matches!(e, Error::TriangleMismatch { triangle: 0, .. }));
}

#[test]
fn planar_round_trip() {
    let m = Mesh3::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let m2 = m.to_2d().unwrap();
    assert_eq!(m2.to_3d(), m);
    assert_eq!(m2.signed_areas(), vec![0.5]);
    let lifted = m
        .with_positions(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
        .unwrap();
    assert!(lifted.to_2d().unwrap_err().to_string().contains("vertex 1"));
}
