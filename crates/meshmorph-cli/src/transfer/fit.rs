//! How well the source, deformed onto the target by the correspondence,
//! lies on it: the report's lines, its JSON and the warnings about poorly
//! fitted regions. Shared by `correspond` and `transfer`.

use meshmorph::{FitReport, Markers};
use serde::Serialize;

use crate::output;

/// The poor regions a warning is given for, largest first.
const WARNED_REGIONS: usize = 3;

/// How well the deformed source lies on the target, measured from the
/// target (distances as fractions of the target's bounding-box diagonal,
/// areas as shares of the target's area).
#[derive(Debug, Serialize)]
pub struct FitSummary {
    /// Area-weighted mean distance from the target to the deformed source.
    pub mean_distance: f64,
    /// Area-weighted 95th percentile of that distance.
    pub distance_95th_percentile: f64,
    /// Distances are measured up to this; farther counts as this far.
    pub distance_limit: f64,
    /// The target's area in triangles with no source partner.
    pub uncovered_area: f64,
    /// The distance past which a target triangle fits poorly (the
    /// matching's threshold).
    pub poor_threshold: f64,
    /// The target's area in poorly fitted triangles.
    pub poor_area: f64,
    /// The connected regions of poorly fitted triangles of at least 0.1 %
    /// of the target's area, largest first.
    pub poor_regions: Vec<PoorRegionSummary>,
}

/// A connected region of poorly fitted target triangles.
#[derive(Debug, Serialize)]
pub struct PoorRegionSummary {
    pub area: f64,
    pub largest_distance: f64,
    pub triangles: usize,
    /// Where the fit is worst (the centroid of the farthest triangle), in
    /// the target's coordinates.
    pub point: [f64; 3],
    /// The markers nearest to the region, nearest first.
    pub nearest_markers: Vec<NearMarker>,
}

/// A marker near a poor region.
#[derive(Debug, Serialize)]
pub struct NearMarker {
    /// Its index among the markers (in the file's order).
    pub marker: usize,
    /// The file and line it was read from, and its vertices.
    pub description: String,
    /// From its target vertex to the region's nearest vertex.
    pub distance: f64,
}

impl FitSummary {
    /// The summary of `fit`, naming the `markers` the correspondence was
    /// computed with.
    pub(crate) fn new(fit: &FitReport, markers: &Markers) -> Self {
        FitSummary {
            mean_distance: fit.mean_distance,
            distance_95th_percentile: fit.distance_95,
            distance_limit: fit.distance_limit,
            uncovered_area: fit.uncovered_area,
            poor_threshold: fit.poor_threshold,
            poor_area: fit.poor_area,
            poor_regions: fit
                .poor_regions
                .iter()
                .map(|r| PoorRegionSummary {
                    area: r.area,
                    largest_distance: r.largest_distance,
                    triangles: r.triangles.len(),
                    point: r.point,
                    nearest_markers: r
                        .nearest_markers
                        .iter()
                        .map(|&(marker, distance)| NearMarker {
                            marker,
                            description: markers.describe(marker),
                            distance,
                        })
                        .collect(),
                })
                .collect(),
        }
    }

    /// A warning for each of the largest poor regions, naming the markers
    /// nearest to it, and one for the rest.
    pub(crate) fn warnings(&self) -> Vec<String> {
        let mut warnings: Vec<String> = self
            .poor_regions
            .iter()
            .take(WARNED_REGIONS)
            .map(|r| {
                let markers: Vec<&str> = r
                    .nearest_markers
                    .iter()
                    .map(|m| m.description.as_str())
                    .collect();
                format!(
                    "the deformed source lies farther than {} of the target's diagonal from the target over {:.2} % of its area, around ({:.4}, {:.4}, {:.4}) ({} away there): that part of the target has no source triangle of its own to follow; {} {} (add a marker pair there, or check {})",
                    percent(self.poor_threshold),
                    100.0 * r.area,
                    r.point[0],
                    r.point[1],
                    r.point[2],
                    self.distance(r.largest_distance),
                    if markers.len() == 1 { "the nearest marker is" } else { "the nearest markers are" },
                    markers.join("; "),
                    if markers.len() == 1 { "it" } else { "them" },
                )
            })
            .collect();
        let rest = self.poor_regions.len().saturating_sub(WARNED_REGIONS);
        if rest > 0 {
            let area: f64 = self.poor_regions[WARNED_REGIONS..]
                .iter()
                .map(|r| r.area)
                .sum();
            warnings.push(format!(
                "{rest} more {} fitted poorly, {:.2} % of the target's area in all (see the JSON report)",
                if rest == 1 { "region is" } else { "regions are" },
                100.0 * area
            ));
        }
        warnings
    }

    /// "1.23 %", or "5.00 % or more" at the distance limit.
    fn distance(&self, d: f64) -> String {
        if d >= self.distance_limit {
            format!("{} or more", percent(d))
        } else {
            percent(d)
        }
    }

    /// The report's two lines.
    pub(crate) fn print(&self) {
        say!(
            "fit:            target to deformed source {} of the target's diagonal (mean), {} (95th percentile)",
            percent(self.mean_distance),
            self.distance(self.distance_95th_percentile)
        );
        say!(
            "coverage:       {:.2} % of the target's area has no source partner; {:.2} % lies farther than {} ({} of 0.1 % of the area or more)",
            100.0 * self.uncovered_area,
            100.0 * self.poor_area,
            percent(self.poor_threshold),
            output::count(self.poor_regions.len(), "region")
        );
    }
}

/// A fraction as a percentage with three significant decimals.
fn percent(f: f64) -> String {
    format!("{:.3} %", 100.0 * f)
}
