//! Animated GIF: any sequence of indexed pictures ([`write_gif`]), and the
//! animation of a planar mesh ([`write_gif_2d`]).

use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap};
use std::io::{self, Read, Seek, SeekFrom, Write};
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
    /// The longer side of the picture in pixels, the other following the
    /// aspect ratio of the animation's bounds: a tall animation gets a
    /// narrower picture rather than a taller one. When set, `width` and
    /// `height` are not used; `None` (the default) keeps them.
    pub longest_side: Option<u32>,
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
            longest_side: None,
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
        crate::playback::shown_order(num_frames, self.boomerang)
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
/// pictures are consumed a few at a time and compressed in parallel, so an
/// animation can be rendered as it is written.
///
/// # Errors
/// [`Error::InvalidArgument`] for a size of 0 or above 65535 or no
/// pictures; [`Error::Io`] when writing fails or a picture does not have
/// `width * height` pixels.
pub fn write_gif<P: AsRef<[u8]> + Sync>(
    path: &Path,
    width: u32,
    height: u32,
    palette: &Palette,
    loop_forever: bool,
    frames: impl IntoIterator<Item = (P, Duration)>,
) -> Result<()> {
    let (w, h) = gif_size(width, height)?;
    let mut frames = frames.into_iter().peekable();
    if frames.peek().is_none() {
        return Err(Error::InvalidArgument(
            "an animation needs at least one picture".into(),
        ));
    }
    crate::io::write_atomic(path, |out| {
        let mut sequence = Sequence::new(out, w, h, palette, loop_forever)?;
        let mut last: Option<P> = None;
        loop {
            let batch: Vec<(P, Duration)> = frames.by_ref().take(batch_len()).collect();
            if batch.is_empty() {
                break;
            }
            let encoded: Vec<Encoded> = (0..batch.len())
                .into_par_iter()
                .map(|i| {
                    let prev = match i {
                        0 => last.as_ref().map(AsRef::as_ref),
                        _ => Some(batch[i - 1].0.as_ref()),
                    };
                    Encoded::new(prev, batch[i].0.as_ref(), w, h)
                })
                .collect::<io::Result<_>>()?;
            for (e, (_, duration)) in encoded.into_iter().zip(&batch) {
                sequence.push(e, *duration)?;
            }
            last = batch.into_iter().last().map(|(p, _)| p);
        }
        sequence.finish()
    })
}

/// The size of a GIF as its header holds it.
fn gif_size(width: u32, height: u32) -> Result<(u16, u16)> {
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
    Ok((w, h))
}

/// How many pictures are drawn or compressed at once: enough to keep every
/// thread busy, few enough to hold.
fn batch_len() -> usize {
    (2 * rayon::current_num_threads()).max(4)
}

/// Writes an animated GIF of `count` frames, each drawn once by `draw` (a
/// `width * height` picture of indices into `palette`), shown per
/// `options`' [`schedule`](GifOptions::schedule).
///
/// Frames are drawn and compressed in parallel, a few at a time in order.
/// Each frame is compressed once: the rectangle holding its changes from
/// every frame the schedule shows just before it (on the way there and, in
/// a boomerang, on the way back), so that every showing stores the same
/// data. A frame shown again later is kept compressed (on disk beyond a few
/// megabytes) until its turn. The file is the same whatever the number of
/// threads.
fn write_drawn(
    path: &Path,
    (width, height): (u32, u32),
    palette: &Palette,
    options: &GifOptions,
    count: usize,
    draw: impl Fn(usize) -> Vec<u8> + Sync,
) -> Result<()> {
    let (w, h) = gif_size(width, height)?;
    let schedule = options.schedule(count);
    if schedule.is_empty() {
        return Err(Error::InvalidArgument(
            "an animation needs at least one picture".into(),
        ));
    }
    let order: Vec<usize> = schedule.iter().map(|s| s.0).collect();
    let mut showings: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (j, &k) in order.iter().enumerate() {
        showings[k].push(j);
    }
    // The last frame to draw before frame `k` can be compressed: the
    // schedule steps one frame at a time, so it is `k` or `k + 1`.
    let needs = |k: usize| {
        showings[k]
            .iter()
            .filter(|&&j| j > 0)
            .map(|&j| order[j - 1])
            .fold(k, usize::max)
    };
    debug_assert!((1..order.len()).all(|j| order[j].abs_diff(order[j - 1]) <= 1));
    crate::io::write_atomic(path, |out| {
        let mut sequence = Sequence::new(out, w, h, palette, options.loop_forever)?;
        let mut store = Store::new(order.len());
        let mut drawn: BTreeMap<usize, Vec<u8>> = BTreeMap::new();
        let (mut compressed, mut next) = (0, 0);
        let batch = batch_len();
        for first in (0..count).step_by(batch) {
            let end = (first + batch).min(count);
            let new: Vec<Vec<u8>> = (first..end).into_par_iter().map(&draw).collect();
            drawn.extend((first..end).zip(new));
            let ready = (compressed..count)
                .find(|&k| needs(k) >= end)
                .unwrap_or(count);
            let frames: Vec<Compressed> = (compressed..ready)
                .into_par_iter()
                .map(|k| Compressed::new(k, &drawn, &order, &showings[k], (w, h)))
                .collect::<io::Result<_>>()?;
            for (k, frame) in (compressed..ready).zip(frames) {
                store.put(k, frame)?;
            }
            compressed = ready;
            drawn.retain(|&k, _| k + 1 >= compressed);
            while next < order.len() {
                let Some(picture) = store.take(order[next], next)? else {
                    break;
                };
                sequence.push(picture, schedule[next].1)?;
                next += 1;
            }
        }
        debug_assert_eq!(next, order.len());
        sequence.finish()
    })
}

