//! `edmd experiment front`: a reaction front `A + B -> 2A` invading a fluid of `B`, its speed
//! against Fisher-KPP's `2 sqrt(D k n)` and Brunet and Derrida's correction for a finite
//! number of particles.
//!
//! **The model.** Equal hard discs (diameter 1, mass 1, `kT = 1`) at a packing fraction, in a
//! long box of length `L` along x and width `W` along y, periodic on both axes. Species `A`
//! (0) and `B` (1) differ only in their label: the rule `A + B -> A + A` turns the `B` of a
//! colliding pair into an `A` when the kinetic energy of the pair's relative motion along the
//! line of centres is at least `E*` (`--activation`, default 0), with probability `p`
//! (`--probability`). No heat is released, so a reactive collision changes the velocities
//! exactly as the same collision without the rule: the discs move, bit for bit, as the
//! equilibrium hard-disc fluid, and the reaction only relabels them. The density `a` of `A`
//! then obeys, on scales large compared with the mean free path, Fisher's equation
//!
//! `da/dt = D d2a/dx2 + k a (n - a)`,
//!
//! with `D` the fluid's self-diffusion coefficient, `n` its number density and `k` the rate
//! constant as [`edmd_core::measure::Kinetics`] defines it (`k n_A n_B` reactions per unit
//! area and time). Its front into `a = 0` is pulled: its speed is set by the linearised growth
//! rate `r = k n`, `v_KPP = 2 sqrt(D r) = 2 sqrt(D k n)` (R. A. Fisher, Ann. Eugen. 7, 355
//! (1937); A. Kolmogorov, I. Petrovsky and N. Piscounov, Bull. Univ. Moscou A 1, 1 (1937)),
//! and its leading edge decays as `exp(-x / xi)`, `xi = sqrt(D / r)`.
//!
//! **Measured by edmd itself.** `k`: the fluid with its labels drawn at random (half `A`),
//! measured with `Kinetics` over 64 blocks a quarter of `1/r` long, each starting from labels
//! drawn afresh so that the fluid is well mixed; compared with the line-of-centres law
//! `p exp(-E*/kT) omega / n` (Enskog's collision frequency `omega`). `D`: mean square
//! displacements of every disc over windows `2/r` long, fitted over their second half (the
//! time in which the leading edge grows by a factor `e` and diffuses over `xi`), during the
//! front's run, whose trajectories are those of the fluid without reactions; the error comes
//! from eight groups of consecutive windows, each long compared with the slowest shear mode
//! of the box (the windows within a group are correlated through it).
//!
//! **Finite number of particles.** Where `a` is below one disc per strip of width `W` and
//! length `xi`, growth cannot happen as Fisher's equation has it: the leading edge is cut off
//! and the front is slower. Brunet and Derrida (Phys. Rev. E 56, 2597 (1997)) found for a
//! cutoff at `a / n = 1/N`
//!
//! `v_N = v_KPP (1 - pi^2 / (2 ln^2 N))`
//!
//! (their `v = 2 - pi^2 / ln^2 N` for `u_t = u_xx + u (1 - u)`, in units of `xi` and `1/r`).
//! Here `N = n W xi`, the discs in a strip as wide as the box and one decay length deep. The
//! formula is the leading order in `1/ln N`, and `ln N` is 3 to 6 here: a guide to the size
//! of the slowing, not a bound.
//!
//! **The front.** The A fraction `u` in bins one diameter wide along x, over all y. Its
//! position is the A mass, `X = x_lo + sum u dx` over the measured range `[x_lo, L - c)`
//! (below): the place of a step with the same number of `A`s. The place where `u` falls
//! through 1/2 (the rightmost bin at or above 1/2, interpolated to the next) and the rightmost
//! `A` are recorded too. The speed is the slope of a straight line through `X(t)` from
//! `min(T/3, 50/r)` to the end: the front first grows its leading edge from the step it starts
//! as, and Bramson's lag, `(3 xi / 2) ln t` (U. Ebert and W. van Saarloos, Physica D 146, 1
//! (2000)), then bends the line by less than 1% at the defaults. The error comes from the
//! slopes of eight consecutive segments (the position wanders, so neighbouring samples are far
//! from independent). The mean profile seen from `X(t)` gives the width `integral u (1 - u)
//! dx`; integrating Fisher's equation over x shows that it is `v / r` for any travelling
//! front (`2 xi` at `v_KPP`), so it tells whether the front reacts at the mean-field rate
//! `k <a> <b>` and is slow only because its leading edge is cut.
//!
//! **The moving frame.** The front runs into fresh `B` while the `A`s far behind it no longer
//! matter. Every time the front has advanced `s` (a whole number of bins, about `2 xi`) past
//! its home position `h` (about `10 xi`), every disc is moved back by `s` along x. In a
//! periodic box that is a translation: the dynamics is exactly the same, rounding apart, and
//! the front is back near `h`. The discs that the translation carries out of the left end come
//! in at the right end: they are the far-behind `A`s, and become the fuel ahead. The zone
//! `[L - c, L)` at the right end, `c = s + 8 xi`, holds them in transit under a third label,
//! `C` (2), with no rule: at each move every disc in the zone becomes `C`, and every `C` in
//! the fuel region `[h + s, L - c)` becomes `B`. So the `B`s the front meets were `C`s, and
//! no `B` touches the `A`s at the left end (with which a second front would start, running
//! left into the zone and round the box). `A`s from the left end and `B`s from the fuel region
//! still diffuse into the zone between two moves; when one has crossed half of it, the zone
//! is relabelled the same way without a move. Then the simulation is built again from the
//! discs' positions and velocities at that instant (the clock carries on), with the rule's
//! seed advanced so that no random draw repeats.
//!
//! What the frame does to the dynamics: nothing to the positions and velocities, which stay
//! an equilibrium fluid with no seam, no wall and no density step anywhere; no disc is added
//! or removed. It changes labels only, and only in the zone and of the `C`s ahead of the
//! front, at least `L - c - h - s` ahead of it. It would cut the front's leading edge if an
//! `A` of the front reached the zone: the box must be long enough (`--length` at least
//! `h + s + 16 xi + c`, 38 `xi` in all, with `xi` from Enskog's diffusion coefficient, which
//! is smaller than the fluid's), and the run reports how far ahead the rightmost `A` ever was
//! (`tip_max`) and how far ahead the zone began at its nearest (`tip_limit`). The position is
//! measured from `x_lo = 4 xi`, beyond the `C`s that diffuse out of the zone into the left end
//! (they stay `C` until the moves carry them back into it). The instant of a move depends on
//! the front, but the discs relabelled are so far from it that the choice cannot feed back on
//! its motion.
//!
//! Two dimensions only: the same frame works in 3D, but a front across a box wide enough for
//! `N` to matter holds tens of thousands of spheres, minutes per run.

