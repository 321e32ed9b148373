//! Reflection from a flat wall perpendicular to an axis: that velocity component changes sign.

use crate::math::Vector;

/// Reflects `v` from a wall perpendicular to `axis`; returns the impulse given to the disc.
#[inline(always)]
pub fn reflect<const D: usize>(v: &mut Vector<D>, axis: usize, mass: f64) -> Vector<D> {
    let mut impulse = Vector::ZERO;
    impulse[axis] = -2.0 * mass * v[axis];
    v[axis] = -v[axis];
    impulse
}

/// Reflects `v` from a surface with unit normal `n` (a door edge seen from the disc); returns
/// the impulse given to the disc. Only the normal component changes sign.
#[inline(always)]
pub fn reflect_normal<const D: usize>(v: &mut Vector<D>, n: Vector<D>, mass: f64) -> Vector<D> {
    let vn = v.dot(n);
    let dv = n * (-2.0 * vn);
    *v += dv;
    dv * mass
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

    #[test]
    fn reflection_about_a_normal_keeps_the_tangent() {
        let s = 0.5f64.sqrt();
        let mut v = Vector::new([1.0, 0.0]);
        let j = reflect_normal(&mut v, Vector::new([-s, -s]), 1.0);
        assert!((v - Vector::new([0.0, -1.0])).norm2() < 1e-30, "{v:?}");
        assert!((j - Vector::new([-1.0, -1.0])).norm2() < 1e-30);
    }
}
