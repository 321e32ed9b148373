//! Prediction: a disc's earliest event (cell exit, walls, barriers, the discs around it).

use crate::cells::{CellGrid, Visit};
use crate::events::{Pending, Side};
use crate::math::Vector;
use crate::predict::barrier::{time_to_barrier, time_to_doorway, Contact};
use crate::predict::{
    contact_root, contact_terms, interval_exit, interval_exit_accel_or_inf, ContactTerms,
    FAR_CONTACT_RATIO2,
};
use crate::schedule::EventQueue;
use crate::state::{Gravity, SimBox};

use super::{Body, Simulation, NO_PARTNER};

impl<const D: usize> Simulation<D> {
    /// [`Self::predict`] as a function of its own, for the places off the event loop.
    #[inline(never)]
    pub(super) fn predict_outlined(&mut self, i: usize) {
        if self.has_extras() {
            self.predict::<true>(i);
        } else {
            self.predict::<false>(i);
        }
    }

    /// The earliest barrier event of disc `i` from its own clock (when predicting, advanced to
    /// the last event time) if it beats `(best_t, best)`.
    #[inline(never)]
    pub(super) fn predict_barriers(
        &self,
        i: usize,
        mut best_t: f64,
        mut best: Pending,
    ) -> (f64, Pending) {
        let bi = self.body[i];
        let t0 = bi.time;
        for (k, w) in self.barriers.iter().enumerate() {
            if let Some((dt, c)) =
                time_to_barrier(bi.pos, bi.vel, bi.radius, w.axis, w.position, w.door)
            {
                if t0 + dt < best_t {
                    best_t = t0 + dt;
                    let part = match c {
                        Contact::Face => 0,
                        Contact::Edge(e) => 1 + e,
                    };
                    best = Pending::Barrier {
                        index: k as u16,
                        part,
                    };
                }
            }
            if let (Some(door), Some(_)) = (w.door, w.demon) {
                let below = self.below[i] & (1 << k) != 0;
                if let Some(dt) = time_to_doorway(bi.pos, bi.vel, w.axis, w.position, door, below) {
                    if t0 + dt < best_t {
                        best_t = t0 + dt;
                        best = Pending::Barrier {
                            index: k as u16,
                            part: 3,
                        };
                    }
                }
            }
        }
        (best_t, best)
    }

    /// Disc `i`'s earliest event that follows from its own motion alone (its cell exit, a wall
    /// or a barrier), from its own clock, computed as [`Self::predict`] computes it (it
    /// predicts from the disc's own clock, having just advanced it), ties decided the same
    /// way. For checking checkpoints: a pending event is never later, and a pending event of
    /// one of these kinds is this one, to the bit. It repeats the start of `predict_with`,
    /// which must stay in step with it: calling it from there instead cost 0.7% more
    /// instructions per collision and measured slower in 2D (BENCHMARKS.md).
    pub(super) fn own_event(&self, i: usize) -> (f64, Pending) {
        let bi = self.body[i];
        if self.ring.is_some() {
            return self.own_event_ring(i, bi.time, bi.pos, bi.vel);
        }
        if let Some(f) = self.gravity {
            return self.own_event_in_field(i, bi.time, bi.pos, bi.vel, f);
        }
        if let Some(s) = self.sheets.as_deref() {
            return self.own_event_sheets(i, bi.time, bi.pos, bi.vel, s);
        }
        if self.shear.is_some() {
            return self.own_event_sheared(i, bi.time, bi.pos, bi.vel);
        }
        let (mut best_t, mut best) = (f64::INFINITY, Pending::Nothing);
        if let Some(steps) = self.steps.as_deref() {
            let dt = super::steps::leash_time(steps, bi.pos, bi.vel, i);
            if dt != f64::INFINITY {
                best_t = bi.time + dt;
                best = Pending::Relist;
            }
        } else {
            let (dt, axis, high) = self.grid.exit_time(i, bi.pos, bi.vel);
            if dt != f64::INFINITY {
                best_t = bi.time + dt;
                best = Pending::Cell {
                    axis: axis as u8,
                    side: if high { Side::High } else { Side::Low },
                };
            }
        }
        for a in 0..D {
            if self.sim_box.is_periodic(a) {
                continue;
            }
            if let Some((dt, side)) = interval_exit(
                bi.pos[a],
                bi.vel[a],
                bi.radius,
                self.sim_box.lengths[a] - bi.radius,
            ) {
                if bi.time + dt < best_t {
                    best_t = bi.time + dt;
                    best = Pending::Wall {
                        axis: a as u8,
                        side,
                    };
                }
            }
        }
        if !self.barriers.is_empty() {
            (best_t, best) = self.predict_barriers(i, best_t, best);
        }
        if self.bath.is_some() {
            (best_t, best) = self.bath_event(i, best_t, best);
        }
        (best_t, best)
    }

