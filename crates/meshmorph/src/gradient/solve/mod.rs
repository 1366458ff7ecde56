//! Sparse symmetric positive definite systems: assembly, elimination of
//! pinned unknowns, one Cholesky factorization, many solves.
//!
//! Every algorithm in meshmorph ends in a least-squares problem whose normal
//! matrix does not change from frame to frame (or pose to pose). This module
//! owns that pattern and keeps faer behind it (faer's API moves between minor
//! releases):
//!
//! 1. accumulate the upper triangle of the normal matrix with
//!    [`SymmetricBuilder`];
//! 2. [`PinnedSystem::new`] removes the pinned unknowns (their columns move
//!    to the right-hand side, so the matrix stays symmetric positive definite,
//!    as in libigl's `min_quad_with_fixed`) and factors the rest once;
//! 3. [`PinnedSystem::solve`] back-substitutes any number of right-hand sides,
//!    each with a caller-owned [`Workspace`] so frames can run on several
//!    threads.
//!
//! # Performance
//! Solves are sequential: parallelism comes from solving independent frames
//! at once (faer's supernodal solve with a parallel `Par` and several
//! right-hand-side columns is about 30 times slower on small machines).
//! Up to 4 right-hand-side columns, [`PinnedSystem::solve`] gathers them
//! side by side into the factor's row order and substitutes with
//! `substitution.rs` (one cache line per row, and no dense kernel calls per
//! supernode); more columns go through faer's solve, column by column.

pub mod ordering;
pub mod substitution;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use crate::error::{Error, Result};
use rayon::prelude::*;

/// Which Cholesky variant to use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum FactorKind {
    /// Simplicial up to [`FactorKind::SIMPLICIAL_LIMIT`] unknowns,
    /// supernodal above.
    #[default]
    Auto,
    /// Column-by-column factor: slower to factor large systems; the
    /// fastest solves of small ones.
    Simplicial,
    /// Blocked factor: fast to factor large systems, and (with the
    /// substitution of `solve/substitution.rs`) solves within about 10 % of
    /// the simplicial factor's at a million triangles.
    Supernodal,
}

impl FactorKind {
    /// Systems up to this many unknowns get the simplicial factor under
    /// [`FactorKind::Auto`]: their factorization is cheap either way and the
    /// faster solve wins over many frames. Above it the simplicial
    /// factorization takes seconds (2.3 s at 500k unknowns on a strip, 5.7 s
    /// on a square sheet) and the supernodal one about half of that or less.
    pub const SIMPLICIAL_LIMIT: usize = 150_000;

    /// faer's threshold on the ratio of factorization flops to factor
    /// entries above which it chooses the supernodal factor.
    fn threshold(self, n: usize) -> SupernodalThreshold {
        match self {
            FactorKind::Simplicial => SupernodalThreshold::FORCE_SIMPLICIAL,
            FactorKind::Supernodal => SupernodalThreshold::FORCE_SUPERNODAL,
            FactorKind::Auto if n <= Self::SIMPLICIAL_LIMIT => {
                SupernodalThreshold::FORCE_SIMPLICIAL
            }
            FactorKind::Auto => SupernodalThreshold::FORCE_SUPERNODAL,
        }
    }
}

/// The upper triangle of a symmetric sparse matrix in compressed-column form,
/// rows sorted within each column, duplicates summed.
#[derive(Clone, Debug)]
pub struct SymmetricMatrix {
    pub n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    pub values: Vec<f64>,
}

