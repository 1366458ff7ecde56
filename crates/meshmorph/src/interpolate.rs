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

use rayon::prelude::*;

use crate::error::{Error, Result, LIST_LIMIT};
use crate::geometry::{centroid, signed_area2};
use crate::mesh::{bounding_box_diagonal, check_areas, Mesh2};
use crate::polar::{mul, polar_decomposition, rotation, Mat2, SymmetricEigen2};
use crate::rotation::make_consistent;
use crate::solve::{FactorKind, PinnedSystem, SymmetricBuilder, Workspace};
use crate::topology::{connected_components, TriangleAdjacency};

/// How the symmetric stretch `S` of each triangle is interpolated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum StretchMode {
    /// `(1−t) I + t S`, as in Alexa et al. 2000. The default: it is the
    /// published method, so frames match other implementations of it, and
    /// for `t` in `[0, 1]` it never collapses a triangle (a convex
    /// combination of two positive definite matrices is positive definite).
    /// Beyond `[0, 1]` an eigenvalue `1 + t(λ − 1)` reaches zero at
    /// `t = 1/(1 − λ)` for a triangle shrunk by `λ < 1`, or at
    /// `t = −1/(λ − 1)` for one stretched by `λ > 1`.
    #[default]
    Linear,
    /// `Sᵗ = V diag(λᵗ) Vᵀ` through the eigen decomposition of `S`: positive
    /// definite for every real `t`, so extrapolation never collapses a
    /// triangle. Stretches then grow geometrically rather than linearly.
    /// (With [`InterpolatorOptions::allow_flips`], a reversed triangle has
    /// no positive definite stretch: its symmetric part is used with
    /// eigenvalues raised to a tiny positive floor, so the fit reaches the
    /// target only approximately at `t = 1`.)
    Log,
}

/// Options of [`Interpolator::new`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct InterpolatorOptions {
    /// Make rotation angles continuous across neighbouring triangles
    /// (Baxter et al. 2008). Default `true`; without it, any part that turns
    /// by more than half a turn tears.
    pub consistency: bool,
    /// Whole extra turns added to every triangle's rotation: `2π · turns`
    /// radians, counter-clockwise for positive values. Default 0.
    pub turns: i32,
    /// How stretches are interpolated. Default [`StretchMode::Linear`].
    pub stretch: StretchMode,
    /// Accept triangles whose orientation is reversed between source and
    /// target instead of failing. Default `false`.
    pub allow_flips: bool,
    /// Which Cholesky variant factors the system. Default [`FactorKind::Auto`].
    pub factor: FactorKind,
}

impl Default for InterpolatorOptions {
    fn default() -> Self {
        Self {
            consistency: true,
            turns: 0,
            stretch: StretchMode::Linear,
            allow_flips: false,
            factor: FactorKind::Auto,
        }
    }
}

impl InterpolatorOptions {
    /// Sets [`InterpolatorOptions::consistency`].
    pub fn with_consistency(mut self, on: bool) -> Self {
        self.consistency = on;
        self
    }
    /// Sets [`InterpolatorOptions::turns`].
    pub fn with_turns(mut self, turns: i32) -> Self {
        self.turns = turns;
        self
    }
    /// Sets [`InterpolatorOptions::stretch`].
    pub fn with_stretch(mut self, mode: StretchMode) -> Self {
        self.stretch = mode;
        self
    }
    /// Sets [`InterpolatorOptions::allow_flips`].
    pub fn with_allow_flips(mut self, allow: bool) -> Self {
        self.allow_flips = allow;
        self
    }
    /// Sets [`InterpolatorOptions::factor`].
    pub fn with_factor(mut self, kind: FactorKind) -> Self {
        self.factor = kind;
        self
    }
}

/// The per-triangle part of the map that varies with `t`.
#[derive(Clone, Copy, Debug)]
enum Stretch {
    Linear(Mat2),
    Log(SymmetricEigen2),
}

/// Eigenvalues of `S` below this are raised to it before taking powers.
const LOG_FLOOR: f64 = 1e-12;

