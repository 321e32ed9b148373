//! The event loop: the queue's front event, stale events, and the handlers that change the
//! state (pair collisions, walls, cell crossings). See the parent module for the flow.

use crate::events::{EventKind, EventRecord, Pending, Side, Wall};
use crate::hint::prefetch;
use crate::math::Vector;
use crate::observer::Observer;
use crate::resolve::wall::reflect;
use crate::schedule::EventQueue;

use super::{Body, Simulation, NO_DISC};

/// Whether this processor runs the event loop compiled for x86-64-v3 (AVX, AVX2, FMA, BMI1,
/// BMI2, LZCNT, POPCNT, MOVBE; checked once). Always false off x86-64.
pub fn x86_64_v3_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        x86_64_v3()
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
}

#[cfg(target_arch = "x86_64")]
fn x86_64_v3() -> bool {
    use std::sync::OnceLock;
    static HAS: OnceLock<bool> = OnceLock::new();
    *HAS.get_or_init(|| {
        std::is_x86_feature_detected!("avx")
            && std::is_x86_feature_detected!("avx2")
            && std::is_x86_feature_detected!("fma")
            && std::is_x86_feature_detected!("bmi1")
            && std::is_x86_feature_detected!("bmi2")
            && std::is_x86_feature_detected!("lzcnt")
            && std::is_x86_feature_detected!("popcnt")
            && std::is_x86_feature_detected!("movbe")
    })
}

impl<const D: usize> Simulation<D> {
    /// Time of the next event that would be processed (`None` if nothing will ever happen).
    /// Stale events are resolved first, so this may update the schedule.
    pub fn next_event_time(&mut self) -> Option<f64> {
        loop {
            let (i, t) = self.queue.min()?;
            if !t.is_finite() {
                return None;
            }
            let stale = if self.has_extras() {
                self.discard_if_stale::<true>(i)
            } else {
                self.discard_if_stale::<false>(i)
            };
            if stale {
                continue;
            }
            return Some(t);
        }
    }

    /// Processes every event with time `<= t_end`, showing each to `observer`, then sets the
    /// current time to `t_end` (if later). Discs are not moved by this last step: positions are
    /// computed on demand, so stopping at intermediate times never changes the trajectory.
    ///
    /// If the clock stops advancing (more than [`Self::stall_limit`] events in a row at one
    /// time), the run stops there instead, the clock stays at that time and
    /// [`Self::stalled`] says why; check it after running.
    pub fn run_until<O: Observer<D>>(&mut self, t_end: f64, observer: &mut O) {
        self.run_loop(t_end, u64::MAX, observer);
        if t_end > self.now && self.stall.is_none() {
            self.now = t_end;
        }
    }

    /// Processes up to `n` events (cell crossings included) regardless of time, showing each to
    /// `observer`. Returns how many were processed (fewer only if nothing will ever happen, or
    /// the clock stopped advancing: [`Self::stalled`]).
    pub fn run_events<O: Observer<D>>(&mut self, n: u64, observer: &mut O) -> u64 {
        self.run_loop(f64::INFINITY, n, observer)
    }

    /// Processes up to `n` events with time `<= t_limit`, showing each to `observer`, without
    /// moving the clock on to `t_limit` afterwards (as [`Self::run_until`] does). Returns how
    /// many were processed (fewer if the next event is later than `t_limit`, nothing will ever
    /// happen, or the clock stopped advancing: [`Self::stalled`]). For running in slices, for
    /// example to watch for Ctrl-C.
    pub fn run_events_to<O: Observer<D>>(&mut self, t_limit: f64, n: u64, observer: &mut O) -> u64 {
        self.run_loop(t_limit, n, observer)
    }

    /// Processes up to `n` events with time `<= t_limit`; returns how many. Runs the loop in
    /// the stall watcher's chunks of `STALL_CHUNK` events and looks at the clock between chunks, so that a
    /// run whose clock stops advancing stops (`stall.rs`) at no cost per event.
    pub(super) fn run_loop<O: Observer<D>>(
        &mut self,
        t_limit: f64,
        n: u64,
        observer: &mut O,
    ) -> u64 {
        let mut done = 0;
        while done < n && self.stall.is_none() {
            let k = (n - done).min(self.chunk_room());
            let got = self.run_chunk(t_limit, k, observer);
            done += got;
            if self.count_events(got).is_some() {
                self.stall_seen(t_limit, observer);
            }
            if got < k {
                break;
            }
        }
        done
    }

