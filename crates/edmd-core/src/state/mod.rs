//! The system's state as the user describes it: discs and the box.

pub mod barrier;
pub mod disc;
pub mod gravity;
pub mod potential;
pub mod reaction;
pub mod restitution;
pub mod ring;
pub mod self_gravity;
pub mod shear;
pub mod sim_box;

pub use barrier::{Barrier, Demon};
pub use disc::{Colour, Disc};
pub use gravity::Gravity;
pub use potential::{
    steps_too_large, PairSteps, Potential, Step, MAX_POTENTIAL_SPECIES, MAX_STEPS, MAX_STEP_ENERGY,
};
pub use reaction::{species_colour, Reaction, Reactions, MAX_REACTION_SPECIES};
pub use restitution::{Restitution, RestitutionLaw, BRIDGES_EXPONENT, MAX_RESTITUTION_SPECIES};
pub use ring::Ring;
pub use self_gravity::SelfGravity;
pub use shear::Shear;
pub use sim_box::{Boundary, SimBox};

/// A complete system description: discs, the box, and any internal barriers.
#[derive(Clone, Debug, PartialEq)]
pub struct System<const D: usize = 2> {
    /// The discs.
    pub discs: Vec<Disc<D>>,
    /// The box.
    pub sim_box: SimBox<D>,
    /// Internal barriers (walls across the box, possibly with doors).
    pub barriers: Vec<Barrier>,
}
