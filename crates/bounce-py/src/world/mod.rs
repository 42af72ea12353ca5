//! `bounce.World`: the Rust [`bounce::World`] with NumPy arrays in and out, stepping without
//! the GIL, and the zero-copy storage view.

mod gsd;
pub(crate) use gsd::GsdWriter;

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use bounce::law::Law;
use bounce::{Particle, World as RustWorld};
use numpy::ndarray::{Array1, Array2, ArrayView1};
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::obstacle::Obstacle;

use crate::config::Config;
use crate::events::Recorded;
use crate::query::Queries;

/// A world of discs: the simulation.
///
/// ``World(config=None, dt=None, threads=1)`` starts empty (``config`` defaults to
/// ``bounce.Config()``, the default model in an open world); ``World.from_scenario(path)`` builds the scenario file
/// the ``bounce`` command runs, with the same ids; ``World.load(path)`` reads a checkpoint.
///
/// Arrays come out as NumPy copies in id order (``positions``, ``velocities``, ``radii``,
/// ``masses``, ``ids``); ``storage_view()`` gives read-only arrays over the engine's own
/// memory, without a copy, for hot loops. Results are bit-identical for every ``threads``.
#[pyclass(module = "bounce", name = "World")]
pub struct World {
    /// The engine's world (a `Mutex` only because pyclasses must be `Sync`; `&mut self`
    /// methods reach it without locking).
    world: Mutex<RustWorld>,
    /// The time step `step` uses when given none (a scenario's `time.dt`).
    dt: Option<f64>,
    /// Particle type names and each id's type, for GSD files.
    pub(crate) types: Vec<String>,
    pub(crate) typeid: Vec<u32>,
    /// Storage views alive: while any is, the world refuses to change.
    views: Arc<AtomicUsize>,
    /// Trajectory writers fed by `step`.
    writers: Vec<Py<GsdWriter>>,
    /// The contact events of the last `step` call's steps.
    events: Recorded,
    /// The momentum each obstacle has received over every step this object took.
    obstacle_impulses_total: Vec<[f64; 2]>,
    /// Each emitter's colour and type: the discs it adds get its type in `typeid`.
    emitted: Vec<(Option<bounce_scenario::Rgb>, u32)>,
}

/// The message of a world error, as Python's `ValueError`.
fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// `value` as a C-contiguous float64 NumPy array (any array-like, any real dtype, any
/// strides), with its shape checked against `shape` (`None` for any length).
fn float_array<'py>(
    py: Python<'py>,
    name: &str,
    value: &Bound<'py, PyAny>,
    columns: Option<usize>,
    rows: Option<usize>,
) -> PyResult<(Vec<f64>, usize)> {
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", numpy.getattr("float64")?)?;
    let array = numpy
        .call_method("ascontiguousarray", (value,), Some(&kwargs))
        .map_err(|e| {
            PyValueError::new_err(format!(
                "{name}: cannot be read as an array of numbers: {e}"
            ))
        })?;
    let array = array.cast_into::<numpy::PyArrayDyn<f64>>()?;
    let shape = array.shape().to_vec();
    let expected = match columns {
        Some(c) => format!("(N, {c})"),
        None => "(N,)".to_string(),
    };
    let ok = match columns {
        Some(c) => shape.len() == 2 && shape[1] == c,
        None => shape.len() == 1,
    };
    if !ok {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape {expected}; got {}",
            shape_text(&shape)
        )));
    }
    if let Some(rows) = rows
        && shape[0] != rows
    {
        return Err(PyValueError::new_err(format!(
            "{name} has {} rows; expected {rows}",
            shape[0]
        )));
    }
    let values = array.readonly().as_slice()?.to_vec();
    Ok((values, shape[0]))
}

/// `n` tags from a sequence or array of non-negative integers (or one for all).
fn tag_array(value: &Bound<'_, PyAny>, n: usize) -> PyResult<Vec<u64>> {
    if let Ok(one) = value.extract::<u64>() {
        return Ok(vec![one; n]);
    }
    let tags: Vec<u64> = value.extract().map_err(|_| {
        PyTypeError::new_err("tags must be integers in [0, 2**64) (one, or one per disc)")
    })?;
    if tags.len() != n {
        return Err(PyValueError::new_err(format!(
            "tags has {} values for {n} discs",
            tags.len()
        )));
    }
    Ok(tags)
}

fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

impl World {
    fn wrap(
        world: RustWorld,
        dt: Option<f64>,
        (types, typeid): (Vec<String>, Vec<u32>),
        emitted: Vec<(Option<bounce_scenario::Rgb>, u32)>,
    ) -> World {
        World {
            world: Mutex::new(world),
            dt,
            types,
            typeid,
            views: Arc::new(AtomicUsize::new(0)),
            writers: Vec::new(),
            events: Recorded::default(),
            obstacle_impulses_total: Vec::new(),
            emitted,
        }
    }

