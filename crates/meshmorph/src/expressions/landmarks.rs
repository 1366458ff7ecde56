//! The template's landmark names: the 68 points of the Multi-PIE / iBUG
//! 300-W scheme by number (`"1"` to `"68"`, or `"ibug37"`), and readable
//! aliases for the points people place by hand (`eyeOuterRight`,
//! `noseTip`, `mouthCornerLeft`, `chin`, ...). Left and right are the
//! head's own, as in ARKit's `eyeBlinkLeft`: iBUG's point 37, on the left
//! of a photograph, is the outer corner of the right eye.
//!
//! A user's point file names points on their head by these names; any
//! [`MIN_LANDMARKS`] or more suffice when they are spread over the face
//! ([`check_landmarks`] refuses fewer, naming the recommended ones that are
//! missing, and warns about a region none of them holds).

use crate::error::{Error, Result};
use crate::linalg::similarity::Similarity;
use crate::linalg::vector::{add, norm, scale, sub};

/// The fewest landmarks [`check_landmarks`] accepts.
pub const MIN_LANDMARKS: usize = 12;

/// Readable names of iBUG points, `(alias, number)`.
pub const ALIASES: &[(&str, u8)] = &[
    ("jawRight", 1),
    ("jawAngleRight", 4),
    ("chin", 9),
    ("jawAngleLeft", 14),
    ("jawLeft", 17),
    ("browOuterRight", 18),
    ("browMiddleRight", 20),
    ("browInnerRight", 22),
    ("browInnerLeft", 23),
    ("browMiddleLeft", 25),
    ("browOuterLeft", 27),
    ("noseBridge", 28),
    ("noseTip", 31),
    ("nostrilRight", 32),
    ("noseBase", 34),
    ("nostrilLeft", 36),
    ("eyeOuterRight", 37),
    ("eyeUpperRight", 38),
    ("eyeInnerRight", 40),
    ("eyeLowerRight", 42),
    ("eyeInnerLeft", 43),
    ("eyeUpperLeft", 45),
    ("eyeOuterLeft", 46),
    ("eyeLowerLeft", 47),
    ("mouthCornerRight", 49),
    ("upperLipTop", 52),
    ("mouthCornerLeft", 55),
    ("lowerLipBottom", 58),
    ("upperLipInner", 63),
    ("lowerLipInner", 67),
];

/// The 17 landmarks the README recommends: the jaw's ends and the chin, the
/// brows' ends, the eyes' corners, the bridge and tip of the nose, the
/// mouth's corners and the middle of each lip, each lid's middle.
pub const RECOMMENDED: [u8; 17] = [
    1, 9, 17, 18, 22, 23, 27, 28, 31, 37, 40, 43, 46, 49, 52, 55, 58,
];

/// The regions of the face a fit needs a landmark in, with the iBUG points
/// that hold each.
pub const REGIONS: &[(&str, std::ops::RangeInclusive<u8>)] = &[
    ("the jaw and chin", 1..=17),
    ("the right brow", 18..=22),
    ("the left brow", 23..=27),
    ("the nose", 28..=36),
    ("the right eye", 37..=42),
    ("the left eye", 43..=48),
    ("the mouth", 49..=68),
];

/// The iBUG number (1 to 68) of a landmark name: a number, `ibug` and a
/// number, or an alias (case does not matter).
pub fn landmark_number(name: &str) -> Option<u8> {
    let name = name.trim();
    let digits = name
        .strip_prefix("ibug")
        .or_else(|| name.strip_prefix("iBUG"))
        .unwrap_or(name);
    if let Ok(n) = digits.parse::<u8>() {
        return (1..=68).contains(&n).then_some(n);
    }
    ALIASES
        .iter()
        .find(|(alias, _)| alias.eq_ignore_ascii_case(name))
        .map(|&(_, n)| n)
}

/// The readable name of iBUG point `number`: its alias, else `ibug` and
/// its number (a name that is not a number alone, so that a line of text
/// `name x y z` reads it as a name).
pub fn landmark_name(number: u8) -> String {
    ALIASES
        .iter()
        .find(|&&(_, n)| n == number)
        .map_or_else(|| format!("ibug{number}"), |(alias, _)| alias.to_string())
}

