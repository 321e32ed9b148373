//! `edmd experiment square-well`: the equation of state and the energy of the square-well
//! fluid in a heat bath.
//!
//! For each number density `rho` (in units of the hard-core diameter `sigma = 1`): `N`
//! particles of mass 1 in a periodic box, a well of depth 1 out to `lambda sigma`, started on a
//! lattice and held at `kT` by the Andersen thermostat. After an equilibration, the run is
//! measured in blocks until the errors of `Z` and of the potential energy per particle are
//! within `--precision` of their values (or `--max-blocks` is reached):
//! - `Z = P / (rho kT) = 1 + sum r_ij . J_ij / (D t N kT)`, the collision virial over every
//!   impulse between a pair (hard-core collisions, and crossings of and bounces at the well's
//!   edge), with `kT` the mean kinetic temperature;
//! - `U / N`, the potential energy per particle, sampled along each block;
//! - the heat capacity per particle from the fluctuations of the total energy in the bath,
//!   `C_V / (N k) = var(E) / (N kT^2)` (canonical ensemble; it includes the kinetic `D/2`).
//!
//! Compared with, in each row: the exact low-density limits (`Z = 1 + B2 rho` with the exact
//! second virial coefficient, `U/N = (rho / 2) Int u exp(-u/kT) dr`), and in 3D with the
//! equation of state of Espindola-Heredia, del Rio and Malijevsky (J. Chem. Phys. 130, 024509
//! (2009)), fitted to simulation data of the square-well fluid of variable range.

use anyhow::Result;
use clap::Args;
use edmd_core::measure::theory::{stepped_b2, stepped_energy_low_density};
use edmd_core::measure::{variance, Estimate, Pressure};
use edmd_core::setup::lattice_fluid_in;
use edmd_core::{Andersen, Boundary, Options, Potential, Simulation, Step};
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_once, files_line, interrupted_after, out_dir, outputs, report, write_csv, CommonArgs,
    Progress,
};

