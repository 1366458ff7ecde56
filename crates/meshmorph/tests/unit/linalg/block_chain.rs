use meshmorph::linalg::block_chain::*;

/// Random chains against the product of the system with the solution.
#[test]
fn solves_random_chains() {
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut random = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for n in [1usize, 2, 3, 17, 200] {
        // Diagonally dominant, symmetric diagonal blocks.
        let next: Vec<Block> = (1..n)
            .map(|_| std::array::from_fn(|_| std::array::from_fn(|_| random())))
            .collect();
        let diagonal: Vec<Block> = (0..n)
            .map(|_| {
                let o = random();
                [[4.0 + random(), o], [o, 4.0 + random()]]
            })
            .collect();
        let x: Vec<[f64; 2]> = (0..n).map(|_| [random(), random()]).collect();
        let b: Vec<[f64; 2]> = (0..n)
            .map(|i| {
                let mut r = apply(&diagonal[i], &x[i]);
                if i > 0 {
                    let c = apply(&transpose(&next[i - 1]), &x[i - 1]);
                    r = [r[0] + c[0], r[1] + c[1]];
                }
                if i + 1 < n {
                    let c = apply(&next[i], &x[i + 1]);
                    r = [r[0] + c[0], r[1] + c[1]];
                }
                r
            })
            .collect();
        let chain = PlanarChain::new(&diagonal, next).unwrap();
        let mut solved = b.clone();
        chain.solve(&mut solved);
        for (s, x) in solved.iter().zip(&x) {
            assert!((s[0] - x[0]).abs() < 1e-12 && (s[1] - x[1]).abs() < 1e-12);
        }
    }
    assert!(PlanarChain::new(&[[[1.0, 2.0], [2.0, 1.0]]], Vec::new()).is_none());
}
