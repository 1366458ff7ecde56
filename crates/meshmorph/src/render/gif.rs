//! Animated GIF: any sequence of indexed pictures ([`write_gif`]), and the
//! animation of a planar mesh ([`write_gif_2d`]).

use std::borrow::Cow;
use std::io;
use std::path::Path;
use std::time::Duration;

use super::canvas::Canvas;
use super::grid::{GridLayout, GridOptions, GridRow};
use super::mesh2d::draw_prepared;
use super::palette::Palette;
use super::shade3d::{Camera3d, Style3d};
use super::style::{mean_area, EdgeSets, Style2d};
use super::view::View2d;
use crate::error::{Error, Result};
use crate::mesh::frame_source::{map_frame, FrameSource};
use rayon::prelude::*;

/// Size and timing of an animation.
#[derive(Clone, Debug, PartialEq)]
pub struct GifOptions {
    /// Picture width in pixels (640).
    pub width: u32,
    /// Picture height in pixels; `None` (the default) follows the aspect
    /// ratio of the animation's bounds (see [`View2d::fitting`]).
    pub height: Option<u32>,
    /// Background pixels kept around the mesh (16).
    pub margin_px: u32,
    /// Frames per second (25). GIF delays are whole hundredths of a second
    /// and browsers slow down anything faster than 50, so rates above 50
    /// play at 50; other rates are kept on average. A rate outside
    /// [`FRAME_RATES`](crate::limits::FRAME_RATES) plays at the nearest end of it.
    pub fps: f64,
    /// How long to pause on the first and on the last frame (0.5 s).
    pub hold_ends: Duration,
    /// Play forwards then backwards (true), instead of jumping from the
    /// last frame back to the first.
    pub boomerang: bool,
    /// Loop forever (true) rather than play once.
    pub loop_forever: bool,
    /// Anti-aliasing of planar animations: each pixel is the mean of
    /// `supersample²` samples (3; 1 for none). Grids of meshes in space use
    /// [`GridOptions::supersample`](super::GridOptions::supersample).
    pub supersample: u32,
}

impl Default for GifOptions {
    fn default() -> Self {
        GifOptions {
            width: 640,
            height: None,
            margin_px: 16,
            fps: 25.0,
            hold_ends: Duration::from_millis(500),
            boomerang: true,
            loop_forever: true,
            supersample: 3,
        }
    }
}

impl GifOptions {
    /// The order in which to show `num_frames` frames and for how long:
    /// `0, 1, ..., n - 1` (then `n - 2, ..., 1` when `boomerang`), each
    /// for one frame time, the first and last also for `hold_ends`.
    pub fn schedule(&self, num_frames: usize) -> Vec<(usize, Duration)> {
        let (slowest, fastest) = (
            *crate::limits::FRAME_RATES.start(),
            *crate::limits::FRAME_RATES.end(),
        );
        let fps = if self.fps.is_nan() {
            25.0
        } else {
            self.fps.clamp(slowest, fastest)
        };
        let step = Duration::from_secs_f64(1.0 / fps);
        let mut order: Vec<usize> = (0..num_frames).collect();
        if self.boomerang && num_frames > 2 {
            order.extend((1..num_frames - 1).rev());
        }
        order
            .into_iter()
            .map(|i| {
                let hold = i == 0 || i + 1 == num_frames;
                (i, if hold { step + self.hold_ends } else { step })
            })
            .collect()
    }
}

