//! The equilibrium runs, `A + B -> B + A` in a fluid at `kT`, and their rows.

use anyhow::Result;
use edmd_core::measure::theory::{line_of_centres_fraction, line_of_centres_rate_constant};
use edmd_core::measure::{block_error, Kinetics};
use edmd_core::{Reaction, Reactions};
use serde::Serialize;

use super::super::common::Progress;
use super::fluid::{binomial_error, fluid, rule, run_observed, species_temperature, PairCount};
use super::ReactionArgs;

/// One equilibrium run: a dimension, a packing fraction and an activation energy.
#[derive(Debug, Serialize)]
pub(super) struct Row {
    /// Dimension.
    pub(super) dim: usize,
    /// Packing fraction.
    pub(super) packing: f64,
    /// Discs (spheres).
    pub(super) n: usize,
    /// Independent fluids measured.
    pub(super) runs: u64,
    /// Activation energy in units of kT.
    pub(super) activation: f64,
    /// Reactive collisions over all collisions, all runs together (every pair of species has
    /// a rule: `A + B -> B + A`, `A + A -> A + A`, `B + B -> B + B`).
    pub(super) reactive_fraction: f64,
    /// Its statistical error (one standard deviation: the standard error of the runs' mean, or
    /// the binomial counting error where that is larger).
    pub(super) reactive_fraction_error: f64,
    /// The line-of-centres law, `exp(-E*/kT)`.
    pub(super) reactive_fraction_theory: f64,
    /// Reactions of `A + B -> B + A` over the collisions of an A with a B.
    pub(super) reactive_fraction_ab: f64,
    /// Its statistical error.
    pub(super) reactive_fraction_ab_error: f64,
    /// The line-of-centres law, `exp(-E*/kT)`.
    pub(super) reactive_fraction_ab_theory: f64,
    /// Rate constant `k` (reactions per unit volume and time over `n_A n_B`; diameter 1,
    /// mass 1, kT 1).
    pub(super) rate_constant: f64,
    /// Its statistical error.
    pub(super) rate_constant_error: f64,
    /// The line-of-centres law with Enskog's collision rate, `(omega / n) exp(-E*/kT)`.
    pub(super) rate_constant_theory: f64,
    /// Enskog's contact value `g(sigma)` in that law.
    pub(super) contact_value: f64,
    /// Kinetic temperature of species A at the runs' ends, in units of kT (equilibrium: 1).
    pub(super) temperature_a: f64,
    /// Its statistical error.
    pub(super) temperature_a_error: f64,
    /// Collisions of an A with a B measured over, all runs together.
    pub(super) ab_collisions: u64,
    /// Reactions of `A + B -> B + A` counted.
    pub(super) reactions: u64,
    /// Simulated time measured over, all runs together.
    pub(super) time: f64,
}

/// Half the labels 0 and half 1 (one more 0 for odd `n`), in a random order drawn from `seed`.
///
/// The labels must not depend on where the discs are. With `A + B -> B + A` a label moves at
/// each energetic collision, so fast discs soon carry labels from around them while slow ones
/// keep theirs: labels placed in a pattern (alternating in the generator's cell order, say,
/// which makes neighbours unlike) would then make the unlike collisions of slow discs more
/// frequent than those of fast ones, and in a dense fluid, where neighbours stay neighbours,
/// the measured fraction would read low (by 2% at packing 0.6 in 2D over 25 collisions per
/// disc). Labels independent of the phase point stay so, since the exchanges only permute
/// them.
fn random_halves(n: usize, seed: u64) -> Vec<u16> {
    use rand::seq::SliceRandom;
    use rand::SeedableRng;
    let mut labels: Vec<u16> = (0..n).map(|k| u16::from(k >= n.div_ceil(2))).collect();
    labels.shuffle(&mut rand_pcg::Pcg64Mcg::seed_from_u64(
        seed ^ 0x5EED_1AB3_1500_0000,
    ));
    labels
}

/// `A + B -> B + A`, and `A + A -> A + A` and `B + B -> B + B`, which change nothing but count
/// as reactions: every collision can react, so reactions over all collisions follow the
/// line-of-centres law, and the first rule's over A-B collisions too.
fn every_pair(activation: f64) -> Reactions {
    let same = |s: u16| Reaction {
        reactants: (s, s),
        products: (s, s),
        activation,
        probability: 1.0,
        heat: 0.0,
    };
    let mut r = rule((0, 1), (1, 0), activation);
    r.rules.extend([same(0), same(1)]);
    r
}

