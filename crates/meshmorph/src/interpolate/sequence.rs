//! As-rigid-as-possible interpolation through any number of keys, in the
//! plane and in space.
//!
//! Each key `K_j` is a pose of the first key `K_0` (the same triangles).
//! Per triangle the `D × D` map from `K_0` to `K_j` (in space Sumner and
//! Popović's, with a fourth vertex off the triangle's plane) is split by
//! the polar decomposition `A_j = R_j S_j`, `R_j` a proper rotation. Within
//! the segment from key `j` to `j + 1`, at `u ∈ [0, 1]`:
//!
//! - the rotation goes from `R_j` to `R_{j+1}` along the difference of
//!   their logarithms with branches ([`Rotations::segments`]): in the plane
//!   the rotation by `θ_j + u (θ_{j+1} − θ_j)`; in space `exp(u c) exp(u e)
//!   R_j`, where `e` is the principal rotation vector of `R_{j+1} R_jᵀ` and
//!   `c` its whole turns (between later keys chosen over the mesh from
//!   these relative rotations, as a key's branches are). In the first
//!   segment (`R_0 = I`) this is `R(t)` interpolated along its axis by
//!   angle (Alexa et al. 2000), with whole turns where a part turns by more
//!   than half a turn;
//! - the stretch is `(1−u) S_j + u S_{j+1}` ([`StretchMode::Linear`], with
//!   `S_0 = I`: Alexa et al. 2000), or `exp((1−u) log S_j + u log S_{j+1})`
//!   ([`StretchMode::Log`]; `S_1ᵘ` in the first segment), which never
//!   collapses a triangle;
//! - the vertices are the least-squares fit of these maps ([`RestSystem`],
//!   factored once for every segment), each connected part placed with its
//!   area-weighted centroid on the straight line between the keys'
//!   centroids; but a separate part that keeps its place in the part it
//!   sits in (eyes in a head) goes along with the surface around it, its
//!   offset from that surface turned with it, so a head that turns does not
//!   leave its eyes behind.
//!
//! Rotations are measured from `K_0` and continue across keys: each key's
//! branches are chosen by rotation consistency over the mesh
//! ([`Rotations::choose_branches`]), and the seed of a later key takes the
//! branch nearest to the previous key's, so a part that keeps turning keeps
//! turning the same way. Key `j` is at time `s = j`.
#![allow(non_snake_case)]

use std::sync::{Arc, OnceLock};

use rayon::prelude::*;

use super::area_blend::area_blend;
use super::attached::Attached;
use super::outline_lengths::OutlineLengths;
use super::poses::{check_poses, decompose};
use super::rest::{EachTriangle, TriangleRows};
use super::{
    FrameWorkspace, InterpolatorOptions, RestSystem, StretchMode, FRAMES_PER_SOLVE,
    TRIANGLES_PER_STEP as STEP,
};
use crate::error::{Error, Result};
use crate::gradient::TriangleMaps;
use crate::interpolate::rotation::{consistent_rotations, Rotations};
use crate::interpolate::Dimension;
use crate::linalg::lanes::{array, Lanes, Real};
use crate::linalg::matrix::{identity, lerp, mul, Mat};
use crate::linalg::Space;
use crate::mesh::topology::TriangleAdjacency;
use crate::mesh::Mesh;
use crate::outline::{FrameMender, OutlineUntier};

/// Eigenvalues of stretches below this are raised to it before logarithms
/// and powers.
pub(crate) const LOG_FLOOR: f64 = 1e-12;

/// A rotation's logarithm in `D` dimensions.
pub(crate) type Log<const D: usize> = <Space<D> as Rotations<D>>::Log;
type Principal<const D: usize> = <Space<D> as Rotations<D>>::Principal;
type SegmentRotation<const D: usize> = <Space<D> as Rotations<D>>::Segment;
type SegmentTurns<const D: usize> = <Space<D> as Rotations<D>>::SegmentTurns;
type RestFolds<const D: usize> = <Space<D> as TriangleMaps<D>>::RestFolds;
type StretchPowers<const D: usize> = <Space<D> as Rotations<D>>::StretchPowers;

#[derive(Debug)]
pub enum SegmentStretches<const D: usize>
where
    Space<D>: Rotations<D>,
{
    /// `S_1`, for `(1−u) I + u S_1` (first segment).
    FromIdentity(Vec<Mat<D>>),
    /// `(S_j, S_{j+1})`, interpolated linearly.
    Linear(Vec<(Mat<D>, Mat<D>)>),
    /// Either of the two above, folded into each triangle's right-hand side
    /// ([`Sequence::build`]): `(P_0, P_1 − P_0)` with `P_0`, `P_1` the rows of
    /// [`RestSystem::fit_rows`] for the maps `B S_j` and `B S_{j+1}`, and
    /// `B` the segment's starting rotation. The map at `u` is `R_u B S_u`
    /// with `R_u` the rotation from the start and `S_u` linear in `u`, so
    /// its rows are `(P_0 + u (P_1 − P_0)) R_uᵀ`: a frame turns three
    /// precomputed rows instead of multiplying the stretch, the rotations
    /// and the gradient operator.
    Fitted(Vec<[[[f64; D]; 3]; 2]>),
    /// `S_1ᵘ` (first segment, log mode).
    Power(Vec<StretchPowers<D>>),
    /// `(log S_j, log S_{j+1})`, interpolated linearly, then exponentiated.
    LogLinear(Vec<(Mat<D>, Mat<D>)>),
    /// `(S_j, S_{j+1})` (the identity first), blended with their areas
    /// kept ([`area_blend`]; planar only).
    AreaBlend(Vec<(Mat<D>, Mat<D>)>),
}

