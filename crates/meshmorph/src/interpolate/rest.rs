//! What interpolation from one source mesh needs whatever the target, in
//! the plane and in space.
//!
//! A frame is given by one `D × D` map `A_T` per triangle (the map from the
//! source triangle to the frame's triangle); its vertices minimise
//! `Σ_T area_T ‖J_T(x) − A_T‖²_F` in the plane (Alexa et al. 2000) and
//! `Σ_T area_T ‖J_T(x) − A_T P_T‖²_F` in space, where `J_T(x)` is the
//! (surface) gradient of the piecewise-linear map that sends the source to
//! `x` and `P_T` projects onto the source triangle's plane. Either way the
//! normal matrix is the cotangent Laplacian of the source, the same for
//! every coordinate and every frame: one factorization, `D` right-hand
//! sides.

use super::attached::{Attached, PartAnchors};
use super::{FrameWorkspace, FRAMES_PER_SOLVE, TRIANGLES_PER_STEP};
use crate::error::Result;
use crate::gradient::solve::{FactorKind, SymmetricBuilder, SymmetricMatrix};
use crate::gradient::weights::vertex_weights;
use crate::gradient::{FactoredSystem, GradientOperators, Pins, Placement, TriangleMaps};
use crate::interpolate::Dimension;
use crate::linalg::matrix::Mat;
use crate::linalg::Space;
use crate::mesh::topology::connected_components;
use crate::mesh::{check_areas, Mesh};

/// The gradient operators and area weights of a source mesh, its normal
/// matrix (the cotangent Laplacian) factored once, and the placement of its
/// connected parts: everything an interpolation from it needs whatever the
/// target. Build it once and share it behind an [`Arc`](std::sync::Arc)
/// between any number of interpolations, sequences and blends from the same
/// source ([`Interpolator::with_rest`](crate::Interpolator::with_rest),
/// [`Sequence::with_surface`](crate::Sequence::with_surface),
/// [`Blend::with_surface`](crate::Blend::with_surface)).
#[derive(Debug)]
pub struct RestSystem<const D: usize> {
    pub(super) source: Mesh<D>,
    /// `|area|` of each source triangle: the weight of its fit.
    pub(super) weights: Vec<f64>,
    pub(super) operators: GradientOperators<D, 3>,
    pub(super) system: FactoredSystem<D>,
    /// Every connected part, placed by its area-weighted centroid.
    pub(super) placement: Placement<D>,
    /// The anchors of the parts that may follow a larger one.
    pub(super) anchors: PartAnchors,
    /// Vertices no triangle uses: they move on straight lines.
    pub(super) loose: Vec<u32>,
    /// The rows of each triangle's corners in the layout of the factored
    /// system's solves ([`FactoredSystem::row_of`]).
    corner_rows: Vec<[u32; 3]>,
}

