//! The course assignment's collision rule: the two discs exchange velocities.
//!
//! "Essentially, we will have the two colliding particles switch velocities":
//! `u1' = u2, v1' = v2, u2' = u1, v2' = v1`. It conserves momentum and energy for equal masses
//! (it is the elastic rule only for head-on collisions).

use crate::math::Vector;

/// Impulse on disc `i` that turns its velocity `vi` into `vj` (and `vj` into `vi`, masses equal).
#[inline(always)]
pub fn impulse<const D: usize>(vi: Vector<D>, vj: Vector<D>, mi: f64) -> Vector<D> {
    (vj - vi) * mi
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::resolve::CollisionRule;

    #[test]
    fn velocities_are_exchanged_to_the_bit() {
        // 0.15 + (-0.2 - 0.15) is not -0.2 in floating point, which is why the rule assigns
        // the velocities instead of adding the impulse.
        let (vi, vj) = (Vector::new([0.15, 0.1]), Vector::new([-0.2, 0.15]));
        let out = CollisionRule::Swap.resolve(Vector::new([2.0, 0.0]), vi, vj, 1.0, 1.0);
        assert_eq!((out.vi, out.vj), (vj, vi));
        assert_eq!(out.impulse, impulse(vi, vj, 1.0));
        assert!(((vi + out.impulse) - vj).norm2() < 1e-30);
    }
}