impl SymmetricMatrix {
    /// Stored entries (upper triangle).
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// `y = A x` for the full symmetric matrix.
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        for j in 0..self.n {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                let (i, v) = (self.row_idx[p], self.values[p]);
                y[i] += v * x[j];
                if i != j {
                    y[j] += v * x[i];
                }
            }
        }
        y
    }

    /// Adds `diagonal[i]` to each diagonal entry `(i, i)`.
    ///
    /// # Panics
    /// If a non-zero value goes to a diagonal entry that is not stored
    /// (store explicit zeros on the diagonal when building).
    #[track_caller]
    pub fn add_to_diagonal(&mut self, diagonal: &[f64]) {
        assert_eq!(diagonal.len(), self.n, "one value per row");
        for (j, &d) in diagonal.iter().enumerate() {
            if d != 0.0 {
                let end = self.col_ptr[j + 1];
                assert!(
                    end > self.col_ptr[j] && self.row_idx[end - 1] == j,
                    "diagonal entry {j} is not stored"
                );
                self.values[end - 1] += d;
            }
        }
    }

    /// Adds `weight · aᵀa` for the sparse row `a` given as `(column, value)`
    /// pairs (distinct columns) to entries already stored: a term over
    /// unknowns that other terms already couple.
    ///
    /// # Panics
    /// If one of the entries is not stored.
    #[track_caller]
    pub fn add_row_outer(&mut self, row: &[(usize, f64)], weight: f64) {
        for (k, &(i, a)) in row.iter().enumerate() {
            for &(j, b) in &row[k..] {
                let (r, c) = (i.min(j), i.max(j));
                let rows = &self.row_idx[self.col_ptr[c]..self.col_ptr[c + 1]];
                let p = rows
                    .binary_search(&r)
                    .unwrap_or_else(|_| panic!("entry ({r}, {c}) is not stored"));
                self.values[self.col_ptr[c] + p] += weight * a * b;
            }
        }
    }

    /// The diagonal entries (0 where not stored).
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n)
            .map(|j| {
                let end = self.col_ptr[j + 1];
                if end > self.col_ptr[j] && self.row_idx[end - 1] == j {
                    self.values[end - 1]
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// Sets the stored diagonal entries to `diagonal` (as
    /// [`SymmetricMatrix::diagonal`] gave them).
    ///
    /// # Panics
    /// As [`SymmetricMatrix::add_to_diagonal`].
    #[track_caller]
    pub fn set_diagonal(&mut self, diagonal: &[f64]) {
        assert_eq!(diagonal.len(), self.n, "one value per row");
        for (j, &d) in diagonal.iter().enumerate() {
            let end = self.col_ptr[j + 1];
            if end > self.col_ptr[j] && self.row_idx[end - 1] == j {
                self.values[end - 1] = d;
            } else {
                assert!(d == 0.0, "diagonal entry {j} is not stored");
            }
        }
    }

    /// Entry `(i, j)` (0 when not stored).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = (i.min(j), i.max(j));
        let rows = &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]];
        match rows.binary_search(&i) {
            Ok(p) => self.values[self.col_ptr[j] + p],
            Err(_) => 0.0,
        }
    }

    pub fn as_faer(&self) -> SparseColMatRef<'_, usize, f64> {
        SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(
                self.n,
                self.n,
                &self.col_ptr,
                None,
                &self.row_idx,
            ),
            &self.values,
        )
    }
}

/// Accumulates entries of a symmetric matrix; each `(i, j)` pair is stored
/// once in the upper triangle, so adding `(i, j)` and `(j, i)` adds twice.
#[derive(Clone, Debug)]
pub struct SymmetricBuilder {
    n: usize,
    entries: Vec<(u32, u32, f64)>,
}

impl SymmetricBuilder {
    /// An `n × n` zero matrix; `capacity` entries are reserved.
    pub fn new(n: usize, capacity: usize) -> Self {
        assert!(n < u32::MAX as usize, "matrix too large");
        Self {
            n,
            entries: Vec::with_capacity(capacity),
        }
    }

