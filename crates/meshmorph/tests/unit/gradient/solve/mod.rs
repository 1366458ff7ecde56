mod ordering;

use meshmorph::gradient::solve::*;

/// Path-graph Laplacian plus `shift` on the diagonal.
fn path_laplacian(n: usize, shift: f64) -> SymmetricMatrix {
    let mut b = SymmetricBuilder::new(n, 3 * n);
    for i in 0..n - 1 {
        b.add(i, i, 1.0);
        b.add(i + 1, i + 1, 1.0);
        b.add(i, i + 1, -1.0);
    }
    for i in 0..n {
        b.add(i, i, shift);
    }
    b.build()
}

#[test]
fn builder_sums_duplicates_and_is_symmetric() {
    let mut b = SymmetricBuilder::new(3, 8);
    b.add(0, 1, 2.0);
    b.add(1, 0, 3.0);
    b.add(2, 2, 1.0);
    b.add(2, 2, 1.5);
    let m = b.build();
    assert_eq!(m.get(0, 1), 5.0);
    assert_eq!(m.get(1, 0), 5.0);
    assert_eq!(m.get(2, 2), 2.5);
    assert_eq!(m.get(0, 2), 0.0);
    assert_eq!(m.mul_vec(&[1.0, 1.0, 1.0]), vec![5.0, 5.0, 2.5]);
}

#[test]
fn solves_match_the_matrix_for_both_factor_kinds() {
    let n = 200;
    let m = path_laplacian(n, 0.01);
    let x_true: Vec<f64> = (0..2 * n).map(|i| (i as f64 * 0.37).sin()).collect();
    let mut b = m.mul_vec(&x_true[..n]);
    b.extend(m.mul_vec(&x_true[n..]));
    for kind in [
        FactorKind::Simplicial,
        FactorKind::Supernodal,
        FactorKind::Auto,
    ] {
        let s = PinnedSystem::new(&m, &[], kind).unwrap();
        let mut ws = s.workspace(2);
        let mut x = vec![0.0; 2 * n];
        s.solve(&b, None, &mut x, &mut ws);
        let err = x
            .iter()
            .zip(&x_true)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-9, "{kind:?}: {err}");
    }
}

#[test]
fn pinned_unknowns_are_eliminated() {
    // A singular Laplacian becomes definite once one unknown is pinned;
    // with both ends pinned the solution of L x = 0 is the straight line.
    let n = 11;
    let m = path_laplacian(n, 0.0);
    assert!(Cholesky::new(&m, FactorKind::Simplicial).is_err());
    let s = PinnedSystem::new(&m, &[n - 1, 0], FactorKind::Auto).unwrap();
    let mut ws = s.workspace(1);
    let mut x = vec![0.0; n];
    s.solve(&vec![0.0; n], Some(&[10.0, 0.0]), &mut x, &mut ws);
    for (i, xi) in x.iter().enumerate() {
        assert!((xi - i as f64).abs() < 1e-12, "{x:?}");
    }
    assert_eq!(s.reduced_index(0), None);
    assert_eq!(s.reduced_index(1), Some(0));
    assert!(PinnedSystem::new(&m, &[3, 3], FactorKind::Auto).is_err());
}

#[test]
fn refactoring_reuses_or_redoes_the_analysis() {
    let n = 50;
    let scaled = |m: &SymmetricMatrix, k: f64| {
        let mut m = m.clone();
        m.values.iter_mut().for_each(|v| *v *= k);
        m
    };
    // Another pattern: a dense row added.
    let mut bigger = SymmetricBuilder::new(n, 4 * n);
    for i in 0..n - 1 {
        bigger.add_row_outer(&[(i, 1.0), (i + 1, -1.0)], 1.0);
        bigger.add_row_outer(&[(i, 0.1), (n - 1, -0.1)], 1.0);
    }
    let bigger = bigger.build();
    let mut s = PinnedSystem::new(&path_laplacian(n, 0.0), &[0], FactorKind::Supernodal).unwrap();
    let mut ws = s.workspace(1);
    let b: Vec<f64> = (0..n).map(|i| (i as f64).cos()).collect();
    // The same pattern (its values copied in place from the second
    // refactoring on, the coupling to the pinned unknown too), another
    // pattern, and back.
    for (k, m) in [
        path_laplacian(n, 0.5),
        path_laplacian(n, 2.0),
        scaled(&path_laplacian(n, 1.0), 3.0),
        bigger.clone(),
        scaled(&bigger, 2.0),
        scaled(&bigger, 0.5),
        path_laplacian(n, 0.5),
    ]
    .iter()
    .enumerate()
    {
        s.refactor(m).unwrap();
        let mut x = vec![0.0; n];
        s.solve(&b, Some(&[0.25]), &mut x, &mut ws);
        let r = m.mul_vec(&x);
        for i in 1..n {
            assert!((r[i] - b[i]).abs() < 1e-9, "matrix {k}: row {i}");
        }
        assert_eq!(x[0], 0.25);
    }
}

/// Laplacian of an `n × n` grid graph (whose factors have supernodes
/// wider than one column).
fn grid_laplacian(n: usize) -> SymmetricMatrix {
    let mut b = SymmetricBuilder::new(n * n, 8 * n * n);
    for i in 0..n {
        for j in 0..n {
            let v = i * n + j;
            if i + 1 < n {
                b.add_row_outer(&[(v, 1.0), (v + n, -1.0)], 1.0);
            }
            if j + 1 < n {
                b.add_row_outer(&[(v, 1.0), (v + 1, -1.0)], 1.0);
            }
        }
    }
    b.build()
}

#[test]
fn every_column_count_and_factor_kind_solves_with_pins() {
    let n = 30;
    let m = grid_laplacian(n);
    let dim = n * n;
    let pinned = [0, dim - 1, 37];
    for kind in [FactorKind::Simplicial, FactorKind::Supernodal] {
        let s = PinnedSystem::new(&m, &pinned, kind).unwrap();
        // The rows path (1 to 4 columns) and column by column (5).
        for k in 1..=5 {
            let b: Vec<f64> = (0..dim * k).map(|i| (i as f64 * 0.71).sin()).collect();
            let values: Vec<f64> = (0..pinned.len() * k).map(|i| i as f64 - 2.0).collect();
            let mut ws = s.workspace(k);
            let mut x = vec![0.0; dim * k];
            s.solve(&b, Some(&values), &mut x, &mut ws);
            for c in 0..k {
                let xc = &x[c * dim..(c + 1) * dim];
                for (q, &p) in pinned.iter().enumerate() {
                    assert_eq!(xc[p], values[c * pinned.len() + q]);
                }
                let r = m.mul_vec(xc);
                for i in (0..dim).filter(|i| !pinned.contains(i)) {
                    let e = (r[i] - b[c * dim + i]).abs();
                    assert!(e < 1e-9, "{kind:?}, {k} columns: row {i} off by {e}");
                }
            }
        }
    }
}

#[test]
fn row_outer_products_match_dense() {
    let mut b = SymmetricBuilder::new(3, 16);
    b.add_row_outer(&[(0, 1.0), (2, -2.0), (0, 0.5)], 2.0);
    let m = b.build();
    // a = (1.5, 0, -2): 2 a aᵀ
    assert!((m.get(0, 0) - 4.5).abs() < 1e-15);
    assert!((m.get(0, 2) + 6.0).abs() < 1e-15);
    assert!((m.get(2, 2) - 8.0).abs() < 1e-15);
}
