//! Time for a coordinate moving at constant speed, or under a constant acceleration, to leave
//! an interval `[lo, hi]`.
//!
//! These kernels serve both disc-wall collisions (the interval of allowed centre positions,
//! `[r, L - r]`) and cell crossings (the cell's extent), one axis at a time.

/// Which end of an interval (a wall pair, a cell) is reached.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// The lower end `lo` (moving in the negative direction).
    Low,
    /// The upper end `hi` (moving in the positive direction).
    High,
}

/// Time until `x + v t` reaches `lo` (for `v < 0`) or `hi` (for `v > 0`); `None` for `v == 0` or
/// an infinite end.
///
/// A coordinate already past the end it is heading for (by rounding) exits at once: the time is
/// clamped to zero, never negative.
#[inline(always)]
pub fn interval_exit(x: f64, v: f64, lo: f64, hi: f64) -> Option<(f64, Side)> {
    let (dt, high) = interval_exit_or_inf(x, v, lo, hi);
    (dt != f64::INFINITY).then_some((dt, if high { Side::High } else { Side::Low }))
}

/// [`interval_exit`] with `+inf` for "never" and `true` for [`Side::High`], computed without
/// branches: the sign of a velocity component is a coin toss for the branch predictor. An
/// infinite `lo` or `hi` is an end that is never reached.
#[inline(always)]
pub fn interval_exit_or_inf(x: f64, v: f64, lo: f64, hi: f64) -> (f64, bool) {
    let high = v > 0.0;
    let end = [lo, hi][high as usize];
    let dt = ((end - x) / v).max(0.0);
    (if v != 0.0 { dt } else { f64::INFINITY }, high)
}

/// Time until `x + v t + g t^2 / 2` first reaches `lo` or `hi`, and which, for a coordinate in
/// a field (`g` its acceleration); `None` if it never does (an infinite end is never reached).
///
/// Closed form, from the quadratic's roots in the form that loses no digits to cancellation
/// (`-2c / (b + sqrt(b^2 - 4ac))`, and `(b + sqrt(b^2 - 4ac)) / -2a` for the way back). The
/// coordinate heads for `hi` when `v > 0` (or `v == 0` and `g > 0`): it reaches `hi` unless it
/// turns first, and then, pulled back (`g < 0`), reaches `lo`; the other way round for the
/// other direction. As [`interval_exit`], a coordinate past the end it heads for (by rounding)
/// exits at once.
#[inline(always)]
pub fn interval_exit_accel(x: f64, v: f64, g: f64, lo: f64, hi: f64) -> Option<(f64, Side)> {
    let (dt, high) = interval_exit_accel_or_inf(x, v, g, lo, hi);
    (dt != f64::INFINITY).then_some((dt, if high { Side::High } else { Side::Low }))
}

