//! Deformation transfer: `correspond` (the triangle correspondence from
//! markers, with its fit report) and `Transfer` (factored once; `apply` a
//! back-substitution, `apply_all` in parallel), the GIL released.

use std::path::PathBuf;

use meshmorph::{
    correspond_with_progress, CorrespondOptions, Correspondence, FitReport, Markers, Mesh3,
    Transfer, TransferOptions,
};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyModule};

use crate::files::PyMarkers;
use crate::progress::Progress;
use crate::{args, arrays, bad, error, work};

fn mesh3(
    py: Python<'_>,
    names: (&str, &str),
    v: &Bound<'_, PyAny>,
    f: &Bound<'_, PyAny>,
) -> PyResult<Mesh3> {
    let positions = arrays::points_of::<3>(names.0, v)?;
    let faces = arrays::faces(names.1, f)?;
    arrays::setup(names.1, faces.len())?;
    arrays::mesh(py, names, positions, faces)
}

/// The markers given to `correspond`: a `Markers`, vertex pairs `(k, 2)`
/// (an array or a list of pairs), or None for none.
fn markers(m: Option<&Bound<'_, PyAny>>) -> PyResult<Markers> {
    let Some(m) = m else {
        return Ok(Markers::new(Vec::new()));
    };
    if let Ok(given) = m.cast::<PyMarkers>() {
        return Ok(given.get().markers.clone());
    }
    const EXPECTED: &str = "a Markers (read_markers), a (k, 2) array of source and target vertex indices, a list of such pairs, or None";
    let pairs: Vec<[i64; 2]> = if m.getattr("shape").is_ok() {
        arrays::index_rows::<2>("markers", m)?
    } else {
        arrays::items("markers", m, (EXPECTED, 0), |name, pair| {
            pair.extract::<[i64; 2]>().map_err(|_| {
                bad(
                    name,
                    format!(
                        "expected a pair of vertex indices (source, target), got {}",
                        args::describe(pair)
                    ),
                )
            })
        })?
    };
    let pairs = pairs
        .into_iter()
        .enumerate()
        .map(|(k, [s, t])| {
            let index = |v: i64| {
                u32::try_from(v)
                    .map_err(|_| bad("markers", format!("pair {k} has the vertex index {v}")))
            };
            Ok([index(s)?, index(t)?])
        })
        .collect::<PyResult<Vec<_>>>()?;
    Ok(Markers::new(pairs))
}

/// A triangle correspondence between a source and a target, with how well
/// the source, deformed onto the target, lies on it (fractions of the
/// target's bounding-box diagonal and shares of its area; None for a
/// correspondence loaded from a file).
#[pyclass(name = "Correspondence", module = "meshmorph", frozen)]
pub struct PyCorrespondence {
    pub inner: Correspondence,
    fit: Option<FitReport>,
    deformed: Option<Vec<[f64; 3]>>,
}