#[derive(Debug)]
pub struct Segment<const D: usize>
where
    Space<D>: Rotations<D>,
{
    pub rotations: Vec<SegmentRotation<D>>,
    /// What the rotations share ([`Rotations::turns_at`] once a frame).
    pub turns: SegmentTurns<D>,
    pub stretches: SegmentStretches<D>,
    /// Whether the segment starts at key 0.
    pub first: bool,
}

impl<const D: usize> SegmentStretches<D>
where
    Space<D>: Dimension<D>,
{
    /// Triangle `t`'s stretch a fraction `u` along the segment, for the
    /// stretches made per triangle and frame (not folded into rows).
    #[inline]
    fn of_triangle(&self, t: usize, u: f64) -> Mat<D> {
        match self {
            Self::Power(v) => Space::<D>::stretch_power(&v[t], u, LOG_FLOOR),
            Self::LogLinear(v) => Space::<D>::stretch_exp(&lerp(&v[t].0, &v[t].1, u)),
            Self::AreaBlend(v) => planar_area_blend(&v[t].0, &v[t].1, u),
            Self::FromIdentity(_) | Self::Linear(_) | Self::Fitted(_) => {
                unreachable!("linear stretches are folded into rows when the sequence is built")
            }
        }
    }
}

impl<const D: usize> Segment<D>
where
    Space<D>: Dimension<D>,
{
    /// The segment with its linear stretches folded into the right-hand
    /// side of `rest` ([`SegmentStretches::Fitted`]).
    fn fitted(self, rest: &RestSystem<D>) -> Self {
        let rotations = &self.rotations;
        let fit = |t: usize, a: &Mat<D>, b: &Mat<D>| {
            let B = Space::<D>::segment_start(&rotations[t]);
            let (from, to) = (rest.fit_rows(t, &mul(B, *a)), rest.fit_rows(t, &mul(B, *b)));
            [
                from,
                std::array::from_fn(|k| std::array::from_fn(|m| to[k][m] - from[k][m])),
            ]
        };
        let stretches = match &self.stretches {
            SegmentStretches::FromIdentity(v) => SegmentStretches::Fitted(
                v.par_iter()
                    .enumerate()
                    .map(|(t, S)| fit(t, &identity(), S))
                    .collect(),
            ),
            SegmentStretches::Linear(v) => SegmentStretches::Fitted(
                v.par_iter()
                    .enumerate()
                    .map(|(t, (a, b))| fit(t, a, b))
                    .collect(),
            ),
            _ => return self,
        };
        Self { stretches, ..self }
    }
}

/// The rows of the right-hand side of triangles with folded rows `fit`
/// ([`SegmentStretches::Fitted`]) fractions `u` along their segment, `turn`
/// their rotation from the segment's start there: `(P_0 + u (P_1 − P_0))
/// turnᵀ`, one triangle and time per lane.
#[inline(always)]
fn fitted_rows<const D: usize, const L: usize>(
    fit: [&[[[f64; D]; 3]; 2]; L],
    turn: &[[Lanes<L>; D]; D],
    u: Lanes<L>,
) -> [[Lanes<L>; D]; 3] {
    // Plain loops: closures here may be left out of line, and then run
    // without the vector instructions of the frame's pass.
    let mut rows = [[Lanes::splat(0.0); D]; 3];
    for (k, out) in rows.iter_mut().enumerate() {
        let mut row = [Lanes::splat(0.0); D];
        for (m, row) in row.iter_mut().enumerate() {
            for (l, x) in row.0.iter_mut().enumerate() {
                *x = fit[l][0][k][m] + u.0[l] * fit[l][1][k][m];
            }
        }
        for (i, out) in out.iter_mut().enumerate() {
            let mut sum = turn[i][0] * row[0];
            for m in 1..D {
                sum = sum + turn[i][m] * row[m];
            }
            *out = sum;
        }
    }
    rows
}

