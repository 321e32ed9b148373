//! `edmd experiment mfp`: free paths and free times, and the mean free path against density.
//!
//! A free path is the distance a disc travels between two successive collisions (with a disc
//! or a wall), a free time the time it takes. In a periodic box only disc-disc collisions end
//! them. Enskog's kinetic theory for hard discs gives the collision frequency
//! `omega = 2 n sigma g(sigma) sqrt(pi kT / m)` with Henderson's contact value
//! `g(sigma) = (1 - 7 eta / 16) / (1 - eta)^2`, and with the mean speed
//! `<v> = sqrt(pi kT / 2m)` the mean free path `lambda = <v> / omega = 1 / (2 sqrt(2) n sigma g)`.
//! For spheres (`--dim 3`) `omega = 4 n sigma^2 g sqrt(pi kT / m)` and
//! `lambda = 1 / (sqrt(2) pi n sigma^2 g)`, with the contact value from Pieprzyk et al.'s
//! equation of state, `g = (Z - 1) / (4 eta)`.

use anyhow::Result;
use clap::Args;
use edmd_core::measure::{theory, Collisions};
use edmd_core::Boundary;
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_packings, files_line, interrupted_after, melted_fluid_in, out_dir, outputs, report,
    stop_requested, write_csv, CommonArgs, Progress,
};

/// Options of `edmd experiment mfp`.
#[derive(Debug, Args)]
pub struct MfpArgs {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[arg(long, default_value_t = 2, value_parser = crate::args::parse_dim)]
    pub dim: usize,
    /// Packing fractions, comma-separated; histograms are drawn for the first (spheres: at
    /// most 0.50).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.05,0.1,0.2,0.3,0.4,0.5",
        allow_negative_numbers = true
    )]
    pub packing: Vec<f64>,
    /// Number of discs.
    #[arg(long, default_value_t = 1000, allow_negative_numbers = true)]
    pub n: usize,
    /// Disc-disc collisions per disc to measure over (the old spelling `--measure` still works).
    /// Flights still in progress at the end are not counted, which biases the mean free path
    /// low by about 1/COLLISIONS: 50 read 1-2.5% low, 500 reads within 0.5% of Enskog.
    #[arg(
        long = "collisions",
        alias = "measure",
        default_value_t = 500,
        allow_negative_numbers = true
    )]
    pub measure: u64,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Enskog's mean free path for discs of diameter 1 at packing fraction `eta`.
pub fn enskog_mean_free_path(eta: f64) -> f64 {
    theory::enskog_mean_free_path(eta, 1.0)
}

/// Enskog's mean free path for particles of diameter 1 in `dim` dimensions.
fn enskog_lambda(eta: f64, dim: usize) -> f64 {
    theory::enskog_mean_free_path_in(eta, 1.0, dim)
}

