//! numpy arrays in and out: vertices `(n, 2)` or `(n, 3)` float64 or
//! float32, faces `(m, 3)` int32, int64 or uint32, stacks `(k, n, d)`,
//! sequences of numbers; results are new float64 arrays, or written into
//! an `out=` array. Every refusal names the argument and the element.
//!
//! Every copy an input implies, and every result, is checked against the
//! memory available ([`need`]) before it is made: a broadcast array of
//! 2**31 rows owns no memory, but its copy would (refused with a
//! `MemoryError` naming the argument, not an abort).

use meshmorph::Mesh;
use numpy::ndarray::{ArrayView2, ArrayView3};
use numpy::{
    PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray2, PyReadonlyArray3,
    PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyString};

use crate::work::{self, Stop};
use crate::{args, bad};

/// Bytes per triangle of a solver's setup: per-triangle data, the sparse
/// system and its Cholesky factor (the command line's measured figure,
/// with its margin).
pub const SETUP_BYTES_PER_TRIANGLE: u128 = 700;

/// Bytes per triangle of each key of a sequence or shape of a blend: its
/// copy of the faces and their adjacency, and its segment's rotations and
/// stretches (480 of them, as the command line counts).
pub const KEY_BYTES_PER_TRIANGLE: u128 = 600;

/// Bytes each member of a stack takes beside its positions (its vector,
/// its name in messages).
const MEMBER_BYTES: u128 = 64;

/// Requests below this size are not checked against the estimate (reading
/// it takes longer than a small call): the allocator still refuses them.
const CHECKED_FROM: u128 = 16 << 20;

/// Refuses, naming `arg`, when `bytes` (what `what` would take) exceed the
/// memory available ([`meshmorph::limits::available_memory`]), or what one
/// allocation can hold.
pub fn need(arg: &str, what: &str, bytes: u128) -> PyResult<()> {
    if bytes < CHECKED_FROM {
        return Ok(());
    }
    let free = meshmorph::limits::available_memory();
    let limit = free.map_or(isize::MAX as u128, u128::from);
    if bytes <= limit {
        return Ok(());
    }
    Err(PyMemoryError::new_err(format!(
        "{arg}: {what} would take about {} of memory, but {}: use a smaller input or free memory",
        human(bytes),
        match free {
            Some(free) => format!("only {} is available", human(u128::from(free))),
            None => "that is more than one allocation can hold".to_string(),
        }
    )))
}

/// Refuses, naming `arg`, when the setup of a solver for `triangles`
/// triangles would not fit.
pub fn setup(arg: &str, triangles: usize) -> PyResult<()> {
    need(
        arg,
        &format!("the setup for its {triangles} triangles"),
        (triangles as u128).saturating_mul(SETUP_BYTES_PER_TRIANGLE),
    )
}

/// The bytes of `count` values of `T`.
pub fn bytes_of<T>(count: &[usize]) -> u128 {
    count
        .iter()
        .fold(std::mem::size_of::<T>() as u128, |b, &n| {
            b.saturating_mul(n as u128)
        })
}

/// An empty vector with room for `n` values of `T` (`items` naming them),
/// checked by [`need`] and reserved without aborting.
pub fn room<T>(arg: &str, items: &str, n: usize) -> PyResult<Vec<T>> {
    let what = format!("copying its {n} {items}");
    need(arg, &what, bytes_of::<T>(&[n]))?;
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        PyMemoryError::new_err(format!(
            "{arg}: {what} would take {} of memory, which could not be allocated",
            human(bytes_of::<T>(&[n]))
        ))
    })?;
    Ok(v)
}

/// "2.1 GB", "256 MB" (powers of 10).
fn human(b: u128) -> String {
    let x = b as f64;
    if x >= 1e12 {
        format!("{:.1} TB", x / 1e12)
    } else if x >= 1e9 {
        format!("{:.1} GB", x / 1e9)
    } else {
        format!("{:.0} MB", (x / 1e6).max(1.0))
    }
}

/// Vertex positions of either dimension.
pub enum Points {
    Plane(Vec<[f64; 2]>),
    Space(Vec<[f64; 3]>),
}

impl Points {
    pub fn dimension(&self) -> usize {
        match self {
            Points::Plane(_) => 2,
            Points::Space(_) => 3,
        }
    }

