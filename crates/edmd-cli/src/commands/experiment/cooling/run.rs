//! One cooling run: an elastic fluid melted and measured at `T0`, then cooled with restitution,
//! sampled on a logarithmic grid of times; and what each run's samples give.

use anyhow::Result;
use edmd_core::measure::theory::{enskog_collision_frequency_in, haff_time_sonine};
use edmd_core::{
    Boundary, EventKind, EventRecord, Observer, Restitution, RestitutionLaw, Simulation,
};

use super::super::common::{melted_fluid_in, stop_requested};

/// What a run is.
pub(super) struct Spec {
    /// Particles.
    pub n: usize,
    /// Packing fraction.
    pub packing: f64,
    /// Coefficient of normal restitution.
    pub e: f64,
    /// The TC model's time, or `None` for [`TC_PER_FREE_TIME`] of the mean free time at `T0`.
    pub tc: Option<f64>,
    /// Collisions per particle to cool for.
    pub collisions: f64,
    /// Seed of the fluid.
    pub seed: u64,
    /// Whether to keep a picture of the end.
    pub snapshot: bool,
}

/// The TC model's time by default, in mean free times at `T0`: far below the time between
/// collisions of a homogeneous gas (it makes about this fraction of them elastic, and fewer as
/// the gas cools and slows), yet a fixed time that stops inelastic collapse in clusters.
pub(super) const TC_PER_FREE_TIME: f64 = 1e-4;

/// Collisions per particle while melting the lattice (the melted-fluid helper's), and then in
/// each of the [`FREQUENCY_BLOCKS`] blocks that measure the collision frequency at `T0`.
const MELT: u64 = 20;
/// Blocks of about one collision per particle each: at `N` in the thousands their counts are
/// independent to well within their errors.
const FREQUENCY_BLOCKS: usize = 10;

/// Samples per decade of time, from `FIRST_SAMPLE` Haff times on: late in the run, where
/// `tau` grows as `ln t`, about `2 dim / (1 - e^2) ln 10 / 20` collisions per particle apart.
const PER_DECADE: f64 = 20.0;
const FIRST_SAMPLE: f64 = 1e-2;
/// Events between looks at the stop flag and the collision budget.
const SLICE: u64 = 50_000;

/// One sample of the cooling gas.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sample {
    /// Time since restitution was switched on.
    pub t: f64,
    /// Collisions per particle since then (twice the disc-disc collisions over `N`).
    pub tau: f64,
    /// Temperature, `2 E_kin / (dim N)`.
    pub kt: f64,
    /// Fraction of the kinetic energy in the transverse (shear) modes of the box's longest
    /// waves, `2 pi / L_a` along each axis `a`: `2 sum_a |J_perp(k_a)|^2 / (N^2 dim kT)`, with
    /// `J(k) = sum_i v_i exp(-i k . r_i)`; `2 (dim - 1) / N` on average in equilibrium.
    pub shear: f64,
    /// The density structure factor at the same waves, `sum_a |rho(k_a)|^2 / (dim N)`: below
    /// 1 in a homogeneous fluid, growing as clusters form.
    pub density: f64,
    /// On the grid of times shared by every run (the last sample, taken when the collision
    /// budget ran out, is not).
    pub on_grid: bool,
}

/// What one run measured.
pub(super) struct Run {
    /// The box's edge lengths.
    pub lengths: Vec<f64>,
    /// Temperature when restitution was switched on.
    pub kt0: f64,
    /// Collision frequency per particle at `T0`, per block, measured while still elastic.
    pub omega_blocks: Vec<f64>,
    /// The TC model's time used.
    pub tc: f64,
    /// The samples, from `t = 0`.
    pub samples: Vec<Sample>,
    /// Disc-disc collisions while cooling, and how many of them the TC model made elastic.
    pub collisions: u64,
    /// See `collisions`.
    pub elastic: u64,
    /// The state at the end, to draw (2D: the discs; 3D: the spheres' mid-plane).
    pub snapshot: Option<edmd_draw::Scene>,
    /// Collisions per particle at the last sample before an inelastic collapse spent the rest
    /// of the run's collisions, if one did.
    pub collapse: Option<f64>,
}

