//! `edmd experiment cooling`: the homogeneous cooling state of a granular gas, its temperature
//! against Haff's law, and the shear instability that ends it.
//!
//! `N` smooth hard discs (spheres with `--dim 3`) of diameter and mass 1 at packing `eta` in a
//! periodic box are melted elastically at `kT = 1`, their collision frequency per particle is
//! measured at that `T0`, and then every collision loses energy with a constant coefficient
//! of normal restitution `e` (with the TC model of Luding and McNamara against inelastic
//! collapse, `tc` a ten-thousandth of the mean free time by default). The gas cools:
//!
//! - Haff's law (Haff, J. Fluid Mech. 134, 401 (1983)): a collision loses `(1 - e^2) T` on
//!   average, there are `N omega / 2` of them per unit time and `omega ∝ sqrt(T)`, so
//!   `T(t) = T0 / (1 + t/t0)^2` with `t0 = 2 dim / ((1 - e^2)(1 + 3 a2/16) omega0)`, `omega0`
//!   Enskog's collision frequency at `T0` and `a2` the Sonine coefficient of the cooling
//!   state's velocities (van Noije and Ernst, Granular Matter 1, 57 (1998)). `t0` is fitted
//!   to the measured `T(t)` before the onset, and compared with this, with the Maxwellian value
//!   (`a2 = 0`) and with the value from the measured `omega0`.
//! - The shear instability: relative to the thermal speed, transverse velocity waves longer
//!   than `L_c` grow (viscosity damps them more slowly than the gas cools), so a box wider than
//!   `L_c` leaves the homogeneous state, first into vortices and then clusters (Goldhirsch and
//!   Zanetti, Phys. Rev. Lett. 70, 1619 (1993)). `L_c` comes from the Enskog viscosity and
//!   cooling rate of Garzó and Dufty (Phys. Rev. E 59, 5895 (1999)); the fraction of the
//!   kinetic energy in the box's longest shear waves is measured against the growth of
//!   fluctuating hydrodynamics (van Noije, Ernst, Brito and Orza, Phys. Rev. Lett. 79, 411
//!   (1997)), and the onset is where it reaches `--onset-fraction`.
//!
//! Each box is run `--runs` times from independent fluids (seeds `seed`, `seed + 1`, ...);
//! the errors are the standard errors of the runs' values (of the collision frequency, of its
//! blocks of a collision per particle). The formulas are in `edmd_core::measure::theory`.

mod output;
mod run;

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use anyhow::Result;
use clap::Args;
use edmd_core::measure::block_error;
use edmd_core::measure::theory::{
    critical_length, enskog_collision_frequency_in, haff_decay_per_collision, haff_time,
    haff_time_sonine, shear_mode_growth, sonine_a2,
};
use serde::Serialize;

use super::common::{
    check_count, check_n, check_once, check_packings, files_line, interrupted_after, out_dir,
    outputs, report, CommonArgs, Progress,
};

