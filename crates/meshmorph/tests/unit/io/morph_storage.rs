use meshmorph::io::morph_storage::*;

#[test]
fn sparse_only_where_it_is_smaller() {
    // 12 bytes dense a vertex against 2 + 12 sparse.
    assert_eq!(Storage::choose(1000, 100, 12).entries, Some(100));
    assert_eq!(Storage::choose(1000, 900, 12).entries, None);
    assert_eq!(Storage::choose(1000, 0, 12).entries, Some(1));
    // Past 65,536 vertices the indices take 4 bytes.
    assert_eq!(Storage::choose(70_000, 10, 12).index_bytes(), 4);
    // Quantised: 8 bytes dense (6, padded), 2 + 6 sparse.
    assert_eq!(Storage::choose(100, 100, 6).entries, None);
    assert_eq!(Storage::choose(100, 50, 6).bytes(), 100 + 300);
}

#[test]
fn quantised_positions_decode_within_the_tolerance() {
    let q = Quantization::new([1.0, -2.0, 0.5], 3.0);
    for &p in &[[1.0, -2.0, 0.5], [3.9, -4.9, 3.4], [-1.3, 0.7, -2.2]] {
        let d = [0.3, -0.7, 0.01];
        let (b, dq) = (q.position(p), q.delta(d));
        for k in 0..3 {
            let decoded = q.center[k] + q.scale * (f64::from(b[k]) + f64::from(dq[k])) / 32767.0;
            assert!((decoded - (p[k] + d[k])).abs() <= q.tolerance() * (1.0 + 1e-9));
        }
    }
}
