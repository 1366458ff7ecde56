//! New values for a pinned system of an unchanged pattern, copied straight
//! into the reduced matrix and the coupling.
//!
//! [`PinnedSystem::new`](super::PinnedSystem::new) splits a matrix into the
//! free-free block and the free-pinned coupling by sorting its entries anew.
//! A system factored again and again with the same pattern (the rounds of
//! the correspondence) need not: each stored entry of the matrix has one
//! place in one of the two, found once in the factored pattern (no copy of
//! the matrix is made).

use super::SymmetricMatrix;

/// The entry goes nowhere (both its unknowns are pinned).
const NOWHERE: u32 = u32::MAX;
/// Set on a destination in the coupling (else it is in the reduced matrix).
const COUPLING: u32 = 1 << 31;

/// Where each stored entry of a matrix of one pattern goes.
#[derive(Debug)]
pub(super) struct Refill {
    /// The pattern of the full matrix.
    col_ptr: Vec<usize>,
    row_idx: Vec<u32>,
    /// For each stored entry: its index among the reduced matrix's values,
    /// or among the coupling's entries with [`COUPLING`] set, or
    /// [`NOWHERE`].
    to: Vec<u32>,
    /// The values of the reduced matrix, refilled in place.
    pub(super) values: Vec<f64>,
}

impl Refill {
    /// The destinations of the entries of `matrix`, if its pattern splits
    /// into exactly the given ones: `reduced_of` and the `coupling`
    /// (`(reduced row, value)` by pinned column, delimited by
    /// `coupling_ptr`, rows sorted) as [`super::PinnedSystem`] keeps them,
    /// `reduced_pattern` the compressed columns of the factored matrix.
    /// `None` when they do not (the matrix has another pattern), or there
    /// are too many entries to number.
    pub(super) fn new(
        matrix: &SymmetricMatrix,
        reduced_of: &[u32],
        pinned_col: impl Fn(usize) -> usize,
        (coupling_ptr, coupling): (&[usize], &[(u32, f64)]),
        (reduced_col_ptr, reduced_row_idx): (&[usize], &[usize]),
    ) -> Option<Self> {
        let reduced_nnz = reduced_row_idx.len();
        if matrix.nnz() >= COUPLING as usize
            || reduced_nnz >= COUPLING as usize
            || coupling.len() >= COUPLING as usize
        {
            return None;
        }
        let mut to = Vec::with_capacity(matrix.nnz());
        let (mut free_entries, mut coupling_entries) = (0, 0);
        for j in 0..matrix.n {
            for p in matrix.col_ptr[j]..matrix.col_ptr[j + 1] {
                let i = matrix.row_idx[p];
                to.push(match (reduced_of[i], reduced_of[j]) {
                    (u32::MAX, u32::MAX) => NOWHERE,
                    (u32::MAX, r) | (r, u32::MAX) => {
                        let q = pinned_col(if reduced_of[i] == u32::MAX { i } else { j });
                        let (start, end) = (coupling_ptr[q], coupling_ptr[q + 1]);
                        let k = coupling[start..end]
                            .binary_search_by_key(&r, |e| e.0)
                            .ok()?;
                        coupling_entries += 1;
                        (start + k) as u32 | COUPLING
                    }
                    (ri, rj) => {
                        let (ri, rj) = (ri as usize, rj as usize);
                        let (start, end) = (reduced_col_ptr[rj], reduced_col_ptr[rj + 1]);
                        let k = reduced_row_idx[start..end].binary_search(&ri).ok()?;
                        free_entries += 1;
                        (start + k) as u32
                    }
                });
            }
        }
        // Each entry has one place (the free unknowns keep their order), so
        // equal counts mean every place is filled.
        if free_entries != reduced_nnz || coupling_entries != coupling.len() {
            return None;
        }
        Some(Self {
            col_ptr: matrix.col_ptr.clone(),
            row_idx: matrix.row_idx.iter().map(|&i| i as u32).collect(),
            to,
            values: vec![0.0; reduced_nnz],
        })
    }

    /// Whether `matrix` has the pattern this was made for.
    pub(super) fn fits(&self, matrix: &SymmetricMatrix) -> bool {
        matrix.col_ptr == self.col_ptr
            && matrix.row_idx.len() == self.row_idx.len()
            && matrix
                .row_idx
                .iter()
                .zip(&self.row_idx)
                .all(|(&a, &b)| a == b as usize)
    }

    /// Copies the values of `matrix` (of the pattern, see
    /// [`Refill::fits`]) into [`Refill::values`] and `coupling`.
    pub(super) fn fill(&mut self, matrix: &SymmetricMatrix, coupling: &mut [(u32, f64)]) {
        debug_assert!(self.fits(matrix));
        for (&to, &v) in self.to.iter().zip(&matrix.values) {
            if to == NOWHERE {
                continue;
            }
            if to & COUPLING != 0 {
                coupling[(to & !COUPLING) as usize].1 = v;
            } else {
                self.values[to as usize] = v;
            }
        }
    }
}
