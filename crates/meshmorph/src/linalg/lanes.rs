//! The same arithmetic on several numbers at once.
//!
//! A frame's pass over the triangles takes several triangles at a time, and
//! frames solved together ask each of them for its rotation at each of
//! their times: the same steps on different numbers. [`Lanes`] holds those
//! numbers side by side, one per triangle and frame, and its operations act
//! on all of them, which the compiler turns into vector instructions. The
//! small-matrix and quaternion steps are written once over [`Real`], which
//! both `f64` and [`Lanes`] are.

use std::ops::{Add, Mul, Neg, Sub};

/// `L` numbers side by side (lanes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lanes<const L: usize>(pub [f64; L]);

impl<const L: usize> Lanes<L> {
    /// `f(x)` in every lane.
    #[inline(always)]
    pub fn map(self, f: impl Fn(f64) -> f64) -> Self {
        Self(array(|i| f(self.0[i])))
    }

    /// `f(x, y)` lane by lane.
    #[inline(always)]
    pub fn zip(self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        Self(array(|i| f(self.0[i], other.0[i])))
    }
}

/// The array of `f(0), …, f(N − 1)`, built by a plain loop. Always
/// inlined: the nested closures of `std::array::from_fn` may be left out of
/// line, and then run without the vector instructions of the code that
/// calls them.
#[inline(always)]
pub fn array<T: Copy, const N: usize>(f: impl Fn(usize) -> T) -> [T; N] {
    const { assert!(N > 0) };
    let mut out = [f(0); N];
    for (i, x) in out.iter_mut().enumerate().skip(1) {
        *x = f(i);
    }
    out
}

/// The arithmetic the shared steps use: `f64`, or [`Lanes`] of them.
pub trait Real:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Neg<Output = Self>
{
    /// `x` in every lane.
    fn splat(x: f64) -> Self;
}

impl Real for f64 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
}

impl<const L: usize> Real for Lanes<L> {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Self([x; L])
    }
}

impl<const L: usize> Add for Lanes<L> {
    type Output = Self;
    #[inline(always)]
    fn add(self, other: Self) -> Self {
        self.zip(other, |a, b| a + b)
    }
}

impl<const L: usize> Sub for Lanes<L> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, other: Self) -> Self {
        self.zip(other, |a, b| a - b)
    }
}

impl<const L: usize> Mul for Lanes<L> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, other: Self) -> Self {
        self.zip(other, |a, b| a * b)
    }
}

impl<const L: usize> Neg for Lanes<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
}
