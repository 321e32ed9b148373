//! `edmd experiment ring`: a patch of a planetary ring (the shearing sheet, `edmd_core::Ring`)
//! of identical smooth spheres, its velocity dispersion and optical depth against time, from
//! a cold and a hot start, for several coefficients of restitution.
//!
//! Units: diameter 1 (radius 0.5), mass 1, `Omega = 1`, so dispersions come out in units of
//! `Omega d` and times in units of `1 / Omega` (an orbit is `2 pi`).
//!
//! Goldreich and Tremaine (Icarus 34, 227 (1978)) showed that identical smooth spheres with a
//! constant coefficient of restitution `e` reach a steady velocity dispersion only below a
//! critical `e` (about 0.63 at low optical depth): the energy the shear feeds in and the energy
//! the collisions lose are both proportional to the collision rate times the dispersion
//! squared, so their balance fixes `e` and not the dispersion. Below it the patch cools until
//! the particles' finite size holds it (a few `Omega d`), above it heats without bound. With
//! Bridges, Hatzes and Lin's law for ice (`e` falling with the impact speed, Nature 309, 333
//! (1984)), the dispersion settles where `e` crosses the critical value, a near-monolayer as
//! in the classic local simulations (Wisdom and Tremaine, AJ 95, 925 (1988); Salo, Icarus 90,
//! 254 (1991)).
//!
//! Constant `e` runs with the TC model (`tc = 1e-3 / Omega`: a collision within `tc` of either
//! sphere's previous one is elastic), without which a cold dense patch undergoes inelastic
//! collapse (infinitely many collisions in a finite time). Bridges' law is elastic at low
//! speeds and needs none.
//!
//! Every eighth of an orbit: the dispersion `sqrt(2 K_pec / (3 N))` (velocities relative to the
//! Keplerian flow), the thickness (rms height about the mid-plane) and the photometric optical
//! depth `-ln(1 - f)`, `f` the fraction of the patch the spheres' discs cover seen from above
//! (rasterised). A run whose dispersion passes a tenth of the box's height (in `Omega d`) is
//! stopped there: it is heating without bound.
//!
//! `steady`: the mean dispersion over the run's last quarter differs from that over the quarter
//! before by less than 4 of its errors (the two quarters' combined), and the run was not
//! stopped. Each quarter is cut into 4 blocks; the block means' fluctuation is measured by
//! their successive differences (von Neumann: `s^2 = sum (b_{k+1} - b_k)^2 / (2 (B - 1))` over
//! the last half's 8 blocks), which a steady trend hardly enlarges, so that a slow growth is
//! not taken for noise; a quarter mean's error is `s / 2`.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use edmd::output::AtomicFile;
use edmd_core::measure::block_error;
use edmd_core::setup::ring::RingPatch;
use edmd_core::{Options, Restitution, RestitutionLaw, Ring, Simulation};
use edmd_draw::{draw3, rgba, speed_colour, Scene3, View};
use edmd_plot::{Figure, Series, PALETTE};
use serde::Serialize;

use super::common::{
    check_count, check_n, check_once, files_line, interrupted_after, out_dir, outputs, report,
    stop_requested, write_csv, CommonArgs, Progress,
};

/// Which starts to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Start {
    /// A cold patch (dispersion 0.2 Omega d, a layer one diameter thick).
    Cold,
    /// A hot patch (dispersion 2.5 Omega d).
    Hot,
    /// Both, one after the other, for each restitution.
    Both,
}

