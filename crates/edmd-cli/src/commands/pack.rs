//! `edmd pack`: Lubachevsky-Stillinger compression to a jammed packing (or to a packing
//! fraction below jamming), from a random start or a file, or continued from a checkpoint.
//! The engine is `edmd_core::pack`; this command validates the options, shows the progress,
//! writes checkpoints (`--checkpoint`, every `--checkpoint-every` seconds and on Ctrl-C),
//! writes the packing in the Princeton format (readable by `edmd run`) and a summary.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::Result;
use clap::Args;
use edmd_core::pack::{
    contacts, gap_tolerance, random_start, PackOptions, PackSizes, Packer, Packing, Status, Stop,
};
use edmd_core::setup::thermal_velocities;
use edmd_core::{Boundary, Disc, Error as EngineError, SimBox, Vector};
use edmd_io::princeton::ColumnOrder;
use edmd_io::Format;
use rand::SeedableRng;
use serde::{Deserialize, Serialize};

use crate::args::BoundaryArg;
use crate::commands::experiment::common::MAX_N;
use crate::commands::run::{read_file_starting, read_magic, write_checkpoint};
use crate::input::{load_any, read_text, refusal_at_line};
use crate::output::{check_distinct, AtomicFile};
use crate::user_error;

/// Default wall-clock seconds between two checkpoints.
pub const CHECKPOINT_EVERY: f64 = 600.0;

/// Options of `edmd pack`.
#[derive(Debug, Args)]
pub struct PackArgs {
    /// Start from this file (Princeton or course format) instead of a random start: its radii
    /// are the initial sizes, which all grow by one factor. Or a checkpoint (`--checkpoint`)
    /// to continue, with the options it carries.
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
    /// Growth rate G: the largest diameter grows as dD/dt = G v_rms (v_rms = 1) [default:
    /// 0.02].
    #[arg(long, value_parser = crate::args::parse_positive, allow_negative_numbers = true)]
    pub growth_rate: Option<f64>,
    /// Stop when the reduced pressure PV/(NkT) passes this [default: 1e12].
    #[arg(long, value_parser = crate::args::parse_positive, allow_negative_numbers = true)]
    pub pressure: Option<f64>,
    /// Stop at this packing fraction (below jamming: dense fluids and glasses).
    #[arg(long, value_parser = crate::args::parse_positive, allow_negative_numbers = true)]
    pub packing: Option<f64>,
    /// Boundaries of a random start.
    #[arg(long, value_enum)]
    pub boundary: Option<BoundaryArg>,
    /// Random seed: the same seed gives the same packing, bit for bit [default: 1].
    #[arg(long, allow_negative_numbers = true)]
    pub seed: Option<u64>,
    /// Write an exact checkpoint of the compression here, replaced atomically every
    /// --checkpoint-every seconds and when Ctrl-C stops it; `edmd pack CHECKPOINT -o OUT`
    /// continues it and writes the packing of a run never stopped, bit for bit.
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Wall-clock seconds between checkpoints, each taken at the first velocity rescaling
    /// after the interval (0: at every rescaling) [default: 600].
    #[arg(long, value_name = "SECONDS", requires = "checkpoint", value_parser = crate::args::parse_non_negative, allow_negative_numbers = true)]
    pub checkpoint_every: Option<f64>,
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

/// A start to compress: the particles and the box, in either dimension, or a checkpoint to
/// continue.
pub enum Start {
    /// Discs.
    Two(Vec<Disc<2>>, SimBox<2>),
    /// Spheres.
    Three(Vec<Disc<3>>, SimBox<3>),
    /// The bytes of a packing checkpoint (`--checkpoint`), in either dimension.
    Checkpoint(Vec<u8>),
}

/// What a packing checkpoint keeps besides the packer: the seed (for the summary) and the
/// wall-clock seconds spent so far (postcard-encoded).
#[derive(Serialize, Deserialize)]
struct CheckpointExtra {
    seed: u64,
    wall_seconds: f64,
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
    /// The line of each particle in the file (`lines[i]` for particle `i`), so that a refused
    /// start names the line; empty when the start is not a file.
    pub lines: Vec<usize>,
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
    check_outputs(args)?;
    if args.json && args.output == "-" {
        return user_error(
            "pack: --json and -o - would both write to standard output; write the packing to a file",
        );
    }
    // The options are checked before the file is read.
    options(args)?;
    let what = args.file.as_ref().map(|f| format!("the file {f}"));
    let given = match &args.file {
        Some(path) => match read_pack_checkpoint(Path::new(path))? {
            Some(bytes) => Some((path.as_str(), Start::Checkpoint(bytes), false, Vec::new())),
            None => {
                refuse_random_options(args, what.as_deref().unwrap_or_default())?;
                let text = read_text(path)?;
                let (start, barriers, lines) =
                    match load_any(path, &text, None, ColumnOrder::RadiusMass)? {
                        edmd_io::AnyLoaded::Two(sys) => (
                            Start::Two(sys.discs, sys.sim_box),
                            !sys.barriers.is_empty(),
                            sys.lines,
                        ),
                        edmd_io::AnyLoaded::Three(sys) => (
                            Start::Three(sys.discs, sys.sim_box),
                            !sys.barriers.is_empty(),
                            sys.lines,
                        ),
                    };
                Some((path.as_str(), start, barriers, lines))
            }
        },
        None => None,
    };
    let given = given.map(|(name, start, barriers, lines)| Given {
        name,
        what: what.as_deref().unwrap_or_default(),
        start,
        barriers,
        lines,
    });
    // Created before the compression so that an unwritable path fails at once, not after it
    // (the file appears only when the packing is written whole).
    let out_file = match args.output.as_str() {
        "-" => None,
        p => Some(AtomicFile::create(Path::new(p))?),
    };
    crate::commands::experiment::common::install_ctrlc();
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
        !crate::commands::experiment::common::stop_requested()
    });
    if let Some(pb) = &bar {
        pb.finish_and_clear();
    }
    let packed = packed?;
    let s = packed.summary();
    if s.stop == Stop::Interrupted.name() {
        let phi = s.packing_fraction;
        match &args.checkpoint {
            Some(ck) => anyhow::bail!(
                "interrupted at packing fraction {phi:.6}: the compression so far is in the checkpoint {} (edmd pack {} -o {} continues it); nothing else written",
                ck.display(),
                ck.display(),
                args.output
            ),
            None => anyhow::bail!("interrupted at packing fraction {phi:.6}: nothing written"),
        }
    }
    match packed {
        Packed::Two(packing, summary) => report(args, out_file, &packing, summary),
        Packed::Three(packing, summary) => report(args, out_file, &packing, summary),
    }
}

