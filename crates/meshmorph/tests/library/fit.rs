//! How well the deformed source fits the target ([`meshmorph::FitReport`]),
//! through [`correspond`], over procedural tubes: a source that is its
//! target fits everywhere, a target longer than its source is uncovered
//! past the source's end with the markers there named, and the figures do
//! not change when both meshes move and grow together.

use meshmorph::shapes::{bend, tube};
use meshmorph::{correspond, CorrespondOptions, CorrespondResult, FitReport, Markers, Mesh3};

/// The segments of every tube here (markers at a quarter turn apart).
const SEGMENTS: usize = 16;

/// A tube along x from 0 to `length`, radius 0.5, rings 0.25 apart.
fn tube_of(length: f64) -> Mesh3 {
    let rings = (length / 0.25).round() as usize + 1;
    tube(length, 0.5, rings, SEGMENTS)
}

/// Vertex `s` of ring `r`.
fn ring(r: usize, s: usize) -> u32 {
    (r * SEGMENTS + s) as u32
}

/// The same vertex of the same ring in both tubes, for rings `rings`, at
/// four angles a quarter turn apart (ring by ring), then the cap centres
/// at x = 0.
fn markers(rings: &[usize], source: &Mesh3, target: &Mesh3) -> Markers {
    let mut pairs: Vec<[u32; 2]> = rings
        .iter()
        .flat_map(|&r| (0..4).map(move |q| [ring(r, q * SEGMENTS / 4); 2]))
        .collect();
    let cap = |m: &Mesh3| (m.num_vertices() - 2) as u32;
    pairs.push([cap(source), cap(target)]);
    Markers::new(pairs)
}

fn found(source: &Mesh3, target: &Mesh3, markers: &Markers) -> CorrespondResult {
    correspond(source, target, markers, &CorrespondOptions::default()).unwrap()
}

#[test]
fn a_source_that_is_its_target_fits_it_everywhere() {
    let straight = tube_of(4.0);
    for (name, mesh) in [
        ("straight tube", straight.clone()),
        ("bent tube", bend(&straight, 4.0, 1.2)),
    ] {
        let fit = found(&mesh, &mesh, &markers(&[0, 8, 16], &mesh, &mesh)).fit;
        assert!(fit.mean_distance < 1e-6, "{name}: {fit:?}");
        assert!(fit.distance_95 < 1e-6, "{name}: {fit:?}");
        assert_eq!(fit.uncovered_area, 0.0, "{name}");
        assert_eq!(fit.poor_area, 0.0, "{name}");
        assert!(fit.poor_regions.is_empty(), "{name}");
        assert_eq!(fit.distances.len(), mesh.num_triangles());
        assert!(fit.poor_threshold > 0.0 && fit.distance_limit > fit.poor_threshold);
    }
}

/// A source 4 long on a target 6 long: the markers at the source's end
/// (ring 16, markers 8 to 11) are the target's ring at x = 4.
fn longer_target() -> (Mesh3, Mesh3, Markers) {
    let (source, target) = (tube_of(4.0), tube_of(6.0));
    let markers = markers(&[0, 8, 16], &source, &target);
    (source, target, markers)
}

#[test]
fn a_target_the_source_does_not_reach_is_uncovered_there_and_names_the_markers_at_its_edge() {
    let (source, target, markers) = longer_target();
    let fit = found(&source, &target, &markers).fit;
    // Past x = 4 lie 2 of the side's 6 and the far cap: about a third.
    assert!(
        (0.2..0.4).contains(&fit.uncovered_area),
        "uncovered {}",
        fit.uncovered_area
    );
    assert_eq!(fit.poor_regions.len(), 1, "{:?}", fit.poor_regions);
    let region = &fit.poor_regions[0];
    assert!((0.2..0.4).contains(&region.area), "{}", region.area);
    assert!((region.area - fit.poor_area).abs() < 1e-12);
    assert_eq!(region.largest_distance, fit.distance_limit);
    assert!(region.point[0] > 4.0, "{:?}", region.point);
    // Every poor triangle lies past the source's end; the region's
    // nearest markers are those at it, 0.25 (a ring) away.
    let diagonal = target.bounding_box_diagonal();
    for &t in &region.triangles {
        let [a, b, c] = target.triangles()[t as usize];
        let x = (target.positions()[a as usize][0]
            + target.positions()[b as usize][0]
            + target.positions()[c as usize][0])
            / 3.0;
        assert!(x > 4.0, "triangle {t} at x = {x}");
    }
    assert_eq!(region.nearest_markers.len(), 3);
    for &(k, d) in &region.nearest_markers {
        assert!((8..12).contains(&k), "marker {k}");
        assert!((d * diagonal - 0.25).abs() < 0.05, "marker {k} at {d}");
    }
    // The 95th percentile sees the far part; the mean weighs it by area.
    assert_eq!(fit.distance_95, fit.distance_limit);
    assert!(fit.mean_distance > 0.1 * fit.distance_limit);
    assert!(fit.mean_distance < 0.5 * fit.distance_limit);
}

#[test]
fn the_fit_does_not_change_when_both_meshes_move_and_grow() {
    let (source, target, markers) = longer_target();
    let before = found(&source, &target, &markers).fit;
    // Moved and grown, not turned: the bounding box's diagonal, the unit of
    // every distance, depends on how the meshes stand.
    let moved = |m: &Mesh3, s: f64| -> Mesh3 {
        let shift = [10.0, -3.0, 250.0];
        m.with_positions(
            m.positions()
                .iter()
                .map(|p| std::array::from_fn(|i| s * p[i] + shift[i]))
                .collect(),
        )
        .unwrap()
    };
    for s in [1.0, 0.001, 37.0] {
        let after = found(&moved(&source, s), &moved(&target, s), &markers).fit;
        let close = |a: f64, b: f64, what: &str| {
            assert!((a - b).abs() < 1e-6, "scale {s}, {what}: {a} against {b}");
        };
        close(after.mean_distance, before.mean_distance, "mean");
        close(after.distance_95, before.distance_95, "95th percentile");
        close(after.uncovered_area, before.uncovered_area, "uncovered");
        close(after.poor_threshold, before.poor_threshold, "threshold");
        close(after.poor_area, before.poor_area, "poor area");
        assert_eq!(after.poor_regions.len(), before.poor_regions.len());
        for (a, b) in after.poor_regions.iter().zip(&before.poor_regions) {
            close(a.area, b.area, "region area");
            close(a.largest_distance, b.largest_distance, "region distance");
            for (m, n) in a.nearest_markers.iter().zip(&b.nearest_markers) {
                close(m.1, n.1, "marker distance");
            }
        }
    }
}

#[test]
fn the_report_on_its_own_is_the_one_the_correspondence_made() {
    let (source, target, markers) = longer_target();
    let result = found(&source, &target, &markers);
    let again = FitReport::new(
        &result.deformed_source,
        &target,
        &result.correspondence,
        &markers,
        result.fit.poor_threshold,
    );
    assert_eq!(again, result.fit);
}
