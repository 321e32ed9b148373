//! # edmd-core: exact event-driven molecular dynamics of hard discs
//!
//! Discs move in straight lines and collide elastically with each other and with the walls of
//! a box; the engine jumps from one collision to the next, never by time steps. Per-event cost
//! does not grow with N: every disc keeps its own clock, a cell grid limits collision tests to
//! nearby discs, and a calendar queue holds one pending event per disc with lazy
//! invalidation. See `ARCHITECTURE.md` for the flow of an event.
//!
//! ```
//! use edmd_core::{Disc, Options, SimBox, Simulation, Vector, CollisionCounter};
//!
//! // Two discs of radius 1 in a 10 x 10 box, meeting head-on at t = 1.
//! let discs = [
//!     Disc::new(Vector::new([3.0, 5.0]), Vector::new([1.0, 0.0]), 1.0),
//!     Disc::new(Vector::new([7.0, 5.0]), Vector::new([-1.0, 0.0]), 1.0),
//! ];
//! let mut sim = Simulation::new(&discs, SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
//! let mut counter = CollisionCounter::new(2);
//! sim.run_until(1.5, &mut counter);
//! assert_eq!(counter.disc, vec![1, 1]);
//! assert_eq!(sim.position(0), Vector::new([3.5, 5.0]));
//! ```

pub mod cells;
pub mod error;
pub mod events;
pub(crate) mod frame;
pub(crate) mod hint;
pub mod math;
pub mod measure;
pub mod observer;
pub mod pack;
pub mod predict;
pub mod resolve;
pub mod schedule;
pub mod setup;
pub mod simulation;
pub mod state;

pub use error::Error;
pub use events::{BarrierHit, EventKind, EventRecord, Side, StepHit, Wall};
pub use math::{Vector, DIM};
pub use observer::{CollisionCounter, Observer};
pub use resolve::CollisionRule;
pub use simulation::{
    checkpoint_dim, is_checkpoint, Andersen, MultiContact, Options, OverlapPolicy, OverlapReport,
    Simulation, Stall, StallCause, Stats, CHECKPOINT_MAGIC, CHECKPOINT_VERSION, CREEP_EVENTS_SPAN,
    MAX_BARRIERS, OVERLAP_ROUNDING, OVERLAP_TOLERANCE,
};
pub use state::{
    species_colour, Barrier, Boundary, Colour, Demon, Disc, Gravity, PairSteps, Potential,
    Reaction, Reactions, Restitution, RestitutionLaw, Ring, SelfGravity, Shear, SimBox, Step,
    System, MAX_REACTION_SPECIES, MAX_STEP_ENERGY,
};
