//! Pressure from the wall impulses and from the collision virial, and the compressibility factor.
//!
//! In 2D the pressure is a force per unit length; "area" is the box area `A`.
//!
//! **Wall pressure.** The momentum the walls receive, per unit wall length and unit time:
//! `P_wall = sum |J_n| / (L_walls t)`, with `J_n` the normal impulse of each wall collision and
//! `L_walls` the total length of the walls (the box perimeter when every axis has walls).
//!
//! **Collision virial.** The virial theorem for impulsive forces (B. J. Alder and
//! T. E. Wainwright, J. Chem. Phys. 33, 1439 (1960); Allen and Tildesley, *Computer Simulation of
//! Liquids*, 2nd ed. (2017), chapter 2) gives, in `D` dimensions,
//! `P A = N kT + (1/(D t)) sum_collisions r_ij . J_ij`, where `r_ij = r_i - r_j` is the
//! contact separation (minimum image) and `J_ij` the impulse received by `i`; in 2D the factor
//! is `1/(2t)`. With periodic boundaries this is the pressure.
//!
//! **Walls shrink the area.** A disc's centre cannot come closer than its radius `R` to a
//! wall. Time-averaging `d/dt sum m r.v = 0` with the wall forces included gives, for a wall
//! pair on axis `a` carrying the force `F_a` each, the term `(L_a - 2R) F_a` instead of
//! `L_a F_a`. With `F_a = P_wall A / L_a` the identity becomes `P_wall A_eff = N kT + (1/(D t))
//! sum r_ij . J_ij` with `A_eff = A (1 - (2R/D) sum_{walled a} 1/L_a)`, in 2D with walls on
//! both axes `A - R (L_x + L_y)`. So the virial form with `A_eff` equals the wall pressure at
//! equilibrium; with the bare `A` it would be low by the relative amount `R (L_x + L_y) / A`
//! (5 % for `R = 1/2` in a 20 x 20 box). `R` is the mean radius, which is exact for equal discs.
//!
//! **Compressibility factor** `Z = P A_eff / (N kT)`; from the virial,
//! `Z = 1 + sum r_ij . J_ij / (D t N kT)`, which does not depend on the area at all.
//!
//! **Errors.** Each call of [`Pressure::sample`] closes a block (from the previous call, or from
//! the start). Values are time-weighted means over the blocks, i.e. totals over the whole
//! measuring time; errors are the standard deviation of the block values over `sqrt(blocks)`
//! (see [`block_error`](super::block_error)). Use blocks of equal length, each longer than the
//! correlation time (a few collisions per disc is plenty for the pressure).
//!
//! **Limits.** Internal barriers are ignored: their forces are neither wall pressure nor pair
//! virial, so with barriers only the wall pressure (averaged over all box walls) means anything.
//! Collisions are taken to be binary: with multi-disc collisions
//! ([`Options::multi`](crate::Options)) the event carries only one disc's impulse and the virial
//! is wrong.

use super::stats::Estimate;
use crate::events::{EventKind, EventRecord};
use crate::observer::Observer;
use crate::simulation::Simulation;

/// Wall and virial pressure, accumulated per block. Attach it as an observer and call
/// [`sample`](Pressure::sample) at the end of each block.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Pressure {
    n: usize,
    area: f64,
    effective_area: f64,
    /// Total wall length (0 without walls).
    wall_length: f64,
    block_start: f64,
    block_wall: f64,
    block_virial: f64,
    blocks: Vec<PressureBlock>,
}

/// One block of a pressure measurement.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PressureBlock {
    /// Start time.
    pub start: f64,
    /// End time.
    pub end: f64,
    /// `N kT` (2 KE / D) at the end of the block.
    pub nkt: f64,
    /// Sum of `|J_n|` over the wall collisions in the block.
    pub wall_impulse: f64,
    /// Sum of `r_ij . J_ij` over the pair collisions in the block.
    pub pair_virial: f64,
    /// Virial pressure of the block.
    pub virial: f64,
    /// Wall pressure of the block (`None` without walls).
    pub wall: Option<f64>,
    /// Compressibility factor of the block from the virial.
    pub z: f64,
}

/// Result of a pressure measurement. See the module documentation for the formulas.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PressureSummary {
    /// Measuring time (sum of the block lengths).
    pub elapsed: f64,
    /// `kT`, time-averaged.
    pub kt: f64,
    /// Box area `A`.
    pub area: f64,
    /// Area available to the discs' centres for the virial, `A_eff` (`A` if fully periodic).
    pub effective_area: f64,
    /// Virial pressure `(N kT + sum r.J / (D t)) / A_eff`.
    pub virial: Estimate,
    /// Wall pressure `sum |J_n| / (L_walls t)` (`None` without walls).
    pub wall: Option<Estimate>,
    /// Compressibility factor from the virial, `1 + sum r.J / (D t N kT)`.
    pub z: Estimate,
    /// Compressibility factor from the walls, `P_wall A_eff / (N kT)` (`None` without walls).
    pub z_wall: Option<Estimate>,
}

