//! Deformation transfer benchmarks on Sumner and Popović's horse -> camel
//! data (../shared/data/dt/horse-camel, markers horse-camel-107.cons):
//! correspondence, transfer setup, one pose solve, and one pose including
//! reading the pose OBJ and writing the result OBJ.
//!
//! Run with `cargo bench -p meshmorph --bench transfer`. Skipped with a
//! message when the data is absent. Results are in BENCHMARKS.md at the
//! workspace root.

use std::path::{Path, PathBuf};

use divan::counter::ItemsCount;
use divan::{black_box, Bencher};
use meshmorph::{
    correspond, io, CorrespondOptions, Markers, Mesh3, Transfer, TransferOptions, VertexNumbering,
};

const DATA: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../../shared/data/dt/horse-camel"
);
const POSES: usize = 10;

fn main() {
    if Path::new(DATA).is_dir() {
        let (horse, camel, markers) = references().unwrap();
        println!(
            "horse {} triangles, {} vertices -> camel {} triangles, {} vertices, {} markers",
            horse.num_triangles(),
            horse.num_vertices(),
            camel.num_triangles(),
            camel.num_vertices(),
            markers.pairs().len()
        );
    } else {
        println!("skipped transfer benchmarks: {DATA} not found");
    }
    divan::main();
}

fn pose_path(k: usize) -> PathBuf {
    Path::new(DATA).join(format!("horse-poses/horse-{k:02}.obj"))
}

/// Source reference, target reference and markers, or `None` without data.
fn references() -> Option<(Mesh3, Mesh3, Markers)> {
    let dir = Path::new(DATA);
    if !dir.is_dir() {
        return None;
    }
    let horse = io::read_mesh(&dir.join("horse-poses/horse-reference.obj")).unwrap();
    let camel = io::read_mesh(&dir.join("camel-poses/camel-reference.obj")).unwrap();
    let markers = Markers::read(
        &dir.join("markers/horse-camel-107.cons"),
        VertexNumbering::FromZero,
    )
    .unwrap();
    Some((horse, camel, markers))
}

/// The references and a transfer set up with the default options.
fn transfer() -> Option<(Mesh3, Mesh3, Transfer)> {
    let (horse, camel, markers) = references()?;
    let c = correspond(&horse, &camel, &markers, &CorrespondOptions::default()).unwrap();
    let t = Transfer::new(
        &horse,
        &camel,
        &c.correspondence,
        &TransferOptions::default(),
    )
    .unwrap();
    Some((horse, camel, t))
}

/// `correspond` with the default options (five deformation rounds, each a
/// factorization, then triangle matching).
#[divan::bench(sample_count = 10, max_time = 60)]
fn correspondence(bencher: Bencher) {
    let Some((horse, camel, markers)) = references() else {
        return;
    };
    let options = CorrespondOptions::default();
    bencher.bench_local(|| correspond(&horse, &camel, &markers, &options).unwrap());
}

/// `Transfer::new`: assembly and factorization of the camel's system.
#[divan::bench(sample_count = 20, max_time = 30)]
fn setup(bencher: Bencher) {
    let Some((horse, camel, markers)) = references() else {
        return;
    };
    let c = correspond(&horse, &camel, &markers, &CorrespondOptions::default()).unwrap();
    let options = TransferOptions::default();
    bencher.bench_local(|| Transfer::new(&horse, &camel, &c.correspondence, &options).unwrap());
}

/// `Transfer::apply_into` with a reused workspace, cycling through the ten
/// horse poses (already in memory).
#[divan::bench(sample_count = 200)]
fn pose_solve(bencher: Bencher) {
    let Some((_, camel, transfer)) = transfer() else {
        return;
    };
    let poses: Vec<Mesh3> = (1..=POSES)
        .map(|k| io::read_mesh(&pose_path(k)).unwrap())
        .collect();
    let mut ws = transfer.workspace();
    let mut out = vec![[0.0; 3]; camel.num_vertices()];
    let mut k = 0;
    bencher.bench_local(|| {
        transfer.apply_into(poses[k].positions(), &mut out, &mut ws);
        k = (k + 1) % POSES;
        black_box(&out);
    });
}

/// One pose from file to file: read the horse pose OBJ, check it, solve,
/// write the camel OBJ (into a temporary directory), cycling through the
/// ten poses.
#[divan::bench(sample_count = 100)]
fn pose_with_io(bencher: Bencher) {
    let Some((_, camel, transfer)) = transfer() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let outputs: Vec<PathBuf> = (1..=POSES)
        .map(|k| dir.path().join(format!("camel-{k:02}.obj")))
        .collect();
    let inputs: Vec<PathBuf> = (1..=POSES).map(pose_path).collect();
    let mut ws = transfer.workspace();
    let mut out = vec![[0.0; 3]; camel.num_vertices()];
    let mut k = 0;
    bencher.bench_local(|| {
        let pose = io::read_mesh(&inputs[k]).unwrap();
        transfer.check_pose(&pose).unwrap();
        transfer.apply_into(pose.positions(), &mut out, &mut ws);
        io::write_positions(&outputs[k], &out, camel.triangles(), io::Format::Obj).unwrap();
        k = (k + 1) % POSES;
    });
}

/// The parts of [`pose_with_io`] alone: reading one pose, writing one result.
mod pose_io {
    use super::*;

    #[divan::bench(sample_count = 100)]
    fn read(bencher: Bencher) {
        if !Path::new(DATA).is_dir() {
            return;
        }
        let mut k = 0;
        bencher.bench_local(|| {
            let pose = io::read_mesh(&pose_path(k + 1)).unwrap();
            k = (k + 1) % POSES;
            pose
        });
    }

    #[divan::bench(sample_count = 100)]
    fn write(bencher: Bencher) {
        let Some((_, camel, _)) = references() else {
            return;
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("camel.obj");
        bencher.bench_local(|| {
            io::write_positions(&path, camel.positions(), camel.triangles(), io::Format::Obj)
                .unwrap()
        });
    }
}

/// All ten poses at once with `Transfer::apply_all` (rayon over poses);
/// throughput is poses per second.
#[divan::bench(sample_count = 50)]
fn ten_poses_parallel(bencher: Bencher) {
    let Some((_, _, transfer)) = transfer() else {
        return;
    };
    let poses: Vec<Mesh3> = (1..=POSES)
        .map(|k| io::read_mesh(&pose_path(k)).unwrap())
        .collect();
    bencher
        .counter(ItemsCount::new(POSES))
        .bench_local(|| transfer.apply_all(&poses).unwrap());
}
