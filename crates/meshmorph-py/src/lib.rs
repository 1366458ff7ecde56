//! meshmorph for Python: as-rigid-as-possible shape interpolation and
//! deformation transfer on numpy arrays, factored once, the GIL released
//! while the work runs, and drawings made into compatible meshes for it. A thin layer over the Rust library: arrays in
//! (`arrays.rs`, their sizes checked before any copy) and other arguments
//! (`args.rs`), the library's objects held, the work run on the module's
//! own threads and stopped by Ctrl-C (`work.rs`), arrays out.

mod args;
mod arrays;
mod expressions;
mod files;
mod gltf;
mod gradients;
mod interpolation;
mod outline;
mod pictures;
mod progress;
mod transfer;
mod work;

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

create_exception!(
    meshmorph,
    MeshmorphError,
    PyValueError,
    "A meshmorph error: bad input (its message names the argument and the element) or a failure of the work. A subclass of ValueError."
);

/// The library's error as a Python exception.
pub(crate) fn error(e: meshmorph::Error) -> PyErr {
    MeshmorphError::new_err(e.to_string())
}

/// An error about the argument `arg`.
pub(crate) fn bad(arg: &str, message: impl std::fmt::Display) -> PyErr {
    MeshmorphError::new_err(format!("{arg}: {message}"))
}

/// As-rigid-as-possible shape interpolation and deformation transfer on
/// triangle meshes: numpy arrays in and out.
#[pymodule(name = "meshmorph")]
fn meshmorph_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("MeshmorphError", m.py().get_type::<MeshmorphError>())?;
    interpolation::register(m)?;
    transfer::register(m)?;
    files::register(m)?;
    gltf::register(m)?;
    gradients::register(m)?;
    outline::register(m)?;
    pictures::register(m)?;
    expressions::register(m)?;
    Ok(())
}
