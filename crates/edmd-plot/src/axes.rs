//! Linear and logarithmic axes for plotters.
//!
//! plotters 0.3.7 has its own, but its `f64` axis gives a single odd tick
//! for very small ranges (around 1e-21), its logarithmic axis hangs when the
//! range spans more than about 308 decades (the ratio of the ends overflows)
//! and silently drops every tick below 2.2e-16. These choose ticks at
//! 1, 2 or 5 × 10^k (decades on the logarithmic axis) for any finite range.

use std::ops::Range;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, KeyPointWeight};
use plotters::prelude::Ranged;

/// Maps `t` in `lo..hi` onto the pixel interval `limit`.
fn map_linear(t: f64, (lo, hi): (f64, f64), limit: (i32, i32)) -> i32 {
    let f = (t - lo) / (hi - lo);
    let span = f64::from(limit.1) - f64::from(limit.0);
    let px = f64::from(limit.0) + f * span;
    if px.is_nan() {
        limit.0
    } else {
        // Far outside the plot is still far outside; `as` saturates.
        px.clamp(-1e7, 1e7).round() as i32
    }
}

/// Ticks at `k × step` inside `lo..=hi`, with `step` 1, 2 or 5 × 10^n, the
/// smallest giving at most `max` ticks. Returns the ticks and the step.
fn nice_ticks(lo: f64, hi: f64, max: usize) -> (Vec<f64>, f64) {
    let span = hi - lo;
    if max == 0 || !span.is_finite() || span <= 0.0 {
        return (Vec::new(), 0.0);
    }
    let raw = span / max as f64;
    let mut decade = 10f64.powf(raw.log10().floor());
    // A step of at least `raw` gives at most `max + 1` ticks, so the second
    // candidate at the latest gives at most `max`.
    for _ in 0..3 {
        for m in [1.0, 2.0, 5.0] {
            let step = m * decade;
            if step < raw * (1.0 - 1e-9) {
                continue;
            }
            if let Some(ticks) = ticks_with_step(lo, hi, step, max) {
                return (ticks, step);
            }
        }
        decade *= 10.0;
    }
    (Vec::new(), 0.0)
}

/// Ticks at `k × step` inside `lo..=hi`; `None` when more than `cap`.
fn ticks_with_step(lo: f64, hi: f64, step: f64, cap: usize) -> Option<Vec<f64>> {
    if !step.is_finite() || step <= 0.0 {
        return None;
    }
    let eps = 1e-9 * step;
    let first = ((lo - eps) / step).ceil();
    let last = ((hi + eps) / step).floor();
    if !(first.is_finite() && last.is_finite()) || last - first >= cap as f64 {
        return None;
    }
    if last < first {
        return Some(Vec::new());
    }
    Some(
        (0..=(last - first) as usize)
            .map(|i| (first + i as f64) * step)
            .collect(),
    )
}

/// Grid lines: the labelled ticks subdivided by 5 (or 2) when that fits.
fn light_ticks(lo: f64, hi: f64, bold: usize, max: usize) -> Vec<f64> {
    let (ticks, step) = nice_ticks(lo, hi, bold);
    [5.0, 2.0]
        .iter()
        .find_map(|div| ticks_with_step(lo, hi, step / div, max))
        .unwrap_or(ticks)
}

/// A linear axis over `lo..hi` (finite, `lo < hi`).
pub(crate) struct LinearAxis {
    range: (f64, f64),
}

impl LinearAxis {
    pub fn new(lo: f64, hi: f64) -> Self {
        Self { range: (lo, hi) }
    }
}

impl Ranged for LinearAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        map_linear(*value, self.range, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        let (lo, hi) = self.range;
        match hint.weight() {
            KeyPointWeight::Bold => nice_ticks(lo, hi, hint.max_num_points()).0,
            KeyPointWeight::Any => light_ticks(lo, hi, hint.bold_points(), hint.max_num_points()),
        }
    }

    fn range(&self) -> Range<f64> {
        self.range.0..self.range.1
    }
}

/// A logarithmic axis over `lo..hi` (positive, finite, `lo < hi`).
pub(crate) struct LogAxis {
    range: (f64, f64),
    /// The same range in log10 space.
    t_range: (f64, f64),
}

impl LogAxis {
    pub fn new(lo: f64, hi: f64) -> Self {
        Self {
            range: (lo, hi),
            t_range: (lo.log10(), hi.log10()),
        }
    }

    /// Every `step`-th decade in range, `step` as small as fits in `max`.
    fn decades(&self, max: usize) -> Vec<f64> {
        let (t0, t1) = self.t_range;
        let (k0, k1) = ((t0 - 1e-9).ceil() as i64, (t1 + 1e-9).floor() as i64);
        if k1 < k0 || max == 0 {
            return Vec::new();
        }
        let count = (k1 - k0 + 1) as usize;
        let step = count.div_ceil(max).max(1) as i64;
        // Multiples of the step, so that 10^0 = 1 is a tick when in range.
        let first = k0.div_euclid(step) * step;
        let first = if first < k0 { first + step } else { first };
        (0..)
            .map(|i| first + i * step)
            .take_while(|&k| k <= k1)
            .map(|k| 10f64.powi(k as i32))
            .collect()
    }

