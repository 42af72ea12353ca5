//! bounce for Python: the extension module `bounce._native`, re-exported by the package
//! `bounce` (`python/bounce/__init__.py`).
//!
//! | file | owns |
//! |---|---|
//! | `config.rs` | `Config`: keyword arguments to the Rust `Config`, validated |
//! | `world/mod.rs` | `World`: NumPy in and out, `step` without the GIL, the storage view |
//! | `world/gsd.rs` | `GSDWriter`: the CLI's GSD writer fed by `World.step` |
//! | `obstacle.rs` | `Obstacle` (segments, pegs; fixed or moving), `polyline`, `rectangle` |
//! | `sources.rs` | `Emitter` and `Sink`: discs added and removed during a run |
//! | `structure.rs` | `rdf`, `psi6`, `msd`: a GSD trajectory's structure, as `bounce analyze`; `speed_histogram` |

use pyo3::prelude::*;

mod config;
mod events;
mod obstacle;
mod query;
mod sources;
mod structure;
mod world;

/// The compiled core of the `bounce` package.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<config::Config>()?;
    m.add_class::<world::World>()?;
    m.add_class::<world::StorageView>()?;
    m.add_class::<world::GsdWriter>()?;
    m.add_class::<obstacle::Obstacle>()?;
    m.add_class::<sources::Emitter>()?;
    m.add_class::<sources::Sink>()?;
    m.add_class::<sources::Sensor>()?;
    m.add_class::<query::Queries>()?;
    m.add_function(wrap_pyfunction!(obstacle::polyline, m)?)?;
    m.add_function(wrap_pyfunction!(obstacle::rectangle, m)?)?;
    m.add_function(wrap_pyfunction!(structure::rdf, m)?)?;
    m.add_function(wrap_pyfunction!(structure::psi6, m)?)?;
    m.add_function(wrap_pyfunction!(structure::msd, m)?)?;
    m.add_function(wrap_pyfunction!(structure::speed_histogram, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