    /// Disc `i`'s earliest event of its own in the field `f` (its cell exit, a wall, a
    /// redraw), from `pos` and `vel` at its own clock `t0`: the event's time and the event.
    /// Predictions and [`Self::own_event`] both take it, so they agree to the bit. (No
    /// barriers or stepped potential: a field is refused with them.)
    #[inline(always)]
    pub(super) fn own_event_in_field(
        &self,
        i: usize,
        t0: f64,
        pos: Vector<D>,
        vel: Vector<D>,
        f: Gravity,
    ) -> (f64, Pending) {
        let (mut best_dt, mut best) = (f64::INFINITY, Pending::Nothing);
        let (dt, axis, high) = self.grid.exit_time_accel(i, pos, vel, f.axis, f.g);
        if dt != f64::INFINITY {
            best_dt = dt;
            best = Pending::Cell {
                axis: axis as u8,
                side: if high { Side::High } else { Side::Low },
            };
        }
        let radius = self.body[i].radius;
        for a in 0..D {
            if self.sim_box.is_periodic(a) {
                continue;
            }
            let ga = if a == f.axis { f.g } else { 0.0 };
            let (dt, high) = interval_exit_accel_or_inf(
                pos[a],
                vel[a],
                ga,
                radius,
                self.sim_box.lengths[a] - radius,
            );
            if dt < best_dt {
                best_dt = dt;
                best = Pending::Wall {
                    axis: a as u8,
                    side: if high { Side::High } else { Side::Low },
                };
            }
        }
        let best_t = if best_dt == f64::INFINITY {
            f64::INFINITY
        } else {
            t0 + best_dt
        };
        self.bath_event(i, best_t, best)
    }

    /// Finds disc `i`'s earliest event from the last event time on and schedules it (with the
    /// steps of a stepped potential and the thermostat's redraws when `EXTRAS`).
    #[inline(always)]
    pub(super) fn predict<const EXTRAS: bool>(&mut self, i: usize) {
        if self.far_contacts {
            self.predict_far::<EXTRAS>(i)
        } else {
            self.predict_with::<false, EXTRAS>(i)
        }
    }

    /// [`Self::predict`] with contact times in the far form, for systems whose candidates can
    /// be far apart ([`far_contacts`]): outlined, as such systems are few and small.
    #[inline(never)]
    fn predict_far<const EXTRAS: bool>(&mut self, i: usize) {
        self.predict_with::<true, EXTRAS>(i)
    }

