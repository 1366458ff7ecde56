//! Reading and writing STL, ASCII and binary: corners welded into vertices,
//! files written back as they were with new positions.

use std::path::Path;

use meshmorph::io::{parse_mesh, write_positions, Format, MeshFile};
use meshmorph::{shapes, Error, Mesh3};

/// A closed tube's corners in `float`, so that binary STL holds them
/// exactly.
fn tube() -> Mesh3 {
    let t = shapes::tube(3.0, 0.5, 7, 9);
    let rounded: Vec<[f64; 3]> = t
        .positions()
        .iter()
        .map(|p| p.map(|x| f64::from(x as f32)))
        .collect();
    t.with_positions(rounded).unwrap()
}

fn normal(m: &Mesh3, t: usize) -> [f64; 3] {
    let [a, b, c] = m.corners(t);
    let (u, v) = (
        [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
        [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
    );
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    n.map(|x| x / len)
}

/// Binary STL of `m` with `header` (80 bytes, padded with spaces).
fn binary(m: &Mesh3, header: &[u8]) -> Vec<u8> {
    let mut out = header.to_vec();
    out.resize(80, b' ');
    out.extend_from_slice(&(m.num_triangles() as u32).to_le_bytes());
    for t in 0..m.num_triangles() {
        for p in std::iter::once(normal(m, t)).chain(m.corners(t)) {
            for x in p {
                out.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

/// ASCII STL of `m`, as CAD tools write it (`%e` numbers).
fn ascii(m: &Mesh3) -> String {
    let mut s = String::from("solid tube\n");
    for t in 0..m.num_triangles() {
        let n = normal(m, t);
        s += &format!(
            "  facet normal {:e} {:e} {:e}\n    outer loop\n",
            n[0], n[1], n[2]
        );
        for p in m.corners(t) {
            s += &format!("      vertex {:e} {:e} {:e}\n", p[0], p[1], p[2]);
        }
        s += "    endloop\n  endfacet\n";
    }
    s + "endsolid tube\n"
}

fn parse(bytes: &[u8]) -> meshmorph::Result<Mesh3> {
    parse_mesh(bytes, Format::Stl, Path::new("fixture.stl"))
}

/// The same surface: the same triangles at the same corners (the vertices
/// numbered in the order their points first occur).
#[track_caller]
fn assert_same(read: &Mesh3, m: &Mesh3) {
    assert_eq!(read.num_vertices(), m.num_vertices());
    assert_eq!(read.num_triangles(), m.num_triangles());
    for t in 0..m.num_triangles() {
        assert_eq!(read.corners(t), m.corners(t), "triangle {t}");
    }
}

#[test]
fn ascii_and_binary_stl_weld_their_corners_into_the_mesh() {
    let m = tube();
    assert_same(&parse(&binary(&m, b"made by a tool")).unwrap(), &m);
    assert_same(&parse(ascii(&m).as_bytes()).unwrap(), &m);
    // A binary file whose header starts with `solid`, as many exporters
    // write it, is binary: its size says so.
    assert_same(&parse(&binary(&m, b"solid tube")).unwrap(), &m);
    // Two solids in one file: two parts.
    let two = ascii(&m) + &ascii(&m).replace("vertex ", "vertex 1");
    let read = parse(two.as_bytes()).unwrap();
    assert_eq!(read.num_triangles(), 2 * m.num_triangles());
}

#[test]
fn stl_written_back_keeps_the_file_with_new_positions() {
    let dir = tempfile::tempdir().unwrap();
    let m = tube();
    let mut bytes = binary(&m, b"solid-looking header kept as it is");
    // An attribute (a colour, in some tools) on the first facet.
    bytes[84 + 48] = 0x1f;
    let input = dir.path().join("in.stl");
    std::fs::write(&input, &bytes).unwrap();
    let file = MeshFile::read(&input).unwrap();
    assert_eq!(file.format(), Format::Stl);

    // The file's own positions: the same bytes.
    let same = dir.path().join("same.stl");
    assert!(file
        .write(&same, file.mesh().positions(), Format::Stl)
        .unwrap()
        .is_empty());
    assert_eq!(std::fs::read(&same).unwrap(), bytes);

    // Moved and turned: each corner at its new place, each normal turned,
    // the header and attribute kept.
    // (Vertices are numbered in the order their points first occur.)
    let welded = file.mesh().clone();
    let turned: Vec<[f64; 3]> = welded
        .positions()
        .iter()
        .map(|p| [-p[1] + 2.0, p[0], p[2]])
        .collect();
    let out = dir.path().join("turned.stl");
    file.write(&out, &turned, Format::Stl).unwrap();
    let written = std::fs::read(&out).unwrap();
    assert_eq!(written.len(), bytes.len());
    assert_eq!(written[..84], bytes[..84]);
    assert_eq!(written[84 + 48], 0x1f);
    let read = parse(&written).unwrap();
    let expected = welded.with_positions(turned.clone()).unwrap();
    for t in 0..m.num_triangles() {
        for (a, b) in read.corners(t).iter().zip(expected.corners(t)) {
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() < 1e-6, "triangle {t}: {a:?} {b:?}");
            }
        }
        let at = 84 + 50 * t;
        let stored: Vec<f64> = (0..3)
            .map(|k| {
                let b = &written[at + 4 * k..at + 4 * k + 4];
                f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            })
            .collect();
        let n = normal(&expected, t);
        for k in 0..3 {
            assert!(
                (stored[k] - n[k]).abs() < 1e-5,
                "normal of facet {t}: {stored:?} {n:?}"
            );
        }
    }

    // ASCII: the same statements, new numbers.
    let input = dir.path().join("in-ascii.stl");
    std::fs::write(&input, ascii(&m)).unwrap();
    let file = MeshFile::read(&input).unwrap();
    let out = dir.path().join("turned-ascii.stl");
    file.write(&out, &turned, Format::Stl).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("solid tube\n  facet normal "));
    assert!(text.ends_with("endsolid tube\n"));
    assert_eq!(text.lines().count(), ascii(&m).lines().count());
    let read = parse(text.as_bytes()).unwrap();
    for t in 0..m.num_triangles() {
        assert_eq!(read.corners(t), expected.corners(t), "triangle {t}");
    }
}

#[test]
fn other_formats_write_binary_stl_and_what_it_cannot_hold_is_said() {
    let dir = tempfile::tempdir().unwrap();
    let m = tube();
    let path = dir.path().join("tube.stl");
    write_positions(&path, m.positions(), m.triangles(), Format::Stl).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(bytes.len(), 84 + 50 * m.num_triangles());
    assert!(!bytes.starts_with(b"solid"));
    assert_same(&parse(&bytes).unwrap(), &m);

    // An OBJ with texture coordinates written as STL: the positions and
    // triangles, and a warning for the coordinates.
    let obj = dir.path().join("quad.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n",
    )
    .unwrap();
    let file = MeshFile::read(&obj).unwrap();
    let out = dir.path().join("quad.stl");
    let warnings = file
        .write(&out, file.mesh().positions(), Format::Stl)
        .unwrap();
    assert!(
        warnings.iter().any(|w| w.contains("texture coordinates")),
        "{warnings:?}"
    );
    let read = parse(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(read.num_triangles(), 2);
}

#[test]
fn broken_stl_files_are_refused_naming_what_is_wrong() {
    let m = tube();
    let message = |bytes: &[u8]| {
        let e = parse(bytes).expect_err("should not parse");
        assert!(matches!(e, Error::Parse { .. }), "{e:?}");
        let msg = e.to_string();
        assert!(msg.contains("fixture.stl"), "{msg}");
        msg
    };
    // Cut short.
    let bytes = binary(&m, b"x");
    let msg = message(&bytes[..bytes.len() - 7]);
    assert!(
        msg.contains(&format!("announces {} facets", m.num_triangles())),
        "{msg}"
    );
    assert!(message(&bytes[..40]).contains("84-byte header"));
    let text = ascii(&m);
    let cut = &text[..text.len() / 2];
    let cut = &cut[..cut.rfind("endfacet").unwrap() + 9];
    assert!(message(cut.as_bytes()).contains("without `endsolid`"));
    // Not a number, not finite.
    let msg = message(text.replacen("vertex ", "vertex x", 1).as_bytes());
    assert!(msg.contains("line 4") && msg.contains("`x"), "{msg}");
    let msg = message(text.replacen("vertex ", "vertex nan ", 1).as_bytes());
    assert!(msg.contains("line 4"), "{msg}");
    let mut nan = bytes.clone();
    nan[84 + 12..84 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
    let msg = message(&nan);
    assert!(msg.contains("facet 1") && msg.contains("corner 1"), "{msg}");
    // A facet with two corners at one point.
    let mut flat = bytes.clone();
    let second: Vec<u8> = flat[84 + 24..84 + 36].to_vec();
    flat[84 + 36..84 + 48].copy_from_slice(&second);
    let msg = message(&flat);
    assert!(
        msg.contains("facet 1") && msg.contains("corners 2 and 3 are the same point"),
        "{msg}"
    );
    // A statement out of place.
    let msg = message(text.replacen("outer loop", "loop", 1).as_bytes());
    assert!(msg.contains("expected `outer`"), "{msg}");
    // No facets.
    assert!(message(b"solid empty\nendsolid empty\n").contains("no facets"));
}

#[test]
fn stl_as_other_tools_write_it_byte_order_marks_upper_case_and_solid_headers() {
    let m = tube();
    // A byte-order mark; keywords in capitals.
    let text = ascii(&m);
    assert_same(&parse(format!("\u{feff}{text}").as_bytes()).unwrap(), &m);
    assert_same(&parse(text.to_uppercase().as_bytes()).unwrap(), &m);
    // A normal that is not a number, as old exporters wrote them.
    let odd = text.replacen("facet normal ", "facet normal -1.#IND00e+000 ", 1);
    let odd = odd.replacen(
        &odd[odd.find("-1.#IND").unwrap()..odd.find("\n    outer").unwrap()],
        "-1.#IND00e+000 0 1",
        1,
    );
    assert_same(&parse(odd.as_bytes()).unwrap(), &m);
    // A binary file with a `solid` header cut short is told as binary.
    let bytes = binary(&m, b"solid exported");
    let e = parse(&bytes[..bytes.len() - 10]).unwrap_err().to_string();
    assert!(e.contains("announces") && e.contains("bytes"), "{e}");
}

#[test]
fn what_single_precision_cannot_hold_is_refused_when_written() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.stl");
    let tri = [[0u32, 1, 2]];
    // Beyond the range of `float`.
    let e = write_positions(
        &path,
        &[[0.0, 0.0, 0.0], [1e39, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &tri,
        Format::Stl,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("out.stl") && e.contains("vertex 2") && e.contains("range"),
        "{e}"
    );
    // Two corners one point once rounded.
    let e = write_positions(
        &path,
        &[[1.0, 0.0, 0.0], [1.00000001, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &tri,
        Format::Stl,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("corners 1 and 2 of facet 1") && e.contains("fall on one point"),
        "{e}"
    );
    assert!(!path.exists());
    // Into a binary STL kept whole, the same.
    let input = dir.path().join("in.stl");
    std::fs::write(&input, binary(&tube(), b"x")).unwrap();
    let file = MeshFile::read(&input).unwrap();
    let mut huge = file.mesh().positions().to_vec();
    huge[0][1] = 1e39;
    assert!(file.write(&path, &huge, Format::Stl).is_err());
    assert!(!path.exists());
}

#[test]
fn a_pose_that_numbers_its_points_otherwise_is_refused_saying_why() {
    let dir = tempfile::tempdir().unwrap();
    let m = tube();
    let reference = dir.path().join("ref.stl");
    std::fs::write(&reference, binary(&m, b"x")).unwrap();
    let file = MeshFile::read(&reference).unwrap();
    // The same shape, its first facet listed from its second corner: its
    // points first occur in another order, so its vertices are numbered
    // otherwise.
    let mut rotated = m.triangles().to_vec();
    rotated[0] = [rotated[0][1], rotated[0][2], rotated[0][0]];
    let pose = dir.path().join("pose.stl");
    std::fs::write(
        &pose,
        binary(&Mesh3::new(m.positions().to_vec(), rotated).unwrap(), b"x"),
    )
    .unwrap();
    let e = file.read_pose(&pose).unwrap_err().to_string();
    assert!(
        e.contains("pose.stl") && e.contains("STL has no vertex indices"),
        "{e}"
    );
    // Listed as the reference lists them: a pose.
    let same = dir.path().join("same.stl");
    std::fs::write(&same, binary(&m, b"y")).unwrap();
    assert!(file.read_pose(&same).is_ok());
}