/// One packing fraction.
#[derive(Debug, Serialize)]
pub struct Point {
    /// Packing fraction.
    pub packing: f64,
    /// Number density (discs per unit area, diameter 1).
    pub density: f64,
    /// Measured mean free path (diameters).
    pub mean_free_path: f64,
    /// Enskog's value.
    pub enskog_mean_free_path: f64,
    /// Measured mean free time.
    pub mean_free_time: f64,
    /// Collision frequency per disc, measured and Enskog's.
    pub collision_frequency: [f64; 2],
    /// Relative kinetic energy change over the run.
    pub relative_energy_change: f64,
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
    /// One entry per packing fraction.
    pub results: Vec<Point>,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

/// Runs the experiment.
pub fn run(args: &MfpArgs) -> Result<()> {
    match args.dim {
        3 => run_in::<3>(args),
        _ => run_in::<2>(args),
    }
}

fn run_in<const D: usize>(args: &MfpArgs) -> Result<()> {
    check_packings(
        "mfp",
        &args.packing,
        if D == 3 { 0.500_000_1 } else { 0.70 },
    )?;
    super::common::check_fluid_n::<D>("mfp", args.n)?;
    super::common::check_count("mfp", "collisions", args.measure, 1, 100_000)?;
    let dir = out_dir(
        &args.common,
        &outputs(
            &["mfp", "mfp_free_path", "mfp_free_time"],
            &["mfp", "mfp_free_path", "mfp_free_time"],
        ),
    )?;
    let progress = Progress::new(args.packing.len() as u64, "mfp");
    let mut results = Vec::new();
    let mut files = Vec::new();
    for (k, &eta) in args.packing.iter().enumerate() {
        if stop_requested() {
            break;
        }
        let Some((mut sim, rate)) = melted_fluid_in::<D>(
            args.n,
            eta,
            Boundary::Periodic,
            args.common.seed + k as u64,
            20,
        )?
        else {
            break;
        };
        let lambda = enskog_lambda(eta, D);
        let e0 = sim.kinetic_energy();
        let mut obs = Collisions::new(&sim, 60, 5.0 * lambda, 5.0 * lambda / 1.25);
        let t_end = sim.time() + args.measure as f64 / rate;
        let blocks = 10;
        let mut stopped = false;
        for b in 1..=blocks {
            let t = sim.time() + (t_end - sim.time()) / (blocks - b + 1) as f64;
            if !edmd::run_until_or_stop(&mut sim, t, &mut obs)? {
                stopped = true;
                break;
            }
            obs.sample(&sim);
        }
        if stopped {
            break;
        }
        let s = obs.summary();
        let density = theory::number_density_in(eta, 1.0, D);
        let omega = theory::enskog_collision_frequency_in(eta, 1.0, 1.0, 1.0, D);
        if k == 0 {
            for (name, h, unit) in [
                ("path", obs.free_path_histogram(), "diameters"),
                ("time", obs.free_time_histogram(), "time units"),
            ] {
                let rows: Vec<(f64, f64)> = h.density();
                let csv = dir.join(format!("mfp_free_{name}.csv"));
                write_csv(
                    &csv,
                    &[&format!("free_{name}"), "density"],
                    rows.iter().map(|&(x, y)| vec![x, y]),
                )?;
                let mean = if name == "path" {
                    s.mean_free_path
                } else {
                    s.mean_free_time
                };
                let (png, svg) = Figure::new(
                    &format!("Free {name}s at packing {eta} (mean {mean:.4})"),
                    &format!("free {name} ({unit})"),
                    "probability density",
                )
                .with(Series::bars(&format!("{} free {name}s", s.flights), rows))
                .save(&dir.join(format!("mfp_free_{name}")))?;
                files.extend([csv, png, svg]);
            }
        }
        results.push(Point {
            packing: eta,
            density,
            mean_free_path: s.mean_free_path,
            enskog_mean_free_path: lambda,
            mean_free_time: s.mean_free_time,
            collision_frequency: [s.frequency.value, omega],
            relative_energy_change: (sim.kinetic_energy() - e0) / e0,
        });
        progress.set(k as u64 + 1);
    }
    progress.finish();
    let interrupted = results.len() < args.packing.len();
    let csv = dir.join("mfp.csv");
    write_csv(
        &csv,
        &[
            "packing",
            "density",
            "mean_free_path",
            "enskog_mean_free_path",
            "mean_free_time",
            "collision_frequency",
            "enskog_collision_frequency",
        ],
        results.iter().map(|p| {
            vec![
                p.packing,
                p.density,
                p.mean_free_path,
                p.enskog_mean_free_path,
                p.mean_free_time,
                p.collision_frequency[0],
                p.collision_frequency[1],
            ]
        }),
    )?;
    let top = args.packing.iter().cloned().fold(0.0, f64::max);
    let curve: Vec<(f64, f64)> = (1..=200)
        .map(|i| top * i as f64 / 200.0)
        .map(|e| (theory::number_density_in(e, 1.0, D), enskog_lambda(e, D)))
        .collect();
    let (what, per, formula) = if D == 3 {
        (
            "spheres",
            "diameter^3",
            "Enskog 1 / (sqrt(2) pi n sigma^2 g(sigma))",
        )
    } else {
        (
            "discs",
            "diameter^2",
            "Enskog 1 / (2 sqrt(2) n sigma g(sigma))",
        )
    };
    let (png, svg) = Figure::new(
        &format!("Mean free path ({} {what}, periodic)", args.n),
        &format!("number density n ({what} per {per})"),
        "mean free path (diameters)",
    )
    .with_log_y()
    .with(Series::line(formula, curve))
    .with(Series::points(
        "edmd",
        results
            .iter()
            .map(|p| (p.density, p.mean_free_path))
            .collect(),
    ))
    .save(&dir.join("mfp"))?;
    files.extend([csv, png, svg]);
    let mut human = format!(
        "mean free path, {} {what}, periodic box:\n  packing  measured  Enskog   deviation\n",
        args.n
    );
    for p in &results {
        human += &format!(
            "  {:7.3}  {:8.4}  {:8.4}  {:+.1}%\n",
            p.packing,
            p.mean_free_path,
            p.enskog_mean_free_path,
            100.0 * (p.mean_free_path / p.enskog_mean_free_path - 1.0)
        );
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    human += &files_line(&files);
    report(
        &args.common,
        &Summary {
            experiment: "mfp",
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
