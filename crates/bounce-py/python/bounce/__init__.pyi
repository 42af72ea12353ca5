"""Type stubs for bounce (the compiled module ``bounce._native``)."""

from os import PathLike
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, PathLike[str]]
_Pair = Tuple[float, float]

class WallImpulse(TypedDict):
    left: float
    right: float
    bottom: float
    top: float

class Thermostat(TypedDict, total=False):
    kind: Literal["rescale", "andersen", "white_noise"]
    temperature: float
    rate: float
    seed: int

class Stats(TypedDict):
    kinetic_energy: float
    momentum: _Pair
    collisions: int
    contacts: int
    wall_impulse: WallImpulse
    max_overlap: float
    virial: float
    pressure: Optional[float]
    substeps: int
    obstacle_work: float
    friction_work: float
    thermostat_work: float
    virial_tensor: List[float]
    rotational_energy: float
    angular_momentum: float
    emitted: int
    removed: int

class Emitter:
    """Adds discs in a rectangle at a rate."""

    def __init__(
        self,
        min: _Pair,
        max: _Pair,
        rate: float,
        radius: Union[float, _Pair],
        *,
        velocity: _Pair = (0.0, 0.0),
        spread: float = 0.0,
        seed: int = 0,
        limit: Optional[int] = None,
    ) -> None: ...
    @property
    def rate(self) -> float: ...

class Sink:
    """Removes the discs whose centre enters a rectangle."""

    def __init__(self, min: _Pair, max: _Pair) -> None: ...

class Sensor:
    """Counts the discs whose centre enters and leaves a box (min, max) or a circle
    (centre, radius)."""

    def __init__(
        self,
        name: str,
        min: Optional[_Pair] = ...,
        max: Optional[_Pair] = ...,
        centre: Optional[_Pair] = ...,
        radius: Optional[float] = ...,
    ) -> None: ...
    @property
    def name(self) -> str: ...

class Queries:
    """A snapshot of the discs binned for spatial queries (World.queries()); answers are ids."""

    def in_circle(self, centre: _Pair, radius: float) -> npt.NDArray[np.uint32]: ...
    def in_box(self, min: _Pair, max: _Pair) -> npt.NDArray[np.uint32]: ...
    def nearest(self, point: _Pair) -> Optional[Tuple[int, float]]: ...
    def ray_cast(
        self, origin: _Pair, direction: _Pair, max_fraction: float = ...
    ) -> Optional[Dict[str, object]]: ...
    def __len__(self) -> int: ...

class Obstacle:
    """A segment or a peg that discs collide with, fixed or moving."""

    @staticmethod
    def segment(
        a: _Pair,
        b: _Pair,
        *,
        restitution: Optional[float] = None,
        velocity: Optional[_Pair] = None,
        force: Optional[_Pair] = None,
        mass: Optional[float] = None,
        friction: Optional[float] = None,
    ) -> Obstacle: ...
    @staticmethod
    def peg(
        centre: _Pair,
        radius: float,
        *,
        restitution: Optional[float] = None,
        velocity: Optional[_Pair] = None,
        force: Optional[_Pair] = None,
        mass: Optional[float] = None,
        friction: Optional[float] = None,
    ) -> Obstacle: ...
    @property
    def kind(self) -> Literal["segment", "peg"]: ...
    @property
    def ends(self) -> Optional[Tuple[_Pair, _Pair]]: ...
    @property
    def centre(self) -> Optional[_Pair]: ...
    @property
    def radius(self) -> Optional[float]: ...
    @property
    def restitution(self) -> Optional[float]: ...
    @property
    def friction(self) -> Optional[float]: ...

def polyline(
    points: Sequence[_Pair],
    closed: bool = False,
    *,
    restitution: Optional[float] = None,
    velocity: Optional[_Pair] = None,
    friction: Optional[float] = None,
) -> List[Obstacle]: ...
def rectangle(
    centre: _Pair,
    size: _Pair,
    angle: float = 0.0,
    *,
    restitution: Optional[float] = None,
    velocity: Optional[_Pair] = None,
    friction: Optional[float] = None,
) -> List[Obstacle]: ...

