//! `edmd bench`: the event loop's speed on a melted lattice fluid (discs, or spheres with
//! `--dim 3`), as one JSON line.

use std::time::Instant;

use anyhow::Result;
use edmd_core::setup::lattice::{close_packing, lattice_fluid_in};
use edmd_core::{Boundary, Options, Simulation};
use serde::Serialize;

use crate::args::{BenchArgs, BoundaryArg};
use edmd::user_error;

/// The JSON line.
#[derive(Debug, Serialize)]
pub struct BenchResult {
    /// Dimension (2: discs, 3: spheres).
    pub dim: usize,
    /// Number of discs.
    pub n: usize,
    /// Packing fraction.
    pub packing: f64,
    /// `periodic` or `walls`.
    pub boundary: &'static str,
    /// Disc-disc collisions timed.
    pub collisions: u64,
    /// All events timed (collisions, wall bounces, cell crossings, step events, neighbour
    /// lists made again).
    pub events: u64,
    /// Events per second.
    pub events_per_second: f64,
    /// Under `--well`: the well's range, and the step events timed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub well: Option<f64>,
    /// Step events timed (crossings of and bounces at the well's edge).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_events: Option<u64>,
    /// Under `--well`: hard-core collisions and step events per second (the events DynamO
    /// counts).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pair_events_per_second: Option<f64>,
    /// Under `--well`: neighbour lists made again while timing (in place of cell crossings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub neighbour_lists: Option<u64>,
    /// Stale predictions discarded while timing.
    pub stale: u64,
    /// Wall-clock seconds of the timed event loop.
    pub seconds: f64,
    /// Wall-clock seconds to make the lattice, its velocities and the engine (cells, every
    /// disc's first prediction), before melting.
    pub setup_seconds: f64,
    /// Wall-clock seconds of melting (`--melt` collisions per disc).
    pub melt_seconds: f64,
    /// Disc-disc collisions per second.
    pub collisions_per_second: f64,
    /// Which copy of the event loop ran: `x86-64-v3` or `portable`.
    pub event_loop: &'static str,
    /// Cells per axis.
    pub grid: Vec<u32>,
    /// Bytes held by the engine's arrays, per disc.
    pub engine_bytes_per_disc: f64,
    /// Peak resident memory of the process (VmHWM), bytes per disc.
    pub peak_rss_bytes_per_disc: Option<f64>,
    /// Relative kinetic energy change over the whole run.
    pub relative_energy_change: f64,
}

/// Runs the benchmark.
pub fn run(args: &BenchArgs) -> Result<()> {
    let result = match args.dim {
        1 => bench::<1>(args)?,
        3 => bench::<3>(args)?,
        _ => bench::<2>(args)?,
    };
    edmd::front::print_line(&serde_json::to_string(&result)?);
    Ok(())
}

