use meshmorph::mesh::seams::*;
use meshmorph::mesh::Mesh3;

/// Two triangles sharing an edge, the second with its own copies of
/// the shared corners (a seam).
fn split_square() -> Mesh3 {
    Mesh3::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        vec![[0, 1, 2], [3, 4, 5]],
    )
    .unwrap()
}

#[test]
fn copies_weld_and_unweld() {
    let mesh = split_square();
    let seams = Seams::find(&[&mesh]);
    assert_eq!(seams.num_welded(), 2);
    let welded = seams.weld(&mesh);
    assert_eq!(welded.num_vertices(), 4);
    assert_eq!(welded.triangles(), &[[0, 1, 2], [1, 3, 2]]);
    assert_eq!(seams.unweld(welded.positions()), mesh.positions());
    assert_eq!(seams.welded(5), 2);
}

#[test]
fn copies_apart_in_another_mesh_stay_apart() {
    let mesh = split_square();
    let mut moved = mesh.positions().to_vec();
    moved[3][2] = 0.5;
    let moved = mesh.with_positions(moved).unwrap();
    // One corner of the seam left: the two triangles only touch there.
    let seams = Seams::find(&[&mesh, &moved]);
    assert!(seams.is_empty());
    assert_eq!(seams.num_apart(moved.positions()), 0);
    let alone = Seams::find(&[&mesh]);
    assert_eq!(alone.num_apart(moved.positions()), 1);
    assert_eq!(alone.weld_positions(moved.positions())[1], [1.0, 0.0, 0.25]);
}

#[test]
fn a_triangle_never_loses_a_corner() {
    // A zero-area triangle whose two corners coincide: no weld.
    let mesh = Mesh3::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap();
    let seams = Seams::find(&[&mesh]);
    assert!(seams.is_empty());
    assert_eq!(seams.weld(&mesh), mesh);
}

#[test]
fn parts_that_touch_at_a_point_stay_apart() {
    // Two triangles meeting at one corner only.
    let mesh = Mesh3::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
        ],
        vec![[0, 1, 2], [3, 4, 5]],
    )
    .unwrap();
    assert!(Seams::find(&[&mesh]).is_empty());
}

#[test]
fn front_and_back_faces_stay_apart() {
    // A double-sided square: the back's own vertices behind the front's.
    let front = split_square();
    let mut p = front.positions().to_vec();
    p.extend_from_within(..);
    let mut t = front.triangles().to_vec();
    t.extend(
        front
            .triangles()
            .iter()
            .map(|&[a, b, c]| [a + 6, c + 6, b + 6]),
    );
    let sheet = Mesh3::new(p, t).unwrap();
    // Front and back are not welded together (and here the copies
    // along the seam, coincident with the back's, stay apart too).
    let seams = Seams::find(&[&sheet]);
    for v in 0..6 {
        assert_ne!(seams.welded(v + 6), seams.welded(v), "vertex {v}");
    }
}

#[test]
fn minus_zero_is_zero() {
    let mut mesh = split_square().positions().to_vec();
    mesh[3] = [1.0, -0.0, 0.0];
    let mesh = Mesh3::new(mesh, vec![[0, 1, 2], [3, 4, 5]]).unwrap();
    assert_eq!(Seams::find(&[&mesh]).num_welded(), 2);
}