/// Counts disc-disc collisions and those that were elastic: from the impulse `J` along the
/// line of centres and the velocities after, the normal relative speed before is
/// `v_after + |J| / mu`, so the coefficient applied is `-v_after / v_before`; elastic ones
/// (the TC model's) are told from `e` by being nearer 1.
struct ElasticCount {
    e: f64,
    collisions: u64,
    elastic: u64,
}

impl<const D: usize> Observer<D> for ElasticCount {
    fn on_event(&mut self, ev: &EventRecord<D>, sim: &Simulation<D>) {
        if let EventKind::DiscDisc { i, j } = ev.kind {
            self.collisions += 1;
            let size = ev.impulse.norm2().sqrt();
            if size == 0.0 {
                return;
            }
            let u = ev.impulse / size;
            let (mi, mj) = (sim.mass(i), sim.mass(j));
            let after = (sim.velocity(j) - sim.velocity(i)).dot(u);
            let before = after + size * (mi + mj) / (mi * mj);
            if -after > 0.5 * (1.0 + self.e) * before {
                self.elastic += 1;
            }
        }
    }
}

/// The shear and density modes of `sim` at its current time (see [`Sample`]).
fn modes<const D: usize>(sim: &Simulation<D>) -> (f64, f64) {
    let lengths = sim.sim_box().lengths;
    let (mut jc, mut js) = ([[0.0; D]; D], [[0.0; D]; D]);
    let (mut rc, mut rs) = ([0.0; D], [0.0; D]);
    for i in 0..sim.len() {
        let (p, v) = (sim.position(i), sim.velocity(i));
        for a in 0..D {
            let (s, c) = (std::f64::consts::TAU * p[a] / lengths[a]).sin_cos();
            rc[a] += c;
            rs[a] += s;
            for b in 0..D {
                jc[a][b] += v[b] * c;
                js[a][b] += v[b] * s;
            }
        }
    }
    let n = sim.len() as f64;
    let kt = 2.0 * sim.kinetic_energy() / (D as f64 * n);
    let mut transverse = 0.0;
    let mut density = 0.0;
    for a in 0..D {
        for b in (0..D).filter(|&b| b != a) {
            transverse += jc[a][b] * jc[a][b] + js[a][b] * js[a][b];
        }
        density += rc[a] * rc[a] + rs[a] * rs[a];
    }
    (
        2.0 * transverse / (n * n * D as f64 * kt),
        density / (D as f64 * n),
    )
}

fn sample<const D: usize>(sim: &Simulation<D>, t: f64, c0: u64, on_grid: bool) -> Sample {
    let n = sim.len() as f64;
    let (shear, density) = modes(sim);
    Sample {
        t,
        tau: 2.0 * (sim.stats().disc_disc - c0) as f64 / n,
        kt: 2.0 * sim.kinetic_energy() / (D as f64 * n),
        shear,
        density,
        on_grid,
    }
}

