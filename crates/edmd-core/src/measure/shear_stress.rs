//! The shear stress of a sheared system (Lees-Edwards boundaries, [`crate::Shear`]) and its
//! viscosity `eta = -P_xy / gamma`: the non-equilibrium route to the shear viscosity, beside
//! the Einstein-Helfand route at equilibrium ([`super::viscosity`]).
//!
//! **The pressure tensor** (Irving and Kirkwood; for hard spheres, Alder, Gass and Wainwright,
//! J. Chem. Phys. 53, 3813 (1970); Allen and Tildesley, *Computer Simulation of Liquids*, 2nd
//! ed. (2017), sections 2.4 and 11.3): `P_xy V = <sum_i m c_x c_y> + (1/t) sum_collisions
//! r_ij,x J_ij,y`, where `c = v - u(y)` is a disc's velocity relative to the streaming profile
//! `u_x = gamma (y - L_y / 2)`, `r_ij = r_i - r_j` the contact separation at the nearest
//! (slid) image and `J_ij` the impulse `i` receives. The collisional sum is symmetrised
//! (`(r_x J_y + r_y J_x) / 2`), as the tensor is.
//!
//! **Exact time averages.** Between its events a disc's `v` is constant and its `y` grows
//! linearly, so `c_x = v_x - gamma (y - L_y / 2)` falls linearly: each flight's integrals of
//! `m c_x c_y` and `m |c|^2` are worked out in closed form when the flight ends (any event of
//! the disc, crossings of the boundary included, at which `c` carries on unchanged) or a block
//! closes. Nothing is sampled.
//!
//! **Errors.** Each call of [`ShearStress::sample`] closes a block; values are totals over the
//! whole measuring time, errors the standard deviation of the block values over
//! `sqrt(blocks)` ([`super::block_error`]). Blocks should be longer than the stress's
//! correlation time (tens of collisions per disc).

use super::stats::Estimate;
use crate::events::{EventKind, EventRecord};
use crate::math::Vector;
use crate::observer::Observer;
use crate::simulation::Simulation;

/// The shear stress and the peculiar kinetic energy, integrated exactly over time. Attach it as
/// an observer and call [`sample`](ShearStress::sample) at the end of each block.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ShearStress {
    rate: f64,
    volume: f64,
    dim: usize,
    mass: Vec<f64>,
    /// Per disc: its clock, and its velocity relative to the profile then (as `[x, y, z]`,
    /// `z` 0 in 2D).
    since: Vec<f64>,
    velocity: Vec<[f64; 3]>,
    block_start: f64,
    /// This block's integrals of `sum m c_x c_y` and `sum m |c|^2`, and its collisional sum.
    block_kinetic: f64,
    block_twice_ke: f64,
    block_collisional: f64,
    blocks: Vec<ShearStressBlock>,
}

/// One block of a shear-stress measurement.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ShearStressBlock {
    /// Start time.
    pub start: f64,
    /// End time.
    pub end: f64,
    /// `P_xy`, kinetic part.
    pub kinetic: f64,
    /// `P_xy`, collisional part.
    pub collisional: f64,
    /// `kT` of the velocities relative to the profile, time-averaged.
    pub kt: f64,
    /// `-P_xy / gamma`.
    pub eta: f64,
}

/// Result of a shear-stress measurement.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ShearStressSummary {
    /// The shear rate.
    pub rate: f64,
    /// Measuring time.
    pub elapsed: f64,
    /// `kT` relative to the streaming profile, time-averaged.
    pub kt: Estimate,
    /// The shear stress `P_xy` (negative for `gamma > 0`).
    pub pxy: Estimate,
    /// Its kinetic part.
    pub kinetic: f64,
    /// Its collisional part.
    pub collisional: f64,
    /// The viscosity `-P_xy / gamma`.
    pub eta: Estimate,
    /// The reduced shear rate `gamma sigma sqrt(m / kT)` (mean diameter and mass): well below
    /// 1, the viscosity is the Newtonian one.
    pub reduced_rate: f64,
}

