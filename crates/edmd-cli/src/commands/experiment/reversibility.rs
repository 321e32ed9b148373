//! `edmd experiment reversibility`: run forward, reverse every velocity, run back the same
//! time, and see how far the discs land from where they started.
//!
//! Hard-disc dynamics is exactly reversible, so with exact arithmetic every disc would return.
//! Rounding (about 1e-16 relative per operation) is amplified at every collision by roughly
//! the ratio of free path to diameter, so the miss grows exponentially with the number of
//! collisions until it saturates at the size of the box: short runs of small systems come back
//! to within 1e-9, long ones forget where they came from.

use anyhow::Result;
use clap::Args;
use edmd_core::setup::lattice_fluid;
use edmd_core::{Boundary, Disc, Options, Simulation};
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_n, check_once, check_packings, check_span, files_line, interrupted_after, out_dir,
    outputs, report, run_collisions, stop_requested, write_csv, CommonArgs, Progress,
};
use edmd::user_error;

/// Options of `edmd experiment reversibility`.
#[derive(Debug, Args)]
pub struct ReversibilityArgs {
    /// Number of discs.
    #[arg(long, default_value_t = 100, allow_negative_numbers = true)]
    pub n: usize,
    /// Packing fraction.
    #[arg(long, default_value_t = 0.3, allow_negative_numbers = true)]
    pub packing: f64,
    /// Forward run lengths (simulated time), comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.5,1,2,3,4,6,8,12,16",
        allow_negative_numbers = true
    )]
    pub times: Vec<f64>,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// One forward-and-back run.
#[derive(Debug, Serialize)]
pub struct Run {
    /// Forward (and backward) simulated time.
    pub time: f64,
    /// Disc-disc collisions on the way forward.
    pub collisions: u64,
    /// Largest distance of a disc from its start after the return (diameters).
    pub max_error: f64,
    /// Root mean square distance from the start.
    pub rms_error: f64,
    /// Relative kinetic energy change over the whole run.
    pub relative_energy_change: f64,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Discs.
    pub n: usize,
    /// Packing fraction.
    pub packing: f64,
    /// The runs, shortest first.
    pub runs: Vec<Run>,
    /// True if stopped by Ctrl-C before all runs were done.
    pub interrupted: bool,
}

/// Runs the experiment.
pub fn run(args: &ReversibilityArgs) -> Result<()> {
    for &t in &args.times {
        check_span("reversibility", "times", t, 1e6)?;
    }
    check_once("reversibility", "--times", &args.times)?;
    check_n("reversibility", args.n, 2)?;
    check_packings("reversibility", &[args.packing], 0.70)?;
    let dir = out_dir(
        &args.common,
        &outputs(&["reversibility"], &["reversibility"]),
    )?;
    let (discs, bx) = lattice_fluid(args.n, args.packing, Boundary::Walls, args.common.seed)
        .or_else(|e| user_error(format!("reversibility: {e}")))?;
    // Start from a melted state, not the lattice.
    let mut melt = Simulation::new(&discs, bx, Options::default())?;
    if !run_collisions(&mut melt, 20 * args.n as u64)? {
        return edmd::interrupted("interrupted while melting the start: nothing written");
    }
    let start: Vec<Disc> = melt.discs();
    let diameter = 2.0 * start[0].radius;
    let progress = Progress::new(args.times.len() as u64, "reversibility");
    let mut runs = Vec::new();
    for (k, &t) in args.times.iter().enumerate() {
        if stop_requested() {
            break;
        }
        let mut sim = Simulation::new(&start, bx, Options::default())?;
        let e0 = sim.kinetic_energy();
        if !edmd::run_until_or_stop(&mut sim, t, &mut ())? {
            break;
        }
        let collisions = sim.stats().disc_disc;
        sim.reverse_velocities();
        if !edmd::run_until_or_stop(&mut sim, 2.0 * t, &mut ())? {
            break;
        }
        let d2: Vec<f64> = start
            .iter()
            .enumerate()
            .map(|(i, d)| (sim.position(i) - d.pos).norm2())
            .collect();
        let max = d2.iter().cloned().fold(0.0, f64::max).sqrt() / diameter;
        let rms = (d2.iter().sum::<f64>() / d2.len() as f64).sqrt() / diameter;
        runs.push(Run {
            time: t,
            collisions,
            max_error: max,
            rms_error: rms,
            relative_energy_change: (sim.kinetic_energy() - e0) / e0,
        });
        progress.set(k as u64 + 1);
    }
    progress.finish();
    let interrupted = runs.len() < args.times.len();

    let csv = dir.join("reversibility.csv");
    write_csv(
        &csv,
        &[
            "time",
            "collisions",
            "max_error_diameters",
            "rms_error_diameters",
            "relative_energy_change",
        ],
        runs.iter().map(|r| {
            vec![
                r.time,
                r.collisions as f64,
                r.max_error,
                r.rms_error,
                r.relative_energy_change,
            ]
        }),
    )?;
    let floor = 1e-17;
    let pts = |f: fn(&Run) -> f64| -> Vec<(f64, f64)> {
        runs.iter()
            .map(|r| (r.collisions as f64, f(r).max(floor)))
            .collect()
    };
    let (png, svg) = Figure::new(
        &format!("Time reversal: {} discs, packing {}", args.n, args.packing),
        "disc-disc collisions on the way forward",
        "distance from the start after the return (diameters)",
    )
    .with_log_y()
    .with(Series::line("largest", pts(|r| r.max_error)))
    .with(Series::points("root mean square", pts(|r| r.rms_error)))
    .save(&dir.join("reversibility"))?;

    let mut human = format!(
        "time reversal of {} discs at packing {}:\n  time  collisions  max error (diameters)\n",
        args.n, args.packing
    );
    for r in &runs {
        human += &format!("{:6}  {:10}  {:.3e}\n", r.time, r.collisions, r.max_error);
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    let files = [csv, png, svg];
    human += &files_line(&files);
    let summary = Summary {
        experiment: "reversibility",
        n: args.n,
        packing: args.packing,
        runs,
        interrupted,
    };
    report(&args.common, &summary, &human)?;
    if interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}
