//! A uniform field between Python and the engine: `Simulation.set_gravity(g, axis=...)` and
//! the `gravity=` argument of `Simulation.from_arrays` read into an [`edmd_core::Gravity`]
//! (with messages that name the argument), and `Simulation.gravity` given back in the form
//! they take.
//!
//! The form is `None` (no field), a number `g` (the acceleration along the last axis: y in
//! 2D, z in 3D; negative pulls towards 0), or a dict `{"axis": k, "g": g}` (`axis` 0, 1, 2 or
//! "x", "y", "z"; the last axis when left out). It says what a file's `# edmd gravity` line
//! says (`edmd_io::princeton`).

use edmd_core::{Error, Gravity, Simulation};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::args::{self, num, repr};

fn value_error(m: String) -> PyErr {
    PyValueError::new_err(args::shorten_numbers(&m))
}

/// The axes' names, by number.
const AXES: [&str; 3] = ["x", "y", "z"];

/// A field read from Python before the dimension is known: its axis is resolved against the
/// simulation's dimension by [`Field::resolve`].
#[derive(Clone, Copy, Debug)]
pub struct Field {
    g: f64,
    /// The axis given (0, 1 or 2); `None`: the last axis.
    axis: Option<usize>,
    /// The names of `g` and of the axis, for messages.
    names: (&'static str, &'static str),
}

/// `g`: a finite number other than 0.
fn acceleration(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    let g = args::real(obj, name)?;
    if !(g.is_finite() && g != 0.0) {
        return Err(value_error(format!(
            "{name}: the acceleration must be a finite number other than 0 (negative pulls towards 0), got {}",
            num(g)
        )));
    }
    Ok(g)
}