/// Checks a set of landmark numbers: refuses duplicates and fewer than
/// [`MIN_LANDMARKS`] (naming the recommended ones that are missing), and
/// returns a warning for each region of [`REGIONS`] without a landmark.
///
/// # Errors
/// [`Error::InvalidArgument`] saying what is missing or repeated.
pub fn check_landmarks(numbers: &[u8]) -> Result<Vec<String>> {
    let mut seen = [false; 69];
    for &n in numbers {
        if std::mem::replace(&mut seen[n as usize], true) {
            return Err(Error::InvalidArgument(format!(
                "landmark {} ({}) is given twice",
                n,
                landmark_name(n)
            )));
        }
    }
    if numbers.len() < MIN_LANDMARKS {
        let missing: Vec<String> = RECOMMENDED
            .iter()
            .filter(|&&n| !seen[n as usize])
            .map(|&n| landmark_name(n))
            .collect();
        return Err(Error::InvalidArgument(format!(
            "{} landmarks given, at least {MIN_LANDMARKS} are needed, spread over the face; \
             of the recommended set these are missing: {}",
            numbers.len(),
            missing.join(", ")
        )));
    }
    Ok(REGIONS
        .iter()
        .filter(|(_, range)| !range.clone().any(|n| seen[n as usize]))
        .map(|(region, range)| {
            format!(
                "no landmark on {region} (iBUG {}-{}): it is placed by the fit alone",
                range.start(),
                range.end()
            )
        })
        .collect())
}

/// How far from where the others put it a landmark may lie before it is
/// named in a warning, as a fraction of the landmarks' spread (their RMS
/// distance from their centre). Right landmarks lie up to 0.13 of it on
/// heads sampled from the template's identity model and 0.31 on a head
/// of other proportions; an eye corner named for the other corner of its
/// eye lies 1.45, one placed on the nose tip 1.03.
pub const LANDMARK_MISPLACED: f64 = 0.6;

/// How far (as [`LANDMARK_MISPLACED`]) a landmark may lie before it is
/// refused: three times the farthest right one seen, below a landmark put
/// on the nose tip (1.03). The fit from such a landmark pulls the face
/// apart (a jaw landmark put at the jaw's angle, 1.14 of the spread, made
/// jawOpen move the chin by more than the head's size).
pub const LANDMARK_WRONG: f64 = 0.9;

