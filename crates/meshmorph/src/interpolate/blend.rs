//! Blends of poses of a mesh, in the plane and in space: a base mesh and any
//! number of shapes (the same triangles), combined with real weights
//! (Baxter, Barla and Anjyo, "Rigid shape interpolation using normal
//! equations", NPAR 2008, section 5).
//!
//! Per triangle, the map from the base to shape `k` is split as
//! `A_k = R_k S_k`; with weights `w_k` the blended map is
//! `exp(Σ w_k log R_k) · exp(Σ w_k log S_k)`, the rotations' logarithms with
//! their branches chosen by rotation consistency as for a two-key
//! interpolation ([`Rotations::choose_branches`](crate::Rotations::choose_branches));
//! in space `exp(Σ w_k c_k) exp(Σ w_k e_k)` with `e_k` the principal
//! rotation vectors and `c_k` their whole turns. Stretches combine by their
//! logarithms (the `Sᵗ` rule of [`StretchMode::Log`](crate::StretchMode::Log)),
//! so any weights, negative or above 1, give positive definite stretches:
//! nothing collapses. One weight 1 and the others 0 gives that shape's maps
//! exactly; a single shape with weight `t` is the interpolation to it with
//! `Sᵗ`. Each connected part's centroid is the base's plus the weighted sum
//! of the shapes' displacements of it, except for separate parts that keep
//! their place in the part they sit in: their offsets from the surface
//! around them are blended, and turn with it (as in a [`Sequence`](crate::Sequence)).
//! The system is factored once for every weight vector.
#![allow(non_snake_case)]

use std::sync::{Arc, OnceLock};

use super::attached::Attached;
use super::poses::{check_poses, decompose};
use super::rest::EachTriangle;
use super::sequence::{Log, LOG_FLOOR};
use super::{FrameWorkspace, InterpolatorOptions, RestSystem};
use crate::error::{Error, Result};
use crate::gradient::TriangleMaps;
use crate::interpolate::rotation::{consistent_rotations, Rotations};
use crate::interpolate::Dimension;
use crate::linalg::matrix::{mul, Mat};
use crate::linalg::Space;
use crate::mesh::topology::TriangleAdjacency;
use crate::mesh::Mesh;

#[derive(Debug)]
struct BlendShape<const D: usize>
where
    Space<D>: Rotations<D>,
{
    /// The rotation of each triangle, its branch chosen.
    logs: Vec<Log<D>>,
    /// `log S` of each triangle.
    stretch_logs: Vec<Mat<D>>,
    centroids: Vec<[f64; D]>,
    /// Each anchored part's offset from its anchors (in the anchors' frame
    /// of the base).
    offsets: Vec<[f64; D]>,
    /// The shape's positions (a weight of 1 on it alone gives them).
    positions: Vec<[f64; D]>,
}

/// A base mesh and shapes to blend with weights, in the plane (`D = 2`) or
/// in space (`D = 3`) (see the module documentation).
///
/// ```
/// use meshmorph::{shapes, Blend, InterpolatorOptions};
///
/// let tube = shapes::tube(4.0, 0.3, 17, 8);
/// let bent = shapes::bend(&tube, 4.0, 1.5);
/// let blend = Blend::new(&tube, &[bent.clone()], &InterpolatorOptions::default())?;
/// let again = blend.at(&[1.0]);
/// let err = again.iter().zip(bent.positions()).map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max)).fold(0.0, f64::max);
/// assert!(err < 1e-9);
/// # Ok::<(), meshmorph::Error>(())
/// ```
#[derive(Debug)]
pub struct Blend<const D: usize>
where
    Space<D>: Rotations<D>,
{
    rest: Arc<RestSystem<D>>,
    adjacency: TriangleAdjacency,
    /// For [`Blend::count_turned_over`], made at its first call.
    rest_folds: OnceLock<<Space<D> as TriangleMaps<D>>::RestFolds>,
    shapes: Vec<BlendShape<D>>,
    base_centroids: Vec<[f64; D]>,
    /// The parts that follow their anchors.
    attached: Attached,
    base_offsets: Vec<[f64; D]>,
}

