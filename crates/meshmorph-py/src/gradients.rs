//! The gradient-domain solve on its own: positions whose triangles take
//! given linear maps (per-triangle Jacobians), as pipelines that predict
//! Jacobians need (Neural Jacobian Fields and its followers solve this
//! Poisson system), factored once for repeated calls.

use meshmorph::{FactorKind, Mat, RestSystem, Space, TriangleMaps};
use numpy::ndarray::Array3;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyModule;

use crate::arrays::{self, Points};
use crate::{bad, error, work};

/// The rest mesh's system, of either dimension.
enum System {
    Plane(RestSystem<2>),
    Space(RestSystem<3>),
}

/// Maps `(m, D, D)` float64 or float32, each row-major (`J @ x` maps a
/// rest edge `x` to a deformed one).
fn maps<const D: usize>(arg: &str, a: &Bound<'_, PyAny>, m: usize) -> PyResult<Vec<Mat<D>>> {
    let wrong = || {
        bad(
            arg,
            format!(
                "expected a ({m}, {D}, {D}) float64 or float32 numpy array, got {}",
                arrays::describe(a)
            ),
        )
    };
    let read =
        |shape: &[usize], at: &dyn Fn(usize, usize, usize) -> f64| -> PyResult<Vec<Mat<D>>> {
            if shape != [m, D, D] {
                return Err(bad(
                    arg,
                    format!("expected the shape ({m}, {D}, {D}), got {shape:?}"),
                ));
            }
            let mut out = arrays::room(arg, "the copy of the maps", m)?;
            for t in 0..m {
                let j: Mat<D> = std::array::from_fn(|r| std::array::from_fn(|c| at(t, r, c)));
                if j.iter().flatten().any(|x| !x.is_finite()) {
                    return Err(bad(
                        arg,
                        format!("the map of triangle {t} has an entry that is not finite"),
                    ));
                }
                out.push(j);
            }
            Ok(out)
        };
    arrays::read_3d(a, read).unwrap_or_else(|| Err(wrong()))
}

/// Positions from per-triangle linear maps on a rest mesh `(n, d)`, faces
/// `(m, 3)`: the least-squares fit (weighted by area) of every triangle to
/// its map, each connected part placed at `centroids` (default: the rest
/// mesh's). Factored once; `solve(J)` is a back-substitution.
#[pyclass(name = "GradientSolver", module = "meshmorph", frozen)]
pub struct PyGradientSolver {
    system: System,
    triangles: usize,
}

#[pymethods]
impl PyGradientSolver {
    #[new]
    fn new(py: Python<'_>, v_rest: &Bound<'_, PyAny>, f: &Bound<'_, PyAny>) -> PyResult<Self> {
        let faces = arrays::faces("f", f)?;
        let triangles = faces.len();
        arrays::setup("f", triangles)?;
        let system = match arrays::points("v_rest", v_rest)? {
            Points::Plane(p) => {
                let mesh = arrays::mesh(py, ("v_rest", "f"), p, faces)?;
                System::Plane(
                    work::run(py, || RestSystem::new(&mesh, FactorKind::Auto))?.map_err(error)?,
                )
            }
            Points::Space(p) => {
                let mesh = arrays::mesh(py, ("v_rest", "f"), p, faces)?;
                System::Space(
                    work::run(py, || RestSystem::new(&mesh, FactorKind::Auto))?.map_err(error)?,
                )
            }
        };
        Ok(Self { system, triangles })
    }

    /// The positions `(n, d)` whose triangles best take the maps `j`
    /// `(m, d, d)`; each connected part centred at the rest mesh's centroid
    /// of it, or at `centroids` `(parts, d)`.
    #[pyo3(signature = (j, *, centroids = None))]
    fn solve<'py>(
        &self,
        py: Python<'py>,
        j: &Bound<'py, PyAny>,
        centroids: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        macro_rules! run {
            ($s:expr, $d:literal) => {{
                let maps = maps::<$d>("j", j, self.triangles)?;
                let centres = match centroids {
                    Some(c) => {
                        let c = arrays::points_of::<$d>("centroids", c)?;
                        if c.len() != $s.num_components() {
                            return Err(bad(
                                "centroids",
                                format!(
                                    "{} centroids, the mesh has {} parts",
                                    c.len(),
                                    $s.num_components()
                                ),
                            ));
                        }
                        c
                    }
                    None => $s.centroids($s.source().positions()),
                };
                let out = py.detach(|| {
                    let mut out = $s.source().positions().to_vec();
                    $s.solve_into(|t| maps[t], &centres, &mut out, &mut $s.workspace());
                    out
                });
                arrays::array(py, &out)
            }};
        }
        match &self.system {
            System::Plane(s) => run!(s, 2),
            System::Space(s) => run!(s, 3),
        }
    }
}

/// `GradientSolver(v_rest, f).solve(j)` once.
#[pyfunction]
fn positions_from_gradients<'py>(
    py: Python<'py>,
    v_rest: &Bound<'py, PyAny>,
    f: &Bound<'py, PyAny>,
    j: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    PyGradientSolver::new(py, v_rest, f)?.solve(py, j, None)
}

/// The linear map of every triangle of `rest` (with `faces`) to `v`,
/// `(m, D, D)`.
fn linear_maps<const D: usize>(
    py: Python<'_>,
    rest: Vec<[f64; D]>,
    faces: Vec<[u32; 3]>,
    v: &Bound<'_, PyAny>,
) -> PyResult<Array3<f64>>
where
    Space<D>: TriangleMaps<D>,
{
    arrays::need(
        "f",
        &format!("the maps of its {} triangles", faces.len()),
        arrays::bytes_of::<[[f64; D]; D]>(&[faces.len()]),
    )?;
    let rest = arrays::mesh(py, ("v_rest", "f"), rest, faces)?;
    let posed = arrays::points_of::<D>("v", v)?;
    if posed.len() != rest.num_vertices() {
        return Err(bad(
            "v",
            format!(
                "{} vertices, v_rest has {}",
                posed.len(),
                rest.num_vertices()
            ),
        ));
    }
    let mut out = Array3::zeros((rest.num_triangles(), D, D));
    for (t, tri) in rest.triangles().iter().enumerate() {
        let r: [[f64; D]; 3] = tri.map(|v| rest.positions()[v as usize]);
        let p: [[f64; D]; 3] = tri.map(|v| posed[v as usize]);
        let g = Space::<D>::hat_gradients(&r, Space::<D>::area(&r));
        let m = Space::<D>::linear_map(&r, &g, &p);
        for i in 0..D {
            for k in 0..D {
                out[[t, i, k]] = m[i][k];
            }
        }
    }
    Ok(out)
}

/// The linear map of every triangle from `v_rest` to `v` (same faces
/// `f`): `(m, d, d)`, the `j` that `positions_from_gradients` takes back
/// to `v` (up to each part's place).
#[pyfunction]
fn deformation_gradients<'py>(
    py: Python<'py>,
    v_rest: &Bound<'py, PyAny>,
    f: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let faces = arrays::faces("f", f)?;
    let out = match arrays::points("v_rest", v_rest)? {
        Points::Plane(p) => linear_maps(py, p, faces, v)?,
        Points::Space(p) => linear_maps(py, p, faces, v)?,
    };
    Ok(out.into_pyarray(py).into_any())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyGradientSolver>()?;
    m.add_function(wrap_pyfunction!(positions_from_gradients, m)?)?;
    m.add_function(wrap_pyfunction!(deformation_gradients, m)?)?;
    Ok(())
}
