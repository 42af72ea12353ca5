//! Contact events for Python: the events of every step a `World.step(n)` call took, kept
//! with their step and time, and handed out as one NumPy structured array.

use bounce::{ContactEvent, Party, World as RustWorld};
use numpy::IntoPyArray;
use pyo3::prelude::*;

/// The events of the steps of the last `step` call, with each one's step and the end of
/// its substep.
#[derive(Default)]
pub(crate) struct Recorded(Vec<(u64, f64, ContactEvent)>);

impl Recorded {
    /// A `step` call begins.
    pub(crate) fn clear(&mut self) {
        self.0.clear();
    }

    /// After one step of `dt`: its events.
    pub(crate) fn add(&mut self, world: &RustWorld, dt: f64) {
        let step = world.step_count();
        let substeps = world.stats().substeps;
        for event in world.contact_events() {
            self.0
                .push((step, event.time(world.time(), dt, substeps), *event));
        }
    }

    /// The structured array (see `World.contact_events`).
    pub(crate) fn array<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let numpy = py.import("numpy")?;
        let fields: Vec<(&str, &str)> = vec![
            ("step", "u8"),
            ("time", "f8"),
            ("substep", "u4"),
            ("kind", "U5"),
            ("a", "u4"),
            ("b_kind", "U8"),
            ("b", "u4"),
            ("x", "f8"),
            ("y", "f8"),
            ("nx", "f8"),
            ("ny", "f8"),
            ("normal_impulse", "f8"),
            ("tangent_impulse", "f8"),
            ("approach_speed", "f8"),
        ];
        let dtype = numpy.call_method1("dtype", (fields,))?;
        let out = numpy.call_method1("zeros", (self.0.len(), dtype))?;
        let events = &self.0;
        let column = |f: &dyn Fn(&(u64, f64, ContactEvent)) -> f64| -> Vec<f64> {
            events.iter().map(f).collect()
        };
        out.set_item(
            "step",
            events
                .iter()
                .map(|e| e.0)
                .collect::<Vec<u64>>()
                .into_pyarray(py),
        )?;
        out.set_item("time", column(&|e| e.1).into_pyarray(py))?;
        let substeps: Vec<u32> = events.iter().map(|e| e.2.substep).collect();
        out.set_item("substep", substeps.into_pyarray(py))?;
        let kinds: Vec<&str> = events.iter().map(|e| e.2.kind.name()).collect();
        out.set_item("kind", kinds)?;
        let ids: Vec<u32> = events.iter().map(|e| e.2.a.0).collect();
        out.set_item("a", ids.into_pyarray(py))?;
        let (b_kinds, bs): (Vec<&str>, Vec<u32>) = events
            .iter()
            .map(|e| match e.2.b {
                Party::Disc(id) => ("disc", id.0),
                Party::Wall(side) => ("wall", side as u32),
                Party::Obstacle(k) => ("obstacle", k),
            })
            .unzip();
        out.set_item("b_kind", b_kinds)?;
        out.set_item("b", bs.into_pyarray(py))?;
        out.set_item("x", column(&|e| e.2.point[0]).into_pyarray(py))?;
        out.set_item("y", column(&|e| e.2.point[1]).into_pyarray(py))?;
        out.set_item("nx", column(&|e| e.2.normal[0]).into_pyarray(py))?;
        out.set_item("ny", column(&|e| e.2.normal[1]).into_pyarray(py))?;
        out.set_item(
            "normal_impulse",
            column(&|e| e.2.normal_impulse).into_pyarray(py),
        )?;
        out.set_item(
            "tangent_impulse",
            column(&|e| e.2.tangent_impulse).into_pyarray(py),
        )?;
        out.set_item(
            "approach_speed",
            column(&|e| e.2.approach_speed).into_pyarray(py),
        )?;
        Ok(out)
    }
}
