//! A calendar queue (R. Brown 1988; for EDMD, G. Paul, J. Comput. Phys. 221 (2007) 615): time
//! is cut into buckets of equal width, each an unsorted singly linked list of the discs whose
//! event falls in it, and only the current bucket is kept sorted. Setting a disc's time is
//! O(1) (unlink, link), where a binary tree replays O(log N) matches; the minimum is the end of
//! the sorted current bucket.
//!
//! `M` buckets (a power of two, about `N` in the engine) cover the times ahead cyclically;
//! events beyond them wait in the overflow and are put in their buckets when the calendar
//! comes round.
//! The width is chosen from the times in the queue so that a bucket holds a few events, and is
//! chosen again whenever the calendar comes round with buckets far too full or too empty, or
//! when the current bucket grows far too long (at most once per N updates; then no wider than
//! makes that bucket hold a few, as a crowded front behind a far tail needs).
//!
//! Bucket numbers are `floor((t - origin) / width)`, a monotone function of `t` under rounding,
//! so an earlier event is never in a later bucket, and equal times share a bucket, where they
//! are sorted by disc index: the engine's tie rule holds exactly.
//!
//! Each disc costs 12 bytes and a bucket 4: its time and one link, which also says where the
//! disc is. A disc in a bucket's list finds its bucket again from its time (the same
//! arithmetic as when it was filed, and the width and origin change only when every disc is
//! filed again), so the lists need no back links: taking a disc out walks its bucket's few
//! entries from the head. The overflow is not a list: the discs in it are found by a pass over
//! the links when the calendar comes round, once in about `M` buckets' worth of events.

use super::EventQueue;
use crate::hint::filled;

/// `next` of a disc in the sorted current bucket.
const CURRENT: u32 = u32::MAX;
/// `next` of a disc in the overflow.
const OVERFLOW: u32 = u32::MAX - 1;
/// End of a bucket's list (and the head of an empty bucket).
const END: u32 = u32::MAX - 2;
/// Discs a queue can hold: every index is below [`END`].
pub const MAX_LEN: usize = END as usize;
/// Events per bucket the width aims at.
const PER_BUCKET: f64 = 3.0;
/// A current bucket longer than this makes the queue re-tune its width.
const OVERFULL: usize = 64;

/// Calendar queue over per-disc event times.
#[derive(Clone, Debug)]
pub struct CalendarQueue {
    time: Vec<f64>,
    /// The next disc in the same bucket's list or [`END`]; or [`CURRENT`] or [`OVERFLOW`].
    next: Vec<u32>,
    /// First disc of each bucket's list.
    head: Vec<u32>,
    /// The current bucket, sorted by decreasing `(time, disc)`: the minimum is last.
    current: Vec<(f64, u32)>,
    /// Absolute number of the current bucket.
    cur: u64,
    origin: f64,
    inv_width: f64,
    /// Discs in buckets (not counting the current one or the overflow).
    in_buckets: usize,
    /// Buckets opened and discs taken from them since the calendar last came round.
    opened: u64,
    taken: u64,
    /// Between [`EventQueue::begin_bulk`] and [`EventQueue::end_bulk`]: `set` only records.
    bulk: bool,
    /// Updates since the last rebuild.
    sets: u64,
}