/// The benchmark in `D` dimensions.
fn bench<const D: usize>(args: &BenchArgs) -> Result<BenchResult> {
    let boundary = match args.boundary {
        BoundaryArg::Periodic => Boundary::Periodic,
        BoundaryArg::Walls => Boundary::Walls,
    };
    use crate::commands::experiment::common::{check_count, check_packings};
    if !(2..=MAX_BENCH_N).contains(&args.n) {
        return user_error(format!(
            "bench: --n must be from 2 to {MAX_BENCH_N}, found {}",
            args.n
        ));
    }
    let need = args.n as f64 * BYTES_PER_DISC_AT_PEAK[D - 1];
    if let Some(free) = available_bytes() {
        if need > free as f64 {
            return user_error(format!(
                "bench: {} {} need about {:.1} GB at peak and this machine has {:.1} GB available",
                args.n,
                if D == 3 { "spheres" } else { "discs" },
                need / 1e9,
                free as f64 / 1e9
            ));
        }
    }
    check_packings("bench", &[args.packing], close_packing(D))?;
    check_count("bench", "melt", args.melt, 0, 100_000)?;
    check_count("bench", "collisions", args.collisions, 1, 100_000)?;
    let started = Instant::now();
    let (mut discs, sim_box) =
        match lattice_fluid_in::<D>(args.n, args.packing, boundary, args.seed) {
            Ok(x) => x,
            Err(e) => return user_error(format!("bench: {e}")),
        };
    if args.kt != 1.0 {
        for d in &mut discs {
            d.vel = d.vel * args.kt.sqrt();
        }
    }
    let potential = match args.well {
        None => edmd_core::Potential::default(),
        Some(l) if l.is_finite() && l > 1.0 && l <= 10.0 => {
            edmd_core::Potential::single(0, 0, l, -1.0)
        }
        Some(l) => {
            return user_error(format!(
                "bench: --well must be above 1 and at most 10, found {l}"
            ))
        }
    };
    let mut sim =
        Simulation::with_potential_owned(discs, sim_box, &[], &potential, Options::default(), 0.0)
            .or_else(|e| user_error(format!("bench: {e}")))?;
    let setup_seconds = started.elapsed().as_secs_f64();
    let v3 = sim.set_portable_loop(args.portable);
    let e0 = sim.kinetic_energy() + sim.potential_energy();
    let melt = args.melt * args.n as u64;
    let started = Instant::now();
    while sim.stats().disc_disc < melt {
        edmd::run_events(&mut sim, 1 << 16)?;
    }
    let melt_seconds = started.elapsed().as_secs_f64();
    let before = sim.stats();
    let target = before.disc_disc + args.collisions * args.n as u64;
    let started = Instant::now();
    while sim.stats().disc_disc < target {
        edmd::run_events(&mut sim, 1 << 16)?;
    }
    let seconds = started.elapsed().as_secs_f64();
    let after = sim.stats();
    let collisions = after.disc_disc - before.disc_disc;
    let all =
        |s: edmd_core::Stats| s.disc_disc + s.wall + s.cell_crossing + s.step + s.neighbour_list;
    let events = all(after) - all(before);
    let pair_events = collisions + after.step - before.step;
    let result = BenchResult {
        dim: D,
        n: args.n,
        packing: args.packing,
        boundary: match boundary {
            Boundary::Periodic => "periodic",
            Boundary::Walls => "walls",
        },
        collisions,
        events,
        events_per_second: events as f64 / seconds,
        well: args.well,
        step_events: args.well.map(|_| after.step - before.step),
        pair_events_per_second: args.well.map(|_| pair_events as f64 / seconds),
        neighbour_lists: args
            .well
            .map(|_| after.neighbour_list - before.neighbour_list),
        stale: after.stale - before.stale,
        seconds,
        setup_seconds,
        melt_seconds,
        collisions_per_second: collisions as f64 / seconds,
        event_loop: if v3 { "x86-64-v3" } else { "portable" },
        grid: sim.grid_dims().to_vec(),
        engine_bytes_per_disc: sim.memory_bytes() as f64 / args.n as f64,
        peak_rss_bytes_per_disc: peak_rss_bytes().map(|b| b as f64 / args.n as f64),
        relative_energy_change: (sim.kinetic_energy() + sim.potential_energy() - e0) / e0.abs(),
    };
    Ok(result)
}

/// The most discs a bench takes: disc indices are 32-bit, and 2^31 discs already need about
/// 210 GB.
const MAX_BENCH_N: usize = 1 << 31;

/// Peak bytes per disc of a bench, with a margin, by dimension (BENCHMARKS.md, "Memory at
/// scale": 100 in 2D, 158 in 3D at 10^6).
const BYTES_PER_DISC_AT_PEAK: [f64; 3] = [115.0, 115.0, 175.0];

/// MemAvailable from /proc/meminfo (Linux), in bytes: a bench that cannot fit is refused
/// rather than stopped by the kernel halfway.
fn available_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = s.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// VmHWM from /proc/self/status (Linux), in bytes.
fn peak_rss_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