    /// [`Self::predict`], the contact times in the far form when `FAR`. Its start (cell exit,
    /// walls, barriers) is [`Self::own_event`]'s, which must stay in step with it.
    #[inline(always)]
    fn predict_with<const FAR: bool, const EXTRAS: bool>(&mut self, i: usize) {
        let t0 = self.event_time;
        if EXTRAS && self.sheets.is_some() {
            return self.predict_sheets(i);
        }
        if EXTRAS && self.ring.is_some() {
            return self.predict_ring(i);
        }
        if EXTRAS && self.gravity.is_some() {
            return self.predict_in_field::<FAR>(i);
        }
        if EXTRAS && self.shear.is_some() {
            return self.predict_sheared::<FAR>(i);
        }
        self.body[i].advance_to(t0);
        // The fields read, not a copy of the record: the copy, just after `advance_to` wrote
        // the record, was made with wide loads that the stores could not forward to.
        let (pos, vel, radius) = {
            let b = &self.body[i];
            (b.pos, b.vel, b.radius)
        };
        let mut best_t = f64::INFINITY;
        let mut best = Pending::Nothing;
        if EXTRAS && self.steps.is_some() {
            // Filed by its list's centre, a disc under a stepped potential has no cell
            // crossings: its list is made again when it strays half the skin from there.
            let steps = self.steps.as_deref().expect("a stepped simulation");
            let dt = super::steps::leash_time(steps, pos, vel, i);
            if dt != f64::INFINITY {
                best_t = t0 + dt;
                best = Pending::Relist;
            }
        } else {
            let (dt, axis, high) = self.grid.exit_time(i, pos, vel);
            if dt != f64::INFINITY {
                let side = if high { Side::High } else { Side::Low };
                best_t = t0 + dt;
                best = Pending::Cell {
                    axis: axis as u8,
                    side,
                };
            }
        }
        for a in 0..D {
            if self.sim_box.is_periodic(a) {
                continue;
            }
            if let Some((dt, side)) =
                interval_exit(pos[a], vel[a], radius, self.sim_box.lengths[a] - radius)
            {
                if t0 + dt < best_t {
                    best_t = t0 + dt;
                    best = Pending::Wall {
                        axis: a as u8,
                        side,
                    };
                }
            }
        }
        if !self.barriers.is_empty() {
            (best_t, best) = self.predict_barriers(i, best_t, best);
        }
        if EXTRAS && self.bath.is_some() {
            (best_t, best) = self.bath_event(i, best_t, best);
        }
        // Every candidate's contact terms are worked out, and those that meet are kept, without
        // branches (whether a pair meets is a coin toss for the branch predictor); only the
        // kept ones pay for the square root and the division (BENCHMARKS.md).
        let mut nearest = Nearest::new(t0, best_t, &mut self.kept);
        // The hard-core scans start from the disc's cell; a stepped potential's scan reads the
        // disc's neighbour list, and reading the cell there cost 4% of the loop at N = 10^5.
        let c = if EXTRAS && self.steps.is_some() {
            [0; D]
        } else {
            self.grid.cell_of(i)
        };
        #[cfg(target_arch = "x86_64")]
        let simd = D == 3 && !FAR && self.v3;
        #[cfg(not(target_arch = "x86_64"))]
        let simd = false;
        if EXTRAS && self.steps.is_some() {
            let steps = self.steps.as_deref().expect("a stepped simulation");
            if simd && steps.uniform.is_some() {
                // Four neighbours at a time, bit-identical to the scan below (`steps_x86.rs`).
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `v3` is only set when the processor has AVX2 (`set_portable_loop`).
                #[allow(unsafe_code)]
                unsafe {
                    super::steps_x86::scan(&self.body, steps, i, t0, &mut nearest)
                };
            } else {
                super::steps::scan_stepped::<D, FAR>(
                    &self.body,
                    &self.species,
                    steps,
                    i,
                    t0,
                    &mut nearest,
                );
            }
        } else if simd {
            // Four candidates at a time, bit-identical to the scan below (`scan_x86.rs`).
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `v3` is only set when the processor has AVX2 (`set_portable_loop`).
            #[allow(unsafe_code)]
            unsafe {
                super::scan_x86::scan(
                    &self.grid,
                    c,
                    &self.body,
                    i,
                    t0,
                    &mut nearest,
                    &mut self.batch,
                )
            };
        } else {
            let mut scan = Candidates::<D, FAR> {
                body: &self.body,
                t0,
                pos,
                vel,
                radius,
                nearest,
            };
            if D == 3 {
                // The scan that works out the neighbour cells near the grid's edges once per
                // axis (a third of the cells at N = 4000 touch an edge; BENCHMARKS.md). In 2D
                // the plain scan is kept as it was measured.
                self.grid.visit_near_edges_once(c, &mut scan);
            } else {
                self.grid.visit_near(c, &mut scan);
            }
            nearest = scan.nearest;
        }
        let settled = nearest.settle();
        self.schedule(i, best, settled);
    }

    /// Schedules disc `i`'s earliest event: the pair the scan `settled` on, if any, else its
    /// own event `own` (which, in 3D, stands second behind a pair when no second pair did).
    #[inline(always)]
    pub(super) fn schedule(&mut self, i: usize, own: Pending, settled: (f64, u32, f64, u32)) {
        let (best_t, partner, second_t, second_partner) = settled;
        let mut best = own;
        if partner != NO_PARTNER {
            best = Pending::Disc {
                partner,
                seen: self.body[partner as usize].count,
            };
            if D == 3 {
                let second = if second_partner != NO_PARTNER {
                    Pending::Disc {
                        partner: second_partner,
                        seen: self.body[second_partner as usize].count,
                    }
                } else {
                    own
                };
                self.second[i] = (second_t, second);
            }
        } else if D == 3 {
            self.second[i] = (f64::INFINITY, Pending::Nothing);
        }
        self.body[i].pending = best;
        self.queue.set(i, best_t);
    }
}