impl Pressure {
    /// Starts measuring at the simulation's current time.
    pub fn new<const D: usize>(sim: &Simulation<D>) -> Self {
        let bx = sim.sim_box();
        let area = bx.volume();
        let n = sim.len();
        let mean_radius = (0..n).map(|i| sim.radius(i)).sum::<f64>() / n.max(1) as f64;
        let walled = (0..D).filter(|&a| !bx.is_periodic(a));
        let inverse_lengths: f64 = walled.clone().map(|a| 1.0 / bx.lengths[a]).sum();
        Pressure {
            n,
            area,
            effective_area: area * (1.0 - 2.0 * mean_radius / D as f64 * inverse_lengths),
            // The walls perpendicular to axis a have "length" (area in 3D) A / L_a.
            wall_length: walled.map(|a| 2.0 * area / bx.lengths[a]).sum(),
            block_start: sim.time(),
            block_wall: 0.0,
            block_virial: 0.0,
            blocks: Vec::new(),
        }
    }

    /// Closes the current block at the simulation's current time and starts the next one.
    /// Does nothing if no time has passed since the last call.
    pub fn sample<const D: usize>(&mut self, sim: &Simulation<D>) {
        let (start, end) = (self.block_start, sim.time());
        let dt = end - start;
        if dt <= 0.0 {
            return;
        }
        let nkt = 2.0 * sim.kinetic_energy() / D as f64;
        let collisional = self.block_virial / (D as f64 * dt);
        let wall = (self.wall_length > 0.0).then(|| self.block_wall / (self.wall_length * dt));
        self.blocks.push(PressureBlock {
            start,
            end,
            nkt,
            wall_impulse: self.block_wall,
            pair_virial: self.block_virial,
            virial: (nkt + collisional) / self.effective_area,
            wall,
            z: 1.0 + collisional / nkt,
        });
        self.block_start = end;
        self.block_wall = 0.0;
        self.block_virial = 0.0;
    }

    /// The closed blocks.
    pub fn blocks(&self) -> &[PressureBlock] {
        &self.blocks
    }

    /// `(block end, virial pressure of the block)`.
    pub fn virial_series(&self) -> Vec<(f64, f64)> {
        self.blocks.iter().map(|b| (b.end, b.virial)).collect()
    }

    /// `(block end, wall pressure of the block)`; empty without walls.
    pub fn wall_series(&self) -> Vec<(f64, f64)> {
        self.blocks
            .iter()
            .filter_map(|b| b.wall.map(|w| (b.end, w)))
            .collect()
    }

    /// `(block end, compressibility factor of the block)`.
    pub fn z_series(&self) -> Vec<(f64, f64)> {
        self.blocks.iter().map(|b| (b.end, b.z)).collect()
    }

    /// Values over all closed blocks with their block errors (`NaN` values if there are none).
    pub fn summary(&self) -> PressureSummary {
        let elapsed: f64 = self.blocks.iter().map(|b| b.end - b.start).sum();
        let mean = |f: &dyn Fn(&PressureBlock) -> f64| -> Estimate {
            let values: Vec<f64> = self.blocks.iter().map(f).collect();
            let weighted: f64 = self.blocks.iter().map(|b| f(b) * (b.end - b.start)).sum();
            Estimate::new(weighted / elapsed, &values)
        };
        let nkt = mean(&|b| b.nkt).value;
        let a_eff = self.effective_area;
        let has_walls = self.wall_length > 0.0;
        PressureSummary {
            elapsed,
            kt: nkt / self.n as f64,
            area: self.area,
            effective_area: a_eff,
            virial: mean(&|b| b.virial),
            wall: has_walls.then(|| mean(&|b| b.wall.unwrap_or(f64::NAN))),
            z: mean(&|b| b.z),
            z_wall: has_walls.then(|| mean(&|b| b.wall.unwrap_or(f64::NAN) * a_eff / b.nkt)),
        }
    }
}

