//! Events: what the scheduler keeps per disc, and what observers are shown.

use crate::math::Vector;
pub use crate::predict::Side;

/// A flat wall of the box: the axis it is perpendicular to and which end of that axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Wall {
    /// Axis the wall is perpendicular to (0 = x, 1 = y).
    pub axis: usize,
    /// `Low` is the wall at 0, `High` the wall at L.
    pub side: Side,
}

/// A processed event, as observers see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EventKind {
    /// Discs `i` and `j` collided.
    DiscDisc {
        /// The disc whose schedule held the event.
        i: usize,
        /// Its partner.
        j: usize,
    },
    /// Discs `i` and `j` collided and reacted under reaction rule `rule` (their species and
    /// colours are already the products').
    Reaction {
        /// The disc whose schedule held the event.
        i: usize,
        /// Its partner.
        j: usize,
        /// Index of the rule in [`crate::Reactions::rules`].
        rule: usize,
    },
    /// Disc `i` bounced off a wall.
    Wall {
        /// The disc.
        i: usize,
        /// The wall.
        wall: Wall,
    },
    /// Disc `i` met internal barrier `barrier`.
    Barrier {
        /// The disc.
        i: usize,
        /// Index of the barrier.
        barrier: usize,
        /// What happened there.
        hit: BarrierHit,
    },
    /// Discs `i` and `j` met a step of their stepped potential.
    Step {
        /// The disc whose schedule held the event.
        i: usize,
        /// Its partner.
        j: usize,
        /// What happened there.
        hit: StepHit,
    },
    /// Disc `i`'s velocity was redrawn by the thermostat.
    Thermostat {
        /// The disc.
        i: usize,
    },
    /// Disc `i`'s neighbour list was made again, the disc having moved half the lists' skin
    /// since it was last made (bookkeeping under a stepped potential, in place of cell
    /// crossings; no velocity change).
    NeighbourList {
        /// The disc.
        i: usize,
    },
    /// Under shear, the images across y slid one more cell width, and disc `i`, in a row of
    /// cells next to that boundary, looked at them again (bookkeeping; no velocity change).
    Slide {
        /// The disc.
        i: usize,
    },
    /// Disc `i` moved into a neighbouring cell (bookkeeping; no velocity change; under shear,
    /// a crossing of the y boundary changes its x and x velocity to the images').
    CellCrossing {
        /// The disc.
        i: usize,
        /// Axis crossed.
        axis: usize,
        /// Direction.
        side: Side,
    },
}

impl EventKind {
    /// Whether this is bookkeeping that changes no velocity: a cell crossing, a neighbour
    /// list made again, or a slide of the sheared images.
    pub fn is_bookkeeping(&self) -> bool {
        matches!(
            self,
            EventKind::CellCrossing { .. }
                | EventKind::NeighbourList { .. }
                | EventKind::Slide { .. }
        )
    }
}

/// What happened at a barrier.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BarrierHit {
    /// Bounced off the solid face.
    Face,
    /// Bounced off a door edge.
    Edge,
    /// Reached the doorway and the demon let it through (no velocity change).
    DoorPassed,
    /// Reached the doorway and the demon shut the door on it (bounced).
    DoorShut,
}

/// What happened when a pair met a step of its potential.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepHit {
    /// Crossed the step inward (into a well, or over a shoulder).
    Entered,
    /// Crossed the step outward.
    Left,
    /// Met the step from outside and bounced off it (a shoulder too high to climb).
    Repelled,
    /// Met the step from inside and bounced back in (a well too deep to leave).
    Held,
}

/// One processed event. The simulation's state has already been updated when observers see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventRecord<const D: usize = 2> {
    /// Simulation time of the event.
    pub time: f64,
    /// What happened.
    pub kind: EventKind,
    /// Impulse received by disc `i` (for a pair, `j` received its negative); zero for crossings.
    pub impulse: Vector<D>,
}

/// The one event a disc has scheduled (the engine's internal form of [`EventKind`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Pending {
    /// Nothing ahead (time `+inf`).
    Nothing,
    /// Collision with `partner`, valid while the partner's collision counter is still `seen`.
    Disc { partner: u32, seen: u32 },
    /// Wall collision.
    Wall { axis: u8, side: Side },
    /// Cell crossing.
    Cell { axis: u8, side: Side },
    /// Barrier `index`: face (`part` 0), door edge lo/hi (1, 2), or the doorway's demon (3).
    Barrier { index: u16, part: u8 },
    /// The thermostat's next redraw of the disc's velocity.
    Thermostat,
    /// Its neighbour list made again (stepped potentials).
    Relist,
    /// The end of the shear's epoch: its scan across the sliding boundary made again.
    Slide,
    /// A ring's disc filed again in the grid before it strays out of its cell's margin.
    Refile,
    /// A ring's disc predicted again where a contact search stopped unsettled.
    Recheck,
}
