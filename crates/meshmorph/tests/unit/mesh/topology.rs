use meshmorph::mesh::topology::*;

#[test]
fn edges_and_adjacency_with_boundary_and_nonmanifold_edge() {
    // Three triangles on edge (0, 1), plus one triangle hanging off (1, 2).
    let tris = [[0, 1, 2], [1, 0, 3], [0, 1, 4], [2, 1, 5]];
    let e = edges(&tris);
    let e01 = e.iter().find(|e| e.vertices == [0, 1]).unwrap();
    assert_eq!(e01.triangles, vec![0, 1, 2]);
    assert_eq!(e.iter().filter(|e| e.triangles.len() == 1).count(), 7);
    let adj = TriangleAdjacency::new(&tris);
    assert_eq!(adj.edge_components(), (vec![0, 0, 0, 0], 1));
    // A bow-tie: two triangles sharing only vertex 0.
    let bow = TriangleAdjacency::new(&[[0, 1, 2], [0, 3, 4]]);
    assert_eq!(bow.edge_components(), (vec![0, 1], 2));
    assert_eq!(adj.of(0), &[1, 2, 3]);
    assert_eq!(adj.of(1), &[0, 2]);
    assert_eq!(adj.of(3), &[0]);
}

/// `n` triangles on the edge (0, 1), each with its own third vertex.
fn book(n: u32) -> Vec<[u32; 3]> {
    (0..n).map(|k| [0, 1, k + 2]).collect()
}

/// Every pair of triangles sharing an edge, by brute force.
fn all_pairs(tris: &[[u32; 3]]) -> Vec<Vec<u32>> {
    let shares_edge = |a: [u32; 3], b: [u32; 3]| a.iter().filter(|v| b.contains(v)).count() >= 2;
    (0..tris.len())
        .map(|t| {
            (0..tris.len() as u32)
                .filter(|&u| u as usize != t && shares_edge(tris[t], tris[u as usize]))
                .collect()
        })
        .collect()
}

#[test]
fn up_to_eight_triangles_on_an_edge_are_all_neighbours() {
    // A strip whose triangles are repeated 1 to 4 times: edges shared
    // by up to 8 triangles.
    let mut tris = Vec::new();
    for i in 0..6u32 {
        for _ in 0..=(i % 4) {
            tris.push([2 * i, 2 * i + 1, 2 * i + 2]);
            tris.push([2 * i + 1, 2 * i + 3, 2 * i + 2]);
        }
    }
    let adj = TriangleAdjacency::new(&tris);
    let expected = all_pairs(&tris);
    for (t, near) in expected.iter().enumerate() {
        assert_eq!(adj.of(t), near.as_slice(), "triangle {t}");
    }
    assert_eq!(
        TriangleAdjacency::from_edges(tris.len(), &edges(&tris)),
        adj
    );
    for n in 1..=ALL_PAIRS_UP_TO as u32 {
        let b = book(n);
        assert_eq!(
            TriangleAdjacency::new(&b).neighbors.len(),
            (n * (n - 1)) as usize
        );
    }
}

#[test]
fn many_triangles_on_one_edge_stay_linear() {
    let n = 10_000;
    let repeated = vec![[0, 1, 2]; n as usize];
    // A book of n pages, and one of n pages each printed twice.
    let twice: Vec<[u32; 3]> = book(n).into_iter().flat_map(|t| [t, t]).collect();
    for tris in [book(n), repeated, twice] {
        let t = tris.len();
        let adj = TriangleAdjacency::new(&tris);
        // Past eight on an edge, each triangle meets the one before and
        // the one after it: a chain, connected, no triangle with more
        // than two neighbours per edge.
        assert!(
            adj.neighbors.len() <= 6 * t,
            "{} pairs",
            adj.neighbors.len()
        );
        assert!((0..t).all(|k| adj.of(k).len() <= 6));
        assert_eq!(adj.edge_components().1, 1);
        assert_eq!(TriangleAdjacency::from_edges(t, &edges(&tris)), adj);
        let pairs: usize = edges(&tris)
            .iter()
            .map(|e| linked_pairs(&e.triangles).count())
            .sum();
        assert!(pairs <= 3 * t, "{pairs} smoothness pairs");
    }
    let fan = TriangleAdjacency::new(&book(n));
    assert_eq!(fan.of(0), &[1]);
    assert_eq!(fan.of(5), &[4, 6]);
}

#[test]
fn linked_pairs_are_all_pairs_then_a_chain() {
    let pairs: Vec<_> = linked_pairs(&[3, 5, 9]).collect();
    assert_eq!(pairs, [(3, 5), (3, 9), (5, 9)]);
    let many: Vec<u32> = (0..ALL_PAIRS_UP_TO as u32 + 1).collect();
    let chain: Vec<_> = linked_pairs(&many).collect();
    assert_eq!(
        chain,
        (0..ALL_PAIRS_UP_TO as u32)
            .map(|k| (k, k + 1))
            .collect::<Vec<_>>()
    );
    assert_eq!(linked_pairs(&[7]).count(), 0);
}

#[test]
fn components() {
    let tris = [[0, 1, 2], [5, 6, 7], [2, 3, 0], [7, 8, 5]];
    let c = connected_components(10, &tris);
    assert_eq!(c.count, 2);
    assert_eq!(c.of_triangle, vec![0, 1, 0, 1]);
    assert_eq!(c.of_vertex[4], None);
    assert_eq!(c.of_vertex[8], Some(1));
}
