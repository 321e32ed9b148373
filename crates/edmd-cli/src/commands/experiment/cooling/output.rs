//! The CSV files, the figures, the pictures of the end and the human summary.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Result;
use edmd_core::measure::theory::{critical_length, haff_temperature};
use edmd_plot::{Figure, Series, PALETTE};

use super::super::common::write_csv;
use super::run::{Analysis, Run};
use super::{shear_theory, CoolingArgs, Row};

/// A box: its row, its runs and what each run's samples gave.
pub(super) struct Measured {
    pub row: Row,
    pub runs: Vec<Run>,
    pub found: Vec<Analysis>,
}

/// A box's samples averaged over its runs at the times they share: `(t, tau, T/T0, shear
/// fraction, density mode)`.
fn mean_curve(runs: &[Run]) -> Vec<[f64; 5]> {
    let shared = runs
        .iter()
        .map(|r| r.samples.iter().take_while(|s| s.on_grid).count())
        .min()
        .unwrap_or(0);
    let k = runs.len() as f64;
    (0..shared)
        .map(|i| {
            let sum = |f: &dyn Fn(&Run) -> f64| runs.iter().map(f).sum::<f64>() / k;
            [
                runs[0].samples[i].t,
                sum(&|r| r.samples[i].tau),
                sum(&|r| r.samples[i].kt / r.kt0),
                sum(&|r| r.samples[i].shear),
                sum(&|r| r.samples[i].density),
            ]
        })
        .collect()
}

fn label(r: &Row) -> String {
    format!("N = {}, L = {:.2} L_c", r.n, r.length_ratio)
}

