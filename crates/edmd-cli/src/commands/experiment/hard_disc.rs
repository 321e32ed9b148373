//! `edmd experiment hard-disc-transition`: the equation of state of hard discs across the
//! liquid-hexatic transition, `beta P d^2` against the packing fraction from 0.698 to 0.720 at
//! N = 256^2 in a square periodic box, against Engel et al.'s published EDMD and massively
//! parallel Monte Carlo (MPMC) values.
//!
//! Engel, Anderson, Glotzer, Isobe, Bernard and Krauth, "Hard-disk equation of state:
//! First-order liquid-hexatic transition in two dimensions with three simulation methods",
//! Phys. Rev. E 87, 042134 (2013), found a loop in the pressure between about 0.700 and 0.716
//! (a first-order liquid-hexatic transition), about 0.02 in `beta P d^2` on a baseline of 9.18
//! (0.2 %), shrinking as N grows. The numbers embedded here ([`REFERENCE`]) are theirs as
//! collected, "data provided by the authors", in the file `DigitizedData/Engel_2013/
//! Engel_2013.csv` of the repository jellyfysh/HistoricDisks (Li, Nishikawa, Höllmer, Carillo,
//! Maggs and Krauth, "Hard-disk computer simulations - a historic perspective", J. Chem. Phys.
//! 157, 234111 (2022)). There the unit is `beta P (2 sigma)^2` with `sigma` the radius, that is
//! `beta P d^2`.
//!
//! **The chain.** The packings run from the densest down. The densest starts from discs on a
//! centred rectangular lattice (`n_side` rows of `n_side`, odd rows shifted by half a spacing)
//! filling the square box; each next (lower) packing starts from the state the one above it
//! reached after its equilibration, expanded about the origin to the new box. An expansion moves
//! every pair apart, so no overlap can arise: the state is exact (a compression would not be).
//! Each point then runs `--equilibrate` disc-disc collisions per disc, then `--collisions` per
//! disc of production in `--blocks` blocks of equal collision counts.
//!
//! **The measurement.** Each block's compressibility factor from the collision virial,
//! `Z = 1 + sum r_ij . J_ij / (2 t N kT)` (Alder and Wainwright 1960), and
//! `beta P d^2 = Z rho d^2 = Z 4 eta / pi`. The value is the time-weighted mean over the blocks,
//! its error the blocks' standard deviation over `sqrt(blocks)`. Near coexistence the blocks are
//! correlated over far longer than a block, so this error is a lower bound until the blocks
//! themselves are long.
//!
//! **Checkpoints.** Each point's final state is written to `hard-disc-<packing>.checkpoint` in
//! the output folder: the engine's exact checkpoint, with, after its bytes, what this
//! experiment carries (the collisions so far, the blocks measured, the CPU time spent), block
//! values stored as their bits. `--resume` continues every point from its checkpoint (a packing
//! without one starts from the chain), adding `--collisions` per disc of blocks to those it has,
//! so a long study is a chain of runs of any length; the engine's checkpoints continue to the
//! bit, so a run resumed gives what one uninterrupted run of the same total gives. With
//! `--resume --equilibrate K` the blocks so far are dropped (counted as equilibration) and K
//! more collisions per disc are run before measuring again.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;
use clap::Args;
use edmd::output::AtomicFile;
use edmd_core::measure::{block_error, Pressure};
use edmd_core::setup::{lattice_fluid_in, psi6, Neighbours};
use edmd_core::{Boundary, Disc, Options, SimBox, Simulation, Vector};
use edmd_plot::{Figure, Series};
use serde::{Deserialize, Serialize};

use super::common::{
    check_count, files_line, interrupted_after, out_dir, outputs, report, stop_requested,
    write_csv, CommonArgs, Progress, MAX_N,
};

