use meshmorph::error::Error;
use meshmorph::mesh::surface_point::SurfacePoint;

use meshmorph::mesh::shapes::tube;
use meshmorph::transfer::markers::*;
use std::path::Path;

#[test]
fn validation() {
    let (small, large) = (tube(1.0, 0.2, 2, 3), tube(1.0, 0.2, 3, 4));
    let p = Path::new("m.txt");
    let m = Markers::parse("0 1\n9 2\n", p, VertexNumbering::FromZero).unwrap();
    assert!(m.validate(&large, &small).is_ok());
    let e = m.validate(&small, &small).unwrap_err();
    assert!(
        matches!(
            e,
            Error::InvalidMarker {
                marker: 1,
                line: Some(2),
                ..
            }
        ),
        "{e:?}"
    );
    let e = e.to_string();
    assert!(e.contains("line 2") && e.contains("source vertex 9"), "{e}");
    let m = Markers::parse("0 1\n2 9\n", p, VertexNumbering::FromZero).unwrap();
    let e = m.validate(&small, &small).unwrap_err().to_string();
    assert!(e.contains("target vertex 9"), "{e}");
    let e = Markers::new(vec![[0, 1], [0, 1]])
        .validate(&large, &large)
        .unwrap_err()
        .to_string();
    assert!(e.contains("repeats marker 0"), "{e}");
    let e = Markers::new(vec![[0, 1], [0, 2]])
        .validate(&large, &large)
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::InvalidMarker {
                marker: 1,
                line: None,
                ..
            }
        ),
        "{e:?}"
    );
    let e = e.to_string();
    assert!(
        e.contains("paired with target vertex 2 here and with target vertex 1"),
        "{e}"
    );
    // A corner of a triangle is its vertex.
    let corner = SurfacePoint::Triangle {
        triangle: 0,
        barycentric: [1.0, 0.0, 0.0],
    };
    let v = large.triangles()[0][0];
    let e = Markers::on_surfaces(vec![
        [SurfacePoint::Vertex(v), SurfacePoint::Vertex(1)],
        [corner, SurfacePoint::Vertex(2)],
    ])
    .validate(&large, &large)
    .unwrap_err()
    .to_string();
    assert!(e.contains("different partners"), "{e}");
}

#[test]
fn snapping_finds_the_surface_and_says_how_far() {
    let mesh = tube(2.0, 0.5, 3, 8);
    let corners = mesh.corners(0);
    let normal = meshmorph::mesh::closest::unit_normal(corners);
    let centre = meshmorph::linalg::vector::centroid(corners);
    let near =
        meshmorph::linalg::vector::add(centre, meshmorph::linalg::vector::scale(normal, 0.01));
    let on_vertex = mesh.positions()[3];
    let (m, snap) = Markers::from_points(vec![[near, on_vertex], [on_vertex, near]])
        .snap(&mesh, &mesh)
        .unwrap();
    assert_eq!(m.pairs()[0][1], SurfacePoint::Vertex(3));
    assert!(matches!(m.pairs()[0][0], SurfacePoint::Triangle { .. }));
    let p = m.pairs()[0][0].position(&mesh);
    assert!((0..3).all(|i| (p[i] - centre[i]).abs() < 1e-12), "{p:?}");
    assert!(snap.largest_source > 0.0 && snap.largest_source < SNAP_LIMIT);
    assert_eq!(snap.points, 2);
    let e = Markers::from_points(vec![[[0.0, 5.0, 0.0], near]])
        .snap(&mesh, &mesh)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("the source point 0 5 0") && e.contains("surface"),
        "{e}"
    );
}
