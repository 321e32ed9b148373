//! The radial distribution function `g(r)`: how much more likely than in an ideal gas a
//! particle is to have another at distance `r`, from pair distances histogrammed at the
//! sampled times.
//!
//! `g(r_k) = 2 H_k / (S N rho V_k)` for bin `k` of `[0, r_max)`, with `H_k` the pairs counted
//! over `S` samples, `rho = N / V` and `V_k` the shell's volume (area in 2D) (Allen and
//! Tildesley, *Computer Simulation of Liquids*, 2nd ed. (2017), section 8.2). Distances are
//! minimum images on periodic axes; near walls fewer neighbours are seen, so in a walled box
//! `g` falls off at large `r` by the share of shells the walls cut.

use super::stats::Histogram;
use crate::math::Vector;
use crate::simulation::Simulation;

/// Pair distance counts for `g(r)`.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Rdf {
    hist: Histogram,
    samples: u64,
    /// `N` and the box volume (area) at the samples.
    n: usize,
    volume: f64,
}

impl Rdf {
    /// Distances in `bins` bins on `[0, r_max)`. `r_max` is cut to half the shortest box side
    /// (beyond it, pairs are counted twice or missed).
    ///
    /// # Panics
    /// If `bins == 0` or `r_max` is not finite and positive.
    pub fn new<const D: usize>(sim: &Simulation<D>, r_max: f64, bins: usize) -> Self {
        let half = 0.5
            * sim
                .sim_box()
                .lengths
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
        Rdf {
            hist: Histogram::new(0.0, r_max.min(half), bins),
            samples: 0,
            n: sim.len(),
            volume: sim.sim_box().lengths.iter().product(),
        }
    }

    /// The largest distance counted.
    pub fn r_max(&self) -> f64 {
        self.hist.lo + self.hist.width * self.hist.counts.len() as f64
    }

    /// Counts every pair closer than `r_max` now: the particles sorted into cells at least
    /// `r_max` wide, each pair found in its own or a neighbouring cell.
    pub fn sample<const D: usize>(&mut self, sim: &Simulation<D>) {
        self.samples += 1;
        let n = sim.len();
        let bx = sim.sim_box();
        let r_max = self.r_max();
        let dims: [usize; D] =
            std::array::from_fn(|a| ((bx.lengths[a] / r_max).floor() as usize).clamp(1, 1 << 10));
        let cells: usize = dims.iter().product();
        let pos: Vec<Vector<D>> = (0..n).map(|i| bx.wrap(sim.position(i))).collect();
        let cell_of = |p: &Vector<D>| -> [usize; D] {
            std::array::from_fn(|a| {
                ((p[a] / bx.lengths[a] * dims[a] as f64) as usize).min(dims[a] - 1)
            })
        };
        let index = |c: [usize; D]| c.iter().zip(&dims).fold(0, |k, (&x, &d)| k * d + x);
        let mut head = vec![usize::MAX; cells];
        let mut next = vec![usize::MAX; n];
        for (i, p) in pos.iter().enumerate() {
            let k = index(cell_of(p));
            next[i] = head[k];
            head[k] = i;
        }
        let r2max = r_max * r_max;
        for (i, p) in pos.iter().enumerate() {
            let c = cell_of(p);
            // The neighbour cells, each once even where fewer than three span an axis.
            let mut seen: Vec<usize> = Vec::with_capacity(27);
            for code in 0..3usize.pow(D as u32) {
                let mut nc = [0usize; D];
                let mut ok = true;
                let mut rest = code;
                for a in 0..D {
                    let d = (rest % 3) as isize - 1;
                    rest /= 3;
                    let x = c[a] as isize + d;
                    let periodic = bx.is_periodic(a);
                    nc[a] = if x < 0 || x >= dims[a] as isize {
                        if !periodic {
                            ok = false;
                            0
                        } else {
                            x.rem_euclid(dims[a] as isize) as usize
                        }
                    } else {
                        x as usize
                    };
                }
                let k = index(nc);
                if !ok || seen.contains(&k) {
                    continue;
                }
                seen.push(k);
                let mut j = head[k];
                while j != usize::MAX {
                    if j > i {
                        let d2 = bx.minimum_image(pos[j] - *p).norm2();
                        if d2 < r2max {
                            self.hist.add(d2.sqrt());
                        }
                    }
                    j = next[j];
                }
            }
        }
    }

    /// `(r, g(r))` at the bins' centres (empty before the first sample).
    pub fn curve<const D: usize>(&self) -> Vec<(f64, f64)> {
        if self.samples == 0 || self.n < 2 {
            return Vec::new();
        }
        let rho = self.n as f64 / self.volume;
        let w = self.hist.width;
        let ball = |r: f64| crate::setup::lattice::ball_volume(2.0 * r, D);
        self.hist
            .counts
            .iter()
            .enumerate()
            .map(|(k, &h)| {
                let (lo, hi) = (k as f64 * w, (k + 1) as f64 * w);
                let ideal = 0.5 * self.samples as f64 * self.n as f64 * rho * (ball(hi) - ball(lo));
                (0.5 * (lo + hi), h as f64 / ideal)
            })
            .collect()
    }

    /// Samples taken.
    pub fn samples(&self) -> u64 {
        self.samples
    }
}