/// Options of `edmd experiment hard-disc-transition`.
#[derive(Debug, Args)]
pub struct HardDiscArgs {
    /// Discs per side: N = n_side^2 discs in a square periodic box (even, at least 4).
    #[arg(long, default_value_t = 256, allow_negative_numbers = true)]
    pub n_side: usize,
    /// Packing fractions, comma-separated, each in [0.30, 0.78] [default: 0.698,0.700,...,0.720].
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub packings: Option<Vec<f64>>,
    /// Disc-disc collisions per disc to run before measuring [default: 500; with --resume 0,
    /// and a number above 0 drops the blocks measured so far].
    #[arg(long, allow_negative_numbers = true)]
    pub equilibrate: Option<u64>,
    /// Disc-disc collisions per disc to measure over (added to those so far with --resume;
    /// 0 with --resume reports the checkpoints as they are, running nothing).
    #[arg(long, default_value_t = 1000, allow_negative_numbers = true)]
    pub collisions: u64,
    /// Blocks for the error bar, of equal collision counts, in this run's --collisions.
    #[arg(long, default_value_t = 20, allow_negative_numbers = true)]
    pub blocks: u64,
    /// Continue every point from its checkpoint in --out-dir.
    #[arg(long)]
    pub resume: bool,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// One packing of Engel et al. (2013) at N = 256^2 (EDMD and MPMC) and N = 1024^2 (MPMC),
/// square periodic box; `beta P d^2` with its error.
#[derive(Debug, Clone, Copy)]
pub struct Reference {
    /// Packing fraction.
    pub packing: f64,
    /// EDMD, N = 256^2, virial.
    pub edmd: (f64, f64),
    /// MPMC, N = 256^2, fitted g(r) at contact.
    pub mpmc: (f64, f64),
    /// MPMC, N = 1024^2.
    pub mpmc_1024: (f64, f64),
}

const fn r(packing: f64, edmd: (f64, f64), mpmc: (f64, f64), big: (f64, f64)) -> Reference {
    Reference {
        packing,
        edmd,
        mpmc,
        mpmc_1024: big,
    }
}

/// Engel et al., Phys. Rev. E 87, 042134 (2013), as collected in jellyfysh/HistoricDisks
/// (`DigitizedData/Engel_2013/Engel_2013.csv`, "data provided by the authors").
pub const REFERENCE: [Reference; 12] = [
    r(
        0.698,
        (9.17059, 0.00018),
        (9.170780, 0.000045),
        (9.169342, 0.000023),
    ),
    r(
        0.700,
        (9.18896, 0.00024),
        (9.187831, 0.000098),
        (9.185405, 0.000085),
    ),
    r(
        0.702,
        (9.19144, 0.00036),
        (9.191999, 0.000090),
        (9.18818, 0.00016),
    ),
    r(
        0.704,
        (9.18903, 0.00039),
        (9.18881, 0.00012),
        (9.18674, 0.00014),
    ),
    r(
        0.706,
        (9.18585, 0.00036),
        (9.185404, 0.000080),
        (9.18587, 0.00018),
    ),
    r(
        0.708,
        (9.18226, 0.00026),
        (9.18216, 0.00012),
        (9.184959, 0.000061),
    ),
    r(
        0.710,
        (9.17914, 0.00029),
        (9.17921, 0.00012),
        (9.18415, 0.00017),
    ),
    r(
        0.712,
        (9.17715, 0.00021),
        (9.17690, 0.00010),
        (9.183379, 0.000070),
    ),
    r(
        0.714,
        (9.17563, 0.00034),
        (9.175513, 0.000091),
        (9.18195, 0.00024),
    ),
    r(
        0.716,
        (9.17823, 0.00041),
        (9.17769, 0.00023),
        (9.18327, 0.00010),
    ),
    r(
        0.718,
        (9.18468, 0.00060),
        (9.18685, 0.00054),
        (9.19507, 0.00020),
    ),
    r(
        0.720,
        (9.22350, 0.00075),
        (9.248, 0.018),
        (9.23083, 0.00080),
    ),
];

/// The citation, for the summary and the figure.
pub const CITATION: &str = "Engel et al., Phys. Rev. E 87, 042134 (2013), via jellyfysh/HistoricDisks (Li et al., J. Chem. Phys. 157, 234111 (2022))";

/// The reference at `packing`, if it is one of the published ones.
pub fn reference(packing: f64) -> Option<&'static Reference> {
    REFERENCE
        .iter()
        .find(|r| (r.packing - packing).abs() < 1e-9)
}

/// `beta P d^2` from the compressibility factor at a packing fraction: `Z 4 eta / pi`.
pub fn pressure_from_z(z: f64, packing: f64) -> f64 {
    z * 4.0 * packing / std::f64::consts::PI
}

const DEFAULT_EQUILIBRATE: u64 = 500;
/// The tag of what this experiment writes after the engine's bytes in a checkpoint.
const CARRIED_FORMAT: &str = "edmd experiment hard-disc-transition 1";
/// Events per slice between looks at the stop flag.
const SLICE: u64 = 10_000;

/// What a point's checkpoint carries besides the engine's state (JSON, floats as their bits so
/// that a resumed run continues exactly).
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Carried {
    format: String,
    n_side: usize,
    /// The packing's bits.
    packing: u64,
    /// Disc-disc collisions this point's state has seen before its measured blocks, the
    /// chain's included (the points above it, before it was expanded).
    equilibration: u64,
    /// Disc-disc collisions in the blocks.
    production: u64,
    /// CPU seconds spent on this point, the bits of an f64.
    cpu_seconds: u64,
    /// The blocks: (duration, Z), the bits of f64s.
    blocks: Vec<[u64; 2]>,
}

