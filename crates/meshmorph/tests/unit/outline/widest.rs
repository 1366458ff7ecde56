use meshmorph::outline::geometry::orient;

use meshmorph::outline::widest::*;

#[test]
fn a_point_outside_its_star_is_brought_into_its_kernel() {
    // An L-shaped hexagon around one free point, put outside it: only
    // the part of the L near its inner corner sees every side.
    let ring = [
        [0.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 2.0],
        [0.0, 2.0],
    ];
    for start in [[5.0, 5.0], [1.9, 1.9], [-3.0, 0.5]] {
        let mut positions: Vec<[f64; 2]> = ring.to_vec();
        positions.push(start);
        let triangles: Vec<[u32; 3]> = (0..6u32).map(|i| [6, i, (i + 1) % 6]).collect();
        let (at, corners) = triangles_at(7, &triangles);
        let ok = widen(
            &mut positions,
            &triangles,
            &[1.0; 6],
            &[6],
            (&at, &corners),
            3,
        );
        assert!(ok, "from {start:?}: {:?}", positions[6]);
        for t in &triangles {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            assert!(orient(a, b, c) > 0.0);
        }
    }
}

#[test]
fn points_with_no_room_alone_are_given_room_by_their_neighbours() {
    // A strip of free points between two bent rows of held ones,
    // scrambled: the free points untangle only together.
    let width = 8usize;
    let mut positions: Vec<[f64; 2]> = Vec::new();
    for row in 0..3 {
        for i in 0..width {
            let x = i as f64;
            let bend = 0.8 * (x * 0.9).sin();
            positions.push([x, row as f64 + bend]);
        }
    }
    let id = |row: usize, i: usize| (row * width + i) as u32;
    let mut triangles = Vec::new();
    for row in 0..2 {
        for i in 0..width - 1 {
            triangles.push([id(row, i), id(row, i + 1), id(row + 1, i + 1)]);
            triangles.push([id(row, i), id(row + 1, i + 1), id(row + 1, i)]);
        }
    }
    let rest: Vec<f64> = triangles
        .iter()
        .map(|t| {
            0.5 * orient(
                positions[t[0] as usize],
                positions[t[1] as usize],
                positions[t[2] as usize],
            )
        })
        .collect();
    assert!(rest.iter().all(|&a| a > 0.0));
    let free: Vec<usize> = (1..width - 1).map(|i| id(1, i) as usize).collect();
    // Every free point pushed below the lower row, reversed.
    for (k, &v) in free.iter().enumerate() {
        positions[v] = [(width - 2 - k) as f64, -2.0];
    }
    let (at, corners) = triangles_at(positions.len(), &triangles);
    assert!(widen(
        &mut positions,
        &triangles,
        &rest,
        &free,
        (&at, &corners),
        50
    ));
}
