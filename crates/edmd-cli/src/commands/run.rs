//! `edmd run FILE --until T`: simulate a data file and write the final state.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;
use edmd_core::{
    CollisionRule, MultiContact, Observer, Options, OverlapPolicy, Simulation, Stats,
    OVERLAP_TOLERANCE,
};
use edmd_io::princeton::ColumnOrder;
use edmd_io::Format;
use serde::Serialize;

use crate::args::{ColumnsArg, FormatArg, RuleArg, RunArgs};
use edmd::checkpoint::{
    checkpoint_bytes, measure_names as names, read_checkpoint, read_extra, same_file,
    write_checkpoint, Measuring, MAX_STOPS, MAX_TRAJECTORY_BYTES,
};
use edmd::input::{build_seeded, read_any, DEFAULT_SEED};
use edmd::measure::Measure;
use edmd::output::{check_distinct, check_file_destinations, check_folder_destination, AtomicFile};
use edmd::user_error;

/// The run summary (`--json` prints it as one object).
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Input file.
    pub file: String,
    /// Input format.
    pub format: &'static str,
    /// Dimension (2: discs, 3: spheres).
    pub dim: usize,
    /// Number of discs.
    pub n: usize,
    /// End time.
    pub until: f64,
    /// Disc-disc collisions.
    pub disc_collisions: u64,
    /// Wall collisions.
    pub wall_collisions: u64,
    /// Cell crossings.
    pub cell_crossings: u64,
    /// Stale predictions discarded.
    pub stale_events: u64,
    /// Events at internal barriers.
    pub barrier_events: u64,
    /// Wall-clock seconds spent in the event loop.
    pub seconds: f64,
    /// Disc-disc collisions per second of wall-clock time.
    pub collisions_per_second: f64,
    /// `(E_end - E_start) / E_start` of the energy (kinetic, plus potential under a stepped
    /// potential, less the heat released by reactions, plus the energy lost in inelastic
    /// collisions).
    pub relative_energy_change: f64,
    /// Under a stepped potential: events at its steps (crossings and bounces).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_events: Option<u64>,
    /// Under a stepped potential: neighbour lists made again (its discs have no cell
    /// crossings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub neighbour_lists: Option<u64>,
    /// Under a stepped potential: the potential energy at the end.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub potential_energy: Option<f64>,
    /// With reaction rules: each rule and its reactions so far (from the run's start, a
    /// checkpoint's included).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reactions: Option<Vec<RuleCount>>,
    /// With reaction rules: the heat they released so far (into the discs' kinetic energy;
    /// negative: taken from it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reaction_heat: Option<f64>,
    /// With restitution: the kinetic energy lost in inelastic collisions so far (from the
    /// run's start, a checkpoint's included).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dissipated: Option<f64>,
    /// Under Lees-Edwards boundaries: the shear rate `du_x / dy`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shear_rate: Option<f64>,
    /// Under Lees-Edwards boundaries: the images' offset along x at the end, in `[0, L_x)`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shear_offset: Option<f64>,
    /// Under Lees-Edwards boundaries: the temperature of the velocities relative to the
    /// streaming profile at the end, `2 K' / (D N)` with `K'` the peculiar kinetic energy (the
    /// flow's own kinetic energy left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peculiar_kt: Option<f64>,
    /// On a ring patch: the orbital frequency `Omega` (its shear is `shear_rate`, `-3/2 Omega`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ring_omega: Option<f64>,
    /// On a ring patch: the velocity dispersion relative to the Keplerian flow at the end,
    /// `sqrt(2 K' / (N D))` (per axis, `K'` the peculiar kinetic energy; unit masses give the
    /// root mean square of each peculiar velocity component).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dispersion: Option<f64>,
    /// On a ring patch: the ring's potential energy at the end (tidal and vertical, see
    /// `Simulation::ring_energy`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ring_energy: Option<f64>,
    /// Under one-dimensional self-gravity: its coupling (`# edmd self-gravity C`); null
    /// without it.
    pub self_gravity: Option<f64>,
    /// Under self-gravity: the sheets' potential energy at the end, `U = sum over pairs of
    /// coupling m_i m_j |y_i - y_j|` (see `Simulation::self_gravity_energy`; it is counted in
    /// `relative_energy_change`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sheets_energy: Option<f64>,
    /// Under self-gravity: the virial ratio `2K/U` at the end (the virial theorem for a
    /// potential homogeneous of degree 1: `2<K> = <U>` on time averages).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub virial_ratio: Option<f64>,
    /// Discs moved into the box by `--allow-overlaps`.
    pub discs_moved_into_box: usize,
    /// Trajectory frames written.
    pub frames: u64,
}

