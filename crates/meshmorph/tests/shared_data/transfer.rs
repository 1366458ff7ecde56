//! Sumner's horse and camel, face and head of ../shared/data/dt: the
//! transfers come close to Sumner's own, the mirror planes are found, and
//! the camel's non-manifold edges and boundaries are handled.

use std::path::{Path, PathBuf};

use meshmorph::{
    correspond, io, CorrespondOptions, Markers, Mesh3, Transfer, TransferOptions, VertexNumbering,
};

use crate::common::{all_finite, assert_close, mean, norm, self_transfer, sub};

type P3 = [f64; 3];

fn read(dir: &Path, name: &str) -> Mesh3 {
    io::read_mesh(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// RMS distance of corresponding vertices after moving each set's vertex
/// centroid to the origin.
fn rms_centred(a: &[P3], b: &[P3]) -> f64 {
    let (ca, cb) = (mean(a), mean(b));
    let s: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| norm(sub(sub(*p, ca), sub(*q, cb))).powi(2))
        .sum();
    (s / a.len() as f64).sqrt()
}

/// Mean and worst score of the ten horse poses transferred to the camel,
/// against Sumner's own camel poses.
fn horse_to_camel_scores(dir: &Path, options: &CorrespondOptions) -> (f64, f64) {
    let start = std::time::Instant::now();
    let horse = read(dir, "horse-poses/horse-reference.obj");
    let camel = read(dir, "camel-poses/camel-reference.obj");
    let markers = Markers::read(
        &dir.join("markers/horse-camel-107.cons"),
        VertexNumbering::FromZero,
    )
    .unwrap();
    assert_eq!(markers.pairs().len(), 107);
    let result = correspond(&horse, &camel, &markers, options).unwrap();
    let c = &result.correspondence;
    println!(
        "{} pairs, unmatched source {}, target {}",
        c.pairs().len(),
        c.unmatched_source(),
        c.unmatched_target()
    );
    let transfer = Transfer::new(&horse, &camel, c, &TransferOptions::default()).unwrap();
    let poses: Vec<Mesh3> = (1..=10)
        .map(|k| read(dir, &format!("horse-poses/horse-{k:02}.obj")))
        .collect();
    let outputs = transfer.apply_all(&poses).unwrap();
    let diag = camel.bounding_box_diagonal();
    let mut scores = Vec::new();
    for (k, out) in (1..=10).zip(&outputs) {
        assert!(all_finite(out), "pose {k}: non-finite output");
        let sumner = read(dir, &format!("camel-poses/camel-{k:02}.obj"));
        let score = rms_centred(out, sumner.positions()) / diag;
        println!("pose {k:02}: score {score:.5}");
        scores.push(score);
    }
    let mean = scores.iter().sum::<f64>() / scores.len() as f64;
    let worst = scores.iter().copied().fold(0.0, f64::max);
    println!(
        "mean {mean:.5} worst {worst:.5} ({:.1} s)",
        start.elapsed().as_secs_f64()
    );
    (mean, worst)
}

pub fn horse_poses_transfer_to_the_camel_close_to_sumners(dir: PathBuf) {
    // Sumner's camel poses were transferred from horse and camel as they
    // stand in the files, without an alignment: compared with them as such.
    let (mean, worst) =
        horse_to_camel_scores(&dir, &CorrespondOptions::default().with_align(false));
    assert!(mean < 0.0144, "mean score {mean:.5}");
    assert!(worst < 0.0215, "worst score {worst:.5}");
}

pub fn horse_poses_transfer_to_the_camel_aligned(dir: PathBuf) {
    // The default: the horse brought onto the camel by the markers, the
    // transfer in the orientation of the matched surface, with their planes
    // of symmetry together.
    let (mean, worst) = horse_to_camel_scores(&dir, &CorrespondOptions::default());
    assert!(mean < 0.0148, "mean score {mean:.5}");
    assert!(worst < 0.0218, "worst score {worst:.5}");
}

pub fn horse_and_camel_are_their_own_mirror_images_about_their_files_middle_plane(dir: PathBuf) {
    for name in [
        "horse-poses/horse-reference.obj",
        "camel-poses/camel-reference.obj",
    ] {
        let mesh = read(&dir, name);
        let plane = mesh
            .mirror_plane()
            .unwrap_or_else(|| panic!("{name}: no mirror plane"));
        // x = 0 across the body (the files stand along z, up along y).
        assert!(plane.normal[0].abs() > 0.9999, "{name}: {plane:?}");
        let size = mesh.bounding_box_diagonal();
        assert!(plane.offset.abs() < 0.01 * size, "{name}: {plane:?}");
        assert!(plane.misfit < 0.03, "{name}: {plane:?}");
    }
}

/// The face mask of ../shared/data/dt/face-head (8 times smaller than the
/// head and elsewhere) onto the whole head, in the default configuration.
pub fn the_face_masks_cry_transfers_to_the_head_close_to_sumners(dir: PathBuf) {
    let face = read(&dir, "face-poses/face-reference.obj");
    let head = read(&dir, "head-poses/head-reference.obj");
    let markers = Markers::read(
        &dir.join("markers/face-head.txt"),
        VertexNumbering::FromZero,
    )
    .unwrap();
    let result = correspond(&face, &head, &markers, &CorrespondOptions::default()).unwrap();
    let transfer = Transfer::new(
        &face,
        &head,
        &result.correspondence,
        &TransferOptions::default(),
    )
    .unwrap();
    let out = transfer
        .apply(&read(&dir, "face-poses/face-02-cry.obj"))
        .unwrap();
    let sumner = read(&dir, "head-poses/head-02-cry.obj");
    let score = rms_centred(&out, sumner.positions()) / head.bounding_box_diagonal();
    let nothing = rms_centred(head.positions(), sumner.positions()) / head.bounding_box_diagonal();
    println!("cry: score {score:.5}, doing nothing {nothing:.5}");
    assert!(score < 0.0087, "score {score:.5}");
}

pub fn the_camels_nonmanifold_edges_and_boundaries_are_handled(dir: PathBuf) {
    let camel = read(&dir, "camel-poses/camel-reference.obj");
    let counts = camel.surface_counts();
    assert_eq!((counts.crowded_edges, counts.boundary_edges), (26, 5));
    // The camel onto itself: every one of Sumner's camel poses comes back.
    let transfer = self_transfer(&camel);
    let poses: Vec<Mesh3> = (1..=10)
        .map(|k| read(&dir, &format!("camel-poses/camel-{k:02}.obj")))
        .collect();
    for (k, (pose, out)) in (1..=10).zip(poses.iter().zip(transfer.apply_all(&poses).unwrap())) {
        assert_close(
            &out,
            pose.positions(),
            pose,
            1e-8,
            &format!("camel pose {k}"),
        );
    }
}