/// [`fitted_rows`] of the triangles from `first` on of segment `seg`
/// (`rows.len() / F` of them, at most `L / F`), whose folded rows are
/// `fits`, in `F` frames at the fractions `us` with the segment's whole
/// turns `turns_at` at each: those of triangle `first + i` in frame `f` into
/// `rows[i * F + f]`. Lane `l` holds triangle `l / F` in frame `l % F`; lanes
/// beyond the triangles repeat the last one.
#[inline(always)]
pub fn fitted_rows_of_step<const D: usize, const F: usize, const L: usize>(
    seg: &Segment<D>,
    fits: &[[[[f64; D]; 3]; 2]],
    first: usize,
    turns_at: &[Vec<[f64; 4]>],
    us: &[f64],
    rows: &mut [[[f64; D]; 3]],
) where
    Space<D>: Rotations<D>,
{
    debug_assert!(L.is_multiple_of(F) && rows.len() <= L && rows.len().is_multiple_of(F));
    let last = first + rows.len() / F - 1;
    let triangle = |l: usize| (first + l / F).min(last);
    let u = Lanes::<L>(array(|l| us[l % F]));
    let turn = Space::<D>::turn_at(
        array(|l| &seg.rotations[triangle(l)]),
        array(|l| turns_at[l % F].as_slice()),
        u,
    );
    let fitted = fitted_rows(array(|l| &fits[triangle(l)]), &turn, u);
    for (l, rows) in rows.iter_mut().enumerate() {
        for (row, fitted) in rows.iter_mut().zip(&fitted) {
            for (x, lanes) in row.iter_mut().zip(fitted) {
                *x = lanes.0[l];
            }
        }
    }
}

/// The rows of a segment's triangles with folded rows `fits` in the frames
/// at fractions `us` along it, with the segment's whole turns `turns_at` at
/// each ([`fitted_rows_of_step`]).
struct FittedRows<'a, const D: usize>
where
    Space<D>: Rotations<D>,
{
    seg: &'a Segment<D>,
    fits: &'a [[[[f64; D]; 3]; 2]],
    turns_at: &'a [Vec<[f64; 4]>],
    us: &'a [f64],
}

impl<const D: usize> TriangleRows<D> for FittedRows<'_, D>
where
    Space<D>: Rotations<D>,
{
    #[inline(always)]
    fn rows(&self, first: usize, rows: &mut [[[f64; D]; 3]]) {
        let Self {
            seg,
            fits,
            turns_at,
            us,
        } = *self;
        match us.len() {
            1 => fitted_rows_of_step::<D, 1, STEP>(seg, fits, first, turns_at, us, rows),
            2 => fitted_rows_of_step::<D, 2, { 2 * STEP }>(seg, fits, first, turns_at, us, rows),
            _ => unreachable!("at most {FRAMES_PER_SOLVE} frames at once"),
        }
    }
}

/// A keyframe sequence of meshes in the plane (`D = 2`) or surfaces in
/// space (`D = 3`): as-rigid-as-possible frames through every key (see the
/// module documentation). Two keys make an interpolation from the first
/// (`s = 0`) to the second (`s = 1`), the same as [`Interpolator`](crate::Interpolator).
///
/// Everything that does not depend on `s` is computed in
/// [`Sequence::new`]; [`Sequence::at`] cannot fail.
///
/// ```
/// use meshmorph::{shapes, InterpolatorOptions, Sequence};
///
/// // A tube bent through 540 degrees: the frame halfway is bent through 270.
/// let tube = shapes::tube(10.0, 0.2, 81, 8);
/// let bent = shapes::bend(&tube, 10.0, 3.0 * std::f64::consts::PI);
/// let morph = Sequence::new(&[tube, bent], &InterpolatorOptions::default())?;
/// let halfway = morph.at(0.5);
/// assert_eq!(morph.count_turned_over(&halfway), 0);
/// # Ok::<(), meshmorph::Error>(())
/// ```
#[derive(Debug)]
pub struct Sequence<const D: usize>
where
    Space<D>: Rotations<D>,
{
    pub rest: Arc<RestSystem<D>>,
    pub adjacency: TriangleAdjacency,
    /// For [`Sequence::count_turned_over`], made at its first call.
    rest_folds: OnceLock<RestFolds<D>>,
    pub segments: Vec<Segment<D>>,
    /// Centroid of each part in each key.
    centroids: Vec<Vec<[f64; D]>>,
    /// The parts that follow their anchors between keys.
    attached: Attached,
    /// Each anchored part's offset from its anchors in each key (in the
    /// anchors' frame of the first key).
    offsets: Vec<Vec<[f64; D]>>,
    /// The positions of every key after the first (the first is the rest
    /// system's source): frames at the keys' times are the keys themselves,
    /// to the bit, and the vertices no triangle uses move on straight lines
    /// between them.
    later: Vec<Vec<[f64; D]>>,
    /// Unties the frames' outlines where they knot
    /// ([`InterpolatorOptions::untie_outlines`]; planar only).
    untier: Option<OutlineUntier>,
    /// Mends the frames where triangles turn over
    /// ([`InterpolatorOptions::mend_folds`]; planar only).
    mender: Option<FrameMender>,
    /// Gives the frames' outlines their blended lengths
    /// ([`InterpolatorOptions::outline_lengths`]; planar only).
    lengths: Option<OutlineLengths>,
}

