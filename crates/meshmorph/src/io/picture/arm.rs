//! A sprite made in code, for the demo, the tests and the benchmarks: an
//! arm (upper arm and forearm, striped across, a hand at the end), its
//! forearm bent at the elbow by any angle, five points matched on the
//! outlines of the straight arm and a bent one, and two more at the fold
//! of the elbow.

use super::Picture;

/// The arm's shoulder and elbow (pixels, y down), its forearm's length and
/// its half width, on the sprite of 320 × 240 pixels; other sizes scale
/// them.
const SHOULDER: [f64; 2] = [50.0, 170.0];
const ELBOW: [f64; 2] = [160.0, 170.0];
const FOREARM: f64 = 100.0;
const HALF_WIDTH: f64 = 13.0;
/// Length of a stripe along a part.
const STRIPE: f64 = 12.0;
/// The hand's radius in half widths.
const HAND: f64 = 1.4;

/// The size the arm is drawn for; [`arm_sprite`] scales it into others.
pub const ARM_SPRITE_SIZE: (u32, u32) = (320, 240);

/// How much the arm is scaled on a sprite of `width × height` pixels: as
/// much as fits on both sides.
fn arm_scale((width, height): (u32, u32)) -> f64 {
    let (w, h) = ARM_SPRITE_SIZE;
    (f64::from(width) / f64::from(w)).min(f64::from(height) / f64::from(h))
}

/// The arm sprite of `width × height` pixels (the arm of the 320 × 240
/// sprite scaled by as much as fits, from the top-left corner), its
/// forearm bent by `bend` radians at the elbow (counter-clockwise on the
/// screen: upwards). Each part is striped across in its own coordinates,
/// so that the stripes turn with the forearm; opaque inside, transparent
/// outside (no soft edge).
pub fn arm_sprite(bend: f64, (width, height): (u32, u32)) -> Picture {
    let s = arm_scale((width, height));
    let (shoulder, elbow) = (SHOULDER.map(|v| v * s), ELBOW.map(|v| v * s));
    let (upper, fore, half_width) = ((ELBOW[0] - SHOULDER[0]) * s, FOREARM * s, HALF_WIDTH * s);
    let stripe_length = STRIPE * s;
    let (c, sin) = (bend.cos(), bend.sin());
    // Along the part and across it, for a point `p` of a part starting at
    // `from` in direction (dx, dy).
    let local = |p: [f64; 2], from: [f64; 2], (dx, dy): (f64, f64)| {
        let (x, y) = (p[0] - from[0], p[1] - from[1]);
        (x * dx + y * dy, -x * dy + y * dx)
    };
    // A rounded bar of `length` and the colour of its point.
    let part = |along: f64, across: f64, length: f64, hue: [u8; 3]| -> Option<[u8; 4]> {
        let clamped = along.clamp(0.0, length);
        let d = ((along - clamped).powi(2) + across.powi(2)).sqrt();
        (d <= half_width).then(|| {
            let stripe = ((along / stripe_length).floor() as i64).rem_euclid(2) == 0;
            let shade = 1.0 - 0.35 * (across / half_width).powi(2);
            let k = if stripe { shade } else { 0.7 * shade };
            [
                (f64::from(hue[0]) * k) as u8,
                (f64::from(hue[1]) * k) as u8,
                (f64::from(hue[2]) * k) as u8,
                255,
            ]
        })
    };
    Picture::from_fn(width, height, |x, y| {
        let p = [f64::from(x) + 0.5, f64::from(y) + 0.5];
        // The forearm (drawn over the upper arm), turning upwards from the
        // elbow: screen y grows downwards.
        let (a, b) = local(p, elbow, (c, -sin));
        if (a - fore).hypot(b) <= HAND * half_width {
            return [236, 184, 140, 255];
        }
        if let Some(colour) = part(a, b, fore, [70, 130, 220]) {
            return colour;
        }
        let (a, b) = local(p, shoulder, (1.0, 0.0));
        part(a, b, upper, [220, 90, 70]).unwrap_or([0, 0, 0, 0])
    })
}

/// Five points matched on the outlines of the straight arm and the arm
/// bent by `bend`, on sprites of `size` pixels, as a user marks them: the
/// shoulder's end, the underside of the upper arm, the outside of the
/// elbow, the forearm's side and the hand's tip (the bent forearm lies
/// along the upper arm and hides part of its outline, and the outlines
/// alone could pair them either way). Each: its name, then the point on
/// the straight arm and on the bent one (pixels, y down).
pub fn arm_anchors(bend: f64, size: (u32, u32)) -> [(&'static str, [f64; 2], [f64; 2]); 5] {
    let s = arm_scale(size);
    let (shoulder, elbow_at, half_width) = (SHOULDER, ELBOW, HALF_WIDTH);
    let tip = FOREARM + HAND * half_width;
    let end = [shoulder[0] - half_width, shoulder[1]];
    let elbow = [elbow_at[0], elbow_at[1] + half_width];
    let upper = [0.5 * (shoulder[0] + elbow_at[0]), elbow_at[1] + half_width];
    // The forearm's side that faces down when straight, halfway along.
    let (along, side) = (0.5 * FOREARM, half_width);
    let forearm = [
        elbow_at[0] + along * bend.cos() + side * bend.sin(),
        elbow_at[1] - along * bend.sin() + side * bend.cos(),
    ];
    let hand = [
        elbow_at[0] + tip * bend.cos(),
        elbow_at[1] - tip * bend.sin(),
    ];
    let scaled = |p: [f64; 2]| p.map(|v| v * s);
    [
        ("shoulder", end, end),
        ("upper_arm", upper, upper),
        ("elbow", elbow, elbow),
        (
            "forearm",
            [elbow_at[0] + along, elbow_at[1] + side],
            forearm,
        ),
        ("hand", [elbow_at[0] + tip, elbow_at[1]], hand),
    ]
    .map(|(name, a, b)| (name, scaled(a), scaled(b)))
}

/// Two more points matched where the arm folds, as a user who knows how an
/// elbow bends marks them: bent, the forearm's upper side meets the upper
/// arm's top in a corner, `half_width · tan(bend / 2)` along the forearm
/// from the elbow; the straight arm's top edge from that corner to the
/// forearm's side just past it (a quarter of a half width) folds away into
/// the corner. The corner is the same point of the upper arm in both
/// pictures; the other, the same point of the forearm. Without them the
/// outline's length the fold takes is shared along the whole arm.
pub fn arm_fold_anchors(bend: f64, size: (u32, u32)) -> [(&'static str, [f64; 2], [f64; 2]); 2] {
    let s = arm_scale(size);
    let (elbow, half_width) = (ELBOW, HALF_WIDTH);
    let fold = half_width * (0.5 * bend).tan();
    let top = elbow[1] - half_width;
    let corner = [elbow[0] - half_width * bend.sin() + fold * bend.cos(), top];
    let past = fold + 0.25 * half_width;
    let forearm = [
        elbow[0] - half_width * bend.sin() + past * bend.cos(),
        elbow[1] - half_width * bend.cos() - past * bend.sin(),
    ];
    let scaled = |p: [f64; 2]| p.map(|v| v * s);
    [
        ("inner_elbow", corner, corner),
        ("inner_forearm", [elbow[0] + past, top], forearm),
    ]
    .map(|(name, a, b)| (name, scaled(a), scaled(b)))
}
