//! `edmd pack`: Lubachevsky-Stillinger compression to a jammed packing (or to a packing
//! fraction below jamming), from a random start or a file. The engine is
//! `edmd_core::pack`; this command validates the options, shows the progress, writes the
//! packing in the Princeton format (readable by `edmd run`) and a summary.

use std::io::IsTerminal;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use clap::Args;
use edmd_core::pack::{
    contacts, gap_tolerance, random_start, PackOptions, PackSizes, Packer, Packing, Status,
};
use edmd_core::setup::thermal_velocities;
use edmd_core::{Boundary, Disc, SimBox, Vector};
use edmd_io::princeton::ColumnOrder;
use edmd_io::Format;
use rand::SeedableRng;
use serde::Serialize;

use crate::args::BoundaryArg;
use crate::commands::experiment::common::MAX_N;
use crate::input::{load_any, read_text};
use crate::output::{check_distinct, AtomicFile};
use crate::user_error;

/// Options of `edmd pack`.
#[derive(Debug, Args)]
pub struct PackArgs {
    /// Start from this file (Princeton or course format) instead of a random start: its radii
    /// are the initial sizes, which all grow by one factor.
    pub file: Option<String>,
    /// Write the packing here (Princeton format; `-` for standard output).
    #[arg(long, short, value_name = "FILE")]
    pub output: String,
    /// Dimension of a random start: 2 (discs) or 3 (spheres).
    #[arg(long, value_parser = crate::args::parse_dim)]
    pub dim: Option<usize>,
    /// Number of particles of a random start.
    #[arg(long, value_parser = crate::args::parse_count, allow_negative_numbers = true)]
    pub n: Option<usize>,
    /// Bidisperse: diameter ratio large/small (default 1, monodisperse).
    #[arg(long, value_parser = crate::args::parse_positive, allow_negative_numbers = true)]
    pub size_ratio: Option<f64>,
    /// Bidisperse: number fraction of large particles (default 0.5 with --size-ratio).
    #[arg(long, allow_negative_numbers = true)]
    pub fraction_large: Option<f64>,
    /// Polydisperse: diameters uniform with this relative standard deviation (mean 1).
    #[arg(long, value_parser = crate::args::parse_positive, allow_negative_numbers = true)]
    pub polydispersity: Option<f64>,
    /// Growth rate G: the largest diameter grows as dD/dt = G v_rms (v_rms = 1).
    #[arg(long, default_value_t = 0.02, value_parser = crate::args::parse_positive, allow_negative_numbers = true)]
    pub growth_rate: f64,
    /// Stop when the reduced pressure PV/(NkT) passes this.
    #[arg(long, default_value_t = 1e12, value_parser = crate::args::parse_positive, allow_negative_numbers = true)]
    pub pressure: f64,
    /// Stop at this packing fraction (below jamming: dense fluids and glasses).
    #[arg(long, value_parser = crate::args::parse_positive, allow_negative_numbers = true)]
    pub packing: Option<f64>,
    /// Boundaries of a random start.
    #[arg(long, value_enum)]
    pub boundary: Option<BoundaryArg>,
    /// Random seed: the same seed gives the same packing, bit for bit.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// Print the summary as one JSON object on standard output.
    #[arg(long)]
    pub json: bool,
}

/// The summary `--json` prints.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// 2 or 3.
    pub dim: usize,
    /// Particles.
    pub n: usize,
    /// G.
    pub growth_rate: f64,
    /// The seed.
    pub seed: u64,
    /// Packing fraction at the end.
    pub packing_fraction: f64,
    /// Reduced pressure of the last interval (null if none was measured).
    pub reduced_pressure: Option<f64>,
    /// Why it stopped: pressure, converged, packing.
    pub stop: &'static str,
    /// Rattlers (fewer than dim + 1 contacts, removed iteratively).
    pub rattlers: usize,
    /// Contacts per non-rattler (null if every particle rattles).
    pub mean_contacts: Option<f64>,
    /// Relative gap below which a pair touches.
    pub gap_tolerance: f64,
    /// Smallest relative gap (negative: an overlap, by rounding).
    pub min_gap: f64,
    /// Pair collisions.
    pub collisions: u64,
    /// Wall collisions.
    pub wall_collisions: u64,
    /// Velocity rescalings.
    pub rescales: u64,
    /// Wall-clock seconds of the compression.
    pub wall_seconds: f64,
    /// Pair collisions per wall-clock second.
    pub collisions_per_second: f64,
    /// The output file.
    pub output: String,
}

