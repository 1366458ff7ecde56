//! Sine and cosine of one angle together, for the per-triangle rotations of
//! every frame.
//!
//! A frame evaluates one rotation per triangle, a million for a large mesh,
//! each needing the sine and cosine of its angle at the frame's time. The
//! C library's `sincos` saves and restores the floating-point environment on
//! every call, which costs more than the arithmetic; here the angle is
//! reduced by multiples of `π/2` (Cody and Waite: `π/2` in four parts, the
//! products of the multiple with the first three exact) and both functions
//! come from the minimax polynomials on `[−π/4, π/4]` of Sun Microsystems'
//! fdlibm, the kernels of most C libraries' `sin` and `cos`. Up to
//! [`REDUCED_LIMIT`] the results agree with the standard library's to
//! 2 units in the last place, or to 2 machine epsilons absolutely where
//! they are below 1e-3 (near a zero of either function the reduced angle
//! carries an absolute error of about 1e-26, which is no relative accuracy
//! for a value that small: a rotation does not notice). Beyond it (angles
//! no frame of a mesh reaches) the standard library answers.

use crate::linalg::lanes::{Lanes, Real};

/// Angles up to this magnitude are reduced here: the multiple `k` of `π/2`
/// then has at most 16 bits, so `k` times each of the first three 33-bit
/// parts of `π/2` is exact.
pub const REDUCED_LIMIT: f64 = 1.0e5;

/// Adding it to a double below 2⁵¹ in magnitude rounds the sum to a whole
/// number, held in the low bits of the sum's significand.
const ROUNDING_SHIFT: f64 = 6_755_399_441_055_744.0;

/// `π/2` as the sum of four doubles: three of 33 significant bits, and
/// what remains (fdlibm's decimal forms, each of which rounds to the double
/// meant).
#[allow(clippy::excessive_precision)]
const PI_2_HI: f64 = 1.570_796_326_734_125_614_17;
#[allow(clippy::excessive_precision)]
const PI_2_MID: f64 = 6.077_100_506_303_965_976_6e-11;
#[allow(clippy::excessive_precision)]
const PI_2_LO: f64 = 2.022_266_248_711_166_455_8e-21;
#[allow(clippy::excessive_precision)]
const PI_2_TAIL: f64 = 8.478_427_660_368_899_569_97e-32;

/// Coefficients of `sin x = x + x³ (S1 + x² S2 + …)` on `[−π/4, π/4]`.
#[allow(clippy::excessive_precision)]
const S: [f64; 6] = [
    -1.666_666_666_666_663_243_48e-1,
    8.333_333_333_322_489_461_24e-3,
    -1.984_126_982_985_794_931_34e-4,
    2.755_731_370_707_006_767_89e-6,
    -2.505_076_025_340_686_341_95e-8,
    1.589_690_995_211_550_102_21e-10,
];

/// Coefficients of `cos x = 1 − x²/2 + x⁴ (C1 + x² C2 + …)` on `[−π/4, π/4]`.
#[allow(clippy::excessive_precision)]
const C: [f64; 6] = [
    4.166_666_666_666_660_190_37e-2,
    -1.388_888_888_887_410_957_49e-3,
    2.480_158_728_947_672_941_78e-5,
    -2.755_731_435_139_066_330_35e-7,
    2.087_572_321_298_174_827_90e-9,
    -1.135_964_755_778_819_482_65e-11,
];

/// `(sin x, cos x)`, as [`f64::sin_cos`] to the accuracy of the module's
/// documentation; NaN for NaN and infinities.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    let (s, c) = sin_cos_lanes(Lanes([x]));
    (s.0[0], c.0[0])
}

/// [`sin_cos`] of every lane, each lane as [`sin_cos`] of its own angle:
/// the same steps on all of them, without a branch unless a lane is beyond
/// [`REDUCED_LIMIT`] or NaN (the standard library answers for that lane).
#[inline(always)]
pub fn sin_cos_lanes<const L: usize>(x: Lanes<L>) -> (Lanes<L>, Lanes<L>) {
    // The nearest whole multiple `k` of π/2, rounded by adding and taking
    // away 1.5 · 2⁵² (an instruction set without a rounding instruction
    // would call a library function); its last two bits are the quadrant.
    let shifted = x.map(|x| x * std::f64::consts::FRAC_2_PI + ROUNDING_SHIFT);
    let k = shifted - Lanes::splat(ROUNDING_SHIFT);
    let y = x.zip(k, |x, k| {
        (((x - k * PI_2_HI) - k * PI_2_MID) - k * PI_2_LO) - k * PI_2_TAIL
    });
    let (s, c) = (kernel_sin(y), kernel_cos(y));
    // Odd quadrants swap the two; the sine is negative in quadrants 2 and 3,
    // the cosine in 1 and 2 (the sign bit flipped, without a branch).
    let (mut sin, mut cos) = (s, c);
    for l in 0..L {
        let quadrant = shifted.0[l].to_bits() & 3;
        if quadrant & 1 == 1 {
            (sin.0[l], cos.0[l]) = (c.0[l], s.0[l]);
        }
        let flip = |v: f64, negative: u64| f64::from_bits(v.to_bits() ^ ((negative & 2) << 62));
        sin.0[l] = flip(sin.0[l], quadrant);
        cos.0[l] = flip(cos.0[l], quadrant + 1);
    }
    let mut beyond = false;
    for x in x.0 {
        beyond |= x.abs() > REDUCED_LIMIT || x.is_nan();
    }
    if beyond {
        for l in 0..L {
            if x.0[l].abs() > REDUCED_LIMIT || x.0[l].is_nan() {
                (sin.0[l], cos.0[l]) = x.0[l].sin_cos();
            }
        }
    }
    (sin, cos)
}

/// `sin y` for `|y| ≤ π/4` (a little beyond, after rounding `k`).
#[inline(always)]
fn kernel_sin<T: Real>(y: T) -> T {
    let z = y * y;
    let s = |i: usize| T::splat(S[i]);
    let r = s(1) + z * (s(2) + z * (s(3) + z * (s(4) + z * s(5))));
    y + y * z * (s(0) + z * r)
}

/// `cos y` for `|y| ≤ π/4`: `1 − z/2` summed with its rounding error
/// carried into the small terms, as fdlibm does.
#[inline(always)]
fn kernel_cos<T: Real>(y: T) -> T {
    let z = y * y;
    let c = |i: usize| T::splat(C[i]);
    let r = z * (c(0) + z * (c(1) + z * (c(2) + z * (c(3) + z * (c(4) + z * c(5))))));
    let hz = T::splat(0.5) * z;
    let one = T::splat(1.0);
    let w = one - hz;
    w + (((one - w) - hz) + z * r)
}