/// A reaction rule and its reactions.
#[derive(Debug, Serialize)]
pub struct RuleCount {
    /// The rule as the file's `# edmd reaction` line writes it.
    pub rule: String,
    /// Its reactants' species.
    pub reactants: [u16; 2],
    /// Its products' species.
    pub products: [u16; 2],
    /// Reactions so far.
    pub reactions: u64,
}

/// Runs `edmd run`.
pub fn run(args: &RunArgs) -> Result<()> {
    check_options(args)?;
    if let Some(bytes) = read_checkpoint(Path::new(&args.file))? {
        return match edmd_core::checkpoint_dim(&bytes) {
            Ok(3) => resume::<3>(args, &bytes),
            Ok(1) => resume::<1>(args, &bytes),
            Ok(_) => resume::<2>(args, &bytes),
            Err(e) => user_error(format!("{}: {e}", args.file)),
        };
    }
    let order = match args.columns {
        None | Some(ColumnsArg::RadiusMass) => ColumnOrder::RadiusMass,
        Some(ColumnsArg::MassRadius) => ColumnOrder::MassRadius,
    };
    let format = match args.format {
        FormatArg::Auto => None,
        FormatArg::Course => Some(Format::Course),
        FormatArg::Princeton => Some(Format::Princeton(order)),
    };
    match read_any(&args.file, format, order, args.frame)? {
        edmd_io::AnyLoaded::Two(sys) => run_in(args, sys),
        edmd_io::AnyLoaded::Three(sys) => run_in(args, sys),
        edmd_io::AnyLoaded::One(sys) => run_in(args, sys),
    }
}

/// Runs a system read from the file, in its dimension.
fn run_in<const D: usize>(args: &RunArgs, sys: edmd_io::LoadedSystem<D>) -> Result<()> {
    if args.columns.is_some() && sys.format == Format::Course {
        return user_error(format!(
            "{}: --columns applies to the Princeton format, and this is a course file (N, R, Lx Ly, then x y u v)",
            args.file
        ));
    }
    let rule = match args.rule {
        Some(RuleArg::Elastic) => CollisionRule::Elastic,
        Some(RuleArg::Swap) => CollisionRule::Swap,
        None if sys.format == Format::Course => CollisionRule::Swap,
        None => CollisionRule::Elastic,
    };
    let overlaps = if args.allow_overlaps {
        OverlapPolicy::Allow
    } else {
        OverlapPolicy::Refuse
    };
    let multi = args.multi.then(MultiContact::default);
    if args.seed.is_some() && args.thermostat.is_none() && sys.reactions.is_empty() {
        return user_error(format!(
            "{}: --seed seeds the thermostat's redraws and the draws of reaction rules: give --thermostat, or a file with '# edmd reaction' lines",
            args.file
        ));
    }
    let mut sim = build_seeded(
        &args.file,
        &sys,
        Options {
            rule,
            overlaps,
            multi,
        },
        args.seed.unwrap_or(DEFAULT_SEED),
    )?;
    if sys.time != 0.0 {
        if args.until < sys.time {
            return user_error(format!(
                "{}: the state is at t = {} ('# edmd time'), after --until {}: give a later end time",
                args.file, sys.time, args.until
            ));
        }
        sim.start_at(sys.time)
            .or_else(|e| user_error(format!("{}: {e}", args.file)))?;
    }
    if let Some(bath) = args.andersen() {
        sim.set_thermostat(Some(bath))
            .or_else(|e| user_error(format!("{}: {e}", args.file)))?;
    }
    execute(args, sim, sys.format, None)
}

/// Continues a run from a checkpoint.
fn resume<const D: usize>(args: &RunArgs, bytes: &[u8]) -> Result<()> {
    let (sim, extra) = Simulation::<D>::from_checkpoint(bytes)
        .or_else(|e| user_error(format!("{}: {e}", args.file)))?;
    let unreadable = || {
        user_error(format!(
            "{}: {}",
            args.file,
            edmd::checkpoint::unreadable_extra(&extra)
        ))
    };
    let Some((format, measuring)) = read_extra::<D>(&extra) else {
        return unreadable();
    };
    check_carried(args, &sim, format)?;
    let measuring = match measuring {
        Some(m) if !m.fits(&sim) => return unreadable(),
        Some(m) => {
            let mut asked = args.measure.clone();
            asked.sort();
            asked.dedup();
            if !args.measure.is_empty() && asked != m.which {
                return user_error(format!(
                    "{}: --measure {} differs from the checkpoint's run (--measure {}), which goes on measuring: give those with --measure, or none",
                    args.file,
                    names(&asked),
                    names(&m.which)
                ));
            }
            if let Some(dt) = args.sample_every.filter(|dt| *dt != m.every) {
                return user_error(format!(
                    "{}: --sample-every {dt:?} differs from the checkpoint's run, which samples every {:?}: give that --sample-every, or none",
                    args.file, m.every
                ));
            }
            check_outputs(args, &m.which)?;
            Some(m)
        }
        None => None,
    };
    if args.until < sim.time() {
        return user_error(format!(
            "{}: the checkpoint is at t = {}, after --until {}: give a later end time",
            args.file,
            sim.time(),
            args.until
        ));
    }
    execute(args, sim, format, measuring)
}

