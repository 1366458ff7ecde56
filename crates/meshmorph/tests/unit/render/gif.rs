use meshmorph::error::Error;
use meshmorph::mesh::frame_source::FrameSource;
use meshmorph::render::canvas::Canvas;
use meshmorph::render::grid::{GridOptions, GridRow};
use meshmorph::render::palette::Palette;
use meshmorph::render::shade3d::Style3d;
use meshmorph::render::style::Style2d;
use meshmorph::render::view::View2d;
use std::path::Path;
use std::time::Duration;

use meshmorph::render::gif::*;

fn decode(path: &Path) -> (u16, u16, Vec<(u16, Vec<u8>)>) {
    let mut opts = ::gif::DecodeOptions::new();
    opts.set_color_output(::gif::ColorOutput::Indexed);
    let mut d = opts.read_info(std::fs::File::open(path).unwrap()).unwrap();
    let (w, h) = (d.width(), d.height());
    let mut screen = vec![0u8; usize::from(w) * usize::from(h)];
    let mut frames = vec![];
    while let Some(f) = d.read_next_frame().unwrap() {
        for y in 0..usize::from(f.height) {
            let row = &f.buffer[y * usize::from(f.width)..(y + 1) * usize::from(f.width)];
            let at = (y + usize::from(f.top)) * usize::from(w) + usize::from(f.left);
            screen[at..at + row.len()].copy_from_slice(row);
        }
        frames.push((f.delay, screen.clone()));
    }
    (w, h, frames)
}

/// A bar of `n` squares bending by `angle` radians about its left end.
fn bar(n: u32, angle: f64) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut p = vec![];
    let mut t = vec![];
    for i in 0..=n {
        let s = f64::from(i) / f64::from(n);
        let r = 1.0 / angle.max(1e-9);
        let th = angle * s;
        for side in [-0.1, 0.1] {
            let rr = r - side;
            p.push(if angle < 1e-9 {
                [s, side]
            } else {
                [rr * th.sin(), r - rr * th.cos()]
            });
        }
        if i < n {
            let v = 2 * i;
            t.push([v, v + 2, v + 3]);
            t.push([v, v + 3, v + 1]);
        }
    }
    (p, t)
}

/// Frames in memory, counting how often a writer asks for one.
struct Counting<'a, const D: usize>(&'a [Vec<[f64; D]>], std::sync::atomic::AtomicUsize);

impl<const D: usize> FrameSource<D> for Counting<'_, D> {
    fn num_frames(&self) -> usize {
        self.0.len()
    }
    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; D]])) {
        self.1.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        use_frame(&self.0[k])
    }
}

#[test]
fn rates_beyond_the_frame_rates_play_at_their_ends() {
    let step = |fps: f64| {
        let o = GifOptions {
            fps,
            boomerang: false,
            ..GifOptions::default()
        };
        o.schedule(3)[1].1.as_secs_f64()
    };
    assert_eq!(step(1e-20), 100.0);
    assert_eq!(step(0.0), 100.0);
    assert_eq!(step(1e50), 1e-3);
    assert_eq!(step(f64::NAN), 0.04);
}

#[test]
fn frames_on_demand_draw_what_frames_in_memory_draw() {
    let dir = tempfile::tempdir().unwrap();
    let options = GifOptions::default();
    // In space: the camera fitted to each frame's extreme points is
    // the one fitted to all points.
    let tube = meshmorph::mesh::shapes::tube(4.0, 0.3, 17, 8);
    let frames: Vec<Vec<[f64; 3]>> = [0.0, 1.0, 2.5]
        .iter()
        .map(|&a| {
            meshmorph::mesh::shapes::bend(&tube, 4.0, a)
                .positions()
                .to_vec()
        })
        .collect();
    let grid = GridOptions {
        cell_width: 120,
        ..GridOptions::default()
    };
    let style = Style3d::default();
    let rows: Vec<Vec<GridRow<'_>>> = frames
        .iter()
        .map(|f| {
            vec![GridRow {
                triangles: tube.triangles(),
                poses: vec![f.as_slice()],
                style,
            }]
        })
        .collect();
    let (held, streamed) = (dir.path().join("a.gif"), dir.path().join("b.gif"));
    write_gif_grid(&held, &rows, &grid, &options).unwrap();
    let source = Counting(&frames, 0.into());
    write_gif_3d_frames(&streamed, &source, tube.triangles(), style, &grid, &options).unwrap();
    assert_eq!(
        std::fs::read(&held).unwrap(),
        std::fs::read(&streamed).unwrap()
    );
    // Once to fit, then once to draw (a frame shown twice is drawn
    // once).
    let asked = source.1.into_inner();
    assert_eq!(asked, 3 + 3);
    // In the plane: the same pictures as frames in memory give.
    let (_, t) = bar(8, 0.0);
    let planar: Vec<Vec<[f64; 2]>> = (0..4).map(|k| bar(8, 0.6 * f64::from(k)).0).collect();
    let source = Counting(&planar, 0.into());
    write_gif_2d(&held, &planar, &t, &options, &Style2d::default()).unwrap();
    write_gif_2d_frames(&streamed, &source, &t, &options, &Style2d::default()).unwrap();
    assert_eq!(
        std::fs::read(&held).unwrap(),
        std::fs::read(&streamed).unwrap()
    );
    assert_eq!(source.1.into_inner(), 4 + 4);
}

