//! One-dimensional self-gravity between Python and the engine: `Simulation.set_self_gravity
//! (coupling)` and the `self_gravity=` argument of `Simulation.from_arrays` read into an
//! `edmd_core::SelfGravity` (with messages that name the argument), and
//! `Simulation.self_gravity` given back as the coupling they take. It says what a file's
//! `# edmd self-gravity C` line says (`edmd_io::princeton`).

use edmd_core::{Error, SelfGravity, Simulation};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::args::{self, num};

fn value_error(m: String) -> PyErr {
    PyValueError::new_err(args::shorten_numbers(&m))
}

/// `None` (no self-gravity) or the coupling, a finite number above 0, as argument `name`.
pub fn parse(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Option<SelfGravity>> {
    if obj.is_none() {
        return Ok(None);
    }
    let coupling = args::real(obj, name)?;
    if !(coupling.is_finite() && coupling > 0.0) {
        return Err(value_error(format!(
            "{name}: the coupling must be a finite number above 0, got {}",
            num(coupling)
        )));
    }
    Ok(Some(SelfGravity { coupling }))
}

/// Puts `sim` under self-gravity (none for `None`), refused with a message naming the
/// argument `name`, and then nothing changes. The self-gravity `sim` has already changes
/// nothing, so that `set_self_gravity(sim.self_gravity)` keeps the rods' ranks.
pub fn apply<const D: usize>(
    sim: &mut Simulation<D>,
    gravity: Option<SelfGravity>,
    name: &str,
) -> PyResult<()> {
    let now = sim.self_gravity();
    if now.map(|g| g.coupling.to_bits()) == gravity.map(|g| g.coupling.to_bits()) {
        return Ok(());
    }
    sim.set_self_gravity(gravity).map_err(|e| message(name, e))
}

/// The engine's refusal as `name: why` (its self-gravity messages name self-gravity).
fn message(name: &str, e: Error) -> PyErr {
    value_error(format!("{name}: {e}"))
}
