//! Transfers the poses of both deformation-transfer pairs of
//! ../shared/data/dt (Sumner and Popović's horse to camel with both marker
//! sets, and the face mask onto the whole head) and scores each pose
//! against Sumner's own result: the RMS vertex distance after centring,
//! over the target reference's bounding-box diagonal. Each pair runs with
//! all its markers and with every 2nd, 4th, 7th and 12th line of its marker
//! file (the face's every 2nd and 4th: a marker set a user places in a few
//! minutes). Prints a summary table (mean and worst error, correspondence
//! time) and, with `POSES=1`, one table per pair and marker set.
//!
//! Run with `cargo run --release -p meshmorph --example horse_camel`;
//! `OUT=dir` also writes every result as OBJ; `ONLY=text` runs the cases
//! whose name contains `text`.

#[path = "support/shared_data.rs"]
mod shared_data;
use std::path::{Path, PathBuf};
use std::time::Instant;

use meshmorph::io::MeshFile;
use meshmorph::{
    correspond, CorrespondOptions, FitReport, Markers, Transfer, TransferOptions, VertexNumbering,
};

/// One evaluation: a pair, a marker file, and (source pose, reference
/// result) files.
#[derive(Clone)]
struct Case {
    name: &'static str,
    source_ref: &'static str,
    target_ref: &'static str,
    markers: &'static str,
    /// Every `every`-th marker line, from the first (none for 0).
    every: usize,
    poses: Vec<(String, String)>,
}

fn cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for case in full_cases() {
        let subsets: &[usize] = match case.name {
            n if n.starts_with("horse") && n.contains("107") => &[1, 2, 4, 7, 12, 0],
            n if n.starts_with("face") => &[1, 2, 4, 0],
            _ => &[1],
        };
        for &every in subsets {
            cases.push(Case {
                every,
                ..case.clone()
            });
        }
    }
    cases
}

fn full_cases() -> Vec<Case> {
    let horse_poses: Vec<(String, String)> = (1..=10)
        .map(|k| {
            (
                format!("horse-camel/horse-poses/horse-{k:02}.obj"),
                format!("horse-camel/camel-poses/camel-{k:02}.obj"),
            )
        })
        .collect();
    vec![
        Case {
            name: "horse -> camel, horse-camel-107.cons",
            source_ref: "horse-camel/horse-poses/horse-reference.obj",
            target_ref: "horse-camel/camel-poses/camel-reference.obj",
            markers: "horse-camel/markers/horse-camel-107.cons",
            every: 1,
            poses: horse_poses.clone(),
        },
        Case {
            name: "horse -> camel, horse-camel-124.txt",
            source_ref: "horse-camel/horse-poses/horse-reference.obj",
            target_ref: "horse-camel/camel-poses/camel-reference.obj",
            markers: "horse-camel/markers/horse-camel-124.txt",
            every: 1,
            poses: horse_poses,
        },
        Case {
            name: "face -> head, face-head.txt",
            source_ref: "face-head/face-poses/face-reference.obj",
            target_ref: "face-head/head-poses/head-reference.obj",
            markers: "face-head/markers/face-head.txt",
            every: 1,
            poses: vec![(
                "face-head/face-poses/face-02-cry.obj".into(),
                "face-head/head-poses/head-02-cry.obj".into(),
            )],
        },
    ]
}

/// What one case measured.
struct Outcome {
    markers: usize,
    fit: FitReport,
    mean: f64,
    worst: f64,
    correspond: f64,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let Some(dir) = shared_data::dir("dt") else {
        return Ok(());
    };
    let out_dir = std::env::var_os("OUT").map(PathBuf::from);
    let only = std::env::var("ONLY").unwrap_or_default();
    let mut rows = Vec::new();
    let mut refused = Vec::new();
    for case in cases().into_iter().filter(|c| label(c).contains(&only)) {
        match run(&dir, &case, out_dir.as_deref()) {
            Ok(outcome) => rows.push((label(&case), outcome)),
            // Without markers, a poor fit is refused rather than used.
            Err(e) if case.every == 0 => refused.push((label(&case), e.to_string())),
            Err(e) => return Err(e),
        }
    }
    println!(
        "\n| pair and markers | markers | mean error | worst error | fit: mean / 95th pct | uncovered | poor (regions) | correspondence |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    for (name, o) in rows {
        println!(
            "| {name} | {} | {:.5} | {:.5} | {:.3} % / {:.3} % | {:.2} % | {:.2} % ({}) | {:.3} s |",
            o.markers,
            o.mean,
            o.worst,
            100.0 * o.fit.mean_distance,
            100.0 * o.fit.distance_95,
            100.0 * o.fit.uncovered_area,
            100.0 * o.fit.poor_area,
            o.fit.poor_regions.len(),
            o.correspond
        );
    }
    for (name, why) in refused {
        println!("\n{name}: refused: {why}");
    }
    Ok(())
}

/// "horse -> camel, horse-camel-107.cons, every 4th line".
fn label(case: &Case) -> String {
    match case.every {
        0 => format!("{}, no markers", case.name),
        1 => format!("{}, every line", case.name),
        2 => format!("{}, every 2nd line", case.name),
        k => format!("{}, every {k}th line", case.name),
    }
}

