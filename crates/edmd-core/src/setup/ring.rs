//! A patch of a planetary ring (see [`crate::state::ring`]): equal particles placed at random
//! in a square shearing-periodic patch at a given optical depth, on the Keplerian flow with a
//! Gaussian velocity dispersion, and (3D) a Gaussian layer about the mid-plane.

use rand::{Rng, SeedableRng};
use rand_distr::StandardNormal;
use rand_pcg::Pcg64Mcg;

use crate::error::Error;
use crate::math::Vector;
use crate::state::{Boundary, Disc, SimBox};

/// The smallest optical depth a patch is made at. Below it a patch of a few thousand
/// particles is a box thousands of diameters wide whose particles almost never meet (Saturn's
/// faintest rings, near 1e-5, are beyond what such a patch can show).
pub const MIN_OPTICAL_DEPTH: f64 = 1e-4;

/// A ring patch of `n` equal particles of mass 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingPatch {
    /// Number of particles (at least 2).
    pub n: usize,
    /// The dynamical optical depth, `n pi r^2 / (L_x L_y)` (in 2D the area fraction): in
    /// `[1e-4, 0.5]` in 2D, `[1e-4, 2]` in 3D ([`MIN_OPTICAL_DEPTH`]).
    pub tau: f64,
    /// Each particle's radius.
    pub radius: f64,
    /// The orbital frequency `Omega`.
    pub omega: f64,
    /// The velocity dispersion to start with (per axis, about the Keplerian flow).
    pub dispersion: f64,
    /// 3D: the height of the box, between walls, in particle diameters (at least 4; the
    /// layer starts at scale height `dispersion / Omega`).
    pub height: f64,
    /// Seed of the random positions and velocities.
    pub seed: u64,
}

impl RingPatch {
    /// The particles and their box: square in the plane (`L_x = L_y`), periodic along x and y,
    /// walls along z. Velocities are the Keplerian flow `-3/2 Omega (y - L_y / 2)` along x
    /// plus Gaussian deviations of the dispersion given, with the mean deviation taken out.
    pub fn build<const D: usize>(&self) -> Result<(Vec<Disc<D>>, SimBox<D>), Error> {
        let bad = |what: String| Err(Error::Invalid(format!("ring patch: {what}")));
        if !(D == 2 || D == 3) {
            return bad(format!("two or three dimensions, not {D}"));
        }
        if self.n < 2 {
            return bad(format!("at least 2 particles, found {}", self.n));
        }
        for (name, v) in [
            ("optical depth", self.tau),
            ("radius", self.radius),
            ("orbital frequency", self.omega),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return bad(format!(
                    "{name} must be a finite number above 0, found {v:?}"
                ));
            }
        }
        if !(self.dispersion.is_finite() && self.dispersion >= 0.0) {
            return bad(format!(
                "the dispersion must be a finite number >= 0, found {:?}",
                self.dispersion
            ));
        }
        if self.tau < MIN_OPTICAL_DEPTH {
            return bad(format!(
                "optical depth {:?} is below {MIN_OPTICAL_DEPTH:e}: the particles would almost never meet",
                self.tau
            ));
        }
        let most = if D == 2 { 0.5 } else { 2.0 };
        if self.tau > most {
            return bad(format!(
                "optical depth {} is above {most}, as dense as random placement goes in {D}D",
                self.tau
            ));
        }
        let d = 2.0 * self.radius;
        if D == 3 && !(self.height.is_finite() && self.height >= 4.0) {
            return bad(format!(
                "the box's height must be at least 4 diameters, found {:?}",
                self.height
            ));
        }
        let n = self.n;
        let side = (n as f64 * std::f64::consts::PI * self.radius * self.radius / self.tau).sqrt();
        let mut lengths = [side; D];
        let mut boundaries = [Boundary::Periodic; D];
        if D == 3 {
            lengths[2] = self.height * d;
            boundaries[2] = Boundary::Walls;
            // The layer (scale height `dispersion / Omega`, at least a diameter) must fit.
            let fill = n as f64 * 4.0 / 3.0 * std::f64::consts::PI * self.radius.powi(3)
                / (side * side * lengths[2]);
            if fill > 0.3 {
                return bad(format!(
                    "the box is too low for this optical depth: the particles would fill {:.0}% of it",
                    100.0 * fill
                ));
            }
        }
        if side < 3.0 * CELLS_ACROSS * d {
            return bad(format!(
                "a patch of {n} particles at optical depth {} is {side:.3} across, less than the {} diameters the shearing boundaries need: use more particles",
                self.tau,
                3.0 * CELLS_ACROSS
            ));
        }
        let sim_box = SimBox {
            lengths,
            boundaries,
        };
        let mut rng = Pcg64Mcg::seed_from_u64(self.seed);
        let h = (self.dispersion / self.omega).max(d);
        let mut placed: Vec<Vector<D>> = Vec::with_capacity(n);
        // A hash of cells at least one diameter wide, for the overlap test: no more of them
        // than about four per particle, so that a dilute patch (a tiny optical depth) does not
        // ask for a grid of its width squared.
        let most = 2 * (n as f64).sqrt().ceil() as usize + 1;
        let cells = ((side / d).floor().max(1.0) as usize).min(most);
        let mut grid: Vec<Vec<u32>> = vec![Vec::new(); cells * cells];
        let cell = |p: Vector<D>| -> (usize, usize) {
            let f = |x: f64| ((x / side * cells as f64) as usize).min(cells - 1);
            (f(p[0]), f(p[1]))
        };
        let mut tries = 0u64;
        while placed.len() < n {
            tries += 1;
            if tries > 1000 * n as u64 + 100_000 {
                return bad(format!(
                    "could not place {n} particles at optical depth {} without overlaps",
                    self.tau
                ));
            }
            let mut p = Vector::<D>::ZERO;
            p[0] = side * rng.random::<f64>();
            p[1] = side * rng.random::<f64>();
            if D == 3 {
                let z: f64 = rng.sample(StandardNormal);
                let half = 0.5 * lengths[2] - self.radius;
                if (z * h).abs() >= half - self.radius {
                    continue;
                }
                p[2] = 0.5 * lengths[2] + z * h;
            }
            let (cx, cy) = cell(p);
            let mut free = true;
            'near: for dx in [cells - 1, 0, 1] {
                for dy in [cells - 1, 0, 1] {
                    for &j in &grid[((cx + dx) % cells) * cells + (cy + dy) % cells] {
                        let dr = sim_box.minimum_image(placed[j as usize] - p);
                        if dr.norm2() < d * d * (1.0 + 1e-9) {
                            free = false;
                            break 'near;
                        }
                    }
                }
            }
            if free {
                grid[cx * cells + cy].push(placed.len() as u32);
                placed.push(p);
            }
        }
        let mut vel: Vec<Vector<D>> = (0..n)
            .map(|_| {
                Vector(std::array::from_fn(|_| {
                    self.dispersion * rng.sample::<f64, _>(StandardNormal)
                }))
            })
            .collect();
        let mean = vel.iter().fold(Vector::<D>::ZERO, |s, &v| s + v) * (1.0 / n as f64);
        for v in &mut vel {
            *v -= mean;
        }
        let discs = placed
            .into_iter()
            .zip(vel)
            .map(|(p, mut v)| {
                v[0] += -1.5 * self.omega * (p[1] - 0.5 * side);
                Disc::new(p, v, self.radius)
            })
            .collect();
        Ok((discs, sim_box))
    }
}

/// The fewest cells across the patch the shearing boundaries take per third of it (rows of
/// cells next to the boundary, and one between).
const CELLS_ACROSS: f64 = 1.2;
