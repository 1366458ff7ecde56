use meshmorph::linalg::lanes::Lanes;

use meshmorph::linalg::trig::*;

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

#[test]
fn every_lane_is_its_own_angle() {
    // Every quadrant side by side, then one lane beyond the reduction.
    let angles: Vec<f64> = (-9..9).map(|k| 0.7 * k as f64 + 0.1).collect();
    for four in angles.chunks_exact(4) {
        let (s, c) = sin_cos_lanes(Lanes([four[0], four[1], four[2], four[3]]));
        for (f, &x) in four.iter().enumerate() {
            assert_eq!((s.0[f], c.0[f]), sin_cos(x), "lane {f}, angle {x}");
        }
    }
    // Beside an angle the standard library answers for (or NaN), each
    // lane keeps its own answer (the two differ in the last place for
    // some of these angles).
    let far = 3.0 * REDUCED_LIMIT;
    for other in [far, f64::NAN] {
        for k in 0..1000 {
            let x = 0.001 + 0.00314 * k as f64;
            let (s, c) = sin_cos_lanes(Lanes([x, other]));
            assert_eq!((s.0[0], c.0[0]), sin_cos(x), "beside {other}");
            assert_eq!(s.0[1].to_bits(), other.sin_cos().0.to_bits());
            assert_eq!(c.0[1].to_bits(), other.sin_cos().1.to_bits());
        }
    }
}
