//! numpy arrays in and out: `(N, dim)` float64 matrices, per-disc columns, and the arrays of
//! `Simulation.from_arrays` checked with messages that name the argument.

use edmd_core::{Boundary, Disc, Options, SimBox, Simulation, Vector};
use numpy::{AllowTypeChange, PyArray1, PyArrayLike1, PyArrayLike2, PyArrayMethods};
use pyo3::prelude::*;

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

/// A float64 matrix from anything numpy can convert.
fn float_matrix(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<f64>, usize, usize)> {
    let a: PyArrayLike2<'_, f64, AllowTypeChange> = obj.extract().map_err(|_| {
        value_error(format!(
            "{name}: expected an (N, 2) or (N, 3) array of numbers"
        ))
    })?;
    let view = a.as_array();
    let (n, d) = view.dim();
    Ok((view.iter().copied().collect(), n, d))
}

/// `n` numbers: one number repeated, or an array of `n`.
fn per_disc(obj: &Bound<'_, PyAny>, n: usize, name: &str) -> PyResult<Vec<f64>> {
    if let Ok(x) = obj.extract::<f64>() {
        return Ok(vec![x; n]);
    }
    let a: PyArrayLike1<'_, f64, AllowTypeChange> = obj.extract().map_err(|_| {
        value_error(format!(
            "{name}: expected a number or an array of N = {n} numbers"
        ))
    })?;
    let v: Vec<f64> = a.as_array().iter().copied().collect();
    if v.len() != n {
        return Err(value_error(format!(
            "{name}: expected N = {n} values (one per disc), got {}",
            v.len()
        )));
    }
    Ok(v)
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
}

impl Input {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        positions: &Bound<'_, PyAny>,
        velocities: &Bound<'_, PyAny>,
        radii: &Bound<'_, PyAny>,
        masses: Option<&Bound<'_, PyAny>>,
        lengths: Option<Vec<f64>>,
        boundary: Option<&Bound<'_, PyAny>>,
        species: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let (pos, n, dim) = float_matrix(positions, "positions")?;
        if dim != 2 && dim != 3 {
            return Err(value_error(format!(
                "positions: expected shape (N, 2) or (N, 3), got ({n}, {dim})"
            )));
        }
        let (vel, nv, dv) = float_matrix(velocities, "velocities")?;
        if (nv, dv) != (n, dim) {
            return Err(value_error(format!(
                "velocities: expected shape ({n}, {dim}) like positions, got ({nv}, {dv})"
            )));
        }
        let radii = per_disc(radii, n, "radii")?;
        let masses = match masses {
            Some(m) => per_disc(m, n, "masses")?,
            None => vec![1.0; n],
        };
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
                                "species: expected integers from 0 to {}, got {x}",
                                u16::MAX
                            )))
                        }
                    })
                    .collect::<PyResult<Vec<u16>>>()?
            }
        };
        let Some(lengths) = lengths else {
            return Err(value_error(format!(
                "box: give the box lengths ({})",
                if dim == 2 { "Lx, Ly" } else { "Lx, Ly, Lz" }
            )));
        };
        if lengths.len() != dim {
            return Err(value_error(format!(
                "box: expected {dim} lengths for {dim}D positions, got {}",
                lengths.len()
            )));
        }
        let boundaries = match boundary {
            None => vec![Boundary::Periodic; dim],
            Some(b) => {
                if let Ok(s) = b.extract::<String>() {
                    vec![parse_boundary(&s)?; dim]
                } else {
                    let v: Vec<String> = b.extract().map_err(|_| {
                        value_error("boundary: expected 'periodic', 'walls', or one per axis")
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
        })
    }

    /// The simulation, in dimension `D` (= `self.dim`). The engine validates the discs and
    /// the box; its message names the disc by index.
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
        Simulation::new(&discs, sim_box, options).map_err(value_error)
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
    if let Some(k) = vel.iter().position(|x| !x.is_finite()) {
        return Err(value_error(format!(
            "velocities: disc {} has a velocity that is not finite",
            k / D
        )));
    }
    sim.modify_velocities(|i, _| Vector(std::array::from_fn(|a| vel[i * D + a])));
    Ok(())
}
