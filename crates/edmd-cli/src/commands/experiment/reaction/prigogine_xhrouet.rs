//! The Prigogine-Xhrouet runs, `A + A -> B + B` in a closed box, their windows and the
//! speeds of the A left.

use anyhow::Result;
use edmd_core::measure::theory::{line_of_centres_fraction, line_of_centres_rate_constant};
use edmd_core::measure::{maxwell_cdf, Kinetics};
use serde::Serialize;

use super::super::common::stop_requested;
use super::fluid::{binomial_error, fluid, rule, species_temperature, PairCount};
use super::ReactionArgs;

/// Windows of each Prigogine-Xhrouet run, equal steps of the fraction of A left.
const WINDOWS: usize = 8;
/// Bins of the speed histogram of the A left, over speeds from 0 to `SPEED_MAX` sqrt(kT/m).
const SPEED_BINS: usize = 16;
pub(super) const SPEED_MAX: f64 = 4.0;

/// One window of a Prigogine-Xhrouet run.
#[derive(Debug, Serialize)]
pub(super) struct Window {
    /// Fraction of the discs that are A at the window's start.
    pub(super) a_fraction_start: f64,
    /// At its end.
    pub(super) a_fraction_end: f64,
    /// Simulated time at the window's end (from the start of the reaction).
    pub(super) time: f64,
    /// A-A collisions in the window.
    pub(super) aa_collisions: u64,
    /// Reactions in the window.
    pub(super) reactions: u64,
    /// Reactive A-A collisions over all A-A collisions.
    pub(super) reactive_fraction: f64,
    /// Its counting error (binomial).
    pub(super) reactive_fraction_error: f64,
    /// The equilibrium value `exp(-E*/kT)`.
    pub(super) reactive_fraction_equilibrium: f64,
    /// `exp(-E*/kT_A)` with the measured temperature of the A (the reactants as a Maxwellian
    /// gas at their own temperature).
    pub(super) reactive_fraction_temperature: f64,
    /// Kinetic temperature of the A in units of kT, averaged over the window's start and end.
    pub(super) temperature_a: f64,
    /// Its error (from the spread of the A's kinetic energies).
    pub(super) temperature_a_error: f64,
    /// Rate constant of the window (`k n_A^2 / 2` reactions per unit volume and time).
    pub(super) rate_constant: f64,
    /// Its counting error (Poisson).
    pub(super) rate_constant_error: f64,
    /// The equilibrium value, `(omega / n) exp(-E*/kT)`.
    pub(super) rate_constant_equilibrium: f64,
}

/// One Prigogine-Xhrouet run.
#[derive(Debug, Serialize)]
pub(super) struct PxRun {
    /// Dimension.
    pub(super) dim: usize,
    /// Packing fraction.
    pub(super) packing: f64,
    /// Discs (spheres).
    pub(super) n: usize,
    /// Activation energy in units of kT.
    pub(super) activation: f64,
    /// Reactive A-A collisions over all A-A collisions, over the whole run.
    pub(super) reactive_fraction: f64,
    /// Its counting error.
    pub(super) reactive_fraction_error: f64,
    /// The equilibrium value `exp(-E*/kT)`.
    pub(super) reactive_fraction_equilibrium: f64,
    /// `1 - reactive_fraction / exp(-E*/kT)`: the relative shortfall of the rate.
    pub(super) deficit: f64,
    /// Its error.
    pub(super) deficit_error: f64,
    /// The temperature estimate over the run: each window's `exp(-E*/kT_A)`, weighted by its
    /// A-A collisions.
    pub(super) reactive_fraction_temperature: f64,
    /// The lowest kinetic temperature of the A at a window's end (in units of kT).
    pub(super) temperature_a_min: f64,
    /// Its error.
    pub(super) temperature_a_min_error: f64,
    /// Fraction of A left at the end.
    pub(super) a_fraction_end: f64,
    /// The windows.
    pub(super) windows: Vec<Window>,
    /// The speeds of the A at the windows' ends, pooled: `(speed, measured density, Maxwell
    /// at kT, count)` per bin.
    #[serde(skip)]
    pub(super) speeds: Vec<(f64, f64, f64, u64)>,
}

