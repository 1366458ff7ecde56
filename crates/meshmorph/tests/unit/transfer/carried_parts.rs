use meshmorph::linalg::vector::add;

use meshmorph::mesh::shapes::tube;
use meshmorph::mesh::topology::connected_components;
use meshmorph::transfer::carried_parts::*;

#[test]
fn a_paired_part_in_the_body_follows_it_and_one_standing_apart_does_not() {
    // A body, an eye inside it, a smaller body beside it (a gap of a
    // tenth of its size) and another farther than its own size (each
    // triangle weighs 1: the first body, with the most triangles, is
    // the main part).
    let parts = [
        (tube(4.0, 0.5, 9, 8), [0.0, 0.0, 0.0]),
        (tube(0.3, 0.06, 3, 6), [3.5, 0.1, 0.0]),
        (tube(4.0, 0.5, 5, 8), [0.0, 1.4, 0.0]),
        (tube(4.0, 0.5, 5, 8), [0.0, 9.0, 0.0]),
    ];
    let (mut positions, mut triangles) = (Vec::new(), Vec::new());
    for (mesh, at) in &parts {
        let n = positions.len() as u32;
        positions.extend(mesh.positions().iter().map(|p| add(*p, *at)));
        triangles.extend(mesh.triangles().iter().map(|t| t.map(|v| v + n)));
    }
    let components = connected_components(positions.len(), &triangles);
    let area = vec![1.0; triangles.len()];
    let found = CarriedParts::new(
        &positions,
        &components,
        &vec![true; triangles.len()],
        &area,
        &[],
    );
    assert!(found.is_empty());
    let following: Vec<u32> = found.following().iter().map(|f| f.component).collect();
    assert_eq!(following, vec![1, 2]);
    // The eye's anchors are the body's vertices around its end.
    let eye = &found.following()[0];
    assert!(eye.anchors.iter().all(|&a| {
        let p = positions[a as usize];
        components.of_vertex[a as usize] == Some(0) && p[0] > 2.5
    }));
    // A part held by a pin is neither carried nor following.
    let held = [false, true, false, false];
    let found = CarriedParts::new(
        &positions,
        &components,
        &vec![true; triangles.len()],
        &area,
        &held,
    );
    let following: Vec<u32> = found.following().iter().map(|f| f.component).collect();
    assert_eq!(following, vec![2]);
}