/// Options of `edmd experiment square-well`.
#[derive(Debug, Args)]
pub struct SquareWellArgs {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[arg(long, default_value_t = 3, value_parser = crate::args::parse_dim)]
    pub dim: usize,
    /// Range of the well, in hard-core diameters.
    #[arg(long, default_value_t = 1.5, allow_negative_numbers = true)]
    pub lambda: f64,
    /// Temperature of the heat bath, in units of the well depth.
    #[arg(long, default_value_t = 1.5, allow_negative_numbers = true)]
    pub kt: f64,
    /// Number densities rho sigma^D, comma-separated [default: 3D 0.1,0.2,...,0.8; 2D
    /// 0.1,0.2,...,0.7].
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub density: Option<Vec<f64>>,
    /// Number of particles.
    #[arg(long, allow_negative_numbers = true)]
    pub n: Option<usize>,
    /// The relative error of Z and of the energy per particle the runs aim at.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub precision: f64,
    /// The most measuring blocks per density (each about 20 events per particle).
    #[arg(long, default_value_t = 4000, allow_negative_numbers = true)]
    pub max_blocks: usize,
    /// Thermostat redraws per particle per unit time.
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    pub rate: f64,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// One density.
#[derive(Debug, Serialize)]
pub struct Row {
    /// Number density in units of the hard-core diameter.
    pub density: f64,
    /// The bath's temperature (units of the well depth).
    pub kt: f64,
    /// Range of the well (hard-core diameters).
    pub lambda: f64,
    /// Compressibility factor `P / (rho kT)`.
    #[serde(rename = "Z")]
    pub z: f64,
    /// Its statistical error (one standard deviation, from block averages).
    #[serde(rename = "Z_error")]
    pub z_error: f64,
    /// Potential energy per particle (units of the well depth).
    pub energy_per_particle: f64,
    /// Its statistical error.
    pub energy_per_particle_error: f64,
    /// Heat capacity per particle `C_V / (N k)` from the fluctuations of the total energy.
    pub heat_capacity: f64,
    /// Its statistical error.
    pub heat_capacity_error: f64,
    /// Mean kinetic temperature over the measurement.
    pub kinetic_temperature: f64,
    /// `1 + B2 rho` with the exact second virial coefficient.
    #[serde(rename = "Z_second_virial")]
    pub z_second_virial: f64,
    /// The low-density energy per particle, to first order in the density.
    pub energy_per_particle_low_density: f64,
    /// Espindola-Heredia et al.'s equation of state (3D, 1.1 <= lambda <= 2).
    #[serde(rename = "Z_eos", skip_serializing_if = "Option::is_none")]
    pub z_eos: Option<f64>,
    /// The energy per particle of the same equation of state.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_per_particle_eos: Option<f64>,
    /// Simulated time measured over.
    pub time: f64,
    /// Measuring blocks.
    pub blocks: usize,
    /// Events measured over (hard-core collisions and step events).
    pub events: u64,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Dimension.
    pub dim: usize,
    /// Particles.
    pub n: usize,
    /// One row per density.
    pub rows: Vec<Row>,
    /// What the rows are compared with.
    pub theory: &'static str,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

const THEORY: &str = "Z_second_virial = 1 + B2 rho with the exact B2 of the square well; energy_per_particle_low_density = (rho/2) Int u exp(-u/kT) dr (first order in rho); Z_eos and energy_per_particle_eos: the equation of state of Espindola-Heredia, del Rio and Malijevsky, J. Chem. Phys. 130, 024509 (2009), fitted to simulation data (3D, 1.1 <= lambda <= 2)";

/// Runs the experiment.
pub fn run(args: &SquareWellArgs) -> Result<()> {
    match args.dim {
        3 => run_in::<3>(args),
        _ => run_in::<2>(args),
    }
}

/// The volume (area) of a particle of unit diameter.
pub(super) fn particle_volume<const D: usize>() -> f64 {
    edmd_core::setup::lattice::ball_volume(1.0, D)
}

fn check(args: &SquareWellArgs, densities: &[f64], n: usize, max_density: f64) -> Result<()> {
    let bad = |m: String| edmd::user_error(format!("square-well: {m}"));
    if !(args.lambda.is_finite() && args.lambda > 1.0 && args.lambda <= 5.0) {
        return bad(format!(
            "--lambda must be above 1 and at most 5, found {}",
            args.lambda
        ));
    }
    if !(args.kt.is_finite() && args.kt >= 0.05 && args.kt <= 1e3) {
        return bad(format!("--kt must be from 0.05 to 1000, found {}", args.kt));
    }
    if densities.is_empty() {
        return bad("give at least one density".into());
    }
    check_once("square-well", "density", densities)?;
    let min = edmd_core::setup::MIN_PACKING / edmd_core::setup::lattice::ball_volume(1.0, args.dim);
    if let Some(r) = densities
        .iter()
        .find(|&&r| !(r.is_finite() && r >= min && r <= max_density))
    {
        return bad(format!(
            "density {r} is outside [{min:.4}, {max_density}] (a fluid, from the generator's lowest packing)"
        ));
    }
    if !(16..=200_000).contains(&n) {
        return bad(format!("--n must be from 16 to 200000, found {n}"));
    }
    check_bath("square-well", args.precision, args.max_blocks, args.rate)
}

/// A value that `values` holds more than once.
/// Checks the options of a run in the bath (`--precision`, `--max-blocks`, `--rate`) for
/// the experiment `name`.
pub(super) fn check_bath(name: &str, precision: f64, max_blocks: usize, rate: f64) -> Result<()> {
    let bad = |m: String| edmd::user_error(format!("{name}: {m}"));
    if !(precision.is_finite() && (1e-4..=0.5).contains(&precision)) {
        return bad(format!(
            "--precision must be from 1e-4 to 0.5, found {precision}"
        ));
    }
    if !(20..=1_000_000).contains(&max_blocks) {
        return bad(format!(
            "--max-blocks must be from 20 to 1000000, found {max_blocks}"
        ));
    }
    // Each density settles for 10 / rate and measures in blocks of at least 2 / rate: below
    // 0.01 a single density would take hours.
    if !(rate.is_finite() && (0.01..=100.0).contains(&rate)) {
        return bad(format!("--rate must be from 0.01 to 100, found {rate}"));
    }
    Ok(())
}

/// How a stepped fluid is held and measured in the bath.
pub(super) struct Bath {
    /// Temperature.
    pub kt: f64,
    /// Redraws per particle per unit time.
    pub rate: f64,
    /// The relative error of Z and U/N aimed at.
    pub precision: f64,
    /// The most blocks.
    pub max_blocks: usize,
}

/// What a run in the bath measured.
pub(super) struct Measured {
    /// Compressibility factor.
    pub z: Estimate,
    /// Potential energy per particle.
    pub u: Estimate,
    /// Heat capacity per particle.
    pub cv: Estimate,
    /// Mean kinetic temperature.
    pub kt: f64,
    /// Simulated time measured over.
    pub time: f64,
    /// Blocks.
    pub blocks: usize,
    /// Pair events (hard-core collisions and step events) measured over.
    pub events: u64,
}

/// Runs `discs` in `bx` under `potential` in the bath: an equilibration (at least 50 pair
/// events per particle and ten redraws per particle), then blocks of about 20 pair events per
/// particle, each with 20 energy samples, until the errors of `Z` and `U/N` are within the
/// precision (or the most blocks). `None` if a stop was requested. `what` names the system in
/// messages.
/// Sets up a start's engine and drops it: run over every point before the first runs, so
/// that a point the engine would refuse (a box too small for the potential's reach) is
/// refused before any work rather than after the points before it.
pub(super) fn check_start<const D: usize>(
    what: &str,
    discs: &[edmd_core::Disc<D>],
    bx: edmd_core::SimBox<D>,
    potential: &Potential,
) -> Result<()> {
    Simulation::with_potential_at(discs, bx, &[], potential, Options::default(), 0.0)
        .map(drop)
        .or_else(|e| edmd::user_error(format!("{what}: {e}")))
}

pub(super) fn measure_in_bath<const D: usize>(
    what: &str,
    discs: &[edmd_core::Disc<D>],
    bx: edmd_core::SimBox<D>,
    potential: &Potential,
    bath: &Bath,
    seed: u64,
) -> Result<Option<Measured>> {
    let n = discs.len();
    let mut sim = Simulation::with_potential_at(discs, bx, &[], potential, Options::default(), 0.0)
        .or_else(|e| edmd::user_error(format!("{what}: {e}")))?;
    sim.set_thermostat(Some(Andersen {
        kt: bath.kt,
        rate: bath.rate,
        seed,
    }))
    .or_else(|e| edmd::user_error(format!("{what}: {e}")))?;
    let events = |s: &Simulation<D>| s.stats().disc_disc + s.stats().step;
    let t_bath = 10.0 / bath.rate;
    let e0 = events(&sim);
    while events(&sim) - e0 < 50 * n as u64 || sim.time() < t_bath {
        let probe = sim.time() + 0.1 * t_bath;
        if !edmd::run_until_or_stop(&mut sim, probe, &mut ())? {
            return Ok(None);
        }
        if events(&sim) == e0 && sim.time() > 100.0 * t_bath {
            return edmd::user_error(format!("{what}: no pair ever meets in this system"));
        }
    }
    let rate = (events(&sim) - e0) as f64 / sim.time().max(f64::MIN_POSITIVE);
    let block = (20.0 * n as f64 / rate.max(f64::MIN_POSITIVE)).max(2.0 / bath.rate);
    let per_block = 20;
    let mut pressure = Pressure::new(&sim);
    let (t0, c0) = (sim.time(), events(&sim));
    let nf = n as f64;
    let (mut u_blocks, mut all_e, mut kt_sum) = (Vec::new(), Vec::new(), 0.0);
    let mut blocks = 0;
    loop {
        let mut u_sum = 0.0;
        for k in 1..=per_block {
            let t = t0 + (blocks as f64 + k as f64 / per_block as f64) * block;
            if !edmd::run_until_or_stop(&mut sim, t, &mut pressure)? {
                return Ok(None);
            }
            let (u, ke) = (sim.potential_energy(), sim.kinetic_energy());
            u_sum += u / nf;
            all_e.push(u + ke);
            kt_sum += 2.0 * ke / (D as f64 * nf);
        }
        pressure.sample(&sim);
        u_blocks.push(u_sum / per_block as f64);
        blocks += 1;
        if blocks >= 20 && blocks % 10 == 0 || blocks >= bath.max_blocks {
            let z = pressure.summary().z;
            let u = Estimate::new(mean(&u_blocks), &u_blocks);
            // A zero energy (no pair inside a step, as in a dilute shoulder fluid) is exact.
            let precise = |e: &Estimate| e.error <= bath.precision * e.value.abs();
            if (precise(&z) && (precise(&u) || u.value == 0.0)) || blocks >= bath.max_blocks {
                break;
            }
        }
    }
    // C_V / (N k) = var(E) / (N kT^2), with an error from the variances of the blocks.
    let cv_of = |e: &[f64]| variance(e) / (nf * bath.kt * bath.kt);
    let cv_blocks: Vec<f64> = all_e
        .chunks(per_block * (blocks / 10).max(1))
        .map(cv_of)
        .collect();
    Ok(Some(Measured {
        z: pressure.summary().z,
        u: Estimate::new(mean(&u_blocks), &u_blocks),
        cv: Estimate::new(cv_of(&all_e), &cv_blocks),
        kt: kt_sum / all_e.len() as f64,
        time: sim.time() - t0,
        blocks,
        events: events(&sim) - c0,
    }))
}

/// The start at one density: its name in messages, the fluid and its box.
type Start<const D: usize> = (String, Vec<edmd_core::Disc<D>>, edmd_core::SimBox<D>);

/// The start at density `rho`.
fn start<const D: usize>(n: usize, rho: f64, seed: u64) -> Result<Start<D>> {
    let what = format!("square-well: density {rho}");
    let (discs, bx) =
        lattice_fluid_in::<D>(n, rho * particle_volume::<D>(), Boundary::Periodic, seed)
            .or_else(|e| edmd::user_error(format!("{what}: {e}")))?;
    Ok((what, discs, bx))
}

/// What one density gave from its start, or `None` if a stop was requested.
fn measure<const D: usize>(
    args: &SquareWellArgs,
    potential: &Potential,
    (what, discs, bx): &Start<D>,
    rho: f64,
    seed: u64,
) -> Result<Option<Row>> {
    let steps = [Step {
        radius: args.lambda,
        energy: -1.0,
    }];
    let bath = Bath {
        kt: args.kt,
        rate: args.rate,
        precision: args.precision,
        max_blocks: args.max_blocks,
    };
    let Some(m) = measure_in_bath::<D>(what, discs, *bx, potential, &bath, seed)? else {
        return Ok(None);
    };
    let eos = (D == 3)
        .then(|| eos_values(args.lambda, args.kt, rho))
        .flatten();
    let b2 = stepped_b2(D, 1.0, &steps, args.kt);
    Ok(Some(Row {
        density: rho,
        kt: args.kt,
        lambda: args.lambda,
        z: m.z.value,
        z_error: m.z.error,
        energy_per_particle: m.u.value,
        energy_per_particle_error: m.u.error,
        heat_capacity: m.cv.value,
        heat_capacity_error: m.cv.error,
        kinetic_temperature: m.kt,
        z_second_virial: 1.0 + b2 * rho,
        energy_per_particle_low_density: stepped_energy_low_density(D, 1.0, &steps, args.kt, rho),
        z_eos: eos.map(|e| e.0),
        energy_per_particle_eos: eos.map(|e| e.1),
        time: m.time,
        blocks: m.blocks,
        events: m.events,
    }))
}

/// Espindola-Heredia et al.'s `Z` and `U/N` where the fit holds.
fn eos_values(lambda: f64, kt: f64, rho: f64) -> Option<(f64, f64)> {
    use edmd_core::measure::square_well_eos as eos;
    eos::lambda_in_fit_range(lambda).then(|| {
        (
            eos::compressibility(lambda, kt, rho),
            eos::energy_per_particle(lambda, kt, rho),
        )
    })
}

pub(super) fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

fn run_in<const D: usize>(args: &SquareWellArgs) -> Result<()> {
    let densities = args.density.clone().unwrap_or_else(|| {
        let top = if D == 3 { 8 } else { 7 };
        (1..=top).map(|k| 0.1 * k as f64).collect()
    });
    let n = args.n.unwrap_or(if D == 3 { 2000 } else { 1000 });
    // Fluid densities the lattice start melts from: below freezing of hard spheres (packing
    // 0.494) and hard discs (0.70).
    let max_density = if D == 3 { 0.9 } else { 0.85 };
    check(args, &densities, n, max_density)?;
    let potential = Potential::single(0, 0, args.lambda, -1.0);
    // Every start is made and checked before the first density runs.
    let mut starts = Vec::with_capacity(densities.len());
    for (k, &rho) in densities.iter().enumerate() {
        let s = start::<D>(n, rho, args.common.seed + k as u64)?;
        check_start(&s.0, &s.1, s.2, &potential)?;
        starts.push(s);
    }
    let dir = out_dir(
        &args.common,
        &outputs(&["square-well"], &["square-well-z", "square-well-energy"]),
    )?;
    let bar = Progress::new(densities.len() as u64, "square-well");
    let mut rows = Vec::new();
    for (k, (&rho, s)) in densities.iter().zip(&starts).enumerate() {
        match measure::<D>(args, &potential, s, rho, args.common.seed + k as u64)? {
            Some(row) => rows.push(row),
            None => break,
        }
        bar.set(k as u64 + 1);
    }
    bar.finish();
    let interrupted = rows.len() < densities.len();
    let csv = dir.join("square-well.csv");
    write_csv(
        &csv,
        &[
            "density",
            "Z",
            "Z_error",
            "energy_per_particle",
            "energy_per_particle_error",
            "heat_capacity",
            "heat_capacity_error",
            "Z_second_virial",
            "energy_per_particle_low_density",
            "Z_eos",
            "energy_per_particle_eos",
        ],
        rows.iter().map(|r| {
            vec![
                r.density,
                r.z,
                r.z_error,
                r.energy_per_particle,
                r.energy_per_particle_error,
                r.heat_capacity,
                r.heat_capacity_error,
                r.z_second_virial,
                r.energy_per_particle_low_density,
                r.z_eos.unwrap_or(f64::NAN),
                r.energy_per_particle_eos.unwrap_or(f64::NAN),
            ]
        }),
    )?;
    let top = densities.iter().copied().fold(0.0, f64::max);
    let grid: Vec<f64> = (1..=200).map(|i| top * i as f64 / 200.0).collect();
    let steps = [Step {
        radius: args.lambda,
        energy: -1.0,
    }];
    let b2 = stepped_b2(D, 1.0, &steps, args.kt);
    let title = format!(
        "Square-well {} (lambda {}, kT {}, {n} particles)",
        if D == 3 { "spheres" } else { "discs" },
        args.lambda,
        args.kt
    );
    let mut fig_z =
        Figure::new(&title, "number density rho sigma^D", "Z = P / (rho kT)").with(Series::line(
            "1 + B2 rho (exact B2)",
            grid.iter().map(|&r| (r, 1.0 + b2 * r)).collect(),
        ));
    let mut fig_u =
        Figure::new(&title, "number density rho sigma^D", "U / N (well depth)").with(Series::line(
            "low density, first order",
            grid.iter()
                .map(|&r| (r, stepped_energy_low_density(D, 1.0, &steps, args.kt, r)))
                .collect(),
        ));
    if D == 3 && eos_values(args.lambda, args.kt, top).is_some() {
        let curve = |which: fn((f64, f64)) -> f64| {
            grid.iter()
                .filter_map(|&r| eos_values(args.lambda, args.kt, r).map(|v| (r, which(v))))
                .collect()
        };
        fig_z = fig_z.with(Series::line(
            "Espindola-Heredia et al. 2009",
            curve(|v| v.0),
        ));
        fig_u = fig_u.with(Series::line(
            "Espindola-Heredia et al. 2009",
            curve(|v| v.1),
        ));
    }
    let (z_png, z_svg) = fig_z
        .with(Series::error_bars(
            "edmd (Andersen bath)",
            rows.iter().map(|r| (r.density, r.z)).collect(),
            rows.iter().map(|r| r.z_error).collect(),
        ))
        .save(&dir.join("square-well-z"))?;
    let (u_png, u_svg) = fig_u
        .with(Series::error_bars(
            "edmd (Andersen bath)",
            rows.iter()
                .map(|r| (r.density, r.energy_per_particle))
                .collect(),
            rows.iter().map(|r| r.energy_per_particle_error).collect(),
        ))
        .save(&dir.join("square-well-energy"))?;
    let mut human = format!(
        "square-well fluid, {} {n}, lambda {}, kT {} (Andersen bath):\n  density        Z    error   1+B2rho      EOS      U/N    error  low-dens      EOS   C_V/Nk\n",
        if D == 3 { "spheres" } else { "discs" },
        args.lambda,
        args.kt
    );
    for r in &rows {
        let opt = |x: Option<f64>| x.map_or("        -".to_string(), |v| format!("{v:9.4}"));
        human += &format!(
            "  {:7.4} {:8.4} {:8.4} {:9.4} {} {:8.4} {:8.4} {:9.4} {} {:8.3}\n",
            r.density,
            r.z,
            r.z_error,
            r.z_second_virial,
            opt(r.z_eos),
            r.energy_per_particle,
            r.energy_per_particle_error,
            r.energy_per_particle_low_density,
            opt(r.energy_per_particle_eos),
            r.heat_capacity
        );
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    let files = [csv, z_png, z_svg, u_png, u_svg];
    human += &files_line(&files);
    report(
        &args.common,
        &Summary {
            experiment: "square-well",
            dim: D,
            n,
            rows,
            theory: THEORY,
            interrupted,
        },
        &human,
    )?;
    if interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}
