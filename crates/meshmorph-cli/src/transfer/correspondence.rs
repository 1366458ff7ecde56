//! The two references and their triangle correspondence: computed from
//! markers (`CorrespondArgs`) or loaded, with the report on how the markers
//! fitted. Shared by `transfer` and `correspond`.

use std::path::{Path, PathBuf};

use crate::output::WeldedFile;
use anyhow::{bail, Context, Result};
use meshmorph::{
    correspond_with_progress, CorrespondOptions, Correspondence, Markers, Mesh3, SurfacePoint,
    VertexNumbering,
};
use serde::Serialize;

use super::fit::FitSummary;
use crate::output::{self, finite_number};
use crate::progress;

/// How the triangle correspondence is computed (Sumner and Popovic 2004, section 5).
#[derive(Debug, Clone, clap::Args)]
pub struct CorrespondArgs {
    /// Markers: one file of pairs, or `--markers` twice with files of
    /// points, the source's then the target's (MeshLab's picked points
    /// `.pp`, Wrap's `.json`, or one point a line), paired by name when
    /// every point is named, else in order. A file of pairs holds `source target` vertex indices, a
    /// position on each mesh `sx sy sz tx ty tz`, or `[name] SIDE SIDE`
    /// with each side `v I` (a vertex), `t T b0 b1 b2` (a triangle's point,
    /// barycentric) or `p x y z` (a position); positions are snapped to the
    /// nearest point of the surface; white space or a comma between, `#`
    /// comments, an optional first line with the count.
    #[arg(long, value_name = "FILE")]
    pub markers: Vec<PathBuf>,
    /// Correspond without markers, for two references that stand alike
    /// (the same way up, facing the same way, as two characters exported
    /// from one scene): the source is moved and scaled onto the target and
    /// drawn onto its surface; a fit that leaves more than a tenth of the
    /// source without a partner is refused.
    #[arg(long, conflicts_with = "markers")]
    pub no_markers: bool,
    /// Vertex and triangle indices in meshmorph's marker files start at 1
    /// instead of 0.
    #[arg(long)]
    pub one_based: bool,
    /// Do not bring the source onto the target by the similarity (rotation,
    /// uniform scale, translation) that best fits the markers: the two
    /// references must then already overlap.
    #[arg(long)]
    pub no_align: bool,
    /// Weight of the smoothness term w_S [default: 1].
    #[arg(long, value_name = "W", allow_negative_numbers = true, value_parser = finite_number)]
    pub smoothness_weight: Option<f64>,
    /// Weight of the identity term w_I, above 0 [default: 0.3]: each
    /// triangle keeps its shape up to a turn and a uniform scale.
    #[arg(long, value_name = "W", allow_negative_numbers = true, value_parser = finite_number)]
    pub identity_weight: Option<f64>,
    /// Weights w_C of the closest-point rounds, comma-separated, after a
    /// first round without closest points, with distances measured in
    /// diagonals of the target's bounding box [default: 1 to 5000 in four
    /// even steps].
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LIST",
        allow_hyphen_values = true,
        value_parser = finite_number
    )]
    pub closest_weights: Option<Vec<f64>>,
    /// Largest distance to a closest point, as a fraction of the target's
    /// bounding-box diagonal [default: 0.02].
    #[arg(long, value_name = "FRACTION", allow_negative_numbers = true, value_parser = finite_number)]
    pub closest_cutoff: Option<f64>,
    /// Largest centroid distance of matched triangles, as a fraction of the
    /// target's bounding-box diagonal, and never less than the mean edge
    /// length of either mesh [default: 0.01].
    #[arg(long, value_name = "FRACTION", allow_negative_numbers = true, value_parser = finite_number)]
    pub match_threshold: Option<f64>,
    /// Largest angle, in degrees, between a source vertex's normal and the
    /// surface its closest point lies on [default: 25].
    #[arg(long, value_name = "DEGREES", allow_negative_numbers = true, value_parser = finite_number)]
    pub closest_normal_angle: Option<f64>,
    /// Largest angle, in degrees, between the normals of matched triangles
    /// [default: 60].
    #[arg(long, value_name = "DEGREES", allow_negative_numbers = true, value_parser = finite_number)]
    pub match_normal_angle: Option<f64>,
}

