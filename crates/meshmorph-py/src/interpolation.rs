//! `Interpolator`, `Sequence` and `Blend`: as-rigid-as-possible shapes
//! between keys, factored once when made; each frame a back-substitution,
//! many frames in parallel, with the GIL released.

use meshmorph::{Blend, Interpolator, InterpolatorOptions, Mesh, Sequence, StretchMode};
use pyo3::prelude::*;
use pyo3::types::PyModule;

use crate::arrays::{self, Points};
use crate::{args, bad, error, work};

/// A value of either dimension.
enum Either<A, B> {
    Plane(A),
    Space(B),
}

impl<A, B> Either<A, B> {
    /// The bytes of a new frame of `n` vertices, or none when written
    /// into `out`.
    fn frame_bytes(&self, n: usize, out: &Option<Bound<'_, PyAny>>) -> u128 {
        let d = match self {
            Either::Plane(_) => 2,
            Either::Space(_) => 3,
        };
        match out {
            None => arrays::bytes_of::<f64>(&[n, d]),
            Some(_) => 0,
        }
    }
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

/// The options as given (None for each one's default).
pub(crate) fn options(
    consistency: Option<&Bound<'_, PyAny>>,
    turns: Option<&Bound<'_, PyAny>>,
    stretch: Option<&Bound<'_, PyAny>>,
) -> PyResult<InterpolatorOptions> {
    options_or(consistency, turns, stretch, "linear")
}

/// [`options`] with `stretch` `default` unless given.
pub(crate) fn options_or(
    consistency: Option<&Bound<'_, PyAny>>,
    turns: Option<&Bound<'_, PyAny>>,
    stretch: Option<&Bound<'_, PyAny>>,
    default: &'static str,
) -> PyResult<InterpolatorOptions> {
    let stretch = match args::choice("stretch", stretch, &["linear", "log", "area"], default)? {
        "log" => StretchMode::Log,
        "area" => StretchMode::AreaBlend,
        _ => StretchMode::Linear,
    };
    Ok(InterpolatorOptions::default()
        .with_consistency(args::flag("consistency", consistency, true)?)
        .with_turns(args::whole("turns", turns, 0)?)
        .with_stretch(stretch))
}

/// [`options`] with `mend_folds` (planar frames mended where triangles
/// turn over), `untie_outlines` (planar frames' outlines untied where they
/// knot) and `outline_lengths` (planar frames' outline edges on the blend
/// of their lengths); all default off.
fn frame_options(
    consistency: Option<&Bound<'_, PyAny>>,
    turns: Option<&Bound<'_, PyAny>>,
    stretch: Option<&Bound<'_, PyAny>>,
    [mend_folds, untie_outlines, outline_lengths]: [Option<&Bound<'_, PyAny>>; 3],
) -> PyResult<InterpolatorOptions> {
    Ok(options(consistency, turns, stretch)?
        .with_mend_folds(args::flag("mend_folds", mend_folds, false)?)
        .with_untie_outlines(args::flag("untie_outlines", untie_outlines, false)?)
        .with_outline_lengths(args::flag("outline_lengths", outline_lengths, false)?))
}

/// Keys of one dimension (checked by [`dimension`]) with the faces
/// `triangles`, each checked, named in messages as given.
fn keys<const D: usize>(
    py: Python<'_>,
    named: Vec<(String, Points)>,
    triangles: &[[u32; 3]],
) -> PyResult<Vec<Mesh<D>>> {
    named
        .into_iter()
        .map(|(name, p)| {
            let rows = p.into_dimension::<D>(&name)?;
            arrays::mesh(py, (&name, "f"), rows, triangles.to_vec())
        })
        .collect()
}

/// The keys `named` with the faces `triangles` (of the argument `f`),
/// checked (one dimension, one vertex count, the memory the setup needs),
/// made into the plane's or the space's `$make` (with `$k` the keys) in
/// the pool, the GIL released.
macro_rules! build {
    ($py:expr, $named:expr, $triangles:expr, |$k:ident| $make:expr) => {{
        let (named, triangles) = ($named, $triangles);
        let d = dimension(&named)?;
        arrays::setup("f", triangles.len())?;
        match d {
            2 => {
                let $k = keys::<2>($py, named, &triangles)?;
                Either::Plane(work::run($py, || $make)?.map_err(error)?)
            }
            _ => {
                let $k = keys::<3>($py, named, &triangles)?;
                Either::Space(work::run($py, || $make)?.map_err(error)?)
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

/// As-rigid-as-possible interpolation from `v0` to `v1` (Alexa, Cohen-Or and
/// Levin 2000; rotations made consistent across the mesh, Baxter, Barla and
/// Anjyo 2008). Vertices `(n, 2)` or `(n, 3)`, faces `(m, 3)`. Factored once;
/// `at(t)` is one back-substitution; `frames(ts)` runs in parallel.
/// `mend_folds=True` (planar): a frame in which triangles turn over is mended
/// where they are, its outline kept, as drawings' compatible meshes want
/// (such a frame then takes more than its back-substitution).
/// `untie_outlines=True` (planar): where a frame's outline knots (a short
/// stretch crumpled across itself), that stretch is laid straight; an
/// outline that stays simple is kept to the bit.
/// `outline_lengths=True` (planar): each frame's outline edges take the
/// straight blend of their lengths in the keys, in the fit's directions and
/// with the fit's area, and the inside moves with them (where two drawings
/// differ a great deal the fit alone shortens them by 10 to 17 %).
#[pyclass(name = "Interpolator", module = "meshmorph", frozen)]
pub struct PyInterpolator(Either<Interpolator<2>, Interpolator<3>>);

#[pymethods]
impl PyInterpolator {
    #[new]
    #[allow(clippy::too_many_arguments)] // the keyword arguments Python takes
    #[pyo3(signature = (v0, v1, f, *, consistency = None, turns = None, stretch = None, mend_folds = None, untie_outlines = None, outline_lengths = None))]
    #[pyo3(
        text_signature = "(v0, v1, f, *, consistency=True, turns=0, stretch='linear', mend_folds=False, untie_outlines=False, outline_lengths=False)"
    )]
    fn new(
        py: Python<'_>,
        v0: &Bound<'_, PyAny>,
        v1: &Bound<'_, PyAny>,
        f: &Bound<'_, PyAny>,
        consistency: Option<&Bound<'_, PyAny>>,
        turns: Option<&Bound<'_, PyAny>>,
        stretch: Option<&Bound<'_, PyAny>>,
        mend_folds: Option<&Bound<'_, PyAny>>,
        untie_outlines: Option<&Bound<'_, PyAny>>,
        outline_lengths: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let options = frame_options(
            consistency,
            turns,
            stretch,
            [mend_folds, untie_outlines, outline_lengths],
        )?;
        let named = vec![
            ("v0".to_string(), arrays::points("v0", v0)?),
            ("v1".to_string(), arrays::points("v1", v1)?),
        ];
        let triangles = arrays::faces("f", f)?;
        let inner = build!(py, named, triangles, |k| Interpolator::new(
            &k[0], &k[1], &options
        ));
        Ok(Self(inner))
    }

    /// The shape at time `t` (0 is `v0`, 1 is `v1`; others extrapolate),
    /// `(n, d)` float64, or written into `out`.
    #[pyo3(signature = (t, *, out = None))]
    fn at<'py>(
        &self,
        py: Python<'py>,
        t: &Bound<'py, PyAny>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let t = args::number("t", t)?;
        each!(&self.0, i => { let frame = py.detach(|| i.at(t)); arrays::give(py, &frame, out) })
    }

    /// The shapes at times `ts`, `(k, n, d)` float64, computed in parallel,
    /// or written into `out`.
    #[pyo3(signature = (ts, *, out = None))]
    fn frames<'py>(
        &self,
        py: Python<'py>,
        ts: &Bound<'py, PyAny>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let each = self
            .0
            .frame_bytes(each!(&self.0, i => i.num_vertices()), &out);
        let ts = arrays::numbers("ts", ts, each)?;
        each!(&self.0, i => arrays::frames_in_place(py, ("ts", ts.len(), i.num_vertices()), out, || i.workspace(), |ws, fs, outs| i.sequence().frames_into(&ts[fs], outs, ws)))
    }

    /// The number of vertices.
    #[getter]
    fn num_vertices(&self) -> usize {
        each!(&self.0, i => i.num_vertices())
    }
}

/// As-rigid-as-possible interpolation through keys `(k, n, d)` with faces
/// `(m, 3)`: `at(s)` passes through key `j` at `s = j`. Its keyword
/// arguments are [`PyInterpolator`]'s (with `outline_lengths`, each frame's
/// outline takes the blend of its two keys' lengths).
#[pyclass(name = "Sequence", module = "meshmorph", frozen)]
pub struct PySequence(Either<Sequence<2>, Sequence<3>>);

/// The keys of a stack `(k, n, d)` with `triangles` faces, each named
/// `arg[j]`, their memory checked with what each key's setup needs.
fn stacked(arg: &str, a: &Bound<'_, PyAny>, triangles: usize) -> PyResult<Vec<(String, Points)>> {
    let each = (triangles as u128).saturating_mul(arrays::KEY_BYTES_PER_TRIANGLE);
    Ok(arrays::stack_points(arg, a, each)?
        .into_iter()
        .enumerate()
        .map(|(j, p)| (format!("{arg}[{j}]"), p))
        .collect())
}

#[pymethods]
impl PySequence {
    #[new]
    #[allow(clippy::too_many_arguments)] // the keyword arguments Python takes
    #[pyo3(signature = (keys, f, *, consistency = None, turns = None, stretch = None, mend_folds = None, untie_outlines = None, outline_lengths = None))]
    #[pyo3(
        text_signature = "(keys, f, *, consistency=True, turns=0, stretch='linear', mend_folds=False, untie_outlines=False, outline_lengths=False)"
    )]
    fn new(
        py: Python<'_>,
        keys: &Bound<'_, PyAny>,
        f: &Bound<'_, PyAny>,
        consistency: Option<&Bound<'_, PyAny>>,
        turns: Option<&Bound<'_, PyAny>>,
        stretch: Option<&Bound<'_, PyAny>>,
        mend_folds: Option<&Bound<'_, PyAny>>,
        untie_outlines: Option<&Bound<'_, PyAny>>,
        outline_lengths: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let options = frame_options(
            consistency,
            turns,
            stretch,
            [mend_folds, untie_outlines, outline_lengths],
        )?;
        let triangles = arrays::faces("f", f)?;
        let named = stacked("keys", keys, triangles.len())?;
        if named.len() < 2 {
            return Err(bad(
                "keys",
                format!("{} keys: a sequence needs two or more", named.len()),
            ));
        }
        let inner = build!(py, named, triangles, |k| Sequence::new(&k, &options));
        Ok(Self(inner))
    }

    /// The shape at `s` (key `j` at `s = j`), `(n, d)`, or written into `out`.
    #[pyo3(signature = (s, *, out = None))]
    fn at<'py>(
        &self,
        py: Python<'py>,
        s: &Bound<'py, PyAny>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let s = args::number("s", s)?;
        each!(&self.0, q => { let frame = py.detach(|| q.at(s)); arrays::give(py, &frame, out) })
    }

