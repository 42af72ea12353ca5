//! `bounce.Config`: the Rust [`bounce::Config`] with keyword arguments, validated on
//! construction.

use bounce::{
    Boundary, Config as RustConfig, MassModel, Method, RestingContacts, RestitutionModel,
    Thermostat, ThermostatKind, VelocityUpdate,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::Deserialize;

use crate::obstacle::Obstacle;
use crate::sources::{Emitter, Sensor, Sink};
use serde::de::IntoDeserializer;

/// The world's configuration: the collision model, the boundary and the model options.
///
/// Every keyword is optional; the defaults are the default model's (an open world, no gravity,
/// ``collision_radius_scale = 1``, ``coefficient_of_restitution = 1``, one substep, one
/// solver pass, radii as masses, each normal velocity scaled by the restitution, every
/// detected pair updated, every contact bouncing however slow).
///
/// Keywords: ``collision_radius_scale``, ``coefficient_of_restitution``, ``gravity``
/// (``(gx, gy)``), ``substeps``, ``solver_iterations``, ``max_travel`` (``None`` or a
/// fraction of the smallest radius), ``boundary`` (``"open"``, ``"walls"``,
/// ``"periodic"`` or ``"lees_edwards"``, a periodic box under shear at ``shear_rate``),
/// ``min`` and ``max`` (the box corners, for a box),
/// ``wall_restitution`` (``None``: the coefficient of restitution), ``mass_model``
/// (``"radius"``, ``"area"``, ``"per_particle"``), ``restitution_model``
/// (``"scale_each_normal_velocity"``, ``"relative_normal_velocity"``) and
/// ``velocity_update`` (``"all_detected"``, ``"approaching_only"``), ``resting_contacts``
/// (``"bounce"``; ``"rest"``: contacts slower than 4 substeps of gravity's pull get
/// restitution 0, so a disc resting on the floor, a segment or a peg keeps no ``|g| h``
/// speed), the rough discs' ``friction``, ``wall_friction`` (``None``: ``friction``),
/// ``tangential_restitution``, ``rolling_resistance`` and ``inertia_factor`` (all 0 but the
/// last, ½: smooth discs; any friction makes the discs turn), ``obstacles`` (a list
/// of :class:`Obstacle`), ``emitters`` (of :class:`Emitter`), ``sinks`` (of :class:`Sink`),
/// ``sensors`` (of :class:`Sensor`),
/// ``method`` (``"time_stepped"``, step by step, or ``"event_driven"``: exact hard discs,
/// every collision at its moment of contact, ``dt`` only how often the world is observed)
/// ``contact_duration`` (the event-driven TC model's ``t_c``: a disc's collision within
/// it of its last one is elastic; 0, off), ``contact_events`` (``True``: steps record the
/// contacts that begin and end, ``World.contact_events()``; default ``False``) and
/// ``contact_event_threshold`` (the smallest normal impulse a begin is reported with;
/// default 0) and ``thermostat`` (``None``, or a dict ``{"kind": "rescale" | "andersen" |
/// "white_noise", "temperature": T, "rate": r, "seed": s}``: a heat bath or random drive at
/// the end of every step; the energy it added is ``World.stats["thermostat_work"]``) and
/// ``pressure_tensor`` (``True``: each step measures the virial tensor,
/// ``World.pressure_tensor``; default ``False``) and ``collision_counts`` (``True``: each
/// disc's collisions with other discs are counted, ``World.collision_counts``; default
/// ``False``).
///
/// Raises ``ValueError`` naming the field and the value when one is out of range, and
/// ``TypeError`` for an unknown keyword or a value of the wrong type.
#[pyclass(module = "bounce", name = "Config", frozen)]
#[derive(Clone)]
pub struct Config {
    pub(crate) inner: RustConfig,
}

/// The scenario-file names of the model options.
fn mass_model_name(m: MassModel) -> &'static str {
    match m {
        MassModel::Radius => "radius",
        MassModel::Area => "area",
        MassModel::PerParticle => "per_particle",
    }
}

