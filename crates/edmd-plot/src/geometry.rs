//! Pure arithmetic behind the figures: histograms, axis ranges, clipping.

use crate::{Figure, SeriesKind};

/// Counts `values` into `bins` equal bins over `range` (default: the extent
/// of the finite values) and returns `(bin centre, count)` pairs, or
/// `(bin centre, density)` when `normalise` (densities integrate to 1 over
/// the range).
///
/// Bins are half-open `[lo, hi)` except the last, which also takes values
/// equal to the upper end. Non-finite values and values outside the range
/// are ignored. A degenerate range (all values equal) is widened around the
/// value. Returns an empty vector when `bins` is 0, or when no range is
/// given and there is no finite value.
///
/// ```
/// let h = edmd_plot::histogram(&[0.0, 0.2, 0.6, 1.0], 2, Some((0.0, 1.0)), false);
/// assert_eq!(h, vec![(0.25, 2.0), (0.75, 2.0)]);
/// ```
pub fn histogram(
    values: &[f64],
    bins: usize,
    range: Option<(f64, f64)>,
    normalise: bool,
) -> Vec<(f64, f64)> {
    if bins == 0 {
        return Vec::new();
    }
    let range = range
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .or_else(|| extent(values.iter().copied()));
    let Some((lo, hi)) = range else {
        return Vec::new();
    };
    let (lo, hi) = widen(lo.min(hi), lo.max(hi));
    let width = (hi - lo) / bins as f64;
    let mut counts = vec![0usize; bins];
    for &v in values {
        if !(v >= lo && v <= hi) {
            continue;
        }
        // `v <= hi`, so only the upper end (or rounding near it) can reach `bins`.
        let i = (((v - lo) / (hi - lo)) * bins as f64) as usize;
        counts[i.min(bins - 1)] += 1;
    }
    let total: usize = counts.iter().sum();
    // Density: count / (total × width); zero everywhere when nothing counted.
    let norm = if normalise {
        total.max(1) as f64 * width
    } else {
        1.0
    };
    counts
        .iter()
        .enumerate()
        .map(|(i, &c)| (lo + (i as f64 + 0.5) * width, c as f64 / norm))
        .collect()
}

/// The smallest and largest finite values, if any.
fn extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((a, b)) => Some((a.min(v), b.max(v))),
        })
}

/// Widens a zero-width (or inverted) interval to a usable one.
fn widen(lo: f64, hi: f64) -> (f64, f64) {
    // Keep widths finite (a plot from -f64::MAX to f64::MAX cannot be drawn).
    let (lo, hi) = (lo.clamp(-1e300, 1e300), hi.clamp(-1e300, 1e300));
    if hi > lo {
        return (lo, hi);
    }
    let mid = 0.5 * (lo + hi);
    let half = if mid == 0.0 { 1.0 } else { 0.1 * mid.abs() };
    (mid - half, mid + half)
}

/// Adds a 5% margin each side.
fn with_margin(lo: f64, hi: f64) -> (f64, f64) {
    let (lo, hi) = widen(lo, hi);
    let m = 0.05 * (hi - lo);
    (lo - m, hi + m)
}

/// Plot-space y: `log10(y)` on a logarithmic axis (NaN for `y <= 0`).
fn to_axis(log: bool, y: f64) -> f64 {
    if !log {
        y
    } else if y > 0.0 {
        y.log10()
    } else {
        f64::NAN
    }
}

fn from_axis(log: bool, t: f64) -> f64 {
    if log {
        10f64.powf(t)
    } else {
        t
    }
}

/// The data window of a figure, after defaults and sanitising.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Frame {
    /// x range, `lo < hi`, both finite.
    pub x: (f64, f64),
    /// y range, `lo < hi`, both finite (both positive when `log_y`).
    pub y: (f64, f64),
    /// Logarithmic y axis.
    pub log_y: bool,
}

