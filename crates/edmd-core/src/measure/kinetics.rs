//! Chemical kinetics of a reactive run: the species counts over time and each reaction rule's
//! rate constant.
//!
//! A rule `A + B -> ...` with rate constant `k` happens `k n_A n_B` times per unit volume and
//! time (`n` the number densities), `k n_A^2 / 2` for like reactants: each of the `N_A N_B`
//! pairs (`N_A (N_A - 1) / 2` of like ones) reacts at the rate `k / V`. So
//! `k = V * reactions / integral(pairs dt)`, the integral taken over the measuring time with
//! the counts as they change reaction by reaction. Samples end blocks; the error of `k` comes
//! from the blocks' values ([`Estimate`]).

use crate::events::{EventKind, EventRecord};
use crate::measure::stats::Estimate;
use crate::observer::Observer;
use crate::simulation::Simulation;

/// Species counts and reactions per rule, observed event by event.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Kinetics {
    volume: f64,
    /// Each rule's reactants and products.
    rules: Vec<[u16; 4]>,
    /// Discs of each species now.
    counts: Vec<usize>,
    /// Time up to which the exposures are integrated.
    last: f64,
    start: f64,
    /// Per rule, reactions and `integral(pairs dt)` in the block under way.
    block_events: Vec<u64>,
    block_exposure: Vec<f64>,
    /// Per rule, per finished block: reactions and exposure.
    blocks: Vec<Vec<(u64, f64)>>,
    /// `(time, counts)` at each sample (and the start).
    series: Vec<(f64, Vec<usize>)>,
}

/// A rule's measured rate constant.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RuleRate {
    /// Reactants and products, `[A, B, C, D]` for `A + B -> C + D`.
    pub rule: [u16; 4],
    /// Reactions counted.
    pub reactions: u64,
    /// `integral(pairs dt) / V`: reactions divided by it give `k`.
    pub exposure: f64,
    /// The rate constant `k` with its block error (`NaN` value with no exposure).
    pub rate_constant: Estimate,
}

impl Kinetics {
    /// Starts observing `sim` now (with no reaction rules there is nothing to count but the
    /// species).
    pub fn new<const D: usize>(sim: &Simulation<D>) -> Self {
        let rules: Vec<[u16; 4]> = sim.reactions().map_or_else(Vec::new, |r| {
            r.rules
                .iter()
                .map(|r| [r.reactants.0, r.reactants.1, r.products.0, r.products.1])
                .collect()
        });
        let width = (0..sim.len())
            .map(|i| sim.species(i) as usize + 1)
            .chain(rules.iter().flatten().map(|&s| s as usize + 1))
            .max()
            .unwrap_or(0);
        let mut counts = vec![0; width];
        for i in 0..sim.len() {
            counts[sim.species(i) as usize] += 1;
        }
        let n = rules.len();
        Kinetics {
            volume: sim.sim_box().volume(),
            rules,
            series: vec![(sim.time(), counts.clone())],
            counts,
            last: sim.time(),
            start: sim.time(),
            block_events: vec![0; n],
            block_exposure: vec![0.0; n],
            blocks: vec![Vec::new(); n],
        }
    }

    /// Pairs of rule `k`'s reactants now.
    fn pairs(&self, k: usize) -> f64 {
        let [a, b, _, _] = self.rules[k];
        let na = self.counts[a as usize] as f64;
        if a == b {
            na * (na - 1.0) / 2.0
        } else {
            na * self.counts[b as usize] as f64
        }
    }

    fn integrate_to(&mut self, t: f64) {
        let dt = t - self.last;
        if dt > 0.0 {
            for k in 0..self.rules.len() {
                self.block_exposure[k] += self.pairs(k) * dt;
            }
            self.last = t;
        }
    }

