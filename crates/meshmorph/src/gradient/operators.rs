//! The gradient operators of every triangle of a rest mesh, and the
//! least-squares terms built from them.
//!
//! Triangle `t` has `K` unknowns (its three corners, and in space also a
//! fourth vertex of its own) and a `K × D` operator `G_t`: the gradient of
//! the piecewise-linear map that sends the rest mesh to positions `X` is,
//! on `t`, the `D × D` matrix `X_t G_t` with `X_t` the `D × K` matrix of the
//! triangle's unknowns. Every coordinate has the same coefficients, so the
//! normal matrix is assembled once for all `D` coordinates and a right-hand
//! side has `D` columns (column-major, `#unknowns × D`).
#![allow(non_snake_case)]

use crate::gradient::solve::SymmetricBuilder;
use crate::linalg::matrix::Mat;

/// The operators `G_t` (`K × D`) of the triangles of a rest mesh over its
/// unknowns: the `#V` vertices, then (for `K = 4`) one fourth vertex per
/// triangle.
#[derive(Clone, Debug)]
pub struct GradientOperators<const D: usize, const K: usize> {
    num_vertices: usize,
    triangles: Vec<[u32; 3]>,
    operators: Vec<[[f64; D]; K]>,
}

impl<const D: usize, const K: usize> GradientOperators<D, K> {
    /// Operators `operators[t]` of the `triangles` over `num_vertices` vertices.
    pub(crate) fn from_parts(
        num_vertices: usize,
        triangles: Vec<[u32; 3]>,
        operators: Vec<[[f64; D]; K]>,
    ) -> Self {
        const { assert!(K == 3 || K == 4, "three corners, and maybe a fourth vertex") };
        debug_assert_eq!(triangles.len(), operators.len());
        Self {
            num_vertices,
            triangles,
            operators,
        }
    }

    /// Number of unknowns: vertices, and fourth vertices when `K = 4`.
    #[inline]
    pub fn num_unknowns(&self) -> usize {
        self.num_vertices + (K - 3) * self.triangles.len()
    }

    /// Number of vertices of the rest mesh.
    #[inline]
    pub(crate) fn num_vertices(&self) -> usize {
        self.num_vertices
    }

    /// The triangles of the rest mesh.
    #[inline]
    pub(crate) fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The unknowns of triangle `t`: its corners, then its fourth vertex.
    #[inline]
    pub(crate) fn unknowns(&self, t: usize) -> [usize; K] {
        let [a, b, c] = self.triangles[t];
        std::array::from_fn(|k| match k {
            0 => a as usize,
            1 => b as usize,
            2 => c as usize,
            _ => self.num_vertices + t,
        })
    }

    /// The gradient `X_t G_t` (`D × D`) on triangle `t` of the map to the
    /// positions `x` (column-major `#unknowns × D`, as a solve leaves them).
    #[inline]
    pub(crate) fn gradient(&self, x: &[f64], t: usize) -> Mat<D> {
        let m = self.num_unknowns();
        let (G, u) = (&self.operators[t], self.unknowns(t));
        std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..K).map(|k| x[i * m + u[k]] * G[k][j]).sum())
        })
    }

    /// `weight · ‖X G_t‖²_F`, the matrix part of a fit of triangle `t`.
    #[inline]
    pub(crate) fn add_fit(&self, builder: &mut SymmetricBuilder, t: usize, weight: f64) {
        builder.add_gram(&self.unknowns(t), &self.operators[t], weight);
    }

    /// The right-hand side part of `weight · ‖X G_t − Q‖²_F` (whose matrix
    /// part is [`GradientOperators::add_fit`]): `weight · G_t Qᵀ`, which is
    /// all a new target `Q` changes.
    #[inline]
    pub(crate) fn add_fit_rhs(&self, rhs: &mut [f64], t: usize, Q: &Mat<D>, weight: f64) {
        let m = self.num_unknowns();
        for (u, row) in self.unknowns(t).into_iter().zip(self.fit_rhs(t, Q, weight)) {
            for i in 0..D {
                rhs[i * m + u] += row[i];
            }
        }
    }

    /// The rows of `weight · G_t Qᵀ` ([`GradientOperators::add_fit_rhs`]),
    /// one per unknown of triangle `t`, for a caller that lays the
    /// right-hand side out its own way.
    #[inline]
    pub(crate) fn fit_rhs(&self, t: usize, Q: &Mat<D>, weight: f64) -> [[f64; D]; K] {
        let G = &self.operators[t];
        std::array::from_fn(|k| {
            std::array::from_fn(|i| weight * (0..D).map(|j| G[k][j] * Q[i][j]).sum::<f64>())
        })
    }

    /// `weight · ‖X G_a − X G_b‖²_F` (no right-hand side): triangles `a`
    /// and `b` asked to deform alike.
    pub(crate) fn add_difference(
        &self,
        builder: &mut SymmetricBuilder,
        a: usize,
        b: usize,
        weight: f64,
    ) {
        let (ua, ub) = (self.unknowns(a), self.unknowns(b));
        let mut idx = [0usize; 8];
        let mut coef = [[0.0; D]; 8];
        idx[..K].copy_from_slice(&ua);
        coef[..K].copy_from_slice(&self.operators[a]);
        // The corners the two share (two across an edge) are one unknown
        // each: one coefficient row, `G_a − G_b`, and fewer entries to sum.
        let mut len = K;
        for k in 0..K {
            let minus = self.operators[b][k];
            match idx[..K].iter().position(|&u| u == ub[k]) {
                Some(j) => (0..D).for_each(|i| coef[j][i] -= minus[i]),
                None => {
                    idx[len] = ub[k];
                    coef[len] = minus.map(|x| -x);
                    len += 1;
                }
            }
        }
        builder.add_gram(&idx[..len], &coef[..len], weight);
    }
}