/// `f` run on a pool of `threads` threads.
fn on_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn frames_drawn_in_parallel_make_the_file_one_thread_makes() {
    let dir = tempfile::tempdir().unwrap();
    let tube = meshmorph::shapes::tube(4.0, 0.3, 17, 8);
    // More frames than a batch, so that frames shown on the way back
    // wait for their turn across batches.
    let frames: Vec<Vec<[f64; 3]>> = (0..23)
        .map(|k| {
            let a = 0.15 * f64::from(k);
            meshmorph::shapes::bend(&tube, 4.0, a).positions().to_vec()
        })
        .collect();
    let grid = GridOptions {
        longest_side: Some(96),
        supersample: 2,
        ..GridOptions::default()
    };
    let (_, t) = bar(8, 0.0);
    let planar: Vec<Vec<[f64; 2]>> = (0..23).map(|k| bar(8, 0.1 * f64::from(k)).0).collect();
    let write = |threads: usize, name: &str, options: &GifOptions| {
        let space = dir.path().join(format!("{name}-space.gif"));
        let plane = dir.path().join(format!("{name}-plane.gif"));
        on_threads(threads, || {
            let style = Style3d::default();
            write_gif_3d_frames(&space, &frames, tube.triangles(), style, &grid, options).unwrap();
            write_gif_2d(&plane, &planar, &t, options, &Style2d::default()).unwrap();
        });
        (std::fs::read(space).unwrap(), std::fs::read(plane).unwrap())
    };
    for boomerang in [true, false] {
        let options = GifOptions {
            width: 120,
            boomerang,
            ..GifOptions::default()
        };
        let one = write(1, "one", &options);
        for threads in [2, 3, 8] {
            assert!(one == write(threads, "many", &options), "{threads} threads");
        }
        // Every showing decodes to the picture of its frame.
        let (_, _, decoded) = decode(&dir.path().join("many-plane.gif"));
        let shown: Vec<usize> = options.schedule(23).iter().map(|s| s.0).collect();
        assert_eq!(decoded.len(), shown.len());
        for (j, &k) in shown.iter().enumerate() {
            let first = shown.iter().position(|&f| f == k).unwrap();
            assert!(decoded[j].1 == decoded[first].1, "showing {j} of frame {k}");
        }
    }
}

#[test]
fn gif_decodes_with_the_right_frames_and_size() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bar.gif");
    let (_, t) = bar(8, 0.0);
    let frames: Vec<Vec<[f64; 2]>> = (0..5).map(|k| bar(8, 0.5 * f64::from(k)).0).collect();
    // Anti-aliased (the default): the same size, and blended colours
    // along the edges besides background, fill and edge.
    let aa = dir.path().join("aa.gif");
    let options = GifOptions {
        width: 160,
        ..GifOptions::default()
    };
    write_gif_2d(&aa, &frames, &t, &options, &Style2d::default()).unwrap();
    let (aw, ah, smooth) = decode(&aa);
    let mut colours = smooth[0].1.clone();
    colours.sort_unstable();
    colours.dedup();
    assert!(colours.len() > 3, "{colours:?}");
    // Without anti-aliasing: exactly the picture draw_mesh_2d makes.
    let options = GifOptions {
        supersample: 1,
        ..options
    };
    write_gif_2d(&path, &frames, &t, &options, &Style2d::default()).unwrap();
    let (w, h, decoded) = decode(&path);
    assert_eq!((aw, ah), (w, h));
    let view = View2d::fitting(frames.iter().map(Vec::as_slice), 160, None, 16);
    assert_eq!((w, h), (160, view.height as u16));
    // Boomerang: 0 1 2 3 4 3 2 1.
    assert_eq!(decoded.len(), 8);
    let delays: Vec<u16> = decoded.iter().map(|f| f.0).collect();
    assert_eq!(delays, vec![54, 4, 4, 4, 54, 4, 4, 4]);
    // Frames 3 and 5 (both pose 3) are the same picture, drawn as the
    // mesh should be.
    assert_eq!(decoded[3].1, decoded[5].1);
    let mut c = Canvas::with_style(160, view.height, &Style2d::default());
    meshmorph::render::draw_mesh_2d(&mut c, &frames[3], &t, &view, &Style2d::default());
    assert_eq!(decoded[3].1, c.pixels);

    let no_boomerang = GifOptions {
        width: 160,
        boomerang: false,
        loop_forever: false,
        fps: 30.0,
        ..GifOptions::default()
    };
    write_gif_2d(&path, &frames, &t, &no_boomerang, &Style2d::default()).unwrap();
    let (_, _, decoded) = decode(&path);
    let delays: Vec<u16> = decoded.iter().map(|f| f.0).collect();
    assert_eq!(delays, vec![53, 4, 3, 3, 54]);
}