impl<const D: usize> Simulation<D> {
    /// [`Self::predict`] in a field (see `field.rs`): the disc advanced along its parabola, its
    /// own events from [`Self::own_event_in_field`], and the candidates of the grid's scan at
    /// their positions and velocities now (their relative motion is straight: the field
    /// cancels from it). Inlined into the extras' copies of the loop only (the hard cores'
    /// never come here), so that the x86-64-v3 copy compiles it for its instruction set: an
    /// outlined copy was the baseline's, 8% more instructions per event in a 2D column.
    #[inline(always)]
    fn predict_in_field<const FAR: bool>(&mut self, i: usize) {
        let t0 = self.event_time;
        let f = self.gravity.expect("a field");
        self.body[i].advance_in(t0, Some(f));
        let (pos, vel, radius) = {
            let b = &self.body[i];
            (b.pos, b.vel, b.radius)
        };
        let (best_t, best) = self.own_event_in_field(i, t0, pos, vel, f);
        let nearest = Nearest::new(t0, best_t, &mut self.kept);
        let c = self.grid.cell_of(i);
        let mut scan = FieldCandidates::<D, FAR> {
            body: &self.body,
            field: f,
            t0,
            pos,
            vel,
            radius,
            nearest,
        };
        if D == 3 {
            // As the hard cores' scalar scan: the neighbour cells near the grid's edges
            // worked out once per axis.
            self.grid.visit_near_edges_once(c, &mut scan);
        } else {
            self.grid.visit_near(c, &mut scan);
        }
        let settled = scan.nearest.settle();
        self.schedule(i, best, settled);
    }
}

/// [`Candidates`] in a field: each candidate at its position and velocity at `t0`.
struct FieldCandidates<'a, const D: usize, const FAR: bool> {
    body: &'a [Body<D>],
    field: Gravity,
    t0: f64,
    pos: Vector<D>,
    vel: Vector<D>,
    radius: f64,
    nearest: Nearest<'a>,
}

impl<const D: usize, const FAR: bool> Visit<D> for &mut FieldCandidates<'_, D, FAR> {
    #[inline(always)]
    fn visit(&mut self, j: usize, shift: Vector<D>) {
        let bj = &self.body[j];
        let f = Some(self.field);
        let pj = bj.position_in(self.t0, f) + shift;
        let vj = bj.velocity_in(self.t0, f);
        self.nearest.offer(
            j,
            contact_terms::<D, FAR>(pj - self.pos, vj - self.vel, self.radius + bj.radius),
        );
    }
}

/// A prediction's scan of the discs around the disc predicted (at `pos` at `t0`, moving at
/// `vel`): each candidate's contact terms go to [`Nearest`].
struct Candidates<'a, const D: usize, const FAR: bool> {
    body: &'a [Body<D>],
    t0: f64,
    pos: Vector<D>,
    vel: Vector<D>,
    radius: f64,
    nearest: Nearest<'a>,
}

impl<const D: usize, const FAR: bool> Visit<D> for &mut Candidates<'_, D, FAR> {
    #[inline(always)]
    fn visit(&mut self, j: usize, shift: Vector<D>) {
        let bj = &self.body[j];
        let pj = bj.position_at(self.t0) + shift;
        // Disc `i` itself is at `dr = 0` (or a whole box length: a periodic image), with
        // `dv = 0`, which never meets (`b = 0`): no test needed.
        self.nearest.offer(
            j,
            contact_terms::<D, FAR>(pj - self.pos, bj.vel - self.vel, self.radius + bj.radius),
        );
    }
}

/// How many meeting candidates [`Nearest`] keeps before it works out their contact times: a
/// power of two, larger than a dense fluid's candidates per prediction (about 25 in 3D).
const KEPT: usize = 32;