impl<const D: usize> Sequence<D>
where
    Space<D>: Dimension<D>,
{
    /// Prepares the sequence through `keys` (at least two), factoring the
    /// system of the first.
    ///
    /// # Errors
    /// - [`Error::InvalidArgument`] for fewer than two keys, or `turns` other
    ///   than 0 with more than two keys or in space (whole extra turns need
    ///   a common axis: two planar keys only);
    /// - [`Error::Mismatch`] naming the first key whose vertex or triangle
    ///   count differs from the first key's, [`Error::TriangleMismatch`] the
    ///   first key and triangle whose corners differ;
    /// - [`Error::DegenerateTriangles`] for zero-area triangles of the first key;
    /// - [`Error::ReflectedTriangles`] for triangles of a key turned over
    ///   relative to the first (unless [`InterpolatorOptions::allow_flips`]);
    /// - [`Error::Solver`] if the system cannot be factored.
    pub fn new(keys: &[Mesh<D>], options: &InterpolatorOptions) -> Result<Self> {
        <Space<D> as Dimension<D>>::new_sequence(keys, options)
    }

    /// The work of [`Self::new`], instantiated for each dimension in
    /// `dimension.rs`.
    pub(super) fn new_generic(keys: &[Mesh<D>], options: &InterpolatorOptions) -> Result<Self> {
        let Some(first) = keys.first() else {
            return Err(Error::InvalidArgument(
                "a sequence needs at least two keys".into(),
            ));
        };
        RestSystem::check_rest(first, "first key")?;
        let adjacency = TriangleAdjacency::new(first.triangles());
        check_poses(first, &adjacency, &keys[1..], "key", options)?;
        Self::with_checked_first(first, "first key", adjacency, &keys[1..], options).map(|(s, _)| s)
    }

    /// The sequence from `first` (called `name` in messages, its triangles
    /// checked) through `later_keys` (checked against it), factoring the
    /// system of `first` while the per-triangle work runs beside it; with
    /// the logarithms of the last key's rotations.
    pub(super) fn with_checked_first(
        first: &Mesh<D>,
        name: &str,
        adjacency: TriangleAdjacency,
        later_keys: &[Mesh<D>],
        options: &InterpolatorOptions,
    ) -> Result<(Self, Vec<Log<D>>)> {
        check_arguments::<D>(later_keys.len(), options)?;
        // The factorization and the per-triangle work are independent.
        let (rest, segments) = rayon::join(
            || RestSystem::named(first, name, options.factor),
            || segments(first, &adjacency, later_keys, options),
        );
        let rest = Arc::new(rest?);
        let (segments, last) = segments?;
        let lengths = outline_lengths(&rest, later_keys, options)?;
        let mut sequence = Self::build(rest, adjacency, later_keys, segments);
        (sequence.untier, sequence.mender) = menders(first, options);
        sequence.lengths = lengths;
        Ok((sequence, last))
    }

    /// The sequence from the rest system's source (key 0) through
    /// `later_keys`: any number of sequences, blends and interpolations can
    /// share one factorization.
    ///
    /// # Errors
    /// As [`Sequence::new`].
    pub fn with_surface(
        rest: Arc<RestSystem<D>>,
        later_keys: &[Mesh<D>],
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        <Space<D> as Dimension<D>>::sequence_with_surface(rest, later_keys, options)
    }

    /// The work of [`Self::with_surface`], instantiated for each dimension in
    /// `dimension.rs`.
    pub(super) fn with_surface_generic(
        rest: Arc<RestSystem<D>>,
        later_keys: &[Mesh<D>],
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        let adjacency = TriangleAdjacency::new(rest.source().triangles());
        check_poses(rest.source(), &adjacency, later_keys, "key", options)?;
        Self::with_checked_keys(rest, adjacency, later_keys, options).map(|(s, _)| s)
    }

    /// [`Sequence::with_surface`] for keys already checked, with the
    /// logarithms of the last key's rotations.
    pub(super) fn with_checked_keys(
        rest: Arc<RestSystem<D>>,
        adjacency: TriangleAdjacency,
        later_keys: &[Mesh<D>],
        options: &InterpolatorOptions,
    ) -> Result<(Self, Vec<Log<D>>)> {
        let (segments, last) = segments(rest.source(), &adjacency, later_keys, options)?;
        let (untier, mender) = menders(rest.source(), options);
        let lengths = outline_lengths(&rest, later_keys, options)?;
        let mut sequence = Self::build(rest, adjacency, later_keys, segments);
        (sequence.untier, sequence.mender, sequence.lengths) = (untier, mender, lengths);
        Ok((sequence, last))
    }

    fn build(
        rest: Arc<RestSystem<D>>,
        adjacency: TriangleAdjacency,
        later: &[Mesh<D>],
        segments: Vec<Segment<D>>,
    ) -> Self {
        // The linear stretches are folded into the right-hand side here, where
        // the rest system is at hand.
        let segments = segments
            .into_iter()
            .map(|segment| segment.fitted(&rest))
            .collect();
        let first = rest.source().positions();
        let keys = || std::iter::once(first).chain(later.iter().map(Mesh::positions));
        let centroids: Vec<_> = keys().map(|k| rest.centroids(k)).collect();
        let key_offsets: Vec<_> = keys()
            .zip(&centroids)
            .map(|(k, c)| rest.anchors.offsets(first, k, c))
            .collect();
        let attached = rest.anchors.attached(&key_offsets);
        let later = later.iter().map(|k| k.positions().to_vec()).collect();
        let offsets = key_offsets
            .iter()
            .map(|k| k.iter().map(|o| o.local).collect())
            .collect();
        Self {
            rest,
            adjacency,
            rest_folds: OnceLock::new(),
            segments,
            centroids,
            attached,
            offsets,
            later,
            untier: None,
            mender: None,
            lengths: None,
        }
    }

    /// The rest system (key 0's), to share with other sequences, blends and
    /// interpolations.
    pub fn surface(&self) -> &Arc<RestSystem<D>> {
        &self.rest
    }

    /// For each segment (key `j` to `j + 1`), how many triangles take whole
    /// turns beyond the shortest way: 0 wherever no part turns by more than
    /// half a turn.
    pub fn triangles_with_whole_turns(&self) -> Vec<usize> {
        <Space<D> as Dimension<D>>::sequence_whole_turns(self)
    }

    /// The work of [`Self::triangles_with_whole_turns`], instantiated for each dimension in
    /// `dimension.rs`.
    pub(super) fn triangles_with_whole_turns_generic(&self) -> Vec<usize> {
        self.segments
            .iter()
            .map(|s| {
                s.rotations
                    .iter()
                    .filter(|r| Space::<D>::has_whole_turns(r))
                    .count()
            })
            .collect()
    }

    /// Number of connected parts of the mesh.
    pub fn num_parts(&self) -> usize {
        self.rest.num_components()
    }

    /// Number of separate parts that follow the part they sit in between
    /// keys (eyes in a head that turns), rather than moving their centroids
    /// on straight lines: see the module documentation.
    pub fn parts_following_host(&self) -> usize {
        self.attached.count()
    }

    /// Number of keys (the last one is at `s = num_keys() − 1`).
    pub fn num_keys(&self) -> usize {
        self.segments.len() + 1
    }

    /// Number of vertices of every frame.
    pub fn num_vertices(&self) -> usize {
        self.rest.num_vertices()
    }

    /// The triangles shared by every frame.
    pub fn triangles(&self) -> &[[u32; 3]] {
        self.rest.source().triangles()
    }

    /// Scratch for [`Sequence::at_into`]; one per thread.
    pub fn workspace(&self) -> FrameWorkspace<D> {
        self.rest.workspace()
    }

    /// Vertex positions at time `s`: key `j` at `s = j` (its positions
    /// exactly); times before 0 or after the last key extrapolate the first
    /// or last segment.
    pub fn at(&self, s: f64) -> Vec<[f64; D]> {
        let mut out = vec![[0.0; D]; self.num_vertices()];
        self.at_into(s, &mut out, &mut self.workspace());
        out
    }

    /// Frames at each of `times`, computed in parallel: each thread takes
    /// an equal share of the times, with one scratch for all of them
    /// ([`Sequence::frames_with`]).
    pub fn frames(&self, times: &[f64]) -> Vec<Vec<[f64; D]>> {
        <Space<D> as Dimension<D>>::sequence_frames(self, times)
    }

    /// The work of [`Self::frames`], instantiated for each dimension in
    /// `dimension.rs`.
    pub(super) fn frames_generic(&self, times: &[f64]) -> Vec<Vec<[f64; D]>> {
        let share = times.len().div_ceil(rayon::current_num_threads()).max(1);
        times
            .par_chunks(share)
            .flat_map_iter(|times| self.frames_with(times, &mut self.workspace()))
            .collect()
    }

    /// The frames at `times`, on this thread, with a caller's scratch
    /// ([`Sequence::frames_into`] into new buffers).
    pub fn frames_with(&self, times: &[f64], ws: &mut FrameWorkspace<D>) -> Vec<Vec<[f64; D]>> {
        let mut frames = vec![vec![[0.0; D]; self.num_vertices()]; times.len()];
        let mut outs: Vec<&mut [[f64; D]]> = frames.iter_mut().map(Vec::as_mut_slice).collect();
        self.frames_into(times, &mut outs, ws);
        frames
    }

    /// [`Sequence::at`] into a caller's buffer, with a caller's scratch.
    ///
    /// # Panics
    /// If `out.len()` is not the number of vertices.
    #[track_caller]
    pub fn at_into(&self, s: f64, out: &mut [[f64; D]], ws: &mut FrameWorkspace<D>) {
        self.frames_into(&[s], &mut [out], ws);
    }

    /// The frames at `times` into the caller's buffers `outs` (one per
    /// time), with a caller's scratch. Consecutive times within one segment
    /// are solved together, up to [`FRAMES_PER_SOLVE`] at once: one pass
    /// over the triangles and one substitution for all of them, which takes
    /// less time than solving them one by one.
    ///
    /// # Panics
    /// If `outs` does not have one buffer per time, or a buffer's length is
    /// not the number of vertices.
    #[track_caller]
    pub fn frames_into(
        &self,
        times: &[f64],
        outs: &mut [&mut [[f64; D]]],
        ws: &mut FrameWorkspace<D>,
    ) {
        <Space<D> as Dimension<D>>::sequence_frames_into(self, times, outs, ws)
    }

    /// The work of [`Self::frames_into`], instantiated for each dimension in
    /// `dimension.rs`.
    #[track_caller]
    pub(super) fn frames_into_generic(
        &self,
        times: &[f64],
        outs: &mut [&mut [[f64; D]]],
        ws: &mut FrameWorkspace<D>,
    ) {
        assert_eq!(times.len(), outs.len(), "one buffer per time");
        let mut group: Option<(usize, usize)> = None;
        for (k, &s) in times.iter().enumerate() {
            let (j, u) = self.locate(s);
            if let Some((start, segment)) = group {
                if segment != j || k - start == FRAMES_PER_SOLVE || u == 0.0 || u == 1.0 {
                    self.segment_frames(segment, &times[start..k], &mut outs[start..k], ws);
                    group = None;
                }
            }
            if u == 0.0 || u == 1.0 {
                outs[k].copy_from_slice(self.key(j + u as usize));
            } else if group.is_none() {
                group = Some((k, j));
            }
        }
        if let Some((start, segment)) = group {
            let end = times.len();
            self.segment_frames(segment, &times[start..end], &mut outs[start..end], ws);
        }
    }

    /// The segment of time `s` and the time `u` within it.
    fn locate(&self, s: f64) -> (usize, f64) {
        let last = self.segments.len() - 1;
        let j = if s.is_nan() {
            0
        } else {
            (s.floor().max(0.0) as usize).min(last)
        };
        (j, s - j as f64)
    }

    /// The frames at `times` (at most [`FRAMES_PER_SOLVE`]), all within
    /// segment `j` and none at a key, solved together.
    fn segment_frames(
        &self,
        j: usize,
        times: &[f64],
        outs: &mut [&mut [[f64; D]]],
        ws: &mut FrameWorkspace<D>,
    ) {
        let us: Vec<f64> = times.iter().map(|&s| s - j as f64).collect();
        let seg = &self.segments[j];
        let between = |f: usize, a: [f64; D], b: [f64; D]| -> [f64; D] {
            std::array::from_fn(|k| (1.0 - us[f]) * a[k] + us[f] * b[k])
        };
        // Each part's centroid is on its straight path.
        let (from, to) = (&self.centroids[j], &self.centroids[j + 1]);
        let centroid = |f: usize, c: usize| between(f, from[c], to[c]);
        let (from, to) = (&self.offsets[j], &self.offsets[j + 1]);
        let offset = |f: usize, i: usize| between(f, from[i], to[i]);
        let attached = &self.attached;
        let mut turns_at = std::mem::take(&mut ws.turns);
        turns_at.resize_with(us.len(), Vec::new);
        for (turns, &u) in turns_at.iter_mut().zip(&us) {
            Space::<D>::turns_at(&seg.turns, u, turns);
        }
        let rot = |f: usize, t: usize| {
            Space::<D>::segment_at(&seg.rotations[t], &turns_at[f], us[f], seg.first)
        };
        let rest = &*self.rest;
        match &seg.stretches {
            SegmentStretches::Fitted(fits) => rest.solve_frames(
                FittedRows {
                    seg,
                    fits,
                    turns_at: &turns_at,
                    us: &us,
                },
                centroid,
                attached,
                offset,
                outs,
                ws,
            ),
            stretches => rest.solve_frames(
                EachTriangle {
                    frames: us.len(),
                    rows_of: |t, f| {
                        let S = stretches.of_triangle(t, us[f]);
                        rest.fit_rows(t, &mul(rot(f, t), S))
                    },
                },
                centroid,
                attached,
                offset,
                outs,
                ws,
            ),
        }
        let (from, to) = (self.key(j), self.key(j + 1));
        for &v in rest.loose_vertices() {
            let (a, b) = (from[v as usize], to[v as usize]);
            for (f, out) in outs.iter_mut().enumerate() {
                // A vertex that does not move stays exactly where it is.
                let c = between(f, a, b);
                out[v as usize] = std::array::from_fn(|i| if a[i] == b[i] { a[i] } else { c[i] });
            }
        }
        if self.lengths.is_some() || self.untier.is_some() || self.mender.is_some() {
            // All three exist for planar sequences only.
            for (out, &u) in outs.iter_mut().zip(&us) {
                self.shape_frame(j, u, bytemuck::cast_slice_mut(out), &mut ws.outline);
            }
        }
        ws.turns = turns_at;
    }

    /// Gives the planar frame `out` at time `u` of segment `j` its
    /// outline's blended lengths, unties its knots and mends its folds, as
    /// the options ask: the outline first, since straightening a knot can
    /// turn triangles over that the mending then puts right. Where the
    /// outline with the blended lengths still crosses itself once untied
    /// (two far places of it pushed together, which untying leaves), or
    /// leaves triangles turned over that the mending cannot put right, the
    /// frame goes back towards the fit's, to half, a quarter, then none of
    /// the change (the frame is linear in it), until it is simple and
    /// mended. `rows` is scratch.
    fn shape_frame(&self, j: usize, u: f64, out: &mut [[f64; 2]], rows: &mut Vec<[f64; 2]>) {
        let untie = |out: &mut [[f64; 2]]| self.untier.as_ref().map_or(0, |u| u.untie(out));
        let mend = |out: &mut [[f64; 2]]| self.mender.as_ref().map_or(0, |m| m.mend(out));
        let Some(lengths) = &self.lengths else {
            untie(out);
            mend(out);
            return;
        };
        if self.untier.is_none() && self.mender.is_none() {
            lengths.apply(j, u, out, rows);
            return;
        }
        let fitted = out.to_vec();
        lengths.apply(j, u, out, rows);
        let lengthened = out.to_vec();
        for share in [1.0, 0.5, 0.25, 0.0] {
            if share < 1.0 {
                for (o, (f, l)) in out.iter_mut().zip(fitted.iter().zip(&lengthened)) {
                    *o = std::array::from_fn(|i| f[i] + share * (l[i] - f[i]));
                }
            }
            // The fit's own frame (share 0) is untied and mended as well as
            // they can.
            let fits = share == 0.0;
            if untie(out) > 0 && !fits {
                continue;
            }
            if mend(out) == 0 || fits {
                return;
            }
        }
    }

    /// The positions of key `j`.
    fn key(&self, j: usize) -> &[[f64; D]] {
        match j {
            0 => self.rest.source().positions(),
            _ => &self.later[j - 1],
        }
    }

    /// Number of triangles of `positions` turned over relative to the first
    /// key (in the plane reversed; in space folded back onto their
    /// neighbours; or collapsed).
    pub fn count_turned_over(&self, positions: &[[f64; D]]) -> usize {
        <Space<D> as Dimension<D>>::sequence_turned_over(self, positions)
    }

    /// The work of [`Self::count_turned_over`], instantiated for each dimension in
    /// `dimension.rs`.
    pub(super) fn count_turned_over_generic(&self, positions: &[[f64; D]]) -> usize {
        let source = self.rest.source();
        let folds = self
            .rest_folds
            .get_or_init(|| Space::<D>::rest_folds(source, &self.adjacency));
        Space::<D>::turned_over(source, &self.adjacency, folds, positions).len()
    }
}

