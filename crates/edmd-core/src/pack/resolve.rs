//! The Lubachevsky-Stillinger collision rule.
//!
//! At contact, with `n` the unit vector from `i` to `j`, `u = (v_j - v_i).n` the normal
//! relative velocity (negative when approaching) and `b` the growth speed of the contact
//! distance, the pair must come out separating faster than the contact grows. The rule
//! reverses the normal relative velocity about `b`: `u' = 2 b - u`, so `u' - b = b - u > 0`
//! (Donev, Torquato and Stillinger, J. Comput. Phys. 202 (2005) 737; the `b = 0` limit
//! is the elastic collision). The impulse on `j` along `n` is `J = mu (u' - u) = 2 mu (b - u)`,
//! `mu = m_i m_j / (m_i + m_j)`; `i` receives `-J`. Of it, `-2 mu u` is the elastic part, the
//! one the pressure virial counts; the rest, `2 mu b`, is the kinetic energy the growth feeds
//! in (removed by the velocity rescaling).
//!
//! A wall is a partner of infinite mass: `mu = m`, `u` the velocity along the wall's inward
//! normal and `b` the radius' growth speed.

/// Relative margin: the outgoing `u' - b` is at least this times `b`. A pair that meets with
/// `u` within rounding of `b` (touching, barely closing) would otherwise leave with `u' ~ b`,
/// and rounding could have it "collide" again at once.
pub const MIN_SEPARATION: f64 = 1e-10;

/// The impulse of one collision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LsImpulse {
    /// Impulse on `j` along `n` (on `i`, its negative): `2 mu (b - u)`, `> 0`.
    pub total: f64,
    /// Its elastic part `-2 mu u` (what a collision without growth would exchange).
    pub elastic: f64,
}

/// The LS impulse for normal relative velocity `u`, contact growth speed `b >= 0` and reduced
/// mass `mu`.
#[inline(always)]
pub fn ls_impulse(u: f64, b: f64, mu: f64) -> LsImpulse {
    let w = (b - u).max(MIN_SEPARATION * b);
    LsImpulse {
        total: 2.0 * mu * w,
        elastic: -2.0 * mu * u,
    }
}

/// Reduced mass `m_i m_j / (m_i + m_j)`.
#[inline(always)]
pub fn reduced_mass(mi: f64, mj: f64) -> f64 {
    mi * mj / (mi + mj)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_growth_it_is_elastic() {
        // Equal unit masses approaching at 2: the velocities are exchanged (J = 2 mu 2 = 2).
        let j = ls_impulse(-2.0, 0.0, 0.5);
        assert_eq!(j.total, 2.0);
        assert_eq!(j.elastic, 2.0);
    }

    #[test]
    fn growth_makes_the_pair_separate_faster_than_the_contact_grows() {
        // u = -1, b = 0.5, mu = 0.5: J = 2 * 0.5 * 1.5 = 1.5, so u' = u + J/mu = 2 = 2b - u.
        let j = ls_impulse(-1.0, 0.5, 0.5);
        assert_eq!(j.total, 1.5);
        assert_eq!(j.elastic, 1.0);
        assert_eq!(-1.0 + j.total / 0.5, 2.0);
    }
}
