//! `rdf`, `psi6` and `msd`: the structure of a GSD trajectory's frames, as
//! `bounce analyze` computes it (`bounce_scenario::structure`), as NumPy arrays.

use std::path::{Path, PathBuf};

use bounce_scenario::structure::{self, Edges, Snapshot};
use bounce_scenario::trajectory::Trajectory;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyFileNotFoundError, PyValueError};
use pyo3::prelude::*;

type Curve<'py, X> = (Bound<'py, PyArray1<X>>, Bound<'py, PyArray1<f64>>);

/// The frames of `path` from `first`, with the box's edges `boundary` (or the file's).
fn frames(path: &Path, first: i64, boundary: Option<&str>) -> PyResult<Vec<Snapshot>> {
    if !path.exists() {
        return Err(PyFileNotFoundError::new_err(format!(
            "no trajectory {}",
            path.display()
        )));
    }
    let edges = match boundary {
        None => None,
        Some("periodic") => Some(Edges::Periodic),
        Some("walls") => Some(Edges::Walls),
        Some("open") => Some(Edges::Open),
        Some(other) => {
            return Err(PyValueError::new_err(format!(
                "boundary = {other:?}: expected \"periodic\", \"walls\" or \"open\""
            )));
        }
    };
    let mut trajectory = Trajectory::open(path).map_err(PyValueError::new_err)?;
    trajectory
        .snapshots(first, edges)
        .map_err(PyValueError::new_err)
}

/// The radial distribution function g(r) of a GSD trajectory's frames from ``first``
/// (negative: from the end), as ``bounce analyze`` writes ``rdf.csv``: returns ``(r, g)``,
/// the bins' centres and g there. ``r_max`` (default: 5 mean diameters, or as far as the box
/// allows) and ``bin`` (default: 0.01 mean diameters) are lengths. In a periodic box it is
/// freud's ``RDF`` (``normalization_mode="exact"``) with the minimum image; between walls and
/// in an open world, pairs are divided by an ideal gas's in the rectangle the centres fill.
/// ``boundary`` (``"periodic"``, ``"walls"``, ``"open"``) overrides what the file records.
#[pyfunction]
#[pyo3(signature = (path, r_max=None, bin=None, first=0, boundary=None))]
pub fn rdf<'py>(
    py: Python<'py>,
    path: PathBuf,
    r_max: Option<f64>,
    bin: Option<f64>,
    first: i64,
    boundary: Option<&str>,
) -> PyResult<Curve<'py, f64>> {
    let frames = frames(&path, first, boundary)?;
    let (r, g) = py
        .detach(|| structure::rdf(&frames, r_max, bin))
        .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
    Ok((r.into_pyarray(py), g.into_pyarray(py)))
}

/// The global bond-orientational order |ψ6| of each frame from ``first``: returns
/// ``(steps, psi6)``. Each disc's ψ6 is over its 6 nearest neighbours, the global order the
/// modulus of their mean (freud's ``Hexatic(k=6)``).
#[pyfunction]
#[pyo3(signature = (path, first=0, boundary=None))]
pub fn psi6<'py>(
    py: Python<'py>,
    path: PathBuf,
    first: i64,
    boundary: Option<&str>,
) -> PyResult<Curve<'py, u64>> {
    let frames = frames(&path, first, boundary)?;
    let order: Vec<f64> = py.detach(|| frames.iter().map(structure::psi6).collect());
    let steps: Vec<u64> = frames.iter().map(|f| f.step).collect();
    Ok((steps.into_pyarray(py), order.into_pyarray(py)))
}

/// The mean-square displacement over every time origin (freud's ``MSD``, ``mode="window"``)
/// from unwrapped positions, of the frames from ``first``: returns ``(lags, msd)``, the lags
/// in steps. The frames must be evenly spaced and hold the same discs.
#[pyfunction]
#[pyo3(signature = (path, first=0, boundary=None))]
pub fn msd<'py>(
    py: Python<'py>,
    path: PathBuf,
    first: i64,
    boundary: Option<&str>,
) -> PyResult<Curve<'py, u64>> {
    let frames = frames(&path, first, boundary)?;
    let (lags, values) = py
        .detach(|| structure::msd(&frames))
        .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
    Ok((lags.into_pyarray(py), values.into_pyarray(py)))
}
