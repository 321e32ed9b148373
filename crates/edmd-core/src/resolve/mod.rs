//! Collision resolution kernels: velocity changes at the instant of contact.

pub mod cluster;
pub mod elastic;
pub mod swap;
pub mod wall;

use crate::math::Vector;

/// How two discs that touch change their velocities.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CollisionRule {
    /// Smooth elastic discs of any masses: an impulse along the line of centres.
    #[default]
    Elastic,
    /// The course assignment's rule: the two discs exchange velocities (equal masses only).
    Swap,
}

/// The outcome of a disc-disc collision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairOutcome<const D: usize = 2> {
    /// New velocity of disc `i`.
    pub vi: Vector<D>,
    /// New velocity of disc `j`.
    pub vj: Vector<D>,
    /// Impulse received by disc `i` (disc `j` receives its negative).
    pub impulse: Vector<D>,
}

impl CollisionRule {
    /// Resolves a collision of disc `i` (velocity `vi`, mass `mi`) with disc `j` (`vj`, `mj`) at
    /// contact, `dr = r_j - r_i`.
    #[inline(always)]
    pub fn resolve<const D: usize>(
        self,
        dr: Vector<D>,
        vi: Vector<D>,
        vj: Vector<D>,
        mi: f64,
        mj: f64,
    ) -> PairOutcome<D> {
        match self {
            CollisionRule::Elastic => {
                let impulse = elastic::impulse(dr, vj - vi, mi, mj);
                PairOutcome {
                    vi: vi + impulse / mi,
                    vj: vj - impulse / mj,
                    impulse,
                }
            }
            // Assigned, not computed from the impulse, so the exchange is exact to the bit.
            CollisionRule::Swap => PairOutcome {
                vi: vj,
                vj: vi,
                impulse: swap::impulse(vi, vj, mi),
            },
        }
    }
}
