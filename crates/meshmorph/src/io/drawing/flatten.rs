//! Curves to chords: quadratic and cubic Bézier segments replaced by
//! chords no farther than a tolerance from the curve.

/// One piece of a path outline in the drawing's coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
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

pub fn len(v: [f64; 2]) -> f64 {
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
pub fn flatten(segments: &[Segment], tolerance: f64) -> (Vec<Vec<[f64; 2]>>, usize) {
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
