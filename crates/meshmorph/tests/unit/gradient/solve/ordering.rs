use meshmorph::gradient::solve::SymmetricMatrix;

use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymmetricOrdering};
use faer::Side;
use meshmorph::gradient::solve::ordering::*;
use meshmorph::gradient::solve::SymmetricBuilder;

/// The fit pattern of a triangulated `k × k` grid whose every triangle
/// has a fourth vertex (unknowns `k² + t`) coupled with its corners and,
/// for every `stride`-th pair of consecutive triangles (none when
/// `stride` is 0), a coupling between the pair's fourth vertices.
fn grid_with_fourth_vertices(k: usize, stride: usize) -> SymmetricMatrix {
    let grid = meshmorph::mesh::shapes::strip(1.0, 1.0, k - 1, k - 1);
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
