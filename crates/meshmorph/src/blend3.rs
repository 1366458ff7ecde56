//! Blends of poses of a surface: a base mesh and any number of shapes (the
//! same triangles), combined with real weights (Baxter, Barla and Anjyo,
//! "Rigid shape interpolation using normal equations", NPAR 2008, section 5).
//!
//! Per triangle, the map from the base to shape `k` is split as
//! `A_k = R_k S_k`; with weights `w_k` the blended map is
//! `exp(Σ w_k c_k) exp(Σ w_k e_k) · exp(Σ w_k log S_k)`, where `e_k` is
//! `R_k`'s principal rotation vector and `c_k` its whole turns (chosen by
//! rotation consistency as for a two-key interpolation, see
//! [`crate::consistency3`]). Stretches combine by their logarithms (the
//! `Sᵗ` rule of [`StretchMode::Log`](crate::StretchMode::Log)), so any
//! weights, negative or above 1, give positive definite stretches: nothing
//! collapses. One weight 1 and the others 0 gives that shape's maps
//! exactly; a single shape with weight `t` is the interpolation to it with
//! `Sᵗ`. Each connected part's centroid is the base's plus the weighted sum
//! of the shapes' displacements of it; the system is factored once for
//! every weight vector.
#![allow(non_snake_case)]

use std::sync::Arc;

use crate::consistency3::whole_turns;
use crate::error::{Error, Result};
use crate::interpolate::{InterpolatorOptions, PreparedSurface};
use crate::matrix::{mul as mul3, Mat3};
use crate::mesh::Mesh3;
use crate::polar3::SymmetricEigen3;
use crate::pose3::{shared_edge_length, RestFrames};
use crate::rotation3::{quat_exp, quat_log, quat_mul, quat_to_matrix};
use crate::sequence3::{check_poses, SequenceWorkspace, LOG_FLOOR};

#[derive(Debug)]
struct BlendShape {
    /// Whole-turn vector of each triangle.
    turns: Vec<[f64; 3]>,
    /// Principal rotation vector of each triangle.
    logs: Vec<[f64; 3]>,
    /// `log S` of each triangle.
    stretch_logs: Vec<Mat3>,
    centroids: Vec<[f64; 3]>,
    loose: Vec<[f64; 3]>,
}

/// A base surface and shapes to blend with weights (see the module
/// documentation).
///
/// ```
/// use meshmorph::{shapes, Blend3, InterpolatorOptions};
///
/// let tube = shapes::tube(4.0, 0.3, 17, 8);
/// let bent = shapes::bend(&tube, 4.0, 1.5);
/// let blend = Blend3::new(&tube, &[bent.clone()], &InterpolatorOptions::default())?;
/// let again = blend.at(&[1.0]);
/// let err = again.iter().zip(bent.positions()).map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max)).fold(0.0, f64::max);
/// assert!(err < 1e-9);
/// # Ok::<(), meshmorph::Error>(())
/// ```
#[derive(Debug)]
pub struct Blend3 {
    surface: Arc<PreparedSurface>,
    frames: RestFrames,
    shapes: Vec<BlendShape>,
    base_centroids: Vec<[f64; 3]>,
    base_loose: Vec<[f64; 3]>,
}

impl Blend3 {
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
    pub fn new(base: &Mesh3, shapes: &[Mesh3], options: &InterpolatorOptions) -> Result<Self> {
        base.check_no_degenerate_triangles("base")?;
        let frames = RestFrames::new(base, "base")?;
        check_poses(base, &frames, shapes, "blend shape", options)?;
        let surface = Arc::new(PreparedSurface::named(base, "base", options.factor)?);
        Self::build(surface, frames, shapes, options)
    }

    /// Blends relative to the prepared surface's rest mesh, sharing its
    /// factorization.
    ///
    /// # Errors
    /// As [`Blend3::new`].
    pub fn with_surface(
        surface: Arc<PreparedSurface>,
        shapes: &[Mesh3],
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        let frames = RestFrames::new(surface.source(), "base")?;
        check_poses(surface.source(), &frames, shapes, "blend shape", options)?;
        Self::build(surface, frames, shapes, options)
    }