/// Writes everything; returns the paths.
pub(super) fn write(dir: &Path, args: &CoolingArgs, boxes: &[Measured]) -> Result<Vec<PathBuf>> {
    let dim = args.dim;
    let e = args.restitution;
    let lc = critical_length(dim, e, args.packing);
    let mut files = Vec::new();

    let csv = dir.join("cooling.csv");
    write_csv(
        &csv,
        &[
            "n",
            "box_length",
            "length_ratio",
            "kt0",
            "collision_frequency",
            "collision_frequency_error",
            "collision_frequency_theory",
            "t0",
            "t0_error",
            "t0_theory",
            "t0_maxwell",
            "t0_measured_frequency",
            "decay_per_collision",
            "decay_per_collision_error",
            "decay_per_collision_theory",
            "onset_collisions",
            "onset_collisions_error",
            "onset_collisions_theory",
            "departure_collisions",
            "tc",
            "tc_elastic_fraction",
        ],
        boxes.iter().map(|b| {
            let r = &b.row;
            let o = |x: Option<f64>| x.unwrap_or(f64::NAN);
            vec![
                r.n as f64,
                r.box_length,
                r.length_ratio,
                r.kt0,
                r.collision_frequency,
                r.collision_frequency_error,
                r.collision_frequency_theory,
                r.t0,
                r.t0_error,
                r.t0_theory,
                r.t0_maxwell,
                r.t0_measured_frequency,
                r.decay_per_collision,
                r.decay_per_collision_error,
                r.decay_per_collision_theory,
                o(r.onset_collisions),
                o(r.onset_collisions_error),
                o(r.onset_collisions_theory),
                o(r.departure_collisions),
                r.tc,
                r.tc_elastic_fraction,
            ]
        }),
    )?;
    files.push(csv);

    let csv = dir.join("cooling-runs.csv");
    write_csv(
        &csv,
        &[
            "n",
            "run",
            "kt0",
            "collision_frequency",
            "t0",
            "decay_per_collision",
            "onset_collisions",
            "departure_collisions",
            "tc",
            "tc_elastic_fraction",
        ],
        boxes.iter().flat_map(|b| {
            b.runs
                .iter()
                .zip(&b.found)
                .enumerate()
                .map(move |(k, (run, a))| {
                    let omega =
                        run.omega_blocks.iter().sum::<f64>() / run.omega_blocks.len() as f64;
                    vec![
                        b.row.n as f64,
                        k as f64,
                        run.kt0,
                        omega,
                        a.t0,
                        a.decay,
                        a.onset.unwrap_or(f64::NAN),
                        a.departure.unwrap_or(f64::NAN),
                        run.tc,
                        run.elastic as f64 / run.collisions.max(1) as f64,
                    ]
                })
        }),
    )?;
    files.push(csv);

    let curves: Vec<Vec<[f64; 5]>> = boxes.iter().map(|b| mean_curve(&b.runs)).collect();
    let csv = dir.join("cooling-samples.csv");
    write_csv(
        &csv,
        &[
            "n",
            "time",
            "time_over_t0",
            "collisions_per_particle",
            "temperature_over_t0",
            "haff",
            "shear_fraction",
            "shear_fraction_theory",
            "density_mode",
        ],
        boxes.iter().zip(&curves).flat_map(|(b, curve)| {
            let (r, runs) = (&b.row, &b.runs);
            curve.iter().map(move |c| {
                vec![
                    r.n as f64,
                    c[0],
                    c[0] / r.t0_theory,
                    c[1],
                    c[2],
                    haff_temperature(c[0], 1.0, r.t0_theory),
                    c[3],
                    shear_theory(dim, e, lc, r.n, &runs[0].lengths, c[1]),
                    c[4],
                ]
            })
        }),
    )?;
    files.push(csv);

    let what = if dim == 3 { "spheres" } else { "discs" };
    let title = format!(
        "Homogeneous cooling, {what} at packing {}, e = {e}",
        args.packing
    );
    let x_of = |t: f64, r: &Row| (1.0 + t / r.t0_theory).log10();
    let mut fig = Figure::new(
        &title,
        "log10(1 + t / t0), t0 from Enskog's frequency with a2",
        "temperature T / T0",
    )
    .with_log_y();
    let mut x_max: f64 = 0.0;
    for (k, (b, curve)) in boxes.iter().zip(&curves).enumerate() {
        let r = &b.row;
        let pts: Vec<(f64, f64)> = curve.iter().map(|c| (x_of(c[0], r), c[2])).collect();
        x_max = pts.iter().map(|p| p.0).fold(x_max, f64::max);
        fig = fig.with(Series::points(&label(r), pts).coloured(PALETTE[k % PALETTE.len()]));
    }
    let haff: Vec<(f64, f64)> = (0..=100)
        .map(|i| {
            let x = x_max * i as f64 / 100.0;
            (x, 10f64.powf(-2.0 * x))
        })
        .collect();
    let (png, svg) = fig
        .with(Series::line("Haff's law (1 + t/t0)^-2", haff).coloured([0, 0, 0]))
        .save(&dir.join("cooling-temperature"))?;
    files.extend([png, svg]);

    let mut fig = Figure::new(
        &title,
        "collisions per particle",
        "energy fraction in the longest shear waves",
    )
    .with_log_y();
    let mut tau_max: f64 = 0.0;
    for (k, (b, curve)) in boxes.iter().zip(&curves).enumerate() {
        let (r, runs) = (&b.row, &b.runs);
        let colour = PALETTE[k % PALETTE.len()];
        let pts: Vec<(f64, f64)> = curve.iter().map(|c| (c[1], c[3])).collect();
        let end = pts.last().map_or(1.0, |p| p.0);
        tau_max = tau_max.max(end);
        let theory: Vec<(f64, f64)> = (0..=200)
            .map(|i| {
                let tau = end * i as f64 / 200.0;
                (tau, shear_theory(dim, e, lc, r.n, &runs[0].lengths, tau))
            })
            .filter(|p| p.1 <= 1.0)
            .collect();
        fig = fig
            .with(Series::points(&label(r), pts).coloured(colour))
            .with(
                Series::line("  predicted (linear fluctuating hydrodynamics)", theory)
                    .coloured(colour),
            );
    }
    // One line per onset level (boxes of few particles take a higher one), in its box's
    // colour when they differ.
    let mut levels: Vec<(f64, [u8; 3])> = Vec::new();
    for (k, b) in boxes.iter().enumerate() {
        if !levels.iter().any(|l| l.0 == b.row.onset_fraction) {
            levels.push((b.row.onset_fraction, PALETTE[k % PALETTE.len()]));
        }
    }
    let single = levels.len() == 1;
    for (level, colour) in levels {
        fig = fig.with(
            Series::line(
                &format!("onset: fraction {level}"),
                vec![(0.0, level), (tau_max, level)],
            )
            .coloured(if single { [0, 0, 0] } else { colour }),
        );
    }
    let (png, svg) = fig.save(&dir.join("cooling-shear"))?;
    files.extend([png, svg]);

    for b in boxes {
        let r = &b.row;
        if let Some(scene) = &b.runs[0].snapshot {
            let path = dir.join(format!("cooling-snapshot-{}.png", r.n));
            let png = edmd_draw::draw(scene, 600, 600)
                .encode_png()
                .map_err(|e| anyhow::anyhow!("cannot encode {}: {e}", path.display()))?;
            let mut f = edmd::output::AtomicFile::create(&path)?;
            f.write_all(&png)?;
            f.commit()?;
            files.push(path);
        }
    }
    Ok(files)
}

