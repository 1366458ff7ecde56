//! Rotations as the interpolation needs them, for any dimension through the
//! [`Rotations`] trait: the polar decomposition of a triangle's map, the
//! rotation's logarithm (with its branch: whole turns count) and
//! exponential, a triangle's rotation along a segment between two keys, and
//! the choice of every triangle's branch from its neighbours' (Baxter, Barla
//! and Anjyo, NPAR 2008), in the plane by a walk over the adjacency
//! ([`planar`]), in space by whole turns of the patches between jumps
//! ([`patches`]), both behind one entry point ([`consistent_rotations`]).

pub mod consistency;
pub mod patches;
pub mod planar;
pub mod spatial;

use std::fmt::Debug;

use crate::gradient::TriangleMaps;
use crate::linalg::lanes::Lanes;
use crate::linalg::matrix::Mat;
use crate::linalg::Space;
use crate::mesh::topology::TriangleAdjacency;

pub use consistency::consistent_rotations;
pub use consistency::make_consistent;
pub use spatial::RotationLog3;

/// The rotations of `D`-dimensional space, as interpolation, keyframe
/// sequences and blends use them.
///
/// A triangle's rotation comes from the polar decomposition of its map as a
/// *principal* rotation (in the plane an angle in (−π, π], in space a unit
/// quaternion with scalar part ≥ 0), and is interpolated through its
/// *logarithm with a branch*: in the plane an angle in radians,
/// counter-clockwise, where `θ` and `θ + 2π` are the same rotation but
/// interpolate differently; in space a whole-turn vector and a principal
/// rotation vector ([`RotationLog3`]). Which branch each triangle takes is
/// chosen over the triangle adjacency by [`Rotations::choose_branches`].
pub trait Rotations<const D: usize>: TriangleMaps<D> {
    /// A principal rotation, as the polar decomposition gives it.
    type Principal: Copy + Debug + Send + Sync + 'static;
    /// A rotation's logarithm with its branch; the default value is the
    /// identity.
    type Log: Copy + Debug + Default + PartialEq + Send + Sync + 'static;
    /// One triangle's rotation along a segment from one key to the next,
    /// prepared for [`Rotations::segment_at`].
    type Segment: Copy + Debug + Send + Sync + 'static;
    /// What the rotations of one segment share: in space the distinct
    /// whole-turn vectors (a part turning by more than half a turn turns
    /// through one vector, so a frame computes each once), in the plane
    /// nothing.
    type SegmentTurns: Debug + Send + Sync + 'static;
    /// A symmetric positive definite stretch prepared for real powers.
    type StretchPowers: Copy + Debug + Send + Sync + 'static;

    /// The identity rotation.
    const IDENTITY: Self::Principal;

