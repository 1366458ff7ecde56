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
pub(super) fn fill_reducing_order(matrix: &SymmetricMatrix) -> Result<Vec<usize>> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gradient::solve::SymmetricBuilder;
    use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymmetricOrdering};
    use faer::Side;

    /// The fit pattern of a triangulated `k × k` grid whose every triangle
    /// has a fourth vertex (unknowns `k² + t`) coupled with its corners and,
    /// for every `stride`-th pair of consecutive triangles (none when
    /// `stride` is 0), a coupling between the pair's fourth vertices.
    fn grid_with_fourth_vertices(k: usize, stride: usize) -> SymmetricMatrix {
        let grid = crate::mesh::shapes::strip(1.0, 1.0, k - 1, k - 1);
        let n_vertices = grid.num_vertices();
        assert_eq!(n_vertices, k * k);
        let triangles: Vec<[usize; 3]> = grid
            .triangles()
            .iter()
            .map(|t| t.map(|v| v as usize))
            .collect();
        let n = n_vertices + triangles.len();
        let mut b = SymmetricBuilder::new(n, 16 * n);
        for (t, tri) in triangles.iter().enumerate() {
            let all = [tri[0], tri[1], tri[2], n_vertices + t];
            for &p in &all {
                for &q in &all {
                    if p <= q {
                        b.add(p, q, if p == q { 4.0 } else { -1.0 });
                    }
                }
            }
        }
        for t in (0..triangles.len()).step_by(2 * stride.max(1)) {
            if stride > 0 {
                b.add(n_vertices + t, n_vertices + t + 1, -1.0);
            }
        }
        b.build()
    }

    fn fill(matrix: &SymmetricMatrix, ordering: SymmetricOrdering<'_, usize>) -> usize {
        factorize_symbolic_cholesky(
            matrix.as_faer().symbolic(),
            Side::Upper,
            ordering,
            Default::default(),
        )
        .unwrap()
        .len_val()
    }

    #[test]
    fn an_order_is_a_permutation_with_fourth_vertices_first_and_no_more_fill_than_amd() {
        for (k, stride) in [(2, 0), (5, 0), (12, 0), (12, 1), (12, 3), (30, 0), (30, 4)] {
            let matrix = grid_with_fourth_vertices(k, stride);
            let order = fill_reducing_order(&matrix).unwrap();
            let n = matrix.n;
            let mut seen = vec![false; n];
            for &i in &order {
                assert!(i < n && !std::mem::replace(&mut seen[i], true));
            }
            assert_eq!(order.len(), n);
            // Without the couplings across edges every fourth vertex is
            // eliminated before any vertex inside the grid.
            if stride == 0 {
                let position = |i: usize| order.iter().position(|&o| o == i).unwrap();
                let last_fourth = (k * k..n).map(position).max().unwrap();
                for i in 1..k - 1 {
                    for j in 1..k - 1 {
                        assert!(position(i * k + j) > last_fourth, "k = {k}");
                    }
                }
            }
            let mut inverse = vec![0; n];
            for (r, &i) in order.iter().enumerate() {
                inverse[i] = r;
            }
            let ours = fill(
                &matrix,
                SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(&order, &inverse, n)),
            );
            let amd = fill(&matrix, SymmetricOrdering::Amd);
            assert!(
                ours as f64 <= 1.02 * amd as f64,
                "k = {k}, stride {stride}: fill {ours} against AMD's {amd}"
            );
        }
    }

    #[test]
    fn an_empty_or_diagonal_system_is_ordered() {
        let empty = SymmetricBuilder::new(0, 0).build();
        assert!(fill_reducing_order(&empty).unwrap().is_empty());
        let mut b = SymmetricBuilder::new(4, 4);
        for i in 0..4 {
            b.add(i, i, 1.0);
        }
        assert_eq!(fill_reducing_order(&b.build()).unwrap(), vec![0, 1, 2, 3]);
    }
}
