//! Self-gravitating sheets on a line (see [`crate::state::self_gravity`]): the water-bag start
//! the literature relaxes (positions and velocities uniform in a rectangle of phase space), in
//! a walled box its energy keeps them from reaching.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

use crate::error::Error;
use crate::math::Vector;
use crate::state::{Disc, SimBox};

/// A water bag of `n` equal sheets of mass 1: positions uniform in `[-width, width]`,
/// velocities uniform in `[-speed, speed]`, then the centre of mass put at the middle of the
/// box and at rest. The sheets are rods of length `2 radius` (which only shifts them; see
/// [`crate::state::self_gravity`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaterBag {
    /// Number of sheets (at least 2).
    pub n: usize,
    /// Half the width of the bag.
    pub width: f64,
    /// Half the range of velocities.
    pub speed: f64,
    /// Each rod's half-length (small against `width / n`).
    pub radius: f64,
    /// The self-gravity's coupling (`2 pi G`).
    pub coupling: f64,
    /// Seed of the random positions and velocities.
    pub seed: u64,
}

impl WaterBag {
    /// The sheets and a walled box around them: the energy `E` bounds the system's extent,
    /// since `U >= coupling (n - 1) (x_max - x_min)` for unit masses, so no sheet gets farther
    /// than `E / (coupling (n - 1))` (plus the rods' lengths) from the centre of mass, which
    /// stays at rest at the middle of the box. The walls are that far, or 16 bag widths if
    /// nearer.
    pub fn build(&self) -> Result<(Vec<Disc<1>>, SimBox<1>), Error> {
        let bad = |what: String| Err(Error::Invalid(format!("water bag: {what}")));
        if self.n < 2 {
            return bad(format!("at least 2 sheets, found {}", self.n));
        }
        for (name, v) in [
            ("width", self.width),
            ("speed", self.speed),
            ("radius", self.radius),
            ("coupling", self.coupling),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return bad(format!(
                    "{name} must be a finite number above 0, found {v:?}"
                ));
            }
        }
        let n = self.n;
        let mut rng = Pcg64Mcg::seed_from_u64(self.seed);
        let mut y: Vec<f64> = (0..n)
            .map(|_| self.width * (2.0 * rng.random::<f64>() - 1.0))
            .collect();
        let mut v: Vec<f64> = (0..n)
            .map(|_| self.speed * (2.0 * rng.random::<f64>() - 1.0))
            .collect();
        y.sort_by(f64::total_cmp);
        let (my, mv) = (mean(&y), mean(&v));
        for k in 0..n {
            y[k] -= my;
            v[k] -= mv;
        }
        // Energy of the sheets (rods' lengths taken out): kinetic plus sum over pairs of
        // coupling |y_i - y_j|, which in order is coupling sum_r y_r (2 r - (n - 1)).
        let kinetic: f64 = v.iter().map(|v| 0.5 * v * v).sum();
        let potential: f64 = y
            .iter()
            .enumerate()
            .map(|(r, &y)| self.coupling * y * (2.0 * r as f64 - (n as f64 - 1.0)))
            .sum();
        let reach = (kinetic + potential) / (self.coupling * (n as f64 - 1.0));
        let rods = 2.0 * self.radius * n as f64;
        // The energy's bound, or 16 bag widths if nearer: the bound grows with `n` (all the
        // energy could go into one sheet), and coordinates of order `n` would cost their
        // digits (at 10^5 sheets the energy drifted by 1e-9 in 1.7 10^7 crossings, against 2e-13
        // with the box at 16 widths). No sheet of a bag comes near 16 widths but the walls
        // reflect one exactly if it does, and the runs count such hits.
        let half = reach.min(16.0 * self.width) + rods;
        let length = 2.0 * half * 1.25 + 4.0 * self.radius;
        if !(length.is_finite() && length > 0.0) {
            return bad(format!("no box holds these sheets (length {length:?})"));
        }
        let middle = 0.5 * length;
        // Rod positions: each sheet shifted right by the rods to its left, the whole centred.
        let shift = self.radius * (n as f64 - 1.0);
        let discs = (0..n)
            .map(|r| {
                let x = middle + y[r] + 2.0 * self.radius * r as f64 - shift;
                Disc::new(Vector::new([x]), Vector::new([v[r]]), self.radius)
            })
            .collect();
        Ok((discs, SimBox::walls([length])))
    }
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}
