//! numpy arrays in and out: vertices `(n, 2)` or `(n, 3)` float64 or
//! float32, faces `(m, 3)` int32, int64 or uint32, stacks `(k, n, d)`;
//! results are new float64 arrays, or written into an `out=` array. Every
//! refusal names the argument and the element.

use meshmorph::Mesh;
use numpy::ndarray::{ArrayView2, ArrayView3};
use numpy::{
    PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray2, PyReadonlyArray3,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::bad;

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
fn describe(a: &Bound<'_, PyAny>) -> String {
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
    let mut out = Vec::with_capacity(view.nrows());
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
                return Ok(view
                    .outer_iter()
                    .map(|row| std::array::from_fn(|c| i64::from(row[c])))
                    .collect());
            }
        };
    }
    read!(i64);
    read!(i32);
    read!(u32);
    Err(wrong())
}

/// Faces `(m, 3)`, int32, int64 or uint32, 0-based.
pub fn faces(arg: &str, a: &Bound<'_, PyAny>) -> PyResult<Vec<[u32; 3]>> {
    index_rows::<3>(arg, a)?
        .into_iter()
        .enumerate()
        .map(|(f, row)| {
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
            Ok(face)
        })
        .collect()
}

/// A mesh of `positions` and `faces`, checked, the error naming both.
pub fn mesh<const D: usize>(
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
    Mesh::new(positions, faces).map_err(|e| bad(&format!("{}, {}", args.0, args.1), e))
}

/// A stack of positions `(k, n, d)`, float64 or float32.
pub fn stack<const D: usize>(arg: &str, a: &Bound<'_, PyAny>) -> PyResult<Vec<Vec<[f64; D]>>> {
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
    ) -> PyResult<Vec<Vec<[f64; D]>>> {
        view.outer_iter()
            .enumerate()
            .map(|(k, m)| rows(&format!("{arg}[{k}]"), m))
            .collect()
    }
    if let Ok(array) = a.cast::<PyArray3<f64>>() {
        let array: PyReadonlyArray3<'_, f64> = array.readonly();
        if array.shape()[2] == D {
            return read(arg, array.as_array());
        }
    } else if let Ok(array) = a.cast::<PyArray3<f32>>() {
        let array = array.readonly();
        if array.shape()[2] == D {
            return read(arg, array.as_array());
        }
    }
    Err(wrong())
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
/// frame copied: a new one, or `out` (a writeable, C-contiguous array of
/// that shape, returned). Each thread takes an equal share of the frames,
/// with its own `init()` workspace, and `fill(ws, frames, outs)` writes the
/// frames of the range `frames` into `outs`.
pub fn frames_in_place<'py, const D: usize, W>(
    py: Python<'py>,
    (k, n): (usize, usize),
    out: Option<Bound<'py, PyAny>>,
    init: impl Fn() -> W + Send + Sync,
    fill: impl Fn(&mut W, std::ops::Range<usize>, &mut [&mut [[f64; D]]]) + Send + Sync,
) -> PyResult<Bound<'py, PyAny>> {
    use rayon::prelude::*;
    let array = match out {
        None => PyArray3::<f64>::zeros(py, [k, n, D], false),
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
        let share = k.div_ceil(rayon::current_num_threads()).max(1);
        let mut write = array
            .try_readwrite()
            .map_err(|_| bad("out", "the array is not writeable (or is borrowed)"))?;
        let flat = write
            .as_slice_mut()
            .map_err(|_| bad("out", "the array is not C-contiguous"))?;
        py.detach(|| {
            flat.par_chunks_mut(share * n * D)
                .enumerate()
                .for_each_init(init, |ws, (c, block)| {
                    let mut outs: Vec<&mut [[f64; D]]> = block
                        .chunks_mut(n * D)
                        .map(|frame| frame.as_chunks_mut::<D>().0)
                        .collect();
                    let first = c * share;
                    fill(ws, first..first + outs.len(), &mut outs);
                });
        });
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