/// Options of `edmd experiment ring`.
#[derive(Debug, Args)]
pub struct RingArgs {
    /// Number of particles (spheres of diameter 1).
    #[arg(long, default_value_t = 500, allow_negative_numbers = true)]
    pub n: usize,
    /// Dynamical optical depth, N pi r^2 / (L_x L_y), from 1e-4 to 1.
    #[arg(long, default_value_t = 0.25, allow_negative_numbers = true)]
    pub tau: f64,
    /// Length of each run, in orbital periods 2 pi / Omega.
    #[arg(long, default_value_t = 30, allow_negative_numbers = true)]
    pub orbits: u64,
    /// Coefficients of restitution, comma-separated: numbers in [0, 1], or `bridges` for
    /// Bridges, Hatzes and Lin's law e = min(1, (v_n / v_c)^-0.234).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.25,0.5,0.75,0.9,bridges",
        allow_hyphen_values = true
    )]
    pub restitution: Vec<String>,
    /// Bridges' speed v_c, in units of Omega d: 0.0077 cm/s (Bridges et al. 1984) over
    /// Omega d = 2e-4 /s x 100 cm for metre-sized particles in Saturn's B ring is about 0.4.
    #[arg(long, default_value_t = 0.4, allow_negative_numbers = true)]
    pub bridges_vc: f64,
    /// The initial state: cold, hot or both (a steady state is the same from both sides).
    #[arg(long, value_enum, default_value_t = Start::Both)]
    pub start: Start,
    /// Frames of the movie of the Bridges run (of the last restitution without one).
    #[arg(long, default_value_t = 80, allow_negative_numbers = true)]
    pub frames: u64,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Samples per orbit.
const PER_ORBIT: u64 = 8;
/// The box's height, in diameters, and the dispersion (in `Omega d`) that stops a run.
const HEIGHT: f64 = 100.0;
const CAP: f64 = HEIGHT / 10.0;
/// The starting dispersions, in `Omega d`.
const COLD: f64 = 0.2;
const HOT: f64 = 2.5;
/// The TC model's time for constant `e`, in `1 / Omega`.
const TC: f64 = 1e-3;
/// Goldreich and Tremaine's critical restitution at low optical depth.
const E_CRIT: f64 = 0.63;
/// How many of its errors the last quarter's mean dispersion may differ from the quarter
/// before's in a steady run (4: the error, from 8 blocks, is itself uncertain by a quarter).
const STEADY_ERRORS: f64 = 4.0;
/// Blocks per quarter of a run.
const BLOCKS: usize = 4;
/// The raster's pixels per diameter, for the covered fraction.
const RASTER: f64 = 16.0;

/// A restitution asked for.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Law {
    Constant(f64),
    Bridges,
}

impl Law {
    /// The law as `--restitution` names it (-0 and 0 are one restitution).
    fn word(&self) -> String {
        match self {
            Law::Constant(e) => (e + 0.0).to_string(),
            Law::Bridges => "bridges".to_string(),
        }
    }

    fn label(&self) -> String {
        match self {
            Law::Constant(e) => format!("e = {e}"),
            Law::Bridges => "Bridges".to_string(),
        }
    }
}

