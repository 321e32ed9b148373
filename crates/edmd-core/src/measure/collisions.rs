//! Collision frequency, free paths and free times.
//!
//! **Collision frequency per disc** `omega = 2 C / (N t)` for `C` disc-disc collisions in the
//! time `t` (each collision involves two discs). Kinetic theory predicts it for hard discs of
//! diameter `sigma` at number density `n` (D. M. Gass, J. Chem. Phys. 54, 1898 (1971), Enskog
//! theory for a rigid-disc fluid): `omega_E = 2 n sigma g(sigma) sqrt(pi kT / m)`, the
//! Boltzmann rate `2 n sigma <|v_12|>` (with the 2D mean relative speed `sqrt(pi kT / m)`)
//! times the pair distribution at contact `g(sigma)`.
//!
//! **Free paths and times.** A free flight is the straight stretch between two successive
//! collisions of a disc, with a disc, a wall or an internal barrier (a demon letting a disc
//! through its door is not a collision). Its time is the time between the collisions and
//! its length is the speed after the first of them times that time. The stretch from the start
//! of the measurement to each disc's first collision is partial and is left out, as is the
//! unfinished stretch at the end. The mean free path is then total distance over number of
//! flights, the collision-weighted mean `<v> / omega` of kinetic theory (Chapman and Cowling,
//! *The Mathematical Theory of Non-Uniform Gases*, 3rd ed. (1970), chapter 5), and the mean free
//! time is `1 / omega`. Long flights are the likelier to straddle the ends of the measuring time,
//! so leaving the partial ones out biases both means low by a relative `1 / (omega t)` or so.
//!
//! **Errors.** Each call of [`Collisions::sample`] closes a block; the frequency's error is the
//! block error of the per-block frequencies (see [`block_error`](super::block_error)).
//!
//! Collisions are taken to be binary. With multi-disc collisions
//! ([`Options::multi`](crate::Options)) the event names only two of the discs that changed
//! course, so the others' flights run on into the next one.

use super::stats::{Estimate, Histogram};
use crate::events::{BarrierHit, EventKind, EventRecord};
use crate::observer::Observer;
use crate::simulation::Simulation;

/// Collision counts per block and the free flights of every disc. Attach it as an observer
/// and call [`sample`](Collisions::sample) at the end of each block.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Collisions {
    n: usize,
    block_start: f64,
    block_disc_disc: u64,
    block_wall: u64,
    block_barrier: u64,
    blocks: Vec<CollisionBlock>,
    /// Time and speed after each disc's last collision (`None` before its first).
    last: Vec<Option<(f64, f64)>>,
    free_path: Histogram,
    free_time: Histogram,
    per_disc: Vec<DiscFlights>,
}

/// The completed free flights of one disc.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DiscFlights {
    /// Number of completed flights.
    pub flights: u64,
    /// Their total length.
    pub path: f64,
    /// Their total time.
    pub time: f64,
}

impl DiscFlights {
    /// Mean free path of the disc (`NaN` without flights).
    pub fn mean_free_path(&self) -> f64 {
        self.path / self.flights as f64
    }

    /// Mean free time of the disc (`NaN` without flights).
    pub fn mean_free_time(&self) -> f64 {
        self.time / self.flights as f64
    }
}

/// One block of a collision measurement.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CollisionBlock {
    /// Start time.
    pub start: f64,
    /// End time.
    pub end: f64,
    /// Disc-disc collisions in the block.
    pub disc_disc: u64,
    /// Wall collisions in the block.
    pub wall: u64,
    /// Bounces off internal barriers in the block.
    pub barrier: u64,
}

/// Result of a collision measurement.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CollisionSummary {
    /// Measuring time (sum of the block lengths).
    pub elapsed: f64,
    /// Disc-disc collisions in the closed blocks.
    pub disc_disc: u64,
    /// Wall collisions in the closed blocks.
    pub wall: u64,
    /// Bounces off internal barriers in the closed blocks.
    pub barrier: u64,
    /// Disc-disc collisions per disc per unit time, `2 C / (N t)`, with its block error.
    pub frequency: Estimate,
    /// Wall collisions per disc per unit time.
    pub wall_frequency: f64,
    /// Completed free flights (all events observed, closed blocks or not).
    pub flights: u64,
    /// Mean free path (`NaN` without flights).
    pub mean_free_path: f64,
    /// Mean free time (`NaN` without flights).
    pub mean_free_time: f64,
}

