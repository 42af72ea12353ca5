//! Spatial queries for Python: a snapshot of the discs binned once, asked many times.

use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;

/// A snapshot of the discs for spatial queries (``World.queries()``): binning costs one pass
/// over the discs, each query then only what is near it. It does not follow the world: ask
/// for a new one after a step. Answers are ids, in id order.
#[pyclass(module = "bounce", name = "Queries", frozen)]
pub struct Queries {
    pub(crate) inner: bounce::query::Queries,
}

#[pymethods]
impl Queries {
    /// The ids of the discs overlapping the circle of ``radius`` around ``centre``.
    fn in_circle<'py>(
        &self,
        py: Python<'py>,
        centre: (f64, f64),
        radius: f64,
    ) -> Bound<'py, PyArray1<u32>> {
        ids(py, self.inner.in_circle([centre.0, centre.1], radius))
    }

    /// The ids of the discs overlapping the box ``[min, max]``.
    fn in_box<'py>(
        &self,
        py: Python<'py>,
        min: (f64, f64),
        max: (f64, f64),
    ) -> Bound<'py, PyArray1<u32>> {
        ids(py, self.inner.in_box([min.0, min.1], [max.0, max.1]))
    }

    /// ``(id, distance)`` of the disc whose edge is nearest ``point`` (negative inside it),
    /// or ``None`` without discs.
    fn nearest(&self, point: (f64, f64)) -> Option<(u32, f64)> {
        self.inner
            .nearest([point.0, point.1])
            .map(|(id, gap)| (id.0, gap))
    }

    /// The first disc the ray from ``origin`` along ``direction`` enters within
    /// ``max_fraction`` of the direction's length: a dict with ``id``, ``fraction``,
    /// ``point`` and ``normal``, or ``None``. Discs holding the origin are not entered.
    #[pyo3(signature = (origin, direction, max_fraction = 1.0))]
    fn ray_cast<'py>(
        &self,
        py: Python<'py>,
        origin: (f64, f64),
        direction: (f64, f64),
        max_fraction: f64,
    ) -> PyResult<Option<Bound<'py, pyo3::types::PyDict>>> {
        let Some(hit) = self.inner.ray_cast(
            [origin.0, origin.1],
            [direction.0, direction.1],
            max_fraction,
        ) else {
            return Ok(None);
        };
        let out = pyo3::types::PyDict::new(py);
        out.set_item("id", hit.id.0)?;
        out.set_item("fraction", hit.fraction)?;
        out.set_item("point", (hit.point[0], hit.point[1]))?;
        out.set_item("normal", (hit.normal[0], hit.normal[1]))?;
        Ok(Some(out))
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }
}

fn ids(py: Python<'_>, found: Vec<bounce::ParticleId>) -> Bound<'_, PyArray1<u32>> {
    found
        .into_iter()
        .map(|id| id.0)
        .collect::<Vec<u32>>()
        .into_pyarray(py)
}
