//! Invariant checks (overlaps, discs outside the box) and input validation.

use super::Simulation;
use crate::error::Error;
use crate::events::Pending;
use crate::predict::{contact_root, contact_terms};
use crate::schedule::EventQueue;
use crate::state::{Disc, SimBox};

impl<const D: usize> Simulation<D> {
    /// Overlapping pairs at the current time: those closer than `sigma (1 - tol)`, less the
    /// rounding allowance [`super::OVERLAP_ROUNDING`]` (L + (|v_i| + |v_j|) |t|)`.
    pub fn overlaps(&self, tol: f64) -> OverlapReport {
        if let Some(s) = self.sheets.as_deref() {
            return self.overlaps_in_order(s, tol);
        }
        let mut report = OverlapReport::default();
        let now = self.now;
        let longest = self.sim_box.lengths.iter().copied().fold(0.0, f64::max);
        let speed = |k: usize| self.velocity_of(k, now).norm2().sqrt();
        for i in 0..self.len() {
            let pi = self.position_of(i, now);
            self.for_each_neighbour(i, now, |j, shift, _| {
                if j <= i {
                    return;
                }
                let pj = self.position_of(j, now) + shift;
                let sigma = self.body[i].radius + self.body[j].radius;
                let d = (pj - pi).norm2().sqrt();
                let rounding =
                    super::OVERLAP_ROUNDING * (longest + (speed(i) + speed(j)) * now.abs());
                if d < sigma * (1.0 - tol) - rounding {
                    report.count += 1;
                    let overlap = (sigma - d) / sigma;
                    // "First" is the pair completed earliest in input order.
                    if report.first.is_none_or(|(fi, fj, _)| (j, i) < (fj, fi)) {
                        report.first = Some((i, j, overlap));
                    }
                }
            });
        }
        report
    }

    /// The first pair (in scan order) whose pending events would let it pass through a contact:
    /// `(i, j, contact time, the earliest event that would look at the pair again)`. For
    /// checking checkpoints, whose pending collisions cannot be recomputed to the bit (a
    /// partner's record may have moved on since the prediction).
    ///
    /// Why every honest state passes. A disc's events are predicted whenever its course
    /// changes, from its new course and that of every disc around it. So for a pair that meets
    /// at `t_c`, whichever of the two was predicted last saw the other on its present course:
    /// its event is no later than `t_c`, and in 3D, unless the pair is its earliest event, so
    /// is its second-earliest (the fallback of a stale event, taken without a new scan). The
    /// time at which disc `i` will look at `j` again is therefore its event's time, unless it
    /// has a second event and its event is not a live collision with `j` (a stale event falls
    /// back on the second without looking), in which case it is the second's.
    ///
    /// Rounding. The contact time computed here, from the discs' clocks at the last event,
    /// differs in its last bits from the one predicted, most for grazing pairs. So a pair is
    /// reported only when, by the time either looks again (or by its closest approach, if
    /// earlier), the two would be closer than the overlap check allows (`sigma (1 - tol)`
    /// less [`super::OVERLAP_ROUNDING`]` (L + (|v_i| + |v_j|) |t|)`): a pair that is let
    /// through by no more than that is one the overlap check would not see either.
    pub(super) fn missed_contact(&self) -> Option<(usize, usize, f64, f64)> {
        if let Some(s) = self.sheets.as_deref() {
            return self.missed_contact_sheets(s);
        }
        let t0 = self.event_time;
        let longest = self.sim_box.lengths.iter().copied().fold(0.0, f64::max);
        let looks_again = |i: usize, j: usize| {
            let (t1, first) = (self.queue.get(i), self.body[i].pending);
            let (t2, second) = self
                .second
                .get(i)
                .copied()
                .unwrap_or((f64::INFINITY, Pending::Nothing));
            let live_with_j = matches!(first, Pending::Disc { partner, seen }
                if partner as usize == j && seen == self.body[j].count);
            if second == Pending::Nothing || live_with_j {
                t1
            } else {
                t2
            }
        };
        let mut missed = None;
        for i in 0..self.len() {
            let bi = &self.body[i];
            let pi = self.position_of(i, t0);
            let vi = self.velocity_of(i, t0);
            self.for_each_neighbour(i, t0, |j, shift, dv| {
                if j <= i || missed.is_some() {
                    return;
                }
                let bj = &self.body[j];
                let dr = self.position_of(j, t0) + shift - pi;
                let vj = self.velocity_of(j, t0) + dv;
                let dv = vj - vi;
                let sigma = bi.radius + bj.radius;
                if self.ring.is_some() {
                    // Deeper than the overlaps a run allows, before either looks again (the
                    // contact times themselves differ in their last bits with the time they
                    // were reckoned from).
                    let again = looks_again(i, j).min(looks_again(j, i));
                    let speeds = vi.norm2().sqrt() + self.velocity_of(j, t0).norm2().sqrt();
                    let rounding = super::OVERLAP_ROUNDING * (longest + speeds * again.abs());
                    let inside = sigma * (1.0 - super::OVERLAP_TOLERANCE) - rounding;
                    if let Some(t) = self.ring_contact_before(dr, dv, inside, t0, again) {
                        missed = Some((i, j, t, again));
                    }
                    return;
                }
                let terms = contact_terms::<D, true>(dr, dv, sigma);
                if !terms.meets() {
                    return;
                }
                let t_contact = t0 + contact_root(terms);
                let again = looks_again(i, j).min(looks_again(j, i));
                if again <= t_contact {
                    return;
                }
                // Their closest approach (`b < 0`, so `a > 0`) or the time either looks again.
                let t = again.min(t0 - terms.b / dv.norm2());
                let gap = (dr + dv * (t - t0)).norm2().sqrt();
                let speeds = vi.norm2().sqrt() + vj.norm2().sqrt();
                let rounding = super::OVERLAP_ROUNDING * (longest + speeds * t.abs());
                if gap < sigma * (1.0 - super::OVERLAP_TOLERANCE) - rounding {
                    missed = Some((i, j, t_contact, again));
                }
            });
            if missed.is_some() {
                break;
            }
        }
        missed
    }

