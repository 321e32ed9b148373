//! The box and the moving frame: its layout from the options, and the front's run, which
//! moves the frame and relabels the zone as the front advances.

use anyhow::Result;
use edmd_core::measure::{theory, Estimate};
use edmd_core::{Simulation, OVERLAP_TOLERANCE};

use super::super::common::{MAX_N, MIN_PACKING};
use super::measure::{look, shape_bin, Msd, Sample};
use super::setup::{build, label};
use super::{FrontArgs, A, B, BIN, C};

/// The densest fluid the experiment makes (equal discs are liquid up to 0.70; a lattice with
/// vacancies melts within a few collisions per disc up to about 0.6).
const MAX_PACKING: f64 = 0.6;

/// Most samples of the front's run (the CSV file and the figure stay small).
const MAX_FRONT_SAMPLES: f64 = 5000.0;

/// The box and the moving frame, in diameters (all whole bins but the width).
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    pub(super) length: f64,
    pub(super) width: f64,
    /// Number density aimed at.
    pub(super) density: f64,
    /// Growth rate r from Enskog's collision frequency (the line-of-centres law), to size
    /// the windows and blocks before k is measured.
    pub(super) growth: f64,
    /// Home position of the front.
    pub(super) home: f64,
    /// Distance of a move.
    pub(super) shift: f64,
    /// Left end of the measured range.
    pub(super) x_lo: f64,
    /// Width of the zone at the right end.
    pub(super) zone: f64,
}

impl Frame {
    pub(super) fn bins(&self) -> usize {
        (self.length / BIN).round() as usize
    }

    /// Right end of the measured range (the zone begins there).
    pub(super) fn x_hi(&self) -> f64 {
        self.length - self.zone
    }
}

/// Enskog's self-diffusion coefficient of hard discs, `sqrt(kT / (pi m)) / (2 n sigma g)`
/// (D. M. Gass, J. Chem. Phys. 54, 1898 (1971)), `kT = m = sigma = 1`: only to size the box
/// before `D` is measured (the fluid's is higher, by half at a packing of 0.3 over the times
/// that matter here).
fn enskog_diffusion(eta: f64) -> f64 {
    let n = theory::number_density(eta, 1.0);
    (1.0 / std::f64::consts::PI).sqrt() / (2.0 * n * theory::contact_value(eta, 2))
}

fn whole_bins(x: f64) -> f64 {
    (x / BIN).ceil() * BIN
}

