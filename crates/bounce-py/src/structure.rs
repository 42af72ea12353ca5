//! `rdf`, `psi6` and `msd`: the structure of a GSD trajectory's frames (or, for `rdf` and
//! `psi6`, of a world as it is now), as `bounce analyze` computes it
//! (`bounce_scenario::structure`), as NumPy arrays; and `speed_histogram`, a world's speeds
//! against Maxwell–Boltzmann as the viewer draws them.

use std::path::{Path, PathBuf};

use bounce_scenario::structure::{self, Edges, Snapshot};
use bounce_scenario::trajectory::Trajectory;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyFileNotFoundError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

type Curve<'py, X> = (Bound<'py, PyArray1<X>>, Bound<'py, PyArray1<f64>>);

/// The frames of `source`: a GSD path's from `first` ([`frames`]), or a world's state now.
fn frames_of(
    source: &Bound<'_, PyAny>,
    first: i64,
    boundary: Option<&str>,
) -> PyResult<(String, Vec<Snapshot>)> {
    if let Ok(world) = source.cast::<crate::world::World>() {
        let world = world.borrow();
        return Ok(("the world".into(), vec![Snapshot::of(&world.get())]));
    }
    let path: PathBuf = source
        .extract()
        .map_err(|_| PyTypeError::new_err("expected a GSD trajectory's path or a bounce.World"))?;
    let frames = frames(&path, first, boundary)?;
    Ok((path.display().to_string(), frames))
}

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
        Some(name) => Some(Edges::from_name(name).ok_or_else(|| {
            PyValueError::new_err(format!(
                "boundary = {name:?}: expected \"periodic\", \"walls\" or \"open\""
            ))
        })?),
    };
    let mut trajectory = Trajectory::open(path).map_err(PyValueError::new_err)?;
    trajectory
        .snapshots(first, edges)
        .map_err(PyValueError::new_err)
}

/// The radial distribution function g(r) of a GSD trajectory's frames from ``first``
/// (negative: from the end), or of a :class:`World` as it is now (``source``), as ``bounce
/// analyze`` writes ``rdf.csv``: returns ``(r, g)``,
/// the bins' centres and g there. ``r_max`` (default: 5 mean diameters, or as far as the box
/// allows) and ``bin`` (default: 0.01 mean diameters) are lengths. In a periodic box it is
/// freud's ``RDF`` (``normalization_mode="exact"``) with the minimum image; between walls and
/// in an open world, pairs are divided by an ideal gas's in the rectangle the centres fill.
/// ``boundary`` (``"periodic"``, ``"walls"``, ``"open"``) overrides what the file records.
#[pyfunction]
#[pyo3(signature = (source, r_max=None, bin=None, first=0, boundary=None))]
pub fn rdf<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    r_max: Option<f64>,
    bin: Option<f64>,
    first: i64,
    boundary: Option<&str>,
) -> PyResult<Curve<'py, f64>> {
    let (name, frames) = frames_of(source, first, boundary)?;
    let (r, g) = py
        .detach(|| structure::rdf(&frames, r_max, bin))
        .map_err(|e| PyValueError::new_err(format!("{name}: {e}")))?;
    Ok((r.into_pyarray(py), g.into_pyarray(py)))
}

/// The global bond-orientational order |ψ6| of each frame from ``first`` (or of a
/// :class:`World` now): returns ``(steps, psi6)``. Each disc's ψ6 is over its 6 nearest neighbours, the global order the
/// modulus of their mean (freud's ``Hexatic(k=6)``).
#[pyfunction]
#[pyo3(signature = (source, first=0, boundary=None))]
pub fn psi6<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    first: i64,
    boundary: Option<&str>,
) -> PyResult<Curve<'py, u64>> {
    let (_, frames) = frames_of(source, first, boundary)?;
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

/// The speeds of a :class:`World`'s discs in ``bins`` bins against the 2D Maxwell–Boltzmann
/// distribution at their temperature, as the viewer's panel draws them
/// (``bounce_scenario::analysis::speed_histogram``): a dict with ``width`` (bin ``k`` covers
/// ``[k width, (k + 1) width)``), ``density`` (probability density a bin, integrating to 1),
/// ``kt`` (the temperature in the centre-of-mass frame) and ``curve``, shape (201, 2):
/// ``(speed, density)`` of the mix of the Rayleigh curves of the masses present.
#[pyfunction]
#[pyo3(signature = (world, bins=30))]
pub fn speed_histogram<'py>(
    py: Python<'py>,
    world: &Bound<'py, crate::world::World>,
    bins: usize,
) -> PyResult<Bound<'py, PyDict>> {
    if bins == 0 {
        return Err(PyValueError::new_err("bins = 0: expected at least one bin"));
    }
    let h = {
        let world = world.borrow();
        let world = world.get();
        let total_mass = bounce_scenario::analysis::total_mass(&world);
        bounce_scenario::analysis::speed_histogram(&world, bins, total_mass)
    };
    let d = PyDict::new(py);
    d.set_item("width", h.width)?;
    d.set_item("density", h.density.into_pyarray(py))?;
    d.set_item("kt", h.kt)?;
    let curve: Vec<f64> = h.curve.iter().flatten().copied().collect();
    d.set_item("curve", curve.into_pyarray(py).reshape([h.curve.len(), 2])?)?;
    Ok(d)
}
