//! The CSV files and figures of both kinds of run.

use anyhow::Result;
use edmd_core::measure::theory::line_of_centres_rate_constant;
use edmd_plot::{Figure, Series, PALETTE};

use super::super::common::write_csv;
use super::equilibrium::Row;
use super::prigogine_xhrouet::{PxRun, Window, SPEED_MAX};

pub(super) fn write_outputs(
    dir: &std::path::Path,
    rows: &[Row],
    px: &[PxRun],
) -> Result<Vec<std::path::PathBuf>> {
    let mut files = Vec::new();
    let csv = dir.join("reaction.csv");
    write_csv(
        &csv,
        &[
            "dim",
            "packing",
            "activation",
            "reactive_fraction",
            "reactive_fraction_error",
            "reactive_fraction_theory",
            "reactive_fraction_ab",
            "reactive_fraction_ab_error",
            "reactive_fraction_ab_theory",
            "rate_constant",
            "rate_constant_error",
            "rate_constant_theory",
            "temperature_a",
        ],
        rows.iter().map(|r| {
            vec![
                r.dim as f64,
                r.packing,
                r.activation,
                r.reactive_fraction,
                r.reactive_fraction_error,
                r.reactive_fraction_theory,
                r.reactive_fraction_ab,
                r.reactive_fraction_ab_error,
                r.reactive_fraction_ab_theory,
                r.rate_constant,
                r.rate_constant_error,
                r.rate_constant_theory,
                r.temperature_a,
            ]
        }),
    )?;
    files.push(csv);
    // The cases (dimension, packing) in the order run.
    let mut cases: Vec<(usize, f64)> = Vec::new();
    for r in rows {
        if !cases.contains(&(r.dim, r.packing)) {
            cases.push((r.dim, r.packing));
        }
    }
    let top = rows
        .iter()
        .map(|r| r.activation)
        .fold(0.0, f64::max)
        .max(1.0);
    let grid: Vec<f64> = (0..=100).map(|i| top * i as f64 / 100.0).collect();
    let name = |d: usize, eta: f64| format!("{}D, packing {eta}", d);
    let mut fig = Figure::new(
        "Reactive collisions in equilibrium (A + B -> B + A)",
        "activation energy E*/kT",
        "reactive fraction of A-B collisions",
    )
    .with_log_y()
    .with(
        Series::line(
            "line of centres exp(-E*/kT)",
            grid.iter().map(|&a| (a, (-a).exp())).collect(),
        )
        .coloured([0, 0, 0]),
    );
    let mut fig_k = Figure::new(
        "Rate constant in equilibrium (A + B -> B + A)",
        "activation energy E*/kT",
        "rate constant k (sigma^D / tau)",
    )
    .with_log_y();
    for (c, &(d, eta)) in cases.iter().enumerate() {
        let colour = PALETTE[c % PALETTE.len()];
        let these: Vec<&Row> = rows
            .iter()
            .filter(|r| (r.dim, r.packing) == (d, eta))
            .collect();
        fig = fig.with(
            Series::error_bars(
                &format!("edmd, {}", name(d, eta)),
                these
                    .iter()
                    .map(|r| (r.activation, r.reactive_fraction))
                    .collect(),
                these.iter().map(|r| r.reactive_fraction_error).collect(),
            )
            .coloured(colour),
        );
        let prefactor = line_of_centres_rate_constant(eta, 1.0, 1.0, 1.0, d, 0.0);
        fig_k = fig_k
            .with(
                Series::line(
                    &format!("Enskog x line of centres, {}", name(d, eta)),
                    grid.iter().map(|&a| (a, prefactor * (-a).exp())).collect(),
                )
                .coloured(colour),
            )
            .with(
                Series::error_bars(
                    &format!("edmd, {}", name(d, eta)),
                    these
                        .iter()
                        .map(|r| (r.activation, r.rate_constant))
                        .collect(),
                    these.iter().map(|r| r.rate_constant_error).collect(),
                )
                .coloured(colour),
            );
    }
    let (png, svg) = fig.save(&dir.join("reaction"))?;
    files.extend([png, svg]);
    // The same against the law: measured over exp(-E*/kT), the cases side by side.
    let mut fig_r = Figure::new(
        "Reactive collisions over the line-of-centres law (A + B -> B + A)",
        "activation energy E*/kT (cases side by side)",
        "reactive fraction / exp(-E*/kT)",
    )
    .with(Series::line("line of centres", vec![(0.0, 1.0), (top, 1.0)]).coloured([0, 0, 0]));
    for (c, &(d, eta)) in cases.iter().enumerate() {
        let shift = 0.04 * (c as f64 - 0.5 * (cases.len() as f64 - 1.0));
        let these: Vec<&Row> = rows
            .iter()
            .filter(|r| (r.dim, r.packing) == (d, eta))
            .collect();
        fig_r = fig_r.with(
            Series::error_bars(
                &format!("edmd, {}", name(d, eta)),
                these
                    .iter()
                    .map(|r| {
                        (
                            r.activation + shift,
                            r.reactive_fraction / r.reactive_fraction_theory,
                        )
                    })
                    .collect(),
                these
                    .iter()
                    .map(|r| r.reactive_fraction_error / r.reactive_fraction_theory)
                    .collect(),
            )
            .coloured(PALETTE[c % PALETTE.len()]),
        );
    }
    let (png, svg) = fig_r.save(&dir.join("reaction-ratio"))?;
    files.extend([png, svg]);
    let (png, svg) = fig_k.save(&dir.join("reaction-rate"))?;
    files.extend([png, svg]);

    // Prigogine-Xhrouet: windows and speeds.
    let csv = dir.join("prigogine-xhrouet.csv");
    write_csv(
        &csv,
        &[
            "dim",
            "packing",
            "activation",
            "a_fraction_start",
            "a_fraction_end",
            "time",
            "aa_collisions",
            "reactions",
            "reactive_fraction",
            "reactive_fraction_error",
            "reactive_fraction_equilibrium",
            "reactive_fraction_temperature",
            "temperature_a",
            "temperature_a_error",
            "rate_constant",
            "rate_constant_error",
            "rate_constant_equilibrium",
        ],
        px.iter().flat_map(|p| {
            p.windows.iter().map(move |w| {
                vec![
                    p.dim as f64,
                    p.packing,
                    p.activation,
                    w.a_fraction_start,
                    w.a_fraction_end,
                    w.time,
                    w.aa_collisions as f64,
                    w.reactions as f64,
                    w.reactive_fraction,
                    w.reactive_fraction_error,
                    w.reactive_fraction_equilibrium,
                    w.reactive_fraction_temperature,
                    w.temperature_a,
                    w.temperature_a_error,
                    w.rate_constant,
                    w.rate_constant_error,
                    w.rate_constant_equilibrium,
                ]
            })
        }),
    )?;
    files.push(csv);
    let csv = dir.join("prigogine-xhrouet-speeds.csv");
    write_csv(
        &csv,
        &["dim", "activation", "speed", "density", "maxwell", "count"],
        px.iter().flat_map(|p| {
            p.speeds
                .iter()
                .map(move |&(v, f, m, c)| vec![p.dim as f64, p.activation, v, f, m, c as f64])
        }),
    )?;
    files.push(csv);
    let consumed = |w: &Window| 1.0 - 0.5 * (w.a_fraction_start + w.a_fraction_end);
    let mut fig = Figure::new(
        "Prigogine-Xhrouet effect (A + A -> B + B, closed box)",
        "fraction of A consumed",
        "reactive fraction of A-A collisions / exp(-E*/kT)",
    )
    // Room below the points for the legend.
    .with_y_range(0.45, 1.05)
    .with(Series::line("equilibrium", vec![(0.0, 1.0), (1.0, 1.0)]).coloured([0, 0, 0]));
    let mut fig_v = Figure::new(
        "Speeds of the A left over Maxwell's law at kT",
        "speed v / sqrt(kT/m)",
        "density of the A at the windows' ends / Maxwell at kT",
    )
    .with(Series::line("Maxwell at kT", vec![(0.0, 1.0), (SPEED_MAX, 1.0)]).coloured([0, 0, 0]));
    for (c, p) in px.iter().enumerate() {
        let colour = PALETTE[c % PALETTE.len()];
        let label = format!("{}D, E* = {} kT", p.dim, p.activation);
        fig = fig
            .with(
                Series::error_bars(
                    &format!("edmd, {label}"),
                    p.windows
                        .iter()
                        .map(|w| {
                            (
                                consumed(w),
                                w.reactive_fraction / w.reactive_fraction_equilibrium,
                            )
                        })
                        .collect(),
                    p.windows
                        .iter()
                        .map(|w| w.reactive_fraction_error / w.reactive_fraction_equilibrium)
                        .collect(),
                )
                .coloured(colour),
            )
            .with(
                Series::line(
                    // One legend entry says what all the lines are; each has its run's colour.
                    if c == 0 {
                        "lines: exp(-E*/kT_A) / exp(-E*/kT), kT_A the A's temperature"
                    } else {
                        ""
                    },
                    p.windows
                        .iter()
                        .map(|w| {
                            (
                                consumed(w),
                                w.reactive_fraction_temperature / w.reactive_fraction_equilibrium,
                            )
                        })
                        .collect(),
                )
                .coloured(colour),
            );
        let (points, errors): (Vec<(f64, f64)>, Vec<f64>) = p
            .speeds
            .iter()
            .filter(|s| s.3 >= 10)
            .map(|&(v, f, m, c)| ((v, f / m), f / m / (c as f64).sqrt()))
            .unzip();
        fig_v = fig_v.with(Series::error_bars(&label, points, errors).coloured(colour));
    }
    let (png, svg) = fig.save(&dir.join("prigogine-xhrouet"))?;
    files.extend([png, svg]);
    let (png, svg) = fig_v.save(&dir.join("prigogine-xhrouet-speeds"))?;
    files.extend([png, svg]);
    Ok(files)
}
