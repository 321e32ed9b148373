//! Lees-Edwards boundaries: simple shear flow along x, its gradient along y.
//!
//! The box's images above (`y + L_y`) slide along x at `gamma L_y` relative to the box, and
//! those below at `-gamma L_y`: at time `t` the images above are shifted by `delta(t)` (the
//! offset), which grows by `gamma L_y` per unit time. A disc leaving through the top comes back
//! through the bottom with its x shifted by `-delta` and its x velocity by `-gamma L_y` (and the
//! other way round), so that its velocity relative to the streaming profile
//! `u_x(y) = gamma (y - L_y / 2)` carries on unchanged. With no thermostat and elastic
//! collisions the shear heats the discs without bound (viscous heating); a thermostat of the
//! velocities relative to the profile, or inelastic collisions, give a steady state.

use crate::error::Error;

/// Sliding images at a shear rate, flow along x and gradient along y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shear {
    /// The shear rate `gamma = du_x / dy` (negative: the images above slide towards -x).
    pub rate: f64,
    /// The images' offset along x, `delta`, when the shear is set: in `[0, L_x)`.
    pub offset: f64,
}

impl Shear {
    /// Shear at `rate` from an offset of 0.
    pub fn new(rate: f64) -> Self {
        Shear { rate, offset: 0.0 }
    }

    /// Checks the shear on its own: a finite rate, an offset in `[0, L_x)`, at least two
    /// dimensions.
    pub fn validate(&self, dim: usize, length_x: f64) -> Result<(), Error> {
        if dim < 2 {
            return Err(Error::BadShear(
                "Lees-Edwards boundaries need at least two dimensions".into(),
            ));
        }
        if !self.rate.is_finite() {
            return Err(Error::BadShear(format!(
                "the rate must be a finite number, found {:?}",
                self.rate
            )));
        }
        if !(self.offset.is_finite() && self.offset >= 0.0 && self.offset < length_x) {
            return Err(Error::BadShear(format!(
                "the offset must be in [0, L_x) = [0, {length_x}), found {:?}",
                self.offset
            )));
        }
        Ok(())
    }
}