/// A start to compress: the particles and the box, in either dimension.
pub enum Start {
    /// Discs.
    Two(Vec<Disc<2>>, SimBox<2>),
    /// Spheres.
    Three(Vec<Disc<3>>, SimBox<3>),
}

/// A start given rather than drawn at random (a file for the command, a simulation for the
/// Python package).
pub struct Given<'a> {
    /// Its name in messages (`glass.txt:`).
    pub name: &'a str,
    /// What sets the random start's options in messages (`the file glass.txt`).
    pub what: &'a str,
    /// Its particles and box.
    pub start: Start,
    /// Whether it has barriers (pack refuses them).
    pub barriers: bool,
}

/// A compressed packing and its summary (`output` left empty).
pub enum Packed {
    /// Discs.
    Two(Packing<2>, Summary),
    /// Spheres.
    Three(Packing<3>, Summary),
}

impl Packed {
    /// The summary.
    pub fn summary(&self) -> &Summary {
        match self {
            Packed::Two(_, s) | Packed::Three(_, s) => s,
        }
    }
}

/// Runs `edmd pack`.
pub fn run(args: &PackArgs) -> Result<()> {
    check_distinct(
        &args
            .file
            .as_deref()
            .map(|f| vec![("the input file", Path::new(f))])
            .unwrap_or_default(),
        &[("-o", Path::new(&args.output))],
    )?;
    if args.json && args.output == "-" {
        return user_error(
            "pack: --json and -o - would both write to standard output; write the packing to a file",
        );
    }
    // The options are checked before the file is read.
    options(args)?;
    let what = args.file.as_ref().map(|f| format!("the file {f}"));
    let given = match &args.file {
        Some(path) => {
            refuse_random_options(args, what.as_deref().unwrap_or_default())?;
            let text = read_text(path)?;
            let (start, barriers) = match load_any(path, &text, None, ColumnOrder::RadiusMass)? {
                edmd_io::AnyLoaded::Two(sys) => {
                    (Start::Two(sys.discs, sys.sim_box), !sys.barriers.is_empty())
                }
                edmd_io::AnyLoaded::Three(sys) => (
                    Start::Three(sys.discs, sys.sim_box),
                    !sys.barriers.is_empty(),
                ),
            };
            Some((path.as_str(), start, barriers))
        }
        None => None,
    };
    let given = given.map(|(name, start, barriers)| Given {
        name,
        what: what.as_deref().unwrap_or_default(),
        start,
        barriers,
    });
    let bar = progress_bar();
    let packed = pack(args, given, |s: &Status| {
        if let Some(pb) = &bar {
            pb.set_message(format!(
                "packing fraction {:.6}  reduced pressure {:.3e}  {} collisions",
                s.packing_fraction,
                s.reduced_pressure.unwrap_or(f64::NAN),
                s.collisions
            ));
            pb.tick();
        }
        true
    });
    if let Some(pb) = &bar {
        pb.finish_and_clear();
    }
    match packed? {
        Packed::Two(packing, summary) => report(args, &packing, summary),
        Packed::Three(packing, summary) => report(args, &packing, summary),
    }
}

