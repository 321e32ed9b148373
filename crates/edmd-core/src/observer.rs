//! Observers: callers see every processed event without the engine knowing about them.
//!
//! The `particles` counters, the measurements and the viewer all hang off this trait. The
//! engine is generic over it, so an observer costs nothing when it does nothing.

use crate::events::{EventKind, EventRecord};
use crate::simulation::Simulation;

/// Sees every processed event, after the state has been updated.
pub trait Observer<const D: usize = 2> {
    /// Called once per processed event.
    fn on_event(&mut self, event: &EventRecord<D>, sim: &Simulation<D>);
}

impl<const D: usize> Observer<D> for () {
    #[inline(always)]
    fn on_event(&mut self, _: &EventRecord<D>, _: &Simulation<D>) {}
}

impl<const D: usize, O: Observer<D> + ?Sized> Observer<D> for &mut O {
    #[inline(always)]
    fn on_event(&mut self, e: &EventRecord<D>, s: &Simulation<D>) {
        (**self).on_event(e, s)
    }
}

impl<const D: usize, O: Observer<D> + ?Sized> Observer<D> for Box<O> {
    #[inline(always)]
    fn on_event(&mut self, e: &EventRecord<D>, s: &Simulation<D>) {
        (**self).on_event(e, s)
    }
}

impl<const D: usize, A: Observer<D>, B: Observer<D>> Observer<D> for (A, B) {
    #[inline(always)]
    fn on_event(&mut self, e: &EventRecord<D>, s: &Simulation<D>) {
        self.0.on_event(e, s);
        self.1.on_event(e, s);
    }
}

impl<const D: usize, O: Observer<D>> Observer<D> for Vec<O> {
    fn on_event(&mut self, e: &EventRecord<D>, s: &Simulation<D>) {
        for o in self {
            o.on_event(e, s);
        }
    }
}

/// Counts wall and disc collisions per disc (the course assignment's `cwall` and `cpart`).
#[derive(Clone, Debug, Default)]
pub struct CollisionCounter {
    /// Wall collisions of each disc.
    pub wall: Vec<u64>,
    /// Disc-disc collisions of each disc.
    pub disc: Vec<u64>,
}

impl CollisionCounter {
    /// Counters for `n` discs, all zero.
    pub fn new(n: usize) -> Self {
        CollisionCounter {
            wall: vec![0; n],
            disc: vec![0; n],
        }
    }
}

impl<const D: usize> Observer<D> for CollisionCounter {
    #[inline]
    fn on_event(&mut self, e: &EventRecord<D>, _: &Simulation<D>) {
        match e.kind {
            EventKind::DiscDisc { i, j } | EventKind::Reaction { i, j, .. } => {
                self.disc[i] += 1;
                self.disc[j] += 1;
            }
            EventKind::Wall { i, .. } => self.wall[i] += 1,
            EventKind::Barrier { i, hit, .. } => {
                if hit != crate::events::BarrierHit::DoorPassed {
                    self.wall[i] += 1;
                }
            }
            EventKind::Step { .. }
            | EventKind::Thermostat { .. }
            | EventKind::NeighbourList { .. }
            | EventKind::Slide { .. }
            | EventKind::CellCrossing { .. } => {}
        }
    }
}

/// The observer as a trait object, for the unit tests: the engine's loop is compiled once for
/// each type of observer it runs with, and tests passing theirs through here share one copy
/// per dimension (`tests/support` does the same for the integration tests): the unit tests
/// built in 128 s on two cores (155 s of CPU) where a copy for each took 290 s (312 s).
#[cfg(test)]
pub(crate) fn obs<const D: usize>(o: &mut impl Observer<D>) -> &mut dyn Observer<D> {
    o
}