/// Options of `edmd experiment cooling`.
#[derive(Debug, Args)]
pub struct CoolingArgs {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[arg(long, default_value_t = 2, value_parser = crate::args::parse_dim)]
    pub dim: usize,
    /// Coefficient of normal restitution e, above 0 and below 1.
    #[arg(long, default_value_t = 0.9, allow_negative_numbers = true)]
    pub restitution: f64,
    /// Packing fraction (area fraction; volume fraction in 3D).
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    pub packing: f64,
    /// Number of particles; several, comma-separated, run one box each [default: 10000 discs,
    /// 20000 spheres; at the defaults a box 4.5 (3D: 1.6) times the critical size].
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub n: Option<Vec<usize>>,
    /// The TC model's time: a collision less than this after either particle's previous one is
    /// elastic (0: off, and inelastic collapse may stop the run) [default: 1e-4 of the mean
    /// free time at the start].
    #[arg(long, allow_negative_numbers = true)]
    pub tc: Option<f64>,
    /// Independent runs per box; the errors are their spread.
    #[arg(long, default_value_t = 4, allow_negative_numbers = true)]
    pub runs: u64,
    /// Collisions per particle to cool for [default: as many as Haff's law takes to cool by
    /// 10^5, ln(10^5) dim / ((1 - e^2)(1 + 3 a2/16)/(1 - a2/16)), at most 5000].
    #[arg(long, allow_negative_numbers = true)]
    pub collisions: Option<f64>,
    /// The fraction of the kinetic energy in the box's longest shear waves that marks the onset
    /// of the instability (it starts at 2 (dim - 1) / N, and ten times that is used if more;
    /// beyond a few per cent its growth saturates, as the vortices break into clusters).
    #[arg(long, default_value_t = 0.02, allow_negative_numbers = true)]
    pub onset_fraction: f64,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// One box.
#[derive(Debug, Serialize)]
pub struct Row {
    /// Dimension.
    pub dim: usize,
    /// Coefficient of normal restitution.
    pub restitution: f64,
    /// Packing fraction.
    pub packing: f64,
    /// Particles.
    pub n: usize,
    /// The box's longest edge (diameters); its longest shear wave is `2 pi / box_length`.
    pub box_length: f64,
    /// All its edges.
    pub box_lengths: Vec<f64>,
    /// The TC model's time (the runs' mean, when it is a fraction of their free time).
    pub tc: f64,
    /// The fraction of the collisions while cooling that the TC model made elastic.
    pub tc_elastic_fraction: f64,
    /// Independent runs.
    pub runs: usize,
    /// Collisions per particle each run cooled for.
    pub collisions: f64,
    /// Temperature at the start (per degree of freedom).
    pub kt0: f64,
    /// Its error.
    pub kt0_error: f64,
    /// Collision frequency per particle at `T0`, measured before restitution is switched on.
    pub collision_frequency: f64,
    /// Its error (blocks of a collision per particle).
    pub collision_frequency_error: f64,
    /// Enskog's, `2 n sigma g sqrt(pi kT/m)` (discs), `4 n sigma^2 g sqrt(pi kT/m)` (spheres).
    pub collision_frequency_theory: f64,
    /// Haff's time fitted to `T(t)` before the onset.
    pub t0: f64,
    /// Its error (the spread of the runs).
    pub t0_error: f64,
    /// Haff's time from Enskog's frequency with the Sonine correction.
    pub t0_theory: f64,
    /// The same without it (Maxwellian velocities).
    pub t0_maxwell: f64,
    /// With the Sonine correction and the measured collision frequency.
    pub t0_measured_frequency: f64,
    /// The Sonine coefficient of the cooling state.
    pub sonine_a2: f64,
    /// `-d ln T / d tau` per collision per particle, fitted over the same samples as `t0`.
    pub decay_per_collision: f64,
    /// Its error.
    pub decay_per_collision_error: f64,
    /// `(1 - e^2)(1 + 3 a2/16) / (dim (1 - a2/16))`.
    pub decay_per_collision_theory: f64,
    /// The collisions per particle `t0` was fitted over (the runs' mean window).
    pub fit_collisions: [f64; 2],
    /// The critical size of the shear instability (diameters).
    pub critical_length: f64,
    /// `box_length / critical_length`: above 1 the box is unstable.
    pub length_ratio: f64,
    /// The fraction of the kinetic energy in the longest shear waves that marks the onset
    /// (`--onset-fraction`, or ten times its equilibrium share `2 (dim - 1) / N` if more).
    pub onset_fraction: f64,
    /// Collisions per particle at the onset (the mean over the runs that reached it; `null`
    /// if none did).
    pub onset_collisions: Option<f64>,
    /// Its error.
    pub onset_collisions_error: Option<f64>,
    /// How many runs reached the onset.
    pub onset_runs: usize,
    /// The onset linear fluctuating hydrodynamics predicts (`null` if it never comes).
    pub onset_collisions_theory: Option<f64>,
    /// Collisions per particle when `T` first stood 10% above the fitted Haff law (mean over
    /// the runs where it did).
    pub departure_collisions: Option<f64>,
    /// Its error.
    pub departure_collisions_error: Option<f64>,
    /// The final temperature over `T0` (mean of the runs; of their last samples before a
    /// collapse).
    pub final_temperature: f64,
    /// How many runs ended in an inelastic collapse (possible only with `--tc 0`).
    pub collapsed_runs: usize,
    /// Collisions per particle at their last sample before it (mean; `null` if none did).
    pub collapse_collisions: Option<f64>,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Haff's time of the first box (a copy of its row's).
    pub t0: f64,
    /// Its error.
    pub t0_error: f64,
    /// The first box's collision frequency per particle at `T0`.
    pub collision_frequency: f64,
    /// The first box's temperature at the start.
    pub kt0: f64,
    /// One row per box.
    pub rows: Vec<Row>,
    /// What the rows are compared with.
    pub theory: &'static str,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

const THEORY: &str = "t0_theory = 2 dim / ((1 - e^2)(1 + 3 a2/16) omega_Enskog(T0)) (Haff 1983; a2 of van Noije and Ernst, Granular Matter 1, 57 (1998)); t0_maxwell: a2 = 0; t0_measured_frequency: the measured omega0; collision_frequency_theory: Enskog's; critical_length: 2 pi sqrt(2 eta / (m n zeta)) with the Enskog viscosity and cooling rate of Garzo and Dufty, Phys. Rev. E 59, 5895 (1999); onset_collisions_theory: when 2 (dim - 1)/(N dim) sum_a (exp(r (1 - x_a) tau) - x_a)/(1 - x_a), x_a = (L_c/L_a)^2, reaches onset_fraction (van Noije, Ernst, Brito and Orza, Phys. Rev. Lett. 79, 411 (1997))";

/// The most collisions per particle a run cools for.
const MAX_COLLISIONS: f64 = 5000.0;

/// Runs the experiment.
pub fn run(args: &CoolingArgs) -> Result<()> {
    match args.dim {
        3 => run_in::<3>(args),
        _ => run_in::<2>(args),
    }
}

fn check(args: &CoolingArgs, sizes: &[usize], dim: usize) -> Result<()> {
    let bad = |m: String| edmd::user_error(format!("cooling: {m}"));
    let e = args.restitution;
    if !(e.is_finite() && e > 0.0 && e < 1.0) {
        return bad(format!(
            "--restitution must be above 0 and below 1 (1 is elastic: nothing cools), found {e}"
        ));
    }
    // The melted fluids: discs below 0.70, spheres to 0.50 (freezing at 0.494).
    check_packings(
        "cooling",
        &[args.packing],
        if dim == 3 { 0.500_000_1 } else { 0.70 },
    )?;
    if sizes.is_empty() {
        return bad("give at least one --n".into());
    }
    for &n in sizes {
        check_n("cooling", n, 100)?;
    }
    check_once("cooling", "--n", sizes)?;
    check_count("cooling", "runs", args.runs, 2, 1000)?;
    if let Some(tc) = args.tc {
        if !(tc.is_finite() && tc >= 0.0) {
            return bad(format!("--tc must be a finite number >= 0, found {tc}"));
        }
    }
    if let Some(c) = args.collisions {
        if !(c.is_finite() && (1.0..=MAX_COLLISIONS * 20.0).contains(&c)) {
            return bad(format!(
                "--collisions must be from 1 to {}, found {}",
                MAX_COLLISIONS * 20.0,
                // Past 1e15 in exponent form: 2^64 - 1 read as a float is not what was typed.
                if c.abs() < 1e15 {
                    c.to_string()
                } else {
                    format!("{c:e}")
                }
            ));
        }
    }
    let f = args.onset_fraction;
    if !(f.is_finite() && f > 0.0 && f < 1.0) {
        return bad(format!(
            "--onset-fraction must be above 0 and below 1, found {f}"
        ));
    }
    Ok(())
}

/// The predicted fraction of the kinetic energy in the longest shear waves after `tau`
/// collisions per particle, in a box of `n` particles with edges `lengths`.
fn shear_theory(dim: usize, e: f64, lc: f64, n: usize, lengths: &[f64], tau: f64) -> f64 {
    let per_axis = 2.0 * (dim as f64 - 1.0) / (n as f64 * dim as f64);
    lengths
        .iter()
        .map(|l| per_axis * shear_mode_growth(dim, e, (lc / l).powi(2), tau))
        .sum()
}

/// The `x = (k / k_c)^2` below 1 of the box's shear waves: every wavevector
/// `2 pi (m_1/L_1, ..., m_dim/L_dim)` longer than the critical wavelength, one of each pair
/// `k`, `-k`.
fn growing_waves(lc: f64, lengths: &[f64]) -> Vec<f64> {
    let reach: Vec<i64> = lengths.iter().map(|l| (l / lc).floor() as i64).collect();
    let sizes: Vec<i64> = reach.iter().map(|r| 2 * r + 1).collect();
    let mut xs = Vec::new();
    for index in 0..sizes.iter().product::<i64>() {
        let mut rest = index;
        let m: Vec<i64> = reach
            .iter()
            .zip(&sizes)
            .map(|(r, size)| {
                let c = rest % size - r;
                rest /= size;
                c
            })
            .collect();
        // One of each pair: the first non-zero component positive.
        if m.iter().find(|&&c| c != 0).is_none_or(|&c| c < 0) {
            continue;
        }
        let x: f64 = m
            .iter()
            .zip(lengths)
            .map(|(&c, l)| (c as f64 * lc / l).powi(2))
            .sum();
        if x < 1.0 {
            xs.push(x);
        }
    }
    xs
}

/// The predicted fraction of the kinetic energy the growing shear waves `xs`
/// ([`growing_waves`]) hold above their equilibrium share after `tau` collisions per particle,
/// `2 / (N dim) (y - 1)` per polarisation, `dim - 1` polarisations each. Haff's law does not
/// account for it (it decays by viscosity, not by collisions), so the fit of `t0` ends where it
/// reaches [`FIT_EXCESS`].
fn growing_excess(dim: usize, e: f64, n: usize, xs: &[f64], tau: f64) -> f64 {
    let per = 2.0 * (dim as f64 - 1.0) / (n as f64 * dim as f64);
    xs.iter()
        .map(|&x| per * (shear_mode_growth(dim, e, x, tau) - 1.0))
        .sum()
}

/// The predicted excess energy in growing shear waves up to which `t0` is fitted.
const FIT_EXCESS: f64 = 0.005;

/// The first `tau >= 0` at which `f`, which only grows, reaches `level`, by bisection;
/// `None` if never.
fn first_reach(f: impl Fn(f64) -> f64, level: f64) -> Option<f64> {
    if f(0.0) >= level {
        return Some(0.0);
    }
    let mut hi = 1.0;
    while f(hi) < level {
        hi *= 2.0;
        if hi > 1e9 {
            return None;
        }
    }
    let mut lo = 0.0;
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < level {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// When [`shear_theory`] reaches `level`; `None` if never.
fn onset_theory(dim: usize, e: f64, lc: f64, n: usize, lengths: &[f64], level: f64) -> Option<f64> {
    first_reach(|tau| shear_theory(dim, e, lc, n, lengths, tau), level)
}

/// The collisions per particle up to which `t0` is fitted (see [`growing_excess`]); `None`
/// when the box has no growing wave.
fn fit_end(dim: usize, e: f64, lc: f64, n: usize, lengths: &[f64]) -> Option<f64> {
    let xs = growing_waves(lc, lengths);
    if xs.is_empty() {
        return None;
    }
    first_reach(|tau| growing_excess(dim, e, n, &xs, tau), FIT_EXCESS)
}

/// The shear fraction that marks the onset in a box of `n` particles: `fraction`, or ten times
/// the equilibrium share `2 (dim - 1) / N` when that is more. A small box's fluctuations alone
/// reach a few per cent now and then, the more so near the critical size, where they settle
/// at `x / (x - 1)` times that share.
fn onset_level(dim: usize, n: usize, fraction: f64) -> f64 {
    fraction.max(10.0 * 2.0 * (dim as f64 - 1.0) / n as f64)
}

/// The mean and standard error of `values`.
fn mean_error(values: &[f64]) -> (f64, f64) {
    (
        values.iter().sum::<f64>() / values.len() as f64,
        block_error(values),
    )
}

/// A box's runs, in order; `None` in place of a run a stop cut short. The runs go on as many
/// threads as there are cores: each has its own simulation, so the results do not depend on
/// how many.
fn run_box<const D: usize>(
    args: &CoolingArgs,
    n: usize,
    collisions: f64,
    seed: u64,
    bar: &Progress,
    done: &AtomicU64,
) -> Result<Vec<Option<run::Run>>> {
    let runs = args.runs as usize;
    let next = AtomicUsize::new(0);
    let threads = std::thread::available_parallelism()
        .map_or(1, |k| k.get())
        .min(runs);
    let work = || -> Result<Vec<(usize, Option<run::Run>)>> {
        let mut mine = Vec::new();
        loop {
            let k = next.fetch_add(1, Ordering::Relaxed);
            if k >= runs {
                return Ok(mine);
            }
            let spec = run::Spec {
                n,
                packing: args.packing,
                e: args.restitution,
                tc: args.tc,
                collisions,
                seed: seed + k as u64,
                snapshot: k == 0,
            };
            let r = run::cool::<D>(&spec)?;
            bar.set(done.fetch_add(1, Ordering::Relaxed) + 1);
            mine.push((k, r));
        }
    };
    let mut all: Vec<(usize, Option<run::Run>)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads).map(|_| s.spawn(work)).collect();
        let mut all = Vec::new();
        for h in handles {
            match h.join() {
                Ok(r) => all.extend(r?),
                Err(p) => std::panic::resume_unwind(p),
            }
        }
        Ok::<_, anyhow::Error>(all)
    })?;
    all.sort_by_key(|r| r.0);
    Ok(all.into_iter().map(|r| r.1).collect())
}