/// Accepts the options a checkpoint carries when they are given again with the same value (the
/// same command line run again after a crash) and refuses a different value, naming the option
/// and both values. `--allow-overlaps` only decides how a file's discs are let in, which a
/// checkpoint's state has been already, so it changes nothing here and is accepted.
fn check_carried<const D: usize>(
    args: &RunArgs,
    sim: &Simulation<D>,
    format: Format,
) -> Result<()> {
    let differs = |option: String, carried: String| {
        user_error(format!(
            "{}: {option} differs from the checkpoint's run ({carried}): a checkpoint carries its run's options; drop {}",
            args.file,
            option.split(' ').next().unwrap_or_default()
        ))
    };
    let carried_format = match format {
        Format::Course => "course",
        Format::Princeton(_) => "princeton",
    };
    match (args.format, format) {
        (FormatArg::Auto, _)
        | (FormatArg::Course, Format::Course)
        | (FormatArg::Princeton, Format::Princeton(_)) => {}
        (given, _) => {
            return differs(
                format!("--format {}", value_name(given)),
                format!("--format {carried_format}"),
            )
        }
    }
    if let Some(columns) = args.columns {
        let want = match columns {
            ColumnsArg::RadiusMass => ColumnOrder::RadiusMass,
            ColumnsArg::MassRadius => ColumnOrder::MassRadius,
        };
        match format {
            Format::Princeton(order) if order == want => {}
            Format::Princeton(order) => {
                let carried = match order {
                    ColumnOrder::RadiusMass => ColumnsArg::RadiusMass,
                    ColumnOrder::MassRadius => ColumnsArg::MassRadius,
                };
                return differs(
                    format!("--columns {}", value_name(columns)),
                    format!("--columns {}", value_name(carried)),
                );
            }
            Format::Course => {
                return differs(
                    format!("--columns {}", value_name(columns)),
                    "a course file, which has no columns option".into(),
                )
            }
        }
    }
    if let Some(rule) = args.rule {
        let carried = match sim.rule() {
            CollisionRule::Elastic => RuleArg::Elastic,
            CollisionRule::Swap => RuleArg::Swap,
        };
        if rule != carried {
            return differs(
                format!("--rule {}", value_name(rule)),
                format!("--rule {}", value_name(carried)),
            );
        }
    }
    if args.multi {
        match sim.multi() {
            Some(mc) if mc == MultiContact::default() => {}
            Some(mc) => {
                return differs(
                    "--multi (tolerance 1e-3, exponent 1.5)".into(),
                    format!(
                        "multi-disc contacts with tolerance {:e}, exponent {}",
                        mc.tolerance, mc.exponent
                    ),
                )
            }
            None => return differs("--multi".into(), "binary collisions, no --multi".into()),
        }
    }
    if let Some(seed) = args.seed {
        let carried: Vec<u64> = [
            sim.thermostat().map(|a| a.seed),
            sim.reactions().map(|r| r.seed),
        ]
        .into_iter()
        .flatten()
        .collect();
        if carried.is_empty() {
            return user_error(format!(
                "{}: --seed seeds the thermostat's redraws and the draws of reaction rules, and the checkpoint's run has neither; drop --seed",
                args.file
            ));
        }
        if let Some(c) = carried.into_iter().find(|&c| c != seed) {
            return differs(format!("--seed {seed}"), format!("--seed {c}"));
        }
    }
    if let Some(asked) = args.andersen() {
        let name = |a: edmd_core::Andersen| {
            format!(
                "--thermostat andersen --kT {} --rate {} --seed {}",
                a.kt, a.rate, a.seed
            )
        };
        match sim.thermostat() {
            Some(carried) if carried == asked => {}
            Some(carried) => return differs(name(asked), name(carried)),
            None => return differs(name(asked), "no thermostat".into()),
        }
    }
    Ok(())
}