/// ARAP interpolation between two planar meshes with the same triangles.
///
/// Everything that does not depend on `t` is computed in [`Interpolator::new`];
/// [`Interpolator::at`] cannot fail.
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
pub struct Interpolator {
    triangles: Vec<[u32; 3]>,
    /// Rotation angle of each triangle, radians, consistent branch chosen.
    angles: Vec<f64>,
    stretches: Vec<Stretch>,
    /// `|area_T| ∇φ_v` for the three corners of each source triangle.
    weighted_gradients: Vec<[[f64; 2]; 3]>,
    source_areas: Vec<f64>,
    system: PinnedSystem,
    /// Component of each vertex, `u32::MAX` for vertices no triangle uses.
    vertex_component: Vec<u32>,
    /// Area weight of each vertex in its component's centroid.
    vertex_weight: Vec<f64>,
    /// Per component: total weight, source centroid, target centroid.
    centroid_paths: Vec<(f64, [f64; 2], [f64; 2])>,
    /// Vertices no triangle uses: they move on straight lines.
    loose: Vec<(u32, [f64; 2], [f64; 2])>,
}

/// Per-thread scratch for [`Interpolator::at_into`].
#[derive(Debug)]
pub struct FrameWorkspace {
    solve: Workspace,
    rhs: Vec<f64>,
    x: Vec<f64>,
    sums: Vec<[f64; 2]>,
}

impl Interpolator {
    /// Prepares the interpolation from `source` (t = 0) to `target` (t = 1).
    ///
    /// # Errors
    /// - [`Error::Mismatch`] when the meshes differ in vertex count or triangles;
    /// - [`Error::DegenerateTriangles`] for zero-area source triangles;
    /// - [`Error::FlippedTriangles`] for triangles reversed (or collapsed to
    ///   zero area) between source and target, unless
    ///   [`InterpolatorOptions::allow_flips`];
    /// - [`Error::Solver`] if the system cannot be factored.
    ///
    /// # Performance
    /// Linear in the number of triangles apart from one sparse Cholesky
    /// factorization of a `#V × #V` matrix.
    pub fn new(source: &Mesh2, target: &Mesh2, options: &InterpolatorOptions) -> Result<Self> {
        source.check_same_connectivity(target, ["the source", "the target"])?;
        let n = source.num_vertices();
        let triangles = source.triangles().to_vec();
        let (p, q) = (source.positions(), target.positions());

        let source_areas = source.signed_areas();
        check_areas(&source_areas, bounding_box_diagonal(p), "source")?;
        let target_areas = target.signed_areas();
        let flipped: Vec<usize> = (0..triangles.len())
            .filter(|&t| source_areas[t] * target_areas[t] <= 0.0)
            .collect();
        if !flipped.is_empty() && !options.allow_flips {
            return Err(Error::FlippedTriangles {
                count: flipped.len(),
                first: flipped.into_iter().take(LIST_LIMIT).collect(),
            });
        }

        let weighted_gradients: Vec<[[f64; 2]; 3]> = triangles
            .iter()
            .zip(&source_areas)
            .map(|(&[a, b, c], &area)| {
                let g = hat_gradients([p[a as usize], p[b as usize], p[c as usize]], area);
                g.map(|gk| [gk[0] * area.abs(), gk[1] * area.abs()])
            })
            .collect();

        let mut angles = Vec::with_capacity(triangles.len());
        let mut stretches = Vec::with_capacity(triangles.len());
        for (t, &[a, b, c]) in triangles.iter().enumerate() {
            let A = affine_map(
                &weighted_gradients[t],
                source_areas[t].abs(),
                [q[a as usize], q[b as usize], q[c as usize]],
            );
            let polar = polar_decomposition(A);
            angles.push(polar.angle);
            stretches.push(match options.stretch {
                StretchMode::Linear => Stretch::Linear(polar.stretch),
                StretchMode::Log => Stretch::Log(SymmetricEigen2::new(polar.stretch)),
            });
        }

        let components = connected_components(n, &triangles);
        if options.consistency {
            // Angles propagate across edges, so each part connected across
            // edges gets its own seed.
            let adjacency = TriangleAdjacency::new(&triangles);
            let (parts, count) = adjacency.edge_components();
            let seeds = angle_seeds(&angles, &parts, count, source);
            make_consistent(&mut angles, &adjacency, &seeds);
        }
        let extra = std::f64::consts::TAU * options.turns as f64;
        angles.iter_mut().for_each(|a| *a += extra);

        // The normal matrix: the area-weighted cotangent Laplacian.
        let mut builder = SymmetricBuilder::new(n, 6 * triangles.len());
        for (tri, (g, &area)) in triangles
            .iter()
            .zip(weighted_gradients.iter().zip(&source_areas))
        {
            let inv = 1.0 / area.abs();
            for i in 0..3 {
                for j in i..3 {
                    let v = (g[i][0] * g[j][0] + g[i][1] * g[j][1]) * inv;
                    builder.add(tri[i] as usize, tri[j] as usize, v);
                }
            }
        }
        // Translation is free in each component: pin one vertex of each (the
        // result is moved afterwards, so which one does not matter), and
        // every vertex no triangle uses.
        let mut vertex_component = vec![u32::MAX; n];
        let mut pinned = Vec::with_capacity(components.count);
        let mut seen = vec![false; components.count];
        for (v, c) in components.of_vertex.iter().enumerate() {
            match c {
                Some(c) => {
                    vertex_component[v] = *c;
                    if !std::mem::replace(&mut seen[*c as usize], true) {
                        pinned.push(v);
                    }
                }
                None => pinned.push(v),
            }
        }
        let system = PinnedSystem::new(&builder.build(), &pinned, options.factor)?;

        let mut vertex_weight = vec![0.0; n];
        for (tri, area) in triangles.iter().zip(&source_areas) {
            for &v in tri {
                vertex_weight[v as usize] += area.abs() / 3.0;
            }
        }
        let mut centroid_paths = vec![(0.0, [0.0; 2], [0.0; 2]); components.count];
        for v in 0..n {
            if let Some(c) = components.of_vertex[v] {
                let (w, cs, ct) = &mut centroid_paths[c as usize];
                let wv = vertex_weight[v];
                *w += wv;
                for k in 0..2 {
                    cs[k] += wv * p[v][k];
                    ct[k] += wv * q[v][k];
                }
            }
        }
        for (w, cs, ct) in &mut centroid_paths {
            for k in 0..2 {
                cs[k] /= *w;
                ct[k] /= *w;
            }
        }
        let loose = (0..n)
            .filter(|&v| components.of_vertex[v].is_none())
            .map(|v| (v as u32, p[v], q[v]))
            .collect();

        Ok(Self {
            triangles,
            angles,
            stretches,
            weighted_gradients,
            source_areas,
            system,
            vertex_component,
            vertex_weight,
            centroid_paths,
            loose,
        })
    }

