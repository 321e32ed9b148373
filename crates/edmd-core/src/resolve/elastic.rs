//! Elastic collision of smooth discs.
//!
//! The impulse acts along the line of centres `n = dr/|dr|` (Princeton assignment,
//! "Collision resolution"): `J = 2 m_i m_j (dv.dr) / ((m_i + m_j) |dr|^2) dr`, applied as
//! `v_i += J/m_i`, `v_j -= J/m_j`. Using `|dr|^2` rather than `sigma^2` conserves kinetic energy
//! exactly (in exact arithmetic) even when rounding leaves the pair a hair off contact.

use crate::math::Vector;

/// Impulse on disc `i` for `dr = r_j - r_i`, `dv = v_j - v_i` and masses `mi`, `mj`.
#[inline(always)]
pub fn impulse<const D: usize>(dr: Vector<D>, dv: Vector<D>, mi: f64, mj: f64) -> Vector<D> {
    let j = 2.0 * mi * mj * dv.dot(dr) / ((mi + mj) * dr.norm2());
    dr * j
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector {
        Vector::new([x, y])
    }

    #[test]
    fn equal_masses_head_on_exchange_velocities() {
        let (vi, vj) = (v(1.0, 0.0), v(-1.0, 0.0));
        let j = impulse(v(2.0, 0.0), vj - vi, 1.0, 1.0);
        assert_eq!(vi + j, vj);
        assert_eq!(vj - j, vi);
    }

    #[test]
    fn oblique_equal_masses_exchange_normal_components_only() {
        // Line of centres along x; i moves (1, 1), j at rest: i keeps (0, 1), j gets (1, 0).
        let (vi, vj) = (v(1.0, 1.0), v(0.0, 0.0));
        let j = impulse(v(2.0, 0.0), vj - vi, 1.0, 1.0);
        assert_eq!(vi + j, v(0.0, 1.0));
        assert_eq!(vj - j, v(1.0, 0.0));
    }

    #[test]
    fn unequal_masses_one_dimensional_textbook() {
        // 1D elastic: v1' = ((m1 - m2) v1 + 2 m2 v2)/(m1 + m2), v2' = ((m2 - m1) v2 + 2 m1 v1)/(m1 + m2).
        let (m1, m2, v1, v2) = (1.0, 3.0, 2.0, -1.0);
        let j = impulse(v(1.0, 0.0), v(v2 - v1, 0.0), m1, m2);
        let v1p = v1 + j[0] / m1;
        let v2p = v2 - j[0] / m2;
        assert!((v1p - ((m1 - m2) * v1 + 2.0 * m2 * v2) / (m1 + m2)).abs() < 1e-15);
        assert!((v2p - ((m2 - m1) * v2 + 2.0 * m1 * v1) / (m1 + m2)).abs() < 1e-15);
        let e0 = 0.5 * (m1 * v1 * v1 + m2 * v2 * v2);
        let e1 = 0.5 * (m1 * v1p * v1p + m2 * v2p * v2p);
        assert!((e1 - e0).abs() < 1e-15);
    }
}