impl Frame {
    /// The ranges a figure is drawn with.
    pub fn of(fig: &Figure) -> Self {
        let log = fig.log_y;
        let mut xs: Vec<f64> = Vec::new();
        // y values in plot space (log10 when the axis is logarithmic).
        let mut ts: Vec<f64> = Vec::new();
        for s in &fig.series {
            let valid = || {
                s.points
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| p.0.is_finite() && to_axis(log, p.1).is_finite())
            };
            match &s.kind {
                SeriesKind::Line | SeriesKind::Points => {
                    for (_, p) in valid() {
                        xs.push(p.0);
                        ts.push(to_axis(log, p.1));
                    }
                }
                SeriesKind::Bars => {
                    let half = 0.5 * bar_width(&s.points, log);
                    for (_, p) in valid() {
                        xs.extend([p.0 - half, p.0 + half]);
                        ts.push(to_axis(log, p.1));
                        if !log {
                            ts.push(0.0);
                        }
                    }
                }
                SeriesKind::ErrorBars(errors) => {
                    for (i, p) in valid() {
                        xs.push(p.0);
                        ts.push(to_axis(log, p.1));
                        if let Some(e) = errors.get(i).map(|e| e.abs()).filter(|e| e.is_finite()) {
                            ts.push(to_axis(log, p.1 + e));
                            ts.push(to_axis(log, p.1 - e));
                        }
                    }
                }
            }
        }
        let auto_x = || {
            extent(xs.iter().copied())
                .map(|(a, b)| with_margin(a, b))
                .unwrap_or((0.0, 1.0))
        };
        let auto_t = || {
            extent(ts.iter().copied())
                .map(|(a, b)| with_margin(a, b))
                .unwrap_or((0.0, 1.0))
        };
        let x = fig
            .x_range
            .and_then(|(a, b)| user_range(false, a, b))
            .unwrap_or_else(auto_x);
        let t = fig
            .y_range
            .and_then(|(a, b)| user_range(log, a, b))
            .unwrap_or_else(auto_t);
        let y = if log {
            // Keep the range representable: 1e-300 .. 1e300.
            let (a, b) = (t.0.clamp(-300.0, 299.0), t.1.clamp(-299.0, 300.0));
            let (a, b) = if b > a { (a, b) } else { (a, a + 1.0) };
            (from_axis(true, a), from_axis(true, b))
        } else {
            t
        };
        Frame { x, y, log_y: log }
    }

    /// `(x, plot-space y)` of the window's corners, lower then upper.
    fn axis_box(&self) -> ((f64, f64), (f64, f64)) {
        (
            (self.x.0, to_axis(self.log_y, self.y.0)),
            (self.x.1, to_axis(self.log_y, self.y.1)),
        )
    }

    /// Whether a data point can be drawn at all on this axis.
    pub fn valid(&self, p: (f64, f64)) -> bool {
        p.0.is_finite() && to_axis(self.log_y, p.1).is_finite()
    }

    /// Whether a data point lies inside the window.
    pub fn contains(&self, p: (f64, f64)) -> bool {
        self.valid(p) && p.0 >= self.x.0 && p.0 <= self.x.1 && p.1 >= self.y.0 && p.1 <= self.y.1
    }

    /// Clamps a y value into the window (for bars and error bars).
    pub fn clamp_y(&self, y: f64) -> f64 {
        if self.log_y && y <= 0.0 {
            self.y.0
        } else {
            y.clamp(self.y.0, self.y.1)
        }
    }

    /// Cuts a polyline into the runs that lie inside the window; invalid
    /// points break it.
    pub fn clip_polyline(&self, points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
        let log = self.log_y;
        let to = |p: (f64, f64)| (p.0, to_axis(log, p.1));
        let back = |p: (f64, f64)| (p.0, from_axis(log, p.1));
        let (lo, hi) = self.axis_box();
        let mut runs = Vec::new();
        let mut run: Vec<(f64, f64)> = Vec::new();
        let mut flush = |run: &mut Vec<(f64, f64)>| {
            if run.len() > 1 {
                runs.push(std::mem::take(run));
            } else {
                run.clear();
            }
        };
        for w in points.windows(2) {
            if !(self.valid(w[0]) && self.valid(w[1])) {
                flush(&mut run);
                continue;
            }
            let (a, b) = (to(w[0]), to(w[1]));
            match clip_segment(a, b, lo, hi) {
                None => flush(&mut run),
                Some(Clipped {
                    start: p,
                    end: q,
                    start_cut,
                    end_cut,
                }) => {
                    if start_cut || run.is_empty() {
                        flush(&mut run);
                        // Exact data point when not cut, to avoid a round trip.
                        run.push(if start_cut { back(p) } else { w[0] });
                    }
                    run.push(if end_cut { back(q) } else { w[1] });
                    if end_cut {
                        flush(&mut run);
                    }
                }
            }
        }
        flush(&mut run);
        runs
    }
}

