//! What every experiment shares: the output folder, CSV files, progress, Ctrl-C, the summary.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Result;
use clap::Args;
use serde::Serialize;

use crate::output::AtomicFile;

/// Options every experiment takes.
#[derive(Debug, Clone, Args)]
pub struct CommonArgs {
    /// Folder for the CSV files and plots (created if missing). The default is the current
    /// folder, and files there with the names this experiment writes (its name, .csv, .png,
    /// .svg; see the list printed at the end) are replaced.
    #[arg(long, value_name = "DIR", default_value = ".")]
    pub out_dir: PathBuf,
    /// Random seed: the same seed gives the same results.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// Print the summary as one JSON object on standard output.
    #[arg(long)]
    pub json: bool,
}

static STOP: AtomicBool = AtomicBool::new(false);
/// Set when the command has seen [`STOP`] (through [`stop_requested`]).
static NOTICED: AtomicBool = AtomicBool::new(false);
/// Set by [`stop_promptly`]: the command must end within [`STOP_GRACE`] of a signal.
static PROMPT: AtomicBool = AtomicBool::new(false);

/// How long a command that asked to stop promptly may take to notice a signal before the
/// program ends without it. Every loop of such a command looks at the flag at least every
/// tenth of a second or so; this covers the steps that cannot look (reading a large file,
/// building a large simulation, drawing one large frame).
pub const STOP_GRACE: std::time::Duration = std::time::Duration::from_millis(1000);

/// Makes Ctrl-C (SIGINT), SIGTERM and SIGHUP ask the running command to stop: an experiment
/// then writes what it measured so far, `run` and `render` abandon the run and remove their
/// temporary files. A second signal removes the temporary files and ends the program at once
/// (exit status [`crate::INTERRUPTED_STATUS`]). Commands install it before any work, so that a
/// signal is never met by the default action, which would leave temporary files.
pub fn install_ctrlc() {
    let _ = ctrlc::set_handler(|| {
        if STOP.swap(true, Ordering::SeqCst) {
            end_now("interrupted again: stopped at once");
        }
        eprintln!("\nstopping (Ctrl-C again to quit at once)");
        if PROMPT.load(Ordering::SeqCst) {
            // The handler runs on its own thread; the deadline gets another so that a second
            // Ctrl-C is still heard at once.
            std::thread::spawn(|| {
                std::thread::sleep(STOP_GRACE);
                if !NOTICED.load(Ordering::SeqCst) {
                    end_now(
                        "interrupted in a step that cannot stop half-way: nothing more written",
                    );
                }
            });
        }
    });
}

/// Also makes the program end by itself (temporary files removed, exit status
/// [`crate::INTERRUPTED_STATUS`]) when the command has not noticed a stop request within
/// [`STOP_GRACE`]. For `run`, `render`, `soak` and the experiments, whose loops all look at the
/// flag; not for `edmd pack`, which stops at its next velocity rescaling to write a checkpoint
/// however long that takes.
pub fn stop_promptly() {
    PROMPT.store(true, Ordering::SeqCst);
}

/// Ends the program on a signal: temporary files and a folder this run created (if still
/// empty) removed, one line, exit status 130.
fn end_now(why: &str) -> ! {
    crate::output::remove_temporaries();
    if let Some(dir) = CREATED_DIR.try_lock().ok().and_then(|mut c| c.take()) {
        let _ = std::fs::remove_dir(dir);
    }
    eprintln!("edmd: {why}");
    std::process::exit(crate::INTERRUPTED_STATUS.into());
}

/// True once Ctrl-C (SIGTERM, SIGHUP) has been pressed.
pub fn stop_requested() -> bool {
    let stop = STOP.load(Ordering::SeqCst);
    if stop {
        NOTICED.store(true, Ordering::SeqCst);
    }
    stop
}

