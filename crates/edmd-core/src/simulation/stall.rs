//! Runs whose clock stops advancing.
//!
//! Exact event times only move forward, but they can stop moving: discs jammed so that every
//! event they have is at `dt = 0` (a column of touching discs filling the box's height, a
//! square lattice of touching discs filling the box) collide with each other for ever at one
//! instant, and the run would never reach its end time. The event loop cannot fail, so it
//! counts instead: [`Simulation::run_until`] and the other loops stop when more than
//! [`Simulation::stall_limit`] events in a row have happened at one time, and record a
//! [`Stall`], which [`Simulation::stalled`] returns. The loop then does nothing more.
//!
//! The clock can also creep: 400 touching discs filling a box, given random velocities, collide
//! across gaps of rounding size, so that millions of events move the clock by 1e-12 in all and
//! the run would take years. A chunk of events that moves the clock by less than
//! [`CREEP_EVENTS_SPAN`] per event, in units of the time the fastest disc the energy allows
//! takes to cross the smallest diameter, counts as standing still ([`StallCause::Creep`]). No
//! fluid comes near it: events that close together need gaps below the overlap tolerance
//! (`Simulation::creep_span`).
//!
//! The loop counts whole chunks of events rather than single events (a chunk in which the time
//! did not advance adds its events; one in which it did starts the count again), so the count
//! costs nothing per event and the two compiled copies of the loop are untouched. A stall is
//! therefore noticed between [`Simulation::stall_limit`] and that plus [`STALL_CHUNK`] events
//! after it began; the count never exceeds the true number of events in a row at that time.
//! The chunks are counted from the start of the run, not from the start of each call, and
//! checkpoints carry the count and the position in the chunk: a run cut into calls of any size,
//! or continued from a checkpoint, counts exactly as the run made in one call.

use std::fmt;

use super::Simulation;
use crate::events::EventKind;
use crate::observer::Observer;
use crate::schedule::EventQueue;

/// The most events the loop processes between two looks at the clock.
pub(super) const STALL_CHUNK: u64 = 1 << 16;

/// Events run after the limit to see which discs take part in a stall.
pub(super) const STALL_SAMPLE: u64 = 4096;

/// The fewest events in a row at one time that count as a stall, whatever the number of discs.
pub const MIN_STALL_EVENTS: u64 = 1_000_000;

/// Events in a row at one time per disc that count as a stall (see [`Simulation::stall_limit`]).
pub const STALL_EVENTS_PER_DISC: u64 = 100;

/// The creep bound per event, in units of `sigma_min / v_max` (the time the fastest disc the
/// energy allows takes to cross the smallest contact distance): sixteen units of rounding.
pub const CREEP_EVENTS_SPAN: f64 = 16.0 * f64::EPSILON;

/// A run stopped because its clock stopped advancing.
#[derive(Clone, Debug, PartialEq)]
pub struct Stall {
    /// The time at which the clock stopped.
    pub time: f64,
    /// Events counted at that time before the run was stopped (a lower bound).
    pub events: u64,
    /// The discs that took part in the last events at that time (or, when the run went event
    /// by event with [`Simulation::step`], those with an event pending at that time), lowest
    /// index first: at most [`Stall::NAMED`] of them.
    pub discs: Vec<usize>,
    /// How many discs took part (or had an event pending).
    pub count: usize,
    /// Why the run stopped.
    pub cause: StallCause,
}

/// Why a run stopped: see [`Stall`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StallCause {
    /// More than [`Simulation::stall_limit`] events in a row at one time (`Stall::events`).
    Clock,
    /// A multi-disc collision (`Options::multi`) that did not end within
    /// [`crate::resolve::cluster::MAX_CONTACT_STEPS`]: masses or speeds in contact that differ
    /// by many orders of magnitude, or discs jammed in contact. `Stall::events` is 1; the
    /// discs are the cluster's.
    Cluster,
    /// More than [`Simulation::stall_limit`] events in a row that moved the clock by less than
    /// [`CREEP_EVENTS_SPAN`] each (see the module's notes): discs jammed at contact, colliding
    /// across gaps of rounding size.
    Creep,
}

impl Stall {
    /// The most discs a stall names.
    pub const NAMED: usize = 8;

    fn new(time: f64, events: u64, mut discs: Vec<usize>, cause: StallCause) -> Stall {
        let count = discs.len();
        discs.truncate(Stall::NAMED);
        Stall {
            time,
            events,
            discs,
            count,
            cause,
        }
    }
}

/// A time as a reader takes it in: as is from 0.001 to 10^9, in exponent form beyond
/// (`5.95140722740378e-12`, not `0.00000000000595140722740378`); exact either way (the shortest
/// decimal that reads back to the same number).
fn readable(t: f64) -> String {
    if t == 0.0 || (1e-3..1e9).contains(&t.abs()) {
        format!("{t}")
    } else {
        format!("{t:e}")
    }
}

