//! Arguments that are not arrays: flags, whole numbers, numbers, words,
//! paths, callbacks and the module's own objects, each taken as whatever
//! Python gives and refused, naming the argument and saying what it is
//! and what was expected, as arrays are (`arrays.rs`).

use std::path::PathBuf;

use pyo3::exceptions::PyOverflowError;
use pyo3::prelude::*;
use pyo3::types::PyString;

use crate::{arrays, bad};

/// What `v` is, for messages: `'abc' (a str)`, `2.5 (a float)`, or the
/// array's shape and dtype.
pub fn describe(v: &Bound<'_, PyAny>) -> String {
    if v.getattr("shape").is_ok() {
        return arrays::describe(v);
    }
    let kind = v
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_default();
    let article = if kind.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    };
    match v.repr() {
        Ok(r) if r.to_string().chars().count() <= 40 => format!("{r} ({article} {kind})"),
        _ => format!("{article} {kind}"),
    }
}

/// True or False (numpy's bools too); `default` for None.
pub fn flag(arg: &str, v: Option<&Bound<'_, PyAny>>, default: bool) -> PyResult<bool> {
    match v {
        Some(v) if !v.is_none() => v
            .extract::<bool>()
            .map_err(|_| bad(arg, format!("expected True or False, got {}", describe(v)))),
        _ => Ok(default),
    }
}

/// How vertex indices in a file are numbered: from 1 with `one_based`
/// True, else from 0.
pub fn numbering(v: Option<&Bound<'_, PyAny>>) -> PyResult<meshmorph::VertexNumbering> {
    Ok(if flag("one_based", v, false)? {
        meshmorph::VertexNumbering::FromOne
    } else {
        meshmorph::VertexNumbering::FromZero
    })
}

/// A whole number that fits an `i32`; `default` for None.
pub fn whole(arg: &str, v: Option<&Bound<'_, PyAny>>, default: i32) -> PyResult<i32> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(default);
    };
    v.extract::<i32>().map_err(|e| {
        if e.is_instance_of::<PyOverflowError>(v.py()) {
            bad(
                arg,
                format!(
                    "{} is out of range: expected a whole number from {} to {}",
                    describe(v),
                    i32::MIN,
                    i32::MAX
                ),
            )
        } else {
            bad(arg, format!("expected a whole number, got {}", describe(v)))
        }
    })
}

/// A finite number (an int, a float or a numpy scalar).
pub fn number(arg: &str, v: &Bound<'_, PyAny>) -> PyResult<f64> {
    if v.is_instance_of::<PyString>() {
        return Err(bad(arg, format!("expected a number, got {}", describe(v))));
    }
    let x = v
        .extract::<f64>()
        .map_err(|_| bad(arg, format!("expected a number, got {}", describe(v))))?;
    arrays::finite(arg, x)
}

/// A finite number, or None.
pub fn optional_number(arg: &str, v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<f64>> {
    v.filter(|v| !v.is_none())
        .map(|v| number(arg, v))
        .transpose()
}

/// One of the words `choices`; `default` for None.
pub fn choice(
    arg: &str,
    v: Option<&Bound<'_, PyAny>>,
    choices: &[&'static str],
    default: &'static str,
) -> PyResult<&'static str> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(default);
    };
    let given = v.extract::<String>().ok();
    choices
        .iter()
        .find(|c| given.as_deref() == Some(**c))
        .copied()
        .ok_or_else(|| {
            let listed: Vec<String> = choices.iter().map(|c| format!("{c:?}")).collect();
            bad(
                arg,
                format!("expected {}, got {}", listed.join(" or "), describe(v)),
            )
        })
}

/// A path: a str, bytes or an `os.PathLike`.
pub fn path(arg: &str, v: &Bound<'_, PyAny>) -> PyResult<PathBuf> {
    v.extract::<PathBuf>().map_err(|_| {
        bad(
            arg,
            format!(
                "expected a path (a str or an os.PathLike), got {}",
                describe(v)
            ),
        )
    })
}

/// A path, or None.
pub fn optional_path(arg: &str, v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<PathBuf>> {
    v.filter(|v| !v.is_none()).map(|v| path(arg, v)).transpose()
}

/// A path to write: refused, naming it, when it exists and is not a
/// regular file (links followed): a device, a FIFO or a folder would be
/// replaced by a regular file, or wait for a reader.
pub fn output_path(arg: &str, v: &Bound<'_, PyAny>) -> PyResult<PathBuf> {
    let path = path(arg, v)?;
    meshmorph::io::refuse_unless_replaceable(&path).map_err(|e| bad(arg, e))?;
    Ok(path)
}

/// A callable `progress(done, total)`, or None.
pub fn callback(arg: &str, v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Py<PyAny>>> {
    match v {
        Some(v) if !v.is_none() => {
            if v.is_callable() {
                Ok(Some(v.clone().unbind()))
            } else {
                Err(bad(
                    arg,
                    format!(
                        "expected a callable {arg}(done, total) or None, got {}",
                        describe(v)
                    ),
                ))
            }
        }
        _ => Ok(None),
    }
}

/// One of the module's objects, `what` naming where it comes from.
pub fn object<'a, 'py, T: pyo3::PyClass>(
    arg: &str,
    v: &'a Bound<'py, PyAny>,
    what: &str,
) -> PyResult<&'a Bound<'py, T>> {
    v.cast::<T>()
        .map_err(|_| bad(arg, format!("expected {what}, got {}", describe(v))))
}