/// The untier and the mender of frames of `first`'s triangles, each when
/// the options ask for it and the meshes are planar (and `first`'s
/// boundary is simple loops, its triangles all run one way).
fn menders<const D: usize>(
    first: &Mesh<D>,
    options: &InterpolatorOptions,
) -> (Option<OutlineUntier>, Option<FrameMender>) {
    if D != 2 {
        return (None, None);
    }
    let positions: &[[f64; 2]] = bytemuck::cast_slice(first.positions());
    (
        options
            .untie_outlines
            .then(|| OutlineUntier::new(first.triangles()))
            .flatten(),
        options
            .mend_folds
            .then(|| FrameMender::new(positions, first.triangles()))
            .flatten(),
    )
}

/// What gives the frames of `rest`'s source through `later` keys their
/// blended outline lengths (or, with
/// [`InterpolatorOptions::outline_straight`], their outline on the
/// straight blend of the keys'), when the options ask for it and the
/// meshes are planar (and the source's boundary is simple loops).
///
/// # Errors
/// [`Error::Solver`] when the system with the outline held cannot be
/// factored.
fn outline_lengths<const D: usize>(
    rest: &RestSystem<D>,
    later: &[Mesh<D>],
    options: &InterpolatorOptions,
) -> Result<Option<OutlineLengths>>
where
    Space<D>: Dimension<D>,
{
    if D != 2 || !(options.outline_lengths || options.outline_straight) {
        return Ok(None);
    }
    let keys = std::iter::once(rest.source().positions())
        .chain(later.iter().map(Mesh::positions))
        .map(bytemuck::cast_slice::<[f64; D], [f64; 2]>);
    OutlineLengths::new(rest, keys, options.factor, options.outline_straight)
}