    /// Processes up to `n` events with time `<= t_limit`; returns how many.
    ///
    /// On x86-64 processors with the x86-64-v3 instruction set (AVX2, FMA, BMI: most x86-64
    /// processors made since about 2015, though not Atom-class ones and not every Pentium or
    /// Celeron) the loop runs in a copy compiled for it, chosen at run time:
    /// 3-operand instructions make it about 10% faster (BENCHMARKS.md). Both copies are the
    /// same Rust code and give bit-identical results: Rust never fuses a multiply and an add
    /// by itself, so the extra instructions change nothing but speed.
    fn run_chunk<O: Observer<D>>(&mut self, t_limit: f64, n: u64, observer: &mut O) -> u64 {
        if self.multi.is_some() {
            return self.run_loop_watched(t_limit, n, observer);
        }
        // The interaction (and a thermostat) is a parameter of the loop, chosen here once per
        // chunk: hard cores alone run a copy with no trace of steps or redraws, and hard cores
        // with reaction rules alone a copy that differs only in its pair events (its
        // predictions are the hard cores': the extras' copy cost 12% more per collision in 2D
        // at N = 10^4).
        let extras = self.needs_extras();
        let react = !extras && self.has_rule();
        #[cfg(target_arch = "x86_64")]
        if self.v3 {
            // SAFETY: `run_loop_v3` only needs the processor features, and `v3` is only set
            // when `x86_64_v3` has found them (`set_portable_loop`).
            #[allow(unsafe_code)]
            return unsafe {
                if extras {
                    self.run_loop_v3::<O, true, false>(t_limit, n, observer)
                } else if react {
                    self.run_loop_v3::<O, false, true>(t_limit, n, observer)
                } else {
                    self.run_loop_v3::<O, false, false>(t_limit, n, observer)
                }
            };
        }
        if extras {
            self.run_loop_inline::<O, true, false>(t_limit, n, observer)
        } else if react {
            self.run_loop_inline::<O, false, true>(t_limit, n, observer)
        } else {
            self.run_loop_inline::<O, false, false>(t_limit, n, observer)
        }
    }

    /// [`Self::run_chunk`] compiled for x86-64-v3.
    ///
    /// # Safety
    /// The processor must have the features named here ([`x86_64_v3`] checks them).
    #[cfg(target_arch = "x86_64")]
    #[allow(unsafe_code)]
    #[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
    unsafe fn run_loop_v3<O: Observer<D>, const EXTRAS: bool, const REACT: bool>(
        &mut self,
        t_limit: f64,
        n: u64,
        observer: &mut O,
    ) -> u64 {
        self.run_loop_inline::<O, EXTRAS, REACT>(t_limit, n, observer)
    }

    /// The event loop, for hard cores alone, or (`EXTRAS`) with a stepped potential, a
    /// thermostat, a field, reaction rules or restitution, or (`REACT`) with reaction rules or
    /// restitution alone.
    #[inline(always)]
    pub(super) fn run_loop_inline<O: Observer<D>, const EXTRAS: bool, const REACT: bool>(
        &mut self,
        t_limit: f64,
        n: u64,
        observer: &mut O,
    ) -> u64 {
        for k in 0..n {
            match self.step_inline::<EXTRAS, REACT>(t_limit) {
                Some(e) => observer.on_event(&e, self),
                None => return k,
            }
        }
        n
    }

    /// The loop for multi-disc collisions, which can give a cluster up and stop the run
    /// (`StallCause::Cluster`): it looks for that after each event, so that a run stops at the
    /// cluster whatever the size of its chunks. The other loops have no such check per event;
    /// multi-disc collisions are for demonstrations, where speed matters less.
    #[inline(never)]
    fn run_loop_watched<O: Observer<D>>(&mut self, t_limit: f64, n: u64, observer: &mut O) -> u64 {
        for k in 0..n {
            // Multi-disc collisions are refused with a stepped potential.
            match self.step_inline::<false, false>(t_limit) {
                Some(e) => {
                    observer.on_event(&e, self);
                    if self.stall.is_some() {
                        return k + 1;
                    }
                }
                None => return k,
            }
        }
        n
    }

    /// Whether the loop must run its copy with steps, redraws, reactions and restitution (the
    /// one-event paths; `run_chunk` gives reactions or restitution alone a copy of their own).
    #[inline(always)]
    pub(super) fn has_extras(&self) -> bool {
        self.needs_extras() || self.has_rule()
    }

