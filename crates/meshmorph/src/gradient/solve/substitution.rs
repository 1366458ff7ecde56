//! Forward and back substitution with a Cholesky factor `L` (`L Lᵀ x = b`),
//! the `K` right-hand sides interleaved (row `i` of every column side by
//! side), so that each row the substitution touches is one cache line
//! rather than `K` far apart.
//!
//! A frame's solve reads the whole factor twice and does two flops per
//! value read: it is bound by memory traffic. faer's solves take the
//! right-hand sides column by column, and its supernodal solve hands every
//! supernode, however small, to dense kernels; here the simplicial factor
//! is read value by value with its row indices, and the supernodal factor
//! by supernode: values only, with one list of row indices per supernode
//! (half the bytes of the simplicial factor for the same values).

use faer::sparse::linalg::cholesky::simplicial::SymbolicSimplicialCholesky;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;

/// `x ← L⁻ᵀ L⁻¹ x` for a simplicial factor: columns of `L` in compressed
/// form, each starting with its diagonal entry.
#[inline(always)]
pub(super) fn simplicial<const K: usize>(
    symbolic: &SymbolicSimplicialCholesky<usize>,
    values: &[f64],
    x: &mut [[f64; K]],
) {
    let (col_ptr, row_idx) = (symbolic.col_ptr(), symbolic.row_idx());
    let n = x.len();
    for j in 0..n {
        let (start, end) = (col_ptr[j], col_ptr[j + 1]);
        let d = values[start];
        let xj = x[j].map(|v| v / d);
        x[j] = xj;
        subtract_scaled(&values[start + 1..end], &row_idx[start + 1..end], xj, x);
    }
    for j in (0..n).rev() {
        let (start, end) = (col_ptr[j], col_ptr[j + 1]);
        let sum = dot(&values[start + 1..end], &row_idx[start + 1..end], x);
        let d = values[start];
        x[j] = std::array::from_fn(|c| (x[j][c] - sum[c]) / d);
    }
}

/// `x[rows[k]] −= l[k] · y` for every `k`.
#[inline(always)]
fn subtract_scaled<const K: usize>(l: &[f64], rows: &[usize], y: [f64; K], x: &mut [[f64; K]]) {
    for (&l, &r) in l.iter().zip(rows) {
        let xi = &mut x[r];
        for c in 0..K {
            xi[c] -= l * y[c];
        }
    }
}

/// `Σ_k l[k] · x[rows[k]]`, with two sums in flight so that the additions
/// do not wait on each other.
#[inline(always)]
fn dot<const K: usize>(l: &[f64], rows: &[usize], x: &[[f64; K]]) -> [f64; K] {
    let (mut even, mut odd) = ([0.0; K], [0.0; K]);
    let mut pairs = l.chunks_exact(2).zip(rows.chunks_exact(2));
    for (l2, r2) in &mut pairs {
        let (a, b) = (x[r2[0]], x[r2[1]]);
        for c in 0..K {
            even[c] += l2[0] * a[c];
            odd[c] += l2[1] * b[c];
        }
    }
    if l.len() % 2 == 1 {
        let (l, a) = (l[l.len() - 1], x[rows[rows.len() - 1]]);
        for c in 0..K {
            even[c] += l * a[c];
        }
    }
    std::array::from_fn(|c| even[c] + odd[c])
}

/// `x ← L⁻ᵀ L⁻¹ x` for a supernodal factor: each supernode a dense
/// column-major block, its diagonal block (lower triangle) on top of the
/// rows of its pattern.
#[inline(always)]
pub(super) fn supernodal<const K: usize>(
    symbolic: &SymbolicSupernodalCholesky<usize>,
    values: &[f64],
    x: &mut [[f64; K]],
) {
    let count = symbolic.n_supernodes();
    let (begin, end) = (symbolic.supernode_begin(), symbolic.supernode_end());
    let val_ptr = symbolic.col_ptr_for_val();
    for s in 0..count {
        let (first, width) = (begin[s], end[s] - begin[s]);
        let pattern = symbolic.supernode(s).pattern();
        let height = width + pattern.len();
        let block = &values[val_ptr[s]..val_ptr[s + 1]];
        for jj in 0..width {
            let column = &block[jj * height..(jj + 1) * height];
            let xj = x[first + jj].map(|v| v / column[jj]);
            x[first + jj] = xj;
            for ii in jj + 1..width {
                let (l, xi) = (column[ii], &mut x[first + ii]);
                for c in 0..K {
                    xi[c] -= l * xj[c];
                }
            }
            subtract_scaled(&column[width..], pattern, xj, x);
        }
    }
    for s in (0..count).rev() {
        let (first, width) = (begin[s], end[s] - begin[s]);
        let pattern = symbolic.supernode(s).pattern();
        let height = width + pattern.len();
        let block = &values[val_ptr[s]..val_ptr[s + 1]];
        for jj in (0..width).rev() {
            let column = &block[jj * height..(jj + 1) * height];
            let mut acc = dot(&column[width..], pattern, x);
            for ii in jj + 1..width {
                let (l, xi) = (column[ii], x[first + ii]);
                for c in 0..K {
                    acc[c] += l * xi[c];
                }
            }
            let d = column[jj];
            x[first + jj] = std::array::from_fn(|c| (x[first + jj][c] - acc[c]) / d);
        }
    }
}