impl Carried {
    /// What is wrong with a record read back, if anything: counts too large to add to (more
    /// than 10^18 collisions, which no run reaches), a CPU time or a block that is not a
    /// finite number (a block's duration must be above 0).
    fn fault(&self) -> Option<String> {
        const MOST: u64 = 1_000_000_000_000_000_000;
        let f = f64::from_bits;
        if self.equilibration > MOST || self.production > MOST {
            return Some(format!(
                "{} collisions of equilibration and {} of production",
                self.equilibration, self.production
            ));
        }
        let cpu = f(self.cpu_seconds);
        if !(cpu.is_finite() && cpu >= 0.0) {
            return Some(format!("CPU time {cpu:e} s"));
        }
        self.blocks.iter().enumerate().find_map(|(k, &[dt, z])| {
            let (dt, z) = (f(dt), f(z));
            (!(dt.is_finite() && dt > 0.0 && z.is_finite()))
                .then(|| format!("block {k} lasts {dt:e} with Z {z:e}"))
        })
    }
}

/// One packing.
#[derive(Debug, Serialize)]
pub struct Row {
    /// Packing fraction.
    pub packing: f64,
    /// Discs.
    pub n: usize,
    /// beta P d^2 from the collision virial.
    pub pressure: f64,
    /// Its block error (one standard deviation).
    pub pressure_error: f64,
    /// The compressibility factor P A / (N kT).
    #[serde(rename = "Z")]
    pub z: f64,
    /// Its block error.
    #[serde(rename = "Z_error")]
    pub z_error: f64,
    /// The global hexatic order |psi_6| (6 nearest neighbours) of the final state.
    pub psi6: f64,
    /// Engel et al.'s EDMD value at N = 256^2 (null off their packings).
    pub reference_edmd: Option<f64>,
    /// Its error.
    pub reference_edmd_error: Option<f64>,
    /// Engel et al.'s MPMC value at N = 256^2.
    pub reference_mpmc: Option<f64>,
    /// Its error.
    pub reference_mpmc_error: Option<f64>,
    /// Engel et al.'s MPMC value at N = 1024^2.
    pub reference_mpmc_1024: Option<f64>,
    /// (pressure - reference_edmd) over the two errors combined.
    pub deviation_sigmas: Option<f64>,
    /// The drift over the measurement: the pressure of the later half of the blocks less that
    /// of the earlier half, over their errors combined (null with fewer than 4 blocks). Well
    /// beyond 2 in size, the point was still relaxing as it was measured.
    pub drift_sigmas: Option<f64>,
    /// Disc-disc collisions per disc the state has seen in all: the chain's, equilibration and
    /// production, over every run so far.
    pub collisions_per_disc: f64,
    /// Of which measured over.
    pub production_per_disc: f64,
    /// Blocks measured.
    pub blocks: usize,
    /// CPU seconds spent on this point over every run so far.
    pub cpu_seconds: f64,
    /// The point's checkpoint.
    pub checkpoint: String,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Discs per side.
    pub n_side: usize,
    /// Discs.
    pub n: usize,
    /// True when the points were continued from their checkpoints.
    pub resumed: bool,
    /// Wall-clock seconds of this run.
    pub wall_seconds: f64,
    /// CPU seconds of this run (Linux; null elsewhere).
    pub cpu_seconds: Option<f64>,
    /// Disc-disc collisions in this run.
    pub collisions: u64,
    /// Of this run, per wall-clock second.
    pub collisions_per_second: f64,
    /// Of this run, per CPU second.
    pub collisions_per_cpu_second: Option<f64>,
    /// The reference data.
    pub reference: &'static str,
    /// One row per packing, in increasing packing.
    pub rows: Vec<Row>,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

/// CPU seconds of this process so far (user and system, from `/proc/self/stat`, in the
/// kernel's clock ticks of 1/100 s); `None` where that file is missing.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The fields after the command name, which is in parentheses and may hold spaces.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // utime and stime are fields 14 and 15 of the line, 12 and 13 after the name and state.
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    Some((utime + stime) / 100.0)
}

/// The checkpoint file of a packing.
fn checkpoint_path(dir: &Path, packing: f64) -> PathBuf {
    dir.join(checkpoint_name(packing))
}

/// The name of the checkpoint of the point at `packing`.
fn checkpoint_name(packing: f64) -> String {
    format!("hard-disc-{packing:.4}.checkpoint")
}

/// The side of the square box of `n` discs of diameter 1 at `packing`.
fn side(n: usize, packing: f64) -> f64 {
    (n as f64 * std::f64::consts::PI / (4.0 * packing)).sqrt()
}

/// The densest point's start: `n_side` rows of `n_side` discs, odd rows shifted by half a
/// spacing, filling the square box; thermal velocities at kT = 1 (the engine's lattice
/// generator's, whose positions are replaced).
fn lattice_start(n_side: usize, packing: f64, seed: u64) -> Result<Simulation> {
    let n = n_side * n_side;
    let (discs, _) = lattice_fluid_in::<2>(n, packing, Boundary::Periodic, seed)?;
    let l = side(n, packing);
    let a = l / n_side as f64;
    let discs: Vec<Disc> = discs
        .into_iter()
        .enumerate()
        .map(|(k, d)| {
            let (row, col) = (k / n_side, k % n_side);
            let shift = if row % 2 == 1 { 0.5 } else { 0.0 };
            Disc {
                pos: Vector::new([(col as f64 + 0.25 + shift) * a, (row as f64 + 0.5) * a]),
                ..d
            }
        })
        .collect();
    let sim_box = SimBox {
        lengths: [l, l],
        boundaries: [Boundary::Periodic; 2],
    };
    Ok(Simulation::new(&discs, sim_box, Options::default())?)
}

