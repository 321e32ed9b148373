//! `edmd experiment sheets`: the one-dimensional self-gravitating system (Princeton's "one
//! dimensional self-gravitating systems"): `N` parallel sheets of mass 1, each pulled towards
//! the others by `coupling (M_right - M_left)`, run event by event as hard rods that keep their
//! order (Noullez, Fanelli and Aurell, J. Comput. Phys. 186, 697 (2003)).
//!
//! Units: `coupling = 1 / N`, so that the whole mass pulls with `coupling M = 1`; lengths in
//! units of the water bag's half-width, times in `sqrt(length / (coupling M))`.
//!
//! Two runs from a water bag (positions and velocities uniform in `[-1, 1] x [-1, 1]`, which
//! is in virial equilibrium: `2K = U` for a uniform bag when `V^2 = X coupling M`):
//! - **Isolated** (energy conserved): `2K/U` against time, oscillating as the bag winds up
//!   into a spiral in phase space and settling slowly (Hohl and Feix, Astrophys. J. 147, 1164
//!   (1967); the long relaxation of the sheet model is Miller's, Phys. Rev. E 53, R4279
//!   (1996)); a movie of the phase plane. The virial theorem holds for time averages: `U` is
//!   homogeneous of degree 1 in the separations, so `2 <K> = 1 <U>`, from the second half of
//!   the run with block errors.
//! - **In a heat bath** (Andersen, `kT = 0.5`): the canonical equilibrium, whose density for
//!   large `N` is the isothermal sheet (Spitzer, Astrophys. J. 95, 329 (1942)),
//!   `n(x) = N / (2 x0) sech^2(x / x0)` with `x0 = 2 kT / (m coupling M)`, from the balance
//!   `kT dn/dx = -n dPhi/dx` and Poisson's `Phi'' = 2 coupling rho` (its variance is
//!   `pi^2 x0^2 / 12`, which gives `x0` measured). Positions are taken from the centre of mass
//!   at each sample (the bath kicks the whole about).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use edmd::output::AtomicFile;
use edmd_core::measure::block_error;
use edmd_core::setup::sheets::WaterBag;
use edmd_core::{Andersen, Options, SelfGravity, Simulation};
use edmd_plot::{Figure, Series, PALETTE};
use serde::Serialize;

use super::common::{
    check_count, check_n, files_line, interrupted_after, out_dir, outputs, report, stop_requested,
    write_csv, CommonArgs, Progress,
};

