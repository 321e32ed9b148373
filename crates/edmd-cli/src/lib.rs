//! # edmd-cli: the `edmd` and `particles` programs
//!
//! Arguments are parsed by clap into plain values ([`args`]), then each command builds a
//! validated configuration and runs. Errors in what the user gave (files, options) are
//! [`UserError`]s: one line on standard error and exit status 2. Nothing is written before
//! everything has been validated, and output files appear whole or not at all.

#![forbid(unsafe_code)]

pub mod args;
pub mod commands;
pub mod input;
pub mod output;

use std::fmt;
use std::process::ExitCode;

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

/// Prints a line on standard output. A closed pipe (`edmd ... | head`) is not an error: the
/// reader has what it wanted, so the program ends quietly instead of panicking like
/// `println!`.
pub fn print_line(text: &str) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = writeln!(out, "{text}").and_then(|_| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to standard output: {e}");
        std::process::exit(1);
    }
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
/// simulation to a time goes through here.
pub fn run_until<const D: usize, O: edmd_core::Observer<D>>(
    sim: &mut edmd_core::Simulation<D>,
    t: f64,
    observer: &mut O,
) -> anyhow::Result<()> {
    sim.run_until(t, observer);
    check_stall(sim)
}

/// Refuses an end time (`--until`) at or beyond the clock's limit for this system
/// ([`edmd_core::Simulation::check_clock`]): one line naming the file, before any work.
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
/// (Ctrl-C, SIGTERM: [`commands::experiment::common::stop_requested`]) after each, so that a
/// long stretch between two outputs can be interrupted. Returns `Ok(false)` when a stop was
/// requested (the simulation is then somewhere before `t`), `Ok(true)` when it reached `t`.
/// Positions are computed on demand, so the slices do not change the trajectory: without a
/// stop the state at `t` is bit for bit that of [`run_until`].
pub fn run_until_or_stop<const D: usize, O: edmd_core::Observer<D>>(
    sim: &mut edmd_core::Simulation<D>,
    t: f64,
    observer: &mut O,
) -> anyhow::Result<bool> {
    loop {
        let more = sim.run_events_to(t, STOP_CHECK_EVENTS, observer) == STOP_CHECK_EVENTS;
        check_stall(sim)?;
        if commands::experiment::common::stop_requested() {
            return Ok(false);
        }
        if !more {
            break;
        }
    }
    run_until(sim, t, observer)?;
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

/// Runs a command body and turns its outcome into an exit status, printing errors in one line.
pub fn exit_with(program: &str, result: anyhow::Result<()>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e)
            if e.downcast_ref::<std::io::Error>()
                .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe) =>
        {
            // The reader went away (`particles f 10 | head`): it has what it wanted.
            ExitCode::SUCCESS
        }
        Err(e) if e.downcast_ref::<Interrupted>().is_some() => {
            eprintln!("{program}: {}", format!("{e:#}").replace('\n', " "));
            ExitCode::from(INTERRUPTED_STATUS)
        }
        Err(e) => {
            let user = is_user_error(&e);
            let msg = format!("{e:#}").replace('\n', " ");
            eprintln!("{program}: error: {msg}");
            ExitCode::from(if user { 2 } else { 1 })
        }
    }
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

/// Parses command-line arguments with clap; usage errors become one line and exit status 2,
/// `--help` and `--version` print as usual and exit 0.
pub fn parse_args<P: clap::Parser>(program: &str) -> Result<P, ExitCode> {
    match P::try_parse() {
        Ok(p) => Ok(p),
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                let _ = e.print();
                return Err(
                    if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                        ExitCode::from(2)
                    } else {
                        ExitCode::SUCCESS
                    },
                );
            }
            eprintln!(
                "{program}: error: {} (try '{program} --help')",
                one_line(&e.render().to_string())
            );
            Err(ExitCode::from(2))
        }
    }
}

/// clap's message without the usage block, folded into one line.
fn one_line(rendered: &str) -> String {
    let body: Vec<&str> = rendered
        .lines()
        .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    body.join(" ").trim_start_matches("error: ").to_string()
}
