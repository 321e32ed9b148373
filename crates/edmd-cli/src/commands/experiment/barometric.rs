//! `edmd experiment barometric`: a gas column in a uniform field, its density against height
//! against the barometric law (dilute) and the local-density approximation (dense), and its
//! temperature against height (flat: equipartition holds in a field).
//!
//! Each column holds `N` hard discs (spheres with `--dim 3`) of diameter and mass 1 between a
//! floor and a ceiling, periodic sideways, under `g` (`--g`, in units of `kT / (m sigma)` at
//! the bath's `kT = 1`, so that the scale height `lambda = kT / (m g)` is `1/g` diameters). A
//! column is named by its floor packing (`--packing`) in the local-density approximation
//! (LDA) at `kT = 1`; its box is as tall as the LDA column takes to thin to `e^-4` of its
//! floor density (four scale heights for a dilute gas) and as wide as `N` discs need. The discs
//! start on a lattice spread like the LDA profile, are held at `kT = 1` by the Andersen bath
//! for 40 flight times `lambda / sqrt(kT/m)` and left alone for 5, and are then sampled four
//! times per flight time with the energy conserved (`--samples`), in 40 blocks for the errors.
//!
//! Compared with, with `kT` the mean kinetic temperature of the samples and `n(h)` the number
//! density of centres at a height `h` above the lowest a centre can be:
//! - the barometric law `n(h) ∝ exp(-m g h / kT)` normalised over the column, and the scale
//!   height fitted to the measured heights (maximum likelihood: the law's mean height is the
//!   measured one) against `kT / (m g)`;
//! - the LDA: hydrostatic balance `dP/dh = -m g n` with the bulk equation of state
//!   `P = n kT Z(eta)` (Henderson's for discs, Pieprzyk et al.'s for spheres), integrated
//!   upwards by fourth-order Runge-Kutta from a floor density found by bisection so that the
//!   column holds `N` (`edmd_core::measure::column`). The walls' own layering (particles pack
//!   against a hard wall, a few diameters deep in a dense fluid) is not in it, so the profiles
//!   are compared from [`FLOOR_LAYERS`] diameters above the floor.

mod output;
mod run;

use anyhow::Result;
use clap::Args;
use edmd_core::measure::column::{
    barometric_density, barometric_mean_height, lda_profile, scale_height_from_mean, Column,
    HardFluid, Profile,
};
use edmd_core::measure::{block_error, Estimate};
use serde::Serialize;

use super::common::{
    check_count, check_n, check_once, files_line, interrupted_after, out_dir, outputs, report,
    CommonArgs, Progress,
};
use run::{Plan, Samples, BLOCKS};

