//! `edmd experiment eos`: the hard-disc equation of state.
//!
//! For each packing fraction eta: N discs in a periodic box, melted from a lattice, then the
//! compressibility factor `Z = P A / (N kT)` from the collision virial
//! (`Z = 1 + sum r_ij . J_ij / (2 t N kT)`, Alder & Wainwright 1960) with an error bar from
//! block averages, drawn against Henderson's equation of state
//! `Z = (1 + eta^2 / 8) / (1 - eta)^2` (Mol. Phys. 30, 971 (1975)).

use anyhow::Result;
use clap::Args;
use edmd_core::measure::Pressure;
use edmd_core::Boundary;
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_n, check_packings, files_line, melted_fluid, out_dir, report, stop_requested, write_csv,
    CommonArgs, Progress,
};

/// Options of `edmd experiment eos`.
#[derive(Debug, Args)]
pub struct EosArgs {
    /// Packing fractions, comma-separated (fluid: below 0.70).
    #[arg(long, value_delimiter = ',', default_values_t = vec![0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.65], allow_negative_numbers = true)]
    pub packing: Vec<f64>,
    /// Number of discs.
    #[arg(long, default_value_t = 1000, allow_negative_numbers = true)]
    pub n: usize,
    /// Disc-disc collisions per disc to melt before measuring.
    #[arg(long, default_value_t = 50, allow_negative_numbers = true)]
    pub melt: u64,
    /// Disc-disc collisions per disc to measure over (the old spelling `--measure` still works).
    #[arg(
        long = "collisions",
        alias = "measure",
        default_value_t = 200,
        allow_negative_numbers = true
    )]
    pub measure: u64,
    /// Blocks for the error bar.
    #[arg(long, default_value_t = 20, allow_negative_numbers = true)]
    pub blocks: usize,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

use edmd_core::measure::theory::henderson_z as henderson;

/// One packing fraction.
#[derive(Debug, Serialize)]
pub struct Point {
    /// Packing fraction.
    pub packing: f64,
    /// Compressibility factor.
    #[serde(rename = "Z")]
    pub z: f64,
    /// Its statistical error (one standard deviation).
    #[serde(rename = "Z_err")]
    pub z_err: f64,
    /// Henderson's value.
    pub henderson: f64,
    /// Disc-disc collisions measured over.
    pub collisions: u64,
    /// Relative kinetic energy change over the run.
    pub relative_energy_change: f64,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Discs.
    pub n: usize,
    /// One entry per packing fraction.
    pub results: Vec<Point>,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

/// Runs the experiment.
pub fn run(args: &EosArgs) -> Result<()> {
    check_packings("eos", &args.packing, 0.70)?;
    check_n("eos", args.n, 16)?;
    super::common::check_count("eos", "collisions", args.measure, 1, 100_000)?;
    super::common::check_count("eos", "melt", args.melt, 0, 100_000)?;
    super::common::check_count("eos", "blocks", args.blocks as u64, 2, 10_000)?;
    if args.blocks < 2 || args.measure == 0 {
        return crate::user_error("eos: --blocks must be >= 2 and --collisions >= 1");
    }
    let dir = out_dir(&args.common)?;
    let progress = Progress::new((args.packing.len() * args.blocks) as u64, "eos");
    let mut results = Vec::new();
    'packings: for (k, &eta) in args.packing.iter().enumerate() {
        let (mut sim, rate) = melted_fluid(
            args.n,
            eta,
            Boundary::Periodic,
            args.common.seed + k as u64,
            args.melt,
        )?;
        let block = args.measure as f64 / args.blocks as f64 / rate;
        let mut pressure = Pressure::new(&sim);
        let c0 = sim.stats().disc_disc;
        let e0 = sim.kinetic_energy();
        for b in 0..args.blocks {
            if stop_requested() {
                break 'packings;
            }
            let t = sim.time() + block;
            sim.run_until(t, &mut pressure);
            pressure.sample(&sim);
            progress.set((k * args.blocks + b + 1) as u64);
        }
        let z = pressure.summary().z;
        results.push(Point {
            packing: eta,
            z: z.value,
            z_err: z.error,
            henderson: henderson(eta),
            collisions: sim.stats().disc_disc - c0,
            relative_energy_change: (sim.kinetic_energy() - e0) / e0,
        });
    }
    progress.finish();
    let interrupted = results.len() < args.packing.len();
    let csv = dir.join("eos.csv");
    write_csv(
        &csv,
        &["packing", "Z", "Z_err", "henderson"],
        results
            .iter()
            .map(|p| vec![p.packing, p.z, p.z_err, p.henderson]),
    )?;
    let top = args.packing.iter().cloned().fold(0.0, f64::max);
    // Enough points that the steep end of the curve does not show as steps.
    let curve: Vec<(f64, f64)> = (0..=1000)
        .map(|i| top * i as f64 / 1000.0)
        .map(|e| (e, henderson(e)))
        .collect();
    let (png, svg) = Figure::new(
        &format!("Hard-disc equation of state ({} discs, periodic)", args.n),
        "packing fraction eta",
        "compressibility factor Z = PA / (N kT)",
    )
    .with(Series::line("Henderson (1 + eta^2/8) / (1 - eta)^2", curve))
    .with(Series::error_bars(
        "edmd, collision virial",
        results.iter().map(|p| (p.packing, p.z)).collect(),
        results.iter().map(|p| p.z_err).collect(),
    ))
    .save(&dir.join("eos"))?;
    let mut human = format!("equation of state, {} discs, periodic box:\n  packing        Z     error  Henderson  deviation\n", args.n);
    for p in &results {
        human += &format!(
            "  {:7.3}  {:8.4}  {:8.4}  {:9.4}  {:+.2}%\n",
            p.packing,
            p.z,
            p.z_err,
            p.henderson,
            100.0 * (p.z / p.henderson - 1.0)
        );
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    human += &files_line(&[csv, png, svg]);
    report(
        &args.common,
        &Summary {
            experiment: "eos",
            n: args.n,
            results,
            interrupted,
        },
        &human,
    )
}