/// Refuses outputs that are the input or each other, before anything is read. The checkpoint
/// may replace the checkpoint the compression continues from (atomically).
fn check_outputs(args: &PackArgs) -> Result<()> {
    let input = args.file.as_deref().map(Path::new);
    if args.checkpoint.as_deref() == Some(Path::new("-")) {
        return user_error(
            "pack: --checkpoint -: checkpoints are written to a file; give a file name",
        );
    }
    let mut outputs = vec![("-o", Path::new(&args.output))];
    let in_place = match (input, args.checkpoint.as_deref()) {
        (Some(i), Some(c)) => {
            crate::commands::run::same_file(i, c)
                && read_magic(i)?.is_some_and(|m| edmd_core::pack::is_pack_checkpoint(&m))
        }
        _ => false,
    };
    if let Some(c) = args.checkpoint.as_deref() {
        if in_place {
            check_distinct(&[("the checkpoint", c)], &outputs)?;
        } else {
            outputs.push(("--checkpoint", c));
        }
    }
    check_distinct(
        &input
            .map(|f| vec![("the input file", f)])
            .unwrap_or_default(),
        &outputs,
    )?;
    crate::output::check_file_destinations(&outputs)
}

/// Reads `path` whole if it is a packing checkpoint; `None` for any other file (a data file).
/// A run's checkpoint is refused by name.
pub fn read_pack_checkpoint(path: &Path) -> Result<Option<Vec<u8>>> {
    if read_magic(path)? == Some(*edmd_core::CHECKPOINT_MAGIC) {
        return user_error(format!(
            "{}: a run checkpoint (edmd run continues it), not a packing's",
            path.display()
        ));
    }
    read_file_starting(path, edmd_core::pack::PACK_MAGIC)
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
        Some(Given {
            name,
            start: Start::Checkpoint(bytes),
            ..
        }) => resume(args, name, &bytes, progress),
        Some(given) => {
            refuse_random_options(args, given.what)?;
            if given.barriers {
                return user_error(format!("{}: pack does not take barriers", given.name));
            }
            match given.start {
                Start::Two(discs, sim_box) => {
                    let discs = at_speed(args, given.name, discs)?;
                    let at = Some((given.name, &given.lines[..]));
                    let (p, s) = compress(args, at, discs, sim_box, options, progress)?;
                    Ok(Packed::Two(p, s))
                }
                Start::Three(discs, sim_box) => {
                    let discs = at_speed(args, given.name, discs)?;
                    let at = Some((given.name, &given.lines[..]));
                    let (p, s) = compress(args, at, discs, sim_box, options, progress)?;
                    Ok(Packed::Three(p, s))
                }
                Start::Checkpoint(_) => unreachable!("continued above"),
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
                    let (discs, sim_box) = random_start::<3>(n, sizes, boundary, seed(args))
                        .or_else(|e| user_error(e.to_string()))?;
                    let (p, s) = compress(args, None, discs, sim_box, options, progress)?;
                    Ok(Packed::Three(p, s))
                }
                _ => {
                    let (discs, sim_box) = random_start::<2>(n, sizes, boundary, seed(args))
                        .or_else(|e| user_error(e.to_string()))?;
                    let (p, s) = compress(args, None, discs, sim_box, options, progress)?;
                    Ok(Packed::Two(p, s))
                }
            }
        }
    }
}