/// A closed box of A at `eta` with `A + A -> B + B` at activation `a` kT, run in windows until
/// the fraction of A left reaches `--px-until`; `None` if a stop was requested.
pub(super) fn prigogine_xhrouet<const D: usize>(
    args: &ReactionArgs,
    eta: f64,
    a: f64,
    seed: u64,
) -> Result<Option<PxRun>> {
    let n = args.px_n;
    let Some((mut sim, kt)) = fluid::<D>(n, eta, seed, |_| 0)? else {
        return Ok(None);
    };
    sim.set_reactions(Some(rule((0, 0), (1, 1), a * kt)))
        .or_else(|e| edmd::user_error(format!("reaction: {e}")))?;
    let equilibrium = line_of_centres_fraction(a * kt, kt);
    let k_equilibrium = line_of_centres_rate_constant(eta, 1.0, kt, 1.0, D, a * kt);
    let mut kinetics = Kinetics::new(&sim);
    let t0 = sim.time();
    // Slices of about a tenth of a collision per disc: a window overshoots its end by that.
    let slice = (n as u64 / 10).max(100);
    let mut windows: Vec<Window> = Vec::new();
    let (mut total_collisions, mut total_reactions) = (0u64, 0u64);
    let mut at_start = species_temperature(&sim, 0, kt);
    let mut before = (0u64, 0.0);
    let mut speeds = Vec::new();
    let mut coldest = (f64::INFINITY, f64::NAN);
    for w in 1..=WINDOWS {
        let target = 1.0 - (1.0 - args.px_until) * w as f64 / WINDOWS as f64;
        let start = kinetics.counts()[0] as f64 / n as f64;
        let mut count = PairCount::new((0, 0));
        while (kinetics.counts()[0] as f64) > target * n as f64 {
            if stop_requested() {
                return Ok(None);
            }
            let done = sim.run_events(slice, &mut edmd::shared(&mut (&mut kinetics, &mut count)));
            edmd::check_stall(&sim)?;
            if done == 0 {
                return edmd::user_error("reaction: no disc moves");
            }
        }
        kinetics.sample(&sim);
        // The window's own rate constant: its reactions over its exposure.
        let r = &kinetics.rates()[0];
        let (reactions, exposure) = (r.reactions - before.0, r.exposure - before.1);
        before = (r.reactions, r.exposure);
        let k = reactions as f64 / exposure;
        let at_end = species_temperature(&sim, 0, kt);
        if at_end.0 < coldest.0 {
            coldest = at_end;
        }
        let ta = 0.5 * (at_start.0 + at_end.0);
        let ta_error = 0.5 * at_start.1.hypot(at_end.1);
        at_start = at_end;
        speeds.extend(
            (0..sim.len())
                .filter(|&i| sim.species(i) == 0)
                .map(|i| (sim.velocity(i).norm2() / kt).sqrt()),
        );
        windows.push(Window {
            a_fraction_start: start,
            a_fraction_end: kinetics.counts()[0] as f64 / n as f64,
            time: sim.time() - t0,
            aa_collisions: count.pair_collisions,
            reactions: count.reactions,
            reactive_fraction: count.reactions as f64 / count.pair_collisions.max(1) as f64,
            reactive_fraction_error: binomial_error(count.reactions, count.pair_collisions),
            reactive_fraction_equilibrium: equilibrium,
            reactive_fraction_temperature: line_of_centres_fraction(a * kt, ta * kt),
            temperature_a: ta,
            temperature_a_error: ta_error,
            rate_constant: k,
            rate_constant_error: k / (reactions.max(1) as f64).sqrt(),
            rate_constant_equilibrium: k_equilibrium,
        });
        total_collisions += count.pair_collisions;
        total_reactions += count.reactions;
    }
    let fraction = total_reactions as f64 / total_collisions.max(1) as f64;
    let error = binomial_error(total_reactions, total_collisions);
    // The temperature estimate over the run: each window's, weighted by its A-A collisions.
    let estimate = windows
        .iter()
        .map(|w| w.reactive_fraction_temperature * w.aa_collisions as f64)
        .sum::<f64>()
        / total_collisions.max(1) as f64;
    Ok(Some(PxRun {
        dim: D,
        packing: eta,
        n,
        activation: a,
        reactive_fraction: fraction,
        reactive_fraction_error: error,
        reactive_fraction_equilibrium: equilibrium,
        deficit: 1.0 - fraction / equilibrium,
        deficit_error: error / equilibrium,
        reactive_fraction_temperature: estimate,
        temperature_a_min: coldest.0,
        temperature_a_min_error: coldest.1,
        a_fraction_end: kinetics.counts()[0] as f64 / n as f64,
        windows,
        speeds: speed_histogram(&speeds, D),
    }))
}

/// `(bin centre, density, Maxwell's density at kT, count)` of speeds in units of sqrt(kT/m).
fn speed_histogram(speeds: &[f64], dim: usize) -> Vec<(f64, f64, f64, u64)> {
    let width = SPEED_MAX / SPEED_BINS as f64;
    let mut counts = [0u64; SPEED_BINS];
    for &v in speeds {
        let k = (v / width) as usize;
        if k < SPEED_BINS {
            counts[k] += 1;
        }
    }
    let total = speeds.len().max(1) as f64;
    counts
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let (lo, hi) = (k as f64 * width, (k + 1) as f64 * width);
            // Maxwell's probability of the bin over its width (the density averaged over it).
            let maxwell = (maxwell_cdf(hi, 1.0, 1.0, dim) - maxwell_cdf(lo, 1.0, 1.0, dim)) / width;
            (0.5 * (lo + hi), c as f64 / (total * width), maxwell, c)
        })
        .collect()
}
