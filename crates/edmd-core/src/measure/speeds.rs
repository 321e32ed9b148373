//! Speed distribution against the Maxwell-Boltzmann law, in 2D or 3D.
//!
//! In equilibrium each velocity component of a particle of mass `m` is normal with variance
//! `kT/m` (Reif, *Fundamentals of Statistical and Thermal Physics* (1965), chapter 7), so the
//! speed follows a chi law with `D` degrees of freedom scaled by `sqrt(kT/m)`:
//! - in 2D the Rayleigh law `f(v) = (m v / kT) exp(-m v^2 / (2 kT))`,
//!   `F(v) = 1 - exp(-m v^2 / (2 kT))`, mean speed `sqrt(pi kT / (2m))`;
//! - in 3D the Maxwell law `f(v) = sqrt(2/pi) (m/kT)^(3/2) v^2 exp(-m v^2 / (2 kT))`,
//!   `F(v) = erf(x / sqrt 2) - sqrt(2/pi) x exp(-x^2/2)` with `x = v sqrt(m/kT)`, mean speed
//!   `sqrt(8 kT / (pi m))`;
//!
//! and in both the root mean square speed is `sqrt(D kT / m)`.
//!
//! The fit is judged with the Kolmogorov-Smirnov test ([`ks_test`]) on the values
//! `F(v_i; m_i)`, which are uniform on `[0, 1]` if the law holds: for equal masses this is the
//! plain test of the speeds against `F`, and it also covers mixtures of masses. The speeds of
//! one disc at two times are independent only if many collisions separate the times, so sample
//! at well-separated times (a few collisions per disc apart) or the p-value is meaningless.

use super::stats::{ks_test, Histogram, KsTest};
use crate::simulation::Simulation;

/// The 2D Maxwell-Boltzmann (Rayleigh) speed density `(m v / kT) exp(-m v^2 / (2 kT))`.
pub fn rayleigh_pdf(v: f64, m: f64, kt: f64) -> f64 {
    m * v / kt * (-m * v * v / (2.0 * kt)).exp()
}

/// The 2D Maxwell-Boltzmann (Rayleigh) speed CDF `1 - exp(-m v^2 / (2 kT))`.
pub fn rayleigh_cdf(v: f64, m: f64, kt: f64) -> f64 {
    -(-m * v * v / (2.0 * kt)).exp_m1()
}

/// The Maxwell-Boltzmann speed density in `dim` dimensions (2 or 3; the Rayleigh law in 2D).
///
/// # Panics
/// If `dim` is not 2 or 3.
pub fn maxwell_pdf(v: f64, m: f64, kt: f64, dim: usize) -> f64 {
    match dim {
        2 => rayleigh_pdf(v, m, kt),
        3 => {
            let a = m / kt;
            (2.0 / std::f64::consts::PI).sqrt() * a.powf(1.5) * v * v * (-a * v * v / 2.0).exp()
        }
        _ => panic!("no Maxwell-Boltzmann law for dimension {dim}"),
    }
}

/// The Maxwell-Boltzmann speed CDF in `dim` dimensions (2 or 3).
///
/// # Panics
/// If `dim` is not 2 or 3.
pub fn maxwell_cdf(v: f64, m: f64, kt: f64, dim: usize) -> f64 {
    match dim {
        2 => rayleigh_cdf(v, m, kt),
        3 => {
            let x = v * (m / kt).sqrt();
            libm::erf(x / std::f64::consts::SQRT_2)
                - (2.0 / std::f64::consts::PI).sqrt() * x * (-x * x / 2.0).exp()
        }
        _ => panic!("no Maxwell-Boltzmann law for dimension {dim}"),
    }
}

/// Mean speed of the Maxwell-Boltzmann law in `dim` dimensions (2 or 3).
fn maxwell_mean(m: f64, kt: f64, dim: usize) -> f64 {
    let pi = std::f64::consts::PI;
    match dim {
        2 => (pi * kt / (2.0 * m)).sqrt(),
        _ => (8.0 * kt / (pi * m)).sqrt(),
    }
}

/// Speeds of every disc pooled over the snapshots the caller takes.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Speeds {
    speeds: Vec<f64>,
    masses: Vec<f64>,
    histogram: Histogram,
    snapshots: usize,
    /// The dimension of the sampled system (2 until a sample says otherwise).
    dim: usize,
}

/// Result of a speed measurement, against the Maxwell-Boltzmann law (Rayleigh in 2D) at a
/// given `kT`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpeedSummary {
    /// Speeds pooled.
    pub samples: usize,
    /// Snapshots taken.
    pub snapshots: usize,
    /// Mean speed.
    pub mean: f64,
    /// Root mean square speed `sqrt(<v^2>)`.
    pub rms: f64,
    /// Mean speed of the law, `sqrt(pi kT / (2m))` in 2D and `sqrt(8 kT / (pi m))` in 3D,
    /// averaged over the samples' masses.
    pub mean_theory: f64,
    /// RMS speed of the law, `sqrt(D kT <1/m>)`.
    pub rms_theory: f64,
    /// Kolmogorov-Smirnov test against the law.
    pub ks: KsTest,
}