/// The seed: `--seed`, or 1.
fn seed(args: &PackArgs) -> u64 {
    args.seed.unwrap_or(1)
}

/// Continues the compression a checkpoint holds (`name` names it).
fn resume(
    args: &PackArgs,
    name: &str,
    bytes: &[u8],
    progress: impl FnMut(&Status) -> bool,
) -> Result<Packed> {
    let compression = [
        ("growth-rate", args.growth_rate.is_some()),
        ("pressure", args.pressure.is_some()),
        ("packing", args.packing.is_some()),
        ("seed", args.seed.is_some()),
    ];
    for (flag, set) in random_start_options(args).into_iter().chain(compression) {
        if set {
            return user_error(format!(
                "pack: --{flag} is carried by the checkpoint {name}; drop it to continue"
            ));
        }
    }
    fn load<const D: usize>(name: &str, bytes: &[u8]) -> Result<(Packer<D>, CheckpointExtra)> {
        let (packer, extra) =
            Packer::<D>::from_checkpoint(bytes).or_else(|e| user_error(format!("{name}: {e}")))?;
        let Ok(extra) = postcard::from_bytes::<CheckpointExtra>(&extra) else {
            return user_error(format!(
                "{name}: checkpoint: the command's settings are missing or unreadable"
            ));
        };
        Ok((packer, extra))
    }
    match edmd_core::pack::pack_checkpoint_dim(bytes) {
        Ok(3) => {
            let (packer, extra) = load::<3>(name, bytes)?;
            let (p, s) = drive(args, packer, extra.seed, extra.wall_seconds, progress)?;
            Ok(Packed::Three(p, s))
        }
        Ok(_) => {
            let (packer, extra) = load::<2>(name, bytes)?;
            let (p, s) = drive(args, packer, extra.seed, extra.wall_seconds, progress)?;
            Ok(Packed::Two(p, s))
        }
        Err(e) => user_error(format!("{name}: {e}")),
    }
}

/// The options that describe a random start, and whether each was given.
fn random_start_options(args: &PackArgs) -> [(&'static str, bool); 6] {
    [
        ("dim", args.dim.is_some()),
        ("n", args.n.is_some()),
        ("size-ratio", args.size_ratio.is_some()),
        ("fraction-large", args.fraction_large.is_some()),
        ("polydispersity", args.polydispersity.is_some()),
        ("boundary", args.boundary.is_some()),
    ]
}

/// Refuses the options of a random start when a start is given (`what` names it).
fn refuse_random_options(args: &PackArgs, what: &str) -> Result<()> {
    for (flag, set) in random_start_options(args) {
        if set {
            return user_error(format!(
                "pack: --{flag} is for a random start; {what} sets it"
            ));
        }
    }
    Ok(())
}

fn options(args: &PackArgs) -> Result<PackOptions> {
    let default = PackOptions::default();
    let options = PackOptions {
        growth_rate: args.growth_rate.unwrap_or(default.growth_rate),
        max_pressure: args.pressure.unwrap_or(default.max_pressure),
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
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed(args));
        thermal_velocities(&mut discs, 1.0, &mut rng);
    }
    Ok(discs)
}