/// Runs `work` on a thread of its own and waits for it, looking at the stop flag meanwhile:
/// `None` when a stop was requested first (the thread is left to the end of the program). For
/// the steps of an experiment that the engine runs in one call (generating and melting a large
/// fluid, building a large simulation), so that a signal there still lets the experiment write
/// the results of the steps before.
pub fn interruptible<T: Send + 'static>(
    work: impl FnOnce() -> T + Send + 'static,
) -> Result<Option<T>> {
    use std::sync::mpsc::RecvTimeoutError;
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::Builder::new()
        .spawn(move || {
            let _ = tx.send(work());
        })
        .map_err(|e| anyhow::anyhow!("cannot start a thread: {e}"))?;
    loop {
        if stop_requested() {
            return Ok(None);
        }
        match rx.recv_timeout(std::time::Duration::from_millis(20)) {
            Ok(x) => return Ok(Some(x)),
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => {
                anyhow::bail!("internal error: a step of the experiment ended without a result")
            }
        }
    }
}

/// The one line an experiment stopped by a signal ends with (exit status
/// [`crate::INTERRUPTED_STATUS`]), after it wrote the results so far.
pub fn interrupted_after(files: &[PathBuf]) -> Result<()> {
    crate::interrupted(format!(
        "interrupted: the results so far are written ({})",
        files_line(files)
    ))
}

/// The output folder when this run created it (removed again if the experiment fails and
/// leaves it empty).
pub static CREATED_DIR: std::sync::Mutex<Option<PathBuf>> = std::sync::Mutex::new(None);

/// Creates the output folder.
pub fn out_dir(common: &CommonArgs) -> Result<&Path> {
    if !common.out_dir.exists() {
        if let Ok(mut c) = CREATED_DIR.lock() {
            *c = Some(common.out_dir.clone());
        }
    }
    std::fs::create_dir_all(&common.out_dir).map_err(|e| {
        crate::UserError(format!(
            "{}: cannot create the output folder: {e}",
            common.out_dir.display()
        ))
    })?;
    Ok(&common.out_dir)
}

/// Writes a CSV file (header line, then one row per record), whole or not at all.
pub fn write_csv(
    path: &Path,
    header: &[&str],
    rows: impl IntoIterator<Item = Vec<f64>>,
) -> Result<()> {
    let mut f = AtomicFile::create(path)?;
    let w = f.writer();
    writeln!(w, "{}", header.join(","))?;
    for row in rows {
        let cells: Vec<String> = row.iter().map(|x| format!("{x:?}")).collect();
        writeln!(w, "{}", cells.join(","))?;
    }
    f.commit()
}

/// A progress bar on standard error, only when it is a terminal.
pub struct Progress(Option<indicatif::ProgressBar>);

impl Progress {
    /// A bar of `len` steps with a label.
    pub fn new(len: u64, label: &str) -> Self {
        if !std::io::stderr().is_terminal() {
            return Progress(None);
        }
        let pb = indicatif::ProgressBar::new(len);
        if let Ok(style) = indicatif::ProgressStyle::with_template(&format!(
            "{label} {{bar:40}} {{pos}}/{{len}} {{elapsed}} (eta {{eta}})"
        )) {
            pb.set_style(style);
        }
        Progress(Some(pb))
    }