/// Checks the options, makes the start (the random one of `args`, or `given`) and compresses
/// it, calling `progress` at every rescaling (`false` stops the compression). What `edmd pack`
/// writes and what `edmd.pack` returns in Python, so the two agree bit for bit.
pub fn pack(
    args: &PackArgs,
    given: Option<Given<'_>>,
    progress: impl FnMut(&Status) -> bool,
) -> Result<Packed> {
    let options = options(args)?;
    match given {
        Some(given) => {
            refuse_random_options(args, given.what)?;
            if given.barriers {
                return user_error(format!("{}: pack does not take barriers", given.name));
            }
            match given.start {
                Start::Two(discs, sim_box) => {
                    let discs = at_speed(args, given.name, discs)?;
                    let (p, s) = compress(args, discs, sim_box, options, progress)?;
                    Ok(Packed::Two(p, s))
                }
                Start::Three(discs, sim_box) => {
                    let discs = at_speed(args, given.name, discs)?;
                    let (p, s) = compress(args, discs, sim_box, options, progress)?;
                    Ok(Packed::Three(p, s))
                }
            }
        }
        None => {
            let Some(n) = args.n else {
                return user_error(
                    "pack: give --n (the number of particles) or a FILE to start from",
                );
            };
            if !(2..=MAX_N).contains(&n) {
                return user_error(format!("pack: --n must be from 2 to {MAX_N}, found {n}"));
            }
            let sizes = sizes(args)?;
            let boundary = match args.boundary {
                None | Some(BoundaryArg::Periodic) => Boundary::Periodic,
                Some(BoundaryArg::Walls) => Boundary::Walls,
            };
            match args.dim.unwrap_or(2) {
                3 => {
                    let (discs, sim_box) = random_start::<3>(n, sizes, boundary, args.seed)
                        .or_else(|e| user_error(e.to_string()))?;
                    let (p, s) = compress(args, discs, sim_box, options, progress)?;
                    Ok(Packed::Three(p, s))
                }
                _ => {
                    let (discs, sim_box) = random_start::<2>(n, sizes, boundary, args.seed)
                        .or_else(|e| user_error(e.to_string()))?;
                    let (p, s) = compress(args, discs, sim_box, options, progress)?;
                    Ok(Packed::Two(p, s))
                }
            }
        }
    }
}

/// Refuses the options of a random start when a start is given (`what` names it).
fn refuse_random_options(args: &PackArgs, what: &str) -> Result<()> {
    for (flag, set) in [
        ("dim", args.dim.is_some()),
        ("n", args.n.is_some()),
        ("size-ratio", args.size_ratio.is_some()),
        ("fraction-large", args.fraction_large.is_some()),
        ("polydispersity", args.polydispersity.is_some()),
        ("boundary", args.boundary.is_some()),
    ] {
        if set {
            return user_error(format!(
                "pack: --{flag} is for a random start; {what} sets it"
            ));
        }
    }
    Ok(())
}

fn options(args: &PackArgs) -> Result<PackOptions> {
    let options = PackOptions {
        growth_rate: args.growth_rate,
        max_pressure: args.pressure,
        target_packing: args.packing,
        ..PackOptions::default()
    };
    options
        .validate()
        .or_else(|e| user_error(format!("{e} (--growth-rate, --pressure, --packing)")))?;
    Ok(options)
}

fn sizes(args: &PackArgs) -> Result<PackSizes> {
    let sizes = match (args.polydispersity, args.size_ratio, args.fraction_large) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            return user_error(
                "pack: --polydispersity and --size-ratio/--fraction-large exclude each other",
            )
        }
        (Some(std), None, None) => PackSizes::Polydisperse { std },
        (None, None, None) => PackSizes::MONODISPERSE,
        (None, None, Some(_)) => return user_error("pack: --fraction-large needs --size-ratio"),
        (None, Some(size_ratio), fraction_large) => PackSizes::Binary {
            size_ratio,
            fraction_large: fraction_large.unwrap_or(0.5),
        },
    };
    sizes.validate().or_else(|e| user_error(e.to_string()))?;
    Ok(sizes)
}

