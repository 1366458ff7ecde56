//! `meshmorph correspond`: the triangle correspondence between two meshes,
//! computed and saved.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use serde::Serialize;

use crate::memory;
use crate::output::{self};
use crate::outputs::Plan;
use crate::pictures::PictureArgs;
use crate::transfer::{
    print_unmatched, print_welded, signed_for, CorrespondArgs, FitSummary, MarkerReport,
    PictureOutputs, References,
};

/// Compute the triangle correspondence between two meshes and save it.
#[derive(Debug, clap::Args)]
#[command(
    mut_arg("png", |a| a.help("Also write a still picture (PNG): the deformed source above the target (beside it when both are tall), the target coloured by its distance to the deformed source: green up to 0.25 % of the target's diagonal, then a colour every 0.25 % through yellow and orange to red, purple past 1.75 %")),
    mut_arg("gif", |a| a.help("Also write an animated GIF: the source reference turning into the deformed source, above the target")),
)]
pub struct CorrespondCommand {
    #[command(flatten)]
    pub refs: References,
    #[command(flatten)]
    pub correspond: CorrespondArgs,
    /// Where to save the correspondence.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Also write the source reference deformed onto the target, to see how
    /// well it fits.
    #[arg(long, value_name = "MESH")]
    pub deformed_source: Option<PathBuf>,
    /// `--png` and `--gif`, with their help for correspondences (above).
    #[command(flatten)]
    pub pictures: PictureArgs,
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// What `correspond` did.
#[derive(Debug, Serialize)]
pub struct CorrespondReport {
    #[serde(serialize_with = "output::lossy")]
    pub output: PathBuf,
    pub seconds: f64,
    pub matched_pairs: usize,
    pub unmatched_source_triangles: usize,
    pub unmatched_target_triangles: usize,
    /// Copies of vertices at seams welded for the solve, in the source and
    /// in the target.
    pub welded_source_vertices: usize,
    pub welded_target_vertices: usize,
    /// The source reference deformed onto the target, if written.
    #[serde(serialize_with = "output::lossy")]
    pub deformed_source: Option<PathBuf>,
    /// The GIF written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub gif: Option<PathBuf>,
    /// The PNG written, if any.
    #[serde(serialize_with = "output::lossy")]
    pub png: Option<PathBuf>,
    /// Every file written, in order.
    #[serde(serialize_with = "output::lossy")]
    pub files_written: Vec<PathBuf>,
    /// How the markers fitted.
    pub markers: MarkerReport,
    /// How well the source deformed onto the target lies on it.
    pub fit: FitSummary,
    /// The warnings given (also printed on stderr).
    pub warnings: Vec<String>,
}

pub fn run_correspond(args: &CorrespondCommand) -> Result<()> {
    let marker_files = args.correspond.marker_files()?;
    // Checked before any work, so that a bad name leaves no output behind.
    let deformed_format = args
        .deformed_source
        .as_deref()
        .map(meshmorph::io::Format::from_path)
        .transpose()?;
    let mut plan = Plan::new();
    plan.input(&args.refs.source_ref, "source reference");
    plan.input(&args.refs.target_ref, "target reference");
    for path in marker_files {
        plan.input(path, "marker file");
    }
    let saved = plan.file(&args.output, "correspondence");
    let deformed = args
        .deformed_source
        .as_deref()
        .map(|p| plan.file(p, "deformed source"));
    let pictures = PictureOutputs::plan(&mut plan, &args.pictures);
    let staging = plan.prepare()?;
    memory::check_reading(&[&args.refs.source_ref, &args.refs.target_ref])?;
    let (source_ref, target_ref) = args.refs.read()?;
    output::protect_side_files(&staging, &source_ref.file.file, "source reference")?;
    output::protect_side_files(&staging, &target_ref.file.file, "target reference")?;
    let (source, target) = (&source_ref.mesh, &target_ref.mesh);
    memory::check_setup(
        source.num_triangles() + target.num_triangles(),
        "the correspondence",
    )?;
    let begin = Instant::now();
    let mut warnings = staging.warnings();
    warnings.extend(
        [&source_ref, &target_ref]
            .iter()
            .flat_map(|r| output::surface_warnings(&r.file.file)),
    );
    let (result, markers, fit) =
        args.correspond
            .compute(&args.refs, &source_ref, &target_ref, &mut warnings)?;
    let seconds = begin.elapsed().as_secs_f64();
    let c = &result.correspondence;
    let on_file = signed_for(c, source_ref.file_mesh(), target_ref.file_mesh());
    staging.write(saved, |path| Ok(on_file.save(path)?))?;
    let mut files_written = vec![args.output.clone()];
    if let (Some(output), Some(path), Some(format)) =
        (deformed, &args.deformed_source, deformed_format)
    {
        staging.write_to(output, |staged, w| {
            let dropped =
                source_ref
                    .file
                    .write_to(w, staged, result.deformed_source.positions(), format)?;
            warnings.extend(output::dropped_for(path, &dropped));
            Ok(())
        })?;
        files_written.push(path.clone());
    }
    let names = (
        crate::gltf::mesh_name(&args.refs.source_ref),
        crate::gltf::mesh_name(&args.refs.target_ref),
    );
    files_written.extend(pictures.write(&staging, &args.pictures, |staged| {
        crate::pictures::write_correspondence_pictures(
            staged,
            (source.triangles(), &[source.positions()]),
            result.deformed_source.positions(),
            (target.triangles(), &[target.positions()]),
            &result.fit.distances,
            (&names.0, &names.1),
        )
        .map(|_| ())
    })?);
    if c.unmatched_target() > 0 {
        warnings.push(format!(
            "{} no source partner",
            output::count_doing(c.unmatched_target(), "target triangle", "has", "have")
        ));
    }
    output::print_warnings(&warnings);
    staging.commit()?;
    let report = CorrespondReport {
        output: args.output.clone(),
        seconds,
        matched_pairs: c.pairs().len(),
        unmatched_source_triangles: c.unmatched_source(),
        unmatched_target_triangles: c.unmatched_target(),
        welded_source_vertices: source_ref.file.seams.num_welded(),
        welded_target_vertices: target_ref.file.seams.num_welded(),
        deformed_source: args.deformed_source.clone(),
        gif: args.pictures.gif.clone(),
        png: args.pictures.png.clone(),
        files_written,
        markers,
        fit,
        warnings,
    };
    if args.json {
        output::print_json(&report);
    } else {
        report.markers.print();
        report.fit.print();
        say!(
            "correspondence: {} in {}, saved to {}",
            output::count(report.matched_pairs, "pair"),
            output::human_seconds(seconds),
            args.output.display()
        );
        print_unmatched(
            report.unmatched_source_triangles,
            report.unmatched_target_triangles,
        );
        print_welded(report.welded_source_vertices, report.welded_target_vertices);
        output::print_files(
            &[
                ("deformed:", report.deformed_source.as_deref()),
                ("picture:", report.png.as_deref()),
                ("animation:", report.gif.as_deref()),
            ],
            16,
        );
    }
    Ok(())
}