    pub fn len(&self) -> usize {
        match self {
            Points::Plane(p) => p.len(),
            Points::Space(p) => p.len(),
        }
    }

    /// The positions as rows of `D` coordinates; refused, naming `arg`, when
    /// they have the other dimension.
    pub fn into_dimension<const D: usize>(self, arg: &str) -> PyResult<Vec<[f64; D]>> {
        // Called with `A == D` only: the rows as they are, retyped.
        fn retyped<const A: usize, const D: usize>(v: Vec<[f64; A]>) -> Vec<[f64; D]> {
            v.into_iter()
                .map(|x| std::array::from_fn(|c| x[c]))
                .collect()
        }
        match (self, D) {
            (Points::Plane(p), 2) => Ok(retyped(p)),
            (Points::Space(p), 3) => Ok(retyped(p)),
            (p, _) => Err(bad(
                arg,
                format!("expected {D} coordinates a vertex, got {}", p.dimension()),
            )),
        }
    }
}

/// What `a` is, for messages: "a (4, 2) float64 array" or its type.
pub fn describe(a: &Bound<'_, PyAny>) -> String {
    let shape = a.getattr("shape").ok().map(|s| s.to_string());
    let dtype = a.getattr("dtype").ok().map(|d| d.to_string());
    match (shape, dtype) {
        (Some(s), Some(d)) => format!("a {s} {d} array"),
        _ => format!(
            "a {}",
            a.get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ),
    }
}

fn rows<T: Copy + Into<f64>, const D: usize>(
    arg: &str,
    view: ArrayView2<'_, T>,
) -> PyResult<Vec<[f64; D]>> {
    let mut out = room(arg, "rows", view.nrows())?;
    for (i, row) in view.outer_iter().enumerate() {
        let p: [f64; D] = std::array::from_fn(|c| row[c].into());
        if p.iter().any(|x| !x.is_finite()) {
            return Err(bad(
                arg,
                format!("vertex {i} has a coordinate that is not finite ({p:?})"),
            ));
        }
        out.push(p);
    }
    Ok(out)
}

/// Vertex positions `(n, 2)` or `(n, 3)`, float64 or float32.
pub fn points(arg: &str, a: &Bound<'_, PyAny>) -> PyResult<Points> {
    let wrong = || {
        bad(
            arg,
            format!(
                "expected a (n, 2) or (n, 3) float64 or float32 numpy array, got {}",
                describe(a)
            ),
        )
    };
    macro_rules! read {
        ($t:ty) => {
            if let Ok(array) = a.cast::<PyArray2<$t>>() {
                let array: PyReadonlyArray2<'_, $t> = array.readonly();
                let view = array.as_array();
                return match view.ncols() {
                    2 => Ok(Points::Plane(rows(arg, view)?)),
                    3 => Ok(Points::Space(rows(arg, view)?)),
                    _ => Err(wrong()),
                };
            }
        };
    }
    read!(f64);
    read!(f32);
    Err(wrong())
}

/// Positions of dimension `D`.
pub fn points_of<const D: usize>(arg: &str, a: &Bound<'_, PyAny>) -> PyResult<Vec<[f64; D]>> {
    points(arg, a)?.into_dimension(arg)
}

/// Rows of `W` indices, int32, int64 or uint32.
pub fn index_rows<const W: usize>(arg: &str, a: &Bound<'_, PyAny>) -> PyResult<Vec<[i64; W]>> {
    let wrong = || {
        bad(
            arg,
            format!(
                "expected a (m, {W}) int32, int64 or uint32 numpy array, got {}",
                describe(a)
            ),
        )
    };
    macro_rules! read {
        ($t:ty) => {
            if let Ok(array) = a.cast::<PyArray2<$t>>() {
                let array = array.readonly();
                let view = array.as_array();
                if view.ncols() != W {
                    return Err(wrong());
                }
                let mut out = room(arg, "rows", view.nrows())?;
                out.extend(
                    view.outer_iter()
                        .map(|row| std::array::from_fn(|c| i64::from(row[c]))),
                );
                return Ok(out);
            }
        };
    }
    read!(i64);
    read!(i32);
    read!(u32);
    Err(wrong())
}

