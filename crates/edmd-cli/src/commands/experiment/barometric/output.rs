//! The CSV files, the figures and the human summary.

use std::path::{Path, PathBuf};

use anyhow::Result;
use edmd_core::setup::lattice::ball_volume;
use edmd_plot::{Figure, Series, PALETTE};

use super::super::common::write_csv;
use super::{BarometricArgs, Measured};

/// Writes the profiles and the figures; returns the paths.
pub(super) fn write(
    dir: &Path,
    args: &BarometricArgs,
    columns: &[Measured],
) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let csv = dir.join("barometric.csv");
    write_csv(
        &csv,
        &[
            "packing",
            "height",
            "density",
            "density_error",
            "barometric",
            "lda",
            "lda_above",
        ],
        columns.iter().flat_map(|c| {
            c.density
                .iter()
                .map(|d| vec![c.row.packing, d[0], d[1], d[2], d[3], d[4], d[5]])
        }),
    )?;
    files.push(csv);
    let csv = dir.join("barometric-temperature.csv");
    write_csv(
        &csv,
        &["packing", "height", "kt", "kt_error"],
        columns.iter().flat_map(|c| {
            c.temperature
                .iter()
                .map(|t| vec![c.row.packing, t[0], t[1], t[2]])
        }),
    )?;
    files.push(csv);

    let v = ball_volume(1.0, args.dim);
    let what = if args.dim == 3 { "spheres" } else { "discs" };
    for c in columns {
        let r = &c.row;
        let title = format!(
            "A column of {} {what} in a field g = {}, floor packing {} (kT = {:.4})",
            r.n, r.g, r.packing, r.kt
        );
        let eta = |k: usize| {
            c.density
                .iter()
                .map(|d| (d[0], v * d[k]))
                .collect::<Vec<_>>()
        };
        let dilute = r.packing < 0.1;
        let top = c
            .density
            .iter()
            .map(|d| v * (d[1] + d[2]))
            .fold(0.0, f64::max);
        let bottom = c
            .density
            .iter()
            .map(|d| v * d[3].min(d[4]))
            .fold(f64::INFINITY, f64::min);
        let mut fig = Figure::new(
            &title,
            "height of the centres above the lowest they can be, h (diameters)",
            "packing fraction of the centres' density, n v",
        )
        .with(Series::error_bars(
            "edmd",
            eta(1),
            c.density.iter().map(|d| v * d[2]).collect(),
        ))
        .with(Series::line("barometric law", eta(3)).coloured(PALETTE[1]))
        .with(Series::line("local-density approximation (LDA)", eta(4)).coloured([0, 0, 0]))
        .with(
            Series::line(
                "LDA of the column above the floor's layers",
                eta(5).into_iter().filter(|p| p.1.is_finite()).collect(),
            )
            .coloured(PALETTE[2]),
        )
        .with(
            Series::line(
                "compared from here up",
                vec![
                    (r.compared_from, 0.5 * bottom),
                    (r.compared_from, 2.0 * top),
                ],
            )
            .coloured(PALETTE[7]),
        );
        fig = if dilute {
            fig.with_log_y().with_y_range(0.5 * bottom, 1.5 * top)
        } else {
            fig.with_y_range(0.0, 1.05 * top)
        };
        let (png, svg) = fig.save(&dir.join(format!("barometric-packing-{}", r.packing)))?;
        files.extend([png, svg]);
    }

    let mut fig = Figure::new(
        &format!("Temperature against height ({what}, g = {})", args.g),
        "height over the scale height, h m g / kT",
        "kinetic temperature / its mean",
    );
    let reach = columns
        .iter()
        .flat_map(|c| c.temperature.iter().map(|t| t[0] / (c.row.kt / c.row.g)))
        .fold(0.0, f64::max);
    fig =
        fig.with(Series::line("equipartition", vec![(0.0, 1.0), (reach, 1.0)]).coloured([0, 0, 0]));
    for (k, c) in columns.iter().enumerate() {
        let (kt, lambda) = (c.row.kt, c.row.kt / c.row.g);
        fig = fig.with(
            Series::error_bars(
                &format!("floor packing {}", c.row.packing),
                c.temperature
                    .iter()
                    .map(|t| (t[0] / lambda, t[1] / kt))
                    .collect(),
                c.temperature.iter().map(|t| t[2] / kt).collect(),
            )
            .coloured(PALETTE[k % PALETTE.len()]),
        );
    }
    let (png, svg) = fig.save(&dir.join("barometric-temperature"))?;
    files.extend([png, svg]);
    Ok(files)
}

/// The human summary.
pub(super) fn human(columns: &[Measured], interrupted: bool) -> String {
    let mut s = String::from(
        "barometric: columns in a field, compared from a few diameters above the floor\n",
    );
    s += "  packing      kT  scale height (error)   kT/mg    LDA's  chi2: baro      LDA  LDA above  max |d eta|  kT slope/lambda (error)\n";
    for c in columns {
        let r = &c.row;
        s += &format!(
            "  {:7.4} {:7.4} {:8.4} ({:7.4}) {:8.4} {:8.4} {:11.2} {:8.2} {:10.2} {:12.4} {:9.4} ({:6.4})\n",
            r.packing,
            r.kt,
            r.scale_height,
            r.scale_height_error,
            r.scale_height_theory,
            r.scale_height_lda,
            r.chi2_barometric,
            r.chi2_lda,
            r.chi2_lda_above,
            r.packing_max_deviation_lda_above,
            r.kt_slope,
            r.kt_slope_error
        );
    }
    if interrupted {
        s += "interrupted: results so far\n";
    }
    s
}