/// One run.
#[derive(Debug, Serialize)]
pub struct Row {
    /// The coefficient of restitution (a number), or "bridges".
    pub restitution: serde_json::Value,
    /// "constant" or "bridges".
    pub law: &'static str,
    /// Bridges' v_c (Omega d), for the Bridges runs.
    pub bridges_vc: Option<f64>,
    /// The TC model's time (1 / Omega): 0.001 for constant e, 0 for Bridges.
    pub tc: f64,
    /// "cold" or "hot".
    pub start: &'static str,
    /// The starting dispersion (Omega d).
    pub initial_dispersion: f64,
    /// True when the dispersion settled (see the module's rule).
    pub steady: bool,
    /// Mean dispersion over the last quarter of the run (Omega d); at a stop, the last one.
    pub dispersion: f64,
    /// Its error (successive differences of block means).
    pub dispersion_error: f64,
    /// Mean dispersion over the quarter before.
    pub dispersion_before: f64,
    /// The rms height about the mid-plane over the last quarter (diameters).
    pub thickness: f64,
    /// Its error (blocks).
    pub thickness_error: f64,
    /// The dynamical optical depth, N pi r^2 / (L_x L_y).
    pub tau_dynamic: f64,
    /// The photometric optical depth -ln(1 - covered fraction) over the last quarter.
    pub tau_photometric: f64,
    /// Its error (blocks).
    pub tau_photometric_error: f64,
    /// A monolayer's photometric depth, -ln(1 - tau_dynamic) (a thick layer's: tau_dynamic).
    pub tau_monolayer: f64,
    /// The time reached (1 / Omega).
    pub time: f64,
    /// True when the dispersion passed the cap (a tenth of the box height, Omega d).
    pub capped: bool,
    /// Hits on the z walls.
    pub wall_hits: u64,
    /// Collisions.
    pub collisions: u64,
    /// Goldreich and Tremaine's critical restitution (low optical depth).
    pub critical_restitution: f64,
    /// Whether that theory expects a steady state: e below the critical one, and always with
    /// Bridges' law (e falls with the speed until it reaches the critical value).
    pub theory_steady: bool,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Particles.
    pub n: usize,
    /// Dynamical optical depth.
    pub tau: f64,
    /// Run length in orbits.
    pub orbits: u64,
    /// The patch's side, in diameters.
    pub side: f64,
    /// The box's height (diameters) and the dispersion cap (Omega d).
    pub height: f64,
    /// The cap.
    pub cap: f64,
    /// Goldreich and Tremaine's critical restitution.
    pub critical_restitution: f64,
    /// The runs.
    pub rows: Vec<Row>,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

/// One sample of a run.
#[derive(Debug, Clone, Copy)]
struct Sample {
    time: f64,
    dispersion: f64,
    thickness: f64,
    tau_photometric: f64,
}

/// Runs the experiment.
pub fn run(args: &RingArgs) -> Result<()> {
    check_n("ring", args.n, 20)?;
    if !(args.tau >= edmd_core::setup::ring::MIN_OPTICAL_DEPTH && args.tau <= 1.0) {
        return edmd::user_error(format!(
            "ring: --tau must be from {:e} to 1, found {}",
            edmd_core::setup::ring::MIN_OPTICAL_DEPTH,
            args.tau
        ));
    }
    check_count("ring", "orbits", args.orbits, 2, 10_000)?;
    check_count("ring", "frames", args.frames, 1, 10_000)?;
    // Below a thousandth of the shear across a particle every collision of the Bridges run is
    // all but perfectly inelastic (e < 0.2 at v_n = Omega d), and the patch collapses.
    if !(args.bridges_vc.is_finite() && (1e-3..=1e3).contains(&args.bridges_vc)) {
        return edmd::user_error(format!(
            "ring: --bridges-vc must be from 0.001 to 1000 (units of Omega d), found {}",
            args.bridges_vc
        ));
    }
    let laws = parse_laws(&args.restitution)?;
    let patch = patch(args, COLD);
    // The generator's own checks (a patch too small for its cells), before anything is written.
    patch
        .build::<3>()
        .or_else(|e| edmd::user_error(format!("ring: {e}")))?;
    let mut names = outputs(
        &["ring-time-series", "ring"],
        &["ring-dispersion", "ring-optical-depth"],
    );
    names.push("ring-patch.gif".to_string());
    let dir = out_dir(&args.common, &names)?;
    let starts: &[(&'static str, f64)] = match args.start {
        Start::Cold => &[("cold", COLD)],
        Start::Hot => &[("hot", HOT)],
        Start::Both => &[("cold", COLD), ("hot", HOT)],
    };
    let movie_law = laws
        .iter()
        .position(|l| *l == Law::Bridges)
        .unwrap_or(laws.len() - 1);
    let mut files = Vec::new();
    let mut rows = Vec::new();
    let mut series: Vec<(String, Vec<Sample>)> = Vec::new();
    let total = (laws.len() * starts.len()) as u64;
    let progress = Progress::new(total * args.orbits * PER_ORBIT, "ring");
    let gif_path = dir.join("ring-patch.gif");
    let mut interrupted = false;
    'runs: for (k, law) in laws.iter().enumerate() {
        for (j, &(start, dispersion)) in starts.iter().enumerate() {
            let mut movie = if k == movie_law && j == 0 {
                Some(Movie::create(&gif_path)?)
            } else {
                None
            };
            let done = ((k * starts.len() + j) as u64) * args.orbits * PER_ORBIT;
            let outcome = one_run(args, *law, start, dispersion, movie.as_mut(), |s| {
                progress.set(done + s)
            })
            .with_context(|| {
                let vc = match law {
                    Law::Constant(_) => String::new(),
                    Law::Bridges => format!(" --bridges-vc {}", args.bridges_vc),
                };
                format!(
                    "ring: the run with --restitution {}{vc} ({start} start) stopped",
                    law.word()
                )
            })?;
            if let Some(m) = movie {
                m.finish()?;
                files.push(gif_path.clone());
            }
            match outcome {
                Some((row, samples)) => {
                    series.push((format!("{}, {start}", law.label()), samples));
                    rows.push(row);
                }
                None => {
                    interrupted = true;
                    break 'runs;
                }
            }
        }
    }
    progress.finish();
    if !series.is_empty() {
        write_outputs(args, dir, &rows, &series, &mut files)?;
    }
    let side = (args.n as f64 * std::f64::consts::PI * 0.25 / args.tau).sqrt();
    let mut human = format!(
        "ring: {} spheres of diameter 1, optical depth {}, patch {side:.1} x {side:.1} x {HEIGHT}, Omega = 1, {} orbits per run\n  Goldreich & Tremaine (1978): steady only below e_crit ~ {E_CRIT} (low optical depth)\n",
        args.n, args.tau, args.orbits
    );
    human += "  restitution  start  steady  dispersion (Omega d)  thickness (d)  tau_phot  walls  theory\n";
    for r in &rows {
        let e = match &r.restitution {
            serde_json::Value::String(s) => format!("{s} (v_c {})", r.bridges_vc.unwrap_or(0.0)),
            v => v.to_string(),
        };
        human += &format!(
            "  {e:<11}  {:<5}  {:<6}  {:>8.3} +- {:<8.3}  {:>6.2}         {:>6.3}    {:>5}  {}{}\n",
            r.start,
            if r.steady { "yes" } else { "no" },
            r.dispersion,
            r.dispersion_error,
            r.thickness,
            r.tau_photometric,
            r.wall_hits,
            if r.theory_steady { "steady" } else { "grows" },
            if r.capped {
                format!(" (stopped at t = {:.0}: past {CAP} Omega d)", r.time)
            } else {
                String::new()
            }
        );
    }
    // Equal spheres in one layer cover at most pi / (2 sqrt 3) of the plane (the hexagonal
    // packing): a denser patch is thicker than a monolayer, whose -ln(1 - tau) then does not
    // apply (and at tau = 1 would be infinite).
    let densest = std::f64::consts::PI / (2.0 * 3f64.sqrt());
    human += &if args.tau <= densest {
        format!(
            "  tau_dynamic {:.3}; a monolayer's photometric depth -ln(1 - tau) = {:.3}\n",
            args.tau,
            -(1.0 - args.tau).ln()
        )
    } else {
        format!(
            "  tau_dynamic {:.3}: above {densest:.3}, the most a single layer of equal spheres covers, so no monolayer's -ln(1 - tau) applies; the table's tau_phot is the patch's own\n",
            args.tau
        )
    };
    human += &files_line(&files);
    let summary = Summary {
        experiment: "ring",
        n: args.n,
        tau: args.tau,
        orbits: args.orbits,
        side,
        height: HEIGHT,
        cap: CAP,
        critical_restitution: E_CRIT,
        rows,
        interrupted,
    };
    report(&args.common, &summary, &human)?;
    if interrupted {
        if files.is_empty() {
            return edmd::interrupted("interrupted: nothing written");
        }
        return interrupted_after(&files);
    }
    Ok(())
}

/// The restitutions from the option's words.
fn parse_laws(words: &[String]) -> Result<Vec<Law>> {
    if words.is_empty() {
        return edmd::user_error("ring: --restitution needs at least one value");
    }
    let mut laws = Vec::new();
    for w in words {
        let w = w.trim();
        let law = if w.eq_ignore_ascii_case("bridges") {
            Law::Bridges
        } else {
            match w.parse::<f64>() {
                Ok(e) if (0.0..=1.0).contains(&e) => Law::Constant(e),
                Ok(e) => {
                    return edmd::user_error(format!("ring: --restitution {e} is outside [0, 1]"))
                }
                Err(_) => {
                    return edmd::user_error(format!(
                        "ring: --restitution takes numbers in [0, 1] or `bridges`, found {w:?}"
                    ))
                }
            }
        };
        laws.push(law);
    }
    let words: Vec<String> = laws.iter().map(Law::word).collect();
    check_once("ring", "--restitution", &words)?;
    Ok(laws)
}

fn patch(args: &RingArgs, dispersion: f64) -> RingPatch {
    RingPatch {
        n: args.n,
        tau: args.tau,
        radius: 0.5,
        omega: 1.0,
        dispersion,
        height: HEIGHT,
        seed: args.common.seed,
    }
}

/// One run: its row and samples, `None` when stopped.
fn one_run(
    args: &RingArgs,
    law: Law,
    start: &'static str,
    dispersion: f64,
    mut movie: Option<&mut Movie>,
    progress: impl Fn(u64),
) -> Result<Option<(Row, Vec<Sample>)>> {
    let (discs, sim_box) = patch(args, dispersion).build::<3>()?;
    let mut sim = Simulation::new(&discs, sim_box, Options::default())?;
    sim.set_ring(Some(Ring { omega: 1.0 }))?;
    let restitution = match law {
        Law::Constant(e) => Restitution {
            tc: TC,
            ..Restitution::constant(e)
        },
        Law::Bridges => Restitution {
            all: RestitutionLaw::Bridges {
                v_c: args.bridges_vc,
            },
            ..Restitution::default()
        },
    };
    sim.set_restitution(Some(restitution))?;
    let mut raster = Raster::new(sim.sim_box().lengths[0], sim.sim_box().lengths[1]);
    let samples_total = args.orbits * PER_ORBIT;
    let frame_every = (samples_total / args.frames).max(1);
    let dt = 2.0 * std::f64::consts::PI / PER_ORBIT as f64;
    let mut samples = vec![sample(&sim, &mut raster)];
    if let Some(m) = movie.as_deref_mut() {
        m.frame(&sim, dispersion)?;
    }
    let mut capped = false;
    for s in 1..=samples_total {
        if !edmd::run_until_or_stop(&mut sim, s as f64 * dt, &mut ())? || stop_requested() {
            return Ok(None);
        }
        let now = sample(&sim, &mut raster);
        samples.push(now);
        if let Some(m) = movie.as_deref_mut() {
            if s % frame_every == 0 {
                m.frame(
                    &sim,
                    samples[1..].iter().map(|x| x.dispersion).sum::<f64>() / s as f64,
                )?;
            }
        }
        progress(s);
        if now.dispersion > CAP {
            capped = true;
            break;
        }
    }
    let measured = &samples[1..];
    let q = measured.len() / 4;
    let (last, before) = if capped || q < BLOCKS {
        (
            &measured[measured.len() - 1..],
            &measured[measured.len() - 1..],
        )
    } else {
        (
            &measured[measured.len() - q..],
            &measured[measured.len() - 2 * q..measured.len() - q],
        )
    };
    let mean_of =
        |x: &[Sample], f: fn(&Sample) -> f64| x.iter().map(f).sum::<f64>() / x.len() as f64;
    let blocks_of = |x: &[Sample], f: fn(&Sample) -> f64| -> Vec<f64> {
        let per = (x.len() / BLOCKS).max(1);
        x.chunks(per)
            .filter(|c| c.len() == per)
            .map(|c| c.iter().map(f).sum::<f64>() / per as f64)
            .collect()
    };
    let disp = |s: &Sample| s.dispersion;
    let (d_last, d_before) = (mean_of(last, disp), mean_of(before, disp));
    let mut half_blocks = blocks_of(before, disp);
    half_blocks.extend(blocks_of(last, disp));
    let d_error = if half_blocks.len() >= 2 {
        let ss: f64 = half_blocks.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum();
        (ss / (2.0 * (half_blocks.len() - 1) as f64)).sqrt() / (BLOCKS as f64).sqrt()
    } else {
        f64::NAN
    };
    let steady =
        !capped && (d_last - d_before).abs() < STEADY_ERRORS * std::f64::consts::SQRT_2 * d_error;
    let thick = |s: &Sample| s.thickness;
    let photo = |s: &Sample| s.tau_photometric;
    let (tc, e_value, law_name, vc) = match law {
        Law::Constant(e) => (TC, serde_json::json!(e), "constant", None),
        Law::Bridges => (
            0.0,
            serde_json::json!("bridges"),
            "bridges",
            Some(args.bridges_vc),
        ),
    };
    let theory_steady = match law {
        Law::Constant(e) => e < E_CRIT,
        Law::Bridges => true,
    };
    let row = Row {
        restitution: e_value,
        law: law_name,
        bridges_vc: vc,
        tc,
        start,
        initial_dispersion: dispersion,
        steady,
        dispersion: d_last,
        dispersion_error: d_error,
        dispersion_before: d_before,
        thickness: mean_of(last, thick),
        thickness_error: block_error(&blocks_of(last, thick)),
        tau_dynamic: args.tau,
        tau_photometric: mean_of(last, photo),
        tau_photometric_error: block_error(&blocks_of(last, photo)),
        tau_monolayer: -(1.0 - args.tau).ln(),
        time: sim.time(),
        capped,
        wall_hits: sim.stats().wall,
        collisions: sim.stats().disc_disc,
        critical_restitution: E_CRIT,
        theory_steady,
    };
    Ok(Some((row, samples)))
}

/// The dispersion, thickness and photometric depth now.
fn sample(sim: &Simulation<3>, raster: &mut Raster) -> Sample {
    let n = sim.len();
    let mid = 0.5 * sim.sim_box().lengths[2];
    let (mut v2, mut z2) = (0.0, 0.0);
    for i in 0..n {
        v2 += sim.peculiar_velocity(i).norm2();
        z2 += (sim.position(i)[2] - mid).powi(2);
    }
    let offset = sim.shear().map_or(0.0, |s| s.offset);
    let covered = raster.covered(sim, offset);
    Sample {
        time: sim.time(),
        dispersion: (v2 / (3.0 * n as f64)).sqrt(),
        thickness: (z2 / n as f64).sqrt(),
        tau_photometric: -(1.0 - covered).max(f64::MIN_POSITIVE).ln(),
    }
}

/// A grid over the patch seen from above, for the fraction the spheres cover.
struct Raster {
    nx: usize,
    ny: usize,
    lx: f64,
    ly: f64,
    cells: Vec<bool>,
}

impl Raster {
    fn new(lx: f64, ly: f64) -> Self {
        let nx = (lx * RASTER).ceil() as usize;
        let ny = (ly * RASTER).ceil() as usize;
        Raster {
            nx,
            ny,
            lx,
            ly,
            cells: vec![false; nx * ny],
        }
    }