    /// Ends a block at the simulation's time and records the species counts.
    pub fn sample<const D: usize>(&mut self, sim: &Simulation<D>) {
        self.integrate_to(sim.time());
        for k in 0..self.rules.len() {
            self.blocks[k].push((self.block_events[k], self.block_exposure[k]));
            self.block_events[k] = 0;
            self.block_exposure[k] = 0.0;
        }
        self.series.push((sim.time(), self.counts.clone()));
    }

    /// Discs of each species now (indexed by species).
    pub fn counts(&self) -> &[usize] {
        &self.counts
    }

    /// The species counts at the start and at each sample.
    pub fn series(&self) -> &[(f64, Vec<usize>)] {
        &self.series
    }

    /// Time observed (from the start to the last sample or event seen).
    pub fn duration(&self) -> f64 {
        self.last - self.start
    }

    /// Each rule's reactions and rate constant over the finished blocks.
    pub fn rates(&self) -> Vec<RuleRate> {
        (0..self.rules.len())
            .map(|k| {
                let reactions: u64 = self.blocks[k].iter().map(|b| b.0).sum();
                let exposure: f64 = self.blocks[k].iter().map(|b| b.1).sum::<f64>() / self.volume;
                let per_block: Vec<f64> = self.blocks[k]
                    .iter()
                    .filter(|b| b.1 > 0.0)
                    .map(|b| b.0 as f64 * self.volume / b.1)
                    .collect();
                let value = if exposure > 0.0 {
                    reactions as f64 / exposure
                } else {
                    f64::NAN
                };
                RuleRate {
                    rule: self.rules[k],
                    reactions,
                    exposure,
                    rate_constant: Estimate::new(value, &per_block),
                }
            })
            .collect()
    }
}

impl<const D: usize> Observer<D> for Kinetics {
    #[inline]
    fn on_event(&mut self, e: &EventRecord<D>, _: &Simulation<D>) {
        // A rule beyond the ones seen at the start (rules set afresh since) is not counted:
        // the caller starts a new measurement with new rules.
        if let EventKind::Reaction { rule, .. } = e.kind {
            if rule >= self.rules.len() {
                return;
            }
            self.integrate_to(e.time);
            let [a, b, c, d] = self.rules[rule];
            for s in [a, b] {
                self.counts[s as usize] -= 1;
            }
            for s in [c, d] {
                self.counts[s as usize] += 1;
            }
            self.block_events[rule] += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::observer::obs;
    use crate::setup::lattice_fluid;
    use crate::{Boundary, Options, Reaction, Reactions};

    #[test]
    fn counts_follow_the_reactions_and_the_rate_is_reactions_over_exposure() {
        let (mut discs, bx) = lattice_fluid(400, 0.3, Boundary::Periodic, 1).unwrap();
        for (k, d) in discs.iter_mut().enumerate() {
            d.species = (k % 2) as u16;
        }
        let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        sim.set_reactions(Some(Reactions::new(vec![Reaction {
            reactants: (0, 1),
            products: (2, 2),
            activation: 0.5,
            probability: 1.0,
            heat: 0.0,
        }])))
        .unwrap();
        let mut kin = Kinetics::new(&sim);
        for k in 1..=5 {
            sim.run_until(k as f64, &mut obs(&mut kin));
            kin.sample(&sim);
        }
        let n2 = (0..sim.len()).filter(|&i| sim.species(i) == 2).count();
        assert!(n2 > 50);
        assert_eq!(kin.counts()[2], n2);
        assert_eq!(kin.counts()[0], kin.counts()[1]);
        let r = &kin.rates()[0];
        assert_eq!(r.reactions as usize, n2 / 2);
        assert_eq!(r.reactions, sim.reaction_counts()[0]);
        assert_eq!(r.rate_constant.blocks, 5);
        assert!(r.rate_constant.value > 0.0 && r.rate_constant.error > 0.0);
        assert_eq!(kin.series().len(), 6);
        assert_eq!(kin.series()[0].1[0], 200);
    }
}
