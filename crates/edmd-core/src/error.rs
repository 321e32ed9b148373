//! The engine's error type. Constructors validate, so a [`crate::Simulation`] that exists is
//! valid and its event loop cannot fail.

use thiserror::Error;

/// Why a system or an option was refused. Disc indices are 0-based positions in the input.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum Error {
    /// A checkpoint cannot be read: not one, truncated, corrupted, of another format version or
    /// dimension, or inconsistent.
    #[error("checkpoint: {0}")]
    Checkpoint(String),
    /// A box edge length is not a finite positive number.
    #[error("box length {length} on axis {axis} is not a finite positive number")]
    BadBox {
        /// Axis.
        axis: usize,
        /// The offending length.
        length: f64,
    },
    /// A disc property is invalid (non-finite number, radius or mass not positive).
    #[error("disc {index}: {what}")]
    BadDisc {
        /// Disc index.
        index: usize,
        /// What is wrong.
        what: String,
    },
    /// Discs lie (partly) outside a walled box.
    #[error("disc {first} is outside the box ({count} disc(s) in all)")]
    OutsideBox {
        /// First offending disc.
        first: usize,
        /// How many discs are outside.
        count: usize,
    },
    /// Pairs of discs overlap by more than the tolerance.
    #[error(
        "discs {i} and {j} overlap by {overlap:.3e} (relative to contact distance); {count} overlapping pair(s) in all"
    )]
    Overlap {
        /// First disc of the first offending pair (lower index).
        i: usize,
        /// Second disc of that pair.
        j: usize,
        /// `(sigma - d) / sigma` for that pair.
        overlap: f64,
        /// Number of overlapping pairs.
        count: usize,
    },
    /// A periodic axis is too short for the cell grid's minimum-image convention.
    #[error("periodic box length {length} on axis {axis} is less than {min}, three times the reach of a pair (the largest diameter or, with a stepped potential, its outermost step)")]
    PeriodicBoxTooSmall {
        /// Axis.
        axis: usize,
        /// Box length on it.
        length: f64,
        /// The minimum allowed.
        min: f64,
    },
    /// The swap rule needs equal masses to conserve momentum and energy.
    #[error("the swap rule needs equal masses: disc {index} has mass {mass}, disc 0 has {mass0}")]
    SwapNeedsEqualMasses {
        /// First disc whose mass differs from disc 0's.
        index: usize,
        /// Its mass.
        mass: f64,
        /// Disc 0's mass.
        mass0: f64,
    },
    /// A disc cuts into an internal barrier.
    #[error("disc {disc} cuts into barrier {barrier}")]
    BarrierOverlap {
        /// The disc.
        disc: usize,
        /// The barrier.
        barrier: usize,
    },
    /// A disc is at least as wide as the box on an axis with walls: it fills the box from wall
    /// to wall and cannot move (its wall collisions would all be at one instant).
    #[error(
        "disc {index}: diameter {diameter} does not fit in the box: it is not less than the length {length} of axis {axis}, which has walls (a disc that reaches from wall to wall cannot move)"
    )]
    DiscFillsBox {
        /// Disc index.
        index: usize,
        /// Axis.
        axis: usize,
        /// The disc's diameter.
        diameter: f64,
        /// The box length on that axis.
        length: f64,
    },
    /// A run was stopped because its clock stopped advancing (see
    /// [`crate::simulation::Stall`]).
    #[error("{0}")]
    Stalled(crate::simulation::Stall),
    /// A requested value is out of range (generators, options).
    #[error("{0}")]
    Invalid(String),
    /// A stepped potential that cannot be: steps out of order, not finite, inside the hard
    /// core, or naming a species no disc has.
    #[error("potential: {0}")]
    BadPotential(String),
    /// Reaction rules that cannot be: probabilities outside `[0, 1]`, negative or non-finite
    /// energies, two rules for one pair, a reactant no disc is and no rule makes, or rules
    /// with what they do not go with.
    #[error("reaction {0}")]
    BadReaction(String),
    /// Restitution that cannot be: a coefficient outside `[0, 1]`, a law's speed not
    /// positive, a negative or non-finite TC time, a pair named twice, or restitution with
    /// what it does not go with.
    #[error("restitution: {0}")]
    BadRestitution(String),
    /// A field that cannot be: `g` not finite or 0, an axis beyond the dimension or periodic
    /// (a disc would fall for ever), or a field with what it does not go with.
    #[error("gravity: {0}")]
    BadField(String),
    /// Lees-Edwards boundaries that cannot be: a rate not finite, an offset outside the box,
    /// a walled x or y axis, or shear with what it does not go with.
    #[error("shear: {0}")]
    BadShear(String),
    /// One-dimensional self-gravity that cannot be: a coupling not finite or not above 0, a
    /// dimension other than 1, a periodic line, or self-gravity with what it does not go with.
    /// Its message names self-gravity itself.
    #[error("{0}")]
    BadSelfGravity(String),
    /// A ring patch that cannot be: an orbital frequency not finite or not above 0, fewer
    /// than two dimensions, a box without the shearing-periodic axes, or a ring with what it
    /// does not go with.
    #[error("ring: {0}")]
    BadRing(String),
    /// A time beyond what the clock resolves for these discs (see
    /// [`crate::Simulation::clock_limit`]).
    #[error(
        "t = {time:e} is too late for the clock to place these discs exactly: from t = {limit:e} on, floating-point times are so far apart that the fastest disc moves more than the overlap tolerance (1e-9 of the smallest diameter) between two of them; run to an earlier time, or start the clock nearer 0"
    )]
    ClockResolution {
        /// The time asked for.
        time: f64,
        /// The first time the clock no longer resolves ([`crate::Simulation::clock_limit`]).
        limit: f64,
    },
}
