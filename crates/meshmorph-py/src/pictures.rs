//! `morph_pictures`: one picture into another (two sprites with
//! transparency, or two photos), the frames as one uint8 array. The
//! library's `PictureFrames` does the work; here the arrays are read and
//! the frames written.

use meshmorph::io::picture::{picture_morph_memory, Picture, PictureShape};
use meshmorph::render::{frame_times, PictureFrames, PictureMorphOptions, MAX_FRAME_SIDE};
use meshmorph::InterpolatorOptions;
use numpy::{PyArray3, PyArray4, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyModule, PyTuple};

use crate::arrays::{self, describe};
use crate::work::Stop;
use crate::{args, bad, error, outline, work};

/// The most frames one call makes.
const MAX_FRAMES: i64 = 100_000;

/// A picture `(h, w, 4)` RGBA or `(h, w, 3)` RGB (opaque), uint8.
fn picture(arg: &str, a: &Bound<'_, PyAny>) -> PyResult<Picture> {
    let wrong = || {
        bad(
            arg,
            format!(
                "expected a (height, width, 4) RGBA or (height, width, 3) RGB uint8 numpy array, got {}",
                describe(a)
            ),
        )
    };
    let array = a.cast::<PyArray3<u8>>().map_err(|_| wrong())?;
    let [h, w, channels] = <[usize; 3]>::try_from(array.shape()).map_err(|_| wrong())?;
    if channels != 3 && channels != 4 {
        return Err(wrong());
    }
    if h == 0 || w == 0 {
        return Err(bad(
            arg,
            format!("an empty {w} × {h} picture: a picture needs at least one pixel"),
        ));
    }
    let side = MAX_FRAME_SIDE as usize;
    if w > side || h > side {
        return Err(bad(
            arg,
            format!("a {w} × {h} picture: each side may be at most {side} pixels"),
        ));
    }
    let array = array.readonly();
    let view = array.as_array();
    let mut rgba = arrays::room(arg, "pixels", 4 * w * h)?;
    for row in view.outer_iter() {
        for pixel in row.outer_iter() {
            rgba.extend((0..4).map(|c| if c < channels { pixel[c] } else { 255 }));
        }
    }
    Picture::new(w as u32, h as u32, rgba).map_err(|e| bad(arg, e))
}

/// Anchors: a `(k, 2, 2)` array (anchor, picture, x/y) or two `(k, 2)`
/// arrays, the points on `a` and on `b`.
fn anchors(a: &Bound<'_, PyAny>) -> PyResult<Vec<Vec<[f64; 2]>>> {
    let pair = a
        .cast::<PyTuple>()
        .map(|t| t.iter().collect::<Vec<_>>())
        .or_else(|_| a.cast::<PyList>().map(|l| l.iter().collect::<Vec<_>>()));
    let Ok(pair) = pair else {
        return outline::anchors(a, 2);
    };
    if pair.len() != 2 {
        return Err(bad(
            "anchors",
            format!(
                "expected a (k, 2, 2) array or two (k, 2) arrays (the points on a, the points on b), got a sequence of {}",
                pair.len()
            ),
        ));
    }
    let on_a = arrays::points_of::<2>("anchors[0]", &pair[0])?;
    let on_b = arrays::points_of::<2>("anchors[1]", &pair[1])?;
    if on_a.len() != on_b.len() {
        return Err(bad(
            "anchors",
            format!(
                "{} points on a but {} on b: each anchor is one point on each picture",
                on_a.len(),
                on_b.len()
            ),
        ));
    }
    Ok(on_a
        .into_iter()
        .zip(on_b)
        .map(|(p, q)| vec![p, q])
        .collect())
}

/// The number of frames: 1 to [`MAX_FRAMES`].
fn frame_count(v: &Bound<'_, PyAny>) -> PyResult<usize> {
    let n = v
        .extract::<i64>()
        .ok()
        .filter(|_| !v.is_instance_of::<pyo3::types::PyBool>());
    match n {
        Some(n) if (1..=MAX_FRAMES).contains(&n) => Ok(n as usize),
        _ => Err(bad(
            "frames",
            format!(
                "expected a whole number of frames from 1 to {MAX_FRAMES}, got {}",
                args::describe(v)
            ),
        )),
    }
}