    /// Adds `v` to the symmetric pair of entries `(i, j)` and `(j, i)`
    /// (to the diagonal once when `i == j`).
    #[inline]
    #[track_caller]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(i < self.n && j < self.n);
        let (r, c) = (i.min(j), i.max(j));
        self.entries.push((c as u32, r as u32, v));
    }

    /// Adds `weight · aᵀa` for the sparse row `a` given as `(column, value)`
    /// pairs (a column may appear more than once; its values add up).
    pub fn add_row_outer(&mut self, row: &[(usize, f64)], weight: f64) {
        for (k, &(i, a)) in row.iter().enumerate() {
            self.add(i, i, weight * a * a);
            for &(j, b) in &row[k + 1..] {
                // An off-diagonal pair stands for both (i, j) and (j, i); on
                // the diagonal (a repeated column) it must count twice.
                let factor = if i == j { 2.0 } else { 1.0 };
                self.add(i, j, factor * weight * a * b);
            }
        }
    }

    /// Adds `weight · Σ_j c_j c_jᵀ` where `c_j` is column `j` of the
    /// `idx.len() × D` coefficient block `coef` over the unknowns `idx` (an
    /// unknown may appear more than once). This is the normal-matrix block of
    /// `D` rows `Σ_k coef[k][j] x[idx[k]]`, j = 0..D, as gradients give.
    pub fn add_gram<const D: usize>(&mut self, idx: &[usize], coef: &[[f64; D]], weight: f64) {
        for p in 0..idx.len() {
            for q in p..idx.len() {
                let g: f64 = (0..D).map(|j| coef[p][j] * coef[q][j]).sum::<f64>() * weight;
                let factor = if p != q && idx[p] == idx[q] { 2.0 } else { 1.0 };
                self.add(idx[p], idx[q], factor * g);
            }
        }
    }

    /// Compresses into a [`SymmetricMatrix`], summing duplicates.
    pub fn build(self) -> SymmetricMatrix {
        // Bucket the entries by column (a counting sort), then sort each
        // short column by row and sum duplicates: linear apart from the
        // small per-column sorts.
        let n = self.n;
        let mut start = vec![0usize; n + 1];
        for e in &self.entries {
            start[e.0 as usize + 1] += 1;
        }
        for j in 0..n {
            start[j + 1] += start[j];
        }
        let mut next = start.clone();
        let mut bucket: Vec<(u32, f64)> = vec![(0, 0.0); self.entries.len()];
        for &(c, r, v) in &self.entries {
            bucket[next[c as usize]] = (r, v);
            next[c as usize] += 1;
        }
        drop(self.entries);
        // Columns in parallel: each is summed in the same order whatever
        // the threads.
        let mut columns: Vec<&mut [(u32, f64)]> = Vec::with_capacity(n);
        let mut rest = &mut bucket[..];
        for j in 0..n {
            let (column, tail) = rest.split_at_mut(start[j + 1] - start[j]);
            columns.push(column);
            rest = tail;
        }
        let lengths: Vec<usize> = columns
            .into_par_iter()
            .with_min_len(1024)
            .map(sum_duplicates)
            .collect();
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        for len in &lengths {
            col_ptr.push(col_ptr.last().unwrap() + len);
        }
        let mut row_idx = Vec::with_capacity(col_ptr[n]);
        let mut values: Vec<f64> = Vec::with_capacity(col_ptr[n]);
        for (j, len) in lengths.into_iter().enumerate() {
            for &(r, v) in &bucket[start[j]..start[j] + len] {
                row_idx.push(r as usize);
                values.push(v);
            }
        }
        SymmetricMatrix {
            n,
            col_ptr,
            row_idx,
            values,
        }
    }
}

/// Sorts a column's `(row, value)` entries by row and sums those of one row,
/// in place; returns how many rows remain (at the start of `column`).
fn sum_duplicates(column: &mut [(u32, f64)]) -> usize {
    column.sort_unstable_by_key(|e| e.0);
    let mut len = 0;
    for k in 0..column.len() {
        let (r, v) = column[k];
        if len > 0 && column[len - 1].0 == r {
            column[len - 1].1 += v;
        } else {
            column[len] = (r, v);
            len += 1;
        }
    }
    len
}