/// Writes an animated GIF of `width` × `height` pictures of indices into
/// `palette` (the global colour table: no quantisation), each shown for its
/// duration.
///
/// Durations are rounded to hundredths of a second keeping the total right
/// (at least 2/100 s each: browsers slow down shorter ones). Only the
/// rectangle that changed from the previous picture is stored, and a
/// picture equal to the previous one just lengthens its display time. The
/// pictures are consumed one at a time, so an animation can be rendered as
/// it is written.
///
/// # Errors
/// [`Error::InvalidArgument`] for a size of 0 or above 65535 or no
/// pictures; [`Error::Io`] when writing fails or a picture does not have
/// `width * height` pixels.
pub fn write_gif<P: AsRef<[u8]>>(
    path: &Path,
    width: u32,
    height: u32,
    palette: &Palette,
    loop_forever: bool,
    frames: impl IntoIterator<Item = (P, Duration)>,
) -> Result<()> {
    let (Ok(w), Ok(h)) = (u16::try_from(width), u16::try_from(height)) else {
        return Err(Error::InvalidArgument(format!(
            "a GIF of {width} × {height} pixels is too large (65535 at most)"
        )));
    };
    if w == 0 || h == 0 {
        return Err(Error::InvalidArgument(format!(
            "a GIF of {width} × {height} pixels is empty"
        )));
    }
    let mut frames = frames.into_iter().peekable();
    if frames.peek().is_none() {
        return Err(Error::InvalidArgument(
            "an animation needs at least one picture".into(),
        ));
    }
    let colors = palette.to_bytes();
    crate::io::write_atomic(path, |out| {
        let mut enc = ::gif::Encoder::new(out, w, h, &colors).map_err(gif_error)?;
        if loop_forever {
            enc.set_repeat(::gif::Repeat::Infinite).map_err(gif_error)?;
        }
        let n = usize::from(w) * usize::from(h);
        let mut prev: Vec<u8> = Vec::new();
        let mut pending: Option<::gif::Frame<'static>> = None;
        let (mut elapsed, mut shown_cs) = (Duration::ZERO, 0u64);
        for (pixels, duration) in frames {
            let pixels = pixels.as_ref();
            if pixels.len() != n {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidInput,
                    format!(
                        "a picture of {} pixels in a {width} × {height} GIF",
                        pixels.len()
                    ),
                ));
            }
            elapsed += duration;
            let end_cs = (elapsed.as_secs_f64() * 100.0).round() as u64;
            let delay = end_cs.saturating_sub(shown_cs).max(2);
            shown_cs += delay;
            match changed_rect(&prev, pixels, width as usize) {
                None => {
                    if let Some(f) = &mut pending {
                        // The same picture again: show the last one longer,
                        // starting a new frame if its delay would overflow.
                        let total = u64::from(f.delay) + delay;
                        if total <= u64::from(u16::MAX) {
                            f.delay = total as u16;
                            continue;
                        }
                    }
                    let f = pending.replace(sub_frame(pixels, width as usize, [0, 0, 1, 1], delay));
                    if let Some(f) = f {
                        enc.write_frame(&f).map_err(gif_error)?;
                    }
                }
                Some(rect) => {
                    if let Some(f) = pending.replace(sub_frame(pixels, width as usize, rect, delay))
                    {
                        enc.write_frame(&f).map_err(gif_error)?;
                    }
                    prev.clear();
                    prev.extend_from_slice(pixels);
                }
            }
        }
        if let Some(f) = pending {
            enc.write_frame(&f).map_err(gif_error)?;
        }
        enc.into_inner().map_err(gif_error)?;
        Ok(())
    })
}

fn gif_error(e: ::gif::EncodingError) -> io::Error {
    match e {
        ::gif::EncodingError::Io(e) => e,
        e => io::Error::other(e),
    }
}

/// `[x0, y0, x1, y1]` bounding the pixels that differ between two pictures
/// of `width` columns (everything when `prev` is empty), `None` if equal.
fn changed_rect(prev: &[u8], next: &[u8], width: usize) -> Option<[usize; 4]> {
    let rows = next.len() / width.max(1);
    if prev.len() != next.len() {
        return Some([0, 0, width, rows]);
    }
    let differs = |y: usize| prev[y * width..(y + 1) * width] != next[y * width..(y + 1) * width];
    let y0 = (0..rows).find(|&y| differs(y))?;
    let y1 = (y0..rows).rev().find(|&y| differs(y)).unwrap_or(y0) + 1;
    let (mut x0, mut x1) = (width, 0);
    for y in y0..y1 {
        let (a, b) = (
            &prev[y * width..(y + 1) * width],
            &next[y * width..(y + 1) * width],
        );
        if let Some(first) = (0..x0).find(|&x| a[x] != b[x]) {
            x0 = first;
        }
        if let Some(last) = (x1..width).rev().find(|&x| a[x] != b[x]) {
            x1 = last + 1;
        }
    }
    Some([x0, y0, x1.max(x0 + 1), y1])
}

fn sub_frame(
    pixels: &[u8],
    width: usize,
    [x0, y0, x1, y1]: [usize; 4],
    delay: u64,
) -> ::gif::Frame<'static> {
    let mut buffer = Vec::with_capacity((x1 - x0) * (y1 - y0));
    for y in y0..y1 {
        buffer.extend_from_slice(&pixels[y * width + x0..y * width + x1]);
    }
    ::gif::Frame {
        delay: delay.min(u64::from(u16::MAX)) as u16,
        left: x0 as u16,
        top: y0 as u16,
        width: (x1 - x0) as u16,
        height: (y1 - y0) as u16,
        buffer: Cow::Owned(buffer),
        ..::gif::Frame::default()
    }
}

