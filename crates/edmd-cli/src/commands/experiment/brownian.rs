//! `edmd experiment brownian`: Einstein's explanation of Brownian motion.
//!
//! One big heavy disc among many small ones: the big disc wanders because the small ones hit
//! it from all sides unevenly. Its mean square displacement grows linearly at long times,
//! `<|r(t + tau) - r(t)|^2> = 4 D tau` in 2D (Einstein 1905), averaged here over every start
//! time `t` of the recorded path (time-lag average).

use anyhow::Result;
use clap::Args;
use edmd_core::measure::linear_fit;
use edmd_core::setup::generators::{generate, Brownian, GenKind};
use edmd_core::{Options, Simulation};
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_span, files_line, interrupted_after, out_dir, outputs, report, stop_requested, write_csv,
    CommonArgs, Progress,
};

/// Options of `edmd experiment brownian`.
#[derive(Debug, Args)]
pub struct BrownianArgs {
    /// Number of small discs.
    #[arg(long, default_value_t = 1000, allow_negative_numbers = true)]
    pub n: usize,
    /// Simulated time (small discs move about 0.01 per unit time).
    #[arg(long, default_value_t = 5000.0, allow_negative_numbers = true)]
    pub until: f64,
    /// Points recorded on the big disc's path.
    #[arg(long, default_value_t = 1000, allow_negative_numbers = true)]
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
    /// Small discs.
    pub n: usize,
    /// Simulated time reached.
    pub time: f64,
    /// Diffusion coefficient of the big disc, from MSD = 4 D tau (+ c).
    pub diffusion_coefficient: f64,
    /// Time lags used in the fit (from, to).
    pub fit_range: [f64; 2],
    /// Straight-line distance the big disc travelled from its start.
    pub net_displacement: f64,
    /// Relative kinetic energy change.
    pub relative_energy_change: f64,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

/// Runs the experiment.
pub fn run(args: &BrownianArgs) -> Result<()> {
    // The small discs are placed at random in the unit box around the big one.
    let sizes = Brownian::default();
    let big = std::f64::consts::PI * sizes.big_radius * sizes.big_radius;
    let most = super::common::most_at_random(1.0, big, sizes.small_radius);
    super::common::check_count("brownian", "n", args.n as u64, 1, most as u64)?;
    // The time-lag MSD averages every pair of samples up to a quarter of the path apart (a
    // cost of samples^2 / 4, a few seconds at the most allowed); its fit needs some lags.
    super::common::check_count("brownian", "samples", args.samples as u64, 40, 100_000)?;
    check_span("brownian", "until", args.until, 1e7)?;
    let dir = out_dir(
        &args.common,
        &outputs(
            &["brownian_path", "brownian_msd"],
            &["brownian_path", "brownian_msd"],
        ),
    )?;
    let kind = GenKind::Brownian(Brownian { n: args.n, ..sizes });
    let system = generate(&kind, args.common.seed)
        .or_else(|e| edmd::user_error(format!("brownian: {e}")))?;
    let mut sim = Simulation::new(&system.discs, system.sim_box, Options::default())?;
    let e0 = sim.kinetic_energy();
    let big = 0;
    let dt = args.until / args.samples as f64;
    let mut path = vec![(0.0, sim.position(big))];
    let mut stopped = false;
    let progress = Progress::new(args.samples as u64, "brownian");
    for k in 1..=args.samples {
        if stop_requested() {
            stopped = true;
            break;
        }
        if !edmd::run_until_or_stop(&mut sim, k as f64 * dt, &mut ())? {
            stopped = true;
            break;
        }
        path.push((sim.time(), sim.position(big)));
        progress.set(k as u64);
    }
    progress.finish();
    // Time-lag averaged MSD up to a quarter of the path (longer lags have too few samples).
    let max_lag = (path.len() / 4).max(2);
    let msd: Vec<(f64, f64)> = (1..max_lag)
        .map(|lag| {
            let sum: f64 = (0..path.len() - lag)
                .map(|s| (path[s + lag].1 - path[s].1).norm2())
                .sum();
            (lag as f64 * dt, sum / (path.len() - lag) as f64)
        })
        .collect();
    let from = msd.len() / 5;
    let (slope, intercept) = linear_fit(&msd[from..]).unwrap_or((0.0, 0.0));
    let d = slope / 4.0;
    let csv = dir.join("brownian_path.csv");
    write_csv(
        &csv,
        &["time", "x", "y"],
        path.iter().map(|(t, p)| vec![*t, p[0], p[1]]),
    )?;
    let msd_csv = dir.join("brownian_msd.csv");
    write_csv(
        &msd_csv,
        &["lag", "msd"],
        msd.iter().map(|&(l, m)| vec![l, m]),
    )?;
    let (png, svg) = Figure::new(
        &format!(
            "Path of the big disc among {} small ones (t = 0 to {})",
            args.n,
            sim.time()
        ),
        "x",
        "y",
    )
    .with(
        Series::line("big disc", path.iter().map(|(_, p)| (p[0], p[1])).collect())
            .coloured([200, 0, 0]),
    )
    .save(&dir.join("brownian_path"))?;
    let fit_line: Vec<(f64, f64)> = msd
        .iter()
        .map(|&(l, _)| (l, slope * l + intercept))
        .collect();
    let (png2, svg2) = Figure::new(
        "Mean square displacement of the big disc",
        "time lag tau",
        "<|r(t + tau) - r(t)|^2>",
    )
    .with(Series::points("measured (time-lag average)", msd.clone()))
    .with(Series::line(&format!("4 D tau + c, D = {d:.3e}"), fit_line))
    .save(&dir.join("brownian_msd"))?;
    let net = (path.last().unwrap().1 - path[0].1).norm2().sqrt();
    let summary = Summary {
        experiment: "brownian",
        n: args.n,
        time: sim.time(),
        diffusion_coefficient: d,
        fit_range: [
            msd.get(from).map_or(0.0, |x| x.0),
            msd.last().map_or(0.0, |x| x.0),
        ],
        net_displacement: net,
        relative_energy_change: (sim.kinetic_energy() - e0) / e0,
        interrupted: stopped,
    };
    let files = [csv, msd_csv, png, svg, png2, svg2];
    let human = format!(
        "Brownian motion of one big disc among {} small ones, to t = {}:\n  diffusion coefficient D = {:.4e} (MSD = 4 D tau + c over tau in [{:.0}, {:.0}])\n  net displacement {:.4}\n{}",
        args.n, summary.time, d, summary.fit_range[0], summary.fit_range[1], net, files_line(&files)
    );
    report(&args.common, &summary, &human)?;
    if summary.interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}
