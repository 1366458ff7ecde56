use meshmorph::mesh::surface_point::SurfacePoint;
use meshmorph::transfer::markers::{Markers, VertexNumbering};
use std::path::Path;

use meshmorph::io::marker_file::*;

fn vertex_pairs(m: &Markers) -> Vec<[u32; 2]> {
    m.pairs()
        .iter()
        .map(|p| {
            p.map(|s| match s {
                SurfacePoint::Vertex(v) => v,
                other => panic!("{other:?}"),
            })
        })
        .collect()
}

#[test]
fn parses_the_usual_layouts() {
    let p = Path::new("m.cons");
    let m = Markers::parse(
        "3\n0, 5\n1 6 # tail\n\n# c\n2\t7\r\n",
        p,
        VertexNumbering::FromZero,
    )
    .unwrap();
    assert_eq!(vertex_pairs(&m), [[0, 5], [1, 6], [2, 7]]);
    let m = Markers::parse("1 1\n2 3\n", p, VertexNumbering::FromOne).unwrap();
    assert_eq!(vertex_pairs(&m), [[0, 0], [1, 2]]);
    assert_eq!(
        Markers::parse("", p, VertexNumbering::FromZero)
            .unwrap()
            .pairs()
            .len(),
        0
    );
}

#[test]
fn parses_names_triangles_and_positions() {
    let p = Path::new("m.txt");
    let text = "nose v 3 t 4 0.25 0.25 0.5\n\"left # eye\" p 1 2 3, v 9\n 2 7\n";
    let m = Markers::parse(text, p, VertexNumbering::FromZero).unwrap();
    assert_eq!(m.pairs().len(), 2);
    assert_eq!(m.name(0), Some("nose"));
    assert_eq!(
        m.pairs()[0][1],
        SurfacePoint::Triangle {
            triangle: 4,
            barycentric: [0.25, 0.25, 0.5]
        }
    );
    assert_eq!(m.name(1), None);
    assert_eq!(m.points.len(), 1);
    assert_eq!(m.points[0].name.as_deref(), Some("left # eye"));
    assert_eq!(m.points[0].order, 1);
    let m = Markers::parse("a t 2 0.5 0.5 0 v 1\n", p, VertexNumbering::FromOne).unwrap();
    assert_eq!(
        m.pairs()[0],
        [
            SurfacePoint::Triangle {
                triangle: 1,
                barycentric: [0.5, 0.5, 0.0]
            },
            SurfacePoint::Vertex(0)
        ]
    );
}

#[test]
fn writing_and_reading_back_gives_the_same_markers() {
    let p = Path::new("m.txt");
    let text = "nose v 3 t 4 0.1 0.30000000000000004 0.6\n\"a \\\"b\\\" \\\\ c\" p 1e300 -0.0 3 v 9\n2 7\nv 1 p 0.1 0.2 0.3\n";
    let m = Markers::parse(text, p, VertexNumbering::FromZero).unwrap();
    let mut out = Vec::new();
    m.write(&mut out).unwrap();
    let back = Markers::parse(
        std::str::from_utf8(&out).unwrap(),
        p,
        VertexNumbering::FromZero,
    )
    .unwrap();
    assert_eq!(back.pairs, m.pairs);
    assert_eq!(back.names, m.names);
    let strip = |m: &Markers| {
        m.points
            .iter()
            .map(|p| (p.order, p.sides, p.name.clone()))
            .collect::<Vec<_>>()
    };
    assert_eq!(strip(&back), strip(&m));
    assert_eq!(m.points[0].name.as_deref(), Some("a \"b\" \\ c"));
}