/// `discs` in a square box of side `from`, expanded about the origin into one of side `to`
/// (`to >= from`: every pair moves apart).
fn expanded(discs: &[Disc], from: f64, to: f64) -> Result<Simulation> {
    let s = to / from;
    let moved: Vec<Disc> = discs
        .iter()
        .map(|d| {
            // Rounding can put a disc at exactly `to`; the box is [0, to).
            let p = d.pos.0.map(|x| {
                let y = x * s;
                if y >= to {
                    y - to
                } else {
                    y
                }
            });
            Disc {
                pos: Vector::new(p),
                ..*d
            }
        })
        .collect();
    let sim_box = SimBox {
        lengths: [to, to],
        boundaries: [Boundary::Periodic; 2],
    };
    Ok(Simulation::new(&moved, sim_box, Options::default())?)
}

/// Runs exactly `collisions` more disc-disc collisions shown to `observer`, in slices with a
/// look at the stop flag between them; `false` when a stop was requested first.
fn run_counted<O: edmd_core::Observer<2>>(
    sim: &mut Simulation,
    collisions: u64,
    observer: &mut O,
) -> Result<bool> {
    let target = sim.stats().disc_disc.saturating_add(collisions);
    while sim.stats().disc_disc < target {
        if stop_requested() {
            return Ok(false);
        }
        // A collision is one event, so no more events than collisions to go: the count is
        // reached exactly, and blocks are equal whatever N.
        let k = sim.run_events(
            SLICE.min(target - sim.stats().disc_disc),
            &mut edmd::shared(observer),
        );
        edmd::check_stall(sim)?;
        if k == 0 {
            return edmd::user_error("hard-disc-transition: no disc moves");
        }
    }
    Ok(true)
}

/// Reads a point's checkpoint: the simulation and what the experiment carries.
fn read_point(path: &Path, n_side: usize, packing: f64) -> Result<(Simulation, Carried)> {
    let bytes = std::fs::read(path).map_err(|e| {
        edmd::UserError(format!(
            "{}: cannot read the checkpoint: {e}",
            path.display()
        ))
    })?;
    let (sim, extra) = Simulation::<2>::from_checkpoint(&bytes)
        .map_err(|e| edmd::UserError(format!("{}: {e}", path.display())))?;
    let carried: Carried = serde_json::from_slice(&extra)
        .ok()
        .filter(|c: &Carried| c.format == CARRIED_FORMAT)
        .ok_or_else(|| {
            edmd::UserError(format!(
                "{}: not a checkpoint of edmd experiment hard-disc-transition",
                path.display()
            ))
        })?;
    if carried.n_side != n_side || f64::from_bits(carried.packing) != packing {
        return edmd::user_error(format!(
            "{}: a checkpoint of {}^2 discs at packing {}, not {n_side}^2 at {packing}",
            path.display(),
            carried.n_side,
            f64::from_bits(carried.packing)
        ));
    }
    if let Some(what) = carried.fault() {
        return edmd::user_error(format!(
            "{}: the experiment's record in the checkpoint is damaged: {what}",
            path.display()
        ));
    }
    Ok((sim, carried))
}

/// Writes a point's checkpoint, whole or not at all.
fn write_point(path: &Path, sim: &Simulation, carried: &Carried) -> Result<()> {
    use std::io::Write;
    let bytes = sim.to_checkpoint(&serde_json::to_vec(carried)?);
    let mut f = AtomicFile::create(path)?;
    f.writer().write_all(&bytes)?;
    f.commit()
}

/// The time-weighted mean of the blocks' Z and its block error.
fn z_estimate(blocks: &[[u64; 2]]) -> (f64, f64) {
    let (mut weighted, mut elapsed) = (0.0, 0.0);
    let mut zs = Vec::with_capacity(blocks.len());
    for b in blocks {
        let (dt, z) = (f64::from_bits(b[0]), f64::from_bits(b[1]));
        weighted += z * dt;
        elapsed += dt;
        zs.push(z);
    }
    (weighted / elapsed, block_error(&zs))
}

/// The later half of the blocks' value less the earlier half's, over their block errors
/// combined (the middle block of an odd count in neither); `None` below 4 blocks.
fn drift_sigmas(blocks: &[[u64; 2]]) -> Option<f64> {
    let h = blocks.len() / 2;
    if h < 2 {
        return None;
    }
    let (early, e1) = z_estimate(&blocks[..h]);
    let (late, e2) = z_estimate(&blocks[blocks.len() - h..]);
    Some((late - early) / e1.hypot(e2))
}

