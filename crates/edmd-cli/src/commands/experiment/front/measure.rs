//! Measuring `k` in the well-mixed fluid, `D` from mean square displacements, and the
//! front's position, mean profile and speed.

use anyhow::Result;
use edmd_core::measure::{block_error, linear_fit, Estimate, Kinetics};
use edmd_core::{Simulation, Vector};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

use super::frame::Frame;
use super::setup::{build, label};
use super::{FrontArgs, A, B, BIN};

/// Blocks of the rate constant's measurement.
const RATE_BLOCKS: u64 = 64;

/// Groups of diffusion windows, and segments of the speed's fit, for the errors.
const GROUPS: usize = 8;

/// `k` in the well-mixed fluid: [`RATE_BLOCKS`] blocks, each with labels drawn afresh (half
/// `A`) and a quarter of `1/r` long, so that the `B`s are used up by a few percent at most.
/// Returns the simulation as it ends; `None` when a stop was requested.
pub(super) fn measure_rate(
    args: &FrontArgs,
    mut sim: Simulation,
    frame: &Frame,
    progress: &dyn Fn(f64),
) -> Result<Option<(Estimate, Simulation)>> {
    let mut rng = Pcg64Mcg::seed_from_u64(args.common.seed ^ 0x4B1E_0F5A_11CE_D00D);
    let bx = *sim.sim_box();
    let block = 0.25 / frame.growth;
    let (mut reactions, mut exposure, mut values) = (0u64, 0.0, Vec::new());
    for b in 0..RATE_BLOCKS {
        let mut discs = sim.discs();
        for d in &mut discs {
            label(d, if rng.random_bool(0.5) { A } else { B });
        }
        sim = build(args, &discs, bx, sim.time(), Some(1 << 40 | b))?;
        let mut kin = Kinetics::new(&sim);
        let t = sim.time() + block;
        if !edmd::run_until_or_stop(&mut sim, t, &mut kin)? {
            return Ok(None);
        }
        kin.sample(&sim);
        let rate = &kin.rates()[0];
        reactions += rate.reactions;
        exposure += rate.exposure;
        if rate.exposure > 0.0 {
            values.push(rate.reactions as f64 / rate.exposure);
        }
        progress((b + 1) as f64 / RATE_BLOCKS as f64);
    }
    let value = if exposure > 0.0 {
        reactions as f64 / exposure
    } else {
        f64::NAN
    };
    Ok(Some((Estimate::new(value, &values), sim)))
}

/// One look at the front.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sample {
    /// Time since the front started.
    pub(super) time: f64,
    /// A-mass position.
    pub(super) mass: f64,
    /// Where the A fraction falls through 1/2.
    pub(super) half: f64,
    /// Rightmost A in the measured range.
    pub(super) tip: f64,
    /// A's in the measured range.
    pub(super) a_count: usize,
}

/// Looks at the front in the box: the sample (positions in the box, time absolute) and the
/// A fraction per bin (1 outside the measured range).
pub(super) fn look(sim: &Simulation, frame: &Frame) -> (Sample, Vec<f64>) {
    let bins = frame.bins();
    let (mut a, mut all) = (vec![0usize; bins], vec![0usize; bins]);
    let mut tip = frame.x_lo;
    for i in 0..sim.len() {
        let x = sim.position(i)[0];
        let b = ((x / BIN) as usize).min(bins - 1);
        all[b] += 1;
        if sim.species(i) == A {
            a[b] += 1;
            if x >= frame.x_lo && x < frame.x_hi() {
                tip = tip.max(x);
            }
        }
    }
    let lo = (frame.x_lo / BIN).round() as usize;
    let hi = (frame.x_hi() / BIN).round() as usize;
    // An empty bin (rare: a few discs per bin at the lowest packings) takes the fraction of
    // the bin before it.
    let mut u = vec![1.0; bins];
    for b in lo..hi {
        u[b] = if all[b] > 0 {
            a[b] as f64 / all[b] as f64
        } else {
            u[b - 1]
        };
    }
    let mass = frame.x_lo + u[lo..hi].iter().sum::<f64>() * BIN;
    let half = match (lo..hi).rev().find(|&b| u[b] >= 0.5) {
        Some(b) if b + 1 < hi => {
            let (u0, u1) = (u[b], u[b + 1]);
            (b as f64 + 0.5 + (u0 - 0.5) / (u0 - u1)) * BIN
        }
        Some(b) => (b as f64 + 0.5) * BIN,
        None => frame.x_lo,
    };
    let sample = Sample {
        time: sim.time(),
        mass,
        half,
        tip,
        a_count: a[lo..hi].iter().sum(),
    };
    (sample, u)
}

