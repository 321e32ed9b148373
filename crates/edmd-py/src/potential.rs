//! Stepped pair potentials between Python and the engine: the `potential=` argument of
//! `Simulation.from_arrays` read into an [`edmd_core::Potential`] (with messages that name
//! `potential`), and `Simulation.potential` given back as the same dict.
//!
//! The Python form is a dict mapping a pair of species `(a, b)` to its steps, innermost first:
//! either a list of `(radius, energy)` pairs, or a dict `{"core": c, "steps": [...]}` whose
//! `core`, if given, must be the contact distance (sum of the radii) of every pair of discs of
//! those species. `energy` is the change of the pair's potential energy when it moves inward
//! across the step: a square well of depth 1 out to 1.5 is `[(1.5, -1.0)]`.

use edmd_core::{PairSteps, Potential, Step};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyList, PyString, PyTuple};

use crate::args::{self, num};

/// A potential read from Python, with the hard cores the caller stated (to be checked
/// against the discs).
pub struct Parsed {
    pub potential: Potential,
    /// `(species pair, core)` for each pair given in the dict form with a `"core"`.
    cores: Vec<((u16, u16), f64)>,
}

fn repr(obj: &Bound<'_, PyAny>) -> String {
    obj.repr().map(|r| r.to_string()).unwrap_or_default()
}

/// The species pair of a key: a tuple (or list) of two whole numbers from 0 to 65535.
fn species_pair(key: &Bound<'_, PyAny>) -> PyResult<(u16, u16)> {
    let refuse = || {
        PyTypeError::new_err(format!(
            "potential: expected pairs of species (a, b) as keys, got {} {}",
            args::type_name(key),
            repr(key)
        ))
    };
    if !(key.is_instance_of::<PyTuple>() || key.is_instance_of::<PyList>()) {
        return Err(refuse());
    }
    if key.len()? != 2 {
        return Err(refuse());
    }
    let one = |k: usize| -> PyResult<u16> {
        let x = key.get_item(k)?;
        if x.is_instance_of::<PyBool>() {
            return Err(refuse());
        }
        let index = x.call_method0("__index__").map_err(|_| refuse())?;
        match index.extract::<i128>() {
            Ok(v) if (0..=u16::MAX as i128).contains(&v) => Ok(v as u16),
            _ => Err(PyValueError::new_err(args::shorten_numbers(&format!(
                "potential: key {}: species are whole numbers from 0 to {}",
                repr(key),
                u16::MAX
            )))),
        }
    };
    Ok((one(0)?, one(1)?))
}

/// The steps of one pair: a sequence of `(radius, energy)` pairs.
fn steps(obj: &Bound<'_, PyAny>, pair: &str) -> PyResult<Vec<Step>> {
    let refuse = |what: &str| {
        PyTypeError::new_err(format!(
            "potential: {pair}: expected a list of (radius, energy) steps{what}, got {} {}",
            args::type_name(obj),
            repr(obj)
        ))
    };
    if obj.is_instance_of::<PyString>() || obj.is_instance_of::<PyBytes>() || obj.is_none() {
        return Err(refuse(""));
    }
    let iter = obj
        .try_iter()
        .map_err(|_| refuse(" or a dict {'core': c, 'steps': [...]}"))?;
    let mut out = Vec::new();
    for (k, item) in iter.enumerate() {
        let item = item?;
        let bad = || {
            PyTypeError::new_err(format!(
                "potential: {pair}: step {k}: expected (radius, energy), got {} {}",
                args::type_name(&item),
                repr(&item)
            ))
        };
        if item.is_instance_of::<PyString>() || item.is_instance_of::<PyBytes>() {
            return Err(bad());
        }
        match item.len() {
            Ok(2) => {}
            _ => return Err(bad()),
        }
        let radius = args::real(
            &item.get_item(0)?,
            &format!("potential: {pair}: step {k}: radius"),
        )?;
        let energy = args::real(
            &item.get_item(1)?,
            &format!("potential: {pair}: step {k}: energy"),
        )?;
        out.push(Step { radius, energy });
        if out.len() > edmd_core::state::MAX_STEPS {
            return Err(PyValueError::new_err(format!(
                "potential: {pair}: more than {} steps",
                edmd_core::state::MAX_STEPS
            )));
        }
    }
    Ok(out)
}