/// Runs `spec`; `None` if a stop was requested.
pub(super) fn cool<const D: usize>(spec: &Spec) -> Result<Option<Run>> {
    let Some((mut sim, rate)) =
        melted_fluid_in::<D>(spec.n, spec.packing, Boundary::Periodic, spec.seed, MELT)?
    else {
        return Ok(None);
    };
    let n = spec.n as f64;
    // The collision frequency at T0, still elastic, in blocks of about a collision per disc.
    let block = 1.0 / rate;
    let mut omega_blocks = Vec::with_capacity(FREQUENCY_BLOCKS);
    for _ in 0..FREQUENCY_BLOCKS {
        let (c, t) = (sim.stats().disc_disc, sim.time());
        if !edmd::run_until_or_stop(&mut sim, t + block, &mut ())? {
            return Ok(None);
        }
        omega_blocks.push(2.0 * (sim.stats().disc_disc - c) as f64 / (n * block));
    }
    let kt0 = 2.0 * sim.kinetic_energy() / (D as f64 * n);
    let omega = omega_blocks.iter().sum::<f64>() / omega_blocks.len() as f64;
    let tc = spec.tc.unwrap_or(TC_PER_FREE_TIME / omega);
    sim.set_restitution(Some(Restitution {
        all: RestitutionLaw::Constant(spec.e),
        tc,
        ..Restitution::default()
    }))
    .or_else(|e| edmd::user_error(format!("cooling: {e}")))?;
    let t0_theory = haff_time_sonine(
        D,
        spec.e,
        enskog_collision_frequency_in(spec.packing, 1.0, kt0, 1.0, D),
    );
    let (start, c0) = (sim.time(), sim.stats().disc_disc);
    let budget = c0 + (spec.collisions * n / 2.0).ceil() as u64;
    let mut counter = ElasticCount {
        e: spec.e,
        collisions: 0,
        elastic: 0,
    };
    let mut samples = vec![sample(&sim, 0.0, c0, true)];
    let mut collapse = None;
    let mut k = 0.0;
    'grid: loop {
        let t = t0_theory * FIRST_SAMPLE * 10f64.powf(k / PER_DECADE);
        k += 1.0;
        // The clock resolves positions only up to its limit; a gas that slow has long since
        // cooled past anything measured here.
        if start + t >= sim.clock_limit() {
            break;
        }
        loop {
            let done = sim.run_events_to(start + t, SLICE, &mut edmd::shared(&mut counter));
            // Without the TC model, a clock that stops is the collapse itself: events without
            // end at one instant.
            if sim.stalled().is_some() && tc == 0.0 {
                collapse = samples.last().map(|s| s.tau);
                break 'grid;
            }
            edmd::check_stall(&sim)?;
            if stop_requested() {
                return Ok(None);
            }
            if sim.stats().disc_disc >= budget {
                let now = sim.time() - start;
                let last = samples
                    .last()
                    .expect("the first sample is taken before the loop");
                let end = sample(&sim, now, c0, false);
                // Without the TC model, a gas can collapse: clusters colliding ever faster at
                // vanishing relative speeds. A homogeneous gas collides at its starting
                // frequency scaled by sqrt(T / T0); clustering raises that by a few times at
                // most, while a collapse spends the rest of the run's collisions at once. Ten
                // times as many collisions as that since the last sample are taken for a
                // collapse: the run's end is then no state of the cooling gas, and is left out
                // of the fits.
                let most = omega * (last.kt / kt0).sqrt() * (now - last.t);
                if tc == 0.0 && end.tau - last.tau > 10.0 * most + 2.0 {
                    collapse = Some(last.tau);
                } else {
                    samples.push(end);
                }
                break 'grid;
            }
            if done < SLICE {
                break;
            }
        }
        edmd::run_until(&mut sim, start + t, &mut counter)?;
        samples.push(sample(&sim, t, c0, true));
    }
    let snapshot = spec.snapshot.then(|| picture(&sim));
    Ok(Some(Run {
        lengths: sim.sim_box().lengths.to_vec(),
        kt0,
        omega_blocks,
        tc,
        samples,
        collisions: counter.collisions,
        elastic: counter.elastic,
        snapshot,
        collapse,
    }))
}

/// The discs coloured by speed; for spheres, the plane half-way up the box.
fn picture<const D: usize>(sim: &Simulation<D>) -> edmd_draw::Scene {
    use edmd_draw::{Colouring, Scene, Scene3};
    if D == 3 {
        let scene = Scene3::capture(sim, Colouring::Speed);
        let mid = 0.5 * scene.lengths[2];
        edmd_draw::slice(&scene, 2, mid)
    } else {
        Scene::capture(sim, Colouring::Speed)
    }
}

/// What one run's samples give.
pub(super) struct Analysis {
    /// Haff's time fitted to `T(t)` before the onset.
    pub t0: f64,
    /// `-d ln T / d tau` over the same samples.
    pub decay: f64,
    /// Collisions per particle when the shear fraction first reached the onset fraction.
    pub onset: Option<f64>,
    /// Collisions per particle when `T` first stood 10% above the fitted Haff law (two samples
    /// in a row).
    pub departure: Option<f64>,
    /// The collisions per particle fitted over.
    pub window: (f64, f64),
    /// The samples in the window the law asks for; with fewer than 4 the fit falls back to
    /// the first 4 samples.
    pub fitted: usize,
}