/// A box's row from its runs.
fn row<const D: usize>(
    args: &CoolingArgs,
    n: usize,
    collisions: f64,
    runs: &[run::Run],
) -> (Row, Vec<run::Analysis>) {
    let e = args.restitution;
    let eta = args.packing;
    let lc = critical_length(D, e, eta);
    let lengths = runs[0].lengths.clone();
    let end = fit_end(D, e, lc, n, &lengths);
    let level = onset_level(D, n, args.onset_fraction);
    let found: Vec<run::Analysis> = runs.iter().map(|r| run::analyse(r, level, end)).collect();
    let pick = |f: &dyn Fn(&run::Analysis) -> f64| found.iter().map(f).collect::<Vec<f64>>();
    let (t0, t0_error) = mean_error(&pick(&|a| a.t0));
    let (decay, decay_error) = mean_error(&pick(&|a| a.decay));
    let (kt0, kt0_error) = mean_error(&runs.iter().map(|r| r.kt0).collect::<Vec<_>>());
    let blocks: Vec<f64> = runs.iter().flat_map(|r| r.omega_blocks.clone()).collect();
    let (omega, omega_error) = mean_error(&blocks);
    let optional = |v: Vec<f64>| {
        if v.is_empty() {
            (None, None)
        } else {
            let (m, err) = mean_error(&v);
            (Some(m), err.is_finite().then_some(err))
        }
    };
    let onsets: Vec<f64> = found.iter().filter_map(|a| a.onset).collect();
    let onset_runs = onsets.len();
    let (onset, onset_error) = optional(onsets);
    let (departure, departure_error) = optional(found.iter().filter_map(|a| a.departure).collect());
    let box_length = lengths.iter().copied().fold(0.0, f64::max);
    let omega_theory = enskog_collision_frequency_in(eta, 1.0, kt0, 1.0, D);
    let total: u64 = runs.iter().map(|r| r.collisions).sum();
    let elastic: u64 = runs.iter().map(|r| r.elastic).sum();
    let collapses: Vec<f64> = runs.iter().filter_map(|r| r.collapse).collect();
    let row = Row {
        dim: D,
        restitution: e,
        packing: eta,
        n,
        box_length,
        box_lengths: lengths.clone(),
        // Each term divided first: a sum of `--tc 1e308`s would overflow.
        tc: runs.iter().map(|r| r.tc / runs.len() as f64).sum::<f64>(),
        tc_elastic_fraction: elastic as f64 / total.max(1) as f64,
        runs: runs.len(),
        collisions,
        kt0,
        kt0_error,
        collision_frequency: omega,
        collision_frequency_error: omega_error,
        collision_frequency_theory: omega_theory,
        t0,
        t0_error,
        t0_theory: haff_time_sonine(D, e, omega_theory),
        t0_maxwell: haff_time(D, e, omega_theory),
        t0_measured_frequency: haff_time_sonine(D, e, omega),
        sonine_a2: sonine_a2(D, e),
        decay_per_collision: decay,
        decay_per_collision_error: decay_error,
        decay_per_collision_theory: haff_decay_per_collision(D, e),
        fit_collisions: [
            mean_error(&pick(&|a| a.window.0)).0,
            mean_error(&pick(&|a| a.window.1)).0,
        ],
        critical_length: lc,
        length_ratio: box_length / lc,
        onset_fraction: level,
        onset_collisions: onset,
        onset_collisions_error: onset_error,
        onset_runs,
        onset_collisions_theory: onset_theory(D, e, lc, n, &lengths, level),
        departure_collisions: departure,
        departure_collisions_error: departure_error,
        final_temperature: runs
            .iter()
            .map(|r| r.samples.last().map_or(f64::NAN, |s| s.kt / r.kt0))
            .sum::<f64>()
            / runs.len() as f64,
        collapsed_runs: collapses.len(),
        collapse_collisions: (!collapses.is_empty())
            .then(|| collapses.iter().sum::<f64>() / collapses.len() as f64),
    };
    (row, found)
}