/// A 3-D float64 or float32 array read by `read(shape, at)`, where
/// `at(i, j, k)` is an entry as a float64; `None` when `a` is neither.
pub fn read_3d<T>(
    a: &Bound<'_, PyAny>,
    read: impl FnOnce(&[usize], &dyn Fn(usize, usize, usize) -> f64) -> PyResult<T>,
) -> Option<PyResult<T>> {
    if let Ok(array) = a.cast::<PyArray3<f64>>() {
        let array = array.readonly();
        let view = array.as_array();
        return Some(read(array.shape(), &|i, j, k| view[[i, j, k]]));
    }
    if let Ok(array) = a.cast::<PyArray3<f32>>() {
        let array = array.readonly();
        let view = array.as_array();
        return Some(read(array.shape(), &|i, j, k| f64::from(view[[i, j, k]])));
    }
    None
}

/// Faces `(m, 3)`, int32, int64 or uint32, 0-based.
pub fn faces(arg: &str, a: &Bound<'_, PyAny>) -> PyResult<Vec<[u32; 3]>> {
    if let Some(shape) = shape_of(a, 2) {
        // Read as indices, then as faces: both copies at once.
        let both = bytes_of::<[i64; 3]>(&[shape[0]]) + bytes_of::<[u32; 3]>(&[shape[0]]);
        need(arg, &format!("copying its {} rows", shape[0]), both)?;
    }
    let rows = index_rows::<3>(arg, a)?;
    let mut out = room(arg, "faces", rows.len())?;
    for (f, row) in rows.into_iter().enumerate() {
        let mut face = [0u32; 3];
        for c in 0..3 {
            face[c] = u32::try_from(row[c]).map_err(|_| {
                bad(
                    arg,
                    format!(
                        "face {f} has the vertex index {}, which is not a vertex",
                        row[c]
                    ),
                )
            })?;
        }
        out.push(face);
    }
    Ok(out)
}

/// A mesh of `positions` and `faces`, checked, the error naming both; made
/// in the pool ([`work::run`]), the GIL released.
pub fn mesh<const D: usize>(
    py: Python<'_>,
    args: (&str, &str),
    positions: Vec<[f64; D]>,
    faces: Vec<[u32; 3]>,
) -> PyResult<Mesh<D>> {
    let n = positions.len();
    if let Some((f, v)) = faces
        .iter()
        .enumerate()
        .find_map(|(f, t)| t.iter().find(|&&v| v as usize >= n).map(|&v| (f, v)))
    {
        return Err(bad(
            args.1,
            format!(
                "face {f} refers to vertex {v}, but {} has {n} vertices",
                args.0
            ),
        ));
    }
    work::run(py, || Mesh::new(positions, faces))?
        .map_err(|e| bad(&format!("{}, {}", args.0, args.1), e))
}

/// The shape of `a` when it is a numpy array of `ndim` dimensions.
fn shape_of(a: &Bound<'_, PyAny>, ndim: usize) -> Option<Vec<usize>> {
    let array = a.cast::<PyUntypedArray>().ok()?;
    (array.ndim() == ndim).then(|| array.shape().to_vec())
}

/// A stack of positions `(k, n, D)`, float64 or float32, each of its
/// members named `arg[j]` in messages; its copy, and `each` bytes more a
/// member (what the work will need of it), checked before it is made.
pub fn stack<const D: usize>(
    arg: &str,
    a: &Bound<'_, PyAny>,
    each: u128,
) -> PyResult<Vec<Vec<[f64; D]>>> {
    let wrong = || {
        bad(
            arg,
            format!(
                "expected a (k, n, {D}) float64 or float32 numpy array, got {}",
                describe(a)
            ),
        )
    };
    fn read<T: Copy + Into<f64>, const D: usize>(
        arg: &str,
        view: ArrayView3<'_, T>,
        each: u128,
    ) -> PyResult<Vec<Vec<[f64; D]>>> {
        let (k, n) = (view.shape()[0], view.shape()[1]);
        let member = bytes_of::<[f64; D]>(&[n])
            .saturating_add(MEMBER_BYTES)
            .saturating_add(each);
        need(
            arg,
            &format!("copying its {k} members of {n} vertices, and the work on them,"),
            member.saturating_mul(k as u128),
        )?;
        let mut out = room(arg, "members", k)?;
        for (j, m) in view.outer_iter().enumerate() {
            out.push(rows(&format!("{arg}[{j}]"), m)?);
        }
        Ok(out)
    }
    if let Ok(array) = a.cast::<PyArray3<f64>>() {
        let array: PyReadonlyArray3<'_, f64> = array.readonly();
        if array.shape()[2] == D {
            return read(arg, array.as_array(), each);
        }
    } else if let Ok(array) = a.cast::<PyArray3<f32>>() {
        let array = array.readonly();
        if array.shape()[2] == D {
            return read(arg, array.as_array(), each);
        }
    }
    Err(wrong())
}