impl CalendarQueue {
    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.time.capacity() * 8
            + self.next.capacity() * 4
            + self.head.capacity() * 4
            + self.current.capacity() * 16
    }

    /// The discs whose events come after the front one, nearest first, as far as the sorted
    /// current bucket reaches (for prefetching; events scheduled later may come in between).
    #[inline(always)]
    pub(crate) fn upcoming(&self) -> impl Iterator<Item = usize> + '_ {
        self.current.iter().rev().skip(1).map(|e| e.1 as usize)
    }

    fn buckets(&self) -> u64 {
        self.head.len() as u64
    }

    /// Absolute bucket number of time `t`, or `None` beyond the calendar's horizon.
    #[inline(always)]
    fn bucket_of(&self, t: f64) -> Option<u64> {
        let x = (t - self.origin) * self.inv_width;
        // `floor(x) < horizon` for a whole `horizon`; `as` truncates, which is `floor` for
        // `x >= 0` (and needs no call to libm's `floor`).
        let horizon = (self.cur + self.buckets()) as f64;
        if x < horizon {
            // Negative (an event before the origin) counts as now.
            Some((x.max(0.0) as u64).max(self.cur))
        } else {
            None
        }
    }

    /// The bucket (`0..M`) whose list holds disc `i`, which is in one: the arithmetic that
    /// filed it, on the same time, origin and width.
    #[inline(always)]
    fn listed_bucket(&self, i: usize) -> usize {
        let x = (self.time[i] - self.origin) * self.inv_width;
        ((x as u64) & (self.buckets() - 1)) as usize
    }

    #[inline(always)]
    fn insert(&mut self, i: usize) {
        let t = self.time[i];
        match self.bucket_of(t) {
            Some(b) if b == self.cur => {
                let key = (t, i as u32);
                // Decreasing order: the first place whose entry is below `key`.
                let at = self.current.partition_point(|&e| e > key);
                self.current.insert(at, key);
                self.next[i] = CURRENT;
            }
            Some(b) => {
                let s = (b & (self.buckets() - 1)) as usize;
                self.next[i] = self.head[s];
                self.head[s] = i as u32;
                self.in_buckets += 1;
            }
            None => self.next[i] = OVERFLOW,
        }
    }

    #[inline(always)]
    fn remove(&mut self, i: usize) {
        match self.next[i] {
            CURRENT => {
                let key = (self.time[i], i as u32);
                // Mostly the front disc, whose event was just processed: the last entry.
                if self.current.last() == Some(&key) {
                    self.current.pop();
                } else {
                    let at = self.current.partition_point(|&e| e > key);
                    debug_assert_eq!(self.current[at], key);
                    self.current.remove(at);
                }
            }
            OVERFLOW => {}
            n => {
                let s = self.listed_bucket(i);
                let mut p = self.head[s];
                if p == i as u32 {
                    self.head[s] = n;
                } else {
                    while self.next[p as usize] != i as u32 {
                        debug_assert!(self.next[p as usize] < END, "disc {i} not in bucket {s}");
                        p = self.next[p as usize];
                    }
                    self.next[p as usize] = n;
                }
                self.in_buckets -= 1;
            }
        }
    }

    /// Moves on to the next non-empty bucket and sorts it into `current` (which is empty).
    /// Returns false if nothing finite is left.
    fn advance(&mut self) -> bool {
        loop {
            if self.in_buckets == 0 {
                // Only the overflow is left (every disc is in it): start the calendar again at
                // its earliest time.
                let first = self.time.iter().fold(f64::INFINITY, |a, &t| a.min(t));
                if first == f64::INFINITY {
                    return false;
                }
                self.rebuild(first);
                if !self.current.is_empty() {
                    return true;
                }
                continue;
            }
            self.cur += 1;
            if self.cur & (self.buckets() - 1) == 0 {
                // May re-tune (and start again at bucket 0) or file overflow events, some of
                // them into `current`.
                self.came_round();
            }
            let s = (self.cur & (self.buckets() - 1)) as usize;
            let mut j = self.head[s];
            self.head[s] = END;
            self.opened += (j != END) as u64;
            while j != END {
                self.current.push((self.time[j as usize], j));
                let next = std::mem::replace(&mut self.next[j as usize], CURRENT);
                self.in_buckets -= 1;
                self.taken += 1;
                j = next;
            }
            if self.current.is_empty() {
                continue;
            }
            self.sort_current();
            return true;
        }
    }

    /// Sorts `current` by decreasing `(time, disc)`. Pairs are distinct (one entry per disc),
    /// so the unstable sort is deterministic.
    fn sort_current(&mut self) {
        self.current.sort_unstable_by(|a, b| {
            b.0.partial_cmp(&a.0)
                .expect("times are never NaN")
                .then(b.1.cmp(&a.1))
        });
    }

    /// The calendar has come round: re-tune the width if buckets were far from a few events
    /// each, otherwise file the overflow events that are now within the horizon.
    fn came_round(&mut self) {
        let mean = if self.opened > 0 {
            self.taken as f64 / self.opened as f64
        } else {
            0.0
        };
        self.opened = 0;
        self.taken = 0;
        if !(PER_BUCKET / 4.0..=PER_BUCKET * 4.0).contains(&mean) {
            let now = self.cur as f64 / self.inv_width + self.origin;
            self.rebuild(now);
            return;
        }
        for i in 0..self.next.len() {
            if self.next[i] == OVERFLOW {
                self.insert(i);
            }
        }
    }

    /// [`Self::rebuild`] for buckets seen to hold `crowd` times the events they should: the
    /// width the times ahead give, or the present one shrunk by `crowd` if narrower. The mean
    /// time ahead, from which the width is chosen, can hide a crowded front: in a dense core
    /// among slow outer particles (a self-gravitating system) most events are soon and a few
    /// far off, and buckets as wide as the mean gave a current bucket of hundreds, each
    /// insertion into it a long move.
    fn rebuild_denser(&mut self, now: f64, crowd: f64) {
        let seen = self.inv_width * crowd;
        let ahead = self.inv_width_ahead(now);
        self.rebuild_with(
            now,
            if seen.is_finite() {
                ahead.max(seen)
            } else {
                ahead
            },
        );
    }

    /// Files every disc again with the calendar starting at time `now`, the width chosen from
    /// the finite times ahead.
    fn rebuild(&mut self, now: f64) {
        let inv_width = self.inv_width_ahead(now);
        self.rebuild_with(now, inv_width);
    }

    /// The inverse of the width that puts [`PER_BUCKET`] events in a bucket if the finite
    /// times ahead of `now` spread evenly over twice their mean.
    fn inv_width_ahead(&self, now: f64) -> f64 {
        let (mut sum, mut count) = (0.0, 0usize);
        for &t in &self.time {
            if t.is_finite() {
                sum += (t - now).max(0.0);
                count += 1;
            }
        }
        // The mean time ahead spreads `count` events over about twice that span.
        let span = if count > 0 {
            2.0 * sum / count as f64
        } else {
            0.0
        };
        let inv_width = count.max(1) as f64 / (span * PER_BUCKET);
        // No spread of times (or none finite): any width will do.
        if inv_width.is_finite() && inv_width > 0.0 {
            inv_width
        } else {
            1.0
        }
    }

    /// Files every disc again with the calendar starting at time `now`, buckets
    /// `1 / inv_width` wide.
    fn rebuild_with(&mut self, now: f64, inv_width: f64) {
        self.inv_width = inv_width;
        self.origin = now;
        self.cur = 0;
        self.head.fill(END);
        self.current.clear();
        self.in_buckets = 0;
        self.opened = 0;
        self.taken = 0;
        self.sets = 0;
        for i in 0..self.time.len() {
            match self.bucket_of(self.time[i]) {
                // Sorted once below rather than one insertion at a time.
                Some(b) if b == self.cur => {
                    self.current.push((self.time[i], i as u32));
                    self.next[i] = CURRENT;
                }
                _ => self.insert(i),
            }
        }
        self.sort_current();
    }
}

