//! `edmd experiment jamming`: the jamming packing fraction against the growth rate.
//!
//! For each growth rate G and each of `--seeds` random starts, a Lubachevsky-Stillinger
//! compression (`edmd_core::pack`, as `edmd pack` runs it) to the reduced pressure
//! `--pressure`; then the mean packing fraction phi_J with its standard error, the contacts per
//! non-rattler, the rattler fraction and the collisions. Slower compression packs denser
//! (M. Skoge, A. Donev, F. H. Stillinger and S. Torquato, PRE 74, 041127 (2006)): monodisperse
//! spheres approach random close packing, about 0.64, at moderate rates and crystallise
//! (towards FCC, 0.7405) at slow ones; the 50:50 bidisperse discs of diameter ratio 1.4, the
//! standard 2D glass former, jam near 0.84 (C. S. O'Hern, L. E. Silbert, A. J. Liu and
//! S. R. Nagel, PRE 68, 011306 (2003)). A run whose packing fraction exceeds
//! `--crystal-packing` counts as crystallised.
//!
//! Every rate uses the same seeds, so each rate starts from the same random starts and the
//! differences between rates are not blurred by the starts.

use std::time::Instant;

use anyhow::Result;
use clap::Args;
use edmd_core::pack::{contacts, gap_tolerance, random_start, PackOptions, PackSizes, Packer};
use edmd_core::pack::{Packing, Stop};
use edmd_core::Boundary;
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_count, check_n, check_once, files_line, interrupted_after, out_dir, outputs, report,
    stop_requested, write_csv, CommonArgs, Progress,
};

/// Options of `edmd experiment jamming`.
#[derive(Debug, Args)]
pub struct JammingArgs {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[arg(long, default_value_t = 3, value_parser = crate::args::parse_dim)]
    pub dim: usize,
    /// Number of particles.
    #[arg(long, default_value_t = 500, allow_negative_numbers = true)]
    pub n: usize,
    /// Growth rates G (dD/dt = G v_rms), comma-separated, each in (0, 1].
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.2,0.05,0.02,0.005",
        allow_negative_numbers = true
    )]
    pub rates: Vec<f64>,
    /// Random starts per rate (seeds --seed, --seed + 1, ...), for the mean and its error.
    #[arg(long, default_value_t = 3, allow_negative_numbers = true)]
    pub seeds: u64,
    /// Bidisperse: diameter ratio large/small [default: 1.4 in 2D (with --fraction-large
    /// 0.5, the standard glass former); 1, monodisperse, in 3D].
    #[arg(long, value_parser = crate::args::parse_positive, allow_negative_numbers = true)]
    pub size_ratio: Option<f64>,
    /// Bidisperse: number fraction of large particles [default: 0.5].
    #[arg(long, allow_negative_numbers = true)]
    pub fraction_large: Option<f64>,
    /// Stop each compression when the reduced pressure PV/(NkT) passes this. The default 1e9
    /// (edmd pack's is 1e12) moves the packing fraction by about 1e-9 (phi_J - phi ~ 1/p) and
    /// saves a quarter of the collisions.
    #[arg(long, default_value_t = 1e9, value_parser = crate::args::parse_positive, allow_negative_numbers = true)]
    pub pressure: f64,
    /// A run that ends above this packing fraction counts as crystallised [default: 0.66 in
    /// 3D, above the random close packing; 0.86 in 2D, above the bidisperse discs' jammed
    /// range].
    #[arg(long, value_parser = crate::args::parse_positive, allow_negative_numbers = true)]
    pub crystal_packing: Option<f64>,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// One compression.
#[derive(Debug, Serialize)]
pub struct Run {
    /// Seed of the random start.
    pub seed: u64,
    /// Final packing fraction.
    pub packing_fraction: f64,
    /// Final reduced pressure (null if none was measured).
    pub reduced_pressure: Option<f64>,
    /// Why it stopped: pressure or converged.
    pub stop: &'static str,
    /// Contacts per non-rattler (null if every particle rattles).
    pub mean_contacts: Option<f64>,
    /// Rattlers over particles.
    pub rattler_fraction: f64,
    /// Pair collisions.
    pub collisions: u64,
    /// Wall-clock seconds.
    pub wall_seconds: f64,
}

