//! `compatible_meshes`: two or more drawings (outlines, with holes) to
//! meshes with the same triangles, ready for `Interpolator` and `Sequence`.

use meshmorph::outline::{compatible_set, CompatibleSet, Drawing, OutlineOptions};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyModule};

use crate::arrays::{self, describe};
use crate::{bad, error, work};

/// A drawing: a list of loops, each `(n, 2)`.
fn drawing(arg: &str, d: &Bound<'_, PyAny>) -> PyResult<Vec<Vec<[f64; 2]>>> {
    arrays::items(
        arg,
        d,
        (
            "a list of loops (the outer loop first, then the holes), each a (n, 2) float64 or float32 numpy array",
            0,
        ),
        arrays::points_of::<2>,
    )
}

/// Anchors `(k, count, 2)`: one point on each of the `count` drawings.
pub(crate) fn anchors(a: &Bound<'_, PyAny>, count: usize) -> PyResult<Vec<Vec<[f64; 2]>>> {
    let read = |shape: &[usize], at: &dyn Fn(usize, usize, usize) -> f64| {
        if shape[1..] != [count, 2] {
            return Err(bad(
                "anchors",
                format!(
                    "expected the shape (k, {count}, 2), one point on each of the {count} drawings an anchor, got {shape:?}"
                ),
            ));
        }
        let mut out = arrays::room("anchors", "anchors", shape[0])?;
        for k in 0..shape[0] {
            let points: Vec<[f64; 2]> = (0..count).map(|d| [at(k, d, 0), at(k, d, 1)]).collect();
            if let Some(d) = points.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
                return Err(bad(
                    "anchors",
                    format!(
                        "anchors[{k}, {d}] (anchor {}, its point on drawing {}) is not finite: {:?}",
                        k + 1,
                        d + 1,
                        points[d]
                    ),
                ));
            }
            out.push(points);
        }
        Ok(out)
    };
    arrays::read_3d(a, read).unwrap_or_else(|| {
        Err(bad(
            "anchors",
            format!(
                "expected a (k, {count}, 2) float64 or float32 numpy array or None, got {}",
                describe(a)
            ),
        ))
    })
}

/// Meshes with the same triangles inside two or more drawings, made by
/// `compatible_meshes`: one vertex array per drawing, the triangles they
/// share (positively oriented, counter-clockwise, in every mesh), the
/// outline as vertex indices, and how it went.
#[pyclass(name = "CompatibleMeshes", module = "meshmorph", frozen)]
pub struct PyCompatibleMeshes {
    set: CompatibleSet,
}

/// Vertex indices as a new int64 array.
fn indices<'py>(py: Python<'py>, v: &[u32]) -> Bound<'py, PyArray1<i64>> {
    PyArray1::from_vec(py, v.iter().map(|&i| i64::from(i)).collect())
}

