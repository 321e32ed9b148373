//! What every experiment shares: the output folder, CSV files, progress, Ctrl-C, the summary.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;
use serde::Serialize;

pub use edmd::output::write_csv;
pub use edmd::stop::{install_ctrlc, interruptible, stop_promptly, stop_requested, STOP_GRACE};

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

/// The one line an experiment stopped by a signal ends with (exit status
/// [`edmd::INTERRUPTED_STATUS`]), after it wrote the results so far.
pub fn interrupted_after(files: &[PathBuf]) -> Result<()> {
    if files.is_empty() {
        return edmd::interrupted("interrupted before any result: nothing written");
    }
    edmd::interrupted(format!(
        "interrupted: the results so far are written ({})",
        files_line(files)
    ))
}

/// Creates the output folder, after refusing (exit status 2, before any work) what would
/// make writing the results fail at the end, when the run's work would be lost: a `--out-dir`
/// that is not a folder, one of `files` (the files the experiment will write in it) that is a
/// folder or a link to a place that does not exist, and a folder that cannot be written (a
/// file is made in it and removed again).
pub fn out_dir<'a, S: AsRef<str>>(common: &'a CommonArgs, files: &[S]) -> Result<&'a Path> {
    let dir = &common.out_dir;
    let refuse = |why: String| {
        anyhow::Error::from(edmd::UserError(format!(
            "{}: --out-dir {why}",
            dir.display()
        )))
    };
    if dir.symlink_metadata().is_ok() && !dir.is_dir() {
        return Err(refuse(
            "is not a folder (a file, or a link to nothing); give a folder".into(),
        ));
    }
    for name in files {
        let path = dir.join(name.as_ref());
        if path.is_dir() {
            return edmd::user_error(format!(
                "{}: this experiment writes a file of that name, but it is a folder; \
                 move it or give another --out-dir",
                path.display()
            ));
        }
        if path.symlink_metadata().is_ok_and(|m| m.is_symlink()) && !path.exists() {
            return edmd::user_error(format!(
                "{}: this experiment writes a file of that name, but it is a link to a place that does not exist; \
                 remove it or give another --out-dir",
                path.display()
            ));
        }
    }
    edmd::stop::create_dir_remembered(dir).map_err(|e| refuse(format!("cannot be made: {e}")))?;
    let probe = dir.join(format!(".edmd-probe-{}.tmp", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
        }
        Err(e) => {
            edmd::stop::remove_created_dirs();
            return Err(refuse(format!("cannot be written in: {e}")));
        }
    }
    Ok(dir)
}

/// The names of the files an experiment writes: `stem.csv` for each of `tables` and
/// `stem.png` and `stem.svg` for each of `figures`.
pub fn outputs<S: AsRef<str>>(tables: &[S], figures: &[S]) -> Vec<String> {
    let tables = tables.iter().map(|t| format!("{}.csv", t.as_ref()));
    let figures = figures
        .iter()
        .flat_map(|f| [format!("{}.png", f.as_ref()), format!("{}.svg", f.as_ref())]);
    tables.chain(figures).collect()
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
/// The human text's numbers are written short (`1e-308`, not 308 digits: see
/// [`edmd::front::shorten_numbers`]), whatever options gave them.
pub fn report<T: Serialize>(common: &CommonArgs, summary: &T, human: &str) -> Result<()> {
    if common.json {
        edmd::front::print_line(&serde_json::to_string(summary)?);
    } else {
        edmd::front::print_line(&edmd::front::shorten_numbers(human));
    }
    Ok(())
}

/// Lists the files written, for the human summary.
pub fn files_line(paths: &[PathBuf]) -> String {
    if paths.is_empty() {
        return "nothing written".to_string();
    }
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
        Some(sim) => sim.or_else(|e| edmd::user_error(e.to_string()))?,
    };
    let (c0, t0) = (sim.stats().disc_disc, sim.time());
    while sim.stats().disc_disc - c0 < melt * n as u64 {
        if stop_requested() {
            return Ok(None);
        }
        edmd::run_events(&mut sim, 10_000)?;
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
        edmd::run_events(sim, 10_000)?;
    }
    Ok(true)
}

/// The lowest packing fraction of a melted fluid (the engine's generators refuse lower ones).
pub use edmd_core::setup::MIN_PACKING;

pub use edmd::MAX_N;

/// The most samples (or snapshots) an experiment or run keeps.
pub const MAX_SAMPLES: usize = 1_000_000;