/// Compresses and analyses. `at` is the file the discs were read from and each disc's line
/// there, named when the packer refuses a disc.
fn compress<const D: usize>(
    args: &PackArgs,
    at: Option<(&str, &[usize])>,
    discs: Vec<Disc<D>>,
    sim_box: SimBox<D>,
    options: PackOptions,
    progress: impl FnMut(&Status) -> bool,
) -> Result<(Packing<D>, Summary)> {
    let packer = Packer::new(&discs, sim_box, options).or_else(|e| {
        user_error(match at {
            Some((path, lines)) if !lines.is_empty() && !matches!(e, EngineError::Invalid(_)) => {
                refusal_at_line(
                    path,
                    lines,
                    e,
                    (
                        "pack needs a start without overlaps",
                        "pack needs every disc inside the box",
                    ),
                )
            }
            _ => e.to_string(),
        })
    })?;
    drive(args, packer, seed(args), 0.0, progress)
}

/// Runs a compression to its end (after `before` wall-clock seconds in earlier legs), writing
/// the checkpoints `args` asks for, and analyses the packing.
fn drive<const D: usize>(
    args: &PackArgs,
    packer: Packer<D>,
    seed: u64,
    before: f64,
    mut progress: impl FnMut(&Status) -> bool,
) -> Result<(Packing<D>, Summary)> {
    let growth_rate = packer.options().growth_rate;
    let start = Instant::now();
    let every = Duration::try_from_secs_f64(args.checkpoint_every.unwrap_or(CHECKPOINT_EVERY))
        .unwrap_or(Duration::MAX);
    let mut last = Instant::now();
    let mut failed = None;
    let packing = packer.run_with(|pk| {
        let go = progress(&pk.status());
        if let Some(path) = &args.checkpoint {
            if !go || last.elapsed() >= every {
                let extra = CheckpointExtra {
                    seed,
                    wall_seconds: before + start.elapsed().as_secs_f64(),
                };
                let extra = postcard::to_stdvec(&extra).expect("two numbers encode");
                if let Err(e) = write_checkpoint(path, &pk.checkpoint(&extra)) {
                    failed = Some(e);
                    return false;
                }
                last = Instant::now();
            }
        }
        go
    });
    if let Some(e) = failed {
        return Err(e);
    }
    let packing: Packing<D> = packing.or_else(|e| user_error(e.to_string()))?;
    let wall_seconds = before + start.elapsed().as_secs_f64();
    let tol = gap_tolerance(packing.reduced_pressure.unwrap_or(1.0), D);
    let c = contacts(&packing.discs, &packing.sim_box, tol);
    let summary = Summary {
        dim: D,
        n: packing.discs.len(),
        growth_rate,
        seed,
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
    out_file: Option<AtomicFile>,
    packing: &Packing<D>,
    mut summary: Summary,
) -> Result<()> {
    write(out_file, packing)?;
    summary.output = args.output.clone();
    if args.json {
        crate::print_line(&serde_json::to_string(&summary)?);
    } else {
        // Every particle a rattler (a packing stopped early): no contacts to average.
        let contacts = match summary.mean_contacts {
            Some(z) => format!("{z:.3} contacts per non-rattler"),
            None => "no contacts (every particle rattles)".to_string(),
        };
        eprintln!(
            "edmd pack: {} {} at packing fraction {:.6}, reduced pressure {:.3e} (stopped on {}), {} rattlers, {contacts} (gap tolerance {:.1e}), {} collisions in {:.2} s; written to {}",
            summary.n,
            if D == 3 { "spheres" } else { "discs" },
            summary.packing_fraction,
            summary.reduced_pressure.unwrap_or(f64::NAN),
            summary.stop,
            summary.rattlers,
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

/// Writes the packing to `out_file`, or to standard output when there is none (`-o -`).
fn write<const D: usize>(out_file: Option<AtomicFile>, packing: &Packing<D>) -> Result<()> {
    let format = Format::Princeton(ColumnOrder::RadiusMass);
    let (discs, sim_box) = (&packing.discs, &packing.sim_box);
    match out_file {
        None => {
            let mut out = std::io::stdout().lock();
            edmd_io::write(&mut out, discs, sim_box, &[], format, 0.0)?;
            std::io::Write::flush(&mut out)?;
        }
        Some(mut f) => {
            edmd_io::write(f.writer(), discs, sim_box, &[], format, 0.0)?;
            f.commit()?;
        }
    }
    Ok(())
}
