//! `edmd experiment maxwell`: the speed distribution of a hard-disc gas against the 2D
//! Maxwell-Boltzmann law, the Rayleigh distribution `f(v) = (m v / kT) exp(-m v^2 / 2kT)`, or
//! with `--dim 3` of a hard-sphere gas against the 3D law
//! `f(v) = sqrt(2/pi) (m/kT)^(3/2) v^2 exp(-m v^2 / 2kT)`.
//!
//! The gas starts with every disc at the same speed (random directions), which is as far from
//! Rayleigh as it gets; collisions alone bring it there. Speeds are pooled from snapshots a few
//! collisions per disc apart and compared with the Kolmogorov-Smirnov test.

use anyhow::Result;
use clap::Args;
use edmd_core::measure::{kinetic_temperature, Speeds};
use edmd_core::setup::lattice_fluid_in;
use edmd_core::{Boundary, Options, Simulation, Vector};
use edmd_plot::{Figure, Series};
use rand::{Rng, SeedableRng};
use serde::Serialize;

use super::common::{
    check_packings, files_line, interrupted_after, out_dir, outputs, report, run_collisions,
    stop_requested, write_csv, CommonArgs, Progress,
};

/// Options of `edmd experiment maxwell`.
#[derive(Debug, Args)]
pub struct MaxwellArgs {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[arg(long, default_value_t = 2, value_parser = crate::args::parse_dim)]
    pub dim: usize,
    /// Number of discs.
    #[arg(long, default_value_t = 2000, allow_negative_numbers = true)]
    pub n: usize,
    /// Packing fraction.
    #[arg(long, default_value_t = 0.3, allow_negative_numbers = true)]
    pub packing: f64,
    /// Snapshots pooled into the histogram.
    #[arg(long, default_value_t = 10, allow_negative_numbers = true)]
    pub snapshots: usize,
    /// Histogram bins.
    #[arg(long, default_value_t = 40, allow_negative_numbers = true)]
    pub bins: usize,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Dimension.
    pub dim: usize,
    /// Discs.
    pub n: usize,
    /// Measured temperature kT (mass 1).
    pub kt: f64,
    /// Speeds pooled.
    pub samples: usize,
    /// Mean speed, measured and Rayleigh's `sqrt(pi kT / 2m)`.
    pub mean_speed: [f64; 2],
    /// Root mean square speed, measured and Rayleigh's `sqrt(2 kT / m)`.
    pub rms_speed: [f64; 2],
    /// Kolmogorov-Smirnov statistic against Rayleigh at the measured kT.
    pub ks_statistic: f64,
    /// Its p-value (large: consistent with Rayleigh).
    pub ks_p_value: f64,
    /// The same test on the initial, equal-speed state.
    pub initial_ks_p_value: f64,
    /// Relative kinetic energy change over the run.
    pub relative_energy_change: f64,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

/// Runs the experiment.
pub fn run(args: &MaxwellArgs) -> Result<()> {
    match args.dim {
        3 => run_in::<3>(args),
        _ => run_in::<2>(args),
    }
}

fn run_in<const D: usize>(args: &MaxwellArgs) -> Result<()> {
    check_packings(
        "maxwell",
        &[args.packing],
        if D == 3 { 0.500_000_1 } else { 0.70 },
    )?;
    super::common::check_fluid_n::<D>("maxwell", args.n)?;
    super::common::check_count("maxwell", "snapshots", args.snapshots as u64, 1, 10_000)?;
    super::common::check_count("maxwell", "bins", args.bins as u64, 2, 10_000)?;
    let dir = out_dir(&args.common, &outputs(&["maxwell"], &["maxwell"]))?;
    let (mut discs, bx) =
        lattice_fluid_in::<D>(args.n, args.packing, Boundary::Periodic, args.common.seed)
            .or_else(|e| edmd::user_error(format!("maxwell: {e}")))?;
    // Equal speeds sqrt(D) (kT = 1), random directions in opposite pairs (zero momentum).
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(args.common.seed);
    for k in (0..discs.len()).filter(|_| D == 3) {
        discs[k].vel = if k % 2 == 1 {
            -discs[k - 1].vel
        } else {
            // Uniform on the sphere: z uniform in [-1, 1], the azimuth uniform.
            let z = 2.0 * rng.random::<f64>() - 1.0;
            let phi = rng.random::<f64>() * std::f64::consts::TAU;
            let s = (1.0 - z * z).sqrt();
            Vector(std::array::from_fn(|a| {
                [s * phi.cos(), s * phi.sin(), z][a] * 3f64.sqrt()
            }))
        };
    }
    for k in (0..discs.len()).filter(|_| D == 2) {
        let a: f64 = if k % 2 == 1 {
            std::f64::consts::PI
        } else {
            rng.random::<f64>() * std::f64::consts::TAU
        };
        let base = if k % 2 == 1 {
            discs[k - 1].vel
        } else {
            let mut v = Vector::ZERO;
            v[0] = 2f64.sqrt();
            v
        };
        let (s, c) = a.sin_cos();
        let mut v = Vector::ZERO;
        v[0] = base[0] * c - base[1] * s;
        v[1] = base[0] * s + base[1] * c;
        discs[k].vel = v;
    }
    let mut sim = Simulation::new(&discs, bx, Options::default())?;
    let kt = kinetic_temperature(&sim);
    let e0 = sim.kinetic_energy();
    let max = 5.0 * kt.sqrt();
    let mut initial = Speeds::new(args.bins, max);
    initial.sample(&sim);
    let initial_p = initial.ks_maxwell(kt).p_value;
    // Relax for 30 collisions per disc, then a snapshot every 5.
    let n = args.n as u64;
    if !run_collisions(&mut sim, 30 * n)? {
        return edmd::interrupted("interrupted while the gas relaxed: nothing written");
    }
    let mut speeds = Speeds::new(args.bins, max);
    let progress = Progress::new(args.snapshots as u64, "maxwell");
    for k in 0..args.snapshots {
        if stop_requested() {
            break;
        }
        if !run_collisions(&mut sim, 5 * n)? {
            break;
        }
        speeds.sample(&sim);
        progress.set(k as u64 + 1);
    }
    progress.finish();
    let s = speeds.summary(kt);
    let rows = speeds.histogram_vs_maxwell(kt);
    let (law, what) = if D == 3 {
        ("Maxwell", "spheres")
    } else {
        ("Rayleigh", "discs")
    };
    let csv = dir.join("maxwell.csv");
    let law_column = format!("{}_density", law.to_lowercase());
    write_csv(
        &csv,
        &["speed", "measured_density", &law_column],
        rows.iter().map(|&(v, h, r)| vec![v, h, r]),
    )?;
    let curve: Vec<(f64, f64)> = (0..=300)
        .map(|i| max * i as f64 / 300.0)
        .map(|v| (v, edmd_core::measure::maxwell_pdf(v, 1.0, kt, D)))
        .collect();
    let (png, svg) = Figure::new(
        &format!(
            "Speeds of {} {what} at packing {} (KS p = {:.2})",
            args.n, args.packing, s.ks.p_value
        ),
        "speed v (units of sqrt(kT/m) at kT = 1)",
        "probability density",
    )
    .with(Series::bars(
        "measured",
        rows.iter().map(|&(v, h, _)| (v, h)).collect(),
    ))
    .with(Series::line(&format!("{law} at kT = {kt:.4}"), curve))
    .save(&dir.join("maxwell"))?;
    let files = [csv, png, svg];
    let human = format!(
        "speed distribution of {} {what} at packing {} (kT = {:.4}):\n  {} speeds from {} snapshots\n  mean speed {:.4} ({law} {:.4}), rms {:.4} ({law} {:.4})\n  Kolmogorov-Smirnov against {law}: D = {:.4}, p = {:.3} (the equal-speed start: p = {:.1e})\n{}",
        args.n, args.packing, kt, s.samples, s.snapshots, s.mean, s.mean_theory, s.rms, s.rms_theory, s.ks.statistic, s.ks.p_value, initial_p,
        files_line(&files)
    );
    let summary = Summary {
        experiment: "maxwell",
        dim: D,
        n: args.n,
        kt,
        samples: s.samples,
        mean_speed: [s.mean, s.mean_theory],
        rms_speed: [s.rms, s.rms_theory],
        ks_statistic: s.ks.statistic,
        ks_p_value: s.ks.p_value,
        initial_ks_p_value: initial_p,
        relative_energy_change: (sim.kinetic_energy() - e0) / e0,
        interrupted: s.snapshots < args.snapshots,
    };
    report(&args.common, &summary, &human)?;
    if summary.interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}