/// The earliest contact among a prediction's candidates, found in two passes: the candidates'
/// contact terms as they come ([`Self::offer`]), then the roots of those that meet
/// ([`Self::settle`]), in the order offered, so that the first found wins a tie.
pub(super) struct Nearest<'a> {
    t0: f64,
    best_t: f64,
    partner: u32,
    second_t: f64,
    second: u32,
    kept: usize,
    store: &'a mut Kept,
}

/// The candidates [`Nearest`] keeps: scratch space that lives with the simulation, so that a
/// prediction does not clear it.
#[derive(Clone, Debug)]
pub(super) struct Kept {
    terms: [ContactTerms; KEPT],
    which: [u32; KEPT],
}

impl Default for Kept {
    fn default() -> Self {
        Kept {
            terms: [ContactTerms::default(); KEPT],
            which: [0; KEPT],
        }
    }
}

impl<'a> Nearest<'a> {
    /// No candidate yet, the earliest event so far at `best_t`.
    #[inline(always)]
    pub(super) fn new(t0: f64, best_t: f64, store: &'a mut Kept) -> Self {
        Nearest {
            t0,
            best_t,
            partner: NO_PARTNER,
            second_t: f64::INFINITY,
            second: NO_PARTNER,
            kept: 0,
            store,
        }
    }

    /// Candidate `j` with its contact terms: kept if the pair meets, by moving the end of the
    /// kept list past it (no branch).
    #[inline(always)]
    pub(super) fn offer(&mut self, j: usize, terms: ContactTerms) {
        let k = self.kept & (KEPT - 1);
        self.store.terms[k] = terms;
        self.store.which[k] = j as u32;
        self.kept = k + terms.meets() as usize;
        if self.kept == KEPT {
            self.roots();
        }
    }

    /// The kept candidates' contact times, the earliest taken ([`Self::take`]); empties the
    /// list.
    #[inline(always)]
    fn roots(&mut self) {
        for k in 0..self.kept.min(KEPT) {
            let t = self.t0 + contact_root(self.store.terms[k]);
            self.take(t, self.store.which[k]);
        }
        self.kept = 0;
    }

    /// Candidate `w`'s contact time `t`, kept if it is the earliest so far or the second,
    /// without branches (strict `<` keeps the first found on ties).
    #[inline(always)]
    pub(super) fn take(&mut self, t: f64, w: u32) {
        let keep = ((t < self.best_t) as u32).wrapping_neg();
        let next = ((t < self.second_t) as u32).wrapping_neg();
        // The second: the old best if `t` beats it, else `t` if it beats the second.
        self.second = (self.partner & keep) | (!keep & ((w & next) | (self.second & !next)));
        // Times are never NaN, so `min` and `max` need not look for one (`f64::min` does, at
        // two more instructions on the chain from one candidate to the next).
        self.second_t = least(self.second_t, greatest(self.best_t, t));
        self.partner = (w & keep) | (self.partner & !keep);
        self.best_t = least(self.best_t, t);
    }

    /// The earliest event's time so far.
    #[inline(always)]
    pub(super) fn best_t(&self) -> f64 {
        self.best_t
    }

    /// The earliest time and its partner (`NO_PARTNER` if no pair beats the time given to
    /// [`Self::new`]).
    #[inline(always)]
    pub(super) fn settle(mut self) -> (f64, u32, f64, u32) {
        self.roots();
        (self.best_t, self.partner, self.second_t, self.second)
    }
}

