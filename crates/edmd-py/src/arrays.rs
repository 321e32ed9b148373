//! numpy arrays in and out: `(N, dim)` float64 matrices, per-disc columns, and the arrays of
//! `Simulation.from_arrays` checked with messages that name the argument.

use edmd_core::{Boundary, Disc, Options, SimBox, Simulation, Vector};
use numpy::{AllowTypeChange, PyArray1, PyArrayLike1, PyArrayLike2, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyString};

use crate::args::num;
use crate::value_error;

/// An `(N, D)` float64 array of `row(i)` for every disc.
pub fn matrix<'py, const D: usize>(
    py: Python<'py>,
    sim: &Simulation<D>,
    row: impl Fn(usize) -> [f64; D],
) -> PyResult<Bound<'py, PyAny>> {
    let n = sim.len();
    let mut flat = Vec::with_capacity(n * D);
    for i in 0..n {
        flat.extend_from_slice(&row(i));
    }
    Ok(PyArray1::from_vec(py, flat).reshape([n, D])?.into_any())
}

/// `obj` as a float64 numpy array, refusing what numpy would convert silently but wrongly:
/// complex numbers (the imaginary part dropped), strings ("1" read as 1.0), booleans, and
/// objects that are not numbers (`None`, rows of different lengths). `what` says what was
/// expected, for the messages.
fn float_array<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    what: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let got = |kind: &str| PyTypeError::new_err(format!("{name}: expected {what}, got {kind}"));
    if obj.is_instance_of::<PyString>() || obj.is_instance_of::<PyBytes>() {
        return Err(got("a str"));
    }
    let np = obj.py().import("numpy")?;
    let a = np
        .call_method1("asarray", (obj,))
        .map_err(|e| PyValueError::new_err(format!("{name}: expected {what}: {e}")))?;
    let kind: String = a.getattr("dtype")?.getattr("kind")?.extract()?;
    match kind.as_str() {
        "f" | "i" | "u" => a.call_method1("astype", ("float64",)),
        "c" => Err(got("complex numbers")),
        "b" => Err(got("booleans")),
        "U" | "S" => Err(got("strings")),
        "O" => Err(got(
            "values that are not all numbers (None, or rows of different lengths?)",
        )),
        _ => Err(got(&format!(
            "an array of dtype {}",
            a.getattr("dtype")?.str()?
        ))),
    }
}

/// A float64 matrix from anything numpy can convert: its values, rows and columns.
fn float_matrix(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<f64>, usize, usize)> {
    let what = "an (N, 2) or (N, 3) array of numbers";
    let a = float_array(obj, name, what)?;
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    if shape.len() != 2 {
        return Err(value_error(format!(
            "{name}: expected {what}, got shape {}",
            shape_text(&shape)
        )));
    }
    let a: PyArrayLike2<'_, f64, AllowTypeChange> = a.extract()?;
    let view = a.as_array();
    let (n, d) = view.dim();
    Ok((view.iter().copied().collect(), n, d))
}

