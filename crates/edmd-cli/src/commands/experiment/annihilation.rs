//! `edmd experiment annihilation`: `A + A -> I + I` in two dimensions, the density of A against
//! time.
//!
//! `N` equal discs (diameter 1, mass 1, kT = 1) in a periodic box, melted at a liquid packing
//! fraction, all of species A (0) at the start; a collision of two A whose normal kinetic
//! energy is at least the activation energy turns both, with the given probability, into the
//! inert species I (2), which then only collides elastically. Species are labels only, so the
//! discs move exactly as in the elastic fluid, and the A are tracers that diffuse in it and
//! vanish in pairs. The run is repeated with `--runs` seeds; the error bars are the spread of
//! the runs (standard error of their mean).
//!
//! Conventions (`edmd_core::measure::Kinetics`): the rule happens `k n_A^2 / 2` times per unit
//! area and time and each time two A go, so `dn_A/dt = -k n_A^2`.
//!
//! Compared with:
//! - **the reaction-limited mean-field law** `n_A(t) = n_0 / (1 + k n_0 t)`, with `k` from the
//!   line-of-centres law in equilibrium, `k = p (omega / n) exp(-E*/kT)` with Enskog's
//!   collision frequency `omega` (Henderson's contact value). It holds while the A are many
//!   and well mixed: at first every neighbour of an A is an A, and with a probability `p`
//!   well below 1 a pair that meets seldom reacts, so the rate is that of the collisions. The
//!   rate constant measured while more than half the discs are A is compared with it;
//! - **the diffusion-limited law** of two dimensions: once the A are few and far apart, the
//!   pairs that would have met soon are gone and the decay is set by how fast the A find one
//!   another, `n_A(t) ~ ln(t / t_0) / (8 pi D t)` with `D` the diffusion coefficient of an A
//!   (B. P. Lee, J. Phys. A 27, 2633 (1994), by the renormalisation group; the Smoluchowski
//!   rate of two-dimensional encounters, `4 pi D_rel / ln t` with `D_rel = 2 D` the relative
//!   diffusion coefficient, gives the same leading term). The amplitude `1 / (8 pi D)` is
//!   universal; `t_0` is not (it depends on `p` and on the discs' size). So `t n_A(t)` against
//!   `ln t` becomes a straight line of slope `1 / (8 pi D)` (the mean-field law would level
//!   off at `1 / k`, slope 0), and its slope over the last decade of times is measured and
//!   compared. (Toussaint and Wilczek, J. Chem. Phys. 78, 2642 (1983), is the classic for
//!   `A + B -> 0`, whose slower `t^(-d/4)` comes from the segregation of two species and does
//!   not apply to one.)
//!
//! Which `D`? Lee's walkers are independent. Discs in a two-dimensional fluid are not: the
//! velocity autocorrelation decays as `1/t` (Alder and Wainwright, Phys. Rev. A 1, 18 (1970)),
//! so the mean square displacement's `D` grows with the time it is fitted over, and what
//! makes it grow is collective (vortex) motion that carries a disc together with its
//! neighbours and brings no two A closer. Two values are given: `D` of the mean square
//! displacement of all the discs over the later half of the run (the reaction changes no
//! motion; `edmd_core::measure::Diffusion`), and Enskog's `D_E = sqrt(kT / (pi m)) /
//! (2 n sigma g(sigma))` (D. M. Gass, J. Chem. Phys. 54, 1898 (1971); written out here), the
//! kinetic theory's diffusion of a disc by uncorrelated collisions. The measured slope is
//! compared with both; in runs at packing 0.5 it agrees with Enskog's `D` and is about twice
//! the slope of the mean square displacement's.
//!
//! Each row also carries the rate constant measured since the previous sample (reactions over
//! `integral(N_A (N_A - 1) / 2 dt) / V`, all runs together), which equals the mean-field `k`
//! early and falls as the decay becomes diffusion-limited.

use std::f64::consts::PI;

use anyhow::Result;
use clap::Args;
use edmd_core::measure::theory::{contact_value, line_of_centres_rate_constant, number_density};
use edmd_core::measure::{block_error, linear_fit, Diffusion, Kinetics};
use edmd_core::{Boundary, Reaction, Reactions};
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_count, check_n, check_packings, files_line, interrupted_after, melted_fluid_in, out_dir,
    outputs, report, stop_requested, write_csv, CommonArgs, Progress,
};