impl CalendarQueue {
    /// A queue for `n` discs (at most [`MAX_LEN`]) with at least `buckets` buckets (a power
    /// of two; `with_len` makes about `2 n`). Fewer buckets save memory (4 bytes each) and put
    /// more events in the overflow, which is filed again each time the calendar comes round;
    /// the order of events is the same for any count.
    pub fn with_buckets(n: usize, buckets: usize) -> Self {
        assert!(
            n <= MAX_LEN,
            "a calendar queue holds at most {MAX_LEN} discs"
        );
        let m = buckets.max(2).next_power_of_two();
        CalendarQueue {
            time: filled(f64::INFINITY, n),
            next: filled(OVERFLOW, n),
            head: filled(END, m),
            current: Vec::new(),
            cur: 0,
            origin: 0.0,
            inv_width: 1.0,
            in_buckets: 0,
            opened: 0,
            taken: 0,
            bulk: false,
            sets: 0,
        }
    }
}

impl EventQueue for CalendarQueue {
    fn with_len(n: usize) -> Self {
        Self::with_buckets(n, 2 * n)
    }

    #[inline(always)]
    fn set(&mut self, i: usize, t: f64) {
        debug_assert!(!t.is_nan());
        if self.bulk {
            self.time[i] = t;
            return;
        }
        self.remove(i);
        self.time[i] = t;
        self.insert(i);
        self.sets += 1;
        // A current bucket far too full (the time scale has shrunk, so the calendar would not
        // come round to re-tune itself): re-tune now, at most once per N updates.
        if self.current.len() > OVERFULL && self.sets > self.time.len() as u64 {
            let now = self.current.last().map_or(t, |e| e.0);
            let crowd = self.current.len() as f64 / PER_BUCKET;
            self.rebuild_denser(now, crowd);
        }
    }