class Config:
    """The world's configuration; every keyword defaults to the default model's value."""

    def __init__(
        self,
        *,
        collision_radius_scale: float = ...,
        coefficient_of_restitution: float = ...,
        gravity: _Pair = ...,
        substeps: int = ...,
        solver_iterations: int = ...,
        max_travel: Optional[float] = ...,
        boundary: Literal["open", "walls", "periodic", "lees_edwards"] = ...,
        min: Optional[_Pair] = ...,
        max: Optional[_Pair] = ...,
        wall_restitution: Optional[float] = ...,
        shear_rate: Optional[float] = ...,
        mass_model: Literal["radius", "area", "per_particle"] = ...,
        restitution_model: Literal["scale_each_normal_velocity", "relative_normal_velocity"] = ...,
        velocity_update: Literal["all_detected", "approaching_only"] = ...,
        resting_contacts: Literal["bounce", "rest"] = ...,
        friction: float = ...,
        wall_friction: Optional[float] = ...,
        tangential_restitution: float = ...,
        rolling_resistance: float = ...,
        inertia_factor: float = ...,
        method: Literal["time_stepped", "event_driven"] = ...,
        contact_duration: float = ...,
        contact_events: bool = ...,
        contact_event_threshold: float = ...,
        obstacles: Sequence[Obstacle] = ...,
        emitters: Sequence[Emitter] = ...,
        sinks: Sequence[Sink] = ...,
        sensors: Sequence[Sensor] = ...,
        thermostat: Optional[Thermostat] = ...,
        pressure_tensor: bool = ...,
        collision_counts: bool = ...,
    ) -> None: ...
    @property
    def obstacles(self) -> List[Obstacle]: ...
    @property
    def collision_radius_scale(self) -> float: ...
    @property
    def coefficient_of_restitution(self) -> float: ...
    @property
    def gravity(self) -> _Pair: ...
    @property
    def substeps(self) -> int: ...
    @property
    def solver_iterations(self) -> int: ...
    @property
    def max_travel(self) -> Optional[float]: ...
    @property
    def boundary(self) -> Literal["open", "walls", "periodic", "lees_edwards"]: ...
    @property
    def shear_rate(self) -> Optional[float]: ...
    @property
    def min(self) -> Optional[_Pair]: ...
    @property
    def max(self) -> Optional[_Pair]: ...
    @property
    def wall_restitution(self) -> Optional[float]: ...
    @property
    def mass_model(self) -> str: ...
    @property
    def restitution_model(self) -> str: ...
    @property
    def velocity_update(self) -> str: ...
    @property
    def resting_contacts(self) -> str: ...
    @property
    def friction(self) -> float: ...
    @property
    def wall_friction(self) -> Optional[float]: ...
    @property
    def tangential_restitution(self) -> float: ...
    @property
    def rolling_resistance(self) -> float: ...
    @property
    def inertia_factor(self) -> float: ...
    @property
    def method(self) -> Literal["time_stepped", "event_driven"]: ...
    @property
    def contact_duration(self) -> float: ...
    @property
    def contact_events(self) -> bool: ...
    @property
    def contact_event_threshold(self) -> float: ...
    @property
    def thermostat(self) -> Optional[Thermostat]: ...
    @property
    def pressure_tensor(self) -> bool: ...
    @property
    def collision_counts(self) -> bool: ...

class StorageView:
    """Read-only arrays over the engine's storage; the world is frozen while any lives."""

    @property
    def x(self) -> npt.NDArray[np.float64]: ...
    @property
    def y(self) -> npt.NDArray[np.float64]: ...
    @property
    def vx(self) -> npt.NDArray[np.float64]: ...
    @property
    def vy(self) -> npt.NDArray[np.float64]: ...
    @property
    def radius(self) -> npt.NDArray[np.float64]: ...
    @property
    def ids(self) -> npt.NDArray[np.uint32]: ...
    @property
    def omega(self) -> npt.NDArray[np.float64]: ...
    def close(self) -> None: ...
    def __enter__(self) -> "StorageView": ...
    def __exit__(self, *args: object) -> bool: ...

class GSDWriter:
    """A GSD trajectory, fed by ``World.step`` once attached with ``World.add_writer``."""

    def __init__(self, path: _Path, every: int = 1) -> None: ...
    @property
    def path(self) -> str: ...
    @property
    def every(self) -> int: ...
    def write(self, world: "World") -> None: ...
    def close(self) -> None: ...
    def __enter__(self) -> "GSDWriter": ...
    def __exit__(self, *args: object) -> bool: ...