/// The name of an option's value, as the command line spells it.
fn value_name(v: impl clap::ValueEnum) -> String {
    v.to_possible_value()
        .map(|p| p.get_name().to_string())
        .unwrap_or_default()
}

/// Runs `sim` to `--until`, writing the outputs the options ask for.
///
/// `measuring` holds the measurements a checkpoint carried; without them, `--measure` starts
/// new ones now.
fn execute<const D: usize>(
    args: &RunArgs,
    mut sim: Simulation<D>,
    format: Format,
    measuring: Option<Measuring<D>>,
) -> Result<()> {
    let start_time = sim.time();
    edmd::check_until(&sim, &args.file, args.until)?;
    if measuring.is_none() {
        edmd::measure::Measurements::check(&sim, &args.measure)?;
    }
    check_stops(args, start_time)?;
    if let Some(m) = &measuring {
        check_samples(args, m)?;
    }
    check_trajectory_size(args, &sim)?;
    let start_collisions = sim.stats().disc_disc;
    // Create outputs before the run so that an unwritable path fails at once, not after it.
    let mut out_file = match args.output.as_deref() {
        Some("-") | None => None,
        Some(p) => Some(AtomicFile::create(Path::new(p))?),
    };
    let mut traj = match &args.trajectory {
        Some(p) => Some(AtomicFile::create(p)?),
        None => None,
    };

    // Reactions turn heat into kinetic energy: what they released is taken off, so that the
    // change is the integration's alone.
    let energy = |sim: &Simulation<D>| {
        sim.kinetic_energy() + sim.potential_energy() - sim.reaction_heat() + sim.dissipated()
    };
    let e0 = energy(&sim);
    crate::commands::experiment::common::install_ctrlc();
    let progress = progress_bar(args.until);
    let started = Instant::now();
    let mut frames = 0u64;
    let mut m = measuring.unwrap_or_else(|| {
        let every = args
            .sample_every
            .unwrap_or((args.until - start_time) / 100.0);
        Measuring::new(&sim, &args.measure, every)
    });
    if m.which.is_empty() && (args.sample_every.is_some() || args.measure_dir.is_some()) {
        return user_error("--sample-every and --out-dir go with --measure");
    }
    let sample_dt = (!m.which.is_empty())
        .then_some(m.every)
        .filter(|d| *d > 0.0);
    // Frames and checkpoints at whole multiples of their interval in absolute time (a run
    // continued from a checkpoint at T0 goes on from the first multiple at or after T0);
    // samples at start + k * sample_every.
    let first = |dt: f64, after_start: bool| {
        let k = (start_time / dt).ceil();
        if after_start && k * dt <= start_time {
            k + 1.0
        } else {
            k
        }
    };
    let mut frame_k = args.every.map(|dt| first(dt, false)).unwrap_or(0.0);
    let mut next_frame = traj.as_ref().and(args.every).map(|dt| frame_k * dt);
    let mut ck_k = args
        .checkpoint_every
        .map(|dt| first(dt, true))
        .unwrap_or(0.0);
    let mut next_ck = args.checkpoint_every.map(|dt| ck_k * dt);
    let mut last_checkpoint: Option<(f64, &Path)> = None;
    loop {
        let next_sample = sample_dt
            .map(|_| m.next_sample())
            .filter(|t| *t <= args.until);
        let next = [next_frame, next_sample, next_ck]
            .into_iter()
            .flatten()
            .fold(f64::INFINITY, f64::min);
        if next > args.until {
            break;
        }
        if !run_to(&mut sim, next, &progress, &mut m.obs, &args.file)? {
            return stopped(&sim, last_checkpoint);
        }
        if next_frame == Some(next) {
            let t = traj.as_mut().expect("frames only with a trajectory");
            edmd_io::xyz::write_frame(t.writer(), &sim.discs(), sim.sim_box(), next)?;
            frames += 1;
            frame_k += 1.0;
            next_frame = args.every.map(|dt| frame_k * dt);
        }
        if next_sample == Some(next) {
            m.obs.sample(&sim);
            m.samples += 1;
        }
        if next_ck == Some(next) {
            if let Some(p) = &args.checkpoint {
                write_checkpoint(p, &checkpoint_bytes(&sim, format, Some(&m))?)?;
                last_checkpoint = Some((sim.time(), p.as_path()));
            }
            ck_k += 1.0;
            next_ck = args.checkpoint_every.map(|dt| ck_k * dt);
        }
    }
    if !run_to(&mut sim, args.until, &progress, &mut m.obs, &args.file)? {
        return stopped(&sim, last_checkpoint);
    }
    if let Some(p) = &args.checkpoint {
        write_checkpoint(p, &checkpoint_bytes(&sim, format, Some(&m))?)?;
    }
    let seconds = started.elapsed().as_secs_f64();
    if let Some(pb) = progress {
        pb.finish_and_clear();
    }
    if args.check {
        check(&sim)?;
    }

    let discs = sim.discs();
    let stats: Stats = sim.stats();
    let e1 = energy(&sim);
    let summary = Summary {
        file: args.file.clone(),
        dim: D,
        format: match format {
            Format::Course => "course",
            Format::Princeton(_) => "princeton",
        },
        n: sim.len(),
        until: args.until,
        disc_collisions: stats.disc_disc,
        wall_collisions: stats.wall,
        cell_crossings: stats.cell_crossing,
        stale_events: stats.stale,
        barrier_events: stats.barrier,
        seconds,
        collisions_per_second: if seconds > 0.0 {
            (stats.disc_disc - start_collisions) as f64 / seconds
        } else {
            0.0
        },
        relative_energy_change: if e0 != 0.0 { (e1 - e0) / e0.abs() } else { 0.0 },
        step_events: sim.is_stepped().then_some(stats.step),
        neighbour_lists: sim.is_stepped().then_some(stats.neighbour_list),
        potential_energy: sim.is_stepped().then(|| sim.potential_energy()),
        reactions: sim.reactions().map(|r| {
            r.rules
                .iter()
                .zip(sim.reaction_counts())
                .map(|(r, &count)| RuleCount {
                    rule: edmd_io::reaction::text(r),
                    reactants: [r.reactants.0, r.reactants.1],
                    products: [r.products.0, r.products.1],
                    reactions: count,
                })
                .collect()
        }),
        reaction_heat: sim.reactions().map(|_| sim.reaction_heat()),
        dissipated: sim.restitution().map(|_| sim.dissipated()),
        shear_rate: sim.shear().map(|s| s.rate),
        shear_offset: sim.shear().map(|s| s.offset),
        peculiar_kt: sim
            .shear()
            .filter(|_| !sim.is_empty())
            .map(|_| 2.0 * sim.peculiar_kinetic_energy() / (D * sim.len()) as f64),
        ring_omega: sim.ring().map(|r| r.omega),
        dispersion: sim
            .ring()
            .filter(|_| !sim.is_empty())
            .map(|_| (2.0 * sim.peculiar_kinetic_energy() / (D * sim.len()) as f64).sqrt()),
        ring_energy: sim.ring().map(|_| sim.ring_energy()),
        self_gravity: sim.self_gravity().map(|g| g.coupling),
        sheets_energy: sim.self_gravity().map(|_| sim.self_gravity_energy()),
        virial_ratio: sim
            .self_gravity()
            .map(|_| sim.self_gravity_energy())
            .filter(|&u| u > 0.0)
            .map(|u| 2.0 * sim.kinetic_energy() / u),
        discs_moved_into_box: sim.adjusted_discs(),
        frames,
    };

    if let Some(t) = traj {
        t.commit()?;
    }
    let to_stdout = args.output.as_deref() == Some("-");
    let hard = edmd_io::Interactions::HARD;
    let interactions = edmd_io::Interactions {
        potential: sim.potential().unwrap_or(hard.potential),
        reactions: sim.reactions().map_or(hard.reactions, |r| &r.rules),
        restitution: sim.restitution(),
        gravity: sim.gravity(),
        shear: sim.shear(),
        self_gravity: sim.self_gravity(),
    };
    let write_state = |mut w: &mut dyn Write| {
        edmd_io::write_full_ring(
            &mut w,
            &discs,
            sim.sim_box(),
            sim.barriers(),
            interactions,
            sim.ring(),
            format,
            sim.time(),
        )
    };
    if let Some(mut f) = out_file.take() {
        write_state(f.writer())?;
        f.commit()?;
    } else if to_stdout {
        let mut out = std::io::stdout().lock();
        write_state(&mut out)?;
        out.flush()?;
    }
    // The CSV files only where the user asked for them: without --out-dir the results are
    // only in the summary.
    let (measured, files) = match measure_dir(args) {
        _ if m.which.is_empty() => (serde_json::Value::Null, Vec::new()),
        Some(dir) => m.obs.finish(&sim, dir)?,
        None => (m.obs.results(&sim).0, Vec::new()),
    };
    let text = if args.json {
        let mut v = serde_json::to_value(&summary)?;
        if !measured.is_null() {
            v["measurements"] = measured;
        }
        serde_json::to_string(&v)?
    } else {
        let mut t = human(&summary);
        if !measured.is_null() {
            t += &format!(
                "\nmeasurements: {}",
                serde_json::to_string_pretty(&measured)?
            );
            t += &if files.is_empty() {
                "\nno files written (--out-dir DIR writes the time series as CSV files)".to_string()
            } else {
                format!(
                    "\n{}",
                    crate::commands::experiment::common::files_line(&files)
                )
            };
        }
        t
    };
    if to_stdout {
        eprintln!("{text}");
    } else {
        edmd::front::print_line(&text);
    }
    Ok(())
}