use anyhow::Result;
use clap::Args;
use edmd_core::measure::{block_error, linear_fit, theory, Estimate, Kinetics};
use edmd_core::setup::{melting_threshold, psi6, thermal_velocities, Neighbours};
use edmd_core::state::species_colour;
use edmd_core::{
    Disc, Options, Reaction, Reactions, SimBox, Simulation, Vector, OVERLAP_TOLERANCE,
};
use edmd_plot::{Figure, Series};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::Serialize;

use super::common::{
    files_line, interrupted_after, out_dir, report, run_collisions, stop_requested, write_csv,
    CommonArgs, Progress, MAX_N, MIN_PACKING,
};

/// The invader, the fuel, and discs in transit through the zone (no rule: inert).
const A: u16 = 0;
const B: u16 = 1;
const C: u16 = 2;

/// Width of the bins along x (diameters).
const BIN: f64 = 1.0;

/// The densest fluid the experiment makes (equal discs are liquid up to 0.70; a lattice with
/// vacancies melts within a few collisions per disc up to about 0.6).
const MAX_PACKING: f64 = 0.6;

/// Blocks of the rate constant's measurement.
const RATE_BLOCKS: u64 = 64;

/// Groups of diffusion windows, and segments of the speed's fit, for the errors.
const GROUPS: usize = 8;

/// Most samples of the front's run (the CSV file and the figure stay small).
const MAX_FRONT_SAMPLES: f64 = 5000.0;

