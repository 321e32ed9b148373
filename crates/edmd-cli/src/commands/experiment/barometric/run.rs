//! A column: its box sized from the local-density approximation, its discs placed, its bath,
//! and the time averages of the density and the temperature against height.

use anyhow::Result;
use edmd_core::measure::column::{lda_from_floor, Column, HardFluid, Profile};
use edmd_core::setup::thermal_velocities;
use edmd_core::{Andersen, Boundary, Disc, Gravity, Options, SimBox, Simulation, Vector};
use rand::SeedableRng;

use super::super::common::Progress;

/// The box's height: the centres range up to where the column at `kT = 1` has thinned to
/// `exp(-CEILING_FALL)` of its floor density, four scale heights of an ideal gas.
const CEILING_FALL: f64 = 4.0;

/// The closest two lattice sites of the start are (diameters): a little room to move.
const START_SPACING: f64 = 1.05;

/// Blocks the samples are cut into for the errors.
pub(super) const BLOCKS: usize = 40;

/// Scale heights of equilibration in the bath (at one redraw per disc per scale height's
/// flight time, 40 redraws each), then of settling without it.
const BATH_TIMES: f64 = 40.0;
const SETTLE_TIMES: f64 = 5.0;

/// Samples per scale height's flight time `lambda / sqrt(kT/m)`, at most.
const SAMPLES_PER_TIME: f64 = 4.0;

/// Samples per mean free time, at most: a dilute gas's discs keep their energies from one
/// collision to the next (seven flight times apart at packing 0.01), so that samples closer
/// than that would repeat themselves, and blocks of them would be too short for their errors.
const SAMPLES_PER_FREE_TIME: f64 = 2.0;

/// A column as built: its box and the LDA's profile at `kT = 1`.
pub(super) struct Plan {
    /// The range of the centres' heights.
    pub height: f64,
    /// The box's edge across the field (every sideways axis).
    pub width: f64,
    /// The LDA profile at the bath's `kT = 1` that the box was sized by.
    pub profile: Profile,
}

/// Sizes the column of `n` particles in `D` dimensions whose floor packing is `packing` in
/// the LDA at `kT = 1` under `g`: the height where the profile has thinned by
/// [`CEILING_FALL`], the width that gives it `n` particles.
pub(super) fn plan<const D: usize>(n: usize, packing: f64, g: f64) -> Plan {
    let fluid = HardFluid::reference(D);
    let lambda = 1.0 / g;
    let n0 = packing / fluid.particle_volume;
    // A hard fluid thins more slowly than the ideal gas, and from packing 0.65 (discs) or 0.45
    // (spheres) it has fallen by e^-4 within 13 scale heights: 40 is ample.
    let tall = Column {
        scale_height: lambda,
        height: 40.0 * lambda,
        load: 0.0,
    };
    let steps = 16_000;
    let top = lda_from_floor(&fluid, &tall, n0, steps);
    let last = top
        .density
        .iter()
        .position(|&d| d <= n0 * (-CEILING_FALL).exp())
        .unwrap_or(top.density.len() - 1);
    let height = last as f64 * top.step;
    let column = Column { height, ..tall };
    let profile = lda_from_floor(&fluid, &column, n0, 4000);
    let width = (n as f64 / profile.load()).powf(1.0 / (D as f64 - 1.0));
    Plan {
        height,
        width,
        profile,
    }
}

