//! `edmd experiment diffusion`: two gases mixing after the partition between them is removed.
//!
//! The `diffusion2` configuration: blue discs (species 0) thermalised in the left half, green
//! discs (species 1) in the right half, each behind a partition at x = 1/2 that is removed at
//! t = 0. The fraction of each species in the left half goes from 1 and 0 to 1/2; the mean
//! square displacement gives the self-diffusion coefficient (MSD = 4 D t in 2D).

use anyhow::Result;
use clap::Args;
use edmd_core::measure::{Diffusion, SpeciesHalves};
use edmd_core::setup::generators::{generate, Diffusion2, GenKind};
use edmd_core::{Options, Side, Simulation};
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_partitioned, files_line, interrupted_after, out_dir, outputs, report, stop_requested,
    write_csv, CommonArgs, Progress,
};

/// Options of `edmd experiment diffusion`.
#[derive(Debug, Args)]
pub struct DiffusionArgs {
    /// Discs per side.
    #[arg(long, default_value_t = 200, allow_negative_numbers = true)]
    pub n: usize,
    /// Simulated time (the discs move about 0.01 per unit time in the unit box).
    #[arg(long, default_value_t = 3000.0, allow_negative_numbers = true)]
    pub until: f64,
    /// Samples over the run.
    #[arg(long, default_value_t = 100, allow_negative_numbers = true)]
    pub samples: usize,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Discs per side.
    pub n: usize,
    /// Simulated time reached.
    pub time: f64,
    /// Fraction of the blue discs (species 0) in the left half at the end.
    pub blue_left: f64,
    /// Fraction of the green discs (species 1) in the left half at the end.
    pub green_left: f64,
    /// First time both fractions were within 0.1 of 1/2, if they got there.
    pub mixing_time: Option<f64>,
    /// Self-diffusion coefficient from the mean square displacement.
    pub diffusion_coefficient: Option<f64>,
    /// Relative kinetic energy change.
    pub relative_energy_change: f64,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

/// Runs the experiment.
pub fn run(args: &DiffusionArgs) -> Result<()> {
    check_partitioned("diffusion", args.n, args.samples, args.until)?;
    let dir = out_dir(
        &args.common,
        &outputs(&["diffusion", "diffusion_msd"], &["diffusion"]),
    )?;
    let kind = GenKind::Diffusion2(Diffusion2 {
        n: args.n,
        ..Diffusion2::default()
    });
    let system = generate(&kind, args.common.seed)
        .or_else(|e| edmd::user_error(format!("diffusion: {e}")))?;
    let mut sim = Simulation::new(&system.discs, system.sim_box, Options::default())?;
    let e0 = sim.kinetic_energy();
    let mut halves = SpeciesHalves::new(&sim, 0);
    let mut msd = Diffusion::new(&sim);
    halves.sample(&sim);
    // Fractions at evenly spaced times; the mean square displacement also at log-spaced
    // early times, where it still grows as 4 D t (later the walls of the box cap it).
    let mut times: Vec<(f64, bool)> = (1..=args.samples)
        .map(|k| (args.until * k as f64 / args.samples as f64, true))
        .collect();
    let first = args.until / args.samples as f64;
    times.extend((0..40).map(|k| (first * 1e-2 * 100f64.powf(k as f64 / 40.0), false)));
    times.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut stopped = false;
    let progress = Progress::new(times.len() as u64, "diffusion");
    for (k, &(t, fraction)) in times.iter().enumerate() {
        if stop_requested() {
            stopped = true;
            break;
        }
        if !edmd::run_until_or_stop(&mut sim, t, &mut ())? {
            stopped = true;
            break;
        }
        if fraction {
            halves.sample(&sim);
        }
        msd.sample(&sim);
        progress.set(k as u64 + 1);
    }
    progress.finish();
    // Fit MSD = 4 D t + c where it is well below the box's cap (2% of the area) and past the
    // first tenth of that stretch (ballistic at the shortest times).
    let cap = 0.02 * system.sim_box.volume();
    let free: Vec<(f64, f64)> = msd
        .series()
        .iter()
        .copied()
        .filter(|&(_, m)| m <= cap)
        .collect();
    let fit = (free.len() >= 6)
        .then(|| &free[free.len() / 3..])
        .and_then(edmd_core::measure::linear_fit)
        .map(|(slope, _)| slope / 4.0);
    let blue = halves.series(0, Side::Low);
    let green = halves.series(1, Side::Low);
    let mixing_time = blue
        .iter()
        .zip(&green)
        .find(|(b, g)| (b.1 - 0.5).abs() < 0.1 && (g.1 - 0.5).abs() < 0.1)
        .map(|(b, _)| b.0);
    let csv = dir.join("diffusion.csv");
    write_csv(
        &csv,
        &["time", "blue_in_left_half", "green_in_left_half"],
        blue.iter().zip(&green).map(|(b, g)| vec![b.0, b.1, g.1]),
    )?;
    let msd_csv = dir.join("diffusion_msd.csv");
    write_csv(
        &msd_csv,
        &["time", "msd"],
        msd.series().iter().map(|&(t, d)| vec![t, d]),
    )?;
    let (png, svg) = Figure::new(
        &format!(
            "Mixing of two gases ({} + {} discs) after the partition is removed",
            args.n, args.n
        ),
        "time",
        "fraction of each species in the left half",
    )
    .with_y_range(0.0, 1.0)
    .with(Series::line("blue (started left)", blue.clone()).coloured([0, 0, 200]))
    .with(Series::line("green (started right)", green.clone()).coloured([0, 160, 0]))
    .with(Series::line("even mix", vec![(0.0, 0.5), (sim.time(), 0.5)]).coloured([120, 120, 120]))
    .save(&dir.join("diffusion"))?;
    let summary = Summary {
        experiment: "diffusion",
        n: args.n,
        time: sim.time(),
        blue_left: blue.last().map_or(1.0, |x| x.1),
        green_left: green.last().map_or(0.0, |x| x.1),
        mixing_time,
        diffusion_coefficient: fit,
        relative_energy_change: (sim.kinetic_energy() - e0) / e0,
        interrupted: stopped,
    };
    let files = [csv, msd_csv, png, svg];
    let human = format!(
        "two gases of {} discs mixing, to t = {}:\n  in the left half at the end: blue {:.3}, green {:.3} (even mix: 0.5)\n  mixed to within 0.1 at t = {}\n  self-diffusion coefficient D = {}\n{}",
        args.n,
        summary.time,
        summary.blue_left,
        summary.green_left,
        mixing_time.map_or("(not yet)".into(), |t| format!("{t}")),
        fit.map_or("(not enough samples below the box's cap)".into(), |d| format!("{d:.4e} (MSD = 4 D t + c where MSD < 2% of the box area)")),
        files_line(&files)
    );
    report(&args.common, &summary, &human)?;
    if summary.interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}
