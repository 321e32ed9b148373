//! The fluids both kinds of run start from, the reaction rules put on them, and what is
//! counted and measured as they run.

use anyhow::Result;
use edmd_core::Simulation;
use edmd_core::{Boundary, EventKind, EventRecord, Observer, Options, Reaction, Reactions};

use super::super::common::{melted_fluid_in, stop_requested};

/// Counts the collisions of one pair of species (in either order), all collisions, the
/// reactions of the pair's rule (the first) and all reactions. A reaction of the first rule is
/// one of that pair's collisions; a non-reactive collision leaves the species as they were, so
/// the simulation's species name its pair.
#[derive(Clone, Copy, Default)]
pub(super) struct PairCount {
    pair: (u16, u16),
    pub(super) pair_collisions: u64,
    pub(super) all_collisions: u64,
    pub(super) reactions: u64,
    pub(super) all_reactions: u64,
}

impl PairCount {
    pub(super) fn new(pair: (u16, u16)) -> Self {
        PairCount {
            pair,
            ..Self::default()
        }
    }
}

impl<const D: usize> Observer<D> for PairCount {
    #[inline]
    fn on_event(&mut self, e: &EventRecord<D>, sim: &Simulation<D>) {
        match e.kind {
            EventKind::DiscDisc { i, j } => {
                self.all_collisions += 1;
                let s = (sim.species(i), sim.species(j));
                if s == self.pair || (s.1, s.0) == self.pair {
                    self.pair_collisions += 1;
                }
            }
            EventKind::Reaction { rule, .. } => {
                self.all_collisions += 1;
                self.all_reactions += 1;
                if rule == 0 {
                    self.pair_collisions += 1;
                    self.reactions += 1;
                }
            }
            _ => {}
        }
    }
}

/// Runs `sim` for `collisions` more disc-disc collisions with `observer`, in slices with a
/// look at the stop flag between them; `false` when a stop was requested first.
pub(super) fn run_observed<const D: usize, O: Observer<D>>(
    sim: &mut Simulation<D>,
    collisions: u64,
    observer: &mut O,
) -> Result<bool> {
    let target = sim.stats().disc_disc.saturating_add(collisions);
    while sim.stats().disc_disc < target {
        if stop_requested() {
            return Ok(false);
        }
        let slice = (target - sim.stats().disc_disc).min(10_000);
        let done = sim.run_events(slice, &mut edmd::shared(observer));
        edmd::check_stall(sim)?;
        if done == 0 {
            return edmd::user_error("reaction: no disc moves");
        }
    }
    Ok(true)
}

/// Kinetic temperature of the discs of species `s` in units of `kt`, and its standard error
/// (that of a mean over the discs); `NaN` if there are none.
pub(super) fn species_temperature<const D: usize>(
    sim: &Simulation<D>,
    s: u16,
    kt: f64,
) -> (f64, f64) {
    let per_disc: Vec<f64> = (0..sim.len())
        .filter(|&i| sim.species(i) == s)
        .map(|i| sim.mass(i) * sim.velocity(i).norm2() / (D as f64 * kt))
        .collect();
    let m = per_disc.len() as f64;
    let mean = per_disc.iter().sum::<f64>() / m;
    let var = per_disc.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (m - 1.0);
    (mean, (var / m).sqrt())
}

/// A melted fluid at `eta` whose discs (in the generator's order) are of the species
/// `species(k)`, and its `kT`.
pub(super) fn fluid<const D: usize>(
    n: usize,
    eta: f64,
    seed: u64,
    species: impl Fn(usize) -> u16,
) -> Result<Option<(Simulation<D>, f64)>> {
    let Some((melted, _)) = melted_fluid_in::<D>(n, eta, Boundary::Periodic, seed, 20)? else {
        return Ok(None);
    };
    let mut discs = melted.discs();
    for (k, d) in discs.iter_mut().enumerate() {
        d.species = species(k);
    }
    let sim = Simulation::new(&discs, *melted.sim_box(), Options::default())
        .or_else(|e| edmd::user_error(format!("reaction: {e}")))?;
    let kt = 2.0 * sim.kinetic_energy() / (D * n) as f64;
    Ok(Some((sim, kt)))
}

pub(super) fn rule(reactants: (u16, u16), products: (u16, u16), activation: f64) -> Reactions {
    Reactions::new(vec![Reaction {
        reactants,
        products,
        activation,
        probability: 1.0,
        heat: 0.0,
    }])
}

/// Binomial standard error of a fraction `k / m`.
pub(super) fn binomial_error(k: u64, m: u64) -> f64 {
    if m == 0 {
        return f64::NAN;
    }
    let p = k as f64 / m as f64;
    (p * (1.0 - p) / m as f64).sqrt()
}
