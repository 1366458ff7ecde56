//! Vertices that no triangle uses change nothing: not the scale of the
//! degeneracy test, not the thresholds of the correspondence, not the
//! result; they are carried through unchanged.

use std::f64::consts::PI;

use meshmorph::shapes::{bend, curl, nearest_vertex_pairs, strip, tube};
use meshmorph::{
    correspond, CorrespondOptions, Correspondence, Interpolator, InterpolatorOptions, Markers,
    Mesh2, Mesh3, Transfer, TransferOptions,
};

fn with_extra<const D: usize>(mesh: &meshmorph::Mesh<D>, extra: [f64; D]) -> meshmorph::Mesh<D> {
    let mut p = mesh.positions().to_vec();
    p.push(extra);
    meshmorph::Mesh::new(p, mesh.triangles().to_vec()).unwrap()
}

fn max_diff<const D: usize>(a: &[[f64; D]], b: &[[f64; D]]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(p, q)| (0..D).map(move |k| (p[k] - q[k]).abs()))
        .fold(0.0, f64::max)
}

#[test]
fn an_unused_vertex_far_away_changes_no_interpolation() {
    // Before, a vertex at (1e6, 1e6) made every triangle "degenerate".
    let a = strip(4.0, 0.5, 16, 2);
    let b = curl(&a, 1.5 * PI);
    let far = [1e6, 1e6];
    let (a2, b2): (Mesh2, Mesh2) = (with_extra(&a, far), with_extra(&b, far));
    assert_eq!(a2.num_unused_vertices(), 1);
    assert_eq!(a2.bounding_box_diagonal(), a.bounding_box_diagonal());
    let options = InterpolatorOptions::default();
    let plain = Interpolator::new(&a, &b, &options).unwrap();
    let extra = Interpolator::new(&a2, &b2, &options).unwrap();
    for t in [0.0, 0.3, 0.7, 1.0, 1.4] {
        let f = plain.at(t);
        let g = extra.at(t);
        assert!(max_diff(&f, &g[..f.len()]) < 1e-12, "t = {t}");
        assert_eq!(g[f.len()], far, "the unused vertex is carried through");
    }
}

#[test]
fn an_unused_target_vertex_changes_no_correspondence_or_transfer() {
    // Before, `v 10 10 10` added to a target moved the result: the
    // thresholds scaled with the box of all vertices.
    let thin = tube(2.0, 0.25, 9, 8);
    let thick = tube(2.0, 0.5, 7, 12);
    let widened: Vec<[f64; 3]> = thin
        .positions()
        .iter()
        .map(|p| [p[0], 2.0 * p[1], 2.0 * p[2]])
        .collect();
    let chosen: Vec<u32> = [0u32, 4, 8]
        .iter()
        .flat_map(|&r| [0, 2, 4, 6].map(|s| r * 8 + s))
        .collect();
    let markers = Markers::new(nearest_vertex_pairs(&widened, thick.positions(), &chosen));
    let stray = [10.0, 10.0, 10.0];
    let thick2: Mesh3 = with_extra(&thick, stray);
    assert_eq!(
        thick2.bounding_box_diagonal(),
        thick.bounding_box_diagonal()
    );
    let options = CorrespondOptions::default();
    let plain = correspond(&thin, &thick, &markers, &options).unwrap();
    let extra = correspond(&thin, &thick2, &markers, &options).unwrap();
    assert_eq!(
        plain.correspondence.pairs(),
        extra.correspondence.pairs(),
        "the same triangle pairs"
    );
    let pose = bend(&thin, 2.0, 0.4 * PI);
    let run = |target: &Mesh3, c: &Correspondence| {
        Transfer::new(&thin, target, c, &TransferOptions::default())
            .unwrap()
            .apply(&pose)
            .unwrap()
    };
    let f = run(&thick, &plain.correspondence);
    let g = run(&thick2, &extra.correspondence);
    assert!(max_diff(&f, &g[..f.len()]) < 1e-9);
    assert_eq!(g[f.len()], stray, "the unused vertex stays where it was");
}