#[pymethods]
impl PyCorrespondence {
    /// The matched triangle pairs, `(p, 2)` int64: source, target.
    #[getter]
    fn pairs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let flat: Vec<i64> = self
            .inner
            .pairs()
            .iter()
            .flatten()
            .map(|&t| t as i64)
            .collect();
        Ok(PyArray1::from_vec(py, flat)
            .reshape([self.inner.pairs().len(), 2])?
            .into_any())
    }

    /// The source deformed onto the target, `(n, 3)`.
    #[getter]
    fn deformed_source<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.deformed
            .as_ref()
            .map(|d| arrays::array(py, d))
            .transpose()
    }

    /// Area-weighted mean distance from the target to the deformed source.
    #[getter]
    fn mean_distance(&self) -> Option<f64> {
        self.fit.as_ref().map(|f| f.mean_distance)
    }

    /// Its 95th percentile.
    #[getter]
    fn distance_95(&self) -> Option<f64> {
        self.fit.as_ref().map(|f| f.distance_95)
    }

    /// The share of the target's area no source triangle covers.
    #[getter]
    fn uncovered_area(&self) -> Option<f64> {
        self.fit.as_ref().map(|f| f.uncovered_area)
    }

    /// The share of the target's area fitted poorly.
    #[getter]
    fn poor_area(&self) -> Option<f64> {
        self.fit.as_ref().map(|f| f.poor_area)
    }

    /// The connected poorly fitted regions, largest first: dicts of `area`,
    /// `largest_distance`, `point` and `nearest_markers` (index, distance).
    #[getter]
    fn poor_regions<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyList>>> {
        let Some(fit) = &self.fit else {
            return Ok(None);
        };
        let regions = fit
            .poor_regions
            .iter()
            .map(|r| {
                let d = PyDict::new(py);
                d.set_item("area", r.area)?;
                d.set_item("largest_distance", r.largest_distance)?;
                d.set_item("point", r.point.to_vec())?;
                d.set_item("triangles", r.triangles.len())?;
                d.set_item("nearest_markers", r.nearest_markers.clone())?;
                Ok(d)
            })
            .collect::<PyResult<Vec<_>>>()?;
        Ok(Some(PyList::new(py, regions)?))
    }

    /// Saves the correspondence (atomically).
    fn save(&self, path: &Bound<'_, PyAny>) -> PyResult<()> {
        let path = args::output_path("path", path)?;
        self.inner.save(&path).map_err(error)
    }

    /// Loads a saved correspondence (its fit figures are None).
    #[staticmethod]
    fn load(path: &Bound<'_, PyAny>) -> PyResult<Self> {
        let path: PathBuf = args::path("path", path)?;
        Ok(Self {
            inner: Correspondence::load(&path).map_err(error)?,
            fit: None,
            deformed: None,
        })
    }
}

/// The triangle correspondence from `vs, fs` (source) to `vt, ft`
/// (target) through `markers` (Sumner and Popović 2004, section 5), with
/// its fit report. `progress(done, total)` is called as it goes.
#[pyfunction]
#[pyo3(signature = (vs, fs, vt, ft, markers = None, *, align = None, identity_weight = None, match_threshold = None, progress = None))]
#[pyo3(
    text_signature = "(vs, fs, vt, ft, markers=None, *, align=True, identity_weight=None, match_threshold=None, progress=None)"
)]
#[allow(clippy::too_many_arguments)]
fn correspond(
    py: Python<'_>,
    vs: &Bound<'_, PyAny>,
    fs: &Bound<'_, PyAny>,
    vt: &Bound<'_, PyAny>,
    ft: &Bound<'_, PyAny>,
    markers: Option<&Bound<'_, PyAny>>,
    align: Option<&Bound<'_, PyAny>>,
    identity_weight: Option<&Bound<'_, PyAny>>,
    match_threshold: Option<&Bound<'_, PyAny>>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyCorrespondence> {
    let mut options = CorrespondOptions::default().with_align(args::flag("align", align, true)?);
    if let Some(w) = args::optional_number("identity_weight", identity_weight)? {
        let smoothness = options.smoothness_weight;
        options = options.with_weights(smoothness, w);
    }
    if let Some(m) = args::optional_number("match_threshold", match_threshold)? {
        options = options.with_match_threshold(m);
    }
    let progress = Progress::new(args::callback("progress", progress)?);
    let source = mesh3(py, ("vs", "fs"), vs, fs)?;
    let target = mesh3(py, ("vt", "ft"), vt, ft)?;
    let markers = self::markers(markers)?;
    let total = options.steps();
    let result = work::run(py, || {
        let markers = if markers.has_points() {
            markers.snap(&source, &target)?.0
        } else {
            markers
        };
        markers.validate(&source, &target)?;
        correspond_with_progress(&source, &target, &markers, &options, &mut |done| {
            progress.report(done, total)
        })
    })?;
    progress.finish()?;
    let result = result.map_err(error)?;
    Ok(PyCorrespondence {
        inner: result.correspondence,
        fit: Some(result.fit),
        deformed: Some(result.deformed_source.positions().to_vec()),
    })
}

