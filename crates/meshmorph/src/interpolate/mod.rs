//! As-rigid-as-possible interpolation of planar meshes and of surfaces in
//! space: two keys ([`Interpolator`]), keyframe sequences ([`Sequence`]) and
//! blends ([`Blend`]), one machinery for both dimensions.
//!
//! Alexa, Cohen-Or and Levin, "As-rigid-as-possible shape interpolation",
//! SIGGRAPH 2000; with the factor-once normal equations, the rotation
//! consistency and the blends of Baxter, Barla and Anjyo, "Rigid shape
//! interpolation using normal equations", NPAR 2008.
//!
//! For each triangle the affine map `A` from source to target is split as
//! `A = R S`; the map at time `t` is `A(t) = R(t) ((1−t) I + t S)` (or
//! `R(t) Sᵗ`, see [`StretchMode`]), `R(t)` the rotation interpolated along
//! its axis by angle. The vertex positions at `t` minimise
//! `Σ_T area_T ‖J_T(x) − A_T(t)‖²_F`, where `J_T(x)` is the gradient of the
//! piecewise-linear map that sends the source to `x` ([`RestSystem`]). Its
//! normal matrix is the cotangent Laplacian of the source, the same for
//! every `t`: it is factored once, and each frame is a right-hand side and
//! a back-substitution. What depends on the dimension is behind
//! [`Rotations`](crate::Rotations) and [`TriangleMaps`].

pub mod area_blend;
pub mod attached;
pub mod blend;
pub mod dimension;
pub mod options;
pub mod outline_lengths;
pub mod poses;
pub mod rest;
pub mod rotation;
pub mod sequence;

use std::sync::Arc;

use crate::error::{Error, Result, LIST_LIMIT};
use crate::gradient::TriangleMaps;
use crate::interpolate::rotation::Rotations;
use crate::linalg::Space;
use crate::mesh::topology::TriangleAdjacency;
use crate::mesh::Mesh;

pub use blend::Blend;
pub use dimension::Dimension;
pub use options::{InterpolatorOptions, StretchMode};
pub use rest::RestSystem;
pub use sequence::{frames_per_solve, Sequence};

use sequence::Log;

/// ARAP interpolation between two meshes with the same triangles, in the
/// plane (`D = 2`, the default) or in space (`D = 3`): a keyframe
/// [`Sequence`] of two keys, with the checks and names of a source and a
/// target.
///
/// Everything that does not depend on `t` is computed in [`Interpolator::new`];
/// [`Interpolator::at`] cannot fail. What depends on the source alone is a
/// [`RestSystem`], which any number of interpolators can share.
///
/// ```
/// use meshmorph::{Interpolator, InterpolatorOptions, Mesh2};
///
/// // A unit square made of two triangles, and the same square turned by 90°.
/// let tris = vec![[0, 1, 2], [0, 2, 3]];
/// let source = Mesh2::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], tris.clone())?;
/// let target = Mesh2::new(vec![[0.0, 0.0], [0.0, 1.0], [-1.0, 1.0], [-1.0, 0.0]], tris)?;
/// let morph = Interpolator::new(&source, &target, &InterpolatorOptions::default())?;
/// let halfway = morph.at(0.5);
/// // Rigid all the way: the diagonal keeps its length.
/// let d = [halfway[2][0] - halfway[0][0], halfway[2][1] - halfway[0][1]];
/// assert!((d[0].hypot(d[1]) - 2f64.sqrt()).abs() < 1e-12);
/// # Ok::<(), meshmorph::Error>(())
/// ```
#[derive(Debug)]
pub struct Interpolator<const D: usize>
where
    Space<D>: Rotations<D>,
{
    /// The two-key sequence from the source to the target.
    sequence: Sequence<D>,
    /// Rotation of each triangle, consistent branch chosen, turns added.
    rotations: Vec<Log<D>>,
}