impl fmt::Display for Stall {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let time = readable(self.time);
        match self.cause {
            StallCause::Clock => write!(
                f,
                "the clock stopped advancing at t = {time}: {} events in a row at that time",
                self.events
            )?,
            StallCause::Cluster => write!(
                f,
                "a multi-disc collision at t = {time} did not end within {} contact steps",
                crate::resolve::cluster::MAX_CONTACT_STEPS
            )?,
            StallCause::Creep => write!(
                f,
                "the clock stopped advancing at t = {time}: {} events in a row moved it by next to nothing",
                self.events
            )?,
        }
        if !self.discs.is_empty() {
            let names: Vec<String> = self.discs.iter().map(|d| d.to_string()).collect();
            let s = if self.count == 1 { "" } else { "s" };
            write!(f, ", among disc{s} {} (from 0", names.join(", "))?;
            if self.count > self.discs.len() {
                write!(f, "; {} in all", self.count)?;
            }
            write!(f, ")")?;
        }
        match self.cause {
            StallCause::Clock | StallCause::Creep => {
                write!(f, "; discs jammed at contact cannot move")
            }
            StallCause::Cluster => write!(
                f,
                "; their masses or speeds differ too much for multi-disc collisions, or they are \
                 jammed at contact (run without multi-disc collisions)"
            ),
        }
    }
}

impl<const D: usize> Simulation<D> {
    /// The stall that stopped this simulation's event loop, if any (see [`Stall`]). Once
    /// stalled, the loops process no more events and [`Self::run_until`] leaves the clock where
    /// it stopped.
    pub fn stalled(&self) -> Option<&Stall> {
        self.stall.as_ref()
    }

    /// Events in a row at one time beyond which the loop stops: `max(10^6, 100 N)`.
    ///
    /// A legitimate instant can hold many events: in a perfect lattice every disc may cross a
    /// cell boundary on each axis and meet each of its nearest neighbours (6 in a triangular
    /// lattice, 12 in a face-centred cubic one) at the same time, some `D + 12` events per disc
    /// at most; 100 per disc leaves a wide margin. The floor of `10^6` (well under a second of
    /// events) keeps small systems from being stopped by chance.
    pub fn stall_limit(&self) -> u64 {
        MIN_STALL_EVENTS.max(STALL_EVENTS_PER_DISC.saturating_mul(self.body.len() as u64))
    }

    /// Counts `events` just processed. The watcher looks at the clock only at the end of each
    /// chunk of [`STALL_CHUNK`] events counted from the start of the run (the loops never run
    /// past a chunk's end: [`Self::chunk_room`]), however the run is cut into calls, so that
    /// the count, and so the run and its checkpoints, do not depend on how it was cut. A chunk
    /// in which the clock did not advance adds its events; one in which it did starts the count
    /// again. Returns the cause past the limit (the clock stood still or crept in the last
    /// chunk): the caller then records the stall
    /// ([`Self::stall_seen`] or [`Self::stall_pending`]).
    #[inline]
    pub(super) fn count_events(&mut self, events: u64) -> Option<StallCause> {
        self.chunk_events += events;
        if self.chunk_events < STALL_CHUNK {
            return None;
        }
        self.chunk_events = 0;
        let moved = self.event_time - self.chunk_time;
        self.chunk_time = self.event_time;
        if moved > self.creep_span {
            self.still = 0;
            return None;
        }
        self.still = self.still.saturating_add(STALL_CHUNK);
        (self.still > self.stall_limit()).then_some(if moved == 0.0 {
            StallCause::Clock
        } else {
            StallCause::Creep
        })
    }

    /// Events left in the stall watcher's current chunk.
    #[inline]
    pub(super) fn chunk_room(&self) -> u64 {
        STALL_CHUNK - self.chunk_events
    }