/// Options of `edmd experiment barometric`.
#[derive(Debug, Args)]
pub struct BarometricArgs {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[arg(long, default_value_t = 2, value_parser = crate::args::parse_dim)]
    pub dim: usize,
    /// Packing fractions at the floor, one column each, comma-separated: the LDA's at the
    /// bath's kT = 1, which sets the box's width [default: 2D 0.01,0.55; 3D 0.01,0.4].
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub packing: Option<Vec<f64>>,
    /// Particles per column [default: 1000 discs, 2000 spheres].
    #[arg(long, allow_negative_numbers = true)]
    pub n: Option<usize>,
    /// Strength of the field in units of kT/(m sigma) at the bath's kT = 1: the scale height
    /// kT/(m g) is 1/g diameters. It pulls towards the floor.
    #[arg(long, default_value_t = 0.2, allow_negative_numbers = true)]
    pub g: f64,
    /// Samples of the heights per column, a quarter of a flight time lambda/sqrt(kT/m) apart.
    #[arg(long, default_value_t = 2000, allow_negative_numbers = true)]
    pub samples: u64,
    /// Width of the density's height bins, in diameters.
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    pub bin: f64,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// One column.
#[derive(Debug, Serialize)]
pub struct Row {
    /// Dimension.
    pub dim: usize,
    /// Particles.
    pub n: usize,
    /// Strength of the field (pulling towards the floor).
    pub g: f64,
    /// The floor packing the column was built for (the LDA's at kT = 1).
    pub packing: f64,
    /// The box's edge across the field (diameters).
    pub box_width: f64,
    /// The box's height (diameters); the centres range over it less a diameter.
    pub box_height: f64,
    /// Mean kinetic temperature `sum m v^2 / (dim N)` over the samples.
    pub kt: f64,
    /// Its error (blocks).
    pub kt_error: f64,
    /// The temperature's slope against height, in `kT` per scale height (0 in equilibrium).
    pub kt_slope: f64,
    /// Its error.
    pub kt_slope_error: f64,
    /// `sum ((T_k - kT) / error_k)^2 / bins` over the temperature's bins (about a diameter).
    pub kt_chi2: f64,
    /// The temperature's bins.
    pub kt_bins: usize,
    /// The scale height fitted to the heights (the barometric law's with their mean height).
    pub scale_height: f64,
    /// Its error (blocks).
    pub scale_height_error: f64,
    /// `kT / (m g)` with the measured kT.
    pub scale_height_theory: f64,
    /// Its error, from kT's. The fitted and the theory's errors are anticorrelated (the energy
    /// is conserved: a column that stands higher is cooler), so that their difference's error
    /// is up to their sum.
    pub scale_height_theory_error: f64,
    /// The same fit to the LDA's profile: the barometric scale height with excluded volume.
    pub scale_height_lda: f64,
    /// Mean height of the centres above the lowest they can be.
    pub mean_height: f64,
    /// Its error.
    pub mean_height_error: f64,
    /// The barometric law's.
    pub mean_height_barometric: f64,
    /// The LDA's.
    pub mean_height_lda: f64,
    /// The LDA's floor packing with the measured kT.
    pub packing_floor_lda: f64,
    /// The density is compared from this height (diameters above the lowest a centre can be).
    pub compared_from: f64,
    /// The bins compared (about a diameter each).
    pub bins_compared: usize,
    /// `sum ((n_k - barometric_k) / error_k)^2 / bins_compared`.
    pub chi2_barometric: f64,
    /// `sum ((n_k - lda_k) / error_k)^2 / bins_compared`.
    pub chi2_lda: f64,
    /// The largest difference of packing fraction between the bins and the barometric law.
    pub packing_max_deviation_barometric: f64,
    /// The largest difference of packing fraction between the bins and the LDA.
    pub packing_max_deviation_lda: f64,
    /// `sum ((n_k - lda_k) / error_k)^2 / bins_compared` with the LDA of the column above
    /// `compared_from` holding what was measured there: hydrostatics above the floor's layers,
    /// which take their own share of the particles.
    pub chi2_lda_above: f64,
    /// The largest difference of packing fraction between the bins and that LDA.
    pub packing_max_deviation_lda_above: f64,
    /// Particles below `compared_from` per unit area of floor, less the LDA's there: the
    /// walls' layering (the excess the floor adsorbs).
    pub floor_excess: f64,
    /// Its error.
    pub floor_excess_error: f64,
    /// Samples.
    pub samples: usize,
    /// The time between samples: a quarter of the flight time `lambda / sqrt(kT/m)`, or half
    /// the mean free time when that is longer.
    pub sample_interval: f64,
    /// Blocks the errors come from.
    pub blocks: usize,
    /// Simulated time measured over.
    pub time: f64,
    /// Disc-disc collisions while measuring.
    pub collisions: u64,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Dimension.
    pub dim: usize,
    /// Particles per column.
    pub n: usize,
    /// One row per column.
    pub rows: Vec<Row>,
    /// What the rows are compared with.
    pub theory: &'static str,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

const THEORY: &str = "scale_height_theory = kT/(m g) with the measured kT (the barometric law n(h) ∝ exp(-m g h/kT), normalised over the column); scale_height: the law fitted to the measured heights by maximum likelihood (its mean height equal to theirs); lda: the local-density approximation, hydrostatic balance dP/dh = -m g n with P = n kT Z(eta), Z Henderson's (discs, Mol. Phys. 30, 971 (1975)) or Pieprzyk et al.'s (spheres, Phys. Chem. Chem. Phys. 21, 6886 (2019)), RK4 upwards from a floor density found by bisection so that the column holds N; profiles compared from compared_from above the floor (the walls' layering is in neither theory); kt_slope: 0 (equipartition in a field)";

/// The floor's layering is left out of the comparison up to this height (diameters): in the
/// dense discs the layers against the floor fade within about four diameters.
pub const FLOOR_LAYERS: f64 = 5.0;

/// The most samples per column.
const MAX_SAMPLES: u64 = 1_000_000;

/// Runs the experiment.
pub fn run(args: &BarometricArgs) -> Result<()> {
    match args.dim {
        3 => run_in::<3>(args),
        _ => run_in::<2>(args),
    }
}

fn check(args: &BarometricArgs, packings: &[f64], n: usize, dim: usize) -> Result<()> {
    let bad = |m: String| edmd::user_error(format!("barometric: {m}"));
    let g = args.g;
    if !(g.is_finite() && (0.01..=2.0).contains(&g)) {
        return bad(format!(
            "--g must be from 0.01 to 2 (a scale height kT/(m g) from 100 to half a diameter), found {g}"
        ));
    }
    if packings.is_empty() {
        return bad("give at least one --packing".into());
    }
    // A fluid at the floor: discs below 0.65 (they freeze near 0.70), spheres below 0.45 (0.494).
    let top = if dim == 3 { 0.45 } else { 0.65 };
    if let Some(p) = packings
        .iter()
        .find(|&&p| !(p.is_finite() && (0.001..=top).contains(&p)))
    {
        return bad(format!(
            "--packing {p} is outside [0.001, {top}] (the floor packing of a fluid column)"
        ));
    }
    check_once("barometric", "--packing", packings)?;
    check_n("barometric", n, 50)?;
    check_count(
        "barometric",
        "samples",
        args.samples,
        2 * BLOCKS as u64,
        MAX_SAMPLES,
    )?;
    let b = args.bin;
    if !(b.is_finite() && (0.01..=1.0).contains(&b)) {
        return bad(format!("--bin must be from 0.01 to 1 diameter, found {b}"));
    }
    Ok(())
}

/// A column's results: its row and profiles.
pub(super) struct Measured {
    pub row: Row,
    /// Fine bins: `(height, density, error, barometric, lda, lda above compared_from)`.
    pub density: Vec<[f64; 6]>,
    /// Coarse bins: `(height, kT, error)`.
    pub temperature: Vec<[f64; 3]>,
}

/// The mean of `f` over `[lo, hi]`, by Simpson's rule on eight intervals.
fn bin_mean(f: &dyn Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let k = 8;
    let w = (hi - lo) / k as f64;
    let sum: f64 = (0..=k)
        .map(|i| {
            let c = if i == 0 || i == k {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            c * f(lo + i as f64 * w)
        })
        .sum();
    sum * w / 3.0 / (hi - lo)
}

/// Per bin of `counts` (blocks by bins): the density of each block, `count / (samples area
/// width)`.
fn block_densities(counts: &[Vec<u64>], samples: usize, area: f64, width: f64) -> Vec<Vec<f64>> {
    counts
        .iter()
        .map(|c| {
            c.iter()
                .map(|&k| k as f64 / (samples as f64 * area * width))
                .collect()
        })
        .collect()
}

/// The mean over blocks of bin `k`, and its error.
fn over_blocks(blocks: &[Vec<f64>], k: usize) -> (f64, f64) {
    let v: Vec<f64> = blocks.iter().map(|b| b[k]).collect();
    (v.iter().sum::<f64>() / v.len() as f64, block_error(&v))
}

/// The weighted least-squares slope of `(x, y, error)` points.
fn weighted_slope(points: &[(f64, f64, f64)]) -> f64 {
    let (mut sw, mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &(x, y, e) in points {
        let w = 1.0 / (e * e);
        sw += w;
        sx += w * x;
        sy += w * y;
        sxx += w * x * x;
        sxy += w * x * y;
    }
    (sw * sxy - sx * sy) / (sw * sxx - sx * sx)
}

/// Turns a column's samples into its row and profiles.
fn analyse<const D: usize>(
    args: &BarometricArgs,
    packing: f64,
    plan: &Plan,
    s: &Samples,
) -> Measured {
    let n = plan_n(s);
    let fluid = HardFluid::reference(D);
    let area = plan.width.powi(D as i32 - 1);
    let height = plan.height;
    let total = BLOCKS * s.per_block;
    // kT from the kinetic energy: m v^2 per degree of freedom.
    let kt_blocks: Vec<f64> = s
        .mv2
        .iter()
        .map(|&e| e / (D as f64 * n as f64 * s.per_block as f64))
        .collect();
    let kt = Estimate::new(kt_blocks.iter().sum::<f64>() / BLOCKS as f64, &kt_blocks);
    let lambda = kt.value / args.g;
    let column = Column {
        scale_height: lambda,
        height,
        load: n as f64 / area,
    };
    // The LDA can always hold the column the bath's kT built, and the measured kT is within a
    // few per cent of it; the barometric law stands in should it not.
    let lda = lda_profile(&fluid, &column, 4000).unwrap_or_else(|| Profile {
        step: height,
        density: vec![
            barometric_density(0.0, &column),
            barometric_density(height, &column),
        ],
    });
    let baro = |h: f64| barometric_density(h, &column);
    let lda_at = |h: f64| lda.at(h);

    // Heights: the mean and the fitted scale height, per block.
    let means: Vec<f64> = s
        .height_sums
        .iter()
        .map(|&h| h / (n * s.per_block) as f64)
        .collect();
    let mean = means.iter().sum::<f64>() / BLOCKS as f64;
    let fit = |m: f64| scale_height_from_mean(m, height).unwrap_or(f64::NAN);
    let fits: Vec<f64> = means.iter().map(|&m| fit(m)).collect();

    // Coarse bins, for the comparison and the temperature. Those below the floor's layers
    // give the particles the walls hold there, and the LDA of the column above them.
    let coarse = s.coarse_counts[0].len();
    let cw = height / coarse as f64;
    let coarse_blocks = block_densities(&s.coarse_counts, s.per_block, area, cw);
    let layers = ((FLOOR_LAYERS / cw - 1e-9).ceil() as usize).min(coarse - 1);
    let compared_from = layers as f64 * cw;
    let below: Vec<f64> = coarse_blocks
        .iter()
        .map(|b| b[..layers].iter().sum::<f64>() * cw)
        .collect();
    let lda_below: f64 = (0..layers)
        .map(|k| bin_mean(&lda_at, k as f64 * cw, (k + 1) as f64 * cw) * cw)
        .sum();
    let excess: Vec<f64> = below.iter().map(|x| x - lda_below).collect();
    let above = Column {
        height: height - compared_from,
        load: column.load - below.iter().sum::<f64>() / BLOCKS as f64,
        ..column
    };
    let lda_above = lda_profile(&fluid, &above, 4000);
    let above_at = |h: f64| {
        lda_above
            .as_ref()
            .filter(|_| h >= compared_from - 1e-9)
            .map_or(f64::NAN, |p| p.at(h - compared_from))
    };
    let v = fluid.particle_volume;
    let mut chi = [0.0; 3];
    let mut dev = [0.0f64; 3];
    let mut compared = 0;
    for k in layers..coarse {
        let (lo, hi) = (k as f64 * cw, (k + 1) as f64 * cw);
        let (d, e) = over_blocks(&coarse_blocks, k);
        let theory = [
            bin_mean(&baro, lo, hi),
            bin_mean(&lda_at, lo, hi),
            bin_mean(&above_at, lo, hi),
        ];
        for (j, t) in theory.iter().enumerate() {
            if e > 0.0 {
                chi[j] += ((d - t) / e).powi(2);
            }
            dev[j] = dev[j].max(v * (d - t).abs());
        }
        compared += usize::from(e > 0.0);
    }
    let chi: Vec<f64> = chi.iter().map(|c| c / compared.max(1) as f64).collect();

    // Fine bins, for the profiles.
    let fine = s.counts[0].len();
    let fw = height / fine as f64;
    let fine_blocks = block_densities(&s.counts, s.per_block, area, fw);
    let density: Vec<[f64; 6]> = (0..fine)
        .map(|k| {
            let (lo, hi) = (k as f64 * fw, (k + 1) as f64 * fw);
            let (d, e) = over_blocks(&fine_blocks, k);
            let above = if lo >= compared_from - 1e-9 {
                bin_mean(&above_at, lo, hi)
            } else {
                f64::NAN
            };
            [
                0.5 * (lo + hi),
                d,
                e,
                bin_mean(&baro, lo, hi),
                bin_mean(&lda_at, lo, hi),
                above,
            ]
        })
        .collect();

    // The temperature per coarse bin and block, where the block saw the bin.
    let block_kt = |b: usize, k: usize| {
        let c = s.coarse_counts[b][k];
        (c > 0).then(|| s.coarse_mv2[b][k] / (D as f64 * c as f64))
    };
    let mut kept = Vec::new();
    let mut temperature: Vec<[f64; 3]> = Vec::new();
    for k in 0..coarse {
        let per: Vec<f64> = (0..BLOCKS).filter_map(|b| block_kt(b, k)).collect();
        let count: u64 = (0..BLOCKS).map(|b| s.coarse_counts[b][k]).sum();
        let sum: f64 = (0..BLOCKS).map(|b| s.coarse_mv2[b][k]).sum();
        let e = block_error(&per);
        // A bin most blocks saw, with an error to weigh it by.
        if per.len() >= BLOCKS / 2 && e > 0.0 {
            kept.push(k);
            temperature.push([(k as f64 + 0.5) * cw, sum / (D as f64 * count as f64), e]);
        }
    }
    // The slope in kT per scale height, and its error from each block's own slope: the bins
    // of a block share its fluctuations of the kinetic energy, so their errors are not
    // independent.
    let slope_of = |values: &dyn Fn(usize) -> Option<f64>| {
        // `values(j)`: the temperature of the `j`th kept bin.
        let points: Vec<(f64, f64, f64)> = temperature
            .iter()
            .enumerate()
            .filter_map(|(j, t)| values(j).map(|v| (t[0] / lambda, v / kt.value, t[2] / kt.value)))
            .collect();
        weighted_slope(&points)
    };
    let slope = slope_of(&|j| Some(temperature[j][1]));
    let slopes: Vec<f64> = (0..BLOCKS)
        .map(|b| slope_of(&|j| block_kt(b, kept[j])))
        .collect();
    let slope_error = block_error(&slopes);
    let kt_chi2 = temperature
        .iter()
        .map(|t| ((t[1] - kt.value) / t[2]).powi(2))
        .sum::<f64>()
        / temperature.len().max(1) as f64;

    let row = Row {
        dim: D,
        n,
        g: args.g,
        packing,
        box_width: plan.width,
        box_height: height + 1.0,
        kt: kt.value,
        kt_error: kt.error,
        kt_slope: slope,
        kt_slope_error: slope_error,
        kt_chi2,
        kt_bins: temperature.len(),
        scale_height: fit(mean),
        scale_height_error: block_error(&fits),
        scale_height_theory: lambda,
        scale_height_theory_error: kt.error / args.g,
        scale_height_lda: fit(lda.mean_height()),
        mean_height: mean,
        mean_height_error: block_error(&means),
        mean_height_barometric: barometric_mean_height(lambda, height),
        mean_height_lda: lda.mean_height(),
        packing_floor_lda: v * lda.floor_density(),
        compared_from,
        bins_compared: compared,
        chi2_barometric: chi[0],
        chi2_lda: chi[1],
        packing_max_deviation_barometric: dev[0],
        packing_max_deviation_lda: dev[1],
        chi2_lda_above: chi[2],
        packing_max_deviation_lda_above: dev[2],
        floor_excess: excess.iter().sum::<f64>() / BLOCKS as f64,
        floor_excess_error: block_error(&excess),
        samples: total,
        sample_interval: s.interval,
        blocks: BLOCKS,
        time: s.time,
        collisions: s.collisions,
    };
    Measured {
        row,
        density,
        temperature,
    }
}

/// The particles a column's samples counted.
fn plan_n(s: &Samples) -> usize {
    (s.counts[0].iter().sum::<u64>() / s.per_block as u64) as usize
}

fn run_in<const D: usize>(args: &BarometricArgs) -> Result<()> {
    let packings = args
        .packing
        .clone()
        .unwrap_or_else(|| vec![0.01, if D == 3 { 0.4 } else { 0.55 }]);
    let n = args.n.unwrap_or(if D == 3 { 2000 } else { 1000 });
    check(args, &packings, n, D)?;
    let plans: Vec<Plan> = packings
        .iter()
        .map(|&p| run::plan::<D>(n, p, args.g))
        .collect();
    let seed = |k: usize| args.common.seed.wrapping_add(k as u64);
    let mut starts = Vec::new();
    for (k, (plan, &p)) in plans.iter().zip(&packings).enumerate() {
        // Sideways the box must leave a disc room beside its own image.
        let placed = (plan.width >= 3.0)
            .then(|| run::place::<D>(plan, n, seed(k)))
            .flatten();
        let Some(discs) = placed else {
            let least = (plan.profile.load() * 3f64.powi(D as i32 - 1)).ceil();
            return edmd::user_error(format!(
                "barometric: --n {n} is too few for a column at packing {p}: its box would be {:.2} wide; give at least {least}",
                plan.width
            ));
        };
        starts.push(discs);
    }
    let figures: Vec<String> = packings
        .iter()
        .map(|p| format!("barometric-packing-{p}"))
        .chain(["barometric-temperature".to_string()])
        .collect();
    let tables = ["barometric", "barometric-temperature"].map(String::from);
    let dir = out_dir(&args.common, &outputs(&tables, &figures))?;
    let per_block = (args.samples as usize).div_ceil(BLOCKS);
    let len = (packings.len() * BLOCKS * per_block) as u64;
    let bar = Progress::new(len, "barometric");
    let mut columns = Vec::new();
    for (k, ((plan, discs), &p)) in plans.iter().zip(&starts).zip(&packings).enumerate() {
        let fine = ((plan.height / args.bin).round() as usize).max(1);
        let coarse = (plan.height.round() as usize).max(1);
        let done = (k * BLOCKS * per_block) as u64;
        match run::measure::<D>(
            plan,
            discs,
            args.g,
            (fine, coarse),
            per_block,
            seed(k),
            &bar,
            done,
        )? {
            Some(s) => columns.push(analyse::<D>(args, p, plan, &s)),
            None => break,
        }
    }
    bar.finish();
    let interrupted = columns.len() < packings.len();
    let files = output::write(dir, args, &columns)?;
    let mut human = output::human(&columns, interrupted);
    human += &files_line(&files);
    report(
        &args.common,
        &Summary {
            experiment: "barometric",
            dim: D,
            n,
            rows: columns.into_iter().map(|c| c.row).collect(),
            theory: THEORY,
            interrupted,
        },
        &human,
    )?;
    if interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}