impl Collisions {
    /// Starts measuring at the simulation's current time. The histograms of free paths and free
    /// times have `bins` bins on `[0, max_path)` and `[0, max_time)`.
    ///
    /// # Panics
    /// If `bins == 0` or a maximum is not a finite positive number.
    pub fn new<const D: usize>(
        sim: &Simulation<D>,
        bins: usize,
        max_path: f64,
        max_time: f64,
    ) -> Self {
        Collisions {
            n: sim.len(),
            block_start: sim.time(),
            block_disc_disc: 0,
            block_wall: 0,
            block_barrier: 0,
            blocks: Vec::new(),
            last: vec![None; sim.len()],
            free_path: Histogram::new(0.0, max_path, bins),
            free_time: Histogram::new(0.0, max_time, bins),
            per_disc: vec![DiscFlights::default(); sim.len()],
        }
    }

    /// Whether this measurement can go on observing `sim`: it was made for as many discs (a
    /// measurement read back from a file is checked so before use).
    pub fn fits<const D: usize>(&self, sim: &Simulation<D>) -> bool {
        self.n == sim.len() && self.last.len() == self.n && self.per_disc.len() == self.n
    }

    /// Closes the current block at the simulation's current time and starts the next one.
    /// Does nothing if no time has passed since the last call.
    pub fn sample<const D: usize>(&mut self, sim: &Simulation<D>) {
        let (start, end) = (self.block_start, sim.time());
        if end <= start {
            return;
        }
        self.blocks.push(CollisionBlock {
            start,
            end,
            disc_disc: self.block_disc_disc,
            wall: self.block_wall,
            barrier: self.block_barrier,
        });
        self.block_start = end;
        self.block_disc_disc = 0;
        self.block_wall = 0;
        self.block_barrier = 0;
    }

    /// The closed blocks.
    pub fn blocks(&self) -> &[CollisionBlock] {
        &self.blocks
    }

    /// `(block end, disc-disc collisions per disc per unit time in the block)`.
    pub fn frequency_series(&self) -> Vec<(f64, f64)> {
        self.blocks
            .iter()
            .map(|b| (b.end, self.per_disc_rate(b.disc_disc, b.end - b.start)))
            .collect()
    }

    /// Histogram of the free paths.
    pub fn free_path_histogram(&self) -> &Histogram {
        &self.free_path
    }

    /// Histogram of the free times.
    pub fn free_time_histogram(&self) -> &Histogram {
        &self.free_time
    }

    /// The completed flights of each disc.
    pub fn per_disc(&self) -> &[DiscFlights] {
        &self.per_disc
    }

    /// Frequencies over the closed blocks and means over the completed flights of all discs.
    pub fn summary(&self) -> CollisionSummary {
        let elapsed: f64 = self.blocks.iter().map(|b| b.end - b.start).sum();
        let disc_disc: u64 = self.blocks.iter().map(|b| b.disc_disc).sum();
        let wall: u64 = self.blocks.iter().map(|b| b.wall).sum();
        let barrier: u64 = self.blocks.iter().map(|b| b.barrier).sum();
        let per_block: Vec<f64> = self.frequency_series().iter().map(|s| s.1).collect();
        let mut all = DiscFlights::default();
        for d in &self.per_disc {
            all.flights += d.flights;
            all.path += d.path;
            all.time += d.time;
        }
        CollisionSummary {
            elapsed,
            disc_disc,
            wall,
            barrier,
            frequency: Estimate::new(self.per_disc_rate(disc_disc, elapsed), &per_block),
            wall_frequency: wall as f64 / (self.n as f64 * elapsed),
            flights: all.flights,
            mean_free_path: all.mean_free_path(),
            mean_free_time: all.mean_free_time(),
        }
    }

    fn per_disc_rate(&self, disc_disc: u64, dt: f64) -> f64 {
        2.0 * disc_disc as f64 / (self.n as f64 * dt)
    }

