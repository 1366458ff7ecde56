//! The ARKit shapes on a head that is not ICT's: Sumner's head of
//! ../shared/data/dt/face-head, its lips modelled joined.

use std::collections::HashSet;
use std::path::PathBuf;

use meshmorph::{expressions, io, ExpressionOptions, ExpressionTemplate};

/// The recommended landmarks on Sumner's head, by vertex (y up, facing
/// `+z`, the head's right towards `-x`); its lips meet at `y = -1.02`.
const LANDMARKS: [(&str, usize); 17] = [
    ("jawRight", 6483),
    ("jawLeft", 11867),
    ("browOuterRight", 3935),
    ("browOuterLeft", 9359),
    ("browInnerRight", 13570),
    ("browInnerLeft", 14811),
    ("eyeOuterRight", 13779),
    ("eyeOuterLeft", 15011),
    ("eyeInnerRight", 2007),
    ("eyeInnerLeft", 7457),
    ("mouthCornerRight", 14600),
    ("mouthCornerLeft", 15759),
    ("chin", 13823),
    ("noseBridge", 14282),
    ("noseTip", 14537),
    ("upperLipTop", 4653),
    ("lowerLipBottom", 2372),
];

/// In jawOpen every vertex of the lower lip goes down with it (at least
/// half as far as the landmark below it) and every vertex of the upper lip
/// stays (at most 0.3 of that): no vertex of one lip takes the other's
/// motion, which a correspondence that only looks at what is near would
/// give where the template's lips lie a little off the head's.
pub fn sumners_head_opens_its_jaw_each_lip_moving_as_a_whole(dir: PathBuf) {
    let head =
        io::read_mesh(&dir.join("head-poses/head-reference.obj")).unwrap_or_else(|e| panic!("{e}"));
    let p = head.positions();
    let points: Vec<(String, [f64; 3])> = LANDMARKS
        .iter()
        .map(|&(name, v)| (name.to_string(), p[v]))
        .collect();
    let template = ExpressionTemplate::arkit();
    let out = expressions(&template, &head, &points, &ExpressionOptions::default()).unwrap();
    let jaw = out.names.iter().position(|n| n == "jawOpen").unwrap();
    let d = &out.deltas[jaw];
    // Its lips are one surface: said, and no more.
    assert!(
        out.warnings.len() == 1 && out.warnings[0].contains("lips of the mouth are joined"),
        "{:?}",
        out.warnings
    );

    // The vertices joined to `start` through those that `keep`.
    let mut around = vec![Vec::new(); p.len()];
    for t in head.triangles() {
        for k in 0..3 {
            around[t[k] as usize].push(t[(k + 1) % 3] as usize);
            around[t[(k + 1) % 3] as usize].push(t[k] as usize);
        }
    }
    let grow = |start: usize, keep: &dyn Fn([f64; 3]) -> bool| {
        let mut seen = HashSet::from([start]);
        let mut stack = vec![start];
        while let Some(v) = stack.pop() {
            for &w in &around[v] {
                if keep(p[w]) && seen.insert(w) {
                    stack.push(w);
                }
            }
        }
        seen
    };
    // Each lip short of its corners (at x = ±2.38), in front of them.
    let lower = grow(2372, &|q| {
        q[1] < -1.05 && q[1] > -2.2 && q[0].abs() < 1.9 && q[2] > 5.8
    });
    let upper = grow(4653, &|q| {
        q[1] > -0.99 && q[1] < -0.3 && q[0].abs() < 1.9 && q[2] > 5.8
    });
    assert!(
        lower.len() > 300 && upper.len() > 200,
        "{} {}",
        lower.len(),
        upper.len()
    );

    let down = d[2372];
    let along = |v: usize| {
        (0..3).map(|i| d[v][i] * down[i]).sum::<f64>()
            / (0..3).map(|i| down[i] * down[i]).sum::<f64>()
    };
    let (least, v) = lower
        .iter()
        .map(|&v| (along(v), v))
        .fold((f64::MAX, 0), |a, b| if b.0 < a.0 { b } else { a });
    assert!(
        least > 0.5,
        "lower-lip vertex {v} moves {least:.3} of the lip's motion"
    );
    let (most, v) = upper
        .iter()
        .map(|&v| (along(v), v))
        .fold((f64::MIN, 0), |a, b| if b.0 > a.0 { b } else { a });
    assert!(
        most < 0.3,
        "upper-lip vertex {v} moves {most:.3} of the lower lip's motion"
    );
}