impl CorrespondArgs {
    /// The marker files, checked before anything is read: one file of
    /// pairs or two files of points.
    ///
    /// # Errors
    /// Without `--markers`, with more than two, or with a mesh among them.
    pub(crate) fn marker_files(&self) -> Result<&[PathBuf]> {
        if let Some(mesh) = self
            .markers
            .iter()
            .find(|p| meshmorph::io::Format::from_path(p).is_ok())
        {
            bail!(
                "`{}` given to --markers is a mesh: --markers takes a file of marker pairs, or twice a file of marker points (the source's, then the target's)",
                mesh.display()
            );
        }
        match self.markers.as_slice() {
            [] if self.no_markers => Ok(&[]),
            [] => bail!(
                "--markers is required to compute a correspondence (or pass --correspondence FILE, or --no-markers for two references that stand alike)"
            ),
            files @ ([_] | [_, _]) => Ok(files),
            files => bail!(
                "--markers is given {} times: give it once (a file of marker pairs) or twice (a file of the source's points, then one of the target's)",
                files.len()
            ),
        }
    }

    /// "`a.pp` and `b.pp`", for messages.
    /// "`a.pp` and `b.pp`".
    fn describe_markers(&self) -> String {
        self.markers
            .iter()
            .map(|p| format!("`{}`", p.display()))
            .collect::<Vec<_>>()
            .join(" and ")
    }

    /// The markers, from one file of pairs or two files of points. Wrap
    /// numbers the triangles of a fan over each polygon: its files are
    /// refused for a mesh with polygons, whose triangles meshmorph numbers
    /// otherwise.
    pub(crate) fn read_markers(
        &self,
        source_ref: &Reference,
        target_ref: &Reference,
    ) -> Result<Markers> {
        let numbering = numbering(self.one_based);
        let files = self.marker_files()?;
        crate::memory::check_markers(files)?;
        let markers = match files {
            [] => Ok(Markers::new(Vec::new())),
            [one] => Markers::read(one, numbering),
            [s, t] => {
                for (path, reference, role) in [
                    (s, source_ref, "source reference"),
                    (t, target_ref, "target reference"),
                ] {
                    let wrap = path
                        .extension()
                        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
                    let file = &reference.file.file;
                    if let Some(f) = (0..file.num_faces()).find(|&f| file.face(f).len() > 3) {
                        if wrap {
                            bail!(
                                "`{}` is a Wrap point file, whose triangle numbers count a fan over each polygon, but the {role} `{}` has polygons (face {f} has {} corners), which meshmorph splits otherwise: export the mesh as triangles for both",
                                path.display(),
                                file.path().display(),
                                file.face(f).len()
                            );
                        }
                    }
                }
                Markers::read_pair(s, t, numbering)
            }
            _ => unreachable!("checked by marker_files"),
        };
        markers.with_context(|| format!("reading the markers {}", self.describe_markers()))
    }

    /// The library's defaults, with the options given on the command line.
    pub(crate) fn options(&self) -> CorrespondOptions {
        let d = CorrespondOptions::default();
        CorrespondOptions::default()
            .with_weights(
                self.smoothness_weight.unwrap_or(d.smoothness_weight),
                self.identity_weight.unwrap_or(d.identity_weight),
            )
            .with_closest_weights(self.closest_weights.clone().unwrap_or(d.closest_weights))
            .with_closest_cutoff(self.closest_cutoff.unwrap_or(d.closest_cutoff))
            .with_match_threshold(self.match_threshold.unwrap_or(d.match_threshold))
            .with_align(!self.no_align)
            .with_normal_angles(
                self.closest_normal_angle.unwrap_or(d.closest_normal_angle),
                self.match_normal_angle.unwrap_or(d.match_normal_angle),
            )
    }

    /// Reads the markers (snapping marker points to vertices) and computes
    /// the correspondence, with a progress bar, and how well the deformed
    /// source fits the target. `refs` name the meshes in error messages;
    /// warnings about the markers and the fit go to `warnings`.
    pub(crate) fn compute(
        &self,
        refs: &References,
        source_ref: &Reference,
        target_ref: &Reference,
        warnings: &mut Vec<String>,
    ) -> Result<(meshmorph::CorrespondResult, MarkerReport, FitSummary)> {
        let markers = self.read_markers(source_ref, target_ref)?;
        let described = if self.markers.is_empty() {
            "without markers".to_string()
        } else {
            format!("with the markers {}", self.describe_markers())
        };
        self.compute_from(markers, &described, refs, source_ref, target_ref, warnings)
    }