/// Writes an animated GIF of a planar mesh moving through `frames` (the
/// positions of the vertices in each frame; the triangles stay the same).
///
/// One [`View2d`] is fitted over all frames, so the camera is still; each
/// frame is drawn with [`draw_mesh_2d`](super::draw_mesh_2d) (flipped
/// triangles in the warning colour, edges per [`Style2d::edges`], decided
/// once for all frames) and the frames are shown per
/// [`GifOptions::schedule`]. Frames are drawn as they are written.
///
/// # Errors
/// [`Error::InvalidArgument`] for no frames or a bad size,
/// [`Error::Mismatch`] when the frames have different numbers of vertices,
/// [`Error::Io`] when writing fails.
pub fn write_gif_2d<F: AsRef<[[f64; 2]]> + Sync>(
    path: &Path,
    frames: &[F],
    triangles: &[[u32; 3]],
    options: &GifOptions,
    style: &Style2d,
) -> Result<()> {
    write_gif_2d_frames(path, frames, triangles, options, style)
}

/// [`write_gif_2d`] with frames produced on demand: each frame is asked for
/// once to fit the view (in parallel) and once for each time the schedule
/// shows it; only the frame being drawn is held.
///
/// # Errors
/// As [`write_gif_2d`].
pub fn write_gif_2d_frames<S: FrameSource<2> + ?Sized>(
    path: &Path,
    frames: &S,
    triangles: &[[u32; 3]],
    options: &GifOptions,
    style: &Style2d,
) -> Result<()> {
    let count = frames.num_frames();
    if count == 0 {
        return Err(Error::InvalidArgument(
            "an animation needs at least one frame".into(),
        ));
    }
    // Per frame: its vertex count, bounds and mean triangle area.
    let summaries: Vec<(usize, [[f64; 2]; 2], f64)> = (0..count)
        .into_par_iter()
        .map(|k| {
            map_frame(frames, k, |f| {
                let bounds = View2d::bounds(std::iter::once(f));
                (f.len(), bounds, mean_area(f, triangles))
            })
        })
        .collect();
    let vertices = summaries[0].0;
    if let Some(k) = summaries.iter().position(|s| s.0 != vertices) {
        return Err(Error::Mismatch(format!(
            "frame {k} has {} vertices but frame 0 has {vertices}",
            summaries[k].0
        )));
    }
    // Each frame's bounds as two points: the view fits all of them.
    let corners: Vec<[[f64; 2]; 2]> = summaries.iter().map(|s| s.1).collect();
    let fit = |width: u32, height: Option<u32>, margin: u32| {
        View2d::fitting(corners.iter().map(|c| c.as_slice()), width, height, margin)
    };
    // Drawn `s` times larger, then reduced: anti-aliased.
    let s = options.supersample.clamp(1, 8);
    let size = fit(options.width, options.height, options.margin_px);
    let (width, height) = (size.width, size.height);
    let view = fit(
        width.saturating_mul(s),
        Some(height.saturating_mul(s)),
        options.margin_px.saturating_mul(s),
    );
    let edges = EdgeSets::new(triangles, vertices);
    let smallest = summaries.iter().map(|s| s.2).fold(f64::INFINITY, f64::min);
    let mode = style.resolve_edges(smallest, view.scale / f64::from(s));
    let mut canvas = Canvas::with_style(view.width, view.height, style);
    let palette = canvas.palette.clone();
    let mut scratch = Default::default();
    let pictures = options.schedule(count).into_iter().map(|(i, duration)| {
        canvas.clear(super::palette::slot::BACKGROUND);
        frames.with_frame(i, &mut |f| {
            draw_prepared(
                &mut canvas,
                f,
                triangles,
                &edges,
                mode,
                &view,
                style,
                &mut scratch,
                s,
            )
        });
        let pixels = if s == 1 {
            canvas.pixels.clone()
        } else {
            super::resample::downsample(&canvas, s, width, height).pixels
        };
        (pixels, duration)
    });
    write_gif(
        path,
        width,
        height,
        &palette,
        options.loop_forever,
        pictures,
    )
}

