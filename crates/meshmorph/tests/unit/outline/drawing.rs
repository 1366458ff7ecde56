use meshmorph::outline::geometry::signed_area2;

use meshmorph::outline::drawing::*;

fn square(x: f64, y: f64, s: f64) -> Vec<[f64; 2]> {
    vec![[x, y], [x + s, y], [x + s, y + s], [x, y + s]]
}

#[test]
fn orientation_is_normalised() {
    let mut outer = square(0.0, 0.0, 10.0);
    outer.reverse();
    let hole = square(2.0, 2.0, 2.0);
    let d = Drawing::new(vec![outer, hole]).unwrap();
    assert!(signed_area2(&d.loops()[0]) > 0.0);
    assert!(signed_area2(&d.loops()[1]) < 0.0);
    assert_eq!(d.given_index(0, 0), 3);
}

#[test]
fn repeats_are_kept_once() {
    let outer = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 0.0]];
    let d = Drawing::new(vec![outer]).unwrap();
    assert_eq!(d.num_points(), 3);
    assert_eq!(d.stored_of_given()[0], vec![0, 1, 1, 2, 0]);
}

#[test]
fn refusals_name_loops_and_points() {
    let err = |loops: Vec<Vec<[f64; 2]>>| Drawing::new(loops).unwrap_err().to_string();
    assert!(err(vec![]).contains("no loop"));
    assert!(err(vec![vec![[0.0, 0.0], [1.0, 0.0]]]).contains("2 distinct points"));
    assert!(err(vec![vec![[0.0, 0.0], [f64::NAN, 0.0], [0.0, 1.0]]]).contains("point 1"));
    let bow = vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
    assert!(err(vec![bow]).contains("crosses itself at points"));
    let m = err(vec![square(0.0, 0.0, 10.0), square(8.0, 8.0, 4.0)]);
    assert!(
        m.contains("loop 1 (a hole) crosses loop 0 (the outer loop)"),
        "{m}"
    );
    let m = err(vec![square(0.0, 0.0, 10.0), square(20.0, 20.0, 1.0)]);
    assert!(m.contains("outside loop 0"), "{m}");
    let m = err(vec![
        square(0.0, 0.0, 10.0),
        square(1.0, 1.0, 8.0),
        square(2.0, 2.0, 1.0),
    ]);
    assert!(m.contains("inside loop 1"), "{m}");
    let m = err(vec![
        square(0.0, 0.0, 10.0),
        square(1.0, 1.0, 2.0),
        square(3.0, 1.0, 2.0),
    ]);
    assert!(m.contains("touches"), "{m}");
    let spike = vec![[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
    assert!(err(vec![spike]).contains("folds back"));
    let flat = vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
    assert!(!err(vec![flat]).is_empty());
}
