//! The system's state as the user describes it: discs and the box.

pub mod disc;
pub mod sim_box;

pub use disc::{Colour, Disc};
pub use sim_box::{Boundary, SimBox};
