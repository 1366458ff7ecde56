//! Files: `read_mesh` keeps the whole file so that `write_mesh` writes a
//! result with its polygons, texture coordinates, normals and materials, as
//! the command line does; `read_markers` reads every marker format.

use std::path::PathBuf;

use meshmorph::io::MeshFile;
use meshmorph::{MarkerSide, Markers, SurfacePoint};
use numpy::PyArray1;
use numpy::PyArrayMethods;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyModule};

use crate::{args, arrays, bad, error, work};

/// A mesh file as read: `.vertices` `(n, 3)`, `.faces` `(m, 3)` (polygons
/// split into triangles), and everything else of the file, kept for
/// `write_mesh`.
#[pyclass(name = "Mesh", module = "meshmorph", frozen)]
pub struct PyMesh {
    pub file: MeshFile,
}

#[pymethods]
impl PyMesh {
    /// Vertex positions, `(n, 3)` float64.
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::array(py, self.file.mesh().positions())
    }

    /// Triangles, `(m, 3)` int64 (polygons split as the file's order gives).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let flat: Vec<i64> = self
            .file
            .mesh()
            .triangles()
            .iter()
            .flatten()
            .map(|&v| v as i64)
            .collect();
        Ok(PyArray1::from_vec(py, flat)
            .reshape([self.file.mesh().num_triangles(), 3])?
            .into_any())
    }

    /// The file it was read from.
    #[getter]
    fn path(&self) -> PathBuf {
        self.file.path().to_path_buf()
    }

    fn __repr__(&self) -> String {
        format!(
            "<meshmorph.Mesh {} vertices, {} triangles from {:?}>",
            self.file.mesh().num_vertices(),
            self.file.mesh().num_triangles(),
            self.file.path()
        )
    }
}

