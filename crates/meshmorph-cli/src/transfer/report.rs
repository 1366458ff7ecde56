//! What a transfer did: the report printed (or written as JSON) at the end.

use std::path::PathBuf;

use serde::Serialize;

use super::correspondence::{print_welded, MarkerReport};
use super::fit::FitSummary;
use crate::output::{self};

/// What a transfer did.
#[derive(Debug, Serialize)]
pub struct TransferReport {
    #[serde(serialize_with = "output::lossy")]
    pub output: PathBuf,
    pub poses_written: usize,
    /// Computing (or loading) the correspondence.
    pub correspondence_seconds: f64,
    pub correspondence_loaded: bool,
    /// Factoring the transfer system.
    pub setup_seconds: f64,
    /// Solving one pose, averaged.
    pub seconds_per_pose: f64,
    /// One pose with reading and writing, averaged over the poses run in parallel.
    pub seconds_per_pose_with_io: f64,
    pub matched_pairs: usize,
    /// Source triangles in no pair: their deformation is carried to no
    /// target triangle.
    pub unmatched_source_triangles: usize,
    /// Target triangles in no pair: `gap_target_triangles` +
    /// `unpaired_target_triangles`.
    pub unmatched_target_triangles: usize,
    /// Unmatched target triangles in gaps of the matching (enclosed by the
    /// paired surface, or near a paired triangle): deformed as their
    /// neighbours.
    pub gap_target_triangles: usize,
    /// Unmatched target triangles beyond the source (no source partner
    /// nearby): kept in their rest shape, turned with the paired surface.
    pub unpaired_target_triangles: usize,
    /// How the markers fitted (absent when the correspondence was loaded).
    pub markers: Option<MarkerReport>,
    /// How well the source deformed onto the target lies on it (absent
    /// when the correspondence was loaded).
    pub fit: Option<FitSummary>,
    /// Pose faces that list the reference's corners in another order or winding.
    pub reordered_pose_faces: usize,
    /// Separate parts of the target carried rigidly by the surface around them.
    pub carried_parts: usize,
    /// Separate parts of the target with their own partners, placed by the
    /// main part around them (their shape follows their partners).
    pub following_parts: usize,
    /// Target vertices no triangle uses: written at their rest positions.
    pub unused_target_vertices: usize,
    /// Vertices at the same place as another (copies at seams), welded for
    /// the solve, in the source and in the target; the files keep them.
    pub welded_source_vertices: usize,
    pub welded_target_vertices: usize,
    pub total_seconds: f64,
    /// The correspondence saved, if any.
    #[serde(serialize_with = "output::lossy")]
    pub saved_correspondence: Option<PathBuf>,
    /// The GIF written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub gif: Option<PathBuf>,
    /// The PNG written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub png: Option<PathBuf>,
    /// The GLB written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub gltf: Option<PathBuf>,
    /// Every file written, in order.
    #[serde(serialize_with = "output::lossy")]
    pub files_written: Vec<PathBuf>,
    /// The warnings given (also printed on stderr).
    pub warnings: Vec<String>,
}

impl TransferReport {
    pub(crate) fn print(&self, json: bool) {
        if json {
            output::print_json(self);
            return;
        }
        if let Some(m) = &self.markers {
            m.print();
        }
        if let Some(fit) = &self.fit {
            fit.print();
        }
        if self.output.as_os_str().is_empty() {
            // Only --gltf takes them (its line is below).
            say!("transferred {}", output::count(self.poses_written, "pose"));
        } else {
            say!(
                "wrote {} to {}",
                output::count(self.poses_written, "pose"),
                self.output.display()
            );
        }
        say!(
            "correspondence: {} ({}){}",
            output::human_seconds(self.correspondence_seconds),
            output::count(self.matched_pairs, "pair"),
            if self.correspondence_loaded {
                ", loaded"
            } else {
                ""
            }
        );
        print_unmatched(
            self.unmatched_source_triangles,
            self.unmatched_target_triangles,
        );
        if self.unmatched_target_triangles > 0 {
            say!(
                "  in gaps:      {} (holes in the match: deformed as their neighbours)",
                output::count(self.gap_target_triangles, "target triangle")
            );
            say!(
                "  kept at rest: {} (beyond the source: rest shape, turned with the paired surface)",
                output::count(self.unpaired_target_triangles, "target triangle")
            );
        }
        if self.carried_parts + self.following_parts > 0 {
            say!(
                "separate parts: {} with partners (shaped by them, placed by the main part around them), {} carried rigidly",
                self.following_parts, self.carried_parts
            );
        }
        print_welded(self.welded_source_vertices, self.welded_target_vertices);
        if self.unused_target_vertices > 0 {
            say!(
                "unused target vertices: {} (in no triangle; kept at rest)",
                self.unused_target_vertices
            );
        }
        say!(
            "setup:          {}",
            output::human_seconds(self.setup_seconds)
        );
        say!(
            "time per pose:  {} solving, {} with reading and writing",
            output::human_seconds(self.seconds_per_pose),
            output::human_seconds(self.seconds_per_pose_with_io)
        );
        say!(
            "total:          {}",
            output::human_seconds(self.total_seconds)
        );
        output::print_files(
            &[
                ("saved:", self.saved_correspondence.as_deref()),
                ("picture:", self.png.as_deref()),
                ("animation:", self.gif.as_deref()),
                ("glTF:", self.gltf.as_deref()),
            ],
            16,
        );
    }
}

/// The report's line for the triangles of either reference in no pair.
pub(crate) fn print_unmatched(source: usize, target: usize) {
    say!(
        "unmatched:      {}, {}",
        output::count(source, "source triangle"),
        output::count(target, "target triangle")
    );
}