/// Writes an animation of meshes in space laid out in grids: picture `k`
/// shows `frames[k]` (rows of poses, as for
/// [`render_grid_3d`](super::render_grid_3d)), every picture through one
/// [`GridLayout`] fitted over all frames so that the cameras stay still,
/// shown per [`GifOptions::schedule`]. The picture size comes from `grid`
/// (`options.width`, `height` and `margin_px` are not used).
///
/// # Errors
/// [`Error::InvalidArgument`] for no frames or a picture too large for a
/// GIF, [`Error::Io`] when writing fails.
pub fn write_gif_grid(
    path: &Path,
    frames: &[Vec<GridRow<'_>>],
    grid: &GridOptions,
    options: &GifOptions,
) -> Result<()> {
    if frames.is_empty() {
        return Err(Error::InvalidArgument(
            "an animation needs at least one frame".into(),
        ));
    }
    let num_rows = frames.iter().map(Vec::len).max().unwrap_or(0);
    let all: Vec<GridRow<'_>> = (0..num_rows)
        .filter_map(|r| {
            let first = frames.iter().find_map(|f| f.get(r))?;
            Some(GridRow {
                triangles: first.triangles,
                poses: frames
                    .iter()
                    .filter_map(|f| f.get(r))
                    .flat_map(|row| row.poses.iter().copied())
                    .collect(),
                style: first.style,
            })
        })
        .collect();
    let mut layout = GridLayout::fit(&all, grid);
    layout.columns = frames
        .iter()
        .flatten()
        .map(|row| row.poses.len() as u32)
        .max()
        .unwrap_or(0)
        .max(1);
    let (w, h) = layout.size();
    let pictures = options
        .schedule(frames.len())
        .into_iter()
        .map(|(i, duration)| (layout.render(&frames[i]).pixels, duration));
    write_gif(path, w, h, &layout.palette, options.loop_forever, pictures)
}

/// Writes an animated GIF of a mesh in space moving through `frames`, one
/// flat-shaded view in `style` through a camera looking along
/// `grid.direction` (one cell of `grid`'s size), fitted once over every
/// frame so that it stays still; the frames are shown per
/// [`GifOptions::schedule`]. Frames are produced on demand: each is asked
/// for once to fit the camera (in parallel) and once for each time the
/// schedule shows it; only the frame being drawn is held.
///
/// # Errors
/// [`Error::InvalidArgument`] for no frames or a picture too large for a
/// GIF, [`Error::Io`] when writing fails.
pub fn write_gif_3d_frames<S: FrameSource<3> + ?Sized>(
    path: &Path,
    frames: &S,
    triangles: &[[u32; 3]],
    style: Style3d,
    grid: &GridOptions,
    options: &GifOptions,
) -> Result<()> {
    let count = frames.num_frames();
    if count == 0 {
        return Err(Error::InvalidArgument(
            "an animation needs at least one frame".into(),
        ));
    }
    // A camera fitted to the points of a frame that are extreme along its
    // axes is the camera fitted to all of the frame's points.
    let camera = Camera3d::looking(grid.direction, grid.up);
    let extremes: Vec<Vec<[f64; 3]>> = (0..count)
        .into_par_iter()
        .map(|k| map_frame(frames, k, |f| extreme_points(f, &camera)))
        .collect();
    let fitted = [GridRow {
        triangles,
        poses: extremes.iter().map(Vec::as_slice).collect(),
        style,
    }];
    let mut layout = GridLayout::fit(&fitted, grid);
    layout.columns = 1;
    let (w, h) = layout.size();
    let pictures = options.schedule(count).into_iter().map(|(i, duration)| {
        let mut pixels = Vec::new();
        frames.with_frame(i, &mut |f| {
            let row = GridRow {
                triangles,
                poses: vec![f],
                style,
            };
            pixels = layout.render(&[row]).pixels;
        });
        (pixels, duration)
    });
    write_gif(path, w, h, &layout.palette, options.loop_forever, pictures)
}

/// The finite points of `points` lowest and highest along each of the
/// camera's axes (at most six).
fn extreme_points(points: &[[f64; 3]], camera: &Camera3d) -> Vec<[f64; 3]> {
    let axes = [camera.right, camera.up, camera.forward];
    let mut best: Vec<Option<(f64, [f64; 3])>> = vec![None; 6];
    for p in points.iter().filter(|p| p.iter().all(|x| x.is_finite())) {
        for (a, axis) in axes.iter().enumerate() {
            let d = p[0] * axis[0] + p[1] * axis[1] + p[2] * axis[2];
            for (slot, sign) in [(2 * a, 1.0), (2 * a + 1, -1.0)] {
                if best[slot].is_none_or(|(b, _)| sign * d < sign * b) {
                    best[slot] = Some((d, *p));
                }
            }
        }
    }
    best.into_iter().flatten().map(|(_, p)| p).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let tube = crate::mesh::shapes::tube(4.0, 0.3, 17, 8);
        let frames: Vec<Vec<[f64; 3]>> = [0.0, 1.0, 2.5]
            .iter()
            .map(|&a| {
                crate::mesh::shapes::bend(&tube, 4.0, a)
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
        // Once to fit, then once per picture of the schedule.
        let asked = source.1.into_inner();
        assert_eq!(asked, 3 + options.schedule(3).len());
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
        assert_eq!(source.1.into_inner(), 4 + options.schedule(4).len());
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
        super::super::draw_mesh_2d(&mut c, &frames[3], &t, &view, &Style2d::default());
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
        let (p, t) = super::super::shade3d::tests::cube();
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
}
