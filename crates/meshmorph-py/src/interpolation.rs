//! `Interpolator`, `Sequence` and `Blend`: as-rigid-as-possible shapes
//! between keys, factored once when made; each frame a back-substitution,
//! many frames in parallel, with the GIL released.

use meshmorph::{Blend, Interpolator, InterpolatorOptions, Mesh, Sequence, StretchMode};
use pyo3::prelude::*;
use pyo3::types::PyModule;

use crate::arrays::{self, Points};
use crate::{bad, error};

/// A value of either dimension.
enum Either<A, B> {
    Plane(A),
    Space(B),
}

/// Runs `$body` with `$x` bound to the plane's or the space's value.
macro_rules! each {
    ($e:expr, $x:ident => $body:expr) => {
        match $e {
            Either::Plane($x) => $body,
            Either::Space($x) => $body,
        }
    };
}

fn options(consistency: bool, turns: i32, stretch: &str) -> PyResult<InterpolatorOptions> {
    let stretch = match stretch {
        "linear" => StretchMode::Linear,
        "log" => StretchMode::Log,
        other => {
            return Err(bad(
                "stretch",
                format!("{other:?} is neither \"linear\" nor \"log\""),
            ))
        }
    };
    Ok(InterpolatorOptions::default()
        .with_consistency(consistency)
        .with_turns(turns)
        .with_stretch(stretch))
}

/// Keys of one dimension (checked by [`dimension`]) with the faces
/// `triangles`, each checked, named in messages as given.
fn keys<const D: usize>(
    named: Vec<(String, Points)>,
    triangles: &[[u32; 3]],
) -> PyResult<Vec<Mesh<D>>> {
    named
        .into_iter()
        .map(|(name, p)| {
            let rows = p.into_dimension::<D>(&name)?;
            arrays::mesh((&name, "f"), rows, triangles.to_vec())
        })
        .collect()
}

/// The keys `named` with the faces `f`, checked (one dimension, one
/// vertex count), made into the plane's or the space's `$make` (with `$k`
/// the keys), the GIL released.
macro_rules! build {
    ($py:expr, $named:expr, $f:expr, |$k:ident| $make:expr) => {{
        let named = $named;
        let triangles = arrays::faces("f", $f)?;
        match dimension(&named)? {
            2 => {
                let $k = keys::<2>(named, &triangles)?;
                Either::Plane($py.detach(|| $make).map_err(error)?)
            }
            _ => {
                let $k = keys::<3>(named, &triangles)?;
                Either::Space($py.detach(|| $make).map_err(error)?)
            }
        }
    }};
}

/// The dimension of every key, which must agree.
fn dimension(named: &[(String, Points)]) -> PyResult<usize> {
    let d = named.first().map_or(3, |(_, p)| p.dimension());
    if let Some((name, p)) = named.iter().find(|(_, p)| p.dimension() != d) {
        return Err(bad(
            name,
            format!(
                "has {} coordinates a vertex, the first key {d}",
                p.dimension()
            ),
        ));
    }
    let n = named.first().map_or(0, |(_, p)| p.len());
    if let Some((name, p)) = named.iter().find(|(_, p)| p.len() != n) {
        return Err(bad(
            name,
            format!("has {} vertices, the first key {n}", p.len()),
        ));
    }
    Ok(d)
}

fn times(arg: &str, ts: Vec<f64>) -> PyResult<Vec<f64>> {
    ts.into_iter()
        .enumerate()
        .map(|(k, t)| arrays::finite(&format!("{arg}[{k}]"), t))
        .collect()
}

/// As-rigid-as-possible interpolation from `v0` to `v1` (Alexa, Cohen-Or and
/// Levin 2000; rotations made consistent across the mesh, Baxter, Barla and
/// Anjyo 2008). Vertices `(n, 2)` or `(n, 3)`, faces `(m, 3)`. Factored once;
/// `at(t)` is one back-substitution; `frames(ts)` runs in parallel.
#[pyclass(name = "Interpolator", module = "meshmorph", frozen)]
pub struct PyInterpolator(Either<Interpolator<2>, Interpolator<3>>);

#[pymethods]
impl PyInterpolator {
    #[new]
    #[pyo3(signature = (v0, v1, f, *, consistency = true, turns = 0, stretch = "linear"))]
    fn new(
        py: Python<'_>,
        v0: &Bound<'_, PyAny>,
        v1: &Bound<'_, PyAny>,
        f: &Bound<'_, PyAny>,
        consistency: bool,
        turns: i32,
        stretch: &str,
    ) -> PyResult<Self> {
        let options = options(consistency, turns, stretch)?;
        let named = vec![
            ("v0".to_string(), arrays::points("v0", v0)?),
            ("v1".to_string(), arrays::points("v1", v1)?),
        ];
        let inner = build!(py, named, f, |k| Interpolator::new(&k[0], &k[1], &options));
        Ok(Self(inner))
    }