/// Fits and onsets of one run. Haff's law makes `T^(-1/2)` linear in time,
/// `T^(-1/2) = (1 + t/t0) / sqrt(T0)`: its slope gives `t0 = 1 / (slope sqrt(T0))`, fitted
/// over the samples from `tau = 2` (the Sonine correction settles within a few collisions, and
/// a free intercept absorbs that start) to `fit_end` (where the growing shear waves are
/// predicted to hold a measurable part of the energy), or half the measured onset if that
/// comes first. Each sample is weighted by `T`, the inverse square of `T^(-1/2)`, whose
/// relative noise is the same at every temperature.
pub(super) fn analyse(run: &Run, onset_fraction: f64, fit_end: Option<f64>) -> Analysis {
    let s = &run.samples;
    let onset = crossing(s, onset_fraction);
    let end = s.last().map_or(0.0, |x| x.tau);
    let hi = end
        .min(onset.map_or(f64::INFINITY, |o| 0.5 * o))
        .min(fit_end.unwrap_or(f64::INFINITY));
    let lo = 2f64.min(0.25 * hi);
    let mut window: Vec<&Sample> = s
        .iter()
        .filter(|x| x.tau >= lo && x.tau <= hi && x.kt > 0.0)
        .collect();
    let fitted = window.len();
    if fitted < 4 {
        window = s.iter().filter(|x| x.kt > 0.0).take(4).collect();
    }
    let (a, slope) = line(window.iter().map(|x| (x.t, x.kt.powf(-0.5), x.kt)));
    let (_, decay) = line(window.iter().map(|x| (x.tau, x.kt.ln(), 1.0)));
    let haff = |t: f64| 1.0 / ((a + slope * t) * (a + slope * t));
    let departure = s
        .windows(2)
        .find(|w| w.iter().all(|x| x.tau > lo && x.kt > 1.1 * haff(x.t)))
        .map(|w| w[0].tau);
    Analysis {
        t0: 1.0 / (slope * run.kt0.sqrt()),
        decay: -decay,
        onset,
        departure,
        window: (
            window.first().map_or(f64::NAN, |x| x.tau),
            window.last().map_or(f64::NAN, |x| x.tau),
        ),
        fitted,
    }
}

/// The collisions per particle at which the shear fraction first reaches `level`, interpolated
/// in its logarithm between the samples either side.
fn crossing(s: &[Sample], level: f64) -> Option<f64> {
    let k = s.iter().position(|x| x.shear >= level)?;
    if k == 0 {
        return Some(0.0);
    }
    let (a, b) = (&s[k - 1], &s[k]);
    let (la, lb) = (a.shear.ln(), b.shear.ln());
    let f = if lb > la {
        (level.ln() - la) / (lb - la)
    } else {
        1.0
    };
    Some(a.tau + f * (b.tau - a.tau))
}

/// Weighted least squares `y = a + b x` over `(x, y, weight)`: `(a, b)`.
fn line(points: impl Iterator<Item = (f64, f64, f64)>) -> (f64, f64) {
    let p: Vec<(f64, f64, f64)> = points.collect();
    let w: f64 = p.iter().map(|q| q.2).sum();
    let mx = p.iter().map(|q| q.2 * q.0).sum::<f64>() / w;
    let my = p.iter().map(|q| q.2 * q.1).sum::<f64>() / w;
    let sxy: f64 = p.iter().map(|q| q.2 * (q.0 - mx) * (q.1 - my)).sum();
    let sxx: f64 = p.iter().map(|q| q.2 * (q.0 - mx) * (q.0 - mx)).sum();
    let b = sxy / sxx;
    (my - b * mx, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(tau: f64, shear: f64) -> Sample {
        Sample {
            t: tau,
            tau,
            kt: 1.0,
            shear,
            density: 1.0,
            on_grid: true,
        }
    }

    #[test]
    fn the_onset_is_interpolated_in_the_logarithm() {
        let s = [at(0.0, 1e-3), at(10.0, 1e-2), at(20.0, 1e-1)];
        let o = crossing(&s, 10f64.powf(-1.5)).unwrap();
        assert!((o - 15.0).abs() < 1e-12, "{o}");
        assert_eq!(crossing(&s, 0.5), None);
        assert_eq!(crossing(&s, 1e-4), Some(0.0));
    }

    #[test]
    fn a_line_is_fitted_exactly() {
        let (a, b) = line((0..5).map(|k| (k as f64, 2.0 - 0.5 * k as f64, 1.0 + k as f64)));
        assert!((a - 2.0).abs() < 1e-15 && (b + 0.5).abs() < 1e-15);
    }
}
