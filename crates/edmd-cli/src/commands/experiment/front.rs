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

mod figures;
mod frame;
mod kpp;
mod measure;
mod setup;

use anyhow::Result;
use clap::Args;
use edmd_core::measure::{linear_fit, theory, Estimate};
use serde::Serialize;

use super::common::{
    files_line, interrupted_after, out_dir, outputs, report, stop_requested, CommonArgs, Progress,
};
use figures::{write_outputs, Lines};
use frame::{plan, run_front, Run};
use kpp::{kpp_at, kpp_wave};
use measure::{measure_rate, speed, Sample};
use setup::fluid;

/// The invader, the fuel, and discs in transit through the zone (no rule: inert).
const A: u16 = 0;
const B: u16 = 1;
const C: u16 = 2;

/// Width of the bins along x (diameters).
const BIN: f64 = 1.0;

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
    /// the line-of-centres law (10 400 at the other defaults); at least 6 / r (125), at most
    /// 100 000].
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

/// Runs the experiment.
pub fn run(args: &FrontArgs) -> Result<()> {
    let (frame, until) = plan(args)?;
    let dir = out_dir(
        &args.common,
        &outputs(
            &["front", "front-profile", "front-shape"],
            &["front", "front-profile", "front-shape"],
        ),
    )?;
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
    // An asymptote in large N: below N = exp(pi / sqrt 2), about 9, its correction passes the
    // whole speed and the formula says nothing (null in the JSON, an empty cell in the CSV).
    let bd_factor = 1.0 - std::f64::consts::PI.powi(2) / (2.0 * n_bd.ln().powi(2));
    let v_bd = if n_bd > 1.0 && bd_factor > 0.0 {
        v_kpp * bd_factor
    } else {
        f64::NAN
    };
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
        "  Fisher-KPP 2 sqrt(D k n)       {v_kpp:.4} ± {:.4}   measured / KPP {:.3}\n",
        row.speed_kpp_error,
        v / v_kpp,
    );
    human += &if v_bd.is_nan() {
        format!("  Brunet-Derrida, N = {n_bd:<8.0}   none: their law is for N well above 9\n")
    } else {
        format!(
            "  Brunet-Derrida, N = {n_bd:<8.0}   {v_bd:.4} ± {:.4}   measured / BD {:.3}\n",
            row.speed_brunet_derrida_error,
            v / v_bd
        )
    };
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
