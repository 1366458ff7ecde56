use meshmorph::mesh::surface_point::SurfacePoint;
use meshmorph::transfer::markers::Side;
use std::path::Path;

use meshmorph::io::wrap_points::*;

#[test]
fn reads_lists_and_named_points_in_order() {
    let list = parse("[[42, 0.25, 0.5], [7, 0.0, 1.0]]", Path::new("a.json")).unwrap();
    assert_eq!(
        list.entries[0].side,
        Side::On(SurfacePoint::Triangle {
            triangle: 42,
            barycentric: [0.25, 0.5, 0.25]
        })
    );
    assert_eq!(list.entries[1].place, 2);
    let named = parse(
        "{\"Zed\": [0, 0.5, 0.5], \"Alpha\": [1, 1, 0]}",
        Path::new("b.json"),
    )
    .unwrap();
    let names: Vec<_> = named
        .entries
        .iter()
        .map(|e| e.name.clone().unwrap())
        .collect();
    assert_eq!(names, ["Zed", "Alpha"]);
}

#[test]
fn refuses_bad_points() {
    let e = |text: &str| parse(text, Path::new("a.json")).unwrap_err().to_string();
    let s = e("[[1, 0.5, 0.5], [2, 0.5]]");
    assert!(
        s.contains("`a.json`: point 2") && s.contains("found 2 numbers"),
        "{s}"
    );
    let s = e("[[1.5, 0.5, 0.5]]");
    assert!(s.contains("not a triangle index"), "{s}");
    let s = e("{\"P\": [-1, 0.5, 0.5]}");
    assert!(s.contains("point 1 (`P`)"), "{s}");
    let s = e("[[3, 0.9, 0.9]]");
    assert!(s.contains("outside its triangle"), "{s}");
    let s = e("[[3, 0.9,\n 0.9]");
    assert!(s.contains("`a.json`, line 2"), "{s}");
    let s = e("\"text\"");
    assert!(s.contains("not a Wrap point file"), "{s}");
}
