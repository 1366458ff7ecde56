use meshmorph::transfer::markers::VertexNumbering;
use std::path::Path;

use meshmorph::io::marker_points::*;
use meshmorph::mesh::surface_point::SurfacePoint;

fn list(text: &str, name: &str) -> PointList {
    parse_points(text, Path::new(name), VertexNumbering::FromZero).unwrap()
}

#[test]
fn pairs_by_name_or_in_order() {
    let a = list("nose 3\neye 4\nchin p 1 2 3\n", "a.txt");
    let b = list("eye v 40\nchin 9\nnose t 5 0.5 0.5 0\n", "b.txt");
    let m = pair(&a, &b).unwrap();
    assert_eq!(m.pairs().len(), 2);
    assert_eq!(m.name(0), Some("nose"));
    assert_eq!(
        m.pairs()[1],
        [SurfacePoint::Vertex(4), SurfacePoint::Vertex(40)]
    );
    assert_eq!(m.points.len(), 1);
    assert_eq!(m.points[0].order, 2);
    let unnamed = list("9\n8\n7\n", "c.txt");
    let m = pair(&a, &unnamed).unwrap();
    assert_eq!(
        m.pairs()[0],
        [SurfacePoint::Vertex(3), SurfacePoint::Vertex(9)]
    );
}

#[test]
fn refuses_what_cannot_pair() {
    let a = list("nose 3\neye 4\n", "a.txt");
    let b = list("nose 3\nmouth 4\n", "b.txt");
    let e = pair(&a, &b).unwrap_err().to_string();
    assert!(
        e.contains("`a.txt`, line 2") && e.contains("`eye`") && e.contains("`b.txt`"),
        "{e}"
    );
    let e = pair(&a, &list("1\n2\n3\n", "c.txt"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("2 points here and 3 in `c.txt`"), "{e}");
    let e = parse_points("a 1\n2\n", Path::new("d.txt"), VertexNumbering::FromZero)
        .unwrap_err()
        .to_string();
    assert!(e.contains("line 2") && e.contains("without a name"), "{e}");
    let e = parse_points("a 1\na 2\n", Path::new("d.txt"), VertexNumbering::FromZero)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 2") && e.contains("`a` is given twice"),
        "{e}"
    );
}
