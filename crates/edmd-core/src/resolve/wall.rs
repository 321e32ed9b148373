//! Reflection from a flat wall perpendicular to an axis: that velocity component changes sign.

use crate::math::Vector;

/// Reflects `v` from a wall perpendicular to `axis`; returns the impulse given to the disc.
#[inline(always)]
pub fn reflect(v: &mut Vector, axis: usize, mass: f64) -> Vector {
    let mut impulse = Vector::ZERO;
    impulse[axis] = -2.0 * mass * v[axis];
    v[axis] = -v[axis];
    impulse
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflection_flips_one_component() {
        let mut v = Vector::new([-0.09, -0.38]);
        let j = reflect(&mut v, 1, 2.0);
        assert_eq!(v, Vector::new([-0.09, 0.38]));
        assert_eq!(j, Vector::new([0.0, 1.52]));
    }
}
