//! Lees-Edwards boundaries between Python and the engine: `Simulation.set_shear(rate,
//! offset)` and the `shear=` argument of `Simulation.from_arrays` read into a [`Sliding`]
//! (with messages that name the argument), and `Simulation.shear` given back as the tuple
//! `(rate, offset)` they take.
//!
//! The form is `None` (no shear), a number `rate` (from an offset of 0, or the current one
//! in `set_shear`), or `(rate, offset)`. It says what a file's `# edmd shear RATE OFFSET` line
//! says (`edmd_io::princeton`).

use edmd_core::{Error, Options, OverlapPolicy, Shear, Simulation};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyList, PyString, PyTuple};

use crate::args::{self, num, repr};

fn value_error(m: String) -> PyErr {
    PyValueError::new_err(args::shorten_numbers(&m))
}

/// Shear read from Python before the box is known: the offset is checked against the box by
/// [`apply`].
#[derive(Clone, Copy, Debug)]
pub struct Sliding {
    rate: f64,
    /// The offset given; `None`: the current one if sheared already, else 0.
    offset: Option<f64>,
    /// The names of the rate and of the offset, for messages.
    names: (&'static str, &'static str),
}

/// A finite number.
fn finite(obj: &Bound<'_, PyAny>, name: &str, what: &str) -> PyResult<f64> {
    let x = args::real(obj, name)?;
    if !x.is_finite() {
        return Err(value_error(format!(
            "{name}: {what} must be a finite number, got {}",
            num(x)
        )));
    }
    Ok(x)
}

