//! Kinetic temperature.
//!
//! Equipartition gives `kT/2` per translational degree of freedom, so with `k_B = 1`
//! `kT = sum m v^2 / (D N)`, in 2D `sum m v^2 / (2N)` (Allen and Tildesley, *Computer
//! Simulation of Liquids*, 2nd ed. (2017), chapter 2, the kinetic temperature). The centre-of-mass
//! motion is not removed: systems set up with zero momentum (as
//! [`crate::setup::lattice_fluid`] does) keep it, and the constraint then only shifts the
//! estimate by a relative `1/N`. Under Lees-Edwards shear and in a ring patch the velocities
//! are the peculiar ones, relative to the streaming flow at each particle
//! ([`Simulation::peculiar_velocity`]): the flow's kinetic energy is not heat.

use crate::simulation::Simulation;

/// `kT = sum m v^2 / (D N)` over the discs accepted by `keep` (`NaN` if none), `v` the peculiar
/// velocity (the velocity itself without shear or ring).
fn temperature_of<const D: usize>(sim: &Simulation<D>, keep: impl Fn(usize) -> bool) -> f64 {
    let (mut twice_ke, mut n) = (0.0, 0usize);
    for i in (0..sim.len()).filter(|&i| keep(i)) {
        twice_ke += sim.mass(i) * sim.peculiar_velocity(i).norm2();
        n += 1;
    }
    twice_ke / (D * n) as f64
}

/// The kinetic temperature of the whole system now, `kT = sum m v^2 / (D N)` (peculiar
/// velocities under shear and in a ring patch).
pub fn kinetic_temperature<const D: usize>(sim: &Simulation<D>) -> f64 {
    temperature_of(sim, |_| true)
}

/// Kinetic temperature sampled at times the caller chooses: all discs, or one species.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Temperature {
    species: Option<u16>,
    series: Vec<(f64, f64)>,
}

/// Summary of a [`Temperature`] series.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TemperatureSummary {
    /// Number of samples.
    pub samples: usize,
    /// Mean `kT` over the samples (`NaN` if none).
    pub mean: f64,
    /// Smallest sample.
    pub min: f64,
    /// Largest sample.
    pub max: f64,
}

impl Temperature {
    /// The temperature of all discs.
    pub fn new() -> Self {
        Self::default()
    }

    /// The temperature of the discs of one species (`kT` of a species can differ from the
    /// whole system's out of equilibrium, e.g. when a hot and a cold gas mix).
    pub fn of_species(species: u16) -> Self {
        Temperature {
            species: Some(species),
            series: Vec::new(),
        }
    }

    /// Records `(t, kT)` now.
    pub fn sample<const D: usize>(&mut self, sim: &Simulation<D>) {
        let kt = match self.species {
            None => kinetic_temperature(sim),
            Some(s) => temperature_of(sim, |i| sim.species(i) == s),
        };
        self.series.push((sim.time(), kt));
    }

    /// The samples `(t, kT)`.
    pub fn series(&self) -> &[(f64, f64)] {
        &self.series
    }

    /// Mean, smallest and largest sample.
    pub fn summary(&self) -> TemperatureSummary {
        let values = self.series.iter().map(|s| s.1);
        TemperatureSummary {
            samples: self.series.len(),
            mean: values.clone().sum::<f64>() / self.series.len() as f64,
            min: values.clone().fold(f64::INFINITY, f64::min),
            max: values.fold(f64::NEG_INFINITY, f64::max),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Disc, Options, SimBox, Vector};

    #[test]
    fn temperature_of_hand_made_velocities() {
        // m v^2: 2 * (9 + 16) = 50 and 1 * 4 = 4; kT = 54 / (2 * 2) = 13.5.
        let mut a = Disc::new(Vector::new([2.0, 2.0]), Vector::new([3.0, 4.0]), 0.5);
        a.mass = 2.0;
        let mut b = Disc::new(Vector::new([6.0, 6.0]), Vector::new([0.0, -2.0]), 0.5);
        b.species = 1;
        let sim =
            Simulation::new(&[a, b], SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
        assert_eq!(kinetic_temperature(&sim), 13.5);
        let mut t = Temperature::new();
        let mut t1 = Temperature::of_species(1);
        t.sample(&sim);
        t1.sample(&sim);
        assert_eq!(t.series(), &[(0.0, 13.5)]);
        // Species 1 alone: 4 / 2 = 2.
        assert_eq!(t1.series(), &[(0.0, 2.0)]);
        let s = t.summary();
        assert_eq!((s.samples, s.mean, s.min, s.max), (1, 13.5, 13.5, 13.5));
    }
}