/// Options of `edmd experiment sheets`.
#[derive(Debug, Args)]
pub struct SheetsArgs {
    /// Number of sheets.
    #[arg(long, default_value_t = 1000, allow_negative_numbers = true)]
    pub n: usize,
    /// Length of the isolated run, in dynamical times (the water bag's crossing time is about
    /// 2).
    #[arg(long, default_value_t = 100, allow_negative_numbers = true)]
    pub time: u64,
    /// Length of the heat-bath run, in dynamical times (a quarter of it settles the bath).
    #[arg(long, default_value_t = 200, allow_negative_numbers = true)]
    pub bath_time: u64,
    /// Frames of the phase-plane movie of the isolated run.
    #[arg(long, default_value_t = 100, allow_negative_numbers = true)]
    pub frames: u64,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Samples per dynamical time.
const PER_TIME: u64 = 4;
/// Blocks for the errors.
const BLOCKS: usize = 20;
/// The heat bath's temperature (so that `x0 = 1`) and redraws per sheet per unit time.
const BATH_KT: f64 = 0.5;
const BATH_RATE: f64 = 1.0;
/// Profile bins: width and reach, in units of `x0`.
const BIN: f64 = 0.125;
const REACH: f64 = 5.0;

/// One run.
#[derive(Debug, Serialize)]
pub struct Row {
    /// "isolated" or "heat bath".
    pub start: &'static str,
    /// Sheets.
    pub n: usize,
    /// The self-gravity's coupling, `1 / n`.
    pub coupling: f64,
    /// Length of the run (dynamical times).
    pub time: f64,
    /// Mean kinetic temperature `<v^2>` (mass 1) over the samples measured.
    pub kt: f64,
    /// Its error (blocks).
    pub kt_error: f64,
    /// `2 <K> / <U>` over the samples measured (the second half of the isolated run; the last
    /// three quarters of the bath's).
    pub virial_ratio: f64,
    /// Its error (blocks, the ratio's error from theirs).
    pub virial_ratio_error: f64,
    /// The virial theorem's: 1.
    pub virial_theory: f64,
    /// Relative change of the energy over the run (isolated: rounding only).
    pub relative_energy_change: f64,
    /// The heat bath's: the isothermal sheet's `x0` from the variance of the positions.
    pub x0: Option<f64>,
    /// Its error (blocks).
    pub x0_error: Option<f64>,
    /// Spitzer's `2 kT / (coupling M)` with the measured `kT`.
    pub x0_theory: Option<f64>,
    /// Its error, from `kT`'s.
    pub x0_theory_error: Option<f64>,
    /// `sum ((n_k - sech^2_k) / error_k)^2 / bins` over the profile's bins within 3 x0.
    pub profile_chi2: Option<f64>,
    /// Those bins.
    pub profile_bins: Option<usize>,
    /// Collisions (crossings of sheets).
    pub collisions: u64,
    /// Sheets that reached the walls, 16 bag widths out (none, in a bag).
    pub wall_hits: u64,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Sheets.
    pub n: usize,
    /// The isolated run's `2 <K> / <U>`.
    pub virial_ratio: f64,
    /// Its error.
    pub virial_ratio_error: f64,
    /// The two runs.
    pub rows: Vec<Row>,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

/// Runs the experiment.
pub fn run(args: &SheetsArgs) -> Result<()> {
    check_n("sheets", args.n, 16)?;
    check_count("sheets", "time", args.time, 2, 100_000)?;
    check_count("sheets", "bath-time", args.bath_time, 4, 100_000)?;
    check_count("sheets", "frames", args.frames, 1, 10_000)?;
    let mut names = outputs(
        &["sheets-virial", "sheets-profile"],
        &["sheets-virial", "sheets-profile"],
    );
    names.push("sheets-phase-plane.gif".to_string());
    let dir = out_dir(&args.common, &names)?;
    let mut files = Vec::new();
    let isolated = isolated(args, dir, &mut files)?;
    let bath = match &isolated {
        Some(_) if !stop_requested() => heat_bath(args, dir, &mut files)?,
        _ => None,
    };
    let mut rows: Vec<Row> = isolated.into_iter().collect();
    rows.extend(bath);
    let interrupted = rows.len() < 2;
    let mut human = format!(
        "sheets: {} self-gravitating sheets (coupling 1/N), from a water bag\n",
        args.n
    );
    for r in &rows {
        human += &format!(
            "  {:<9}  2<K>/<U> = {:.4} +- {:.4} (virial theorem: 1)  kT = {:.4}  energy change {:.1e}  {} collisions\n",
            r.start, r.virial_ratio, r.virial_ratio_error, r.kt, r.relative_energy_change, r.collisions
        );
        if let (Some(x0), Some(e), Some(t), Some(te)) =
            (r.x0, r.x0_error, r.x0_theory, r.x0_theory_error)
        {
            human += &format!(
                "             x0 = {x0:.4} +- {e:.4} from the variance, Spitzer's 2kT/(coupling M) = {t:.4} +- {te:.4}; profile chi2/bin {:.2} over {} bins\n",
                r.profile_chi2.unwrap_or(f64::NAN),
                r.profile_bins.unwrap_or(0)
            );
        }
    }
    human += &files_line(&files);
    let summary = Summary {
        experiment: "sheets",
        n: args.n,
        virial_ratio: rows.first().map_or(f64::NAN, |r| r.virial_ratio),
        virial_ratio_error: rows.first().map_or(f64::NAN, |r| r.virial_ratio_error),
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

/// The water bag under its self-gravity.
fn water_bag(args: &SheetsArgs) -> Result<Simulation<1>> {
    let coupling = 1.0 / args.n as f64;
    let (discs, sim_box) = WaterBag {
        n: args.n,
        width: 1.0,
        speed: 1.0,
        radius: 1e-7,
        coupling,
        seed: args.common.seed,
    }
    .build()?;
    let mut sim = Simulation::new(&discs, sim_box, Options::default())?;
    sim.set_self_gravity(Some(SelfGravity { coupling }))?;
    Ok(sim)
}

/// The sheets' positions from their centre of mass, and their velocities.
fn phase_plane(sim: &Simulation<1>) -> Vec<(f64, f64)> {
    let y = sim.sheet_positions().unwrap_or_default();
    let centre = y.iter().sum::<f64>() / y.len().max(1) as f64;
    (0..y.len())
        .map(|i| (y[i] - centre, sim.velocity(i)[0]))
        .collect()
}

/// `2 <K> / <U>` and its error from per-block means of K and U.
fn virial(k: &[f64], u: &[f64]) -> (f64, f64) {
    let blocks = |x: &[f64]| -> Vec<f64> {
        let per = (x.len() / BLOCKS).max(1);
        x.chunks(per)
            .filter(|c| c.len() == per)
            .map(|c| c.iter().sum::<f64>() / per as f64)
            .collect()
    };
    let (kb, ub) = (blocks(k), blocks(u));
    let ratios: Vec<f64> = kb.iter().zip(&ub).map(|(k, u)| 2.0 * k / u).collect();
    let (km, um) = (mean(k), mean(u));
    (2.0 * km / um, block_error(&ratios))
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len().max(1) as f64
}

/// The means of `f` over [`BLOCKS`] runs of consecutive samples (the last one holding the
/// remainder).
fn block_means(x: &[f64], f: impl Fn(f64) -> f64) -> Vec<f64> {
    x.chunks((x.len() / BLOCKS).max(1))
        .map(|c| f(mean(c)))
        .collect()
}

/// The isolated run: virial ratio, energy, the movie and the figure.
fn isolated(args: &SheetsArgs, dir: &Path, files: &mut Vec<PathBuf>) -> Result<Option<Row>> {
    let mut sim = water_bag(args)?;
    let e0 = sim.kinetic_energy() + sim.potential_energy();
    let samples = args.time * PER_TIME;
    let frame_every = (samples / args.frames).max(1);
    let gif_path = dir.join("sheets-phase-plane.gif");
    let mut movie = Movie::create(&gif_path)?;
    movie.frame(&phase_plane(&sim))?;
    let (mut t_k, mut kin, mut pot) = (Vec::new(), Vec::new(), Vec::new());
    let progress = Progress::new(samples, "sheets (isolated)");
    for s in 1..=samples {
        let t = s as f64 / PER_TIME as f64;
        if !edmd::run_until_or_stop(&mut sim, t, &mut ())? {
            progress.finish();
            return Ok(None);
        }
        t_k.push(t);
        kin.push(sim.kinetic_energy());
        pot.push(sim.potential_energy());
        if s % frame_every == 0 {
            movie.frame(&phase_plane(&sim))?;
        }
        progress.set(s);
    }
    progress.finish();
    movie.finish()?;
    files.push(gif_path);
    let half = kin.len() / 2;
    let (ratio, ratio_error) = virial(&kin[half..], &pot[half..]);
    let (k_mean, k_error) = (
        mean(&kin[half..]),
        block_error(&block_means(&kin[half..], |k| k)),
    );
    let n = args.n as f64;
    let csv = dir.join("sheets-virial.csv");
    write_csv(
        &csv,
        &["time", "kinetic", "potential", "virial_ratio"],
        (0..kin.len()).map(|k| vec![t_k[k], kin[k], pot[k], 2.0 * kin[k] / pot[k]]),
    )?;
    files.push(csv);
    let ratio_line: Vec<(f64, f64)> = (0..kin.len())
        .map(|k| (t_k[k], 2.0 * kin[k] / pot[k]))
        .collect();
    let end = args.time as f64;
    let (png, svg) = Figure::new(
        &format!(
            "{} sheets from a water bag: 2<K>/<U> = {ratio:.4} +- {ratio_error:.4}",
            args.n
        ),
        "time (dynamical times)",
        "2K / U",
    )
    .with(Series::line("edmd", ratio_line))
    .with(
        Series::line("virial theorem: 2<K> = <U>", vec![(0.0, 1.0), (end, 1.0)])
            .coloured([0, 0, 0]),
    )
    .save(&dir.join("sheets-virial"))?;
    files.extend([png, svg]);
    let e1 = sim.kinetic_energy() + sim.potential_energy();
    Ok(Some(Row {
        start: "isolated",
        n: args.n,
        coupling: 1.0 / n,
        time: end,
        kt: 2.0 * k_mean / n,
        kt_error: 2.0 * k_error / n,
        virial_ratio: ratio,
        virial_ratio_error: ratio_error,
        virial_theory: 1.0,
        relative_energy_change: (e1 - e0) / e0,
        x0: None,
        x0_error: None,
        x0_theory: None,
        x0_theory_error: None,
        profile_chi2: None,
        profile_bins: None,
        collisions: sim.stats().disc_disc,
        wall_hits: sim.stats().wall,
    }))
}

/// The heat-bath run: the profile against the isothermal sheet.
fn heat_bath(args: &SheetsArgs, dir: &Path, files: &mut Vec<PathBuf>) -> Result<Option<Row>> {
    let mut sim = water_bag(args)?;
    sim.set_thermostat(Some(Andersen {
        kt: BATH_KT,
        rate: BATH_RATE,
        seed: args.common.seed,
    }))?;
    let e0 = sim.kinetic_energy() + sim.potential_energy();
    let n = args.n as f64;
    let x0_bath = 2.0 * BATH_KT; // coupling M = 1
    let bins = (2.0 * REACH / BIN).round() as usize;
    let settle = args.bath_time / 4;
    let samples = (args.bath_time - settle) * PER_TIME;
    let per_block = (samples / BLOCKS as u64).max(1);
    let mut counts = vec![vec![0u64; bins]; BLOCKS];
    let (mut kin, mut pot, mut var) = (Vec::new(), Vec::new(), Vec::new());
    let progress = Progress::new(args.bath_time * PER_TIME, "sheets (heat bath)");
    for s in 1..=args.bath_time * PER_TIME {
        let t = s as f64 / PER_TIME as f64;
        if !edmd::run_until_or_stop(&mut sim, t, &mut ())? {
            progress.finish();
            return Ok(None);
        }
        progress.set(s);
        let k = s.checked_sub(settle * PER_TIME + 1);
        let Some(k) = k else { continue };
        let block = ((k / per_block) as usize).min(BLOCKS - 1);
        let plane = phase_plane(&sim);
        let mut x2 = 0.0;
        for &(x, _) in &plane {
            x2 += x * x;
            let b = ((x / x0_bath + REACH) / BIN).floor();
            if b >= 0.0 && (b as usize) < bins {
                counts[block][b as usize] += 1;
            }
        }
        var.push(x2 / n);
        kin.push(sim.kinetic_energy());
        pot.push(sim.potential_energy());
    }
    progress.finish();
    let (ratio, ratio_error) = virial(&kin, &pot);
    let kt_b = block_means(&kin, |k| 2.0 * k / n);
    let (kt, kt_error) = (2.0 * mean(&kin) / n, block_error(&kt_b));
    // x0 from the variance: pi^2 x0^2 / 12.
    let x0_of = |v: f64| (12.0 * v).sqrt() / std::f64::consts::PI;
    let x0_b = block_means(&var, x0_of);
    let (x0, x0_error) = (x0_of(mean(&var)), block_error(&x0_b));
    let (x0_theory, x0_theory_error) = (2.0 * kt, 2.0 * kt_error);
    // The profile: density per unit length, against Spitzer's with the measured kT.
    let width = BIN * x0_bath;
    let block_samples = |b: usize| -> f64 {
        let start = b as u64 * per_block;
        let end = if b + 1 == BLOCKS {
            kin.len() as u64
        } else {
            (b as u64 + 1) * per_block
        };
        end.saturating_sub(start).max(1) as f64
    };
    let mut profile = Vec::new();
    let (mut chi2, mut used) = (0.0, 0usize);
    for j in 0..bins {
        let x = (j as f64 + 0.5) * width - REACH * x0_bath;
        let per_block: Vec<f64> = (0..BLOCKS)
            .map(|b| counts[b][j] as f64 / (block_samples(b) * width))
            .collect();
        let total: u64 = (0..BLOCKS).map(|b| counts[b][j]).sum();
        let density = total as f64 / (kin.len() as f64 * width);
        let error = block_error(&per_block);
        // Spitzer's profile averaged over the bin: N/2 (tanh(b/x0) - tanh(a/x0)) / width.
        let (a, b) = (x - 0.5 * width, x + 0.5 * width);
        let theory = 0.5 * n * ((b / x0_theory).tanh() - (a / x0_theory).tanh()) / width;
        if x.abs() < 3.0 * x0_theory && error > 0.0 {
            chi2 += ((density - theory) / error).powi(2);
            used += 1;
        }
        profile.push([x, density, error, theory]);
    }
    let csv = dir.join("sheets-profile.csv");
    write_csv(
        &csv,
        &["x", "density", "density_error", "isothermal_sheet"],
        profile.iter().map(|p| p.to_vec()),
    )?;
    files.push(csv);
    let (png, svg) = Figure::new(
        &format!(
            "{} sheets, kT = {kt:.3}: x0 = {x0:.3} +- {x0_error:.3} (Spitzer: {x0_theory:.3})",
            args.n
        ),
        "position from the centre of mass, x",
        "sheets per unit length",
    )
    .with(Series::error_bars(
        "edmd",
        profile.iter().map(|p| (p[0], p[1])).collect(),
        profile.iter().map(|p| p[2]).collect(),
    ))
    .with(
        Series::line(
            "isothermal sheet, N/(2 x0) sech^2(x/x0), x0 = 2kT/(coupling M)",
            profile.iter().map(|p| (p[0], p[3])).collect(),
        )
        .coloured(PALETTE[1]),
    )
    .save(&dir.join("sheets-profile"))?;
    files.extend([png, svg]);
    let e1 = sim.kinetic_energy() + sim.potential_energy();
    Ok(Some(Row {
        start: "heat bath",
        n: args.n,
        coupling: 1.0 / n,
        time: args.bath_time as f64,
        kt,
        kt_error,
        virial_ratio: ratio,
        virial_ratio_error: ratio_error,
        virial_theory: 1.0,
        relative_energy_change: (e1 - e0) / e0,
        x0: Some(x0),
        x0_error: Some(x0_error),
        x0_theory: Some(x0_theory),
        x0_theory_error: Some(x0_theory_error),
        profile_chi2: Some(chi2 / used.max(1) as f64),
        profile_bins: Some(used),
        collisions: sim.stats().disc_disc,
        wall_hits: sim.stats().wall,
    }))
}

/// The phase-plane movie: each frame the sheets as dots, position across, velocity up, over
/// twice the water bag each way.
struct Movie {
    encoder: gif::Encoder<AtomicFile>,
}

const MOVIE_W: usize = 480;
const MOVIE_H: usize = 360;
const MOVIE_REACH: f64 = 2.0;

impl Movie {
    fn create(path: &Path) -> Result<Self> {
        let file = AtomicFile::create(path)?;
        let mut encoder =
            gif::Encoder::new(file, MOVIE_W as u16, MOVIE_H as u16, &[]).context("GIF encoder")?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .context("GIF encoder")?;
        Ok(Movie { encoder })
    }

    fn frame(&mut self, points: &[(f64, f64)]) -> Result<()> {
        let mut px = vec![255u8; MOVIE_W * MOVIE_H * 4];
        let mut put = |x: usize, y: usize, rgb: [u8; 3]| {
            if x < MOVIE_W && y < MOVIE_H {
                let k = 4 * (y * MOVIE_W + x);
                px[k..k + 3].copy_from_slice(&rgb);
            }
        };
        // Axes through the origin.
        for x in 0..MOVIE_W {
            put(x, MOVIE_H / 2, [200, 200, 200]);
        }
        for y in 0..MOVIE_H {
            put(MOVIE_W / 2, y, [200, 200, 200]);
        }
        let colour = PALETTE[0];
        for &(x, v) in points {
            let px_x = (0.5 + x / (2.0 * MOVIE_REACH)) * MOVIE_W as f64;
            let px_y = (0.5 - v / (2.0 * MOVIE_REACH)) * MOVIE_H as f64;
            if px_x.is_finite() && px_y.is_finite() && px_x >= 0.0 && px_y >= 0.0 {
                let (cx, cy) = (px_x as usize, px_y as usize);
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    put(cx + dx, cy + dy, colour);
                }
            }
        }
        let mut frame = gif::Frame::from_rgba_speed(MOVIE_W as u16, MOVIE_H as u16, &mut px, 10);
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
