//! Reading and writing OBJ, OFF and PLY files.

use std::path::{Path, PathBuf};

use meshmorph::io::{
    parse_mesh, read_mesh, read_mesh_as, write_atomic, write_mesh, write_positions, Format,
    MeshFile,
};
use meshmorph::{Error, Mesh2, Mesh3};

const FORMATS: [Format; 3] = [Format::Obj, Format::Off, Format::Ply];

fn parse(text: &str, format: Format) -> meshmorph::Result<Mesh3> {
    parse_mesh(
        text.as_bytes(),
        format,
        Path::new(&format!("fixture.{format}")),
    )
}

fn ok(text: &str, format: Format) -> Mesh3 {
    parse(text, format).unwrap_or_else(|e| panic!("{e}"))
}

/// The error message, checked to name the fixture file and the line.
#[track_caller]
fn error(text: &str, format: Format, line: Option<usize>, needle: &str) -> String {
    let e = parse(text, format).expect_err("should not parse");
    let msg = e.to_string();
    assert!(
        msg.contains(&format!("fixture.{format}")),
        "no file name: {msg}"
    );
    match &e {
        Error::Parse { line: l, .. } => assert_eq!(*l, line, "{msg}"),
        other => panic!("not a parse error: {other:?}"),
    }
    if let Some(l) = line {
        assert!(msg.contains(&format!("line {l}")), "{msg}");
    }
    assert!(msg.contains(needle), "`{needle}` not in: {msg}");
    msg
}

/// Twice the signed area of each triangle's projection on the xy plane.
fn xy_areas(m: &Mesh3) -> Vec<f64> {
    (0..m.num_triangles())
        .map(|t| {
            let [a, b, c] = m.corners(t);
            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        })
        .collect()
}

fn awkward_mesh() -> Mesh3 {
    let positions = vec![
        [0.1, 1.0 / 3.0, -2.5e-300],
        [1e20, -0.0, 5e-324],
        [f64::MAX, f64::MIN_POSITIVE, -1.0],
        [
            std::f64::consts::PI,
            -std::f64::consts::E,
            123_456_789.123_456_78,
        ],
        [0.0, 0.0, 0.0], // unused vertex
    ];
    Mesh3::new(positions, vec![[0, 1, 2], [2, 1, 3], [3, 0, 2]]).unwrap()
}

fn planar_mesh() -> Mesh2 {
    let positions = vec![
        [0.0, 0.0],
        [1.0, 0.0],
        [1.0, 1.0],
        [0.0, 1.0],
        [0.5, 0.7000000000000001],
    ];
    Mesh2::new(positions, vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]).unwrap()
}

#[test]
fn round_trips_are_exact_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = awkward_mesh();
    let planar = planar_mesh();
    for format in FORMATS {
        let path = dir.path().join(format!("mesh.{format}"));
        write_mesh(&path, &mesh, format).unwrap();
        assert_eq!(read_mesh(&path).unwrap(), mesh, "{format}");

        write_mesh(&path, &planar, format).unwrap();
        let back = read_mesh(&path).unwrap();
        assert!(back.positions().iter().all(|p| p[2] == 0.0));
        assert_eq!(back.to_2d().unwrap(), planar, "{format}");

        // write_positions writes the same bytes as write_mesh.
        let other = dir.path().join(format!("positions.{format}"));
        write_positions(&other, planar.positions(), planar.triangles(), format).unwrap();
        assert_eq!(
            std::fs::read(&other).unwrap(),
            std::fs::read(&path).unwrap()
        );
    }
}

#[test]
fn written_files_look_standard() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = planar_mesh();
    let path = dir.path().join("m.obj");
    write_mesh(&path, &mesh, Format::Obj).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("v 0 0 0\nv 1 0 0\n"), "{text}");
    assert!(text.contains("\nv 0.5 0.7000000000000001 0\n"), "{text}");
    assert!(text.ends_with("f 4 1 5\n"), "{text}");

    let path = dir.path().join("m.off");
    write_mesh(&path, &mesh, Format::Off).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("OFF\n5 4 0\n0 0 0\n"), "{text}");
    assert!(text.ends_with("3 3 0 4\n"), "{text}");

    let path = dir.path().join("m.ply");
    write_mesh(&path, &mesh, Format::Ply).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let header = "ply\nformat binary_little_endian 1.0\n";
    assert!(bytes.starts_with(header.as_bytes()));
    let text = String::from_utf8_lossy(&bytes);
    assert!(text.contains("property double x\nproperty double y\nproperty double z\n"));
    assert!(text.contains("property list uchar int vertex_indices\nend_header\n"));
    let body = text.find("end_header\n").unwrap() + "end_header\n".len();
    assert_eq!(bytes.len() - body, 5 * 24 + 4 * 13);
}

#[test]
fn obj_face_syntaxes_and_negative_indices() {
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n\
                f 1 2 3\nf 1/1 3/1 4/1\nf 1/1/1 2/1/1 3/1/1\nf 1//1 3//1 4//1\nf -4 -3 -2\nf -4/1 -2/1/1 -1//1\n";
    let m = ok(text, Format::Obj);
    assert_eq!(m.num_vertices(), 4);
    assert_eq!(
        m.triangles(),
        &[
            [0, 1, 2],
            [0, 2, 3],
            [0, 1, 2],
            [0, 2, 3],
            [0, 1, 2],
            [0, 2, 3]
        ]
    );
    // Relative indices count back from the vertices defined so far.
    let m = ok(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nf -4 -3 -2\n",
        Format::Obj,
    );
    assert_eq!(m.triangles(), &[[0, 1, 2], [0, 1, 2]]);
}

#[test]
fn obj_crlf_comments_blank_lines_and_other_statements() {
    let text = "# a comment\r\nmtllib x.mtl\r\n\r\no thing\r\ng group\r\ns 1\r\nusemtl red\r\n\
                v 0 0 0# touching\r\nv 1 0 0\r\n  v   0 1 0 1.0  \r\n\tv 2 2 2\r\n\r\n\
                vt 0.5 0.5\r\nvn 0 0 1\r\nvp 0.1\r\nl 1 2\r\ncstype bezier\r\nf 1 2 3 # trailing\r\n";
    let m = ok(text, Format::Obj);
    assert_eq!(
        m.positions(),
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 2.0, 2.0]
        ]
    );
    assert_eq!(m.triangles(), &[[0, 1, 2]]);
    // A planar file: every vertex `v x y`, z = 0.
    let m = ok("v 0 0\nv 1 0 # z absent\nv 0 1\nf 1 2 3\n", Format::Obj);
    assert_eq!(
        m.positions(),
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    );
    // A last line without a line end, and forward references.
    let m = ok("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0", Format::Obj);
    assert_eq!(m.triangles(), &[[0, 1, 2]]);
}