    /// [`CorrespondArgs::compute`] with the markers given rather than read
    /// from the files of `--markers` (`meshmorph pick` fits the page's),
    /// `described` for messages ("with the markers `a.txt`").
    pub(crate) fn compute_from(
        &self,
        markers: Markers,
        described: &str,
        refs: &References,
        source_ref: &Reference,
        target_ref: &Reference,
        warnings: &mut Vec<String>,
    ) -> Result<(meshmorph::CorrespondResult, MarkerReport, FitSummary)> {
        let (source, target) = (&source_ref.mesh, &target_ref.mesh);
        let (markers, snap) = markers
            .snap(source_ref.file_mesh(), target_ref.file_mesh())
            .context("snapping the marker points to the surfaces")?;
        markers.check_ranges(source_ref.file_mesh(), target_ref.file_mesh())?;
        let welded = markers.welded(&source_ref.file.seams, &target_ref.file.seams);
        let options = self.options();
        let bar = progress::bar(options.steps() as u64, "correspond");
        let result = correspond_with_progress(source, target, &welded, &options, &mut |done| {
            bar.set_position(done as u64)
        })
        .map_err(|e| name_degenerate_faces(e, source_ref, target_ref))
        .with_context(|| {
            format!(
                "computing the correspondence {} {described}",
                refs.describe()
            )
        })?;
        bar.finish_and_clear();
        let diagonal = target.bounding_box_diagonal();
        let r = &result.marker_residuals;
        let rms = (r.iter().map(|x| x * x).sum::<f64>() / r.len().max(1) as f64).sqrt();
        let suspicious: Vec<String> = result
            .far_markers()
            .into_iter()
            .map(|k| welded.describe(k))
            .collect();
        if !suspicious.is_empty() {
            warnings.push(format!(
                "after the alignment, {} far from {} target vertex ({}): {} may be on the wrong feature",
                if suspicious.len() == 1 { "a marker lies" } else { "markers lie" },
                if suspicious.len() == 1 { "its" } else { "their" },
                suspicious.join("; "),
                if suspicious.len() == 1 { "it" } else { "they" },
            ));
        }
        // Apart by more than the closest-point cut-off, the references' parts
        // go unmatched.
        if !options.align && rms > options.closest_cutoff * diagonal {
            warnings.extend(misplaced_warning(source, target, &welded, rms / diagonal));
        }
        let fit = FitSummary::new(&result.fit, &welded);
        warnings.extend(fit.warnings());
        let report = MarkerReport {
            markers: markers.pairs().len(),
            on_triangles: markers
                .pairs()
                .iter()
                .filter(|p| p.iter().any(|x| matches!(x, SurfacePoint::Triangle { .. })))
                .count(),
            snapped_points: snap.points,
            largest_snap_source: snap.largest_source,
            largest_snap_target: snap.largest_target,
            aligned: options.align,
            alignment_scale: result.correspondence.alignment().scale,
            marker_residual_rms: rms / diagonal,
            marker_residual_max: r.iter().copied().fold(0.0, f64::max) / diagonal,
            suspicious_markers: suspicious,
            turn_from_marker_fit: result
                .marker_fit
                .angle_to(result.correspondence.alignment())
                .to_degrees(),
            mirror_plane_misfits: result.mirror_planes.map(|p| p.map(|p| p.misfit)),
        };
        Ok((result, report, fit))
    }
}

/// With `--no-align`, the warning that the references stand apart: the
/// markers' similarity would bring them at least twice as close as they
/// stand (`rms`, the markers' RMS distance over the target's diagonal). A
/// pair aligned by hand, whose markers differ only as the shapes do, gets
/// none.
pub(crate) fn misplaced_warning(
    source: &Mesh3,
    target: &Mesh3,
    markers: &Markers,
    rms: f64,
) -> Option<String> {
    let r = markers.fit(source, target).ok()?.1;
    let fitted = (r.iter().map(|x| x * x).sum::<f64>() / r.len().max(1) as f64).sqrt()
        / target.bounding_box_diagonal();
    (rms > 2.0 * fitted).then(|| {
        format!(
            "with --no-align the markers lie {:.1} % of the target's diagonal from their partners (RMS), where the similarity that fits them would leave {:.1} %: the references stand apart, and much of the target may stay unmatched; leave out --no-align to bring the source onto the target",
            100.0 * rms,
            100.0 * fitted
        )
    })
}