/// Ends a run stopped by a signal: exit status 130 and one line saying where it stopped and
/// what was kept (the last checkpoint written on the way, if any).
fn stopped<const D: usize>(sim: &Simulation<D>, checkpoint: Option<(f64, &Path)>) -> Result<()> {
    let kept = match checkpoint {
        Some((t, p)) => format!(
            "nothing written but the checkpoint at t = {t} in {} (edmd run {} --until T continues it)",
            p.display(),
            p.display()
        ),
        None => "nothing written".to_string(),
    };
    edmd::interrupted(format!("interrupted at t = {}: {kept}", sim.time()))
}

/// Checks the options against each other and every output against the input and the other
/// outputs, before anything is read or run.
fn check_options(args: &RunArgs) -> Result<()> {
    if args.json && args.output.as_deref() == Some("-") {
        return user_error(
            "--json and --output - would both write to standard output: write the state to a file, or drop --json",
        );
    }
    if args.trajectory.as_deref() == Some(Path::new("-")) {
        return user_error("--trajectory -: trajectories are written to a file; give a file name");
    }
    if args.checkpoint.as_deref() == Some(Path::new("-")) {
        return user_error("--checkpoint -: checkpoints are written to a file; give a file name");
    }
    check_outputs(args, &args.measure)
}

