//! glTF files (`.glb`, `.gltf`, `.vrm`): `read_gltf` reads one mesh of a
//! user's file as arrays (its vertices, triangles and morph targets) and
//! keeps the whole file; `write_gltf` writes a copy of that file with new
//! shapes added as morph targets of that mesh, everything else kept, as
//! the command line's `transfer --gltf` does.

use meshmorph::io::gltf::ShapeKeyOptions;
use meshmorph::io::gltf::{read, write_shape_keys, GltfDocument, GltfMesh, NewShape};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyModule};

use crate::{args, arrays, bad, error, work, MeshmorphError};

/// One mesh of a glTF file as read, and the whole file kept for
/// `write_gltf`: `.vertices` `(n, 3)` (every triangle primitive's vertices
/// side by side, in the mesh's own space: the bind pose of a skinned
/// mesh), `.faces` `(m, 3)`, `.targets` (each morph target's positions,
/// by name).
#[pyclass(name = "Gltf", module = "meshmorph", frozen)]
pub struct PyGltf {
    doc: GltfDocument,
    mesh: GltfMesh,
}

#[pymethods]
impl PyGltf {
    /// Vertex positions, `(n, 3)` float64: every primitive's own vertices
    /// (copies at seams and between primitives are not welded: `welded()`
    /// welds them).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::array(py, self.mesh.surface.positions())
    }

    /// Triangles, `(m, 3)` int64, primitive after primitive.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        triangles(py, self.mesh.surface.triangles())
    }

    /// The morph targets, in the file's order: name to positions `(n, 3)`
    /// (the vertices moved by the target at weight 1).
    #[getter]
    fn targets<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for t in &self.mesh.targets {
            d.set_item(&t.name, arrays::array(py, &t.positions)?)?;
        }
        Ok(d)
    }

    /// The mesh's name.
    #[getter]
    fn mesh_name(&self) -> &str {
        &self.mesh.name
    }

    /// Whether the mesh has a skin (then `vertices` is its bind pose).
    #[getter]
    fn skinned(&self) -> bool {
        self.mesh.skinned
    }

    /// The `(4, 4)` matrix that places the mesh in the scene (its node's,
    /// parents included; the identity for a skinned mesh).
    #[getter]
    fn transform<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let m = &self.mesh.transform;
        let rows: Vec<[f64; 4]> = (0..4)
            .map(|r| std::array::from_fn(|c| m[4 * c + r]))
            .collect();
        arrays::array(py, &rows)
    }

    /// What the reader chose and says (the file's other meshes, when it
    /// chose one).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.mesh.notes.clone()
    }

    /// The file it was read from.
    #[getter]
    fn path(&self) -> std::path::PathBuf {
        self.doc.path().to_path_buf()
    }

    /// The mesh with copies of one vertex (at seams, between primitives)
    /// welded, as a transfer solves on it: `(vertices (w, 3), faces (m,
    /// 3), index (n,))`, where `index[i]` is the welded vertex of vertex
    /// `i` (so `welded_positions[index]` gives positions for `write_gltf`).
    fn welded<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let (seams, mesh) = self.mesh.welded();
        let index: Vec<i64> = (0..self.mesh.surface.num_vertices() as u32)
            .map(|v| i64::from(seams.welded(v)))
            .collect();
        Ok((
            arrays::array(py, mesh.positions())?,
            triangles(py, mesh.triangles())?,
            PyArray1::from_vec(py, index).into_any(),
        ))
    }

    fn __repr__(&self) -> String {
        format!(
            "<meshmorph.Gltf mesh {:?}: {} vertices, {} triangles, {} morph targets from {:?}>",
            self.mesh.name,
            self.mesh.surface.num_vertices(),
            self.mesh.surface.num_triangles(),
            self.mesh.targets.len(),
            self.doc.path()
        )
    }
}

/// `(m, 3)` int64 of triangles.
fn triangles<'py>(py: Python<'py>, t: &[[u32; 3]]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<i64> = t.iter().flatten().map(|&v| i64::from(v)).collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([t.len(), 3])?
        .into_any())
}