    /// The covered fraction: each sphere's disc of radius r, with its sheared images across
    /// y (above shifted by `offset` along x) and periodic images along x.
    fn covered(&mut self, sim: &Simulation<3>, offset: f64) -> f64 {
        self.cells.iter_mut().for_each(|c| *c = false);
        let (hx, hy) = (self.lx / self.nx as f64, self.ly / self.ny as f64);
        for i in 0..sim.len() {
            let p = sim.position(i);
            let r = sim.radius(i);
            for (dx, dy) in [(0.0, 0.0), (offset, self.ly), (-offset, -self.ly)] {
                let (cx, cy) = (p[0] + dx, p[1] + dy);
                if cy + r < 0.0 || cy - r > self.ly {
                    continue;
                }
                let j0 = ((cy - r) / hy).floor().max(0.0) as usize;
                let j1 = (((cy + r) / hy).ceil() as usize).min(self.ny);
                for j in j0..j1 {
                    let y = (j as f64 + 0.5) * hy - cy;
                    let w2 = r * r - y * y;
                    if w2 <= 0.0 {
                        continue;
                    }
                    let w = w2.sqrt();
                    let i0 = ((cx - w) / hx - 0.5).ceil() as i64;
                    let i1 = ((cx + w) / hx - 0.5).floor() as i64;
                    for k in i0..=i1 {
                        let k = k.rem_euclid(self.nx as i64) as usize;
                        self.cells[j * self.nx + k] = true;
                    }
                }
            }
        }
        self.cells.iter().filter(|&&c| c).count() as f64 / self.cells.len() as f64
    }
}

/// The CSV files and the figures.
fn write_outputs(
    args: &RingArgs,
    dir: &Path,
    rows: &[Row],
    series: &[(String, Vec<Sample>)],
    files: &mut Vec<PathBuf>,
) -> Result<()> {
    let orbit = 2.0 * std::f64::consts::PI;
    let csv = dir.join("ring-time-series.csv");
    let mut lines = Vec::new();
    for (k, (_, samples)) in series.iter().enumerate() {
        for s in samples {
            lines.push(vec![
                k as f64,
                rows[k].restitution.as_f64().unwrap_or(-1.0),
                if rows[k].start == "cold" { 0.0 } else { 1.0 },
                s.time,
                s.time / orbit,
                s.dispersion,
                s.thickness,
                s.tau_photometric,
            ]);
        }
    }
    write_csv(
        &csv,
        &[
            "run",
            "restitution",
            "hot",
            "time",
            "orbits",
            "dispersion",
            "thickness",
            "tau_photometric",
        ],
        lines,
    )?;
    files.push(csv);
    let csv = dir.join("ring.csv");
    write_csv(
        &csv,
        &[
            "restitution",
            "hot",
            "steady",
            "dispersion",
            "dispersion_error",
            "thickness",
            "thickness_error",
            "tau_dynamic",
            "tau_photometric",
            "tau_photometric_error",
            "time",
            "wall_hits",
            "theory_steady",
        ],
        rows.iter().map(|r| {
            vec![
                r.restitution.as_f64().unwrap_or(-1.0),
                if r.start == "cold" { 0.0 } else { 1.0 },
                r.steady as u8 as f64,
                r.dispersion,
                r.dispersion_error,
                r.thickness,
                r.thickness_error,
                r.tau_dynamic,
                r.tau_photometric,
                r.tau_photometric_error,
                r.time,
                r.wall_hits as f64,
                r.theory_steady as u8 as f64,
            ]
        }),
    )?;
    files.push(csv);
    // One colour per restitution; the hot start drawn in a lighter shade.
    let colour = |k: usize| -> [u8; 3] {
        let starts = if args.start == Start::Both { 2 } else { 1 };
        let c = PALETTE[(k / starts) % PALETTE.len()];
        if starts == 2 && k % 2 == 1 {
            c.map(|x| ((x as u16 + 2 * 255) / 3) as u8)
        } else {
            c
        }
    };
    let end = args.orbits as f64;
    let mut fig = Figure::new(
        &format!(
            "ring patch, N = {}, tau = {}: velocity dispersion (cold and hot starts)",
            args.n, args.tau
        ),
        "time (orbits)",
        "velocity dispersion (Omega d)",
    )
    .with_log_y();
    for (k, (label, samples)) in series.iter().enumerate() {
        fig = fig.with(
            Series::line(
                label,
                samples
                    .iter()
                    .map(|s| (s.time / orbit, s.dispersion))
                    .collect(),
            )
            .coloured(colour(k)),
        );
    }
    fig = fig.with(
        Series::line(
            &format!("cap: the run stops at {CAP}"),
            vec![(0.0, CAP), (end, CAP)],
        )
        .coloured([0, 0, 0]),
    );
    let (png, svg) = fig.save(&dir.join("ring-dispersion"))?;
    files.extend([png, svg]);
    let mut fig = Figure::new(
        &format!(
            "ring patch, N = {}: photometric optical depth -ln(1 - covered fraction)",
            args.n
        ),
        "time (orbits)",
        "optical depth",
    );
    for (k, (label, samples)) in series.iter().enumerate() {
        fig = fig.with(
            Series::line(
                label,
                samples
                    .iter()
                    .map(|s| (s.time / orbit, s.tau_photometric))
                    .collect(),
            )
            .coloured(colour(k)),
        );
    }
    let mono = -(1.0 - args.tau).ln();
    fig = fig
        .with(
            Series::line(
                &format!("dynamical (a thick layer's): {}", args.tau),
                vec![(0.0, args.tau), (end, args.tau)],
            )
            .coloured([0, 0, 0]),
        )
        .with(
            Series::line(
                &format!("a monolayer's: -ln(1 - tau) = {mono:.3}"),
                vec![(0.0, mono), (end, mono)],
            )
            .coloured([120, 120, 120]),
        );
    let (png, svg) = fig.save(&dir.join("ring-optical-depth"))?;
    files.extend([png, svg]);
    Ok(())
}

/// The movie: the patch from above, and beneath it a side view (along y) of the layer within
/// `SIDE_REACH` diameters of the mid-plane; spheres coloured by their peculiar speed.
struct Movie {
    encoder: gif::Encoder<AtomicFile>,
}

const MOVIE_W: u32 = 480;
const SIDE_H: u32 = 120;
const SIDE_REACH: f64 = 6.0;

impl Movie {
    fn create(path: &Path) -> Result<Self> {
        let file = AtomicFile::create(path)?;
        let mut encoder = gif::Encoder::new(file, MOVIE_W as u16, (MOVIE_W + SIDE_H) as u16, &[])
            .context("GIF encoder")?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .context("GIF encoder")?;
        Ok(Movie { encoder })
    }

