//! Event prediction kernels: pure functions from relative state to a time until the event.
//!
//! Every kernel returns `None` for "never" (no sentinel times) and a non-negative `Some(dt)`
//! otherwise, so an event time `now + dt` can never lie in the past.

pub mod disc_disc;
pub mod interval;

pub use disc_disc::{time_to_contact, time_to_contact_within};
pub use interval::{interval_exit, Side};