fn check(args: &HardDiscArgs) -> Result<Vec<f64>> {
    let name = "hard-disc-transition";
    if !(args.n_side >= 4
        && args.n_side.is_multiple_of(2)
        && args
            .n_side
            .checked_mul(args.n_side)
            .is_some_and(|n| n <= MAX_N))
    {
        return edmd::user_error(format!(
            "{name}: --n-side must be even, at least 4 and at most {} (N = n_side^2 <= {MAX_N}), found {}",
            (MAX_N as f64).sqrt() as usize / 2 * 2,
            args.n_side
        ));
    }
    let mut packings = args
        .packings
        .clone()
        .unwrap_or_else(|| REFERENCE.iter().map(|r| r.packing).collect());
    if packings.is_empty() {
        return edmd::user_error(format!("{name}: give at least one packing fraction"));
    }
    if let Some(p) = packings.iter().find(|&&p| !(0.30..=0.78).contains(&p)) {
        return edmd::user_error(format!(
            "{name}: packing fraction {p:?} is outside [0.30, 0.78]"
        ));
    }
    // The chain runs from the densest down.
    packings.sort_by(|a, b| b.total_cmp(a));
    if let Some(w) = packings.windows(2).find(|w| w[0] == w[1]) {
        return edmd::user_error(format!("{name}: packing fraction {} is given twice", w[0]));
    }
    // The checkpoints are named by the packing to 4 decimals.
    if let Some(w) = packings
        .windows(2)
        .find(|w| format!("{:.4}", w[0]) == format!("{:.4}", w[1]))
    {
        return edmd::user_error(format!(
            "{name}: packing fractions {} and {} are the same to 4 decimals, which name the checkpoints",
            w[1], w[0]
        ));
    }
    check_count(
        name,
        "collisions",
        args.collisions,
        u64::from(!args.resume),
        10_000_000,
    )?;
    check_count(name, "blocks", args.blocks, 2, 100_000)?;
    if let Some(e) = args.equilibrate {
        check_count(name, "equilibrate", e, 0, 10_000_000)?;
        if args.collisions == 0 && e > 0 {
            return edmd::user_error(format!(
                "{name}: --equilibrate {e} drops the blocks measured so far, and --collisions 0 measures none"
            ));
        }
    }
    let n = (args.n_side * args.n_side) as u64;
    if args.collisions > 0 && args.collisions * n < args.blocks {
        return edmd::user_error(format!(
            "{name}: --blocks {} is more than the {} collisions measured",
            args.blocks,
            args.collisions * n
        ));
    }
    Ok(packings)
}