/// The arguments of `set_shear(rate, offset=None)`: `rate` a number, `None` (no shear; then no
/// offset) or the tuple `Simulation.shear` gives (then no offset beside it).
pub fn from_arguments(
    rate: &Bound<'_, PyAny>,
    offset: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<Sliding>> {
    let offset = offset.filter(|o| !o.is_none());
    if rate.is_none() {
        if offset.is_some() {
            return Err(value_error(
                "offset: goes with rate (set_shear(None) removes the shear)".into(),
            ));
        }
        return Ok(None);
    }
    if rate.is_instance_of::<PyTuple>() || rate.is_instance_of::<PyList>() {
        if offset.is_some() {
            return Err(value_error(
                "offset: give the offset in the tuple (rate, offset), or rate as a number with offset=..., not both".into(),
            ));
        }
        return pair(rate, "rate", ("rate", "offset")).map(Some);
    }
    if rate.is_instance_of::<PyString>() || args::real(rate, "rate").is_err() {
        return Err(PyTypeError::new_err(format!(
            "rate: expected a number (the shear rate du_x/dy), None or (rate, offset), got {} {}",
            args::type_name(rate),
            repr(rate)
        )));
    }
    Ok(Some(Sliding {
        rate: finite(rate, "rate", "the shear rate")?,
        offset: offset
            .map(|o| finite(o, "offset", "the offset"))
            .transpose()?,
        names: ("rate", "offset"),
    }))
}

/// The tuple form `(rate, offset)` (`what` in messages of the tuple as a whole; `names` the
/// names its items are given by).
fn pair(
    obj: &Bound<'_, PyAny>,
    what: &str,
    names: (&'static str, &'static str),
) -> PyResult<Sliding> {
    let items: Vec<Bound<'_, PyAny>> = obj.try_iter()?.collect::<PyResult<_>>()?;
    let [rate, offset] = &items[..] else {
        return Err(value_error(format!(
            "{what}: expected (rate, offset), a tuple of two numbers, got {} items",
            items.len()
        )));
    };
    Ok(Sliding {
        rate: finite(rate, names.0, "the shear rate")?,
        offset: if offset.is_none() {
            None
        } else {
            Some(finite(offset, names.1, "the offset")?)
        },
        names,
    })
}

/// The `shear` argument (`from_arrays`): `None`, a rate (from an offset of 0), or
/// `(rate, offset)`.
pub fn parse(obj: &Bound<'_, PyAny>) -> PyResult<Option<Sliding>> {
    if obj.is_none() {
        return Ok(None);
    }
    if obj.is_instance_of::<PyTuple>() || obj.is_instance_of::<PyList>() {
        return pair(obj, "shear", ("shear[0]", "shear[1]")).map(Some);
    }
    if obj.is_instance_of::<PyString>() || args::real(obj, "shear").is_err() {
        return Err(PyTypeError::new_err(format!(
            "shear: expected None, a number (the shear rate du_x/dy) or (rate, offset), got {} {}",
            args::type_name(obj),
            repr(obj)
        )));
    }
    Ok(Some(Sliding {
        rate: finite(obj, "shear", "the shear rate")?,
        offset: None,
        names: ("shear", "shear"),
    }))
}

impl Sliding {
    /// Shear the library has made and checked (`edmd gen --shear`), named `name` in messages.
    pub fn of(s: Shear, name: &'static str) -> Self {
        Sliding {
            rate: s.rate,
            offset: Some(s.offset),
            names: (name, name),
        }
    }
}

/// Shears `sim` (no shear for `None`); refused with a message naming the argument, and then
/// nothing changes. The shear `sim` has already (the same rate with no offset given, or the
/// same rate and offset) changes nothing either: setting it again would start the images'
/// slide afresh from now, which moves the last bits of later offsets.
pub fn apply<const D: usize>(sim: &mut Simulation<D>, s: Option<Sliding>) -> PyResult<()> {
    let Some(s) = s else {
        if sim.shear().is_none() {
            return Ok(());
        }
        return sim
            .set_shear(None)
            .map_err(|e| value_error(format!("rate: {e}")));
    };
    let now = sim.shear();
    if let Some(now) = now {
        if now.rate.to_bits() == s.rate.to_bits()
            && s.offset.is_none_or(|o| o.to_bits() == now.offset.to_bits())
        {
            return Ok(());
        }
    }
    let offset = s.offset.or(now.map(|n| n.offset)).unwrap_or(0.0);
    let lx = sim.sim_box().lengths[0];
    if !(offset >= 0.0 && offset < lx) {
        return Err(value_error(format!(
            "{}: the offset must be in [0, L_x) = [0, {}), got {}",
            s.names.1,
            num(lx),
            num(offset)
        )));
    }
    let shear = Shear {
        rate: s.rate,
        offset,
    };
    sim.set_shear(Some(shear)).map_err(|e| {
        let m = match e {
            Error::BadShear(m) => m,
            other => other.to_string(),
        };
        // An overlap of the slid images is the offset's doing when one was given.
        let name = if m.contains("offset") && s.offset.is_some() {
            s.names.1
        } else {
            s.names.0
        };
        value_error(format!("{name}: {m}"))
    })
}

/// The shear as `Simulation.shear` gives it: `(rate, offset)`, the images' offset now, so that
/// `set_shear(*sim.shear)` (or `set_shear(sim.shear)`) sets it again.
pub fn to_tuple<'py>(py: Python<'py>, s: Shear) -> PyResult<Bound<'py, PyTuple>> {
    PyTuple::new(py, [s.rate, s.offset])
}

/// The simulation of `input`, for `sliding` to be applied next: discs that touch a plain
/// periodic image across y are let through when the shear has an offset, whose slid images
/// replace those (`apply` then checks the overlaps at the offset), as `edmd run` reads a
/// sheared file. Anything else the engine refuses stays refused.
pub fn build<const D: usize>(
    input: &crate::arrays::Input,
    opts: Options,
    sliding: Option<Sliding>,
) -> PyResult<Simulation<D>> {
    let first = input.build::<D>(opts);
    let slid = sliding.is_some_and(|s| s.offset.is_some_and(|o| o != 0.0));
    match first {
        Err(e) if slid && opts.overlaps == OverlapPolicy::Refuse => {
            let allowed = Options {
                overlaps: OverlapPolicy::Allow,
                ..opts
            };
            match input.build::<D>(allowed) {
                Ok(sim) if sim.adjusted_discs() == 0 => Ok(sim),
                _ => Err(e),
            }
        }
        other => other,
    }
}