/// `c` for the meshes `source` and `target` (the files' own, or welded at
/// seams: welding keeps the triangles, which the pairs name). A saved
/// correspondence names the files' meshes, the solvers take welded ones.
pub(crate) fn signed_for(c: &Correspondence, source: &Mesh3, target: &Mesh3) -> Correspondence {
    Correspondence::new(c.pairs().to_vec(), source, target).with_alignment(*c.alignment())
}

/// The report's lines for the copies of vertices welded at seams in each
/// reference, if any.
pub(crate) fn print_welded(source: usize, target: usize) {
    for (mesh, welded) in [("source", source), ("target", target)] {
        if let Some(line) = output::welded_line(welded) {
            say!("welded in the {mesh}: {line}");
        }
    }
}

/// How the markers fitted (distances as fractions of the target's diagonal).
#[derive(Debug, Default, Serialize)]
pub struct MarkerReport {
    pub markers: usize,
    /// Markers with a side inside a triangle (or on an edge).
    pub on_triangles: usize,
    /// Markers with a side given as a position and snapped to the nearest
    /// point of the surface; how far (largest) on each side.
    pub snapped_points: usize,
    pub largest_snap_source: f64,
    pub largest_snap_target: f64,
    /// Whether the source was aligned to the target (not --no-align).
    pub aligned: bool,
    /// The scale of the alignment (target size over source size).
    pub alignment_scale: f64,
    pub marker_residual_rms: f64,
    pub marker_residual_max: f64,
    pub suspicious_markers: Vec<String>,
    /// How far (degrees) the orientation the deformations are transferred
    /// in turns from the markers' fit: that of the matched surface.
    pub turn_from_marker_fit: f64,
    /// When the source's and the target's planes of symmetry were kept
    /// together: how far each mesh is from its mirror image (RMS, over the
    /// RMS distance of its surface from its centroid).
    pub mirror_plane_misfits: Option<[f64; 2]>,
}

impl MarkerReport {
    pub(crate) fn print(&self) {
        let mut line = format!("markers:        {}", self.markers);
        let mut notes = Vec::new();
        if self.snapped_points > 0 {
            notes.push(format!(
                "{} snapped to the surface, moved at most {:.3} % of the source's and {:.3} % of the target's diagonal",
                output::count(self.snapped_points, "position"),
                100.0 * self.largest_snap_source,
                100.0 * self.largest_snap_target
            ));
        }
        if self.on_triangles > 0 {
            notes.push(format!(
                "{} inside triangles",
                output::count(self.on_triangles, "marker")
            ));
        }
        if !notes.is_empty() {
            line += &format!(" ({})", notes.join("; "));
        }
        say!("{line}");
        if self.aligned {
            say!(
                "alignment:      scale {:.6}, marker residual {:.3} % of the target's diagonal (RMS), {:.3} % at most",
                self.alignment_scale,
                100.0 * self.marker_residual_rms,
                100.0 * self.marker_residual_max
            );
            let mut line = format!(
                "orientation:    the matched surface's, {:.2} degrees from the markers' fit",
                self.turn_from_marker_fit
            );
            if let Some([source, target]) = self.mirror_plane_misfits {
                line += &format!(
                    ", the planes of symmetry kept together (each mesh its own mirror image to {:.2} % and {:.2} % of its size)",
                    100.0 * source,
                    100.0 * target
                );
            }
            say!("{line}");
        } else {
            say!(
                "alignment:      off, marker distance {:.3} % of the target's diagonal (RMS)",
                100.0 * self.marker_residual_rms
            );
        }
    }
}

/// `e` with degenerate triangles of either reference named as its file's
/// faces.
pub(crate) fn name_degenerate_faces(
    e: meshmorph::Error,
    source_ref: &Reference,
    target_ref: &Reference,
) -> meshmorph::Error {
    let e = output::degenerate_faces(e, &source_ref.file.file, "source reference");
    output::degenerate_faces(e, &target_ref.file.file, "target reference")
}

