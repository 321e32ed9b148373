//! `edmd experiment eos`: the hard-disc (or, with `--dim 3`, hard-sphere, with `--dim 1`
//! hard-rod) equation of state.
//!
//! For each packing fraction eta: N discs in a periodic box, melted from a lattice, then the
//! compressibility factor `Z = P A / (N kT)` from the collision virial
//! (`Z = 1 + sum r_ij . J_ij / (D t N kT)`, Alder & Wainwright 1960) with an error bar from
//! block averages, drawn against Henderson's equation of state
//! `Z = (1 + eta^2 / 8) / (1 - eta)^2` (Mol. Phys. 30, 971 (1975)) for discs, or Pieprzyk et
//! al.'s (Phys. Chem. Chem. Phys. 21, 6886 (2019)) for spheres, or Tonks's exact
//! `Z = 1 / (1 - eta)` (Phys. Rev. 50, 955 (1936)) for rods on a line. Each row also gives the
//! measured collision rate per particle and the rate the measured Z implies through the exact
//! relation `Gamma = 2 D (Z - 1) sqrt(kT / (pi m)) / sigma`.

use anyhow::Result;
use clap::Args;
use edmd_core::measure::{Collisions, Pressure};
use edmd_core::Boundary;
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_packings, files_line, interrupted_after, melted_fluid_in, out_dir, outputs, report,
    stop_requested, write_csv, CommonArgs, Progress,
};