/// `n` discs of diameter and mass 1 on a lattice spread like the LDA profile: layers across
/// the field at the profile's quantiles (at least [`START_SPACING`] apart), each a square grid
/// of `k^(D-1)` sites (every other layer shifted by half a site), with as many layers as fit,
/// so that a dilute column starts spread over its height and a dense one close to its
/// equilibrium. Velocities Gaussian at `kT = 1`. `None` if the column cannot hold them so.
pub(super) fn place<const D: usize>(plan: &Plan, n: usize, seed: u64) -> Option<Vec<Disc<D>>> {
    let sideways = D - 1;
    let most_layers = (plan.height / START_SPACING).floor() as usize + 1;
    let most_k = (plan.width / START_SPACING).floor() as usize;
    let per_layer = |k: usize| k.pow(sideways as u32);
    let k = (1..=most_k).find(|&k| n.div_ceil(per_layer(k)) <= most_layers)?;
    let layers = n.div_ceil(per_layer(k));
    // The profile's cumulative load at each grid point, for its quantiles.
    let p = &plan.profile;
    let mut cumulative = vec![0.0];
    for w in p.density.windows(2) {
        cumulative.push(cumulative.last().unwrap() + 0.5 * (w[0] + w[1]) * p.step);
    }
    let total = *cumulative.last().unwrap();
    let quantile = |q: f64| {
        let j = cumulative.partition_point(|&c| c < q * total).max(1);
        let (c0, c1) = (cumulative[j - 1], cumulative[j.min(cumulative.len() - 1)]);
        let f = if c1 > c0 {
            (q * total - c0) / (c1 - c0)
        } else {
            0.0
        };
        (j as f64 - 1.0 + f) * p.step
    };
    let mut heights: Vec<f64> = Vec::with_capacity(layers);
    for j in 0..layers {
        let q = quantile((j as f64 + 0.5) / layers as f64);
        let floor = heights.last().map_or(0.0, |h| h + START_SPACING);
        heights.push(q.max(floor));
    }
    // Pushed up by the spacing, the top layers may pass the ceiling: down again, from the top.
    for j in (0..layers).rev() {
        let room = plan.height - (layers - 1 - j) as f64 * START_SPACING;
        heights[j] = heights[j].min(room);
    }
    let a = plan.width / k as f64;
    let mut discs = Vec::with_capacity(n);
    'fill: for (j, &h) in heights.iter().enumerate() {
        let shift = if j % 2 == 0 { 0.25 } else { 0.75 };
        for site in 0..per_layer(k) {
            if discs.len() == n {
                break 'fill;
            }
            let mut rest = site;
            let pos = Vector(std::array::from_fn(|axis| {
                if axis == sideways {
                    0.5 + h
                } else {
                    let c = rest % k;
                    rest /= k;
                    (c as f64 + shift) * a
                }
            }));
            discs.push(Disc::new(pos, Vector::ZERO, 0.5));
        }
    }
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
    thermal_velocities(&mut discs, 1.0, &mut rng);
    Some(discs)
}

/// What one column's run gave, per block: counts and sums per height bin.
pub(super) struct Samples {
    /// Fine bins: the centres counted per block and bin.
    pub counts: Vec<Vec<u64>>,
    /// Coarse bins (about a diameter): the centres counted per block and bin.
    pub coarse_counts: Vec<Vec<u64>>,
    /// Coarse bins: `sum m v^2` per block and bin.
    pub coarse_mv2: Vec<Vec<f64>>,
    /// Per block: the sum of the heights.
    pub height_sums: Vec<f64>,
    /// Per block: the sum of `m v^2` over every disc and sample.
    pub mv2: Vec<f64>,
    /// Samples per block.
    pub per_block: usize,
    /// The time between samples.
    pub interval: f64,
    /// Simulated time measured over.
    pub time: f64,
    /// Disc-disc collisions while measuring.
    pub collisions: u64,
}