impl Speeds {
    /// Pools speeds, with a histogram of `bins` bins on `[0, max_speed)`.
    ///
    /// # Panics
    /// If `bins == 0` or `max_speed` is not a finite positive number.
    pub fn new(bins: usize, max_speed: f64) -> Self {
        Speeds {
            speeds: Vec::new(),
            masses: Vec::new(),
            histogram: Histogram::new(0.0, max_speed, bins),
            snapshots: 0,
            dim: 2,
        }
    }

    /// Adds the speed of every disc now: relative to the streaming flow under shear and in a
    /// ring patch ([`Simulation::peculiar_velocity`]), whose speeds Maxwell's law describes.
    pub fn sample<const D: usize>(&mut self, sim: &Simulation<D>) {
        self.dim = D;
        for i in 0..sim.len() {
            let v = sim.peculiar_velocity(i).norm2().sqrt();
            self.speeds.push(v);
            self.masses.push(sim.mass(i));
            self.histogram.add(v);
        }
        self.snapshots += 1;
    }

    /// The pooled speeds, in sampling order.
    pub fn speeds(&self) -> &[f64] {
        &self.speeds
    }

    /// The histogram of the pooled speeds.
    pub fn histogram(&self) -> &Histogram {
        &self.histogram
    }

    /// `(bin centre, measured density, Rayleigh density at kT)` per histogram bin; with mixed
    /// masses the law is the mixture over the samples' masses.
    pub fn histogram_vs_rayleigh(&self, kt: f64) -> Vec<(f64, f64, f64)> {
        let n = self.masses.len().max(1) as f64;
        self.histogram
            .density()
            .into_iter()
            .map(|(v, f)| {
                let law = self
                    .masses
                    .iter()
                    .map(|&m| rayleigh_pdf(v, m, kt))
                    .sum::<f64>()
                    / n;
                (v, f, law)
            })
            .collect()
    }

    /// Kolmogorov-Smirnov test of the pooled speeds against any law given as a CDF of speed and
    /// mass: the values `cdf(v_i, m_i)` are tested for uniformity on `[0, 1]`.
    pub fn ks_test(&self, cdf: impl Fn(f64, f64) -> f64) -> KsTest {
        let u: Vec<f64> = self
            .speeds
            .iter()
            .zip(&self.masses)
            .map(|(&v, &m)| cdf(v, m))
            .collect();
        ks_test(&u, |x| x.clamp(0.0, 1.0))
    }

    /// Kolmogorov-Smirnov test against the Rayleigh law at `kT` (the 2D law, whatever was
    /// sampled).
    pub fn ks_rayleigh(&self, kt: f64) -> KsTest {
        self.ks_test(|v, m| rayleigh_cdf(v, m, kt))
    }

    /// The dimension of the sampled system.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Kolmogorov-Smirnov test against the Maxwell-Boltzmann law of the sampled dimension.
    pub fn ks_maxwell(&self, kt: f64) -> KsTest {
        let dim = self.dim;
        self.ks_test(|v, m| maxwell_cdf(v, m, kt, dim))
    }

    /// [`Self::histogram_vs_rayleigh`] against the law of the sampled dimension.
    pub fn histogram_vs_maxwell(&self, kt: f64) -> Vec<(f64, f64, f64)> {
        let n = self.masses.len().max(1) as f64;
        self.histogram
            .density()
            .into_iter()
            .map(|(v, f)| {
                let law = self
                    .masses
                    .iter()
                    .map(|&m| maxwell_pdf(v, m, kt, self.dim))
                    .sum::<f64>()
                    / n;
                (v, f, law)
            })
            .collect()
    }