/// Options of `edmd experiment annihilation`.
#[derive(Debug, Args)]
pub struct AnnihilationArgs {
    /// Number of discs (all A at the start).
    #[arg(long, default_value_t = 10_000, allow_negative_numbers = true)]
    pub n: usize,
    /// Packing fraction of the fluid (below 0.70, where discs freeze).
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    pub packing: f64,
    /// Probability that a collision of two A above the activation energy reacts (above 0, at
    /// most 1).
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    pub probability: f64,
    /// Activation energy E*/kT (from 0 to 10).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub activation: f64,
    /// Simulated time of each run (diameters over sqrt(kT/m)).
    #[arg(long, default_value_t = 300.0, allow_negative_numbers = true)]
    pub until: f64,
    /// Independent runs (seeds `--seed`, `--seed` + 1, ...), for the error bars.
    #[arg(long, default_value_t = 3, allow_negative_numbers = true)]
    pub runs: u64,
    /// Samples of the density per run, at times spaced evenly in log t.
    #[arg(long, default_value_t = 30, allow_negative_numbers = true)]
    pub samples: u64,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// One sample time.
#[derive(Debug, Serialize)]
pub struct Row {
    /// Time since the reaction started.
    pub time: f64,
    /// Number density of A (per unit area, diameter 1), the mean over the runs.
    pub density: f64,
    /// Its error (standard error of the mean over the runs).
    pub density_error: f64,
    /// Fraction of the discs that are A.
    pub a_fraction: f64,
    /// The mean-field law `n_0 / (1 + k n_0 t)` with the line-of-centres `k`.
    pub density_mean_field: f64,
    /// Lee's law `ln(t / t_0) / (8 pi D_E t)` with Enskog's `D_E` and `t_0` fitted over the
    /// last decade (`NaN` where `t <= t_0`).
    pub density_lee: f64,
    /// The rate constant since the previous sample, all runs together (`NaN` without
    /// exposure).
    pub rate_constant: f64,
    /// Its error (Poisson, from the reactions counted).
    pub rate_constant_error: f64,
    /// The line-of-centres rate constant `p (omega / n) exp(-E*/kT)`.
    pub rate_constant_theory: f64,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Dimension (always 2).
    pub dim: usize,
    /// Discs.
    pub n: usize,
    /// Packing fraction.
    pub packing: f64,
    /// Reaction probability.
    pub probability: f64,
    /// Activation energy in units of kT.
    pub activation: f64,
    /// Runs averaged.
    pub runs: u64,
    /// Number density of A at the start (all discs).
    pub initial_density: f64,
    /// Diffusion coefficient from the mean square displacement of all discs over the later
    /// half of each run, mean over the runs.
    pub diffusion_coefficient: f64,
    /// Its error (spread of the runs).
    pub diffusion_coefficient_error: f64,
    /// Enskog's diffusion coefficient `sqrt(kT/(pi m)) / (2 n sigma g)`.
    pub diffusion_coefficient_enskog: f64,
    /// The rate constant measured while more than half the discs are A.
    pub rate_constant_early: f64,
    /// Its error (Poisson).
    pub rate_constant_early_error: f64,
    /// The line-of-centres rate constant `p (omega / n) exp(-E*/kT)`.
    pub rate_constant_theory: f64,
    /// Slope of `t n_A` against `ln t` over the last decade of times, mean of the runs'.
    pub lee_slope: f64,
    /// Its error (spread of the runs' slopes).
    pub lee_slope_error: f64,
    /// Lee's amplitude `1 / (8 pi D_E)` with Enskog's `D_E`.
    pub lee_slope_theory: f64,
    /// Lee's amplitude with the mean square displacement's `D`.
    pub lee_slope_msd: f64,
    /// `t_0` of Lee's law with Enskog's `D_E`, fitted over the last decade.
    pub lee_t0: f64,
    /// Times of the Lee fit (from, to).
    pub lee_fit_range: [f64; 2],
    /// One row per sample time.
    pub rows: Vec<Row>,
    /// What the rows are compared with.
    pub theory: &'static str,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

const THEORY: &str = "A + A -> I + I in 2D, dn_A/dt = -k n_A^2 (k n_A^2/2 reactions per unit area and time): density_mean_field = n_0 / (1 + k n_0 t) with k = p (omega/n) exp(-E*/kT) (line of centres, Enskog's omega with Henderson's contact value), compared at early times (rate_constant_early); the diffusion-limited asymptote n_A = ln(t/t_0)/(8 pi D t) of B. P. Lee, J. Phys. A 27, 2633 (1994): lee_slope, the slope of t n_A against ln t over the last decade of times, against 1/(8 pi D) with Enskog's D_E = sqrt(kT/(pi m))/(2 n sigma g) (D. M. Gass, J. Chem. Phys. 54, 1898 (1971)) and with the D of the mean square displacement; density_lee = ln(t/t_0)/(8 pi D_E t) with t_0 fitted";

/// Enskog's self-diffusion coefficient of hard discs of diameter 1 and mass 1 at `kT = 1`,
/// `sqrt(kT / (pi m)) / (2 n sigma g(sigma))` (Gass 1971: the Boltzmann value
/// `sqrt(kT / (pi m)) / (2 n sigma)` over Enskog's factor, Henderson's contact value).
pub fn enskog_diffusion(eta: f64) -> f64 {
    (1.0 / PI).sqrt() / (2.0 * number_density(eta, 1.0) * contact_value(eta, 2))
}

/// What one run measured at each sample: the A count and the cumulative reactions and
/// exposure; and its diffusion coefficient and slope of `t n_A` against `ln t`.
struct RunData {
    counts: Vec<usize>,
    reactions: Vec<u64>,
    exposure: Vec<f64>,
    diffusion: f64,
    lee_slope: f64,
}

fn mean_and_error(v: &[f64]) -> (f64, f64) {
    (
        v.iter().sum::<f64>() / v.len().max(1) as f64,
        block_error(v),
    )
}

/// Runs the experiment.
pub fn run(args: &AnnihilationArgs) -> Result<()> {
    check(args)?;
    let n = args.n;
    let n0 = number_density(args.packing, 1.0);
    let volume = n as f64 / n0;
    let k_theory = args.probability
        * line_of_centres_rate_constant(args.packing, 1.0, 1.0, 1.0, 2, args.activation);
    // From when the mean-field law has lost 5% (or a hundredth of the run) to the end, evenly
    // in log t.
    let first = (0.05 / (k_theory * n0)).min(0.01 * args.until);
    let times_of = |samples: u64| -> Vec<f64> {
        (0..samples)
            .map(|k| first * (args.until / first).powf(k as f64 / (samples - 1) as f64))
            .collect()
    };
    let times = times_of(args.samples);
    // The diffusion coefficient is fitted over the later half of the run (and Lee's slope over
    // its last decade, which holds more samples): a line needs two points.
    let later = |times: &[f64]| times.iter().filter(|&&t| t >= 0.5 * args.until).count();
    if later(&times) < 2 {
        let least = (args.samples..)
            .find(|&s| later(&times_of(s)) >= 2)
            .expect("enough samples put two in the later half");
        return edmd::user_error(format!(
            "annihilation: --samples {} puts {} in the later half of the run, where the diffusion coefficient is fitted, and a line needs two: give at least {least} (they are spaced evenly in log t from t = {first:.3} to {})",
            args.samples,
            later(&times),
            args.until
        ));
    }
    let dir = out_dir(
        &args.common,
        &outputs(&["annihilation"], &["annihilation", "annihilation-lee"]),
    )?
    .to_path_buf();
    let fit_from = 0.1 * args.until;
    let progress = Progress::new(args.runs * args.samples, "annihilation");
    let mut runs = Vec::new();
    for r in 0..args.runs {
        match one_run(args, r, &times, fit_from, &progress)? {
            Some(d) => runs.push(d),
            None => break,
        }
    }
    progress.finish();
    let interrupted = (runs.len() as u64) < args.runs || stop_requested();
    let (d, d_err) = mean_and_error(&runs.iter().map(|r| r.diffusion).collect::<Vec<_>>());
    let d_enskog = enskog_diffusion(args.packing);
    let (slope, slope_err) = mean_and_error(&runs.iter().map(|r| r.lee_slope).collect::<Vec<_>>());
    let amplitude = 1.0 / (8.0 * PI * d_enskog);
    let densities: Vec<(f64, f64)> = (0..times.len())
        .map(|k| {
            mean_and_error(
                &runs
                    .iter()
                    .map(|r| r.counts[k] as f64 / volume)
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    // Lee's t_0 with Enskog's D: the mean of ln t - t n_A / amplitude over the fitted times.
    let late: Vec<f64> = times
        .iter()
        .zip(&densities)
        .filter(|(&t, d)| t >= fit_from && d.0 > 0.0)
        .map(|(&t, &(dens, _))| t.ln() - t * dens / amplitude)
        .collect();
    let lee_t0 = if late.is_empty() {
        f64::NAN
    } else {
        (late.iter().sum::<f64>() / late.len() as f64).exp()
    };
    let mut rows = Vec::new();
    let mut early = (0.0, 0.0);
    for (k, &t) in times.iter().enumerate() {
        // Reactions and exposure since the previous sample, all runs together.
        let (reactions, exposure) = runs
            .iter()
            .map(|r| {
                let before = if k > 0 {
                    (r.reactions[k - 1], r.exposure[k - 1])
                } else {
                    (0, 0.0)
                };
                ((r.reactions[k] - before.0) as f64, r.exposure[k] - before.1)
            })
            .fold((0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1));
        let rate = if exposure > 0.0 {
            reactions / exposure
        } else {
            f64::NAN
        };
        let (dens, dens_err) = densities[k];
        if dens > 0.5 * n0 {
            early.0 += reactions;
            early.1 += exposure;
        }
        rows.push(Row {
            time: t,
            density: dens,
            density_error: dens_err,
            a_fraction: dens / n0,
            density_mean_field: n0 / (1.0 + k_theory * n0 * t),
            density_lee: if t > lee_t0 {
                amplitude * (t / lee_t0).ln() / t
            } else {
                f64::NAN
            },
            rate_constant: rate,
            rate_constant_error: rate / reactions.max(1.0).sqrt(),
            rate_constant_theory: k_theory,
        });
    }
    let k_early = early.0 / early.1;
    let k_early_error = k_early / early.0.max(1.0).sqrt();
    let files = write_outputs(&dir, args, &rows, n0, k_theory, d, d_enskog, lee_t0)?;
    let mut human = format!(
        "A + A -> I + I in 2D: {n} discs at packing {}, probability {}, E* = {} kT, {} runs to t = {}:\n  rate constant while A > N/2: {:.4} +- {:.4}, line of centres {:.4}\n  diffusion coefficient: mean square displacement {:.4} +- {:.4}, Enskog {:.4}\n  t n_A against ln t over t >= {}: slope {:.4} +- {:.4}; Lee's 1/(8 pi D): {:.4} (Enskog's D), {:.4} (the MSD's)\n         t        n_A      error  mean field        Lee     k(t)\n",
        args.packing,
        args.probability,
        args.activation,
        runs.len(),
        args.until,
        k_early,
        k_early_error,
        k_theory,
        d,
        d_err,
        d_enskog,
        fit_from,
        slope,
        slope_err,
        amplitude,
        1.0 / (8.0 * PI * d)
    );
    for r in &rows {
        human += &format!(
            "  {:8.3}  {:9.3e}  {:9.2e}  {:9.3e}  {:>9}  {:>7}\n",
            r.time,
            r.density,
            r.density_error,
            r.density_mean_field,
            // Lee's law holds from its t_0 on (before, ln(t / t_0) is negative).
            if r.density_lee.is_nan() {
                "-".to_string()
            } else {
                format!("{:9.3e}", r.density_lee)
            },
            // No A left to meet, no rate.
            if r.rate_constant.is_nan() {
                "-".to_string()
            } else {
                format!("{:7.4}", r.rate_constant)
            }
        );
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    human += &files_line(&files);
    report(
        &args.common,
        &Summary {
            experiment: "annihilation",
            dim: 2,
            n,
            packing: args.packing,
            probability: args.probability,
            activation: args.activation,
            runs: runs.len() as u64,
            initial_density: n0,
            diffusion_coefficient: d,
            diffusion_coefficient_error: d_err,
            diffusion_coefficient_enskog: d_enskog,
            rate_constant_early: k_early,
            rate_constant_early_error: k_early_error,
            rate_constant_theory: k_theory,
            lee_slope: slope,
            lee_slope_error: slope_err,
            lee_slope_theory: amplitude,
            lee_slope_msd: 1.0 / (8.0 * PI * d),
            lee_t0,
            lee_fit_range: [fit_from, args.until],
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

fn check(args: &AnnihilationArgs) -> Result<()> {
    let bad = |m: String| edmd::user_error(format!("annihilation: {m}"));
    check_packings("annihilation", &[args.packing], 0.70)?;
    check_n("annihilation", args.n, 64)?;
    if !(args.probability.is_finite() && args.probability > 0.0 && args.probability <= 1.0) {
        return bad(format!(
            "--probability must be above 0 and at most 1, found {}",
            args.probability
        ));
    }
    if !(args.activation.is_finite() && (0.0..=10.0).contains(&args.activation)) {
        return bad(format!(
            "--activation {} is outside [0, 10] (in units of kT)",
            args.activation
        ));
    }
    if !(args.until.is_finite() && args.until > 0.0 && args.until <= 1e5) {
        return bad(format!(
            "--until must be above 0 and at most 100000, found {}",
            args.until
        ));
    }
    check_count("annihilation", "runs", args.runs, 2, 1000)?;
    check_count("annihilation", "samples", args.samples, 4, 10_000)?;
    Ok(())
}

/// One run: the melted fluid, all A, the rule, and the samples; `None` if a stop was requested.
fn one_run(
    args: &AnnihilationArgs,
    r: u64,
    times: &[f64],
    fit_from: f64,
    progress: &Progress,
) -> Result<Option<RunData>> {
    let seed = args.common.seed.wrapping_add(r);
    let Some((mut sim, _)) =
        melted_fluid_in::<2>(args.n, args.packing, Boundary::Periodic, seed, 20)?
    else {
        return Ok(None);
    };
    let kt = sim.kinetic_energy() / args.n as f64;
    sim.set_reactions(Some(Reactions {
        rules: vec![Reaction {
            reactants: (0, 0),
            products: (2, 2),
            activation: args.activation * kt,
            probability: args.probability,
            heat: 0.0,
        }],
        seed,
        colours: Vec::new(),
    }))
    .or_else(|e| edmd::user_error(format!("annihilation: {e}")))?;
    let mut kinetics = Kinetics::new(&sim);
    let mut msd = Diffusion::new(&sim);
    let t0 = sim.time();
    let mut data = RunData {
        counts: Vec::new(),
        reactions: Vec::new(),
        exposure: Vec::new(),
        diffusion: f64::NAN,
        lee_slope: f64::NAN,
    };
    for (k, &t) in times.iter().enumerate() {
        if !edmd::run_until_or_stop(&mut sim, t0 + t, &mut kinetics)? {
            return Ok(None);
        }
        kinetics.sample(&sim);
        msd.sample(&sim);
        let rate = &kinetics.rates()[0];
        data.counts.push(kinetics.counts()[0]);
        data.reactions.push(rate.reactions);
        data.exposure.push(rate.exposure);
        progress.set(r * times.len() as u64 + k as u64 + 1);
    }
    data.diffusion = msd.summary().map_or(f64::NAN, |f| f.coefficient);
    let area = sim.sim_box().volume();
    let late: Vec<(f64, f64)> = times
        .iter()
        .zip(&data.counts)
        .filter(|(&t, _)| t >= fit_from)
        .map(|(&t, &c)| (t.ln(), t * c as f64 / area))
        .collect();
    data.lee_slope = linear_fit(&late).map_or(f64::NAN, |f| f.0);
    Ok(Some(data))
}

#[allow(clippy::too_many_arguments)]
fn write_outputs(
    dir: &std::path::Path,
    args: &AnnihilationArgs,
    rows: &[Row],
    n0: f64,
    k: f64,
    d_msd: f64,
    d_enskog: f64,
    t0: f64,
) -> Result<Vec<std::path::PathBuf>> {
    let csv = dir.join("annihilation.csv");
    write_csv(
        &csv,
        &[
            "time",
            "density",
            "density_error",
            "density_mean_field",
            "density_lee",
            "rate_constant",
            "rate_constant_error",
            "rate_constant_theory",
        ],
        rows.iter().map(|r| {
            vec![
                r.time,
                r.density,
                r.density_error,
                r.density_mean_field,
                r.density_lee,
                r.rate_constant,
                r.rate_constant_error,
                r.rate_constant_theory,
            ]
        }),
    )?;
    let (lo, hi) = (
        rows.first().map_or(1e-3, |r| r.time),
        rows.last().map_or(1.0, |r| r.time),
    );
    let grid: Vec<f64> = (0..=200)
        .map(|i| lo * (hi / lo).powf(i as f64 / 200.0))
        .collect();
    let title = format!(
        "A + A -> I + I in 2D ({} discs, packing {}, p = {})",
        args.n, args.packing, args.probability
    );
    let amplitude = 1.0 / (8.0 * PI * d_enskog);
    let lee = |t: f64| amplitude * (t / t0).ln() / t;
    // edmd-plot has no logarithmic x axis: log10 t on a linear one.
    let (png, svg) = Figure::new(
        &title,
        "log10 t (t in diameters / sqrt(kT/m))",
        "density of A (per diameter^2)",
    )
    .with_log_y()
    .with(Series::line(
        "mean field n0 / (1 + k n0 t), line-of-centres k",
        grid.iter()
            .map(|&t| (t.log10(), n0 / (1.0 + k * n0 * t)))
            .collect(),
    ))
    .with(Series::line(
        "Lee ln(t/t0) / (8 pi D t), Enskog's D, t0 fitted",
        grid.iter()
            .filter(|&&t| t > 2.0 * t0 && t >= 0.01 * hi)
            .map(|&t| (t.log10(), lee(t)))
            .collect(),
    ))
    .with(Series::error_bars(
        "edmd",
        rows.iter().map(|r| (r.time.log10(), r.density)).collect(),
        rows.iter().map(|r| r.density_error).collect(),
    ))
    .save(&dir.join("annihilation"))?;
    // t n_A against ln t: Lee's law is a line of slope 1/(8 pi D), the mean field levels off.
    let fit: Vec<&Row> = rows.iter().filter(|r| r.time >= 0.1 * hi).collect();
    let through = |slope: f64| -> Vec<(f64, f64)> {
        // A line of the given slope through the mean of the fitted points.
        let m = fit.len().max(1) as f64;
        let (x0, y0) = fit.iter().fold((0.0, 0.0), |a, r| {
            (a.0 + r.time.ln() / m, a.1 + r.time * r.density / m)
        });
        grid.iter()
            .filter(|&&t| t >= 0.01 * hi)
            .map(|&t| (t.log10(), y0 + slope * (t.ln() - x0)))
            .collect()
    };
    let (png2, svg2) = Figure::new(
        &title,
        "log10 t (t in diameters / sqrt(kT/m))",
        "t n_A (per diameter^2 x time)",
    )
    .with(Series::line(
        "mean field t n0 / (1 + k n0 t)",
        grid.iter()
            .map(|&t| (t.log10(), t * n0 / (1.0 + k * n0 * t)))
            .collect(),
    ))
    .with(Series::line(
        &format!("slope 1/(8 pi D), Enskog's D = {d_enskog:.3}"),
        through(amplitude),
    ))
    .with(Series::line(
        &format!("slope 1/(8 pi D), the MSD's D = {d_msd:.3}"),
        through(1.0 / (8.0 * PI * d_msd)),
    ))
    .with(Series::error_bars(
        "edmd",
        rows.iter()
            .map(|r| (r.time.log10(), r.time * r.density))
            .collect(),
        rows.iter().map(|r| r.time * r.density_error).collect(),
    ))
    .save(&dir.join("annihilation-lee"))?;
    Ok(vec![csv, png, svg, png2, svg2])
}