/// Reads the `potential=` argument. The engine checks the steps themselves (order, finite,
/// outside the hard core) when the simulation is built, with messages that start
/// "potential:".
pub fn parse(obj: &Bound<'_, PyAny>) -> PyResult<Parsed> {
    let dict = obj.cast::<PyDict>().map_err(|_| {
        PyTypeError::new_err(format!(
            "potential: expected a dict mapping pairs of species (a, b) to their steps, got {}",
            args::type_name(obj)
        ))
    })?;
    let mut pairs = Vec::new();
    let mut cores = Vec::new();
    for (key, value) in dict.iter() {
        let species = species_pair(&key)?;
        let pair = format!("({}, {})", species.0, species.1);
        let list = if let Ok(form) = value.cast::<PyDict>() {
            let mut list = None;
            for (k, v) in form.iter() {
                match k.extract::<String>().as_deref() {
                    Ok("core") => {
                        let c = args::real(&v, &format!("potential: {pair}: core"))?;
                        if !(c.is_finite() && c > 0.0) {
                            return Err(PyValueError::new_err(format!(
                                "potential: {pair}: core {} is not a finite positive number",
                                num(c)
                            )));
                        }
                        cores.push((species, c));
                    }
                    Ok("steps") => list = Some(v),
                    _ => {
                        return Err(PyValueError::new_err(format!(
                        "potential: {pair}: unknown key {} (the dict form has 'core' and 'steps')",
                        repr(&k)
                    )))
                    }
                }
            }
            list.ok_or_else(|| {
                PyValueError::new_err(format!(
                    "potential: {pair}: the dict form needs 'steps' (a list of (radius, energy)), and may give 'core'"
                ))
            })?
        } else {
            value
        };
        pairs.push(PairSteps {
            species,
            steps: steps(&list, &pair)?,
        });
    }
    Ok(Parsed {
        potential: Potential { pairs },
        cores,
    })
}

/// Whether `sum` is `core` up to rounding (a few units in the last place).
fn same(sum: f64, core: f64) -> bool {
    (sum - core).abs() <= 4.0 * f64::EPSILON * core
}

impl Parsed {
    /// Checks each stated core against the discs: every pair of discs of those species has
    /// the core as its contact distance (the sum of their radii).
    pub fn check_cores(&self, radii: &[f64], species: &[u16]) -> PyResult<()> {
        for &((a, b), core) in &self.cores {
            // The discs of each species, smallest radius first: the extreme pairs bound all.
            let of = |s: u16| {
                let mut v: Vec<(f64, usize)> = (0..radii.len())
                    .filter(|&i| species[i] == s)
                    .map(|i| (radii[i], i))
                    .collect();
                v.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
                v
            };
            let (da, db) = (of(a), of(b));
            let extremes: Vec<((f64, usize), (f64, usize))> = if a == b {
                let k = da.len();
                if k < 2 {
                    Vec::new()
                } else {
                    vec![(da[0], da[1]), (da[k - 2], da[k - 1])]
                }
            } else if da.is_empty() || db.is_empty() {
                Vec::new()
            } else {
                vec![(da[0], db[0]), (da[da.len() - 1], db[db.len() - 1])]
            };
            for ((ri, i), (rj, j)) in extremes {
                if !same(ri + rj, core) {
                    return Err(PyValueError::new_err(format!(
                        "potential: ({a}, {b}): core {} is not the contact distance of every pair of discs of those species: discs {i} and {j} have {} + {} = {}",
                        num(core),
                        num(ri),
                        num(rj),
                        num(ri + rj)
                    )));
                }
            }
        }
        Ok(())
    }
}

/// The potential as the dict `from_arrays` takes: `{(a, b): [(radius, energy), ...]}`, for
/// the pairs that have steps (as files hold it: a pair given no steps is a hard core, and
/// `# edmd potential` lines are written for the others only).
pub fn to_dict<'py>(py: Python<'py>, potential: &Potential) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for p in potential.pairs.iter().filter(|p| !p.steps.is_empty()) {
        let steps: Vec<(f64, f64)> = p.steps.iter().map(|s| (s.radius, s.energy)).collect();
        d.set_item(p.species, PyList::new(py, steps)?)?;
    }
    Ok(d)
}