/// A Cholesky factorization `A = L Lᵀ` (with a fill-reducing ordering).
#[derive(Debug)]
pub struct Cholesky {
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    kind: FactorKind,
    /// The sparsity pattern the symbolic analysis was made for.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl Cholesky {
    /// Number of stored values of the factor `L` (each read once by a
    /// forward and once by a back substitution).
    pub fn factor_len(&self) -> usize {
        self.l_values.len()
    }

    /// Factors the symmetric positive definite `matrix`.
    ///
    /// # Errors
    /// [`Error::Solver`] when the matrix is not numerically positive definite.
    pub fn new(matrix: &SymmetricMatrix, kind: FactorKind) -> Result<Self> {
        let threshold = kind.threshold(matrix.n);
        let a = matrix.as_faer();
        let order = ordering::fill_reducing_order(matrix)?;
        let mut inverse = vec![0; order.len()];
        for (k, &i) in order.iter().enumerate() {
            inverse[i] = k;
        }
        let symbolic = factorize_symbolic_cholesky(
            a.symbolic(),
            Side::Upper,
            SymmetricOrdering::Custom(PermRef::new_checked(&order, &inverse, matrix.n)),
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: threshold,
                ..Default::default()
            },
        )
        .map_err(|e| Error::Solver(format!("symbolic factorization failed: {e:?}")))?;
        let mut this = Self {
            l_values: vec![0.0; symbolic.len_val()],
            symbolic,
            kind,
            col_ptr: matrix.col_ptr.clone(),
            row_idx: matrix.row_idx.clone(),
        };
        this.factor_numeric(matrix)?;
        Ok(this)
    }

    /// Factors a new matrix, reusing the ordering and symbolic analysis when
    /// it has the sparsity pattern of the one given to [`Cholesky::new`]
    /// (and starting afresh when it does not).
    ///
    /// # Errors
    /// [`Error::Solver`] when the matrix is not numerically positive definite.
    pub fn refactor(&mut self, matrix: &SymmetricMatrix) -> Result<()> {
        if matrix.col_ptr != self.col_ptr || matrix.row_idx != self.row_idx {
            *self = Self::new(matrix, self.kind)?;
            return Ok(());
        }
        self.factor_numeric(matrix)
    }

    /// The numeric factorization of `matrix`, whose pattern is the analysed one.
    fn factor_numeric(&mut self, matrix: &SymmetricMatrix) -> Result<()> {
        let a = matrix.as_faer();
        let par = Par::Seq;
        let req = self
            .symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default());
        let mut mem = MemBuffer::new(req);
        self.symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                a,
                Side::Upper,
                LltRegularization::default(),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|_| {
                Error::Solver(
                    "the matrix is not positive definite (a disconnected part with nothing \
                     to hold it, or degenerate triangles)"
                        .into(),
                )
            })?;
        Ok(())
    }

    /// Dimension.
    pub fn dim(&self) -> usize {
        self.symbolic.nrows()
    }

    /// Bytes a solve reads from the factor: its values and the row indices
    /// that go with them (one per value for the simplicial factor, one per
    /// row of each supernode for the supernodal one).
    pub fn factor_bytes(&self) -> usize {
        let indices = match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => s.row_idx().len(),
            SymbolicCholeskyRaw::Supernodal(s) => s.row_idx().len(),
        };
        8 * (self.l_values.len() + indices)
    }

    /// The fill-reducing ordering: row `i` of the factored system is row
    /// `permutation[i]` of the matrix (`None`: the identity).
    pub fn permutation(&self) -> Option<&[usize]> {
        self.symbolic.perm().map(|p| p.arrays().0)
    }

    /// Overwrites `rows` (`K` right-hand sides side by side, rows in the
    /// order of [`Cholesky::permutation`]) with the solution, in that order.
    ///
    /// # Panics
    /// If `rows.len()` is not the dimension.
    #[track_caller]
    pub fn solve_rows<const K: usize>(&self, rows: &mut [[f64; K]]) {
        assert_eq!(rows.len(), self.dim(), "right-hand side has the wrong size");
        pulp::Arch::new().dispatch(Substitution { factor: self, rows });
    }

    /// Scratch space needed to solve `ncols` right-hand sides at once.
    pub fn solve_scratch(&self, ncols: usize) -> StackReq {
        self.symbolic.solve_in_place_scratch::<f64>(ncols, Par::Seq)
    }

    /// Overwrites the column-major `dim × ncols` block `rhs` with `A⁻¹ rhs`.
    ///
    /// # Panics
    /// If `rhs.len() != dim * ncols` or `stack` is smaller than
    /// [`Cholesky::solve_scratch`] asks.
    #[track_caller]
    pub fn solve_in_place(&self, rhs: &mut [f64], ncols: usize, stack: &mut MemStack) {
        let n = self.dim();
        assert_eq!(rhs.len(), n * ncols, "right-hand side has the wrong size");
        let rhs = MatMut::from_column_major_slice_mut(rhs, n, ncols);
        LltRef::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            stack,
        );
    }
}