    /// Whether the chunks must run the extras' copy of the loop: a stepped potential, a
    /// thermostat or a field (reactions or restitution alone have a copy of their own).
    #[inline(always)]
    fn needs_extras(&self) -> bool {
        self.steps.is_some()
            || self.bath.is_some()
            || self.gravity.is_some()
            || self.shear.is_some()
            || self.sheets.is_some()
            || self.ring.is_some()
    }

    /// Whether collisions follow a rule other than the hard cores' elastic one: reactions or
    /// restitution.
    #[inline(always)]
    pub(super) fn has_rule(&self) -> bool {
        self.chemistry.is_some() || self.dissipation.is_some()
    }

    /// Chooses the portable event loop (`true`) even where the processor runs the faster
    /// x86-64-v3 copy, which is the default there. Results are bit-identical either way; this
    /// is for tests and benchmarks. Returns whether the x86-64-v3 copy is in use.
    pub fn set_portable_loop(&mut self, portable: bool) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            self.v3 = !portable && x86_64_v3();
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = portable;
        self.v3
    }

    /// Processes the next event if its time is `<= t_limit` and returns it. Returns `None`
    /// without processing anything once the clock has stopped advancing ([`Self::stalled`]),
    /// which is counted here event by event.
    pub fn step(&mut self, t_limit: f64) -> Option<EventRecord<D>> {
        if self.stall.is_some() {
            return None;
        }
        let e = if self.has_extras() {
            self.step_inline::<true, false>(t_limit)?
        } else {
            self.step_inline::<false, false>(t_limit)?
        };
        if let Some(cause) = self.count_events(1) {
            self.stall_pending(cause);
        }
        Some(e)
    }

    #[inline(always)]
    pub(super) fn step_inline<const EXTRAS: bool, const REACT: bool>(
        &mut self,
        t_limit: f64,
    ) -> Option<EventRecord<D>> {
        loop {
            let (i, t) = self.queue.min()?;
            // Times are never NaN: `+inf` is "nothing ahead".
            if t > t_limit || t == f64::INFINITY {
                return None;
            }
            if EXTRAS && self.steps.is_some() {
                self.prefetch_upcoming_listed();
            } else {
                self.prefetch_upcoming();
            }
            if self.discard_if_stale::<EXTRAS>(i) {
                continue;
            }
            self.event_time = t;
            self.now = t;
            if EXTRAS && (self.gravity.is_some() || self.sheets.is_some() || self.ring.is_some()) {
                self.advance_in_field(i, t);
            }
            // The handlers change the state; the discs whose course changed (or whose cell
            // did) are predicted again here, in one place rather than in every handler, so
            // that each copy of the loop inlines the prediction twice (here and for stale
            // events) instead of six times.
            let (record, again) = match self.body[i].pending {
                Pending::Disc { partner, .. } if EXTRAS && self.steps.is_some() => {
                    self.collide_stepped(i, partner as usize, t)
                }
                Pending::Disc { partner, .. } if EXTRAS && self.shear.is_some() => {
                    self.collide_sheared(i, partner as usize, t)
                }
                Pending::Disc { partner, .. } if (REACT || EXTRAS) && self.has_rule() => {
                    if self.dissipation.is_some() {
                        self.collide_inelastic(i, partner as usize, t)
                    } else {
                        self.collide_reactive(i, partner as usize, t)
                    }
                }
                Pending::Disc { partner, .. } => self.collide(i, partner as usize, t),
                Pending::Wall { axis, side } if (REACT || EXTRAS) && self.dissipation.is_some() => {
                    (
                        self.bounce_inelastic(i, axis as usize, side, t),
                        [i, NO_DISC],
                    )
                }
                Pending::Wall { axis, side } => {
                    (self.bounce(i, axis as usize, side, t), [i, NO_DISC])
                }
                Pending::Cell { axis, side } if EXTRAS && self.shear.is_some() => {
                    (self.cross_sheared(i, axis as usize, side, t), [i, NO_DISC])
                }
                Pending::Cell { axis, side } => {
                    (self.cross(i, axis as usize, side, t), [i, NO_DISC])
                }
                Pending::Barrier { index, part } => {
                    (self.meet_barrier(i, index as usize, part, t), [i, NO_DISC])
                }
                Pending::Thermostat => (self.redraw(i, t), [i, NO_DISC]),
                Pending::Relist if EXTRAS => (self.relist(i, t), [i, NO_DISC]),
                Pending::Slide if EXTRAS => (self.slide(i, t), [i, NO_DISC]),
                Pending::Refile | Pending::Recheck if EXTRAS => (self.refile(i, t), [i, NO_DISC]),
                // Only a stepped potential (`EXTRAS`) has neighbour lists, and only shear
                // (`EXTRAS`) slides.
                Pending::Nothing
                | Pending::Relist
                | Pending::Slide
                | Pending::Refile
                | Pending::Recheck => {
                    unreachable!("finite time with nothing pending")
                }
            };
            for d in again {
                if d != NO_DISC {
                    self.predict::<EXTRAS>(d);
                }
            }
            return Some(record);
        }
    }

    /// In a field, advances disc `i` and its partner, if its event has one, along their
    /// parabolas to the event at `t`: the handlers then advance them by nothing, as if their
    /// flights were straight.
    #[inline(never)]
    fn advance_in_field(&mut self, i: usize, t: f64) {
        if let Some(o) = self.ring.as_deref() {
            if let Pending::Disc { partner, .. } = self.body[i].pending {
                self.body[partner as usize].advance_on_orbit(t, o);
            }
            self.body[i].advance_on_orbit(t, o);
            return;
        }
        if let Pending::Disc { partner, .. } = self.body[i].pending {
            let field = self.flight(partner as usize);
            self.body[partner as usize].advance_in(t, field);
        }
        let field = self.flight(i);
        self.body[i].advance_in(t, field);
    }

    /// Starts loading what the next events will read, so that memory latency overlaps with the
    /// work of this one (BENCHMARKS.md: 1.2 to 1.6 M collisions/s at N = 10^5). A pipeline
    /// over the next three discs in the queue, each stage needing what the one before
    /// requested an event earlier: the third disc's record and cell; the second disc's
    /// partner's record and cell, the two masses, in 3D the second disc's second event, and
    /// the list heads of its neighbourhood (in 3D the cells' first four); the first disc in each cell
    /// around the next disc. Hints only: nothing here changes the results.
    #[inline(always)]
    pub(super) fn prefetch_upcoming(&self) {
        let mut up = self.queue.upcoming();
        let (Some(k1), k2, k3) = (up.next(), up.next(), up.next()) else {
            return;
        };
        if let Some(k3) = k3 {
            self.prefetch_record(k3);
            self.grid.prefetch_cell_of(k3);
        }
        if let Some(k2) = k2 {
            if let Pending::Disc { partner, .. } = self.body[k2].pending {
                self.prefetch_record(partner as usize);
                // The masses, read by the collision rule, and the partner's cell, read by
                // its prediction.
                prefetch(&self.mass[k2]);
                prefetch(&self.mass[partner as usize]);
                self.grid.prefetch_cell_of(partner as usize);
                if D == 3 {
                    // The second event, read if this one has gone stale.
                    prefetch(&self.second[k2]);
                }
            }
            self.grid.prefetch_heads_around(k2);
        }
        // An empty cell gives `NONE`, clamped to some disc: cheaper than a branch.
        let last = (self.body.len() as u32).saturating_sub(1);
        self.grid
            .prefetch_first_around(k1, |j| self.prefetch_record(j.min(last) as usize));
    }

    /// [`Self::prefetch_upcoming`] under a stepped potential, whose predictions read the
    /// discs' neighbour lists rather than the grid. A pipeline as there: the third disc's
    /// record and list; the second disc's list and its partner's record and list; the records
    /// of the first disc's neighbours. Hints only.
    #[inline(always)]
    fn prefetch_upcoming_listed(&self) {
        let steps = self.steps.as_deref().expect("a stepped simulation");
        let mut up = self.queue.upcoming();
        let (Some(k1), k2, k3) = (up.next(), up.next(), up.next()) else {
            return;
        };
        // A list's row is found from the disc alone: its first three lines (the length and
        // 23 neighbours) asked for at once.
        let row = |k: usize| {
            let row = steps.near.row(k);
            for e in row.iter().step_by(8).take(3) {
                prefetch(e);
            }
        };
        if let Some(k3) = k3 {
            self.prefetch_record(k3);
            row(k3);
            // The list centre, read by the prediction (the list's departure).
            prefetch(&steps.centre[k3]);
        }
        if let Some(k2) = k2 {
            row(k2);
            if let Pending::Disc { partner, .. } = self.body[k2].pending {
                let p = partner as usize;
                self.prefetch_record(p);
                row(p);
                prefetch(&steps.centre[p]);
                // The masses, read at the event, and the second event, read if this one
                // has gone stale.
                prefetch(&self.mass[k2]);
                prefetch(&self.mass[p]);
                if D == 3 {
                    prefetch(&self.second[k2]);
                }
            }
        }
        for &(j, _) in steps.near.get(k1) {
            prefetch(&self.body[j as usize]);
        }
    }

    /// Prefetches disc `i`'s record: its first line and, in 3D, where an 80-byte record
    /// can straddle two lines, the line its end is in.
    #[inline(always)]
    fn prefetch_record(&self, i: usize) {
        let b = &self.body[i];
        prefetch(b);
        if size_of::<Body<D>>() > 64 {
            prefetch(&b.pending);
        }
    }

    /// If disc `i`'s pending event names a partner that has changed course since, schedules
    /// `i`'s next event and returns true. In 3D that is the second-earliest event of `i`'s last
    /// prediction when it kept one, without a scan: `i` has not changed course since, the
    /// partner's new course was checked against `i` when the partner was predicted again, and
    /// every other disc that changed course since was too; the rest were seen by `i`'s
    /// prediction, none before the second event (BENCHMARKS.md). Otherwise
    /// (2D, whose trajectories stay as they were, or no second event) `i` is predicted again.
    #[inline(always)]
    pub(super) fn discard_if_stale<const EXTRAS: bool>(&mut self, i: usize) -> bool {
        if let Pending::Disc { partner, seen } = self.body[i].pending {
            if self.body[partner as usize].count != seen {
                self.stats.stale = self.stats.stale.wrapping_add(1);
                // Taken, so that a second stale event predicts afresh.
                let (t2, second) = if D == 3 {
                    std::mem::replace(&mut self.second[i], (f64::INFINITY, Pending::Nothing))
                } else {
                    (f64::INFINITY, Pending::Nothing)
                };
                if second != Pending::Nothing {
                    self.body[i].pending = second;
                    self.queue.set(i, t2);
                } else {
                    self.predict::<EXTRAS>(i);
                }
                return true;
            }
        }
        false
    }

    /// Resolves the collision of `i` and `j`; returns the record and the discs to predict
    /// again ([`NO_DISC`] for none).
    #[inline(always)]
    pub(super) fn collide(&mut self, i: usize, j: usize, t: f64) -> (EventRecord<D>, [usize; 2]) {
        self.body[i].advance_to(t);
        self.body[j].advance_to(t);
        if let Some(mc) = self.multi {
            self.last_cluster.clear();
            if let Some(record) = self.collide_cluster(i, j, t, mc) {
                return (record, [NO_DISC; 2]);
            }
        }
        let dr = self
            .sim_box
            .minimum_image(self.body[j].pos - self.body[i].pos);
        let out = self.rule.resolve(
            dr,
            self.body[i].vel,
            self.body[j].vel,
            self.mass[i],
            self.mass[j],
        );
        self.body[i].vel = out.vi;
        self.body[j].vel = out.vj;
        self.body[i].count = self.body[i].count.wrapping_add(1);
        self.body[j].count = self.body[j].count.wrapping_add(1);
        self.stats.disc_disc = self.stats.disc_disc.wrapping_add(1);
        let record = EventRecord {
            time: t,
            kind: EventKind::DiscDisc { i, j },
            impulse: out.impulse,
        };
        (record, [i, j])
    }

    #[inline(always)]
    pub(super) fn bounce(&mut self, i: usize, axis: usize, side: Side, t: f64) -> EventRecord<D> {
        let b = &mut self.body[i];
        b.advance_to(t);
        // Exactly at contact, as the course text asks (x = R or x = Lx - R).
        b.pos[axis] = match side {
            Side::Low => b.radius,
            Side::High => self.sim_box.lengths[axis] - b.radius,
        };
        let impulse = reflect(&mut b.vel, axis, self.mass[i]);
        b.count = b.count.wrapping_add(1);
        self.stats.wall = self.stats.wall.wrapping_add(1);
        EventRecord {
            time: t,
            kind: EventKind::Wall {
                i,
                wall: Wall { axis, side },
            },
            impulse,
        }
    }

    #[inline(always)]
    pub(super) fn cross(&mut self, i: usize, axis: usize, side: Side, t: f64) -> EventRecord<D> {
        self.body[i].advance_to(t);
        let wrap = self.grid.cross(i, axis, side);
        if wrap != 0 {
            self.body[i].pos[axis] += wrap as f64 * self.sim_box.lengths[axis];
            self.image.add(i, axis, -wrap);
        }
        self.stats.cell_crossing = self.stats.cell_crossing.wrapping_add(1);
        EventRecord {
            time: t,
            kind: EventKind::CellCrossing { i, axis, side },
            impulse: Vector::ZERO,
        }
    }
}