/// Options of `edmd experiment front`.
#[derive(Debug, Args)]
pub struct FrontArgs {
    /// Packing fraction of the fluid (equal discs of diameter 1).
    #[arg(long, default_value_t = 0.3, allow_negative_numbers = true)]
    pub packing: f64,
    /// Probability that a collision of an A with a B (above the activation energy) reacts.
    /// Small values (many collisions per reaction) are Fisher-KPP's continuum regime.
    #[arg(long, default_value_t = 0.02, allow_negative_numbers = true)]
    pub probability: f64,
    /// Activation energy E* (units of kT): the least kinetic energy of the pair's relative
    /// motion along the line of centres for a collision to react.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub activation: f64,
    /// Width of the box across the front (y, periodic), in diameters.
    #[arg(long, default_value_t = 40.0, allow_negative_numbers = true)]
    pub width: f64,
    /// Length of the box along the front's motion (x, periodic), in diameters: at least 38
    /// decay lengths xi = sqrt(D / k n) of the leading edge (114 at the other defaults; the
    /// message for too short a box gives the least length).
    #[arg(long, default_value_t = 140.0, allow_negative_numbers = true)]
    pub length: f64,
    /// Time the front runs [default: 500 / r, with r = k n the linearised growth rate from
    /// the line-of-centres law (10 400 at the other defaults), at most 100 000].
    #[arg(long, allow_negative_numbers = true)]
    pub until: Option<f64>,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// The one row of the summary.
#[derive(Debug, Serialize)]
pub struct Row {
    /// Packing fraction (of the discs placed).
    pub packing: f64,
    /// Number density n (discs per unit area).
    pub density: f64,
    /// Reaction probability p.
    pub probability: f64,
    /// Activation energy E* (kT).
    pub activation: f64,
    /// Box width W (y).
    pub width: f64,
    /// Box length L (x).
    pub length: f64,
    /// Discs in the box (the moving frame relabels; it neither adds nor removes).
    pub discs: usize,
    /// Time the front ran.
    pub until: f64,
    /// Front speed: slope of the A-mass position over the fitted range.
    pub speed: f64,
    /// Its error, from the slopes of eight consecutive segments.
    pub speed_error: f64,
    /// Speed of the place where the A fraction falls through 1/2.
    pub speed_half: f64,
    /// Its error.
    pub speed_half_error: f64,
    /// Self-diffusion coefficient D (MSD over windows 2/r long, their second half).
    pub diffusion: f64,
    /// Its error.
    pub diffusion_error: f64,
    /// Rate constant k of A + B -> 2A in the well-mixed fluid (k n_A n_B per area and time).
    pub rate_constant: f64,
    /// Its error.
    pub rate_constant_error: f64,
    /// The line-of-centres law, p exp(-E*/kT) omega / n with Enskog's omega.
    pub rate_constant_line_of_centres: f64,
    /// Linearised growth rate r = k n (measured k).
    pub growth_rate: f64,
    /// Decay length of the leading edge, xi = sqrt(D / r).
    pub decay_length: f64,
    /// Fisher-KPP's speed 2 sqrt(D k n) with the measured D and k.
    pub speed_kpp: f64,
    /// Its error, from those of D and k.
    pub speed_kpp_error: f64,
    /// Brunet and Derrida's N: discs in a strip W wide and xi deep, n W xi.
    pub brunet_derrida_n: f64,
    /// Brunet and Derrida's speed, v_KPP (1 - pi^2 / (2 ln^2 N)).
    pub speed_brunet_derrida: f64,
    /// Its error, from those of D and k.
    pub speed_brunet_derrida_error: f64,
    /// Width of the mean front, integral of u (1 - u) dx over the profile seen from the front.
    pub front_width: f64,
    /// The same integral over Fisher-KPP's travelling wave at v_KPP: 2 xi (integrated from
    /// the wave's equation, whose integral over x gives v / r exactly).
    pub front_width_kpp: f64,
    /// speed / growth_rate: what the width must be if the reactions in the front go at the
    /// mean-field rate k <a> <b> (Fisher's equation integrated over x: v n = r n integral
    /// u (1 - u) dx).
    pub front_width_from_speed: f64,
    /// Start of the fitted range (time since the front started).
    pub fit_from: f64,
    /// End of the fitted range.
    pub fit_to: f64,
    /// Reactions while the front ran.
    pub reactions: u64,
    /// Moves of the frame.
    pub frame_moves: usize,
    /// Relabellings of the zone between moves (an A or a B had crossed half of it).
    pub frame_refreshes: usize,
    /// Distance of each move, s (diameters).
    pub frame_move: f64,
    /// Home position of the front in the box, h.
    pub frame_home: f64,
    /// Width c of the zone at the right end.
    pub zone: f64,
    /// A's made C in the zone over the run: the far-behind ones the moves carry in, and those
    /// that diffuse in from the left end.
    pub relabelled: u64,
    /// Farthest the rightmost A ever was ahead of the front position.
    pub tip_max: f64,
    /// Nearest the zone ever was ahead of the front position: tip_max must stay below it.
    pub tip_limit: f64,
    /// Overlapping pairs at the end (0).
    pub overlaps: usize,
    /// Relative change of the kinetic energy over the front's run (no heat: rounding only).
    pub relative_energy_change: f64,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Dimension.
    pub dim: usize,
    /// One row: the run.
    pub rows: Vec<Row>,
    /// What the row is compared with.
    pub theory: &'static str,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

const THEORY: &str = "speed_kpp = 2 sqrt(D k n), the speed of the pulled front of da/dt = D d2a/dx2 + k a (n - a) (Fisher 1937; Kolmogorov, Petrovsky and Piscounov 1937), with D (diffusion) and k (rate_constant, k n_A n_B reactions per unit area and time) measured; speed_brunet_derrida = speed_kpp (1 - pi^2 / (2 ln^2 N)), N = brunet_derrida_n = n W xi, xi = sqrt(D / (k n)) (E. Brunet and B. Derrida, Phys. Rev. E 56, 2597 (1997)); rate_constant_line_of_centres = p exp(-E*/kT) omega / n with Enskog's collision frequency omega; front_width_kpp = integral of u (1 - u) dx over Fisher-KPP's travelling wave at v_KPP (= v_KPP / r = 2 xi); front_width_from_speed = speed / (k n), the width the measured speed implies if the front reacts at the mean-field rate k <a> <b>";

/// The box and the moving frame, in diameters (all whole bins but the width).
#[derive(Clone, Copy, Debug)]
struct Frame {
    length: f64,
    width: f64,
    /// Number density aimed at.
    density: f64,
    /// Growth rate r from Enskog's collision frequency (the line-of-centres law), to size
    /// the windows and blocks before k is measured.
    growth: f64,
    /// Home position of the front.
    home: f64,
    /// Distance of a move.
    shift: f64,
    /// Left end of the measured range.
    x_lo: f64,
    /// Width of the zone at the right end.
    zone: f64,
}

impl Frame {
    fn bins(&self) -> usize {
        (self.length / BIN).round() as usize
    }