/// A frame compressed for every showing of it: the rectangle holding its
/// changes from each picture shown just before it, LZW-encoded, and which
/// showings change nothing.
struct Compressed {
    frame: ::gif::Frame<'static>,
    /// The showings (indices into the schedule) and whether each shows the
    /// same picture as the one before it.
    unchanged: Vec<(usize, bool)>,
}

impl Compressed {
    fn new(
        k: usize,
        drawn: &BTreeMap<usize, Vec<u8>>,
        order: &[usize],
        showings: &[usize],
        (w, h): (u16, u16),
    ) -> io::Result<Self> {
        let width = usize::from(w);
        let pixels = &drawn[&k];
        check_len(pixels, w, h)?;
        let mut union: Option<[usize; 4]> = None;
        let mut unchanged = Vec::with_capacity(showings.len());
        for &j in showings {
            let before: &[u8] = if j == 0 { &[] } else { &drawn[&order[j - 1]] };
            let rect = changed_rect(before, pixels, width);
            unchanged.push((j, rect.is_none()));
            union = match (union, rect) {
                (Some(a), Some(b)) => Some([
                    a[0].min(b[0]),
                    a[1].min(b[1]),
                    a[2].max(b[2]),
                    a[3].max(b[3]),
                ]),
                (a, b) => a.or(b),
            };
        }
        let mut frame = sub_frame(pixels, width, union.unwrap_or([0, 0, 1, 1]), 0);
        frame.make_lzw_pre_encoded();
        Ok(Compressed { frame, unchanged })
    }
}

/// Refuses a picture that does not have `w * h` pixels.
fn check_len(pixels: &[u8], w: u16, h: u16) -> io::Result<()> {
    if pixels.len() == usize::from(w) * usize::from(h) {
        Ok(())
    } else {
        Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("a picture of {} pixels in a {w} × {h} GIF", pixels.len()),
        ))
    }
}

/// A picture compressed for the GIF: the rectangle that changed from the
/// picture before it (the whole picture for the first), LZW-encoded; or,
/// when nothing changed, its top-left pixel (written only when the
/// previous frame's delay cannot grow any longer).
struct Encoded {
    unchanged: bool,
    frame: ::gif::Frame<'static>,
}

impl Encoded {
    fn new(prev: Option<&[u8]>, pixels: &[u8], w: u16, h: u16) -> io::Result<Self> {
        check_len(pixels, w, h)?;
        let width = usize::from(w);
        let rect = changed_rect(prev.unwrap_or_default(), pixels, width);
        let mut frame = sub_frame(pixels, width, rect.unwrap_or([0, 0, 1, 1]), 0);
        frame.make_lzw_pre_encoded();
        Ok(Encoded {
            unchanged: rect.is_none(),
            frame,
        })
    }
}

/// The frames of a GIF as they are written: delays rounded keeping the
/// total right, a picture equal to the one before lengthening its delay.
struct Sequence<W: io::Write> {
    encoder: ::gif::Encoder<W>,
    pending: Option<::gif::Frame<'static>>,
    elapsed: Duration,
    shown_cs: u64,
}

impl<W: io::Write> Sequence<W> {
    fn new(out: W, w: u16, h: u16, palette: &Palette, loop_forever: bool) -> io::Result<Self> {
        let mut encoder = ::gif::Encoder::new(out, w, h, &palette.to_bytes()).map_err(gif_error)?;
        if loop_forever {
            encoder
                .set_repeat(::gif::Repeat::Infinite)
                .map_err(gif_error)?;
        }
        Ok(Sequence {
            encoder,
            pending: None,
            elapsed: Duration::ZERO,
            shown_cs: 0,
        })
    }

    /// Shows `picture` for `duration` after the pictures before it.
    fn push(&mut self, picture: Encoded, duration: Duration) -> io::Result<()> {
        self.elapsed += duration;
        let end_cs = (self.elapsed.as_secs_f64() * 100.0).round() as u64;
        let delay = end_cs.saturating_sub(self.shown_cs).max(2);
        self.shown_cs += delay;
        if picture.unchanged {
            if let Some(f) = &mut self.pending {
                // The same picture again: show the last one longer,
                // starting a new frame if its delay would overflow.
                let total = u64::from(f.delay) + delay;
                if total <= u64::from(u16::MAX) {
                    f.delay = total as u16;
                    return Ok(());
                }
            }
        }
        let mut frame = picture.frame;
        frame.delay = delay.min(u64::from(u16::MAX)) as u16;
        if let Some(f) = self.pending.replace(frame) {
            self.encoder
                .write_lzw_pre_encoded_frame(&f)
                .map_err(gif_error)?;
        }
        Ok(())
    }

