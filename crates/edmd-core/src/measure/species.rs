//! Composition of the two halves of the box, over time: how two species mix.
//!
//! The box is cut in two at `L_a / 2` along an axis (a disc belongs to the half holding its
//! centre). For each half and species, the fraction of the half's discs that are of that
//! species, `x_s(half) = N_s(half) / N(half)`. Two species started apart mix until each half
//! holds the overall composition `N_s / N`.

use crate::events::Side;
use crate::simulation::Simulation;

/// Counts of each species in the two halves of the box, sampled at times the caller chooses.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpeciesHalves {
    axis: usize,
    species: usize,
    snapshots: Vec<SpeciesSnapshot>,
}

/// The counts at one time.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpeciesSnapshot {
    /// Time.
    pub time: f64,
    /// `counts[s] = [in the low half, in the high half]` for species `s`.
    pub counts: Vec<[usize; 2]>,
}

/// Summary of a [`SpeciesHalves`] series.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpeciesSummary {
    /// Number of snapshots.
    pub samples: usize,
    /// `overall[s]`: fraction of all discs that are of species `s`.
    pub overall: Vec<f64>,
    /// `last[s] = [x_s(low), x_s(high)]` at the last snapshot (empty if none).
    pub last: Vec<[f64; 2]>,
}

fn half_index(half: Side) -> usize {
    match half {
        Side::Low => 0,
        Side::High => 1,
    }
}

impl SpeciesSnapshot {
    /// Fraction of the discs in `half` that are of `species` (`NaN` if the half is empty, 0 for
    /// a species never seen).
    pub fn fraction(&self, species: usize, half: Side) -> f64 {
        let h = half_index(half);
        let total: usize = self.counts.iter().map(|c| c[h]).sum();
        let n = self.counts.get(species).map_or(0, |c| c[h]);
        if total == 0 {
            f64::NAN
        } else {
            n as f64 / total as f64
        }
    }
}

impl SpeciesHalves {
    /// Halves along `axis`. Species are the labels `0..=max` found in the simulation.
    ///
    /// # Panics
    /// If `axis` is not an axis of the box.
    pub fn new<const D: usize>(sim: &Simulation<D>, axis: usize) -> Self {
        assert!(axis < D, "no axis {axis}");
        let species = (0..sim.len()).map(|i| sim.species(i) as usize + 1).max();
        SpeciesHalves {
            axis,
            species: species.unwrap_or(0),
            snapshots: Vec::new(),
        }
    }

    /// Whether this measurement can go on observing `sim`: the axis exists (a measurement read
    /// back from a file is checked so before use; species it has not seen yet are counted from
    /// their first sample on).
    pub fn fits<const D: usize>(&self, _sim: &Simulation<D>) -> bool {
        self.axis < D
    }

    /// Records the counts now. A species first seen now (made by a reaction) is counted from
    /// here on; earlier snapshots hold no count of it, read as 0.
    pub fn sample<const D: usize>(&mut self, sim: &Simulation<D>) {
        let mid = 0.5 * sim.sim_box().lengths[self.axis];
        let seen = (0..sim.len()).map(|i| sim.species(i) as usize + 1).max();
        self.species = self.species.max(seen.unwrap_or(0));
        let mut counts = vec![[0usize; 2]; self.species];
        for i in 0..sim.len() {
            let s = sim.species(i) as usize;
            let h = (sim.position(i)[self.axis] >= mid) as usize;
            counts[s][h] += 1;
        }
        self.snapshots.push(SpeciesSnapshot {
            time: sim.time(),
            counts,
        });
    }

    /// The snapshots.
    pub fn snapshots(&self) -> &[SpeciesSnapshot] {
        &self.snapshots
    }

    /// `(t, fraction of the discs in half that are of species)` over the snapshots.
    pub fn series(&self, species: usize, half: Side) -> Vec<(f64, f64)> {
        self.snapshots
            .iter()
            .map(|s| (s.time, s.fraction(species, half)))
            .collect()
    }

