//! Mean square displacement and the diffusion coefficient.
//!
//! `MSD(t) = <|r_i(t0 + t) - r_i(t0)|^2>` over the tagged discs, with unwrapped positions (the
//! periodic images crossed are added back). For times long compared with the time between
//! collisions the Einstein relation `MSD = 2 D D t + c` holds, in 2D `4 D t + c` (A. Einstein,
//! Ann. Phys. 17, 549 (1905); Allen and Tildesley, *Computer Simulation of Liquids*, 2nd ed.
//! (2017), chapter 2), so `D` is a quarter of the slope of a least-squares line through the
//! later part of the series.
//!
//! Two cautions. In 2D the velocity autocorrelation decays as `1/t` (B. J. Alder and
//! T. E. Wainwright, Phys. Rev. A 1, 18 (1970)), so `D` grows slowly (logarithmically) with the
//! fitting window: the result is an effective `D` for that window. In a box with walls the MSD
//! saturates at the box size; fit only times well before that. The displacement includes any
//! centre-of-mass drift (none for systems set up with zero momentum).

use super::stats::linear_fit;
use crate::math::Vector;
use crate::simulation::Simulation;

/// Mean square displacement of tagged discs, sampled at times the caller chooses.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Diffusion<const D: usize = 2> {
    start_time: f64,
    tagged: Vec<usize>,
    start: Vec<Vector<D>>,
    series: Vec<(f64, f64)>,
}

/// A least-squares fit `MSD = 2 D D t + c`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DiffusionFit {
    /// Diffusion coefficient `D`.
    pub coefficient: f64,
    /// Intercept `c`.
    pub intercept: f64,
    /// Number of samples fitted.
    pub points: usize,
    /// First fitted time (since the start of the measurement).
    pub from: f64,
    /// Last fitted time.
    pub to: f64,
}

impl<const D: usize> Diffusion<D> {
    /// Tags every disc, starting at the simulation's current time.
    pub fn new(sim: &Simulation<D>) -> Self {
        Self::tagged(sim, (0..sim.len()).collect())
    }

    /// Tags the discs `tagged`, starting at the simulation's current time.
    ///
    /// # Panics
    /// If an index is out of range.
    pub fn tagged(sim: &Simulation<D>, tagged: Vec<usize>) -> Self {
        let start = tagged.iter().map(|&i| sim.unwrapped_position(i)).collect();
        Diffusion {
            start_time: sim.time(),
            tagged,
            start,
            series: Vec::new(),
        }
    }

    /// Whether this measurement can go on observing `sim`: every tagged disc exists and has its
    /// starting point (a measurement read back from a file is checked so before use).
    pub fn fits(&self, sim: &Simulation<D>) -> bool {
        self.start.len() == self.tagged.len() && self.tagged.iter().all(|&i| i < sim.len())
    }

    /// Records `(time since the start, MSD)` now.
    pub fn sample(&mut self, sim: &Simulation<D>) {
        let sum: f64 = self
            .tagged
            .iter()
            .zip(&self.start)
            .map(|(&i, &r0)| (sim.unwrapped_position(i) - r0).norm2())
            .sum();
        let msd = sum / self.tagged.len() as f64;
        self.series.push((sim.time() - self.start_time, msd));
    }

    /// The samples `(time since the start, MSD)`.
    pub fn series(&self) -> &[(f64, f64)] {
        &self.series
    }

    /// Fits the samples at times `>= from * (last sample time)`; `from` in `[0, 1)`, e.g. 0.5
    /// for the later half. `None` with fewer than two such samples.
    pub fn fit(&self, from: f64) -> Option<DiffusionFit> {
        let t_last = self.series.last()?.0;
        let points: Vec<(f64, f64)> = self
            .series
            .iter()
            .copied()
            .filter(|p| p.0 >= from * t_last)
            .collect();
        let (slope, intercept) = linear_fit(&points)?;
        Some(DiffusionFit {
            coefficient: slope / (2.0 * D as f64),
            intercept,
            points: points.len(),
            from: points[0].0,
            to: t_last,
        })
    }

    /// The fit over the later half of the series, `fit(0.5)`.
    pub fn summary(&self) -> Option<DiffusionFit> {
        self.fit(0.5)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Disc, Options, SimBox};

    #[test]
    fn ballistic_disc_across_periodic_boundaries() {
        // One disc at (1, 1) with velocity (1, 0) in a periodic 4 x 4 box crosses the boundary
        // twice by t = 10; unwrapped, its displacement is t, so MSD = t^2. The fit over
        // t = 5..10 of y = t^2 has slope 2 * 7.5 = 15 (D = 15 / 4) and intercept
        // mean(t^2) - 15 * 7.5 = 355/6 - 112.5.
        let d = Disc::new(Vector::new([1.0, 1.0]), Vector::new([1.0, 0.0]), 0.5);
        let mut sim =
            Simulation::new(&[d], SimBox::periodic([4.0, 4.0]), Options::default()).unwrap();
        let mut msd = Diffusion::new(&sim);
        for k in 1..=10 {
            sim.run_until(k as f64, &mut ());
            msd.sample(&sim);
        }
        for &(t, m) in msd.series() {
            assert!((m - t * t).abs() < 1e-12, "MSD {m} at {t}");
        }
        let fit = msd.summary().unwrap();
        assert_eq!((fit.points, fit.from, fit.to), (6, 5.0, 10.0));
        assert!((fit.coefficient - 3.75).abs() < 1e-12);
        assert!((fit.intercept - (355.0 / 6.0 - 112.5)).abs() < 1e-10);
    }

    #[test]
    fn only_tagged_discs_count() {
        // Disc 0 moves 2 per unit time, disc 1 stands still: tagging disc 1 alone gives 0,
        // both gives (4 t^2) / 2.
        let discs = [
            Disc::new(Vector::new([1.0, 1.0]), Vector::new([0.0, 2.0]), 0.5),
            Disc::new(Vector::new([3.0, 3.0]), Vector::ZERO, 0.5),
        ];
        let mut sim =
            Simulation::new(&discs, SimBox::periodic([5.0, 5.0]), Options::default()).unwrap();
        let mut all = Diffusion::new(&sim);
        let mut still = Diffusion::tagged(&sim, vec![1]);
        sim.run_until(1.5, &mut ());
        all.sample(&sim);
        still.sample(&sim);
        assert!((all.series()[0].1 - 4.5).abs() < 1e-12);
        assert_eq!(still.series(), &[(1.5, 0.0)]);
        assert!(still.summary().is_none());
    }
}
