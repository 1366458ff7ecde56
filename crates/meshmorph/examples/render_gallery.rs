//! A gallery of the pictures meshmorph draws, to look at: planar meshes
//! (PNG, GIF, SVG) and shaded meshes in space (PNG, GIF).
//!
//! ```text
//! cargo run --release -p meshmorph --example render_gallery [-- DIR]
//! ```
//!
//! writes into DIR (default `render-gallery/`). Its one test, that SVG paths
//! hold the triangles the raster draws, runs with
//! `cargo test -p meshmorph --example render_gallery -- --ignored`.

use std::path::PathBuf;
use std::time::Instant;

use meshmorph::render::*;

fn out(name: &str) -> PathBuf {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "render-gallery".into()),
    );
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn main() {
    pictures_2d();
    pictures_3d();
}

/// An annulus of `rings` × `sectors` quads split into triangles,
/// counter-clockwise.
fn annulus(r0: f64, r1: f64, rings: u32, sectors: u32) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut p = vec![];
    for i in 0..=rings {
        let r = r0 + (r1 - r0) * f64::from(i) / f64::from(rings);
        for j in 0..sectors {
            let a = std::f64::consts::TAU * f64::from(j) / f64::from(sectors);
            p.push([r * a.cos(), r * a.sin()]);
        }
    }
    let mut t = vec![];
    for i in 0..rings {
        for j in 0..sectors {
            let v = |i: u32, j: u32| i * sectors + j % sectors;
            let (a, b, c, d) = (v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i + 1, j));
            if (i + j) % 2 == 0 {
                t.push([a, c, b]);
                t.push([a, d, c]);
            } else {
                t.push([a, d, b]);
                t.push([b, d, c]);
            }
        }
    }
    (p, t)
}

fn rotate(p: &[[f64; 2]], angle: impl Fn([f64; 2]) -> f64) -> Vec<[f64; 2]> {
    p.iter()
        .map(|&q| {
            let a = angle(q);
            [
                a.cos() * q[0] - a.sin() * q[1],
                a.sin() * q[0] + a.cos() * q[1],
            ]
        })
        .collect()
}

/// A torus around the y axis; `twist` bends it into a saddle.
fn torus(big: f64, small: f64, n: u32, m: u32, twist: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut p = vec![];
    for i in 0..n {
        let u = std::f64::consts::TAU * f64::from(i) / f64::from(n);
        for j in 0..m {
            let v = std::f64::consts::TAU * f64::from(j) / f64::from(m);
            let r = big + small * v.cos();
            p.push([
                r * u.cos(),
                small * v.sin() + twist * (2.0 * u).sin(),
                r * u.sin(),
            ]);
        }
    }
    let mut t = vec![];
    for i in 0..n {
        for j in 0..m {
            let k = |i: u32, j: u32| (i % n) * m + j % m;
            t.push([k(i, j), k(i, j + 1), k(i + 1, j + 1)]);
            t.push([k(i, j), k(i + 1, j + 1), k(i + 1, j)]);
        }
    }
    (p, t)
}

/// A UV sphere with poles on the y axis.
fn sphere(n: u32, m: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut p = vec![[0.0, 1.0, 0.0], [0.0, -1.0, 0.0]];
    for i in 1..n {
        let th = std::f64::consts::PI * f64::from(i) / f64::from(n);
        for j in 0..m {
            let ph = std::f64::consts::TAU * f64::from(j) / f64::from(m);
            p.push([th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin()]);
        }
    }
    let ring = |i: u32, j: u32| 2 + (i - 1) * m + j % m;
    let mut t = vec![];
    for j in 0..m {
        t.push([0, ring(1, j + 1), ring(1, j)]);
        t.push([1, ring(n - 1, j), ring(n - 1, j + 1)]);
    }
    for i in 1..n - 1 {
        for j in 0..m {
            t.push([ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)]);
            t.push([ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)]);
        }
    }
    (p, t)
}

/// A square grid of `n` × `n` cells, two triangles each.
fn grid(n: u32) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut p = vec![];
    for j in 0..=n {
        for i in 0..=n {
            // A little wobble so that edges are not axis-aligned.
            let (x, y) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
            p.push([
                x + 0.02 * (7.0 * y).sin(),
                0.75 * y + 0.02 * (5.0 * x).cos(),
            ]);
        }
    }
    let mut t = vec![];
    for j in 0..n {
        for i in 0..n {
            let v = j * (n + 1) + i;
            t.push([v, v + 1, v + n + 2]);
            t.push([v, v + n + 2, v + n + 1]);
        }
    }
    (p, t)
}