/// Runs the experiment.
pub fn run(args: &HardDiscArgs) -> Result<()> {
    let packings = check(args)?;
    let n = args.n_side * args.n_side;
    let nu = n as u64;
    let mut names = outputs(&["hard-disc-eos"], &["hard-disc-eos"]);
    names.extend(packings.iter().map(|&p| checkpoint_name(p)));
    let dir = out_dir(&args.common, &names)?;
    if !args.resume {
        if let Some(p) = packings
            .iter()
            .map(|&p| checkpoint_path(dir, p))
            .find(|p| p.exists())
        {
            return edmd::user_error(format!(
                "hard-disc-transition: {} exists: continue it with --resume, or choose another --out-dir",
                p.display()
            ));
        }
    }
    // `--resume --collisions 0`: a report of the checkpoints, which must all be there.
    let report_only = args.collisions == 0;
    if report_only {
        if let Some(p) = packings
            .iter()
            .map(|&p| checkpoint_path(dir, p))
            .find(|p| !p.exists())
        {
            return edmd::user_error(format!(
                "hard-disc-transition: {} does not exist: --resume --collisions 0 reports points already measured",
                p.display()
            ));
        }
    }
    // Every checkpoint is read once before any point runs, so that a damaged one is refused
    // with the others as they were (a point run first would have been rewritten, and would
    // add its blocks twice when the run is made again).
    if args.resume {
        for &p in &packings {
            let path = checkpoint_path(dir, p);
            if path.exists() {
                read_point(&path, args.n_side, p)?;
            }
        }
    }
    let equilibrate = args
        .equilibrate
        .unwrap_or(if args.resume { 0 } else { DEFAULT_EQUILIBRATE });
    let block_collisions = args.collisions * nu / args.blocks;
    let started = Instant::now();
    let cpu0 = cpu_seconds();
    let progress = Progress::new(packings.len() as u64 * args.blocks, "hard-disc-transition");
    let mut rows = Vec::new();
    // The checkpoints this run wrote, for the list of files written.
    let mut written = Vec::new();
    let mut collisions = 0u64;
    // The state the next (lower) packing starts from: discs, the box's side, collisions seen.
    let mut chain: Option<(Vec<Disc>, f64, u64)> = None;
    let mut interrupted = false;
    'points: for (k, &packing) in packings.iter().enumerate() {
        let path = checkpoint_path(dir, packing);
        let point_cpu = cpu_seconds();
        let (mut sim, mut carried) = if args.resume && path.exists() {
            read_point(&path, args.n_side, packing)?
        } else {
            let (sim, seen) = match chain.take() {
                None => (lattice_start(args.n_side, packing, args.common.seed)?, 0),
                Some((discs, from, seen)) => (expanded(&discs, from, side(n, packing))?, seen),
            };
            let carried = Carried {
                format: CARRIED_FORMAT.to_string(),
                n_side: args.n_side,
                packing: packing.to_bits(),
                equilibration: seen,
                production: 0,
                cpu_seconds: 0f64.to_bits(),
                blocks: Vec::new(),
            };
            (sim, carried)
        };
        let c0 = sim.stats().disc_disc;
        if equilibrate > 0 {
            if !run_counted(&mut sim, equilibrate * nu, &mut ())? {
                collisions += sim.stats().disc_disc - c0;
                interrupted = true;
                break 'points;
            }
            // What was measured before counts as equilibration now.
            carried.equilibration += carried.production + sim.stats().disc_disc - c0;
            carried.production = 0;
            carried.blocks.clear();
        }
        chain = Some((
            sim.discs(),
            sim.sim_box().lengths[0],
            carried.equilibration + carried.production,
        ));
        for b in 0..if report_only { 0 } else { args.blocks } {
            let before = sim.stats().disc_disc;
            let mut pressure = Pressure::new(&sim);
            if !run_counted(&mut sim, block_collisions, &mut pressure)? {
                collisions += sim.stats().disc_disc - c0;
                interrupted = true;
                break 'points;
            }
            pressure.sample(&sim);
            let block = pressure.blocks()[0];
            carried
                .blocks
                .push([(block.end - block.start).to_bits(), block.z.to_bits()]);
            carried.production += sim.stats().disc_disc - before;
            progress.set(k as u64 * args.blocks + b + 1);
        }
        collisions += sim.stats().disc_disc - c0;
        // A report leaves the checkpoint as it was.
        if !report_only {
            if let (Some(a), Some(b)) = (point_cpu, cpu_seconds()) {
                carried.cpu_seconds = (f64::from_bits(carried.cpu_seconds) + b - a).to_bits();
            }
            write_point(&path, &sim, &carried)?;
            written.push(path.clone());
        }
        let (z, z_error) = z_estimate(&carried.blocks);
        let l = sim.sim_box().lengths[0];
        // The packing as built (equal to the requested one up to rounding).
        let eta = n as f64 * std::f64::consts::PI / (4.0 * l * l);
        let reference = reference(packing);
        let (pressure, pressure_error) = (pressure_from_z(z, eta), pressure_from_z(z_error, eta));
        rows.push(Row {
            packing,
            n,
            pressure,
            pressure_error,
            z,
            z_error,
            psi6: psi6(&sim.discs(), sim.sim_box(), Neighbours::Nearest(6)),
            reference_edmd: reference.map(|r| r.edmd.0),
            reference_edmd_error: reference.map(|r| r.edmd.1),
            reference_mpmc: reference.map(|r| r.mpmc.0),
            reference_mpmc_error: reference.map(|r| r.mpmc.1),
            reference_mpmc_1024: reference.map(|r| r.mpmc_1024.0),
            deviation_sigmas: reference
                .map(|r| (pressure - r.edmd.0) / pressure_error.hypot(r.edmd.1)),
            drift_sigmas: drift_sigmas(&carried.blocks),
            collisions_per_disc: (carried.equilibration + carried.production) as f64 / n as f64,
            production_per_disc: carried.production as f64 / n as f64,
            blocks: carried.blocks.len(),
            cpu_seconds: f64::from_bits(carried.cpu_seconds),
            checkpoint: path.display().to_string(),
        });
    }
    progress.finish();
    rows.sort_by(|a, b| a.packing.total_cmp(&b.packing));
    let wall_seconds = started.elapsed().as_secs_f64();
    let cpu = cpu0.zip(cpu_seconds()).map(|(a, b)| b - a);
    let mut files = Vec::new();
    if !rows.is_empty() {
        write_outputs(args, dir, &rows, &mut files)?;
    }
    files.extend(written);
    let summary = Summary {
        experiment: "hard-disc-transition",
        n_side: args.n_side,
        n,
        resumed: args.resume,
        wall_seconds,
        cpu_seconds: cpu,
        collisions,
        collisions_per_second: collisions as f64 / wall_seconds.max(1e-9),
        collisions_per_cpu_second: cpu.filter(|&c| c > 0.0).map(|c| collisions as f64 / c),
        reference: CITATION,
        rows,
        interrupted,
    };
    let human = human_summary(&summary, &files);
    report(&args.common, &summary, &human)?;
    if interrupted {
        if files.is_empty() {
            return edmd::interrupted("interrupted: nothing written");
        }
        return interrupted_after(&files);
    }
    Ok(())
}

