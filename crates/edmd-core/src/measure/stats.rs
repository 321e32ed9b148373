//! Small statistics kit for the measurements: block errors, histograms, a straight-line fit and
//! the Kolmogorov-Smirnov test. Written out here so the engine needs no statistics crate.

/// A measured value with its statistical error.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Estimate {
    /// The value over the whole measuring time (totals divided by the total time).
    pub value: f64,
    /// Standard error from block averages; `NaN` with fewer than two blocks.
    pub error: f64,
    /// Number of blocks the error comes from.
    pub blocks: usize,
}

impl Estimate {
    /// `value` with the block-average error of `block_values` (see [`block_error`]).
    pub fn new(value: f64, block_values: &[f64]) -> Self {
        Estimate {
            value,
            error: block_error(block_values),
            blocks: block_values.len(),
        }
    }
}

/// Standard error of the mean of `values`, `s / sqrt(B)` with `s` the sample standard deviation
/// (denominator `B - 1`) of the `B` block means.
///
/// Block averaging (Flyvbjerg and Petersen, J. Chem. Phys. 91, 461 (1989)): if each block is
/// longer than the correlation time, the block means are independent and this is the error of
/// their mean. `NaN` for fewer than two blocks.
pub fn block_error(values: &[f64]) -> f64 {
    let b = values.len();
    if b < 2 {
        return f64::NAN;
    }
    let mean = values.iter().sum::<f64>() / b as f64;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (b - 1) as f64;
    (var / b as f64).sqrt()
}

/// Sample variance of `values` (denominator `n - 1`); `NaN` below two values.
pub fn variance(values: &[f64]) -> f64 {
    let k = values.len();
    if k < 2 {
        return f64::NAN;
    }
    let mean = values.iter().sum::<f64>() / k as f64;
    values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (k - 1) as f64
}

/// A histogram of equal bins on `[lo, hi)`, with counts of the values that fell outside.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Histogram {
    /// Lower edge of the first bin.
    pub lo: f64,
    /// Bin width.
    pub width: f64,
    /// Counts per bin.
    pub counts: Vec<u64>,
    /// Values below `lo`.
    pub below: u64,
    /// Values at or above the upper edge (and `NaN`s).
    pub above: u64,
}

impl Histogram {
    /// `bins` equal bins on `[lo, hi)`.
    ///
    /// # Panics
    /// If `bins == 0` or the range is empty or not finite.
    pub fn new(lo: f64, hi: f64, bins: usize) -> Self {
        assert!(bins > 0, "a histogram needs at least one bin");
        assert!(
            lo.is_finite() && hi.is_finite() && hi > lo,
            "bad histogram range [{lo}, {hi})"
        );
        Histogram {
            lo,
            width: (hi - lo) / bins as f64,
            counts: vec![0; bins],
            below: 0,
            above: 0,
        }
    }

    /// Counts one value.
    pub fn add(&mut self, x: f64) {
        if x < self.lo {
            self.below += 1;
            return;
        }
        let k = ((x - self.lo) / self.width).floor();
        // Also catches NaN, for which the comparison is false.
        if k < self.counts.len() as f64 {
            self.counts[k as usize] += 1;
        } else {
            self.above += 1;
        }
    }

    /// Every value counted, in range or not.
    pub fn total(&self) -> u64 {
        self.counts.iter().sum::<u64>() + self.below + self.above
    }

    /// Centre of bin `k`.
    pub fn centre(&self, k: usize) -> f64 {
        self.lo + (k as f64 + 0.5) * self.width
    }

    /// `(bin centre, probability density)` per bin: count / (total * width), so that the
    /// densities integrate to the fraction of values in range.
    pub fn density(&self) -> Vec<(f64, f64)> {
        let norm = self.total().max(1) as f64 * self.width;
        self.counts
            .iter()
            .enumerate()
            .map(|(k, &c)| (self.centre(k), c as f64 / norm))
            .collect()
    }
}

/// Least-squares straight line `y = slope x + intercept` through `points`; `None` for fewer
/// than two points or when all `x` are equal.
pub fn linear_fit(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    Some((slope, my - slope * mx))
}

/// Result of a one-sample Kolmogorov-Smirnov test.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct KsTest {
    /// `D = sup |F_n(x) - F(x)|`, the largest distance between the empirical and the model CDF.
    pub statistic: f64,
    /// Asymptotic probability of a distance at least `D` if the samples follow the model.
    pub p_value: f64,
    /// Number of samples.
    pub samples: usize,
}

