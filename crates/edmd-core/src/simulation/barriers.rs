//! Internal barriers (2D only): setting them, overlaps with them, and their events.

use super::{Simulation, MAX_BARRIERS, OVERLAP_TOLERANCE};
use crate::error::Error;
use crate::events::{BarrierHit, EventKind, EventRecord};
use crate::math::Vector;
use crate::predict::barrier::across;
use crate::resolve::wall::{reflect, reflect_normal};
use crate::state::{Barrier, SimBox};

impl<const D: usize> Simulation<D> {
    /// The internal barriers.
    pub fn barriers(&self) -> &[Barrier] {
        &self.barriers
    }

    /// Replaces the internal barriers at the current time (removing a partition, opening a
    /// door) and schedules everything again. Fails, changing nothing, if a barrier is invalid
    /// or cuts through a disc.
    pub fn set_barriers(&mut self, barriers: &[Barrier]) -> Result<(), Error> {
        validate_barriers(barriers, &self.sim_box)?;
        let old = std::mem::replace(&mut self.barriers, barriers.to_vec());
        let now = self.now;
        for b in self.body.iter_mut() {
            b.advance_to(now);
        }
        if let Some((disc, barrier)) = self.barrier_overlap() {
            self.barriers = old;
            return Err(Error::BarrierOverlap { disc, barrier });
        }
        self.below = vec![0; if barriers.is_empty() { 0 } else { self.len() }];
        self.event_time = now;
        self.schedule_all();
        Ok(())
    }

    /// The first (disc, barrier) pair where a disc cuts into a barrier (beyond
    /// [`OVERLAP_TOLERANCE`]) at the current time, if any.
    pub fn barrier_overlap(&self) -> Option<(usize, usize)> {
        for (i, b) in self.body.iter().enumerate() {
            let p = b.position_at(self.now);
            let tol = OVERLAP_TOLERANCE * b.radius;
            for (k, w) in self.barriers.iter().enumerate() {
                let d = (p[w.axis] - w.position).abs();
                if d >= b.radius - tol {
                    continue;
                }
                let y = p[across(w.axis)];
                let cuts = match w.door {
                    None => true,
                    Some((lo, hi)) => {
                        let edge = |e: f64| ((y - e).powi(2) + d * d).sqrt() < b.radius - tol;
                        y <= lo || y >= hi || edge(lo) || edge(hi)
                    }
                };
                if cuts {
                    return Some((i, k));
                }
            }
        }
        None
    }

    pub(super) fn meet_barrier(&mut self, i: usize, k: usize, part: u8, t: f64) -> EventRecord<D> {
        let w = self.barriers[k];
        let m = self.mass[i];
        self.body[i].advance_to(t);
        let b = &mut self.body[i];
        let (hit, impulse) = match part {
            0 => {
                // Exactly at contact, on the side the disc is on: the centre is there up to
                // rounding. A disc that cuts into the face (allowed at the start,
                // `OverlapPolicy::Allow`) is turned round where it is, as an overlapping pair
                // is: put at contact it could jump across the box's wall beside the barrier.
                let contact = if b.pos[w.axis] < w.position {
                    w.position - b.radius
                } else {
                    w.position + b.radius
                };
                if (b.pos[w.axis] - contact).abs() <= OVERLAP_TOLERANCE * b.radius {
                    b.pos[w.axis] = contact;
                }
                (BarrierHit::Face, reflect(&mut b.vel, w.axis, m))
            }
            1 | 2 => {
                let (lo, hi) = w.door.expect("edges belong to doors");
                let mut q = Vector::ZERO;
                q[w.axis] = w.position;
                q[across(w.axis)] = if part == 1 { lo } else { hi };
                let d = b.pos - q;
                let n = d / d.norm2().sqrt();
                (BarrierHit::Edge, reflect_normal(&mut b.vel, n, m))
            }
            _ => {
                let demon = w.demon.expect("doorway events belong to demons");
                let below = self.below[i] & (1 << k) != 0;
                let mv2 = m * b.vel.norm2();
                let pass = if below {
                    mv2 >= demon.fast * self.mean_mv2
                } else {
                    mv2 <= demon.slow * self.mean_mv2
                };
                if pass {
                    self.below[i] ^= 1 << k;
                    (BarrierHit::DoorPassed, Vector::ZERO)
                } else {
                    (BarrierHit::DoorShut, reflect(&mut b.vel, w.axis, m))
                }
            }
        };
        if hit != BarrierHit::DoorPassed {
            b.count = b.count.wrapping_add(1);
        }
        self.stats.barrier = self.stats.barrier.wrapping_add(1);
        EventRecord {
            time: t,
            kind: EventKind::Barrier { i, barrier: k, hit },
            impulse,
        }
    }
}

pub(crate) fn validate_barriers<const D: usize>(
    barriers: &[Barrier],
    sim_box: &SimBox<D>,
) -> Result<(), Error> {
    if barriers.len() > MAX_BARRIERS {
        return Err(Error::Invalid(format!(
            "at most {MAX_BARRIERS} barriers, got {}",
            barriers.len()
        )));
    }
    for (k, w) in barriers.iter().enumerate() {
        let bad = |what: String| Err(Error::Invalid(format!("barrier {k}: {what}")));
        if D != 2 {
            return bad(format!("barriers exist in two dimensions only, not in {D}"));
        }
        if w.axis >= D {
            return bad(format!("axis {} does not exist", w.axis));
        }
        if (0..D).any(|a| sim_box.is_periodic(a)) {
            return bad(
                "barriers need walls on every axis (periodic boxes are not supported)".into(),
            );
        }
        let (l, lb) = (sim_box.lengths[w.axis], sim_box.lengths[across(w.axis)]);
        if !(w.position > 0.0 && w.position < l) {
            return bad(format!(
                "position {} is not inside the box (0, {l})",
                w.position
            ));
        }
        if let Some((lo, hi)) = w.door {
            if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && lo < hi && hi <= lb) {
                return bad(format!(
                    "door ({lo}, {hi}) is not an opening within (0, {lb})"
                ));
            }
        }
        if let Some(d) = w.demon {
            if w.door.is_none() {
                return bad("a demon needs a door".into());
            }
            if !(d.fast.is_finite() && d.fast >= 0.0 && d.slow.is_finite() && d.slow >= 0.0) {
                return bad(format!(
                    "demon thresholds must be finite and >= 0, got {} and {}",
                    d.fast, d.slow
                ));
            }
        }
    }
    Ok(())
}