    /// Number of stored values of the Cholesky factor (for measuring a
    /// frame against the memory traffic of its back-substitution).
    pub fn factor_len(&self) -> usize {
        self.system.factor_len()
    }

    /// Number of vertices of every frame.
    pub fn num_vertices(&self) -> usize {
        self.vertex_component.len()
    }

    /// The triangles shared by every frame.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Rotation angle of each triangle from source to target, radians,
    /// counter-clockwise, with the branch chosen by rotation consistency and
    /// the extra turns added.
    pub fn angles(&self) -> &[f64] {
        &self.angles
    }

    /// Scratch for [`Interpolator::at_into`]; one per thread.
    pub fn workspace(&self) -> FrameWorkspace {
        let n = self.num_vertices();
        FrameWorkspace {
            solve: self.system.workspace(2),
            rhs: vec![0.0; 2 * n],
            x: vec![0.0; 2 * n],
            sums: vec![[0.0; 2]; self.centroid_paths.len()],
        }
    }

    /// Vertex positions at time `t`: the source at 0, the target at 1, any
    /// real `t` allowed.
    pub fn at(&self, t: f64) -> Vec<[f64; 2]> {
        let mut out = vec![[0.0; 2]; self.num_vertices()];
        self.at_into(t, &mut out, &mut self.workspace());
        out
    }

