use meshmorph::linalg::vector::{norm, sub};
use meshmorph::mesh::closest::{vertex_normals, ClosestPoint, SurfaceIndex};
use meshmorph::mesh::topology::VertexStar;
use meshmorph::mesh::Mesh3;
use std::collections::HashSet;

use meshmorph::expressions::places::*;

/// A closed mouth: an upper lip's underside facing down at y = 0, a
/// lower lip's top facing up a thousandth below it, both ending at
/// x = 1, and past that the cheek, facing forward, 0.05 in front.
fn lips() -> SurfaceIndex {
    let lip = |y: f64| [[-1.0, y, -1.0], [1.0, y, -1.0], [1.0, y, 3.0]];
    let [a, b, c] = lip(-0.001);
    let cheek = [[1.05, -1.0, 0.05], [2.05, -1.0, 0.05], [1.05, 1.0, 0.05]];
    let corners = [lip(0.0), [a, c, b], cheek];
    let positions: Vec<[f64; 3]> = corners.iter().flatten().copied().collect();
    SurfaceIndex::new(&positions, &[[0, 1, 2], [3, 4, 5], [6, 7, 8]])
}

#[test]
fn a_vertex_takes_the_lip_facing_its_way_but_the_closest_point_at_a_fold() {
    let index = lips();
    let diagonal = 4.0;
    // Nearer the other lip by a hair: the lip facing its way.
    let upper = place_of(&index, [0.9, -0.0006, 0.0], [0.0, -1.0, 0.0], diagonal);
    assert_eq!(upper.triangle, 0);
    let lower = place_of(&index, [0.9, -0.0004, 0.0], [0.0, 1.0, 0.0], diagonal);
    assert_eq!(lower.triangle, 1);
    // At the lips' corner the normal points across the fold (here
    // forward): the cheek faces that way but lies 0.11 away, against
    // 0.0004 for the upper lip.
    let fold = place_of(&index, [0.95, -0.0004, 0.0], [0.0, 0.0, 1.0], diagonal);
    assert_eq!(fold.triangle, 0);
}

/// A grid of `nx × nz` vertices, `at(i, j)` each, its triangles
/// turned so that their normals point along `+y` where the grid is
/// flat.
fn grid(nx: usize, nz: usize, at: impl Fn(usize, usize) -> [f64; 3]) -> Mesh3 {
    let positions = (0..nx)
        .flat_map(|i| (0..nz).map(move |j| (i, j)))
        .map(|(i, j)| at(i, j))
        .collect();
    let v = |i: usize, j: usize| (i * nz + j) as u32;
    let triangles = (0..nx - 1)
        .flat_map(|i| (0..nz - 1).map(move |j| (i, j)))
        .flat_map(|(i, j)| {
            [
                [v(i, j), v(i, j + 1), v(i + 1, j)],
                [v(i + 1, j), v(i, j + 1), v(i + 1, j + 1)],
            ]
        })
        .collect();
    Mesh3::new(positions, triangles).unwrap()
}

/// Two lips 0.1 apart, joined at their corner `x = 1` by a half
/// circle: one sheet folded, each lip's surface facing the other.
fn folded_lips() -> Mesh3 {
    let gap = 0.1;
    let (lip, around) = (2.0, std::f64::consts::PI * gap / 2.0);
    let length = 2.0 * lip + around;
    let steps = 60;
    grid(steps + 1, 11, |i, j| {
        let s = length * i as f64 / steps as f64;
        let z = -0.5 + 0.1 * j as f64;
        if s <= lip {
            [-1.0 + s, 0.0, z]
        } else if s <= lip + around {
            let a = (s - lip) / (gap / 2.0);
            [1.0 + gap / 2.0 * a.sin(), gap / 2.0 * (1.0 - a.cos()), z]
        } else {
            [1.0 - (s - lip - around), gap, z]
        }
    })
}

#[test]
fn a_vertex_that_found_the_other_lip_takes_its_place_from_around_it() {
    let lips = folded_lips();
    let template = Template {
        mesh: &lips,
        index: SurfaceIndex::new(lips.positions(), lips.triangles()),
        smooth: lips.positions(),
        star: VertexStar::new(lips.num_vertices(), lips.triangles()),
    };
    // The lower lip of a head, a hair above the template's, facing up.
    let head = grid(21, 11, |i, j| {
        [-1.0 + 0.09 * i as f64, 0.005, -0.5 + 0.1 * j as f64]
    });
    let normals = vertex_normals(head.positions(), head.triangles());
    let diagonal = head.bounding_box_diagonal();
    let lower = |hit: &ClosestPoint| hit.point[1] < 0.05;
    let mut hits: Vec<ClosestPoint> = head
        .positions()
        .iter()
        .zip(&normals)
        .map(|(&p, &n)| place_of(&template.index, p, n, diagonal))
        .collect();
    assert!(hits.iter().all(lower));
    let star = VertexStar::new(head.num_vertices(), head.triangles());
    assert!(cut_edges(&template, &star, head.positions(), &hits).is_empty());

    // One vertex in the middle finds the upper lip, 0.095 away in
    // space, 2 along the template around the corner.
    let wrong = 10 * 11 + 5;
    let above = [hits[wrong].point[0], 0.2, hits[wrong].point[2]];
    hits[wrong] = template.index.closest(above).unwrap();
    assert!(!lower(&hits[wrong]));
    let cut = cut_edges(&template, &star, head.positions(), &hits);
    assert_eq!(cut.len(), 6, "{cut:?}");
    let found = islands(&star, head.num_vertices(), &cut);
    assert_eq!(found, HashSet::from([wrong as u32]));
    retake_islands(
        &template,
        &star,
        head.positions(),
        &normals,
        diagonal,
        &found,
        &mut hits,
    );
    assert!(lower(&hits[wrong]), "{:?}", hits[wrong]);
    let p = head.positions()[wrong];
    assert!(norm(sub(hits[wrong].point, [p[0], 0.0, p[2]])) < 1e-9);
}

#[test]
fn a_mesh_onto_itself_has_no_cut_edges_and_each_vertex_its_own_place() {
    let lips = folded_lips();
    let found = find_places(&lips, lips.positions(), &lips);
    assert!(found.cut.is_empty());
    for (v, place) in found.places.iter().enumerate() {
        let tri = lips.triangles()[place.triangle as usize];
        let k = tri.iter().position(|&c| c as usize == v).unwrap();
        assert!((place.weights[k] - 1.0).abs() < 1e-9, "{v}: {place:?}");
    }
}