/// Deformation transfer from poses of `vs, fs` to the target `vt, ft`
/// through `correspondence` (Sumner and Popović 2004, section 4): factored
/// once; `apply(pose)` is a back-substitution, `apply_all` runs in parallel.
#[pyclass(name = "Transfer", module = "meshmorph", frozen)]
pub struct PyTransfer {
    inner: Transfer,
    source_vertices: usize,
}

#[pymethods]
impl PyTransfer {
    #[new]
    fn new(
        py: Python<'_>,
        vs: &Bound<'_, PyAny>,
        fs: &Bound<'_, PyAny>,
        vt: &Bound<'_, PyAny>,
        ft: &Bound<'_, PyAny>,
        correspondence: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let correspondence = args::object::<PyCorrespondence>(
            "correspondence",
            correspondence,
            "a Correspondence (correspond or Correspondence.load)",
        )?
        .get();
        let source = mesh3(py, ("vs", "fs"), vs, fs)?;
        let target = mesh3(py, ("vt", "ft"), vt, ft)?;
        let inner = work::run(py, || {
            Transfer::new(
                &source,
                &target,
                &correspondence.inner,
                &TransferOptions::default(),
            )
        })?
        .map_err(error)?;
        Ok(Self {
            inner,
            source_vertices: source.num_vertices(),
        })
    }

    /// The target in the source's pose `pose` `(n, 3)`, or written into `out`.
    #[pyo3(signature = (pose, *, out = None))]
    fn apply<'py>(
        &self,
        py: Python<'py>,
        pose: &Bound<'py, PyAny>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let pose = arrays::points_of::<3>("pose", pose)?;
        if pose.len() != self.source_vertices {
            return Err(bad(
                "pose",
                format!(
                    "{} vertices, the source has {}",
                    pose.len(),
                    self.source_vertices
                ),
            ));
        }
        let result = py.detach(|| {
            let mut out = vec![[0.0; 3]; self.target_vertices()];
            self.inner
                .apply_into(&pose, &mut out, &mut self.inner.workspace());
            out
        });
        arrays::give(py, &result, out)
    }

    /// The target in each pose of `poses` `(k, n, 3)`, `(k, m, 3)`, in
    /// parallel, or written into `out`; `progress(done, total)` is called
    /// as poses finish.
    #[pyo3(signature = (poses, *, out = None, progress = None))]
    fn apply_all<'py>(
        &self,
        py: Python<'py>,
        poses: &Bound<'py, PyAny>,
        out: Option<Bound<'py, PyAny>>,
        progress: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let progress = Progress::new(args::callback("progress", progress)?);
        // Each pose's result, unless written into `out`.
        let each = match out {
            None => arrays::bytes_of::<[f64; 3]>(&[self.target_vertices()]),
            Some(_) => 0,
        };
        let poses = arrays::stack::<3>("poses", poses, each)?;
        if let Some(k) = poses.iter().position(|p| p.len() != self.source_vertices) {
            return Err(bad(
                "poses",
                format!(
                    "pose {k} has {} vertices, the source has {}",
                    poses[k].len(),
                    self.source_vertices
                ),
            ));
        }
        let total = poses.len();
        let done = std::sync::atomic::AtomicUsize::new(0);
        let results = arrays::frames_in_place(
            py,
            ("poses", total, self.target_vertices()),
            out,
            || self.inner.workspace(),
            |ws, ks, outs| {
                for (k, out) in ks.zip(outs.iter_mut()) {
                    self.inner.apply_into(&poses[k], out, ws);
                    let finished = done.fetch_add(1, std::sync::atomic::Ordering::SeqCst) + 1;
                    progress.report(finished, total);
                }
            },
        )?;
        progress.finish()?;
        Ok(results)
    }
}

impl PyTransfer {
    fn target_vertices(&self) -> usize {
        self.inner.num_target_vertices()
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyCorrespondence>()?;
    m.add_class::<PyTransfer>()?;
    m.add_function(wrap_pyfunction!(correspond, m)?)?;
    Ok(())
}