/// [`area_blend`] of two planar stretches (`D` is 2: other dimensions are
/// refused by [`check_arguments`]).
#[inline]
fn planar_area_blend<const D: usize>(a: &Mat<D>, b: &Mat<D>, u: f64) -> Mat<D> {
    let two = |m: &Mat<D>| [[m[0][0], m[0][1]], [m[1][0], m[1][1]]];
    let s = area_blend(&two(a), &two(b), u);
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            if i < 2 && j < 2 {
                s[i][j]
            } else {
                f64::from(u8::from(i == j))
            }
        })
    })
}

/// Refuses what no sequence of `later` keys after the first can take:
/// none, or `turns` beyond two planar keys.
fn check_arguments<const D: usize>(later: usize, options: &InterpolatorOptions) -> Result<()> {
    if later == 0 {
        return Err(Error::InvalidArgument(
            "a sequence needs at least two keys".into(),
        ));
    }
    if options.stretch == StretchMode::AreaBlend && D != 2 {
        return Err(Error::InvalidArgument(
            "the stretch mode AreaBlend is for planar meshes: use Linear or Log in space".into(),
        ));
    }
    if options.turns != 0 && (D != 2 || later > 1) {
        return Err(Error::InvalidArgument(
            "whole extra turns need a common axis of rotation and apply to one interpolation: two planar keys only"
                .into(),
        ));
    }
    Ok(())
}