#[test]
fn concave_polygon_is_ear_clipped_with_its_orientation() {
    // An L-shaped hexagon of area 3; a fan from vertex 0 would cover the notch.
    let l_shape = "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n";
    for (faces, sign) in [("f 4 5 6 1 2 3\n", 1.0), ("f 6 5 4 3 2 1\n", -1.0)] {
        let m = ok(&format!("{l_shape}{faces}"), Format::Obj);
        assert_eq!(m.num_triangles(), 4);
        let areas = xy_areas(&m);
        assert!(areas.iter().all(|&a| sign * a > 0.0), "{:?}", m.triangles());
        assert!((areas.iter().sum::<f64>() - sign * 6.0).abs() < 1e-12);
        // No triangle covers the notch (1.5, 1.5).
        for t in 0..m.num_triangles() {
            let [a, b, c] = m.corners(t);
            let x = [1.5, 1.5];
            let s = |p: [f64; 3], q: [f64; 3]| {
                sign * ((q[0] - p[0]) * (x[1] - p[1]) - (q[1] - p[1]) * (x[0] - p[0]))
            };
            assert!(!(s(a, b) > 0.0 && s(b, c) > 0.0 && s(c, a) > 0.0));
        }
    }
    // The same polygon in a tilted plane (z = x + y) in OFF.
    let off = "OFF\n6 1 0\n0 0 0\n2 0 2\n2 1 3\n1 1 2\n1 2 3\n0 2 2\n6 0 1 2 3 4 5\n";
    let m = ok(off, Format::Off);
    assert_eq!(m.num_triangles(), 4);
    let areas = xy_areas(&m);
    assert!(areas.iter().all(|&a| a > 0.0));
    assert!((areas.iter().sum::<f64>() - 6.0).abs() < 1e-12);
}

#[test]
fn convex_quad_is_split_along_the_shorter_diagonal() {
    let m = ok(
        "v 0 0 0\nv 4 0 0\nv 4.5 1 0\nv 0 1 0\nf 1 2 3 4\n",
        Format::Obj,
    );
    assert_eq!(m.triangles(), &[[1, 2, 3], [1, 3, 0]]);
    let m = ok(
        "v 0 0 0\nv 4 0 0\nv 4 1 0\nv -0.5 1 0\nf 1 2 3 4\n",
        Format::Obj,
    );
    assert_eq!(m.triangles(), &[[0, 1, 2], [0, 2, 3]]);
}

#[test]
fn off_variants_colours_and_polygons() {
    let text = "# leading comment\n\nOFF\n# counts next\n5 3 0\n0 0 0\n1 0 0\n1 1 0 # comment\n\n0 1 0\n0.5 2 0\n\
                3 0 1 2 255 0 0\n3 0 2 3 0.1 0.2 0.3 1.0\n3 3 2 4\n";
    let m = ok(text, Format::Off);
    assert_eq!(m.num_vertices(), 5);
    assert_eq!(m.triangles(), &[[0, 1, 2], [0, 2, 3], [3, 2, 4]]);
    // COFF with vertex colours, counts on the keyword line, CRLF, a quad.
    let text = "COFF 4 1 4\r\n0 0 0 255 0 0 255\r\n1 0 0 0 255 0 255\r\n1 1 0 0 0 255 255\r\n0 1 0 9 9 9 255\r\n4 0 1 2 3 7 7 7\r\n";
    let m = ok(text, Format::Off);
    assert_eq!(m.num_triangles(), 2);
    assert!(xy_areas(&m).iter().all(|&a| (a - 1.0).abs() < 1e-15));
    // Keyword glued to the counts, as some exporters write it; no keyword.
    assert_eq!(
        ok("OFF3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", Format::Off).num_triangles(),
        1
    );
    assert_eq!(
        ok("3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", Format::Off).num_triangles(),
        1
    );
}

/// The PLY header for the test fixtures.
fn ply_header(format: &str, vertex_props: &str, face_list: &str, nv: usize, nf: usize) -> Vec<u8> {
    format!(
        "ply\nformat {format} 1.0\ncomment hand-made\nobj_info test\nelement vertex {nv}\n{vertex_props}\
         element face {nf}\nproperty {face_list}\nproperty uchar flags\nelement edge 2\n\
         property int vertex1\nproperty int vertex2\nend_header\n"
    )
    .into_bytes()
}

fn ply_quad(m: &Mesh3) {
    assert_eq!(
        m.positions(),
        &[
            [0.0, 0.0, 0.5],
            [2.0, 0.0, 0.5],
            [2.0, 1.0, 0.5],
            [0.0, 1.0, 0.5],
            [1.0, 3.0, -0.25]
        ]
    );
    assert_eq!(m.num_triangles(), 3);
    assert!(xy_areas(m).iter().all(|&a| a > 0.0));
    assert!((xy_areas(m).iter().sum::<f64>() - 8.0).abs() < 1e-12);
}

#[test]
fn ply_ascii() {
    let props = "property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty uchar red\n";
    let mut text = ply_header("ascii", props, "list uchar int vertex_indices", 5, 2);
    text.extend_from_slice(
        b"0 0 0.5 0 1\n2 0 0.5 0 2\r\n2 1 0.5 0 3\n\n0 1 0.5 0 4\n1 3 -0.25 0 5\n\
          4 0 1 2 3 7\n3 3 2 4 0\n0 1\n1 2\n",
    );
    ply_quad(&parse_mesh(&text, Format::Ply, Path::new("a.ply")).unwrap());
    // Without z, with `vertex_index` and other types.
    let mut text = ply_header(
        "ascii",
        "property double y\nproperty double x\n",
        "list int uint vertex_index",
        3,
        1,
    );
    text.extend_from_slice(b"0 0\n0 1\n1 0\n3 0 1 2 0\n0 1\n1 2\n");
    let m = parse_mesh(&text, Format::Ply, Path::new("a.ply")).unwrap();
    assert_eq!(
        m.positions(),
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    );
}

#[test]
fn ply_binary_little_and_big_endian() {
    let vertices: [[f64; 3]; 5] = [
        [0.0, 0.0, 0.5],
        [2.0, 0.0, 0.5],
        [2.0, 1.0, 0.5],
        [0.0, 1.0, 0.5],
        [1.0, 3.0, -0.25],
    ];
    let faces: [&[u32]; 2] = [&[0, 1, 2, 3], &[3, 2, 4]];
    for big in [false, true] {
        let (name, props) = if big {
            (
                "binary_big_endian",
                "property short id\nproperty float x\nproperty float y\nproperty double z\n",
            )
        } else {
            ("binary_little_endian", "property double x\nproperty list uchar uchar junk\nproperty float y\nproperty float z\n")
        };
        let list = if big {
            "list ushort uint vertex_indices"
        } else {
            "list uchar int vertex_indices"
        };
        let mut bytes = ply_header(name, props, list, 5, 2);
        macro_rules! put {
            ($v:expr) => {
                bytes.extend_from_slice(&if big {
                    $v.to_be_bytes()
                } else {
                    $v.to_le_bytes()
                })
            };
        }
        for (i, p) in vertices.iter().enumerate() {
            if big {
                put!(i as i16);
                put!(p[0] as f32);
                put!(p[1] as f32);
                put!(p[2]);
            } else {
                put!(p[0]);
                bytes.extend_from_slice(&[2, 7, 7]);
                put!(p[1] as f32);
                put!(p[2] as f32);
            }
        }
        for f in faces {
            if big {
                put!(f.len() as u16);
                for &i in f {
                    put!(i);
                }
            } else {
                bytes.push(f.len() as u8);
                for &i in f {
                    put!(i as i32);
                }
            }
            bytes.push(0); // flags
        }
        for e in [[0i32, 1], [1, 2]] {
            put!(e[0]);
            put!(e[1]);
        }
        let m =
            parse_mesh(&bytes, Format::Ply, Path::new("b.ply")).unwrap_or_else(|e| panic!("{e}"));
        ply_quad(&m);
    }
}