/// [`Cholesky::solve_rows`] with AVX2 (x86-64-v3) when the processor has
/// it (chosen when the program runs): the interleaved rows of several
/// right-hand sides are then one or two vectors each.
struct Substitution<'a, const K: usize> {
    factor: &'a Cholesky,
    rows: &'a mut [[f64; K]],
}

impl<const K: usize> pulp::WithSimd for Substitution<'_, K> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) {
        let Self { factor, rows } = self;
        match factor.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                substitution::simplicial(s, &factor.l_values, rows)
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                substitution::supernodal(s, &factor.l_values, rows)
            }
        }
    }
}

/// Per-thread scratch for [`PinnedSystem::solve`].
pub struct Workspace {
    mem: MemBuffer,
    reduced: Vec<f64>,
    /// `Vec<[f64; ncols]>` of one row per unknown, for 1 to 4 columns.
    rows: Box<dyn std::any::Any + Send + Sync>,
    ncols: usize,
}

impl std::fmt::Debug for Workspace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Workspace")
            .field("ncols", &self.ncols)
            .finish_non_exhaustive()
    }
}

/// `A x = b` with some unknowns held at given values, the rest factored once.
///
/// The pinned unknowns are eliminated: with `f` the free and `p` the pinned
/// indices, `A_ff x_f = b_f - A_fp x_p`, where `A_ff` is factored in
/// [`PinnedSystem::new`].
#[derive(Debug)]
pub struct PinnedSystem {
    n: usize,
    /// Free index in the reduced system of each unknown, or `u32::MAX` if pinned.
    reduced_of: Vec<u32>,
    free: Vec<u32>,
    pinned: Vec<u32>,
    /// `A_fp` in compressed-column form over the pinned columns:
    /// `(reduced row, value)` pairs, columns delimited by `coupling_ptr`.
    coupling_ptr: Vec<usize>,
    coupling: Vec<(u32, f64)>,
    cholesky: Cholesky,
    /// The unknown at each row of the factored system (free unknowns in
    /// the factor's ordering).
    order: Vec<u32>,
    /// The row of each unknown in the layout of
    /// [`PinnedSystem::solve_in_rows`]: the free unknowns in the factor's
    /// order, then the pinned ones in the order they were given.
    row_of: Vec<u32>,
}

