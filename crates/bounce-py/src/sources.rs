//! `bounce.Emitter` and `bounce.Sink`: discs added in a region at a rate, and removed where
//! they enter a region; the Rust [`bounce::Emitter`] and [`bounce::Sink`] inside.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// Adds discs in the rectangle ``[min, max]`` at ``rate`` per unit time, radii uniform in
/// ``radius`` (one number or ``(lo, hi)``), velocities ``velocity`` plus a uniform part in
/// ``[-spread, spread]`` per component; ``seed`` fixes the random numbers, ``limit`` stops
/// it after that many discs. A disc that would touch another or an obstacle waits for a
/// later attempt. Pass them as ``Config(emitters=[...])``.
#[pyclass(module = "bounce", name = "Emitter", frozen)]
#[derive(Clone)]
pub struct Emitter {
    pub(crate) inner: bounce::Emitter,
}

#[pymethods]
impl Emitter {
    #[new]
    #[pyo3(signature = (min, max, rate, radius, *, velocity = (0.0, 0.0), spread = 0.0, seed = 0, limit = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        min: (f64, f64),
        max: (f64, f64),
        rate: f64,
        radius: &Bound<'_, PyAny>,
        velocity: (f64, f64),
        spread: f64,
        seed: u64,
        limit: Option<u64>,
    ) -> PyResult<Self> {
        let radius = match radius.extract::<f64>() {
            Ok(r) => [r, r],
            Err(_) => {
                let (lo, hi): (f64, f64) = radius.extract()?;
                [lo, hi]
            }
        };
        let inner = bounce::Emitter {
            min: [min.0, min.1],
            max: [max.0, max.1],
            rate,
            radius,
            velocity: [velocity.0, velocity.1],
            spread,
            seed,
            limit,
        };
        let config = bounce::Config {
            emitters: vec![inner],
            ..bounce::Config::default()
        };
        config
            .validate()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Emitter { inner })
    }

    /// Discs per unit time.
    #[getter]
    fn rate(&self) -> f64 {
        self.inner.rate
    }

    fn __repr__(&self) -> String {
        let e = &self.inner;
        format!(
            "Emitter(min=({}, {}), max=({}, {}), rate={}, radius=({}, {}), velocity=({}, {}), \
             spread={}, seed={}, limit={:?})",
            e.min[0],
            e.min[1],
            e.max[0],
            e.max[1],
            e.rate,
            e.radius[0],
            e.radius[1],
            e.velocity[0],
            e.velocity[1],
            e.spread,
            e.seed,
            e.limit
        )
    }
}

/// Removes every disc whose centre is in the rectangle ``[min, max]`` at the end of a step.
/// Pass them as ``Config(sinks=[...])``.
#[pyclass(module = "bounce", name = "Sink", frozen)]
#[derive(Clone)]
pub struct Sink {
    pub(crate) inner: bounce::Sink,
}

#[pymethods]
impl Sink {
    #[new]
    fn new(min: (f64, f64), max: (f64, f64)) -> PyResult<Self> {
        let inner = bounce::Sink {
            min: [min.0, min.1],
            max: [max.0, max.1],
        };
        let config = bounce::Config {
            sinks: vec![inner],
            ..bounce::Config::default()
        };
        config
            .validate()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Sink { inner })
    }

    fn __repr__(&self) -> String {
        let s = &self.inner;
        format!(
            "Sink(min=({}, {}), max=({}, {}))",
            s.min[0], s.min[1], s.max[0], s.max[1]
        )
    }
}

/// Counts the discs whose centre enters and leaves a region: a box, ``Sensor(name,
/// min=(x, y), max=(x, y))``, or a circle, ``Sensor(name, centre=(x, y), radius=r)``. Pass
/// them as ``Config(sensors=[...])``; ``World.sensors`` gives the counts by name.
#[pyclass(module = "bounce", name = "Sensor", frozen)]
#[derive(Clone)]
pub struct Sensor {
    pub(crate) inner: bounce::Sensor,
}

#[pymethods]
impl Sensor {
    #[new]
    #[pyo3(signature = (name, min = None, max = None, centre = None, radius = None))]
    fn new(
        name: String,
        min: Option<(f64, f64)>,
        max: Option<(f64, f64)>,
        centre: Option<(f64, f64)>,
        radius: Option<f64>,
    ) -> PyResult<Self> {
        let region = match (min, max, centre, radius) {
            (Some(min), Some(max), None, None) => bounce::Region::Box {
                min: [min.0, min.1],
                max: [max.0, max.1],
            },
            (None, None, Some(c), Some(radius)) => bounce::Region::Circle {
                centre: [c.0, c.1],
                radius,
            },
            _ => {
                return Err(PyValueError::new_err(
                    "Sensor: give a box (min=, max=) or a circle (centre=, radius=)",
                ));
            }
        };
        let inner = bounce::Sensor::new(name, region);
        let config = bounce::Config {
            sensors: vec![inner.clone()],
            ..bounce::Config::default()
        };
        config
            .validate()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Sensor { inner })
    }

    /// Its name.
    #[getter]
    fn name(&self) -> &str {
        &self.inner.name
    }

    fn __repr__(&self) -> String {
        let name = &self.inner.name;
        match self.inner.region {
            bounce::Region::Box { min, max } => format!(
                "Sensor({name:?}, min=({}, {}), max=({}, {}))",
                min[0], min[1], max[0], max[1]
            ),
            bounce::Region::Circle { centre, radius } => format!(
                "Sensor({name:?}, centre=({}, {}), radius={radius})",
                centre[0], centre[1]
            ),
        }
    }
}