/// Morphs an annulus into a copy of itself rotated by 120 degrees whose
/// right side is turned inside out (the inner ring pushed past the outer
/// one), moving each vertex in a straight line: the ring shrinks and folds,
/// which shows the flipped triangles.
fn annulus_frames(n: usize) -> (Vec<Vec<[f64; 2]>>, Vec<[u32; 3]>) {
    let (p, t) = annulus(0.55, 1.0, 6, 48);
    let folded: Vec<[f64; 2]> = p
        .iter()
        .map(|q| {
            let (r, a) = (q[0].hypot(q[1]), q[1].atan2(q[0]));
            let w = a.cos().max(0.0).powi(2);
            let r = r + w * 1.3 * (1.0 - r);
            [r * a.cos(), r * a.sin()]
        })
        .collect();
    let end = rotate(&folded, |_| 120f64.to_radians());
    let frames = (0..n)
        .map(|k| {
            let s = k as f64 / (n - 1) as f64;
            p.iter()
                .zip(&end)
                .map(|(a, b)| [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])])
                .collect()
        })
        .collect();
    (frames, t)
}

fn pictures_2d() {
    let (frames, t) = annulus_frames(31);
    let style = Style2d::default();
    let view = View2d::fitting(frames.iter().map(Vec::as_slice), 480, None, 16);
    for k in [0, 12, 20, 30] {
        let mut c = Canvas::with_style(view.width, view.height, &style);
        draw_mesh_2d(&mut c, &frames[k], &t, &view, &style);
        write_png(&out(&format!("annulus_{k:02}.png")), &c).unwrap();
        std::fs::write(
            out(&format!("annulus_{k:02}.svg")),
            svg_frame(&frames[k], &t, &view, &style),
        )
        .unwrap();
    }
    let start = Instant::now();
    write_gif_2d(
        &out("annulus.gif"),
        &frames,
        &t,
        &GifOptions {
            width: 480,
            ..GifOptions::default()
        },
        &style,
    )
    .unwrap();
    println!(
        "annulus.gif: {} frames in {:?}",
        frames.len(),
        start.elapsed()
    );

    // A dense mesh: Auto draws only the outline.
    let (p, t) = grid(160);
    let view = View2d::fitting([p.as_slice()], 480, None, 16);
    let mut c = Canvas::with_style(view.width, view.height, &style);
    draw_mesh_2d(&mut c, &p, &t, &view, &style);
    write_png(&out("dense_grid.png"), &c).unwrap();
    let svg = svg_frame(&p, &t, &view, &style);
    println!("dense_grid.svg: {} triangles, {} bytes", t.len(), svg.len());
    std::fs::write(out("dense_grid.svg"), svg).unwrap();
}