/// Checks the options and lays out the box and the frame; also returns the front's time.
pub(super) fn plan(args: &FrontArgs) -> Result<(Frame, f64)> {
    let bad = |m: String| edmd::user_error(format!("front: {m}"));
    if !(args.packing >= MIN_PACKING && args.packing <= MAX_PACKING) {
        return bad(format!(
            "--packing must be from {MIN_PACKING} to {MAX_PACKING}, found {}",
            args.packing
        ));
    }
    if !(args.probability.is_finite() && args.probability > 0.0 && args.probability <= 1.0) {
        return bad(format!(
            "--probability must be above 0 and at most 1, found {}",
            args.probability
        ));
    }
    if !(args.activation.is_finite() && args.activation >= 0.0 && args.activation <= 10.0) {
        return bad(format!(
            "--activation must be from 0 to 10 (kT), found {}",
            args.activation
        ));
    }
    if !(args.width.is_finite() && args.width >= 4.0 && args.width <= 10_000.0) {
        return bad(format!(
            "--width must be from 4 to 10000 diameters, found {}",
            args.width
        ));
    }
    if !(args.length.is_finite() && args.length > 0.0 && args.length <= 100_000.0) {
        return bad(format!(
            "--length must be above 0 and at most 100000 diameters, found {}",
            args.length
        ));
    }
    let eta = args.packing;
    let density = theory::number_density(eta, 1.0);
    let k = args.probability
        * theory::line_of_centres_rate_constant(eta, 1.0, 1.0, 1.0, 2, args.activation);
    let growth = k * density;
    let xi = (enskog_diffusion(eta) / growth).sqrt();
    let shift = whole_bins((2.0 * xi).max(2.0));
    let x_lo = whole_bins((4.0 * xi).max(3.0));
    let home = x_lo + whole_bins((6.0 * xi).max(5.0));
    let reach = whole_bins((16.0 * xi).max(10.0));
    let zone = shift + whole_bins((8.0 * xi).max(8.0));
    let least = home + shift + reach + zone;
    let length = (args.length / BIN).round() * BIN;
    if least > 100_000.0 {
        return bad(format!(
            "--probability and --activation make the front's leading edge decay over xi = {xi:.2} diameters, and the box must be 38 of them long, more than the 100000 diameters allowed: give a larger --probability or a smaller --activation"
        ));
    }
    if args.length < least {
        return bad(format!(
            "--length must be at least {least} for this packing, probability and activation (about 38 decay lengths xi = {xi:.2} of the front's leading edge, and at least 30 for the moving frame), found {}",
            args.length
        ));
    }
    let n = (density * length * args.width).round();
    if n > MAX_N as f64 {
        return bad(format!(
            "the box holds {n} discs, more than {MAX_N}: make --length or --width smaller"
        ));
    }
    // The diffusion coefficient is measured over windows of 2 / r: a front run shorter than
    // three of them leaves D, and all the theory made from it, without a value.
    // Rounded up to the tenth that the message shows, so that the check and it agree.
    let least_until = (60.0 / growth).ceil() / 10.0;
    if least_until > 1e5 {
        return bad(format!(
            "--probability and --activation make the front grow at r = k n = {growth:.3e} per unit time, so slowly that it needs --until of at least 6 / r = {least_until:.3e}, more than the 100000 allowed: give a larger --probability or a smaller --activation"
        ));
    }
    let until = args.until.unwrap_or((500.0 / growth).min(1e5));
    if !(until.is_finite() && until >= least_until && until <= 1e5) {
        return bad(format!(
            "--until must be at least 6 / r = {least_until} (r = k n = {growth:.4}, the front's growth rate: diffusion is measured over windows of 2 / r) and at most 100000, found {until}"
        ));
    }
    Ok((
        Frame {
            length,
            width: args.width,
            density,
            growth,
            home,
            shift,
            x_lo,
            zone,
        },
        until,
    ))
}

/// What the front's run gathered.
#[derive(Default)]
pub(super) struct Run {
    pub(super) samples: Vec<Sample>,
    /// `(time, A fraction per bin, frame offset)` at six times from the start.
    pub(super) snapshots: Vec<(f64, Vec<f64>, f64)>,
    /// A's and discs per bin of the position relative to the front, from the fit's start.
    pub(super) shape_a: Vec<u64>,
    pub(super) shape_all: Vec<u64>,
    pub(super) diffusion: Option<Estimate>,
    pub(super) reactions: u64,
    pub(super) relabelled: u64,
    pub(super) moves: usize,
    pub(super) refreshes: usize,
    pub(super) tip_max: f64,
    pub(super) tip_limit: f64,
    pub(super) overlaps: usize,
    pub(super) energy_change: f64,
    pub(super) finished: bool,
}

/// Whether an `A` has crossed half the zone from its right end (the `A`s at the left end of
/// the box meet the zone's `C`s across the periodic boundary and diffuse into them), or a `B`
/// half the zone from its left end: between two moves they could meet and start a second
/// front, and the zone must be made all `C` again now.
fn leaking(sim: &Simulation, frame: &Frame) -> bool {
    let mid = frame.x_hi() + 0.5 * frame.zone;
    (0..sim.len()).any(|i| {
        let x = sim.position(i)[0];
        match sim.species(i) {
            A => x >= frame.x_hi() && x < mid,
            B => x >= mid,
            _ => false,
        }
    })
}

