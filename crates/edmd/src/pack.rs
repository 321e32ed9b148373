//! `edmd pack`: Lubachevsky-Stillinger compression to a jammed packing (or to a packing
//! fraction below jamming), from a random start or a file, or continued from a checkpoint.
//! The engine is `edmd_core::pack`; this command validates the options, shows the progress,
//! writes checkpoints (`--checkpoint`, every `--checkpoint-every` seconds and on Ctrl-C),
//! writes the packing in the Princeton format (readable by `edmd run`) and a summary.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::Result;
use clap::Args;
use edmd_core::pack::{
    contacts, gap_tolerance, random_start, PackOptions, PackSizes, Packer, Packing, Status, Stop,
};
use edmd_core::setup::thermal_velocities;
use edmd_core::{Boundary, Disc, Error as EngineError, SimBox, Vector};
use rand::SeedableRng;
use serde::{Deserialize, Serialize};

use crate::checkpoint::{read_file_starting, read_magic, write_checkpoint};
use crate::input::refusal_at_line;
use crate::options::BoundaryArg;
use crate::user_error;
use crate::MAX_N;

/// Default wall-clock seconds between two checkpoints.
pub const CHECKPOINT_EVERY: f64 = 600.0;

/// With `--checkpoint`, the bytes of a rescaling's checkpoint are kept in memory at least this
/// often (wall-clock seconds), so that a stop between two rescalings, which cannot be
/// checkpointed where it falls, writes the last one kept: at most this much, plus one
/// interval between rescalings, is done again when the run is continued. Taking them costs a
/// copy of the state, a small part of a rescaling, so they are not taken at every one.
const KEEP_EVERY: Duration = Duration::from_millis(250);

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
    #[arg(long, value_parser = crate::options::parse_dim)]
    pub dim: Option<usize>,
    /// Number of particles of a random start.
    #[arg(long, value_parser = crate::options::parse_count, allow_negative_numbers = true)]
    pub n: Option<usize>,
    /// Bidisperse: diameter ratio large/small (default 1, monodisperse).
    #[arg(long, value_parser = crate::options::parse_positive, allow_negative_numbers = true)]
    pub size_ratio: Option<f64>,
    /// Bidisperse: number fraction of large particles (default 0.5 with --size-ratio).
    #[arg(long, allow_negative_numbers = true)]
    pub fraction_large: Option<f64>,
    /// Polydisperse: diameters uniform with this relative standard deviation (mean 1).
    #[arg(long, value_parser = crate::options::parse_positive, allow_negative_numbers = true)]
    pub polydispersity: Option<f64>,
    /// Growth rate G: the largest diameter grows as dD/dt = G v_rms (v_rms = 1) [default:
    /// 0.02].
    #[arg(long, value_parser = crate::options::parse_positive, allow_negative_numbers = true)]
    pub growth_rate: Option<f64>,
    /// Stop when the reduced pressure PV/(NkT) passes this [default: 1e12].
    #[arg(long, value_parser = crate::options::parse_positive, allow_negative_numbers = true)]
    pub pressure: Option<f64>,
    /// Stop at this packing fraction (below jamming: dense fluids and glasses).
    #[arg(long, value_parser = crate::options::parse_positive, allow_negative_numbers = true)]
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
    #[arg(long, value_name = "SECONDS", requires = "checkpoint", value_parser = crate::options::parse_non_negative, allow_negative_numbers = true)]
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

/// What a packing checkpoint keeps besides the packer: the seed (for the summary), the
/// wall-clock seconds spent so far and, for a random start, its sizes (postcard-encoded), so
/// that options given again on continuing can be compared with the ones it carries.
#[derive(Serialize, Deserialize)]
struct CheckpointExtra {
    seed: u64,
    wall_seconds: f64,
    /// The random start's sizes; `None` for a start given as a file or a simulation.
    sizes: Option<CarriedSizes>,
}

/// The extra bytes of checkpoints written before they carried the sizes.
#[derive(Deserialize)]
struct CheckpointExtraV1 {
    seed: u64,
    wall_seconds: f64,
}

/// A random start's sizes, as a checkpoint carries them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
enum CarriedSizes {
    Binary {
        size_ratio: f64,
        fraction_large: f64,
    },
    Polydisperse {
        std: f64,
    },
}