/// Per-thread scratch for the frames of interpolations, sequences and
/// blends ([`Interpolator::at_into`], [`Sequence::at_into`],
/// [`Blend::at_into`]) and [`RestSystem::solve_into`].
#[derive(Debug)]
pub struct FrameWorkspace<const D: usize = 2> {
    /// The right-hand sides and then the solutions of the frames solved
    /// together, side by side in the rows of the factored system.
    rows: Vec<f64>,
    /// For each frame, one vector per part: its centroid, then its shift.
    parts: Vec<Vec<[f64; D]>>,
    /// For each frame, its rotations of the segment's shared whole turns
    /// ([`Rotations::turns_at`]).
    turns: Vec<Vec<[f64; 4]>>,
    /// The moves of a planar frame's vertices when its outline takes the
    /// blended lengths ([`InterpolatorOptions::outline_lengths`]).
    outline: Vec<[f64; 2]>,
}

/// The most frames solved together ([`Sequence::frames_into`]): one pass
/// over the triangles and one substitution serve them all, reading the
/// factor and the triangles' data once. Two: a frame's own arithmetic (a
/// rotation per triangle) does not shrink with more, while the wider rows
/// of the right-hand side cost more to gather (BENCHMARKS.md).
pub const FRAMES_PER_SOLVE: usize = 2;

/// How many triangles a frame's pass over the triangles takes at a time.
/// A triangle's rotation at a time is one long chain of dependent steps
/// (a sine and cosine, a quaternion, a matrix, its rows); the steps of
/// several triangles side by side keep the processor busy while each waits
/// for the one before.
pub const TRIANGLES_PER_STEP: usize = 4;

