//! `kea`, the Python module: worlds built in code or from scene files, and batches of worlds
//! stepped on all cores with the GIL released, read and written as numpy arrays.
//!
//! Every error is a Python exception whose message names the argument and its value:
//! `ValueError` for bad input, `IndexError` for a body, collider or joint that does not
//! exist, `RuntimeError` for a failure inside the engine.

mod batch;
mod batch_robot;
mod convert;
mod link_states;
mod pickle;
mod queries;
mod robot;
mod state;
mod world;

use pyo3::prelude::*;

/// Kea: rigid-body dynamics with an exact constraint solver.
#[pymodule]
fn _kea(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<world::PyWorld>()?;
    m.add_class::<batch::PyBatch>()?;
    m.add("STATE_WIDTH", state::STATE_WIDTH)?;
    m.add("DOUBLE_PRECISION", cfg!(feature = "f64"))?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