/// Runs the front from a step at the home position for `until`, moving the frame as it
/// goes; fills `run` as far as it got.
pub(super) fn run_front(
    args: &FrontArgs,
    mixed: &Simulation,
    frame: &Frame,
    until: f64,
    fit_from: f64,
    run: &mut Run,
    progress: &dyn Fn(f64),
) -> Result<()> {
    let mut discs = mixed.discs();
    for d in &mut discs {
        let x = d.pos[0];
        label(
            d,
            if x < frame.home {
                A
            } else if x < frame.x_hi() {
                B
            } else {
                C
            },
        );
    }
    let bx = *mixed.sim_box();
    let t0 = mixed.time();
    let mut build_no = 0u64;
    let mut sim = build(args, &discs, bx, t0, Some(build_no))?;
    let e0 = sim.kinetic_energy();
    let steps = ((until * frame.growth / 0.1)
        .max(until)
        .min(MAX_FRONT_SAMPLES))
    .ceil() as usize;
    let dt = until / steps as f64;
    let mut msd = Msd::new(&sim, ((2.0 / frame.growth / dt).round() as usize).max(4));
    let span = ((frame.x_hi() - frame.x_lo) / BIN).round() as usize + 1;
    let shape_bins = ((frame.home - frame.x_lo) / BIN).round() as usize + span;
    run.shape_a = vec![0; shape_bins];
    run.shape_all = vec![0; shape_bins];
    run.tip_limit = f64::INFINITY;
    // Six profiles 10 / r apart (the front moves 15 to 20 xi between two) show it grow from
    // the step; later ones look the same.
    let snap_every = ((until.min(50.0 / frame.growth) / 5.0 / dt).round() as usize).max(1);
    let mut offset = 0.0;
    for step in 0..=steps {
        if step > 0 {
            if !edmd::run_until_or_stop(&mut sim, t0 + step as f64 * dt, &mut ())? {
                break;
            }
            msd.sample(&sim);
        }
        let (s, u) = look(&sim, frame);
        let time = s.time - t0;
        run.tip_max = run.tip_max.max(s.tip - s.mass);
        run.tip_limit = run.tip_limit.min(frame.x_hi() - s.mass);
        run.samples.push(Sample {
            time,
            mass: s.mass + offset,
            half: s.half + offset,
            tip: s.tip + offset,
            ..s
        });
        if step % snap_every == 0 && run.snapshots.len() < 6 {
            run.snapshots.push((time, u, offset));
        }
        if time >= fit_from {
            for i in 0..sim.len() {
                let x = sim.position(i)[0];
                if x < frame.x_lo || x >= frame.x_hi() {
                    continue;
                }
                if let Some(b) = shape_bin(frame, x - s.mass, shape_bins) {
                    run.shape_all[b] += 1;
                    if sim.species(i) == A {
                        run.shape_a[b] += 1;
                    }
                }
            }
        }
        let moving = s.mass - frame.home >= frame.shift;
        if moving || leaking(&sim, frame) {
            let shift = if moving { frame.shift } else { 0.0 };
            let mut discs = sim.discs();
            for d in &mut discs {
                d.pos[0] -= shift;
                d.pos = bx.wrap(d.pos);
                if d.pos[0] >= frame.x_hi() {
                    run.relabelled += u64::from(d.species == A);
                    label(d, C);
                } else if d.species == C && d.pos[0] >= frame.home + frame.shift {
                    label(d, B);
                }
            }
            run.reactions += sim.reaction_counts()[0];
            if moving {
                offset += shift;
                run.moves += 1;
            } else {
                run.refreshes += 1;
            }
            build_no += 1;
            let next = build(args, &discs, bx, sim.time(), Some(build_no))?;
            msd.rebase(&sim, &next);
            sim = next;
        }
        progress(step as f64 / steps as f64);
        run.finished = step == steps;
    }
    run.reactions += sim.reaction_counts()[0];
    run.overlaps = sim.overlaps(OVERLAP_TOLERANCE).count;
    run.energy_change = (sim.kinetic_energy() - e0) / e0;
    if !msd.values.is_empty() {
        run.diffusion = Some(msd.estimate());
    }
    Ok(())
}