#[test]
fn obj_errors_name_the_file_and_line() {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let o = Format::Obj;
    error(
        &format!("{tri}v 1 2 x3\nf 1 2 3\n"),
        o,
        Some(4),
        "`x3` is not a number",
    );
    error(
        &format!("{tri}v 1 nan 3\nf 1 2 3\n"),
        o,
        Some(4),
        "vertex 4",
    );
    error(
        &format!("{tri}\nv 1 1e999 3\nf 1 2 3\n"),
        o,
        Some(5),
        "not a finite number",
    );
    error(
        &format!("{tri}v 1 -inf 3\n"),
        o,
        Some(4),
        "not a finite number",
    );
    error(&format!("{tri}v 1\n"), o, Some(4), "at least 2 coordinates");
    error(
        &format!("{tri}f 1 2\n"),
        o,
        Some(4),
        "at least 3 vertices, found 2",
    );
    error(&format!("{tri}f 1\n"), o, Some(4), "found 1");
    error(&format!("{tri}f 1 0 2\n"), o, Some(4), "index 0");
    error(
        &format!("{tri}f 1 x 2\n"),
        o,
        Some(4),
        "`x` is not a vertex index",
    );
    // Checked after the whole file: the face's line, the index and the count.
    let msg = error(
        &format!("{tri}f 1 2 3\nf 1 2 7 # bad\nv 1 1 1\n"),
        o,
        Some(5),
        "vertex index 7 is out of range",
    );
    assert!(msg.contains("4 vertices"), "{msg}");
    error(
        &format!("{tri}f 1 2 -4\n"),
        o,
        Some(4),
        "only 3 vertices are defined",
    );
    error(
        &format!("{tri}f 1 2 99999999999\n"),
        o,
        Some(4),
        "out of range",
    );
    error(
        &format!("{tri}f 1 2 1\n"),
        o,
        Some(4),
        "vertex 1 (1-based) more than once",
    );
    error(
        &format!("{tri}f 1 3 -1\n"),
        o,
        Some(4),
        "vertex 3 (1-based) more than once",
    );
    error("", o, None, "no triangles");
    error("# nothing\n\n", o, None, "no triangles");
    error(tri, o, None, "no triangles");
}

#[test]
fn off_errors_name_the_file_and_line() {
    let f = Format::Off;
    let head = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
    error(
        &format!("{head}3 0 1 3\n"),
        f,
        Some(6),
        "vertex index 3 is out of range: the file has 3 vertices",
    );
    error(&format!("{head}3 0 1 -1\n"), f, Some(6), "out of range");
    error(
        &format!("{head}3 0 1 1\n"),
        f,
        Some(6),
        "uses vertex 1 more than once",
    );
    error(&format!("{head}2 0 1\n"), f, Some(6), "at least 3");
    error(
        &format!("{head}4 0 1 2\n"),
        f,
        Some(6),
        "announces 4 vertices but lists 3",
    );
    error(
        &format!("{head}3 0 1 z\n"),
        f,
        Some(6),
        "`z` is not a vertex index",
    );
    error(
        "OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n",
        f,
        Some(4),
        "`zero` is not a number",
    );
    error(
        "OFF\n3 1 0\n0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n",
        f,
        Some(4),
        "vertex 1 has a coordinate that is not a finite",
    );
    error(
        "OFF\n3 1 0\n0 0 0\n1 0\n",
        f,
        Some(4),
        "vertex 1 has 2 coordinates",
    );
    error("OFF\n3 -1 0\n", f, Some(2), "face count `-1`");
    error("OFF\n3 1 0 7\n", f, Some(2), "found 4 values");
    error("PLY\n", f, Some(1), "expected the `OFF` keyword");
    error("4OFF\n", f, Some(1), "not supported");
    error("OFF\n", f, Some(1), "no counts");
    error(head, f, None, "ends after 0 of the 1 faces");
    error(
        "OFF\n4 0 0\n0 0 0\n1 0 0\n",
        f,
        None,
        "ends after 2 of the 4 vertices",
    );
    error("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", f, None, "no triangles");
    error("", f, None, "no triangles");
}

#[test]
fn ply_errors_name_the_file_and_place() {
    let p = Format::Ply;
    let head = |nv: usize, nf: usize| {
        format!(
            "ply\nformat ascii 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\n\
             element face {nf}\nproperty list uchar int vertex_indices\nend_header\n"
        )
    };
    let verts = "0 0\n1 0\n0 1\n";
    error(
        &format!("{}{verts}3 0 1 3\n", head(3, 1)),
        p,
        Some(12),
        "vertex index 3 is out of range: the file has 3 vertices",
    );
    error(
        &format!("{}{verts}3 0 1 1\n", head(3, 1)),
        p,
        Some(12),
        "face 0: the face uses vertex 1 more than once",
    );
    error(
        &format!("{}{verts}2 0 1\n", head(3, 1)),
        p,
        Some(12),
        "at least 3 vertices",
    );
    error(
        &format!("{}{verts}4 0 1 2\n", head(3, 1)),
        p,
        Some(12),
        "a list of 4 values, but only 3 are left",
    );
    error(
        &format!("{}{verts}3 0 1 2 5\n", head(3, 1)),
        p,
        Some(12),
        "more than the header's properties",
    );
    error(
        &format!("{}0 0\n1 x\n", head(3, 1)),
        p,
        Some(10),
        "vertex 1: `x` is not a number",
    );
    error(
        &format!("{}0 0\n1 nan\n", head(3, 1)),
        p,
        Some(10),
        "coordinate y is not a finite number",
    );
    error(
        &format!("{}{verts}", head(3, 1)),
        p,
        Some(11),
        "announces 1 `face` elements",
    );
    error(&format!("{}{verts}", head(3, 0)), p, None, "no triangles");
    error(
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nend_header\n",
        p,
        None,
        "no triangles",
    );
    error(
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty floaty x\n",
        p,
        Some(4),
        "unknown property type `floaty`",
    );
    error(
        "ply\nformat ascii 1.0\nelemnt vertex 1\n",
        p,
        Some(3),
        "unexpected header line",
    );
    error(
        "ply\nformat ascii 1.0\nelement vertex 1\n",
        p,
        None,
        "no `end_header`",
    );
    error("plx\n", p, Some(1), "not a PLY file");
    // Binary: the element, its number and the byte offset instead of a line.
    let mut bytes = head(3, 1)
        .replace("ascii", "binary_little_endian")
        .into_bytes();
    for x in [0f32, 0., 1., 0., 0., 1.] {
        bytes.extend_from_slice(&x.to_le_bytes());
    }
    bytes.push(3);
    for i in [0i32, 1] {
        bytes.extend_from_slice(&i.to_le_bytes());
    }
    let e = parse_mesh(&bytes, p, Path::new("t.ply"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`t.ply`")
            && e.contains("face 0 (body byte 25)")
            && e.contains("a list of 3 values"),
        "{e}"
    );
    bytes.extend_from_slice(&2i32.to_le_bytes()[..3]);
    let e = parse_mesh(&bytes, p, Path::new("t.ply"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("`t.ply`") && e.contains("face 0"), "{e}");
}

/// A tiny deterministic generator for garbage bytes.
fn lcg(seed: &mut u64) -> u8 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 56) as u8
}

