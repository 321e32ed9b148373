//! `edmd experiment shoulder`: the square-shoulder model of Young and Alder (Phys. Rev. Lett.
//! 38, 1213 (1977); J. Chem. Phys. 70, 473 (1979)): a hard core `sigma = 1` with a repulsive
//! step of height 1 out to `lambda sigma`.
//!
//! At low temperature and a narrow shoulder the solid has two forms with the same lattice: an
//! expanded one, where neighbours keep outside each other's shoulders (hard discs of diameter
//! `lambda`), and a condensed one, where they sit inside (hard discs of diameter 1). Between
//! them the isotherm `P(rho)` of a finite system at fixed density shows the isostructural
//! transition as a loop or a plateau, with the potential energy per particle climbing from
//! about 0 to the number of neighbours over 2. At zero temperature the transition pressure is
//! where the enthalpies of the two close-packed solids meet, `P* = (z / 2) / (v_lambda - v_1)`
//! with `z` neighbours and `v` the volume per particle of each close packing.
//!
//! Each density starts as a perfect crystal (a triangular lattice in 2D, FCC in 3D) in a box
//! that fits it, is held at `kT` by the Andersen thermostat and measured as `square-well` is
//! (`Z` from the collision virial with every impulse between a pair, `U/N` sampled). A dilute
//! first row (`--low-density`) is compared with the exact second virial coefficient.

use anyhow::Result;
use clap::Args;
use edmd_core::measure::theory::{stepped_b2, stepped_energy_low_density};
use edmd_core::setup::lattice_fluid_in;
use edmd_core::{Boundary, Disc, Potential, SimBox, Step, Vector};
use edmd_plot::{Figure, Series};
use rand::SeedableRng;
use serde::Serialize;

use super::common::{
    check_once, files_line, interrupted_after, out_dir, outputs, report, write_csv, CommonArgs,
    Progress,
};
use super::square_well::{check_bath, check_start, measure_in_bath, particle_volume, Bath};