    /// `m × 10^k` for m = 1..9 in range, ascending; empty when there would
    /// be more than `max`.
    fn mantissas(&self, max: usize) -> Vec<f64> {
        let (t0, t1) = self.t_range;
        let (k0, k1) = (t0.floor() as i64, t1.ceil() as i64);
        if (k1 - k0 + 1) * 9 > 2 * max as i64 + 18 {
            return Vec::new();
        }
        let (lo, hi) = self.range;
        let ticks: Vec<f64> = (k0..=k1)
            .flat_map(|k| (1..=9).map(move |m| f64::from(m) * 10f64.powi(k as i32)))
            .filter(|v| *v >= lo * (1.0 - 1e-9) && *v <= hi * (1.0 + 1e-9))
            .collect();
        if ticks.len() <= max {
            ticks
        } else {
            Vec::new()
        }
    }
}

impl Ranged for LogAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let t = if *value > 0.0 {
            value.log10()
        } else {
            f64::MIN_POSITIVE.log10()
        };
        map_linear(t, self.t_range, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        let (lo, hi) = self.range;
        let bold = self.decades(hint.bold_points());
        if bold.len() < 2 {
            // Less than about a decade: ordinary ticks read better.
            return LinearAxis::new(lo, hi).key_points(hint);
        }
        match hint.weight() {
            KeyPointWeight::Bold => bold,
            KeyPointWeight::Any => {
                let fine = self.mantissas(hint.max_num_points());
                if fine.is_empty() {
                    bold
                } else {
                    fine
                }
            }
        }
    }

    fn range(&self) -> Range<f64> {
        self.range.0..self.range.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::coord::ranged1d::{BoldPoints, LightPoints};

    fn close(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(x, y)| (x - y).abs() <= 1e-12 * y.abs().max(1e-300))
    }

    #[test]
    fn linear_ticks() {
        let axis = LinearAxis::new(-0.05, 1.05);
        let t = axis.key_points(BoldPoints(10));
        assert!(close(&t, &[0.0, 0.2, 0.4, 0.6, 0.8, 1.0]), "{t:?}");
        assert_eq!(t[0], 0.0);
        // Tiny and huge ranges work alike.
        let t = LinearAxis::new(-1.1e-21, 1.1e-21).key_points(BoldPoints(10));
        assert!(close(&t, &[-1e-21, -5e-22, 0.0, 5e-22, 1e-21]), "{t:?}");
        let t = LinearAxis::new(0.0, 3e8).key_points(BoldPoints(4));
        assert!(close(&t, &[0.0, 1e8, 2e8, 3e8]), "{t:?}");
        // Grid lines subdivide the labelled ticks (0, 0.5, 1) by 5.
        let light = LinearAxis::new(0.0, 1.0).key_points(LightPoints::new(5, 50));
        assert_eq!(light.len(), 11);
        assert!((light[3] - 0.3).abs() < 1e-15);
        // Never more than asked for.
        for n in 1..30 {
            assert!(LinearAxis::new(-3.7, 12.9).key_points(BoldPoints(n)).len() <= n);
        }
    }

    #[test]
    fn mapping() {
        assert_eq!(LinearAxis::new(0.0, 2.0).map(&1.0, (0, 100)), 50);
        assert_eq!(LinearAxis::new(0.0, 2.0).map(&f64::NAN, (0, 100)), 0);
        let axis = LogAxis::new(1.0, 100.0);
        assert_eq!(axis.map(&1.0, (0, 200)), 0);
        assert_eq!(axis.map(&10.0, (0, 200)), 100);
        assert_eq!(axis.map(&100.0, (0, 200)), 200);
        // Non-positive values go far below (and do not panic).
        assert!(axis.map(&0.0, (0, 200)) < 0);
    }

    #[test]
    fn decade_ticks() {
        let axis = LogAxis::new(0.5, 2000.0);
        assert_eq!(
            axis.key_points(BoldPoints(10)),
            vec![1.0, 10.0, 100.0, 1000.0]
        );
        // Too many decades: every n-th one, including 1.
        let ticks = LogAxis::new(1e-300, 1e300).key_points(BoldPoints(10));
        assert!(ticks.len() <= 10 && ticks.len() >= 5, "{ticks:?}");
        assert!(ticks.contains(&1.0));
        // Below 2.2e-16 too.
        let ticks = LogAxis::new(1e-25, 1e-19).key_points(BoldPoints(10));
        assert_eq!(ticks.len(), 7);
        // Less than a decade: linear ticks.
        let ticks = LogAxis::new(2.0, 3.0).key_points(BoldPoints(5));
        assert!(close(&ticks, &[2.0, 2.5, 3.0]), "{ticks:?}");
    }
}