impl PinnedSystem {
    /// Eliminates the `pinned` unknowns (any order, no repeats) from `matrix`
    /// and factors what remains.
    ///
    /// # Errors
    /// [`Error::Solver`] when the reduced matrix is not positive definite,
    /// [`Error::InvalidArgument`] when a pinned index is out of range or repeated.
    pub fn new(matrix: &SymmetricMatrix, pinned: &[usize], kind: FactorKind) -> Result<Self> {
        let n = matrix.n;
        let mut reduced_of = vec![0u32; n];
        for &p in pinned {
            if p >= n || reduced_of[p] == u32::MAX {
                return Err(Error::InvalidArgument(format!(
                    "pinned unknown {p} is out of range or repeated"
                )));
            }
            reduced_of[p] = u32::MAX;
        }
        let mut free = Vec::with_capacity(n - pinned.len());
        for (i, r) in reduced_of.iter_mut().enumerate() {
            if *r != u32::MAX {
                *r = free.len() as u32;
                free.push(i as u32);
            }
        }
        let pinned: Vec<u32> = pinned.iter().map(|&p| p as u32).collect();
        let (reduced, coupling_ptr, coupling) = split(matrix, &reduced_of, &free, &pinned);
        let cholesky = Cholesky::new(&reduced, kind)?;
        let (order, row_of) = ordering(&cholesky, &free, &pinned);
        Ok(Self {
            n,
            reduced_of,
            free,
            pinned,
            coupling_ptr,
            coupling,
            cholesky,
            order,
            row_of,
        })
    }

    /// Factors a new matrix with the same sparsity pattern and the same
    /// pinned unknowns, reusing the ordering and symbolic analysis.
    ///
    /// # Errors
    /// [`Error::Solver`] when the reduced matrix is not positive definite.
    ///
    /// # Panics
    /// If the matrix has another dimension.
    pub fn refactor(&mut self, matrix: &SymmetricMatrix) -> Result<()> {
        assert_eq!(matrix.n, self.n, "matrix of another dimension");
        let (reduced, coupling_ptr, coupling) =
            split(matrix, &self.reduced_of, &self.free, &self.pinned);
        self.cholesky.refactor(&reduced)?;
        (self.order, self.row_of) = ordering(&self.cholesky, &self.free, &self.pinned);
        self.coupling_ptr = coupling_ptr;
        self.coupling = coupling;
        Ok(())
    }

    /// Number of unknowns, pinned ones included.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Number of stored values of the Cholesky factor.
    pub fn factor_len(&self) -> usize {
        self.cholesky.factor_len()
    }

    /// Bytes a solve reads from the factor ([`Cholesky::factor_bytes`]).
    pub fn factor_bytes(&self) -> usize {
        self.cholesky.factor_bytes()
    }

    /// Scratch for solving `ncols` right-hand sides at once; one per thread.
    pub fn workspace(&self, ncols: usize) -> Workspace {
        let m = self.free.len();
        let rows: Box<dyn std::any::Any + Send + Sync> = match ncols {
            1 => Box::new(vec![[0.0; 1]; self.n]),
            2 => Box::new(vec![[0.0; 2]; self.n]),
            3 => Box::new(vec![[0.0; 3]; self.n]),
            4 => Box::new(vec![[0.0; 4]; self.n]),
            _ => Box::new(()),
        };
        let columns = if ncols <= 4 { 0 } else { m * ncols };
        Workspace {
            mem: MemBuffer::new(if ncols <= 4 {
                StackReq::EMPTY
            } else {
                self.cholesky.solve_scratch(ncols)
            }),
            reduced: vec![0.0; columns],
            rows,
            ncols,
        }
    }