impl<const D: usize> RestSystem<D>
where
    Space<D>: Dimension<D>,
{
    /// Prepares and factors the system of `source`; `factor` chooses the
    /// Cholesky variant.
    ///
    /// # Errors
    /// - [`Error::DegenerateTriangles`](crate::Error::DegenerateTriangles)
    ///   for zero-area source triangles;
    /// - [`Error::Solver`](crate::Error::Solver) if the system cannot be
    ///   factored.
    ///
    /// # Performance
    /// Linear in the number of triangles apart from one sparse Cholesky
    /// factorization of a `#V × #V` matrix.
    pub fn new(source: &Mesh<D>, factor: FactorKind) -> Result<Self> {
        Self::named(source, "source", factor)
    }

    /// [`RestSystem::new`], the source called `name` in error messages
    /// ("first key", "base", ...).
    ///
    /// # Errors
    /// As [`RestSystem::new`].
    pub fn named(source: &Mesh<D>, name: &str, factor: FactorKind) -> Result<Self> {
        <Space<D> as Dimension<D>>::new_rest_system(source, name, factor)
    }

    /// The work of [`Self::named`], instantiated for each dimension in
    /// `dimension.rs`.
    pub(super) fn named_generic(source: &Mesh<D>, name: &str, factor: FactorKind) -> Result<Self> {
        let (n, tris) = (source.num_vertices(), source.triangles());
        let areas = Self::check_rest(source, name)?;
        let operators = GradientOperators::from_parts(
            n,
            tris.to_vec(),
            (0..tris.len())
                .map(|t| Space::<D>::hat_gradients(&source.corners(t), areas[t]))
                .collect(),
        );
        let weights: Vec<f64> = areas.iter().map(|a| a.abs()).collect();
        let components = connected_components(n, tris);
        let mut pins = Pins::new(n);
        pins.hold_free_parts(&components, |_| [0.0; D]);
        let system = FactoredSystem::new(&normal_matrix(&operators, &weights), &pins, factor)?;
        let placement = Placement::new(&components, |_| true, vertex_weights(n, tris, &weights));
        let mut part_area = vec![0.0; components.count];
        for (t, &c) in components.of_triangle.iter().enumerate() {
            part_area[c as usize] += weights[t];
        }
        let anchors = PartAnchors::new(source.positions(), &components, &part_area);
        let loose = (0..n as u32)
            .filter(|&v| components.of_vertex[v as usize].is_none())
            .collect();
        let corner_rows = tris
            .iter()
            .map(|t| t.map(|v| system.row_of(v as usize) as u32))
            .collect();
        Ok(Self {
            corner_rows,
            source: source.clone(),
            weights,
            operators,
            system,
            placement,
            anchors,
            loose,
        })
    }

    /// The normal matrix of the fit (the area-weighted cotangent Laplacian
    /// of the source), unfactored: for systems that hold other vertices.
    pub(super) fn normal_matrix(&self) -> SymmetricMatrix {
        normal_matrix(&self.operators, &self.weights)
    }

    /// The (signed, in the plane) area of each triangle of `source`, after
    /// checking that none is degenerate.
    ///
    /// # Errors
    /// [`Error::DegenerateTriangles`](crate::Error::DegenerateTriangles)
    /// naming zero-area triangles of `source` (called `name`).
    pub(crate) fn check_rest(source: &Mesh<D>, name: &str) -> Result<Vec<f64>> {
        let areas: Vec<f64> = (0..source.num_triangles())
            .map(|t| Space::<D>::area(&source.corners(t)))
            .collect();
        check_areas(&areas, source.bounding_box_diagonal(), name)?;
        Ok(areas)
    }

    /// Number of stored values of the Cholesky factor (for measuring a
    /// frame against the memory traffic of its back-substitution).
    pub fn factor_len(&self) -> usize {
        self.system.factor_len()
    }

    /// Bytes a frame's solve reads from the Cholesky factor, once forward
    /// and once back: its values and their row indices.
    pub fn factor_bytes(&self) -> usize {
        self.system.factor_bytes()
    }

    /// The source mesh.
    pub fn source(&self) -> &Mesh<D> {
        &self.source
    }

    /// Number of vertices of every frame.
    pub fn num_vertices(&self) -> usize {
        self.source.num_vertices()
    }

    /// Number of connected parts (triangles sharing vertices).
    pub fn num_components(&self) -> usize {
        self.placement.count()
    }

    /// Vertices no triangle uses: frames place them themselves.
    pub fn loose_vertices(&self) -> &[u32] {
        &self.loose
    }

    /// The area-weighted centroid of each connected part of `positions`
    /// (positions of the source's vertices in some pose).
    pub fn centroids(&self, positions: &[[f64; D]]) -> Vec<[f64; D]> {
        let mut out = vec![[0.0; D]; self.num_components()];
        self.placement.centroids(positions, &mut out);
        out
    }

    /// Scratch for [`RestSystem::solve_into`]; one per thread.
    pub fn workspace(&self) -> FrameWorkspace<D> {
        FrameWorkspace {
            rows: Vec::new(),
            parts: Vec::new(),
            turns: Vec::new(),
            outline: Vec::new(),
        }
    }

    /// The frame whose triangle `t` has the map `map(t)`, each part moved so
    /// that its centroid is `centroids[part]`. Vertices no triangle uses are
    /// left as they are in `out`.
    ///
    /// # Panics
    /// If `out` or `centroids` has the wrong length.
    #[track_caller]
    pub fn solve_into(
        &self,
        map: impl Fn(usize) -> Mat<D>,
        centroids: &[[f64; D]],
        out: &mut [[f64; D]],
        ws: &mut FrameWorkspace<D>,
    ) {
        assert_eq!(
            centroids.len(),
            self.num_components(),
            "one centroid per part"
        );
        self.solve_frames(
            EachTriangle {
                frames: 1,
                rows_of: |t, _| self.fit_rows(t, &map(t)),
            },
            |_, c| centroids[c],
            &Attached::none(),
            |_, _| [0.0; D],
            &mut [out],
            ws,
        );
    }

    /// The rows of the right-hand side that ask triangle `t` to take the map
    /// `map` (one row per corner): `w_t G_t mapᵀ`, with `w_t` its weight and
    /// `G_t` its gradient operator. Linear in `map`.
    #[inline]
    pub fn fit_rows(&self, t: usize, map: &Mat<D>) -> [[f64; D]; 3] {
        self.operators.fit_rhs(t, map, self.weights[t])
    }

    /// Up to [`FRAMES_PER_SOLVE`] frames at once (`frames = outs.len()`):
    /// `rows_of(first, rows)` gives the triangles from `first` on their rows
    /// of the right-hand side in each frame ([`RestSystem::fit_rows`] of the
    /// triangle's map), those of triangle `first + i` in frame `f` into
    /// `rows[i * frames + f]`, for up to [`TRIANGLES_PER_STEP`] triangles at
    /// a time; part `c` takes the centroid `centroid(f, c)`, except for the
    /// `attached` parts, placed by their anchors with the offset `offset(f,
    /// i)` of the `i`-th anchored part ([`PartAnchors::place`]).
    ///
    /// One pass over the triangles builds every frame's right-hand side,
    /// straight in the factor's row order with the frames side by side; one
    /// substitution solves them all, reading the factor once for all; one
    /// pass over the solution finds every frame's parts' centroids, and one
    /// writes every frame's vertices, each moved with its part.
    #[track_caller]
    pub(super) fn solve_frames(
        &self,
        rows_of: impl TriangleRows<D>,
        centroid: impl Fn(usize, usize) -> [f64; D],
        attached: &Attached,
        offset: impl Fn(usize, usize) -> [f64; D],
        outs: &mut [&mut [[f64; D]]],
        ws: &mut FrameWorkspace<D>,
    ) {
        // The arms below cover up to two frames in the plane and in space.
        const { assert!(FRAMES_PER_SOLVE <= 2) };
        assert!(
            (1..=FRAMES_PER_SOLVE).contains(&outs.len()),
            "from 1 to {FRAMES_PER_SOLVE} frames at once"
        );
        match D * outs.len() {
            2 => self.solve_columns::<2>(&rows_of, &centroid, attached, &offset, outs, ws),
            3 => self.solve_columns::<3>(&rows_of, &centroid, attached, &offset, outs, ws),
            4 => self.solve_columns::<4>(&rows_of, &centroid, attached, &offset, outs, ws),
            6 => self.solve_columns::<6>(&rows_of, &centroid, attached, &offset, outs, ws),
            _ => unreachable!("D · frames is 2, 3, 4 or 6"),
        }
    }

    /// [`RestSystem::solve_frames`] with its `K = D · frames` columns.
    #[track_caller]
    fn solve_columns<const K: usize>(
        &self,
        rows_of: &impl TriangleRows<D>,
        centroid: &impl Fn(usize, usize) -> [f64; D],
        attached: &Attached,
        offset: &impl Fn(usize, usize) -> [f64; D],
        outs: &mut [&mut [[f64; D]]],
        ws: &mut FrameWorkspace<D>,
    ) {
        let n = self.num_vertices();
        for out in outs.iter() {
            assert_eq!(out.len(), n, "output has the wrong number of vertices");
        }
        let frames = K / D;
        ws.rows.clear();
        ws.rows.resize(K * n, 0.0);
        let rows: &mut [[f64; K]] = bytemuck::cast_slice_mut(&mut ws.rows);
        pulp::Arch::new().dispatch(RightHandSide::<_, D, K> {
            rows_of,
            corner_rows: &self.corner_rows,
            rows: &mut *rows,
        });
        self.system.solve_in_rows(rows);
        let rows = &*rows;
        let row = |v: usize| &rows[self.system.row_of(v)];
        let position =
            |f: usize, v: usize| -> [f64; D] { std::array::from_fn(|i| row(v)[f * D + i]) };
        ws.parts.resize_with(frames, Vec::new);
        let parts = &mut ws.parts[..frames];
        self.placement.centroids_of_frames(row, parts);
        for (f, parts) in parts.iter_mut().enumerate() {
            for (c, shift) in parts.iter_mut().enumerate() {
                if !attached.holds(c) {
                    let target = centroid(f, c);
                    *shift = std::array::from_fn(|i| target[i] - shift[i]);
                }
            }
            if attached.count() > 0 {
                self.anchors.place(
                    attached,
                    self.source.positions(),
                    |v| position(f, v),
                    |v| self.placement.part_of_vertex(v).unwrap_or(0),
                    |i| offset(f, i),
                    parts,
                );
            }
        }
        for v in 0..n {
            if let Some(c) = self.placement.part_of_vertex(v) {
                let solved = row(v);
                for (f, out) in outs.iter_mut().enumerate() {
                    let shift = ws.parts[f][c];
                    out[v] = std::array::from_fn(|i| solved[f * D + i] + shift[i]);
                }
            }
        }
    }
}

