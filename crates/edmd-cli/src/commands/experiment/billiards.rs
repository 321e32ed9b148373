//! `edmd experiment billiards`: the break of a racked triangle, the assignment's extra credit.
//!
//! The rack is struck dead centre, once with multi-disc collisions (every ball touching the
//! struck ones takes part at the same instant, as stiff elastic Hertz contacts:
//! `edmd_core::resolve::cluster`) and once with binary collisions processed one after another.
//! Why the first is symmetric: all contact forces act at once and depend only on the contact
//! geometry, which is mirror-symmetric, so the mirror image of every ball leaves with the
//! mirrored velocity. Binary collisions must pick an order for contacts that happen at the
//! same instant (the apex ball meets both second-row balls together); whichever goes first is
//! deflected differently from its mirror twin, and the break comes out lopsided.

use anyhow::Result;
use clap::Args;
use edmd_core::{Disc, MultiContact, Options, SimBox, Simulation, Vector};
use edmd_plot::{Figure, Series};
use serde::Serialize;

use super::common::{
    check_span, files_line, interrupted_after, out_dir, outputs, report, write_csv, CommonArgs,
};
use edmd::user_error;

/// Options of `edmd experiment billiards`.
#[derive(Debug, Args)]
pub struct BilliardsArgs {
    /// Rows in the rack (5 gives the 15-ball triangle).
    #[arg(long, default_value_t = 5, allow_negative_numbers = true)]
    pub rows: usize,
    /// Gap between neighbouring rack balls, relative to the diameter.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub gap: f64,
    /// Sideways offset of the cue ball from the rack's axis, in diameters (0: dead centre).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub offset: f64,
    /// Simulated time after the strike to follow the balls.
    #[arg(long, default_value_t = 3.0, allow_negative_numbers = true)]
    pub follow: f64,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Summary of one break.
#[derive(Debug, Serialize)]
pub struct Break {
    /// "multi" or "binary".
    pub model: &'static str,
    /// Largest mismatch between a ball's velocity and its mirror ball's mirrored velocity just
    /// after the strike (0 for a symmetric break).
    pub mirror_mismatch: f64,
    /// Balls moving after the strike.
    pub moving: usize,
    /// Relative kinetic energy change over the run.
    pub relative_energy_change: f64,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Balls, cue included.
    pub balls: usize,
    /// The two breaks.
    pub breaks: Vec<Break>,
    /// True if stopped by Ctrl-C before both breaks were followed to the end.
    pub interrupted: bool,
}

const R: f64 = 0.025;

fn rack(rows: usize, gap: f64, offset: f64) -> (Vec<Disc>, usize) {
    let d = 2.0 * R * (1.0 + gap);
    let h = d * 3f64.sqrt() / 2.0;
    let apex_y = 0.6;
    let mut discs = Vec::new();
    for row in 0..rows {
        for k in 0..=row {
            let x = 0.5 + (k as f64 - row as f64 / 2.0) * d;
            let mut disc = Disc::new(Vector::new([x, apex_y + row as f64 * h]), Vector::ZERO, R);
            disc.colour = [200, 40, 40];
            discs.push(disc);
        }
    }
    let mut cue = Disc::new(
        Vector::new([0.5 + offset * 2.0 * R, 0.15]),
        Vector::new([0.0, 0.5]),
        R,
    );
    cue.colour = [240, 240, 240];
    discs.push(cue);
    (discs, rows * (rows + 1) / 2)
}

/// Mirror twin of each ball (by initial position, about x = 0.5).
fn twins(discs: &[Disc]) -> Vec<Option<usize>> {
    discs
        .iter()
        .map(|d| {
            (0..discs.len()).find(|&j| {
                (discs[j].pos[0] - (1.0 - d.pos[0])).abs() < 1e-9
                    && (discs[j].pos[1] - d.pos[1]).abs() < 1e-9
            })
        })
        .collect()
}

/// Runs the experiment.
pub fn run(args: &BilliardsArgs) -> Result<()> {
    if !(1..=8).contains(&args.rows) {
        return user_error("billiards: --rows must be from 1 to 8");
    }
    if !(args.gap >= 0.0 && args.gap < 0.04) {
        return user_error("billiards: --gap must be in [0, 0.04) (balls within 4% of touching take part together)");
    }
    if !(args.offset.is_finite() && args.offset.abs() <= 0.9) {
        return user_error("billiards: --offset must be within +-0.9 diameters");
    }
    check_span("billiards", "follow", args.follow, 1e6)?;
    let dir = out_dir(
        &args.common,
        &outputs(
            &["billiards_multi", "billiards_binary"],
            &["billiards_multi", "billiards_binary"],
        ),
    )?;
    let (discs, n_rack) = rack(args.rows, args.gap, args.offset);
    let twins = twins(&discs);
    // The cue ball reaches the apex at about (0.6 - 0.15 - 2R) / 0.5.
    let strike = (0.6 - 0.15 - 2.0 * R) / 0.5;
    let mut breaks = Vec::new();
    let mut files = Vec::new();
    let mut interrupted = false;
    'models: for (model, multi) in [
        (
            "multi",
            Some(MultiContact {
                tolerance: 0.04,
                exponent: 1.5,
            }),
        ),
        ("binary", None),
    ] {
        let mut sim = Simulation::new(
            &discs,
            SimBox::unit(),
            Options {
                multi,
                ..Default::default()
            },
        )?;
        let e0 = sim.kinetic_energy();
        if !edmd::run_until_or_stop(&mut sim, strike + 0.02, &mut ())? {
            interrupted = true;
            break;
        }
        let mismatch = twins
            .iter()
            .enumerate()
            .filter_map(|(i, t)| t.map(|j| (i, j)))
            .map(|(i, j)| {
                let (vi, vj) = (sim.velocity(i), sim.velocity(j));
                (vi[0] + vj[0]).abs().max((vi[1] - vj[1]).abs())
            })
            .fold(0.0, f64::max);
        let moving = (0..sim.len())
            .filter(|&i| sim.velocity(i).norm2() > 1e-12)
            .count();
        // Follow the balls.
        let steps = 200;
        let mut paths: Vec<Vec<(f64, f64)>> = vec![Vec::new(); discs.len()];
        let mut rows = Vec::new();
        for k in 0..=steps {
            let t = strike - 0.2 + (args.follow + 0.2) * k as f64 / steps as f64;
            // A long --follow can take hours between two steps.
            if !edmd::run_until_or_stop(&mut sim, t, &mut ())? {
                interrupted = true;
                break 'models;
            }
            for (i, p) in paths.iter_mut().enumerate() {
                let q = sim.position(i);
                p.push((q[0], q[1]));
                rows.push(vec![t, i as f64, q[0], q[1]]);
            }
        }
        let csv = dir.join(format!("billiards_{model}.csv"));
        write_csv(&csv, &["time", "ball", "x", "y"], rows)?;
        let mut fig = Figure::new(
            &format!(
                "Break with {} collisions (offset {} diameters)",
                if multi.is_some() {
                    "multi-disc"
                } else {
                    "binary"
                },
                args.offset
            ),
            "x (box lengths)",
            "y (box lengths)",
        )
        .with_x_range(0.0, 1.0)
        .with_y_range(0.0, 1.0);
        for (i, p) in paths.into_iter().enumerate() {
            let label = if i == n_rack {
                "cue ball".to_string()
            } else if i == 0 {
                "rack balls".to_string()
            } else {
                String::new()
            };
            let colour = if i == n_rack {
                [30, 30, 30]
            } else {
                [200, 40, 40]
            };
            fig = fig.with(Series::line(&label, p).coloured(colour));
        }
        let (png, svg) = fig.save(&dir.join(format!("billiards_{model}")))?;
        files.extend([csv, png, svg]);
        breaks.push(Break {
            model,
            mirror_mismatch: mismatch,
            moving,
            relative_energy_change: (sim.kinetic_energy() - e0) / e0,
        });
    }
    let mut human = format!(
        "break of a {}-ball rack, cue offset {} diameters:\n",
        n_rack, args.offset
    );
    for b in &breaks {
        human += &format!(
            "  {:6}: mirror mismatch {:.2e}, {} balls moving, energy change {:.1e}\n",
            b.model, b.mirror_mismatch, b.moving, b.relative_energy_change
        );
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    human += &files_line(&files);
    report(
        &args.common,
        &Summary {
            experiment: "billiards",
            balls: discs.len(),
            breaks,
            interrupted,
        },
        &human,
    )?;
    if interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}
