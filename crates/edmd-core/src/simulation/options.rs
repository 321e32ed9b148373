//! Run parameters and event counts.

use crate::resolve::CollisionRule;

/// Relative tolerance on overlaps and wall penetration: discs closer than
/// `sigma (1 - OVERLAP_TOLERANCE)` overlap, less the rounding allowance
/// [`OVERLAP_ROUNDING`]. Input files written with rounded coordinates touch with overlaps of
/// about 1e-15; the engine's own rounding stays at that level too in systems whose discs are
/// not many orders of magnitude smaller than the distance they travel.
pub const OVERLAP_TOLERANCE: f64 = 1e-9;

/// The absolute rounding allowance of the overlap check, in units of
/// `L + (|v_i| + |v_j|) |t|` (`L` the longest box side, `t` the clock): a pair counts as
/// overlapping only when closer than `sigma (1 - tol) - OVERLAP_ROUNDING (L + (|v_i| + |v_j|) |t|)`.
///
/// Event times are absolute, so a position computed at time `t` is `x + v (t - t_i)` with `t`
/// rounded to `eps |t|`: a contact is found to within a few `eps (L + |v| |t|)`, whatever the
/// discs' size. For spheres of radius 1e-4 moving at speed 8 between walls 0.84 apart, it was
/// measured at 9.5e-9 of the contact distance at t = 1155 (an input found by fuzzing,
/// RELIABILITY.md), beyond the relative tolerance alone; for unit discs at unit speed it stays
/// below 1e-9 of the contact distance until t is about 10^5. Sixteen units of rounding
/// (`16 eps`) is well above the largest error seen.
pub const OVERLAP_ROUNDING: f64 = 16.0 * f64::EPSILON;

/// What to do with input discs that overlap each other or stick out of a walled box.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OverlapPolicy {
    /// Refuse the system with [`Error::Overlap`] or [`Error::OutsideBox`].
    #[default]
    Refuse,
    /// Run it anyway: a disc outside the box is moved (along each axis) to the nearest position
    /// touching the wall; overlapping pairs are left overlapping. An overlapping pair that
    /// approaches collides at once (which turns it round), and one that separates moves freely
    /// until it is apart; from then on it is an ordinary pair.
    Allow,
}

/// Run parameters, validated when the simulation is built.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Options {
    /// Collision rule.
    pub rule: CollisionRule,
    /// Treatment of overlapping input.
    pub overlaps: OverlapPolicy,
    /// Multi-disc collisions: when set, a collision involves every disc touching the pair
    /// (see [`MultiContact`]); otherwise every collision is binary.
    pub multi: Option<MultiContact>,
}

/// Multi-disc collisions (the Princeton assignment's extra credit, billiard breaks).
///
/// When two discs collide, every disc connected to them through contacts (gap at most
/// `tolerance` times the contact distance) takes part at the same instant, resolved by
/// [`crate::resolve::cluster`]: the impulsive limit of stiff elastic contacts with force
/// `delta^exponent`. Clusters of two are ordinary elastic collisions. Needs the elastic rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MultiContact {
    /// Largest gap, relative to the contact distance, at which discs count as touching.
    pub tolerance: f64,
    /// Contact force exponent: 1.5 for elastic spheres (Hertz), 1 for linear springs.
    pub exponent: f64,
}

impl Default for MultiContact {
    fn default() -> Self {
        MultiContact {
            tolerance: 1e-3,
            exponent: 1.5,
        }
    }
}

/// Counts of processed events.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Disc-disc collisions.
    pub disc_disc: u64,
    /// Disc-wall collisions.
    pub wall: u64,
    /// Cell crossings.
    pub cell_crossing: u64,
    /// Stale events discarded (partner changed course after the prediction).
    pub stale: u64,
    /// Events at internal barriers (bounces and demon decisions).
    pub barrier: u64,
    /// Events at the steps of a stepped potential (crossings and bounces); hard-core
    /// collisions count in `disc_disc`.
    pub step: u64,
    /// Velocities redrawn by the Andersen thermostat.
    pub thermostat: u64,
    /// Neighbour lists made again (stepped potentials, whose discs are filed by where their
    /// lists were made and have no cell crossings).
    pub neighbour_list: u64,
    /// Reactive collisions (counted in `disc_disc` too).
    pub reaction: u64,
}