/// One-sample Kolmogorov-Smirnov test of `samples` against the continuous CDF `cdf`.
///
/// `D = max_i max(i/n - F(x_(i)), F(x_(i)) - (i-1)/n)` over the sorted samples, and
/// `p = Q_KS((sqrt(n) + 0.12 + 0.11/sqrt(n)) D)` with Stephens' small-sample correction
/// (Numerical Recipes, 3rd ed., section 14.3; M. A. Stephens, J. R. Stat. Soc. B 32, 115
/// (1970)). See [`kolmogorov_q`]. The samples must be independent for `p` to mean anything.
/// An empty sample gives `D = 0`, `p = 1`.
pub fn ks_test(samples: &[f64], cdf: impl Fn(f64) -> f64) -> KsTest {
    let mut x = samples.to_vec();
    x.sort_by(f64::total_cmp);
    let n = x.len();
    let nf = n as f64;
    let mut d: f64 = 0.0;
    for (i, &xi) in x.iter().enumerate() {
        let f = cdf(xi);
        d = d.max((i + 1) as f64 / nf - f).max(f - i as f64 / nf);
    }
    let p_value = if n == 0 {
        1.0
    } else {
        let s = nf.sqrt();
        kolmogorov_q((s + 0.12 + 0.11 / s) * d)
    };
    KsTest {
        statistic: d,
        p_value,
        samples: n,
    }
}

/// The Kolmogorov distribution's complementary CDF,
/// `Q_KS(l) = 2 sum_{k>=1} (-1)^(k-1) exp(-2 k^2 l^2)`.
///
/// For `l < 1.18` the equivalent, faster converging form
/// `1 - sqrt(2 pi)/l sum_{k>=1} exp(-(2k-1)^2 pi^2 / (8 l^2))` is used (Numerical Recipes,
/// 3rd ed., section 6.14, the Kolmogorov-Smirnov distribution).
pub fn kolmogorov_q(l: f64) -> f64 {
    if l.is_nan() {
        return f64::NAN;
    }
    if l <= 0.0 {
        return 1.0;
    }
    if l < 1.18 {
        let y = -std::f64::consts::PI.powi(2) / (8.0 * l * l);
        let s: f64 = (1..=6)
            .map(|k| ((2 * k - 1) as f64).powi(2) * y)
            .map(f64::exp)
            .sum();
        (1.0 - (2.0 * std::f64::consts::PI).sqrt() / l * s).clamp(0.0, 1.0)
    } else {
        let s: f64 = (1..=20)
            .map(|k| {
                let sign = if k % 2 == 1 { 1.0 } else { -1.0 };
                sign * (-2.0 * (k * k) as f64 * l * l).exp()
            })
            .sum();
        (2.0 * s).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_error_of_known_values() {
        // Mean 2.5, sample variance 5/3, error sqrt(5/3 / 4).
        let e = block_error(&[1.0, 2.0, 3.0, 4.0]);
        assert!((e - (5.0f64 / 12.0).sqrt()).abs() < 1e-15);
        assert!(block_error(&[1.0]).is_nan());
    }

    #[test]
    fn histogram_bins_and_density() {
        let mut h = Histogram::new(0.0, 2.0, 4);
        for x in [-0.1, 0.0, 0.49, 0.5, 1.99, 2.0, f64::NAN] {
            h.add(x);
        }
        assert_eq!(h.counts, vec![2, 1, 0, 1]);
        assert_eq!((h.below, h.above, h.total()), (1, 2, 7));
        assert_eq!(h.centre(1), 0.75);
        let d = h.density();
        assert!((d[0].1 - 2.0 / (7.0 * 0.5)).abs() < 1e-15);
    }

    #[test]
    fn line_through_exact_points() {
        let pts: Vec<(f64, f64)> = (0..5).map(|k| (k as f64, 3.0 * k as f64 - 1.0)).collect();
        let (a, b) = linear_fit(&pts).unwrap();
        assert!((a - 3.0).abs() < 1e-14 && (b + 1.0).abs() < 1e-14);
        assert!(linear_fit(&[(1.0, 2.0), (1.0, 3.0)]).is_none());
    }

    #[test]
    fn kolmogorov_distribution_known_values() {
        // Tabulated: Q(0.5) = 0.9639, Q(1.0) = 0.2700, Q(1.36) = 0.0494, Q(1.63) = 0.0098.
        for (l, q) in [(0.5, 0.9639), (1.0, 0.2700), (1.36, 0.0494), (1.63, 0.0098)] {
            assert!(
                (kolmogorov_q(l) - q).abs() < 1e-4,
                "Q({l}) = {}",
                kolmogorov_q(l)
            );
        }
        // The two series agree where they meet.
        let below = kolmogorov_q(1.18 - 1e-12);
        let above = kolmogorov_q(1.18);
        assert!((below - above).abs() < 1e-10);
        assert_eq!(kolmogorov_q(0.0), 1.0);
    }

    #[test]
    fn ks_statistic_of_a_hand_made_sample() {
        // Uniform CDF, samples 0.1, 0.2, 0.9: D = max(1/3 - 0.1, 2/3 - 0.2, 1 - 0.9,
        // 0.1 - 0, 0.2 - 1/3, 0.9 - 2/3) = 2/3 - 0.2.
        let t = ks_test(&[0.9, 0.1, 0.2], |x| x);
        assert!((t.statistic - (2.0 / 3.0 - 0.2)).abs() < 1e-15);
        assert_eq!(t.samples, 3);
        // A perfect grid of quantiles is at distance 1/(2n).
        let grid: Vec<f64> = (0..100).map(|k| (k as f64 + 0.5) / 100.0).collect();
        let t = ks_test(&grid, |x| x);
        assert!((t.statistic - 0.005).abs() < 1e-12);
        assert!(t.p_value > 0.999);
    }
}
