//! Event queues: one pending event time per disc, and the disc whose time is smallest.
//!
//! Each disc keeps exactly one scheduled event (its earliest predicted one), so the queue has
//! N entries and memory is O(N). Stale events are detected when they reach the front (their
//! partner's collision counter has moved on) and the disc is simply predicted again.
//!
//! Equal times: the lowest disc index comes first. This is the documented tie rule of the
//! engine, and every implementation here follows it. The engine uses the calendar queue; the
//! tournament tree is kept as a second, simpler O(log N) queue to compare against.

pub mod calendar;
pub mod reference;
pub mod tournament;

pub use calendar::CalendarQueue;
pub use reference::ReferenceQueue;
pub use tournament::TournamentQueue;

/// A priority queue holding one time per disc.
pub trait EventQueue {
    /// A queue for `n` discs, every time `+inf`.
    fn with_len(n: usize) -> Self;
    /// Sets disc `i`'s time (`+inf` for "no event"). Times are never NaN.
    fn set(&mut self, i: usize, t: f64);
    /// The disc with the smallest time (lowest index on ties) and that time; `None` if empty.
    /// When every time is `+inf` the disc is unspecified. Takes `&mut self` so that a queue
    /// may tidy itself up on the way (the calendar queue opens its next bucket).
    fn min(&mut self) -> Option<(usize, f64)>;
    /// Disc `i`'s time.
    fn get(&self, i: usize) -> f64;
    /// Starts setting many times at once (every disc's, typically): until
    /// [`end_bulk`](Self::end_bulk), `set` may only record the time.
    fn begin_bulk(&mut self) {}
    /// Ends a [`begin_bulk`](Self::begin_bulk); `now` is no later than any time set.
    fn end_bulk(&mut self, _now: f64) {}
}
