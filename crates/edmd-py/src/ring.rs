//! A patch of a planetary ring between Python and the engine: `Simulation.set_ring(omega)`
//! and the `ring=` argument of `Simulation.from_arrays` read into an `edmd_core::Ring` (with
//! messages that name the argument), and `Simulation.ring` given back as the orbital
//! frequency they take. It says what a file's `# edmd ring OMEGA` line says
//! (`edmd_io::princeton`).

use edmd_core::{Error, Ring, Simulation};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::args::{self, num};

fn value_error(m: String) -> PyErr {
    PyValueError::new_err(args::shorten_numbers(&m))
}

/// `None` (no ring) or the orbital frequency, a finite number above 0, as argument `name`.
pub fn parse(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Option<Ring>> {
    if obj.is_none() {
        return Ok(None);
    }
    let omega = args::real(obj, name)?;
    if !(omega.is_finite() && omega > 0.0) {
        return Err(value_error(format!(
            "{name}: the orbital frequency must be a finite number above 0, got {}",
            num(omega)
        )));
    }
    Ok(Some(Ring { omega }))
}

/// Makes `sim` a ring patch (none for `None`), refused with a message naming the argument
/// `name`, and then nothing changes. The ring `sim` has already changes nothing, so that
/// `set_ring(sim.ring)` keeps the images' offset and the flights as they are; another
/// frequency is refused until the ring is taken off.
pub fn apply<const D: usize>(
    sim: &mut Simulation<D>,
    ring: Option<Ring>,
    name: &str,
) -> PyResult<()> {
    let now = sim.ring();
    if now.map(|r| r.omega.to_bits()) == ring.map(|r| r.omega.to_bits()) {
        return Ok(());
    }
    // Another frequency: its images would slide at another rate from the old offset, which
    // is seldom what is meant; taking the ring off first says so.
    if let (Some(now), Some(new)) = (now, ring) {
        return Err(value_error(format!(
            "{name}: the system is a ring patch at omega {} already, not {}: set_ring(None) first to start another",
            num(now.omega),
            num(new.omega)
        )));
    }
    sim.set_ring(ring).map_err(|e| message(name, e))
}

/// The engine's refusal as `name: why`.
fn message(name: &str, e: Error) -> PyErr {
    let m = match e {
        Error::BadRing(m) => m,
        other => other.to_string(),
    };
    value_error(format!("{name}: {m}"))
}