    /// [`Self::overlaps`] for rods that keep their order (self-gravity): each pair of
    /// neighbours in order, whose gap from the left one to the right one (negative when out of
    /// order) must be the contact distance less the same allowances.
    fn overlaps_in_order(&self, s: &super::sheets::Sheets, tol: f64) -> OverlapReport {
        let mut report = OverlapReport::default();
        let now = self.now;
        let longest = self.sim_box.lengths[0];
        for w in s.order.windows(2) {
            let (i, j) = (w[0] as usize, w[1] as usize);
            let gap = self.position_of(j, now)[0] - self.position_of(i, now)[0];
            let sigma = self.body[i].radius + self.body[j].radius;
            let speeds =
                self.velocity_of(i, now).norm2().sqrt() + self.velocity_of(j, now).norm2().sqrt();
            let rounding = super::OVERLAP_ROUNDING * (longest + speeds * now.abs());
            if gap < sigma * (1.0 - tol) - rounding {
                report.count += 1;
                let (a, b) = (i.min(j), i.max(j));
                if report.first.is_none_or(|(fi, fj, _)| (b, a) < (fj, fi)) {
                    report.first = Some((a, b, (sigma - gap) / sigma));
                }
            }
        }
        report
    }

    /// Discs outside the box (walled axes) at the current time, beyond `tol` relative to radius.
    pub fn discs_outside(&self, tol: f64) -> Vec<usize> {
        (0..self.len())
            .filter(|&i| {
                let p = self.position_of(i, self.now);
                let r = self.body[i].radius;
                (0..D).any(|a| {
                    !self.sim_box.is_periodic(a)
                        && (p[a] < r * (1.0 - tol)
                            || p[a] > self.sim_box.lengths[a] - r * (1.0 - tol))
                })
            })
            .collect()
    }
}

/// Result of [`Simulation::overlaps`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OverlapReport {
    /// Number of overlapping pairs.
    pub count: usize,
    /// The pair completed earliest in input order, `(i, j, (sigma - d)/sigma)` with `i < j`.
    pub first: Option<(usize, usize, f64)>,
}

pub(super) fn validate_discs<const D: usize>(
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
) -> Result<(), Error> {
    for (k, d) in discs.iter().enumerate() {
        let bad = |what: &str| {
            Err(Error::BadDisc {
                index: k,
                what: what.to_string(),
            })
        };
        if !d.pos.is_finite() {
            return bad("position is not finite");
        }
        if !d.vel.is_finite() {
            return bad("velocity is not finite");
        }
        if !(d.radius.is_finite() && d.radius > 0.0) {
            return bad(&format!(
                "radius {} is not a finite positive number",
                d.radius
            ));
        }
        if !(d.mass.is_finite() && d.mass > 0.0) {
            return bad(&format!("mass {} is not a finite positive number", d.mass));
        }
        if !(0.5 * d.mass * d.vel.norm2()).is_finite() {
            return bad("kinetic energy is not finite (speed or mass too large)");
        }
        // A disc exactly as wide as the box is refused too: its wall collisions would all be
        // at one instant, and the clock would never advance. (On a periodic axis the cell grid
        // refuses boxes under 3 diameters, so a disc never meets its own image.)
        for a in 0..D {
            if !sim_box.is_periodic(a) && 2.0 * d.radius >= sim_box.lengths[a] {
                return Err(Error::DiscFillsBox {
                    index: k,
                    axis: a,
                    diameter: 2.0 * d.radius,
                    length: sim_box.lengths[a],
                });
            }
        }
    }
    Ok(())
}
