//! The Andersen thermostat: each disc's velocity redrawn from the Maxwell-Boltzmann
//! distribution at temperature `kT`, at the times of a Poisson process of rate `rate` per disc.
//!
//! Each disc's next redraw is one of its own events, like a wall or its cell exit, found by its
//! prediction. The random numbers of the `k`-th redraw of disc `i` come from a generator seeded
//! with `(seed, i, k)` alone, so a run gives the same redraws however it is sliced, and a
//! checkpoint holds only each disc's next time and count: a continued run is the run never
//! stopped, bit for bit.

use rand::SeedableRng;
use rand_distr::{Distribution, Exp, StandardNormal};

use crate::events::{EventKind, EventRecord, Pending};
use crate::math::Vector;

use super::Simulation;

/// The thermostat's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Andersen {
    /// Temperature of the bath, in energy units.
    pub kt: f64,
    /// Redraws per disc per unit time.
    pub rate: f64,
    /// Seed of the redraws.
    pub seed: u64,
}

/// The thermostat with each disc's next redraw time and count of redraws so far.
#[derive(Clone, Debug)]
pub(super) struct Bath {
    pub(super) settings: Andersen,
    pub(super) next: Vec<f64>,
    pub(super) count: Vec<u32>,
}

/// The generator of the `k`-th redraw of disc `i` (`k = 0`: the first time only).
fn stream(seed: u64, i: usize, k: u32) -> rand_pcg::Pcg64Mcg {
    // SplitMix64 of the three, so that neighbouring discs and counts get unrelated streams.
    let mut z = seed
        ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (u64::from(k)).wrapping_mul(0xD1B5_4A32_D192_ED03);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    rand_pcg::Pcg64Mcg::seed_from_u64(z)
}

impl Andersen {
    /// Checks the settings: a positive temperature no larger than a step's energy may be
    /// ([`crate::MAX_STEP_ENERGY`]: the speeds drawn at a larger one overflow into infinite
    /// energies), and a finite positive rate.
    pub fn validate(&self) -> Result<(), crate::Error> {
        if !(self.kt.is_finite() && self.kt > 0.0 && self.kt <= crate::MAX_STEP_ENERGY) {
            return Err(crate::Error::Invalid(format!(
                "thermostat: kT must be above 0 and at most {:e}, found {:?}",
                crate::MAX_STEP_ENERGY,
                self.kt
            )));
        }
        if !(self.rate.is_finite() && self.rate > 0.0) {
            return Err(crate::Error::Invalid(format!(
                "thermostat: the rate must be a finite number > 0, found {}",
                self.rate
            )));
        }
        Ok(())
    }

    fn interval(&self, rng: &mut rand_pcg::Pcg64Mcg) -> f64 {
        Exp::new(self.rate).expect("a positive rate").sample(rng)
    }
}

impl<const D: usize> Simulation<D> {
    /// Puts the discs in contact with an Andersen heat bath from now on (`None`: none, the
    /// default, which conserves energy). Each disc's first redraw is drawn afresh.
    pub fn set_thermostat(&mut self, thermostat: Option<Andersen>) -> Result<(), crate::Error> {
        match thermostat {
            None => self.bath = None,
            Some(a) => {
                a.validate()?;
                let now = self.now;
                let n = self.body.len();
                let next = (0..n)
                    .map(|i| now + a.interval(&mut stream(a.seed, i, 0)))
                    .collect();
                self.bath = Some(Box::new(Bath {
                    settings: a,
                    next,
                    count: vec![0; n],
                }));
            }
        }
        // Every disc predicted again from now, with its first redraw among its events.
        self.replace_velocities(|_, v| v);
        Ok(())
    }

    /// The thermostat, if the discs are in contact with one.
    pub fn thermostat(&self) -> Option<Andersen> {
        self.bath.as_ref().map(|b| b.settings)
    }

    /// Disc `i`'s next redraw as an own event, if it beats `(best_t, best)`.
    #[inline(always)]
    pub(super) fn bath_event(&self, i: usize, best_t: f64, best: Pending) -> (f64, Pending) {
        match &self.bath {
            Some(b) if b.next[i] < best_t => (b.next[i], Pending::Thermostat),
            _ => (best_t, best),
        }
    }

    /// Redraws disc `i`'s velocity at `t` and draws its next redraw time.
    #[inline(never)]
    pub(super) fn redraw(&mut self, i: usize, t: f64) -> EventRecord<D> {
        let bath = self.bath.as_mut().expect("a redraw with a thermostat");
        let a = bath.settings;
        bath.count[i] = bath.count[i].wrapping_add(1);
        let mut rng = stream(a.seed, i, bath.count[i]);
        let m = self.mass[i];
        let sd = (a.kt / m).sqrt();
        let mut v = Vector::<D>(std::array::from_fn(|_| {
            let z: f64 = StandardNormal.sample(&mut rng);
            z * sd
        }));
        bath.next[i] = t + a.interval(&mut rng);
        let b = &mut self.body[i];
        b.advance_to(t);
        // Under shear the velocity is drawn about the streaming profile at the disc's height.
        if let Some(s) = self.shear.as_deref() {
            v[0] += s.stream(b.pos[1]);
        }
        let impulse = (v - b.vel) * m;
        b.vel = v;
        b.count = b.count.wrapping_add(1);
        self.stats.thermostat = self.stats.thermostat.wrapping_add(1);
        EventRecord {
            time: t,
            kind: EventKind::Thermostat { i },
            impulse,
        }
    }
}
