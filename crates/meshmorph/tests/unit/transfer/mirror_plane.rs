use meshmorph::linalg::vector::{dot, sub};
use meshmorph::mesh::Mesh3;

use meshmorph::linalg::vector::norm;
use meshmorph::mesh::shapes::{bend, octahedron, rigid_motion3, tube, twist};
use meshmorph::transfer::mirror_plane::*;

/// A tube that widens along x and curves up in y: the mirror image of
/// itself about z = 0 alone.
fn one_plane() -> Mesh3 {
    widened_and_curved(tube(4.0, 0.5, 17, 12))
}

fn widened_and_curved(t: Mesh3) -> Mesh3 {
    let p = t
        .positions()
        .iter()
        .map(|&[x, y, z]| {
            let u = x / 4.0;
            [x, y * (1.0 + 0.5 * u) + 0.8 * u * u, z * (1.0 + 0.3 * u)]
        })
        .collect();
    t.with_positions(p).unwrap()
}

#[test]
fn a_shape_with_one_mirror_plane_gets_it_wherever_it_stands() {
    let mesh = one_plane();
    let plane = mirror_plane(&mesh).expect("one mirror plane");
    assert!(plane.normal[2].abs() > 1.0 - 1e-12, "{plane:?}");
    assert!(
        plane.offset.abs() < 1e-12 && plane.misfit < 1e-12,
        "{plane:?}"
    );
    // Turned, scaled and moved: the plane is turned, scaled and moved.
    let (a, b) = (0.7f64, -1.2f64);
    let turn = meshmorph::linalg::matrix::mul(
        [
            [a.cos(), -a.sin(), 0.0],
            [a.sin(), a.cos(), 0.0],
            [0.0, 0.0, 1.0],
        ],
        [
            [1.0, 0.0, 0.0],
            [0.0, b.cos(), -b.sin()],
            [0.0, b.sin(), b.cos()],
        ],
    );
    let scaled = turn.map(|row| row.map(|r| 3.5 * r));
    let moved = rigid_motion3(&mesh, scaled, [10.0, -4.0, 2.5]);
    let there = mirror_plane(&moved).expect("one mirror plane");
    let expected = meshmorph::linalg::matrix::mul_vec(&turn, [0.0, 0.0, 1.0]);
    assert!(dot(there.normal, expected).abs() > 1.0 - 1e-12, "{there:?}");
    for &p in moved.positions().iter().step_by(7) {
        let image = there.mirror(p);
        let nearest = moved
            .positions()
            .iter()
            .map(|&q| norm(sub(q, image)))
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 1e-9 * moved.bounding_box_diagonal());
    }
}

#[test]
fn a_coarse_body_with_caps_split_from_one_corner_gets_its_plane() {
    // Eight vertices a ring: each ring is also its own mirror image
    // between its vertices, but the curved body only about z = 0. Each
    // cap is an octagon split into a fan from a corner off that plane,
    // as exporters split n-gons.
    let t = widened_and_curved(tube(4.0, 0.5, 9, 8));
    let (rings, segments) = (9u32, 8u32);
    let fan = |first: u32, flip: bool| {
        (1..segments - 1).map(move |k| {
            let (b, c) = (first + (1 + k) % segments, first + (2 + k) % segments);
            if flip {
                [first + 1, c, b]
            } else {
                [first + 1, b, c]
            }
        })
    };
    let mut triangles: Vec<[u32; 3]> = t
        .triangles()
        .iter()
        .filter(|tri| tri.iter().all(|&v| v < rings * segments))
        .copied()
        .collect();
    triangles.extend(fan(0, true));
    triangles.extend(fan((rings - 1) * segments, false));
    let positions = t.positions()[..(rings * segments) as usize].to_vec();
    let mesh = Mesh3::new(positions, triangles).unwrap();
    let plane = mirror_plane(&mesh).expect("one mirror plane");
    assert!(plane.normal[2].abs() > 1.0 - 1e-12, "{plane:?}");
    assert!(plane.misfit < 1e-12, "{plane:?}");
}

#[test]
fn shapes_with_no_mirror_plane_or_several_get_none() {
    // A straight tube: the plane across its middle and every plane
    // through its axis at a ring vertex.
    assert_eq!(mirror_plane(&tube(4.0, 0.5, 17, 12)), None);
    // Bent evenly: the bend's plane and the plane across its middle.
    assert_eq!(mirror_plane(&bend(&tube(4.0, 0.5, 17, 12), 4.0, 1.0)), None);
    // A regular octahedron: nine.
    assert_eq!(mirror_plane(&octahedron([1.0, 2.0, 3.0], 0.5)), None);
    // Twisted and bent unevenly: none.
    let twisted = twist(&one_plane(), 4.0, 0.8);
    assert_eq!(mirror_plane(&twisted), None);
}