    fn build(
        surface: Arc<PreparedSurface>,
        frames: RestFrames,
        shapes: &[Mesh3],
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        if shapes.is_empty() {
            return Err(Error::InvalidArgument(
                "a blend needs at least one shape".into(),
            ));
        }
        let rest = surface.source();
        let loose_of = |p: &[[f64; 3]]| -> Vec<[f64; 3]> {
            surface
                .loose_vertices()
                .iter()
                .map(|&v| p[v as usize])
                .collect()
        };
        let shapes = shapes
            .iter()
            .map(|shape| {
                let maps = frames.decompose(rest, shape);
                let turns = if options.consistency {
                    let seeds = frames.seeds(rest, &maps.rotations);
                    whole_turns(
                        &maps.rotations,
                        &frames.adjacency,
                        |a, b| shared_edge_length(rest, a, b),
                        &seeds,
                    )
                } else {
                    vec![[0.0; 3]; rest.num_triangles()]
                };
                BlendShape {
                    turns,
                    logs: maps.rotations.iter().map(|&q| quat_log(q)).collect(),
                    stretch_logs: maps
                        .stretches
                        .iter()
                        .map(|S| SymmetricEigen3::new(*S).map_values(|l| l.max(LOG_FLOOR).ln()))
                        .collect(),
                    centroids: surface.centroids(shape.positions()),
                    loose: loose_of(shape.positions()),
                }
            })
            .collect();
        Ok(Self {
            base_centroids: surface.centroids(rest.positions()),
            base_loose: loose_of(rest.positions()),
            surface,
            frames,
            shapes,
        })
    }

    /// Number of shapes (the length of every weight vector).
    pub fn num_shapes(&self) -> usize {
        self.shapes.len()
    }

    /// Number of vertices of every blend.
    pub fn num_vertices(&self) -> usize {
        self.surface.num_vertices()
    }

    /// The triangles shared by every blend.
    pub fn triangles(&self) -> &[[u32; 3]] {
        self.surface.source().triangles()
    }

    /// The prepared base surface, to share with sequences and other blends.
    pub fn surface(&self) -> &Arc<PreparedSurface> {
        &self.surface
    }

    /// Scratch for [`Blend3::at_into`]; one per thread.
    pub fn workspace(&self) -> SequenceWorkspace {
        SequenceWorkspace {
            surface: self.surface.workspace(),
            centroids: vec![[0.0; 3]; self.surface.num_components()],
        }
    }

    /// The blend with one weight per shape (any real numbers; all zero is
    /// the base).
    ///
    /// # Panics
    /// If `weights.len()` is not the number of shapes.
    #[track_caller]
    pub fn at(&self, weights: &[f64]) -> Vec<[f64; 3]> {
        let mut out = vec![[0.0; 3]; self.num_vertices()];
        self.at_into(weights, &mut out, &mut self.workspace());
        out
    }

    /// [`Blend3::at`] into a caller's buffer, with a caller's scratch.
    ///
    /// # Panics
    /// If `weights` or `out` has the wrong length.
    #[track_caller]
    pub fn at_into(&self, weights: &[f64], out: &mut [[f64; 3]], ws: &mut SequenceWorkspace) {
        assert_eq!(weights.len(), self.shapes.len(), "one weight per shape");
        let active: Vec<(f64, &BlendShape)> = weights
            .iter()
            .zip(&self.shapes)
            .filter(|(w, _)| **w != 0.0)
            .map(|(&w, s)| (w, s))
            .collect();
        for (p, c) in ws.centroids.iter_mut().enumerate() {
            *c = self.base_centroids[p];
            for (w, s) in &active {
                for k in 0..3 {
                    c[k] += w * (s.centroids[p][k] - self.base_centroids[p][k]);
                }
            }
        }
        let map = |t: usize| {
            let (mut c, mut e, mut L) = ([0.0; 3], [0.0; 3], [[0.0; 3]; 3]);
            for (w, s) in &active {
                for k in 0..3 {
                    c[k] += w * s.turns[t][k];
                    e[k] += w * s.logs[t][k];
                    for m in 0..3 {
                        L[k][m] += w * s.stretch_logs[t][k][m];
                    }
                }
            }
            let R = quat_to_matrix(quat_mul(quat_exp(c), quat_exp(e)));
            mul3(R, SymmetricEigen3::new(L).map_values(f64::exp))
        };
        self.surface
            .solve_into(map, &ws.centroids, out, &mut ws.surface);
        for (k, &v) in self.surface.loose_vertices().iter().enumerate() {
            let mut p = self.base_loose[k];
            for (w, s) in &active {
                for m in 0..3 {
                    p[m] += w * (s.loose[k][m] - self.base_loose[k][m]);
                }
            }
            out[v as usize] = p;
        }
    }

    /// Number of triangles of `positions` turned over relative to the base.
    pub fn count_turned_over(&self, positions: &[[f64; 3]]) -> usize {
        self.frames
            .turned_over(self.surface.source(), positions)
            .len()
    }
}