/// `(width, height)`, each 1 to 16384, or None.
fn frame_size(v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<(u32, u32)>> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    let side = 1..=i64::from(MAX_FRAME_SIDE);
    match v.extract::<(i64, i64)>() {
        Ok((w, h)) if side.contains(&w) && side.contains(&h) => Ok(Some((w as u32, h as u32))),
        _ => Err(bad(
            "size",
            format!(
                "expected (width, height) in pixels, each a whole number from 1 to {MAX_FRAME_SIDE}, got {}",
                args::describe(v)
            ),
        )),
    }
}

/// `(start, end)`: two fractions of the morph, or None.
fn dissolve(v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<[f64; 2]>> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    match v.extract::<(f64, f64)>() {
        Ok((s, e)) if [s, e].iter().all(|x| (0.0..=1.0).contains(x)) && s <= e => {
            Ok(Some([s, e]))
        }
        Ok((s, e)) if s > e => Err(bad(
            "dissolve",
            format!("({s}, {e}) ends before it starts: give the start first (the same fraction twice cuts from one picture to the other there)"),
        )),
        _ => Err(bad(
            "dissolve",
            format!(
                "expected (start, end), two fractions of the morph from 0 to 1 such as (0.3, 0.7), got {}",
                args::describe(v)
            ),
        )),
    }
}

/// How it went: the figures the command line's `--json` prints.
struct Figures {
    shape: &'static str,
    frame_size: (u32, u32),
    outline_points: (usize, usize),
    left_out: (usize, usize),
    faint_left_out: (usize, usize),
    anchors: usize,
    vertices: usize,
    triangles: usize,
    min_angle_degrees: Vec<f64>,
    text: String,
}

impl Figures {
    fn of(frames: &PictureFrames<'_>) -> Self {
        let set = &frames.meshes.set;
        let [da, db] = &frames.drawings;
        Self {
            shape: match frames.shape() {
                PictureShape::Sprite => "sprite",
                PictureShape::Photo => "photo",
            },
            frame_size: frames.size(),
            outline_points: (da.drawing.num_points(), db.drawing.num_points()),
            left_out: (da.left_out.len(), db.left_out.len()),
            faint_left_out: (da.faint_left_out, db.faint_left_out),
            anchors: set.anchors.len(),
            vertices: set.meshes[0].num_vertices(),
            triangles: set.report.triangles,
            min_angle_degrees: set.report.min_angle_degrees.clone(),
            text: set.report.to_string(),
        }
    }

    fn dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("shape", self.shape)?;
        d.set_item("frame_size", self.frame_size)?;
        d.set_item("outline_points", self.outline_points)?;
        d.set_item("left_out", self.left_out)?;
        d.set_item("faint_left_out", self.faint_left_out)?;
        d.set_item("anchors", self.anchors)?;
        d.set_item("vertices", self.vertices)?;
        d.set_item("triangles", self.triangles)?;
        d.set_item("min_angle_degrees", self.min_angle_degrees.clone())?;
        d.set_item("text", &self.text)?;
        Ok(d)
    }
}

