//! A uniform field: every disc accelerated at `g` along one axis, as gravity near the ground.
//!
//! Between events a disc then flies on a parabola, `x(t) = x + v t + g t^2 / 2` along the
//! field's axis. Pairs meet as without the field (a shared acceleration cancels from their
//! relative motion), and walls and cell crossings along that axis come at the roots of a
//! quadratic. The field's potential energy `-m g x` (its axis' coordinate `x`) is counted with
//! the kinetic energy: their sum is conserved to rounding in elastic runs.

use crate::error::Error;

/// A uniform field along one axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gravity {
    /// The axis (0 for x, 1 for y, 2 for z).
    pub axis: usize,
    /// The acceleration along it (negative: towards 0, "down").
    pub g: f64,
}

impl Gravity {
    /// Checks the field on its own: `g` finite and not 0, the axis below `dim`.
    pub fn validate(&self, dim: usize) -> Result<(), Error> {
        if self.axis >= dim {
            return Err(Error::BadField(format!(
                "the axis must be below the dimension {dim}, found {}",
                self.axis
            )));
        }
        if !(self.g.is_finite() && self.g != 0.0) {
            return Err(Error::BadField(format!(
                "g must be a finite number other than 0, found {:?}",
                self.g
            )));
        }
        Ok(())
    }
}