    fn begin_bulk(&mut self) {
        self.bulk = true;
    }

    fn end_bulk(&mut self, now: f64) {
        self.bulk = false;
        self.rebuild(now);
    }

    #[inline(always)]
    fn min(&mut self) -> Option<(usize, f64)> {
        if self.time.is_empty() {
            return None;
        }
        if self.current.is_empty() && !self.advance() {
            return Some((0, f64::INFINITY));
        }
        let &(t, i) = self
            .current
            .last()
            .expect("advance filled the current bucket");
        Some((i as usize, t))
    }

    #[inline]
    fn get(&self, i: usize) -> f64 {
        self.time[i]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schedule::ReferenceQueue;

    /// Engine-like use over many turns of the calendar, with a time scale that grows 1000-fold
    /// and then shrinks a millionfold: the queue must agree with the reference at every step,
    /// come round, use the overflow, and re-tune its width both ways.
    #[test]
    fn agrees_with_reference_across_turns_overflow_and_retuning() {
        let n = 300;
        let mut a = CalendarQueue::with_len(n);
        let mut b = ReferenceQueue::with_len(n);
        let mut seed = 12345u64;
        let mut uniform = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        a.begin_bulk();
        for i in 0..n {
            let t = uniform();
            a.set(i, t);
            b.set(i, t);
        }
        a.end_bulk(0.0);
        let width0 = 1.0 / a.inv_width;
        let mut overflowed = false;
        let mut came_round = false;
        let mut width1 = 0.0;
        for step in 0..60_000 {
            if step == 40_000 {
                width1 = 1.0 / a.inv_width;
            }
            let (x, y) = (a.min(), b.min());
            assert_eq!(x, y, "step {step}");
            let (i, now) = x.unwrap();
            let scale = match step {
                0..20_000 => 1.0,
                20_000..40_000 => 1000.0,
                _ => 1e-3,
            };
            // Mostly near events, some far beyond the horizon, a few never.
            let u = uniform();
            let t = if u < 0.02 {
                f64::INFINITY
            } else if u < 0.1 {
                now + scale * 1e3 * uniform()
            } else {
                now + scale * uniform()
            };
            a.set(i, t);
            b.set(i, t);
            overflowed |= a.next[i] == OVERFLOW && t.is_finite();
            came_round |= a.cur >= a.buckets();
            // Another disc changes course too, as a collision partner does.
            let j = (uniform() * n as f64) as usize;
            let t = now + scale * uniform();
            a.set(j, t);
            b.set(j, t);
        }
        assert!(overflowed, "the overflow list was used");
        assert!(came_round, "the calendar came round");
        assert!(width1 > 100.0 * width0, "re-tuned: {width0} -> {width1}");
        // Then the time scale shrinks a millionfold: the overfull current bucket re-tunes it.
        let width2 = 1.0 / a.inv_width;
        assert!(width2 < 1e-4 * width1, "re-tuned: {width1} -> {width2}");
    }

    /// A crowded front behind a far tail (most events soon, a few far off, as in a
    /// self-gravitating system's core and halo): the mean time ahead makes buckets so wide that
    /// the current one holds most events. The overfull current bucket narrows the buckets to
    /// what it held, so that it stays short, and the order is the reference's throughout.
    #[test]
    fn a_crowded_front_narrows_the_buckets() {
        let n = 2000;
        let mut a = CalendarQueue::with_len(n);
        let mut b = ReferenceQueue::with_len(n);
        let mut seed = 99u64;
        let mut uniform = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        // Every tenth disc far off (10^4 ahead, which the mean follows), the rest within 1.
        let far = |i: usize| i.is_multiple_of(10);
        a.begin_bulk();
        for i in 0..n {
            let t = if far(i) { 1e4 + uniform() } else { uniform() };
            a.set(i, t);
            b.set(i, t);
        }
        a.end_bulk(0.0);
        let mut longest_late = 0;
        for step in 0..20 * n {
            let (x, y) = (a.min(), b.min());
            assert_eq!(x, y, "step {step}");
            let (i, now) = x.unwrap();
            let t = if far(i) { now + 1e4 } else { now + uniform() };
            a.set(i, t);
            b.set(i, t);
            if step > 10 * n {
                longest_late = longest_late.max(a.current.len());
            }
        }
        assert!(
            longest_late <= 2 * OVERFULL,
            "the current bucket held {longest_late}"
        );
    }
}
