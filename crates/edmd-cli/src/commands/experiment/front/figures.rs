//! The CSV files and the figures: the front's position, its profiles, its mean shape.

use anyhow::Result;
use edmd_plot::{Figure, Series};

use super::super::common::write_csv;
use super::frame::{Frame, Run};
use super::measure::Sample;
use super::{FrontArgs, BIN};

/// The lines drawn over the front's position.
pub(super) struct Lines {
    pub(super) fit_from: f64,
    pub(super) t_end: f64,
    /// The fit `(slope, intercept)`.
    pub(super) line: Option<(f64, f64)>,
    pub(super) v: f64,
    pub(super) v_err: f64,
    pub(super) v_kpp: f64,
    pub(super) v_bd: f64,
    pub(super) n_bd: f64,
}

/// Writes the CSV files and the figures; returns their paths.
pub(super) fn write_outputs(
    dir: &std::path::Path,
    args: &FrontArgs,
    frame: &Frame,
    run: &Run,
    shape: &[(f64, f64, f64)],
    lines: Lines,
) -> Result<Vec<std::path::PathBuf>> {
    let mut files = Vec::new();
    let csv = dir.join("front.csv");
    write_csv(
        &csv,
        &[
            "time",
            "position",
            "position_half",
            "position_tip",
            "a_count",
        ],
        run.samples
            .iter()
            .map(|s| vec![s.time, s.mass, s.half, s.tip, s.a_count as f64]),
    )?;
    files.push(csv);
    let bins = frame.bins();
    let in_range = |b: usize| {
        let x = (b as f64 + 0.5) * BIN;
        x >= frame.x_lo && x < frame.x_hi()
    };
    let csv = dir.join("front-profile.csv");
    write_csv(
        &csv,
        &["time", "x", "a_fraction"],
        run.snapshots.iter().flat_map(|(t, u, offset)| {
            (0..bins)
                .filter(|&b| in_range(b))
                .map(move |b| vec![*t, (b as f64 + 0.5) * BIN + offset, u[b]])
        }),
    )?;
    files.push(csv);
    let csv = dir.join("front-shape.csv");
    write_csv(
        &csv,
        &["x_from_front", "a_fraction", "fisher_kpp"],
        shape.iter().map(|&(x, u, w)| vec![x, u, w]),
    )?;
    files.push(csv);

    let Lines {
        fit_from,
        t_end,
        line,
        v,
        v_err,
        v_kpp,
        v_bd,
        n_bd,
    } = lines;
    let title = format!(
        "A + B -> 2A front: packing {}, p = {}, {} x {} box",
        args.packing, args.probability, frame.length, frame.width
    );
    let every = run.samples.len().div_ceil(2000).max(1);
    let thin = |f: &dyn Fn(&Sample) -> f64| -> Vec<(f64, f64)> {
        run.samples
            .iter()
            .step_by(every)
            .map(|s| (s.time, f(s)))
            .collect()
    };
    let mut fig = Figure::new(
        &title,
        "time (sqrt(m sigma^2 / kT))",
        "front position (diameters)",
    )
    .with(Series::line("A mass / n W", thin(&|s| s.mass)))
    .with(Series::line("A fraction 1/2", thin(&|s| s.half)));
    if let Some((slope, icpt)) = line {
        let x0 = slope * fit_from + icpt;
        let through = |v: f64| vec![(fit_from, x0), (t_end, x0 + v * (t_end - fit_from))];
        fig = fig
            .with(
                Series::line(&format!("fit: v = {v:.4} ± {v_err:.4}"), through(slope))
                    .coloured([0, 0, 0]),
            )
            .with(Series::line(
                &format!("Fisher-KPP 2 sqrt(D k n) = {v_kpp:.4}"),
                through(v_kpp),
            ))
            .with(Series::line(
                &format!("Brunet-Derrida, N = {n_bd:.0}: {v_bd:.4}"),
                through(v_bd),
            ));
    }
    let (png, svg) = fig.save(&dir.join("front"))?;
    files.extend([png, svg]);

    let mut fig = Figure::new(
        "The front growing from a step: A fraction along the box",
        "x (diameters, the frame's moves added back)",
        "A fraction u",
    )
    .with_y_range(0.0, 1.05);
    for (t, u, offset) in &run.snapshots {
        let pts = (0..bins)
            .filter(|&b| in_range(b))
            .map(|b| ((b as f64 + 0.5) * BIN + offset, u[b]))
            .collect();
        fig = fig.with(Series::line(&format!("t = {t:.0}"), pts));
    }
    let (png, svg) = fig.save(&dir.join("front-profile"))?;
    files.extend([png, svg]);

    let (png, svg) = Figure::new(
        "Mean front seen from its A-mass position X(t)",
        "x - X(t) (diameters)",
        "A fraction u",
    )
    .with_y_range(0.0, 1.05)
    .with(Series::points(
        "edmd",
        shape.iter().map(|p| (p.0, p.1)).collect(),
    ))
    .with(
        Series::line(
            "Fisher-KPP wave at v_KPP",
            shape.iter().map(|p| (p.0, p.2)).collect(),
        )
        .coloured([0, 0, 0]),
    )
    .save(&dir.join("front-shape"))?;
    files.extend([png, svg]);
    Ok(files)
}