#[test]
fn truncated_and_garbage_inputs_are_errors_not_panics() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = awkward_mesh();
    let mut seed = 7;
    for format in FORMATS {
        let path = dir.path().join(format!("m.{format}"));
        write_mesh(&path, &mesh, format).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        // Every prefix (most cut a number or a face short: errors or a
        // smaller mesh; never a panic) and the empty file.
        for len in 0..bytes.len() {
            let _ = parse_mesh(&bytes[..len], format, &path);
        }
        assert!(parse_mesh(&[], format, &path).is_err());
        // Bytes flipped at random places.
        for _ in 0..300 {
            let mut b = bytes.clone();
            for _ in 0..4 {
                let at = (lcg(&mut seed) as usize * 257 + lcg(&mut seed) as usize) % b.len();
                b[at] = lcg(&mut seed);
            }
            let _ = parse_mesh(&b, format, &path);
        }
        // Pure garbage.
        for len in [1, 10, 100, 1000] {
            let b: Vec<u8> = (0..len).map(|_| lcg(&mut seed)).collect();
            assert!(parse_mesh(&b, format, &path).is_err());
        }
    }
    // Truncated binary PLY: an error, not a panic.
    let path = dir.path().join("m.ply");
    let bytes = std::fs::read(&path).unwrap();
    assert!(parse_mesh(&bytes[..bytes.len() - 1], Format::Ply, &path).is_err());
    // Huge counts in headers must not allocate or loop blindly.
    let huge = "ply\nformat binary_little_endian 1.0\nelement vertex 18446744073709551615\nproperty double x\n\
                property double y\nelement face 4000000000000\nproperty list uint uint vertex_indices\nend_header\n";
    assert!(parse(huge, Format::Ply).is_err());
    let huge = "ply\nformat ascii 1.0\nelement vertex 900000000000000000\nproperty double x\n\
                property double y\nelement face 1\nproperty list uint uint vertex_indices\nend_header\n0 0\n";
    assert!(parse(huge, Format::Ply).is_err());
    let huge = "ply\nformat binary_big_endian 1.0\nelement junk 900000000000000000\nproperty double a\n\
                element vertex 0\nproperty double x\nproperty double y\nelement face 0\nproperty list uint uint vertex_indices\nend_header\n";
    assert!(parse(huge, Format::Ply).is_err());
    assert!(parse(
        "OFF\n900000000000000000 900000000000000000 0\n0 0 0\n",
        Format::Off
    )
    .is_err());
    let mut list = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty uchar x\nproperty uchar y\n\
                    element face 1\nproperty list uint uint vertex_indices\nend_header\n\0\0\x01\0\0\x01"
        .as_bytes()
        .to_vec();
    list.extend_from_slice(&u32::MAX.to_le_bytes());
    assert!(parse_mesh(&list, Format::Ply, Path::new("x.ply"))
        .unwrap_err()
        .to_string()
        .contains("a list of 4294967295"));
}

fn dir_entries(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect()
}

#[test]
fn failed_writes_leave_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("out.obj");
    // The writer fails half-way.
    let e = write_atomic(&target, |w| {
        w.write_all(b"partial")?;
        Err(std::io::Error::other("disk full"))
    })
    .unwrap_err();
    assert!(matches!(e, Error::Io { .. }));
    assert!(
        e.to_string().contains("out.obj") && e.to_string().contains("disk full"),
        "{e}"
    );
    assert!(dir_entries(dir.path()).is_empty());

    // The target is an existing directory: renaming onto it fails.
    let sub = dir.path().join("taken.obj");
    std::fs::create_dir(&sub).unwrap();
    let e = write_mesh(&sub, &planar_mesh(), Format::Obj).unwrap_err();
    assert!(e.to_string().contains("taken.obj"), "{e}");
    assert_eq!(dir_entries(dir.path()), vec![sub.clone()]);
    assert!(dir_entries(&sub).is_empty());

    // The directory does not exist.
    let e = write_mesh(
        &dir.path().join("missing/out.off"),
        &planar_mesh(),
        Format::Off,
    )
    .unwrap_err();
    assert!(e.to_string().contains("out.off"), "{e}");
    assert_eq!(dir_entries(dir.path()), vec![sub.clone()]);

    // Unwritable input: NaN coordinates, bad indices.
    let target = dir.path().join("nan.ply");
    let e = write_positions(
        &target,
        &[[0.0, f64::NAN], [1.0, 0.0], [0.0, 1.0]],
        &[[0, 1, 2]],
        Format::Ply,
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("nan.ply") && e.to_string().contains("vertex 0"),
        "{e}"
    );
    let e = write_positions(&target, &[[0.0; 3]; 3], &[[0, 1, 3]], Format::Ply).unwrap_err();
    assert!(e.to_string().contains("triangle 0"), "{e}");
    assert_eq!(dir_entries(dir.path()), vec![sub]);
}

#[test]
fn atomic_write_replaces_and_keeps_usual_permissions() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("a.txt");
    write_atomic(&target, |w| w.write_all(b"old")).unwrap();
    write_atomic(&target, |w| writeln!(w, "new")).unwrap();
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "new\n");
    // A failed rewrite leaves the old contents.
    assert!(write_atomic(&target, |_| Err(std::io::Error::other("no"))).is_err());
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "new\n");
    assert_eq!(dir_entries(dir.path()), vec![target.clone()]);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        let mode = std::fs::metadata(&target).unwrap().permissions().mode();
        assert_ne!(mode & 0o044, 0, "not the 0600 of temporary files: {mode:o}");
    }
    // A relative path without a directory part writes to the working directory.
    let name = format!("meshmorph-io-test-{}.txt", std::process::id());
    write_atomic(Path::new(&name), |w| w.write_all(b"x")).unwrap();
    assert_eq!(std::fs::read(&name).unwrap(), b"x");
    std::fs::remove_file(&name).unwrap();
}

#[test]
fn formats_and_file_errors() {
    assert_eq!(
        Format::from_path(Path::new("dir/x.Ply")).unwrap(),
        Format::Ply
    );
    assert_eq!(Format::Off.extension(), "off");
    assert_eq!("obj".parse::<Format>().unwrap(), Format::Obj);
    assert_eq!(".STL".parse::<Format>().unwrap(), Format::Stl);
    assert!("fbx"
        .parse::<Format>()
        .unwrap_err()
        .to_string()
        .contains("obj, off, ply, stl"));
    let e = read_mesh(Path::new("mesh.fbx")).unwrap_err();
    assert!(
        matches!(e, Error::UnknownFormat { .. }) && e.to_string().contains("mesh.fbx"),
        "{e}"
    );
    let e = read_mesh(Path::new("/nonexistent/dir/mesh.obj")).unwrap_err();
    assert!(
        matches!(e, Error::Io { .. }) && e.to_string().contains("mesh.obj"),
        "{e}"
    );
    // read_mesh_as ignores the extension.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mesh.txt");
    write_mesh(&path, &planar_mesh(), Format::Off).unwrap();
    assert_eq!(
        read_mesh_as(&path, Format::Off).unwrap().to_2d().unwrap(),
        planar_mesh()
    );
    let e = read_mesh_as(&path, Format::Ply).unwrap_err().to_string();
    assert!(e.contains("mesh.txt") && e.contains("line 1"), "{e}");
}

/// A `n × n` grid of vertices with irrational-looking coordinates.
fn grid(n: u32) -> Mesh3 {
    let positions = (0..n * n)
        .map(|k| {
            let (i, j) = (f64::from(k % n), f64::from(k / n));
            [i / 7.0 + 0.1, j / 3.0 - 0.3, (i * 0.37 + j * 0.11).sin()]
        })
        .collect();
    let mut triangles = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let k = j * n + i;
            triangles.push([k, k + 1, k + n + 1]);
            triangles.push([k, k + n + 1, k + n]);
        }
    }
    Mesh3::new(positions, triangles).unwrap()
}

#[test]
fn large_mesh_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = grid(317); // 100 489 vertices, 200 032 triangles
    for format in FORMATS {
        let path = dir.path().join(format!("big.{format}"));
        let start = std::time::Instant::now();
        write_mesh(&path, &mesh, format).unwrap();
        let written = start.elapsed();
        let start = std::time::Instant::now();
        let back = read_mesh(&path).unwrap();
        println!(
            "{format}: {} V, {} T written in {written:?}, read in {:?}",
            mesh.num_vertices(),
            mesh.num_triangles(),
            start.elapsed()
        );
        assert_eq!(back, mesh, "{format}");
    }
}