    /// The world, to read.
    pub(crate) fn get(&self) -> MutexGuard<'_, RustWorld> {
        self.world.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The world, to change.
    fn get_mut(&mut self) -> &mut RustWorld {
        self.world.get_mut().unwrap_or_else(|e| e.into_inner())
    }

    /// Refuses a change while a storage view is alive (its arrays point into the storage).
    fn check_unlocked(&self) -> PyResult<()> {
        if self.views.load(Ordering::SeqCst) > 0 {
            return Err(PyRuntimeError::new_err(
                "a storage view of this world is still alive: leave its `with` block and drop \
                 the arrays taken from it before changing the world",
            ));
        }
        Ok(())
    }

    fn pairs_to_rows(values: Vec<f64>) -> Vec<[f64; 2]> {
        values.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
    }

    /// Writes a frame to every attached writer whose period divides the step count.
    fn feed_writers(&mut self, py: Python<'_>) -> PyResult<()> {
        self.writers.retain(|w| !w.borrow(py).is_closed());
        let world = self.get();
        let step = world.step_count();
        for writer in &self.writers {
            let mut writer = writer.borrow_mut(py);
            if step.is_multiple_of(writer.every) {
                writer.frame(&world, &self.types, &self.typeid)?;
            }
        }
        Ok(())
    }
}

#[pymethods]
impl World {
    #[new]
    #[pyo3(signature = (config = None, dt = None, threads = 1))]
    fn new(config: Option<PyRef<'_, Config>>, dt: Option<f64>, threads: usize) -> PyResult<Self> {
        let config = config.map(|c| c.inner.clone()).unwrap_or_default();
        let mut world = RustWorld::new(config).map_err(value_error)?;
        world.set_threads(threads).map_err(value_error)?;
        if let Some(dt) = dt
            && !(dt.is_finite() && dt > 0.0)
        {
            return Err(PyValueError::new_err(format!(
                "dt = {dt}: must be finite and > 0"
            )));
        }
        Ok(World::wrap(
            world,
            dt,
            (vec!["A".into()], Vec::new()),
            Vec::new(),
        ))
    }

    /// The world a scenario file describes (the TOML the ``bounce`` command runs), discs
    /// placed with the same ids; ``dt`` is the scenario's ``time.dt``. Raises
    /// ``FileNotFoundError`` or ``ValueError`` naming the file, line and field.
    #[staticmethod]
    #[pyo3(signature = (path, threads = 1))]
    fn from_scenario(path: PathBuf, threads: usize) -> PyResult<Self> {
        if !path.exists() {
            return Err(PyFileNotFoundError::new_err(format!(
                "no scenario file {}",
                path.display()
            )));
        }
        let session = bounce_scenario::Session::load(&path).map_err(value_error)?;
        let mut world = session.world;
        world.set_threads(threads).map_err(value_error)?;
        Ok(World::wrap(
            world,
            Some(session.dt),
            (session.types, session.typeid),
            session.emitted,
        ))
    }

    /// Reads a checkpoint written by ``save`` or by ``bounce run`` (``checkpoint.bin``).
    #[staticmethod]
    #[pyo3(signature = (path, dt = None, threads = 1))]
    fn load(path: PathBuf, dt: Option<f64>, threads: usize) -> PyResult<Self> {
        if !path.exists() {
            return Err(PyFileNotFoundError::new_err(format!(
                "no checkpoint {}",
                path.display()
            )));
        }
        let checkpoint = bounce_scenario::checkpoint::load(&path).map_err(value_error)?;
        let mut world = checkpoint.world;
        world.set_threads(threads).map_err(value_error)?;
        Ok(World::wrap(
            world,
            dt,
            (vec!["A".into()], Vec::new()),
            Vec::new(),
        ))
    }

