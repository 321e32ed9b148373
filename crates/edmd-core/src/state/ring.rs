//! A patch of a planetary ring: the local frame that rotates with the orbital frequency
//! `Omega` at the patch's centre, in which particles fly under Hill's equations
//! ([`crate::predict::hill`]).
//!
//! Axes: x along the orbit (the direction of the flow), y outwards (radial), z out of the
//! ring plane (3D). Relative to the patch's centre, the Keplerian flow is `u_x = -3/2 Omega
//! (y - L_y / 2)`, so the box's radial images slide along x at `-3/2 Omega L_y` (Lees-Edwards
//! boundaries at the rate `-3/2 Omega`: the shearing sheet), and the vertical pull `-Omega^2
//! (z - L_z / 2)` holds the particles about the mid-plane, between walls far enough away
//! that a patch in a steady state does not reach them. The energy the shear feeds in is lost
//! in inelastic collisions ([`crate::Restitution`]), and whether the two balance at a finite
//! velocity dispersion is the classic question of the rings' stability (Goldreich and
//! Tremaine, Icarus 34, 227 (1978)).

use crate::error::Error;

/// A ring patch at orbital frequency `omega`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ring {
    /// The local orbital frequency `Omega` (a finite number above 0).
    pub omega: f64,
}

impl Ring {
    /// The shear rate of the Keplerian flow, `du_x/dy = -3/2 Omega`.
    pub fn shear_rate(&self) -> f64 {
        -1.5 * self.omega
    }

    /// Checks it on its own: a finite frequency above 0, in two or three dimensions.
    pub fn validate(&self, dim: usize) -> Result<(), Error> {
        if dim < 2 {
            return Err(Error::BadRing(format!(
                "a ring patch has two or three dimensions, not {dim}"
            )));
        }
        if !(self.omega.is_finite() && self.omega > 0.0) {
            return Err(Error::BadRing(format!(
                "the orbital frequency must be a finite number above 0, found {:?}",
                self.omega
            )));
        }
        Ok(())
    }
}