/// What the checkpoint carries, read back: the seed, the seconds so far, and the random
/// start's sizes if known (`None` inside: a start that was not random; `None` outside: a
/// checkpoint written before the sizes were kept).
fn read_extra(name: &str, extra: &[u8]) -> Result<(u64, f64, Option<Option<CarriedSizes>>)> {
    if let Ok(e) = postcard::from_bytes::<CheckpointExtra>(extra) {
        return Ok((e.seed, e.wall_seconds, Some(e.sizes)));
    }
    match postcard::from_bytes::<CheckpointExtraV1>(extra) {
        Ok(e) => Ok((e.seed, e.wall_seconds, None)),
        Err(_) => user_error(format!(
            "{name}: checkpoint: the command's settings are missing or unreadable"
        )),
    }
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
    /// Whether it has a stepped potential (pack refuses it: it compresses hard particles).
    pub stepped: bool,
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
/// it, calling `progress` at every rescaling (`false` stops the compression) and `stop` every
/// few milliseconds (`true` stops it: Ctrl-C). What `edmd pack` writes and what `edmd.pack`
/// returns in Python, so the two agree bit for bit. A stopped compression comes back with the
/// summary's `stop` "interrupted" (and, with `--checkpoint`, its last rescaling written there).
pub fn pack(
    args: &PackArgs,
    given: Option<Given<'_>>,
    stop: impl FnMut() -> bool,
    progress: impl FnMut(&Status) -> bool,
) -> Result<Packed> {
    let options = options(args)?;
    match given {
        Some(Given {
            name,
            start: Start::Checkpoint(bytes),
            ..
        }) => resume(args, name, &bytes, stop, progress),
        Some(given) => {
            refuse_random_options(args, given.what)?;
            if given.barriers {
                return user_error(format!("{}: pack does not take barriers", given.name));
            }
            if given.stepped {
                return user_error(format!(
                    "{}: pack compresses hard particles, and this start has a stepped potential; pack its discs without it",
                    given.name
                ));
            }
            match given.start {
                Start::Two(discs, sim_box) => {
                    let discs = at_speed(args, given.name, discs)?;
                    let at = Some((given.name, &given.lines[..]));
                    let (p, s) = compress(args, at, None, discs, sim_box, options, stop, progress)?;
                    Ok(Packed::Two(p, s))
                }
                Start::Three(discs, sim_box) => {
                    let discs = at_speed(args, given.name, discs)?;
                    let at = Some((given.name, &given.lines[..]));
                    let (p, s) = compress(args, at, None, discs, sim_box, options, stop, progress)?;
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
            let carried = Some(match sizes {
                PackSizes::Binary {
                    size_ratio,
                    fraction_large,
                } => CarriedSizes::Binary {
                    size_ratio,
                    fraction_large,
                },
                PackSizes::Polydisperse { std } => CarriedSizes::Polydisperse { std },
            });
            let boundary = match args.boundary {
                None | Some(BoundaryArg::Periodic) => Boundary::Periodic,
                Some(BoundaryArg::Walls) => Boundary::Walls,
            };
            match args.dim.unwrap_or(2) {
                3 => {
                    let (discs, sim_box) = random_start::<3>(n, sizes, boundary, seed(args))
                        .or_else(|e| user_error(e.to_string()))?;
                    let (p, s) =
                        compress(args, None, carried, discs, sim_box, options, stop, progress)?;
                    Ok(Packed::Three(p, s))
                }
                _ => {
                    let (discs, sim_box) = random_start::<2>(n, sizes, boundary, seed(args))
                        .or_else(|e| user_error(e.to_string()))?;
                    let (p, s) =
                        compress(args, None, carried, discs, sim_box, options, stop, progress)?;
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

/// Continues the compression a checkpoint holds (`name` names it). Options given again must
/// be the ones it carries (the same command line run again after a crash is accepted); a
/// different value is refused, naming the option and both values.
fn resume(
    args: &PackArgs,
    name: &str,
    bytes: &[u8],
    stop: impl FnMut() -> bool,
    progress: impl FnMut(&Status) -> bool,
) -> Result<Packed> {
    fn load<const D: usize>(
        args: &PackArgs,
        name: &str,
        bytes: &[u8],
    ) -> Result<(Packer<D>, u64, f64, Option<CarriedSizes>)> {
        let (packer, extra) =
            Packer::<D>::from_checkpoint(bytes).or_else(|e| user_error(format!("{name}: {e}")))?;
        let (seed, wall_seconds, sizes) = read_extra(name, &extra)?;
        check_carried(args, name, &packer, seed, sizes)?;
        Ok((packer, seed, wall_seconds, sizes.flatten()))
    }
    match edmd_core::pack::pack_checkpoint_dim(bytes) {
        Ok(3) => {
            let (packer, seed, before, sizes) = load::<3>(args, name, bytes)?;
            let (p, s) = drive(args, packer, seed, sizes, before, stop, progress)?;
            Ok(Packed::Three(p, s))
        }
        Ok(_) => {
            let (packer, seed, before, sizes) = load::<2>(args, name, bytes)?;
            let (p, s) = drive(args, packer, seed, sizes, before, stop, progress)?;
            Ok(Packed::Two(p, s))
        }
        Err(e) => user_error(format!("{name}: {e}")),
    }
}

/// Refuses an option given beside a checkpoint with a value other than the one the checkpoint
/// carries. `sizes` is the random start's sizes (`Some(None)`: the start was not random;
/// `None`: a checkpoint too old to say).
fn check_carried<const D: usize>(
    args: &PackArgs,
    name: &str,
    packer: &Packer<D>,
    seed: u64,
    sizes: Option<Option<CarriedSizes>>,
) -> Result<()> {
    let differs = |flag: &str, given: String, carried: String| -> Result<()> {
        user_error(format!(
            "pack: --{flag} {given} differs from the value carried by the checkpoint {name}, {carried}; give the same or drop it to continue"
        ))
    };
    let o = packer.options();
    let same = |given: Option<f64>, carried: f64| given.is_none_or(|g| g == carried);
    if let Some(d) = args.dim.filter(|&d| d != D) {
        return differs("dim", d.to_string(), D.to_string());
    }
    if let Some(n) = args.n.filter(|&n| n != packer.particle_count()) {
        return differs("n", n.to_string(), packer.particle_count().to_string());
    }
    if let Some(b) = args.boundary {
        let want = match b {
            BoundaryArg::Periodic => Boundary::Periodic,
            BoundaryArg::Walls => Boundary::Walls,
        };
        let boxed = packer.sim_box();
        if !(0..D).all(|a| boxed.is_periodic(a) == (want == Boundary::Periodic)) {
            let carried = if (0..D).all(|a| boxed.is_periodic(a)) {
                "periodic"
            } else if (0..D).all(|a| !boxed.is_periodic(a)) {
                "walls"
            } else {
                "mixed boundaries"
            };
            let given = if want == Boundary::Periodic {
                "periodic"
            } else {
                "walls"
            };
            return differs("boundary", given.into(), carried.into());
        }
    }
    let size_flags = [
        ("size-ratio", args.size_ratio),
        ("fraction-large", args.fraction_large),
        ("polydispersity", args.polydispersity),
    ];
    if let Some((flag, given)) = size_flags.iter().find_map(|&(f, v)| v.map(|v| (f, v))) {
        match sizes {
            None => {
                return user_error(format!(
                    "pack: --{flag} is carried by the checkpoint {name}, written before checkpoints kept the start's sizes to compare with; drop it to continue"
                ))
            }
            Some(None) => {
                return user_error(format!(
                    "pack: --{flag} {given} is for a random start, and the checkpoint {name} continues a given start whose sizes it carries; drop it to continue"
                ))
            }
            Some(Some(carried)) => {
                let (ratio, large, poly) = match carried {
                    CarriedSizes::Binary {
                        size_ratio,
                        fraction_large,
                    } => (Some(size_ratio), Some(fraction_large), None),
                    CarriedSizes::Polydisperse { std } => (None, None, Some(std)),
                };
                for (flag, given, carried) in [
                    ("size-ratio", args.size_ratio, ratio),
                    ("fraction-large", args.fraction_large, large),
                    ("polydispersity", args.polydispersity, poly),
                ] {
                    if let Some(g) = given {
                        match carried {
                            Some(c) if c == g => {}
                            Some(c) => return differs(flag, format!("{g}"), format!("{c}")),
                            None => return differs(flag, format!("{g}"), "other sizes".into()),
                        }
                    }
                }
            }
        }
    }
    if !same(args.growth_rate, o.growth_rate) {
        let g = args.growth_rate.unwrap_or_default();
        return differs("growth-rate", format!("{g}"), format!("{}", o.growth_rate));
    }
    if !same(args.pressure, o.max_pressure) {
        let p = args.pressure.unwrap_or_default();
        return differs(
            "pressure",
            format!("{p:e}"),
            format!("{:e}", o.max_pressure),
        );
    }
    if let Some(phi) = args.packing {
        if o.target_packing != Some(phi) {
            let carried = o
                .target_packing
                .map_or("none".to_string(), |c| format!("{c}"));
            return differs("packing", format!("{phi}"), carried);
        }
    }
    if let Some(s) = args.seed.filter(|&s| s != seed) {
        return differs("seed", s.to_string(), seed.to_string());
    }
    Ok(())
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
pub fn refuse_random_options(args: &PackArgs, what: &str) -> Result<()> {
    for (flag, set) in random_start_options(args) {
        if set {
            return user_error(format!(
                "pack: --{flag} is for a random start; {what} sets it"
            ));
        }
    }
    Ok(())
}

/// The compression options `args` ask for, checked (before any file is read).
pub fn options(args: &PackArgs) -> Result<PackOptions> {
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
/// there, named when the packer refuses a disc; `sizes` those of a random start.
#[allow(clippy::too_many_arguments)]
fn compress<const D: usize>(
    args: &PackArgs,
    at: Option<(&str, &[usize])>,
    sizes: Option<CarriedSizes>,
    discs: Vec<Disc<D>>,
    sim_box: SimBox<D>,
    options: PackOptions,
    stop: impl FnMut() -> bool,
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
    drive(args, packer, seed(args), sizes, 0.0, stop, progress)
}

/// Runs a compression to its end (after `before` wall-clock seconds in earlier legs), writing
/// the checkpoints `args` asks for, and analyses the packing. Stopped by `stop` between two
/// rescalings, it writes the last rescaling's checkpoint it kept (the state there is the only
/// one a continuation can start from exactly).
fn drive<const D: usize>(
    args: &PackArgs,
    packer: Packer<D>,
    seed: u64,
    sizes: Option<CarriedSizes>,
    before: f64,
    stop: impl FnMut() -> bool,
    mut progress: impl FnMut(&Status) -> bool,
) -> Result<(Packing<D>, Summary)> {
    let growth_rate = packer.options().growth_rate;
    let start = Instant::now();
    let every = Duration::try_from_secs_f64(args.checkpoint_every.unwrap_or(CHECKPOINT_EVERY))
        .unwrap_or(Duration::MAX);
    let bytes = |pk: &Packer<D>| {
        let extra = CheckpointExtra {
            seed,
            wall_seconds: before + start.elapsed().as_secs_f64(),
            sizes,
        };
        pk.checkpoint(&postcard::to_stdvec(&extra).expect("numbers encode"))
    };
    // The last checkpoint taken and not yet written: the start's, so that a stop before the
    // first rescaling leaves one too.
    let mut kept = args.checkpoint.as_ref().map(|_| bytes(&packer));
    let mut taken = Instant::now();
    let mut last = Instant::now();
    let mut failed = None;
    let packing = packer.run_watched(
        |pk| {
            let go = progress(&pk.status());
            if let Some(path) = &args.checkpoint {
                let due = !go || last.elapsed() >= every;
                if due || taken.elapsed() >= KEEP_EVERY {
                    kept = Some(bytes(pk));
                    taken = Instant::now();
                }
                if due {
                    let b = kept.take().expect("just taken");
                    if let Err(e) = write_checkpoint(path, &b) {
                        failed = Some(e);
                        return false;
                    }
                    last = Instant::now();
                }
            }
            go
        },
        stop,
    );
    if let Some(e) = failed {
        return Err(e);
    }
    if let (Some(path), Some(b), Ok(p)) = (&args.checkpoint, &kept, &packing) {
        if p.stop == Stop::Interrupted {
            write_checkpoint(path, b)?;
        }
    }
    let packing: Packing<D> = packing.or_else(|e| user_error(e.to_string()))?;
    let wall_seconds = before + start.elapsed().as_secs_f64();
    let tol = gap_tolerance(packing.reduced_pressure.unwrap_or(1.0), D);
    let c = if packing.stop == Stop::Interrupted {
        // Nothing is written: the analysis (about a second for 10^6 particles) would only
        // delay the end Ctrl-C asked for.
        edmd_core::pack::Contacts {
            gap_tolerance: tol,
            rattler: Vec::new(),
            rattlers: 0,
            contacts: Vec::new(),
            mean_contacts: f64::NAN,
            min_gap: f64::NAN,
        }
    } else {
        contacts(&packing.discs, &packing.sim_box, tol)
    };
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
