//! The normal matrix of a gradient-domain energy with its pinned unknowns
//! eliminated, factored once, and its solves.

use super::Pins;
use crate::error::Result;
use crate::gradient::solve::{FactorKind, PinnedSystem, SymmetricMatrix, Workspace};

/// A factored system over `D` coordinate columns with pinned values.
#[derive(Debug)]
pub struct FactoredSystem<const D: usize> {
    system: PinnedSystem,
    /// Column-major `#pinned × D`.
    pinned_values: Vec<f64>,
}

/// Per-thread scratch for [`FactoredSystem::solve`].
#[derive(Debug)]
pub struct SolveWorkspace {
    solve: Workspace,
    /// Column-major `#unknowns × D`: the right-hand side, then the solution.
    pub(crate) rhs: Vec<f64>,
    pub(crate) x: Vec<f64>,
}

impl<const D: usize> FactoredSystem<D> {
    /// Eliminates the `pins` from `matrix` and factors the rest.
    ///
    /// # Errors
    /// [`Error::Solver`](crate::Error::Solver) when what remains is not
    /// positive definite.
    pub(crate) fn new(matrix: &SymmetricMatrix, pins: &Pins<D>, kind: FactorKind) -> Result<Self> {
        Ok(Self {
            system: PinnedSystem::new(matrix, pins.vertices(), kind)?,
            pinned_values: pins.packed_values(),
        })
    }

    /// Factors a new matrix with the same pattern and pins.
    ///
    /// # Errors
    /// As [`FactoredSystem::new`].
    pub(crate) fn refactor(&mut self, matrix: &SymmetricMatrix) -> Result<()> {
        self.system.refactor(matrix)
    }

    /// Number of unknowns, pinned ones included.
    pub(crate) fn num_unknowns(&self) -> usize {
        self.system.dim()
    }

    /// Number of stored values of the Cholesky factor.
    pub(crate) fn factor_len(&self) -> usize {
        self.system.factor_len()
    }

    /// Bytes a solve reads from the Cholesky factor.
    pub(crate) fn factor_bytes(&self) -> usize {
        self.system.factor_bytes()
    }

    /// Scratch for [`FactoredSystem::solve`]; one per thread.
    pub(crate) fn workspace(&self) -> SolveWorkspace {
        let m = self.num_unknowns();
        SolveWorkspace {
            solve: self.system.workspace(D),
            rhs: vec![0.0; D * m],
            x: vec![0.0; D * m],
        }
    }

    /// Solves for the right-hand side in `ws.rhs` into `ws.x` (column-major
    /// `#unknowns × D`, the pinned unknowns at their values).
    pub(crate) fn solve(&self, ws: &mut SolveWorkspace) {
        self.system
            .solve(&ws.rhs, Some(&self.pinned_values), &mut ws.x, &mut ws.solve);
    }

    /// Vertex `v` of the solution in `ws.x`.
    #[inline]
    pub(crate) fn position(&self, ws: &SolveWorkspace, v: usize) -> [f64; D] {
        let m = self.num_unknowns();
        std::array::from_fn(|i| ws.x[i * m + v])
    }

    /// The row of unknown `u` in the layout of
    /// [`FactoredSystem::solve_in_rows`].
    #[inline]
    pub(crate) fn row_of(&self, u: usize) -> usize {
        self.system.row_of(u)
    }

    /// Solves for `K / D` right-hand sides of `D` coordinates each, side by
    /// side, in rows laid out as [`FactoredSystem::row_of`] says: on entry
    /// the rows of the free unknowns hold the right-hand side (whatever the
    /// rows of pinned unknowns hold is ignored); on return every row holds
    /// its unknown's value, the pinned ones their pinned values.
    ///
    /// # Panics
    /// If `rows` does not have one row per unknown, or `K` is not a multiple
    /// of `D`.
    #[track_caller]
    pub(crate) fn solve_in_rows<const K: usize>(&self, rows: &mut [[f64; K]]) {
        assert_eq!(K % D, 0, "whole right-hand sides of D coordinates");
        let np = self.pinned_values.len() / D;
        let free = self.num_unknowns() - np;
        for (q, row) in rows[free..].iter_mut().enumerate() {
            *row = std::array::from_fn(|c| self.pinned_values[(c % D) * np + q]);
        }
        self.system.solve_in_rows(rows);
    }
}
