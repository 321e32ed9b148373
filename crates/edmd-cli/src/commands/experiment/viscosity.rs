//! `edmd experiment viscosity`: the shear viscosity and the thermal conductivity of the
//! hard-sphere (or, with `--dim 2`, hard-disc) fluid against Enskog's theory.
//!
//! For each packing fraction: N particles in a periodic box, melted, then the Einstein-Helfand
//! viscosity `eta = lim <Delta G_xy(tau)^2> / (2 V kT tau)` (E. Helfand, Phys. Rev. 119, 1
//! (1960); B. J. Alder, D. M. Gass and T. E. Wainwright, J. Chem. Phys. 53, 3813 (1970)) from
//! the engine's observer ([`edmd_core::measure::Viscosity`]: windows up to 10 mean collision
//! times, the slope fitted over the longer half, blocks of four windows for the error bar),
//! drawn as `eta / eta_0` against Enskog's `eta_E / eta_0` (Chapman and Cowling (1970) section
//! 16.41 for spheres, D. M. Gass, J. Chem. Phys. 54, 1898 (1971) for discs), `eta_0` the
//! dilute gas's first Sonine viscosity, and for spheres Chapman and Cowling's form with the
//! higher Sonine approximations' factor 1.016 on the kinetic part. Alder, Gass and
//! Wainwright's factors `eta / eta_E` are not drawn: their table was not at hand to check
//! (`eta_agw` is `null`).
//!
//! The thermal conductivity is measured in the same runs by the same route
//! ([`edmd_core::measure::Conductivity`]: `lambda = lim <Delta G_x(tau)^2> / (2 V kT^2 tau)`
//! with `G_x = sum_i x_i e_i`, windows up to 20 mean collision times, blocks of four windows,
//! so half as many blocks as the viscosity's), and drawn as `lambda / lambda_0` against
//! Enskog's `lambda_E / lambda_0` (Chapman and Cowling section 16.5; Gass 1971 for discs), and
//! for spheres with the higher Sonine approximations' factor 1.025 on the kinetic part.
//!
//! The shear viscosity's second route is steady shear: the same fluid, sheared with
//! Lees-Edwards boundaries at `--shear-rate` (in units of `sqrt(kT / m) / sigma`) from the
//! streaming profile, under an Andersen thermostat about the profile at one redraw per 20 mean
//! collision times, relaxed for 50 mean collision times and measured over `--shear-blocks`
//! blocks of 50 ([`edmd_core::measure::ShearStress`]: `eta = -P_xy / gamma`, the pressure
//! tensor's kinetic part from exact integrals over each flight and its collisional part from
//! the collisions' virial), against Enskog's at the sheared fluid's own temperature, which
//! the shear raises a little above the bath's.

use anyhow::Result;
use clap::Args;
use edmd_core::measure::theory::{
    contact_value, enskog_conductivity_ratio, enskog_conductivity_ratio_chapman_cowling,
};
use edmd_core::measure::viscosity::enskog_viscosity;
use edmd_core::measure::viscosity::{
    dilute_viscosity, enskog_ratio, enskog_ratio_chapman_cowling, BLOCK_WINDOWS,
};
use edmd_core::measure::{Conductivity, ShearStress, Viscosity};
use edmd_core::{Andersen, Boundary, Shear, Simulation};
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_count, check_packings, files_line, interrupted_after, melted_fluid_in, out_dir, outputs,
    report, stop_requested, write_csv, CommonArgs, Progress,
};

