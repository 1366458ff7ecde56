//! `expressions`: a template's facial expressions (the 52 ARKit shapes of
//! the built-in template) put on a head from named landmarks.

use meshmorph::{CarryMethod, ExpressionOptions, ExpressionTemplate};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyModule, PyTuple};

use crate::arrays::{self, describe};
use crate::{args, bad, error, work};

/// The landmarks: a dict `{name: (x, y, z)}` or a sequence of `(name,
/// (x, y, z))` pairs.
fn landmarks(a: &Bound<'_, PyAny>) -> PyResult<Vec<(String, [f64; 3])>> {
    let expected = "a dict {name: (x, y, z)} or a list of (name, (x, y, z)) pairs";
    let pairs: Vec<(Bound<'_, PyAny>, Bound<'_, PyAny>)> = if let Ok(d) = a.cast::<PyDict>() {
        d.iter().collect()
    } else if a.is_instance_of::<pyo3::types::PyString>() {
        return Err(bad(
            "landmarks",
            format!("expected {expected}, got {}", describe(a)),
        ));
    } else {
        let items = a.try_iter().map_err(|_| {
            bad(
                "landmarks",
                format!("expected {expected}, got {}", describe(a)),
            )
        })?;
        items
            .enumerate()
            .map(|(k, item)| {
                let item = item?;
                let pair = item
                    .cast::<PyTuple>()
                    .ok()
                    .filter(|t| t.len() == 2)
                    .ok_or_else(|| {
                        bad(
                            &format!("landmarks[{k}]"),
                            format!("expected a (name, (x, y, z)) pair, got {}", describe(&item)),
                        )
                    })?;
                Ok((pair.get_item(0)?, pair.get_item(1)?))
            })
            .collect::<PyResult<_>>()?
    };
    pairs
        .into_iter()
        .enumerate()
        .map(|(k, (name, point))| {
            let name: String = name.extract().map_err(|_| {
                bad(
                    &format!("landmarks[{k}]"),
                    format!("a landmark's name must be a str, got {}", describe(&name)),
                )
            })?;
            let arg = format!("landmarks[{name:?}]");
            let xyz: Vec<f64> = point.extract().map_err(|_| {
                bad(
                    &arg,
                    format!("expected (x, y, z), got {}", describe(&point)),
                )
            })?;
            let [x, y, z] = xyz[..] else {
                return Err(bad(
                    &arg,
                    format!("expected 3 coordinates, got {}", xyz.len()),
                ));
            };
            for c in [x, y, z] {
                arrays::finite(&arg, c)?;
            }
            Ok((name, [x, y, z]))
        })
        .collect()
}