impl<const D: usize> Observer<D> for Pressure {
    #[inline]
    fn on_event(&mut self, e: &EventRecord<D>, sim: &Simulation<D>) {
        match e.kind {
            // Every impulse between a pair counts in the virial: hard-core collisions and the
            // crossings of and bounces at a stepped potential's steps.
            EventKind::DiscDisc { i, j }
            | EventKind::Reaction { i, j, .. }
            | EventKind::Step { i, j, .. } => {
                // Under shear a pair across y meets at its slid image.
                let r_ij = if sim.shear().is_some() {
                    -sim.separation(i, j).0
                } else {
                    sim.sim_box()
                        .minimum_image(sim.position(i) - sim.position(j))
                };
                self.block_virial += r_ij.dot(e.impulse);
            }
            EventKind::Wall { wall, .. } => self.block_wall += e.impulse[wall.axis].abs(),
            // A redraw by the thermostat exchanges momentum with the bath, not with a pair or a
            // wall: no pressure.
            EventKind::Barrier { .. }
            | EventKind::Thermostat { .. }
            | EventKind::NeighbourList { .. }
            | EventKind::Slide { .. }
            | EventKind::CellCrossing { .. } => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::observer::obs;
    use crate::{Disc, Options, SimBox, Vector};

    #[test]
    fn one_disc_between_two_walls() {
        // Box 10 x 4, R = 1, mass 2, speed 3 along x: the centre runs over L - 2R = 8 and back,
        // hitting a wall every 8/3 with impulse 2 m v = 12. Over t = 16 (6 hits; the disc
        // starts at x = 1 + 8 * 0.5 so it hits at 4/3, 4, 20/3, ..., 44/3): wall length
        // 2 (10 + 4) = 28, P_wall = 6 * 12 / (28 * 16). Only the x walls are hit.
        let mut d = Disc::new(Vector::new([5.0, 2.0]), Vector::new([3.0, 0.0]), 1.0);
        d.mass = 2.0;
        let mut sim =
            Simulation::new(&[d], SimBox::walls([10.0, 4.0]), Options::default()).unwrap();
        let mut p = Pressure::new(&sim);
        sim.run_until(16.0, &mut obs(&mut p));
        p.sample(&sim);
        let s = p.summary();
        assert_eq!(sim.stats().wall, 6);
        assert!((s.wall.unwrap().value - 72.0 / (28.0 * 16.0)).abs() < 1e-15);
        // No pairs: the virial pressure is N kT / A_eff, kT = m v^2 / 2 = 9,
        // A_eff = 40 - 1 * (10 + 4) = 26, and Z = 1.
        assert_eq!(s.kt, 9.0);
        assert_eq!(s.effective_area, 26.0);
        assert!((s.virial.value - 9.0 / 26.0).abs() < 1e-15);
        assert_eq!(s.z.value, 1.0);
        assert!(s.z.error.is_nan());
    }

    #[test]
    fn ideal_disc_in_a_square_box_has_wall_pressure_equal_to_virial_pressure() {
        // A disc moving at (3, 1) in a 10 x 10 box with R = 1: over whole periods of both
        // motions (x: 16/3, y: 16; lcm 16) the wall pressure is (2 m |v_x| * 6 + 2 m |v_y| * 2)
        // / (40 * 16) = (36 + 4) / 640 = 1/16, and N kT / A_eff = 5 / (100 - 20) = 1/16: the
        // effective area is what makes the two agree.
        let d = Disc::new(Vector::new([5.0, 5.0]), Vector::new([3.0, 1.0]), 1.0);
        let mut sim =
            Simulation::new(&[d], SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
        let mut p = Pressure::new(&sim);
        for k in 1..=4 {
            sim.run_until(4.0 * k as f64, &mut obs(&mut p));
            p.sample(&sim);
        }
        let s = p.summary();
        assert_eq!(s.wall.unwrap().blocks, 4);
        assert!((s.wall.unwrap().value - 1.0 / 16.0).abs() < 1e-15);
        assert!((s.virial.value - 1.0 / 16.0).abs() < 1e-15);
        assert!((s.z_wall.unwrap().value - 1.0).abs() < 1e-14);
        assert_eq!(p.wall_series().len(), 4);
    }

    #[test]
    fn head_on_pair_virial_in_a_periodic_box() {
        // Two discs of radius 1 meet head-on at speed 1 each (t = 1): the impulse on the left
        // disc is (-2, 0), r_ij = (-2, 0), r.J = 4. Over t = 2 in a periodic 10 x 10 box:
        // N kT = 1, P A = 1 + 4 / (2 * 2) = 2, so P = 0.02 and Z = 2.
        let discs = [
            Disc::new(Vector::new([3.0, 5.0]), Vector::new([1.0, 0.0]), 1.0),
            Disc::new(Vector::new([7.0, 5.0]), Vector::new([-1.0, 0.0]), 1.0),
        ];
        let mut sim =
            Simulation::new(&discs, SimBox::periodic([10.0, 10.0]), Options::default()).unwrap();
        let mut p = Pressure::new(&sim);
        sim.run_until(2.0, &mut obs(&mut p));
        p.sample(&sim);
        p.sample(&sim); // no time passed: no block
        let s = p.summary();
        assert_eq!(p.blocks().len(), 1);
        assert_eq!(s.effective_area, 100.0);
        assert!(s.wall.is_none() && s.z_wall.is_none());
        assert!((s.virial.value - 0.02).abs() < 1e-15);
        assert!((s.z.value - 2.0).abs() < 1e-15);
        assert_eq!(p.z_series(), vec![(2.0, s.z.value)]);
    }
}
