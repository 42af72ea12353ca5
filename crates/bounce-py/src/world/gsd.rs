//! `bounce.GSDWriter`: a GSD trajectory (HOOMD-blue's format) fed by `World.step`, the
//! CLI's writer underneath.

use std::path::PathBuf;

use bounce::World as RustWorld;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

/// A GSD trajectory file, read by the ``gsd`` package, freud and OVITO like the CLI's.
///
/// ``GSDWriter(path, every=1)``; attach it with ``world.add_writer(writer)``: it takes a
/// frame then (when ``every`` divides the step count) and after each step whose count
/// ``every`` divides. ``write(world)`` adds a frame by hand. The file appears, complete,
/// when the writer is closed (``close()``, the end of its ``with`` block, or when it is
/// garbage-collected); until then it is written under a temporary name.
#[pyclass(module = "bounce", name = "GSDWriter")]
pub struct GsdWriter {
    path: PathBuf,
    pub(crate) every: u64,
    /// Opened at the first frame (the types come from the first world written).
    file: Option<bounce_scenario::gsd::GsdWriter>,
    closed: bool,
}

impl GsdWriter {
    pub(crate) fn is_closed(&self) -> bool {
        self.closed
    }

    pub(crate) fn frame(
        &mut self,
        world: &RustWorld,
        types: &[String],
        typeid: &[u32],
    ) -> PyResult<()> {
        if self.closed {
            return Err(PyRuntimeError::new_err(format!(
                "GSD writer {} is closed",
                self.path.display()
            )));
        }
        if self.file.is_none() {
            self.file = Some(bounce_scenario::gsd::GsdWriter::create(
                &self.path, types, typeid,
            )?);
        }
        let file = self.file.as_mut().expect("opened above");
        // Discs added since (by emitters) have their types by now.
        for (id, &t) in typeid.iter().enumerate() {
            file.set_type(id, t);
        }
        Ok(file.frame(world)?)
    }
}

#[pymethods]
impl GsdWriter {
    #[new]
    #[pyo3(signature = (path, every = 1))]
    fn new(path: PathBuf, every: u64) -> PyResult<Self> {
        if every == 0 {
            return Err(PyValueError::new_err("every = 0: must be at least 1"));
        }
        Ok(GsdWriter {
            path,
            every,
            file: None,
            closed: false,
        })
    }

    /// The file's path.
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// The period in steps.
    #[getter]
    fn every(&self) -> u64 {
        self.every
    }

    /// Appends ``world``'s current state as a frame.
    fn write(&mut self, world: PyRef<'_, super::World>) -> PyResult<()> {
        self.frame(&world.get(), &world.types, &world.typeid)
    }

    /// Completes the file (index and header) and moves it into place. A writer that took
    /// no frame writes no file.
    fn close(&mut self) -> PyResult<()> {
        self.closed = true;
        match self.file.take() {
            Some(file) => Ok(file.finish()?),
            None => Ok(()),
        }
    }

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    #[pyo3(signature = (*_args))]
    fn __exit__(&mut self, _args: &Bound<'_, pyo3::types::PyTuple>) -> PyResult<bool> {
        self.close()?;
        Ok(false)
    }
}

impl Drop for GsdWriter {
    fn drop(&mut self) {
        // A writer dropped open still completes its file (errors have no one to go to).
        if let Some(file) = self.file.take() {
            let _ = file.finish();
        }
    }
}