class World:
    """A world of discs; arrays in id order unless said otherwise."""

    def __init__(
        self, config: Optional[Config] = None, dt: Optional[float] = None, threads: int = 1
    ) -> None: ...
    @staticmethod
    def from_scenario(path: _Path, threads: int = 1) -> "World": ...
    @staticmethod
    def load(path: _Path, dt: Optional[float] = None, threads: int = 1) -> "World": ...
    def save(self, path: _Path) -> None: ...
    def write_gsd(self, path: _Path) -> None: ...
    def add_writer(self, writer: GSDWriter) -> None: ...
    def remove_writer(self, writer: GSDWriter) -> None: ...
    def add_discs(
        self,
        positions: npt.ArrayLike,
        velocities: npt.ArrayLike,
        radii: npt.ArrayLike,
        masses: Optional[npt.ArrayLike] = None,
        tags: Optional[npt.ArrayLike] = None,
    ) -> npt.NDArray[np.uint32]: ...
    def add_file(self, path: _Path, frame: int = -1) -> npt.NDArray[np.uint32]: ...
    def step(self, n: int = 1, dt: Optional[float] = None, plain: bool = False) -> None: ...
    @property
    def config(self) -> Config: ...
    @property
    def dt(self) -> Optional[float]: ...
    @dt.setter
    def dt(self, value: Optional[float]) -> None: ...
    @property
    def threads(self) -> int: ...
    @threads.setter
    def threads(self, value: int) -> None: ...
    @property
    def time(self) -> float: ...
    @property
    def step_count(self) -> int: ...
    @property
    def stats(self) -> Stats: ...
    @property
    def profile(self) -> Dict[str, float]: ...
    def state_hash(self) -> int: ...
    def add_obstacles(self, obstacles: Sequence[Obstacle]) -> None: ...
    @property
    def obstacles(self) -> List[Obstacle]: ...
    @property
    def obstacle_impulses_last_step(self) -> npt.NDArray[np.float64]: ...
    @property
    def obstacle_impulses_total(self) -> npt.NDArray[np.float64]: ...
    @property
    def thermostat_work(self) -> float: ...
    @property
    def lees_edwards_offset(self) -> Optional[float]: ...
    @property
    def peculiar_kinetic_energy(self) -> float: ...
    @property
    def energy(self) -> float: ...
    @property
    def obstacle_work(self) -> float: ...
    @property
    def sensors(self) -> Dict[str, Dict[str, int]]: ...
    def queries(self) -> Queries: ...
    @property
    def tags(self) -> npt.NDArray[np.uint64]: ...
    @tags.setter
    def tags(self, value: npt.ArrayLike) -> None: ...
    @property
    def pressure_tensor(self) -> Optional[Tuple[float, float, float]]: ...
    @property
    def collision_counts(self) -> Optional[npt.NDArray[np.uint64]]: ...
    def profiles(
        self, axis: Literal["x", "y"] = "y", bins: int = 20
    ) -> Dict[str, npt.NDArray[np.float64]]:
        """Profiles along an axis: centre, count, density, vx, vy, temperature."""
        ...
    def contact_events(self) -> npt.NDArray[np.void]:
        """The contact events of the last ``step()`` call's steps: a structured array with
        fields step, time, substep, kind, a, b_kind, b, x, y, nx, ny, normal_impulse,
        tangent_impulse, approach_speed."""
        ...
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @positions.setter
    def positions(self, value: npt.ArrayLike) -> None: ...
    @property
    def velocities(self) -> npt.NDArray[np.float64]: ...
    @velocities.setter
    def velocities(self, value: npt.ArrayLike) -> None: ...
    @property
    def angular_velocities(self) -> npt.NDArray[np.float64]: ...
    @angular_velocities.setter
    def angular_velocities(self, value: npt.ArrayLike) -> None: ...
    @property
    def orientations(self) -> npt.NDArray[np.float64]: ...
    @property
    def friction_work(self) -> float: ...
    @property
    def radii(self) -> npt.NDArray[np.float64]: ...
    @property
    def masses(self) -> npt.NDArray[np.float64]: ...
    @property
    def ids(self) -> npt.NDArray[np.uint32]: ...
    def storage_view(self) -> StorageView: ...
    def __len__(self) -> int: ...

def rdf(
    source: Union[_Path, World],
    r_max: Optional[float] = None,
    bin: Optional[float] = None,
    first: int = 0,
    boundary: Optional[Literal["periodic", "walls", "open"]] = None,
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """g(r) of a GSD trajectory's frames from ``first``: ``(r, g)`` (bin centres, g)."""
    ...

def psi6(
    source: Union[_Path, World],
    first: int = 0,
    boundary: Optional[Literal["periodic", "walls", "open"]] = None,
) -> Tuple[npt.NDArray[np.uint64], npt.NDArray[np.float64]]:
    """The global bond order |ψ6| of each frame from ``first``: ``(steps, psi6)``."""
    ...

def msd(
    path: _Path,
    first: int = 0,
    boundary: Optional[Literal["periodic", "walls", "open"]] = None,
) -> Tuple[npt.NDArray[np.uint64], npt.NDArray[np.float64]]:
    """The mean-square displacement over every origin: ``(lags in steps, msd)``."""
    ...

def speed_histogram(world: World, bins: int = 30) -> Dict[str, Any]:
    """The speeds against 2D Maxwell–Boltzmann: ``width``, ``density``, ``kt``, ``curve``."""
    ...

def sweep(
    sweep_file: _Path, out: _Path = "sweep", jobs: int = 1, command: _Path = "bounce"
) -> object:
    """Runs ``bounce sweep``; the signac project (or summary rows without signac)."""
    ...
