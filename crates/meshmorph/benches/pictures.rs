//! Prints a markdown table of what pictures cost next to the frames they
//! show: the horse of Sumner's horse-camel set going from pose 01 to pose
//! 07 in 40 frames (in space) and the USTC elephant in 60 frames (planar),
//! each computed and written as OBJ files (the first key's file with new
//! positions, as `meshmorph interpolate` writes frames), then drawn as a GIF
//! (the frames recomputed, as `meshmorph interpolate --gif` does), on every
//! thread and on one. Medians of several runs; the GIF's size and file size
//! too.
//!
//! `cargo bench -p meshmorph --bench pictures [-- RUNS]`
//! (RUNS 5 by default). The meshes are read from `../shared/data`.

#[path = "../examples/support/shared_data.rs"]
mod shared_data;
#[path = "../examples/support/timing.rs"]
mod timing;
use timing::{fmt, median, time};

use std::path::Path;

use meshmorph::io::{self, Format, MeshFile};
use meshmorph::render::{self, GifOptions, GridOptions, Ramp, Style2d, Style3d};
use meshmorph::{Dimension, FrameSource, Mesh, Sequence, Space};
use rayon::prelude::*;

/// Frames computed when a writer asks for them, one back-substitution
/// each, and given with `E` coordinates (`E` = `D` here: the writers take
/// planar frames or frames in space).
struct Recomputed<'a, const D: usize, const E: usize>
where
    Space<D>: Dimension<D>,
{
    morph: &'a Sequence<D>,
    times: &'a [f64],
}

impl<const D: usize, const E: usize> FrameSource<E> for Recomputed<'_, D, E>
where
    Space<D>: Dimension<D>,
{
    fn num_frames(&self) -> usize {
        self.times.len()
    }

    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; E]])) {
        let mut positions = vec![[0.0; D]; self.morph.num_vertices()];
        let mut ws = self.morph.workspace();
        self.morph.at_into(self.times[k], &mut positions, &mut ws);
        let given: Vec<[f64; E]> = positions.iter().map(lift).collect();
        use_frame(&given)
    }
}

/// `p` with `E` coordinates: z = 0 added, or nothing changed.
fn lift<const D: usize, const E: usize>(p: &[f64; D]) -> [f64; E] {
    std::array::from_fn(|c| if c < D { p[c] } else { 0.0 })
}

/// Computes every frame (a few per solve, in parallel) and writes each as
/// `file` with new positions in `dir`.
fn write_objs<const D: usize>(morph: &Sequence<D>, times: &[f64], file: &MeshFile, dir: &Path)
where
    Space<D>: Dimension<D>,
{
    let together = meshmorph::limits::frames_per_solve(times.len());
    times.par_chunks(together).enumerate().for_each_init(
        || morph.workspace(),
        |ws, (chunk, chunk_times)| {
            for (i, f) in morph.frames_with(chunk_times, ws).iter().enumerate() {
                let path = dir.join(format!("frame_{:04}.obj", chunk * together + i));
                let lifted: Vec<[f64; 3]> = f
                    .iter()
                    .map(|p| std::array::from_fn(|c| if c < D { p[c] } else { 0.0 }))
                    .collect();
                file.write(&path, &lifted, Format::Obj).unwrap();
            }
        },
    );
}

/// The longer side of `meshmorph`'s pictures by default (`--size`).
const SIZE: u32 = 640;

/// The GIF of the frames as `meshmorph interpolate --gif` draws it.
fn write_gif<const D: usize>(morph: &Sequence<D>, times: &[f64], path: &Path)
where
    Space<D>: Dimension<D>,
{
    let options = GifOptions {
        longest_side: Some(SIZE),
        ..GifOptions::default()
    };
    if D == 2 {
        let planar: Recomputed<'_, D, 2> = Recomputed { morph, times };
        let style = Style2d {
            flipped: render::Flipped::AgainstMajority,
            ..Style2d::default()
        };
        render::write_gif_2d_frames(path, &planar, morph.triangles(), &options, &style).unwrap();
    } else {
        let space: Recomputed<'_, D, 3> = Recomputed { morph, times };
        let grid = GridOptions {
            longest_side: Some(SIZE),
            supersample: 2,
            direction: [-0.25, -0.35, -1.0],
            up: [0.0, 1.0, 0.0],
            ..GridOptions::default()
        };
        let style = Style3d::with_ramp(Ramp::BLUE);
        render::write_gif_3d_frames(path, &space, morph.triangles(), style, &grid, &options)
            .unwrap();
    }
}

fn row<const D: usize>(name: &str, file: &MeshFile, keys: &[Mesh<D>], count: usize, runs: usize)
where
    Space<D>: Dimension<D>,
{
    let morph = Sequence::new(keys, &Default::default()).unwrap();
    let times: Vec<f64> = (0..count)
        .map(|k| (keys.len() - 1) as f64 * k as f64 / (count - 1) as f64)
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let gif = dir.path().join("frames.gif");
    // Taken in turns, so that a change in the machine's load weighs on both.
    let (mut objs, mut gifs) = (Vec::new(), Vec::new());
    for _ in 0..runs {
        objs.push(time(1, || write_objs(&morph, &times, file, dir.path())));
        gifs.push(time(1, || write_gif(&morph, &times, &gif)));
    }
    let (obj, all) = (median(objs), median(gifs));
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let one = one_thread.install(|| time(runs.min(3), || write_gif(&morph, &times, &gif)));
    let bytes = std::fs::metadata(&gif).unwrap().len();
    let mut decoder = gif::DecodeOptions::new()
        .read_info(std::fs::File::open(&gif).unwrap())
        .unwrap();
    let (w, h) = (decoder.width(), decoder.height());
    let mut pictures = 0;
    while decoder.next_frame_info().unwrap().is_some() {
        pictures += 1;
    }
    println!(
        "| {name} | {count} | {} | {} | {} | {:.1} | {w} × {h} | {pictures} | {:.2} MB |",
        fmt(obj),
        fmt(all),
        fmt(one),
        all / obj,
        bytes as f64 / 1e6
    );
}

fn main() {
    let runs: usize = timing::args()
        .into_iter()
        .next()
        .map_or(5, |r| r.parse().expect("RUNS is a number"));
    println!(
        "| mesh | frames | OBJ frames | GIF ({} threads) | GIF (1 thread) | GIF / OBJ | GIF size | pictures | file |",
        rayon::current_num_threads()
    );
    println!("|---|---:|---:|---:|---:|---:|---|---:|---:|");
    if let Some(dir) = shared_data::dir("dt/horse-camel/horse-poses") {
        let file = MeshFile::read(&dir.join("horse-01.obj")).unwrap();
        let last = io::read_mesh(&dir.join("horse-07.obj")).unwrap();
        row(
            "horse 01 → 07",
            &file,
            &[file.mesh().clone(), last],
            40,
            runs,
        );
    }
    if let Some(dir) = shared_data::dir("2d/elephant") {
        let file = MeshFile::read(&dir.join("elephant_s.obj")).unwrap();
        let last = io::read_mesh(&dir.join("elephant_t.obj")).unwrap();
        let keys = [file.mesh().to_2d().unwrap(), last.to_2d().unwrap()];
        row("elephant", &file, &keys, 60, runs);
    }
}