/// The human summary of a box.
pub(super) fn describe(r: &Row) -> String {
    let opt = |v: Option<f64>, err: Option<f64>| match (v, err) {
        (Some(v), Some(e)) => format!("{v:.1} ± {e:.1}"),
        (Some(v), None) => format!("{v:.1}"),
        _ => "never".to_string(),
    };
    // Whole collisions, but fractions where the window is that short.
    let few = |c: f64| {
        if c < 10.0 {
            format!("{c:.2}")
        } else {
            format!("{c:.0}")
        }
    };
    format!(
        "  N {}: box {:.1} = {:.2} L_c (L_c = {:.1} diameters)\n\
         \x20   kT0 {:.4}; collision frequency {:.4} ± {:.4} per particle (Enskog {:.4})\n\
         \x20   t0 {:.3} ± {:.3}, fitted over {}-{} collisions per particle (theory {:.3} with a2 = {:.4}; {:.3} Maxwellian; {:.3} from the measured frequency)\n\
         \x20   ln T falls by {:.5} ± {:.5} per collision per particle (theory {:.5})\n\
         \x20   onset (shear fraction {}): {} collisions per particle in {} of {} runs (predicted {}); T 10% above Haff's law: {}\n\
         \x20   TC model: tc = {:.3e}, {:.2e} of the collisions elastic; T/T0 at the end {:.2e}\n",
        r.n,
        r.box_length,
        r.length_ratio,
        r.critical_length,
        r.kt0,
        r.collision_frequency,
        r.collision_frequency_error,
        r.collision_frequency_theory,
        r.t0,
        r.t0_error,
        few(r.fit_collisions[0]),
        few(r.fit_collisions[1]),
        r.t0_theory,
        r.sonine_a2,
        r.t0_maxwell,
        r.t0_measured_frequency,
        r.decay_per_collision,
        r.decay_per_collision_error,
        r.decay_per_collision_theory,
        r.onset_fraction,
        opt(r.onset_collisions, r.onset_collisions_error),
        r.onset_runs,
        r.runs,
        opt(r.onset_collisions_theory, None),
        opt(r.departure_collisions, r.departure_collisions_error),
        r.tc,
        r.tc_elastic_fraction,
        r.final_temperature,
    ) + &match r.collapse_collisions {
        Some(c) => format!(
            "    inelastic collapse in {} of {} runs, after {c:.2} collisions per particle (mean): clusters spent the rest of the collisions at vanishing relative speeds; the fits stop there (--tc above 0 prevents it)\n",
            r.collapsed_runs, r.runs
        ),
        None => String::new(),
    }
}
