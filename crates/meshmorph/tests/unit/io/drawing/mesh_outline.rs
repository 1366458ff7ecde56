use meshmorph::io::drawing::regions::signed_area2;
use meshmorph::mesh::Mesh2;

use meshmorph::io::drawing::mesh_outline::*;

#[test]
fn a_ring_mesh_gives_an_outer_loop_and_a_hole() {
    // A square with a square hole, as 8 triangles.
    let p = vec![
        [0.0, 0.0],
        [3.0, 0.0],
        [3.0, 3.0],
        [0.0, 3.0],
        [1.0, 1.0],
        [2.0, 1.0],
        [2.0, 2.0],
        [1.0, 2.0],
    ];
    let t = vec![
        [0, 1, 5],
        [0, 5, 4],
        [1, 2, 6],
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 0, 4],
        [3, 4, 7],
    ];
    let mesh = Mesh2::new(p, t).unwrap();
    let d = drawing_of_mesh(&mesh, "the ring").unwrap();
    assert_eq!(d.num_loops(), 2);
    assert_eq!(d.loops()[0].len(), 4);
    assert!(signed_area2(&d.loops()[0]) > 8.0);
    let two = Mesh2::new(
        vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [5.0, 5.0],
            [6.0, 5.0],
            [5.0, 6.0],
        ],
        vec![[0, 1, 2], [3, 4, 5]],
    )
    .unwrap();
    let m = drawing_of_mesh(&two, "the mesh `two.obj`")
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("the mesh `two.obj` is in 2 separate parts"),
        "{m}"
    );
}