/// An axis: 0, 1, 2 or "x", "y", "z".
fn axis(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<usize> {
    if let Ok(s) = obj.cast::<PyString>() {
        let s = s.to_string();
        return AXES.iter().position(|a| *a == s).ok_or_else(|| {
            value_error(format!(
                "{name}: expected 0, 1, 2 or 'x', 'y', 'z', got {}",
                repr(obj)
            ))
        });
    }
    let k = args::whole(obj, name).map_err(|_| {
        PyTypeError::new_err(format!(
            "{name}: expected 0, 1, 2 or 'x', 'y', 'z', got {} {}",
            args::type_name(obj),
            repr(obj)
        ))
    })?;
    if (0..3).contains(&k) {
        Ok(k as usize)
    } else {
        Err(value_error(format!(
            "{name}: expected 0, 1, 2 or 'x', 'y', 'z', got {k}"
        )))
    }
}

/// The arguments of `set_gravity(g, axis=...)`: `g` a number, `None` (no field; then no
/// axis) or the dict `Simulation.gravity` gives (then no axis beside it).
pub fn from_arguments(
    g: &Bound<'_, PyAny>,
    axis_arg: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<Field>> {
    let axis_arg = axis_arg.filter(|a| !a.is_none());
    if g.is_none() {
        if axis_arg.is_some() {
            return Err(value_error(
                "axis: goes with g (set_gravity(None) removes the field)".into(),
            ));
        }
        return Ok(None);
    }
    if g.cast::<PyDict>().is_ok() {
        if axis_arg.is_some() {
            return Err(value_error(
                "axis: give the axis in the dict {'axis': k, 'g': g}, or g as a number with axis=k, not both".into(),
            ));
        }
        return dict(g, "g", ("g", "axis")).map(Some);
    }
    if g.is_instance_of::<PyString>() || args::real(g, "g").is_err() {
        return Err(PyTypeError::new_err(format!(
            "g: expected a number (the acceleration along the axis), None or {{'axis': k, 'g': g}}, got {} {}",
            args::type_name(g),
            repr(g)
        )));
    }
    Ok(Some(Field {
        g: acceleration(g, "g")?,
        axis: axis_arg.map(|a| axis(a, "axis")).transpose()?,
        names: ("g", "axis"),
    }))
}

/// The dict form `{"axis": k, "g": g}` (`what` in messages of the dict as a whole; `names`
/// the names the keys are given by).
fn dict(
    obj: &Bound<'_, PyAny>,
    what: &str,
    names: (&'static str, &'static str),
) -> PyResult<Field> {
    let dict = obj.cast::<PyDict>()?;
    let mut g = None;
    let mut k = None;
    for (key, v) in dict.iter() {
        match key.extract::<String>().ok().as_deref() {
            Some("g") => g = Some(acceleration(&v, names.0)?),
            Some("axis") => {
                if !v.is_none() {
                    k = Some(axis(&v, names.1)?);
                }
            }
            _ => {
                return Err(value_error(format!(
                    "{what}: unknown key {} (the dict form is {{'axis': k, 'g': g}})",
                    repr(&key)
                )))
            }
        }
    }
    let Some(g) = g else {
        return Err(value_error(format!(
            "{what}: the dict form needs 'g', the acceleration ({{'axis': k, 'g': g}})"
        )));
    };
    Ok(Field { g, axis: k, names })
}

/// The `gravity` argument (`from_arrays`): `None`, a number for the last axis, or the dict
/// form.
pub fn parse(obj: &Bound<'_, PyAny>) -> PyResult<Option<Field>> {
    if obj.is_none() {
        return Ok(None);
    }
    if obj.cast::<PyDict>().is_ok() {
        return dict(obj, "gravity", ("gravity['g']", "gravity['axis']")).map(Some);
    }
    if obj.is_instance_of::<PyString>() || args::real(obj, "gravity").is_err() {
        return Err(PyTypeError::new_err(format!(
            "gravity: expected None, a number (the acceleration along the last axis) or {{'axis': k, 'g': g}}, got {} {}",
            args::type_name(obj),
            repr(obj)
        )));
    }
    Ok(Some(Field {
        g: acceleration(obj, "gravity")?,
        axis: None,
        names: ("gravity", "gravity"),
    }))
}

impl Field {
    /// A field the library has made and checked (`edmd gen --gravity`), named `name` in
    /// messages.
    pub fn of(f: Gravity, name: &'static str) -> Self {
        Field {
            g: f.g,
            axis: Some(f.axis),
            names: (name, name),
        }
    }

    /// The engine's field in `dim` dimensions.
    fn resolve(&self, dim: usize) -> PyResult<Gravity> {
        let axis = match self.axis {
            None => dim - 1,
            Some(k) if k < dim => k,
            Some(k) => {
                return Err(value_error(format!(
                    "{}: a {dim}D simulation has axes {} ({}), got {k}",
                    self.names.1,
                    (0..dim)
                        .map(|a| a.to_string())
                        .collect::<Vec<_>>()
                        .join(", "),
                    AXES[..dim]
                        .iter()
                        .map(|a| format!("'{a}'"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )))
            }
        };
        Ok(Gravity { axis, g: self.g })
    }
}

/// Puts `sim` in `field` (none for `None`); refused with a message naming the argument, and
/// then nothing changes. The field `sim` is in already changes nothing either: the engine
/// would start every disc's flight again from now, which moves the last bits of later
/// positions.
pub fn apply<const D: usize>(sim: &mut Simulation<D>, field: Option<Field>) -> PyResult<()> {
    let Some(field) = field else {
        if sim.gravity().is_none() {
            return Ok(());
        }
        return sim
            .set_gravity(None)
            .map_err(|e| value_error(format!("g: {e}")));
    };
    let f = field.resolve(D)?;
    if sim.gravity() == Some(f) {
        return Ok(());
    }
    if sim.sim_box().is_periodic(f.axis) {
        return Err(value_error(format!(
            "{}: the field's axis {} must have walls (along a periodic axis a disc would fall for ever)",
            field.names.1, AXES[f.axis]
        )));
    }
    sim.set_gravity(Some(f)).map_err(|e| match e {
        Error::BadField(m) => value_error(format!("{}: {m}", field.names.0)),
        other => value_error(format!("{}: {other}", field.names.0)),
    })
}

/// The field as `Simulation.gravity` gives it: `{"axis": k, "g": g}`, so that
/// `set_gravity(**sim.gravity)` (or `set_gravity(sim.gravity)`) sets it again.
pub fn to_dict<'py>(py: Python<'py>, f: Gravity) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("axis", f.axis)?;
    d.set_item("g", f.g)?;
    Ok(d)
}