fn restitution_model_name(m: RestitutionModel) -> &'static str {
    match m {
        RestitutionModel::ScaleEachNormalVelocity => "scale_each_normal_velocity",
        RestitutionModel::RelativeNormalVelocity => "relative_normal_velocity",
    }
}

fn resting_contacts_name(m: RestingContacts) -> &'static str {
    match m {
        RestingContacts::Bounce => "bounce",
        RestingContacts::Rest => "rest",
    }
}

fn velocity_update_name(m: VelocityUpdate) -> &'static str {
    match m {
        VelocityUpdate::AllDetected => "all_detected",
        VelocityUpdate::ApproachingOnly => "approaching_only",
    }
}

/// A model option from its name, or a `ValueError` listing the choices.
fn option<T: for<'de> Deserialize<'de>>(field: &str, name: &str, choices: &str) -> PyResult<T> {
    T::deserialize(name.into_deserializer()).map_err(|_: serde::de::value::Error| {
        PyValueError::new_err(format!(
            "invalid config: `{field}` = {name:?}: must be one of {choices}"
        ))
    })
}

/// `None`, or a dict `{"kind": ..., "temperature": ..., "rate": ..., "seed": ...}`.
fn thermostat(value: &Bound<'_, PyAny>) -> PyResult<Option<Thermostat>> {
    if value.is_none() {
        return Ok(None);
    }
    let expected = "None or a dict with kind, temperature, rate (and seed)";
    let dict = value.cast::<PyDict>().map_err(|_| {
        PyTypeError::new_err(format!("Config(thermostat=...): expected {expected}"))
    })?;
    let (mut kind, mut temperature, mut rate, mut seed) = (None, None, None, 0u64);
    for (k, v) in dict.iter() {
        let k: String = k.extract().map_err(|_| {
            PyTypeError::new_err("Config(thermostat=...): the dict's keys must be strings")
        })?;
        let field = format!("thermostat.{k}");
        match k.as_str() {
            "kind" => {
                let name: String = typed(&field, &v, "a string")?;
                kind = Some(option::<ThermostatKind>(
                    &field,
                    &name,
                    "\"rescale\", \"andersen\", \"white_noise\"",
                )?);
            }
            "temperature" => temperature = Some(typed(&field, &v, "a number")?),
            "rate" => rate = Some(typed(&field, &v, "a number")?),
            "seed" => seed = typed(&field, &v, "an integer >= 0")?,
            _ => {
                return Err(PyTypeError::new_err(format!(
                    "Config(thermostat=...): unknown key {k:?} (expected kind, temperature, \
                     rate, seed)"
                )));
            }
        }
    }
    let missing = |what: &str| {
        PyValueError::new_err(format!(
            "invalid config: `thermostat` is missing {what}: expected {expected}"
        ))
    };
    Ok(Some(Thermostat {
        kind: kind.ok_or_else(|| missing("kind"))?,
        temperature: temperature.ok_or_else(|| missing("temperature"))?,
        rate: rate.ok_or_else(|| missing("rate"))?,
        seed,
    }))
}

fn pair(field: &str, value: &Bound<'_, PyAny>) -> PyResult<[f64; 2]> {
    value
        .extract::<(f64, f64)>()
        .map(|(a, b)| [a, b])
        .or_else(|_| {
            value
                .extract::<Vec<f64>>()
                .ok()
                .and_then(|v| <[f64; 2]>::try_from(v).ok())
                .ok_or(())
        })
        .map_err(|()| {
            PyTypeError::new_err(format!("Config({field}=...): expected two numbers (x, y)"))
        })
}

