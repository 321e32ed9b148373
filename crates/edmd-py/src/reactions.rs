//! Reaction rules between Python and the engine: the `reactions=` argument of
//! `Simulation.from_arrays` and the arguments of `Simulation.set_reactions` read into
//! [`edmd_core::Reactions`] (with messages that name the argument), and `Simulation.reactions`
//! given back in the form they take.
//!
//! A rule is a str, `"A + B -> C + D"`, optionally followed by `activation E`, `probability P`
//! and `heat Q` (the text of a file's `# edmd reaction` line, read by the same function,
//! `edmd_io::reaction::parse_text`), or a dict
//! `{"reactants": (A, B), "products": (C, D), "activation": E, "probability": P, "heat": Q}`;
//! either way the activation is 0, the probability 1 and the heat 0 unless given. The rules
//! come as a list, or as the dict `Simulation.reactions` gives,
//! `{"rules": [...], "seed": S, "colours": {species: (r, g, b)}}`.

use edmd_core::{Colour, Error, Reaction, Reactions, Simulation, MAX_REACTION_SPECIES};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList, PyString, PyTuple};

use crate::args::{self, repr};

fn value_error(m: String) -> PyErr {
    PyValueError::new_err(args::shorten_numbers(&m))
}

/// A species of a rule: a whole number below [`MAX_REACTION_SPECIES`].
fn species(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<u16> {
    args::species(obj, what, MAX_REACTION_SPECIES)
}

/// A pair of species of a rule: a tuple or list of two.
fn species_pair(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<(u16, u16)> {
    args::species_pair(obj, what, MAX_REACTION_SPECIES)
}

/// One rule: its text, or the dict form.
fn rule(item: &Bound<'_, PyAny>, what: &str) -> PyResult<Reaction> {
    if let Ok(s) = item.cast::<PyString>() {
        let text = s.to_cow()?;
        return edmd_io::reaction::parse_text(&text)
            .map_err(|e| value_error(format!("{what}: '{text}': {e}")));
    }
    let Ok(dict) = item.cast::<PyDict>() else {
        return Err(PyTypeError::new_err(format!(
            "{what}: expected a rule, 'A + B -> C + D' or a dict with 'reactants' and 'products', got {} {}",
            args::type_name(item),
            repr(item)
        )));
    };
    let (mut reactants, mut products) = (None, None);
    let mut r = Reaction {
        reactants: (0, 0),
        products: (0, 0),
        activation: 0.0,
        probability: 1.0,
        heat: 0.0,
    };
    for (k, v) in dict.iter() {
        let key = k.extract::<String>().ok();
        let field = |key: &str| format!("{what}: {key}");
        match key.as_deref() {
            Some(key @ ("reactants" | "products")) => {
                let pair = Some(species_pair(&v, &field(key))?);
                if key == "reactants" {
                    reactants = pair;
                } else {
                    products = pair;
                }
            }
            Some(key @ "activation") => r.activation = args::real(&v, &field(key))?,
            Some(key @ "probability") => r.probability = args::real(&v, &field(key))?,
            Some(key @ "heat") => r.heat = args::real(&v, &field(key))?,
            _ => {
                return Err(value_error(format!(
                    "{what}: unknown key {} (a rule has 'reactants', 'products', 'activation', 'probability' and 'heat')",
                    repr(&k)
                )))
            }
        }
    }
    let (Some(a), Some(p)) = (reactants, products) else {
        return Err(value_error(format!(
            "{what}: a rule needs 'reactants' and 'products' (pairs of species), and may give 'activation', 'probability' and 'heat'"
        )));
    };
    r.reactants = a;
    r.products = p;
    Ok(r)
}

/// The rules: a list (or other sequence) of rules.
fn rules(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<Reaction>> {
    let refuse = || {
        PyTypeError::new_err(format!(
            "{name}: expected a list of rules ('A + B -> C + D', or dicts with 'reactants' and 'products'), got {} {}",
            args::type_name(obj),
            repr(obj)
        ))
    };
    if obj.is_instance_of::<PyString>() || obj.is_instance_of::<PyBytes>() || obj.is_none() {
        return Err(refuse());
    }
    let iter = obj.try_iter().map_err(|_| refuse())?;
    let mut out = Vec::new();
    for (k, item) in iter.enumerate() {
        out.push(rule(&item?, &format!("{name}: rule {k}"))?);
        // The engine refuses a second rule for a pair, so more rules than pairs cannot all be
        // valid; refusing here keeps a huge list (or an endless iterator) from being read to
        // the end.
        let species = usize::from(MAX_REACTION_SPECIES);
        if out.len() > species * (species + 1) / 2 {
            return Err(value_error(format!(
                "{name}: more rules than pairs of species (species are below {MAX_REACTION_SPECIES})"
            )));
        }
    }
    Ok(out)
}

/// The colours of species: a dict `{species: (r, g, b)}`, each from 0 to 255.
fn colours(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<(u16, Colour)>> {
    let dict = obj.cast::<PyDict>().map_err(|_| {
        PyTypeError::new_err(format!(
            "{name}: expected a dict mapping species to colours (r, g, b), got {} {}",
            args::type_name(obj),
            repr(obj)
        ))
    })?;
    let mut out = Vec::new();
    for (k, v) in dict.iter() {
        let s = species(&k, &format!("{name}: key {}", repr(&k)))?;
        let what = format!("{name}: species {s}");
        let refuse = || {
            PyTypeError::new_err(format!(
                "{what}: expected a colour (r, g, b) of whole numbers from 0 to 255, got {} {}",
                args::type_name(&v),
                repr(&v)
            ))
        };
        if !(v.is_instance_of::<PyTuple>() || v.is_instance_of::<PyList>()) || v.len()? != 3 {
            return Err(refuse());
        }
        let mut c = [0u8; 3];
        for (a, slot) in c.iter_mut().enumerate() {
            let x = args::whole(&v.get_item(a)?, &what)?;
            *slot = u8::try_from(x).map_err(|_| {
                value_error(format!(
                    "{what}: colour components are whole numbers from 0 to 255, got {x}"
                ))
            })?;
        }
        out.push((s, c));
    }
    Ok(out)
}

/// The seed of the draws: a whole number from 0 to 2^64 - 1; for None, `edmd run`'s without
/// `--seed` ([`edmd::input::DEFAULT_SEED`]).
fn seed(obj: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<u64> {
    match obj {
        Some(o) if !o.is_none() => args::count(o, name),
        _ => Ok(edmd::input::DEFAULT_SEED),
    }
}

/// The rules of `set_reactions(rules, seed=..., colours=...)`; `None` (or no rules) for none.
pub fn from_parts(
    rule_list: &Bound<'_, PyAny>,
    seed_obj: Option<&Bound<'_, PyAny>>,
    colour_map: Option<&Bound<'_, PyAny>>,
    names: [&str; 3],
) -> PyResult<Option<Reactions>> {
    if rule_list.is_none() {
        let given = |o: Option<&Bound<'_, PyAny>>| o.is_some_and(|o| !o.is_none());
        if given(seed_obj) || given(colour_map) {
            return Err(value_error(format!(
                "{}: {} and {} go with rules ({}=None removes the rules)",
                names[0], names[1], names[2], names[0]
            )));
        }
        return Ok(None);
    }
    let rules = rules(rule_list, names[0])?;
    let seed = seed(seed_obj, names[1])?;
    let colours = match colour_map {
        Some(c) if !c.is_none() => colours(c, names[2])?,
        _ => Vec::new(),
    };
    Ok(Some(Reactions {
        rules,
        seed,
        colours,
    }))
}

/// The `reactions=` argument of `from_arrays`: a list of rules, or the dict
/// `{"rules": [...], "seed": S, "colours": {...}}` that `Simulation.reactions` gives.
pub fn parse(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Option<Reactions>> {
    if obj.is_none() {
        return Ok(None);
    }
    let Ok(dict) = obj.cast::<PyDict>() else {
        return from_parts(obj, None, None, [name, "seed", "colours"]);
    };
    let (mut list, mut seed_obj, mut colour_map) = (None, None, None);
    for (k, v) in dict.iter() {
        match k.extract::<String>().ok().as_deref() {
            Some("rules") => list = Some(v),
            Some("seed") => seed_obj = Some(v),
            Some("colours") => colour_map = Some(v),
            _ => {
                return Err(value_error(format!(
                    "{name}: unknown key {} (the dict form has 'rules', 'seed' and 'colours'; or give a list of rules)",
                    repr(&k)
                )))
            }
        }
    }
    let Some(list) = list.filter(|l| !l.is_none()) else {
        return Err(value_error(format!(
            "{name}: the dict form needs 'rules' (a list of rules), and may give 'seed' and 'colours'"
        )));
    };
    let names = [
        format!("{name}: rules"),
        format!("{name}: seed"),
        format!("{name}: colours"),
    ];
    from_parts(
        &list,
        seed_obj.as_ref(),
        colour_map.as_ref(),
        [&names[0], &names[1], &names[2]],
    )
}

/// The engine's refusal, said of the argument `name`.
fn engine_error(name: &str, e: Error) -> PyErr {
    match e {
        Error::BadReaction(m) if m.starts_with("rules ") => {
            value_error(format!("{name}: reaction {m}"))
        }
        Error::BadReaction(m) => value_error(format!("{name}: {m}")),
        other => value_error(format!("{name}: {other}")),
    }
}

/// Makes `sim`'s collisions reactive under `reactions` (or not, for `None`), the colours of
/// the species the rules make filled in as the file readers fill them (the colour of the
/// first disc of that species, else the species' own); refused with a message naming `name`,
/// and then nothing changes.
pub fn apply<const D: usize>(
    sim: &mut Simulation<D>,
    reactions: Option<Reactions>,
    name: &str,
) -> PyResult<()> {
    let reactions = reactions.map(|mut r| {
        r.fill_colours((0..sim.len()).map(|i| (sim.species(i), sim.colour(i))));
        r
    });
    sim.set_reactions(reactions)
        .map_err(|e| engine_error(name, e))
}

/// A rule as the dict form takes it.
fn rule_dict<'py>(py: Python<'py>, r: &Reaction) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("reactants", r.reactants)?;
    d.set_item("products", r.products)?;
    d.set_item("activation", r.activation)?;
    d.set_item("probability", r.probability)?;
    d.set_item("heat", r.heat)?;
    Ok(d)
}

/// The rules as `Simulation.reactions` gives them: `{"rules", "seed", "colours"}`, so that
/// `set_reactions(**sim.reactions)` and `from_arrays(..., reactions=sim.reactions)` set them
/// again.
pub fn to_dict<'py>(py: Python<'py>, reactions: &Reactions) -> PyResult<Bound<'py, PyDict>> {
    let rules = PyList::empty(py);
    for r in &reactions.rules {
        rules.append(rule_dict(py, r)?)?;
    }
    let colours = PyDict::new(py);
    for &(s, c) in &reactions.colours {
        colours.set_item(s, (c[0], c[1], c[2]))?;
    }
    let d = PyDict::new(py);
    d.set_item("rules", rules)?;
    d.set_item("seed", reactions.seed)?;
    d.set_item("colours", colours)?;
    Ok(d)
}
