//! `edmd pack`: the command over [`edmd::pack::pack`]: it checks the outputs, reads the start,
//! shows the progress, and writes the packing and its summary.

use std::io::IsTerminal;
use std::path::Path;
use std::time::Duration;

use anyhow::Result;
use edmd::input::read_any;
use edmd::output::{check_distinct, AtomicFile};
use edmd::pack::{
    options, pack, read_pack_checkpoint, refuse_random_options, Given, PackArgs, Packed, Start,
    Summary,
};
use edmd::user_error;
use edmd_core::pack::{Packing, Status, Stop};
use edmd_io::princeton::ColumnOrder;
use edmd_io::Format;

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
    crate::commands::experiment::common::install_ctrlc();
    let setup = SetupWatch::start();
    let what = args.file.as_ref().map(|f| format!("the file {f}"));
    // A file's reaction rules go with its particles, whose species the compression keeps, into
    // the packing written (a packing's checkpoint keeps particles only).
    let mut reactions = Vec::new();
    let given = match &args.file {
        Some(path) => match read_pack_checkpoint(Path::new(path))? {
            Some(bytes) => Some((
                path.as_str(),
                Start::Checkpoint(bytes),
                false,
                false,
                Vec::new(),
            )),
            None => {
                refuse_random_options(args, what.as_deref().unwrap_or_default())?;
                let (start, barriers, stepped, lines) =
                    match read_any(path, None, ColumnOrder::RadiusMass, None)? {
                        edmd_io::AnyLoaded::Two(sys) => {
                            reactions = sys.reactions;
                            (
                                Start::Two(sys.discs, sys.sim_box),
                                !sys.barriers.is_empty(),
                                !sys.potential.is_hard(),
                                sys.lines,
                            )
                        }
                        edmd_io::AnyLoaded::One(_) => {
                            return user_error(format!(
                                "{path}: a 1D file (rods on a line): edmd pack compresses discs and spheres; rods fill a line of any packing below 1 as they are (edmd gen fluid --dim 1 --packing ETA)"
                            ))
                        }
                        edmd_io::AnyLoaded::Three(sys) => {
                            reactions = sys.reactions;
                            (
                                Start::Three(sys.discs, sys.sim_box),
                                !sys.barriers.is_empty(),
                                !sys.potential.is_hard(),
                                sys.lines,
                            )
                        }
                    };
                Some((path.as_str(), start, barriers, stepped, lines))
            }
        },
        None => None,
    };
    let given = given.map(|(name, start, barriers, stepped, lines)| Given {
        name,
        what: what.as_deref().unwrap_or_default(),
        start,
        barriers,
        stepped,
        lines,
    });
    // The output's place was checked with the others (`check_outputs`), without creating
    // anything: its temporary file is made only when the packing is written, so that a run
    // killed outright (SIGKILL, which no handler sees) leaves nothing behind.
    let bar = progress_bar();
    let stop = || {
        setup.end();
        crate::commands::experiment::common::stop_requested()
    };
    let packed = pack(args, given, stop, |s: &Status| {
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
        return match &args.checkpoint {
            Some(ck) => edmd::interrupted(format!(
                "interrupted at packing fraction {phi:.6}: the compression up to its last velocity rescaling is in the checkpoint {} (edmd pack {} -o {} continues it); nothing else written",
                ck.display(),
                ck.display(),
                args.output
            )),
            None => edmd::interrupted(format!(
                "interrupted at packing fraction {phi:.6}: nothing written"
            )),
        };
    }
    match packed {
        Packed::Two(packing, summary) => report(args, &packing, &reactions, summary),
        Packed::Three(packing, summary) => report(args, &packing, &reactions, summary),
    }
}

/// Watches for Ctrl-C while the compression is being set up (the file read, the random start
/// placed, the packer's checks and first predictions: seconds for 10^6 particles, more for
/// 10^7), when the packer cannot yet look and there is nothing to keep: a stop request then
/// ends the program at once, with exit status 130. [`SetupWatch::end`], called when the
/// compression first looks itself, ends the watch; the lock makes the two exclusive, so the
/// program is never ended while a checkpoint is being written.
struct SetupWatch {
    done: std::sync::Arc<std::sync::Mutex<bool>>,
}

impl SetupWatch {
    fn start() -> Self {
        let done = std::sync::Arc::new(std::sync::Mutex::new(false));
        let watched = done.clone();
        std::thread::spawn(move || loop {
            {
                let Ok(done) = watched.lock() else { return };
                if *done {
                    return;
                }
                if crate::commands::experiment::common::stop_requested() {
                    edmd::output::remove_temporaries();
                    eprintln!("edmd: interrupted before the compression started: nothing written");
                    std::process::exit(edmd::INTERRUPTED_STATUS.into());
                }
            }
            std::thread::sleep(Duration::from_millis(20));
        });
        SetupWatch { done }
    }

    fn end(&self) {
        if let Ok(mut done) = self.done.lock() {
            *done = true;
        }
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
            edmd::checkpoint::same_file(i, c)
                && edmd::checkpoint::read_magic(i)?
                    .is_some_and(|m| edmd_core::pack::is_pack_checkpoint(&m))
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
    edmd::output::check_file_destinations(&outputs)
}

/// Writes the packing (with the reaction rules of the file it started from) and prints the
/// summary.
fn report<const D: usize>(
    args: &PackArgs,
    packing: &Packing<D>,
    reactions: &[edmd_core::Reaction],
    mut summary: Summary,
) -> Result<()> {
    write(&args.output, packing, reactions)?;
    summary.output = args.output.clone();
    if args.json {
        edmd::front::print_line(&serde_json::to_string(&summary)?);
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

/// Writes the packing, with `reactions`, to `output`, or to standard output for `-`.
fn write<const D: usize>(
    output: &str,
    packing: &Packing<D>,
    reactions: &[edmd_core::Reaction],
) -> Result<()> {
    let format = Format::Princeton(ColumnOrder::RadiusMass);
    let (discs, sim_box) = (&packing.discs, &packing.sim_box);
    let interactions = edmd_io::Interactions {
        reactions,
        ..edmd_io::Interactions::HARD
    };
    let out_file = match output {
        "-" => None,
        p => Some(AtomicFile::create(Path::new(p))?),
    };
    match out_file {
        None => {
            let mut out = std::io::stdout().lock();
            edmd_io::write_full(&mut out, discs, sim_box, &[], interactions, format, 0.0)?;
            std::io::Write::flush(&mut out)?;
        }
        Some(mut f) => {
            edmd_io::write_full(f.writer(), discs, sim_box, &[], interactions, format, 0.0)?;
            f.commit()?;
        }
    }
    Ok(())
}
