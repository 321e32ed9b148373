//! One-dimensional self-gravity: particles on a line attract every other particle with a force
//! that does not depend on their distance, as parallel infinite sheets of mass do.
//!
//! A particle of mass `m` is pulled towards the others with `F = coupling m (M_right -
//! M_left)`, the masses on its right and on its left (`coupling` is `2 pi G` per unit area of
//! the sheets). The pair potential is `coupling m_i m_j |x_i - x_j|`, homogeneous of degree 1,
//! so the virial theorem reads `2 <K> = <U>`. The particles are hard rods: they keep their
//! order, so each one's acceleration stays what its rank gives it and flights are parabolas
//! between events. For equal masses a collision exchanges the velocities, which is the same
//! motion as the sheets passing through each other with their labels exchanged: the rods'
//! lengths only shift the positions (`y = x - rank sigma` are the sheets' positions), and the
//! dynamics is exactly that of the sheet model (Noullez, Fanelli and Aurell, J. Comput. Phys.
//! 186, 697 (2003), whose algorithm this is: only neighbours in order can meet).

use crate::error::Error;

/// One-dimensional self-gravity of strength `coupling`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SelfGravity {
    /// The force per product of masses, `2 pi G` for sheets (a finite number above 0).
    pub coupling: f64,
}

impl SelfGravity {
    /// Checks it on its own: a finite coupling above 0, on a line.
    pub fn validate(&self, dim: usize) -> Result<(), Error> {
        if dim != 1 {
            return Err(Error::BadSelfGravity(format!(
                "self-gravity is one-dimensional (sheets on a line), not for dimension {dim}"
            )));
        }
        if !(self.coupling.is_finite() && self.coupling > 0.0) {
            return Err(Error::BadSelfGravity(format!(
                "the self-gravity's coupling must be a finite number above 0, found {:?}",
                self.coupling
            )));
        }
        Ok(())
    }
}