/// Options of `edmd experiment shoulder`.
#[derive(Debug, Args)]
pub struct ShoulderArgs {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[arg(long, default_value_t = 2, value_parser = crate::args::parse_dim)]
    pub dim: usize,
    /// Range of the shoulder, in hard-core diameters.
    #[arg(long, default_value_t = 1.1, allow_negative_numbers = true)]
    pub lambda: f64,
    /// Temperature of the heat bath, in units of the shoulder's height.
    #[arg(long, default_value_t = 0.25, allow_negative_numbers = true)]
    pub kt: f64,
    /// Number densities rho sigma^D of the crystals, comma-separated [default: 2D
    /// 0.80,0.84,...,1.12; 3D 0.90,0.95,...,1.35].
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub density: Option<Vec<f64>>,
    /// The dilute fluid's density, compared with the exact second virial coefficient (0:
    /// none).
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub low_density: f64,
    /// Lattice cells along each axis: 2D, 20 x 24 sites (480 discs; the rows' count is made
    /// even); 3D, k^3 FCC cells of 4 (default 6: 864 spheres).
    #[arg(long, allow_negative_numbers = true)]
    pub cells: Option<usize>,
    /// The relative error of Z and of the energy per particle the runs aim at.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub precision: f64,
    /// The most measuring blocks per density.
    #[arg(long, default_value_t = 400, allow_negative_numbers = true)]
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
    /// The bath's temperature (units of the shoulder's height).
    pub kt: f64,
    /// Range of the shoulder (hard-core diameters).
    pub lambda: f64,
    /// Where the run started: "crystal" or "fluid" (the dilute row).
    pub start: &'static str,
    /// Compressibility factor `P / (rho kT)`.
    #[serde(rename = "Z")]
    pub z: f64,
    /// Its error.
    #[serde(rename = "Z_error")]
    pub z_error: f64,
    /// Pressure `P sigma^D / epsilon = Z rho kT`.
    pub pressure: f64,
    /// Its error.
    pub pressure_error: f64,
    /// Potential energy per particle (units of the shoulder's height).
    pub energy_per_particle: f64,
    /// Its error.
    pub energy_per_particle_error: f64,
    /// Heat capacity per particle from the fluctuations of the total energy.
    pub heat_capacity: f64,
    /// Its error.
    pub heat_capacity_error: f64,
    /// Mean kinetic temperature.
    pub kinetic_temperature: f64,
    /// `1 + B2 rho` with the exact second virial coefficient.
    #[serde(rename = "Z_second_virial")]
    pub z_second_virial: f64,
    /// The low-density energy per particle, first order in the density.
    pub energy_per_particle_low_density: f64,
    /// Simulated time measured over.
    pub time: f64,
    /// Blocks.
    pub blocks: usize,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Dimension.
    pub dim: usize,
    /// Particles in the crystals.
    pub n: usize,
    /// One row per density.
    pub rows: Vec<Row>,
    /// The zero-temperature transition pressure between the close-packed solids.
    pub transition_pressure_zero_temperature: f64,
    /// What the rows are compared with.
    pub theory: &'static str,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

const THEORY: &str = "Z_second_virial = 1 + B2 rho with the exact B2 of the square shoulder (meaningful in the dilute row); transition_pressure_zero_temperature = (z/2) / (v_lambda - v_1), where the enthalpies of the expanded (neighbours at lambda) and condensed (neighbours at 1) close-packed crystals meet at T = 0; Young and Alder, J. Chem. Phys. 70, 473 (1979)";

/// Runs the experiment.
pub fn run(args: &ShoulderArgs) -> Result<()> {
    match args.dim {
        3 => run_in::<3>(args),
        _ => run_in::<2>(args),
    }
}

/// A perfect crystal of unit-diameter particles at number density `rho`: triangular in 2D
/// (`cells` sites a row, `cells * 6 / 5` rows rounded to even), FCC in 3D (`cells^3` cubic
/// cells), velocities at `kT`.
fn crystal<const D: usize>(
    cells: usize,
    rho: f64,
    kt: f64,
    seed: u64,
) -> Result<(Vec<Disc<D>>, SimBox<D>)> {
    if D == 3 {
        let n = 4 * cells.pow(3);
        let (mut discs, bx) =
            lattice_fluid_in::<D>(n, rho * particle_volume::<D>(), Boundary::Periodic, seed)
                .or_else(|e| edmd::user_error(format!("shoulder: density {rho}: {e}")))?;
        for d in &mut discs {
            d.vel = d.vel * kt.sqrt();
        }
        return Ok((discs, bx));
    }
    let nx = cells;
    let ny = ((cells * 6 / 5).div_ceil(2) * 2).max(2);
    let a = (2.0 / (3f64.sqrt() * rho)).sqrt();
    let h = a * 3f64.sqrt() / 2.0;
    let mut discs = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let x = (i as f64 + 0.5 * (j % 2) as f64 + 0.25) * a;
            let y = (j as f64 + 0.5) * h;
            let mut p = [0.0; D];
            p[0] = x;
            p[1] = y;
            discs.push(Disc::new(Vector(p), Vector::ZERO, 0.5));
        }
    }
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
    edmd_core::setup::thermal_velocities(&mut discs, kt, &mut rng);
    let mut lengths = [0.0; D];
    lengths[0] = nx as f64 * a;
    lengths[1] = ny as f64 * h;
    Ok((discs, SimBox::periodic(lengths)))
}

