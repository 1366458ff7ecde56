use meshmorph::mesh::bvh::*;

/// A deterministic scatter of points in the unit cube.
fn points(n: usize) -> Vec<[f64; 3]> {
    let mut s: u64 = 0x9e3779b97f4a7c15;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n).map(|_| [next(), next(), next()]).collect()
}

fn d2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum()
}

#[test]
fn nearest_accepted_item_matches_brute_force() {
    let items = points(1000);
    let bvh = Bvh::new(
        items.iter().copied().enumerate().collect::<Vec<_>>(),
        |(_, p)| Aabb::around([*p]),
        |&(i, _)| i,
    );
    for (k, q) in points(300).into_iter().enumerate() {
        let max2 = [0.001, 0.01, 1.0, 10.0][k % 4];
        // Only items of one parity count.
        let accept = |i: usize| i % 2 == k % 2;
        let expected = items
            .iter()
            .enumerate()
            .filter(|&(i, p)| accept(i) && d2(*p, q) <= max2)
            .min_by(|a, b| d2(*a.1, q).total_cmp(&d2(*b.1, q)).then(a.0.cmp(&b.0)))
            .map(|(i, _)| i as u32);
        let found = bvh.nearest(q, max2, |(i, _)| accept(*i), |(_, p)| d2(*p, q));
        assert_eq!(found.map(|f| f.0), expected, "query {k}");
        if let Some((i, item, d)) = found {
            assert_eq!(item.0, i as usize);
            assert_eq!(d, d2(items[i as usize], q));
        }
    }
}

#[test]
fn piles_at_one_place_keep_one_item_per_key_and_answer_as_before() {
    // One triangle repeated: one item kept.
    let pile = vec![[0.25; 3]; 3000];
    let bvh = Bvh::new(pile, |p| Aabb::around([*p]), |p| p.map(f64::to_bits));
    assert_eq!((bvh.items.len(), bvh.index.as_slice()), (1, &[0][..]));
    // 3000 items at 3 places, with 2 keys at each: the piles shrink to
    // their 6 keys, with a few more where a split falls between piles.
    let places = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let items: Vec<(usize, [f64; 3])> = (0..3000).map(|i| (i % 6, places[i % 3])).collect();
    let bvh = Bvh::new(items.clone(), |(_, p)| Aabb::around([*p]), |&(k, _)| k);
    assert!(bvh.items.len() < 100, "{} items kept", bvh.items.len());
    for (k, q) in points(200).into_iter().enumerate() {
        let accept = |key: usize| key % 2 == k % 2;
        let expected = items
            .iter()
            .enumerate()
            .filter(|&(_, (key, _))| accept(*key))
            .min_by(|a, b| d2(a.1 .1, q).total_cmp(&d2(b.1 .1, q)).then(a.0.cmp(&b.0)))
            .map(|(i, _)| i as u32);
        let found = bvh.nearest(q, 10.0, |(key, _)| accept(*key), |(_, p)| d2(*p, q));
        assert_eq!(found.map(|f| f.0), expected, "query {k}");
    }
    // Distinct keys at one place are all kept, and the first wins.
    let pile: Vec<(usize, [f64; 3])> = (0..5000).map(|i| (i, [0.5; 3])).collect();
    let bvh = Bvh::new(pile, |(_, p)| Aabb::around([*p]), |&(k, _)| k);
    assert_eq!(bvh.items.len(), 5000);
    let found = bvh.nearest(
        [0.0; 3],
        10.0,
        |&(k, _)| k >= 4000,
        |(_, p)| d2(*p, [0.0; 3]),
    );
    assert_eq!(found.map(|f| f.0), Some(4000));
}

#[test]
fn ties_go_to_the_first_item_and_empty_trees_find_nothing() {
    let same = vec![[1.0, 2.0, 3.0]; 40];
    let bvh = Bvh::new(same, |p| Aabb::around([*p]), |_| ());
    let found = bvh.nearest([0.0; 3], 100.0, |_| true, |p| d2(*p, [0.0; 3]));
    assert_eq!(found.map(|f| f.0), Some(0));
    let empty: Bvh<[f64; 3]> = Bvh::new(Vec::new(), |p| Aabb::around([*p]), |_| ());
    assert!(empty.nearest([0.0; 3], 1.0, |_| true, |_| 0.0).is_none());
}