/// Runs the column: `BATH_TIMES` flight times `lambda` in the Andersen bath at `kT = 1`, then
/// `SETTLE_TIMES` on its own, then `BLOCKS * per_block` samples with the energy conserved,
/// `lambda / SAMPLES_PER_TIME` apart or, in a gas whose discs meet more rarely than that,
/// `1 / (SAMPLES_PER_FREE_TIME omega)` with `omega` the collisions per disc per unit time
/// while in the bath. `None` if a stop was requested.
#[allow(clippy::too_many_arguments)]
pub(super) fn measure<const D: usize>(
    plan: &Plan,
    discs: &[Disc<D>],
    g: f64,
    bins: (usize, usize),
    per_block: usize,
    seed: u64,
    bar: &Progress,
    done: u64,
) -> Result<Option<Samples>> {
    let up = D - 1;
    let mut bx = SimBox {
        lengths: [plan.width; D],
        boundaries: [Boundary::Periodic; D],
    };
    bx.lengths[up] = plan.height + 1.0;
    bx.boundaries[up] = Boundary::Walls;
    let what = "barometric";
    let mut sim = Simulation::new(discs, bx, Options::default())
        .or_else(|e| edmd::user_error(format!("{what}: {e}")))?;
    sim.set_gravity(Some(Gravity { axis: up, g: -g }))
        .or_else(|e| edmd::user_error(format!("{what}: {e}")))?;
    let flight = 1.0 / g;
    sim.set_thermostat(Some(Andersen {
        kt: 1.0,
        rate: 1.0 / flight,
        seed,
    }))
    .or_else(|e| edmd::user_error(format!("{what}: {e}")))?;
    let steps = 20;
    let c_bath = sim.stats().disc_disc;
    for s in 1..=steps {
        let t = BATH_TIMES * flight * s as f64 / steps as f64;
        if !edmd::run_until_or_stop(&mut sim, t, &mut ())? {
            return Ok(None);
        }
        bar.set(done + s as u64 * (BLOCKS * per_block) as u64 / (2 * steps) as u64);
    }
    sim.set_thermostat(None)
        .or_else(|e| edmd::user_error(format!("{what}: {e}")))?;
    let t0 = sim.time() + SETTLE_TIMES * flight;
    if !edmd::run_until_or_stop(&mut sim, t0, &mut ())? {
        return Ok(None);
    }
    let (fine, coarse) = bins;
    let n = discs.len();
    let c0 = sim.stats().disc_disc;
    // Collisions per disc per unit time, over the bath and the settling.
    let rate = 2.0 * (c0 - c_bath) as f64 / (n as f64 * sim.time());
    // At most 25 flight times: a gas so thin that its discs hardly meet is sampled anyway.
    let free = if rate > 0.0 {
        1.0 / (SAMPLES_PER_FREE_TIME * rate)
    } else {
        f64::INFINITY
    };
    let dt = (flight / SAMPLES_PER_TIME).max(free).min(25.0 * flight);
    let fine_w = plan.height / fine as f64;
    let coarse_w = plan.height / coarse as f64;
    let bin = |h: f64, w: f64, k: usize| ((h / w).floor().max(0.0) as usize).min(k - 1);
    let mut out = Samples {
        counts: vec![vec![0; fine]; BLOCKS],
        coarse_counts: vec![vec![0; coarse]; BLOCKS],
        coarse_mv2: vec![vec![0.0; coarse]; BLOCKS],
        height_sums: vec![0.0; BLOCKS],
        mv2: vec![0.0; BLOCKS],
        per_block,
        interval: dt,
        time: 0.0,
        collisions: 0,
    };
    for b in 0..BLOCKS {
        for s in 0..per_block {
            let t = t0 + ((b * per_block + s + 1) as f64) * dt;
            if !edmd::run_until_or_stop(&mut sim, t, &mut ())? {
                return Ok(None);
            }
            for i in 0..n {
                let h = sim.position(i)[up] - 0.5;
                let v = sim.velocity(i);
                let mv2: f64 = (0..D).map(|a| v[a] * v[a]).sum();
                out.counts[b][bin(h, fine_w, fine)] += 1;
                let c = bin(h, coarse_w, coarse);
                out.coarse_counts[b][c] += 1;
                out.coarse_mv2[b][c] += mv2;
                out.height_sums[b] += h;
                out.mv2[b] += mv2;
            }
        }
        bar.set(done + (BLOCKS * per_block / 2 + (b + 1) * per_block / 2) as u64);
    }
    out.time = sim.time() - t0;
    out.collisions = sim.stats().disc_disc - c0;
    Ok(Some(out))
}