/// Refuses intervals that would make more than [`MAX_STOPS`] frames, samples or checkpoints
/// between the run's start (a file's `# edmd time` or a checkpoint's) and `--until`.
fn check_stops(args: &RunArgs, start: f64) -> Result<()> {
    let span = args.until - start;
    if let Some(every) = args.every {
        if span / every > MAX_STOPS {
            return user_error(format!(
                "--every {every:?}: {:.3e} trajectory frames from t = {start} to {} is too many (at most {MAX_STOPS:.0}): --every must be >= {:e}",
                span / every,
                args.until,
                span / MAX_STOPS
            ));
        }
    }
    if let Some(dt) = args.sample_every {
        if span / dt > MAX_STOPS {
            return user_error(format!(
                "--sample-every {dt:?}: {:.3e} samples from t = {start} to {} is too many (at most {MAX_STOPS:.0}): --sample-every must be >= {:e}",
                span / dt,
                args.until,
                span / MAX_STOPS
            ));
        }
    }
    if let Some(dt) = args.checkpoint_every {
        if span / dt > MAX_STOPS {
            return user_error(format!(
                "--checkpoint-every {dt:?}: {:.3e} checkpoints from t = {start} to {} is too many (at most {MAX_STOPS:.0})",
                span / dt,
                args.until
            ));
        }
    }
    Ok(())
}

/// Refuses to go on with measurements read from a checkpoint when they would take more than
/// [`MAX_STOPS`] samples in all by `--until`: the samples are kept in memory from the run's
/// start, so the first leg's limit counts from there on every leg too.
fn check_samples<const D: usize>(args: &RunArgs, m: &Measuring<D>) -> Result<()> {
    let total = (args.until - m.start) / m.every;
    if !m.which.is_empty() && total > MAX_STOPS {
        return user_error(format!(
            "{}: the checkpoint's measurements sample every {:?} from t = {}: {total:.3e} samples by --until {} is too many (at most {MAX_STOPS:.0}): give --until at most {:e}",
            args.file,
            m.every,
            m.start,
            args.until,
            m.start + MAX_STOPS * m.every
        ));
    }
    Ok(())
}

