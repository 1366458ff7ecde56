//! `meshmorph blend`.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use meshmorph::{Blend3, InterpolatorOptions};
use serde::Serialize;

use crate::output::{self, FormatArg};

/// Blend shapes of a base mesh with weights (as-rigid-as-possible: rotations
/// and stretches combined per triangle, then one least-squares solve).
///
/// Writes OUT: BASE moved by SHAPE1 x W1 + SHAPE2 x W2 + ... . A weight of 1
/// on one shape and 0 on the others gives that shape; weights may be
/// negative or above 1 (extrapolation), and stretches combine by their
/// logarithms, so nothing collapses.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The base mesh (OBJ, OFF or PLY).
    pub base: PathBuf,
    /// A shape and its weight, FILE=WEIGHT (repeat for more shapes); every
    /// shape has the base's vertices and triangles.
    #[arg(long = "shape", required = true, value_name = "FILE=WEIGHT", value_parser = parse_shape)]
    pub shapes: Vec<(PathBuf, f64)>,
    /// The blended mesh to write.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Output mesh format [default: from OUT's extension].
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Planar (2) or in space (3) [default: 2 when every z of every mesh is 0].
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=3), value_name = "2|3")]
    pub dim: Option<u8>,
    /// Combine each triangle's principal rotations as they are, without
    /// making them continuous across neighbours.
    #[arg(long)]
    pub no_consistency: bool,
    /// Go on when a shape has triangles turned over relative to the base.
    #[arg(long)]
    pub allow_flips: bool,
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// `FILE=WEIGHT`, split at the last `=`; the weight a finite number.
fn parse_shape(text: &str) -> Result<(PathBuf, f64), String> {
    let Some((file, weight)) = text.rsplit_once('=') else {
        return Err(format!(
            "`{text}`: expected FILE=WEIGHT, e.g. smile.obj=0.5"
        ));
    };
    if file.is_empty() {
        return Err(format!("`{text}`: no file before `=`"));
    }
    match weight.trim().parse::<f64>() {
        Ok(w) if w.is_finite() => Ok((PathBuf::from(file), w)),
        _ => Err(format!(
            "`{text}`: the weight `{weight}` is not a finite number"
        )),
    }
}

/// What a run did.
#[derive(Debug, Serialize)]
pub struct Report {
    /// The file written.
    pub output: PathBuf,
    /// 2 for planar meshes, 3 for meshes in space.
    pub dimension: usize,
    /// Vertices of the mesh.
    pub vertices: usize,
    /// Triangles of the mesh.
    pub triangles: usize,
    /// Preparing the blend: decompositions, factorization.
    pub setup_seconds: f64,
    /// Computing the blend.
    pub blend_seconds: f64,
    /// Triangles of the result turned over relative to the base.
    pub turned_over_triangles: usize,
    /// Every file written.
    pub files_written: Vec<PathBuf>,
    /// The warnings given (also printed on stderr).
    pub warnings: Vec<String>,
}

pub fn run(args: &Args) -> Result<()> {
    let start = Instant::now();
    let format = output::format_or_like(args.format, &args.output)?;
    let mut inputs: Vec<&std::path::Path> = vec![args.base.as_path()];
    inputs.extend(args.shapes.iter().map(|(p, _)| p.as_path()));
    output::refuse_input(&args.output, &inputs)?;
    let base = output::read_mesh(&args.base, "base mesh")?;
    let mut shapes = Vec::with_capacity(args.shapes.len());
    for (path, _) in &args.shapes {
        let shape = output::read_mesh(path, "blend shape")?;
        shape.check_same_connectivity(
            &base,
            [
                &format!("`{}`", path.display()),
                &format!("the base `{}`", args.base.display()),
            ],
        )?;
        shapes.push(shape);
    }
    let all_planar = std::iter::once(&base)
        .chain(&shapes)
        .all(|m| m.positions().iter().all(|p| p[2] == 0.0));
    let planar = match args.dim {
        Some(2) if !all_planar => bail!("--dim 2: the meshes are not planar (some z is not 0)"),
        Some(d) => d == 2,
        None => all_planar,
    };
    let options = InterpolatorOptions::default()
        .with_consistency(!args.no_consistency)
        .with_allow_flips(args.allow_flips);
    let context = || format!("blending `{}`", args.base.display());
    let setup = Instant::now();
    let paths: Vec<PathBuf> = args.shapes.iter().map(|(p, _)| p.clone()).collect();
    let blend = Blend3::new(&base, &shapes, &options)
        .map_err(|e| name_numbered(e, "blend shape", &paths))
        .with_context(context)?;
    let setup_seconds = setup.elapsed().as_secs_f64();
    let weights: Vec<f64> = args.shapes.iter().map(|(_, w)| *w).collect();
    let begin = Instant::now();
    let result = blend.at(&weights);
    let blend_seconds = begin.elapsed().as_secs_f64();
    let turned_over = blend.count_turned_over(&result);
    if planar {
        let flat: Vec<[f64; 2]> = result.iter().map(|p| [p[0], p[1]]).collect();
        meshmorph::io::write_positions(&args.output, &flat, blend.triangles(), format)
    } else {
        meshmorph::io::write_positions(&args.output, &result, blend.triangles(), format)
    }
    .with_context(|| format!("writing `{}`", args.output.display()))?;
    let mut warnings = Vec::new();
    if turned_over > 0 {
        warnings.push(format!(
            "the blend has {turned_over} triangles turned over relative to the base"
        ));
    }
    output::print_warnings(&warnings);
    let report = Report {
        output: args.output.clone(),
        dimension: if planar { 2 } else { 3 },
        vertices: blend.num_vertices(),
        triangles: blend.triangles().len(),
        setup_seconds,
        blend_seconds,
        turned_over_triangles: turned_over,
        files_written: vec![args.output.clone()],
        warnings,
    };
    if args.json {
        output::print_json(&report);
    } else {
        println!(
            "wrote {} ({} vertices, {} triangles, {} shapes)",
            report.output.display(),
            report.vertices,
            report.triangles,
            args.shapes.len()
        );
        println!("setup: {}", output::human_seconds(setup_seconds));
        println!("blend: {}", output::human_seconds(blend_seconds));
        println!("turned-over triangles: {turned_over}");
        println!(
            "total: {}",
            output::human_seconds(start.elapsed().as_secs_f64())
        );
    }
    Ok(())
}

/// The library names shapes and keys by number ("blend shape 2", "key 1",
/// counted from 1 after the first mesh); say the file instead.
pub(crate) fn name_numbered(e: meshmorph::Error, role: &str, paths: &[PathBuf]) -> anyhow::Error {
    let text = e.to_string();
    for (k, path) in paths.iter().enumerate().rev() {
        let label = format!("{role} {}", k + 1);
        if text.contains(&label) {
            return anyhow::anyhow!(
                "{}",
                text.replace(&label, &format!("{role} `{}`", path.display()))
            );
        }
    }
    e.into()
}