    /// Writes a checkpoint (the format ``bounce run --resume`` reads), atomically.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        bounce_scenario::checkpoint::save(&self.get(), None, &path).map_err(PyOSError::new_err)
    }

    /// Writes the current state as a one-frame GSD file (HOOMD's format).
    fn write_gsd(&self, path: PathBuf) -> PyResult<()> {
        let mut writer = bounce_scenario::gsd::GsdWriter::create(&path, &self.types, &self.typeid)?;
        writer.frame(&self.get())?;
        Ok(writer.finish()?)
    }

    /// Feeds ``writer`` a frame now (when its period divides the step count) and after
    /// every step whose count it divides, until the writer is closed.
    fn add_writer(&mut self, py: Python<'_>, writer: Py<GsdWriter>) -> PyResult<()> {
        if self.writers.iter().any(|w| w.is(&writer)) {
            return Ok(());
        }
        {
            let mut w = writer.borrow_mut(py);
            if w.is_closed() {
                return Err(PyValueError::new_err("the GSD writer is closed"));
            }
            let world = self.get();
            if world.step_count().is_multiple_of(w.every) {
                w.frame(&world, &self.types, &self.typeid)?;
            }
        }
        self.writers.push(writer);
        Ok(())
    }

    /// Stops feeding ``writer`` (it stays open).
    fn remove_writer(&mut self, writer: Py<GsdWriter>) {
        self.writers.retain(|w| !w.is(&writer));
    }

    /// Adds discs: ``positions`` and ``velocities`` of shape (N, 2), ``radii`` of shape (N,)
    /// or one number, ``masses`` (for ``mass_model = "per_particle"``) likewise or ``None``.
    /// Any array-like of real numbers is accepted. All or nothing: a bad row raises
    /// ``ValueError`` naming its index and the world is unchanged. Returns the new ids.
    #[pyo3(signature = (positions, velocities, radii, masses = None, tags = None))]
    fn add_discs<'py>(
        &mut self,
        py: Python<'py>,
        positions: &Bound<'py, PyAny>,
        velocities: &Bound<'py, PyAny>,
        radii: &Bound<'py, PyAny>,
        masses: Option<&Bound<'py, PyAny>>,
        tags: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<u32>>> {
        self.check_unlocked()?;
        let (positions, n) = float_array(py, "positions", positions, Some(2), None)?;
        let (velocities, _) = float_array(py, "velocities", velocities, Some(2), Some(n))?;
        let per_disc = |name: &str, value: &Bound<'py, PyAny>| -> PyResult<Vec<f64>> {
            if let Ok(v) = value.extract::<f64>() {
                return Ok(vec![v; n]);
            }
            Ok(float_array(py, name, value, None, Some(n))?.0)
        };
        let radii = per_disc("radii", radii)?;
        let masses = masses.map(|m| per_disc("masses", m)).transpose()?;
        let tags = tags.map(|t| tag_array(t, n)).transpose()?;
        let discs = (0..n).map(|k| Particle {
            mass: masses.as_ref().map(|m| m[k]),
            tag: tags.as_ref().map_or(0, |t| t[k]),
            ..Particle::new(
                [positions[2 * k], positions[2 * k + 1]],
                [velocities[2 * k], velocities[2 * k + 1]],
                radii[k],
            )
        });
        let ids = self
            .get_mut()
            .add_particles(discs)
            .map_err(|(k, e)| PyValueError::new_err(format!("disc {k}: {e}")))?;
        // New discs take the first type, as the CLI gives discs without one.
        Ok(Array1::from_iter(ids.iter().map(|id| id.0)).into_pyarray(py))
    }

    /// Adds the discs of a file, as a scenario's ``[[file]]`` table does: a GSD frame
    /// (``frame``, negative from the end; positions around the box centre, the file's box
    /// the world's size) or a CSV table with the columns ``x, y, radius`` and optionally
    /// ``vx, vy, mass, type``. The file's types go into GSD files this world writes. All or
    /// nothing: a bad file or disc raises ``ValueError`` naming the file and the line or
    /// particle, and the world is unchanged. Returns the new ids.
    #[pyo3(signature = (path, frame = -1))]
    fn add_file<'py>(
        &mut self,
        py: Python<'py>,
        path: PathBuf,
        frame: i64,
    ) -> PyResult<Bound<'py, PyArray1<u32>>> {
        self.check_unlocked()?;
        let boundary = self.get().config().boundary.clone();
        let read = py
            .detach(|| bounce_scenario::start::read_for(&path, frame, &boundary))
            .map_err(PyValueError::new_err)?;
        let name = path.display().to_string();
        let ids = self
            .get_mut()
            .add_particles(read.discs)
            .map_err(|(k, e)| PyValueError::new_err(format!("{name}: particle {k}: {e}")))?;
        let map: Vec<u32> = read
            .types
            .into_iter()
            .map(|t| match self.types.iter().position(|s| *s == t) {
                Some(k) => k as u32,
                None => {
                    self.types.push(t);
                    self.types.len() as u32 - 1
                }
            })
            .collect();
        for (id, t) in ids.iter().zip(&read.typeid) {
            let id = id.0 as usize;
            if self.typeid.len() <= id {
                self.typeid.resize(id + 1, 0);
            }
            self.typeid[id] = map[*t as usize];
        }
        Ok(Array1::from_iter(ids.iter().map(|id| id.0)).into_pyarray(py))
    }

    /// Adds obstacles (a list of :class:`Obstacle`) after the existing ones, which keep their
    /// motion. Raises ``ValueError`` if the world refuses one; the world is then unchanged.
    fn add_obstacles(&mut self, obstacles: Vec<PyRef<'_, Obstacle>>) -> PyResult<()> {
        self.check_unlocked()?;
        self.get_mut()
            .add_obstacles(obstacles.iter().map(|o| o.inner))
            .map_err(value_error)
    }

    /// The obstacles where they are now (moving ones moved), in the configuration's order.
    #[getter]
    fn obstacles(&self) -> Vec<Obstacle> {
        let world = self.get();
        world
            .obstacle_shapes()
            .into_iter()
            .zip(&world.config().obstacles)
            .map(|(shape, o)| Obstacle {
                inner: bounce::Obstacle { shape, ..*o },
            })
            .collect()
    }

    /// The momentum each obstacle received in the last step only, shape (K, 2): divide by
    /// ``dt`` for the force then. Zero rows for an obstacle no disc touched in that step;
    /// ``obstacle_impulses_total`` adds up every step.
    #[getter]
    fn obstacle_impulses_last_step<'py>(
        &self,
        py: Python<'py>,
    ) -> Bound<'py, numpy::PyArray2<f64>> {
        let values: Vec<f64> = self
            .get()
            .obstacle_impulses()
            .iter()
            .flat_map(|j| [j[0], j[1]])
            .collect();
        rows(py, values, 2)
    }

    /// The momentum each obstacle has received over every step this ``World`` object took
    /// (since it was made, loaded or read from a scenario), shape (K, 2): divided by the
    /// time stepped, the mean force on each.
    #[getter]
    fn obstacle_impulses_total<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        let count = self.get().obstacle_impulses().len();
        let values: Vec<f64> = (0..count)
            .map(|k| {
                self.obstacle_impulses_total
                    .get(k)
                    .copied()
                    .unwrap_or([0.0; 2])
            })
            .flat_map(|j| [j[0], j[1]])
            .collect();
        rows(py, values, 2)
    }

    /// The work the moving obstacles have done on the discs since the start.
    #[getter]
    fn obstacle_work(&self) -> f64 {
        self.get().obstacle_work()
    }

    /// The kinetic energy the thermostat has added since the start (0 without one).
    #[getter]
    fn thermostat_work(&self) -> f64 {
        self.get().thermostat_work()
    }

    /// Where a Lees–Edwards box's images above stand along x now (``shear_rate`` × height ×
    /// time, brought into ``[-width/2, width/2)``); ``None`` in any other boundary.
    #[getter]
    fn lees_edwards_offset(&self) -> Option<f64> {
        self.get().lees_edwards_offset()
    }

    /// The kinetic energy of the motion relative to the centre of mass and, in a
    /// Lees–Edwards box, to the streaming velocity ``shear_rate (y − centre)``: ``N kT`` in
    /// two dimensions, summed in id order.
    #[getter]
    fn peculiar_kinetic_energy(&self) -> f64 {
        self.get().peculiar_kinetic_energy()
    }

    /// The discs' energy now: kinetic, rotational and potential (in gravity), each summed
    /// in id order. The energy dissipated over an interval (by inelastic collisions and
    /// friction) is ``energy`` before, less ``energy`` after, plus the growth of
    /// ``thermostat_work`` and ``obstacle_work`` over it: what ``stats.csv``'s
    /// ``dissipated`` column reports between rows.
    #[getter]
    fn energy(&self) -> f64 {
        bounce_scenario::analysis::total_energy(&self.get())
    }

    /// Advances ``n`` steps of ``dt`` (default: the world's ``dt``), without the GIL: other
    /// Python threads run meanwhile. Ctrl-C raises ``KeyboardInterrupt`` between steps,
    /// the world left after a whole step. Attached GSD writers get their frames.
    /// ``plain=True`` takes the plain reference step instead (one thread, slow; the same
    /// bits as the fast one, which tests hold it to).
    #[pyo3(signature = (n = 1, dt = None, plain = false))]
    fn step(&mut self, py: Python<'_>, n: u64, dt: Option<f64>, plain: bool) -> PyResult<()> {
        self.check_unlocked()?;
        let dt = dt.or(self.dt).ok_or_else(|| {
            PyValueError::new_err(
                "step() needs dt: this world has none (give World(..., dt=...) or step(dt=...))",
            )
        })?;
        self.events.clear();
        for _ in 0..n {
            let world = self.world.get_mut().unwrap_or_else(|e| e.into_inner());
            py.detach(|| {
                if plain {
                    bounce::plain::step(world, dt).map(|_| ())
                } else {
                    world.step(dt).map(|_| ())
                }
            })
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
            if world.config().contact_events {
                self.events.add(world, dt);
            }
            // Discs the emitters added take their emitter's type (in GSD files).
            bounce_scenario::note_emitted(world, &self.emitted, None, &mut self.typeid);
            let impulses = world.obstacle_impulses();
            let totals = &mut self.obstacle_impulses_total;
            totals.resize(impulses.len(), [0.0; 2]);
            for (total, j) in totals.iter_mut().zip(impulses) {
                total[0] += j[0];
                total[1] += j[1];
            }
            py.check_signals()?;
            if !self.writers.is_empty() {
                self.feed_writers(py)?;
            }
        }
        Ok(())
    }

    /// The contact events of every step the last ``step()`` call took (with
    /// ``Config(contact_events=True)``), as a NumPy structured array, one row an event in
    /// order (step, substep, then the parties' ids): ``step``, ``time`` (the end of the
    /// event's substep), ``substep``, ``kind`` (``"begin"`` or ``"end"``), ``a`` (a disc
    /// id), ``b_kind`` (``"disc"``, ``"wall"`` or ``"obstacle"``) and ``b`` (a disc id;
    /// a wall 0–3: left, right, bottom, top; an obstacle's index), ``x``, ``y`` (the
    /// contact point), ``nx``, ``ny`` (the unit normal from ``a`` towards ``b``),
    /// ``normal_impulse`` (what ``b`` gave ``a`` against the normal), ``tangent_impulse``
    /// and ``approach_speed`` (0 for an end). The plain step reports none.
    fn contact_events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.events.array(py)
    }

    /// Each sensor's counts by name: ``{"entered": ..., "left": ..., "inside": ...,
    /// "entered_last_step": ..., "left_last_step": ...}`` (the discs whose centre entered
    /// and left its region since the world was made, those inside now, and the last step's).
    #[getter]
    fn sensors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let world = self.get();
        let out = PyDict::new(py);
        for (sensor, count) in world.config().sensors.iter().zip(world.sensors()) {
            let d = PyDict::new(py);
            d.set_item("entered", count.entered)?;
            d.set_item("left", count.left)?;
            d.set_item("inside", count.inside)?;
            d.set_item("entered_last_step", count.entered_last_step)?;
            d.set_item("left_last_step", count.left_last_step)?;
            out.set_item(&sensor.name, d)?;
        }
        Ok(out)
    }

    /// The pressure tensor ``(P_xx, P_yy, P_xy)`` now, kinetic plus collisional (the last
    /// step's virial), over the area of ``stats["pressure"]``; ``None`` unless
    /// ``Config(pressure_tensor=True)``, or in an open world. ``(P_xx + P_yy) / 2`` is the
    /// pressure.
    #[getter]
    fn pressure_tensor(&self) -> Option<(f64, f64, f64)> {
        self.get()
            .pressure_tensor()
            .map(|[xx, yy, xy]| (xx, yy, xy))
    }

    /// Profiles binned along ``axis`` (``"x"`` or ``"y"``) in ``bins`` equal bins across the
    /// box, as ``profile.csv`` writes them: a dict of arrays ``centre``, ``count``,
    /// ``density`` (discs per area), ``vx``, ``vy`` (the mass-weighted mean velocity) and
    /// ``temperature`` (2D kT in the bin's frame, over ``count − 1``). Raises ``ValueError``
    /// in an open world.
    #[pyo3(signature = (axis="y", bins=20))]
    fn profiles<'py>(
        &self,
        py: Python<'py>,
        axis: &str,
        bins: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        use bounce_scenario::observables::{Axis, profile};
        let axis = match axis {
            "x" => Axis::X,
            "y" => Axis::Y,
            other => {
                return Err(PyValueError::new_err(format!(
                    "axis = {other:?}: expected \"x\" or \"y\""
                )));
            }
        };
        let p = profile(&self.get(), axis, bins).map_err(PyValueError::new_err)?;
        let d = PyDict::new(py);
        d.set_item("centre", p.centre.into_pyarray(py))?;
        d.set_item("count", p.count.into_pyarray(py))?;
        d.set_item("density", p.density.into_pyarray(py))?;
        let (vx, vy): (Vec<f64>, Vec<f64>) = p.velocity.iter().map(|v| (v[0], v[1])).unzip();
        d.set_item("vx", vx.into_pyarray(py))?;
        d.set_item("vy", vy.into_pyarray(py))?;
        d.set_item("temperature", p.temperature.into_pyarray(py))?;
        Ok(d)
    }

    /// A snapshot of the discs binned for spatial queries (:class:`Queries`: ``in_circle``,
    /// ``in_box``, ``nearest``, ``ray_cast``); ask for a new one after a step.
    fn queries(&self) -> Queries {
        Queries {
            inner: self.get().queries(),
        }
    }

    /// The configuration.
    #[getter]
    fn config(&self) -> Config {
        Config {
            inner: self.get().config().clone(),
        }
    }

    /// The time step ``step`` uses by default (``None`` when there is none).
    #[getter]
    fn dt(&self) -> Option<f64> {
        self.dt
    }

    #[setter]
    fn set_dt(&mut self, dt: Option<f64>) -> PyResult<()> {
        if let Some(dt) = dt
            && !(dt.is_finite() && dt > 0.0)
        {
            return Err(PyValueError::new_err(format!(
                "dt = {dt}: must be finite and > 0"
            )));
        }
        self.dt = dt;
        Ok(())
    }

    /// Worker threads of the step (results are the same bits for any count).
    #[getter]
    fn threads(&self) -> usize {
        self.get().threads()
    }

    #[setter]
    fn set_threads(&mut self, threads: usize) -> PyResult<()> {
        self.get_mut().set_threads(threads).map_err(value_error)
    }

    /// Simulated time.
    #[getter]
    fn time(&self) -> f64 {
        self.get().time()
    }

    /// Steps taken.
    #[getter]
    fn step_count(&self) -> u64 {
        self.get().step_count()
    }

    /// What the last step measured, as a dict: ``kinetic_energy``, ``momentum`` (px, py),
    /// ``collisions`` (impacts: pairs that met approaching faster than a resting contact),
    /// ``contacts`` (every pair found in every substep, resting ones included),
    /// ``wall_impulse`` (a dict per wall), ``max_overlap``,
    /// ``virial``, ``pressure`` (``None`` in an open world), ``substeps`` and
    /// ``obstacle_work`` (the work moving obstacles did on the discs in the step),
    /// ``emitted`` and ``removed`` (discs the emitters added and the sinks took).
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let world = self.get();
        let s = world.stats();
        let d = PyDict::new(py);
        d.set_item("kinetic_energy", s.kinetic_energy)?;
        d.set_item("momentum", (s.momentum[0], s.momentum[1]))?;
        d.set_item("collisions", s.collisions)?;
        d.set_item("contacts", s.pairs)?;
        let walls = PyDict::new(py);
        walls.set_item("left", s.wall_impulse.left)?;
        walls.set_item("right", s.wall_impulse.right)?;
        walls.set_item("bottom", s.wall_impulse.bottom)?;
        walls.set_item("top", s.wall_impulse.top)?;
        d.set_item("wall_impulse", walls)?;
        d.set_item("max_overlap", s.max_overlap)?;
        d.set_item("virial", s.virial)?;
        d.set_item("pressure", s.pressure)?;
        d.set_item("substeps", s.substeps)?;
        d.set_item("obstacle_work", s.obstacle_work)?;
        d.set_item("friction_work", s.friction_work)?;
        d.set_item("thermostat_work", s.thermostat_work)?;
        d.set_item("virial_tensor", s.virial_tensor.to_vec())?;
        d.set_item("rotational_energy", world.rotational_energy())?;
        d.set_item("angular_momentum", world.angular_momentum())?;
        d.set_item("emitted", s.emitted)?;
        d.set_item("removed", s.removed)?;
        Ok(d)
    }

    /// Wall-clock seconds of each stage of the last step, measured inside the engine:
    /// ``integrate``, ``bin`` (broadphase upkeep), ``pairs``, ``resolve``, ``obstacles``,
    /// ``walls`` (the hold after later solver passes), ``measure``, ``total``; and counts: ``rebuilds`` (substeps that rebuilt the candidate list),
    /// ``sorted_detections`` (detections that sorted their contacts rather than finding
    /// them presorted) and ``out_of_place`` (contacts a presorted detection merged in).
    #[getter]
    fn profile<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let world = self.get();
        let p = world.profile();
        let d = PyDict::new(py);
        d.set_item("integrate", p.integrate)?;
        d.set_item("bin", p.bin)?;
        d.set_item("pairs", p.pairs)?;
        d.set_item("resolve", p.resolve)?;
        d.set_item("obstacles", p.obstacles)?;
        d.set_item("walls", p.walls)?;
        d.set_item("measure", p.measure)?;
        d.set_item("total", p.total())?;
        d.set_item("rebuilds", p.rebuilds)?;
        d.set_item("sorted_detections", p.sorted_detections)?;
        d.set_item("out_of_place", p.out_of_place)?;
        Ok(d)
    }

    /// A 64-bit hash of the state (ids, positions, velocities, radii bit for bit, angular
    /// velocities and orientations where discs turn, and the step count): the one
    /// ``bounce run`` prints.
    fn state_hash(&self) -> u64 {
        self.get().state_hash()
    }

    /// Positions, shape (N, 2), in id order (a copy). Settable: all rows are checked
    /// against the boundary first; a bad row raises naming its index, nothing changes.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        let world = self.get();
        let p = world.particles();
        let values = by_id(&world, |i| [p.x()[i], p.y()[i]]);
        rows(py, values, 2)
    }

    #[setter]
    fn set_positions(&mut self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.check_unlocked()?;
        let n = self.get().len();
        let (values, _) = float_array(py, "positions", value, Some(2), Some(n))?;
        self.get_mut()
            .set_positions(&World::pairs_to_rows(values))
            .map_err(|(k, e)| PyValueError::new_err(format!("disc {k}: {e}")))
    }

    /// Velocities, shape (N, 2), in id order (a copy). Settable like ``positions``.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        let world = self.get();
        let p = world.particles();
        let values = by_id(&world, |i| [p.vx()[i], p.vy()[i]]);
        rows(py, values, 2)
    }

    #[setter]
    fn set_velocities(&mut self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.check_unlocked()?;
        let n = self.get().len();
        let (values, _) = float_array(py, "velocities", value, Some(2), Some(n))?;
        self.get_mut()
            .set_velocities(&World::pairs_to_rows(values))
            .map_err(|(k, e)| PyValueError::new_err(format!("disc {k}: {e}")))
    }

    /// Angular velocities (counter-clockwise, radians per time unit), shape (N,), in id
    /// order (a copy; zeros for discs that never turned). Settable: a spinning disc turns,
    /// and rough discs (``Config(friction=...)``) change their spin at contacts.
    #[getter]
    fn angular_velocities<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        Array1::from(self.get().angular_velocities()).into_pyarray(py)
    }

    #[setter]
    fn set_angular_velocities(&mut self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.check_unlocked()?;
        let n = self.get().len();
        let (values, _) = float_array(py, "angular_velocities", value, None, Some(n))?;
        self.get_mut()
            .set_angular_velocities(&values)
            .map_err(|(k, e)| PyValueError::new_err(format!("disc {k}: {e}")))
    }

    /// Orientations (radians, within one turn), shape (N,), in id order (a copy).
    #[getter]
    fn orientations<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        Array1::from(self.get().orientations()).into_pyarray(py)
    }

    /// The energy friction and rolling resistance have removed since the start.
    #[getter]
    fn friction_work(&self) -> f64 {
        self.get().friction_work()
    }

    /// Radii, shape (N,), in id order (a copy).
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let world = self.get();
        let p = world.particles();
        Array1::from(by_id(&world, |i| [p.radius()[i]])).into_pyarray(py)
    }

    /// Masses under the configured mass model, shape (N,), in id order (a copy).
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let world = self.get();
        let p = world.particles();
        let law = Law::new(world.config());
        let m = p.per_particle_mass();
        Array1::from(by_id(&world, |i| [law.mass(p.radius()[i], m[i])])).into_pyarray(py)
    }

    /// Ids, shape (N,): ``0 .. N-1``, the order of every id-ordered array.
    #[getter]
    fn ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u32>> {
        let order = self.get().in_id_order();
        Array1::from_iter(order.into_iter().map(|(id, _)| id.0)).into_pyarray(py)
    }

    /// Each disc's collisions with other discs so far (``uint64``, id order, as ``ids``),
    /// with ``Config(collision_counts=True)``; ``None`` otherwise. An impact counts once for
    /// each of its two discs (as ``stats["collisions"]`` counts impacts).
    #[getter]
    fn collision_counts<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<u64>>> {
        let world = self.get();
        let counts = world.collision_counts()?;
        let order = world.in_id_order();
        Some(
            Array1::from_iter(order.into_iter().map(|(id, _)| counts[id.0 as usize]))
                .into_pyarray(py),
        )
    }

    /// Each disc's tag (``uint64``, id order): the user's own number, carried through every
    /// step, checkpoint and GSD frame (``log/particles/tag``); 0 unless set.
    #[getter]
    fn tags<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u64>> {
        let world = self.get();
        let p = world.particles();
        let order = world.in_id_order();
        Array1::from_iter(order.into_iter().map(|(_, i)| p.tag_of(i))).into_pyarray(py)
    }

    #[setter]
    fn set_tags(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.check_unlocked()?;
        let n = self.get().len();
        let tags = tag_array(value, n)?;
        let world = self.get_mut();
        for ((id, _), tag) in world.in_id_order().into_iter().zip(tags) {
            world.set_tag(id, tag).map_err(value_error)?;
        }
        Ok(())
    }

    /// Read-only arrays over the engine's own memory, in storage order, without a copy:
    /// ``x``, ``y``, ``vx``, ``vy``, ``radius``, ``omega`` (float64; ``omega`` empty while no
    /// disc turns) and ``ids`` (uint32, the id of each storage slot). Storage order changes when the world steps, so while the view or
    /// any array taken from it is alive the world refuses to step or change (``RuntimeError``).
    /// Use it as a context manager::
    ///
    ///     with world.storage_view() as v:
    ///         speed2 = v.vx**2 + v.vy**2
    fn storage_view(slf: &Bound<'_, World>) -> PyResult<StorageView> {
        let py = slf.py();
        let this = slf.borrow();
        let guard =
            Bound::new(py, ViewGuard::new(this.views.clone(), slf.clone().unbind()))?.into_any();
        let world = this.get();
        let p = world.particles();
        let view = |values: &[f64]| -> PyResult<Py<PyAny>> {
            // SAFETY: the array borrows the world's storage, which neither moves nor changes
            // while `guard` (its base object) lives: every changing method checks the count
            // `guard` holds up, and `guard` keeps the world object alive.
            let array =
                unsafe { PyArray1::borrow_from_array(&ArrayView1::from(values), guard.clone()) };
            read_only(&array)?;
            Ok(array.into_any().unbind())
        };
        // SAFETY: `ParticleId` is `repr(transparent)` over `u32`.
        let ids: &[u32] =
            unsafe { std::slice::from_raw_parts(p.ids().as_ptr().cast::<u32>(), p.len()) };
        // SAFETY: as for `view`.
        let ids = unsafe { PyArray1::borrow_from_array(&ArrayView1::from(ids), guard.clone()) };
        read_only(&ids)?;
        Ok(StorageView {
            arrays: Some([
                view(p.x())?,
                view(p.y())?,
                view(p.vx())?,
                view(p.vy())?,
                view(p.radius())?,
                ids.into_any().unbind(),
                view(p.angular_velocity())?,
            ]),
        })
    }

    fn __len__(&self) -> usize {
        self.get().len()
    }

    fn __repr__(&self) -> String {
        let world = self.get();
        format!(
            "bounce.World({} discs, step {}, time {:?}, {})",
            world.len(),
            world.step_count(),
            world.time(),
            Config {
                inner: world.config().clone()
            }
            .__repr__()
        )
    }
}

