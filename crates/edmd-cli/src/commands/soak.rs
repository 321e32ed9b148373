//! `edmd soak`: a long run of a dense periodic fluid, checked every so often for what must
//! never happen however long a run lasts: overlaps beyond tolerance, discs outside the box, a
//! drift of the kinetic energy or the momentum, a clock that goes backwards or stops, and memory
//! that grows. RELIABILITY.md records a run of 10^9 collisions; CI runs a short one.

use std::time::Instant;

use anyhow::Result;
use clap::Args;
use edmd_core::setup::lattice::{close_packing, lattice_fluid_in};
use edmd_core::{Boundary, Options, Simulation, Vector, OVERLAP_TOLERANCE};
use serde::Serialize;

use crate::args::{parse_count, parse_dim_with_rods, parse_positive};
use crate::commands::experiment::common::{check_n, check_packings};
use edmd::user_error;

/// `edmd soak`.
#[derive(Debug, Args)]
pub struct SoakArgs {
    /// Dimension: 1 (rods on a line), 2 (discs) or 3 (spheres).
    #[arg(long, default_value_t = 2, value_parser = parse_dim_with_rods)]
    pub dim: usize,
    /// Number of discs (spheres in 3D).
    #[arg(long, default_value_t = 10_000, value_parser = parse_count)]
    pub n: usize,
    /// Packing fraction of the fluid (default 0.6 for rods and discs, 0.45 for spheres).
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub packing: Option<f64>,
    /// Disc-disc collisions to run in all (`1e9` is accepted).
    #[arg(long, default_value = "1e9", value_parser = parse_total)]
    pub collisions: u64,
    /// Number of checks, evenly spread over the run.
    #[arg(long, default_value_t = 100, value_parser = parse_count)]
    pub checks: usize,
    /// Random seed for the velocities.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// Print the summary as one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// A whole number of collisions from 1 to 10^13, written plainly or as `1e9`.
fn parse_total(s: &str) -> Result<u64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.fract() == 0.0 && (1.0..=1e13).contains(&x) => Ok(x as u64),
        _ => Err(format!(
            "must be a whole number from 1 to 1e13, found '{s}'"
        )),
    }
}

/// Bounds on what a check may find. Energy and momentum are compared with the start; rounding
/// adds up like a random walk, so 10^9 collisions at 1e-16 each stay far below these.
const MAX_ENERGY_DRIFT: f64 = 1e-9;
/// Momentum drift relative to `sqrt(N m kT)`, the momentum of one thermal fluctuation.
const MAX_MOMENTUM_DRIFT: f64 = 1e-9;
/// Resident memory may grow by this much over the first check's (allocator noise).
const MAX_MEMORY_GROWTH: f64 = 0.05;

/// What one check reads off the simulation.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Reading {
    /// Disc-disc collisions so far.
    pub collisions: u64,
    /// Simulated time.
    pub time: f64,
    /// Pairs closer than `sigma (1 - OVERLAP_TOLERANCE)`.
    pub overlaps: usize,
    /// Discs outside the box.
    pub outside: usize,
    /// `|E - E0| / E0`.
    pub energy_drift: f64,
    /// `|P - P0| / sqrt(N m kT)`.
    pub momentum_drift: f64,
    /// Resident memory in bytes (VmRSS), when the system tells it.
    pub rss_bytes: Option<u64>,
}