/// An OBJ result written to another folder than its source keeps its
/// materials: each relative `mtllib` path is rewritten to lead from there to
/// the same `.mtl` file, which is neither copied nor changed; in the source's
/// own folder, and for absolute paths, the bytes are the source's.
#[test]
fn obj_material_libraries_resolve_from_the_output_folder() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().canonicalize().unwrap();
    let src = root.join("assets");
    std::fs::create_dir_all(src.join("mat")).unwrap();
    let libraries = [
        ("sheet.mtl", "newmtl red\nKd 1 0 0\n"),
        ("mat/other.mtl", "newmtl blue\nKd 0 0 1\n"),
        ("my skin.mtl", "newmtl skin\nKd 1 0.8 0.6\n"),
    ];
    for (name, text) in libraries {
        std::fs::write(src.join(name), text).unwrap();
    }
    let absolute = root.join("elsewhere/abs.mtl");
    let head = format!(
        "# materials\r\nmtllib sheet.mtl\r\nmtllib  ./mat/other.mtl sheet.mtl  # two\r\n\
         mtllib my skin.mtl\r\nmtllib {}\r\n",
        absolute.display()
    );
    let body = "o sheet\r\nv 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nusemtl red\r\nf 1 2 3 4\r\n";
    let text = head.clone() + body;
    let source = src.join("sheet.obj");
    std::fs::write(&source, &text).unwrap();
    let file = MeshFile::read(&source).unwrap();
    let moved: Vec<[f64; 3]> = file
        .mesh()
        .positions()
        .iter()
        .map(|p| [p[0], p[1], 0.5 * p[0]])
        .collect();

    // The source's folder, by another spelling too: the file as it was.
    for name in ["same.obj", "mat/../same.obj"] {
        let out = src.join(name);
        file.write(&out, file.mesh().positions(), Format::Obj)
            .unwrap();
        assert_eq!(std::fs::read_to_string(&out).unwrap(), text, "{name}");
    }

    // Folders below, beside and above the source's.
    for (name, prefix) in [
        ("out/r2/frame.obj", "../../assets/"),
        ("beside/frame.obj", "../assets/"),
        ("frame.obj", "assets/"),
        ("assets/deep/er/frame.obj", "../../"),
    ] {
        let out = root.join(name);
        std::fs::create_dir_all(out.parent().unwrap()).unwrap();
        file.write(&out, &moved, Format::Obj).unwrap();
        let written = std::fs::read_to_string(&out).unwrap();
        let expected_head = format!(
            "# materials\r\nmtllib {prefix}sheet.mtl\r\nmtllib  {prefix}mat/other.mtl {prefix}sheet.mtl  # two\r\n\
             mtllib {prefix}my skin.mtl\r\nmtllib {}\r\n",
            absolute.display()
        );
        assert!(written.starts_with(&expected_head), "{name}:\n{written}");
        // Everything else is what the source's folder gets.
        let beside = src.join("moved.obj");
        file.write(&beside, &moved, Format::Obj).unwrap();
        let beside_text = std::fs::read_to_string(&beside).unwrap();
        assert_eq!(&written[expected_head.len()..], &beside_text[head.len()..]);
        // Each path leads to the library it named.
        let folder = out.parent().unwrap();
        for (library, text) in libraries {
            let path = folder.join(format!("{prefix}{library}"));
            assert_eq!(
                std::fs::read_to_string(&path).unwrap(),
                text,
                "{}",
                path.display()
            );
        }
        assert_eq!(read_mesh(&out).unwrap().positions(), &moved[..], "{name}");
    }
    // Nothing copied, nothing changed.
    for (name, text) in libraries {
        assert_eq!(std::fs::read_to_string(src.join(name)).unwrap(), text);
    }
    assert!(!root.join("out/r2/sheet.mtl").exists());
}

/// A vertex with 2 coordinates among vertices with 3 (or the other way
/// round) is refused at its line, not read as z = 0; files whose vertices
/// all have 2 coordinates are planar meshes and stay readable, whatever
/// they are read through.
#[test]
fn obj_vertices_with_2_and_3_coordinates_do_not_mix() {
    let square = |vertices: [&str; 4]| {
        format!(
            "# square\nv {}\nv {}\nv {}\nv {}\nf 1 2 3 4\n",
            vertices[0], vertices[1], vertices[2], vertices[3]
        )
    };
    let planar = square(["0 0", "1 0", "1 1", "0 1"]);
    assert_eq!(ok(&planar, Format::Obj).positions()[2], [1.0, 1.0, 0.0]);
    let spatial = square(["0 0 0", "1 0 0", "1 1 0.5", "0 1 0 1"]);
    assert_eq!(ok(&spatial, Format::Obj).positions()[2], [1.0, 1.0, 0.5]);
    let msg = error(
        &square(["0 0 0", "1 0 0", "0.1 0.2", "0 1 0"]),
        Format::Obj,
        Some(4),
        "vertex 3 (1-based) has 2 coordinates where the vertices before it have 3 (the first at line 2)",
    );
    assert!(msg.contains("planar"), "{msg}");
    error(
        &square(["0 0", "1 0", "1 1", "0 1 0"]),
        Format::Obj,
        Some(5),
        "vertex 4 (1-based) has 3 coordinates where the vertices before it have 2 (the first at line 2)",
    );

    // Read whole, and as a pose of a file in space.
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("rest.obj");
    std::fs::write(&reference, &spatial).unwrap();
    let pose = dir.path().join("pose.obj");
    std::fs::write(&pose, square(["0 0 0", "1 0 0", "0.1 0.2", "0 1 0"])).unwrap();
    let rest = MeshFile::read(&reference).unwrap();
    for e in [
        MeshFile::read(&pose).unwrap_err(),
        rest.read_pose(&pose).unwrap_err(),
    ] {
        let msg = e.to_string();
        assert!(
            msg.contains(&pose.display().to_string())
                && msg.contains("line 4")
                && msg.contains("has 2 coordinates"),
            "{msg}"
        );
    }
}

/// Lines (`l`) and points (`p`) have their indices checked as faces' are,
/// with the same messages, and are written back as they were.
#[test]
fn obj_lines_and_points_are_checked_as_faces_are() {
    let triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n";
    // Absolute, relative, with texture coordinates, forward references.
    let good = format!(
        "{triangle}l 1 2 3 1\nl -3 -2\np 3\np 1 -1\nl 1/1 2/1\nl 1 4\np 4\nf 1 2 3\nv 1 1 0\n"
    );
    assert_eq!(ok(&good, Format::Obj).num_vertices(), 4);
    for (element, needle) in [
        (
            "l 508 9999",
            "vertex index 9999 is out of range: the file has 3 vertices",
        ),
        ("p 0", "vertex index 0 is invalid"),
        ("l 1 2 3 abc", "`abc` is not a vertex index"),
        ("l 1 x/1", "`x/1` is not a vertex index"),
        (
            "l -4 1",
            "vertex index -4 is out of range: only 3 vertices are defined before this line",
        ),
        ("l 1", "a line (`l`) needs at least 2 vertices, found 1"),
        ("p", "a point (`p`) needs at least 1 vertex, found 0"),
        (
            "l 1/2 2/1",
            "texture coordinate index 2 is out of range: the file has 1 texture coordinates",
        ),
        ("l 1/0 2", "texture coordinate index 0 is out of range"),
        ("p 1/1", "`1/1` is not a vertex index (`v`)"),
        ("l 1/1/1 2", "`1/1/1` is not a vertex index (`v` or `v/vt`)"),
    ] {
        let text = format!("{triangle}f 1 2 3\n{element}\n");
        error(&text, Format::Obj, Some(6), needle);
    }

    // Kept as written in results; refused in a pose too.
    let dir = tempfile::tempdir().unwrap();
    let rest = dir.path().join("rest.obj");
    std::fs::write(&rest, &good).unwrap();
    let file = MeshFile::read(&rest).unwrap();
    let out = dir.path().join("out.obj");
    let moved: Vec<[f64; 3]> = file
        .mesh()
        .positions()
        .iter()
        .map(|p| [p[0] + 1.0, p[1], p[2]])
        .collect();
    file.write(&out, &moved, Format::Obj).unwrap();
    let elements = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| l.starts_with("l ") || l.starts_with("p "))
            .map(String::from)
            .collect()
    };
    assert_eq!(
        elements(&std::fs::read_to_string(&out).unwrap()),
        elements(&good)
    );
    let pose = dir.path().join("pose.obj");
    std::fs::write(&pose, good.replace("l -3 -2", "l -3 -9")).unwrap();
    let msg = file.read_pose(&pose).unwrap_err().to_string();
    assert!(
        msg.contains(&pose.display().to_string())
            && msg.contains("line 6")
            && msg.contains("vertex index -9 is out of range"),
        "{msg}"
    );
}

