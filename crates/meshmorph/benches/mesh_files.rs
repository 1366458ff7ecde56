//! Time to read and write the mesh files of deformation transfer: a source
//! pose read as new positions for the source reference's faces, a reference
//! kept whole, and a target pose written back into the target reference's
//! file (normals turned with the surface), for horse -> camel and
//! face -> head; and the head as binary and ASCII STL.
//!
//! Run with `cargo bench -p meshmorph --bench mesh_files [RUNS]
//! [TEXT]`: RUNS calls of each row (default 21), only the rows whose name
//! holds TEXT (default all). Needs ../shared/data/dt beside the workspace
//! (skipped otherwise). One thread; the median and the fastest of the runs
//! (other work on the machine only ever adds time).

// Its `time` gives the median only: the rows here give the fastest too.
#[allow(dead_code)]
#[path = "../examples/support/timing.rs"]
mod timing;

#[path = "../examples/support/shared_data.rs"]
mod shared_data;
use std::path::Path;

use meshmorph::io::{Format, MeshFile};

/// How many times each row runs, and the rows run (those whose name holds
/// this text).
struct Runs {
    runs: usize,
    only: String,
}

/// One table row: the median and the fastest of `runs` calls of `f` over
/// `bytes`.
fn row<T>(what: &str, bytes: u64, runs: &Runs, f: impl FnMut() -> T) {
    if !what.contains(&runs.only) {
        return;
    }
    let seconds = timing::samples(runs.runs, f);
    let fastest = seconds.iter().copied().fold(f64::INFINITY, f64::min);
    let median = timing::median(seconds);
    println!(
        "| {what} | {:.2} MB | {} | {} | {:.0} MB/s |",
        bytes as f64 / 1e6,
        timing::fmt(median),
        timing::fmt(fastest),
        bytes as f64 / 1e6 / median
    );
}

fn size(path: &Path) -> u64 {
    std::fs::metadata(path).map_or(0, |m| m.len())
}

/// The rows of one pair: reading a source pose (alone and as a pose of its
/// reference), reading the target reference, writing a target pose.
fn pair(
    dir: &Path,
    [source_ref, source_pose, target_ref, target_pose]: [&str; 4],
    out: &Path,
    runs: &Runs,
) -> Result<(), Box<dyn std::error::Error>> {
    let [source_ref, source_pose, target_ref, target_pose] =
        [source_ref, source_pose, target_ref, target_pose].map(|f| dir.join(f));
    let source = MeshFile::read(&source_ref)?;
    let target = MeshFile::read(&target_ref)?;
    let new_shape = MeshFile::read(&target_pose)?.into_mesh();
    let pose_name = source_pose
        .file_name()
        .unwrap_or_default()
        .to_string_lossy();
    let target_name = target_ref.file_name().unwrap_or_default().to_string_lossy();
    row(
        &format!("read `{pose_name}` (`MeshFile::read`)"),
        size(&source_pose),
        runs,
        || MeshFile::read(&source_pose).unwrap(),
    );
    row(
        &format!("read `{pose_name}` as a pose of its reference"),
        size(&source_pose),
        runs,
        || source.read_pose(&source_pose).unwrap(),
    );
    row(
        &format!("read `{target_name}` (`MeshFile::read`)"),
        size(&target_ref),
        runs,
        || MeshFile::read(&target_ref).unwrap(),
    );
    // The first write finds the normals' groups (once per file).
    target.write(out, new_shape.positions(), Format::Obj)?;
    row(
        &format!("write a pose of `{target_name}` (`MeshFile::write`)"),
        size(&target_ref),
        runs,
        || {
            target
                .write(out, new_shape.positions(), Format::Obj)
                .unwrap()
        },
    );
    std::fs::remove_file(out)?;
    Ok(())
}

/// The same mesh as binary and as ASCII STL (written from `mesh` into the
/// temporary folder): reading each, and writing a pose back into the binary
/// one.
fn stl(dir: &Path, mesh: &str, runs: &Runs) -> Result<(), Box<dyn std::error::Error>> {
    let m = MeshFile::read(&dir.join(mesh))?.into_mesh();
    let tmp = std::env::temp_dir();
    let binary = tmp.join(format!("meshmorph-bench-io-{}.stl", std::process::id()));
    meshmorph::io::write_mesh(&binary, &m, Format::Stl)?;
    let file = MeshFile::read(&binary)?;
    let name = Path::new(mesh)
        .file_stem()
        .unwrap_or_default()
        .to_string_lossy();
    row(
        &format!("read `{name}` as binary STL (`MeshFile::read`)"),
        size(&binary),
        runs,
        || MeshFile::read(&binary).unwrap(),
    );
    let out = tmp.join(format!("meshmorph-bench-io-{}-out.stl", std::process::id()));
    row(
        &format!("write a pose of `{name}` as binary STL (`MeshFile::write`)"),
        size(&binary),
        runs,
        || {
            file.write(&out, file.mesh().positions(), Format::Stl)
                .unwrap()
        },
    );
    // ASCII as CAD tools write it: `%e` numbers.
    let ascii = tmp.join(format!(
        "meshmorph-bench-io-{}-ascii.stl",
        std::process::id()
    ));
    let mut text = String::from("solid bench\n");
    for t in 0..m.num_triangles() {
        text += "facet normal 0 0 0\nouter loop\n";
        for p in m.corners(t) {
            text += &format!("vertex {:e} {:e} {:e}\n", p[0], p[1], p[2]);
        }
        text += "endloop\nendfacet\n";
    }
    text += "endsolid bench\n";
    std::fs::write(&ascii, text)?;
    row(
        &format!("read `{name}` as ASCII STL (`MeshFile::read`)"),
        size(&ascii),
        runs,
        || MeshFile::read(&ascii).unwrap(),
    );
    for f in [binary, out, ascii] {
        std::fs::remove_file(f)?;
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = timing::args().into_iter();
    let runs = Runs {
        runs: args
            .next()
            .map_or(Ok(21), |a| a.parse())
            .map_err(|e| format!("RUNS: {e}"))?,
        only: args.next().unwrap_or_default(),
    };
    let Some(dir) = shared_data::dir("dt") else {
        return Ok(());
    };
    let out = std::env::temp_dir().join(format!("meshmorph-bench-io-{}.obj", std::process::id()));
    println!(
        "| file | size | median of {} | fastest | rate (median) |",
        runs.runs
    );
    println!("|---|---:|---:|---:|---:|");
    pair(
        &dir,
        [
            "horse-camel/horse-poses/horse-reference.obj",
            "horse-camel/horse-poses/horse-01.obj",
            "horse-camel/camel-poses/camel-reference.obj",
            "horse-camel/camel-poses/camel-01.obj",
        ],
        &out,
        &runs,
    )?;
    pair(
        &dir,
        [
            "face-head/face-poses/face-reference.obj",
            "face-head/face-poses/face-02-cry.obj",
            "face-head/head-poses/head-reference.obj",
            "face-head/head-poses/head-02-cry.obj",
        ],
        &out,
        &runs,
    )?;
    stl(&dir, "face-head/head-poses/head-reference.obj", &runs)?;
    Ok(())
}