#[pymethods]
impl PyCompatibleMeshes {
    /// The vertices of each drawing's mesh: a list of `(v, 2)` float64
    /// arrays, in the drawings' order (the same `v` in all).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        self.set
            .meshes
            .iter()
            .map(|m| arrays::array(py, m.positions()))
            .collect()
    }

    /// The triangles, the same in every mesh: a `(m, 3)` int64 array.
    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let flat: Vec<i64> = self.set.meshes[0]
            .triangles()
            .iter()
            .flatten()
            .map(|&i| i64::from(i))
            .collect();
        let n = flat.len() / 3;
        Ok(PyArray1::from_vec(py, flat).reshape([n, 3])?.into_any())
    }

    /// The outline as vertex indices, the same in every mesh: a list of
    /// int64 arrays, the outer loop first (counter-clockwise), then the
    /// holes in the first drawing's order (clockwise).
    #[getter]
    fn loops<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyArray1<i64>>> {
        self.set.loops.iter().map(|l| indices(py, l)).collect()
    }

    /// For each drawing, each of its loops as given and each of their
    /// points, the vertex at that point: `given[d][l][i]`.
    #[getter]
    fn given<'py>(&self, py: Python<'py>) -> Vec<Vec<Bound<'py, PyArray1<i64>>>> {
        self.set
            .given
            .iter()
            .map(|d| d.iter().map(|l| indices(py, l)).collect())
            .collect()
    }

    /// The vertex of each anchor: an int64 array.
    #[getter]
    fn anchors<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        indices(py, &self.set.anchors)
    }

    /// How it went, as a dict: `drawing_points`, `boundary_points`,
    /// `inside_anchors`, `steiner_points`, `triangles`,
    /// `min_angle_degrees` (one a mesh), `overlay_min_angle_degrees` (or
    /// None), `path` ("mapped" or "overlay"), `seconds`, and `text`.
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = &self.set.report;
        let d = PyDict::new(py);
        d.set_item("drawing_points", r.drawing_points.clone())?;
        d.set_item("boundary_points", r.boundary_points)?;
        d.set_item("inside_anchors", r.inside_anchors)?;
        d.set_item("steiner_points", r.steiner_points)?;
        d.set_item("triangles", r.triangles)?;
        d.set_item("min_angle_degrees", r.min_angle_degrees.clone())?;
        d.set_item(
            "overlay_min_angle_degrees",
            r.overlay_min_angle_degrees.clone(),
        )?;
        d.set_item("path", format!("{:?}", r.path).to_lowercase())?;
        d.set_item("seconds", r.seconds)?;
        d.set_item("text", r.to_string())?;
        Ok(d)
    }

    fn __len__(&self) -> usize {
        self.set.meshes.len()
    }

    fn __repr__(&self) -> String {
        let r = &self.set.report;
        format!(
            "<CompatibleMeshes: {} drawings, {} vertices, {} triangles, smallest angle {:.1} degrees>",
            self.set.meshes.len(),
            self.set.meshes[0].num_vertices(),
            r.triangles,
            r.min_angle_degrees.iter().copied().fold(f64::INFINITY, f64::min)
        )
    }
}

/// Meshes with the same triangles inside two or more drawings.
///
/// `drawings`: a list of 2 or more drawings, each a list of loops (the
/// outer loop first, then its holes), each loop a `(n, 2)` float64 or
/// float32 array of points in order, in either direction, starting
/// anywhere; every drawing needs the same number of holes. `anchors`: an
/// optional `(k, len(drawings), 2)` array, each anchor one point on each
/// drawing, kept matched (on the outlines, or inside the shapes, where
/// each becomes a vertex). The outlines are matched automatically
/// otherwise. The GIL is released during the work.
#[pyfunction]
#[pyo3(signature = (drawings, anchors=None))]
fn compatible_meshes(
    py: Python<'_>,
    drawings: &Bound<'_, PyAny>,
    anchors: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyCompatibleMeshes> {
    let given = arrays::items(
        "drawings",
        drawings,
        ("a list of 2 or more drawings, each a list of loops", 0),
        drawing,
    )?;
    if given.len() < 2 {
        return Err(bad(
            "drawings",
            format!(
                "expected 2 or more drawings, got {}: compatible meshes need a drawing to go to",
                given.len()
            ),
        ));
    }
    let anchors = match anchors.filter(|a| !a.is_none()) {
        Some(a) => self::anchors(a, given.len())?,
        None => Vec::new(),
    };
    let set = work::run(py, || {
        let made: Vec<Drawing> = given
            .into_iter()
            .enumerate()
            .map(|(k, loops)| Drawing::new(loops).map_err(|e| bad(&format!("drawings[{k}]"), e)))
            .collect::<PyResult<_>>()?;
        compatible_set(&made, &anchors, &OutlineOptions::default()).map_err(error)
    })??;
    Ok(PyCompatibleMeshes { set })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyCompatibleMeshes>()?;
    m.add_function(wrap_pyfunction!(compatible_meshes, m)?)?;
    Ok(())
}