/// Triangles of a grid of `n` x `n` quads, each split along the diagonal
/// from its first corner, except quad `other`, split along the other one:
/// as an exporter triangulating by the shape splits a bent pose. The two
/// halves of each quad follow each other, or (`apart`, as Blender writes
/// them) the second halves come after all the first.
fn split_grid_obj(n: u32, other: Option<u32>, apart: bool) -> String {
    let mut text = String::from("# split quads\n");
    for j in 0..=n {
        for i in 0..=n {
            text += &format!("v {i} {j} {}\n", (i * j) % 3);
        }
    }
    let at = |i: u32, j: u32| j * (n + 1) + i + 1;
    let mut halves = [String::new(), String::new()];
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            let [first, second] = if other == Some(j * n + i) {
                [[a, b, d], [b, c, d]]
            } else {
                [[a, b, c], [a, c, d]]
            };
            let face = |t: [u32; 3]| format!("f {} {} {}\n", t[0], t[1], t[2]);
            halves[0] += &face(first);
            halves[usize::from(apart)] += &face(second);
        }
    }
    text + &halves[0] + &halves[1]
}

/// A pose whose triangles split a quad of the reference along the other
/// diagonal is refused, saying so (the quad's corners, both diagonals, both
/// faces and their lines, numbered from 1) and how to avoid it; any other
/// difference names the face and its vertices numbered from 1 too.
#[test]
fn a_quad_split_along_the_other_diagonal_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let n = 4;
    let first_face_line = 2 + ((n + 1) * (n + 1)) as usize;
    for apart in [false, true] {
        let rest_path = dir.path().join(format!("rest{apart}.obj"));
        std::fs::write(&rest_path, split_grid_obj(n, None, apart)).unwrap();
        let rest = MeshFile::read(&rest_path).unwrap();
        for quad in 0..n * n {
            let (i, j) = (quad % n, quad / n);
            let at = |i: u32, j: u32| j * (n + 1) + i + 1;
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            let pose_path = dir.path().join(format!("pose{quad}{apart}.obj"));
            std::fs::write(&pose_path, split_grid_obj(n, Some(quad), apart)).unwrap();
            let (face, second) = if apart {
                (quad as usize, (n * n + quad) as usize)
            } else {
                (2 * quad as usize, 2 * quad as usize + 1)
            };
            let line = first_face_line + face;
            let errors = [
                rest.read_pose(&pose_path).unwrap_err(),
                rest.pose(&MeshFile::read(&pose_path).unwrap()).unwrap_err(),
            ];
            for e in errors {
                assert!(
                    matches!(e, Error::FaceMismatch { face: f, line: Some(l), .. } if f == face && l == line),
                    "{e:?}"
                );
                let msg = e.to_string();
                for needle in [
                    pose_path.display().to_string(),
                    rest_path.display().to_string(),
                    format!(
                        "faces {} and {} (lines {line} and {})",
                        face + 1,
                        second + 1,
                        first_face_line + second
                    ),
                    format!("splits the quad [{a}, {b}, {c}, {d}] along its diagonal {b}-{d}"),
                    format!("splits it along {a}-{c}"),
                    "without triangulating".to_string(),
                    "same triangulation".to_string(),
                ] {
                    assert!(msg.contains(&needle), "`{needle}` not in: {msg}");
                }
            }
        }
    }
    let rest_path = dir.path().join("restfalse.obj");
    let rest = MeshFile::read(&rest_path).unwrap();
    // The two halves of a quad swapped: the same split in another order,
    // not a quad split the other way.
    let text = split_grid_obj(n, None, false);
    let mut lines: Vec<&str> = text.lines().collect();
    lines.swap(first_face_line + 1, first_face_line + 2);
    let swapped = dir.path().join("swapped.obj");
    std::fs::write(&swapped, lines.join("\n")).unwrap();
    let msg = rest.read_pose(&swapped).unwrap_err().to_string();
    let (l3, l4) = (
        text.lines().nth(first_face_line + 1).unwrap(),
        text.lines().nth(first_face_line + 2).unwrap(),
    );
    let corners = |l: &str| l[2..].replace(' ', ", ");
    let expected = format!(
        "face 3 (line {}): vertices [{}] but face 3 of `{}` has [{}] (faces and vertices numbered from 1)",
        first_face_line + 2,
        corners(l4),
        rest_path.display(),
        corners(l3)
    );
    assert!(msg.contains(&expected), "`{expected}` not in: {msg}");
    assert!(!msg.contains("diagonal"), "{msg}");
}

/// A PLY or OFF written as OBJ keeps its texture coordinates (`vt`) and its
/// normals (`vn`, turned with the surface), each corner indexing its own;
/// only what OBJ cannot hold is named as dropped.
#[test]
fn ply_and_off_as_obj_keep_texture_coordinates_and_normals() {
    let dir = tempfile::tempdir().unwrap();
    let ply = "ply\nformat ascii 1.0\nelement vertex 5\n\
               property float x\nproperty float y\nproperty float z\n\
               property float nx\nproperty float ny\nproperty float nz\n\
               property float s\nproperty float t\nproperty uchar red\n\
               element face 2\nproperty list uchar int vertex_indices\nend_header\n\
               0 0 0 0 0 1 0 0 255\n1 0 0 0 0 1 0.5 0 0\n1 1 0 0.6 0 0.8 0.5 1 0\n\
               0 1 0 0 0 1 0 1 0\n2 0 0 0 0 1 1 0 0\n4 0 1 2 3\n3 1 4 2\n";
    let off = "STNOFF\n5 2 0\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 0.5 0\n1 1 0 0.6 0 0.8 0.5 1\n\
               0 1 0 0 0 1 0 1\n2 0 0 0 0 1 1 0\n4 0 1 2 3\n3 1 4 2\n";
    // A quarter turn about x.
    let turn = |p: [f64; 3]| [p[0], -p[2], p[1]];
    let normals = [
        [0.0, 0.0, 1.0],
        [0.0, 0.0, 1.0],
        [0.6, 0.0, 0.8],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, 1.0],
    ];
    for (name, text) in [("quad.ply", ply), ("quad.off", off)] {
        let source = dir.path().join(name);
        std::fs::write(&source, text).unwrap();
        let file = MeshFile::read(&source).unwrap();
        let turned: Vec<[f64; 3]> = file.mesh().positions().iter().map(|&p| turn(p)).collect();
        let out = dir.path().join(format!("{name}.obj"));
        let dropped = file.write(&out, &turned, Format::Obj).unwrap();
        let all = dropped.join("\n");
        assert!(
            !all.contains("texture coordinates") && !all.contains("normals"),
            "{name}: {all}"
        );
        if name.ends_with("ply") {
            assert!(all.contains("vertex property `red`"), "{all}");
        }
        let written = std::fs::read_to_string(&out).unwrap();
        let lines = |keyword: &str| -> Vec<Vec<f64>> {
            written
                .lines()
                .filter_map(|l| l.strip_prefix(keyword))
                .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
                .collect()
        };
        assert_eq!(lines("vt ").len(), 5, "{written}");
        let vn = lines("vn ");
        assert_eq!(vn.len(), 5, "{written}");
        for (got, want) in vn.iter().zip(normals) {
            let want = turn(want);
            assert!(
                (0..3).all(|k| (got[k] - want[k]).abs() < 1e-9),
                "{name}: {got:?} against {want:?}"
            );
        }
        assert!(
            written.contains("\nf 1/1/1 2/2/2 3/3/3 4/4/4\nf 2/2/2 5/5/5 3/3/3\n"),
            "{written}"
        );
        let back = MeshFile::read(&out).unwrap();
        assert_eq!(back.mesh().positions(), &turned[..]);
        assert_eq!(back.mesh().triangles(), file.mesh().triangles());
        assert_eq!(back.triangle_corner_uvs(), file.triangle_corner_uvs());
        assert!(back.triangle_corner_uvs().is_some());
    }
}