/// The segments between consecutive keys (see the module documentation),
/// and the logarithms of the last key's rotations.
pub fn segments<const D: usize>(
    rest: &Mesh<D>,
    adjacency: &TriangleAdjacency,
    later: &[Mesh<D>],
    options: &InterpolatorOptions,
) -> Result<(Vec<Segment<D>>, Vec<Log<D>>)>
where
    Space<D>: Dimension<D>,
{
    check_arguments::<D>(later.len(), options)?;
    let num_triangles = rest.num_triangles();
    let areas: Vec<f64> = (0..num_triangles)
        .map(|t| Space::<D>::area(&rest.corners(t)).abs())
        .collect();
    let mut previous_rotations: Vec<Principal<D>> = vec![Space::<D>::IDENTITY; num_triangles];
    let mut previous_logs: Vec<Log<D>> = vec![<Log<D> as Default>::default(); num_triangles];
    let mut previous_stretch = vec![identity::<D>(); num_triangles];
    let mut segments = Vec::with_capacity(later.len());
    for (j, key) in later.iter().enumerate() {
        let maps = decompose(rest, adjacency, key, &format!("key {}", j + 1))?;
        let mut logs: Vec<Log<D>> = if options.consistency {
            let previous = (j > 0).then_some((previous_logs.as_slice(), areas.as_slice()));
            consistent_rotations(rest, adjacency, &maps.rotations, previous)
        } else {
            maps.rotations
                .iter()
                .map(Space::<D>::principal_log)
                .collect()
        };
        if options.turns != 0 {
            logs.iter_mut()
                .for_each(|r| *r = Space::<D>::add_turns(r, options.turns));
        }
        // Whole turns between keys where the branches say so: always from
        // key 0 (its branches are the user's choice), between later keys
        // only with consistency.
        let whole_turns = options.consistency || j == 0;
        let (rotations, turns) = Space::<D>::segments(
            (&previous_rotations, &previous_logs),
            (&maps.rotations, &logs),
            whole_turns,
        );
        let log = |S: &Mat<D>| Space::<D>::stretch_log(S, LOG_FLOOR);
        let stretches = match options.stretch {
            StretchMode::Log if j == 0 => SegmentStretches::Power(
                maps.stretches
                    .par_iter()
                    .map(Space::<D>::stretch_powers)
                    .collect(),
            ),
            StretchMode::Log => SegmentStretches::LogLinear(
                previous_stretch
                    .par_iter()
                    .zip(&maps.stretches)
                    .map(|(a, b)| (log(a), log(b)))
                    .collect(),
            ),
            StretchMode::AreaBlend => SegmentStretches::AreaBlend(
                previous_stretch
                    .iter()
                    .copied()
                    .zip(maps.stretches.iter().copied())
                    .collect(),
            ),
            StretchMode::Linear if j == 0 => SegmentStretches::FromIdentity(maps.stretches.clone()),
            StretchMode::Linear => SegmentStretches::Linear(
                previous_stretch
                    .iter()
                    .copied()
                    .zip(maps.stretches.iter().copied())
                    .collect(),
            ),
        };
        segments.push(Segment {
            rotations,
            turns,
            stretches,
            first: j == 0,
        });
        previous_rotations = maps.rotations;
        previous_logs = logs;
        previous_stretch = maps.stretches;
    }
    Ok((segments, previous_logs))
}

/// How many frames each thread solves together when `count` frames are
/// shared among the threads: as many as [`FRAMES_PER_SOLVE`] allows, but
/// no thread left without frames for it.
pub fn frames_per_solve(count: usize) -> usize {
    count
        .div_ceil(rayon::current_num_threads())
        .clamp(1, FRAMES_PER_SOLVE)
}