/// Every `every`-th marker of `markers` (in the file's order); none for 0.
fn every_nth(markers: &Markers, every: usize) -> Markers {
    if every == 0 {
        return Markers::new(Vec::new());
    }
    Markers::on_surfaces(markers.pairs().iter().step_by(every).copied().collect())
}

fn run(
    dir: &Path,
    case: &Case,
    out_dir: Option<&Path>,
) -> Result<Outcome, Box<dyn std::error::Error>> {
    let detail = std::env::var_os("POSES").is_some();
    let source = MeshFile::read(&dir.join(case.source_ref))?;
    let target = MeshFile::read(&dir.join(case.target_ref))?;
    let markers = every_nth(
        &Markers::read(&dir.join(case.markers), VertexNumbering::FromZero)?,
        case.every,
    );
    let t = Instant::now();
    let options = CorrespondOptions::default().with_align(std::env::var_os("NOALIGN").is_none());
    let found = correspond(source.mesh(), target.mesh(), &markers, &options)?;
    let t_corr = t.elapsed().as_secs_f64();
    let c = &found.correspondence;
    let t = Instant::now();
    let transfer = Transfer::new(source.mesh(), target.mesh(), c, &TransferOptions::default())?;
    let t_setup = t.elapsed().as_secs_f64();
    let diagonal = target.mesh().bounding_box_diagonal();
    if detail {
        println!("\n### {}\n", label(case));
        let r = c.alignment().rotation;
        println!(
            "alignment rotation {:.2} degrees",
            ((r[0][0] + r[1][1] + r[2][2] - 1.0) / 2.0)
                .clamp(-1.0, 1.0)
                .acos()
                .to_degrees()
        );
        println!(
            "correspondence {:.3} s ({} pairs; unmatched: {} source, {} target triangles), \
             transfer setup {:.3} s, alignment scale {:.4}, carried parts {}, \
             target triangles held at rest shape {}\n",
            t_corr,
            c.pairs().len(),
            c.unmatched_source(),
            c.unmatched_target(),
            t_setup,
            c.alignment().scale,
            transfer.carried_parts(),
            transfer.unpaired_triangles()
        );
        print_fit(&found.fit, &markers);
        println!("| pose | error | doing nothing | solve |");
        println!("|---|---:|---:|---:|");
    }
    let mut ws = transfer.workspace();
    let mut scores = Vec::new();
    for (pose_path, reference_path) in &case.poses {
        let (pose, _) = source.pose(&MeshFile::read(&dir.join(pose_path))?)?;
        let reference = MeshFile::read(&dir.join(reference_path))?.into_mesh();
        let t = Instant::now();
        let mut out = vec![[0.0; 3]; target.mesh().num_vertices()];
        transfer.apply_into(pose.positions(), &mut out, &mut ws);
        let solve = t.elapsed().as_secs_f64();
        let score = rms_centred(&out, reference.positions()) / diagonal;
        let nothing = rms_centred(target.mesh().positions(), reference.positions()) / diagonal;
        let name = Path::new(pose_path)
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy();
        if detail {
            println!(
                "| {name} | {score:.5} | {nothing:.4} | {:.1} ms |",
                solve * 1e3
            );
        }
        if let Some(d) = out_dir {
            target.write(
                &d.join(format!("{name}.obj")),
                &out,
                meshmorph::io::Format::Obj,
            )?;
        }
        scores.push(score);
    }
    let mean = scores.iter().sum::<f64>() / scores.len() as f64;
    let worst = scores.iter().copied().fold(0.0, f64::max);
    if detail {
        println!("| **mean / worst** | **{mean:.5} / {worst:.5}** | | |");
    }
    Ok(Outcome {
        markers: markers.pairs().len(),
        fit: found.fit.clone(),
        mean,
        worst,
        correspond: t_corr,
    })
}

/// The fit's figures (percentages of the target's diagonal and area) and
/// its largest poor regions with their nearest markers.
fn print_fit(fit: &FitReport, markers: &Markers) {
    println!(
        "fit: distance target to deformed source {:.3} % mean, {:.3} % 95th percentile; \
         uncovered {:.2} %; farther than {:.3} %: {:.2} % in {} regions",
        100.0 * fit.mean_distance,
        100.0 * fit.distance_95,
        100.0 * fit.uncovered_area,
        100.0 * fit.poor_threshold,
        100.0 * fit.poor_area,
        fit.poor_regions.len()
    );
    for r in fit.poor_regions.iter().take(3) {
        let near: Vec<String> = r
            .nearest_markers
            .iter()
            .map(|&(k, d)| format!("{} at {:.2} %", markers.describe(k), 100.0 * d))
            .collect();
        println!(
            "  region of {:.2} % (up to {:.2} %) at ({:.3}, {:.3}, {:.3}), nearest markers: {}",
            100.0 * r.area,
            100.0 * r.largest_distance,
            r.point[0],
            r.point[1],
            r.point[2],
            near.join("; ")
        );
    }
    println!();
}

fn rms_centred(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let (ca, cb) = (mean(a), mean(b));
    let s: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| {
            (0..3)
                .map(|i| ((p[i] - ca[i]) - (q[i] - cb[i])).powi(2))
                .sum::<f64>()
        })
        .sum();
    (s / a.len() as f64).sqrt()
}

fn mean(p: &[[f64; 3]]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for q in p {
        for i in 0..3 {
            c[i] += q[i];
        }
    }
    c.map(|x| x / p.len() as f64)
}
