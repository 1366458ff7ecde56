use rstar::primitives::GeomWithData;
use rstar::RTree;

use meshmorph::mesh::nearest_vertices::*;

#[test]
fn a_ring_around_the_point_is_taken_whole() {
    // 16 vertices on a circle about the point, one nearer, one farther;
    // single-precision rounding on the circle's.
    let mut items: Vec<GeomWithData<[f64; 3], u32>> = (0..16)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 16.0;
            let p = [3.5, 0.6 * a.cos(), 0.6 * a.sin()].map(|x| f64::from(x as f32));
            GeomWithData::new(p, k)
        })
        .collect();
    items.push(GeomWithData::new([3.5, 0.1, 0.0], 16));
    items.push(GeomWithData::new([3.5, 0.9, 0.0], 17));
    let tree = RTree::bulk_load(items);
    let mut got = nearest_with_ties(&tree, [3.5, 0.0, 0.0], 4, 64, |_| true);
    got.sort_unstable();
    assert_eq!(got, (0..17).collect::<Vec<u32>>());
    // Without the nearest one, the ring alone; filtered, what is kept.
    let got = nearest_with_ties(&tree, [3.5, 0.0, 0.0], 4, 64, |v| v != 16);
    assert_eq!(got.len(), 16);
    let got = nearest_with_ties(&tree, [3.5, 0.0, 0.0], 2, 64, |v| v >= 16);
    assert_eq!(got, vec![16, 17]);
    // A tie is finished past the search: 4 asked among the 5 nearest.
    let got = nearest_with_ties(&tree, [3.5, 0.0, 0.0], 4, 5, |v| v != 16);
    assert_eq!(got.len(), 16);
}