    /// Frames at each of `times`, computed in parallel.
    pub fn frames(&self, times: &[f64]) -> Vec<Vec<[f64; 2]>> {
        times
            .par_iter()
            .map_init(
                || self.workspace(),
                |ws, &t| {
                    let mut out = vec![[0.0; 2]; self.num_vertices()];
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
    pub fn at_into(&self, t: f64, out: &mut [[f64; 2]], ws: &mut FrameWorkspace) {
        let n = self.num_vertices();
        assert_eq!(out.len(), n, "output has the wrong number of vertices");
        ws.rhs.fill(0.0);
        let (bx, by) = ws.rhs.split_at_mut(n);
        for ((tri, g), (&angle, stretch)) in self
            .triangles
            .iter()
            .zip(&self.weighted_gradients)
            .zip(self.angles.iter().zip(&self.stretches))
        {
            let A = self.map_at(t, angle, stretch);
            for k in 0..3 {
                let v = tri[k] as usize;
                bx[v] += A[0][0] * g[k][0] + A[0][1] * g[k][1];
                by[v] += A[1][0] * g[k][0] + A[1][1] * g[k][1];
            }
        }
        self.system.solve(&ws.rhs, None, &mut ws.x, &mut ws.solve);

        // Move each component so its centroid is on its straight path.
        ws.sums.fill([0.0; 2]);
        let (xs, ys) = ws.x.split_at(n);
        for v in 0..n {
            let c = self.vertex_component[v];
            if c != u32::MAX {
                let s = &mut ws.sums[c as usize];
                s[0] += self.vertex_weight[v] * xs[v];
                s[1] += self.vertex_weight[v] * ys[v];
            }
        }
        for (s, (w, cs, ct)) in ws.sums.iter_mut().zip(&self.centroid_paths) {
            for k in 0..2 {
                s[k] = (1.0 - t) * cs[k] + t * ct[k] - s[k] / w;
            }
        }
        for v in 0..n {
            let c = self.vertex_component[v];
            if c != u32::MAX {
                let s = ws.sums[c as usize];
                out[v] = [xs[v] + s[0], ys[v] + s[1]];
            }
        }
        for &(v, a, b) in &self.loose {
            out[v as usize] = [(1.0 - t) * a[0] + t * b[0], (1.0 - t) * a[1] + t * b[1]];
        }
    }

    #[inline]
    fn map_at(&self, t: f64, angle: f64, stretch: &Stretch) -> Mat2 {
        let S = match stretch {
            Stretch::Linear(S) => [
                [(1.0 - t) + t * S[0][0], t * S[0][1]],
                [t * S[1][0], (1.0 - t) + t * S[1][1]],
            ],
            Stretch::Log(e) => e.power(t, LOG_FLOOR),
        };
        mul(rotation(t * angle), S)
    }

    /// Number of triangles of `positions` whose orientation is reversed
    /// relative to the source (a triangle of zero area counts as reversed).
    pub fn count_flipped(&self, positions: &[[f64; 2]]) -> usize {
        self.triangles
            .iter()
            .zip(&self.source_areas)
            .filter(|(&[a, b, c], &s)| {
                let area = signed_area2(
                    positions[a as usize],
                    positions[b as usize],
                    positions[c as usize],
                );
                area * s <= 0.0
            })
            .count()
    }
}

/// Gradients of the three hat functions of a planar triangle with the given
/// signed area: `∇φ_i = rot90(p_{i+2} − p_{i+1}) / (2 area)`.
fn hat_gradients(p: [[f64; 2]; 3], signed_area: f64) -> [[f64; 2]; 3] {
    let inv = 0.5 / signed_area;
    std::array::from_fn(|i| {
        let (a, b) = (p[(i + 1) % 3], p[(i + 2) % 3]);
        [-(b[1] - a[1]) * inv, (b[0] - a[0]) * inv]
    })
}

/// The linear part of the affine map that sends a source triangle to the
/// target corners `q`: `A = Σ_k q_k ∇φ_kᵀ` (the gradients are passed
/// pre-multiplied by the area).
fn affine_map(weighted_gradients: &[[f64; 2]; 3], area: f64, q: [[f64; 2]; 3]) -> Mat2 {
    let mut A = [[0.0; 2]; 2];
    for (g, qk) in weighted_gradients.iter().zip(q) {
        for i in 0..2 {
            for j in 0..2 {
                A[i][j] += qk[i] * g[j] / area;
            }
        }
    }
    A
}

/// One seed triangle per part (angles are principal, in (−π, π]): the one that turns least, ties broken by
/// the position of its source centroid, so the choice does not depend on how
/// the triangles are numbered.
fn angle_seeds(angles: &[f64], of_triangle: &[u32], count: usize, source: &Mesh2) -> Vec<usize> {
    let key = |t: usize| {
        let c = centroid(source.corners(t));
        (angles[t].abs(), c[0], c[1])
    };
    type Best = Option<(usize, (f64, f64, f64))>;
    let mut best: Vec<Best> = vec![None; count];
    for (t, &c) in of_triangle.iter().enumerate() {
        let k = key(t);
        let slot = &mut best[c as usize];
        if slot.is_none_or(|(_, b)| k.partial_cmp(&b) == Some(std::cmp::Ordering::Less)) {
            *slot = Some((t, k));
        }
    }
    best.into_iter().flatten().map(|(t, _)| t).collect()
}