    fn finish(mut self) -> io::Result<()> {
        if let Some(f) = self.pending.take() {
            self.encoder
                .write_lzw_pre_encoded_frame(&f)
                .map_err(gif_error)?;
        }
        self.encoder.into_inner().map_err(gif_error)?;
        Ok(())
    }
}

/// Compressed frames waiting for their showings, in memory up to
/// [`Store::IN_MEMORY`] bytes, then in a temporary file.
struct Store {
    file: tempfile::SpooledTempFile,
    /// Each frame's header (without its data), where its data is, and how
    /// many showings it has left.
    frames: HashMap<usize, (::gif::Frame<'static>, u64, usize, usize)>,
    /// Whether each showing shows the same picture as the one before.
    unchanged: Vec<bool>,
    end: u64,
}

impl Store {
    const IN_MEMORY: usize = 16 << 20;

    fn new(showings: usize) -> Self {
        Store {
            file: tempfile::spooled_tempfile(Self::IN_MEMORY),
            frames: HashMap::new(),
            unchanged: vec![false; showings],
            end: 0,
        }
    }

    fn put(&mut self, k: usize, compressed: Compressed) -> io::Result<()> {
        let mut frame = compressed.frame;
        let data = std::mem::take(frame.buffer.to_mut());
        self.file.seek(SeekFrom::Start(self.end))?;
        self.file.write_all(&data)?;
        for &(j, same) in &compressed.unchanged {
            self.unchanged[j] = same;
        }
        let showings = compressed.unchanged.len();
        self.frames
            .insert(k, (frame, self.end, data.len(), showings));
        self.end += data.len() as u64;
        Ok(())
    }

    /// Frame `k` for its showing `j`, if it has been compressed.
    fn take(&mut self, k: usize, j: usize) -> io::Result<Option<Encoded>> {
        let Some((frame, at, len, left)) = self.frames.get_mut(&k) else {
            return Ok(None);
        };
        let mut data = vec![0; *len];
        self.file.seek(SeekFrom::Start(*at))?;
        self.file.read_exact(&mut data)?;
        let mut frame = frame.clone();
        frame.buffer = Cow::Owned(data);
        *left -= 1;
        if *left == 0 {
            self.frames.remove(&k);
        }
        Ok(Some(Encoded {
            unchanged: self.unchanged[j],
            frame,
        }))
    }
}

pub fn gif_error(e: ::gif::EncodingError) -> io::Error {
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
/// [`GifOptions::schedule`]. Frames are drawn as they are written, a few
/// at a time on every thread, each once however often it is shown.
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
/// once to fit the view and once to draw it (in parallel); only the frames
/// being drawn are held.
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
    let size = match options.longest_side {
        Some(side) => View2d::fitting_longest(
            corners.iter().map(|c| c.as_slice()),
            side,
            options.margin_px,
        ),
        None => fit(options.width, options.height, options.margin_px),
    };
    let (width, height) = (size.width, size.height);
    let view = fit(
        width.saturating_mul(s),
        Some(height.saturating_mul(s)),
        options.margin_px.saturating_mul(s),
    );
    let edges = EdgeSets::new(triangles, vertices);
    let smallest = summaries.iter().map(|s| s.2).fold(f64::INFINITY, f64::min);
    let mode = style.resolve_edges(smallest, view.scale / f64::from(s));
    let palette = Palette::standard().with_style(style);
    write_drawn(path, (width, height), &palette, options, count, |i| {
        let mut canvas = Canvas::new(view.width, view.height, palette.clone());
        let mut scratch = Default::default();
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
        if s == 1 {
            canvas.pixels
        } else {
            super::resample::downsample(&canvas, s, width, height).pixels
        }
    })
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
    write_drawn(
        path,
        layout.size(),
        &layout.palette,
        options,
        frames.len(),
        |i| layout.render(&frames[i]).pixels,
    )
}

/// Writes an animated GIF of a mesh in space moving through `frames`, one
/// flat-shaded view in `style` through a camera looking along
/// `grid.direction` (one cell of `grid`'s size), fitted once over every
/// frame so that it stays still; the frames are shown per
/// [`GifOptions::schedule`]. Frames are produced on demand: each is asked
/// for once to fit the camera and once to draw it (in parallel); only the
/// frames being drawn are held.
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
    write_drawn(path, layout.size(), &layout.palette, options, count, |i| {
        map_frame(frames, i, |f| {
            let row = GridRow {
                triangles,
                poses: vec![f],
                style,
            };
            layout.render(&[row]).pixels
        })
    })
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