    /// A frame; `scale` is the speed drawn brightest (half of it mid-scale).
    fn frame(&mut self, sim: &Simulation<3>, scale: f64) -> Result<()> {
        let lengths = sim.sim_box().lengths;
        let n = sim.len();
        let colours: Vec<[u8; 3]> = (0..n)
            .map(|i| {
                speed_colour(sim.peculiar_velocity(i).norm2().sqrt() / (2.0 * scale.max(1e-9)))
            })
            .collect();
        let positions: Vec<[f64; 3]> = (0..n).map(|i| sim.position(i).0).collect();
        let radii: Vec<f64> = (0..n).map(|i| sim.radius(i)).collect();
        let top = Scene3 {
            lengths: [lengths[0], lengths[1], lengths[2]],
            periodic: [true, true, false],
            positions: positions.clone(),
            radii: radii.clone(),
            colours: colours.clone(),
            bonds: Vec::new(),
        };
        let top_px = rgba(&draw3(
            &top,
            View::Orbit {
                azimuth: -90.0,
                elevation: 90.0,
            },
            MOVIE_W,
            MOVIE_W,
        ));
        let low = 0.5 * lengths[2] - SIDE_REACH;
        let keep: Vec<usize> = (0..n)
            .filter(|&i| (positions[i][2] - 0.5 * lengths[2]).abs() < SIDE_REACH - radii[i])
            .collect();
        let side = Scene3 {
            lengths: [lengths[0], lengths[1], 2.0 * SIDE_REACH],
            periodic: [true, true, false],
            positions: keep
                .iter()
                .map(|&i| [positions[i][0], positions[i][1], positions[i][2] - low])
                .collect(),
            radii: keep.iter().map(|&i| radii[i]).collect(),
            colours: keep.iter().map(|&i| colours[i]).collect(),
            bonds: Vec::new(),
        };
        let side_px = rgba(&draw3(
            &side,
            View::Orbit {
                azimuth: -90.0,
                elevation: 0.0,
            },
            MOVIE_W,
            SIDE_H,
        ));
        let mut px = top_px;
        px.extend(side_px);
        let mut frame =
            gif::Frame::from_rgba_speed(MOVIE_W as u16, (MOVIE_W + SIDE_H) as u16, &mut px, 10);
        frame.delay = 8;
        self.encoder
            .write_frame(&frame)
            .context("writing the GIF")?;
        Ok(())
    }

    fn finish(self) -> Result<()> {
        let file = self.encoder.into_inner().context("finishing the GIF")?;
        file.commit()
    }
}
