//! A caller's `progress(done, total)` callback, called from the threads of
//! work that runs without the GIL: the GIL is taken for each call, and the
//! first exception the callback raises is kept and raised once the work is
//! done (the work itself goes on).

use std::sync::Mutex;

use pyo3::prelude::*;

pub struct Progress {
    callback: Option<Py<PyAny>>,
    failed: Mutex<Option<PyErr>>,
}

impl Progress {
    pub fn new(callback: Option<Py<PyAny>>) -> Self {
        Self {
            callback,
            failed: Mutex::new(None),
        }
    }

    /// Calls the callback, if any, with `(done, total)`.
    pub fn report(&self, done: usize, total: usize) {
        if let Some(callback) = &self.callback {
            Python::attach(|py| {
                if let Err(e) = callback.call1(py, (done, total)) {
                    self.failed
                        .lock()
                        .unwrap_or_else(|p| p.into_inner())
                        .get_or_insert(e);
                }
            });
        }
    }

    /// The first exception the callback raised, if any.
    pub fn finish(self) -> PyResult<()> {
        match self.failed.into_inner().unwrap_or_else(|p| p.into_inner()) {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}