fn run_in<const D: usize>(args: &CoolingArgs) -> Result<()> {
    let sizes = args
        .n
        .clone()
        .unwrap_or_else(|| vec![if D == 3 { 20_000 } else { 10_000 }]);
    check(args, &sizes, D)?;
    let decay = haff_decay_per_collision(D, args.restitution);
    let collisions = args
        .collisions
        .unwrap_or_else(|| ((1e5f64).ln() / decay).min(MAX_COLLISIONS));
    // Haff's law is fitted to the temperature's fall: a gas that does not even halve its
    // temperature over the run has no fall to fit (and its first sample, a hundredth of
    // Haff's time, would come after the run's end).
    if decay * collisions < 2f64.ln() {
        let needed = (2f64.ln() / decay).ceil();
        let remedy = if needed <= MAX_COLLISIONS * 20.0 {
            format!("give a lower --restitution or more --collisions (at least {needed})")
        } else {
            // The restitution at which the most collisions allowed just halve it.
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if haff_decay_per_collision(D, mid) * MAX_COLLISIONS * 20.0 >= 2f64.ln() {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            format!(
                "give a --restitution of at most {} (with --collisions {})",
                (lo * 1e6).floor() / 1e6,
                MAX_COLLISIONS * 20.0
            )
        };
        return edmd::user_error(format!(
            "cooling: --restitution {} would cool the gas by a factor of only {:.6} over {collisions} collisions per particle: {remedy}",
            args.restitution,
            (decay * collisions).exp(),
        ));
    }
    let mut names = outputs(
        &["cooling", "cooling-runs", "cooling-samples"],
        &["cooling-temperature", "cooling-shear"],
    );
    names.extend(sizes.iter().map(|n| format!("cooling-snapshot-{n}.png")));
    let dir = out_dir(&args.common, &names)?;
    let bar = Progress::new(sizes.len() as u64 * args.runs, "cooling");
    let done = AtomicU64::new(0);
    let mut boxes = Vec::new();
    for (k, &n) in sizes.iter().enumerate() {
        let seed = args.common.seed + (k as u64) * args.runs;
        let runs = run_box::<D>(args, n, collisions, seed, &bar, &done)?;
        if runs.iter().any(Option::is_none) {
            break;
        }
        let runs: Vec<run::Run> = runs.into_iter().flatten().collect();
        let (r, found) = row::<D>(args, n, collisions, &runs);
        // A box whose every run collapsed before Haff's law had the samples it is fitted over
        // has nothing to show.
        if runs.iter().all(|r| r.collapse.is_some()) && found.iter().all(|a| a.fitted < 4) {
            let most = runs.iter().filter_map(|r| r.collapse).fold(0.0, f64::max);
            return edmd::user_error(format!(
                "cooling: every run of N = {n} ended in an inelastic collapse by {most:.2} collisions per particle (e = {}, tc = 0), before the four samples Haff's law is fitted over: nothing written; a --tc above 0 prevents it (by default a ten-thousandth of the mean free time)",
                args.restitution,
            ));
        }
        boxes.push(output::Measured {
            row: r,
            runs,
            found,
        });
    }
    bar.finish();
    let interrupted = boxes.len() < sizes.len();
    let files = output::write(dir, args, &boxes)?;
    let mut human = format!(
        "homogeneous cooling, {} at packing {}, e = {} ({} runs per box, {collisions:.0} collisions per particle):\n",
        if D == 3 { "spheres" } else { "discs" },
        args.packing,
        args.restitution,
        args.runs,
    );
    for b in &boxes {
        human += &output::describe(&b.row);
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    human += &files_line(&files);
    let first = boxes.first().map(|b| &b.row);
    let summary = Summary {
        experiment: "cooling",
        t0: first.map_or(f64::NAN, |r| r.t0),
        t0_error: first.map_or(f64::NAN, |r| r.t0_error),
        collision_frequency: first.map_or(f64::NAN, |r| r.collision_frequency),
        kt0: first.map_or(f64::NAN, |r| r.kt0),
        rows: boxes.into_iter().map(|b| b.row).collect(),
        theory: THEORY,
        interrupted,
    };
    report(&args.common, &summary, &human)?;
    if interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_predicted_onset_is_where_the_predicted_fraction_reaches_the_level() {
        // Discs at e = 0.9 in a square box twice the critical size: x = 1/4 on both axes.
        let (lc, n) = (60.0, 10_000);
        let lengths = [120.0, 120.0];
        let at = onset_theory(2, 0.9, lc, n, &lengths, 0.05).unwrap();
        assert!((shear_theory(2, 0.9, lc, n, &lengths, at) - 0.05).abs() < 1e-9);
        // In closed form, F = 2 (dim - 1) y / N with both axes alike: y = 0.05 N / 2 = 250 at
        // tau = ln(x + (1 - x) y) / (r (1 - x)).
        let r = haff_decay_per_collision(2, 0.9);
        let want = (0.25 + 0.75 * 250.0f64).ln() / (0.75 * r);
        assert!((at - want).abs() < 1e-6, "{at} {want}");
        // Below the critical size the fraction settles at 2 x/(x - 1)/N: never 0.05.
        assert_eq!(onset_theory(2, 0.9, lc, n, &[30.0, 30.0], 0.05), None);
    }
}