/// Mean square displacements over consecutive windows, each giving `D` from its second half.
/// Positions are followed across the frame's moves and rebuilds: disc `i` is at
/// `base[i] + sim.unwrapped_position(i)`.
pub(super) struct Msd {
    /// Samples per window.
    window: usize,
    base: Vec<Vector>,
    start: Vec<Vector>,
    /// `(time lag, MSD)` of the window under way.
    points: Vec<(f64, f64)>,
    t0: f64,
    /// `D` of each finished window.
    pub(super) values: Vec<f64>,
}

impl Msd {
    pub(super) fn new(sim: &Simulation, window: usize) -> Self {
        let n = sim.len();
        let mut msd = Msd {
            window,
            base: vec![Vector::ZERO; n],
            start: Vec::new(),
            points: Vec::new(),
            t0: sim.time(),
            values: Vec::new(),
        };
        msd.start = (0..n).map(|i| msd.at(sim, i)).collect();
        msd
    }

    fn at(&self, sim: &Simulation, i: usize) -> Vector {
        self.base[i] + sim.unwrapped_position(i)
    }

    /// Carries the positions over from `old` to `new` (the same discs at the same instant).
    pub(super) fn rebase(&mut self, old: &Simulation, new: &Simulation) {
        for i in 0..old.len() {
            self.base[i] = self.at(old, i) - new.unwrapped_position(i);
        }
    }

    pub(super) fn sample(&mut self, sim: &Simulation) {
        let n = sim.len();
        let sum: f64 = (0..n)
            .map(|i| (self.at(sim, i) - self.start[i]).norm2())
            .sum();
        self.points.push((sim.time() - self.t0, sum / n as f64));
        if self.points.len() == self.window {
            let half = self.points[self.window / 2 - 1].0;
            let later: Vec<(f64, f64)> = self
                .points
                .iter()
                .copied()
                .filter(|p| p.0 >= half)
                .collect();
            if let Some((slope, _)) = linear_fit(&later) {
                self.values.push(slope / 4.0);
            }
            self.points.clear();
            self.t0 = sim.time();
            self.start = (0..n).map(|i| self.at(sim, i)).collect();
        }
    }

    /// The mean over the windows, the error from [`GROUPS`] groups of consecutive ones.
    pub(super) fn estimate(&self) -> Estimate {
        let v = &self.values;
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let per = v.len().div_ceil(GROUPS).max(1);
        let groups: Vec<f64> = v
            .chunks(per)
            .map(|c| c.iter().sum::<f64>() / c.len() as f64)
            .collect();
        Estimate::new(mean, &groups)
    }
}

/// The relative bin of the mean profile that holds `x - X` (`X` the front position), if
/// any: bins run from `x_lo - h` to `x_hi - x_lo` past the front.
pub(super) fn shape_bin(frame: &Frame, rel: f64, bins: usize) -> Option<usize> {
    let r = ((rel + frame.home - frame.x_lo) / BIN).floor();
    (r >= 0.0 && (r as usize) < bins).then_some(r as usize)
}

/// `(slope, error)` of a straight line through `points`, the error from the slopes of
/// [`GROUPS`] consecutive segments (the front's position wanders, so neighbouring points are
/// far from independent, while segments hundreds of `1/r` long nearly are).
pub(super) fn speed(points: &[(f64, f64)]) -> (f64, f64) {
    let Some((slope, _)) = linear_fit(points) else {
        return (f64::NAN, f64::NAN);
    };
    let len = points.len() / GROUPS;
    let slopes: Vec<f64> = if len >= 2 {
        points
            .chunks(len)
            .take(GROUPS)
            .filter_map(|c| linear_fit(c).map(|f| f.0))
            .collect()
    } else {
        Vec::new()
    };
    (slope, block_error(&slopes))
}