    /// Polar decomposition `A = R S` of `map`: the principal rotation `R`
    /// (the proper rotation closest to `A` that makes `S` symmetric), and
    /// `S = Rᵀ A` (positive definite when `det A > 0`).
    fn polar(map: &Mat<D>) -> (Self::Principal, Mat<D>);
    /// The angle of a principal rotation, radians, in `[0, π]` (not a number
    /// when the rotation is not).
    fn angle(rotation: &Self::Principal) -> f64;
    /// Settles rotations whose principal form is ambiguous (exactly half a
    /// turn) by their neighbours, before branches are chosen. Nothing to
    /// settle by default.
    fn settle_half_turns(_rotations: &mut [Self::Principal], _adjacency: &TriangleAdjacency) {}
    /// The principal logarithm: no whole turns.
    fn principal_log(rotation: &Self::Principal) -> Self::Log;
    /// The logarithms of `rotations` (one per triangle) with branches that
    /// make them consistent over `adjacency`, each seed's part taking the
    /// principal branch at the seed, or, given `previous` (the logarithms of
    /// the previous key of a sequence and the triangles' areas), the branch
    /// nearest to it, with (in space) the whole turns of the way from the
    /// previous key, for [`Rotations::segments`]. `edge_weight(i, j)`
    /// weighs the edge between neighbours `i` and `j` (its length). The
    /// interpolation calls it through one entry point that chooses the
    /// seeds (the triangle of each part that turns least) the same way in
    /// every dimension.
    fn choose_branches(
        rotations: &[Self::Principal],
        adjacency: &TriangleAdjacency,
        edge_weight: &dyn Fn(usize, usize) -> f64,
        seeds: &[usize],
        previous: Option<(&[Self::Log], &[f64])>,
    ) -> Vec<Self::Log>;
    /// `log` with `turns` whole turns added (counter-clockwise in the
    /// plane; in space about the rotation's own axis, the x axis for the
    /// identity).
    fn add_turns(log: &Self::Log, turns: i32) -> Self::Log;
    /// The rotation of every triangle from key `j` (`from`: the principal
    /// rotations and logarithms) to key `j + 1` (`to`), and what they share.
    /// With `whole_turns` each takes the whole turns by which the branches
    /// of its two logarithms differ (in space, between later keys, those
    /// [`Rotations::choose_branches`] chose with `to`'s branches); without,
    /// it goes the shortest way.
    fn segments(
        from: (&[Self::Principal], &[Self::Log]),
        to: (&[Self::Principal], &[Self::Log]),
        whole_turns: bool,
    ) -> (Vec<Self::Segment>, Self::SegmentTurns);
    /// The rotations of a segment's shared whole turns a fraction `u` along
    /// it, as unit quaternions, into `out`: once per frame, for
    /// [`Rotations::segment_at`].
    fn turns_at(turns: &Self::SegmentTurns, u: f64, out: &mut Vec<[f64; 4]>);
    /// The rotation matrix a fraction `u` along `segment`, with its
    /// segment's [`Rotations::turns_at`] for `u`; `first` when the segment
    /// starts from key 0 (the identity).
    fn segment_at(segment: &Self::Segment, turns_at: &[[f64; 4]], u: f64, first: bool) -> Mat<D>;
    /// The rotation at the start of `segment` (its key's rotation):
    /// [`Rotations::segment_at`] is [`Rotations::turn_at`] times it.
    fn segment_start(segment: &Self::Segment) -> Mat<D>;
    /// The rotations from the start of segments a fraction along them, one
    /// per lane: lane `l` the rotation of `segments[l]` at `u[l]`, with its
    /// segment's [`Rotations::turns_at`] for that fraction, `turns_at[l]`.
    fn turn_at<const L: usize>(
        segments: [&Self::Segment; L],
        turns_at: [&[[f64; 4]]; L],
        u: Lanes<L>,
    ) -> [[Lanes<L>; D]; D];
    /// Whether `segment` takes whole turns beyond the shortest way.
    fn has_whole_turns(segment: &Self::Segment) -> bool;
    /// `sum + w · log`, for blends (Baxter et al. 2008, section 5).
    fn add_scaled(sum: &mut Self::Log, w: f64, log: &Self::Log);
    /// The rotation matrix `exp(log)`.
    fn exp(log: &Self::Log) -> Mat<D>;
    /// Prepares the symmetric stretch `S` for [`Rotations::stretch_power`].
    fn stretch_powers(stretch: &Mat<D>) -> Self::StretchPowers;
    /// `Sᵗ`, with eigenvalues below `floor` raised to it first so that every
    /// power is defined and positive definite.
    fn stretch_power(stretch: &Self::StretchPowers, t: f64, floor: f64) -> Mat<D>;
    /// `log S` of a symmetric `S`, eigenvalues below `floor` raised to it.
    fn stretch_log(stretch: &Mat<D>, floor: f64) -> Mat<D>;
    /// `exp L` of a symmetric `L`.
    fn stretch_exp(log: &Mat<D>) -> Mat<D>;
}