    /// Sets the position.
    pub fn set(&self, pos: u64) {
        if let Some(pb) = &self.0 {
            pb.set_position(pos);
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Some(pb) = &self.0 {
            pb.finish_and_clear();
        }
    }
}

/// Prints the summary: JSON on request, else the human text.
pub fn report<T: Serialize>(common: &CommonArgs, summary: &T, human: &str) -> Result<()> {
    if common.json {
        crate::print_line(&serde_json::to_string(summary)?);
    } else {
        crate::print_line(human);
    }
    Ok(())
}

/// Lists the files written, for the human summary.
pub fn files_line(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    format!("wrote: {}", names.join(", "))
}

/// A fluid of `n` equal discs (diameter 1, mass 1, kT = 1) at `packing`, melted from a lattice
/// by `melt` disc-disc collisions per disc, and its collision rate per disc per unit time
/// (measured while melting, to size the measuring runs); `None` when a stop was requested on
/// the way.
pub fn melted_fluid(
    n: usize,
    packing: f64,
    boundary: edmd_core::Boundary,
    seed: u64,
    melt: u64,
) -> Result<Option<(edmd_core::Simulation, f64)>> {
    melted_fluid_in::<2>(n, packing, boundary, seed, melt)
}

/// [`melted_fluid`] in `D` dimensions. Spheres come from the fluid generator (an FCC lattice
/// melted at a lower packing, compressed and checked), since a lattice of spheres near 0.5
/// need not melt by collisions alone; then `melt` more collisions per sphere measure the rate.
/// The generator and the construction are single calls that take minutes for millions of
/// discs, so they run [`interruptible`]; the melting looks at the stop flag between slices.
pub fn melted_fluid_in<const D: usize>(
    n: usize,
    packing: f64,
    boundary: edmd_core::Boundary,
    seed: u64,
    melt: u64,
) -> Result<Option<(edmd_core::Simulation<D>, f64)>> {
    let built = interruptible(move || {
        let (discs, bx) = if D == 3 {
            let fluid = edmd_core::setup::Fluid {
                n,
                packing,
                boundary,
                ..Default::default()
            };
            let (s, _) = fluid.generate_in::<D>(seed)?;
            (s.discs, s.sim_box)
        } else {
            edmd_core::setup::lattice_fluid_in::<D>(n, packing, boundary, seed)?
        };
        edmd_core::Simulation::new(&discs, bx, edmd_core::Options::default())
    })?;
    let mut sim = match built {
        None => return Ok(None),
        Some(sim) => sim.or_else(|e| crate::user_error(e.to_string()))?,
    };
    let (c0, t0) = (sim.stats().disc_disc, sim.time());
    while sim.stats().disc_disc - c0 < melt * n as u64 {
        if stop_requested() {
            return Ok(None);
        }
        crate::run_events(&mut sim, 10_000)?;
    }
    let rate = 2.0 * (sim.stats().disc_disc - c0) as f64
        / (n as f64 * (sim.time() - t0).max(f64::MIN_POSITIVE));
    Ok(Some((sim, rate)))
}

/// Runs `sim` for `collisions` more disc-disc collisions, in slices with a look at the stop
/// flag between them; `false` when a stop was requested first.
pub fn run_collisions<const D: usize>(
    sim: &mut edmd_core::Simulation<D>,
    collisions: u64,
) -> Result<bool> {
    let target = sim.stats().disc_disc.saturating_add(collisions);
    while sim.stats().disc_disc < target {
        if stop_requested() {
            return Ok(false);
        }
        crate::run_events(sim, 10_000)?;
    }
    Ok(true)
}

/// The lowest packing fraction of a melted fluid (the engine's generators refuse lower ones).
pub use edmd_core::setup::MIN_PACKING;

/// The most discs a command generates.
pub const MAX_N: usize = 10_000_000;

/// The most samples (or snapshots) an experiment or run keeps.
pub const MAX_SAMPLES: usize = 1_000_000;

/// Checks a list of packing fractions: each in `[MIN_PACKING, max)`.
pub fn check_packings(name: &str, packings: &[f64], max: f64) -> Result<()> {
    if packings.is_empty() {
        return crate::user_error(format!("{name}: give at least one packing fraction"));
    }
    if let Some(p) = packings.iter().find(|&&p| !(p >= MIN_PACKING && p < max)) {
        return crate::user_error(format!(
            "{name}: packing fraction {p:?} is outside [{MIN_PACKING}, {max})"
        ));
    }
    Ok(())
}

/// Checks a disc count: from `min` to [`MAX_N`].
pub fn check_n(name: &str, n: usize, min: usize) -> Result<()> {
    if !(min..=MAX_N).contains(&n) {
        return crate::user_error(format!(
            "{name}: --n must be from {min} to {MAX_N}, found {n}"
        ));
    }
    Ok(())
}

/// Checks a count option (samples, collisions per disc, ...): from `min` to `max`.
pub fn check_count(name: &str, flag: &str, value: u64, min: u64, max: u64) -> Result<()> {
    if !(min..=max).contains(&value) {
        return crate::user_error(format!(
            "{name}: --{flag} must be from {min} to {max}, found {value}"
        ));
    }
    Ok(())
}
