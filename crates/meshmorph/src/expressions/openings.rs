//! The face's openings (the mouth, the eyes) found modelled closed on a
//! head: its lips (or lids) one surface where the template's are two.
//!
//! Where they are, the head's edges that cross from one lip to the other
//! have ends whose places on the template are far apart along it: they are
//! cut ([`Places::cut`](super::places::Places)). A head whose cut edges
//! line the opening from one corner to the other across more than
//! [`JOINED_SPAN`] of its width has the opening modelled closed: the shapes
//! that part the lips (jawOpen, mouthFunnel, ...) or the lids (eyeWide)
//! stretch the faces between them into a curtain, which no way of carrying
//! the shapes can avoid while the head keeps its faces.

use crate::expressions::template::ExpressionTemplate;
use crate::linalg::vector::{add, dot, norm, scale, sub};

/// The share of an opening's width, between its corners, that the head's
/// cut edges must line for the opening to be found closed. A mouth or an
/// eye modelled open has cut edges at most near its corners, where the
/// fitted template and the head meet at a slant.
pub const JOINED_SPAN: f64 = 0.5;

/// An opening by the template landmarks (iBUG numbers) of its corners.
const OPENINGS: [(&str, &str, &str, &str); 3] = [
    ("mouth", "lips", "49", "55"),
    ("right eye", "eyelids", "37", "40"),
    ("left eye", "eyelids", "43", "46"),
];

/// How many parts of an opening's width are told apart.
const BINS: usize = 20;

/// Warnings for each opening of the template whose lips or lids are one
/// surface on the head: `positions` are the head's (its main surface's),
/// `cut` its edges cut between places, `corner(v)` where the template's
/// vertex `v` lies laid onto the head.
pub fn joined_openings(
    template: &ExpressionTemplate,
    corner: impl Fn(u32) -> [f64; 3],
    positions: &[[f64; 3]],
    cut: &[(u32, u32)],
) -> Vec<String> {
    OPENINGS
        .iter()
        .filter_map(|&(opening, sides, a, b)| {
            let (a, b) = (corner(template.landmark(a)?), corner(template.landmark(b)?));
            let across = sub(b, a);
            let width = norm(across);
            if width == 0.0 {
                return None;
            }
            let mut lined = [false; BINS];
            for &(u, v) in cut {
                let (p, q) = (positions[u as usize], positions[v as usize]);
                let mid = scale(add(p, q), 0.5);
                let along = dot(sub(mid, a), across) / (width * width);
                let off = norm(sub(sub(mid, a), scale(across, along)));
                if (0.0..1.0).contains(&along) && off < 0.25 * width {
                    lined[(along * BINS as f64) as usize] = true;
                }
            }
            let span = lined.iter().filter(|&&x| x).count() as f64 / BINS as f64;
            (span > JOINED_SPAN).then(|| {
                format!(
                    "the {sides} of the {opening} are joined by faces on this head (one surface \
                     across {:.0} % of its width, where the template has two): the shapes that part \
                     them stretch those faces between them. Cut the {opening} open (split its \
                     vertices along the line where the {sides} meet) for them to part cleanly",
                    100.0 * span
                )
            })
        })
        .collect()
}