/// A given start's particles, with thermal velocities from the seed if all are at rest.
fn at_speed<const D: usize>(
    args: &PackArgs,
    name: &str,
    mut discs: Vec<Disc<D>>,
) -> Result<Vec<Disc<D>>> {
    if discs.len() < 2 {
        return user_error(format!("{name}: pack needs at least 2 particles"));
    }
    if discs.iter().all(|d| d.vel == Vector::ZERO) {
        // Particles at rest: thermal velocities from the seed.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(args.seed);
        thermal_velocities(&mut discs, 1.0, &mut rng);
    }
    Ok(discs)
}

/// Compresses and analyses.
fn compress<const D: usize>(
    args: &PackArgs,
    discs: Vec<Disc<D>>,
    sim_box: SimBox<D>,
    options: PackOptions,
    progress: impl FnMut(&Status) -> bool,
) -> Result<(Packing<D>, Summary)> {
    let n = discs.len();
    let packer = Packer::new(&discs, sim_box, options).or_else(|e| user_error(e.to_string()))?;
    let start = Instant::now();
    let packing: Packing<D> = packer
        .run(progress)
        .or_else(|e| user_error(e.to_string()))?;
    let wall_seconds = start.elapsed().as_secs_f64();
    let tol = gap_tolerance(packing.reduced_pressure.unwrap_or(1.0), D);
    let c = contacts(&packing.discs, &packing.sim_box, tol);
    let summary = Summary {
        dim: D,
        n,
        growth_rate: args.growth_rate,
        seed: args.seed,
        packing_fraction: packing.packing_fraction,
        reduced_pressure: packing.reduced_pressure,
        stop: packing.stop.name(),
        rattlers: c.rattlers,
        mean_contacts: c.mean_contacts.is_finite().then_some(c.mean_contacts),
        gap_tolerance: tol,
        min_gap: c.min_gap,
        collisions: packing.collisions,
        wall_collisions: packing.wall_collisions,
        rescales: packing.rescales,
        wall_seconds,
        collisions_per_second: packing.collisions as f64 / wall_seconds.max(1e-9),
        output: String::new(),
    };
    Ok((packing, summary))
}

/// Writes the packing and prints the summary.
fn report<const D: usize>(
    args: &PackArgs,
    packing: &Packing<D>,
    mut summary: Summary,
) -> Result<()> {
    write(args, packing)?;
    summary.output = args.output.clone();
    if args.json {
        crate::print_line(&serde_json::to_string(&summary)?);
    } else {
        eprintln!(
            "edmd pack: {} {} at packing fraction {:.6}, reduced pressure {:.3e} (stopped on {}), {} rattlers, {:.3} contacts per non-rattler (gap tolerance {:.1e}), {} collisions in {:.2} s; written to {}",
            summary.n,
            if D == 3 { "spheres" } else { "discs" },
            summary.packing_fraction,
            summary.reduced_pressure.unwrap_or(f64::NAN),
            summary.stop,
            summary.rattlers,
            summary.mean_contacts.unwrap_or(f64::NAN),
            summary.gap_tolerance,
            summary.collisions,
            summary.wall_seconds,
            args.output
        );
    }
    Ok(())
}

/// A spinner with the packing fraction and pressure, on standard error when it is a terminal.
fn progress_bar() -> Option<indicatif::ProgressBar> {
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let pb = indicatif::ProgressBar::new_spinner();
    if let Ok(style) = indicatif::ProgressStyle::with_template("pack {spinner} {msg} {elapsed}") {
        pb.set_style(style);
    }
    Some(pb)
}

fn write<const D: usize>(args: &PackArgs, packing: &Packing<D>) -> Result<()> {
    let format = Format::Princeton(ColumnOrder::RadiusMass);
    if args.output == "-" {
        let mut out = std::io::stdout().lock();
        edmd_io::write(&mut out, &packing.discs, &packing.sim_box, &[], format, 0.0)?;
        std::io::Write::flush(&mut out)?;
    } else {
        let mut f = AtomicFile::create(Path::new(&args.output))?;
        edmd_io::write(
            f.writer(),
            &packing.discs,
            &packing.sim_box,
            &[],
            format,
            0.0,
        )?;
        f.commit()?;
    }
    Ok(())
}