    /// Moments and the fit to the Maxwell-Boltzmann law of the sampled dimension at `kT` (for instance
    /// [`kinetic_temperature`](super::kinetic_temperature), which is constant in a run).
    pub fn summary(&self, kt: f64) -> SpeedSummary {
        let n = self.speeds.len() as f64;
        let mean_of = |f: &dyn Fn(f64, f64) -> f64| -> f64 {
            self.speeds
                .iter()
                .zip(&self.masses)
                .map(|(&v, &m)| f(v, m))
                .sum::<f64>()
                / n
        };
        SpeedSummary {
            samples: self.speeds.len(),
            snapshots: self.snapshots,
            mean: mean_of(&|v, _| v),
            rms: mean_of(&|v, _| v * v).sqrt(),
            mean_theory: mean_of(&|_, m| maxwell_mean(m, kt, self.dim)),
            rms_theory: mean_of(&|_, m| self.dim as f64 * kt / m).sqrt(),
            ks: self.ks_maxwell(kt),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Disc, Options, SimBox, Vector};

    #[test]
    fn rayleigh_law_is_normalised_and_has_its_moments() {
        // Midpoint rule on [0, 20] for m = 2, kT = 1.5: integral 1, mean sqrt(pi kT / 2m),
        // mean square 2 kT / m.
        let (m, kt, h) = (2.0, 1.5, 1e-4);
        let (mut norm, mut mean, mut sq) = (0.0, 0.0, 0.0);
        for k in 0..200_000 {
            let v = (k as f64 + 0.5) * h;
            let f = rayleigh_pdf(v, m, kt) * h;
            norm += f;
            mean += v * f;
            sq += v * v * f;
        }
        assert!((norm - 1.0).abs() < 1e-8);
        assert!((mean - (std::f64::consts::PI * kt / (2.0 * m)).sqrt()).abs() < 1e-8);
        assert!((sq - 2.0 * kt / m).abs() < 1e-8);
        assert!((rayleigh_cdf(1.0, m, kt) - (1.0 - (-2.0f64 / 3.0).exp())).abs() < 1e-15);
    }

    #[test]
    fn maxwell_law_in_3d_is_normalised_has_its_moments_and_its_cdf_integrates_its_density() {
        // Reif (1965) eq. 7.10.x: in 3D the mean speed is sqrt(8 kT / (pi m)) and the mean
        // square speed 3 kT / m. Midpoint rule on [0, 20], m = 2, kT = 1.5; the CDF is checked
        // against the running integral of the density.
        let (m, kt, h) = (2.0, 1.5, 1e-4);
        let (mut norm, mut mean, mut sq) = (0.0, 0.0, 0.0);
        for k in 0..200_000 {
            let v = (k as f64 + 0.5) * h;
            let f = maxwell_pdf(v, m, kt, 3) * h;
            norm += f;
            mean += v * f;
            sq += v * v * f;
            if (k + 1) % 10_000 == 0 {
                let cdf = maxwell_cdf((k + 1) as f64 * h, m, kt, 3);
                assert!(
                    (cdf - norm).abs() < 1e-8,
                    "F({}) = {cdf}, integral {norm}",
                    (k + 1) as f64 * h
                );
            }
        }
        assert!((norm - 1.0).abs() < 1e-8);
        assert!((mean - (8.0 * kt / (std::f64::consts::PI * m)).sqrt()).abs() < 1e-8);
        assert!((sq - 3.0 * kt / m).abs() < 1e-8);
        assert_eq!(maxwell_cdf(0.7, m, kt, 2), rayleigh_cdf(0.7, m, kt));
    }

    #[test]
    fn speeds_of_hand_made_discs() {
        // Speeds 5 (mass 2) and 2 (mass 1), twice: mean 3.5, rms sqrt(14.5).
        let mut a = Disc::new(Vector::new([2.0, 2.0]), Vector::new([3.0, 4.0]), 0.5);
        a.mass = 2.0;
        let b = Disc::new(Vector::new([6.0, 6.0]), Vector::new([0.0, -2.0]), 0.5);
        let sim =
            Simulation::new(&[a, b], SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
        let mut s = Speeds::new(10, 10.0);
        s.sample(&sim);
        s.sample(&sim);
        let sum = s.summary(1.0);
        assert_eq!((sum.samples, sum.snapshots), (4, 2));
        assert_eq!(sum.mean, 3.5);
        assert_eq!(sum.rms, 14.5f64.sqrt());
        // <1/m> = 3/4: rms_theory = sqrt(2 * 3/4).
        assert!((sum.rms_theory - 1.5f64.sqrt()).abs() < 1e-15);
        assert_eq!(s.histogram().counts[2], 2);
        assert_eq!(s.histogram().counts[5], 2);
        assert_eq!(s.speeds(), &[5.0, 2.0, 5.0, 2.0]);
        // Each disc's value of F is its own CDF: F(5; 2, 1) = 1 - e^-25, F(2; 1, 1) = 1 - e^-2.
        let ks = s.ks_rayleigh(1.0);
        let f_low = 1.0 - (-2.0f64).exp();
        assert!((ks.statistic - f_low).abs() < 1e-12);
        let v = s.histogram_vs_rayleigh(1.0);
        assert_eq!(v.len(), 10);
        let expect = 0.5 * (rayleigh_pdf(2.5, 2.0, 1.0) + rayleigh_pdf(2.5, 1.0, 1.0));
        assert!((v[2].2 - expect).abs() < 1e-15);
        assert!((v[2].1 - 2.0 / (4.0 * 1.0)).abs() < 1e-15);
    }
}