/// The normal matrix of the fit of every triangle's map with `weights`:
/// the area-weighted cotangent Laplacian of the source.
fn normal_matrix<const D: usize>(
    operators: &GradientOperators<D, 3>,
    weights: &[f64],
) -> SymmetricMatrix {
    let mut builder = SymmetricBuilder::new(operators.num_vertices(), 6 * weights.len());
    for (t, &w) in weights.iter().enumerate() {
        operators.add_fit(&mut builder, t, w);
    }
    builder.build()
}

/// The rows of the right-hand side each frame gives each triangle, for
/// [`RestSystem::solve_frames`]: `rows(first, rows)` gives the triangles
/// from `first` on their rows in each of the `frames` frames solved
/// together, those of triangle `first + i` in frame `f` into
/// `rows[i * frames + f]`, up to [`TRIANGLES_PER_STEP`] triangles at a time.
pub trait TriangleRows<const D: usize> {
    fn rows(&self, first: usize, rows: &mut [[[f64; D]; 3]]);
}

/// [`TriangleRows`] one triangle and frame at a time: `rows_of(t, f)` of
/// triangle `t` in frame `f`, of `frames` frames.
pub struct EachTriangle<R> {
    pub frames: usize,
    pub rows_of: R,
}

impl<const D: usize, R: Fn(usize, usize) -> [[f64; D]; 3]> TriangleRows<D> for EachTriangle<R> {
    #[inline]
    fn rows(&self, first: usize, rows: &mut [[[f64; D]; 3]]) {
        for (i, rows) in rows.chunks_mut(self.frames).enumerate() {
            for (f, rows) in rows.iter_mut().enumerate() {
                *rows = (self.rows_of)(first + i, f);
            }
        }
    }
}