/// A caller's range, sanitised; `None` when unusable (not finite, or not
/// positive on a logarithmic axis). Returned in plot space.
fn user_range(log: bool, a: f64, b: f64) -> Option<(f64, f64)> {
    let (a, b) = (to_axis(log, a), to_axis(log, b));
    if !(a.is_finite() && b.is_finite()) {
        return None;
    }
    Some(widen(a.min(b), a.max(b)))
}

/// The visible part of a segment, and whether its ends were cut.
struct Clipped {
    start: (f64, f64),
    end: (f64, f64),
    start_cut: bool,
    end_cut: bool,
}

/// Liang–Barsky clipping of segment `a`–`b` to the box `lo`–`hi`. Returns
/// the visible part and whether its start and end were cut.
fn clip_segment(a: (f64, f64), b: (f64, f64), lo: (f64, f64), hi: (f64, f64)) -> Option<Clipped> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let mut t0 = 0.0f64;
    let mut t1 = 1.0f64;
    for (p, q) in [
        (-dx, a.0 - lo.0),
        (dx, hi.0 - a.0),
        (-dy, a.1 - lo.1),
        (dy, hi.1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 || !t0.is_finite() || !t1.is_finite() {
        return None;
    }
    let at = |t: f64| (a.0 + t * dx, a.1 + t * dy);
    Some(Clipped {
        start: at(t0),
        end: at(t1),
        start_cut: t0 > 0.0,
        end_cut: t1 < 1.0,
    })
}

/// Width of the bars of a histogram: the smallest gap between distinct
/// neighbouring centres (1, or a fifth of |x|, for a single bar).
pub(crate) fn bar_width(points: &[(f64, f64)], log: bool) -> f64 {
    let mut xs: Vec<f64> = points
        .iter()
        .filter(|p| p.0.is_finite() && to_axis(log, p.1).is_finite())
        .map(|p| p.0)
        .collect();
    xs.sort_by(f64::total_cmp);
    let gap = xs
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0 && d.is_finite())
        .fold(f64::INFINITY, f64::min);
    if gap.is_finite() {
        gap
    } else {
        match xs.first() {
            Some(&x) if x != 0.0 => 0.2 * x.abs(),
            _ => 1.0,
        }
    }
}

/// A corner of the plot, for the legend.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Corner {
    UpperRight,
    UpperLeft,
    LowerRight,
    LowerLeft,
}

/// The corner whose box (40% of the width, 35% of the height, in plot
/// space) holds the fewest data points; ties prefer the upper right.
pub(crate) fn legend_corner(fig: &Figure, frame: &Frame) -> Corner {
    let ((x0, t0), (x1, t1)) = frame.axis_box();
    let (fx, ft) = (0.40, 0.35);
    let corners = [
        Corner::UpperRight,
        Corner::UpperLeft,
        Corner::LowerRight,
        Corner::LowerLeft,
    ];
    let mut counts = [0usize; 4];
    for s in &fig.series {
        for &p in &s.points {
            if !frame.contains(p) {
                continue;
            }
            let u = (p.0 - x0) / (x1 - x0);
            let v = (to_axis(frame.log_y, p.1) - t0) / (t1 - t0);
            let (right, left) = (u >= 1.0 - fx, u <= fx);
            let (upper, lower) = (v >= 1.0 - ft, v <= ft);
            // Bars fill down to the axis: count them in the lower boxes too.
            let bar = s.kind == SeriesKind::Bars;
            for (k, c) in corners.iter().enumerate() {
                let hit = match c {
                    Corner::UpperRight => right && upper,
                    Corner::UpperLeft => left && upper,
                    Corner::LowerRight => right && (lower || bar),
                    Corner::LowerLeft => left && (lower || bar),
                };
                counts[k] += usize::from(hit);
            }
        }
    }
    let best = (0..4).min_by_key(|&k| counts[k]).unwrap_or(0);
    corners[best]
}

