use meshmorph::io::drawing::regions::*;

fn square(x: f64, y: f64, s: f64, ccw: bool) -> Vec<[f64; 2]> {
    let mut v = vec![[x, y], [x + s, y], [x + s, y + s], [x, y + s]];
    if !ccw {
        v.reverse();
    }
    v
}

fn filled(element: usize, points: Vec<[f64; 2]>) -> FilledLoop {
    FilledLoop { element, points }
}

#[test]
fn fill_rules_tell_holes() {
    // Two loops the same way round: a hole under even-odd, fill on both
    // sides of the inner one under non-zero.
    let same = [
        filled(0, square(0.0, 0.0, 10.0, true)),
        filled(0, square(2.0, 2.0, 2.0, true)),
    ];
    let one_hole = vec![Region {
        outer: 0,
        holes: vec![1],
    }];
    assert_eq!(regions(&same, &[Rule::EvenOdd]), one_hole);
    assert_eq!(
        regions(&same, &[Rule::NonZero]),
        vec![Region {
            outer: 0,
            holes: vec![]
        }]
    );
    let opposite = [
        filled(0, square(0.0, 0.0, 10.0, true)),
        filled(0, square(2.0, 2.0, 2.0, false)),
    ];
    assert_eq!(regions(&opposite, &[Rule::NonZero]), one_hole);
    // An island in a hole is a second region.
    let island = [
        filled(0, square(0.0, 0.0, 10.0, true)),
        filled(0, square(2.0, 2.0, 6.0, true)),
        filled(0, square(4.0, 4.0, 2.0, true)),
    ];
    assert_eq!(regions(&island, &[Rule::EvenOdd]).len(), 2);
    // Separate paths never make holes in each other.
    let apart = [
        filled(0, square(0.0, 0.0, 10.0, true)),
        filled(1, square(2.0, 2.0, 2.0, true)),
    ];
    assert_eq!(regions(&apart, &[Rule::EvenOdd, Rule::EvenOdd]).len(), 2);
}

#[test]
fn loops_touching_at_a_vertex_are_told_apart() {
    // A figure eight drawn as one path: two diamonds the same way round
    // that share the vertex each starts at. Two regions under either
    // rule, neither taken for a loop within the other's fill.
    let right = vec![
        [100.0, 100.0],
        [150.0, 150.0],
        [190.0, 100.0],
        [150.0, 50.0],
    ];
    let left = vec![[100.0, 100.0], [50.0, 50.0], [10.0, 100.0], [50.0, 150.0]];
    let eight = [filled(0, right.clone()), filled(0, left)];
    for rule in [Rule::NonZero, Rule::EvenOdd] {
        assert_eq!(regions(&eight, &[rule]).len(), 2, "{rule:?}");
    }
    // A hole starting at a vertex of its outer loop is still its hole.
    let mut hole = square(120.0, 90.0, 20.0, true);
    hole[0] = [150.0, 50.0];
    let found = regions(&[filled(0, right), filled(0, hole)], &[Rule::NonZero]);
    assert_eq!(
        found,
        vec![Region {
            outer: 0,
            holes: vec![1]
        }]
    );
}