/// Checks landmarks that are on the head for a misnamed or misplaced one:
/// `template` and `head` are the landmarks' positions on the template and
/// on the head, pair by pair, `names` their names. Returns the warnings.
///
/// - Left and right swapped: the head's landmarks fit the template's far
///   better mirrored than as given (a face is nearly symmetric, so
///   swapping every left with its right mirrors the set). Refused.
/// - Two swapped ([`swapped_pair`]): refused, naming them.
/// - One misplaced: after the similarity that best lays the template's
///   landmarks onto the head's, a landmark lying more than
///   [`LANDMARK_MISPLACED`] of the spread from where it lands is warned
///   about, more than [`LANDMARK_WRONG`] refused.
///
/// # Errors
/// [`Error::InvalidArgument`] saying which landmarks and what to do.
pub fn misplaced_landmarks(
    template: &[[f64; 3]],
    head: &[[f64; 3]],
    names: &[String],
) -> Result<Vec<String>> {
    // Where the template's landmarks land under the similarity that best
    // lays them onto `to`, and how far each is from its point there.
    let landed = |to: &[[f64; 3]]| -> Option<Vec<[f64; 3]>> {
        let s = Similarity::fit(template, to).ok()?;
        Some(template.iter().map(|&t| s.apply(t)).collect())
    };
    let residuals = |landed: &[[f64; 3]], to: &[[f64; 3]]| -> Vec<f64> {
        landed
            .iter()
            .zip(to)
            .map(|(&l, &h)| norm(sub(l, h)))
            .collect()
    };
    let centre = head
        .iter()
        .fold([0.0; 3], |c, p| add(c, scale(*p, 1.0 / head.len() as f64)));
    let spread = (head
        .iter()
        .map(|p| norm(sub(*p, centre)).powi(2))
        .sum::<f64>()
        / head.len() as f64)
        .sqrt();
    let Some(landed_given) = landed(head) else {
        return Ok(Vec::new());
    };
    let given = residuals(&landed_given, head);
    let rms = |r: &[f64]| (r.iter().map(|x| x * x).sum::<f64>() / r.len() as f64).sqrt();
    let mirrored: Vec<[f64; 3]> = head.iter().map(|p| [-p[0], p[1], p[2]]).collect();
    if let Some(m) = landed(&mirrored).map(|l| residuals(&l, &mirrored)) {
        if rms(&m) < 0.5 * rms(&given) && rms(&given) > 0.5 * LANDMARK_MISPLACED * spread {
            return Err(Error::InvalidArgument(format!(
                "the landmarks fit the template far better mirrored (their distance from where the \
                 template puts them {:.0} % of their spread as given, {:.0} % mirrored): left and \
                 right look swapped. Left and right are the head's own: its left eye is on the \
                 viewer's right when facing it; swap every Left and Right name",
                100.0 * rms(&given) / spread,
                100.0 * rms(&m) / spread
            )));
        }
    }
    if let Some(pair) = swapped_pair(&landed_given, head, names, spread) {
        return Err(Error::InvalidArgument(pair));
    }
    let off = |limit: f64| -> Vec<String> {
        given
            .iter()
            .zip(names)
            .filter(|(r, _)| **r > limit * spread)
            .map(|(r, name)| format!("{name} {:.0} %", 100.0 * r / spread))
            .collect()
    };
    let hint = if names.iter().any(|n| n.contains("jaw")) {
        " (jawRight and jawLeft, iBUG 1 and 17, are where the jawline meets the ear, level with \
         the eyes' outer corners, not the jaw's angle)"
    } else {
        ""
    };
    let wrong = off(LANDMARK_WRONG);
    if !wrong.is_empty() {
        return Err(Error::InvalidArgument(format!(
            "landmarks far from where the others put them, in per cent of the landmarks' spread \
             (right ones lie within about 30 %): {}. Check their names and places{hint}, or \
             leave them out ({MIN_LANDMARKS} landmarks suffice)",
            wrong.join(", ")
        )));
    }
    Ok(off(LANDMARK_MISPLACED)
        .into_iter()
        .map(|line| {
            format!(
                "landmark {line} of the landmarks' spread from where the others put it: check its \
                 name and place{hint}"
            )
        })
        .collect())
}

/// Two landmarks whose names look swapped: of the template's landmarks
/// `landed` by the similarity that best lays them onto the head's, each
/// lands far nearer
/// the other's point than its own (their distances to the other's point
/// less than half those to their own, together more than a tenth of the
/// landmarks' spread). Landmarks of a head of other proportions, right
/// but shifted together, never do: a shift brings each nearer the other
/// only by moving the other farther. Returns what to say.
fn swapped_pair(
    landed: &[[f64; 3]],
    head: &[[f64; 3]],
    names: &[String],
    spread: f64,
) -> Option<String> {
    let mut worst: Option<(f64, usize, usize)> = None;
    for a in 0..head.len() {
        for b in a + 1..head.len() {
            let own = norm(sub(landed[a], head[a])) + norm(sub(landed[b], head[b]));
            let other = norm(sub(landed[a], head[b])) + norm(sub(landed[b], head[a]));
            if own > 0.1 * spread && other < 0.5 * own && worst.is_none_or(|w| other / own < w.0) {
                worst = Some((other / own, a, b));
            }
        }
    }
    let (_, a, b) = worst?;
    Some(format!(
        "landmarks {} and {} look swapped: each lies where the other belongs. Check their names \
         (upperLipTop is the top of the upper lip, lowerLipBottom the bottom of the lower one; Left \
         and Right are the head's own)",
        names[a], names[b]
    ))
}