/// The two reference meshes.
#[derive(Debug, Clone, clap::Args)]
pub struct References {
    /// The source character at rest (S0); its poses have its vertices and triangles.
    #[arg(long, value_name = "MESH")]
    pub source_ref: PathBuf,
    /// The target character at rest (T0).
    #[arg(long, value_name = "MESH")]
    pub target_ref: PathBuf,
    /// Keep apart vertices that share a place. By default copies at seams
    /// (vertices at exactly one place in a reference whose neighbours coincide too, as
    /// UV seams and edge splits leave them) are welded for the solve, so that
    /// the surface does not crack along them; the files keep their vertices.
    #[arg(long)]
    pub no_weld: bool,
    /// With a glTF or VRM --source-ref: its mesh to read, by the mesh's or
    /// its node's name [default: the only mesh, else the one with the most
    /// vertices]
    #[arg(long, value_name = "NAME")]
    pub source_mesh: Option<String>,
    /// With a glTF or VRM --target-ref: its mesh to read, by the mesh's or
    /// its node's name [default: the only mesh, else the one with the most
    /// vertices]
    #[arg(long, value_name = "NAME")]
    pub target_mesh: Option<String>,
}

impl References {
    /// Both files, kept whole, and their meshes welded at seams.
    pub(crate) fn read(&self) -> Result<(Reference, Reference)> {
        let read = |path: &Path, role: &str, choice: Option<&str>| {
            Reference::read(path, role, choice, !self.no_weld)
        };
        let (s, t) = rayon::join(
            || {
                read(
                    &self.source_ref,
                    "source reference",
                    self.source_mesh.as_deref(),
                )
            },
            || {
                read(
                    &self.target_ref,
                    "target reference",
                    self.target_mesh.as_deref(),
                )
            },
        );
        Ok((s?, t?))
    }

    /// "from `source.obj` to `target.obj`", for messages.
    pub(crate) fn describe(&self) -> String {
        format!(
            "from `{}` to `{}`",
            self.source_ref.display(),
            self.target_ref.display()
        )
    }
}

/// A reference mesh: its file, and its mesh with the copies of vertices at
/// seams welded ([`meshmorph::Seams`]), which the solvers take.
pub(crate) struct Reference {
    pub(crate) file: WeldedFile,
    pub(crate) mesh: Mesh3,
    /// The glTF file and mesh, when the reference is one.
    pub(crate) rig: Option<Rig>,
}

/// A glTF reference: the file kept whole, and the mesh read from it.
pub(crate) struct Rig {
    pub(crate) doc: meshmorph::io::gltf::GltfDocument,
    pub(crate) mesh: meshmorph::io::gltf::GltfMesh,
}

impl Rig {
    fn read(path: &Path, role: &str, choice: Option<&str>) -> Result<Self> {
        let (doc, mesh) = meshmorph::io::gltf::read(path, choice)
            .map_err(|e| output::reading_error(e, role, path))?;
        Ok(Rig { doc, mesh })
    }

    /// The mesh placed in the scene (its node's matrix), as a mesh file
    /// of its own: markers, correspondence and solve work on it.
    fn mesh_file(&self, path: &Path, role: &str) -> Result<meshmorph::io::MeshFile> {
        let surface = &self.mesh.surface;
        let placed = self.mesh.placed(surface.positions());
        let mut text = Vec::new();
        meshmorph::io::write_positions_to(
            &mut text,
            path,
            &placed,
            surface.triangles(),
            meshmorph::io::Format::Obj,
        )?;
        meshmorph::io::MeshFile::parse(text, meshmorph::io::Format::Obj, path)
            .map_err(|e| output::reading_error(e, role, path))
    }
}

impl Reference {
    /// The file at `path` (called `role`), kept whole, its mesh welded at
    /// seams with `weld`; of a glTF or VRM file, the mesh `choice`.
    pub(crate) fn read(path: &Path, role: &str, choice: Option<&str>, weld: bool) -> Result<Self> {
        if crate::gltf::is_gltf(path) {
            let rig = Rig::read(path, role, choice)?;
            let (file, mesh) = WeldedFile::new(rig.mesh_file(path, role)?, weld);
            return Ok(Reference {
                file,
                mesh,
                rig: Some(rig),
            });
        }
        let (file, mesh) = WeldedFile::new(output::read_mesh_file(path, role)?, weld);
        Ok(Reference {
            file,
            mesh,
            rig: None,
        })
    }

    /// The mesh as the file has it (marker and pin indices refer to it).
    pub(crate) fn file_mesh(&self) -> &Mesh3 {
        self.file.file.mesh()
    }
}

/// How `--one-based` numbers the markers' vertices.
pub(crate) fn numbering(one_based: bool) -> VertexNumbering {
    if one_based {
        VertexNumbering::FromOne
    } else {
        VertexNumbering::FromZero
    }
}
