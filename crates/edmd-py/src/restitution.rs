//! Inelastic collisions between Python and the engine: the `restitution=` argument of
//! `Simulation.from_arrays`, `Simulation.set_restitution` and the generators read into an
//! [`edmd_core::Restitution`] (with messages that name the argument and the key), and
//! `Simulation.restitution` given back in the form they take.
//!
//! The form is `None` (elastic), a coefficient `e` in `[0, 1]` for every pair of species, or a
//! dict `{"all": LAW, "pairs": {(a, b): LAW, ...}, "walls": e, "tc": t}`, every key optional
//! (by default `all` 1, no pairs, `walls` 1, `tc` 0), where a LAW is a coefficient or
//! `{"bridges": v_c}`: Bridges, Hatzes and Lin's `e(v) = min(1, (v / v_c)^-0.234)`. It says
//! what a file's `# edmd restitution` lines say (`edmd_io::restitution`).

use std::collections::HashSet;

use edmd_core::state::MAX_RESTITUTION_SPECIES;
use edmd_core::{Error, Restitution, RestitutionLaw, Simulation};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::args::{self, num, repr};

fn value_error(m: String) -> PyErr {
    PyValueError::new_err(args::shorten_numbers(&m))
}

/// How a law is written, for messages.
const LAW: &str = "a coefficient e in [0, 1] or {'bridges': v_c}";