fn shape_text(shape: &[usize]) -> String {
    match shape {
        [k] => format!("({k},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|k| k.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// A float64 vector (1-D) from anything numpy can convert.
pub fn float_vector(obj: &Bound<'_, PyAny>, name: &str, what: &str) -> PyResult<Vec<f64>> {
    let a = float_array(obj, name, what)?;
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    if shape.len() != 1 {
        return Err(value_error(format!(
            "{name}: expected {what}, got shape {}",
            shape_text(&shape)
        )));
    }
    let a: PyArrayLike1<'_, f64, AllowTypeChange> = a.extract()?;
    Ok(a.as_array().iter().copied().collect())
}

/// `n` numbers: one number repeated, or an array of `n`.
fn per_disc(obj: &Bound<'_, PyAny>, n: usize, name: &str) -> PyResult<Vec<f64>> {
    let what = format!("a number or an array of N = {n} numbers");
    let a = float_array(obj, name, &what)?;
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    let v: Vec<f64> = match shape.len() {
        0 => vec![a.extract::<f64>()?; n],
        1 => {
            let a: PyArrayLike1<'_, f64, AllowTypeChange> = a.extract()?;
            a.as_array().iter().copied().collect()
        }
        _ => {
            return Err(value_error(format!(
                "{name}: expected {what}, got shape {}",
                shape_text(&shape)
            )))
        }
    };
    if v.len() != n {
        return Err(value_error(format!(
            "{name}: expected N = {n} values (one per disc), got {}",
            v.len()
        )));
    }
    Ok(v)
}

/// Refuses values that are not finite positive numbers, naming the argument and the disc.
fn check_positive(v: &[f64], name: &str) -> PyResult<()> {
    match v.iter().position(|x| !(x.is_finite() && *x > 0.0)) {
        Some(k) => Err(value_error(format!(
            "{name}: disc {k}: {} is not a finite positive number",
            num(v[k])
        ))),
        None => Ok(()),
    }
}

/// The velocity checks of the engine's own (`Simulation::new` refuses a disc whose velocity
/// is not finite or whose kinetic energy `m v^2 / 2` overflows): one function, so that
/// `from_arrays` and the `velocities` setter refuse the same velocities with the same message.
/// A velocity the engine would refuse on reading makes a run that never ends and a pickle that
/// cannot be read.
pub fn check_velocities(vel: &[f64], masses: &[f64], dim: usize) -> PyResult<()> {
    for (i, m) in masses.iter().enumerate() {
        let v = &vel[i * dim..(i + 1) * dim];
        if v.iter().any(|x| !x.is_finite()) {
            return Err(value_error(format!(
                "velocities: disc {i}: the velocity {} is not finite",
                vector_text(v)
            )));
        }
        let v2: f64 = v.iter().map(|x| x * x).sum();
        if !(0.5 * m * v2).is_finite() {
            return Err(value_error(format!(
                "velocities: disc {i}: the kinetic energy of velocity {} with mass {} is not finite (speed or mass too large)",
                vector_text(v),
                num(*m)
            )));
        }
    }
    Ok(())
}

fn vector_text(v: &[f64]) -> String {
    format!(
        "({})",
        v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ")
    )
}

fn parse_boundary(s: &str) -> PyResult<Boundary> {
    match s {
        "periodic" => Ok(Boundary::Periodic),
        "walls" => Ok(Boundary::Walls),
        _ => Err(value_error(format!(
            "boundary: expected 'periodic' or 'walls', got '{s}'"
        ))),
    }
}

/// The arguments of `Simulation.from_arrays`, checked against each other.
pub struct Input {
    pub dim: usize,
    n: usize,
    pos: Vec<f64>,
    vel: Vec<f64>,
    radii: Vec<f64>,
    masses: Vec<f64>,
    species: Vec<u16>,
    lengths: Vec<f64>,
    boundaries: Vec<Boundary>,
    potential: Option<crate::potential::Parsed>,
}

impl Input {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        positions: &Bound<'_, PyAny>,
        velocities: &Bound<'_, PyAny>,
        radii: &Bound<'_, PyAny>,
        masses: Option<&Bound<'_, PyAny>>,
        lengths: Option<&Bound<'_, PyAny>>,
        boundary: Option<&Bound<'_, PyAny>>,
        species: Option<&Bound<'_, PyAny>>,
        potential: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let (pos, n, dim) = float_matrix(positions, "positions")?;
        if !(1..=3).contains(&dim) {
            return Err(value_error(format!(
                "positions: expected shape (N, 1), (N, 2) or (N, 3), got ({n}, {dim})"
            )));
        }
        let (vel, nv, dv) = float_matrix(velocities, "velocities")?;
        if (nv, dv) != (n, dim) {
            return Err(value_error(format!(
                "velocities: expected shape ({n}, {dim}) like positions, got ({nv}, {dv})"
            )));
        }
        if let Some(k) = pos.iter().position(|x| !x.is_finite()) {
            return Err(value_error(format!(
                "positions: disc {}: {} is not finite",
                k / dim,
                num(pos[k])
            )));
        }
        let radii = per_disc(radii, n, "radii")?;
        check_positive(&radii, "radii")?;
        let masses = match masses {
            Some(m) => per_disc(m, n, "masses")?,
            None => vec![1.0; n],
        };
        check_positive(&masses, "masses")?;
        check_velocities(&vel, &masses, dim)?;
        let species = match species {
            None => vec![0; n],
            Some(s) => {
                let v = per_disc(s, n, "species")?;
                v.iter()
                    .map(|&x| {
                        if x.fract() == 0.0 && (0.0..=u16::MAX as f64).contains(&x) {
                            Ok(x as u16)
                        } else {
                            Err(value_error(format!(
                                "species: expected integers from 0 to {}, got {}",
                                u16::MAX,
                                num(x)
                            )))
                        }
                    })
                    .collect::<PyResult<Vec<u16>>>()?
            }
        };
        let lengths = match lengths {
            Some(l) => Some(float_vector(
                l,
                "box",
                "the box lengths, a tuple of numbers",
            )?),
            None => None,
        };
        let Some(lengths) = lengths else {
            return Err(value_error(format!(
                "box: give the box lengths ({})",
                ["L", "Lx, Ly", "Lx, Ly, Lz"][dim - 1]
            )));
        };
        if lengths.len() != dim {
            return Err(value_error(format!(
                "box: expected {dim} lengths for {dim}D positions, got {}",
                lengths.len()
            )));
        }
        check_positive(&lengths, "box").map_err(|_| {
            value_error(format!(
                "box: the lengths must be finite positive numbers, got ({})",
                lengths
                    .iter()
                    .map(|l| num(*l))
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })?;
        let boundaries = match boundary {
            None => vec![Boundary::Periodic; dim],
            Some(b) => {
                if let Ok(s) = b.extract::<String>() {
                    vec![parse_boundary(&s)?; dim]
                } else {
                    let v: Vec<String> = b.extract().map_err(|_| {
                        PyTypeError::new_err(format!(
                            "boundary: expected 'periodic', 'walls', or one of them per axis, got {}",
                            crate::args::type_name(b)
                        ))
                    })?;
                    if v.len() != dim {
                        return Err(value_error(format!(
                            "boundary: expected one per axis ({dim}), got {}",
                            v.len()
                        )));
                    }
                    v.iter()
                        .map(|s| parse_boundary(s))
                        .collect::<PyResult<_>>()?
                }
            }
        };
        // The potential last: its hard cores are checked against the radii and species.
        let potential = match potential {
            Some(p) if !p.is_none() => {
                let parsed = crate::potential::parse(p)?;
                parsed.check_cores(&radii, &species)?;
                Some(parsed)
            }
            _ => None,
        };
        Ok(Input {
            dim,
            n,
            pos,
            vel,
            radii,
            masses,
            species,
            lengths,
            boundaries,
            potential,
        })
    }

    /// The simulation, in dimension `D` (= `self.dim`). The engine validates the discs, the
    /// box and the potential; its message names the disc by index, or starts "potential:".
    pub fn build<const D: usize>(&self, options: Options) -> PyResult<Simulation<D>> {
        let row = |v: &[f64], i: usize| Vector::<D>(std::array::from_fn(|a| v[i * D + a]));
        let discs: Vec<Disc<D>> = (0..self.n)
            .map(|i| Disc {
                pos: row(&self.pos, i),
                vel: row(&self.vel, i),
                mass: self.masses[i],
                radius: self.radii[i],
                colour: [0, 0, 0],
                species: self.species[i],
            })
            .collect();
        let sim_box = SimBox {
            lengths: std::array::from_fn(|a| self.lengths[a]),
            boundaries: std::array::from_fn(|a| self.boundaries[a]),
        };
        match &self.potential {
            Some(p) => {
                Simulation::with_potential_at(&discs, sim_box, &[], &p.potential, options, 0.0)
            }
            None => Simulation::new(&discs, sim_box, options),
        }
        .map_err(value_error)
    }
}

/// `sim.velocities = v`: every velocity replaced at the current time and everything
/// scheduled again.
pub fn set_velocities<const D: usize>(
    sim: &mut Simulation<D>,
    v: &Bound<'_, PyAny>,
) -> PyResult<()> {
    let (vel, n, d) = float_matrix(v, "velocities")?;
    if (n, d) != (sim.len(), D) {
        return Err(value_error(format!(
            "velocities: expected shape ({}, {D}), got ({n}, {d})",
            sim.len()
        )));
    }
    let masses: Vec<f64> = (0..n).map(|i| sim.mass(i)).collect();
    check_velocities(&vel, &masses, D)?;
    sim.modify_velocities(|i, _| Vector(std::array::from_fn(|a| vel[i * D + a])));
    Ok(())
}
