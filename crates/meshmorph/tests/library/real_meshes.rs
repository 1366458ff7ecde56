//! Transfer on the meshes people have: polygon files kept whole, poses as
//! new positions for the reference's faces, sources that are not aligned
//! with the target, parts without partners.

use std::path::Path;

use meshmorph::io::{Format, MeshFile};
use meshmorph::shapes::{bend, nearest_vertex_pairs, tube};
use meshmorph::{
    correspond, CorrespondOptions, CorrespondResult, Correspondence, Error, Markers, Mesh3,
    Transfer, VertexNumbering,
};

type P3 = [f64; 3];

fn file(text: &str, name: &str) -> MeshFile {
    let format = Format::from_path(Path::new(name)).unwrap();
    MeshFile::parse(text.as_bytes().to_vec(), format, Path::new(name))
        .unwrap_or_else(|e| panic!("{e}"))
}

/// A bumpy grid of `n × n` quads in OBJ, with texture coordinates, normals,
/// groups, materials and comments; `lift` moves every vertex up by a
/// function of its place, so that the quads' best diagonals change.
fn quad_grid_obj(n: usize, lift: impl Fn(usize, usize) -> f64) -> String {
    sheared_grid_obj(n, 0.0, lift)
}

/// [`quad_grid_obj`] with x sheared by `shear` times y.
fn sheared_grid_obj(n: usize, shear: f64, lift: impl Fn(usize, usize) -> f64) -> String {
    let mut s = String::from("# a grid of quads\nmtllib grid.mtl\no grid\n");
    for j in 0..=n {
        for i in 0..=n {
            let z = lift(i, j);
            let (x, y) = (i as f64 * 0.5, j as f64 * 0.25);
            s += &format!("v {} {y} {z}\n", x + shear * y);
        }
    }
    for j in 0..=n {
        for i in 0..=n {
            s += &format!("vt {} {}\n", i as f64 / n as f64, j as f64 / n as f64);
        }
    }
    s += "vn 0 0 1\n";
    s += "g top\nusemtl skin\ns 1\n";
    let at = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            let c = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
            s += "f";
            for v in c {
                s += &format!(" {v}/{v}/1");
            }
            s += "\n";
        }
    }
    s += "# end\n";
    s
}

#[test]
fn poses_of_a_quad_mesh_use_the_references_split() {
    let reference = file(&quad_grid_obj(6, |_, _| 0.0), "ref.obj");
    // A shear makes the other diagonal the shorter one.
    let lifted = file(&sheared_grid_obj(6, 1.5, |_, _| 0.0), "pose.obj");
    assert_ne!(
        lifted.mesh().triangles(),
        reference.mesh().triangles(),
        "the pose alone would split its quads otherwise"
    );
    let (pose, reordered) = reference.pose(&lifted).unwrap();
    assert_eq!(reordered, 0);
    assert_eq!(pose.triangles(), reference.mesh().triangles());
    assert_eq!(pose.positions(), lifted.mesh().positions());
    assert_eq!(reference.num_faces(), 36);
    assert_eq!(reference.mesh().num_triangles(), 72);
    let uvs = reference
        .triangle_corner_uvs()
        .expect("every corner has a vt");
    assert_eq!(uvs.len(), 72);
    for (t, tri) in reference.mesh().triangles().iter().enumerate() {
        for k in 0..3 {
            let p = reference.mesh().positions()[tri[k] as usize];
            // (The rest grid: x = 0.5 i, y = 0.25 j, uv = (i, j) / 6.)
            assert!((f64::from(uvs[t][k][0]) - p[0] / 3.0).abs() < 1e-6);
            assert!((f64::from(uvs[t][k][1]) - p[1] / 1.5).abs() < 1e-6);
        }
    }
}