    /// Ends disc `i`'s free flight (if one was under way) at time `t` and starts the next.
    fn collided<const D: usize>(&mut self, i: usize, t: f64, sim: &Simulation<D>) {
        if let Some((t0, speed)) = self.last[i] {
            let dt = t - t0;
            let path = speed * dt;
            self.free_time.add(dt);
            self.free_path.add(path);
            let d = &mut self.per_disc[i];
            d.flights += 1;
            d.path += path;
            d.time += dt;
        }
        self.last[i] = Some((t, sim.velocity(i).norm2().sqrt()));
    }
}

impl<const D: usize> Observer<D> for Collisions {
    #[inline]
    fn on_event(&mut self, e: &EventRecord<D>, sim: &Simulation<D>) {
        match e.kind {
            EventKind::DiscDisc { i, j } | EventKind::Reaction { i, j, .. } => {
                self.block_disc_disc += 1;
                self.collided(i, e.time, sim);
                self.collided(j, e.time, sim);
            }
            EventKind::Wall { i, .. } => {
                self.block_wall += 1;
                self.collided(i, e.time, sim);
            }
            EventKind::Barrier { i, hit, .. } => {
                if hit != BarrierHit::DoorPassed {
                    self.block_barrier += 1;
                    self.collided(i, e.time, sim);
                }
            }
            // Crossings of and bounces at a stepped potential's steps are not collisions of
            // the hard cores.
            EventKind::Step { .. }
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
    fn free_flights_of_a_disc_crossing_a_box() {
        // R = 1 in a 10 x 10 box, from (3, 5) at (2, 0): walls at t = 3 (x = 9), 7 (x = 1),
        // 11, 15. The stretch [0, 3) is partial; the flights are 3 of length 8 and time 4.
        let d = Disc::new(Vector::new([3.0, 5.0]), Vector::new([2.0, 0.0]), 1.0);
        let mut sim =
            Simulation::new(&[d], SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
        let mut c = Collisions::new(&sim, 10, 10.0, 5.0);
        sim.run_until(15.0, &mut obs(&mut c));
        c.sample(&sim);
        let s = c.summary();
        assert_eq!((s.disc_disc, s.wall, s.barrier, s.flights), (0, 4, 0, 3));
        assert_eq!((s.mean_free_path, s.mean_free_time), (8.0, 4.0));
        assert_eq!(s.wall_frequency, 4.0 / 15.0);
        assert_eq!(s.frequency.value, 0.0);
        assert_eq!(c.free_path_histogram().counts[8], 3);
        assert_eq!(c.free_time_histogram().counts[8], 3);
    }

    #[test]
    fn pair_collisions_end_flights_of_both_discs() {
        // Two discs (R = 1) on a line in a 20 x 10 box, at x = 5 and 15 moving towards each
        // other at speed 1: they meet at t = 4 (x = 9, 11), go back to the walls (x = 1 and 19)
        // at t = 12, meet again at t = 20, and so on. Flights: 8 long, 8 time units each.
        let discs = [
            Disc::new(Vector::new([5.0, 5.0]), Vector::new([1.0, 0.0]), 1.0),
            Disc::new(Vector::new([15.0, 5.0]), Vector::new([-1.0, 0.0]), 1.0),
        ];
        let mut sim =
            Simulation::new(&discs, SimBox::walls([20.0, 10.0]), Options::default()).unwrap();
        let mut c = Collisions::new(&sim, 4, 16.0, 16.0);
        // Blocks [0, 10] and [10, 22]: pair collisions at 4 and 20, walls at 12 (two).
        sim.run_until(10.0, &mut obs(&mut c));
        c.sample(&sim);
        sim.run_until(22.0, &mut obs(&mut c));
        c.sample(&sim);
        let s = c.summary();
        assert_eq!((s.disc_disc, s.wall, s.flights), (2, 2, 4));
        assert_eq!((s.mean_free_path, s.mean_free_time), (8.0, 8.0));
        // 2 * 2 / (2 * 22) per disc per unit time; blocks 2/20 and 2/24.
        assert!((s.frequency.value - 4.0 / 44.0).abs() < 1e-15);
        assert_eq!(c.frequency_series(), vec![(10.0, 0.1), (22.0, 2.0 / 24.0)]);
        assert_eq!(c.free_time_histogram().counts, vec![0, 0, 4, 0]);
        let both = DiscFlights {
            flights: 2,
            path: 16.0,
            time: 16.0,
        };
        assert_eq!(c.per_disc(), &[both, both]);
        assert_eq!(c.per_disc()[0].mean_free_path(), 8.0);
    }
}