/// What is wrong with `now`, given the previous reading and the first one (empty: nothing).
pub fn judge(now: &Reading, previous: Option<&Reading>, first: Option<&Reading>) -> Vec<String> {
    let mut wrong = Vec::new();
    if now.overlaps > 0 {
        wrong.push(format!("{} overlapping pairs", now.overlaps));
    }
    if now.outside > 0 {
        wrong.push(format!("{} discs outside the box", now.outside));
    }
    if now.energy_drift.is_nan() || now.energy_drift > MAX_ENERGY_DRIFT {
        wrong.push(format!(
            "kinetic energy drifted by {:e} (at most {MAX_ENERGY_DRIFT:e})",
            now.energy_drift
        ));
    }
    if now.momentum_drift.is_nan() || now.momentum_drift > MAX_MOMENTUM_DRIFT {
        wrong.push(format!(
            "momentum drifted by {:e} of a thermal fluctuation (at most {MAX_MOMENTUM_DRIFT:e})",
            now.momentum_drift
        ));
    }
    if let Some(p) = previous {
        if now.time.is_nan() || now.time <= p.time {
            wrong.push(format!(
                "the clock did not advance: t = {} after t = {}",
                now.time, p.time
            ));
        }
        if now.collisions <= p.collisions {
            wrong.push("no collisions since the last check".into());
        }
    }
    if let (Some(f), Some(rss)) = (first.and_then(|f| f.rss_bytes), now.rss_bytes) {
        if rss as f64 > f as f64 * (1.0 + MAX_MEMORY_GROWTH) {
            wrong.push(format!(
                "resident memory grew from {f} to {rss} bytes (more than {}%)",
                MAX_MEMORY_GROWTH * 100.0
            ));
        }
    }
    wrong
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct SoakSummary {
    /// Dimension.
    pub dim: usize,
    /// Number of discs.
    pub n: usize,
    /// Packing fraction.
    pub packing: f64,
    /// Checks made.
    pub checks: usize,
    /// The last reading.
    pub last: Reading,
    /// Largest energy drift seen.
    pub max_energy_drift: f64,
    /// Largest momentum drift seen.
    pub max_momentum_drift: f64,
    /// Resident memory at the first and the last check, bytes.
    pub rss_first_last: Option<(u64, u64)>,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Collisions per second of wall-clock time, checks included.
    pub collisions_per_second: f64,
    /// `true`: every check passed.
    pub ok: bool,
}

/// Runs `edmd soak`.
pub fn run(args: &SoakArgs) -> Result<()> {
    match args.dim {
        1 => soak::<1>(args),
        3 => soak::<3>(args),
        _ => soak::<2>(args),
    }
}

fn soak<const D: usize>(args: &SoakArgs) -> Result<()> {
    let packing = args.packing.unwrap_or(if D == 3 { 0.45 } else { 0.6 });
    check_n("soak", args.n, 2)?;
    check_packings("soak", &[packing], close_packing(D))?;
    // Each check needs collisions since the one before: more checks than collisions would
    // find the clock "stopped" between two of them.
    if args.checks == 0 || args.checks as u64 > args.collisions {
        return user_error(format!(
            "soak: --checks must be from 1 to --collisions ({}), found {}",
            args.collisions, args.checks
        ));
    }
    let (discs, sim_box) = lattice_fluid_in::<D>(args.n, packing, Boundary::Periodic, args.seed)
        .or_else(|e| user_error(format!("soak: {e}")))?;
    let mut sim = Simulation::new(&discs, sim_box, Options::default())
        .or_else(|e| user_error(format!("soak: {e}")))?;
    drop(discs);
    let e0 = sim.kinetic_energy();
    let p0 = sim.momentum();
    // sqrt(N m kT) with kT = 2E/(D N): the size of one thermal momentum fluctuation.
    let m = (0..sim.len()).map(|i| sim.mass(i)).sum::<f64>() / sim.len() as f64;
    let p_scale = (m * 2.0 * e0 / D as f64).sqrt();
    let started = Instant::now();
    let (mut first, mut previous): (Option<Reading>, Option<Reading>) = (None, None);
    let (mut max_e, mut max_p) = (0.0f64, 0.0f64);
    let mut failures = Vec::new();
    for k in 1..=args.checks {
        let target = (args.collisions as u128 * k as u128 / args.checks as u128) as u64;
        while sim.stats().disc_disc < target {
            if crate::commands::experiment::common::stop_requested() {
                return edmd::interrupted(format!(
                    "soak: interrupted at {} collisions, after {} of {} checks (all passed)",
                    sim.stats().disc_disc,
                    k - 1,
                    args.checks
                ));
            }
            let left = target - sim.stats().disc_disc;
            // A clock that stops is an error here too (named discs, exit status 2). Slices of
            // STOP_CHECK_EVENTS so that a signal is heeded within a fraction of a second even
            // for millions of spheres, where each event misses the caches.
            edmd::run_events(&mut sim, left.clamp(1, edmd::STOP_CHECK_EVENTS))?;
        }
        let reading = read(&sim, e0, p0, p_scale);
        max_e = max_e.max(reading.energy_drift);
        max_p = max_p.max(reading.momentum_drift);
        failures = judge(&reading, previous.as_ref(), first.as_ref());
        if !args.json || std::io::IsTerminal::is_terminal(&std::io::stderr()) {
            eprintln!(
                "soak: check {k}/{}: {} collisions, t = {:.6e}, energy drift {:.1e}, momentum drift {:.1e}, rss {} MB{}",
                args.checks,
                reading.collisions,
                reading.time,
                reading.energy_drift,
                reading.momentum_drift,
                reading.rss_bytes.map_or("?".into(), |b| format!("{:.1}", b as f64 / 1e6)),
                if failures.is_empty() { String::new() } else { format!(": FAILED: {}", failures.join("; ")) }
            );
        }
        first.get_or_insert(reading);
        previous = Some(reading);
        if !failures.is_empty() {
            break;
        }
    }
    let last = previous.expect("at least one check");
    let seconds = started.elapsed().as_secs_f64();
    let summary = SoakSummary {
        dim: D,
        n: sim.len(),
        packing,
        checks: args.checks,
        last,
        max_energy_drift: max_e,
        max_momentum_drift: max_p,
        rss_first_last: first.and_then(|f| f.rss_bytes).zip(last.rss_bytes),
        seconds,
        collisions_per_second: last.collisions as f64 / seconds.max(1e-9),
        ok: failures.is_empty(),
    };
    if args.json {
        edmd::front::print_line(&serde_json::to_string(&summary)?);
    } else {
        edmd::front::print_line(&format!(
            "soak: {} {} at packing {packing}: {} collisions to t = {:.6e} in {:.0} s ({:.3e}/s); largest energy drift {:.1e}, momentum drift {:.1e}; {}",
            sim.len(),
            ["rods", "discs", "spheres"][D - 1],
            last.collisions,
            last.time,
            seconds,
            summary.collisions_per_second,
            max_e,
            max_p,
            if summary.ok { "every check passed" } else { "FAILED" }
        ));
    }
    if !failures.is_empty() {
        anyhow::bail!("soak: check failed: {}", failures.join("; "));
    }
    Ok(())
}

fn read<const D: usize>(sim: &Simulation<D>, e0: f64, p0: Vector<D>, p_scale: f64) -> Reading {
    Reading {
        collisions: sim.stats().disc_disc,
        time: sim.time(),
        overlaps: sim.overlaps(OVERLAP_TOLERANCE).count,
        outside: sim.discs_outside(OVERLAP_TOLERANCE).len(),
        energy_drift: ((sim.kinetic_energy() - e0) / e0).abs(),
        momentum_drift: (sim.momentum() - p0).norm2().sqrt() / p_scale,
        rss_bytes: rss_bytes(),
    }
}

/// VmRSS from /proc/self/status (Linux), in bytes.
fn rss_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn good(collisions: u64, time: f64) -> Reading {
        Reading {
            collisions,
            time,
            overlaps: 0,
            outside: 0,
            energy_drift: 1e-14,
            momentum_drift: 1e-13,
            rss_bytes: Some(100 << 20),
        }
    }

    /// Each thing a check looks for is caught, alone, and a sound reading passes.
    #[test]
    fn each_violation_is_caught() {
        let first = good(10, 1.0);
        assert!(judge(&good(20, 2.0), Some(&first), Some(&first)).is_empty());
        type Spoil = fn(&mut Reading);
        let cases: [(&str, Spoil); 7] = [
            ("overlapping", |r| r.overlaps = 3),
            ("outside", |r| r.outside = 1),
            ("kinetic energy", |r| r.energy_drift = 1e-6),
            ("momentum", |r| r.momentum_drift = f64::NAN),
            ("clock", |r| r.time = 1.0),
            ("no collisions", |r| r.collisions = 10),
            ("memory", |r| r.rss_bytes = Some(120 << 20)),
        ];
        for (what, spoil) in cases {
            let mut r = good(20, 2.0);
            spoil(&mut r);
            let wrong = judge(&r, Some(&first), Some(&first));
            assert_eq!(wrong.len(), 1, "{what}: {wrong:?}");
            assert!(wrong[0].contains(what), "{what}: {wrong:?}");
        }
    }

    #[test]
    fn totals_accept_exponent_notation() {
        assert_eq!(parse_total("1e9"), Ok(1_000_000_000));
        assert_eq!(parse_total("2000"), Ok(2000));
        assert!(parse_total("0").is_err());
        assert!(parse_total("1.5").is_err());
        assert!(parse_total("1e300").is_err());
    }
}