/// A tick label with `digits` significant digits, trailing zeros trimmed,
/// scientific notation below 1e-4 and from 1e6 on in magnitude, no `-0`.
pub(crate) fn tick_label(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        return String::new();
    }
    if v == 0.0 {
        return "0".to_owned();
    }
    let digits = digits.clamp(1, 17);
    let mag = v.abs().log10().floor() as i32;
    let s = if (-4..6).contains(&mag) {
        let decimals = (digits as i32 - 1 - mag).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_owned()
        } else {
            s
        }
    } else {
        let s = format!("{v:.prec$e}", prec = digits - 1);
        match s.split_once('e') {
            Some((mantissa, exp)) if mantissa.contains('.') => {
                format!(
                    "{}e{exp}",
                    mantissa.trim_end_matches('0').trim_end_matches('.')
                )
            }
            _ => s,
        }
    };
    if s == "-0" {
        "0".to_owned()
    } else {
        s
    }
}

/// The fewest significant digits (at least 2, at most 15) whose labels tell
/// neighbouring ticks apart, each within a hundredth of the tick spacing.
pub(crate) fn tick_digits(ticks: &[f64]) -> usize {
    let spacing = ticks
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min);
    if !spacing.is_finite() {
        return 6;
    }
    (2..=15)
        .find(|&digits| {
            let labels: Vec<String> = ticks.iter().map(|&v| tick_label(v, digits)).collect();
            let distinct = labels.windows(2).all(|w| w[0] != w[1]);
            let accurate = ticks.iter().zip(&labels).all(|(&v, l)| {
                l.parse::<f64>()
                    .is_ok_and(|p| (p - v).abs() <= 0.01 * spacing)
            });
            distinct && accurate
        })
        .unwrap_or(15)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Series;

    #[test]
    fn widen_degenerate() {
        assert_eq!(widen(2.0, 2.0), (1.8, 2.2));
        assert_eq!(widen(0.0, 0.0), (-1.0, 1.0));
        assert_eq!(widen(0.0, 1.0), (0.0, 1.0));
    }

    #[test]
    fn frame_defaults_and_margins() {
        let fig =
            Figure::new("t", "x", "y").with(Series::line("a", vec![(0.0, 10.0), (10.0, 20.0)]));
        let f = Frame::of(&fig);
        assert_eq!(f.x, (-0.5, 10.5));
        assert_eq!(f.y, (9.5, 20.5));
        // Empty figure: a unit box.
        let f = Frame::of(&Figure::new("t", "x", "y"));
        assert_eq!((f.x, f.y), ((0.0, 1.0), (0.0, 1.0)));
        // Bars include zero and half a bar each side.
        let fig = Figure::new("t", "x", "y").with(Series::bars("h", vec![(1.0, 4.0), (2.0, 2.0)]));
        let f = Frame::of(&fig);
        assert!((f.x.0 - 0.4).abs() < 1e-12 && (f.x.1 - 2.6).abs() < 1e-12);
        assert!((f.y.0 + 0.2).abs() < 1e-12 && (f.y.1 - 4.2).abs() < 1e-12);
    }

    #[test]
    fn frame_log_and_user_ranges() {
        let fig = Figure::new("t", "x", "y")
            .with(Series::points(
                "a",
                vec![(0.0, 1.0), (1.0, 100.0), (2.0, -5.0), (3.0, 0.0)],
            ))
            .with_log_y();
        let f = Frame::of(&fig);
        assert_eq!(f.x, (-0.05, 1.05));
        assert!((f.y.0 - 10f64.powf(-0.1)).abs() < 1e-12);
        assert!((f.y.1 - 10f64.powf(2.1)).abs() < 1e-9);
        // Unusable user ranges fall back to the data; reversed ones are sorted.
        let fig = fig.with_y_range(-1.0, 10.0).with_x_range(5.0, 1.0);
        let f = Frame::of(&fig);
        assert_eq!(f.x, (1.0, 5.0));
        assert!((f.y.0 - 10f64.powf(-0.1)).abs() < 1e-12);
    }

    #[test]
    fn clipping_cuts_runs() {
        let fig = Figure::new("t", "x", "y")
            .with_x_range(0.0, 1.0)
            .with_y_range(0.0, 1.0);
        let f = Frame::of(&fig);
        let runs = f.clip_polyline(&[
            (0.5, 0.5),
            (0.5, 2.0),
            (0.6, 2.0),
            (0.6, 0.5),
            (f64::NAN, 0.5),
            (0.2, 0.2),
            (0.3, 0.3),
        ]);
        assert_eq!(
            runs,
            vec![
                vec![(0.5, 0.5), (0.5, 1.0)],
                vec![(0.6, 1.0), (0.6, 0.5)],
                vec![(0.2, 0.2), (0.3, 0.3)],
            ]
        );
    }

    #[test]
    fn bar_widths() {
        assert_eq!(bar_width(&[(1.0, 1.0), (3.0, 1.0), (1.5, 2.0)], false), 0.5);
        assert_eq!(bar_width(&[(5.0, 1.0)], false), 1.0);
        assert_eq!(bar_width(&[(0.0, 1.0)], false), 1.0);
        assert_eq!(bar_width(&[], false), 1.0);
    }

    #[test]
    fn legend_avoids_data() {
        // A decaying curve fills the upper left: the legend goes elsewhere.
        let pts: Vec<_> = (0..50)
            .map(|i| (i as f64, (-(i as f64) / 5.0).exp()))
            .collect();
        let fig = Figure::new("t", "x", "y").with(Series::line("a", pts.clone()));
        assert_eq!(legend_corner(&fig, &Frame::of(&fig)), Corner::UpperRight);
        let rising: Vec<_> = pts.iter().map(|&(x, y)| (x, 1.0 - y)).collect();
        let fig = Figure::new("t", "x", "y").with(Series::line("a", rising));
        assert_eq!(legend_corner(&fig, &Frame::of(&fig)), Corner::LowerRight);
    }

    #[test]
    fn tick_labels() {
        assert_eq!(tick_label(0.30000000000000004, 6), "0.3");
        assert_eq!(tick_label(-0.0, 6), "0");
        assert_eq!(tick_label(-1e-9, 3), "-1e-9");
        assert_eq!(tick_label(1500.0, 6), "1500");
        assert_eq!(tick_label(2.5e-7, 6), "2.5e-7");
        assert_eq!(tick_label(3e8, 6), "3e8");
        assert_eq!(tick_label(1e-32, 6), "1e-32");
        assert_eq!(tick_label(9.999999999999999e-33, 6), "1e-32");
        assert_eq!(tick_label(-1e-21 * 0.5, 6), "-5e-22");
        assert_eq!(tick_label(1_000_000.0 + 0.002, 10), "1.000000002e6");
        assert_eq!(tick_label(0.0001, 6), "0.0001");
        assert_eq!(tick_label(123456.0, 6), "123456");
        assert_eq!(tick_label(2.6, 1), "3");
        assert_eq!(tick_label(f64::NAN, 6), "");
    }

    #[test]
    fn digits_tell_ticks_apart() {
        let ticks: Vec<f64> = (0..=5).map(|k| f64::from(k) * 0.2).collect();
        assert_eq!(tick_digits(&ticks), 2);
        let ticks = [1.5, 2.0, 2.5];
        assert_eq!(tick_digits(&ticks), 2);
        let labels: Vec<_> = ticks.iter().map(|&t| tick_label(t, 2)).collect();
        assert_eq!(labels, ["1.5", "2", "2.5"]);
        // A small spread on a large offset needs many digits.
        let ticks: Vec<f64> = (0..5)
            .map(|k| (24_691_356_000.0 + f64::from(k)) * 5e-8)
            .collect();
        let d = tick_digits(&ticks);
        let labels: Vec<_> = ticks.iter().map(|&t| tick_label(t, d)).collect();
        assert_eq!(labels[1], "1234.56780005", "{labels:?}");
        assert_eq!(tick_digits(&[7.0]), 6);
        assert_eq!(tick_digits(&[]), 6);
    }
}