#[test]
fn obj_lines_continued_with_a_backslash_read_and_write_back() {
    let dir = tempfile::tempdir().unwrap();
    let plain = "v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1 4/1\n";
    // The same file with lines broken by `\`: spaced or glued to a number,
    // with spaces after it, with CR LF line ends.
    let continued = "v 0 0 \\\n  0\nv 1\\\n 0 0\nv 1 1 0.5 \\  \r\n\nv 0 1 0\nvt 0 \\\n0\nf 1/1 2/1 \\\r\n 3/1 4/1\n";
    let (a, b) = (
        dir.path().join("plain.obj"),
        dir.path().join("continued.obj"),
    );
    std::fs::write(&a, plain).unwrap();
    std::fs::write(&b, continued).unwrap();
    let (fa, fb) = (MeshFile::read(&a).unwrap(), MeshFile::read(&b).unwrap());
    assert_eq!(fa.mesh().positions(), fb.mesh().positions());
    assert_eq!(fa.mesh().triangles(), fb.mesh().triangles());
    assert_eq!(fb.num_faces(), 1);
    let moved: Vec<[f64; 3]> = fb
        .mesh()
        .positions()
        .iter()
        .map(|p| p.map(|x| 2.0 * x))
        .collect();
    let out = dir.path().join("out.obj");
    fb.write(&out, &moved, Format::Obj).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(
        text,
        "v 0 0 \\\n  0\nv 2\\\n 0 0\nv 2 2 1 \\  \r\n\nv 0 2 0\nvt 0 \\\n0\nf 1/1 2/1 \\\r\n 3/1 4/1\n"
    );
    // A comment after the `\` (and on the lines it joins) is a comment.
    std::fs::write(
        &b,
        "v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\nvt 0 0\nf 1/1 2/1 \\ # first two\n 3/1 \\# third\n4/1\n",
    )
    .unwrap();
    let fb = MeshFile::read(&b).unwrap();
    assert_eq!(fb.mesh().triangles(), fa.mesh().triangles());
    // A `\` that ends the file continues nothing.
    std::fs::write(&b, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 \\").unwrap();
    assert!(MeshFile::read(&b).is_err());
}

#[test]
fn a_vertex_repeated_in_a_row_is_read_without_the_repeat() {
    let dir = tempfile::tempdir().unwrap();
    let vertices = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n";
    let read = |name: &str, faces: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, format!("{vertices}{faces}")).unwrap();
        MeshFile::read(&path)
    };
    let plain = read("plain.obj", "f 1 2 3 4\nf 2 5 3\n").unwrap();
    // Repeats in a row, also across the end of the list.
    let repeated = read("repeated.obj", "f 1 2 3 3 4\nf 2 5 3 2\n").unwrap();
    assert_eq!(repeated.mesh().triangles(), plain.mesh().triangles());
    assert_eq!(repeated.faces_repeating_a_vertex(), [0, 1]);
    assert!(plain.faces_repeating_a_vertex().is_empty());
    // A pose of it with the same faces; the file written back as it was.
    let pose = read("pose.obj", "f 1 2 3 3 4\nf 2 5 3 2\n").unwrap();
    assert!(repeated.pose(&pose).is_ok());
    let out = dir.path().join("out.obj");
    repeated
        .write(&out, repeated.mesh().positions(), Format::Obj)
        .unwrap();
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .ends_with("f 1 2 3 3 4\nf 2 5 3 2\n"));
    // A repeat apart, or too few distinct vertices, is refused.
    let e = read("apart.obj", "f 1 2 1 3\n").unwrap_err().to_string();
    assert!(
        e.contains("vertex 1 (1-based) more than once, not in a row"),
        "{e}"
    );
    let e = read("two.obj", "f 1 2 2\n").unwrap_err().to_string();
    assert!(e.contains("2 distinct vertices"), "{e}");
}

#[test]
fn another_format_keeps_what_it_can_hold() {
    let dir = tempfile::tempdir().unwrap();
    // A quad and a triangle: coloured vertices, one texture coordinate and
    // one normal per vertex.
    let obj = dir.path().join("looks.obj");
    std::fs::write(
        &obj,
        "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\nv 2 0 0 0.5 0.5 0.5\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\nvn 0 0 1\n\
         f 1/1/1 2/2/1 3/3/1 4/4/1\nf 2/2/1 5/5/1 3/3/1\n",
    )
    .unwrap();
    let file = MeshFile::read(&obj).unwrap();
    let moved: Vec<[f64; 3]> = file
        .mesh()
        .positions()
        .iter()
        .map(|p| [p[0], p[1], 0.5 * p[0]])
        .collect();
    for format in [Format::Ply, Format::Off] {
        let out = dir.path().join(format!("looks.{format}"));
        let dropped = file.write(&out, &moved, format).unwrap();
        assert!(dropped.is_empty(), "{format}: {dropped:?}");
        let back = MeshFile::read(&out).unwrap();
        assert_eq!(back.mesh().positions(), &moved[..]);
        // Colours as bytes: within one step of 1/255.
        let (got, want) = (back.vertex_colors().unwrap(), file.vertex_colors().unwrap());
        for (a, b) in got.iter().zip(want) {
            assert!(
                (0..4).all(|k| (a[k] - b[k]).abs() <= 1.0 / 255.0),
                "{format}: {a:?} {b:?}"
            );
        }
        assert_eq!(
            back.triangle_corner_uvs(),
            file.triangle_corner_uvs(),
            "{format}"
        );
        // The normal turned with the tilted plane: (-0.5, 0, 1) normalised.
        let normals = back.triangle_corner_normals().expect("normals");
        let want = [-0.5 / 1.25f64.sqrt(), 0.0, 1.0 / 1.25f64.sqrt()];
        for n in normals.iter().flatten() {
            for k in 0..3 {
                assert!((f64::from(n[k]) - want[k]).abs() < 1e-6, "{format}: {n:?}");
            }
        }
    }
    // A texture seam (vertex 3 with two texture coordinates) and a hard
    // edge (vertex 2 with two normals): PLY keeps the coordinates per corner,
    // OFF keeps neither, and both say so.
    std::fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\nvt 0.9 0.9\nvn 0 0 1\nvn 0 1 0\n\
         f 1/1/1 2/2/1 3/3/1 4/4/1\nf 2/2/2 5/5/2 3/6/2\n",
    )
    .unwrap();
    let file = MeshFile::read(&obj).unwrap();
    let ply = dir.path().join("seam.ply");
    let dropped = file
        .write(&ply, file.mesh().positions(), Format::Ply)
        .unwrap();
    assert_eq!(dropped.len(), 1, "{dropped:?}");
    assert!(dropped[0].contains("normals"), "{dropped:?}");
    let back = MeshFile::read(&ply).unwrap();
    assert_eq!(back.triangle_corner_uvs(), file.triangle_corner_uvs());
    let off = dir.path().join("seam.off");
    let dropped = file
        .write(&off, file.mesh().positions(), Format::Off)
        .unwrap()
        .join("\n");
    assert!(
        dropped.contains("texture coordinates") && dropped.contains("normals"),
        "{dropped}"
    );
    // PLY colours to OBJ: `v x y z r g b`.
    let coloured = dir.path().join("c.ply");
    std::fs::write(
        &coloured,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\n\
         element face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n",
    )
    .unwrap();
    let file = MeshFile::read(&coloured).unwrap();
    let as_obj = dir.path().join("c.obj");
    assert!(file
        .write(&as_obj, file.mesh().positions(), Format::Obj)
        .unwrap()
        .is_empty());
    assert_eq!(
        MeshFile::read(&as_obj).unwrap().vertex_colors(),
        file.vertex_colors()
    );
}