    /// Right end of the measured range (the zone begins there).
    fn x_hi(&self) -> f64 {
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
fn plan(args: &FrontArgs) -> Result<(Frame, f64)> {
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
    if length < least {
        return bad(format!(
            "--length must be at least {least} for this packing, probability and activation (38 decay lengths xi = {xi:.2} of the front's leading edge), found {}",
            args.length
        ));
    }
    let n = (density * length * args.width).round();
    if n > MAX_N as f64 {
        return bad(format!(
            "the box holds {n} discs, more than {MAX_N}: make --length or --width smaller"
        ));
    }
    let until = args.until.unwrap_or((500.0 / growth).min(1e5));
    if !(until.is_finite() && until > 0.0 && until <= 1e5) {
        return bad(format!(
            "--until must be above 0 and at most 100000, found {until}"
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

/// `n` discs in a periodic `length x width` box on a triangular lattice with at least 6% of
/// its sites empty (vacancies let it melt within a few collisions per disc), stretched a
/// little to fit the box, the empty sites spread evenly; velocities Gaussian at `kT = 1` with
/// no total momentum; all `B`.
fn strip_lattice(n: usize, length: f64, width: f64, seed: u64) -> Result<Vec<Disc>> {
    let sites = (n as f64 * 1.06).ceil();
    let a = (2.0 * length * width / (3f64.sqrt() * sites)).sqrt();
    let mut rows = ((width / (a * 3f64.sqrt() / 2.0)).round() as usize).max(2);
    rows += rows % 2;
    let cols = (sites as usize).div_ceil(rows).max(1);
    let (dx, dy) = (length / cols as f64, width / rows as f64);
    if dx < 1.0 + 1e-9 || (0.25 * dx * dx + dy * dy).sqrt() < 1.0 + 1e-9 {
        return edmd::user_error(format!(
            "front: {n} discs do not fit a lattice in a {length} x {width} box: make it wider or the packing lower"
        ));
    }
    let total = rows * cols;
    let mut discs: Vec<Disc> = (0..n)
        .map(|i| {
            let site = i * total / n;
            let (r, c) = (site / cols, site % cols);
            let x = (c as f64 + 0.25 + 0.5 * (r % 2) as f64) * dx;
            let y = (r as f64 + 0.5) * dy;
            Disc {
                species: B,
                colour: species_colour(B),
                ..Disc::new(Vector::new([x, y]), Vector::ZERO, 0.5)
            }
        })
        .collect();
    thermal_velocities(&mut discs, 1.0, &mut Pcg64Mcg::seed_from_u64(seed));
    Ok(discs)
}

/// Gives disc `d` species `s` and its colour.
fn label(d: &mut Disc, s: u16) {
    d.species = s;
    d.colour = species_colour(s);
}

/// A new simulation of `discs` at time `t`; with `draw`, under the rule `A + B -> A + A` with
/// the `draw`-th seed (each build gets its own: the collision counters the draws hash start
/// again from 0).
fn build(
    args: &FrontArgs,
    discs: &[Disc],
    bx: SimBox,
    t: f64,
    draw: Option<u64>,
) -> Result<Simulation> {
    let mut sim = Simulation::with_barriers_at(discs, bx, &[], Options::default(), t)
        .or_else(|e| edmd::user_error(format!("front: {e}")))?;
    if let Some(k) = draw {
        let seed = args
            .common
            .seed
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(k.wrapping_mul(0xD1B5_4A32_D192_ED03));
        let rule = Reaction {
            reactants: (A, B),
            products: (A, A),
            activation: args.activation,
            probability: args.probability,
            heat: 0.0,
        };
        let reactions = Reactions {
            rules: vec![rule],
            seed,
            colours: vec![(A, species_colour(A))],
        };
        sim.set_reactions(Some(reactions))
            .or_else(|e| edmd::user_error(format!("front: {e}")))?;
    }
    Ok(sim)
}

/// The melted fluid of the whole box, all `B`: 10 collisions per disc at a time until the
/// bond-orientational order is that of a liquid; `None` when a stop was requested.
fn fluid(args: &FrontArgs, frame: &Frame) -> Result<Option<Simulation>> {
    let n = (frame.density * frame.length * frame.width).round() as usize;
    let discs = strip_lattice(n, frame.length, frame.width, args.common.seed)?;
    let bx = SimBox::periodic([frame.length, frame.width]);
    let mut sim = build(args, &discs, bx, 0.0, None)?;
    for _ in 0..30 {
        if !run_collisions(&mut sim, 5 * n as u64)? {
            return Ok(None);
        }
        if psi6(&sim.discs(), sim.sim_box(), Neighbours::Nearest(6)) < melting_threshold(n) {
            return Ok(Some(sim));
        }
    }
    edmd::user_error("front: the lattice did not melt within 300 collisions per disc")
}

/// `k` in the well-mixed fluid: [`RATE_BLOCKS`] blocks, each with labels drawn afresh (half
/// `A`) and a quarter of `1/r` long, so that the `B`s are used up by a few percent at most.
/// Returns the simulation as it ends; `None` when a stop was requested.
fn measure_rate(
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
struct Sample {
    /// Time since the front started.
    time: f64,
    /// A-mass position.
    mass: f64,
    /// Where the A fraction falls through 1/2.
    half: f64,
    /// Rightmost A in the measured range.
    tip: f64,
    /// A's in the measured range.
    a_count: usize,
}

/// Looks at the front in the box: the sample (positions in the box, time absolute) and the
/// A fraction per bin (1 outside the measured range).
fn look(sim: &Simulation, frame: &Frame) -> (Sample, Vec<f64>) {
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
struct Msd {
    /// Samples per window.
    window: usize,
    base: Vec<Vector>,
    start: Vec<Vector>,
    /// `(time lag, MSD)` of the window under way.
    points: Vec<(f64, f64)>,
    t0: f64,
    /// `D` of each finished window.
    values: Vec<f64>,
}

impl Msd {
    fn new(sim: &Simulation, window: usize) -> Self {
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
    fn rebase(&mut self, old: &Simulation, new: &Simulation) {
        for i in 0..old.len() {
            self.base[i] = self.at(old, i) - new.unwrapped_position(i);
        }
    }

    fn sample(&mut self, sim: &Simulation) {
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
    fn estimate(&self) -> Estimate {
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

/// What the front's run gathered.
#[derive(Default)]
struct Run {
    samples: Vec<Sample>,
    /// `(time, A fraction per bin, frame offset)` at six times from the start.
    snapshots: Vec<(f64, Vec<f64>, f64)>,
    /// A's and discs per bin of the position relative to the front, from the fit's start.
    shape_a: Vec<u64>,
    shape_all: Vec<u64>,
    diffusion: Option<Estimate>,
    reactions: u64,
    relabelled: u64,
    moves: usize,
    refreshes: usize,
    tip_max: f64,
    tip_limit: f64,
    overlaps: usize,
    energy_change: f64,
    finished: bool,
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

/// The relative bin of the mean profile that holds `x - X` (`X` the front position), if
/// any: bins run from `x_lo - h` to `x_hi - x_lo` past the front.
fn shape_bin(frame: &Frame, rel: f64, bins: usize) -> Option<usize> {
    let r = ((rel + frame.home - frame.x_lo) / BIN).floor();
    (r >= 0.0 && (r as usize) < bins).then_some(r as usize)
}

/// Runs the front from a step at the home position for `until`, moving the frame as it
/// goes; fills `run` as far as it got.
fn run_front(
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

/// Fisher-KPP's travelling wave at the minimal speed, `u'' + 2 u' + u (1 - u) = 0` (lengths
/// in `xi`), from `u = 1` on the left to 0 on the right, placed with its A-mass position at
/// 0: `(z, u)` every 0.05, and `integral u (1 - u) dz`. Integrated (RK4) from the unstable
/// manifold of `u = 1`, where `1 - u` grows as `exp((sqrt 2 - 1) z)`.
fn kpp_wave() -> (Vec<(f64, f64)>, f64) {
    let f = |u: f64, q: f64| (q, -2.0 * q - u * (1.0 - u));
    let (h, w0) = (1e-3, 1e-9);
    let lambda = std::f64::consts::SQRT_2 - 1.0;
    let (mut z, mut u, mut q) = (0.0, 1.0 - w0, -lambda * w0);
    // The A mass ahead of the start (trapezoids), and the width's integral.
    let (mut ahead, mut width) = (0.0, 0.0);
    let mut wave = Vec::new();
    let mut k = 0u64;
    while u > 1e-12 && z < 200.0 {
        if k.is_multiple_of(50) {
            wave.push((z, u));
        }
        let (k1u, k1q) = f(u, q);
        let (k2u, k2q) = f(u + 0.5 * h * k1u, q + 0.5 * h * k1q);
        let (k3u, k3q) = f(u + 0.5 * h * k2u, q + 0.5 * h * k2q);
        let (k4u, k4q) = f(u + h * k3u, q + h * k3q);
        let next = u + h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
        q += h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q);
        ahead += 0.5 * h * (u + next);
        width += 0.5 * h * (u * (1.0 - u) + next * (1.0 - next));
        u = next;
        z += h;
        k += 1;
    }
    // Behind the start, `1 - u` adds up to `w0 / lambda`, nothing: the wave holds the A mass
    // of a step at `ahead` from the start.
    (
        wave.into_iter().map(|(z, u)| (z - ahead, u)).collect(),
        width,
    )
}

/// The wave's `u` at `z` (in `xi`), linearly interpolated; 1 behind it, 0 ahead.
fn kpp_at(wave: &[(f64, f64)], z: f64) -> f64 {
    match wave.iter().position(|p| p.0 > z) {
        None => 0.0,
        Some(0) => 1.0,
        Some(k) => {
            let (a, b) = (wave[k - 1], wave[k]);
            a.1 + (b.1 - a.1) * (z - a.0) / (b.0 - a.0)
        }
    }
}

/// `(slope, error)` of a straight line through `points`, the error from the slopes of
/// [`GROUPS`] consecutive segments (the front's position wanders, so neighbouring points are
/// far from independent, while segments hundreds of `1/r` long nearly are).
fn speed(points: &[(f64, f64)]) -> (f64, f64) {
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

/// Runs the experiment.
pub fn run(args: &FrontArgs) -> Result<()> {
    let (frame, until) = plan(args)?;
    let dir = out_dir(&args.common)?;
    let bar = Progress::new(1000, "front");
    let fit_from = (until / 3.0).min(50.0 / frame.growth);
    let mut k_est = None;
    let mut run = Run::default();
    let mut discs = 0;
    'phases: {
        let Some(sim) = fluid(args, &frame)? else {
            break 'phases;
        };
        discs = sim.len();
        bar.set(20);
        let Some((k, mixed)) =
            measure_rate(args, sim, &frame, &|f| bar.set(20 + (80.0 * f) as u64))?
        else {
            break 'phases;
        };
        k_est = Some(k);
        run_front(args, &mixed, &frame, until, fit_from, &mut run, &|f| {
            bar.set(100 + (900.0 * f) as u64)
        })?;
    }
    bar.finish();
    let interrupted = !run.finished || stop_requested();

    // Theory from the measured D and k.
    let pick = |e: Option<Estimate>| e.map_or((f64::NAN, f64::NAN), |e| (e.value, e.error));
    let ((d, d_err), (k, k_err)) = (pick(run.diffusion), pick(k_est));
    let n = if discs > 0 {
        discs as f64 / (frame.length * frame.width)
    } else {
        frame.density
    };
    let r = k * n;
    let xi = (d / r).sqrt();
    let v_kpp = 2.0 * (d * r).sqrt();
    let rel = 0.5 * ((d_err / d).powi(2) + (k_err / k).powi(2)).sqrt();
    let n_bd = n * frame.width * xi;
    let v_bd = v_kpp * (1.0 - std::f64::consts::PI.powi(2) / (2.0 * n_bd.ln().powi(2)));
    let k_loc = args.probability
        * theory::line_of_centres_rate_constant(args.packing, 1.0, 1.0, 1.0, 2, args.activation);
    let (wave, wave_width) = kpp_wave();

    let fitted: Vec<&Sample> = run.samples.iter().filter(|s| s.time >= fit_from).collect();
    let mass: Vec<(f64, f64)> = fitted.iter().map(|s| (s.time, s.mass)).collect();
    let (v, v_err) = speed(&mass);
    let (v_half, v_half_err) = speed(&fitted.iter().map(|s| (s.time, s.half)).collect::<Vec<_>>());
    let line = linear_fit(&mass);

    // The mean profile seen from the front.
    let shape: Vec<(f64, f64, f64)> = (0..run.shape_a.len())
        .filter(|&b| run.shape_all[b] > 0)
        .map(|b| {
            let x = (b as f64 + 0.5) * BIN - (frame.home - frame.x_lo);
            let u = run.shape_a[b] as f64 / run.shape_all[b] as f64;
            (x, u, kpp_at(&wave, x / xi))
        })
        .collect();
    let front_width = if shape.is_empty() {
        f64::NAN
    } else {
        shape.iter().map(|p| p.1 * (1.0 - p.1) * BIN).sum()
    };
    let t_end = run.samples.last().map_or(0.0, |s| s.time);

    let files = write_outputs(
        dir,
        args,
        &frame,
        &run,
        &shape,
        Lines {
            fit_from,
            t_end,
            line,
            v,
            v_err,
            v_kpp,
            v_bd,
            n_bd,
        },
    )?;
    let row = Row {
        packing: n * std::f64::consts::PI / 4.0,
        density: n,
        probability: args.probability,
        activation: args.activation,
        width: frame.width,
        length: frame.length,
        discs,
        until: t_end,
        speed: v,
        speed_error: v_err,
        speed_half: v_half,
        speed_half_error: v_half_err,
        diffusion: d,
        diffusion_error: d_err,
        rate_constant: k,
        rate_constant_error: k_err,
        rate_constant_line_of_centres: k_loc,
        growth_rate: r,
        decay_length: xi,
        speed_kpp: v_kpp,
        speed_kpp_error: v_kpp * rel,
        brunet_derrida_n: n_bd,
        speed_brunet_derrida: v_bd,
        speed_brunet_derrida_error: v_bd * rel,
        front_width,
        front_width_kpp: wave_width * xi,
        front_width_from_speed: v / r,
        fit_from,
        fit_to: t_end,
        reactions: run.reactions,
        frame_moves: run.moves,
        frame_refreshes: run.refreshes,
        frame_move: frame.shift,
        frame_home: frame.home,
        zone: frame.zone,
        relabelled: run.relabelled,
        tip_max: run.tip_max,
        tip_limit: run.tip_limit,
        overlaps: run.overlaps,
        relative_energy_change: run.energy_change,
    };
    let mut human = format!(
        "reaction front A + B -> 2A, 2D: packing {:.3} (n = {n:.4}), p = {}, E* = {}, box {} x {} ({discs} discs), front run {t_end:.0}\n",
        row.packing, args.probability, args.activation, frame.length, frame.width
    );
    human += &format!(
        "  D (MSD over 2/r windows)       {d:.4} ± {d_err:.4}\n  k (well mixed, Kinetics)       {k:.4} ± {k_err:.4}   line of centres {k_loc:.4}\n"
    );
    human += &format!(
        "  front speed (A mass)           {v:.4} ± {v_err:.4}\n  front speed (A fraction 1/2)   {v_half:.4} ± {v_half_err:.4}\n"
    );
    human += &format!(
        "  Fisher-KPP 2 sqrt(D k n)       {v_kpp:.4} ± {:.4}   measured / KPP {:.3}\n  Brunet-Derrida, N = {n_bd:<8.0}   {v_bd:.4} ± {:.4}   measured / BD {:.3}\n",
        row.speed_kpp_error,
        v / v_kpp,
        row.speed_brunet_derrida_error,
        v / v_bd
    );
    human += &format!(
        "  front width, integral u(1-u)   {front_width:.3}   Fisher-KPP {:.3} (2 xi), from the speed v / k n {:.3}\n  frame: {} moves of {}, {} relabellings between moves; the rightmost A was at most {:.1} ahead, the zone at least {:.1}\n",
        row.front_width_kpp, row.front_width_from_speed, run.moves, frame.shift, run.refreshes, run.tip_max, run.tip_limit
    );
    if run.tip_max >= run.tip_limit {
        human += "warning: an A of the front reached the zone, which cut its leading edge: give a longer --length\n";
    }
    if interrupted {
        human += "interrupted: results so far\n";
    }
    human += &files_line(&files);
    report(
        &args.common,
        &Summary {
            experiment: "front",
            dim: 2,
            rows: vec![row],
            theory: THEORY,
            interrupted,
        },
        &human,
    )?;
    if interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}

/// The lines drawn over the front's position.
struct Lines {
    fit_from: f64,
    t_end: f64,
    /// The fit `(slope, intercept)`.
    line: Option<(f64, f64)>,
    v: f64,
    v_err: f64,
    v_kpp: f64,
    v_bd: f64,
    n_bd: f64,
}

/// Writes the CSV files and the figures; returns their paths.
fn write_outputs(
    dir: &std::path::Path,
    args: &FrontArgs,
    frame: &Frame,
    run: &Run,
    shape: &[(f64, f64, f64)],
    lines: Lines,
) -> Result<Vec<std::path::PathBuf>> {
    let mut files = Vec::new();
    let csv = dir.join("front.csv");
    write_csv(
        &csv,
        &[
            "time",
            "position",
            "position_half",
            "position_tip",
            "a_count",
        ],
        run.samples
            .iter()
            .map(|s| vec![s.time, s.mass, s.half, s.tip, s.a_count as f64]),
    )?;
    files.push(csv);
    let bins = frame.bins();
    let in_range = |b: usize| {
        let x = (b as f64 + 0.5) * BIN;
        x >= frame.x_lo && x < frame.x_hi()
    };
    let csv = dir.join("front-profile.csv");
    write_csv(
        &csv,
        &["time", "x", "a_fraction"],
        run.snapshots.iter().flat_map(|(t, u, offset)| {
            (0..bins)
                .filter(|&b| in_range(b))
                .map(move |b| vec![*t, (b as f64 + 0.5) * BIN + offset, u[b]])
        }),
    )?;
    files.push(csv);
    let csv = dir.join("front-shape.csv");
    write_csv(
        &csv,
        &["x_from_front", "a_fraction", "fisher_kpp"],
        shape.iter().map(|&(x, u, w)| vec![x, u, w]),
    )?;
    files.push(csv);

    let Lines {
        fit_from,
        t_end,
        line,
        v,
        v_err,
        v_kpp,
        v_bd,
        n_bd,
    } = lines;
    let title = format!(
        "A + B -> 2A front: packing {}, p = {}, {} x {} box",
        args.packing, args.probability, frame.length, frame.width
    );
    let every = run.samples.len().div_ceil(2000).max(1);
    let thin = |f: &dyn Fn(&Sample) -> f64| -> Vec<(f64, f64)> {
        run.samples
            .iter()
            .step_by(every)
            .map(|s| (s.time, f(s)))
            .collect()
    };
    let mut fig = Figure::new(
        &title,
        "time (sqrt(m sigma^2 / kT))",
        "front position (diameters)",
    )
    .with(Series::line("A mass / n W", thin(&|s| s.mass)))
    .with(Series::line("A fraction 1/2", thin(&|s| s.half)));
    if let Some((slope, icpt)) = line {
        let x0 = slope * fit_from + icpt;
        let through = |v: f64| vec![(fit_from, x0), (t_end, x0 + v * (t_end - fit_from))];
        fig = fig
            .with(
                Series::line(&format!("fit: v = {v:.4} ± {v_err:.4}"), through(slope))
                    .coloured([0, 0, 0]),
            )
            .with(Series::line(
                &format!("Fisher-KPP 2 sqrt(D k n) = {v_kpp:.4}"),
                through(v_kpp),
            ))
            .with(Series::line(
                &format!("Brunet-Derrida, N = {n_bd:.0}: {v_bd:.4}"),
                through(v_bd),
            ));
    }
    let (png, svg) = fig.save(&dir.join("front"))?;
    files.extend([png, svg]);

    let mut fig = Figure::new(
        "The front growing from a step: A fraction along the box",
        "x (diameters, the frame's moves added back)",
        "A fraction u",
    )
    .with_y_range(0.0, 1.05);
    for (t, u, offset) in &run.snapshots {
        let pts = (0..bins)
            .filter(|&b| in_range(b))
            .map(|b| ((b as f64 + 0.5) * BIN + offset, u[b]))
            .collect();
        fig = fig.with(Series::line(&format!("t = {t:.0}"), pts));
    }
    let (png, svg) = fig.save(&dir.join("front-profile"))?;
    files.extend([png, svg]);

    let (png, svg) = Figure::new(
        "Mean front seen from its A-mass position X(t)",
        "x - X(t) (diameters)",
        "A fraction u",
    )
    .with_y_range(0.0, 1.05)
    .with(Series::points(
        "edmd",
        shape.iter().map(|p| (p.0, p.1)).collect(),
    ))
    .with(
        Series::line(
            "Fisher-KPP wave at v_KPP",
            shape.iter().map(|p| (p.0, p.2)).collect(),
        )
        .coloured([0, 0, 0]),
    )
    .save(&dir.join("front-shape"))?;
    files.extend([png, svg]);
    Ok(files)
}
