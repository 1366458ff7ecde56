//! As-rigid-as-possible interpolation of planar shapes.
//!
//! Alexa, Cohen-Or and Levin, "As-rigid-as-possible shape interpolation",
//! SIGGRAPH 2000; with the factor-once normal equations and the rotation
//! consistency of Baxter, Barla and Anjyo, "Rigid shape interpolation using
//! normal equations", NPAR 2008.
//!
//! For each triangle the affine map `A` from source to target is split as
//! `A = R(θ) S`; the map at time `t` is `A(t) = R(tθ) ((1−t) I + t S)`
//! (or `R(tθ) Sᵗ`, see [`StretchMode`]). The vertex positions at `t`
//! minimise `Σ_T area_T ‖J_T(x) − A_T(t)‖²_F`, where `J_T(x)` is the
//! gradient of the piecewise-linear map that sends the source to `x`. Its
//! normal matrix is the cotangent Laplacian of the source, the same for
//! every `t`: it is factored once in [`Interpolator::new`], and each frame
//! is a right-hand side and a back-substitution.

#![allow(non_snake_case)]

mod options;
mod rest;

use std::sync::Arc;

use rayon::prelude::*;

use crate::error::{Error, Result, LIST_LIMIT};
use crate::geometry::centroid;
use crate::gradient::{SolveWorkspace, TriangleMaps};
use crate::matrix::{lerp_from_identity, mul, Mat};
use crate::mesh::Mesh;
use crate::rotation::{make_consistent, Rotations};
use crate::topology::TriangleAdjacency;
use crate::Space;

pub use options::{InterpolatorOptions, StretchMode};
pub use rest::{PreparedSurface, RestSystem};

/// A rotation's logarithm in `D` dimensions.
type Log<const D: usize> = <Space<D> as Rotations<D>>::Log;

/// The per-triangle part of the map that varies with `t`.
#[derive(Clone, Copy, Debug)]
enum Stretch<const D: usize, P> {
    /// `S`, for `(1−t) I + t S`.
    Linear(Mat<D>),
    /// `S` prepared for `Sᵗ`.
    Log(P),
}

type StretchOf<const D: usize> = Stretch<D, <Space<D> as Rotations<D>>::StretchPowers>;

/// Eigenvalues of `S` below this are raised to it before taking powers.
const LOG_FLOOR: f64 = 1e-12;

/// ARAP interpolation between two meshes with the same triangles (planar
/// today: `D = 2`).
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
pub struct Interpolator<const D: usize = 2>
where
    Space<D>: Rotations<D>,
{
    rest: Arc<RestSystem<D>>,
    /// Rotation of each triangle, consistent branch chosen, turns added.
    rotations: Vec<Log<D>>,
    stretches: Vec<StretchOf<D>>,
    /// Per part: source centroid, target centroid.
    centroid_paths: Vec<([f64; D], [f64; D])>,
    /// Target positions of the vertices no triangle uses.
    loose_targets: Vec<[f64; D]>,
}

/// Per-thread scratch for [`Interpolator::at_into`] and
/// [`RestSystem::solve_into`].
#[derive(Debug)]
pub struct FrameWorkspace<const D: usize = 2> {
    solve: SolveWorkspace,
    /// One vector per part: its centroid, then its shift.
    parts: Vec<[f64; D]>,
}

