use meshmorph::render::style::*;

#[test]
fn edge_sets_find_the_boundary() {
    // A square split in two: 5 edges, 4 on the boundary.
    let tris = [[0, 1, 2], [0, 2, 3], [0, 1, 9]];
    let e = EdgeSets::new(&tris, 4);
    assert_eq!(e.all.len(), 5);
    assert_eq!(e.boundary.len(), 4);
    assert!(!e.boundary.contains(&[0, 2]));
}

#[test]
fn flip_rules() {
    let p = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
    let tris = [[0, 1, 2], [1, 3, 2], [1, 2, 3]];
    let mut s = Style2d::default();
    assert_eq!(s.flipped_mask(&p, &tris), vec![false, false, true]);
    s.flipped = Flipped::AgainstMajority;
    assert_eq!(s.flipped_mask(&p, &tris), vec![false, false, true]);
    let cw = [[0, 2, 1], [1, 2, 3], [1, 3, 2]];
    assert_eq!(s.flipped_mask(&p, &cw), vec![false, false, true]);
    s.flipped = Flipped::Mask(vec![true]);
    assert_eq!(s.flipped_mask(&p, &tris), vec![true, false, false]);
    s.flipped = Flipped::None;
    assert_eq!(s.flipped_mask(&p, &tris), vec![false; 3]);
}