/// Options of `edmd experiment viscosity`.
#[derive(Debug, Args)]
pub struct ViscosityArgs {
    /// Dimension: 3 (spheres) or 2 (discs).
    #[arg(long, default_value_t = 3, value_parser = crate::args::parse_dim)]
    pub dim: usize,
    /// Packing fractions, comma-separated (fluid: at most 0.50 for spheres, below 0.70 for
    /// discs) [default: spheres 0.1,0.25,0.4; discs 0.1,0.3,0.5].
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub packing: Option<Vec<f64>>,
    /// Number of spheres (discs).
    #[arg(long, default_value_t = 500, allow_negative_numbers = true)]
    pub n: usize,
    /// Collisions per particle to melt before measuring.
    #[arg(long, default_value_t = 50, allow_negative_numbers = true)]
    pub melt: u64,
    /// Blocks to measure over, each four windows of 10 mean collision times (the error bar
    /// shrinks as one over the square root of the blocks: about 1.5 % for spheres and 3 % for
    /// discs at 800). The thermal conductivity's blocks are twice as long (half as many). At
    /// least 4, so that each has two blocks for its error bar.
    #[arg(long, default_value_t = 800, allow_negative_numbers = true)]
    pub blocks: usize,
    /// Shear rate of the steady-shear route, in units of sqrt(kT / m) / sigma, from 0.001 to 1
    /// (well below 1: the viscosity there is the Newtonian one); 0 leaves that route out.
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    pub shear_rate: f64,
    /// Blocks of the steady-shear route, each 50 mean collision times.
    #[arg(long, default_value_t = 20, allow_negative_numbers = true)]
    pub shear_blocks: usize,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// One packing fraction.
#[derive(Debug, Serialize)]
pub struct Point {
    /// Dimension.
    pub dim: usize,
    /// Packing fraction.
    pub packing: f64,
    /// Particles.
    pub n: usize,
    /// Measured shear viscosity.
    pub eta: f64,
    /// Its statistical error (one standard deviation, from the blocks).
    pub eta_error: f64,
    /// Enskog's viscosity at the measured kT.
    pub eta_enskog: f64,
    /// Chapman and Cowling's Enskog viscosity with the factor 1.016 on the kinetic part
    /// (spheres only).
    pub eta_enskog_cc: Option<f64>,
    /// Enskog's times Alder, Gass and Wainwright's factor: not available (see the module
    /// documentation), always `null`.
    pub eta_agw: Option<f64>,
    /// The dilute gas's first Sonine viscosity at the measured kT, the unit of the figure.
    pub eta_0: f64,
    /// Measured thermal conductivity (k_B = 1).
    pub lambda: f64,
    /// Its statistical error (one standard deviation, from its blocks).
    pub lambda_error: f64,
    /// Enskog's thermal conductivity at the measured kT.
    pub lambda_enskog: f64,
    /// Chapman and Cowling's Enskog conductivity with the factor 1.025 on the kinetic part
    /// (spheres only).
    pub lambda_enskog_cc: Option<f64>,
    /// The dilute gas's first Sonine conductivity at the measured kT, the unit of its figure.
    pub lambda_0: f64,
    /// The conductivity's blocks (each twice the viscosity's).
    pub lambda_blocks: usize,
    /// Time-averaged kT.
    pub kt: f64,
    /// The shear rate of the steady-shear route (`null` when left out).
    pub shear_rate: Option<f64>,
    /// The shear viscosity in steady shear, `-P_xy / gamma`.
    pub eta_shear: Option<f64>,
    /// Its statistical error (from its blocks).
    pub eta_shear_error: Option<f64>,
    /// Enskog's viscosity at the sheared fluid's kT.
    pub eta_shear_enskog: Option<f64>,
    /// The sheared fluid's kT (of the velocities relative to the streaming profile).
    pub kt_shear: Option<f64>,
    /// The shear rate in units of sqrt(kT / m) / sigma at that kT.
    pub shear_reduced_rate: Option<f64>,
    /// The longest window.
    pub window: f64,
    /// The shortest window in the fit.
    pub fit_from: f64,
    /// Blocks measured.
    pub blocks: usize,
    /// Collisions measured over.
    pub collisions: u64,
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
    /// One entry per packing fraction.
    pub results: Vec<Point>,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

/// Runs the experiment.
pub fn run(args: &ViscosityArgs) -> Result<()> {
    match args.dim {
        2 => run_in::<2>(args),
        _ => run_in::<3>(args),
    }
}

fn run_in<const D: usize>(args: &ViscosityArgs) -> Result<()> {
    let packings = args.packing.clone().unwrap_or_else(|| {
        if D == 3 {
            vec![0.1, 0.25, 0.4]
        } else {
            vec![0.1, 0.3, 0.5]
        }
    });
    // Spheres are fluid up to 0.50 (inclusive: the generator makes 0.50), discs below 0.70.
    check_packings(
        "viscosity",
        &packings,
        if D == 3 { 0.500_000_1 } else { 0.70 },
    )?;
    super::common::check_fluid_n::<D>("viscosity", args.n)?;
    check_count("viscosity", "melt", args.melt, 0, 100_000)?;
    check_count("viscosity", "blocks", args.blocks as u64, 4, 100_000)?;
    check_count(
        "viscosity",
        "shear-blocks",
        args.shear_blocks as u64,
        2,
        100_000,
    )?;
    // The viscosity is the stress over the rate: at rates far below the stress's noise over
    // the run it is that noise divided by almost nothing (1e-308 gave 2e305 with an error of
    // inf).
    if !(args.shear_rate == 0.0 || (1e-3..=1.0).contains(&args.shear_rate)) {
        return edmd::user_error(format!(
            "viscosity: --shear-rate must be 0 (no steady shear) or from 0.001 to 1, found {}",
            args.shear_rate
        ));
    }
    let dir = out_dir(
        &args.common,
        &outputs(&["viscosity"], &["viscosity", "conductivity"]),
    )?;
    let progress = Progress::new((packings.len() * args.blocks) as u64, "viscosity");
    let mut results = Vec::new();
    'packings: for (k, &phi) in packings.iter().enumerate() {
        let Some((mut sim, _)) = melted_fluid_in::<D>(
            args.n,
            phi,
            Boundary::Periodic,
            args.common.seed + k as u64,
            args.melt,
        )?
        else {
            break 'packings;
        };
        let mut visc = Viscosity::for_fluid(&sim);
        let mut cond = Conductivity::for_fluid(&sim);
        let (spacing, lags) = visc.grid();
        let block = spacing * (lags * BLOCK_WINDOWS) as f64;
        let (t0, c0) = (sim.time(), sim.stats().disc_disc);
        for b in 0..args.blocks {
            if stop_requested() {
                break 'packings;
            }
            // A block past its last grid point, so that it closes.
            let t = t0 + (b + 1) as f64 * block + 0.5 * spacing;
            if !edmd::run_until_or_stop(&mut sim, t, &mut (&mut visc, &mut cond))? {
                break 'packings;
            }
            progress.set((k * args.blocks + b + 1) as u64);
        }
        visc.sample(&sim);
        cond.sample(&sim);
        let s = visc.summary();
        let c = cond.summary();
        let sheared = if args.shear_rate > 0.0 {
            let seed = args.common.seed.wrapping_add(1000 + k as u64);
            match steady_shear(
                sim.clone(),
                args.shear_rate,
                4.0 * spacing,
                args.shear_blocks,
                seed,
            )? {
                Some(r) => Some(r),
                None => break 'packings,
            }
        } else {
            None
        };
        let eta_0 = dilute_viscosity(D, 1.0, s.kt, 1.0);
        let chi = contact_value(phi, D);
        results.push(Point {
            dim: D,
            packing: phi,
            n: args.n,
            eta: s.eta.value,
            eta_error: s.eta.error,
            eta_enskog: s.eta_enskog,
            eta_enskog_cc: (D == 3).then(|| enskog_ratio_chapman_cowling(phi, chi) * eta_0),
            eta_agw: None,
            eta_0,
            lambda: c.lambda.value,
            lambda_error: c.lambda.error,
            lambda_enskog: c.lambda_enskog,
            lambda_enskog_cc: (D == 3)
                .then(|| enskog_conductivity_ratio_chapman_cowling(phi, chi) * c.lambda_0),
            lambda_0: c.lambda_0,
            lambda_blocks: c.lambda.blocks,
            kt: s.kt,
            shear_rate: sheared.map(|r| r.rate),
            eta_shear: sheared.map(|r| r.eta.value),
            eta_shear_error: sheared.map(|r| r.eta.error),
            eta_shear_enskog: sheared.map(|r| enskog_viscosity(D, phi, 1.0, r.kt.value, 1.0)),
            kt_shear: sheared.map(|r| r.kt.value),
            shear_reduced_rate: sheared.map(|r| r.reduced_rate),
            window: s.window,
            fit_from: s.fit_from,
            blocks: s.eta.blocks,
            collisions: sim.stats().disc_disc - c0,
        });
    }
    progress.finish();
    let interrupted = results.len() < packings.len();
    let what = if D == 3 { "spheres" } else { "discs" };
    let csv = dir.join("viscosity.csv");
    write_csv(
        &csv,
        &[
            "packing",
            "eta",
            "eta_error",
            "eta_0",
            "eta_enskog",
            "eta_enskog_cc",
            "eta_over_eta0",
            "eta_error_over_eta0",
            "lambda",
            "lambda_error",
            "lambda_0",
            "lambda_enskog",
            "lambda_enskog_cc",
            "lambda_over_lambda0",
            "lambda_error_over_lambda0",
            "kT",
            "eta_shear",
            "eta_shear_error",
            "eta_shear_enskog",
            "eta_shear_over_eta0",
            "eta_shear_error_over_eta0",
            "kT_shear",
        ],
        results.iter().map(|p| {
            vec![
                p.packing,
                p.eta,
                p.eta_error,
                p.eta_0,
                p.eta_enskog,
                p.eta_enskog_cc.unwrap_or(f64::NAN),
                p.eta / p.eta_0,
                p.eta_error / p.eta_0,
                p.lambda,
                p.lambda_error,
                p.lambda_0,
                p.lambda_enskog,
                p.lambda_enskog_cc.unwrap_or(f64::NAN),
                p.lambda / p.lambda_0,
                p.lambda_error / p.lambda_0,
                p.kt,
                p.eta_shear.unwrap_or(f64::NAN),
                p.eta_shear_error.unwrap_or(f64::NAN),
                p.eta_shear_enskog.unwrap_or(f64::NAN),
                shear_over_eta0(p).map_or(f64::NAN, |r| r.0),
                shear_over_eta0(p).map_or(f64::NAN, |r| r.1),
                p.kt_shear.unwrap_or(f64::NAN),
            ]
        }),
    )?;
    let top = packings.iter().cloned().fold(0.0, f64::max);
    let grid = |f: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> {
        (1..=500)
            .map(|i| top * i as f64 / 500.0)
            .map(|phi| (phi, f(phi)))
            .collect()
    };
    let mut figure = Figure::new(
        &format!(
            "Shear viscosity of hard {what} ({} {what}, periodic)",
            args.n
        ),
        "packing fraction phi",
        "eta / eta_0",
    )
    .with(Series::line(
        if D == 3 {
            "Enskog (Chapman and Cowling, first Sonine)"
        } else {
            "Enskog (Gass 1971)"
        },
        grid(&|phi| enskog_ratio(D, phi, contact_value(phi, D))),
    ));
    if D == 3 {
        figure = figure.with(Series::line(
            "Enskog with the 1.016 factor (Chapman and Cowling)",
            grid(&|phi| enskog_ratio_chapman_cowling(phi, contact_value(phi, 3))),
        ));
    }
    figure = figure.with(Series::error_bars(
        "edmd, Einstein-Helfand",
        results
            .iter()
            .map(|p| (p.packing, p.eta / p.eta_0))
            .collect(),
        results.iter().map(|p| p.eta_error / p.eta_0).collect(),
    ));
    let shear_points: Vec<(f64, (f64, f64))> = results
        .iter()
        .filter_map(|p| shear_over_eta0(p).map(|r| (p.packing, r)))
        .collect();
    if !shear_points.is_empty() {
        figure = figure.with(Series::error_bars(
            "edmd, steady shear",
            shear_points.iter().map(|&(x, (y, _))| (x, y)).collect(),
            shear_points.iter().map(|&(_, (_, e))| e).collect(),
        ));
    }
    let (png, svg) = figure.save(&dir.join("viscosity"))?;
    let mut figure = Figure::new(
        &format!(
            "Thermal conductivity of hard {what} ({} {what}, periodic)",
            args.n
        ),
        "packing fraction phi",
        "lambda / lambda_0",
    )
    .with(Series::line(
        if D == 3 {
            "Enskog (Chapman and Cowling, first Sonine)"
        } else {
            "Enskog (Gass 1971)"
        },
        grid(&|phi| enskog_conductivity_ratio(D, phi, contact_value(phi, D))),
    ));
    if D == 3 {
        figure = figure.with(Series::line(
            "Enskog with the 1.025 factor (Chapman and Cowling)",
            grid(&|phi| enskog_conductivity_ratio_chapman_cowling(phi, contact_value(phi, 3))),
        ));
    }
    let (png_lambda, svg_lambda) = figure
        .with(Series::error_bars(
            "edmd, Einstein-Helfand",
            results
                .iter()
                .map(|p| (p.packing, p.lambda / p.lambda_0))
                .collect(),
            results
                .iter()
                .map(|p| p.lambda_error / p.lambda_0)
                .collect(),
        ))
        .save(&dir.join("conductivity"))?;
    let mut human = format!(
        "shear viscosity, {} {what}, periodic box (units: diameter, mass, kT = 1):\n  packing       eta     error    Enskog  eta/Enskog   eta/eta_0\n",
        args.n
    );
    for p in &results {
        human += &format!(
            "  {:7.3}  {:8.4}  {:8.4}  {:8.4}  {:10.3}  {:10.3}\n",
            p.packing,
            p.eta,
            p.eta_error,
            p.eta_enskog,
            p.eta / p.eta_enskog,
            p.eta / p.eta_0
        );
    }
    if args.shear_rate > 0.0 {
        human += "steady shear (Lees-Edwards, Andersen thermostat about the profile):\n  packing  rate*   eta_shear     error    Enskog  eta/Enskog     kT\n";
        for p in &results {
            if let (Some(e), Some(err), Some(en), Some(r), Some(kt)) = (
                p.eta_shear,
                p.eta_shear_error,
                p.eta_shear_enskog,
                p.shear_reduced_rate,
                p.kt_shear,
            ) {
                human += &format!(
                    "  {:7.3}  {:5.3}  {:10.4}  {:8.4}  {:8.4}  {:10.3}  {:5.3}\n",
                    p.packing,
                    r,
                    e,
                    err,
                    en,
                    e / en,
                    kt
                );
            }
        }
    }
    human += "thermal conductivity (k_B = 1):\n  packing    lambda     error    Enskog  lambda/Enskog  lambda/lambda_0\n";
    for p in &results {
        human += &format!(
            "  {:7.3}  {:8.4}  {:8.4}  {:8.4}  {:13.3}  {:15.3}\n",
            p.packing,
            p.lambda,
            p.lambda_error,
            p.lambda_enskog,
            p.lambda / p.lambda_enskog,
            p.lambda / p.lambda_0
        );
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    let files = [csv, png, svg, png_lambda, svg_lambda];
    human += &files_line(&files);
    report(
        &args.common,
        &Summary {
            experiment: "viscosity",
            dim: D,
            n: args.n,
            results,
            interrupted,
        },
        &human,
    )?;
    if interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}

/// The steady-shear viscosity over the dilute gas's at the sheared fluid's kT, and its error.
fn shear_over_eta0(p: &Point) -> Option<(f64, f64)> {
    let (eta, err, kt) = (p.eta_shear?, p.eta_shear_error?, p.kt_shear?);
    let eta_0 = dilute_viscosity(p.dim, 1.0, kt, 1.0);
    Some((eta / eta_0, err / eta_0))
}

/// The steady-shear route on a melted fluid at kT = 1 whose mean collision time is `tau`:
/// sheared at `rate` from the streaming profile, under a thermostat about it, relaxed for 50
/// `tau` and measured over `blocks` blocks of 50 `tau`. `None` when stopped by Ctrl-C.
fn steady_shear<const D: usize>(
    mut sim: Simulation<D>,
    rate: f64,
    tau: f64,
    blocks: usize,
    seed: u64,
) -> Result<Option<edmd_core::measure::ShearStressSummary>> {
    let ly = sim.sim_box().lengths[1];
    sim.set_shear(Some(Shear::new(rate)))?;
    let ys: Vec<f64> = (0..sim.len()).map(|i| sim.position(i)[1]).collect();
    sim.modify_velocities(|i, mut v| {
        v[0] += rate * (ys[i] - 0.5 * ly);
        v
    });
    sim.set_thermostat(Some(Andersen {
        kt: 1.0,
        rate: 0.05 / tau,
        seed,
    }))?;
    let block = 50.0 * tau;
    let t0 = sim.time() + block;
    if stop_requested() || !edmd::run_until_or_stop(&mut sim, t0, &mut ())? {
        return Ok(None);
    }
    let mut stress = ShearStress::new(&sim).expect("a sheared simulation");
    for b in 1..=blocks {
        if stop_requested()
            || !edmd::run_until_or_stop(&mut sim, t0 + b as f64 * block, &mut stress)?
        {
            return Ok(None);
        }
        stress.sample(&sim);
    }
    Ok(stress.summary(1.0, 1.0))
}