/// Reads a mesh file (OBJ, OFF, PLY, STL, glTF/GLB).
#[pyfunction]
fn read_mesh(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<PyMesh> {
    let path = args::path("path", path)?;
    let file = work::run(py, || MeshFile::read(&path))?.map_err(error)?;
    Ok(PyMesh { file })
}

/// Writes `mesh` with new `vertices` `(n, 3)` to `path`, in the format its
/// extension names: in the file's own format everything but the positions
/// is kept; never over the file `mesh` was read from, nor over anything
/// but a regular file; atomically.
#[pyfunction]
fn write_mesh(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    mesh: &Bound<'_, PyAny>,
    vertices: &Bound<'_, PyAny>,
) -> PyResult<Vec<String>> {
    let path = args::output_path("path", path)?;
    let mesh = args::object::<PyMesh>("mesh", mesh, "a Mesh (read_mesh)")?.get();
    let positions = arrays::points_of::<3>("vertices", vertices)?;
    let n = mesh.file.mesh().num_vertices();
    if positions.len() != n {
        return Err(bad(
            "vertices",
            format!("{} vertices, the mesh has {n}", positions.len()),
        ));
    }
    not_the_input(&path, mesh.file.path())?;
    let format = meshmorph::io::Format::from_path(&path).map_err(|e| bad("path", e))?;
    work::run(py, || mesh.file.write(&path, &positions, format))?.map_err(|e| match e {
        // What the system says of the path (a missing folder, no room).
        meshmorph::Error::Io { .. } => bad("path", e),
        e => error(e),
    })
}

/// Refuses `path` (argument `path`) when it is the file `input`, from
/// which the mesh was read: meshmorph never writes over its inputs.
pub(crate) fn not_the_input(path: &std::path::Path, input: &std::path::Path) -> PyResult<()> {
    let same = match (std::fs::canonicalize(path), std::fs::canonicalize(input)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same {
        return Err(bad("path", format!("{} is the file the mesh was read from: meshmorph never writes over its inputs; choose another path", path.display())));
    }
    Ok(())
}

/// Marker pairs on two surfaces, with names.
#[pyclass(name = "Markers", module = "meshmorph", frozen)]
pub struct PyMarkers {
    pub markers: Markers,
}

fn point(py: Python<'_>, p: &MarkerSide) -> PyResult<Py<PyAny>> {
    let d = PyDict::new(py);
    match *p {
        MarkerSide::On(SurfacePoint::Vertex(v)) => d.set_item("vertex", v)?,
        MarkerSide::On(SurfacePoint::Triangle {
            triangle,
            barycentric,
        }) => {
            d.set_item("triangle", triangle)?;
            d.set_item("barycentric", barycentric.to_vec())?;
        }
        MarkerSide::At(position) => d.set_item("position", position.to_vec())?,
    }
    Ok(d.into_any().unbind())
}

#[pymethods]
impl PyMarkers {
    fn __len__(&self) -> usize {
        self.markers.len()
    }

    /// The pairs, each `(source, target)`, in the order given:
    /// `{"vertex": v}`, `{"triangle": t, "barycentric": [b0, b1, b2]}`, or
    /// `{"position": [x, y, z]}` for a point given as a position (put on
    /// the surface, the nearest point of it, by `correspond`).
    #[getter]
    fn pairs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let items = self
            .markers
            .entries()
            .iter()
            .map(|(_, [s, t])| Ok((point(py, s)?, point(py, t)?)))
            .collect::<PyResult<Vec<_>>>()?;
        PyList::new(py, items)
    }

    /// Each pair's name, or None.
    #[getter]
    fn names(&self) -> Vec<Option<String>> {
        self.markers
            .entries()
            .into_iter()
            .map(|(name, _)| name.map(str::to_string))
            .collect()
    }

    /// Markers from positions: row `k` of `source` `(k, 3)` paired with
    /// row `k` of `target`, put on the surfaces (the nearest point of
    /// each) by `correspond`; `names`, if given, one per pair.
    #[staticmethod]
    #[pyo3(signature = (source, target, names = None))]
    fn from_points(
        source: &Bound<'_, PyAny>,
        target: &Bound<'_, PyAny>,
        names: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let s = arrays::points_of::<3>("source", source)?;
        let t = arrays::points_of::<3>("target", target)?;
        if s.len() != t.len() {
            return Err(bad(
                "target",
                format!("{} points for the source's {}", t.len(), s.len()),
            ));
        }
        let names = names
            .filter(|n| !n.is_none())
            .map(|n| {
                arrays::items(
                    "names",
                    n,
                    ("a list of names (str or None)", 0),
                    |name, x| {
                        x.extract::<Option<String>>().map_err(|_| {
                            bad(
                                name,
                                format!("expected a str or None, got {}", args::describe(x)),
                            )
                        })
                    },
                )
            })
            .transpose()?;
        let markers = Markers::from_points(s.into_iter().zip(t).map(|(a, b)| [a, b]).collect());
        let markers = match names {
            None => markers,
            Some(n) if n.len() == markers.len() => markers.with_names(n),
            Some(n) => {
                return Err(bad(
                    "names",
                    format!("{} names for {} pairs", n.len(), markers.len()),
                ))
            }
        };
        Ok(PyMarkers { markers })
    }

    /// Writes meshmorph's marker file (names and surface points).
    fn save(&self, path: &Bound<'_, PyAny>) -> PyResult<()> {
        let path = args::output_path("path", path)?;
        self.markers.save(&path).map_err(error)
    }
}

/// Reads markers: one file of pairs (meshmorph's format, `.cons`), or with
/// `target_path` two files of points paired by name or order (MeshLab's
/// `.pp`, Wrap's `.json`, one point a line).
#[pyfunction]
#[pyo3(signature = (path, target_path = None, *, one_based = None))]
#[pyo3(text_signature = "(path, target_path=None, *, one_based=False)")]
fn read_markers(
    path: &Bound<'_, PyAny>,
    target_path: Option<&Bound<'_, PyAny>>,
    one_based: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyMarkers> {
    let path = args::path("path", path)?;
    let target_path = args::optional_path("target_path", target_path)?;
    let numbering = args::numbering(one_based)?;
    let markers = match target_path {
        None => Markers::read(&path, numbering),
        Some(t) => Markers::read_pair(&path, &t, numbering),
    }
    .map_err(error)?;
    Ok(PyMarkers { markers })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyMesh>()?;
    m.add_class::<PyMarkers>()?;
    m.add_function(wrap_pyfunction!(read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(write_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(read_markers, m)?)?;
    Ok(())
}
