//! Disc-disc contact time.
//!
//! Two discs at relative position `dr = r_j - r_i` with relative velocity `dv = v_j - v_i`
//! touch when `|dr + dv t| = sigma`, i.e. `a t^2 + 2 b t + c = 0` with `a = dv.dv`,
//! `b = dr.dv`, `c = dr.dr - sigma^2`. Only approaching pairs (`b < 0`) can collide; the earlier
//! root is taken in the cancellation-free form `t = c / (-b + sqrt(d))`
//! (the textbook `(-b - sqrt(d)) / a` loses all its digits for grazing or slow pairs).
//!
//! The discriminant `d = b^2 - a c` has two forms. The textbook one subtracts `a |dr|^2` from
//! `b^2`, two numbers that for a pair far apart (`|dr| >> sigma`) nearly cancel to leave the
//! `a sigma^2` that matters: a relative error of about `eps (|dr| / sigma)^2`, which made pairs
//! predicted from thousands of contact distances away meet measurably late (RELIABILITY.md).
//! The far form, `a sigma^2 - |dr ^ dv|^2` (Lagrange's identity
//! `|dr|^2 |dv|^2 - (dr.dv)^2 = |dr ^ dv|^2`, the wedge summed from its components), errs by
//! at most `eps |dr| / sigma` relative, and not at all for a head-on pair. It costs about 12
//! more operations per pair in 3D (15% more instructions per collision at packing 0.45), so
//! the event loop takes it only where candidates can be far: [`FAR_CONTACT_RATIO2`].

use crate::math::Vector;

/// The squared ratio of a candidate's distance to the contact distance beyond which the
/// event loop computes contact times in the far form (the module's notes). Below it the
/// textbook form's error, about `eps (|dr| / sigma)^2`, is under `1e-12` of the contact
/// distance, a thousandth of the overlap tolerance. In a dense fluid a candidate is at most
/// two cells, a few diameters, away; only a few small discs in large cells go beyond it.
pub const FAR_CONTACT_RATIO2: f64 = 4096.0;

/// Time until the two discs touch, or `None` if they never do, in the far form (any
/// distance).
///
/// A pair already overlapping (by rounding, `c <= 0`) and approaching collides at once
/// (`Some(0.0)`); a pair that is separating or at rest relative to each other never collides,
/// which is what stops a pair that has just collided from colliding again.
#[inline(always)]
pub fn time_to_contact<const D: usize>(dr: Vector<D>, dv: Vector<D>, sigma: f64) -> Option<f64> {
    let t = contact_time::<D, true>(dr, dv, sigma);
    (t != f64::INFINITY).then_some(t)
}

/// The contact time in the textbook form, `+inf` for "never": for pairs at most
/// `sqrt(FAR_CONTACT_RATIO2)` contact distances apart.
#[inline(always)]
pub fn contact_time_or_inf<const D: usize>(dr: Vector<D>, dv: Vector<D>, sigma: f64) -> f64 {
    contact_time::<D, false>(dr, dv, sigma)
}

/// The contact time, `+inf` for "never", computed without branches; the discriminant in the
/// far form when `FAR` (the module's notes). [`contact_terms`] then [`contact_root`].
#[inline(always)]
pub fn contact_time<const D: usize, const FAR: bool>(
    dr: Vector<D>,
    dv: Vector<D>,
    sigma: f64,
) -> f64 {
    let terms = contact_terms::<D, FAR>(dr, dv, sigma);
    // The root is computed whatever the pair does and then selected: whether a pair meets is
    // a coin toss the branch predictor cannot learn.
    let t = contact_root(terms);
    if terms.meets() {
        t
    } else {
        f64::INFINITY
    }
}

/// What decides a pair's contact time: `b = dr.dv`, `c = dr.dr - sigma^2` and the
/// discriminant `d`.
#[derive(Clone, Copy, Debug, Default)]
pub struct ContactTerms {
    /// `dr.dv`: negative when the pair approaches.
    pub b: f64,
    /// `dr.dr - sigma^2`: negative when the pair overlaps.
    pub c: f64,
    /// The discriminant `b^2 - a c` (`a = dv.dv`), in the textbook or the far form (the
    /// module's notes): negative when the pair passes without touching.
    pub d: f64,
}

impl ContactTerms {
    /// Whether the pair ever touches: it approaches (`b < 0`) and does not pass by (`d >= 0`);
    /// false for NaNs. Evaluated without branches.
    #[inline(always)]
    pub fn meets(&self) -> bool {
        (self.b < 0.0) & (self.d >= 0.0)
    }
}