#[test]
fn grid_animation_keeps_one_layout() {
    let (p, t) = crate::render::shade3d::cube();
    let poses: Vec<Vec<[f64; 3]>> = (0..4)
        .map(|k| {
            p.iter()
                .map(|q| [q[0] * (1.0 + f64::from(k)), q[1], q[2]])
                .collect()
        })
        .collect();
    let frames: Vec<Vec<GridRow<'_>>> = poses
        .iter()
        .map(|pose| {
            vec![GridRow {
                triangles: &t,
                poses: vec![pose.as_slice(), p.as_slice()],
                style: Default::default(),
            }]
        })
        .collect();
    let grid = GridOptions {
        cell_width: 64,
        cell_height: Some(40),
        ..GridOptions::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("grid.gif");
    write_gif_grid(&path, &frames, &grid, &GifOptions::default()).unwrap();
    let (w, h, decoded) = decode(&path);
    assert_eq!((w, h, decoded.len()), (128, 40, 6));
    // The second cell always shows the same cube through the same
    // camera: it never changes.
    let right =
        |f: &[u8]| -> Vec<u8> { f.chunks(128).flat_map(|row| row[64..].to_vec()).collect() };
    assert!(decoded.iter().all(|f| right(&f.1) == right(&decoded[0].1)));
    assert_ne!(decoded[0].1, decoded[3].1);
    let none: [Vec<GridRow<'_>>; 0] = [];
    assert!(write_gif_grid(&path, &none, &grid, &GifOptions::default()).is_err());
}

#[test]
fn equal_pictures_merge_and_bad_input_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("x.gif");
    let p = Palette::standard();
    let a = vec![0u8; 12];
    let mut b = a.clone();
    b[5] = 3;
    let ms = Duration::from_millis;
    write_gif(
        &path,
        4,
        3,
        &p,
        true,
        [(&a, ms(100)), (&a, ms(100)), (&b, ms(40)), (&a, ms(40))],
    )
    .unwrap();
    let (_, _, frames) = decode(&path);
    let delays: Vec<u16> = frames.iter().map(|f| f.0).collect();
    assert_eq!(delays, vec![20, 4, 4]);
    assert_eq!(frames[1].1, b);
    assert_eq!(frames[2].1, a);

    let none: [(&[u8], Duration); 0] = [];
    assert!(matches!(
        write_gif(&path, 4, 3, &p, true, none),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        write_gif(&path, 0, 3, &p, true, [(&a, ms(1))]),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        write_gif(&path, 70000, 1, &p, true, [(&a, ms(1))]),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        write_gif(&path, 5, 3, &p, true, [(&a, ms(1))]),
        Err(Error::Io { .. })
    ));
    let frames: Vec<Vec<[f64; 2]>> = vec![vec![[0.0; 2]; 3], vec![[0.0; 2]; 4]];
    let e = write_gif_2d(
        &path,
        &frames,
        &[[0, 1, 2]],
        &GifOptions::default(),
        &Style2d::default(),
    );
    assert!(matches!(e, Err(Error::Mismatch(_))));
    let empty: [Vec<[f64; 2]>; 0] = [];
    let e = write_gif_2d(
        &path,
        &empty,
        &[[0, 1, 2]],
        &GifOptions::default(),
        &Style2d::default(),
    );
    assert!(matches!(e, Err(Error::InvalidArgument(_))));
    // Degenerate frames still make a picture.
    let frames = vec![
        vec![[1.0, 1.0]; 3],
        vec![[1e300, -1e300], [0.0, 0.0], [1.0, 1.0]],
    ];
    write_gif_2d(
        &path,
        &frames,
        &[[0, 1, 2], [0, 1, 1]],
        &GifOptions::default(),
        &Style2d::default(),
    )
    .unwrap();
    assert_eq!(decode(&path).2.len(), 2);
}
