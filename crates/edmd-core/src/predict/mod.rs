//! Event prediction kernels: pure functions from relative state to a time until the event.
//!
//! Every kernel returns `None` for "never" (no sentinel times) and a non-negative `Some(dt)`
//! otherwise, so an event time `now + dt` can never lie in the past.

pub mod barrier;
pub mod disc_disc;
pub mod hill;
pub mod interval;

pub use disc_disc::{
    contact_root, contact_terms, contact_time, contact_time_or_inf, time_to_contact, ContactTerms,
    FAR_CONTACT_RATIO2,
};
pub use interval::{
    interval_exit, interval_exit_accel, interval_exit_accel_or_inf, interval_exit_or_inf, Side,
};