#[test]
fn rewound_faces_are_the_same_faces_and_other_faces_are_named() {
    let text = quad_grid_obj(3, |_, _| 0.0);
    let reference = file(&text, "ref.obj");
    // Face 2 listed backwards, face 4 from another corner.
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let faces: Vec<usize> = (0..lines.len())
        .filter(|&k| lines[k].starts_with("f "))
        .collect();
    let rewind = |line: &str, how: fn(&mut Vec<&str>)| {
        let mut c: Vec<&str> = line.split_whitespace().skip(1).collect();
        how(&mut c);
        format!("f {}", c.join(" "))
    };
    lines[faces[2]] = rewind(&lines[faces[2]], |c| c.reverse());
    lines[faces[4]] = rewind(&lines[faces[4]], |c| c.rotate_left(1));
    let pose = file(&(lines.join("\n") + "\n"), "rewound.obj");
    let (mesh, reordered) = reference.pose(&pose).unwrap();
    assert_eq!(reordered, 2);
    assert_eq!(mesh.triangles(), reference.mesh().triangles());

    // A face with another corner: refused, naming the file, face and line.
    let mut bad = lines.clone();
    bad[faces[5]] = "f 1 2 3 4".into();
    let e = reference
        .pose(&file(&(bad.join("\n") + "\n"), "other.obj"))
        .unwrap_err();
    let msg = e.to_string();
    assert!(
        matches!(e, Error::FaceMismatch { face: 5, line: Some(l), .. } if l == faces[5] + 1),
        "{e:?}"
    );
    assert!(
        msg.contains("other.obj")
            && msg.contains("face 6")
            && msg.contains(&format!("line {}", faces[5] + 1)),
        "{msg}"
    );
    // Another vertex count: refused.
    let e = reference
        .pose(&file("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "small.obj"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("small.obj") && e.contains("3 vertices"), "{e}");
}

/// `MeshFile::read_pose` gives what reading the file whole and fitting it
/// with `MeshFile::pose` gives: the same mesh and count, or the same error,
/// whatever the pose's format and whatever is wrong with it.
#[test]
fn reading_a_pose_is_reading_it_whole_then_fitting_it() {
    let text = quad_grid_obj(4, |i, j| 0.05 * (i * j) as f64);
    let reference = file(&text, "ref.obj");
    let dir = tempfile::tempdir().unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let faces: Vec<usize> = (0..lines.len())
        .filter(|&k| lines[k].starts_with("f "))
        .collect();
    let with = |k: usize, line: &str| {
        let mut l = lines.clone();
        l[k] = line;
        l.join("\n") + "\n"
    };
    let rewound = {
        let mut c: Vec<&str> = lines[faces[3]].split_whitespace().skip(1).collect();
        c.reverse();
        format!("f {}", c.join(" "))
    };
    let without_last_face: Vec<&str> = lines
        .iter()
        .enumerate()
        .filter(|&(k, _)| k != faces[faces.len() - 1])
        .map(|(_, l)| *l)
        .collect();
    let without_faces: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| !l.starts_with("f "))
        .collect();
    let mut cases: Vec<(&str, String)> = vec![
        ("same.obj", text.clone()),
        ("rewound.obj", with(faces[3], &rewound)),
        ("other.obj", with(faces[2], "f 1 2 3 4")),
        ("fewer.obj", without_last_face.join("\n") + "\n"),
        ("no-faces.obj", without_faces.join("\n") + "\n"),
        ("small.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".into()),
        ("bad-number.obj", with(4, "v 0 zero 0")),
    ];
    // The reference's positions turned, written as PLY and OFF: poses in
    // other formats.
    let turned: Vec<P3> = reference
        .mesh()
        .positions()
        .iter()
        .map(|p| [p[0], -p[2], p[1]])
        .collect();
    for name in ["turned.ply", "turned.off"] {
        let format = Format::from_path(Path::new(name)).unwrap();
        reference
            .write(&dir.path().join(name), &turned, format)
            .unwrap();
    }
    cases.push(("turned.ply", String::new()));
    cases.push(("turned.off", String::new()));
    for (name, contents) in &cases {
        let path = dir.path().join(name);
        if !contents.is_empty() {
            std::fs::write(&path, contents).unwrap();
        }
        let whole = MeshFile::read(&path).and_then(|p| reference.pose(&p));
        let read = reference.read_pose(&path);
        match (whole, read) {
            (Ok((a, n)), Ok((b, m))) => {
                assert_eq!(n, m, "{name}");
                assert_eq!(a.triangles(), b.triangles(), "{name}");
                let bits = |m: &Mesh3| -> Vec<[u64; 3]> {
                    m.positions().iter().map(|p| p.map(f64::to_bits)).collect()
                };
                assert_eq!(bits(&a), bits(&b), "{name}");
            }
            (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{name}"),
            (a, b) => panic!("{name}: {:?} against {:?}", a.err(), b.err()),
        }
    }
}

/// The file with its numbers read as numbers, its other tokens as text.
fn tokens(text: &str) -> Vec<Vec<Result<f64, String>>> {
    text.lines()
        .map(|l| {
            l.split_whitespace()
                .map(|t| t.parse::<f64>().map_err(|_| t.to_string()))
                .collect()
        })
        .collect()
}

#[test]
fn a_reference_transferred_onto_itself_writes_back_its_own_file() {
    let text = quad_grid_obj(5, |i, j| 0.1 * (i as f64).sin() * (j as f64).cos());
    let reference = file(&text, "ref.obj");
    let mesh = reference.mesh();
    let transfer = Transfer::new(
        mesh,
        mesh,
        &Correspondence::identity(mesh),
        &Default::default(),
    )
    .unwrap();
    let out = transfer.apply(mesh).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.obj");
    let dropped = reference.write(&path, &out, Format::Obj).unwrap();
    assert!(dropped.is_empty(), "{dropped:?}");
    let written = std::fs::read_to_string(&path).unwrap();
    let (a, b) = (tokens(&text), tokens(&written));
    assert_eq!(a.len(), b.len());
    for (la, lb) in a.iter().zip(&b) {
        assert_eq!(la.len(), lb.len(), "{la:?} / {lb:?}");
        for (x, y) in la.iter().zip(lb) {
            match (x, y) {
                (Ok(x), Ok(y)) => assert!((x - y).abs() < 1e-9, "{x} / {y}"),
                _ => assert_eq!(x, y),
            }
        }
    }
    // In another format the polygons stay, with what it can hold, and the
    // rest is named as dropped.
    let ply = dir.path().join("out.ply");
    let dropped = reference.write(&ply, &out, Format::Ply).unwrap();
    let all = dropped.join("\n");
    for what in ["groups", "materials"] {
        assert!(all.contains(what), "{what} not in {all}");
    }
    assert!(!all.contains("texture coordinates"), "{all}");
    let back = MeshFile::read(&ply).unwrap();
    assert_eq!(back.num_faces(), 25);
    assert_eq!(back.triangle_corner_uvs(), reference.triangle_corner_uvs());
    assert_eq!(back.has_normals(), !all.contains("normals"));
}

#[test]
fn ply_and_off_files_keep_their_other_data() {
    let ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
               property float z\nproperty uchar red\nproperty float nx\nproperty float ny\nproperty float nz\n\
               element face 1\nproperty list uchar int vertex_indices\nproperty uchar flags\n\
               element extra 1\nproperty int id\nend_header\n\
               0 0 0 255 0 0 1\n1 0 0 128 0 0 1\n1 1 0 7 0 0 1\n0 1 0 9 0 0 1\n4 0 1 2 3 5\n42\n";
    let f = file(ply, "quad.ply");
    assert_eq!(f.num_faces(), 1);
    assert!(f.has_normals());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("turned.ply");
    // Turned a quarter turn about x: positions and normals turn, the rest stays.
    let turned: Vec<P3> = f
        .mesh()
        .positions()
        .iter()
        .map(|p| [p[0], -p[2], p[1]])
        .collect();
    f.write(&path, &turned, Format::Ply).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let body: Vec<&str> = text
        .lines()
        .skip_while(|l| *l != "end_header")
        .skip(1)
        .collect();
    assert_eq!(body[2], "1 -0 1 7 0 -1 0", "{text}");
    assert_eq!(body[4], "4 0 1 2 3 5");
    assert_eq!(body[5], "42");

    let off =
        "COFF\n4 1 0\n0 0 0 1 0 0\n1 0 0 0 1 0\n1 1 0 0 0 1\n0 1 0 1 1 1\n4 0 1 2 3 0.5 0.5 0.5\n";
    let f = file(off, "quad.off");
    let path = dir.path().join("moved.off");
    let moved: Vec<P3> = f
        .mesh()
        .positions()
        .iter()
        .map(|p| [p[0] + 1.0, p[1], p[2]])
        .collect();
    f.write(&path, &moved, Format::Off).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(
        text,
        "COFF\n4 1 0\n1 0 0 1 0 0\n2 0 0 0 1 0\n2 1 0 0 0 1\n1 1 0 1 1 1\n4 0 1 2 3 0.5 0.5 0.5\n"
    );
}

fn turn_scale_move(p: P3) -> P3 {
    let (c, s) = (0.6_f64, 0.8_f64);
    let q = [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]];
    let (c, s) = (0.28_f64, 0.96_f64);
    let q = [q[0], c * q[1] - s * q[2], s * q[1] + c * q[2]];
    [7.5 * q[0] + 3.0, 7.5 * q[1] - 20.0, 7.5 * q[2] + 0.5]
}

/// A uniform scale by 7.5 and a translation.
fn scale_move(p: P3) -> P3 {
    [7.5 * p[0] + 3.0, 7.5 * p[1] - 20.0, 7.5 * p[2] + 0.5]
}

/// [`turn_scale_move`] without the scale: a rigid motion.
fn turn_move(p: P3) -> P3 {
    let q = turn_scale_move(p);
    [
        (q[0] - 3.0) / 7.5 + 3.0,
        (q[1] + 20.0) / 7.5 - 20.0,
        (q[2] - 0.5) / 7.5 + 0.5,
    ]
}

fn mapped(m: &Mesh3, f: impl Fn(P3) -> P3) -> Mesh3 {
    m.with_positions(m.positions().iter().map(|&p| f(p)).collect())
        .unwrap()
}

/// The correspondence of `source` and `target` (default options), and the
/// transfer through it.
fn set_up(source: &Mesh3, target: &Mesh3, markers: &Markers) -> (CorrespondResult, Transfer) {
    let found = correspond(source, target, markers, &CorrespondOptions::default()).unwrap();
    let transfer =
        Transfer::new(source, target, &found.correspondence, &Default::default()).unwrap();
    (found, transfer)
}

/// The correspondence of `source` and `target` (default options), and
/// `pose` transferred through it.
fn transferred(
    source: &Mesh3,
    target: &Mesh3,
    markers: &Markers,
    pose: &Mesh3,
) -> (CorrespondResult, Vec<P3>) {
    let (found, transfer) = set_up(source, target, markers);
    (found, transfer.apply(pose).unwrap())
}

/// How far the transfer of `pose` (`here`) moves when the source and the
/// pose are turned, scaled and moved together ([`turn_scale_move`]): the
/// largest distance between a result vertex and itself.
fn moved_with_the_source(
    source: &Mesh3,
    target: &Mesh3,
    markers: &Markers,
    pose: &Mesh3,
    here: &[P3],
) -> f64 {
    let (_, elsewhere) = transferred(
        &mapped(source, turn_scale_move),
        target,
        markers,
        &mapped(pose, turn_scale_move),
    );
    here.iter()
        .zip(&elsewhere)
        .map(|(p, q)| (0..3).map(|i| (p[i] - q[i]).powi(2)).sum::<f64>().sqrt())
        .fold(0.0, f64::max)
}

#[test]
fn moving_turning_and_scaling_the_source_changes_nothing() {
    let thin = tube(4.0, 0.25, 17, 12);
    let thick = tube(4.0, 0.5, 11, 16);
    let widened: Vec<P3> = thin
        .positions()
        .iter()
        .map(|p| [p[0], 2.0 * p[1], 2.0 * p[2]])
        .collect();
    let ends = [0, 3, 6, 9, 96, 99, 102, 105, 192, 195, 198, 201];
    let markers = Markers::new(nearest_vertex_pairs(&widened, thick.positions(), &ends));
    let pose = bend(&thin, 4.0, 1.0);
    let (_, here) = transferred(&thin, &thick, &markers, &pose);
    let worst = moved_with_the_source(&thin, &thick, &markers, &pose, &here);
    assert!(
        worst < 1e-8 * thick.bounding_box_diagonal(),
        "moved by {worst}"
    );
}

/// A tube along x that widens and curves up: its own mirror image about
/// z = 0 alone. `bump` raises a patch on its z > 0 side, which leaves the
/// plane but tilts the normals' fit of the turn.
fn symmetric_body(radius: f64, bump: f64) -> Mesh3 {
    mapped(&tube(4.0, radius, 17, 12), |[x, y, z]| {
        let u = x / 4.0;
        let hump = bump * (-((x - 2.0) / 0.4).powi(2)).exp() * (z / radius).max(0.0);
        [
            x,
            y * (1.0 + 0.5 * u) + 0.8 * u * u,
            z * (1.0 + 0.3 * u) + hump,
        ]
    })
}

#[test]
fn symmetric_characters_keep_their_planes_together_wherever_the_source_stands() {
    let source = symmetric_body(0.25, 0.0);
    let target = symmetric_body(0.5, 0.08);
    let ends = [0, 3, 6, 9, 96, 99, 102, 105, 192, 195, 198, 201];
    let markers = tube_pair(&source, &target, &ends);
    let pose = bend(&source, 4.0, 1.0);
    let (found, here) = transferred(&source, &target, &markers, &pose);
    let [from, to] = found.mirror_planes.expect("both have one plane");
    assert!(to.normal[2].abs() > 0.9999, "{to:?}");
    assert!(from.misfit < 1e-9, "{from:?}");
    // The transfer's turn (its rotation after the markers') brings the
    // source's plane, as the markers placed it, onto the target's.
    let (all, markers_only) = (
        found.correspondence.alignment().rotation,
        found.marker_fit.rotation,
    );
    let unturned: P3 =
        std::array::from_fn(|j| (0..3).map(|i| markers_only[i][j] * from.normal[i]).sum());
    let turned: P3 = std::array::from_fn(|i| (0..3).map(|j| all[i][j] * unturned[j]).sum());
    let along: f64 = (0..3).map(|i| turned[i] * to.normal[i]).sum();
    assert!(along.abs() > 1.0 - 1e-12, "planes {along} apart");
    let worst = moved_with_the_source(&source, &target, &markers, &pose, &here);
    assert!(
        worst < 1e-8 * target.bounding_box_diagonal(),
        "moved by {worst}"
    );
}

/// Both references (and the pose) scaled by 7.5 and moved: the source
/// deformed onto the target, and the result, are the first ones scaled and
/// moved alike. The target is a little wider than the source, so the
/// closest-point rounds pull the whole surface (a term measured in the
/// meshes' own units would pull 56 times harder after the scale). Not
/// turned: the fractions of the target's bounding-box diagonal that set
/// the cut-offs and thresholds follow its axis-aligned box.
#[test]
fn scaling_both_references_scales_the_result_and_changes_nothing_else() {
    let source = tube(4.0, 0.25, 17, 12);
    let target = tube(4.0, 0.28, 11, 16);
    let widened: Vec<P3> = source
        .positions()
        .iter()
        .map(|p| [p[0], 1.12 * p[1], 1.12 * p[2]])
        .collect();
    let ends = [0, 3, 6, 9, 96, 99, 102, 105, 192, 195, 198, 201];
    let markers = Markers::new(nearest_vertex_pairs(&widened, target.positions(), &ends));
    let pose = bend(&source, 4.0, 1.0);
    let run = |source: &Mesh3, target: &Mesh3, pose: &Mesh3| {
        let (found, out) = transferred(source, target, &markers, pose);
        (found.deformed_source.positions().to_vec(), out)
    };
    let here = run(&source, &target, &pose);
    let elsewhere = run(
        &mapped(&source, scale_move),
        &mapped(&target, scale_move),
        &mapped(&pose, scale_move),
    );
    let diagonal = 7.5 * target.bounding_box_diagonal();
    for (what, a, b) in [
        ("the deformed source", &here.0, &elsewhere.0),
        ("the result", &here.1, &elsewhere.1),
    ] {
        let worst = a
            .iter()
            .zip(b)
            .map(|(&p, q)| distance(scale_move(p), *q))
            .fold(0.0, f64::max);
        assert!(worst < 1e-8 * diagonal, "{what} off by {worst}");
    }
}

#[test]
fn markers_that_cannot_fix_a_similarity_are_refused() {
    let thin = tube(4.0, 0.25, 17, 12);
    let thick = tube(4.0, 0.5, 11, 16);
    // Three markers on one line along the tube.
    let markers = Markers::new(vec![[0, 0], [48, 30], [96, 64]]);
    let e = correspond(&thin, &thick, &markers, &CorrespondOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("on one line"), "{e}");
}

#[test]
fn marker_points_snap_to_the_surface_and_far_points_are_refused() {
    let thin = tube(4.0, 0.25, 17, 12);
    let thick = tube(4.0, 0.5, 11, 16);
    // Out from the axis by 1e-3 (thin) and 2e-3 (thick): the nearest point
    // of the surface is the vertex.
    let nudge = |p: P3| [p[0], p[1] * 1.004, p[2] * 1.004];
    let points = vec![
        [nudge(thin.positions()[5]), nudge(thick.positions()[7])],
        [thin.positions()[100], thick.positions()[90]],
    ];
    let (snapped, snap) = Markers::from_points(points).snap(&thin, &thick).unwrap();
    assert_eq!(
        snapped.pairs(),
        Markers::new(vec![[5, 7], [100, 90]]).pairs()
    );
    assert!((snap.largest_source - 1e-3 / thin.bounding_box_diagonal()).abs() < 1e-9);
    assert!((snap.largest_target - 2e-3 / thick.bounding_box_diagonal()).abs() < 1e-9);
    let text = "0 0 0 0 0 0\n5 5 5 0 0 0\n";
    let m = Markers::parse(text, Path::new("picks.txt"), VertexNumbering::FromZero).unwrap();
    let e = m.snap(&thin, &thick).unwrap_err().to_string();
    assert!(
        e.contains("picks.txt")
            && e.contains("line 2")
            && e.contains("source point 5 5 5")
            && e.contains("from the source mesh's surface"),
        "{e}"
    );
}

/// Two meshes as one (indices of the second shifted).
fn union(a: &Mesh3, b: &Mesh3) -> Mesh3 {
    let mut p = a.positions().to_vec();
    p.extend_from_slice(b.positions());
    let n = a.num_vertices() as u32;
    let mut t = a.triangles().to_vec();
    t.extend(b.triangles().iter().map(|tri| tri.map(|v| v + n)));
    Mesh3::new(p, t).unwrap()
}

fn distance(a: P3, b: P3) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

/// The rigid motion (rotation and translation, no scale) that best takes
/// `from[vertices]` to `to[vertices]`, applied to `p`.
fn rigid_fit(from: &[P3], to: &[P3], vertices: std::ops::Range<usize>) -> impl Fn(P3) -> P3 {
    let fit = meshmorph::Similarity::fit(&from[vertices.clone()], &to[vertices]).unwrap();
    move |p| {
        let q = fit.rotate(p);
        [
            q[0] * fit.scale + fit.translation[0],
            q[1] * fit.scale + fit.translation[1],
            q[2] * fit.scale + fit.translation[2],
        ]
    }
}

/// A source tube and its markers onto a target tube of twice the radius.
fn tube_pair(source: &Mesh3, target: &Mesh3, ends: &[u32]) -> Markers {
    let widened: Vec<P3> = source
        .positions()
        .iter()
        .map(|p| [p[0], 2.0 * p[1], 2.0 * p[2]])
        .collect();
    Markers::new(nearest_vertex_pairs(&widened, target.positions(), ends))
}

#[test]
fn eyes_and_teeth_inside_a_head_stay_in_place() {
    let thin = tube(4.0, 0.25, 17, 12);
    let head = tube(4.0, 0.5, 11, 16);
    // Two "eyes" and a row of "teeth": thin closed tubes on the axis, far
    // from the surface, with no partner on the source.
    let eye = |x: f64| {
        mapped(&tube(0.3, 0.06, 3, 6), move |p| {
            [p[0] + x, p[1] + 0.1, p[2]]
        })
    };
    let teeth = mapped(&tube(0.8, 0.05, 4, 6), |p| [p[0] + 0.3, p[1] - 0.1, p[2]]);
    let parts = union(&union(&eye(3.0), &eye(3.5)), &teeth);
    let target = union(&head, &parts);
    let inner = head.num_vertices()..target.num_vertices();
    let markers = tube_pair(
        &thin,
        &head,
        &[0, 3, 6, 9, 96, 99, 102, 105, 192, 195, 198, 201],
    );
    let (_, transfer) = set_up(&thin, &target, &markers);
    assert_eq!(transfer.carried_parts(), 3);
    let diagonal = target.bounding_box_diagonal();
    // A rigid turn: the parts stay where they were relative to the head.
    let out = transfer.apply(&mapped(&thin, turn_move)).unwrap();
    let head_motion = rigid_fit(target.positions(), &out, 0..head.num_vertices());
    for v in inner.clone() {
        let d = distance(out[v], head_motion(target.positions()[v]));
        assert!(d < 1e-3 * diagonal, "vertex {v}: {d} off the head's motion");
    }
    // A bend ("the jaw opens" at one end): the parts keep their shape and
    // stay next to the surface around them.
    let out = transfer.apply(&bend(&thin, 4.0, 1.2)).unwrap();
    let nearest_head = |p: P3, q: &[P3]| {
        (0..head.num_vertices())
            .map(|h| distance(p, q[h]))
            .fold(f64::INFINITY, f64::min)
    };
    for v in inner.clone().step_by(5) {
        let rest = nearest_head(target.positions()[v], target.positions());
        let now = nearest_head(out[v], &out);
        assert!(
            (now - rest).abs() < 0.5 * rest,
            "vertex {v}: {rest} from the head at rest, {now} bent"
        );
    }
    for (a, b) in [
        (inner.start, inner.start + 7),
        (inner.end - 1, inner.end - 9),
    ] {
        let d = distance(out[a], out[b]) - distance(target.positions()[a], target.positions()[b]);
        assert!(d.abs() < 1e-9, "a part stretched by {d}");
    }
}

/// How far the vertices `part` of `out` lie from where the rigid motion
/// that best takes the `around` vertices of `rest` to `out` puts them.
fn off_the_motion_around(rest: &[P3], out: &[P3], around: &[usize], part: &[usize]) -> f64 {
    let (from, to): (Vec<P3>, Vec<P3>) = around.iter().map(|&v| (rest[v], out[v])).unzip();
    let motion = rigid_fit(&from, &to, 0..around.len());
    part.iter()
        .map(|&v| distance(out[v], motion(rest[v])))
        .fold(0.0, f64::max)
}

#[test]
fn a_paired_eye_follows_the_head_its_own_shape_puts_elsewhere() {
    // The source and the target both have an "eye" inside the far end of a
    // tube, paired with each other. The target's far half is twice as long,
    // so when the tube bends its head ends up elsewhere than the source's:
    // the eye must stay in the target's head, not follow the source's eye.
    let body = tube(4.0, 0.25, 17, 12);
    let eye = tube(0.3, 0.06, 3, 6);
    // (The source's eye a little off the plane z = 0: on it, its closest
    // points on the target's eye tie between mirror-image triangles, and
    // the rounding of where the source stands would pick one.)
    let source = union(
        &body,
        &mapped(&eye, |p| [p[0] + 3.4, p[1] + 0.1, p[2] + 0.03]),
    );
    let longer = |x: f64| if x < 2.0 { x } else { 2.0 + 3.0 * (x - 2.0) };
    let target = union(
        &mapped(&body, |p| [longer(p[0]), p[1], p[2]]),
        &mapped(&eye, |p| [p[0] + longer(3.4), p[1] + 0.1, p[2]]),
    );
    let rings: Vec<u32> = (0..=16)
        .step_by(4)
        .flat_map(|r| [0, 3, 6, 9].map(|s| 12 * r + s))
        .collect();
    let markers = Markers::new(rings.iter().map(|&v| [v, v]).collect());
    let (_, transfer) = set_up(&source, &target, &markers);
    assert_eq!(transfer.carried_parts(), 0, "the eye has its partner");
    assert_eq!(transfer.following_parts(), 1);
    let rest = target.positions();
    let eye_vertices: Vec<usize> = (body.num_vertices()..target.num_vertices()).collect();
    let head: Vec<usize> = (0..body.num_vertices())
        .filter(|&v| (rest[v][0] - longer(3.55)).abs() < 0.8)
        .collect();
    let diagonal = target.bounding_box_diagonal();
    // A rigid turn moves the eye with the head.
    let out = transfer.apply(&mapped(&source, turn_move)).unwrap();
    let off = off_the_motion_around(rest, &out, &head, &eye_vertices);
    assert!(off < 1e-8 * diagonal, "turned: the eye {off} off the head");
    // A bend: the eye stays in the head around it, wherever the source
    // stands.
    let pose = bend(&source, 4.0, 1.2);
    let out = transfer.apply(&pose).unwrap();
    let moved = moved_with_the_source(&source, &target, &markers, &pose, &out);
    assert!(moved < 1e-8 * diagonal, "moved with the source by {moved}");
    let off = off_the_motion_around(rest, &out, &head, &eye_vertices);
    // (The head itself bends: 1.2e-3 of the diagonal off its own best rigid
    // motion. An eye placed by its partner alone lies 6.3e-3 off.)
    assert!(off < 4e-3 * diagonal, "bent: the eye {off} off the head");
}

#[test]
fn a_source_eye_that_looks_aside_leaves_a_target_without_eyes_at_rest() {
    // The source has an "eye" just under its skin, the target none. The eye turns about its own centre, the head
    // does not move: neither does any of the target.
    let head = tube(4.0, 0.5, 17, 12);
    let eye = |turn: f64| {
        mapped(&tube(0.3, 0.1, 3, 6), move |p| {
            let (x, z) = (p[0] - 0.15, p[2]);
            [
                3.5 + x * turn.cos() - z * turn.sin(),
                p[1] + 0.35,
                x * turn.sin() + z * turn.cos(),
            ]
        })
    };
    let source = union(&head, &eye(0.0));
    // The target the same head, or a finer one (the source's coarse skin
    // then lies farther from much of the target's than the eye does).
    for target in [head.clone(), tube(4.0, 0.5, 33, 24)] {
        let markers = Markers::new(nearest_vertex_pairs(
            head.positions(),
            target.positions(),
            &[0, 3, 6, 9, 96, 99, 102, 105, 192, 195, 198, 201],
        ));
        let (_, out) = transferred(&source, &target, &markers, &union(&head, &eye(0.5)));
        let worst = out
            .iter()
            .zip(target.positions())
            .map(|(&p, &q)| distance(p, q))
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-9 * target.bounding_box_diagonal(),
            "the target moved by {worst}"
        );
    }
}