    /// The shapes at `ss`, `(k, n, d)`, computed in parallel, or written
    /// into `out`.
    #[pyo3(signature = (ss, *, out = None))]
    fn frames<'py>(
        &self,
        py: Python<'py>,
        ss: &Bound<'py, PyAny>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let each = self
            .0
            .frame_bytes(each!(&self.0, q => q.num_vertices()), &out);
        let ss = arrays::numbers("ss", ss, each)?;
        each!(&self.0, q => arrays::frames_in_place(py, ("ss", ss.len(), q.num_vertices()), out, || q.workspace(), |ws, fs, outs| q.frames_into(&ss[fs], outs, ws)))
    }
}

/// An n-way as-rigid-as-possible blend of `shapes` `(k, n, d)` of `base`
/// `(n, d)`: `at(weights)` with one weight a shape.
#[pyclass(name = "Blend", module = "meshmorph", frozen)]
pub struct PyBlend(Either<Blend<2>, Blend<3>>, usize);

#[pymethods]
impl PyBlend {
    #[new]
    #[pyo3(signature = (base, shapes, f, *, consistency = None, turns = None, stretch = None))]
    #[pyo3(text_signature = "(base, shapes, f, *, consistency=True, turns=0, stretch='linear')")]
    fn new(
        py: Python<'_>,
        base: &Bound<'_, PyAny>,
        shapes: &Bound<'_, PyAny>,
        f: &Bound<'_, PyAny>,
        consistency: Option<&Bound<'_, PyAny>>,
        turns: Option<&Bound<'_, PyAny>>,
        stretch: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let options = options(consistency, turns, stretch)?;
        let mut named = vec![("base".to_string(), arrays::points("base", base)?)];
        let triangles = arrays::faces("f", f)?;
        named.extend(stacked("shapes", shapes, triangles.len())?);
        let count = named.len() - 1;
        let inner = build!(py, named, triangles, |k| Blend::new(
            &k[0],
            &k[1..],
            &options
        ));
        Ok(Self(inner, count))
    }

    /// The blend with `weights` (one a shape), `(n, d)`, or written into `out`.
    #[pyo3(signature = (weights, *, out = None))]
    fn at<'py>(
        &self,
        py: Python<'py>,
        weights: &Bound<'py, PyAny>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let weights = arrays::numbers("weights", weights, 0)?;
        if weights.len() != self.1 {
            return Err(bad(
                "weights",
                format!("{} weights for {} shapes", weights.len(), self.1),
            ));
        }
        each!(&self.0, b => { let frame = py.detach(|| b.at(&weights)); arrays::give(py, &frame, out) })
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyInterpolator>()?;
    m.add_class::<PySequence>()?;
    m.add_class::<PyBlend>()?;
    Ok(())
}