impl ShearStress {
    /// Starts measuring at the simulation's current time. `None` without shear, or at rate 0
    /// (there is no viscosity to divide out).
    pub fn new<const D: usize>(sim: &Simulation<D>) -> Option<Self> {
        let shear = sim.shear()?;
        if shear.rate == 0.0 {
            return None;
        }
        let n = sim.len();
        let t = sim.time();
        Some(ShearStress {
            rate: shear.rate,
            volume: sim.sim_box().volume(),
            dim: D,
            mass: (0..n).map(|i| sim.mass(i)).collect(),
            since: vec![t; n],
            velocity: (0..n).map(|i| widen(sim.peculiar_velocity(i))).collect(),
            block_start: t,
            block_kinetic: 0.0,
            block_twice_ke: 0.0,
            block_collisional: 0.0,
            blocks: Vec::new(),
        })
    }

    /// Whether this measurement (read back from a checkpoint, say) can go on observing `sim`:
    /// the same dimension, discs, box and shear rate.
    pub fn fits<const D: usize>(&self, sim: &Simulation<D>) -> bool {
        let n = sim.len();
        self.dim == D
            && self.mass.len() == n
            && self.since.len() == n
            && self.velocity.len() == n
            && self.volume == sim.sim_box().volume()
            && sim.shear().is_some_and(|s| s.rate == self.rate)
    }

    /// Adds disc `i`'s flight from its clock to `t` and starts its next from `sim`'s state.
    fn flush<const D: usize>(&mut self, i: usize, t: f64, sim: &Simulation<D>) {
        let dt = t - self.since[i];
        // c_x(s) = a - b s over the flight (the profile's velocity grows as the disc rises),
        // c_y = vy.
        let [a, vy, vz] = self.velocity[i];
        let b = self.rate * vy;
        let m = self.mass[i];
        self.block_kinetic += m * vy * (a * dt - 0.5 * b * dt * dt);
        self.block_twice_ke += m
            * ((a * a * dt - a * b * dt * dt + b * b * dt * dt * dt / 3.0)
                + (vy * vy + vz * vz) * dt);
        self.since[i] = t;
        self.velocity[i] = widen(sim.peculiar_velocity(i));
    }

    /// Closes the current block at the simulation's current time.
    pub fn sample<const D: usize>(&mut self, sim: &Simulation<D>) {
        let t = sim.time();
        for i in 0..self.mass.len() {
            self.flush(i, t, sim);
        }
        let span = t - self.block_start;
        if span > 0.0 {
            let kinetic = self.block_kinetic / (self.volume * span);
            let collisional = self.block_collisional / (self.volume * span);
            let n = self.mass.len().max(1) as f64;
            self.blocks.push(ShearStressBlock {
                start: self.block_start,
                end: t,
                kinetic,
                collisional,
                kt: self.block_twice_ke / (self.dim as f64 * n * span),
                eta: -(kinetic + collisional) / self.rate,
            });
        }
        self.block_start = t;
        self.block_kinetic = 0.0;
        self.block_twice_ke = 0.0;
        self.block_collisional = 0.0;
    }

    /// The blocks so far.
    pub fn blocks(&self) -> &[ShearStressBlock] {
        &self.blocks
    }

    /// Totals over the blocks, with block errors; `None` before the first block closes.
    /// `sigma` and `mass` are the mean diameter and mass, for the reduced rate.
    pub fn summary(&self, sigma: f64, mass: f64) -> Option<ShearStressSummary> {
        let b = &self.blocks;
        if b.is_empty() {
            return None;
        }
        let elapsed: f64 = b.iter().map(|k| k.end - k.start).sum();
        let mean = |f: &dyn Fn(&ShearStressBlock) -> f64| {
            b.iter().map(|k| f(k) * (k.end - k.start)).sum::<f64>() / elapsed
        };
        let kinetic = mean(&|k| k.kinetic);
        let collisional = mean(&|k| k.collisional);
        let kt = mean(&|k| k.kt);
        let pxy = kinetic + collisional;
        let pick = |f: &dyn Fn(&ShearStressBlock) -> f64| b.iter().map(f).collect::<Vec<f64>>();
        Some(ShearStressSummary {
            rate: self.rate,
            elapsed,
            kt: Estimate::new(kt, &pick(&|k| k.kt)),
            pxy: Estimate::new(pxy, &pick(&|k| k.kinetic + k.collisional)),
            kinetic,
            collisional,
            eta: Estimate::new(-pxy / self.rate, &pick(&|k| k.eta)),
            reduced_rate: self.rate.abs() * sigma * (mass / kt).sqrt(),
        })
    }
}

