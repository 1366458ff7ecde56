use meshmorph::outline::untie::*;

/// A fan of `n` triangles round a centre point: a disk whose outline
/// is the `n` points of a circle of radius 10.
fn disk(n: usize) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut p = vec![[0.0, 0.0]];
    p.extend((0..n).map(|k| {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        [10.0 * a.cos(), 10.0 * a.sin()]
    }));
    let t = (0..n as u32)
        .map(|k| [0, 1 + k, 1 + (k + 1) % n as u32])
        .collect();
    (p, t)
}

#[test]
fn a_simple_outline_is_kept_to_the_bit() {
    let (p, t) = disk(40);
    let untier = OutlineUntier::new(&t).unwrap();
    let mut frame = p.clone();
    assert_eq!(untier.untie(&mut frame), 0);
    assert_eq!(frame, p);
}

#[test]
fn a_knot_of_a_few_points_is_laid_straight_and_nothing_else_moves() {
    for (knot_at, size) in [(5usize, 4usize), (38, 5), (0, 3)] {
        let (p, t) = disk(40);
        let untier = OutlineUntier::new(&t).unwrap();
        let mut frame = p.clone();
        // Points knot_at + 1 ..= knot_at + size (vertices one more)
        // tied into a bow a fraction of an edge across at knot_at: the
        // third comes back across the first's edge.
        let n = 40;
        let base = p[1 + knot_at % n];
        let bow = [
            [0.4, 0.4],
            [0.4, -0.4],
            [0.0, 0.4],
            [-0.1, 0.5],
            [-0.2, 0.6],
        ];
        for (k, d) in bow.iter().take(size).enumerate() {
            frame[1 + (knot_at + 1 + k) % n] = [base[0] + d[0], base[1] + d[1]];
        }
        let knotted = frame.clone();
        assert!(
            !untier.meeting_pairs(&knotted).is_empty(),
            "the knot crosses"
        );
        assert_eq!(
            untier.untie(&mut frame),
            0,
            "knot at {knot_at}, {size} points"
        );
        assert!(untier.meeting_pairs(&frame).is_empty());
        // Only the knot's points and its neighbours along the loop
        // may move (the centre too is kept).
        for v in 0..frame.len() {
            let near = (0..=size + 2).any(|k| v == 1 + (knot_at + n + k - 1) % n);
            if !near {
                assert_eq!(frame[v], knotted[v], "vertex {v} kept");
            }
        }
    }
}

#[test]
fn two_far_places_that_meet_are_left_as_they_are() {
    // A disk squashed flat with its top middle pulled down through its
    // bottom: half the loop lies between the edges that cross, either
    // way round.
    let (p, t) = disk(40);
    let untier = OutlineUntier::new(&t).unwrap();
    let mut frame: Vec<[f64; 2]> = p
        .iter()
        .map(|q| {
            if q[1] > 0.0 && q[0].abs() < 3.0 {
                [q[0], -2.0]
            } else {
                [q[0], 0.1 * q[1]]
            }
        })
        .collect();
    let squashed = frame.clone();
    assert!(untier.untie(&mut frame) > 0);
    assert_eq!(frame, squashed);
}

#[test]
fn runs_wrap_and_stop_at_kept_points() {
    let mask = |s: &str| s.chars().map(|c| c == 'x').collect::<Vec<bool>>();
    assert_eq!(runs(&mask("..xxx..x.")), vec![(2, 3), (7, 1)]);
    assert_eq!(runs(&mask("xx..xxx")), vec![(4, 5)]);
    assert_eq!(runs(&mask("xxxx")), vec![]);
    assert_eq!(runs(&mask("....")), vec![]);
}
