//! Compression of a disc configuration to a smaller box, in stages that the engine relaxes.
//!
//! Scaling positions and box together (an affine compression) is limited by the closest pair,
//! which in a fluid of `N` discs is very close indeed (the smallest of `~3N` gaps), so pure
//! affine stages would be tiny. Each stage here instead scales by a fixed step (at first 0.5%
//! of the box length), then pushes apart the few pairs that now overlap (and discs that cross a
//! wall) by repeated half-overlap moves along the line of centres, and finally lets the engine
//! run a collision per disc so that the configuration relaxes towards equilibrium again.
//! A stage whose overlaps do not clear within [`RELAX_SWEEPS`] sweeps is undone and retried
//! with half the step; successful stages let the step grow again. Near jamming the step shrinks
//! below [`MIN_STEP`] and the compression gives up.

use crate::cells::CellGrid;
use crate::math::Vector;
use crate::simulation::{Options, Simulation};
use crate::state::{Disc, SimBox};

use super::fluid::run_collisions;

/// Sweeps of overlap removal allowed per stage.
pub const RELAX_SWEEPS: u32 = 200;

/// First relative shrink of the box length per stage.
const START_STEP: f64 = 0.005;

/// Largest relative shrink of the box length per stage.
const MAX_STEP: f64 = 0.02;

/// The compression gives up when the step would be smaller than this.
pub const MIN_STEP: f64 = 1e-6;

/// Pairs are pushed to a distance this much (relatively) beyond contact.
const MARGIN: f64 = 1e-10;

/// Collisions per disc run after each stage.
const COLLISIONS_PER_STAGE: f64 = 1.0;

/// The outcome of [`compress`].
pub(crate) struct Compressed<const D: usize> {
    /// The simulation at the target box.
    pub sim: Simulation<D>,
    /// Stages taken (including undone ones).
    pub stages: u32,
    /// Collisions per disc run on the way.
    pub collisions_per_disc: f64,
}

/// Compresses the simulation's discs into the box with lengths `target` (each no longer than
/// the current one, same proportions). On failure returns the packing reached and the stages
/// taken.
pub(crate) fn compress<const D: usize>(
    mut sim: Simulation<D>,
    target: [f64; D],
    max_stages: u32,
) -> Result<Compressed<D>, (f64, u32)> {
    let n = sim.len().max(1);
    let per_stage = (COLLISIONS_PER_STAGE * n as f64 / 2.0).ceil() as u64;
    let mut step = START_STEP;
    let mut work = 0.0;
    for stage in 1..=max_stages {
        let discs = sim.discs();
        let sim_box = *sim.sim_box();
        let last = target[0] / sim_box.lengths[0] >= 1.0 - step;
        let mut trial = discs.clone();
        let mut trial_box = sim_box;
        for a in 0..D {
            let scale = if last {
                target[a] / sim_box.lengths[a]
            } else {
                1.0 - step
            };
            for d in &mut trial {
                d.pos[a] *= scale;
            }
            trial_box.lengths[a] = if last {
                target[a]
            } else {
                sim_box.lengths[a] * scale
            };
        }
        if !remove_overlaps(&mut trial, &trial_box, RELAX_SWEEPS) {
            step *= 0.5;
            if step < MIN_STEP {
                return Err((super::packing_of(&discs, &sim_box), stage));
            }
            continue;
        }
        step = (step * 1.5).min(MAX_STEP);
        work += 2.0 * sim.stats().disc_disc as f64 / n as f64;
        sim = match Simulation::new(&trial, trial_box, Options::default()) {
            Ok(s) => s,
            Err(_) => return Err((super::packing_of(&discs, &sim_box), stage)),
        };
        if last {
            return Ok(Compressed {
                sim,
                stages: stage,
                collisions_per_disc: work,
            });
        }
        run_collisions(&mut sim, per_stage, u64::MAX);
    }
    Err((super::packing_of(&sim.discs(), sim.sim_box()), max_stages))
}

/// Moves discs until no two overlap and none crosses a wall, each sweep pushing every
/// overlapping pair apart along its line of centres (each disc half the overlap, plus a tiny
/// margin). Returns false if overlaps remain after `max_sweeps`.
pub fn remove_overlaps<const D: usize>(
    discs: &mut [Disc<D>],
    sim_box: &SimBox<D>,
    max_sweeps: u32,
) -> bool {
    let n = discs.len();
    let d_max = discs.iter().map(|d| 2.0 * d.radius).fold(0.0, f64::max);
    let mut push = vec![Vector::ZERO; n];
    for _ in 0..max_sweeps {
        for d in discs.iter_mut() {
            d.pos = sim_box.wrap(d.pos);
        }
        push.fill(Vector::ZERO);
        let mut clear = true;
        let visit = |i: usize, j: usize, d: Vector<D>, push: &mut [Vector<D>]| {
            let sigma = discs[i].radius + discs[j].radius;
            let r2 = d.norm2();
            if r2 < sigma * sigma {
                let r = r2.sqrt();
                let u = if r > 0.0 {
                    d / r
                } else {
                    let mut x = Vector::ZERO;
                    x[0] = 1.0;
                    x
                };
                let half = 0.5 * (sigma * (1.0 + MARGIN) - r);
                push[i] -= u * half;
                push[j] += u * half;
                false
            } else {
                true
            }
        };
        match CellGrid::new(sim_box, n, d_max) {
            Ok(mut grid) => {
                for (i, d) in discs.iter().enumerate() {
                    grid.insert(i, grid.coord_of(d.pos));
                }
                for i in 0..n {
                    grid.for_each_near(grid.cell_of(i), |j, shift| {
                        if j > i {
                            let d = discs[j].pos + shift - discs[i].pos;
                            clear &= visit(i, j, d, &mut push);
                        }
                    });
                }
            }
            Err(_) => {
                for i in 0..n {
                    for j in i + 1..n {
                        let d = sim_box.minimum_image(discs[j].pos - discs[i].pos);
                        clear &= visit(i, j, d, &mut push);
                    }
                }
            }
        }
        for (d, p) in discs.iter_mut().zip(&push) {
            d.pos += *p;
            for a in 0..D {
                if !sim_box.is_periodic(a) {
                    let (lo, hi) = (d.radius, sim_box.lengths[a] - d.radius);
                    if d.pos[a] < lo || d.pos[a] > hi {
                        clear = false;
                        d.pos[a] = d.pos[a].clamp(lo * (1.0 + MARGIN), hi - lo * MARGIN);
                    }
                }
            }
        }
        if clear {
            return true;
        }
    }
    false
}