fn pictures_3d() {
    let (tp, tt) = torus(1.0, 0.38, 72, 28, 0.0);
    let (bent, _) = torus(1.0, 0.38, 72, 28, 0.35);
    let (sp, st) = sphere(24, 48);

    // One torus from two angles in one picture.
    let mut c = Canvas::new(640, 320, Palette::standard());
    for (k, (az, el)) in [(30.0, 25.0), (110.0, 65.0)].into_iter().enumerate() {
        let cam = Camera3d::orbit(az, el).fitted([tp.as_slice()]);
        let vp = Rect {
            x: 320 * k as u32 + 10,
            y: 10,
            width: 300,
            height: 300,
        };
        draw_mesh_3d(&mut c, &tp, &tt, &cam, vp, &Style3d::default());
    }
    write_png(&out("torus_two_angles.png"), &c).unwrap();

    // A grid: the torus poses in blue, the sphere (and a squashed one) in
    // sand with edges.
    let squashed: Vec<[f64; 3]> = sp.iter().map(|q| [1.3 * q[0], 0.6 * q[1], q[2]]).collect();
    let rows = [
        GridRow {
            triangles: &tt,
            poses: vec![tp.as_slice(), bent.as_slice(), tp.as_slice()],
            style: Style3d::default(),
        },
        GridRow {
            triangles: &st,
            poses: vec![sp.as_slice(), squashed.as_slice()],
            style: Style3d::with_ramp(Ramp::SAND).with_edges(),
        },
    ];
    let start = Instant::now();
    let c = render_grid_3d(
        &rows,
        &GridOptions {
            cell_width: 240,
            ..GridOptions::default()
        },
    );
    println!("grid {}x{} in {:?}", c.width, c.height, start.elapsed());
    write_png(&out("grid.png"), &c).unwrap();

    // An animation: the torus bending back and forth, still camera.
    let poses: Vec<Vec<[f64; 3]>> = (0..16)
        .map(|k| torus(1.0, 0.38, 72, 28, 0.35 * f64::from(k) / 15.0).0)
        .collect();
    let all = [GridRow {
        triangles: &tt,
        poses: poses.iter().map(Vec::as_slice).collect(),
        style: Style3d::default(),
    }];
    let options = GridOptions {
        cell_width: 320,
        ..GridOptions::default()
    };
    let mut layout = GridLayout::fit(&all, &options);
    layout.columns = 1;
    let (w, h) = layout.size();
    let gif = GifOptions::default();
    let frames = gif.schedule(poses.len()).into_iter().map(|(i, d)| {
        let row = [GridRow {
            triangles: &tt,
            poses: vec![poses[i].as_slice()],
            style: Style3d::default(),
        }];
        (layout.render(&row).pixels, d)
    });
    write_gif(&out("torus.gif"), w, h, &layout.palette, true, frames).unwrap();

    // Decode the GIF back and save a frame from the middle to look at.
    let mut opts = ::gif::DecodeOptions::new();
    opts.set_color_output(::gif::ColorOutput::Indexed);
    let mut d = opts
        .read_info(std::fs::File::open(out("torus.gif")).unwrap())
        .unwrap();
    let mut screen = Canvas::new(w, h, layout.palette.clone());
    let mut n = 0;
    while let Some(f) = d.read_next_frame().unwrap() {
        for y in 0..u32::from(f.height) {
            for x in 0..u32::from(f.width) {
                let i = f.buffer[(y * u32::from(f.width) + x) as usize];
                screen.set(x + u32::from(f.left), y + u32::from(f.top), i);
            }
        }
        n += 1;
        if n == 12 {
            write_png(&out("torus_gif_frame12.png"), &screen).unwrap();
        }
    }
    println!("torus.gif: {n} frames of {w}x{h}");
}

/// Parses the triangles back out of the fill paths of `svg_frame`.
#[cfg(test)]
fn svg_triangles(svg: &str) -> Vec<[[f64; 2]; 3]> {
    let mut tris = vec![];
    for line in svg.lines().filter(|l| l.starts_with("<path fill=\"#")) {
        let d = &line[line.find(" d=\"").unwrap() + 4..line.rfind('"').unwrap()];
        for sub in d.split('M').filter(|s| !s.is_empty()) {
            let nums: Vec<f64> = sub
                .trim_end_matches('z')
                .replace('l', " ")
                .replace('-', " -")
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            assert_eq!(nums.len(), 6, "{sub}");
            let a = [nums[0], nums[1]];
            let b = [a[0] + nums[2], a[1] + nums[3]];
            let c = [b[0] + nums[4], b[1] + nums[5]];
            tris.push([a, b, c]);
        }
    }
    tris
}

#[test]
#[ignore = "slow-ish: compares the SVG geometry with the raster"]
fn svg_paths_hold_the_same_triangles() {
    let (frames, t) = annulus_frames(31);
    let style = Style2d {
        edges: Edges::None,
        ..Style2d::default()
    };
    let view = View2d::fitting(frames.iter().map(Vec::as_slice), 480, None, 16);
    for f in &frames {
        let tris = svg_triangles(&svg_frame(f, &t, &view, &style));
        assert_eq!(tris.len(), t.len());
        let mut c = Canvas::with_style(view.width, view.height, &style);
        for tri in &tris {
            c.fill_triangle(*tri, slot::FILL, None);
        }
        let covered = c.pixels.len() - c.count(slot::BACKGROUND);
        let mut r = Canvas::with_style(view.width, view.height, &style);
        draw_mesh_2d(&mut r, f, &t, &view, &style);
        let want = r.pixels.len() - r.count(slot::BACKGROUND);
        // Rounding to 0.01 pixel moves few pixel centres across an edge.
        assert!(covered.abs_diff(want) * 200 <= want, "{covered} vs {want}");
    }
}