fn human_summary(s: &Summary, files: &[PathBuf]) -> String {
    let mut h = format!(
        "hard discs, {}^2 = {} in a square periodic box, beta P d^2 from the collision virial\n  packing  beta P d^2  error     Engel EDMD 256^2   MPMC 256^2   MPMC 1024^2  sigmas  |psi6|  collisions/disc (measured)\n",
        s.n_side, s.n
    );
    let opt = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.5}"));
    for r in &s.rows {
        h += &format!(
            "  {:.4}   {:9.5}  {:8.5}  {:>9} +- {:<7}  {:>9}  {:>11}  {:>6}  {:.3}   {:.0} ({:.0})\n",
            r.packing,
            r.pressure,
            r.pressure_error,
            opt(r.reference_edmd),
            r.reference_edmd_error.map_or("-".into(), |e| format!("{e:.5}")),
            opt(r.reference_mpmc),
            opt(r.reference_mpmc_1024),
            r.deviation_sigmas.map_or("-".into(), |d| format!("{d:+.1}")),
            r.psi6,
            r.collisions_per_disc,
            r.production_per_disc
        );
    }
    h += &format!(
        "  this run: {} collisions in {:.1} s ({:.3e} per second){}\n",
        s.collisions,
        s.wall_seconds,
        s.collisions_per_second,
        s.cpu_seconds
            .map_or(String::new(), |c| format!(", {c:.1} s of CPU time"))
    );
    h += &format!("  reference: {}\n", s.reference);
    if s.interrupted {
        h += "interrupted: results so far (the point under way keeps its previous checkpoint)\n";
    }
    h + &files_line(files)
}

fn write_outputs(
    args: &HardDiscArgs,
    dir: &Path,
    rows: &[Row],
    files: &mut Vec<PathBuf>,
) -> Result<()> {
    let nan = |x: Option<f64>| x.unwrap_or(f64::NAN);
    let csv = dir.join("hard-disc-eos.csv");
    write_csv(
        &csv,
        &[
            "packing",
            "pressure",
            "pressure_error",
            "Z",
            "Z_error",
            "psi6",
            "reference_edmd",
            "reference_edmd_error",
            "reference_mpmc",
            "reference_mpmc_error",
            "reference_mpmc_1024",
            "drift_sigmas",
            "collisions_per_disc",
            "production_per_disc",
            "n",
        ],
        rows.iter().map(|r| {
            vec![
                r.packing,
                r.pressure,
                r.pressure_error,
                r.z,
                r.z_error,
                r.psi6,
                nan(r.reference_edmd),
                nan(r.reference_edmd_error),
                nan(r.reference_mpmc),
                nan(r.reference_mpmc_error),
                nan(r.reference_mpmc_1024),
                nan(r.drift_sigmas),
                r.collisions_per_disc,
                r.production_per_disc,
                r.n as f64,
            ]
        }),
    )?;
    files.push(csv);
    let points = |f: &dyn Fn(&Reference) -> (f64, f64)| -> (Vec<(f64, f64)>, Vec<f64>) {
        REFERENCE
            .iter()
            .map(|r| ((r.packing, f(r).0), f(r).1))
            .unzip()
    };
    let (edmd, edmd_err) = points(&|r| r.edmd);
    let (mpmc, mpmc_err) = points(&|r| r.mpmc);
    let (big, _) = points(&|r| r.mpmc_1024);
    let mut fig = Figure::new(
        &format!(
            "Hard discs near the liquid-hexatic transition, {}^2, square periodic box",
            args.n_side
        ),
        "packing fraction eta",
        "beta P d^2",
    )
    .with(Series::line("Engel et al. 2013, MPMC 1024^2", big).coloured([150, 150, 150]))
    .with(
        Series::error_bars("Engel et al. 2013, MPMC 256^2", mpmc, mpmc_err).coloured([44, 160, 44]),
    )
    .with(
        Series::error_bars("Engel et al. 2013, EDMD 256^2", edmd, edmd_err)
            .coloured([31, 119, 180]),
    )
    .with(
        Series::error_bars(
            "edmd, collision virial",
            rows.iter().map(|r| (r.packing, r.pressure)).collect(),
            rows.iter().map(|r| r.pressure_error).collect(),
        )
        .coloured([214, 39, 40]),
    );
    if let Some((x, y)) = axes(
        rows.iter()
            .map(|r| (r.packing, r.pressure, r.pressure_error)),
    ) {
        fig = fig.with_x_range(x.0, x.1).with_y_range(y.0, y.1);
    }
    let (png, svg) = fig.save(&dir.join("hard-disc-eos"))?;
    files.push(png);
    files.push(svg);
    Ok(())
}