/// Gathers `f(i)` for each id in order, `W` values per disc.
fn by_id<const W: usize>(world: &RustWorld, f: impl Fn(usize) -> [f64; W]) -> Vec<f64> {
    let mut out = Vec::with_capacity(world.len() * W);
    for (_, i) in world.in_id_order() {
        out.extend_from_slice(&f(i));
    }
    out
}

/// `values` (row-major, `width` per row) as an (N, width) array, without a copy.
fn rows(py: Python<'_>, values: Vec<f64>, width: usize) -> Bound<'_, numpy::PyArray2<f64>> {
    let n = values.len() / width;
    Array2::from_shape_vec((n, width), values)
        .expect("whole rows")
        .into_pyarray(py)
}

fn read_only<T>(array: &Bound<'_, T>) -> PyResult<()> {
    let array = array.as_any();
    let py = array.py();
    let kwargs = PyDict::new(py);
    kwargs.set_item("write", false)?;
    array.call_method("setflags", (), Some(&kwargs))?;
    Ok(())
}

/// Holds a world unchanged while arrays of a storage view are alive (it is their base).
#[pyclass(module = "bounce", frozen)]
struct ViewGuard {
    views: Arc<AtomicUsize>,
    _world: Py<World>,
}

impl ViewGuard {
    fn new(views: Arc<AtomicUsize>, world: Py<World>) -> Self {
        views.fetch_add(1, Ordering::SeqCst);
        ViewGuard {
            views,
            _world: world,
        }
    }
}

impl Drop for ViewGuard {
    fn drop(&mut self) {
        self.views.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Read-only arrays over a world's storage (see ``World.storage_view``).
#[pyclass(module = "bounce", name = "StorageView")]
pub struct StorageView {
    arrays: Option<[Py<PyAny>; 7]>,
}

impl StorageView {
    fn array(&self, py: Python<'_>, k: usize) -> PyResult<Py<PyAny>> {
        self.arrays
            .as_ref()
            .map(|a| a[k].clone_ref(py))
            .ok_or_else(|| PyRuntimeError::new_err("the storage view was closed"))
    }
}

#[pymethods]
impl StorageView {
    /// x of each storage slot.
    #[getter]
    fn x(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.array(py, 0)
    }
    /// y of each storage slot.
    #[getter]
    fn y(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.array(py, 1)
    }
    /// vx of each storage slot.
    #[getter]
    fn vx(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.array(py, 2)
    }
    /// vy of each storage slot.
    #[getter]
    fn vy(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.array(py, 3)
    }
    /// Radius of each storage slot.
    #[getter]
    fn radius(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.array(py, 4)
    }
    /// The id in each storage slot.
    #[getter]
    fn ids(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.array(py, 5)
    }
    /// Angular velocity of each storage slot (empty while no disc turns).
    #[getter]
    fn omega(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.array(py, 6)
    }

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    /// Drops the view's arrays (arrays taken from it still hold the world).
    #[pyo3(signature = (*_args))]
    fn __exit__(&mut self, _args: &Bound<'_, pyo3::types::PyTuple>) -> bool {
        self.close();
        false
    }

    /// Drops the view's arrays, as leaving its ``with`` block does.
    fn close(&mut self) {
        self.arrays = None;
    }
}
