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

/// Angles up to this magnitude are reduced here: the multiple `k` of `π/2`
/// then has at most 16 bits, so `k` times each of the first three 33-bit
/// parts of `π/2` is exact.
const REDUCED_LIMIT: f64 = 1.0e5;

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
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() > REDUCED_LIMIT || x.is_nan() {
        return x.sin_cos();
    }
    // The nearest whole multiple `k` of π/2, rounded by adding and taking
    // away 1.5 · 2⁵² (an instruction set without a rounding instruction
    // would call a library function); its last two bits are the quadrant.
    let shifted = x * std::f64::consts::FRAC_2_PI + ROUNDING_SHIFT;
    let k = shifted - ROUNDING_SHIFT;
    let y = (((x - k * PI_2_HI) - k * PI_2_MID) - k * PI_2_LO) - k * PI_2_TAIL;
    let (s, c) = (kernel_sin(y), kernel_cos(y));
    match shifted.to_bits() & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// `sin y` for `|y| ≤ π/4` (a little beyond, after rounding `k`).
#[inline]
fn kernel_sin(y: f64) -> f64 {
    let z = y * y;
    let r = S[1] + z * (S[2] + z * (S[3] + z * (S[4] + z * S[5])));
    y + y * z * (S[0] + z * r)
}

/// `cos y` for `|y| ≤ π/4`: `1 − z/2` summed with its rounding error
/// carried into the small terms, as fdlibm does.
#[inline]
fn kernel_cos(y: f64) -> f64 {
    let z = y * y;
    let r = z * (C[0] + z * (C[1] + z * (C[2] + z * (C[3] + z * (C[4] + z * C[5])))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + z * r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place of `b`.
    fn ulps(a: f64, b: f64) -> f64 {
        if a == b {
            return 0.0;
        }
        let ulp = f64::from_bits(b.abs().to_bits() + 1) - b.abs();
        (a - b).abs() / ulp.max(f64::MIN_POSITIVE)
    }

    #[test]
    fn agrees_with_the_standard_library_to_an_ulp_or_so() {
        // Angles of every size a frame meets, and the quadrant boundaries.
        let mut x = 1e-300f64;
        let mut worst = 0.0f64;
        let mut check = |x: f64| {
            for x in [x, -x] {
                let (s, c) = sin_cos(x);
                let (es, ec) = x.sin_cos();
                // Absolute near zeros of the function, relative elsewhere.
                let err = |a: f64, e: f64| {
                    if e.abs() < 1e-3 {
                        (a - e).abs() / f64::EPSILON
                    } else {
                        ulps(a, e)
                    }
                };
                worst = worst.max(err(s, es)).max(err(c, ec));
            }
        };
        while x < 2.0 * REDUCED_LIMIT {
            check(x);
            x *= 1.0009;
        }
        for k in 0..2000 {
            let q = k as f64 * std::f64::consts::FRAC_PI_2;
            check(q);
            check(q + 1e-9);
            check(f64::from_bits(q.to_bits() + 1));
        }
        assert!(worst <= 2.0, "{worst} units apart");
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert!(sin_cos(f64::NAN).0.is_nan() && sin_cos(f64::INFINITY).1.is_nan());
    }
}
