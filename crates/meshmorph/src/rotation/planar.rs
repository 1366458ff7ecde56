//! Rotations of the plane: angles.
#![allow(non_snake_case)]

use std::f64::consts::TAU;

use super::{Rotations, Space};
use crate::matrix::Mat2;
use crate::polar::{polar_decomposition, rotation, SymmetricEigen2};

/// `angle + 2πk` for the integer `k` that brings it nearest to `reference`.
#[inline]
pub(crate) fn nearest_branch(angle: f64, reference: f64) -> f64 {
    angle + TAU * ((reference - angle) / TAU).round()
}

impl Rotations<2> for Space<2> {
    /// Radians, counter-clockwise.
    type Log = f64;
    type StretchPowers = SymmetricEigen2;

    fn polar(A: &Mat2) -> (f64, Mat2) {
        let p = polar_decomposition(*A);
        (p.angle, p.stretch)
    }

    #[inline]
    fn exp(angle: &f64, t: f64) -> Mat2 {
        rotation(t * angle)
    }

    fn log(R: &Mat2) -> f64 {
        R[1][0].atan2(R[0][0])
    }

    fn relative(from: &f64, to: &f64) -> f64 {
        nearest_branch(to - from, 0.0)
    }

    fn nearest_branch(angle: &f64, reference: &f64) -> f64 {
        nearest_branch(*angle, *reference)
    }

    fn add_turns(angle: &f64, turns: i32) -> f64 {
        angle + TAU * turns as f64
    }

    fn angle(angle: &f64) -> f64 {
        angle.abs()
    }

    fn stretch_powers(S: &Mat2) -> SymmetricEigen2 {
        SymmetricEigen2::new(*S)
    }

    #[inline]
    fn stretch_power(S: &SymmetricEigen2, t: f64, floor: f64) -> Mat2 {
        S.power(t, floor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn branches() {
        assert!((nearest_branch(-0.9 * PI, 0.95 * PI) - 1.1 * PI).abs() < 1e-12);
        assert!((nearest_branch(0.1, 4.0 * PI) - (0.1 + 4.0 * PI)).abs() < 1e-12);
        assert_eq!(nearest_branch(0.5, 0.4), 0.5);
    }

    #[test]
    fn log_exp_and_relative() {
        type P = Space<2>;
        for a in [-3.0, -0.5, 0.0, 1.0, 3.1] {
            assert!((P::log(&P::exp(&a, 1.0)) - a).abs() < 1e-14);
            assert!((P::relative(&a, &(a + 0.3 + 2.0 * TAU)) - 0.3).abs() < 1e-12);
        }
        assert_eq!(P::add_turns(&0.25, -1), 0.25 - TAU);
        assert_eq!(P::angle(&-0.25), 0.25);
    }
}