    /// Overall composition and the composition of each half at the last snapshot.
    pub fn summary(&self) -> SpeciesSummary {
        let (overall, last) = match self.snapshots.last() {
            None => (Vec::new(), Vec::new()),
            Some(snap) => {
                let total: usize = snap.counts.iter().map(|c| c[0] + c[1]).sum();
                let overall = snap
                    .counts
                    .iter()
                    .map(|c| (c[0] + c[1]) as f64 / total as f64)
                    .collect();
                let last = (0..self.species)
                    .map(|s| [snap.fraction(s, Side::Low), snap.fraction(s, Side::High)])
                    .collect();
                (overall, last)
            }
        };
        SpeciesSummary {
            samples: self.snapshots.len(),
            overall,
            last,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Disc, Options, SimBox, Vector};

    #[test]
    fn species_made_by_reactions_are_counted_from_when_they_appear() {
        // Two discs of species 0 meet head on and become species 3, which the measurement,
        // made before, had not seen (it once indexed past its counts).
        let discs = [
            Disc::new(Vector::new([2.0, 5.0]), Vector::new([1.0, 0.0]), 0.5),
            Disc::new(Vector::new([4.0, 5.0]), Vector::new([0.0, 0.0]), 0.5),
        ];
        let mut sim =
            Simulation::new(&discs, SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
        sim.set_reactions(Some(crate::Reactions::new(vec![crate::Reaction {
            reactants: (0, 0),
            products: (3, 3),
            activation: 0.0,
            probability: 1.0,
            heat: 0.0,
        }])))
        .unwrap();
        let mut halves = SpeciesHalves::new(&sim, 0);
        halves.sample(&sim);
        sim.run_until(2.0, &mut ());
        assert!(halves.fits(&sim));
        halves.sample(&sim);
        assert_eq!(halves.snapshots()[0].counts, vec![[2, 0]]);
        // Disc 1, knocked on at speed 1 from x = 4 at t = 1, is at the cut by t = 2.
        assert_eq!(
            halves.snapshots()[1].counts,
            vec![[0, 0], [0, 0], [0, 0], [1, 1]]
        );
        assert_eq!(halves.series(3, Side::Low), vec![(0.0, 0.0), (2.0, 1.0)]);
        assert_eq!(halves.summary().overall, vec![0.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn composition_of_the_halves() {
        // Box 10 x 10 cut along x at 5. Low half: two of species 0, one of species 2. High
        // half: one of species 0. Then disc 3 (species 0, high) crosses into the low half.
        let place = |x: f64, y: f64, vx: f64, s: u16| {
            let mut d = Disc::new(Vector::new([x, y]), Vector::new([vx, 0.0]), 0.5);
            d.species = s;
            d
        };
        let discs = [
            place(1.0, 1.0, 0.0, 0),
            place(1.0, 3.0, 0.0, 0),
            place(3.0, 5.0, 0.0, 2),
            place(6.0, 8.0, -1.0, 0),
        ];
        let mut sim =
            Simulation::new(&discs, SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
        let mut halves = SpeciesHalves::new(&sim, 0);
        halves.sample(&sim);
        sim.run_until(2.0, &mut ());
        halves.sample(&sim);
        let first = &halves.snapshots()[0];
        assert_eq!(first.counts, vec![[2, 1], [0, 0], [1, 0]]);
        assert_eq!(first.fraction(0, Side::Low), 2.0 / 3.0);
        assert_eq!(first.fraction(2, Side::High), 0.0);
        assert_eq!(first.fraction(7, Side::Low), 0.0);
        let high = halves.series(0, Side::High);
        assert_eq!(high[0], (0.0, 1.0));
        assert_eq!(high[1].0, 2.0);
        // Nobody is left in the high half.
        assert!(high[1].1.is_nan());
        let s = halves.summary();
        assert_eq!(s.samples, 2);
        assert_eq!(s.overall, vec![0.75, 0.0, 0.25]);
        assert_eq!(s.last[0][0], 0.75);
        assert!(s.last[0][1].is_nan());
    }
}