fn run_in<const D: usize>(args: &ShoulderArgs) -> Result<()> {
    let bad = |m: String| edmd::user_error(format!("shoulder: {m}"));
    let densities = args.density.clone().unwrap_or_else(|| {
        if D == 3 {
            (0..10).map(|k| 0.9 + 0.05 * k as f64).collect()
        } else {
            (0..9).map(|k| 0.80 + 0.04 * k as f64).collect()
        }
    });
    if !(args.lambda.is_finite() && args.lambda > 1.0 && args.lambda <= 3.0) {
        return bad(format!(
            "--lambda must be above 1 and at most 3, found {}",
            args.lambda
        ));
    }
    if !(args.kt.is_finite() && args.kt >= 0.01 && args.kt <= 1e3) {
        return bad(format!("--kt must be from 0.01 to 1000, found {}", args.kt));
    }
    // Below the close packing of the hard cores, and above a dilute lattice's.
    let close = if D == 3 {
        2f64.sqrt()
    } else {
        2.0 / 3f64.sqrt()
    };
    if densities.is_empty() {
        return bad("give at least one density".into());
    }
    check_once("shoulder", "density", &densities)?;
    if let Some(r) = densities
        .iter()
        .find(|&&r| !(r.is_finite() && r >= 0.05 && r < 0.99 * close))
    {
        return bad(format!(
            "density {r} is outside [0.05, {:.4}) (below close packing of the cores)",
            0.99 * close
        ));
    }
    if !(args.low_density == 0.0 || (args.low_density >= 0.002 && args.low_density <= 0.05)) {
        return bad(format!(
            "--low-density must be 0 or from 0.002 to 0.05, found {}",
            args.low_density
        ));
    }
    let cells = args.cells.unwrap_or(if D == 3 { 6 } else { 20 });
    let cell_range = if D == 3 { 2..=30 } else { 4..=300 };
    if !cell_range.contains(&cells) {
        return bad(format!(
            "--cells must be from {} to {}, found {cells}",
            cell_range.start(),
            cell_range.end()
        ));
    }
    check_bath("shoulder", args.precision, args.max_blocks, args.rate)?;
    let steps = [Step {
        radius: args.lambda,
        energy: 1.0,
    }];
    let potential = Potential::single(0, 0, args.lambda, 1.0);
    let bath = Bath {
        kt: args.kt,
        rate: args.rate,
        precision: args.precision,
        max_blocks: args.max_blocks,
    };
    let b2 = stepped_b2(D, 1.0, &steps, args.kt);
    let mut plan: Vec<(f64, &'static str)> = Vec::new();
    if args.low_density > 0.0 {
        plan.push((args.low_density, "fluid"));
    }
    plan.extend(densities.iter().map(|&r| (r, "crystal")));
    let start_at = |k: usize, rho: f64, start: &str| {
        let seed = args.common.seed + k as u64;
        if start == "fluid" {
            let n = if D == 3 { 1000 } else { 500 };
            let (mut d, b) =
                lattice_fluid_in::<D>(n, rho * particle_volume::<D>(), Boundary::Periodic, seed)
                    .or_else(|e| edmd::user_error(format!("shoulder: density {rho}: {e}")))?;
            for x in &mut d {
                x.vel = x.vel * args.kt.sqrt();
            }
            Ok((d, b))
        } else {
            crystal::<D>(cells, rho, args.kt, seed)
        }
    };
    for (k, &(rho, start)) in plan.iter().enumerate() {
        let (discs, bx) = start_at(k, rho, start)?;
        check_start(&format!("shoulder: density {rho}"), &discs, bx, &potential)?;
    }
    let dir = out_dir(
        &args.common,
        &outputs(&["shoulder"], &["shoulder-pressure", "shoulder-energy"]),
    )?;
    let bar = Progress::new(plan.len() as u64, "shoulder");
    let mut rows = Vec::new();
    let mut n_crystal = 0;
    for (k, &(rho, start)) in plan.iter().enumerate() {
        let seed = args.common.seed + k as u64;
        let (discs, bx) = start_at(k, rho, start)?;
        if start == "crystal" {
            n_crystal = discs.len();
        }
        let what = format!("shoulder: density {rho}");
        let Some(m) = measure_in_bath::<D>(&what, &discs, bx, &potential, &bath, seed)? else {
            break;
        };
        rows.push(Row {
            density: rho,
            kt: args.kt,
            lambda: args.lambda,
            start,
            z: m.z.value,
            z_error: m.z.error,
            pressure: m.z.value * rho * m.kt,
            pressure_error: m.z.error * rho * m.kt,
            energy_per_particle: m.u.value,
            energy_per_particle_error: m.u.error,
            heat_capacity: m.cv.value,
            heat_capacity_error: m.cv.error,
            kinetic_temperature: m.kt,
            z_second_virial: 1.0 + b2 * rho,
            energy_per_particle_low_density: stepped_energy_low_density(
                D, 1.0, &steps, args.kt, rho,
            ),
            time: m.time,
            blocks: m.blocks,
        });
        bar.set(k as u64 + 1);
    }
    bar.finish();
    let interrupted = rows.len() < plan.len();
    // T = 0: z neighbours, volume per particle of the close packing of diameter d:
    // sqrt(3)/2 d^2 (triangular), d^3 / sqrt(2) (FCC).
    let (z_nb, v1) = if D == 3 {
        (12.0, 1.0 / 2f64.sqrt())
    } else {
        (6.0, 3f64.sqrt() / 2.0)
    };
    let v_lambda = v1 * args.lambda.powi(D as i32);
    let p0 = (z_nb / 2.0) / (v_lambda - v1);
    let csv = dir.join("shoulder.csv");
    write_csv(
        &csv,
        &[
            "density",
            "Z",
            "Z_error",
            "pressure",
            "pressure_error",
            "energy_per_particle",
            "energy_per_particle_error",
            "heat_capacity",
            "heat_capacity_error",
            "Z_second_virial",
        ],
        rows.iter().map(|r| {
            vec![
                r.density,
                r.z,
                r.z_error,
                r.pressure,
                r.pressure_error,
                r.energy_per_particle,
                r.energy_per_particle_error,
                r.heat_capacity,
                r.heat_capacity_error,
                r.z_second_virial,
            ]
        }),
    )?;
    let crystal_rows: Vec<&Row> = rows.iter().filter(|r| r.start == "crystal").collect();
    let title = format!(
        "Square shoulder {} (lambda {}, kT {}, {n_crystal} particles)",
        if D == 3 { "spheres" } else { "discs" },
        args.lambda,
        args.kt
    );
    let (lo, hi) = crystal_rows
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(r.density), b.max(r.density))
        });
    let mut fig_p = Figure::new(
        &title,
        "number density rho sigma^D",
        "pressure P sigma^D / epsilon",
    )
    .with(Series::error_bars(
        "edmd, crystal start (Andersen bath)",
        crystal_rows
            .iter()
            .map(|r| (r.density, r.pressure))
            .collect(),
        crystal_rows.iter().map(|r| r.pressure_error).collect(),
    ));
    if lo.is_finite() {
        fig_p = fig_p.with(Series::line(
            "T = 0 transition pressure",
            vec![(lo, p0), (hi, p0)],
        ));
    }
    let (p_png, p_svg) = fig_p.save(&dir.join("shoulder-pressure"))?;
    let (u_png, u_svg) = Figure::new(
        &title,
        "number density rho sigma^D",
        "U / N (shoulder height)",
    )
    .with(Series::error_bars(
        "edmd, crystal start (Andersen bath)",
        crystal_rows
            .iter()
            .map(|r| (r.density, r.energy_per_particle))
            .collect(),
        crystal_rows
            .iter()
            .map(|r| r.energy_per_particle_error)
            .collect(),
    ))
    .save(&dir.join("shoulder-energy"))?;
    let mut human = format!(
        "square shoulder, {} lambda {}, kT {} (Andersen bath); T = 0 transition pressure {p0:.3}:\n  density  start          Z    error   pressure    error      U/N    error   1+B2rho\n",
        if D == 3 { "spheres," } else { "discs," },
        args.lambda,
        args.kt
    );
    for r in &rows {
        human += &format!(
            "  {:7.4}  {:7} {:9.4} {:8.4} {:10.4} {:8.4} {:8.4} {:8.4} {:9.4}\n",
            r.density,
            r.start,
            r.z,
            r.z_error,
            r.pressure,
            r.pressure_error,
            r.energy_per_particle,
            r.energy_per_particle_error,
            r.z_second_virial
        );
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    let files = [csv, p_png, p_svg, u_png, u_svg];
    human += &files_line(&files);
    report(
        &args.common,
        &Summary {
            experiment: "shoulder",
            dim: D,
            n: n_crystal,
            rows,
            transition_pressure_zero_temperature: p0,
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