/// One picture morphed into another: `frames` frames as one
/// `(frames, height, width, 4)` uint8 RGBA array (straight alpha), the
/// first `a` and the last `b` (stretched onto the frame size).
///
/// `a`, `b`: `(height, width, 4)` RGBA or `(height, width, 3)` RGB uint8
/// arrays (rows from the top). Pictures with transparency (sprites) are
/// traced where alpha crosses one half and their outlines morphed; opaque
/// ones (RGB, photos) morph their whole rectangles; give two of a kind, or
/// `frame_only=True` to morph both as rectangles. `anchors`: a `(k, 2, 2)`
/// array (anchor, picture, x/y) or two `(k, 2)` arrays, points kept matched
/// (on the outlines, or inside where each becomes a vertex), in each
/// picture's own pixels, x to the right and y down from its top-left
/// corner (pixel `(i, j)` has its centre at `(i + 0.5, j + 0.5)`), as in
/// the command line's anchor files. `dissolve`: `(start, end)`, the
/// moments (0 to 1) between which the colours go from `a` to `b`
/// (default: over the whole morph). `size`: `(width, height)` of the
/// frames (default: `a`'s). `trace_tolerance`: how far a traced outline
/// may stray, pixels (0 to 16). `consistency`, `turns`, `stretch`: as for
/// `Interpolator`. With `return_report=True`, returns `(frames, report)`,
/// the report a dict: `shape` ("sprite" or "photo"), `frame_size`,
/// `outline_points`, `left_out` (regions left out of each picture: only
/// the largest is morphed), `faint_left_out` (each picture's pixels under
/// half opaque beyond an anti-aliased edge, a glow or a soft shadow, which
/// tracing leaves out; `frame_only=True` keeps them), `anchors`,
/// `vertices`, `triangles`,
/// `min_angle_degrees` and `text`. The GIL is released during the work,
/// and Ctrl-C stops it between frames.
#[pyfunction]
#[pyo3(signature = (a, b, frames, anchors=None, *, frame_only=None, dissolve=None, size=None, trace_tolerance=None, consistency=None, turns=None, stretch=None, return_report=None))]
#[allow(clippy::too_many_arguments)]
fn morph_pictures<'py>(
    py: Python<'py>,
    a: &Bound<'py, PyAny>,
    b: &Bound<'py, PyAny>,
    frames: &Bound<'py, PyAny>,
    anchors: Option<&Bound<'py, PyAny>>,
    frame_only: Option<&Bound<'py, PyAny>>,
    dissolve: Option<&Bound<'py, PyAny>>,
    size: Option<&Bound<'py, PyAny>>,
    trace_tolerance: Option<&Bound<'py, PyAny>>,
    consistency: Option<&Bound<'py, PyAny>>,
    turns: Option<&Bound<'py, PyAny>>,
    stretch: Option<&Bound<'py, PyAny>>,
    return_report: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let count = frame_count(frames)?;
    let pictures = [picture("a", a)?, picture("b", b)?];
    let anchors = match anchors.filter(|a| !a.is_none()) {
        Some(a) => self::anchors(a)?,
        None => Vec::new(),
    };
    let tolerance = args::optional_number("trace_tolerance", trace_tolerance)?.unwrap_or(0.5);
    if !(tolerance > 0.0 && tolerance <= meshmorph::render::MAX_TRACE_TOLERANCE) {
        return Err(bad(
            "trace_tolerance",
            format!(
                "{tolerance} pixels: expected a tolerance from 0 (excluded) to {}, such as 0.5",
                meshmorph::render::MAX_TRACE_TOLERANCE
            ),
        ));
    }
    let interpolation: InterpolatorOptions =
        crate::interpolation::options_or(consistency, turns, stretch, "area")?
            .with_untie_outlines(true)
            .with_mend_folds(true);
    let size = frame_size(size)?.unwrap_or((pictures[0].width, pictures[0].height));
    let options = PictureMorphOptions::default()
        .with_frame_only(args::flag("frame_only", frame_only, false)?)
        .with_trace_tolerance(tolerance)
        .with_frame_size(Some(size))
        .with_dissolve(self::dissolve(dissolve)?)
        .with_interpolation(interpolation);
    let with_report = args::flag("return_report", return_report, false)?;
    let frame_bytes = 4 * size.0 as usize * size.1 as usize;
    let pixels = pictures
        .iter()
        .map(|p| u64::from(p.width) * u64::from(p.height))
        .max()
        .unwrap_or(0);
    arrays::need(
        "a",
        "the setup of the morph of its pictures",
        u128::from(picture_morph_memory(
            pixels,
            u64::from(size.0) * u64::from(size.1),
            2,
        )),
    )?;
    arrays::need(
        "frames",
        &format!("its {count} frames of {} × {} pixels", size.0, size.1),
        arrays::bytes_of::<u8>(&[count, frame_bytes]),
    )?;
    // numpy's own zeros: a failed allocation is a MemoryError.
    let out = py
        .import("numpy")?
        .call_method1("zeros", ((count, size.1, size.0, 4), "uint8"))?
        .cast_into::<PyArray4<u8>>()?;
    let mut write = out.try_readwrite()?;
    let flat = write
        .as_slice_mut()
        .map_err(|_| bad("frames", "the new array is not C-contiguous"))?;
    let names = [String::from("`a`"), String::from("`b`")];
    let made = work::run_stoppable(py, |stop: &Stop| {
        let [pa, pb] = &pictures;
        let morph = PictureFrames::new([pa, pb], &anchors, &options, &names).map_err(error)?;
        let times = frame_times(count);
        for (t, frame) in times.iter().zip(flat.chunks_mut(frame_bytes)) {
            if stop.is_set() {
                break;
            }
            morph.draw_into(*t, frame);
        }
        PyResult::Ok(Figures::of(&morph))
    })??;
    drop(write);
    if with_report {
        let figures = made.dict(py)?.into_any();
        Ok(PyTuple::new(py, [out.into_any(), figures])?.into_any())
    } else {
        Ok(out.into_any())
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(morph_pictures, m)?)?;
    Ok(())
}