impl<const D: usize> Interpolator<D>
where
    Space<D>: Dimension<D>,
{
    /// Prepares the interpolation from `source` (t = 0) to `target` (t = 1).
    ///
    /// # Errors
    /// - [`Error::Mismatch`] when the meshes differ in vertex or triangle
    ///   count, [`Error::TriangleMismatch`] naming the first triangle whose
    ///   corners differ;
    /// - [`Error::DegenerateTriangles`] for zero-area source triangles;
    /// - [`Error::FlippedTriangles`] for triangles reversed (or collapsed to
    ///   zero area) between source and target, unless
    ///   [`InterpolatorOptions::allow_flips`];
    /// - [`Error::Solver`] if the system cannot be factored.
    ///
    /// # Performance
    /// Linear in the number of triangles apart from one sparse Cholesky
    /// factorization of a `#V × #V` matrix ([`RestSystem::new`]).
    pub fn new(source: &Mesh<D>, target: &Mesh<D>, options: &InterpolatorOptions) -> Result<Self> {
        <Space<D> as Dimension<D>>::new_interpolator(source, target, options)
    }

    /// The work of [`Self::new`], instantiated for each dimension in
    /// `dimension.rs`.
    pub(super) fn new_generic(
        source: &Mesh<D>,
        target: &Mesh<D>,
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        source.check_same_connectivity(target, ["the source", "the target"])?;
        RestSystem::check_rest(source, "source")?;
        let adjacency = TriangleAdjacency::new(source.triangles());
        check_flips(source, &adjacency, target, options.allow_flips)?;
        // The factorization runs beside the per-triangle work.
        let (sequence, rotations) = Sequence::with_checked_first(
            source,
            "source",
            adjacency,
            std::slice::from_ref(target),
            options,
        )?;
        Ok(Self {
            sequence,
            rotations,
        })
    }

    /// The interpolation from the source of `rest` to `target`, sharing the
    /// factored system ([`InterpolatorOptions::factor`] is not used).
    ///
    /// # Errors
    /// As [`Interpolator::new`], apart from those of [`RestSystem::new`].
    pub fn with_rest(
        rest: Arc<RestSystem<D>>,
        target: &Mesh<D>,
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        <Space<D> as Dimension<D>>::interpolator_with_rest(rest, target, options)
    }

    /// The work of [`Self::with_rest`], instantiated for each dimension in
    /// `dimension.rs`.
    pub(super) fn with_rest_generic(
        rest: Arc<RestSystem<D>>,
        target: &Mesh<D>,
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        let source = rest.source();
        source.check_same_connectivity(target, ["the source", "the target"])?;
        let adjacency = TriangleAdjacency::new(source.triangles());
        check_flips(source, &adjacency, target, options.allow_flips)?;
        let (sequence, rotations) =
            Sequence::with_checked_keys(rest, adjacency, std::slice::from_ref(target), options)?;
        Ok(Self {
            sequence,
            rotations,
        })
    }

    /// The part of the interpolation that depends on the source alone.
    pub fn rest(&self) -> &Arc<RestSystem<D>> {
        self.sequence.surface()
    }

    /// The interpolation as a keyframe sequence of two keys.
    pub fn sequence(&self) -> &Sequence<D> {
        &self.sequence
    }

    /// Number of vertices of every frame.
    pub fn num_vertices(&self) -> usize {
        self.sequence.num_vertices()
    }

    /// The triangles shared by every frame.
    pub fn triangles(&self) -> &[[u32; 3]] {
        self.sequence.triangles()
    }

    /// The rotation of each triangle from source to target (its logarithm),
    /// with the branch chosen by rotation consistency and the extra turns
    /// added.
    pub fn rotations(&self) -> &[Log<D>] {
        &self.rotations
    }

    /// Scratch for [`Interpolator::at_into`]; one per thread.
    pub fn workspace(&self) -> FrameWorkspace<D> {
        self.sequence.workspace()
    }

    /// Vertex positions at time `t`: the source at 0, the target at 1, any
    /// real `t` allowed.
    pub fn at(&self, t: f64) -> Vec<[f64; D]> {
        self.sequence.at(t)
    }

    /// Frames at each of `times`, computed in parallel.
    pub fn frames(&self, times: &[f64]) -> Vec<Vec<[f64; D]>> {
        self.sequence.frames(times)
    }

    /// [`Interpolator::at`] into a caller's buffer, with a caller's scratch.
    ///
    /// # Panics
    /// If `out.len()` is not the number of vertices.
    #[track_caller]
    pub fn at_into(&self, t: f64, out: &mut [[f64; D]], ws: &mut FrameWorkspace<D>) {
        self.sequence.at_into(t, out, ws)
    }

    /// Number of triangles of `positions` whose orientation is reversed
    /// relative to the source (a triangle of zero area counts as reversed;
    /// in space, turned over relative to its neighbours,
    /// [`TriangleMaps::turned_over`]).
    pub fn count_flipped(&self, positions: &[[f64; D]]) -> usize {
        self.sequence.count_turned_over(positions)
    }
}

impl Interpolator<2> {
    /// Rotation angle of each triangle from source to target, radians,
    /// counter-clockwise, with the branch chosen by rotation consistency and
    /// the extra turns added.
    pub fn angles(&self) -> &[f64] {
        &self.rotations
    }
}

/// Fails on triangles reversed (or collapsed) between source and target,
/// turned over in space, unless they are allowed.
fn check_flips<const D: usize>(
    source: &Mesh<D>,
    adjacency: &TriangleAdjacency,
    target: &Mesh<D>,
    allow: bool,
) -> Result<()>
where
    Space<D>: TriangleMaps<D>,
{
    if allow {
        return Ok(());
    }
    let folds = Space::<D>::rest_folds(source, adjacency);
    let flipped = Space::<D>::turned_over(source, adjacency, &folds, target.positions());
    if !flipped.is_empty() {
        return Err(Error::FlippedTriangles {
            count: flipped.len(),
            first: flipped.into_iter().take(LIST_LIMIT).collect(),
        });
    }
    Ok(())
}