/// The figure's axes for points `(packing, pressure, error)`: the published range (the loop is
/// 0.02 on 9.18), widened to take in every point and its error bar, since one drawn outside
/// the axes would not be seen; `None` (axes fitted to the data) when a point is far from it.
fn axes(points: impl Iterator<Item = (f64, f64, f64)>) -> Option<((f64, f64), (f64, f64))> {
    const PAD: (f64, f64) = (0.002, 0.005);
    let (mut x, mut y) = ((0.696f64, 0.722f64), (9.15f64, 9.26f64));
    for (eta, p, e) in points {
        if !((0.69..=0.73).contains(&eta) && (9.10..=9.32).contains(&p)) {
            return None;
        }
        x = (x.0.min(eta - PAD.0), x.1.max(eta + PAD.0));
        let e = if e.is_finite() { e } else { 0.0 };
        y = (y.0.min(p - e - PAD.1), y.1.max(p + e + PAD.1));
    }
    Some((x, y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_damaged_record_is_found_before_it_is_added_to() {
        let sound = Carried {
            format: CARRIED_FORMAT.to_string(),
            n_side: 8,
            packing: 0.7f64.to_bits(),
            equilibration: 100,
            production: 200,
            cpu_seconds: 1.5f64.to_bits(),
            blocks: vec![[0.25f64.to_bits(), 2.0f64.to_bits()]],
        };
        assert_eq!(sound.fault(), None);
        let damaged = |f: fn(&mut Carried)| {
            let mut c = sound.clone();
            f(&mut c);
            c.fault()
        };
        for (what, fault) in [
            ("equilibration", damaged(|c| c.equilibration = u64::MAX)),
            ("production", damaged(|c| c.production = u64::MAX)),
            (
                "CPU time NaN",
                damaged(|c| c.cpu_seconds = f64::NAN.to_bits()),
            ),
            (
                "CPU time -1",
                damaged(|c| c.cpu_seconds = (-1f64).to_bits()),
            ),
            (
                "block lasting 0",
                damaged(|c| c.blocks[0][0] = 0f64.to_bits()),
            ),
            (
                "block lasting NaN",
                damaged(|c| c.blocks[0][0] = f64::NAN.to_bits()),
            ),
            (
                "Z inf",
                damaged(|c| c.blocks[0][1] = f64::INFINITY.to_bits()),
            ),
        ] {
            assert!(fault.is_some(), "{what} not found");
        }
    }

    #[test]
    fn the_axes_take_in_every_point_and_its_error_bar() {
        // Within the published range: that range.
        assert_eq!(
            axes([(0.70, 9.18, 0.004), (0.72, 9.23, 0.003)].into_iter()),
            Some(((0.696, 0.722), (9.15, 9.26)))
        );
        // A point below it and one above, both shown whole.
        let points = [(0.704, 9.1451, 0.0088), (0.72, 9.2603, 0.0027)];
        let ((x0, x1), (y0, y1)) = axes(points.into_iter()).unwrap();
        for (eta, p, e) in points {
            assert!(
                x0 < eta && eta < x1 && y0 < p - e && p + e < y1,
                "{eta} {p} {e}"
            );
        }
        // Far from it: fitted to the data.
        assert_eq!(axes([(0.50, 4.0, 0.1)].into_iter()), None);
        assert_eq!(axes([(0.70, 9.5, 0.1)].into_iter()), None);
    }

    #[test]
    fn pressure_is_z_times_four_eta_over_pi() {
        // Henderson's Z at 0.5 is 4.5 (to 0.5 %): beta P d^2 = 4.5 * 2 / pi.
        assert!((pressure_from_z(4.5, 0.5) - 9.0 / std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn the_reference_covers_the_published_grid() {
        for (k, r) in REFERENCE.iter().enumerate() {
            assert!((r.packing - (0.698 + 0.002 * k as f64)).abs() < 1e-9);
            assert!(reference(r.packing).is_some());
        }
        assert!(reference(0.6).is_none());
    }

    #[test]
    fn the_lattice_start_and_its_expansion_have_no_overlap() {
        let sim = lattice_start(8, 0.72, 1).unwrap();
        assert_eq!(sim.overlaps(1e-12).count, 0);
        let l = sim.sim_box().lengths[0];
        let lower = expanded(&sim.discs(), l, side(64, 0.70)).unwrap();
        assert_eq!(lower.overlaps(1e-12).count, 0);
    }

    #[test]
    fn the_drift_compares_the_later_half_of_the_blocks_with_the_earlier() {
        let b = |z: f64| [1f64.to_bits(), z.to_bits()];
        assert_eq!(drift_sigmas(&[b(1.0), b(2.0), b(3.0)]), None);
        // Halves 1, 3 and 5, 7 (the middle 4 in neither): means 2 and 6, errors 1 and 1.
        let d = drift_sigmas(&[b(1.0), b(3.0), b(4.0), b(5.0), b(7.0)]).unwrap();
        assert!((d - 4.0 / 2f64.sqrt()).abs() < 1e-12, "{d}");
        let steady = drift_sigmas(&[b(1.0), b(3.0), b(3.0), b(1.0)]).unwrap();
        assert_eq!(steady, 0.0);
    }

    #[test]
    fn blocks_are_time_weighted() {
        let b = |dt: f64, z: f64| [dt.to_bits(), z.to_bits()];
        let (z, e) = z_estimate(&[b(1.0, 2.0), b(3.0, 4.0)]);
        assert_eq!(z, 3.5);
        assert!((e - 1.0).abs() < 1e-12);
    }
}