/// The 52 ARKit expressions (those the template has) put on a head.
///
/// `vertices` `(n, 3)` and `faces` `(m, 3)`: the head at rest (separate
/// pieces such as eyes and teeth are found and moved rigidly).
/// `landmarks`: points on the head named by their landmark (iBUG 300-W
/// number "1" to "68", or an alias such as "noseTip", "eyeOuterLeft",
/// "mouthCornerRight"; left and right the head's own), 12 or more, as a
/// dict `{name: (x, y, z)}` or a list of `(name, (x, y, z))`.
/// `method`: "displacements" (the default, the template's moves copied)
/// or "transfer" (deformation transfer). `compare`: also carry every
/// shape the other way and report where they differ. `all_shapes`: keep
/// the template's shapes beyond ARKit's 52. `template`: None for the
/// built-in template (ICT-FaceKit, MIT licence) or the path of a rig's GLB.
///
/// Returns a dict: "names" (the shapes' names), "deltas" (a `(k, n, 3)`
/// float64 array, each shape's move of every vertex, exactly zero where
/// the template is still), "missing" (ARKit names the template lacks),
/// "warnings", "report" (per shape: "name", "moved", "largest" over the
/// bounding-box diagonal, "methods_differ") and "parts" (each separate
/// piece's "vertices" and the template part it "follows"). The GIL is
/// released during the work.
#[pyfunction]
#[pyo3(signature = (vertices, faces, landmarks, *, method=None, compare=None, all_shapes=None, template=None))]
#[allow(clippy::too_many_arguments)]
fn expressions<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    landmarks: &Bound<'py, PyAny>,
    method: Option<&Bound<'py, PyAny>>,
    compare: Option<&Bound<'py, PyAny>>,
    all_shapes: Option<&Bound<'py, PyAny>>,
    template: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let positions = arrays::points_of::<3>("vertices", vertices)?;
    let triangles = arrays::faces("faces", faces)?;
    let points = self::landmarks(landmarks)?;
    let method = match args::choice(
        "method",
        method,
        &["displacements", "transfer"],
        "displacements",
    )? {
        "transfer" => CarryMethod::Transfer,
        _ => CarryMethod::Displacements,
    };
    let options = ExpressionOptions::default()
        .with_method(method)
        .with_compare(args::flag("compare", compare, false)?)
        .with_all_shapes(args::flag("all_shapes", all_shapes, false)?);
    let template = match args::optional_path("template", template)? {
        None => ExpressionTemplate::arkit(),
        Some(path) => {
            let bytes = std::fs::read(&path)
                .map_err(|e| bad("template", format!("reading `{}`: {e}", path.display())))?;
            ExpressionTemplate::from_glb(&bytes, &path.display().to_string()).map_err(error)?
        }
    };
    arrays::setup("faces", triangles.len())?;
    let head = arrays::mesh::<3>(py, ("vertices", "faces"), positions, triangles)?;
    let made = work::run(py, || {
        meshmorph::expressions(&template, &head, &points, &options)
    })?
    .map_err(error)?;

    let n = head.num_vertices();
    let flat: Vec<f64> = made.deltas.iter().flatten().flatten().copied().collect();
    let deltas = PyArray1::from_vec(py, flat).reshape([made.deltas.len(), n, 3])?;
    let out = PyDict::new(py);
    out.set_item("names", PyList::new(py, &made.names)?)?;
    out.set_item("deltas", deltas)?;
    out.set_item("missing", PyList::new(py, &made.missing)?)?;
    out.set_item("warnings", PyList::new(py, &made.warnings)?)?;
    let report = PyList::empty(py);
    for r in &made.report {
        let line = PyDict::new(py);
        line.set_item("name", &r.name)?;
        line.set_item("moved", r.moved)?;
        line.set_item("largest", r.largest)?;
        line.set_item("methods_differ", r.methods_differ)?;
        report.append(line)?;
    }
    out.set_item("report", report)?;
    let parts = PyList::empty(py);
    for p in &made.parts {
        let part = PyDict::new(py);
        part.set_item("vertices", p.vertices)?;
        part.set_item("follows", &p.follows)?;
        parts.append(part)?;
    }
    out.set_item("parts", parts)?;
    Ok(out)
}

/// The built-in template's neutral head (ICT-FaceKit, MIT licence), to
/// see where its landmarks lie: a dict of "vertices" `(n, 3)` (metres),
/// "faces" `(m, 3)`, "landmarks" (`{name: vertex}` by iBUG number, "1" to
/// "68") and "shapes" (the template's own shape names).
#[pyfunction]
fn arkit_template(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let t = ExpressionTemplate::arkit();
    let out = PyDict::new(py);
    out.set_item("vertices", arrays::array(py, t.head.positions())?)?;
    let faces: Vec<u32> = t.head.triangles().iter().flatten().copied().collect();
    out.set_item(
        "faces",
        PyArray1::from_vec(py, faces).reshape([t.head.num_triangles(), 3])?,
    )?;
    let landmarks = PyDict::new(py);
    for (name, v) in &t.landmarks {
        landmarks.set_item(name, v)?;
    }
    out.set_item("landmarks", landmarks)?;
    out.set_item("shapes", PyList::new(py, &t.shape_names)?)?;
    Ok(out)
}

/// Reads a file of named landmarks on a head (MeshLab's `.pp`, Wrap's
/// `.json`, or lines of `name x y z` / `name v VERTEX`): a list of `(name,
/// (x, y, z))` in the file's order, as `expressions` takes them. Points
/// given by vertex or triangle are placed on `vertices` and `faces`.
#[pyfunction]
#[pyo3(signature = (path, vertices, faces, *, one_based=None))]
fn read_landmarks<'py>(
    py: Python<'py>,
    path: &Bound<'py, PyAny>,
    vertices: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    one_based: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyList>> {
    let path = args::path("path", path)?;
    let numbering = args::numbering(one_based)?;
    let positions = arrays::points_of::<3>("vertices", vertices)?;
    let triangles = arrays::faces("faces", faces)?;
    let head = arrays::mesh::<3>(py, ("vertices", "faces"), positions, triangles)?;
    let points = meshmorph::read_landmarks(&path, &head, numbering).map_err(error)?;
    let out = PyList::empty(py);
    for (name, p) in points {
        out.append((name, (p[0], p[1], p[2])))?;
    }
    Ok(out)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(expressions, m)?)?;
    m.add_function(wrap_pyfunction!(read_landmarks, m)?)?;
    m.add_function(wrap_pyfunction!(arkit_template, m)?)?;
    Ok(())
}