/// What one equilibrium run at one activation energy measured.
#[derive(Clone, Copy, Default)]
struct Measured {
    count: PairCount,
    reactions_per_exposure: f64,
    exposure: f64,
    temperature_a: f64,
    time: f64,
}

/// The equilibrium runs at one packing fraction: `--runs` fluids, each run on at every
/// activation energy; one row per activation energy (none if a stop was requested).
pub(super) fn equilibrium<const D: usize>(
    args: &ReactionArgs,
    eta: f64,
    seed: u64,
    progress: &Progress,
    done: &mut u64,
) -> Result<Vec<Row>> {
    let mut measured: Vec<Vec<Measured>> = vec![Vec::new(); args.activation.len()];
    let mut kts = Vec::new();
    for run in 0..args.runs {
        let labels = random_halves(args.n, seed.wrapping_add(run));
        let Some((base, kt)) = fluid::<D>(args.n, eta, seed.wrapping_add(run), |k| labels[k])?
        else {
            return Ok(Vec::new());
        };
        kts.push(kt);
        for (m, &a) in measured.iter_mut().zip(&args.activation) {
            let mut sim = base.clone();
            sim.set_reactions(Some(every_pair(a * kt)))
                .or_else(|e| edmd::user_error(format!("reaction: {e}")))?;
            let mut kinetics = Kinetics::new(&sim);
            let mut count = PairCount::new((0, 1));
            let t0 = sim.time();
            if !run_observed(
                &mut sim,
                args.collisions * args.n as u64,
                &mut (&mut kinetics, &mut count),
            )? {
                return Ok(Vec::new());
            }
            kinetics.sample(&sim);
            let rate = &kinetics.rates()[0];
            m.push(Measured {
                count,
                reactions_per_exposure: rate.rate_constant.value,
                exposure: rate.exposure,
                temperature_a: species_temperature(&sim, 0, kt).0,
                time: sim.time() - t0,
            });
            *done += 1;
            progress.set(*done);
        }
    }
    let kt = mean(&kts);
    let rows = args
        .activation
        .iter()
        .zip(&measured)
        .map(|(&a, runs)| {
            let sum = |f: fn(&Measured) -> u64| runs.iter().map(f).sum::<u64>();
            let (reactions, pair, all, all_reactions) = (
                sum(|m| m.count.reactions),
                sum(|m| m.count.pair_collisions),
                sum(|m| m.count.all_collisions),
                sum(|m| m.count.all_reactions),
            );
            let each = |f: fn(&Measured) -> f64| runs.iter().map(f).collect::<Vec<f64>>();
            let exposure: f64 = runs.iter().map(|m| m.exposure).sum();
            let temperatures = each(|m| m.temperature_a);
            let theory = line_of_centres_fraction(a, 1.0);
            Row {
                dim: D,
                packing: eta,
                n: args.n,
                runs: args.runs,
                activation: a,
                reactive_fraction: all_reactions as f64 / all.max(1) as f64,
                reactive_fraction_error: block_error(&each(|m| {
                    m.count.all_reactions as f64 / m.count.all_collisions.max(1) as f64
                }))
                .max(binomial_error(all_reactions, all)),
                reactive_fraction_theory: theory,
                reactive_fraction_ab: reactions as f64 / pair.max(1) as f64,
                reactive_fraction_ab_error: block_error(&each(|m| {
                    m.count.reactions as f64 / m.count.pair_collisions.max(1) as f64
                }))
                .max(binomial_error(reactions, pair)),
                reactive_fraction_ab_theory: theory,
                rate_constant: reactions as f64 / exposure,
                rate_constant_error: block_error(&each(|m| m.reactions_per_exposure))
                    .max(reactions as f64 / exposure / (reactions.max(1) as f64).sqrt()),
                rate_constant_theory: line_of_centres_rate_constant(eta, 1.0, kt, 1.0, D, a * kt),
                contact_value: edmd_core::measure::theory::contact_value(eta, D),
                temperature_a: mean(&temperatures),
                temperature_a_error: block_error(&temperatures),
                ab_collisions: pair,
                reactions,
                time: runs.iter().map(|m| m.time).sum(),
            }
        })
        .collect();
    Ok(rows)
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}