    /// The creep bound of a chunk: [`STALL_CHUNK`] events of [`CREEP_EVENTS_SPAN`]
    /// `sigma_min / v_max` each, `v_max` the speed of the lightest disc holding all the kinetic
    /// energy (energy is conserved, so no disc is ever faster). Worked out from the state a
    /// checkpoint restores exactly (radii, masses, and the mean `m v^2` kept from the start), so
    /// a continued run counts as the original did. Zero (no creep test) without motion or
    /// without size.
    ///
    /// Why no fluid is near it: events `CREEP_EVENTS_SPAN sigma_min / v_max` apart on average
    /// need, even for 10^6 discs colliding in turn, gaps below `10^-9` of a diameter: the overlap
    /// tolerance. The same run at any larger gap is merely slow.
    pub(super) fn creep_span(&self) -> f64 {
        let n = self.body.len();
        let sigma_min = 2.0
            * self
                .body
                .iter()
                .map(|b| b.radius)
                .fold(f64::INFINITY, f64::min);
        let m_min = self.mass.iter().copied().fold(f64::INFINITY, f64::min);
        // mean_mv2 = 4 KE / n, so the fastest speed is sqrt(2 KE / m_min).
        // Under shear, pairs across y close at up to the images' speed more.
        let slide = self.shear.as_deref().map_or(0.0, |s| s.speed.abs());
        // Under self-gravity a rod gains speed from the potential energy.
        let fall = if self.sheets.is_some() {
            self.fall_speed2().sqrt()
        } else {
            0.0
        };
        let v_max = (self.mean_mv2 * n as f64 / (2.0 * m_min)).sqrt() + slide + fall;
        let span = STALL_CHUNK as f64 * CREEP_EVENTS_SPAN * sigma_min / v_max;
        if span.is_finite() && span > 0.0 {
            span
        } else {
            0.0
        }
    }

    /// Past the limit in the loop: runs up to [`STALL_SAMPLE`] more events (shown to
    /// `observer` like any other) to see which discs take part, and records the stall naming
    /// them; unless the clock moves on after all, which starts the count again.
    #[cold]
    #[inline(never)]
    pub(super) fn stall_seen<O: Observer<D>>(&mut self, t_limit: f64, observer: &mut O) {
        let t = self.event_time;
        let mut discs = Vec::new();
        for _ in 0..STALL_SAMPLE {
            let e = if self.has_extras() {
                self.step_inline::<true, false>(t_limit)
            } else {
                self.step_inline::<false, false>(t_limit)
            };
            let Some(e) = e else {
                return;
            };
            observer.on_event(&e, self);
            if self.event_time - t > self.creep_span {
                self.still = 0;
                return;
            }
            self.still = self.still.saturating_add(1);
            match e.kind {
                EventKind::DiscDisc { i, j }
                | EventKind::Reaction { i, j, .. }
                | EventKind::Step { i, j, .. } => discs.extend([i, j]),
                EventKind::Wall { i, .. }
                | EventKind::Barrier { i, .. }
                | EventKind::Thermostat { i }
                | EventKind::NeighbourList { i }
                | EventKind::Slide { i }
                | EventKind::CellCrossing { i, .. } => discs.push(i),
            }
            discs.extend(self.last_cluster.iter().copied());
        }
        discs.sort_unstable();
        discs.dedup();
        let cause = if self.event_time == t {
            StallCause::Clock
        } else {
            StallCause::Creep
        };
        self.record_stall(discs, cause);
    }

    /// Past the limit in [`Self::step`], which has no observer to show more events to: records
    /// the stall naming the discs whose next event is at the stalled time (within the creep
    /// bound of a chunk, when the clock was creeping).
    #[cold]
    #[inline(never)]
    pub(super) fn stall_pending(&mut self, cause: StallCause) {
        let t = self.event_time;
        let discs = (0..self.body.len())
            .filter(|&i| {
                let dt = self.queue.get(i) - t;
                match cause {
                    StallCause::Creep => dt <= self.creep_span,
                    _ => dt == 0.0,
                }
            })
            .collect();
        self.record_stall(discs, cause);
    }

    fn record_stall(&mut self, discs: Vec<usize>, cause: StallCause) {
        if self.stall.is_some() {
            // A multi-disc collision given up stopped the run first.
            return;
        }
        self.stall = Some(Stall::new(self.event_time, self.still, discs, cause));
    }

    /// Records that the multi-disc collision of `discs` at time `t` was given up.
    #[cold]
    pub(super) fn record_cluster_stall(&mut self, t: f64, discs: &[usize]) {
        let mut discs = discs.to_vec();
        discs.sort_unstable();
        self.stall = Some(Stall::new(t, 1, discs, StallCause::Cluster));
    }
}

#[cfg(test)]
mod tests {
    use super::readable;

    #[test]
    fn stall_times_read_back_and_read_easily() {
        assert_eq!(readable(0.0), "0");
        assert_eq!(readable(2.5), "2.5");
        assert_eq!(readable(123456.75), "123456.75");
        // The time of a stall `edmd run` once printed as 0.00000000000595140722740378.
        let t = 0.00000000000595140722740378;
        assert_eq!(readable(t), "5.95140722740378e-12");
        assert_eq!(readable(3e12), "3e12");
        for x in [t, 3e12, 1.0 / 3.0, 1e-3, 1e9, -7.25e-9] {
            assert_eq!(readable(x).parse::<f64>().unwrap(), x);
        }
    }
}