/// Checks a list of packing fractions: each in `[MIN_PACKING, max)`.
pub fn check_packings(name: &str, packings: &[f64], max: f64) -> Result<()> {
    if packings.is_empty() {
        return edmd::user_error(format!("{name}: give at least one packing fraction"));
    }
    if let Some(p) = packings.iter().find(|&&p| !(p >= MIN_PACKING && p < max)) {
        // A bound a hair above 0.5 stands for "at most 0.5" (the sphere generator makes 0.50).
        let range = if (max - 0.5).abs() < 1e-6 {
            format!("[{MIN_PACKING}, 0.5]")
        } else {
            format!("[{MIN_PACKING}, {max})")
        };
        return edmd::user_error(format!("{name}: packing fraction {p:?} is outside {range}"));
    }
    check_once(name, "packing fraction", packings)
}

/// Refuses a list option that gives a value twice (`--packing 0.1,0.1`, or the option given
/// again: repeated list options add to the list): the point would be run twice and its
/// files written over.
/// Sorted first, so that a list of a million values is checked at once.
pub fn check_once<T: PartialOrd + std::fmt::Display>(
    name: &str,
    what: &str,
    values: &[T],
) -> Result<()> {
    let mut sorted: Vec<&T> = values.iter().collect();
    sorted.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    match sorted.windows(2).find(|w| w[0] == w[1]) {
        Some(w) => edmd::user_error(format!(
            "{name}: {what} {} is given twice; give each once",
            w[0]
        )),
        None => Ok(()),
    }
}

/// Checks a disc count: from `min` to [`MAX_N`].
pub fn check_n(name: &str, n: usize, min: usize) -> Result<()> {
    if !(min..=MAX_N).contains(&n) {
        return edmd::user_error(format!(
            "{name}: --n must be from {min} to {MAX_N}, found {n}"
        ));
    }
    Ok(())
}

/// Checks a count option (samples, collisions per disc, ...): from `min` to `max`.
pub fn check_count(name: &str, flag: &str, value: u64, min: u64, max: u64) -> Result<()> {
    if !(min..=max).contains(&value) {
        return edmd::user_error(format!(
            "{name}: --{flag} must be from {min} to {max}, found {value}"
        ));
    }
    Ok(())
}

/// Checks a span of simulated time (`--until`, `--follow`, `--times`): above 0 and at most
/// `max`, thousands of times the experiment's default and minutes to tens of minutes of
/// running, so that no run is asked for what no machine finishes (and Ctrl-C is not the only
/// way out of it).
pub fn check_span(name: &str, flag: &str, value: f64, max: f64) -> Result<()> {
    if !(value > 0.0 && value <= max) {
        return edmd::user_error(format!(
            "{name}: --{flag} must be above 0 and at most {max:e}, found {value}"
        ));
    }
    Ok(())
}

/// The checks `demon` and `diffusion` share: `n` discs on each side of the partitioned box
/// (from 2 to [`most_per_side`]), from 1 to [`MAX_SAMPLES`] samples, and `--until` at most
/// 10^7.
pub fn check_partitioned(name: &str, n: usize, samples: usize, until: f64) -> Result<()> {
    check_count(name, "n", n as u64, 2, most_per_side() as u64)?;
    check_count(name, "samples", samples as u64, 1, MAX_SAMPLES as u64)?;
    check_span(name, "until", until, 1e7)
}

/// The most discs of `radius` that random placement puts in a region of `area` of which
/// `taken` is covered already: more would cover over
/// [`edmd_core::setup::placement::MAX_RANDOM_FILL`] of it, which the generators refuse.
pub fn most_at_random(area: f64, taken: f64, radius: f64) -> usize {
    let fill = edmd_core::setup::placement::MAX_RANDOM_FILL * area - taken;
    (fill / (std::f64::consts::PI * radius * radius)).floor() as usize
}

/// The most discs on each side of the partition of `demon` and `diffusion`: the generator's
/// two-species box places Princeton's discs at random in each half of the unit box.
pub fn most_per_side() -> usize {
    most_at_random(
        0.5,
        0.0,
        edmd_core::setup::generators::Diffusion2::default().radius,
    )
}

/// Checks the size of a melted fluid in `D` dimensions: at least 16 discs, or the sphere
/// generator's [`edmd_core::setup::fluid::MIN_FLUID_DISCS`] spheres.
pub fn check_fluid_n<const D: usize>(name: &str, n: usize) -> Result<()> {
    let least = if D == 3 {
        edmd_core::setup::fluid::MIN_FLUID_DISCS
    } else {
        16
    };
    check_n(name, n, least)
}