/// The lesser of two times that are not NaN (either if equal: they are the same time).
#[inline(always)]
fn least(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

/// The greater of two times that are not NaN.
#[inline(always)]
fn greatest(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// Whether a candidate of the grid's scan can be farther than `sqrt(FAR_CONTACT_RATIO2)`
/// contact distances (the smallest, `min_diameter`) from the disc predicted: it lies at most
/// two cells away along each axis. Then the contact times are computed in the far form
/// (`predict/disc_disc.rs`): the textbook form would find such pairs late by about
/// `eps (reach / sigma)^2` of the contact distance.
pub(super) fn far_contacts<const D: usize>(
    grid: &CellGrid<D>,
    sim_box: &SimBox<D>,
    min_diameter: f64,
) -> bool {
    let dims = grid.dims();
    let reach2: f64 = (0..D)
        .map(|a| (2.0 * sim_box.lengths[a] / f64::from(dims[a])).powi(2))
        .sum();
    reach2 > FAR_CONTACT_RATIO2 * min_diameter * min_diameter
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::predict::contact_time;

    /// The contact terms of a pair drawn from `state` (a small LCG): relative positions within
    /// 1.5 contact distances along each axis, relative velocities up to 2, so that many meet.
    fn random_terms(state: &mut u64) -> ContactTerms {
        let mut next = || {
            *state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (*state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let dr = Vector::new([1.5 * next(), 1.5 * next(), 1.5 * next()]);
        let dv = Vector::new([2.0 * next(), 2.0 * next(), 2.0 * next()]);
        contact_terms::<3, false>(dr, dv, 1.0)
    }

    /// What `Nearest` replaces: every contact time computed, the event already found
    /// (`best_t`, no partner) and the pairs that meet sorted by time in the order found (a
    /// stable sort, so the first found wins a tie), and the first two taken.
    fn plainly(t0: f64, best_t: f64, terms: &[ContactTerms]) -> (f64, u32, f64, u32) {
        let mut all = vec![(best_t, NO_PARTNER)];
        for (j, &tm) in terms.iter().enumerate() {
            if tm.meets() {
                all.push((t0 + contact_root(tm), j as u32));
            }
        }
        all.push((f64::INFINITY, NO_PARTNER));
        all.sort_by(|a, b| a.0.total_cmp(&b.0));
        (all[0].0, all[0].1, all[1].0, all[1].1)
    }

    #[test]
    fn nearest_finds_the_earliest_pair_past_a_full_buffer() {
        // 1000 candidates in a prediction: the kept list fills (`KEPT`) and is emptied many
        // times, as around a large disc among many small ones.
        let mut state = 7;
        for n in [0, 1, 5, KEPT - 1, KEPT, KEPT + 1, 3 * KEPT, 1000] {
            let terms: Vec<ContactTerms> = (0..n).map(|_| random_terms(&mut state)).collect();
            let meeting = terms.iter().filter(|t| t.meets()).count();
            if n == 1000 {
                assert!(meeting > 3 * KEPT, "{meeting} of {n} meet");
            }
            for best_t in [f64::INFINITY, 2.0, 0.5] {
                let mut kept = Kept::default();
                let mut nearest = Nearest::new(1.0, best_t, &mut kept);
                for (j, &t) in terms.iter().enumerate() {
                    nearest.offer(j, t);
                }
                assert_eq!(nearest.settle(), plainly(1.0, best_t, &terms), "n {n}");
            }
        }
    }

    #[test]
    fn nearest_keeps_the_first_of_a_tie_and_agrees_with_the_kernel() {
        let mut state = 11;
        let mut terms: Vec<ContactTerms> = (0..200).map(|_| random_terms(&mut state)).collect();
        let (_, winner, _, _) = plainly(0.0, f64::INFINITY, &terms);
        assert_ne!(winner, NO_PARTNER);
        // The winning pair offered again at the end, after several full buffers: an exact tie.
        terms.push(terms[winner as usize]);
        let mut kept = Kept::default();
        let mut nearest = Nearest::new(0.0, f64::INFINITY, &mut kept);
        for (j, &t) in terms.iter().enumerate() {
            nearest.offer(j, t);
        }
        assert_eq!(nearest.settle().1, winner, "a tie goes to the first found");
        // Against the one-pass kernel on vectors: dr = (2, 0.5, 0), closing at 1 along x,
        // sigma 1: contact at x = sqrt(1 - 0.25), t = 2 - sqrt(0.75).
        let dr = Vector::new([2.0, 0.5, 0.0]);
        let dv = Vector::new([-1.0, 0.0, 0.0]);
        let mut kept = Kept::default();
        let mut nearest = Nearest::new(0.0, f64::INFINITY, &mut kept);
        nearest.offer(4, contact_terms::<3, false>(dr, dv, 1.0));
        let (t, partner, second_t, _) = nearest.settle();
        assert_eq!((t, partner), (contact_time::<3, false>(dr, dv, 1.0), 4));
        assert_eq!(second_t, f64::INFINITY);
        assert!((t - (2.0 - 0.75f64.sqrt())).abs() < 1e-15, "{t}");
    }
}
