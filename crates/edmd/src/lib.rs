//! # edmd: exact event-driven molecular dynamics of hard discs and spheres
//!
//! The library under both front doors, the `edmd` command line and the Python package: it reads
//! every input the programs read, builds runs with their options and measurements, checkpoints
//! them and continues them, generates systems, packs them, and writes every output atomically.
//! The engine is [`edmd_core`] (re-exported as [`engine`]), the file formats [`edmd_io`]
//! (re-exported as [`io`]).
//!
//! | module | what it holds |
//! |---|---|
//! | [`input`] | any input file (course, Princeton 2D/3D, GSD), refusals naming the line |
//! | [`options`] | the values options take (formats, rules, boundaries) and number parsers |
//! | [`measure`] | the observers of `edmd run --measure` and `Simulation.measure` |
//! | [`checkpoint`] | a run's checkpoint with its format and measurements under way |
//! | [`gen`] | the systems of `edmd gen` |
//! | [`pack`] | the compressions of `edmd pack` |
//! | [`output`] | files written whole or not at all, destinations checked first |
//! | [`stop`] | Ctrl-C, SIGTERM and SIGHUP as a flag every long loop looks at |
//! | [`front`] | what command-line programs share: one-line usage errors, exit statuses |
//!
//! Errors in what a user gave are [`UserError`]s (the programs exit with status 2 on them);
//! a run stopped by a signal ends with [`Interrupted`].
//!
//! ## Read a file, run it with a measurement, checkpoint it, continue it
//!
//! ```
//! use edmd::checkpoint::{checkpoint_bytes, from_checkpoint_bytes, Measuring};
//! use edmd::io::{princeton::ColumnOrder, AnyLoaded};
//! use edmd::measure::Measure;
//! use edmd::engine::Options;
//!
//! # fn main() -> anyhow::Result<()> {
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/data/gas-300.txt");
//! let AnyLoaded::Two(system) = edmd::input::read_any(path, None, ColumnOrder::RadiusMass, None)?
//! else {
//!     anyhow::bail!("a 2D file");
//! };
//! let mut sim = edmd::input::build(path, &system, Options::default())?;
//!
//! // Temperature and pressure, a sample every 0.5 time units.
//! let mut measuring = Measuring::new(&sim, &[Measure::Temperature, Measure::Pressure], 0.5);
//! assert!(measuring.run_to(&mut sim, 5.0)?);
//! assert_eq!(measuring.samples, 10);
//!
//! // A checkpoint keeps the state, the file's format and the measurements under way: the
//! // continued run is the run never stopped, bit for bit.
//! let bytes = checkpoint_bytes(&sim, system.format, Some(&measuring))?;
//! let (mut resumed, _format, carried) =
//!     from_checkpoint_bytes::<2>(&bytes).map_err(anyhow::Error::msg)?;
//! let mut carried = carried.expect("the measurements travel with the checkpoint");
//! carried.run_to(&mut resumed, 10.0)?;
//! measuring.run_to(&mut sim, 10.0)?;
//! assert!((0..sim.len()).all(|i| resumed.position(i) == sim.position(i)
//!     && resumed.velocity(i) == sim.velocity(i)));
//!
//! // The measured summaries (JSON, as `edmd run --measure --json` prints them) agree too.
//! let (summary, _tables) = carried.obs.results(&resumed);
//! assert_eq!(summary, measuring.obs.results(&sim).0);
//! assert!(summary.get("pressure").is_some());
//! # Ok(())
//! # }
//! ```

#![forbid(unsafe_code)]

pub mod checkpoint;
pub mod front;
pub mod gen;
pub mod input;
pub mod measure;
pub mod options;
pub mod output;
pub mod pack;
pub mod stop;

pub use edmd_core as engine;
pub use edmd_io as io;

/// The largest number of particles the generators, the packer and the experiments take.
pub const MAX_N: usize = 10_000_000;

use std::fmt;

/// A problem with what the user supplied: reported in one line, exit status 2.
#[derive(Debug)]
pub struct UserError(pub String);

impl fmt::Display for UserError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UserError {}

/// Exit status of a command stopped by Ctrl-C, SIGTERM or SIGHUP (the shells' convention for
/// SIGINT, 128 + 2), whichever command it was.
pub const INTERRUPTED_STATUS: u8 = 130;

/// A command stopped by a signal before it finished: reported in one line (what was kept, what
/// was not written), exit status [`INTERRUPTED_STATUS`].
#[derive(Debug)]
pub struct Interrupted(pub String);