/// A stack `(k, n, 2)` or `(k, n, 3)` of either dimension, as [`stack`].
pub fn stack_points(arg: &str, a: &Bound<'_, PyAny>, each: u128) -> PyResult<Vec<Points>> {
    match shape_of(a, 3).map(|s| s[2]) {
        Some(2) => Ok(stack::<2>(arg, a, each)?
            .into_iter()
            .map(Points::Plane)
            .collect()),
        Some(3) => Ok(stack::<3>(arg, a, each)?
            .into_iter()
            .map(Points::Space)
            .collect()),
        _ => Err(bad(
            arg,
            format!(
                "expected a (k, n, 2) or (k, n, 3) float64 or float32 numpy array, got {}",
                describe(a)
            ),
        )),
    }
}

/// The items of a sequence (a list, a tuple, a 1-D numpy array: anything
/// with a length that iterates, but a str), each made by `item` (given
/// its name `arg[k]`); `expected` says what the sequence should be. Its
/// copy, with `each` bytes more an item (what the work will need of it),
/// is checked before it is made.
pub fn items<T>(
    arg: &str,
    a: &Bound<'_, PyAny>,
    (expected, each): (&str, u128),
    item: impl Fn(&str, &Bound<'_, PyAny>) -> PyResult<T>,
) -> PyResult<Vec<T>> {
    let wrong = || {
        bad(
            arg,
            format!("expected {expected}, got {}", args::describe(a)),
        )
    };
    if a.is_instance_of::<PyString>() || a.is_instance_of::<PyBytes>() {
        return Err(wrong());
    }
    if shape_of(a, 1).is_none() && a.cast::<PyUntypedArray>().is_ok() {
        return Err(wrong());
    }
    let n = a.len().map_err(|_| wrong())?;
    need_each::<T>(arg, n, each)?;
    let mut out = room(arg, "items", n)?;
    for (k, x) in a.try_iter().map_err(|_| wrong())?.enumerate() {
        // The memory was checked for `len()` items: no more are taken.
        if k == n {
            return Err(bad(
                arg,
                format!("its len() says {n} items, but iterating it gives more"),
            ));
        }
        out.push(item(&format!("{arg}[{k}]"), &x?)?);
    }
    Ok(out)
}

/// `n` items of `T`, and `each` bytes more an item, checked by [`need`].
fn need_each<T>(arg: &str, n: usize, each: u128) -> PyResult<()> {
    let item = bytes_of::<T>(&[1]).saturating_add(each);
    need(
        arg,
        &format!("copying its {n} items, and the work on them,"),
        item.saturating_mul(n as u128),
    )
}

/// Finite numbers: a 1-D numpy array or a sequence of numbers, checked as
/// [`items`] are, with `each` bytes more a number.
pub fn numbers(arg: &str, a: &Bound<'_, PyAny>, each: u128) -> PyResult<Vec<f64>> {
    if let Ok(array) = a.cast::<PyArray1<f64>>() {
        let array = array.readonly();
        let view = array.as_array();
        need_each::<f64>(arg, view.len(), each)?;
        let mut out = room(arg, "items", view.len())?;
        for (k, &x) in view.iter().enumerate() {
            out.push(finite(&format!("{arg}[{k}]"), x)?);
        }
        return Ok(out);
    }
    items(
        arg,
        a,
        ("a sequence of numbers (a list or a 1-D numpy array)", each),
        args::number,
    )
}

/// A new `(n, D)` float64 array.
pub fn array<'py, const D: usize>(
    py: Python<'py>,
    rows: &[[f64; D]],
) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([rows.len(), D])?
        .into_any())
}

