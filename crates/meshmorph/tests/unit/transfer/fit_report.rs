use meshmorph::linalg::vector::centroid;
use meshmorph::mesh::Mesh3;
use meshmorph::transfer::correspondence::Correspondence;
use meshmorph::transfer::markers::Markers;

use meshmorph::transfer::fit_report::*;

/// A unit square in the plane z = 0 of `n × n` quads, each split in
/// two, facing +z; vertex `(i, j)` is `j (n + 1) + i`.
fn grid(n: u32) -> Mesh3 {
    let s = f64::from(n);
    let positions = (0..=n)
        .flat_map(|j| (0..=n).map(move |i| [f64::from(i) / s, f64::from(j) / s, 0.0]))
        .collect();
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let triangles = (0..n)
        .flat_map(|j| {
            (0..n).flat_map(move |i| {
                [
                    [id(i, j), id(i + 1, j), id(i + 1, j + 1)],
                    [id(i, j), id(i + 1, j + 1), id(i, j + 1)],
                ]
            })
        })
        .collect();
    Mesh3::new(positions, triangles).unwrap()
}

/// The triangles of `mesh` whose centroid has x below `x`.
fn left_of(mesh: &Mesh3, x: f64) -> Vec<u32> {
    (0..mesh.num_triangles() as u32)
        .filter(|&t| centroid(mesh.corners(t as usize))[0] < x)
        .collect()
}

#[test]
fn a_source_on_the_target_fits_it_everywhere() {
    let target = grid(8);
    let markers = Markers::new(vec![[0, 0], [80, 80]]);
    let fit = FitReport::new(
        &target,
        &target,
        &Correspondence::identity(&target),
        &markers,
        0.01,
    );
    assert!(fit.distances.iter().all(|&d| d < 1e-12));
    assert!(fit.mean_distance < 1e-12 && fit.distance_95 < 1e-12);
    assert_eq!((fit.uncovered_area, fit.poor_area), (0.0, 0.0));
    assert!(fit.poor_regions.is_empty());
    assert_eq!(fit.distance_limit, FIT_DISTANCE_LIMIT);
}

#[test]
fn the_half_the_source_misses_is_uncovered_and_one_poor_region() {
    let target = grid(10);
    let half = left_of(&target, 0.5);
    let tris: Vec<[u32; 3]> = half
        .iter()
        .map(|&t| target.triangles()[t as usize])
        .collect();
    let source = Mesh3::new(target.positions().to_vec(), tris).unwrap();
    let pairs = half
        .iter()
        .enumerate()
        .map(|(s, &t)| [s as u32, t])
        .collect();
    let c = Correspondence::new(pairs, &source, &target);
    // Markers at x = 0, 0.5 and 1 (on the row y = 0.5), in that order.
    let markers = Markers::new(vec![[55, 55], [60, 60], [65, 65]]);
    let fit = FitReport::new(&source, &target, &c, &markers, 0.05);
    assert!((fit.uncovered_area - 0.5).abs() < 1e-12, "{fit:?}");
    // Poor beyond 0.05 of the diagonal (about 0.07) from x = 0.5.
    let d = std::f64::consts::SQRT_2;
    for (t, &dt) in fit.distances.iter().enumerate() {
        let at = |x: f64| ((x - 0.5).max(0.0) / d).min(fit.distance_limit);
        let want = target.corners(t).iter().map(|p| at(p[0])).sum::<f64>() / 3.0;
        assert!((dt - want).abs() < 1e-12, "triangle {t}: {dt} {want}");
    }
    assert_eq!(fit.poor_regions.len(), 1);
    let r = &fit.poor_regions[0];
    assert!((r.area - fit.poor_area).abs() < 1e-12 && r.area > 0.3);
    assert_eq!(r.largest_distance, fit.distance_limit);
    assert!(r.point[0] > 0.5 + 0.05 * d);
    // The marker at x = 0.5 first, then the one inside the region.
    let order: Vec<usize> = r.nearest_markers.iter().map(|m| m.0).collect();
    assert_eq!(order, vec![2, 1, 0]);
    assert_eq!(r.nearest_markers[0].1, 0.0);
    // Half the area at 0, the far quarter at the limit.
    assert!(fit.distance_95 == fit.distance_limit);
    assert!(fit.mean_distance > 0.0 && fit.mean_distance < fit.distance_limit / 2.0);
}

#[test]
fn patches_join_across_edges_not_corners() {
    // Two triangles sharing only a corner, a third sharing an edge.
    let triangles = [[0, 1, 2], [2, 3, 4], [0, 2, 5], [6, 7, 8]];
    assert_eq!(
        patches(&triangles, &[true, true, true, false]),
        vec![vec![0, 2], vec![1]]
    );
    assert!(patches(&triangles, &[false; 4]).is_empty());
    // Three triangles on one edge are one patch; a short mask leaves
    // the rest out.
    let book = [[0, 1, 2], [1, 0, 3], [0, 1, 4]];
    assert_eq!(patches(&book, &[true; 3]), vec![vec![0, 1, 2]]);
    assert_eq!(patches(&book, &[true]), vec![vec![0]]);
}

#[test]
fn the_percentile_weighs_by_area() {
    assert_eq!(
        weighted_percentile(&[3.0, 1.0, 2.0], &[1.0, 1.0, 1.0], 0.5),
        2.0
    );
    assert_eq!(
        weighted_percentile(&[3.0, 1.0, 2.0], &[1.0, 8.0, 1.0], 0.8),
        1.0
    );
    assert_eq!(
        weighted_percentile(&[3.0, 1.0], &[1.0, f64::NAN], 0.95),
        3.0
    );
    assert_eq!(weighted_percentile(&[], &[], 0.95), 0.0);
}

#[test]
fn input_that_does_not_fit_is_ignored_without_panicking() {
    let target = grid(4);
    let big = grid(6);
    // A correspondence and markers made for a bigger mesh, a threshold
    // that is not a number, a source facing the other way.
    let flipped: Vec<[u32; 3]> = target
        .triangles()
        .iter()
        .map(|t| [t[0], t[2], t[1]])
        .collect();
    let source = Mesh3::new(target.positions().to_vec(), flipped).unwrap();
    let markers = Markers::new(vec![[0, 0], [48, 48]]);
    for threshold in [f64::NAN, -1.0, f64::INFINITY, 0.0] {
        let fit = FitReport::new(
            &source,
            &target,
            &Correspondence::identity(&big),
            &markers,
            threshold,
        );
        assert_eq!(fit.poor_threshold, 0.0);
        assert!(fit.distances.iter().all(|&d| d == FIT_DISTANCE_LIMIT));
        assert_eq!(fit.poor_regions.len(), 1);
        assert_eq!(fit.poor_regions[0].nearest_markers.len(), 1);
        assert_eq!(fit.uncovered_area, 0.0);
    }
}
