//! Energy: kinetic, potential (a stepped potential's) and total, sampled at times the caller
//! chooses, and the heat capacity from the fluctuations of the total energy in a heat bath.
//!
//! In the canonical ensemble (a run with the Andersen thermostat at `kT`) the heat capacity is
//! `C_V = (<E^2> - <E>^2) / (k T^2)` (Allen and Tildesley, *Computer Simulation of Liquids*,
//! 2nd ed. (2017), section 2.5); per particle and in units of `k`, `C_V / (N k) = var(E) /
//! (N kT^2)`. It is reported only for runs in a bath: in a run without one the total energy is
//! conserved and its fluctuations say nothing. Its error comes from the variances of blocks of
//! samples (each longer than the correlation time, as for the other block errors).

use super::stats::{variance, Estimate};
use crate::simulation::Simulation;

/// Energy samples: `(t, kinetic, potential)`.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Energy {
    series: Vec<(f64, f64, f64)>,
    /// The particles, and the bath's `kT` when there was one at the first sample.
    n: usize,
    bath_kt: Option<f64>,
}

/// Summary of an [`Energy`] series.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EnergySummary {
    /// Samples taken.
    pub samples: usize,
    /// Mean potential energy per particle.
    pub potential_per_particle: Estimate,
    /// Mean kinetic energy per particle.
    pub kinetic_per_particle: Estimate,
    /// Mean total energy per particle.
    pub total_per_particle: Estimate,
    /// Largest relative change of the total energy from the first sample (`NaN` with a bath,
    /// where it is not conserved).
    pub drift: f64,
    /// `C_V / (N k)` from the fluctuations of the total energy, with a bath only.
    pub heat_capacity: Option<Estimate>,
}

/// The number of blocks the samples are cut into for the errors.
const BLOCKS: usize = 10;

impl Energy {
    /// No samples yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Samples the energies of `sim` now.
    pub fn sample<const D: usize>(&mut self, sim: &Simulation<D>) {
        if self.series.is_empty() {
            self.n = sim.len();
            self.bath_kt = sim.thermostat().map(|a| a.kt);
        }
        self.series
            .push((sim.time(), sim.kinetic_energy(), sim.potential_energy()));
    }

    /// The samples `(t, kinetic, potential)`.
    pub fn series(&self) -> &[(f64, f64, f64)] {
        &self.series
    }

    /// Means with block errors, the drift and the heat capacity.
    pub fn summary(&self) -> EnergySummary {
        let n = self.n.max(1) as f64;
        let per = |f: &dyn Fn(&(f64, f64, f64)) -> f64| {
            let values: Vec<f64> = self.series.iter().map(|s| f(s) / n).collect();
            mean_with_blocks(&values)
        };
        let total = |s: &(f64, f64, f64)| s.1 + s.2;
        let e0 = self.series.first().map_or(0.0, total);
        let drift = if self.bath_kt.is_some() {
            f64::NAN
        } else {
            self.series
                .iter()
                .map(|s| ((total(s) - e0) / e0.abs().max(f64::MIN_POSITIVE)).abs())
                .fold(0.0, f64::max)
        };
        let heat_capacity = self.bath_kt.map(|kt| {
            let e: Vec<f64> = self.series.iter().map(total).collect();
            let blocks: Vec<f64> = chunks(&e).map(|b| variance(b) / (n * kt * kt)).collect();
            Estimate::new(variance(&e) / (n * kt * kt), &blocks)
        });
        EnergySummary {
            samples: self.series.len(),
            potential_per_particle: per(&|s| s.2),
            kinetic_per_particle: per(&|s| s.1),
            total_per_particle: per(&total),
            drift,
            heat_capacity,
        }
    }
}

/// The samples cut into [`BLOCKS`] blocks (fewer with fewer than two samples a block).
fn chunks(values: &[f64]) -> impl Iterator<Item = &[f64]> {
    let size = (values.len() / BLOCKS).max(2);
    values.chunks(size).filter(move |c| c.len() == size)
}

/// The mean of `values` and its error from the means of blocks of them.
fn mean_with_blocks(values: &[f64]) -> Estimate {
    let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
    let blocks: Vec<f64> = chunks(values)
        .map(|b| b.iter().sum::<f64>() / b.len() as f64)
        .collect();
    Estimate::new(if values.is_empty() { f64::NAN } else { mean }, &blocks)
}
