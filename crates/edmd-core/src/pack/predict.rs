//! Contact times of growing particles.
//!
//! Two particles whose contact distance grows linearly, `sigma(t) = a + b t`, at relative
//! position `dr = r_j - r_i` and relative velocity `dv = v_j - v_i`, touch when
//! `|dr + dv t| = a + b t`, i.e. `A t^2 + 2 B t + C = 0` with `A = dv.dv - b^2`,
//! `B = dr.dv - a b`, `C = dr.dr - a^2` (Donev, Torquato and Stillinger, J. Comput. Phys. 202
//! (2005) 737). `B < 0` means the gap is closing (the centres approach faster than
//! the contact distance grows). Unlike fixed discs, a pair with `A < 0` (relative speed below
//! the growth speed `b`) always meets again, even when it separates now.
//!
//! Every root is taken in a form without cancellation:
//! - closing (`B < 0`): the earlier root `C / (-B + sqrt(B^2 - A C))`, as in
//!   `predict/disc_disc.rs`; a pair already at or inside contact (`C <= 0`, by rounding)
//!   collides at once;
//! - opening (`B >= 0`) with `A < 0`: the later root `(B + sqrt(B^2 - A C)) / (-A)`. A pair
//!   that has just collided sits at contact (`C ~ 0`) with `B > 0`, so it gets this later root,
//!   never the spurious root at `t ~ 0`.

use crate::math::Vector;
use crate::predict::Side;

/// Time until two growing particles touch, or `None` if they never do.
///
/// `a > 0` is the contact distance now, `b >= 0` its growth speed.
#[inline(always)]
pub fn growing_contact_time<const D: usize>(
    dr: Vector<D>,
    dv: Vector<D>,
    a: f64,
    b: f64,
) -> Option<f64> {
    let bb = dr.dot(dv) - a * b;
    let c = dr.norm2() - a * a;
    let aa = dv.norm2() - b * b;
    if bb < 0.0 {
        if c <= 0.0 {
            return Some(0.0);
        }
        let d = bb * bb - aa * c;
        if d < 0.0 {
            return None;
        }
        Some(c / (-bb + d.sqrt()))
    } else if aa < 0.0 {
        // `d >= B^2` when separated; inside contact by rounding with `d < 0` the gap never
        // opens: the pair meets at the time of its widest gap.
        let d = (bb * bb - aa * c).max(0.0);
        Some((bb + d.sqrt()) / -aa)
    } else {
        None
    }
}

/// Time until a growing particle reaches one of the walls at `lo` and `hi` on one axis, and
/// which: the centre `x` moves at `v`, the radius `r` grows at `rdot`. Growth makes a particle
/// moving away from a wall slower than `rdot` reach it all the same. `None` if neither wall is
/// ever reached (no growth and no motion).
#[inline(always)]
pub fn growing_wall_time(
    x: f64,
    v: f64,
    r: f64,
    rdot: f64,
    lo: f64,
    hi: f64,
) -> Option<(f64, Side)> {
    // Gaps and how fast they close.
    let (gap_lo, close_lo) = (x - r - lo, rdot - v);
    let (gap_hi, close_hi) = (hi - x - r, rdot + v);
    let t_lo = (close_lo > 0.0).then(|| (gap_lo / close_lo).max(0.0));
    let t_hi = (close_hi > 0.0).then(|| (gap_hi / close_hi).max(0.0));
    match (t_lo, t_hi) {
        (Some(l), Some(h)) if h < l => Some((h, Side::High)),
        (Some(l), _) => Some((l, Side::Low)),
        (None, Some(h)) => Some((h, Side::High)),
        (None, None) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector {
        Vector::new([x, y])
    }

    #[test]
    fn without_growth_it_is_the_fixed_disc_time() {
        assert_eq!(
            growing_contact_time(v(10.0, 0.0), v(-2.0, 0.0), 2.0, 0.0),
            Some(4.0)
        );
        assert_eq!(
            growing_contact_time(v(10.0, 0.0), v(2.0, 0.0), 2.0, 0.0),
            None
        );
    }

    #[test]
    fn head_on_growing_pair() {
        // Gap 10 - 2 = 8 closes at 2 (approach) + 2 (growth): t = 2.
        let t = growing_contact_time(v(10.0, 0.0), v(-2.0, 0.0), 2.0, 2.0).unwrap();
        assert!((t - 2.0).abs() < 1e-15, "{t}");
    }

    #[test]
    fn separating_slower_than_growth_meets_later() {
        // Centres 3 apart moving apart at 1, contact 2 growing at 2: 3 + t = 2 + 2t at t = 1.
        let t = growing_contact_time(v(3.0, 0.0), v(1.0, 0.0), 2.0, 2.0).unwrap();
        assert!((t - 1.0).abs() < 1e-15, "{t}");
        // Separating faster than the growth: never.
        assert_eq!(
            growing_contact_time(v(3.0, 0.0), v(3.0, 0.0), 2.0, 2.0),
            None
        );
    }

    #[test]
    fn a_pair_just_after_contact_is_not_hit_again_at_once() {
        // At contact (or a hair inside it by rounding), separating faster than the contact
        // grows: `|dr + dv t| >= |dr| + u t > a + b t` for ever, so never (and `B >= 0` with
        // `C <= 0` forces `A >= 0`: no root at t ~ 0 can appear).
        assert_eq!(
            growing_contact_time(v(2.0, 0.0), v(3.0, 0.0), 2.0, 1.0),
            None
        );
        assert_eq!(
            growing_contact_time(v(2.0 - 1e-15, 0.0), v(2.5, 1.0), 2.0, 2.0),
            None
        );
        // Separating slower than the contact grows: that is closing, and at contact it is a
        // collision now.
        assert_eq!(
            growing_contact_time(v(2.0 - 1e-15, 0.0), v(1.5, 0.0), 2.0, 2.0),
            Some(0.0)
        );
    }

    #[test]
    fn walls_with_growth() {
        // x = 5 in [0, 10], radius 1 growing at 1, moving right at 1: the right gap 4 closes at
        // 2 (t = 2); the left gap 4 closes at 0 (never first).
        assert_eq!(
            growing_wall_time(5.0, 1.0, 1.0, 1.0, 0.0, 10.0),
            Some((2.0, Side::High))
        );
        // At rest: both gaps close at 1; the low wall wins ties.
        assert_eq!(
            growing_wall_time(5.0, 0.0, 1.0, 1.0, 0.0, 10.0),
            Some((4.0, Side::Low))
        );
        assert_eq!(growing_wall_time(5.0, 0.0, 1.0, 0.0, 0.0, 10.0), None);
    }
}