/// The right-hand side of `K / D` frames side by side in the factor's rows,
/// each triangle's rows added to its corners' rows; with AVX2 (x86-64-v3)
/// when the processor has it (chosen when the program runs), which the
/// triangles' rows, computed several at a time, make use of.
struct RightHandSide<'a, R, const D: usize, const K: usize> {
    rows_of: &'a R,
    corner_rows: &'a [[u32; 3]],
    rows: &'a mut [[f64; K]],
}

impl<R: TriangleRows<D>, const D: usize, const K: usize> pulp::WithSimd
    for RightHandSide<'_, R, D, K>
{
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) {
        let frames = K / D;
        let mut of_step = [[[0.0; D]; 3]; TRIANGLES_PER_STEP * FRAMES_PER_SOLVE];
        for (step, triangles) in self.corner_rows.chunks(TRIANGLES_PER_STEP).enumerate() {
            let of_step = &mut of_step[..triangles.len() * frames];
            self.rows_of.rows(step * TRIANGLES_PER_STEP, of_step);
            for (corners, of_frames) in triangles.iter().zip(of_step.chunks(frames)) {
                // The triangle's rows for every frame side by side, then
                // added to its corners' rows whole.
                let mut local = [[0.0; K]; 3];
                for (f, of_frame) in of_frames.iter().enumerate() {
                    for (row, add) in local.iter_mut().zip(of_frame) {
                        row[f * D..(f + 1) * D].copy_from_slice(add);
                    }
                }
                for (&r, add) in corners.iter().zip(&local) {
                    let row = &mut self.rows[r as usize];
                    for c in 0..K {
                        row[c] += add[c];
                    }
                }
            }
        }
    }
}