/// [`interval_exit_accel`] with `+inf` for "never" and `true` for [`Side::High`], computed
/// without branches (which way a disc moves, and whether it turns before an end, are coin
/// tosses for the branch predictor: the branching form made a run in a field twice as slow as
/// one without, for a quarter more instructions). Both roots are worked out and the one that
/// applies selected.
#[inline(always)]
pub fn interval_exit_accel_or_inf(x: f64, v: f64, g: f64, lo: f64, hi: f64) -> (f64, bool) {
    use crate::math::select;
    if g == 0.0 {
        return interval_exit_or_inf(x, v, lo, hi);
    }
    // Heading down is heading up in the mirror image `-x`.
    let up = v > 0.0 || (v == 0.0 && g > 0.0);
    let m = select(up, 1.0, -1.0);
    let (x, v, g) = (m * x, m * v, m * g);
    let (lo, hi) = (select(up, lo, -hi), select(up, hi, -lo));
    let a = 0.5 * g;
    // To `hi`: `a t^2 + v t + c = 0` with `c = x - hi <= 0`, its first root at or after 0, if
    // any (none when the coordinate turns before `hi`, or `hi` is infinite).
    let c = (x - hi).min(0.0);
    let disc = v * v - 4.0 * a * c;
    let t_hi = select(
        c == 0.0,
        0.0,
        (-2.0 * c / (v + disc.max(0.0).sqrt())).max(0.0),
    );
    let reaches_hi = hi.is_finite() && disc >= 0.0;
    // Turned back (`g < 0`) through `x` to `lo`: `c = x - lo >= 0` and `a < 0` give one root at
    // or after 0 (`+inf` for an infinite `lo`).
    let c = (x - lo).max(0.0);
    let disc = v * v - 4.0 * a * c;
    let t_lo = select(
        g < 0.0,
        (v + disc.max(0.0).sqrt()) / (-2.0 * a),
        f64::INFINITY,
    );
    let dt = select(reaches_hi, t_hi, t_lo);
    let dt = select(dt.is_nan(), f64::INFINITY, dt);
    // Mirrored back: the end reached upwards in `-x` is `lo`.
    (dt, reaches_hi == up)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn course_wall_formulas() {
        // Course text: t_R = (Lx - R - x)/u for u > 0, t_L = (R - x)/u for u < 0.
        // Lx = 10, R = 1, x = 5: right wall at 9, 4 away at speed 2 -> 2.
        assert_eq!(interval_exit(5.0, 2.0, 1.0, 9.0), Some((2.0, Side::High)));
        // Left wall at 1, 4 away at speed 0.5 -> 8.
        assert_eq!(interval_exit(5.0, -0.5, 1.0, 9.0), Some((8.0, Side::Low)));
        assert_eq!(interval_exit(5.0, 0.0, 1.0, 9.0), None);
    }

    #[test]
    fn past_the_end_exits_now() {
        assert_eq!(
            interval_exit(9.0 + 1e-15, 1.0, 1.0, 9.0),
            Some((0.0, Side::High))
        );
        assert_eq!(
            interval_exit(1.0 - 1e-15, -1.0, 1.0, 9.0),
            Some((0.0, Side::Low))
        );
    }

    /// A coordinate in a field against the closed forms: thrown up from 1 at speed 2 under
    /// g = -2 it peaks at 2 at t = 1 and is back at 1 at t = 2; with the ceiling at 1.75 it
    /// reaches it first, at t = 1 - sqrt(1 - 0.75) = 0.5.
    #[test]
    fn accelerated_exits_are_the_parabola_s_roots() {
        let (t, side) = interval_exit_accel(1.0, 2.0, -2.0, 0.5, 3.0).unwrap();
        // Back to 1 at t = 2, then to 0.5: 1 + 2t - t^2 = 0.5, t = 1 + sqrt(1.5).
        assert_eq!(side, Side::Low);
        assert!((t - (1.0 + 1.5f64.sqrt())).abs() < 1e-15, "{t}");
        let (t, side) = interval_exit_accel(1.0, 2.0, -2.0, 0.5, 1.75).unwrap();
        assert_eq!(side, Side::High);
        assert!((t - 0.5).abs() < 1e-15, "{t}");
        // Falling from rest from 3 to 1 under g = -2: t = sqrt(2).
        let (t, side) = interval_exit_accel(3.0, 0.0, -2.0, 1.0, 5.0).unwrap();
        assert_eq!(side, Side::Low);
        assert!((t - 2f64.sqrt()).abs() < 1e-15, "{t}");
        // Pulled up (g > 0) while moving down: it turns and reaches the top.
        let (t, side) = interval_exit_accel(1.0, -1.0, 2.0, f64::NEG_INFINITY, 2.0).unwrap();
        assert_eq!(side, Side::High);
        // 1 - t + t^2 = 2: t = (1 + sqrt(5)) / 2.
        assert!((t - (1.0 + 5f64.sqrt()) / 2.0).abs() < 1e-15, "{t}");
        // An infinite end is never reached; at an end heading out, at once.
        assert_eq!(
            interval_exit_accel(1.0, -1.0, 2.0, 0.0, f64::INFINITY),
            None
        );
        assert_eq!(
            interval_exit_accel(1.0, 0.0, -2.0, 1.0, 5.0),
            Some((0.0, Side::Low))
        );
        assert_eq!(
            interval_exit_accel(2.0, 1.0, 0.0, 0.0, 3.0),
            Some((1.0, Side::High))
        );
    }
}
