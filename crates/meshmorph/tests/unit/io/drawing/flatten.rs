use meshmorph::io::drawing::flatten::*;

#[test]
fn a_quarter_circle_keeps_within_the_tolerance() {
    // The usual cubic for a quarter of the unit circle.
    let k = 0.552_284_749_830_793_4;
    let segs = [
        Segment::Move([1.0, 0.0]),
        Segment::Cubic([1.0, k], [k, 1.0], [0.0, 1.0]),
        Segment::Close,
    ];
    for tol in [1e-2, 1e-3, 1e-4] {
        let (loops, curves) = flatten(&segs, tol);
        assert_eq!((loops.len(), curves), (1, 1));
        let pts = &loops[0];
        for w in pts[..pts.len() - 1].windows(2) {
            let mid = [(w[0][0] + w[1][0]) / 2.0, (w[0][1] + w[1][1]) / 2.0];
            // The cubic is within 3e-4 of the circle.
            assert!(1.0 - len(mid) <= tol + 3e-4, "{tol}: {mid:?}");
        }
    }
    assert!(flatten(&segs, 1e-4).0[0].len() > flatten(&segs, 1e-2).0[0].len());
}

#[test]
fn lines_stay_as_given_and_open_paths_close() {
    let segs = [
        Segment::Move([0.0, 0.0]),
        Segment::Line([1.0, 0.0]),
        Segment::Line([1.0, 1.0]),
        Segment::Move([5.0, 5.0]),
        Segment::Line([6.0, 5.0]),
        Segment::Line([6.0, 6.0]),
        Segment::Line([5.0, 5.0]),
        Segment::Close,
    ];
    let (loops, curves) = flatten(&segs, 0.1);
    assert_eq!(curves, 0);
    assert_eq!(loops[0], vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]);
    assert_eq!(loops[1], vec![[5.0, 5.0], [6.0, 5.0], [6.0, 6.0]]);
    assert_eq!(loops.len(), 2);
}
