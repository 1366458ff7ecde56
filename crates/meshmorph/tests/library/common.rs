//! Measures the library's two test binaries share: distances between vertex
//! lists, edge lengths, flipped frames, and the transfer of a mesh onto
//! itself. (`library` holds the tests on procedural meshes, `shared_data`
//! those on the real meshes of ../shared/data.)

use meshmorph::{Correspondence, Interpolator, Mesh3, Transfer, TransferOptions};

pub fn sub<const D: usize>(a: [f64; D], b: [f64; D]) -> [f64; D] {
    std::array::from_fn(|i| a[i] - b[i])
}

pub fn norm<const D: usize>(a: [f64; D]) -> f64 {
    a.iter().map(|x| x * x).sum::<f64>().sqrt()
}

pub fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm(sub(a, b))
}

/// The largest distance between corresponding points of `a` and `b`.
///
/// # Panics
/// When `a` and `b` differ in length.
#[track_caller]
pub fn max_distance<const D: usize>(a: &[[f64; D]], b: &[[f64; D]]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| norm(sub(*p, *q)))
        .fold(0.0, f64::max)
}

pub fn mean<const D: usize>(p: &[[f64; D]]) -> [f64; D] {
    let mut c = [0.0; D];
    for q in p {
        for i in 0..D {
            c[i] += q[i];
        }
    }
    c.map(|x| x / p.len() as f64)
}

pub fn all_finite(p: &[[f64; 3]]) -> bool {
    p.iter().flatten().all(|x| x.is_finite())
}

/// Asserts `got` is within `fraction` of `reference`'s bounding-box diagonal
/// of `want`, vertex by vertex.
#[track_caller]
pub fn assert_close(
    got: &[[f64; 3]],
    want: &[[f64; 3]],
    reference: &Mesh3,
    fraction: f64,
    what: &str,
) {
    assert!(all_finite(got), "{what}: non-finite output");
    let d = max_distance(got, want) / reference.bounding_box_diagonal();
    assert!(d < fraction, "{what}: off by {d:e} of the diagonal");
}

/// The length of every triangle's edges, three a triangle.
pub fn edge_lengths(m: &Mesh3, p: &[[f64; 3]]) -> Vec<f64> {
    m.triangles()
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
        .map(|(a, b)| dist(p[a as usize], p[b as usize]))
        .collect()
}

/// The most triangles flipped in any of `frames` frames evenly spaced from
/// source to target.
pub fn max_flipped(m: &Interpolator<2>, frames: usize) -> usize {
    (0..frames)
        .map(|k| m.count_flipped(&m.at(k as f64 / (frames - 1) as f64)))
        .max()
        .unwrap()
}

/// Identity-correspondence transfer of a mesh onto itself.
pub fn self_transfer(m: &Mesh3) -> Transfer {
    Transfer::new(
        m,
        m,
        &Correspondence::identity(m),
        &TransferOptions::default(),
    )
    .unwrap()
}
