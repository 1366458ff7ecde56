use meshmorph::outline::boundary::*;

fn blob(n: usize, turn: f64, start: usize) -> Vec<[f64; 2]> {
    let mut pts: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            let r = 1.0 + 0.3 * (3.0 * t).cos() + 0.1 * (5.0 * t).sin();
            let (x, y) = (r * t.cos(), r * t.sin());
            let (s, c) = turn.sin_cos();
            [2.0 * (c * x - s * y) + 5.0, 2.0 * (s * x + c * y) - 1.0]
        })
        .collect();
    pts.rotate_left(start);
    pts
}

/// A square into a 4:1 bar, the bar turned, moved and restarted:
/// corners go to corners, though the square's sides are a quarter of
/// its length each and the bar's long sides 0.4.
#[test]
fn a_squares_corners_go_to_a_bars_corners() {
    let square = vec![[30.0, 30.0], [70.0, 30.0], [70.0, 70.0], [30.0, 70.0]];
    for (turn, start) in [(0.0, 0), (2.1, 1), (-0.7, 2), (std::f64::consts::PI, 3)] {
        let (s, c) = f64::sin_cos(turn);
        let mut bar: Vec<[f64; 2]> = [[10.0, 40.0], [90.0, 40.0], [90.0, 60.0], [10.0, 60.0]]
            .iter()
            .map(|p| {
                [
                    3.0 * (c * p[0] - s * p[1]) + 7.0,
                    3.0 * (s * p[0] + c * p[1]),
                ]
            })
            .collect();
        bar.rotate_left(start);
        let m = match_loops(&square, &bar, &[], 256, Some(&TieBreak::Turn)).unwrap();
        assert_eq!(m.len(), 4, "{m:?}");
        assert!(
            m.iter().all(|p| p.from_a.is_some() && p.from_b.is_some()),
            "{m:?}"
        );
    }
}

#[test]
fn a_turned_restarted_copy_matches_point_for_point() {
    let a = blob(61, 0.0, 0);
    let b = blob(61, 2.0 * std::f64::consts::PI / 3.0, 17);
    let m = match_loops(&a, &b, &[], 256, None).unwrap();
    assert_eq!(m.len(), 61);
    for p in &m {
        let (i, j) = (p.from_a.unwrap(), p.from_b.unwrap());
        assert_eq!((i + 61 - 17) % 61, j, "{i} {j}");
    }
}

#[test]
fn different_counts_keep_every_point() {
    let a = blob(37, 0.3, 0);
    let b = blob(211, -1.0, 50);
    let m = match_loops(&a, &b, &[], 256, None).unwrap();
    let mut seen_a: Vec<usize> = m.iter().filter_map(|p| p.from_a).collect();
    let mut seen_b: Vec<usize> = m.iter().filter_map(|p| p.from_b).collect();
    seen_a.sort_unstable();
    seen_b.sort_unstable();
    assert_eq!(seen_a, (0..37).collect::<Vec<_>>());
    assert_eq!(seen_b, (0..211).collect::<Vec<_>>());
    // Matched order: each side goes round once, in its own order.
    let ia: Vec<usize> = m.iter().filter_map(|p| p.from_a).collect();
    let descents = (0..ia.len())
        .filter(|&k| ia[(k + 1) % ia.len()] < ia[k])
        .count();
    assert_eq!(descents, 1);
    let ib: Vec<usize> = m.iter().filter_map(|p| p.from_b).collect();
    let descents = (0..ib.len())
        .filter(|&k| ib[(k + 1) % ib.len()] < ib[k])
        .count();
    assert_eq!(descents, 1);
}