/// Options of `edmd experiment eos`.
#[derive(Debug, Args)]
pub struct EosArgs {
    /// Dimension: 2 (discs), 3 (spheres) or 1 (rods on a line).
    #[arg(long, default_value_t = 2, value_parser = crate::args::parse_dim_with_rods)]
    pub dim: usize,
    /// Packing fractions, comma-separated (fluid: below 0.70 for discs, at most 0.50 for
    /// spheres, below 1 for rods) [default: 0.05,0.1,0.2,0.3,0.4,0.5,0.6,0.65; spheres
    /// 0.05,0.1,0.2,0.3,0.4,0.45,0.5; rods 0.1,0.2,...,0.9].
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub packing: Option<Vec<f64>>,
    /// Number of discs (spheres).
    #[arg(long, default_value_t = 1000, allow_negative_numbers = true)]
    pub n: usize,
    /// Disc-disc collisions per disc to melt before measuring.
    #[arg(long, default_value_t = 50, allow_negative_numbers = true)]
    pub melt: u64,
    /// Disc-disc collisions per disc to measure over (the old spelling `--measure` still works).
    #[arg(
        long = "collisions",
        alias = "measure",
        value_name = "COLLISIONS",
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

use edmd_core::measure::theory::{
    collision_rate_from_z, henderson_z as henderson, pieprzyk_z, tonks_z,
};

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
    /// Henderson's value (discs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub henderson: Option<f64>,
    /// Pieprzyk et al.'s value (spheres).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pieprzyk: Option<f64>,
    /// Tonks's exact value (rods).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tonks: Option<f64>,
    /// Collision rate per particle: measured, and implied by the measured Z.
    pub collision_rate: [f64; 2],
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
pub fn run(args: &EosArgs) -> Result<()> {
    match args.dim {
        3 => run_in::<3>(args),
        1 => run_in::<1>(args),
        _ => run_in::<2>(args),
    }
}

/// The reference equation of state of dimension `D`.
fn reference<const D: usize>(eta: f64) -> f64 {
    if D == 1 {
        tonks_z(eta)
    } else if D == 3 {
        pieprzyk_z(eta)
    } else {
        henderson(eta)
    }
}

fn run_in<const D: usize>(args: &EosArgs) -> Result<()> {
    let packings = args.packing.clone().unwrap_or_else(|| {
        if D == 1 {
            vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]
        } else if D == 3 {
            vec![0.05, 0.1, 0.2, 0.3, 0.4, 0.45, 0.5]
        } else {
            vec![0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.65]
        }
    });
    let args_packing = &packings;
    if D == 1 {
        // Rods are a fluid at any packing below 1 (no freezing in one dimension).
        check_packings("eos", args_packing, 1.0)?;
    } else if D == 3 {
        // Spheres are fluid up to 0.50 (inclusive: the generator makes 0.50).
        check_packings("eos", args_packing, 0.500_000_1)?;
    } else {
        check_packings("eos", args_packing, 0.70)?;
    }
    super::common::check_fluid_n::<D>("eos", args.n)?;
    super::common::check_count("eos", "collisions", args.measure, 1, 100_000)?;
    super::common::check_count("eos", "melt", args.melt, 0, 100_000)?;
    super::common::check_count("eos", "blocks", args.blocks as u64, 2, 10_000)?;
    if args.blocks < 2 || args.measure == 0 {
        return edmd::user_error("eos: --blocks must be >= 2 and --collisions >= 1");
    }
    let dir = out_dir(&args.common, &outputs(&["eos"], &["eos"]))?;
    let progress = Progress::new((args_packing.len() * args.blocks) as u64, "eos");
    let mut results = Vec::new();
    'packings: for (k, &eta) in args_packing.iter().enumerate() {
        let Some((mut sim, rate)) = melted_fluid_in::<D>(
            args.n,
            eta,
            Boundary::Periodic,
            args.common.seed + k as u64,
            args.melt,
        )?
        else {
            break 'packings;
        };
        let block = args.measure as f64 / args.blocks as f64 / rate;
        let mut pressure = Pressure::new(&sim);
        let mut collisions = Collisions::new(&sim, 10, 1.0, 1.0);
        let c0 = sim.stats().disc_disc;
        let e0 = sim.kinetic_energy();
        for b in 0..args.blocks {
            if stop_requested() {
                break 'packings;
            }
            let t = sim.time() + block;
            // A block can hold billions of collisions (large --n and --collisions).
            if !edmd::run_until_or_stop(&mut sim, t, &mut (&mut pressure, &mut collisions))? {
                break 'packings;
            }
            pressure.sample(&sim);
            collisions.sample(&sim);
            progress.set((k * args.blocks + b + 1) as u64);
        }
        let p = pressure.summary();
        let z = p.z;
        results.push(Point {
            packing: eta,
            z: z.value,
            z_err: z.error,
            henderson: (D == 2).then(|| henderson(eta)),
            pieprzyk: (D == 3).then(|| pieprzyk_z(eta)),
            tonks: (D == 1).then(|| tonks_z(eta)),
            collision_rate: [
                collisions.summary().frequency.value,
                collision_rate_from_z(z.value, D, 1.0, p.kt, 1.0),
            ],
            collisions: sim.stats().disc_disc - c0,
            relative_energy_change: (sim.kinetic_energy() - e0) / e0,
        });
    }
    progress.finish();
    let interrupted = results.len() < args_packing.len();
    let (law, law_name, what) = if D == 1 {
        ("tonks", "Tonks 1 / (1 - eta), exact", "rods")
    } else if D == 3 {
        ("pieprzyk", "Pieprzyk et al. 2019", "spheres")
    } else {
        (
            "henderson",
            "Henderson (1 + eta^2/8) / (1 - eta)^2",
            "discs",
        )
    };
    let csv = dir.join("eos.csv");
    write_csv(
        &csv,
        &[
            "packing",
            "Z",
            "Z_err",
            law,
            "collision_rate",
            "collision_rate_from_Z",
        ],
        results.iter().map(|p| {
            vec![
                p.packing,
                p.z,
                p.z_err,
                reference::<D>(p.packing),
                p.collision_rate[0],
                p.collision_rate[1],
            ]
        }),
    )?;
    let top = args_packing.iter().cloned().fold(0.0, f64::max);
    // Enough points that the steep end of the curve does not show as steps.
    let curve: Vec<(f64, f64)> = (0..=1000)
        .map(|i| top * i as f64 / 1000.0)
        .map(|e| (e, reference::<D>(e)))
        .collect();
    let (png, svg) = Figure::new(
        &format!(
            "Hard-{} equation of state ({} {what}, periodic)",
            &what[..what.len() - 1],
            args.n
        ),
        "packing fraction eta",
        if D == 1 {
            "compressibility factor Z = PL / (N kT)"
        } else {
            "compressibility factor Z = PV / (N kT)"
        },
    )
    .with(Series::line(law_name, curve))
    .with(Series::error_bars(
        "edmd, collision virial",
        results.iter().map(|p| (p.packing, p.z)).collect(),
        results.iter().map(|p| p.z_err).collect(),
    ))
    .save(&dir.join("eos"))?;
    let mut human = format!(
        "equation of state, {} {what}, periodic box:\n  packing        Z     error  {:>9}  deviation  collision rate (from Z)\n",
        args.n,
        match D {
            1 => "Tonks",
            3 => "Pieprzyk",
            _ => "Henderson",
        }
    );
    for p in &results {
        let r = reference::<D>(p.packing);
        human += &format!(
            "  {:7.3}  {:8.4}  {:8.4}  {:9.4}  {:+8.2}%  {:.4} ({:.4})\n",
            p.packing,
            p.z,
            p.z_err,
            r,
            100.0 * (p.z / r - 1.0),
            p.collision_rate[0],
            p.collision_rate[1]
        );
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    let files = [csv, png, svg];
    human += &files_line(&files);
    report(
        &args.common,
        &Summary {
            experiment: "eos",
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