#[test]
fn a_source_covering_half_the_target_leaves_the_other_half_at_rest() {
    let half = tube(2.0, 0.25, 9, 12);
    let whole = tube(4.0, 0.5, 21, 16);
    let ends: Vec<u32> = [0u32, 3, 6, 9, 96, 99, 102, 105].to_vec();
    let markers = tube_pair(&half, &whole, &ends);
    let found = correspond(&half, &whole, &markers, &CorrespondOptions::default()).unwrap();
    let transfer =
        Transfer::new(&half, &whole, &found.correspondence, &Default::default()).unwrap();
    assert!(transfer.unpaired_triangles() > 0);
    let far: Vec<usize> = (0..whole.num_vertices())
        .filter(|&v| whole.positions()[v][0] > 3.0)
        .collect();
    let rest = whole.positions();
    // A local deformation of the source (a twist of its far end, the end
    // at x = 0 held): the far half keeps its rest shape.
    let twisted = mapped(&half, |p| {
        let a = 0.4 * p[0] / 2.0;
        [
            p[0],
            p[1] * a.cos() - p[2] * a.sin(),
            p[1] * a.sin() + p[2] * a.cos(),
        ]
    });
    let out = transfer.apply(&twisted).unwrap();
    let diagonal = whole.bounding_box_diagonal();
    for &a in far.iter().step_by(7) {
        for &b in far.iter().step_by(11) {
            let d = distance(out[a], out[b]) - distance(rest[a], rest[b]);
            assert!(
                d.abs() < 2e-3 * diagonal,
                "far half stretched by {d} between {a} and {b}"
            );
        }
    }
    // A rigid motion of the source moves the whole target rigidly.
    let out = transfer.apply(&mapped(&half, turn_move)).unwrap();
    let motion = rigid_fit(rest, &out, 0..whole.num_vertices());
    for v in 0..whole.num_vertices() {
        let d = distance(out[v], motion(rest[v]));
        assert!(d < 1e-8 * diagonal, "vertex {v}: {d} off a rigid motion");
    }
}