    /// The shape at time `t` (0 is `v0`, 1 is `v1`; others extrapolate),
    /// `(n, d)` float64, or written into `out`.
    #[pyo3(signature = (t, *, out = None))]
    fn at<'py>(
        &self,
        py: Python<'py>,
        t: f64,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let t = arrays::finite("t", t)?;
        each!(&self.0, i => { let frame = py.detach(|| i.at(t)); arrays::give(py, &frame, out) })
    }

    /// The shapes at times `ts`, `(k, n, d)` float64, computed in parallel,
    /// or written into `out`.
    #[pyo3(signature = (ts, *, out = None))]
    fn frames<'py>(
        &self,
        py: Python<'py>,
        ts: Vec<f64>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let ts = times("ts", ts)?;
        each!(&self.0, i => arrays::frames_in_place(py, (ts.len(), i.num_vertices()), out, || i.workspace(), |ws, fs, outs| i.sequence().frames_into(&ts[fs], outs, ws)))
    }

    /// The number of vertices.
    #[getter]
    fn num_vertices(&self) -> usize {
        each!(&self.0, i => i.num_vertices())
    }
}

/// As-rigid-as-possible interpolation through keys `(k, n, d)` with faces
/// `(m, 3)`: `at(s)` passes through key `j` at `s = j`.
#[pyclass(name = "Sequence", module = "meshmorph", frozen)]
pub struct PySequence(Either<Sequence<2>, Sequence<3>>);

/// The keys of a stack `(k, n, d)`, each named `arg[j]`.
fn stacked(arg: &str, a: &Bound<'_, PyAny>) -> PyResult<Vec<(String, Points)>> {
    let named = |frames: Vec<Points>| -> Vec<(String, Points)> {
        frames
            .into_iter()
            .enumerate()
            .map(|(j, p)| (format!("{arg}[{j}]"), p))
            .collect()
    };
    if let Ok(s) = arrays::stack::<3>(arg, a) {
        return Ok(named(s.into_iter().map(Points::Space).collect()));
    }
    match arrays::stack::<2>(arg, a) {
        Ok(s) => Ok(named(s.into_iter().map(Points::Plane).collect())),
        Err(_) => Err(bad(
            arg,
            "expected a (k, n, 2) or (k, n, 3) float64 or float32 numpy array",
        )),
    }
}

#[pymethods]
impl PySequence {
    #[new]
    #[pyo3(signature = (keys, f, *, consistency = true, turns = 0, stretch = "linear"))]
    fn new(
        py: Python<'_>,
        keys: &Bound<'_, PyAny>,
        f: &Bound<'_, PyAny>,
        consistency: bool,
        turns: i32,
        stretch: &str,
    ) -> PyResult<Self> {
        let options = options(consistency, turns, stretch)?;
        let named = stacked("keys", keys)?;
        if named.len() < 2 {
            return Err(bad(
                "keys",
                format!("{} keys: a sequence needs two or more", named.len()),
            ));
        }
        let inner = build!(py, named, f, |k| Sequence::new(&k, &options));
        Ok(Self(inner))
    }

    /// The shape at `s` (key `j` at `s = j`), `(n, d)`, or written into `out`.
    #[pyo3(signature = (s, *, out = None))]
    fn at<'py>(
        &self,
        py: Python<'py>,
        s: f64,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let s = arrays::finite("s", s)?;
        each!(&self.0, q => { let frame = py.detach(|| q.at(s)); arrays::give(py, &frame, out) })
    }

    /// The shapes at `ss`, `(k, n, d)`, computed in parallel, or written
    /// into `out`.
    #[pyo3(signature = (ss, *, out = None))]
    fn frames<'py>(
        &self,
        py: Python<'py>,
        ss: Vec<f64>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let ss = times("ss", ss)?;
        each!(&self.0, q => arrays::frames_in_place(py, (ss.len(), q.num_vertices()), out, || q.workspace(), |ws, fs, outs| q.frames_into(&ss[fs], outs, ws)))
    }
}

/// An n-way as-rigid-as-possible blend of `shapes` `(k, n, d)` of `base`
/// `(n, d)`: `at(weights)` with one weight a shape.
#[pyclass(name = "Blend", module = "meshmorph", frozen)]
pub struct PyBlend(Either<Blend<2>, Blend<3>>, usize);

#[pymethods]
impl PyBlend {
    #[new]
    #[pyo3(signature = (base, shapes, f, *, consistency = true, turns = 0, stretch = "linear"))]
    fn new(
        py: Python<'_>,
        base: &Bound<'_, PyAny>,
        shapes: &Bound<'_, PyAny>,
        f: &Bound<'_, PyAny>,
        consistency: bool,
        turns: i32,
        stretch: &str,
    ) -> PyResult<Self> {
        let options = options(consistency, turns, stretch)?;
        let mut named = vec![("base".to_string(), arrays::points("base", base)?)];
        named.extend(stacked("shapes", shapes)?);
        let count = named.len() - 1;
        let inner = build!(py, named, f, |k| Blend::new(&k[0], &k[1..], &options));
        Ok(Self(inner, count))
    }

    /// The blend with `weights` (one a shape), `(n, d)`, or written into `out`.
    #[pyo3(signature = (weights, *, out = None))]
    fn at<'py>(
        &self,
        py: Python<'py>,
        weights: Vec<f64>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        if weights.len() != self.1 {
            return Err(bad(
                "weights",
                format!("{} weights for {} shapes", weights.len(), self.1),
            ));
        }
        let weights = times("weights", weights)?;
        each!(&self.0, b => { let frame = py.detach(|| b.at(&weights)); arrays::give(py, &frame, out) })
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyInterpolator>()?;
    m.add_class::<PySequence>()?;
    m.add_class::<PyBlend>()?;
    Ok(())
}