impl<const D: usize> Interpolator<D>
where
    Space<D>: Rotations<D> + TriangleMaps<D>,
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
        source.check_same_connectivity(target, ["the source", "the target"])?;
        let rest = Arc::new(RestSystem::new(source, options.factor)?);
        Self::with_rest(rest, target, options)
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
        let source = &rest.source;
        source.check_same_connectivity(target, ["the source", "the target"])?;
        check_flips(source, target, options.allow_flips)?;
        let (rotations, stretches) = rotations_and_stretches(&rest, target, options);
        let mut source_centroids = vec![[0.0; D]; rest.placement.count()];
        let mut target_centroids = source_centroids.clone();
        rest.placement
            .centroids(source.positions(), &mut source_centroids);
        rest.placement
            .centroids(target.positions(), &mut target_centroids);
        let loose_targets = rest
            .loose
            .iter()
            .map(|&v| target.positions()[v as usize])
            .collect();
        Ok(Self {
            rotations,
            stretches,
            centroid_paths: source_centroids.into_iter().zip(target_centroids).collect(),
            loose_targets,
            rest,
        })
    }

    /// The part of the interpolation that depends on the source alone.
    pub fn rest(&self) -> &Arc<RestSystem<D>> {
        &self.rest
    }

    /// Number of vertices of every frame.
    pub fn num_vertices(&self) -> usize {
        self.rest.source.num_vertices()
    }

    /// The triangles shared by every frame.
    pub fn triangles(&self) -> &[[u32; 3]] {
        self.rest.source.triangles()
    }

    /// The rotation of each triangle from source to target (its logarithm),
    /// with the branch chosen by rotation consistency and the extra turns
    /// added.
    pub fn rotations(&self) -> &[Log<D>] {
        &self.rotations
    }

    /// Scratch for [`Interpolator::at_into`]; one per thread.
    pub fn workspace(&self) -> FrameWorkspace<D> {
        self.rest.workspace()
    }

    /// Vertex positions at time `t`: the source at 0, the target at 1, any
    /// real `t` allowed.
    pub fn at(&self, t: f64) -> Vec<[f64; D]> {
        let mut out = vec![[0.0; D]; self.num_vertices()];
        self.at_into(t, &mut out, &mut self.workspace());
        out
    }

    /// Frames at each of `times`, computed in parallel.
    pub fn frames(&self, times: &[f64]) -> Vec<Vec<[f64; D]>> {
        times
            .par_iter()
            .map_init(
                || self.workspace(),
                |ws, &t| {
                    let mut out = vec![[0.0; D]; self.num_vertices()];
                    self.at_into(t, &mut out, ws);
                    out
                },
            )
            .collect()
    }

    /// [`Interpolator::at`] into a caller's buffer, with a caller's scratch.
    ///
    /// # Panics
    /// If `out.len()` is not the number of vertices.
    #[track_caller]
    pub fn at_into(&self, t: f64, out: &mut [[f64; D]], ws: &mut FrameWorkspace<D>) {
        let rest = &*self.rest;
        // Each part's centroid is on its straight path.
        rest.solve_frame(
            |k| map_at::<D>(t, &self.rotations[k], &self.stretches[k]),
            |c| {
                let (cs, ct) = &self.centroid_paths[c];
                std::array::from_fn(|i| (1.0 - t) * cs[i] + t * ct[i])
            },
            out,
            ws,
        );
        for (&v, b) in rest.loose.iter().zip(&self.loose_targets) {
            let a = rest.source.positions()[v as usize];
            // A vertex that does not move stays exactly where it is.
            out[v as usize] = std::array::from_fn(|i| {
                if a[i] == b[i] {
                    a[i]
                } else {
                    (1.0 - t) * a[i] + t * b[i]
                }
            });
        }
    }

    /// Number of triangles of `positions` whose orientation is reversed
    /// relative to the source (a triangle of zero area counts as reversed).
    pub fn count_flipped(&self, positions: &[[f64; D]]) -> usize {
        let source = &self.rest.source;
        (0..source.num_triangles())
            .filter(|&t| {
                let corners = source.triangles()[t].map(|v| positions[v as usize]);
                Space::<D>::reversed(&source.corners(t), &corners)
            })
            .count()
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
/// unless they are allowed.
fn check_flips<const D: usize>(source: &Mesh<D>, target: &Mesh<D>, allow: bool) -> Result<()>
where
    Space<D>: TriangleMaps<D>,
{
    if allow {
        return Ok(());
    }
    let flipped: Vec<usize> = (0..source.num_triangles())
        .filter(|&t| Space::<D>::reversed(&source.corners(t), &target.corners(t)))
        .collect();
    if !flipped.is_empty() {
        return Err(Error::FlippedTriangles {
            count: flipped.len(),
            first: flipped.into_iter().take(LIST_LIMIT).collect(),
        });
    }
    Ok(())
}

/// The polar decomposition of every triangle's map from source to target:
/// the rotations, made consistent across edges and turned by the extra
/// turns, and the stretches in the form the stretch mode needs.
fn rotations_and_stretches<const D: usize>(
    rest: &RestSystem<D>,
    target: &Mesh<D>,
    options: &InterpolatorOptions,
) -> (Vec<Log<D>>, Vec<StretchOf<D>>)
where
    Space<D>: Rotations<D> + TriangleMaps<D>,
{
    let (mut rotations, stretches): (Vec<Log<D>>, Vec<StretchOf<D>>) = (0..target.num_triangles())
        .map(|t| {
            let (rotation, S) = Space::<D>::polar(&rest.linear_map(t, &target.corners(t)));
            let stretch = match options.stretch {
                StretchMode::Linear => Stretch::Linear(S),
                StretchMode::Log => Stretch::Log(Space::<D>::stretch_powers(&S)),
            };
            (rotation, stretch)
        })
        .unzip();
    if options.consistency {
        // Rotations propagate across edges, so each part connected across
        // edges gets its own seed.
        let adjacency = TriangleAdjacency::new(target.triangles());
        let (parts, count) = adjacency.edge_components();
        let seeds = rotation_seeds(&rotations, &parts, count, &rest.source);
        make_consistent(
            &mut rotations,
            &adjacency,
            &seeds,
            Space::<D>::nearest_branch,
        );
    }
    if options.turns != 0 {
        rotations
            .iter_mut()
            .for_each(|r| *r = Space::<D>::add_turns(r, options.turns));
    }
    (rotations, stretches)
}

/// The map of a triangle at time `t`: `exp(t log R) S(t)`.
#[inline]
fn map_at<const D: usize>(t: f64, rotation: &Log<D>, stretch: &StretchOf<D>) -> Mat<D>
where
    Space<D>: Rotations<D>,
{
    let S = match stretch {
        Stretch::Linear(S) => lerp_from_identity(S, t),
        Stretch::Log(e) => Space::<D>::stretch_power(e, t, LOG_FLOOR),
    };
    mul(Space::<D>::exp(rotation, t), S)
}

/// One seed triangle per part (rotations are principal): the one that turns
/// least, ties broken by the position of its source centroid, so the choice
/// does not depend on how the triangles are numbered.
fn rotation_seeds<const D: usize>(
    rotations: &[Log<D>],
    of_triangle: &[u32],
    count: usize,
    source: &Mesh<D>,
) -> Vec<usize>
where
    Space<D>: Rotations<D>,
{
    let key = |t: usize| {
        (
            Space::<D>::angle(&rotations[t]),
            centroid(source.corners(t)),
        )
    };
    // The best triangle so far with its key (angle, centroid).
    type Best<const D: usize> = Option<(usize, (f64, [f64; D]))>;
    let mut best: Vec<Best<D>> = vec![None; count];
    for (t, &c) in of_triangle.iter().enumerate() {
        let k = key(t);
        let slot = &mut best[c as usize];
        if slot.is_none_or(|(_, b)| k.partial_cmp(&b) == Some(std::cmp::Ordering::Less)) {
            *slot = Some((t, k));
        }
    }
    best.into_iter().flatten().map(|(t, _)| t).collect()
}
