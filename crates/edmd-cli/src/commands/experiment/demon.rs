//! `edmd experiment demon`: Maxwell's demon.
//!
//! A wall across the middle of the box with a door; the demon at the door lets a disc from the
//! left through only if its kinetic energy is above `fast` times the mean, and a disc from the
//! right only if it is below `slow` times the mean (`edmd_core::Demon`). The right side heats
//! up and the left side cools, with no work done on the gas: total energy is conserved. (The
//! demon pays in information: Landauer's `kT ln 2` per bit erased.)

use anyhow::Result;
use clap::Args;
use edmd_core::setup::generators::{generate, Diffusion2, GenKind, DIFFUSION2_PARTITION};
use edmd_core::{
    Barrier, BarrierHit, Demon, EventKind, EventRecord, Observer, Options, Simulation,
};
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_partitioned, files_line, interrupted_after, out_dir, outputs, report, stop_requested,
    write_csv, CommonArgs, Progress,
};

/// Options of `edmd experiment demon`.
#[derive(Debug, Args)]
pub struct DemonArgs {
    /// Discs per side.
    #[arg(long, default_value_t = 200, allow_negative_numbers = true)]
    pub n: usize,
    /// Width of the door (the box is 1 x 1).
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    pub door: f64,
    /// Left-to-right threshold: kinetic energy relative to the mean.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub fast: f64,
    /// Right-to-left threshold: kinetic energy relative to the mean.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub slow: f64,
    /// Simulated time (discs move about 0.01 per unit time).
    #[arg(long, default_value_t = 5000.0, allow_negative_numbers = true)]
    pub until: f64,
    /// Samples over the run.
    #[arg(long, default_value_t = 100, allow_negative_numbers = true)]
    pub samples: usize,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

#[derive(Default)]
struct Door {
    passed: u64,
    shut: u64,
}

impl Observer for Door {
    fn on_event(&mut self, e: &EventRecord, _: &Simulation) {
        match e.kind {
            EventKind::Barrier {
                hit: BarrierHit::DoorPassed,
                ..
            } => self.passed += 1,
            EventKind::Barrier {
                hit: BarrierHit::DoorShut,
                ..
            } => self.shut += 1,
            _ => {}
        }
    }
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Simulated time reached.
    pub time: f64,
    /// Temperature kT of the left and right sides at the start.
    pub start: [f64; 2],
    /// Temperature kT of the left and right sides at the end.
    pub end: [f64; 2],
    /// Discs on the left and right at the end.
    pub discs: [usize; 2],
    /// Discs the demon let through, and discs it turned back.
    pub passed: u64,
    /// Discs turned back at the door.
    pub shut: u64,
    /// Relative change of the total kinetic energy (the demon does no work).
    pub relative_energy_change: f64,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

/// kT of the discs left and right of `x0`, and how many there are.
fn sides(sim: &Simulation, x0: f64) -> ([f64; 2], [usize; 2]) {
    let (mut e, mut n) = ([0.0; 2], [0usize; 2]);
    for i in 0..sim.len() {
        let s = (sim.position(i)[0] > x0) as usize;
        e[s] += 0.5 * sim.mass(i) * sim.velocity(i).norm2();
        n[s] += 1;
    }
    ([e[0] / n[0].max(1) as f64, e[1] / n[1].max(1) as f64], n)
}

/// Runs the experiment.
pub fn run(args: &DemonArgs) -> Result<()> {
    check_partitioned("demon", args.n, args.samples, args.until)?;
    // A disc goes through only if it touches neither edge of the door: a door no wider than
    // a disc lets none through.
    let diameter = 2.0 * Diffusion2::default().radius;
    if !(args.door > diameter && args.door < 1.0) {
        return edmd::user_error(format!(
            "demon: --door {} must be wider than a disc (diameter {diameter}) and narrower than the box height 1",
            args.door
        ));
    }
    if !(args.fast >= 0.0 && args.slow >= 0.0 && args.fast.is_finite() && args.slow.is_finite()) {
        return edmd::user_error("demon: --fast and --slow must be finite and >= 0");
    }
    let dir = out_dir(&args.common, &outputs(&["demon"], &["demon"]))?;
    let kind = GenKind::Diffusion2(Diffusion2 {
        n: args.n,
        ..Diffusion2::default()
    });
    let system =
        generate(&kind, args.common.seed).or_else(|e| edmd::user_error(format!("demon: {e}")))?;
    let x0 = DIFFUSION2_PARTITION;
    let door = Barrier {
        axis: 0,
        position: x0,
        door: Some((0.5 - args.door / 2.0, 0.5 + args.door / 2.0)),
        demon: Some(Demon {
            fast: args.fast,
            slow: args.slow,
        }),
    };
    let mut sim =
        Simulation::with_barriers(&system.discs, system.sim_box, &[door], Options::default())
            .or_else(|e| edmd::user_error(format!("demon: {e}")))?;
    let e0 = sim.kinetic_energy();
    let (start, _) = sides(&sim, x0);
    let mut series = vec![(0.0, start[0], start[1])];
    let mut watch = Door::default();
    let mut stopped = false;
    let progress = Progress::new(args.samples as u64, "demon");
    for k in 1..=args.samples {
        if stop_requested() {
            stopped = true;
            break;
        }
        if !edmd::run_until_or_stop(
            &mut sim,
            args.until * k as f64 / args.samples as f64,
            &mut watch,
        )? {
            stopped = true;
            break;
        }
        let (t, _) = sides(&sim, x0);
        series.push((sim.time(), t[0], t[1]));
        progress.set(k as u64);
    }
    progress.finish();
    let (end, discs) = sides(&sim, x0);
    let csv = dir.join("demon.csv");
    write_csv(
        &csv,
        &["time", "kT_left", "kT_right"],
        series.iter().map(|&(t, l, r)| vec![t, l, r]),
    )?;
    let (png, svg) = Figure::new(
        &format!(
            "Maxwell's demon: door {} wide, thresholds {} and {} of the mean",
            args.door, args.fast, args.slow
        ),
        "time",
        "temperature kT of each side",
    )
    .with(
        Series::line(
            "left (the demon lets only fast discs out)",
            series.iter().map(|&(t, l, _)| (t, l)).collect(),
        )
        .coloured([0, 0, 200]),
    )
    .with(
        Series::line(
            "right (the demon lets only slow discs out)",
            series.iter().map(|&(t, _, r)| (t, r)).collect(),
        )
        .coloured([200, 0, 0]),
    )
    .save(&dir.join("demon"))?;
    let summary = Summary {
        experiment: "demon",
        time: sim.time(),
        start,
        end,
        discs,
        passed: watch.passed,
        shut: watch.shut,
        relative_energy_change: (sim.kinetic_energy() - e0) / e0,
        interrupted: stopped,
    };
    let files = [csv, png, svg];
    let human = format!(
        "Maxwell's demon, {} discs per side, to t = {}:\n  kT left {:.3e} -> {:.3e}, right {:.3e} -> {:.3e} (ratio right/left {:.2})\n  {} discs let through, {} turned back; discs now left/right: {}/{}\n  total energy change {:.1e}\n{}",
        args.n, summary.time, start[0], end[0], start[1], end[1], end[1] / end[0], watch.passed, watch.shut, discs[0], discs[1], summary.relative_energy_change,
        files_line(&files)
    );
    report(&args.common, &summary, &human)?;
    if summary.interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}
