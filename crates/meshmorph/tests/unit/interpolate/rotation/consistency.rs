use meshmorph::mesh::topology::TriangleAdjacency;

use meshmorph::interpolate::rotation::consistency::*;
use meshmorph::interpolate::rotation::planar::nearest_branch;
use std::f64::consts::PI;

#[test]
fn unwraps_a_chain_of_triangles() {
    // A chain 0-1-2-...-9 whose true angles grow by 0.4π per step.
    let tris: Vec<[u32; 3]> = (0..10).map(|i| [i, i + 1, i + 2]).collect();
    let adj = TriangleAdjacency::new(&tris);
    let truth: Vec<f64> = (0..10).map(|i| 0.4 * PI * i as f64).collect();
    let mut a: Vec<f64> = truth.iter().map(|&x| nearest_branch(x, 0.0)).collect();
    make_consistent(&mut a, &adj, &[0], |&a, &r| nearest_branch(a, r));
    for (x, y) in a.iter().zip(&truth) {
        assert!((x - y).abs() < 1e-12, "{a:?}");
    }
}
