use meshmorph::io::triangulate::Polygons;
use meshmorph::linalg::vector::{norm, sub};

use meshmorph::io::normal_groups::*;

#[test]
fn authored_normals_turn_with_a_rigid_motion_of_any_shape() {
    // A pyramid's fan of four triangles about its apex, every corner at
    // the apex naming normal 0, which leans off the fan's mean normal
    // (as a weighted or custom normal does); the base corners name 1.
    let mut faces = Polygons::default();
    for k in 0..4u32 {
        faces.push(&[4, k, (k + 1) % 4], 1);
    }
    let corner_normal: Vec<u32> = (0..4).flat_map(|_| [0, 1, 1]).collect();
    let rest = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.1, 0.2, 0.8],
    ];
    let lean = 1.0 / (0.3_f64 * 0.3 + 1.0).sqrt();
    let normals = [[0.3 * lean, 0.0, lean], [0.0, 0.0, 1.0]];
    let groups = NormalGroups::new(&faces, &corner_normal, &[], &rest);
    // The file's own shape gives back the file's normals, exactly.
    assert_eq!(groups.for_shape(&normals, &faces, &rest).normals, normals);
    // A shape that stretches and bends the fan, and the same shape
    // turned: its normals are the first one's, turned.
    let bent = rest.map(|p| [1.3 * p[0], p[1] + 0.2 * p[0] * p[0], p[2] + 0.1 * p[1]]);
    let (c, s) = (0.28, 0.96);
    let turn = |p: [f64; 3]| [c * p[0] - s * p[2], p[1], s * p[0] + c * p[2]];
    let here = groups.for_shape(&normals, &faces, &bent);
    let there = groups.for_shape(&normals, &faces, &bent.map(turn));
    for (a, b) in here.normals.iter().zip(&there.normals) {
        assert!(
            norm(sub(turn(*a), *b)) < 1e-12,
            "{:?} against {b:?}",
            turn(*a)
        );
    }
}

#[test]
fn a_double_sided_sheet_keeps_its_normals() {
    // One triangle listed in both windings, its corners naming the
    // normals 0, 1 and 2.
    let mut faces = Polygons::default();
    faces.push(&[0, 1, 2], 1);
    faces.push(&[1, 0, 2], 2);
    let corner_normal = [0, 1, 2, 1, 0, 2];
    let rest = [[0.1, 0.2, 0.3], [1.3, 0.7, 0.11], [0.37, 1.9, 0.5]];
    let normals = [[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, -1.0, 0.0]];
    let groups = NormalGroups::new(&faces, &corner_normal, &[], &rest);
    // Rounding-sized changes of the shape choose no direction.
    let moved = rest.map(|p| p.map(|x| x * (1.0 + 3e-14)));
    let got = groups.for_shape(&normals, &faces, &moved);
    assert_eq!(got.normals, normals);
    assert!(got.added.is_empty());
    // A turn of the whole sheet turns its normals with it.
    let (c, s) = (0.6, 0.8);
    let turn = |p: [f64; 3]| [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]];
    let got = groups.for_shape(&normals, &faces, &rest.map(turn));
    for (got, want) in got.normals.iter().zip(normals.map(turn)) {
        assert!(norm(sub(*got, want)) < 1e-12, "{got:?} against {want:?}");
    }
}