impl<const D: usize> Blend<D>
where
    Space<D>: Dimension<D>,
{
    /// Prepares blends of `shapes` relative to `base`, factoring the base's
    /// system. Of the options, `consistency`, `allow_flips` and `factor`
    /// apply (stretches always combine by logarithms).
    ///
    /// # Errors
    /// - [`Error::InvalidArgument`] when there is no shape;
    /// - [`Error::Mismatch`] naming the first shape whose vertex or triangle
    ///   count differs from the base's, [`Error::TriangleMismatch`] the first
    ///   shape and triangle whose corners differ;
    /// - [`Error::DegenerateTriangles`] for zero-area triangles of the base;
    /// - [`Error::ReflectedTriangles`] for triangles of a shape turned over
    ///   relative to the base (unless [`InterpolatorOptions::allow_flips`]);
    /// - [`Error::Solver`] if the system cannot be factored.
    pub fn new(base: &Mesh<D>, shapes: &[Mesh<D>], options: &InterpolatorOptions) -> Result<Self> {
        <Space<D> as Dimension<D>>::new_blend(base, shapes, options)
    }

    /// The work of [`Self::new`], instantiated for each dimension in
    /// `dimension.rs`.
    pub(super) fn new_generic(
        base: &Mesh<D>,
        shapes: &[Mesh<D>],
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        check_shape_count(shapes)?;
        RestSystem::check_rest(base, "base")?;
        let adjacency = TriangleAdjacency::new(base.triangles());
        check_poses(base, &adjacency, shapes, "blend shape", options)?;
        let rest = Arc::new(RestSystem::named(base, "base", options.factor)?);
        Self::build(rest, adjacency, shapes, options)
    }

    /// Blends relative to the rest system's source, sharing its
    /// factorization.
    ///
    /// # Errors
    /// As [`Blend::new`].
    pub fn with_surface(
        rest: Arc<RestSystem<D>>,
        shapes: &[Mesh<D>],
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        <Space<D> as Dimension<D>>::blend_with_surface(rest, shapes, options)
    }

    /// The work of [`Self::with_surface`], instantiated for each dimension in
    /// `dimension.rs`.
    pub(super) fn with_surface_generic(
        rest: Arc<RestSystem<D>>,
        shapes: &[Mesh<D>],
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        let adjacency = TriangleAdjacency::new(rest.source().triangles());
        check_poses(rest.source(), &adjacency, shapes, "blend shape", options)?;
        Self::build(rest, adjacency, shapes, options)
    }

    fn build(
        rest: Arc<RestSystem<D>>,
        adjacency: TriangleAdjacency,
        shapes: &[Mesh<D>],
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        check_shape_count(shapes)?;
        let base = rest.source();
        let base_centroids = rest.centroids(base.positions());
        let base_offsets =
            rest.anchors
                .offsets(base.positions(), base.positions(), &base_centroids);
        let shapes: Vec<(BlendShape<D>, Vec<_>)> = shapes
            .iter()
            .enumerate()
            .map(|(k, shape)| {
                let maps = decompose(base, &adjacency, shape, &format!("blend shape {}", k + 1))?;
                let logs = if options.consistency {
                    consistent_rotations(base, &adjacency, &maps.rotations, None)
                } else {
                    maps.rotations
                        .iter()
                        .map(Space::<D>::principal_log)
                        .collect()
                };
                let centroids = rest.centroids(shape.positions());
                let offsets = rest
                    .anchors
                    .offsets(base.positions(), shape.positions(), &centroids);
                Ok((
                    BlendShape {
                        logs,
                        stretch_logs: maps
                            .stretches
                            .iter()
                            .map(|S| Space::<D>::stretch_log(S, LOG_FLOOR))
                            .collect(),
                        centroids,
                        offsets: offsets.iter().map(|o| o.local).collect(),
                        positions: shape.positions().to_vec(),
                    },
                    offsets,
                ))
            })
            .collect::<Result<Vec<_>>>()?;
        let key_offsets: Vec<_> = std::iter::once(base_offsets.clone())
            .chain(shapes.iter().map(|(_, o)| o.clone()))
            .collect();
        let attached = rest.anchors.attached(&key_offsets);
        let shapes = shapes.into_iter().map(|(s, _)| s).collect();
        Ok(Self {
            base_centroids,
            attached,
            base_offsets: base_offsets.iter().map(|o| o.local).collect(),
            rest,
            adjacency,
            rest_folds: OnceLock::new(),
            shapes,
        })
    }

    /// Number of separate parts that follow the part they sit in (see
    /// [`Sequence::parts_following_host`](crate::Sequence::parts_following_host)).
    pub fn parts_following_host(&self) -> usize {
        self.attached.count()
    }

    /// Number of shapes (the length of every weight vector).
    pub fn num_shapes(&self) -> usize {
        self.shapes.len()
    }

    /// Number of vertices of every blend.
    pub fn num_vertices(&self) -> usize {
        self.rest.num_vertices()
    }

    /// The triangles shared by every blend.
    pub fn triangles(&self) -> &[[u32; 3]] {
        self.rest.source().triangles()
    }

    /// The rest system (the base's), to share with sequences and other
    /// blends.
    pub fn surface(&self) -> &Arc<RestSystem<D>> {
        &self.rest
    }

    /// Scratch for [`Blend::at_into`]; one per thread.
    pub fn workspace(&self) -> FrameWorkspace<D> {
        self.rest.workspace()
    }

    /// The blend with one weight per shape (any real numbers; all zero is
    /// the base, a weight of 1 on one shape and 0 on the others that shape,
    /// exactly).
    ///
    /// # Panics
    /// If `weights.len()` is not the number of shapes.
    #[track_caller]
    pub fn at(&self, weights: &[f64]) -> Vec<[f64; D]> {
        let mut out = vec![[0.0; D]; self.num_vertices()];
        self.at_into(weights, &mut out, &mut self.workspace());
        out
    }

    /// [`Blend::at`] into a caller's buffer, with a caller's scratch.
    ///
    /// # Panics
    /// If `weights` or `out` has the wrong length.
    #[track_caller]
    pub fn at_into(&self, weights: &[f64], out: &mut [[f64; D]], ws: &mut FrameWorkspace<D>) {
        <Space<D> as Dimension<D>>::blend_at_into(self, weights, out, ws)
    }

    /// The work of [`Self::at_into`], instantiated for each dimension in
    /// `dimension.rs`.
    #[track_caller]
    pub(super) fn at_into_generic(
        &self,
        weights: &[f64],
        out: &mut [[f64; D]],
        ws: &mut FrameWorkspace<D>,
    ) {
        assert_eq!(weights.len(), self.shapes.len(), "one weight per shape");
        // No weight, or a weight of 1 on one shape alone: the base or that
        // shape, to the bit.
        if weights.iter().all(|&w| w == 0.0 || w == 1.0)
            && weights.iter().filter(|&&w| w == 1.0).count() <= 1
        {
            let exact = weights.iter().position(|&w| w == 1.0);
            let positions = exact.map_or(self.rest.source().positions(), |k| {
                &self.shapes[k].positions
            });
            out.copy_from_slice(positions);
            return;
        }
        let active: Vec<(f64, &BlendShape<D>)> = weights
            .iter()
            .zip(&self.shapes)
            .filter(|(w, _)| **w != 0.0)
            .map(|(&w, s)| (w, s))
            .collect();
        // The base's point plus the weighted displacements of the shapes'.
        let blended = |base: [f64; D], of_shape: &dyn Fn(&BlendShape<D>) -> [f64; D]| {
            let mut p = base;
            for (w, s) in &active {
                let q = of_shape(s);
                for k in 0..D {
                    p[k] += w * (q[k] - base[k]);
                }
            }
            p
        };
        let centroid = |c: usize| blended(self.base_centroids[c], &|s| s.centroids[c]);
        let map = |t: usize| {
            let (mut R, mut L) = (Log::<D>::default(), [[0.0; D]; D]);
            for (w, s) in &active {
                Space::<D>::add_scaled(&mut R, *w, &s.logs[t]);
                for k in 0..D {
                    for m in 0..D {
                        L[k][m] += w * s.stretch_logs[t][k][m];
                    }
                }
            }
            mul(Space::<D>::exp(&R), Space::<D>::stretch_exp(&L))
        };
        let offset = |i: usize| blended(self.base_offsets[i], &|s| s.offsets[i]);
        self.rest.solve_frames(
            EachTriangle {
                frames: 1,
                rows_of: |t, _| self.rest.fit_rows(t, &map(t)),
            },
            |_, c| centroid(c),
            &self.attached,
            |_, i| offset(i),
            &mut [&mut *out],
            ws,
        );
        let base = self.rest.source().positions();
        for &v in self.rest.loose_vertices() {
            let v = v as usize;
            out[v] = blended(base[v], &|s| s.positions[v]);
        }
    }

    /// Number of triangles of `positions` turned over relative to the base
    /// (in the plane reversed; in space folded back onto their neighbours;
    /// or collapsed).
    pub fn count_turned_over(&self, positions: &[[f64; D]]) -> usize {
        <Space<D> as Dimension<D>>::blend_turned_over(self, positions)
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

/// Refuses a blend of no shape.
fn check_shape_count<const D: usize>(shapes: &[Mesh<D>]) -> Result<()> {
    if shapes.is_empty() {
        return Err(Error::InvalidArgument(
            "a blend needs at least one shape".into(),
        ));
    }
    Ok(())
}
