use meshmorph::transfer::markers::Side;
use std::path::Path;

use meshmorph::io::picked_points::*;

#[test]
fn reads_points_names_and_lines() {
    let text = "<!DOCTYPE PickedPoints>\n<PickedPoints>\n <DocumentData>\n  <DataFileName name=\"a.ply\"/>\n </DocumentData>\n <point x=\"0.5\" y=\"1\" z=\"-2e-3\" active=\"1\" name=\"nose\"/>\n <point x=\"1\" y=\"2\" z=\"3\" active=\"0\" name=\"a &amp; b\"/>\n</PickedPoints>\n";
    let list = parse(text, Path::new("a.pp")).unwrap();
    assert_eq!(list.entries.len(), 2);
    assert_eq!(list.entries[0].side, Side::At([0.5, 1.0, -2e-3]));
    assert_eq!(list.entries[0].place, 6);
    assert_eq!(list.entries[1].name.as_deref(), Some("a & b"));
    assert!(!list.entries[1].active);
}

#[test]
fn refuses_bad_points() {
    let e = |text: &str| parse(text, Path::new("a.pp")).unwrap_err().to_string();
    let s = e("<PickedPoints>\n<point x=\"1\" y=\"2\"/>\n</PickedPoints>");
    assert!(s.contains("`a.pp`, line 2") && s.contains("no `z`"), "{s}");
    let s = e("<PickedPoints>\n<point x=\"1\" y=\"nan\" z=\"0\"/>\n</PickedPoints>");
    assert!(s.contains("line 2") && s.contains("y=\"nan\""), "{s}");
    let s = e("<PickedPoints>\n\n<point x=\"1\" y=\"2\" z=\"0\" active=\"yes\"/></PickedPoints>");
    assert!(s.contains("line 3") && s.contains("active"), "{s}");
    let s = e("<Other/>");
    assert!(s.contains("`Other`"), "{s}");
    let s = e("<PickedPoints>\n<point x=\"1\"\n");
    assert!(s.contains("`a.pp`, line"), "{s}");
}