fn widen<const D: usize>(v: Vector<D>) -> [f64; 3] {
    std::array::from_fn(|a| if a < D { v[a] } else { 0.0 })
}

impl<const D: usize> Observer<D> for ShearStress {
    fn on_event(&mut self, e: &EventRecord<D>, sim: &Simulation<D>) {
        match e.kind {
            EventKind::DiscDisc { i, j } | EventKind::Reaction { i, j, .. } => {
                self.flush(i, e.time, sim);
                self.flush(j, e.time, sim);
                // At contact, `r_i - r_j` at the nearest (slid) image.
                let r = -sim.separation(i, j).0;
                let jv = e.impulse;
                self.block_collisional += 0.5 * (r[0] * jv[1] + r[1] * jv[0]);
            }
            EventKind::Step { i, j, .. } => {
                self.flush(i, e.time, sim);
                self.flush(j, e.time, sim);
            }
            EventKind::Wall { i, .. }
            | EventKind::Barrier { i, .. }
            | EventKind::Thermostat { i }
            | EventKind::CellCrossing { i, .. } => self.flush(i, e.time, sim),
            // No velocity or position changes: the flight goes on.
            EventKind::NeighbourList { .. } | EventKind::Slide { .. } => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::observer::obs;
    use crate::state::{Disc, SimBox};
    use crate::{Options, Shear};

    #[test]
    fn a_lone_disc_gives_the_exact_integrals_across_the_boundary() {
        // One disc, rate 0.2 in a 10 x 10 box (slide speed 2), from y = 5 at (0.3, 1.0), on
        // the profile there plus c = (0.3, 1.0). Flying straight through the images, its
        // velocity relative to the profile falls as c_x = 0.3 - 0.2 t (c_y = 1), through its
        // crossings of the boundary alike: the blocks' integrals of m c_x c_y and m |c|^2 are
        // those of that line.
        let d = Disc::new(Vector::new([2.0, 5.0]), Vector::new([0.3, 1.0]), 0.5);
        let mut sim =
            Simulation::new(&[d], SimBox::periodic([10.0, 10.0]), Options::default()).unwrap();
        sim.set_shear(Some(Shear::new(0.2))).unwrap();
        let mut m = ShearStress::new(&sim).unwrap();
        for t in [7.0, 18.5, 40.0] {
            sim.run_until(t, &mut obs(&mut m));
            m.sample(&sim);
        }
        let kinetic = |t: f64| 0.3 * t - 0.1 * t * t;
        let twice_ke = |t: f64| t - (0.3f64 - 0.2 * t).powi(3) / 0.6;
        assert_eq!(m.blocks().len(), 3);
        for b in m.blocks() {
            let span = b.end - b.start;
            let want = (kinetic(b.end) - kinetic(b.start)) / (100.0 * span);
            assert!((b.kinetic - want).abs() < 1e-14, "{b:?} for {want}");
            let kt = (twice_ke(b.end) - twice_ke(b.start)) / (2.0 * span);
            assert!((b.kt - kt).abs() < 1e-12 * kt, "{b:?} for {kt}");
            assert_eq!(b.collisional, 0.0);
        }
    }

    #[test]
    fn without_shear_there_is_nothing_to_measure() {
        let d = Disc::new(Vector::new([2.0, 5.0]), Vector::new([0.3, 1.0]), 0.5);
        let mut sim =
            Simulation::new(&[d], SimBox::periodic([10.0, 10.0]), Options::default()).unwrap();
        assert!(ShearStress::new(&sim).is_none());
        sim.set_shear(Some(Shear::new(0.0))).unwrap();
        assert!(ShearStress::new(&sim).is_none());
    }
}