/// A coefficient of restitution: a number in `[0, 1]`.
fn coefficient(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<f64> {
    let e = args::real(obj, what)?;
    if !(0.0..=1.0).contains(&e) {
        return Err(value_error(format!(
            "{what}: the coefficient must be in [0, 1], got {}",
            num(e)
        )));
    }
    Ok(e)
}

/// A law: a coefficient, or `{"bridges": v_c}`.
fn law(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<RestitutionLaw> {
    if let Ok(dict) = obj.cast::<PyDict>() {
        let items: Vec<_> = dict.iter().collect();
        let [(k, v)] = items.as_slice() else {
            return Err(value_error(format!(
                "{what}: expected {LAW}, got {}",
                repr(obj)
            )));
        };
        if k.extract::<String>().ok().as_deref() != Some("bridges") {
            return Err(value_error(format!(
                "{what}: unknown key {} (a law is {LAW})",
                repr(k)
            )));
        }
        let field = format!("{what}['bridges']");
        let v_c = args::real(v, &field)?;
        if !(v_c.is_finite() && v_c > 0.0) {
            return Err(value_error(format!(
                "{field}: Bridges' speed v_c must be a finite number > 0, got {}",
                num(v_c)
            )));
        }
        return Ok(RestitutionLaw::Bridges { v_c });
    }
    if args::real(obj, what).is_err() {
        return Err(PyTypeError::new_err(format!(
            "{what}: expected {LAW}, got {} {}",
            args::type_name(obj),
            repr(obj)
        )));
    }
    Ok(RestitutionLaw::Constant(coefficient(obj, what)?))
}

/// The laws of given pairs: a dict `{(a, b): LAW}`, each pair once (in either order).
fn pairs(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<(u16, u16, RestitutionLaw)>> {
    let dict = obj.cast::<PyDict>().map_err(|_| {
        PyTypeError::new_err(format!(
            "{what}: expected a dict mapping pairs of species (a, b) to laws ({LAW}), got {} {}",
            args::type_name(obj),
            repr(obj)
        ))
    })?;
    let mut seen = HashSet::new();
    let mut out = Vec::new();
    for (k, v) in dict.iter() {
        let key = format!("{what}[{}]", repr(&k));
        let (a, b) = args::species_pair(&k, &key, MAX_RESTITUTION_SPECIES)?;
        if !seen.insert((a.min(b), a.max(b))) {
            return Err(value_error(format!(
                "{key}: species {a} and {b} are given twice ((a, b) and (b, a) are one pair)"
            )));
        }
        out.push((a, b, law(&v, &key)?));
    }
    Ok(out)
}

/// The `restitution` argument (`name` in messages): `None`, a coefficient for every pair, or
/// the dict form. `None` for `None`; an all-elastic restitution is given back as it is (the
/// engine makes it `None`).
pub fn parse(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Option<Restitution>> {
    if obj.is_none() {
        return Ok(None);
    }
    let Ok(dict) = obj.cast::<PyDict>() else {
        if obj.is_instance_of::<PyString>() || args::real(obj, name).is_err() {
            return Err(PyTypeError::new_err(format!(
                "{name}: expected None, a coefficient e in [0, 1] for every pair, or a dict with 'all', 'pairs', 'walls' and 'tc', got {} {}",
                args::type_name(obj),
                repr(obj)
            )));
        }
        return Ok(Some(Restitution::constant(coefficient(obj, name)?)));
    };
    let mut r = Restitution::default();
    for (k, v) in dict.iter() {
        let key = k.extract::<String>().ok();
        let field = |key: &str| format!("{name}['{key}']");
        match key.as_deref() {
            Some(key @ "all") => r.all = law(&v, &field(key))?,
            Some(key @ "pairs") => r.pairs = pairs(&v, &field(key))?,
            Some(key @ "walls") => r.wall = coefficient(&v, &field(key))?,
            Some(key @ "tc") => {
                let what = field(key);
                let tc = args::real(&v, &what)?;
                if !(tc.is_finite() && tc >= 0.0) {
                    return Err(value_error(format!(
                        "{what}: the TC model's time must be a finite number >= 0, got {}",
                        num(tc)
                    )));
                }
                r.tc = tc;
            }
            _ => {
                return Err(value_error(format!(
                    "{name}: unknown key {} (the dict form has 'all', 'pairs', 'walls' and 'tc')",
                    repr(&k)
                )))
            }
        }
    }
    // Everything is checked above; the engine's own checks say the same, should they ever
    // know more.
    r.validate().map_err(|e| engine_error(name, e))?;
    Ok(Some(r))
}

/// The engine's refusal, said of the argument `name`.
fn engine_error(name: &str, e: Error) -> PyErr {
    match e {
        Error::BadRestitution(m) => value_error(format!("{name}: {m}")),
        other => value_error(format!("{name}: {other}")),
    }
}

/// The directive texts (`# edmd restitution` lines' words) of `r`, as `edmd gen
/// --restitution` takes them: those of [`edmd_io::restitution::lines`], or `1` for an elastic
/// restitution, so that the generator refuses what it goes with as the command does.
pub fn directives(r: &Restitution) -> Vec<String> {
    let lines = edmd_io::restitution::lines(r);
    if lines.is_empty() {
        vec!["1".into()]
    } else {
        lines
    }
}

/// Makes `sim`'s collisions inelastic under `restitution` (elastic for `None`); refused with
/// a message naming `name`, and then nothing changes.
pub fn apply<const D: usize>(
    sim: &mut Simulation<D>,
    restitution: Option<Restitution>,
    name: &str,
) -> PyResult<()> {
    sim.set_restitution(restitution)
        .map_err(|e| engine_error(name, e))
}

/// A law as the dict form takes it: a float, or `{"bridges": v_c}`.
fn law_object<'py>(py: Python<'py>, law: RestitutionLaw) -> PyResult<Bound<'py, PyAny>> {
    match law {
        RestitutionLaw::Constant(e) => Ok(e.into_pyobject(py)?.into_any()),
        RestitutionLaw::Bridges { v_c } => {
            let d = PyDict::new(py);
            d.set_item("bridges", v_c)?;
            Ok(d.into_any())
        }
    }
}

/// The restitution as `Simulation.restitution` gives it: the full dict form, so that
/// `set_restitution(sim.restitution)` sets it again.
pub fn to_dict<'py>(py: Python<'py>, r: &Restitution) -> PyResult<Bound<'py, PyDict>> {
    let pairs = PyDict::new(py);
    for &(a, b, l) in &r.pairs {
        pairs.set_item((a, b), law_object(py, l)?)?;
    }
    let d = PyDict::new(py);
    d.set_item("all", law_object(py, r.all)?)?;
    d.set_item("pairs", pairs)?;
    d.set_item("walls", r.wall)?;
    d.set_item("tc", r.tc)?;
    Ok(d)
}