/// Reads a mesh of a glTF file (`.glb`, `.gltf` with its files beside
/// it, `.vrm`): the one `mesh` names (a mesh's or a node's name), else
/// the only one, else the one with the most vertices.
#[pyfunction]
#[pyo3(signature = (path, mesh = None))]
fn read_gltf(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    mesh: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyGltf> {
    let path = args::path("path", path)?;
    let choice = match mesh.filter(|m| !m.is_none()) {
        None => None,
        Some(m) => Some(m.extract::<String>().map_err(|_| {
            bad(
                "mesh",
                format!(
                    "expected a mesh's or node's name (str), got {}",
                    args::describe(m)
                ),
            )
        })?),
    };
    let (doc, mesh) = work::run(py, || read(&path, choice.as_deref()))?.map_err(error)?;
    Ok(PyGltf { doc, mesh })
}

/// Writes a copy of the file `gltf` was read from to `path`, with `shapes`
/// (a dict: name to positions `(n, 3)` of `gltf.vertices`) added to its
/// mesh as morph targets after its own, everything else kept; in the
/// file's own kind (a GLB or VRM stays binary, a `.gltf` stays text and
/// belongs beside the files it names). A name the mesh has is refused
/// unless `replace`; `vrm_expressions` also adds each as a VRM custom
/// expression. Never over the file `gltf` was read from; atomically.
#[pyfunction]
#[pyo3(signature = (path, gltf, shapes, *, replace = None, vrm_expressions = None))]
#[pyo3(text_signature = "(path, gltf, shapes, *, replace=False, vrm_expressions=False)")]
fn write_gltf(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    gltf: &Bound<'_, PyAny>,
    shapes: &Bound<'_, PyAny>,
    replace: Option<&Bound<'_, PyAny>>,
    vrm_expressions: Option<&Bound<'_, PyAny>>,
) -> PyResult<()> {
    let path = args::output_path("path", path)?;
    let gltf = args::object::<PyGltf>("gltf", gltf, "a Gltf (read_gltf)")?.get();
    let options = ShapeKeyOptions::default()
        .with_replace(args::flag("replace", replace, false)?)
        .with_vrm_expressions(args::flag("vrm_expressions", vrm_expressions, false)?);
    let dict = shapes.cast::<PyDict>().map_err(|_| {
        bad(
            "shapes",
            format!(
                "expected a dict of name to (n, 3) positions, got {}",
                args::describe(shapes)
            ),
        )
    })?;
    let n = gltf.mesh.surface.num_vertices();
    let mut named = Vec::with_capacity(dict.len());
    for (name, positions) in dict.iter() {
        let name: String = name.extract().map_err(|_| {
            bad(
                "shapes",
                format!("a key is {}, not a name (str)", args::describe(&name)),
            )
        })?;
        let arg = format!("shapes[{name:?}]");
        let positions = arrays::points_of::<3>(&arg, &positions)?;
        if positions.len() != n {
            return Err(bad(
                &arg,
                format!(
                    "{} vertices, mesh `{}` has {n}",
                    positions.len(),
                    gltf.mesh.name
                ),
            ));
        }
        named.push((name, positions));
    }
    crate::files::not_the_input(&path, gltf.doc.path())?;
    let new: Vec<NewShape<'_>> = named
        .iter()
        .map(|(name, positions)| NewShape { name, positions })
        .collect();
    work::run(py, || {
        write_shape_keys(&path, &gltf.doc, &gltf.mesh, &new, &options)
    })?
    .map_err(|e| match e {
        meshmorph::Error::Io { .. } => bad("path", e),
        // The library names the command line's options; here they are
        // this function's arguments.
        e => MeshmorphError::new_err(
            e.to_string()
                .replace("pass --replace-shapes", "pass replace=True")
                .replace("--vrm-expressions", "vrm_expressions=True"),
        ),
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyGltf>()?;
    m.add_function(wrap_pyfunction!(read_gltf, m)?)?;
    m.add_function(wrap_pyfunction!(write_gltf, m)?)?;
    Ok(())
}