fn typed<'py, T: for<'a> FromPyObject<'a, 'py>>(
    field: &str,
    value: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<T> {
    value.extract::<T>().map_err(|_| {
        PyTypeError::new_err(format!(
            "Config({field}=...): expected {what}, got {}",
            value.repr().map_or_else(|_| "?".into(), |r| r.to_string())
        ))
    })
}

#[pymethods]
impl Config {
    #[new]
    #[pyo3(signature = (**kwargs))]
    fn new(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let mut c = RustConfig::default();
        let mut boundary = "open".to_string();
        let (mut min, mut max, mut wall_restitution) = (None, None, None);
        let mut shear_rate: Option<f64> = None;
        if let Some(kwargs) = kwargs {
            for (key, value) in kwargs.iter() {
                let key: String = key.extract()?;
                let v = &value;
                match key.as_str() {
                    "collision_radius_scale" => {
                        c.collision_radius_scale = typed(&key, v, "a number")?
                    }
                    "coefficient_of_restitution" => {
                        c.coefficient_of_restitution = typed(&key, v, "a number")?
                    }
                    "gravity" => c.gravity = pair(&key, v)?,
                    "substeps" => c.substeps = typed(&key, v, "a positive integer")?,
                    "solver_iterations" => {
                        c.solver_iterations = typed(&key, v, "a positive integer")?
                    }
                    "max_travel" => c.max_travel = typed(&key, v, "None or a number")?,
                    "boundary" => boundary = typed(&key, v, "a string")?,
                    "min" => min = Some(pair(&key, v)?),
                    "max" => max = Some(pair(&key, v)?),
                    "wall_restitution" => wall_restitution = typed(&key, v, "None or a number")?,
                    "shear_rate" => shear_rate = typed(&key, v, "None or a number")?,
                    "mass_model" => {
                        let name: String = typed(&key, v, "a string")?;
                        c.mass_model = option::<MassModel>(
                            &key,
                            &name,
                            "\"radius\", \"area\", \"per_particle\"",
                        )?
                    }
                    "restitution_model" => {
                        let name: String = typed(&key, v, "a string")?;
                        c.restitution_model = option::<RestitutionModel>(
                            &key,
                            &name,
                            "\"scale_each_normal_velocity\", \"relative_normal_velocity\"",
                        )?
                    }
                    "velocity_update" => {
                        let name: String = typed(&key, v, "a string")?;
                        c.velocity_update = option::<VelocityUpdate>(
                            &key,
                            &name,
                            "\"all_detected\", \"approaching_only\"",
                        )?
                    }
                    "resting_contacts" => {
                        let name: String = typed(&key, v, "a string")?;
                        c.resting_contacts =
                            option::<RestingContacts>(&key, &name, "\"bounce\", \"rest\"")?
                    }
                    "method" => {
                        let name: String = typed(&key, v, "a string")?;
                        c.method =
                            option::<Method>(&key, &name, "\"time_stepped\", \"event_driven\"")?
                    }
                    "contact_duration" => c.contact_duration = typed(&key, v, "a number")?,
                    "contact_events" => c.contact_events = typed(&key, v, "True or False")?,
                    "contact_event_threshold" => {
                        c.contact_event_threshold = typed(&key, v, "a number")?
                    }
                    "friction" => c.friction = typed(&key, v, "a number")?,
                    "wall_friction" => c.wall_friction = typed(&key, v, "None or a number")?,
                    "tangential_restitution" => {
                        c.tangential_restitution = typed(&key, v, "a number")?
                    }
                    "rolling_resistance" => c.rolling_resistance = typed(&key, v, "a number")?,
                    "inertia_factor" => c.inertia_factor = typed(&key, v, "a number")?,
                    "obstacles" => {
                        let list: Vec<PyRef<'_, Obstacle>> =
                            typed(&key, v, "a list of bounce.Obstacle")?;
                        c.obstacles = list.iter().map(|o| o.inner).collect();
                    }
                    "emitters" => {
                        let list: Vec<PyRef<'_, Emitter>> =
                            typed(&key, v, "a list of bounce.Emitter")?;
                        c.emitters = list.iter().map(|e| e.inner).collect();
                    }
                    "sinks" => {
                        let list: Vec<PyRef<'_, Sink>> = typed(&key, v, "a list of bounce.Sink")?;
                        c.sinks = list.iter().map(|e| e.inner).collect();
                    }
                    "sensors" => {
                        let list: Vec<PyRef<'_, Sensor>> =
                            typed(&key, v, "a list of bounce.Sensor")?;
                        c.sensors = list.iter().map(|e| e.inner.clone()).collect();
                    }
                    "thermostat" => c.thermostat = thermostat(v)?,
                    "pressure_tensor" => c.pressure_tensor = typed(&key, v, "True or False")?,
                    "collision_counts" => {
                        c.collision_counts = typed(&key, v, "True or False")?;
                    }
                    _ => {
                        return Err(PyTypeError::new_err(format!(
                            "Config() got an unexpected keyword argument '{key}'"
                        )));
                    }
                }
            }
        }
        let corner = |field: &str, corner: Option<[f64; 2]>| {
            corner.ok_or_else(|| {
                PyValueError::new_err(format!(
                    "invalid config: `{field}` is missing: boundary = {boundary:?} needs min and max"
                ))
            })
        };
        c.boundary = match boundary.as_str() {
            "open" => Boundary::Open,
            "walls" => Boundary::Walls {
                min: corner("min", min)?,
                max: corner("max", max)?,
                wall_restitution,
            },
            "periodic" => Boundary::Periodic {
                min: corner("min", min)?,
                max: corner("max", max)?,
            },
            "lees_edwards" => Boundary::LeesEdwards {
                min: corner("min", min)?,
                max: corner("max", max)?,
                shear_rate: shear_rate.ok_or_else(|| {
                    PyValueError::new_err(
                        "invalid config: `shear_rate` is missing: boundary = \"lees_edwards\" needs it",
                    )
                })?,
            },
            other => {
                return Err(PyValueError::new_err(format!(
                    "invalid config: `boundary` = {other:?}: must be one of \"open\", \"walls\", \"periodic\", \"lees_edwards\""
                )));
            }
        };
        if shear_rate.is_some() && !c.boundary.is_sheared() {
            return Err(PyValueError::new_err(
                "invalid config: `shear_rate` needs boundary = \"lees_edwards\"",
            ));
        }
        if wall_restitution.is_some() && !matches!(c.boundary, Boundary::Walls { .. }) {
            return Err(PyValueError::new_err(
                "invalid config: `wall_restitution` needs boundary = \"walls\"",
            ));
        }
        c.validate()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Config { inner: c })
    }

    /// ``collision_radius_scale``: discs collide when their centres are at most
    /// ``(r_i + r_j)`` times it apart.
    #[getter]
    fn collision_radius_scale(&self) -> f64 {
        self.inner.collision_radius_scale
    }

    /// The coefficient of restitution ``e`` (see ``restitution_model``).
    #[getter]
    fn coefficient_of_restitution(&self) -> f64 {
        self.inner.coefficient_of_restitution
    }

    /// Uniform acceleration ``(gx, gy)``.
    #[getter]
    fn gravity(&self) -> (f64, f64) {
        (self.inner.gravity[0], self.inner.gravity[1])
    }

    /// Substeps per step.
    #[getter]
    fn substeps(&self) -> u32 {
        self.inner.substeps
    }

    /// Passes of detection and resolution per substep.
    #[getter]
    fn solver_iterations(&self) -> u32 {
        self.inner.solver_iterations
    }

    /// Adaptive substeps: the farthest a disc may move per substep, as a fraction of the
    /// smallest radius (``None``: fixed substeps).
    #[getter]
    fn max_travel(&self) -> Option<f64> {
        self.inner.max_travel
    }

    /// ``"open"``, ``"walls"``, ``"periodic"`` or ``"lees_edwards"``.
    #[getter]
    pub(crate) fn boundary(&self) -> &'static str {
        match self.inner.boundary {
            Boundary::Open => "open",
            Boundary::Walls { .. } => "walls",
            Boundary::Periodic { .. } => "periodic",
            Boundary::LeesEdwards { .. } => "lees_edwards",
        }
    }

    /// The shear rate of a ``"lees_edwards"`` box (``None`` for any other boundary).
    #[getter]
    fn shear_rate(&self) -> Option<f64> {
        match self.inner.boundary {
            Boundary::LeesEdwards { shear_rate, .. } => Some(shear_rate),
            _ => None,
        }
    }

    /// The lower-left corner of the box (``None`` in an open world).
    #[getter]
    fn min(&self) -> Option<(f64, f64)> {
        self.inner
            .boundary
            .bounds()
            .map(|(min, _)| (min[0], min[1]))
    }

    /// The upper-right corner of the box (``None`` in an open world).
    #[getter]
    fn max(&self) -> Option<(f64, f64)> {
        self.inner
            .boundary
            .bounds()
            .map(|(_, max)| (max[0], max[1]))
    }

    /// The walls' restitution (``None``: the coefficient of restitution).
    #[getter]
    fn wall_restitution(&self) -> Option<f64> {
        match self.inner.boundary {
            Boundary::Walls {
                wall_restitution, ..
            } => wall_restitution,
            _ => None,
        }
    }

    /// The mass each disc has in collisions: ``"radius"`` (the default: mass = radius), ``"area"`` or
    /// ``"per_particle"``.
    #[getter]
    fn mass_model(&self) -> &'static str {
        mass_model_name(self.inner.mass_model)
    }

    /// ``"scale_each_normal_velocity"`` (the default) or ``"relative_normal_velocity"``.
    #[getter]
    fn restitution_model(&self) -> &'static str {
        restitution_model_name(self.inner.restitution_model)
    }

    /// ``"all_detected"`` (the default) or ``"approaching_only"``.
    #[getter]
    fn velocity_update(&self) -> &'static str {
        velocity_update_name(self.inner.velocity_update)
    }

    /// ``"bounce"`` (the default) or ``"rest"``.
    #[getter]
    fn resting_contacts(&self) -> &'static str {
        resting_contacts_name(self.inner.resting_contacts)
    }

    /// ``"time_stepped"`` (the default, step by step) or ``"event_driven"`` (exact hard discs).
    #[getter]
    fn method(&self) -> &'static str {
        self.inner.method.name()
    }

    /// The event-driven TC model's ``t_c`` (0: off).
    #[getter]
    fn contact_duration(&self) -> f64 {
        self.inner.contact_duration
    }

    /// Whether steps record contact events (``World.contact_events``).
    #[getter]
    fn contact_events(&self) -> bool {
        self.inner.contact_events
    }

    /// The smallest normal impulse a contact's begin (and so its end) is reported with.
    #[getter]
    fn contact_event_threshold(&self) -> f64 {
        self.inner.contact_event_threshold
    }

    /// Whether each step measures the virial tensor (``World.pressure_tensor``).
    #[getter]
    fn pressure_tensor(&self) -> bool {
        self.inner.pressure_tensor
    }

    /// Whether each disc's collisions are counted (``World.collision_counts``).
    #[getter]
    fn collision_counts(&self) -> bool {
        self.inner.collision_counts
    }

    /// The thermostat as a dict (``kind``, ``temperature``, ``rate``, ``seed``), or ``None``.
    #[getter]
    fn thermostat<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(t) = self.inner.thermostat else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("kind", kind_name(t.kind))?;
        d.set_item("temperature", t.temperature)?;
        d.set_item("rate", t.rate)?;
        d.set_item("seed", t.seed)?;
        Ok(Some(d))
    }

    /// Coulomb's friction coefficient of disc–disc contacts (0, the default: smooth discs).
    #[getter]
    fn friction(&self) -> f64 {
        self.inner.friction
    }

    /// The walls' friction coefficient (``None``: ``friction``).
    #[getter]
    fn wall_friction(&self) -> Option<f64> {
        self.inner.wall_friction
    }

    /// Walton's tangential restitution in [-1, 1] (0: slip removed).
    #[getter]
    fn tangential_restitution(&self) -> f64 {
        self.inner.tangential_restitution
    }

    /// The rolling resistance (0: none).
    #[getter]
    fn rolling_resistance(&self) -> f64 {
        self.inner.rolling_resistance
    }

    /// ``k`` in each disc's moment of inertia ``k m r²`` (½: a solid disc).
    #[getter]
    fn inertia_factor(&self) -> f64 {
        self.inner.inertia_factor
    }

    /// The obstacles as configured (a moving one where it starts).
    #[getter]
    fn obstacles(&self) -> Vec<Obstacle> {
        self.inner
            .obstacles
            .iter()
            .map(|&inner| Obstacle { inner })
            .collect()
    }

    pub(crate) fn __repr__(&self) -> String {
        let c = &self.inner;
        let mut parts = vec![
            format!("collision_radius_scale={:?}", c.collision_radius_scale),
            format!(
                "coefficient_of_restitution={:?}",
                c.coefficient_of_restitution
            ),
            format!("gravity=({:?}, {:?})", c.gravity[0], c.gravity[1]),
            format!("substeps={}", c.substeps),
            format!("solver_iterations={}", c.solver_iterations),
        ];
        if let Some(f) = c.max_travel {
            parts.push(format!("max_travel={f:?}"));
        }
        parts.push(format!("boundary={:?}", self.boundary()));
        if let (Some(min), Some(max)) = (self.min(), self.max()) {
            parts.push(format!("min={min:?}, max={max:?}"));
        }
        if let Some(e) = self.wall_restitution() {
            parts.push(format!("wall_restitution={e:?}"));
        }
        if let Some(rate) = self.shear_rate() {
            parts.push(format!("shear_rate={rate:?}"));
        }
        parts.push(format!("mass_model={:?}", self.mass_model()));
        parts.push(format!("restitution_model={:?}", self.restitution_model()));
        parts.push(format!("velocity_update={:?}", self.velocity_update()));
        parts.push(format!("resting_contacts={:?}", self.resting_contacts()));
        if c.is_rough() || c.inertia_factor != 0.5 {
            parts.push(format!("friction={:?}", c.friction));
            if let Some(w) = c.wall_friction {
                parts.push(format!("wall_friction={w:?}"));
            }
            parts.push(format!(
                "tangential_restitution={:?}, rolling_resistance={:?}, inertia_factor={:?}",
                c.tangential_restitution, c.rolling_resistance, c.inertia_factor
            ));
        }
        if c.method != Method::TimeStepped || c.contact_duration != 0.0 {
            parts.push(format!(
                "method={:?}, contact_duration={:?}",
                self.method(),
                c.contact_duration
            ));
        }
        if !c.sensors.is_empty() {
            let names: Vec<&str> = c.sensors.iter().map(|s| s.name.as_str()).collect();
            parts.push(format!("sensors={names:?}"));
        }
        if c.contact_events {
            parts.push(format!(
                "contact_events=True, contact_event_threshold={:?}",
                c.contact_event_threshold
            ));
        }
        if !c.obstacles.is_empty() {
            parts.push(format!("obstacles=[{} obstacles]", c.obstacles.len()));
        }
        if c.pressure_tensor {
            parts.push("pressure_tensor=True".into());
        }
        if c.collision_counts {
            parts.push("collision_counts=True".into());
        }
        if let Some(t) = c.thermostat {
            parts.push(format!(
                "thermostat={{\"kind\": {:?}, \"temperature\": {:?}, \"rate\": {:?}, \"seed\": {}}}",
                kind_name(t.kind),
                t.temperature,
                t.rate,
                t.seed
            ));
        }
        format!("bounce.Config({})", parts.join(", "))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<Config>()
            .is_ok_and(|o| o.get().inner == self.inner)
    }
}

/// A thermostat kind's name, as the scenario file and `Config(thermostat=...)` spell it.
fn kind_name(kind: ThermostatKind) -> &'static str {
    match kind {
        ThermostatKind::Rescale => "rescale",
        ThermostatKind::Andersen => "andersen",
        ThermostatKind::WhiteNoise => "white_noise",
    }
}