/// One growth rate.
#[derive(Debug, Serialize)]
pub struct Row {
    /// Growth rate G.
    pub rate: f64,
    /// Mean final packing fraction over the runs.
    pub packing_fraction: f64,
    /// Its standard error (null with one run).
    pub packing_fraction_err: Option<f64>,
    /// Mean contacts per non-rattler, over the runs that have non-rattlers (null if none).
    pub mean_contacts: Option<f64>,
    /// Mean rattler fraction.
    pub rattler_fraction: f64,
    /// Fraction of runs above the crystal packing fraction.
    pub crystallised: f64,
    /// Mean pair collisions per run.
    pub collisions: f64,
    /// Mean wall-clock seconds per run.
    pub wall_seconds: f64,
    /// Every run.
    pub runs: Vec<Run>,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Dimension.
    pub dim: usize,
    /// Particles.
    pub n: usize,
    /// Large over small diameter.
    pub size_ratio: f64,
    /// Number fraction of large particles.
    pub fraction_large: f64,
    /// Reduced pressure each compression stops at.
    pub pressure: f64,
    /// Packing fraction above which a run counts as crystallised.
    pub crystal_packing: f64,
    /// One entry per rate.
    pub rows: Vec<Row>,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

/// Runs the experiment.
pub fn run(args: &JammingArgs) -> Result<()> {
    match args.dim {
        3 => run_in::<3>(args),
        _ => run_in::<2>(args),
    }
}

/// Mean and standard error of the mean (`None` for fewer than two values).
fn mean_err(xs: &[f64]) -> (f64, Option<f64>) {
    let k = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / k;
    if xs.len() < 2 {
        return (mean, None);
    }
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (k - 1.0);
    (mean, Some((var / k).sqrt()))
}

/// The legend of the reference code's points: the figures were measured once with Skoge and
/// Donev's `spheres` (the README gives them), not on the machine that draws the plot, which the
/// legend said ("this machine").
const REFERENCE_POINTS: &str = "Skoge-Donev spheres code, N = 1000 (measured for the edmd README)";

/// The reference lines and points that apply to these sizes: `(label, phi)` lines and the
/// reference code's `(G, phi)` points.
#[allow(clippy::type_complexity)]
fn references(dim: usize, ratio: f64, large: f64) -> (Vec<(&'static str, f64)>, Vec<(f64, f64)>) {
    if dim == 3 && ratio == 1.0 {
        (
            vec![
                ("random close packing 0.64 (Skoge et al. 2006)", 0.64),
                ("FCC crystal 0.7405", 0.7405),
            ],
            vec![(0.2, 0.612), (0.02, 0.6375), (0.002, 0.648)],
        )
    } else if dim == 2 && ratio == 1.4 && large == 0.5 {
        (
            vec![("jamming 0.84 (O'Hern et al. 2003)", 0.84)],
            vec![(0.2, 0.8245), (0.02, 0.841), (0.002, 0.847)],
        )
    } else {
        (Vec::new(), Vec::new())
    }
}

/// A message of the compression, in jamming's words (`--rates` for pack's `--growth-rate`),
/// naming after it the `options` a refused value came from; a compression that failed on the
/// way says its own cause.
fn message(e: impl std::fmt::Display, options: Option<&str>) -> String {
    let e = e.to_string();
    let e = e.strip_prefix("pack: ").unwrap_or(&e);
    let e = e.replace("a larger --growth-rate", "faster --rates");
    match options {
        Some(o) if !e.contains("--") => format!("jamming: {e} ({o})"),
        _ => format!("jamming: {e}"),
    }
}

fn run_in<const D: usize>(args: &JammingArgs) -> Result<()> {
    check_count("jamming", "seeds", args.seeds, 1, 10_000)?;
    if args.rates.is_empty() {
        return edmd::user_error("jamming: give at least one growth rate (--rates)");
    }
    if args.rates.len() > 1000 {
        return edmd::user_error("jamming: at most 1000 growth rates");
    }
    check_once("jamming", "--rates", &args.rates)?;
    let options = |rate: f64| PackOptions {
        growth_rate: rate,
        max_pressure: args.pressure,
        ..PackOptions::default()
    };
    for &rate in &args.rates {
        options(rate)
            .validate()
            .or_else(|e| edmd::user_error(message(e, Some("--rates, --pressure"))))?;
    }
    let (ratio, large) = match (args.size_ratio, args.fraction_large) {
        (None, f) if D == 2 => (1.4, f.unwrap_or(0.5)),
        (None, None) => (1.0, 0.0),
        (None, Some(_)) => return edmd::user_error(
            "jamming: --fraction-large needs --size-ratio for spheres (monodisperse by default)",
        ),
        (Some(r), f) => (r, f.unwrap_or(0.5)),
    };
    let sizes = PackSizes::Binary {
        size_ratio: ratio,
        fraction_large: large,
    };
    sizes
        .validate()
        .or_else(|e| edmd::user_error(message(e, Some("--size-ratio, --fraction-large"))))?;
    // A compression stops with an error once the largest particle has grown to a third of the
    // periodic box. No packing fraction exceeds 1, so with N at least this the largest
    // diameter stays below a third of the box: (d_max / L)^D <= max(1, r)^D / (v_D (N_small +
    // N_large r^D)) with v_D the volume of a ball of diameter 1.
    let d = D as i32;
    let unit_ball = edmd_core::setup::lattice::ball_volume(1.0, D);
    let per_particle = (1.0 - large) + large * ratio.powi(d);
    let least =
        (3f64.powi(d) * ratio.max(1.0).powi(d) / (unit_ball * per_particle)).floor() as usize + 2;
    check_n("jamming", args.n, least)?;
    let crystal = args
        .crystal_packing
        .unwrap_or(if D == 3 { 0.66 } else { 0.86 });
    // A packing fraction: above 0 and below 1 (no packing fills space).
    if !(crystal > 0.0 && crystal < 1.0) {
        return edmd::user_error(format!(
            "jamming: --crystal-packing must be above 0 and below 1, found {crystal}"
        ));
    }
    // A growth rate too slow for double precision in this box is refused by the compression
    // as it starts: ask it before the work, on the first start.
    let (discs, sim_box) = random_start::<D>(args.n, sizes, Boundary::Periodic, args.common.seed)
        .or_else(|e| edmd::user_error(message(e, Some("--n"))))?;
    let packer = Packer::new(&discs, sim_box, options(args.rates[0]))
        .or_else(|e| edmd::user_error(message(e, Some("--rates"))))?;
    for &rate in &args.rates[1..] {
        packer
            .check_growth_rate(rate)
            .or_else(|e| edmd::user_error(message(e, Some("--rates"))))?;
    }
    drop(packer);
    let dir = out_dir(
        &args.common,
        &outputs(&["jamming", "jamming_runs"], &["jamming"]),
    )?;
    let total = args.rates.len() as u64 * args.seeds;
    let progress = Progress::new(total, "jamming");
    let mut rows = Vec::new();
    let mut done = 0;
    let mut interrupted = false;
    'rates: for &rate in &args.rates {
        let mut runs = Vec::new();
        for k in 0..args.seeds {
            if stop_requested() {
                interrupted = true;
            }
            if interrupted {
                break;
            }
            let seed = args.common.seed.wrapping_add(k);
            let (discs, sim_box) = random_start::<D>(args.n, sizes, Boundary::Periodic, seed)
                .or_else(|e| edmd::user_error(message(e, Some("--n"))))?;
            let start = Instant::now();
            let packing: Packing<D> = Packer::new(&discs, sim_box, options(rate))
                .and_then(|p| p.run_watched(|_| !stop_requested(), stop_requested))
                .or_else(|e| edmd::user_error(message(e, None)))?;
            if packing.stop == Stop::Interrupted {
                interrupted = true;
                break;
            }
            let wall_seconds = start.elapsed().as_secs_f64();
            let tol = gap_tolerance(packing.reduced_pressure.unwrap_or(1.0), D);
            let c = contacts(&packing.discs, &packing.sim_box, tol);
            runs.push(Run {
                seed,
                packing_fraction: packing.packing_fraction,
                reduced_pressure: packing.reduced_pressure,
                stop: packing.stop.name(),
                mean_contacts: c.mean_contacts.is_finite().then_some(c.mean_contacts),
                rattler_fraction: c.rattlers as f64 / args.n as f64,
                collisions: packing.collisions,
                wall_seconds,
            });
            done += 1;
            progress.set(done);
        }
        if !runs.is_empty() {
            let k = runs.len() as f64;
            let phis: Vec<f64> = runs.iter().map(|r| r.packing_fraction).collect();
            let (phi, phi_err) = mean_err(&phis);
            let z: Vec<f64> = runs.iter().filter_map(|r| r.mean_contacts).collect();
            rows.push(Row {
                rate,
                packing_fraction: phi,
                packing_fraction_err: phi_err,
                mean_contacts: (!z.is_empty()).then(|| mean_err(&z).0),
                rattler_fraction: runs.iter().map(|r| r.rattler_fraction).sum::<f64>() / k,
                crystallised: phis.iter().filter(|&&p| p > crystal).count() as f64 / k,
                collisions: runs.iter().map(|r| r.collisions as f64).sum::<f64>() / k,
                wall_seconds: runs.iter().map(|r| r.wall_seconds).sum::<f64>() / k,
                runs,
            });
        }
        if interrupted {
            break 'rates;
        }
    }
    progress.finish();
    if rows.is_empty() {
        // Stopped before the first rate was done: earlier results in the folder are kept.
        return interrupted_after(&[]);
    }
    let nan = |x: Option<f64>| x.unwrap_or(f64::NAN);
    let csv = dir.join("jamming.csv");
    write_csv(
        &csv,
        &[
            "rate",
            "packing_fraction",
            "packing_fraction_err",
            "mean_contacts",
            "rattler_fraction",
            "crystallised",
            "collisions",
            "runs",
        ],
        rows.iter().map(|r| {
            vec![
                r.rate,
                r.packing_fraction,
                nan(r.packing_fraction_err),
                nan(r.mean_contacts),
                r.rattler_fraction,
                r.crystallised,
                r.collisions,
                r.runs.len() as f64,
            ]
        }),
    )?;
    let runs_csv = dir.join("jamming_runs.csv");
    write_csv(
        &runs_csv,
        &[
            "rate",
            "seed",
            "packing_fraction",
            "reduced_pressure",
            "mean_contacts",
            "rattler_fraction",
            "collisions",
            "wall_seconds",
        ],
        rows.iter().flat_map(|row| {
            row.runs.iter().map(move |r| {
                vec![
                    row.rate,
                    r.seed as f64,
                    r.packing_fraction,
                    nan(r.reduced_pressure),
                    nan(r.mean_contacts),
                    r.rattler_fraction,
                    r.collisions as f64,
                    r.wall_seconds,
                ]
            })
        }),
    )?;

    // The plot: phi_J against log10 G (edmd-plot has no logarithmic x axis).
    let what = if D == 3 { "spheres" } else { "discs" };
    let (lines, reference_points) = references(D, ratio, large);
    let xs: Vec<f64> = args
        .rates
        .iter()
        .chain(reference_points.iter().map(|p| &p.0))
        .map(|g| g.log10())
        .collect();
    let x_lo = xs.iter().cloned().fold(f64::INFINITY, f64::min) - 0.25;
    let x_hi = xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max) + 0.25;
    let sizes_text = if ratio == 1.0 {
        "monodisperse".to_string()
    } else {
        format!(
            "{}:{} mixture, ratio {ratio}",
            100.0 * large,
            100.0 * (1.0 - large)
        )
    };
    let mut figure = Figure::new(
        &format!("Jammed packing fraction vs growth rate ({} {what})", args.n),
        "log10 G (growth rate dD/dt / v_rms)",
        "packing fraction at jamming",
    )
    .with_x_range(x_lo, x_hi);
    for (label, phi) in &lines {
        figure = figure.with(Series::line(label, vec![(x_lo, *phi), (x_hi, *phi)]));
    }
    if !reference_points.is_empty() {
        figure = figure.with(Series::points(
            REFERENCE_POINTS,
            reference_points
                .iter()
                .map(|&(g, phi)| (g.log10(), phi))
                .collect(),
        ));
    }
    let (png, svg) = figure
        .with(Series::error_bars(
            &format!("edmd, mean of {} starts", args.seeds),
            rows.iter()
                .map(|r| (r.rate.log10(), r.packing_fraction))
                .collect(),
            rows.iter()
                .map(|r| r.packing_fraction_err.unwrap_or(0.0))
                .collect(),
        ))
        .save(&dir.join("jamming"))?;

