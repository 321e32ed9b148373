//! Python arguments read with messages that name the argument: a `TypeError` for a value of
//! the wrong kind, a `ValueError` for one out of range. PyO3's own conversions raise
//! `OverflowError` for a negative count and take `True` for 1, so numbers are read here.

use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyComplex, PyList, PyString, PyTuple};

/// A short exact form of a number for messages: `1e300`, not 301 digits (Rust's `{:?}`).
pub fn num(x: f64) -> String {
    format!("{x:?}")
}

/// The Python type's name of `obj`, for messages.
pub fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "object".into())
}

/// `repr(obj)`, for messages.
pub fn repr(obj: &Bound<'_, PyAny>) -> String {
    obj.repr().map(|r| r.to_string()).unwrap_or_default()
}

/// A real number (a Python or numpy int or float; not a bool, a complex number or a str).
pub fn real(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    let refuse = || {
        PyTypeError::new_err(format!(
            "{name}: expected a number, got {} {}",
            type_name(obj),
            obj.repr().map(|r| r.to_string()).unwrap_or_default()
        ))
    };
    if obj.is_instance_of::<PyBool>()
        || obj.is_instance_of::<PyComplex>()
        || obj.is_instance_of::<PyString>()
    {
        return Err(refuse());
    }
    // numpy's bool and complex scalars are not Python's: ask numpy what kind of number it is.
    if let Ok(kind) = obj
        .getattr("dtype")
        .and_then(|d| d.getattr("kind"))
        .and_then(|k| k.extract::<String>())
    {
        if !matches!(kind.as_str(), "f" | "i" | "u") {
            return Err(refuse());
        }
    }
    obj.extract::<f64>().map_err(|_| refuse())
}

/// A whole number (a Python or numpy int; not a bool or a float), of any size.
pub fn whole(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<i128> {
    let refuse = |what: &str| {
        PyTypeError::new_err(format!(
            "{name}: expected a whole number{what}, got {} {}",
            type_name(obj),
            obj.repr().map(|r| r.to_string()).unwrap_or_default()
        ))
    };
    if obj.is_instance_of::<PyBool>() {
        return Err(refuse(""));
    }
    // Only objects that are integers (`__index__`): 2.0 is refused, as Python's range() does.
    let index = obj.call_method0("__index__").map_err(|_| refuse(""))?;
    index.extract::<i128>().map_err(|_| {
        PyValueError::new_err(format!(
            "{name}: {} is too large",
            index.repr().map(|r| r.to_string()).unwrap_or_default()
        ))
    })
}

/// A species: a whole number below `below` (the most species the feature's tables hold).
pub fn species(obj: &Bound<'_, PyAny>, what: &str, below: u16) -> PyResult<u16> {
    let k = whole(obj, what)?;
    if (0..i128::from(below)).contains(&k) {
        Ok(k as u16)
    } else {
        Err(PyValueError::new_err(shorten_numbers(&format!(
            "{what}: species are whole numbers from 0 to {}, got {k}",
            below - 1
        ))))
    }
}

/// A pair of species `(a, b)`: a tuple or list of two, each below `below`.
pub fn species_pair(obj: &Bound<'_, PyAny>, what: &str, below: u16) -> PyResult<(u16, u16)> {
    if !(obj.is_instance_of::<PyTuple>() || obj.is_instance_of::<PyList>()) || obj.len()? != 2 {
        return Err(PyTypeError::new_err(format!(
            "{what}: expected a pair of species (a, b), got {} {}",
            type_name(obj),
            repr(obj)
        )));
    }
    Ok((
        species(&obj.get_item(0)?, what, below)?,
        species(&obj.get_item(1)?, what, below)?,
    ))
}

/// A count from 0 to 2^64 - 1.
pub fn count(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<u64> {
    let k = whole(obj, name)?;
    u64::try_from(k).map_err(|_| {
        PyValueError::new_err(format!(
            "{name}: expected a count from 0 to 2^64 - 1, got {k}"
        ))
    })
}

/// An optional frame index of a file (`None` for absent; negative counts from the end).
pub fn opt_frame(obj: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<i64>> {
    match obj {
        Some(o) if !o.is_none() => {
            let k = whole(o, name)?;
            i64::try_from(k).map(Some).map_err(|_| {
                PyValueError::new_err(format!("{name}: {k} is not a frame of any file"))
            })
        }
        _ => Ok(None),
    }
}

/// The error of a simulation used while a `run` is under way in another thread.
pub fn busy() -> PyErr {
    PyRuntimeError::new_err(
        "Simulation is busy: run() is under way in another thread; wait for it to return (a \
         Simulation is used by one thread at a time, and is refused, not waited for, while it runs)",
    )
}

/// A str argument (PyO3's own conversion does not name the argument in its `TypeError`).
pub fn text(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<String> {
    obj.extract::<String>().map_err(|_| {
        PyTypeError::new_err(format!("{name}: expected a str, got {}", type_name(obj)))
    })
}

/// An optional str argument (`None` for absent).
pub fn opt_text(obj: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<String>> {
    match obj {
        Some(o) if !o.is_none() => text(o, name).map(Some),
        _ => Ok(None),
    }
}

/// True or False (not 1, not "yes").
pub fn flag(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<bool> {
    if !obj.is_instance_of::<PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected True or False, got {}",
            type_name(obj)
        )));
    }
    obj.extract::<bool>()
}

/// An optional flag: False when absent or None.
pub fn opt_flag(obj: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<bool> {
    match obj {
        Some(o) if !o.is_none() => flag(o, name),
        _ => Ok(false),
    }
}

/// A file name: a str or an `os.PathLike`.
pub fn path(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<std::path::PathBuf> {
    if obj.is_instance_of::<PyBool>() {
        return Err(path_error(obj, name));
    }
    obj.extract::<std::path::PathBuf>()
        .map_err(|_| path_error(obj, name))
}

fn path_error(obj: &Bound<'_, PyAny>, name: &str) -> PyErr {
    PyTypeError::new_err(format!(
        "{name}: expected a file name (str or path), got {}",
        type_name(obj)
    ))
}

pub use edmd::front::shorten_numbers;