    /// Solves for `ncols` right-hand sides at once.
    ///
    /// `b` and `x` are column-major `dim × ncols`; `pinned_values` is
    /// column-major `#pinned × ncols`, or `None` for all zeros. On return `x`
    /// holds the solution with the pinned unknowns at their values (the rows
    /// of `b` at pinned unknowns are ignored).
    ///
    /// # Panics
    /// If a slice has the wrong length or `ws` was made for another `ncols`.
    #[track_caller]
    pub fn solve(
        &self,
        b: &[f64],
        pinned_values: Option<&[f64]>,
        x: &mut [f64],
        ws: &mut Workspace,
    ) {
        let (n, m, k) = (self.n, self.free.len(), ws.ncols);
        assert!(
            b.len() == n * k && x.len() == n * k,
            "right-hand side has the wrong size"
        );
        match k {
            1 => return self.solve_rows::<1>(b, pinned_values, x, ws),
            2 => return self.solve_rows::<2>(b, pinned_values, x, ws),
            3 => return self.solve_rows::<3>(b, pinned_values, x, ws),
            4 => return self.solve_rows::<4>(b, pinned_values, x, ws),
            _ => {}
        }
        let np = self.pinned.len();
        for c in 0..k {
            let (bc, rc) = (&b[c * n..(c + 1) * n], &mut ws.reduced[c * m..(c + 1) * m]);
            for (r, &i) in rc.iter_mut().zip(&self.free) {
                *r = bc[i as usize];
            }
            if let Some(values) = pinned_values {
                assert_eq!(values.len(), np * k, "pinned values have the wrong size");
                for q in 0..np {
                    let xp = values[c * np + q];
                    if xp != 0.0 {
                        for &(r, a) in
                            &self.coupling[self.coupling_ptr[q]..self.coupling_ptr[q + 1]]
                        {
                            rc[r as usize] -= a * xp;
                        }
                    }
                }
            }
        }
        self.cholesky
            .solve_in_place(&mut ws.reduced, k, MemStack::new(&mut ws.mem));
        for c in 0..k {
            let (xc, rc) = (&mut x[c * n..(c + 1) * n], &ws.reduced[c * m..(c + 1) * m]);
            for (&i, &r) in self.free.iter().zip(rc) {
                xc[i as usize] = r;
            }
            for (q, &p) in self.pinned.iter().enumerate() {
                xc[p as usize] = pinned_values.map_or(0.0, |v| v[c * np + q]);
            }
        }
    }

    /// [`PinnedSystem::solve`] for `K` columns: gathered straight into the
    /// row layout ([`PinnedSystem::solve_in_rows`]), solved there, and
    /// scattered back (three passes over the unknowns).
    fn solve_rows<const K: usize>(
        &self,
        b: &[f64],
        pinned_values: Option<&[f64]>,
        x: &mut [f64],
        ws: &mut Workspace,
    ) {
        let (n, np, m) = (self.n, self.pinned.len(), self.free.len());
        let rows = ws
            .rows
            .downcast_mut::<Vec<[f64; K]>>()
            .expect("workspace made for this number of columns");
        for (row, &i) in rows.iter_mut().zip(&self.order) {
            *row = std::array::from_fn(|c| b[c * n + i as usize]);
        }
        if let Some(values) = pinned_values {
            assert_eq!(values.len(), np * K, "pinned values have the wrong size");
        }
        for (q, row) in rows[m..].iter_mut().enumerate() {
            *row = std::array::from_fn(|c| pinned_values.map_or(0.0, |v| v[c * np + q]));
        }
        self.solve_in_rows(rows);
        for (row, &i) in rows.iter().zip(self.order.iter().chain(&self.pinned)) {
            for c in 0..K {
                x[c * n + i as usize] = row[c];
            }
        }
    }

    /// The row of unknown `u` in the layout of
    /// [`PinnedSystem::solve_in_rows`]: the free unknowns in the factor's
    /// order, then the pinned ones in the order they were given.
    #[inline]
    pub fn row_of(&self, u: usize) -> usize {
        self.row_of[u] as usize
    }

    /// Solves for `K` right-hand sides side by side, one row per unknown in
    /// the layout of [`PinnedSystem::row_of`]: on entry the free
    /// rows hold the right-hand side and the pinned rows their values; on
    /// return the free rows hold the solution. Whoever builds the right-hand
    /// side straight in this layout saves the passes of
    /// [`PinnedSystem::solve`] that gather and scatter it.
    ///
    /// # Panics
    /// If `rows` does not have one row per unknown.
    #[track_caller]
    pub fn solve_in_rows<const K: usize>(&self, rows: &mut [[f64; K]]) {
        assert_eq!(rows.len(), self.n, "one row per unknown");
        let (free, pinned) = rows.split_at_mut(self.free.len());
        for (q, xp) in pinned.iter().enumerate() {
            if *xp != [0.0; K] {
                for &(r, a) in &self.coupling[self.coupling_ptr[q]..self.coupling_ptr[q + 1]] {
                    let row = &mut free[self.row_of(self.free[r as usize] as usize)];
                    for c in 0..K {
                        row[c] -= a * xp[c];
                    }
                }
            }
        }
        self.cholesky.solve_rows(free);
    }

