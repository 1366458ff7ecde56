//! The order in which a Cholesky factorization eliminates the unknowns.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::CholeskySymbolicParams;
use faer::sparse::SymbolicSparseColMatRef;

use super::SymmetricMatrix;
use crate::error::{Error, Result};

/// A fill-reducing elimination order of the unknowns of `matrix`:
/// `order[k]` is the unknown eliminated `k`-th.
///
/// First come the unknowns whose neighbours (the other rows of their column)
/// are all coupled with each other: eliminating one adds no entry to the
/// factor, and leaves the others as they were. A triangle's fourth vertex
/// in a fit term, coupled only with the triangle's three corners, is one.
/// The remaining unknowns follow in the approximate minimum degree order
/// (faer's AMD) of the pattern among them. Minimum degree would itself take
/// the first group first; finding it here with a look at each short column
/// halves the graph AMD has to order when a mesh's every triangle has a
/// fourth vertex, and ordering is most of the symbolic analysis.
///
/// # Errors
/// [`Error::Solver`] when faer cannot order the pattern (out of memory).
pub fn fill_reducing_order(matrix: &SymmetricMatrix) -> Result<Vec<usize>> {
    let neighbours = Neighbours::new(matrix);
    let n = matrix.n;
    let eliminated_first: Vec<bool> = (0..n).map(|i| neighbours.form_a_clique(i)).collect();
    let mut order: Vec<usize> = (0..n).filter(|&i| eliminated_first[i]).collect();
    // The pattern among the others, upper triangle, renumbered.
    let mut index_of = vec![usize::MAX; n];
    let rest: Vec<usize> = (0..n).filter(|&i| !eliminated_first[i]).collect();
    for (k, &i) in rest.iter().enumerate() {
        index_of[i] = k;
    }
    let mut col_ptr = Vec::with_capacity(rest.len() + 1);
    let mut row_idx = Vec::with_capacity(matrix.nnz());
    col_ptr.push(0);
    for &j in &rest {
        let rows = &matrix.row_idx[matrix.col_ptr[j]..matrix.col_ptr[j + 1]];
        row_idx.extend(
            rows.iter()
                .map(|&i| index_of[i])
                .filter(|&i| i != usize::MAX),
        );
        col_ptr.push(row_idx.len());
    }
    let m = rest.len();
    let pattern = SymbolicSparseColMatRef::new_checked(m, m, &col_ptr, None, &row_idx);
    let (mut perm, mut perm_inv) = (vec![0usize; m], vec![0usize; m]);
    let mut mem = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(m, row_idx.len()))
        .map_err(|_| Error::Solver("out of memory ordering the unknowns".into()))?;
    amd::order_maybe_unsorted(
        &mut perm,
        &mut perm_inv,
        pattern,
        CholeskySymbolicParams::default().amd_params,
        MemStack::new(&mut mem),
    )
    .map_err(|e| Error::Solver(format!("ordering the unknowns failed: {e:?}")))?;
    order.extend(perm.iter().map(|&k| rest[k]));
    Ok(order)
}

/// The off-diagonal pattern of a symmetric matrix, both triangles: the
/// sorted neighbours of each unknown.
struct Neighbours {
    ptr: Vec<usize>,
    idx: Vec<u32>,
}

impl Neighbours {
    /// Unknowns with more neighbours than this are not examined: the check
    /// is quadratic in the count, and such unknowns are rarely cliques'.
    const MAX_EXAMINED: usize = 8;

    fn new(matrix: &SymmetricMatrix) -> Self {
        let n = matrix.n;
        let mut count = vec![0usize; n + 1];
        for j in 0..n {
            for &i in &matrix.row_idx[matrix.col_ptr[j]..matrix.col_ptr[j + 1]] {
                if i != j {
                    count[i + 1] += 1;
                    count[j + 1] += 1;
                }
            }
        }
        for k in 0..n {
            count[k + 1] += count[k];
        }
        let ptr = count;
        let mut fill = ptr.clone();
        let mut idx = vec![0u32; ptr[n]];
        // Column by column with rows increasing: every list comes out sorted
        // (entries `j` of row `i < j` arrive in increasing `j`, after the
        // entries `i' < i` of column `i` itself).
        for j in 0..n {
            for &i in &matrix.row_idx[matrix.col_ptr[j]..matrix.col_ptr[j + 1]] {
                if i != j {
                    idx[fill[j]] = i as u32;
                    fill[j] += 1;
                    idx[fill[i]] = j as u32;
                    fill[i] += 1;
                }
            }
        }
        Self { ptr, idx }
    }

    fn of(&self, i: usize) -> &[u32] {
        &self.idx[self.ptr[i]..self.ptr[i + 1]]
    }

    /// Whether the neighbours of `i` are all coupled with each other.
    fn form_a_clique(&self, i: usize) -> bool {
        let near = self.of(i);
        near.len() <= Self::MAX_EXAMINED
            && near.iter().enumerate().all(|(k, &a)| {
                let of_a = self.of(a as usize);
                near[k + 1..].iter().all(|b| of_a.binary_search(b).is_ok())
            })
    }
}
