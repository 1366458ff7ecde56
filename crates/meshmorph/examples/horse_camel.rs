//! Transfers the poses of both deformation-transfer pairs of
//! ../shared/data/dt (Sumner and Popović's horse to camel with both marker
//! sets and with every 7th of the 107 markers, and the face mask onto the
//! whole head) and scores each pose against Sumner's own result: the RMS
//! vertex distance after centring, over the target reference's
//! bounding-box diagonal. Prints, per pair and marker set, how well the
//! deformed source fits the target ([`meshmorph::FitReport`], and what
//! measuring it costs) and one markdown table of the poses, with timings.
//!
//! Run with `cargo run --release -p meshmorph --example horse_camel`;
//! `OUT=dir` also writes every result as OBJ.

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
struct Case {
    name: &'static str,
    source_ref: &'static str,
    target_ref: &'static str,
    markers: &'static str,
    /// Every how many-th marker of the file is used (1: all).
    every: usize,
    poses: Vec<(String, String)>,
}

fn cases() -> Vec<Case> {
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
            name: "horse -> camel, 107 markers",
            source_ref: "horse-camel/horse-poses/horse-reference.obj",
            target_ref: "horse-camel/camel-poses/camel-reference.obj",
            markers: "horse-camel/markers/horse-camel-107.cons",
            every: 1,
            poses: horse_poses.clone(),
        },
        Case {
            name: "horse -> camel, every 7th of the 107 markers (16)",
            source_ref: "horse-camel/horse-poses/horse-reference.obj",
            target_ref: "horse-camel/camel-poses/camel-reference.obj",
            markers: "horse-camel/markers/horse-camel-107.cons",
            every: 7,
            poses: horse_poses.clone(),
        },
        Case {
            name: "horse -> camel, 124 markers",
            source_ref: "horse-camel/horse-poses/horse-reference.obj",
            target_ref: "horse-camel/camel-poses/camel-reference.obj",
            markers: "horse-camel/markers/horse-camel-124.txt",
            every: 1,
            poses: horse_poses,
        },
        Case {
            name: "face -> head, 51 markers",
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

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let Some(dir) = shared_data::dir("dt") else {
        return Ok(());
    };
    let out_dir = std::env::var_os("OUT").map(PathBuf::from);
    for case in cases() {
        run(&dir, &case, out_dir.as_deref())?;
    }
    Ok(())
}

fn run(dir: &Path, case: &Case, out_dir: Option<&Path>) -> Result<(), Box<dyn std::error::Error>> {
    let source = MeshFile::read(&dir.join(case.source_ref))?;
    let target = MeshFile::read(&dir.join(case.target_ref))?;
    let markers = Markers::read(&dir.join(case.markers), VertexNumbering::FromZero)?;
    let markers = if case.every > 1 {
        Markers::new(
            markers
                .pairs()
                .iter()
                .step_by(case.every)
                .copied()
                .collect(),
        )
    } else {
        markers
    };
    let t = Instant::now();
    let found = correspond(
        source.mesh(),
        target.mesh(),
        &markers,
        &CorrespondOptions::default().with_align(std::env::var_os("NOALIGN").is_none()),
    )?;
    let t_corr = t.elapsed().as_secs_f64();
    let c = &found.correspondence;
    let t = Instant::now();
    let transfer = Transfer::new(source.mesh(), target.mesh(), c, &TransferOptions::default())?;
    let t_setup = t.elapsed().as_secs_f64();
    let diagonal = target.mesh().bounding_box_diagonal();
    println!("\n### {}\n", case.name);
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
    // The report again on its own, to time it (the correspondence measures
    // it once inside): the fastest of five runs.
    let mut fastest = f64::INFINITY;
    for _ in 0..5 {
        let t = Instant::now();
        let again = FitReport::new(
            &found.deformed_source,
            target.mesh(),
            c,
            &markers,
            found.fit.poor_threshold,
        );
        fastest = fastest.min(t.elapsed().as_secs_f64());
        assert_eq!(again, found.fit);
    }
    println!(
        "fit report {:.1} ms (the fastest of 5) beside the correspondence's {:.0} ms\n",
        fastest * 1e3,
        t_corr * 1e3
    );
    println!("| pose | error | doing nothing | solve |");
    println!("|---|---:|---:|---:|");
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
        println!(
            "| {name} | {score:.5} | {nothing:.4} | {:.1} ms |",
            solve * 1e3
        );
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
    println!("| **mean / worst** | **{mean:.5} / {worst:.5}** | | |");
    Ok(())
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