/// A `(k, n, D)` float64 array filled in place, the GIL released and no
/// frame copied: a new one (its size checked by [`need`], naming `arg`,
/// the argument that asks for the `k` frames), or `out` (a writeable,
/// C-contiguous array of that shape, returned). Each thread of the pool
/// takes an equal share of the frames, with its own `init()` workspace,
/// and `fill(ws, frames, outs)` writes the frames of the range `frames`
/// into `outs`, a few at a time: between them the work stops when Python
/// has a signal to handle ([`work::run_stoppable`]; `out` is then left
/// partly written).
pub fn frames_in_place<'py, const D: usize, W>(
    py: Python<'py>,
    (arg, k, n): (&str, usize, usize),
    out: Option<Bound<'py, PyAny>>,
    init: impl Fn() -> W + Send + Sync,
    fill: impl Fn(&mut W, std::ops::Range<usize>, &mut [&mut [[f64; D]]]) + Send + Sync,
) -> PyResult<Bound<'py, PyAny>> {
    use rayon::prelude::*;
    let array = match out {
        None => {
            need(
                arg,
                &format!("its {k} frames of {n} vertices"),
                bytes_of::<[f64; D]>(&[k, n]),
            )?;
            // numpy's own zeros: a failed allocation is a MemoryError.
            let zeros = py
                .import("numpy")?
                .call_method1("zeros", ((k, n, D), "float64"))?;
            zeros.cast_into::<PyArray3<f64>>()?
        }
        Some(out) => {
            let Ok(array) = out.cast::<PyArray3<f64>>() else {
                return Err(bad(
                    "out",
                    format!(
                        "expected a ({k}, {n}, {D}) float64 numpy array, got {}",
                        describe(&out)
                    ),
                ));
            };
            if array.shape() != [k, n, D] {
                return Err(bad(
                    "out",
                    format!(
                        "expected the shape ({k}, {n}, {D}), got {:?}",
                        array.shape()
                    ),
                ));
            }
            if !array.is_c_contiguous() {
                return Err(bad("out", "the array is not C-contiguous"));
            }
            array.clone()
        }
    };
    if k > 0 && n > 0 {
        let mut write = array
            .try_readwrite()
            .map_err(|_| bad("out", "the array is not writeable (or is borrowed)"))?;
        let flat = write
            .as_slice_mut()
            .map_err(|_| bad("out", "the array is not C-contiguous"))?;
        work::run_stoppable(py, |stop: &Stop| {
            let share = k.div_ceil(rayon::current_num_threads()).max(1);
            let batch = meshmorph::limits::frames_per_solve(k);
            flat.par_chunks_mut(share * n * D)
                .enumerate()
                .for_each_init(init, |ws, (c, block)| {
                    let mut outs: Vec<&mut [[f64; D]]> = block
                        .chunks_mut(n * D)
                        .map(|frame| frame.as_chunks_mut::<D>().0)
                        .collect();
                    for (b, outs) in outs.chunks_mut(batch).enumerate() {
                        if stop.is_set() {
                            return;
                        }
                        let first = c * share + b * batch;
                        fill(ws, first..first + outs.len(), outs);
                    }
                });
        })?;
    }
    Ok(array.into_any())
}

/// `rows` as a new array, or written into `out` (a writeable `(n, D)`
/// float64 array), which is returned.
pub fn give<'py, const D: usize>(
    py: Python<'py>,
    rows: &[[f64; D]],
    out: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let Some(out) = out else {
        return array(py, rows);
    };
    let Ok(target) = out.cast::<PyArray2<f64>>() else {
        return Err(bad(
            "out",
            format!(
                "expected a ({}, {D}) float64 numpy array, got {}",
                rows.len(),
                describe(&out)
            ),
        ));
    };
    if target.shape() != [rows.len(), D] {
        return Err(bad(
            "out",
            format!(
                "expected the shape ({}, {D}), got {:?}",
                rows.len(),
                target.shape()
            ),
        ));
    }
    {
        let mut write = target
            .try_readwrite()
            .map_err(|_| bad("out", "the array is not writeable (or is borrowed)"))?;
        let mut view = write.as_array_mut();
        for (mut row, p) in view.outer_iter_mut().zip(rows) {
            for c in 0..D {
                row[c] = p[c];
            }
        }
    }
    Ok(out)
}

/// A finite number named `arg`.
pub fn finite(arg: &str, x: f64) -> PyResult<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(bad(arg, format!("{x} is not a finite number")))
    }
}
