//! Event queues: one pending event time per disc, and the disc whose time is smallest.
//!
//! Each disc keeps exactly one scheduled event (its earliest predicted one), so the queue has
//! N entries and memory is O(N). Stale events are detected when they reach the front (their
//! partner's collision counter has moved on) and the disc is simply predicted again.
//!
//! Equal times: the lowest disc index comes first. This is the documented tie rule of the
//! engine, and both implementations here follow it.

pub mod reference;
pub mod tournament;

pub use reference::ReferenceQueue;
pub use tournament::TournamentQueue;

/// A priority queue holding one time per disc.
pub trait EventQueue {
    /// A queue for `n` discs, every time `+inf`.
    fn with_len(n: usize) -> Self;
    /// Sets disc `i`'s time (`+inf` for "no event"). Times are never NaN.
    fn set(&mut self, i: usize, t: f64);
    /// The disc with the smallest time (lowest index on ties) and that time; `None` if empty.
    fn min(&self) -> Option<(usize, f64)>;
    /// Disc `i`'s time.
    fn get(&self, i: usize) -> f64;
}