    let mut human = format!(
        "jamming, {} {what} ({sizes_text}), periodic box, to reduced pressure {:.0e}, {} start{} per rate:\n       G   packing    error  contacts  rattlers  crystallised  collisions\n",
        args.n,
        args.pressure,
        args.seeds,
        if args.seeds == 1 { "" } else { "s" }
    );
    // A value that does not exist (one start has no spread; a packing whose every particle
    // rattles has no contacts) is a dash, not a NaN.
    let or_dash = |x: Option<f64>, width: usize, digits: usize| {
        x.map_or(format!("{:>width$}", "-"), |x| {
            format!("{x:width$.digits$}")
        })
    };
    for r in &rows {
        human += &format!(
            "  {:6.4}  {:8.5}  {}  {}  {:7.1}%  {:11.0}%  {:10.3e}\n",
            r.rate,
            r.packing_fraction,
            or_dash(r.packing_fraction_err, 7, 5),
            or_dash(r.mean_contacts, 8, 3),
            100.0 * r.rattler_fraction,
            100.0 * r.crystallised,
            r.collisions
        );
    }
    let loose: Vec<String> = rows
        .iter()
        .filter(|r| r.mean_contacts.is_none())
        .map(|r| r.rate.to_string())
        .collect();
    if !loose.is_empty() {
        human += &format!(
            "  G = {}: every particle rattles (fewer than {} contacts once the rattlers are taken out): compressed this fast, the particles stopped against each other without a rigid contact network\n",
            loose.join(", "),
            D + 1
        );
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    human += &files_line(&[csv, runs_csv, png, svg]);
    report(
        &args.common,
        &Summary {
            experiment: "jamming",
            dim: D,
            n: args.n,
            size_ratio: ratio,
            fraction_large: large,
            pressure: args.pressure,
            crystal_packing: crystal,
            rows,
            interrupted,
        },
        &human,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_and_standard_error() {
        assert_eq!(mean_err(&[0.6]), (0.6, None));
        let (m, e) = mean_err(&[1.0, 2.0, 3.0]);
        assert!((m - 2.0).abs() < 1e-15);
        // Sample variance 1, over 3 values: error sqrt(1/3).
        assert!((e.unwrap() - (1.0f64 / 3.0).sqrt()).abs() < 1e-15);
    }

    // The legend of the peer code's points said "(this machine)" on every machine that drew
    // the plot, though the figures are fixed ones measured once elsewhere.
    #[test]
    fn the_reference_points_say_where_they_come_from() {
        assert!(REFERENCE_POINTS.contains("Skoge-Donev spheres code"));
        assert!(!REFERENCE_POINTS.contains("this machine"));
    }

    #[test]
    fn references_only_for_the_standard_systems() {
        assert_eq!(references(3, 1.0, 0.0).0.len(), 2);
        assert_eq!(references(2, 1.4, 0.5).0.len(), 1);
        assert!(references(2, 1.0, 0.0).0.is_empty());
        assert!(references(3, 1.4, 0.5).1.is_empty());
    }
}