/// A strip of `n` unit quads along x at z = 0, shaded flat or smooth (`s`),
/// every corner using the one normal `vn 0 0 1`, as exporters write the
/// parallel faces' shared normal once.
fn shared_normal_strip(n: usize, smoothing: &str) -> String {
    let mut s = String::new();
    for i in 0..=n {
        s += &format!("v {i} 0 0\nv {i} 1 0\n");
    }
    s += &format!("vn 0 0 1\ns {smoothing}\n");
    for i in 0..n {
        let (a, b, c, d) = (2 * i + 1, 2 * i + 3, 2 * i + 4, 2 * i + 2);
        s += &format!("f {a}//1 {b}//1 {c}//1 {d}//1\n");
    }
    s
}

/// The strip's vertices folded about the y axis: quad `i` turned by
/// `i · step` radians, each quad still flat.
fn folded_strip(n: usize, step: f64) -> Vec<P3> {
    let mut out = Vec::new();
    let (mut x, mut z) = (0.0, 0.0);
    for i in 0..=n {
        out.push([x, 0.0, z]);
        out.push([x, 1.0, z]);
        let a = i as f64 * step;
        x += a.cos();
        z += a.sin();
    }
    out
}

/// The `vn` lines and, per face, the normal each corner uses, of an OBJ text.
fn normals_by_face(text: &str) -> (Vec<P3>, Vec<Vec<usize>>) {
    let mut normals = Vec::new();
    let mut faces = Vec::new();
    for line in text.lines() {
        let mut t = line.split_whitespace();
        match t.next() {
            Some("vn") => {
                let v: Vec<f64> = t.map(|x| x.parse().unwrap()).collect();
                normals.push([v[0], v[1], v[2]]);
            }
            Some("f") => faces.push(
                t.map(|c| c.rsplit('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect(),
            ),
            _ => {}
        }
    }
    (normals, faces)
}

/// Each vertex's normal as Blender and most modellers compute it: the
/// mean of the normals of the triangles around it, each weighing its angle
/// at the vertex.
fn angle_weighted_normals(mesh: &Mesh3) -> Vec<P3> {
    let p = mesh.positions();
    let mut sums = vec![[0.0; 3]; p.len()];
    let sub = |a: P3, b: P3| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: P3, b: P3| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let norm = |a: P3| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    for t in mesh.triangles() {
        let n = cross(
            sub(p[t[1] as usize], p[t[0] as usize]),
            sub(p[t[2] as usize], p[t[0] as usize]),
        );
        let unit = n.map(|x| x / norm(n));
        for k in 0..3 {
            let at = p[t[k] as usize];
            let (a, b) = (
                sub(p[t[(k + 1) % 3] as usize], at),
                sub(p[t[(k + 2) % 3] as usize], at),
            );
            let angle = norm(cross(a, b)).atan2(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
            for i in 0..3 {
                sums[t[k] as usize][i] += angle * unit[i];
            }
        }
    }
    sums.iter().map(|s| s.map(|x| x / norm(*s))).collect()
}

#[test]
fn normals_computed_from_the_shape_are_computed_again_for_a_new_one() {
    // A bent tube with its vertices' normals as a modeller computes them,
    // written with the straight tube's: the bent shape's normals come out.
    let straight = tube(4.0, 0.5, 9, 7);
    let bent = bend(&straight, 4.0, 1.5);
    let mut text = String::new();
    for q in straight.positions() {
        text += &format!("v {:?} {:?} {:?}\n", q[0], q[1], q[2]);
    }
    for n in angle_weighted_normals(&straight) {
        text += &format!("vn {:?} {:?} {:?}\n", n[0], n[1], n[2]);
    }
    for t in straight.triangles() {
        let [a, b, c] = t.map(|v| v + 1);
        text += &format!("f {a}//{a} {b}//{b} {c}//{c}\n");
    }
    let rest = file(&text, "straight.obj");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bent.obj");
    rest.write(&path, bent.positions(), Format::Obj).unwrap();
    let (normals, _) = normals_by_face(&std::fs::read_to_string(&path).unwrap());
    let want = angle_weighted_normals(&bent);
    assert_eq!(normals.len(), want.len());
    for (v, (n, w)) in normals.iter().zip(&want).enumerate() {
        let d = (0..3).map(|i| (n[i] - w[i]).abs()).fold(0.0, f64::max);
        // The angles are weighed to 1e-7 radian.
        assert!(d < 1e-6, "vertex {v}: {n:?} against {w:?}");
    }
}

#[test]
fn flat_faces_sharing_one_normal_get_their_own_when_they_turn_apart() {
    let n = 4;
    let step = 0.4;
    let dir = tempfile::tempdir().unwrap();
    let flat = file(&shared_normal_strip(n, "off"), "flat.obj");
    let folded = folded_strip(n, step);

    // The file's own shape writes the file back.
    let same = dir.path().join("same.obj");
    flat.write(&same, flat.mesh().positions(), Format::Obj)
        .unwrap();
    assert_eq!(
        std::fs::read_to_string(&same).unwrap(),
        shared_normal_strip(n, "off")
    );

    // Folded, each flat face's corners use its own face normal.
    let path = dir.path().join("folded.obj");
    flat.write(&path, &folded, Format::Obj).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let (normals, faces) = normals_by_face(&text);
    assert_eq!(normals.len(), n, "{text}");
    for (i, corners) in faces.iter().enumerate() {
        let a = i as f64 * step;
        let want = [-a.sin(), 0.0, a.cos()];
        for &c in corners {
            let got = normals[c];
            let d = (0..3).map(|k| (got[k] - want[k]).abs()).fold(0.0, f64::max);
            assert!(d < 1e-12, "face {i}: {got:?} against {want:?}\n{text}");
        }
    }
    // It reads back, with the folded positions.
    let back = MeshFile::read(&path).unwrap();
    assert_eq!(back.mesh().positions(), &folded[..]);

    // Shaded smooth, each vertex takes the mean of its faces' normals,
    // shared by the corners around it.
    let smooth = file(&shared_normal_strip(n, "1"), "smooth.obj");
    let path = dir.path().join("smooth.obj");
    smooth.write(&path, &folded, Format::Obj).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let (normals, faces) = normals_by_face(&text);
    assert_eq!(normals.len(), n + 1, "one per column of vertices\n{text}");
    let face_normal = |i: usize| {
        let a = i as f64 * step;
        [-a.sin(), 0.0, a.cos()]
    };
    for (i, corners) in faces.iter().enumerate() {
        // Corners 0 and 3 lie on the column of the face's start, 1 and 2 on
        // its end.
        for (k, &c) in corners.iter().enumerate() {
            let column = if k == 0 || k == 3 { i } else { i + 1 };
            let around: Vec<usize> = [column.wrapping_sub(1), column]
                .into_iter()
                .filter(|&f| f < n)
                .collect();
            let sum = around.iter().fold([0.0; 3], |s, &f| {
                std::array::from_fn(|j| s[j] + face_normal(f)[j])
            });
            let len = sum.iter().map(|x| x * x).sum::<f64>().sqrt();
            let got = normals[c];
            let d = (0..3)
                .map(|j| (got[j] - sum[j] / len).abs())
                .fold(0.0, f64::max);
            assert!(d < 1e-12, "face {i} corner {k}: {got:?}\n{text}");
        }
    }
}

#[test]
fn parallel_faces_apart_sharing_one_normal_are_told_apart() {
    // Two quads that share no vertex but one `vn` (no `s` statement): one
    // turned a quarter turn, the other not.
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 6 1 0\nv 5 1 0\n\
                vn 0 0 1\nvn 1 0 0\nf 1//1 2//1 3//1 4//1\nf 5//1 6//1 7//1 8//1\n";
    check_two_quads_apart(text);
    // The same with CR LF line ends: the added normal's line ends alike.
    let out = check_two_quads_apart(&text.replace('\n', "\r\n"));
    assert_eq!(
        out.matches('\n').count(),
        out.matches("\r\n").count(),
        "{out:?}"
    );
    assert!(!out.contains("\r\n\r\n"), "{out:?}");
    // Faces first, the normals last, the file without a final line end.
    let faces_first = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 6 1 0\nv 5 1 0\n\
                       f 1//2 2//2 3//2 4//2\nf 5//2 6//2 7//2 8//2\nvn 1 0 0\nvn 0 0 1";
    let f = file(faces_first, "last.obj");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.obj");
    f.write(&path, &turned_second_quad(&f), Format::Obj)
        .unwrap();
    let out = std::fs::read_to_string(&path).unwrap();
    assert!(out.ends_with("vn 0 0 1\nvn 0 -1 0\n"), "{out:?}");
    assert!(!out.contains("\n\n"), "{out:?}");
    let (normals, faces) = normals_by_face(&out);
    assert!(faces[0].iter().all(|&c| c == 1), "{out}");
    assert!(faces[1].iter().all(|&c| c == 2), "{out}");
    assert_eq!(normals[2], [0.0, -1.0, 0.0]);
}

/// The positions of a two-quad file with its second quad (vertices 4 to 7)
/// turned a quarter turn about x.
fn turned_second_quad(f: &MeshFile) -> Vec<P3> {
    f.mesh()
        .positions()
        .iter()
        .enumerate()
        .map(|(v, &p)| if v < 4 { p } else { [p[0], -p[2], p[1]] })
        .collect()
}

/// Writes the two quads of `text` with the second turned; checks the
/// normals and returns the text written.
fn check_two_quads_apart(text: &str) -> String {
    let f = file(text, "two.obj");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.obj");
    f.write(&path, &turned_second_quad(&f), Format::Obj)
        .unwrap();
    let out = std::fs::read_to_string(&path).unwrap();
    let (normals, faces) = normals_by_face(&out);
    // The added normal stands right after its own, so `vn 1 0 0` is now
    // the third and nothing uses it.
    assert_eq!(normals.len(), 3, "{out}");
    assert_eq!(normals[2], [1.0, 0.0, 0.0], "{out}");
    assert!(
        faces[0].iter().all(|&c| normals[c] == [0.0, 0.0, 1.0]),
        "{out}"
    );
    assert!(faces[1].iter().all(|&c| c == 1), "{out}");
    let d = (0..3)
        .map(|k| (normals[1][k] - [0.0, -1.0, 0.0][k]).abs())
        .fold(0.0, f64::max);
    assert!(d < 1e-15, "{out}");
    out
}