    /// Reduced index of unknown `i`, `None` if it is pinned.
    pub fn reduced_index(&self, i: usize) -> Option<usize> {
        match self.reduced_of[i] {
            u32::MAX => None,
            r => Some(r as usize),
        }
    }
}

/// The unknown at each row of the factored system (the free unknowns in
/// the factor's order), and the row of each unknown
/// ([`PinnedSystem::row_of`]: the pinned ones after the free ones).
fn ordering(cholesky: &Cholesky, free: &[u32], pinned: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let order: Vec<u32> = match cholesky.permutation() {
        Some(p) => p.iter().map(|&r| free[r]).collect(),
        None => free.to_vec(),
    };
    let mut row_of = vec![0u32; free.len() + pinned.len()];
    for (row, &i) in order.iter().chain(pinned).enumerate() {
        row_of[i as usize] = row as u32;
    }
    (order, row_of)
}

/// The free-free block of `matrix` and the free-pinned coupling, by pinned
/// column: `(A_ff, coupling_ptr, [(reduced row, value)])`.
///
/// Free unknowns keep their relative order (`reduced_of` increases along
/// `free`), so each column of the free block is its column of `matrix`
/// with the pinned rows left out: still sorted, still upper.
#[allow(clippy::type_complexity)]
fn split(
    matrix: &SymmetricMatrix,
    reduced_of: &[u32],
    free: &[u32],
    pinned: &[u32],
) -> (SymmetricMatrix, Vec<usize>, Vec<(u32, f64)>) {
    let mut pinned_col = vec![u32::MAX; matrix.n];
    for (k, &p) in pinned.iter().enumerate() {
        pinned_col[p as usize] = k as u32;
    }
    let mut col_ptr = Vec::with_capacity(free.len() + 1);
    let mut row_idx = Vec::with_capacity(matrix.nnz());
    let mut values = Vec::with_capacity(matrix.nnz());
    col_ptr.push(0);
    let mut coupling_entries: Vec<(u32, u32, f64)> = Vec::new();
    for j in 0..matrix.n {
        let rj = reduced_of[j];
        for p in matrix.col_ptr[j]..matrix.col_ptr[j + 1] {
            let (i, v) = (matrix.row_idx[p], matrix.values[p]);
            match (reduced_of[i], rj) {
                (u32::MAX, u32::MAX) => {}
                (u32::MAX, rj) => coupling_entries.push((pinned_col[i], rj, v)),
                (ri, u32::MAX) => coupling_entries.push((pinned_col[j], ri, v)),
                (ri, _) => {
                    row_idx.push(ri as usize);
                    values.push(v);
                }
            }
        }
        if rj != u32::MAX {
            col_ptr.push(row_idx.len());
        }
    }
    let reduced = SymmetricMatrix {
        n: free.len(),
        col_ptr,
        row_idx,
        values,
    };
    coupling_entries.sort_unstable_by_key(|e| (e.0, e.1));
    let mut coupling_ptr = vec![0usize; pinned.len() + 1];
    for e in &coupling_entries {
        coupling_ptr[e.0 as usize + 1] += 1;
    }
    for k in 0..pinned.len() {
        coupling_ptr[k + 1] += coupling_ptr[k];
    }
    let coupling = coupling_entries
        .into_iter()
        .map(|(_, r, v)| (r, v))
        .collect();
    (reduced, coupling_ptr, coupling)
}
