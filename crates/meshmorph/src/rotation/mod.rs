//! Rotations as the interpolation needs them, for any dimension through the
//! [`Rotations`] trait: the polar decomposition of a triangle's map, the
//! rotation's logarithm (with its branch: whole turns count) and
//! exponential, and the consistency walk that chooses every triangle's
//! branch from its neighbours' (Baxter, Barla and Anjyo, NPAR 2008).

mod consistency;
mod planar;

use std::fmt::Debug;

use crate::matrix::Mat;

pub use consistency::make_consistent;

/// `D`-dimensional space, the type that carries the dimension-dependent
/// algebra ([`Rotations`], [`TriangleMaps`](crate::TriangleMaps)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Space<const D: usize>;

/// The rotations of `D`-dimensional space.
///
/// A rotation is held through its logarithm with its branch chosen: in the
/// plane an angle in radians, counter-clockwise, where `θ` and `θ + 2π` are
/// the same rotation but interpolate differently; in space it would be an
/// axis-angle vector whose angle may exceed `π` (whole turns about its own
/// axis).
pub trait Rotations<const D: usize> {
    /// A rotation's logarithm with its branch.
    type Log: Copy + Debug + PartialEq + Send + Sync + 'static;
    /// A symmetric positive definite stretch prepared for real powers.
    type StretchPowers: Copy + Debug + Send + Sync + 'static;

    /// Polar decomposition `A = R S` of `map`: the principal logarithm of
    /// `R`, the rotation closest to `A` in the Frobenius norm, and `S = Rᵀ A`
    /// (symmetric, and positive definite when `det A > 0`).
    fn polar(map: &Mat<D>) -> (Self::Log, Mat<D>);
    /// `exp(t · log)`: the rotation by the fraction `t` of `log`, as a matrix.
    fn exp(log: &Self::Log, t: f64) -> Mat<D>;
    /// The principal logarithm of the rotation matrix `rotation`.
    fn log(rotation: &Mat<D>) -> Self::Log;
    /// The principal logarithm of the rotation from `from` to `to`:
    /// `log(exp(from)⁻¹ exp(to))`.
    fn relative(from: &Self::Log, to: &Self::Log) -> Self::Log;
    /// The logarithm of the same rotation as `log`, whole turns added, nearest
    /// to `reference`: the branch choice of the consistency walk.
    fn nearest_branch(log: &Self::Log, reference: &Self::Log) -> Self::Log;
    /// `log` with `turns` whole turns added (counter-clockwise in the plane).
    fn add_turns(log: &Self::Log, turns: i32) -> Self::Log;
    /// The rotation angle of `log`, radians, at least 0.
    fn angle(log: &Self::Log) -> f64;
    /// Prepares the symmetric stretch `S` for [`Rotations::stretch_power`].
    fn stretch_powers(stretch: &Mat<D>) -> Self::StretchPowers;
    /// `Sᵗ`, with eigenvalues below `floor` raised to it first so that every
    /// power is defined and positive definite.
    fn stretch_power(stretch: &Self::StretchPowers, t: f64, floor: f64) -> Mat<D>;
}