impl fmt::Display for Interrupted {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Interrupted {}

/// Shorthand for returning an [`Interrupted`].
pub fn interrupted<T>(msg: impl Into<String>) -> anyhow::Result<T> {
    Err(Interrupted(msg.into()).into())
}

/// Shorthand for returning a [`UserError`].
pub fn user_error<T>(msg: impl Into<String>) -> anyhow::Result<T> {
    Err(UserError(msg.into()).into())
}

/// Fails with one line naming the discs (a [`UserError`]: exit status 2) if the simulation's
/// clock stopped advancing ([`edmd_core::Simulation::stalled`]): discs jammed so that their
/// events all fall at one instant.
pub fn check_stall<const D: usize>(sim: &edmd_core::Simulation<D>) -> anyhow::Result<()> {
    match sim.stalled() {
        None => Ok(()),
        Some(s) => user_error(s.to_string()),
    }
}

/// [`edmd_core::Simulation::run_until`], then [`check_stall`]: every command that runs a
/// simulation to a time goes through here. The observer runs as a [`shared`] one.
pub fn run_until<const D: usize, O: edmd_core::Observer<D>>(
    sim: &mut edmd_core::Simulation<D>,
    t: f64,
    observer: &mut O,
) -> anyhow::Result<()> {
    run_until_shared(sim, t, shared(observer))
}

fn run_until_shared<const D: usize>(
    sim: &mut edmd_core::Simulation<D>,
    t: f64,
    mut observer: &mut dyn edmd_core::Observer<D>,
) -> anyhow::Result<()> {
    sim.run_until(t, &mut observer);
    check_stall(sim)
}

/// The observer as a trait object, for the runs of commands other than `edmd run` and `edmd
/// bench`. The engine's event loop is compiled once for each type of observer it runs with
/// (six copies: three kinds of interaction, two instruction sets). With an instance for each
/// experiment's observer they were nearly two-thirds of the command-line library's machine
/// code (11.6 MB in the test build); observers passed through here share one copy per
/// dimension (6.6 MB in all), at the cost of a call through a pointer per event (a few
/// nanoseconds, against the hundreds an event takes).
pub fn shared<const D: usize>(
    observer: &mut impl edmd_core::Observer<D>,
) -> &mut dyn edmd_core::Observer<D> {
    observer
}

/// Refuses an end time (`--until`) at or beyond the clock's limit for this system
/// ([`edmd_core::Simulation::check_clock`], never under self-gravity): one line naming the file,
/// before any work.
pub fn check_until<const D: usize>(
    sim: &edmd_core::Simulation<D>,
    file: &str,
    until: f64,
) -> anyhow::Result<()> {
    sim.check_clock(until)
        .or_else(|e| user_error(format!("{file}: --until: {e}")))
}

/// Events run between two looks at the stop flag in [`run_until_or_stop`] (and `edmd run`):
/// a fraction of a second at the engine's speed.
pub const STOP_CHECK_EVENTS: u64 = 100_000;

/// [`run_until`], in slices of [`STOP_CHECK_EVENTS`] events with a look at the stop flag
/// (Ctrl-C, SIGTERM: [`stop::stop_requested`]) after each, so that a
/// long stretch between two outputs can be interrupted. Returns `Ok(false)` when a stop was
/// requested (the simulation is then somewhere before `t`), `Ok(true)` when it reached `t`.
/// Positions are computed on demand, so the slices do not change the trajectory: without a
/// stop the state at `t` is bit for bit that of [`run_until`]. The observer runs as a
/// [`shared`] one.
pub fn run_until_or_stop<const D: usize, O: edmd_core::Observer<D>>(
    sim: &mut edmd_core::Simulation<D>,
    t: f64,
    observer: &mut O,
) -> anyhow::Result<bool> {
    run_until_or_stop_shared(sim, t, shared(observer))
}

fn run_until_or_stop_shared<const D: usize>(
    sim: &mut edmd_core::Simulation<D>,
    t: f64,
    mut observer: &mut dyn edmd_core::Observer<D>,
) -> anyhow::Result<bool> {
    loop {
        let more = sim.run_events_to(t, STOP_CHECK_EVENTS, &mut observer) == STOP_CHECK_EVENTS;
        check_stall(sim)?;
        if stop::stop_requested() {
            return Ok(false);
        }
        if !more {
            break;
        }
    }
    run_until_shared(sim, t, observer)?;
    Ok(true)
}

/// [`edmd_core::Simulation::run_events`] (without an observer), then [`check_stall`]; also
/// fails when no event is left at all, so that a loop waiting for a number of collisions always
/// ends. Returns how many events were processed.
pub fn run_events<const D: usize>(
    sim: &mut edmd_core::Simulation<D>,
    n: u64,
) -> anyhow::Result<u64> {
    let k = sim.run_events(n, &mut ());
    check_stall(sim)?;
    if k == 0 && n > 0 {
        return user_error("no disc moves: nothing will ever happen in this system");
    }
    Ok(k)
}

/// True when the error, or an I/O error in its chain, is a [`UserError`] (write errors on output
/// files carry one, naming the file).
pub fn is_user_error(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<UserError>().is_some()
            || c.downcast_ref::<std::io::Error>()
                .and_then(|io| io.get_ref())
                .is_some_and(|inner| inner.downcast_ref::<UserError>().is_some())
    })
}
