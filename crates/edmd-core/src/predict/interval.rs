//! Time for a coordinate moving at constant speed to leave an interval `[lo, hi]`.
//!
//! This one kernel serves both disc-wall collisions (the interval of allowed centre positions,
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
}