/// The terms of a pair's contact time, without the square root and the division: cheap
/// enough to be worked out for every candidate, so that only the pairs that meet
/// ([`ContactTerms::meets`]) pay for [`contact_root`]. The x86-64-v3 scan in 3D repeats it
/// four lanes wide, operation for operation (`simulation/scan_x86.rs`): a change here must
/// be made there too (a test compares the two loops' trajectories bit for bit).
#[inline(always)]
pub fn contact_terms<const D: usize, const FAR: bool>(
    dr: Vector<D>,
    dv: Vector<D>,
    sigma: f64,
) -> ContactTerms {
    // Sums started from `-0.0`, which the compiler can drop (`-0.0 + x` is `x` for every `x`),
    // where `Vector::dot` starts from `0.0` and must add it. They differ only in the sign of
    // a zero sum, which decides nothing here (`b < 0`, `b * b`, and `|dr|^2`, `|dv|^2` are
    // zero only with every component zero).
    let dot = |p: Vector<D>, q: Vector<D>| (0..D).fold(-0.0, |s, k| s + p[k] * q[k]);
    let b = dot(dr, dv);
    let c = dot(dr, dr) - sigma * sigma;
    let a = dot(dv, dv);
    let d = if FAR {
        a * (sigma * sigma) - dr.wedge2(dv)
    } else {
        b * b - a * c
    };
    ContactTerms { b, c, d }
}

/// The contact time of a pair that meets: the earlier root in the cancellation-free form.
/// For `c <= 0` (overlapping) the quotient is `<= 0` and is clamped to "now".
#[inline(always)]
pub fn contact_root(terms: ContactTerms) -> f64 {
    let ContactTerms { b, c, d } = terms;
    (c / (-b + d.max(0.0).sqrt())).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector {
        Vector::new([x, y])
    }

    #[test]
    fn head_on_pair_meets_when_gap_closes() {
        // Centres 10 apart, sigma 2, closing at speed 2: gap 8 closes at t = 4.
        assert_eq!(time_to_contact(v(10.0, 0.0), v(-2.0, 0.0), 2.0), Some(4.0));
    }

    #[test]
    fn oblique_pair_matches_hand_solution() {
        // dr = (4, 1), dv = (-1, 0), sigma = sqrt(2): |(4 - t, 1)|^2 = 2 -> (4 - t)^2 = 1 -> t = 3.
        let t = time_to_contact(v(4.0, 1.0), v(-1.0, 0.0), 2f64.sqrt()).unwrap();
        assert!((t - 3.0).abs() < 1e-15, "{t}");
    }

    #[test]
    fn misses_and_separations_are_none() {
        // Passing at impact parameter 3 > sigma = 2.
        assert_eq!(time_to_contact(v(10.0, 3.0), v(-1.0, 0.0), 2.0), None);
        // Moving apart.
        assert_eq!(time_to_contact(v(10.0, 0.0), v(1.0, 0.0), 2.0), None);
        // At rest relative to each other.
        assert_eq!(time_to_contact(v(10.0, 0.0), v(0.0, 0.0), 2.0), None);
        // Exactly grazing (impact parameter = sigma) is a tangent touch: d = 0, t = 10 - 0.
        assert_eq!(time_to_contact(v(10.0, 2.0), v(-1.0, 0.0), 2.0), Some(10.0));
    }

    #[test]
    fn overlapping_and_approaching_collides_now() {
        assert_eq!(time_to_contact(v(1.9, 0.0), v(-1.0, 0.0), 2.0), Some(0.0));
        // Overlapping but separating: left alone.
        assert_eq!(time_to_contact(v(1.9, 0.0), v(1.0, 0.0), 2.0), None);
    }

    #[test]
    fn head_on_pair_from_afar_meets_at_contact() {
        // 3D, sigma 2e-5 from 0.196 away closing at speed 1 (the fuzz input
        // `engine_3d-contact-from-afar`): the exact time is 0.196 - 2e-5. The textbook
        // discriminant b^2 - a c is 0.196^2 - (0.196^2 - 4e-10), which keeps only about
        // 7 digits of 4e-10 and so of the root; the wedge form is exact for a head-on pair.
        let sigma = 2e-5;
        let t = time_to_contact(
            Vector::new([0.196, 0.0, 0.0]),
            Vector::new([-1.0, 0.0, 0.0]),
            sigma,
        )
        .unwrap();
        let exact = 0.196 - sigma;
        assert!(
            (t - exact).abs() <= 4.0 * f64::EPSILON * 0.196,
            "{t} vs {exact}"
        );
        // Obliquely, at impact parameter sigma/2 along y and z: contact where
        // (0.196 - t)^2 = sigma^2 - sigma^2/4, so t = 0.196 - sigma sqrt(3)/2.
        let h = sigma / (2.0 * 2f64.sqrt());
        let t = time_to_contact(
            Vector::new([0.196, h, h]),
            Vector::new([-1.0, 0.0, 0.0]),
            sigma,
        )
        .unwrap();
        let exact = 0.196 - sigma * 3f64.sqrt() / 2.0;
        let gap = ((0.196 - t).powi(2) + 2.0 * h * h).sqrt() - sigma;
        assert!(gap.abs() <= 1e-9 * sigma, "t {t} vs {exact}: gap {gap:e}");
    }

    #[test]
    fn stable_root_keeps_digits_for_slow_pairs() {
        // dv tiny: the naive formula (-b - sqrt(d))/a cancels; the stable one gives gap/speed.
        let t = time_to_contact(v(3.0, 0.0), v(-1e-12, 0.0), 2.0).unwrap();
        assert!((t - 1e12).abs() / 1e12 < 1e-14, "{t}");
    }
}