#[test]
fn off_colours_are_bytes_or_fractions_for_the_whole_file() {
    let dir = tempfile::tempdir().unwrap();
    let read = |body: &str| {
        let path = dir.path().join("c.off");
        std::fs::write(&path, format!("COFF\n3 1 0\n{body}3 0 1 2\n")).unwrap();
        MeshFile::read(&path)
            .unwrap()
            .vertex_colors()
            .unwrap()
            .to_vec()
    };
    // Numbers from 0 to 1, one vertex written without a fraction.
    let c = read("0 0 0 0.5 0.25 0.1 1\n1 0 0 1 0 0 1\n0 1 0 0 0 1\n");
    assert_eq!(c[1], [1.0, 0.0, 0.0, 1.0]);
    assert_eq!(c[2], [0.0, 0.0, 1.0, 1.0]);
    // Bytes.
    let c = read("0 0 0 255 0 0 255\n1 0 0 0 51 0 255\n0 1 0 0 0 255\n");
    assert_eq!(c[0], [1.0, 0.0, 0.0, 1.0]);
    assert!((c[1][1] - 0.2).abs() < 1e-6);
}

#[test]
fn ply_texture_coordinates_of_a_face_of_many_corners_read_back() {
    let dir = tempfile::tempdir().unwrap();
    // A 130-gon, and a triangle that gives its first vertex a second
    // texture coordinate (a seam): PLY holds them per corner.
    let n = 130;
    let mut text = String::new();
    for k in 0..n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        text += &format!(
            "v {} {} 0\nvt {} {}\n",
            a.cos(),
            a.sin(),
            0.5 + 0.4 * a.cos(),
            0.5 + 0.4 * a.sin()
        );
    }
    text += &format!(
        "v 2 0 0\nvt 0.9 0.9\nvt 0.1 0.1\nf {}\n",
        (1..=n)
            .map(|k| format!("{k}/{k}"))
            .collect::<Vec<_>>()
            .join(" ")
    );
    text += &format!("f 1/{} {}/{} 2/2\n", n + 2, n + 1, n + 1);
    let obj = dir.path().join("big.obj");
    std::fs::write(&obj, text).unwrap();
    let file = MeshFile::read(&obj).unwrap();
    let ply = dir.path().join("big.ply");
    file.write(&ply, file.mesh().positions(), Format::Ply)
        .unwrap();
    let back = MeshFile::read(&ply).unwrap();
    let (a, b) = (
        back.triangle_corner_uvs().unwrap(),
        file.triangle_corner_uvs().unwrap(),
    );
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().flatten().zip(b.iter().flatten()) {
        assert!((x[0] - y[0]).abs() < 1e-6 && (x[1] - y[1]).abs() < 1e-6);
    }
}

#[test]
fn planar_obj_lines_stay_planar_unless_the_shape_leaves_the_plane() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flat.obj");
    std::fs::write(&path, "v 0 0\nv 1 0\nv 0 1\nf 1 2 3\n").unwrap();
    let file = MeshFile::read(&path).unwrap();
    let out = dir.path().join("moved.obj");
    let written = |positions: &[[f64; 3]]| {
        file.write(&out, positions, Format::Obj).unwrap();
        std::fs::read_to_string(&out).unwrap()
    };
    assert_eq!(
        written(&[[0.5, 0.0, 0.0], [1.5, 0.0, 0.0], [0.5, 1.0, 0.0]]),
        "v 0.5 0\nv 1.5 0\nv 0.5 1\nf 1 2 3\n"
    );
    assert_eq!(
        written(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.25], [0.0, 1.0, 0.0]]),
        "v 0 0 0\nv 1 0 0.25\nv 0 1 0\nf 1 2 3\n"
    );
    // Read back: a file never mixes 2 and 3 coordinates.
    assert_eq!(read_mesh(&out).unwrap().positions()[1], [1.0, 0.0, 0.25]);
}

/// OFF and PLY files with more than their header announces are read as
/// the header says, with a warning naming the file and where the rest
/// begins.
#[test]
fn content_past_the_header_counts_is_read_with_a_warning() {
    let warnings = |bytes: &[u8], format: Format| {
        let path = PathBuf::from(format!("extra.{format}"));
        MeshFile::parse(bytes.to_vec(), format, &path)
            .unwrap_or_else(|e| panic!("{e}"))
            .read_warnings()
            .to_vec()
    };
    // OBJ normals that are not numbers (exporters write them for faces of
    // no area) are read, and said.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn nan 0 1\nvn 0 inf 1\nf 1//2 2//3 3//1\n";
    let w = warnings(obj.as_bytes(), Format::Obj);
    assert!(
        w.len() == 1 && w[0].contains("`extra.obj`, line 5: 2 normals (`vn`) with a coordinate that is not a finite number (the first is normal 2"),
        "{w:?}"
    );
    let off = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    assert!(warnings(off.as_bytes(), Format::Off).is_empty());
    let w = warnings(
        format!("{off}3 0 2 1\n# end\n\n3 1 2 0\n").as_bytes(),
        Format::Off,
    );
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("`extra.off`, line 7: 2 more lines")
            && w[0].contains("1 faces that line 2 announces"),
        "{w:?}"
    );
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
               element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n1 0\n0 1\n3 0 1 2\n";
    assert!(warnings(ply.as_bytes(), Format::Ply).is_empty());
    let w = warnings(format!("{ply}3 0 2 1\n").as_bytes(), Format::Ply);
    assert!(
        w[0].contains("`extra.ply`, line 13: 1 more line after"),
        "{w:?}"
    );
    let mut binary = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
                       property float y\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        .to_vec();
    for x in [0.0f32, 0.0, 1.0, 0.0, 0.0, 1.0] {
        binary.extend(x.to_le_bytes());
    }
    binary.push(3);
    for i in [0i32, 1, 2] {
        binary.extend(i.to_le_bytes());
    }
    assert!(warnings(&binary, Format::Ply).is_empty());
    binary.extend([0; 7]);
    let w = warnings(&binary, Format::Ply);
    assert!(
        w[0].contains("`extra.ply`: 7 bytes after the elements"),
        "{w:?}"
    );
}
