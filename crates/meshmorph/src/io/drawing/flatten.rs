//! Curves to chords: quadratic and cubic Bézier segments replaced by
//! chords no farther than a tolerance from the curve.

/// One piece of a path outline in the drawing's coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Segment {
    /// Starts a new loop at the point.
    Move([f64; 2]),
    /// A straight line to the point.
    Line([f64; 2]),
    /// A quadratic Bézier: control point, end.
    Quad([f64; 2], [f64; 2]),
    /// A cubic Bézier: two control points, end.
    Cubic([f64; 2], [f64; 2], [f64; 2]),
    /// Closes the loop.
    Close,
}

/// The most chords one curve becomes, whatever the tolerance: a curve
/// that would need more is far larger than the drawing it is in.
const MAX_CHORDS: usize = 4096;

/// Chords for a curve whose second derivative is at most `bound` in
/// length: a chord over a parameter step $h$ strays at most $M h^2 / 8$
/// from the curve, so $n = \lceil \sqrt{M / (8\,\mathrm{tol})} \rceil$
/// chords keep within `tolerance`.
fn chords(bound: f64, tolerance: f64) -> usize {
    let n = (bound / (8.0 * tolerance)).sqrt().ceil();
    if n.is_finite() {
        (n as usize).clamp(1, MAX_CHORDS)
    } else {
        1
    }
}

fn len(v: [f64; 2]) -> f64 {
    v[0].hypot(v[1])
}

fn second_difference(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> [f64; 2] {
    [a[0] - 2.0 * b[0] + c[0], a[1] - 2.0 * b[1] + c[1]]
}

/// Starts a loop at `last` when none is under way (after a close).
fn start_at(current: &mut Vec<[f64; 2]>, last: [f64; 2]) {
    if current.is_empty() {
        current.push(last);
    }
}

/// The closed loops of `segments` (a path's outline), curves replaced by
/// chords within `tolerance` (> 0) of them; each loop's points without
/// the closing repeat of its first. An open subpath is closed, as a fill
/// closes it. Returns the loops and how many curves were flattened.
pub(super) fn flatten(segments: &[Segment], tolerance: f64) -> (Vec<Vec<[f64; 2]>>, usize) {
    let mut loops = Vec::new();
    let mut current: Vec<[f64; 2]> = Vec::new();
    let mut curves = 0;
    // Loops of fewer than 3 points enclose nothing and draw nothing.
    let mut finish = |current: &mut Vec<[f64; 2]>| {
        if current.len() > 1 && current.first() == current.last() {
            current.pop();
        }
        if current.len() >= 3 {
            loops.push(std::mem::take(current));
        }
        current.clear();
    };
    let mut last = [0.0, 0.0];
    for &s in segments {
        match s {
            Segment::Move(p) => {
                finish(&mut current);
                current.push(p);
                last = p;
            }
            Segment::Line(p) => {
                start_at(&mut current, last);
                current.push(p);
                last = p;
            }
            Segment::Quad(c, p) => {
                start_at(&mut current, last);
                curves += 1;
                let n = chords(2.0 * len(second_difference(last, c, p)), tolerance);
                for k in 1..=n {
                    let t = k as f64 / n as f64;
                    let u = 1.0 - t;
                    current.push(std::array::from_fn(|i| {
                        u * u * last[i] + 2.0 * u * t * c[i] + t * t * p[i]
                    }));
                }
                last = p;
            }
            Segment::Cubic(c1, c2, p) => {
                start_at(&mut current, last);
                curves += 1;
                let bound = 6.0
                    * len(second_difference(last, c1, c2)).max(len(second_difference(c1, c2, p)));
                let n = chords(bound, tolerance);
                for k in 1..=n {
                    let t = k as f64 / n as f64;
                    let u = 1.0 - t;
                    current.push(std::array::from_fn(|i| {
                        u * u * u * last[i]
                            + 3.0 * u * u * t * c1[i]
                            + 3.0 * u * t * t * c2[i]
                            + t * t * t * p[i]
                    }));
                }
                last = p;
            }
            Segment::Close => {
                if let Some(&first) = current.first() {
                    last = first;
                }
                // A segment after a close without a move starts at the
                // closed loop's first point.
                finish(&mut current);
            }
        }
    }
    finish(&mut current);
    (loops, curves)
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