/// Refuses a `--trajectory` whose frames would take more than [`MAX_TRAJECTORY_BYTES`],
/// estimated before any work as the number of frames times the size of the first (written to
/// a counter, not a file): every frame has the same lines, with numbers of about the same
/// length.
fn check_trajectory_size<const D: usize>(args: &RunArgs, sim: &Simulation<D>) -> Result<()> {
    let (Some(path), Some(every)) = (&args.trajectory, args.every) else {
        return Ok(());
    };
    let start = sim.time();
    let frames = ((args.until / every).floor() - (start / every).ceil() + 1.0).max(0.0);
    if frames == 0.0 {
        return Ok(());
    }
    struct Count(u64);
    impl Write for Count {
        fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
            self.0 += b.len() as u64;
            Ok(b.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let mut count = Count(0);
    // A species the format cannot name fails here as it would at the first frame.
    edmd_io::xyz::write_frame(&mut count, &sim.discs(), sim.sim_box(), start)
        .or_else(|e| user_error(format!("--trajectory {}: {e}", path.display())))?;
    let bytes = frames * count.0 as f64;
    if bytes > MAX_TRAJECTORY_BYTES {
        return user_error(format!(
            "--trajectory {}: about {bytes:.2e} bytes ({frames:.0} frames of {} bytes) is more than a trajectory may take ({MAX_TRAJECTORY_BYTES:.0e} bytes, 100 GB): raise --every or write it in parts through --checkpoint",
            path.display(),
            count.0
        ));
    }
    Ok(())
}

/// Checks that no output (the final state, the trajectory, the CSV files of the measurements
/// `which`, the checkpoint) is the input or another output.
fn check_outputs(args: &RunArgs, which: &[Measure]) -> Result<()> {
    let csvs: Vec<PathBuf> = match measure_dir(args) {
        Some(dir) => which
            .iter()
            .flat_map(|m| m.files().iter().map(|f| dir.join(f)))
            .collect(),
        None => Vec::new(),
    };
    let mut outputs: Vec<(&str, &Path)> = Vec::new();
    if let Some(o) = args.output.as_deref() {
        outputs.push(("--output", Path::new(o)));
    }
    if let Some(t) = &args.trajectory {
        outputs.push(("--trajectory", t));
    }
    for c in &csvs {
        outputs.push(("a --measure file", c));
    }
    // A checkpoint may replace the checkpoint it continues from (atomically), but no other
    // input and no other output.
    let input = Path::new(&args.file);
    let continuing_in_place = args
        .checkpoint
        .as_deref()
        .is_some_and(|c| same_file(c, input) && read_checkpoint(input).ok().flatten().is_some());
    if let Some(c) = &args.checkpoint {
        if !continuing_in_place {
            outputs.push(("--checkpoint", c));
        } else {
            check_distinct(&[("the checkpoint", c.as_path())], &outputs)?;
        }
    }
    check_distinct(&[("the input file", input)], &outputs)?;
    // The measurement files' folder is made by the run; the other outputs' must exist.
    let files: Vec<(&str, &Path)> = outputs
        .iter()
        .copied()
        .filter(|(_, path)| !csvs.iter().any(|c| c == path))
        .collect();
    check_file_destinations(&files)?;
    if let (false, Some(dir)) = (csvs.is_empty(), measure_dir(args)) {
        if let Some((what, _)) = files.iter().find(|(_, p)| *p == dir) {
            return edmd::user_error(format!(
                "{}: --out-dir names the file {what} writes; give the folder another name",
                dir.display()
            ));
        }
        check_folder_destination("--out-dir", dir)?;
    }
    Ok(())
}

/// The folder for the measurements' CSV files: only the one the user named (`--out-dir`), for
/// no file is written that the user did not ask for.
fn measure_dir(args: &RunArgs) -> Option<&Path> {
    args.measure_dir.as_deref()
}

/// What the particles of a `dim`-dimensional system are called, one or many.
fn particles(dim: usize, many: bool) -> &'static str {
    match (dim, many) {
        (1, false) => "rod",
        (1, true) => "rods",
        (3, false) => "sphere",
        (3, true) => "spheres",
        (_, false) => "disc",
        (_, true) => "discs",
    }
}

fn human(s: &Summary) -> String {
    let mut t = format!(
        "{}: {} {} ({} format) simulated to t = {}\nevents: {} disc-disc, {} wall, {} cell crossings ({} stale predictions discarded)\nspeed: {:.3e} collisions per second ({:.3} s in the event loop)\nenergy: relative change {:.3e}",
        s.file,
        s.n,
        particles(s.dim, true),
        s.format,
        s.until,
        s.disc_collisions,
        s.wall_collisions,
        s.cell_crossings,
        s.stale_events,
        s.collisions_per_second,
        s.seconds,
        s.relative_energy_change
    );
    if s.barrier_events > 0 {
        t += &format!("\nbarriers: {} events", s.barrier_events);
    }
    if let (Some(steps), Some(u), Some(lists)) =
        (s.step_events, s.potential_energy, s.neighbour_lists)
    {
        t += &format!(
            "\nsteps: {steps} events, {lists} neighbour lists made again; potential energy at the end {u}"
        );
    }
    if let (Some(rules), Some(heat)) = (&s.reactions, s.reaction_heat) {
        let each: Vec<String> = rules
            .iter()
            .map(|r| format!("{} by {}", r.reactions, r.rule))
            .collect();
        t += &format!("\nreactions: {}; heat released {heat}", each.join(", "));
    }
    if let Some(lost) = s.dissipated {
        t += &format!("\ninelastic collisions: {lost} of kinetic energy lost");
    }
    if let (Some(omega), Some(offset)) = (s.ring_omega, s.shear_offset) {
        t += &format!(
            "\nring patch: Omega {omega} (shear rate {}), images' offset {offset} at the end",
            -1.5 * omega
        );
        if let Some(c) = s.dispersion {
            t += &format!("; velocity dispersion {c:.6} about the Keplerian flow");
        }
    } else if let (Some(rate), Some(offset)) = (s.shear_rate, s.shear_offset) {
        t += &format!("\nshear: rate {rate}, images' offset {offset} at the end");
        if let Some(kt) = s.peculiar_kt {
            t += &format!("; kT {kt:.6} about the streaming profile");
        }
    }
    if let (Some(c), Some(u)) = (s.self_gravity, s.sheets_energy) {
        t += &format!("\nself-gravity: coupling {c}, sheets' potential energy {u} at the end");
        if let Some(v) = s.virial_ratio {
            t += &format!("; virial ratio 2K/U {v:.6}");
        }
    }
    if s.discs_moved_into_box > 0 {
        t += &format!(
            "\nmoved into the box: {} {}(s)",
            s.discs_moved_into_box,
            particles(s.dim, false)
        );
    }
    if s.frames > 0 {
        t += &format!("\ntrajectory: {} frames", s.frames);
    }
    t
}

/// Runs to time `t`, updating the progress bar, in chunks of events so that Ctrl-C is noticed
/// (then it returns `false` and the run is abandoned: nothing more is written, temporary files
/// are removed). Positions are computed on demand, so stopping between chunks does not change
/// the trajectory. A run whose clock stops advancing fails, naming the discs (`file` names the
/// input).
fn run_to<const D: usize, O: Observer<D>>(
    sim: &mut Simulation<D>,
    t: f64,
    progress: &Option<indicatif::ProgressBar>,
    obs: &mut O,
    file: &str,
) -> Result<bool> {
    const CHUNK: u64 = edmd::STOP_CHECK_EVENTS;
    loop {
        let more = sim.run_events_to(t, CHUNK, obs) == CHUNK;
        if let Some(s) = sim.stalled() {
            return edmd::user_error(format!("{file}: {s}; nothing written"));
        }
        if let Some(pb) = progress {
            let total = pb.length().unwrap_or(1) as f64;
            let until = pb.message().parse::<f64>().unwrap_or(t);
            pb.set_position((sim.time() / until * total) as u64);
        }
        if crate::commands::experiment::common::stop_requested() {
            return Ok(false);
        }
        if !more {
            break;
        }
    }
    sim.run_until(t, obs);
    Ok(true)
}

fn progress_bar(until: f64) -> Option<indicatif::ProgressBar> {
    if !std::io::stderr().is_terminal() || until <= 0.0 {
        return None;
    }
    let pb = indicatif::ProgressBar::new(1000);
    pb.set_message(format!("{until:?}"));
    pb.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {percent:>3}% of simulated time, {elapsed} elapsed, eta {eta}",
        )
        .expect("valid template"),
    );
    Some(pb)
}

/// Fails if any disc overlaps another or leaves the box.
pub fn check<const D: usize>(sim: &Simulation<D>) -> Result<()> {
    let (one, many) = (particles(D, false), particles(D, true));
    let o = sim.overlaps(OVERLAP_TOLERANCE);
    if let Some((i, j, ov)) = o.first {
        anyhow::bail!(
            "check failed: {many} {i} and {j} overlap by {ov:.3e} ({} pairs)",
            o.count
        );
    }
    let out = sim.discs_outside(OVERLAP_TOLERANCE);
    if let Some(i) = out.first() {
        anyhow::bail!(
            "check failed: {one} {i} is outside the box ({} {many})",
            out.len()
        );
    }
    Ok(())
}