#[test]
fn reports_lines() {
    let p = Path::new("m.txt");
    let bad = |text: &str, numbering| Markers::parse(text, p, numbering).unwrap_err().to_string();
    let e = bad("0 1\n2 x\n", VertexNumbering::FromZero);
    assert!(
        e.contains("m.txt") && e.contains("line 2") && e.contains("`x`"),
        "{e}"
    );
    let e = bad("0 1 2\n", VertexNumbering::FromZero);
    assert!(e.contains("line 1"), "{e}");
    let e = bad("4\n0 1\n", VertexNumbering::FromZero);
    assert!(e.contains("says 4 pairs but 1"), "{e}");
    let e = bad("0 1\n", VertexNumbering::FromOne);
    assert!(e.contains("1-based"), "{e}");
    let e = bad("0 -1\n", VertexNumbering::FromZero);
    assert!(e.contains("out of range"), "{e}");
    let e = bad("a v 1 t 2 0.5 0.6 0.1\n", VertexNumbering::FromZero);
    assert!(e.contains("line 1") && e.contains("sum to"), "{e}");
    // Rounded to 9 decimals (summing to 1.000000001): taken, made exact;
    // 1e-5 off: refused, naming the line.
    let m = Markers::parse(
        "v 1 t 2 0.333333334 0.333333334 0.333333333\n",
        p,
        VertexNumbering::FromZero,
    )
    .unwrap();
    let SurfacePoint::Triangle { barycentric: b, .. } = m.pairs()[0][1] else {
        panic!("{:?}", m.pairs()[0])
    };
    assert!((b.iter().sum::<f64>() - 1.0).abs() <= 2.0 * f64::EPSILON);
    let e = bad(
        "x 0 0\nv 1 t 2 0.5 0.5 0.00001\n",
        VertexNumbering::FromZero,
    );
    assert!(
        e.contains("m.txt") && e.contains("line 2") && e.contains("sum to"),
        "{e}"
    );
    let e = bad("a 1 2\nb 3 4\na 5 6\n", VertexNumbering::FromZero);
    assert!(
        e.contains("line 3") && e.contains("`a` is given twice (line 1"),
        "{e}"
    );
    let e = bad("\"a 1 2\n", VertexNumbering::FromZero);
    assert!(e.contains("closing quote"), "{e}");
    let e = bad("v 1 t 2 0.5\n", VertexNumbering::FromZero);
    assert!(e.contains("`t` needs 4 numbers"), "{e}");
    let e = bad("v 1\n", VertexNumbering::FromZero);
    assert!(e.contains("found 1 side"), "{e}");
}

#[test]
fn a_file_past_the_most_markers_is_refused_at_the_first_one_too_many() {
    let p = Path::new("m.txt");
    let text = "0 1\n".repeat(MAX_MARKERS + 1);
    let e = Markers::parse(&text, p, VertexNumbering::FromZero)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!("line {}", MAX_MARKERS + 1)) && e.contains("more than"),
        "{e}"
    );
    let points = "7\n".repeat(MAX_MARKERS + 1);
    let e = meshmorph::io::marker_points::parse_points(&points, p, VertexNumbering::FromZero)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("more than"), "{e}");
}

#[test]
fn messages_number_vertices_as_the_file_does() {
    let p = Path::new("m.txt");
    let mesh = meshmorph::mesh::shapes::tube(1.0, 0.2, 2, 3);
    // 8 vertices: the 9th (or 10th, counting from 1) is out of range.
    for (one_based, text, shown) in [(false, "0 4\n1 9\n", "9"), (true, "1 5\n2 10\n", "10")] {
        let numbering = if one_based {
            VertexNumbering::FromOne
        } else {
            VertexNumbering::FromZero
        };
        let m = Markers::parse(text, p, numbering).unwrap();
        let e = m.check_ranges(&mesh, &mesh).unwrap_err().to_string();
        assert!(
            e.contains(&format!("target vertex {shown} is out of range")),
            "{e}"
        );
        assert!(m.describe(0).contains(if one_based {
            "target vertex 5"
        } else {
            "target vertex 4"
        }));
    }
    let m = Markers::parse("1 5\n1 6\n", p, VertexNumbering::FromOne).unwrap();
    let e = m.validate(&mesh, &mesh).unwrap_err().to_string();
    assert!(
        e.contains("source vertex 1 is paired with target vertex 6 here and with target vertex 5"),
        "{e}"
    );
}
