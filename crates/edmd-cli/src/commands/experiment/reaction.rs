//! `edmd experiment reaction`: reactive collisions against the line-of-centres law, and the
//! Prigogine-Xhrouet effect.
//!
//! **In equilibrium.** For each dimension and packing fraction, `--runs` fluids of `N` equal
//! discs (spheres) of diameter 1 and mass 1 in a periodic box at `kT = 1`, melted, half of
//! species A (0) and half of B (1) in a random order; then, for each activation energy `E*`
//! (given in units of kT), the rule `A + B -> B + A` with that activation, probability 1 and no
//! heat. A reactive collision exchanges the two discs' labels and nothing else: the velocities
//! change exactly as in an elastic collision, so the trajectory is the elastic fluid's, bit for
//! bit, and every activation energy sees the same collisions. The exchange keeps each species
//! Maxwellian at `kT`: an exchange at a collision of like discs would change nothing, so the
//! labels at any time are the starting labels permuted by the energetic collisions alone, a
//! permutation that depends on the trajectory and not on the labels; labels that start
//! independent of the discs' positions and velocities stay so. The fluid stays in equilibrium
//! and the collisions of an A with a B are a random half of all collisions, which obey the
//! line-of-centres law exactly (`edmd_core::measure::theory::line_of_centres_fraction`,
//! derived there): the fraction whose kinetic energy of relative motion along the line of
//! centres is at least `E*` is `exp(-E*/kT)`, in 2D as in 3D, dilute or dense, because the
//! pair correlation at contact sets how many pairs collide, not how fast (Present, *Kinetic
//! Theory of Gases* (1958), section 8.2; Levine, *Molecular Reaction Dynamics* (2005), section
//! 3.2.1).
//!
//! Measured per activation energy, all runs together. The errors are the spread of the runs
//! (standard error of their mean; a dense fluid's slow modes, heat diffusing across the box,
//! outlast blocks of one run, whose errors came out at two thirds of the runs' spread), or the
//! counting error (binomial, Poisson for the rate constant) where that is larger: eight runs
//! give only a rough spread.
//! - `reactive_fraction`: reactive collisions over all collisions, against `exp(-E*/kT)`.
//!   Every pair of species has a rule with the same activation energy: `A + B -> B + A`, and
//!   `A + A -> A + A` and `B + B -> B + B`, which change nothing but are counted, so that every
//!   collision can react. `reactive_fraction_ab` is the first rule's over the collisions of an
//!   A with a B, against the same law;
//! - `rate_constant`: `edmd_core::measure::Kinetics`' `k`, reactions per unit volume and
//!   time `= k n_A n_B`, against `line_of_centres_rate_constant`: Enskog's collision rate per
//!   pair `omega / n` (with the contact value `g(sigma)` of Henderson's equation of state for
//!   discs, of Pieprzyk et al.'s for spheres) times `exp(-E*/kT)`. Its accuracy is that of the
//!   contact value: at packing 0.6 Henderson's `Z` is 1.3% above the discs' (`edmd experiment
//!   eos`), and the rate constant reads about as much below the law;
//! - `temperature_a`: the kinetic temperature of the A, which stays `kT`.
//!
//! **Out of equilibrium: the Prigogine-Xhrouet effect.** Prigogine and Xhrouet (Physica 15,
//! 913 (1949)) and Present (J. Chem. Phys. 31, 747 (1959)) showed that a reaction with an
//! activation energy perturbs the velocity distribution of its own reactants: the collisions
//! that react are the energetic ones, so the reactants that remain lose their fast tail and
//! the rate falls below its equilibrium value. Here, in a closed box of discs all of species A
//! at the lowest packing (a dilute gas, where the Boltzmann equation's analyses apply), the rule
//! `A + A -> B + B` with probability 1 and no heat. The whole fluid still moves as an elastic
//! one (its velocities stay Maxwellian at `kT`), but the A among it do not: the B products
//! carry off the fast tail, and give energy back only in their elastic collisions with the A.
//! The run is cut into windows by the fraction of A left, and in each the fraction of A-A
//! collisions that react is compared with:
//! - the equilibrium `exp(-E*/kT)`: the measured fraction falls below it. Its error is the
//!   binomial counting error, which is conservative here (the deficits of five independent
//!   runs spread by a quarter of it: each run ends when a set number has reacted);
//! - `exp(-E*/kT_A)` with `kT_A` the measured kinetic temperature of the A: the reactants
//!   treated as a Maxwellian gas at their own, lower temperature, as Cukrowski, Fritzsche and
//!   Fort (Chem. Phys. Lett. 341, 585 (2001)) did with the nonequilibrium temperatures of
//!   Shizgal and Karplus (J. Chem. Phys. 52, 4262 (1970)). This accounts for most of the
//!   deficit; the measured fraction still reads 1-2% lower, the tail being depleted more than
//!   a cooler Maxwellian's.
//!
//! The perturbation solutions of the Boltzmann equation for `A + A -> B + B` with the
//! line-of-centres cross section (Cukrowski, Fritzsche and Popielawski, Acta Phys. Pol. A 84,
//! 369 (1993); A. S. Cukrowski, Physica A 275, 134 (2000); Cukrowski, Fritzsche and Fort 2001)
//! find the rate lowered by tens of per cent, up to nearly 45% for `A + A <-> B + B` at small
//! activation energies once products are many, far more than when the energy the products
//! carry away is neglected; Gorecki and Gorecka's molecular dynamics of an exothermic
//! `A + A -> B + B` (Forma 15, 329 (2000)) found large changes of the rate constants too. The
//! speeds of the A at the windows' ends, pooled, are shown as their ratio to Maxwell's law at
//! `kT`, which falls below 1 in the tail.

use anyhow::Result;
use clap::Args;
use edmd_core::measure::theory::{line_of_centres_fraction, line_of_centres_rate_constant};
use edmd_core::measure::{block_error, maxwell_cdf, Kinetics};
use edmd_core::Simulation;
use edmd_core::{Boundary, EventKind, EventRecord, Observer, Options, Reaction, Reactions};
use edmd_plot::{Figure, Series, PALETTE};
use serde::Serialize;

use super::common::{
    check_count, check_n, check_packings, files_line, interrupted_after, melted_fluid_in, out_dir,
    report, stop_requested, write_csv, CommonArgs, Progress,
};

/// Options of `edmd experiment reaction`.
#[derive(Debug, Args)]
pub struct ReactionArgs {
    /// Dimension: 2 (discs) or 3 (spheres) [default: both].
    #[arg(long, value_parser = crate::args::parse_dim)]
    pub dim: Option<usize>,
    /// Activation energies E*/kT of the equilibrium runs, comma-separated (each from 0 to 10).
    #[arg(long, value_delimiter = ',', default_values_t = vec![0.0, 0.5, 1.0, 2.0, 3.0, 4.0], allow_negative_numbers = true)]
    pub activation: Vec<f64>,
    /// Packing fractions of the equilibrium runs, comma-separated; the lowest is also the
    /// Prigogine-Xhrouet run's [default: discs 0.05,0.6; spheres 0.05,0.4].
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub packing: Option<Vec<f64>>,
    /// Discs (spheres) in each equilibrium run.
    #[arg(long, default_value_t = 2000, allow_negative_numbers = true)]
    pub n: usize,
    /// Disc-disc collisions per disc measured at each activation energy, in each run.
    #[arg(long, default_value_t = 25, allow_negative_numbers = true)]
    pub collisions: u64,
    /// Independent fluids (seeds) per packing fraction in equilibrium: the error bars are the
    /// spread of their results (slow modes of a dense fluid outlast blocks of one run).
    #[arg(long, default_value_t = 8, allow_negative_numbers = true)]
    pub runs: u64,
    /// Activation energies E*/kT of the Prigogine-Xhrouet runs (A + A -> B + B in a closed
    /// box), comma-separated (each above 0, at most 6).
    #[arg(long = "px-activation", value_delimiter = ',', default_values_t = vec![1.0, 2.0, 3.0], allow_negative_numbers = true)]
    pub px_activation: Vec<f64>,
    /// Discs (spheres) in each Prigogine-Xhrouet run.
    #[arg(long = "px-n", default_value_t = 20_000, allow_negative_numbers = true)]
    pub px_n: usize,
    /// The fraction of A left at which a Prigogine-Xhrouet run ends (from 0.05 to 0.9).
    #[arg(
        long = "px-until",
        default_value_t = 0.2,
        allow_negative_numbers = true
    )]
    pub px_until: f64,
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Windows of each Prigogine-Xhrouet run, equal steps of the fraction of A left.
const WINDOWS: usize = 8;
/// Bins of the speed histogram of the A left, over speeds from 0 to `SPEED_MAX` sqrt(kT/m).
const SPEED_BINS: usize = 16;
const SPEED_MAX: f64 = 4.0;

/// One equilibrium run: a dimension, a packing fraction and an activation energy.
#[derive(Debug, Serialize)]
pub struct Row {
    /// Dimension.
    pub dim: usize,
    /// Packing fraction.
    pub packing: f64,
    /// Discs (spheres).
    pub n: usize,
    /// Independent fluids measured.
    pub runs: u64,
    /// Activation energy in units of kT.
    pub activation: f64,
    /// Reactive collisions over all collisions, all runs together (every pair of species has
    /// a rule: `A + B -> B + A`, `A + A -> A + A`, `B + B -> B + B`).
    pub reactive_fraction: f64,
    /// Its statistical error (one standard deviation: the standard error of the runs' mean, or
    /// the binomial counting error where that is larger).
    pub reactive_fraction_error: f64,
    /// The line-of-centres law, `exp(-E*/kT)`.
    pub reactive_fraction_theory: f64,
    /// Reactions of `A + B -> B + A` over the collisions of an A with a B.
    pub reactive_fraction_ab: f64,
    /// Its statistical error.
    pub reactive_fraction_ab_error: f64,
    /// The line-of-centres law, `exp(-E*/kT)`.
    pub reactive_fraction_ab_theory: f64,
    /// Rate constant `k` (reactions per unit volume and time over `n_A n_B`; diameter 1,
    /// mass 1, kT 1).
    pub rate_constant: f64,
    /// Its statistical error.
    pub rate_constant_error: f64,
    /// The line-of-centres law with Enskog's collision rate, `(omega / n) exp(-E*/kT)`.
    pub rate_constant_theory: f64,
    /// Enskog's contact value `g(sigma)` in that law.
    pub contact_value: f64,
    /// Kinetic temperature of species A at the runs' ends, in units of kT (equilibrium: 1).
    pub temperature_a: f64,
    /// Its statistical error.
    pub temperature_a_error: f64,
    /// Collisions of an A with a B measured over, all runs together.
    pub ab_collisions: u64,
    /// Reactions of `A + B -> B + A` counted.
    pub reactions: u64,
    /// Simulated time measured over, all runs together.
    pub time: f64,
}

/// One window of a Prigogine-Xhrouet run.
#[derive(Debug, Serialize)]
pub struct Window {
    /// Fraction of the discs that are A at the window's start.
    pub a_fraction_start: f64,
    /// At its end.
    pub a_fraction_end: f64,
    /// Simulated time at the window's end (from the start of the reaction).
    pub time: f64,
    /// A-A collisions in the window.
    pub aa_collisions: u64,
    /// Reactions in the window.
    pub reactions: u64,
    /// Reactive A-A collisions over all A-A collisions.
    pub reactive_fraction: f64,
    /// Its counting error (binomial).
    pub reactive_fraction_error: f64,
    /// The equilibrium value `exp(-E*/kT)`.
    pub reactive_fraction_equilibrium: f64,
    /// `exp(-E*/kT_A)` with the measured temperature of the A (the reactants as a Maxwellian
    /// gas at their own temperature).
    pub reactive_fraction_temperature: f64,
    /// Kinetic temperature of the A in units of kT, averaged over the window's start and end.
    pub temperature_a: f64,
    /// Its error (from the spread of the A's kinetic energies).
    pub temperature_a_error: f64,
    /// Rate constant of the window (`k n_A^2 / 2` reactions per unit volume and time).
    pub rate_constant: f64,
    /// Its counting error (Poisson).
    pub rate_constant_error: f64,
    /// The equilibrium value, `(omega / n) exp(-E*/kT)`.
    pub rate_constant_equilibrium: f64,
}

/// One Prigogine-Xhrouet run.
#[derive(Debug, Serialize)]
pub struct PxRun {
    /// Dimension.
    pub dim: usize,
    /// Packing fraction.
    pub packing: f64,
    /// Discs (spheres).
    pub n: usize,
    /// Activation energy in units of kT.
    pub activation: f64,
    /// Reactive A-A collisions over all A-A collisions, over the whole run.
    pub reactive_fraction: f64,
    /// Its counting error.
    pub reactive_fraction_error: f64,
    /// The equilibrium value `exp(-E*/kT)`.
    pub reactive_fraction_equilibrium: f64,
    /// `1 - reactive_fraction / exp(-E*/kT)`: the relative shortfall of the rate.
    pub deficit: f64,
    /// Its error.
    pub deficit_error: f64,
    /// The temperature estimate over the run: each window's `exp(-E*/kT_A)`, weighted by its
    /// A-A collisions.
    pub reactive_fraction_temperature: f64,
    /// The lowest kinetic temperature of the A at a window's end (in units of kT).
    pub temperature_a_min: f64,
    /// Its error.
    pub temperature_a_min_error: f64,
    /// Fraction of A left at the end.
    pub a_fraction_end: f64,
    /// The windows.
    pub windows: Vec<Window>,
    /// The speeds of the A at the windows' ends, pooled: `(speed, measured density, Maxwell
    /// at kT, count)` per bin.
    #[serde(skip)]
    pub speeds: Vec<(f64, f64, f64, u64)>,
}

/// The summary.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Experiment name.
    pub experiment: &'static str,
    /// Dimensions run.
    pub dims: Vec<usize>,
    /// Disc-disc collisions per disc measured at each activation energy, in each run.
    pub collisions: u64,
    /// Independent fluids per packing fraction.
    pub runs: u64,
    /// One row per dimension, packing fraction and activation energy, in equilibrium.
    pub rows: Vec<Row>,
    /// What the rows are compared with.
    pub theory: &'static str,
    /// One entry per dimension and activation energy: `A + A -> B + B` in a closed box.
    pub prigogine_xhrouet: Vec<PxRun>,
    /// What the Prigogine-Xhrouet runs are compared with.
    pub prigogine_xhrouet_theory: &'static str,
    /// True if stopped by Ctrl-C early.
    pub interrupted: bool,
}

const THEORY: &str = "A + B -> B + A with probability 1 and no heat in an equilibrium fluid at kT = 1: with A + A -> A + A and B + B -> B + B (which change nothing) so that every collision can react: reactive_fraction (reactive collisions over all collisions) against the line-of-centres law exp(-E*/kT) (Present, Kinetic Theory of Gases (1958), section 8.2; exact in equilibrium in 2D and 3D at any density); reactive_fraction_ab (reactions of A + B over A-B collisions) against the same; rate_constant (reactions per unit volume and time over n_A n_B) against (omega/n) exp(-E*/kT) with Enskog's collision frequency omega (contact value: Henderson's equation of state for discs, Pieprzyk et al.'s for spheres)";

const PX_THEORY: &str = "A + A -> B + B with probability 1 and no heat in a closed box, all A at the start: the fraction of A-A collisions that react against its equilibrium value exp(-E*/kT) (Prigogine and Xhrouet, Physica 15, 913 (1949); Present, J. Chem. Phys. 31, 747 (1959): the rate falls below it as the reaction depletes the reactants' fast tail; Boltzmann-equation estimates up to some 40% for a few kT, Cukrowski, Fritzsche and Fort, Chem. Phys. Lett. 341, 585 (2001)) and against exp(-E*/kT_A) with the measured temperature of the A (the Shizgal-Karplus temperature estimate)";

/// Runs the experiment.
pub fn run(args: &ReactionArgs) -> Result<()> {
    let dims = match args.dim {
        Some(d) => vec![d],
        None => vec![2, 3],
    };
    check(args, &dims)?;
    let dir = out_dir(&args.common)?.to_path_buf();
    let steps: usize = dims
        .iter()
        .map(|&d| {
            packings(args, d).len() * args.activation.len() * args.runs as usize
                + args.px_activation.len()
        })
        .sum();
    let progress = Progress::new(steps as u64, "reaction");
    let mut done = 0u64;
    let mut rows = Vec::new();
    let mut px = Vec::new();
    let mut interrupted = false;
    'dims: for &dim in &dims {
        let etas = packings(args, dim);
        for (k, &eta) in etas.iter().enumerate() {
            // Each run of each packing its own seed (runs are at most 1000).
            let seed = args
                .common
                .seed
                .wrapping_add(1000 * (10 * dim as u64 + k as u64));
            let measured = match dim {
                3 => equilibrium::<3>(args, eta, seed, &progress, &mut done)?,
                _ => equilibrium::<2>(args, eta, seed, &progress, &mut done)?,
            };
            let finished = measured.len() == args.activation.len();
            rows.extend(measured);
            if !finished {
                interrupted = true;
                break 'dims;
            }
        }
        let eta = etas.iter().copied().fold(f64::INFINITY, f64::min);
        for (k, &a) in args.px_activation.iter().enumerate() {
            let seed = args
                .common
                .seed
                .wrapping_add(1_000_000 + 1000 * dim as u64 + k as u64);
            let run = match dim {
                3 => prigogine_xhrouet::<3>(args, eta, a, seed)?,
                _ => prigogine_xhrouet::<2>(args, eta, a, seed)?,
            };
            match run {
                Some(r) => px.push(r),
                None => {
                    interrupted = true;
                    break 'dims;
                }
            }
            done += 1;
            progress.set(done);
        }
    }
    progress.finish();
    interrupted |= stop_requested();
    let files = write_outputs(&dir, &rows, &px)?;
    let human = human(args, &rows, &px, interrupted, &files);
    report(
        &args.common,
        &Summary {
            experiment: "reaction",
            dims,
            collisions: args.collisions,
            runs: args.runs,
            rows,
            theory: THEORY,
            prigogine_xhrouet: px,
            prigogine_xhrouet_theory: PX_THEORY,
            interrupted,
        },
        &human,
    )?;
    if interrupted {
        return interrupted_after(&files);
    }
    Ok(())
}

/// The packing fractions of dimension `dim`.
fn packings(args: &ReactionArgs, dim: usize) -> Vec<f64> {
    args.packing.clone().unwrap_or_else(|| {
        if dim == 3 {
            vec![0.05, 0.4]
        } else {
            vec![0.05, 0.6]
        }
    })
}

fn check(args: &ReactionArgs, dims: &[usize]) -> Result<()> {
    let bad = |m: String| edmd::user_error(format!("reaction: {m}"));
    if args.activation.is_empty() {
        return bad("give at least one activation energy (--activation)".into());
    }
    if let Some(a) = args
        .activation
        .iter()
        .find(|&&a| !(a.is_finite() && (0.0..=10.0).contains(&a)))
    {
        return bad(format!(
            "--activation {a} is outside [0, 10] (activation energies in units of kT)"
        ));
    }
    if args.px_activation.is_empty() {
        return bad("give at least one activation energy (--px-activation)".into());
    }
    // Above 6 kT a run to the end takes over 4 e^6 collisions per disc.
    if let Some(a) = args
        .px_activation
        .iter()
        .find(|&&a| !(a.is_finite() && a > 0.0 && a <= 6.0))
    {
        return bad(format!(
            "--px-activation {a} must be above 0 and at most 6 (activation energies in units of kT)"
        ));
    }
    for &dim in dims {
        // Fluid: below freezing, 0.70 for discs; spheres up to 0.50 (the generator makes 0.50).
        let max = if dim == 3 { 0.500_000_1 } else { 0.70 };
        check_packings("reaction", &packings(args, dim), max)?;
    }
    check_n("reaction", args.n, 64)?;
    check_count("reaction", "collisions", args.collisions, 1, 100_000)?;
    check_count("reaction", "runs", args.runs, 2, 1000)?;
    if !(64..=edmd::MAX_N).contains(&args.px_n) {
        return bad(format!(
            "--px-n must be from 64 to {}, found {}",
            edmd::MAX_N,
            args.px_n
        ));
    }
    if !(args.px_until.is_finite() && (0.05..=0.9).contains(&args.px_until)) {
        return bad(format!(
            "--px-until must be from 0.05 to 0.9 (the fraction of A left), found {}",
            args.px_until
        ));
    }
    Ok(())
}

/// Counts the collisions of one pair of species (in either order), all collisions, the
/// reactions of the pair's rule (the first) and all reactions. A reaction of the first rule is
/// one of that pair's collisions; a non-reactive collision leaves the species as they were, so
/// the simulation's species name its pair.
#[derive(Clone, Copy, Default)]
struct PairCount {
    pair: (u16, u16),
    pair_collisions: u64,
    all_collisions: u64,
    reactions: u64,
    all_reactions: u64,
}

impl PairCount {
    fn new(pair: (u16, u16)) -> Self {
        PairCount {
            pair,
            ..Self::default()
        }
    }
}

impl<const D: usize> Observer<D> for PairCount {
    #[inline]
    fn on_event(&mut self, e: &EventRecord<D>, sim: &Simulation<D>) {
        match e.kind {
            EventKind::DiscDisc { i, j } => {
                self.all_collisions += 1;
                let s = (sim.species(i), sim.species(j));
                if s == self.pair || (s.1, s.0) == self.pair {
                    self.pair_collisions += 1;
                }
            }
            EventKind::Reaction { rule, .. } => {
                self.all_collisions += 1;
                self.all_reactions += 1;
                if rule == 0 {
                    self.pair_collisions += 1;
                    self.reactions += 1;
                }
            }
            _ => {}
        }
    }
}

/// Runs `sim` for `collisions` more disc-disc collisions with `observer`, in slices with a
/// look at the stop flag between them; `false` when a stop was requested first.
fn run_observed<const D: usize, O: Observer<D>>(
    sim: &mut Simulation<D>,
    collisions: u64,
    observer: &mut O,
) -> Result<bool> {
    let target = sim.stats().disc_disc.saturating_add(collisions);
    while sim.stats().disc_disc < target {
        if stop_requested() {
            return Ok(false);
        }
        let slice = (target - sim.stats().disc_disc).min(10_000);
        let done = sim.run_events(slice, observer);
        edmd::check_stall(sim)?;
        if done == 0 {
            return edmd::user_error("reaction: no disc moves");
        }
    }
    Ok(true)
}

/// Kinetic temperature of the discs of species `s` in units of `kt`, and its standard error
/// (that of a mean over the discs); `NaN` if there are none.
fn species_temperature<const D: usize>(sim: &Simulation<D>, s: u16, kt: f64) -> (f64, f64) {
    let per_disc: Vec<f64> = (0..sim.len())
        .filter(|&i| sim.species(i) == s)
        .map(|i| sim.mass(i) * sim.velocity(i).norm2() / (D as f64 * kt))
        .collect();
    let m = per_disc.len() as f64;
    let mean = per_disc.iter().sum::<f64>() / m;
    let var = per_disc.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (m - 1.0);
    (mean, (var / m).sqrt())
}

/// Half the labels 0 and half 1 (one more 0 for odd `n`), in a random order drawn from `seed`.
///
/// The labels must not depend on where the discs are. With `A + B -> B + A` a label moves at
/// each energetic collision, so fast discs soon carry labels from around them while slow ones
/// keep theirs: labels placed in a pattern (alternating in the generator's cell order, say,
/// which makes neighbours unlike) would then make the unlike collisions of slow discs more
/// frequent than those of fast ones, and in a dense fluid, where neighbours stay neighbours,
/// the measured fraction would read low (by 2% at packing 0.6 in 2D over 25 collisions per
/// disc). Labels independent of the phase point stay so, since the exchanges only permute
/// them.
fn random_halves(n: usize, seed: u64) -> Vec<u16> {
    use rand::seq::SliceRandom;
    use rand::SeedableRng;
    let mut labels: Vec<u16> = (0..n).map(|k| u16::from(k >= n.div_ceil(2))).collect();
    labels.shuffle(&mut rand_pcg::Pcg64Mcg::seed_from_u64(
        seed ^ 0x5EED_1AB3_1500_0000,
    ));
    labels
}

/// A melted fluid at `eta` whose discs (in the generator's order) are of the species
/// `species(k)`, and its `kT`.
fn fluid<const D: usize>(
    n: usize,
    eta: f64,
    seed: u64,
    species: impl Fn(usize) -> u16,
) -> Result<Option<(Simulation<D>, f64)>> {
    let Some((melted, _)) = melted_fluid_in::<D>(n, eta, Boundary::Periodic, seed, 20)? else {
        return Ok(None);
    };
    let mut discs = melted.discs();
    for (k, d) in discs.iter_mut().enumerate() {
        d.species = species(k);
    }
    let sim = Simulation::new(&discs, *melted.sim_box(), Options::default())
        .or_else(|e| edmd::user_error(format!("reaction: {e}")))?;
    let kt = 2.0 * sim.kinetic_energy() / (D * n) as f64;
    Ok(Some((sim, kt)))
}

/// `A + B -> B + A`, and `A + A -> A + A` and `B + B -> B + B`, which change nothing but count
/// as reactions: every collision can react, so reactions over all collisions follow the
/// line-of-centres law, and the first rule's over A-B collisions too.
fn every_pair(activation: f64) -> Reactions {
    let same = |s: u16| Reaction {
        reactants: (s, s),
        products: (s, s),
        activation,
        probability: 1.0,
        heat: 0.0,
    };
    let mut r = rule((0, 1), (1, 0), activation);
    r.rules.extend([same(0), same(1)]);
    r
}

fn rule(reactants: (u16, u16), products: (u16, u16), activation: f64) -> Reactions {
    Reactions::new(vec![Reaction {
        reactants,
        products,
        activation,
        probability: 1.0,
        heat: 0.0,
    }])
}

/// What one equilibrium run at one activation energy measured.
#[derive(Clone, Copy, Default)]
struct Measured {
    count: PairCount,
    reactions_per_exposure: f64,
    exposure: f64,
    temperature_a: f64,
    time: f64,
}

/// The equilibrium runs at one packing fraction: `--runs` fluids, each run on at every
/// activation energy; one row per activation energy (none if a stop was requested).
fn equilibrium<const D: usize>(
    args: &ReactionArgs,
    eta: f64,
    seed: u64,
    progress: &Progress,
    done: &mut u64,
) -> Result<Vec<Row>> {
    let mut measured: Vec<Vec<Measured>> = vec![Vec::new(); args.activation.len()];
    let mut kts = Vec::new();
    for run in 0..args.runs {
        let labels = random_halves(args.n, seed.wrapping_add(run));
        let Some((base, kt)) = fluid::<D>(args.n, eta, seed.wrapping_add(run), |k| labels[k])?
        else {
            return Ok(Vec::new());
        };
        kts.push(kt);
        for (m, &a) in measured.iter_mut().zip(&args.activation) {
            let mut sim = base.clone();
            sim.set_reactions(Some(every_pair(a * kt)))
                .or_else(|e| edmd::user_error(format!("reaction: {e}")))?;
            let mut kinetics = Kinetics::new(&sim);
            let mut count = PairCount::new((0, 1));
            let t0 = sim.time();
            if !run_observed(
                &mut sim,
                args.collisions * args.n as u64,
                &mut (&mut kinetics, &mut count),
            )? {
                return Ok(Vec::new());
            }
            kinetics.sample(&sim);
            let rate = &kinetics.rates()[0];
            m.push(Measured {
                count,
                reactions_per_exposure: rate.rate_constant.value,
                exposure: rate.exposure,
                temperature_a: species_temperature(&sim, 0, kt).0,
                time: sim.time() - t0,
            });
            *done += 1;
            progress.set(*done);
        }
    }
    let kt = mean(&kts);
    let rows = args
        .activation
        .iter()
        .zip(&measured)
        .map(|(&a, runs)| {
            let sum = |f: fn(&Measured) -> u64| runs.iter().map(f).sum::<u64>();
            let (reactions, pair, all, all_reactions) = (
                sum(|m| m.count.reactions),
                sum(|m| m.count.pair_collisions),
                sum(|m| m.count.all_collisions),
                sum(|m| m.count.all_reactions),
            );
            let each = |f: fn(&Measured) -> f64| runs.iter().map(f).collect::<Vec<f64>>();
            let exposure: f64 = runs.iter().map(|m| m.exposure).sum();
            let temperatures = each(|m| m.temperature_a);
            let theory = line_of_centres_fraction(a, 1.0);
            Row {
                dim: D,
                packing: eta,
                n: args.n,
                runs: args.runs,
                activation: a,
                reactive_fraction: all_reactions as f64 / all.max(1) as f64,
                reactive_fraction_error: block_error(&each(|m| {
                    m.count.all_reactions as f64 / m.count.all_collisions.max(1) as f64
                }))
                .max(binomial_error(all_reactions, all)),
                reactive_fraction_theory: theory,
                reactive_fraction_ab: reactions as f64 / pair.max(1) as f64,
                reactive_fraction_ab_error: block_error(&each(|m| {
                    m.count.reactions as f64 / m.count.pair_collisions.max(1) as f64
                }))
                .max(binomial_error(reactions, pair)),
                reactive_fraction_ab_theory: theory,
                rate_constant: reactions as f64 / exposure,
                rate_constant_error: block_error(&each(|m| m.reactions_per_exposure))
                    .max(reactions as f64 / exposure / (reactions.max(1) as f64).sqrt()),
                rate_constant_theory: line_of_centres_rate_constant(eta, 1.0, kt, 1.0, D, a * kt),
                contact_value: edmd_core::measure::theory::contact_value(eta, D),
                temperature_a: mean(&temperatures),
                temperature_a_error: block_error(&temperatures),
                ab_collisions: pair,
                reactions,
                time: runs.iter().map(|m| m.time).sum(),
            }
        })
        .collect();
    Ok(rows)
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// Binomial standard error of a fraction `k / m`.
fn binomial_error(k: u64, m: u64) -> f64 {
    if m == 0 {
        return f64::NAN;
    }
    let p = k as f64 / m as f64;
    (p * (1.0 - p) / m as f64).sqrt()
}

/// A closed box of A at `eta` with `A + A -> B + B` at activation `a` kT, run in windows until
/// the fraction of A left reaches `--px-until`; `None` if a stop was requested.
fn prigogine_xhrouet<const D: usize>(
    args: &ReactionArgs,
    eta: f64,
    a: f64,
    seed: u64,
) -> Result<Option<PxRun>> {
    let n = args.px_n;
    let Some((mut sim, kt)) = fluid::<D>(n, eta, seed, |_| 0)? else {
        return Ok(None);
    };
    sim.set_reactions(Some(rule((0, 0), (1, 1), a * kt)))
        .or_else(|e| edmd::user_error(format!("reaction: {e}")))?;
    let equilibrium = line_of_centres_fraction(a * kt, kt);
    let k_equilibrium = line_of_centres_rate_constant(eta, 1.0, kt, 1.0, D, a * kt);
    let mut kinetics = Kinetics::new(&sim);
    let t0 = sim.time();
    // Slices of about a tenth of a collision per disc: a window overshoots its end by that.
    let slice = (n as u64 / 10).max(100);
    let mut windows: Vec<Window> = Vec::new();
    let (mut total_collisions, mut total_reactions) = (0u64, 0u64);
    let mut at_start = species_temperature(&sim, 0, kt);
    let mut before = (0u64, 0.0);
    let mut speeds = Vec::new();
    let mut coldest = (f64::INFINITY, f64::NAN);
    for w in 1..=WINDOWS {
        let target = 1.0 - (1.0 - args.px_until) * w as f64 / WINDOWS as f64;
        let start = kinetics.counts()[0] as f64 / n as f64;
        let mut count = PairCount::new((0, 0));
        while (kinetics.counts()[0] as f64) > target * n as f64 {
            if stop_requested() {
                return Ok(None);
            }
            let done = sim.run_events(slice, &mut (&mut kinetics, &mut count));
            edmd::check_stall(&sim)?;
            if done == 0 {
                return edmd::user_error("reaction: no disc moves");
            }
        }
        kinetics.sample(&sim);
        // The window's own rate constant: its reactions over its exposure.
        let r = &kinetics.rates()[0];
        let (reactions, exposure) = (r.reactions - before.0, r.exposure - before.1);
        before = (r.reactions, r.exposure);
        let k = reactions as f64 / exposure;
        let at_end = species_temperature(&sim, 0, kt);
        if at_end.0 < coldest.0 {
            coldest = at_end;
        }
        let ta = 0.5 * (at_start.0 + at_end.0);
        let ta_error = 0.5 * at_start.1.hypot(at_end.1);
        at_start = at_end;
        speeds.extend(
            (0..sim.len())
                .filter(|&i| sim.species(i) == 0)
                .map(|i| (sim.velocity(i).norm2() / kt).sqrt()),
        );
        windows.push(Window {
            a_fraction_start: start,
            a_fraction_end: kinetics.counts()[0] as f64 / n as f64,
            time: sim.time() - t0,
            aa_collisions: count.pair_collisions,
            reactions: count.reactions,
            reactive_fraction: count.reactions as f64 / count.pair_collisions.max(1) as f64,
            reactive_fraction_error: binomial_error(count.reactions, count.pair_collisions),
            reactive_fraction_equilibrium: equilibrium,
            reactive_fraction_temperature: line_of_centres_fraction(a * kt, ta * kt),
            temperature_a: ta,
            temperature_a_error: ta_error,
            rate_constant: k,
            rate_constant_error: k / (reactions.max(1) as f64).sqrt(),
            rate_constant_equilibrium: k_equilibrium,
        });
        total_collisions += count.pair_collisions;
        total_reactions += count.reactions;
    }
    let fraction = total_reactions as f64 / total_collisions.max(1) as f64;
    let error = binomial_error(total_reactions, total_collisions);
    // The temperature estimate over the run: each window's, weighted by its A-A collisions.
    let estimate = windows
        .iter()
        .map(|w| w.reactive_fraction_temperature * w.aa_collisions as f64)
        .sum::<f64>()
        / total_collisions.max(1) as f64;
    Ok(Some(PxRun {
        dim: D,
        packing: eta,
        n,
        activation: a,
        reactive_fraction: fraction,
        reactive_fraction_error: error,
        reactive_fraction_equilibrium: equilibrium,
        deficit: 1.0 - fraction / equilibrium,
        deficit_error: error / equilibrium,
        reactive_fraction_temperature: estimate,
        temperature_a_min: coldest.0,
        temperature_a_min_error: coldest.1,
        a_fraction_end: kinetics.counts()[0] as f64 / n as f64,
        windows,
        speeds: speed_histogram(&speeds, D),
    }))
}

/// `(bin centre, density, Maxwell's density at kT, count)` of speeds in units of sqrt(kT/m).
fn speed_histogram(speeds: &[f64], dim: usize) -> Vec<(f64, f64, f64, u64)> {
    let width = SPEED_MAX / SPEED_BINS as f64;
    let mut counts = [0u64; SPEED_BINS];
    for &v in speeds {
        let k = (v / width) as usize;
        if k < SPEED_BINS {
            counts[k] += 1;
        }
    }
    let total = speeds.len().max(1) as f64;
    counts
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let (lo, hi) = (k as f64 * width, (k + 1) as f64 * width);
            // Maxwell's probability of the bin over its width (the density averaged over it).
            let maxwell = (maxwell_cdf(hi, 1.0, 1.0, dim) - maxwell_cdf(lo, 1.0, 1.0, dim)) / width;
            (0.5 * (lo + hi), c as f64 / (total * width), maxwell, c)
        })
        .collect()
}

fn write_outputs(
    dir: &std::path::Path,
    rows: &[Row],
    px: &[PxRun],
) -> Result<Vec<std::path::PathBuf>> {
    let mut files = Vec::new();
    let csv = dir.join("reaction.csv");
    write_csv(
        &csv,
        &[
            "dim",
            "packing",
            "activation",
            "reactive_fraction",
            "reactive_fraction_error",
            "reactive_fraction_theory",
            "reactive_fraction_ab",
            "reactive_fraction_ab_error",
            "reactive_fraction_ab_theory",
            "rate_constant",
            "rate_constant_error",
            "rate_constant_theory",
            "temperature_a",
        ],
        rows.iter().map(|r| {
            vec![
                r.dim as f64,
                r.packing,
                r.activation,
                r.reactive_fraction,
                r.reactive_fraction_error,
                r.reactive_fraction_theory,
                r.reactive_fraction_ab,
                r.reactive_fraction_ab_error,
                r.reactive_fraction_ab_theory,
                r.rate_constant,
                r.rate_constant_error,
                r.rate_constant_theory,
                r.temperature_a,
            ]
        }),
    )?;
    files.push(csv);
    // The cases (dimension, packing) in the order run.
    let mut cases: Vec<(usize, f64)> = Vec::new();
    for r in rows {
        if !cases.contains(&(r.dim, r.packing)) {
            cases.push((r.dim, r.packing));
        }
    }
    let top = rows
        .iter()
        .map(|r| r.activation)
        .fold(0.0, f64::max)
        .max(1.0);
    let grid: Vec<f64> = (0..=100).map(|i| top * i as f64 / 100.0).collect();
    let name = |d: usize, eta: f64| format!("{}D, packing {eta}", d);
    let mut fig = Figure::new(
        "Reactive collisions in equilibrium (A + B -> B + A)",
        "activation energy E*/kT",
        "reactive fraction of A-B collisions",
    )
    .with_log_y()
    .with(
        Series::line(
            "line of centres exp(-E*/kT)",
            grid.iter().map(|&a| (a, (-a).exp())).collect(),
        )
        .coloured([0, 0, 0]),
    );
    let mut fig_k = Figure::new(
        "Rate constant in equilibrium (A + B -> B + A)",
        "activation energy E*/kT",
        "rate constant k (sigma^D / tau)",
    )
    .with_log_y();
    for (c, &(d, eta)) in cases.iter().enumerate() {
        let colour = PALETTE[c % PALETTE.len()];
        let these: Vec<&Row> = rows
            .iter()
            .filter(|r| (r.dim, r.packing) == (d, eta))
            .collect();
        fig = fig.with(
            Series::error_bars(
                &format!("edmd, {}", name(d, eta)),
                these
                    .iter()
                    .map(|r| (r.activation, r.reactive_fraction))
                    .collect(),
                these.iter().map(|r| r.reactive_fraction_error).collect(),
            )
            .coloured(colour),
        );
        let prefactor = line_of_centres_rate_constant(eta, 1.0, 1.0, 1.0, d, 0.0);
        fig_k = fig_k
            .with(
                Series::line(
                    &format!("Enskog x line of centres, {}", name(d, eta)),
                    grid.iter().map(|&a| (a, prefactor * (-a).exp())).collect(),
                )
                .coloured(colour),
            )
            .with(
                Series::error_bars(
                    &format!("edmd, {}", name(d, eta)),
                    these
                        .iter()
                        .map(|r| (r.activation, r.rate_constant))
                        .collect(),
                    these.iter().map(|r| r.rate_constant_error).collect(),
                )
                .coloured(colour),
            );
    }
    let (png, svg) = fig.save(&dir.join("reaction"))?;
    files.extend([png, svg]);
    // The same against the law: measured over exp(-E*/kT), the cases side by side.
    let mut fig_r = Figure::new(
        "Reactive collisions over the line-of-centres law (A + B -> B + A)",
        "activation energy E*/kT (cases side by side)",
        "reactive fraction / exp(-E*/kT)",
    )
    .with(Series::line("line of centres", vec![(0.0, 1.0), (top, 1.0)]).coloured([0, 0, 0]));
    for (c, &(d, eta)) in cases.iter().enumerate() {
        let shift = 0.04 * (c as f64 - 0.5 * (cases.len() as f64 - 1.0));
        let these: Vec<&Row> = rows
            .iter()
            .filter(|r| (r.dim, r.packing) == (d, eta))
            .collect();
        fig_r = fig_r.with(
            Series::error_bars(
                &format!("edmd, {}", name(d, eta)),
                these
                    .iter()
                    .map(|r| {
                        (
                            r.activation + shift,
                            r.reactive_fraction / r.reactive_fraction_theory,
                        )
                    })
                    .collect(),
                these
                    .iter()
                    .map(|r| r.reactive_fraction_error / r.reactive_fraction_theory)
                    .collect(),
            )
            .coloured(PALETTE[c % PALETTE.len()]),
        );
    }
    let (png, svg) = fig_r.save(&dir.join("reaction-ratio"))?;
    files.extend([png, svg]);
    let (png, svg) = fig_k.save(&dir.join("reaction-rate"))?;
    files.extend([png, svg]);

    // Prigogine-Xhrouet: windows and speeds.
    let csv = dir.join("prigogine-xhrouet.csv");
    write_csv(
        &csv,
        &[
            "dim",
            "packing",
            "activation",
            "a_fraction_start",
            "a_fraction_end",
            "time",
            "aa_collisions",
            "reactions",
            "reactive_fraction",
            "reactive_fraction_error",
            "reactive_fraction_equilibrium",
            "reactive_fraction_temperature",
            "temperature_a",
            "temperature_a_error",
            "rate_constant",
            "rate_constant_error",
            "rate_constant_equilibrium",
        ],
        px.iter().flat_map(|p| {
            p.windows.iter().map(move |w| {
                vec![
                    p.dim as f64,
                    p.packing,
                    p.activation,
                    w.a_fraction_start,
                    w.a_fraction_end,
                    w.time,
                    w.aa_collisions as f64,
                    w.reactions as f64,
                    w.reactive_fraction,
                    w.reactive_fraction_error,
                    w.reactive_fraction_equilibrium,
                    w.reactive_fraction_temperature,
                    w.temperature_a,
                    w.temperature_a_error,
                    w.rate_constant,
                    w.rate_constant_error,
                    w.rate_constant_equilibrium,
                ]
            })
        }),
    )?;
    files.push(csv);
    let csv = dir.join("prigogine-xhrouet-speeds.csv");
    write_csv(
        &csv,
        &["dim", "activation", "speed", "density", "maxwell", "count"],
        px.iter().flat_map(|p| {
            p.speeds
                .iter()
                .map(move |&(v, f, m, c)| vec![p.dim as f64, p.activation, v, f, m, c as f64])
        }),
    )?;
    files.push(csv);
    let consumed = |w: &Window| 1.0 - 0.5 * (w.a_fraction_start + w.a_fraction_end);
    let mut fig = Figure::new(
        "Prigogine-Xhrouet effect (A + A -> B + B, closed box)",
        "fraction of A consumed",
        "reactive fraction of A-A collisions / exp(-E*/kT)",
    )
    // Room below the points for the legend.
    .with_y_range(0.45, 1.05)
    .with(Series::line("equilibrium", vec![(0.0, 1.0), (1.0, 1.0)]).coloured([0, 0, 0]));
    let mut fig_v = Figure::new(
        "Speeds of the A left over Maxwell's law at kT",
        "speed v / sqrt(kT/m)",
        "density of the A at the windows' ends / Maxwell at kT",
    )
    .with(Series::line("Maxwell at kT", vec![(0.0, 1.0), (SPEED_MAX, 1.0)]).coloured([0, 0, 0]));
    for (c, p) in px.iter().enumerate() {
        let colour = PALETTE[c % PALETTE.len()];
        let label = format!("{}D, E* = {} kT", p.dim, p.activation);
        fig = fig
            .with(
                Series::error_bars(
                    &format!("edmd, {label}"),
                    p.windows
                        .iter()
                        .map(|w| {
                            (
                                consumed(w),
                                w.reactive_fraction / w.reactive_fraction_equilibrium,
                            )
                        })
                        .collect(),
                    p.windows
                        .iter()
                        .map(|w| w.reactive_fraction_error / w.reactive_fraction_equilibrium)
                        .collect(),
                )
                .coloured(colour),
            )
            .with(
                Series::line(
                    // One legend entry says what all the lines are; each has its run's colour.
                    if c == 0 {
                        "lines: exp(-E*/kT_A) / exp(-E*/kT), kT_A the A's temperature"
                    } else {
                        ""
                    },
                    p.windows
                        .iter()
                        .map(|w| {
                            (
                                consumed(w),
                                w.reactive_fraction_temperature / w.reactive_fraction_equilibrium,
                            )
                        })
                        .collect(),
                )
                .coloured(colour),
            );
        let (points, errors): (Vec<(f64, f64)>, Vec<f64>) = p
            .speeds
            .iter()
            .filter(|s| s.3 >= 10)
            .map(|&(v, f, m, c)| ((v, f / m), f / m / (c as f64).sqrt()))
            .unzip();
        fig_v = fig_v.with(Series::error_bars(&label, points, errors).coloured(colour));
    }
    let (png, svg) = fig.save(&dir.join("prigogine-xhrouet"))?;
    files.extend([png, svg]);
    let (png, svg) = fig_v.save(&dir.join("prigogine-xhrouet-speeds"))?;
    files.extend([png, svg]);
    Ok(files)
}

fn human(
    args: &ReactionArgs,
    rows: &[Row],
    px: &[PxRun],
    interrupted: bool,
    files: &[std::path::PathBuf],
) -> String {
    let mut s = format!(
        "reactive collisions A + B -> B + A in equilibrium, {} runs of {} discs (spheres), {} collisions per disc each:\n  dim  packing  E*/kT  fraction    error  exp(-E*/kT)   dev/err        k    error   k theory  dev\n",
        args.runs, args.n, args.collisions
    );
    for r in rows {
        let sigmas = if r.reactive_fraction_error > 0.0 {
            format!(
                "{:+8.1}",
                (r.reactive_fraction - r.reactive_fraction_theory) / r.reactive_fraction_error
            )
        } else {
            "       -".into()
        };
        s += &format!(
            "  {:3}  {:7.3}  {:5.2}  {:8.5}  {:7.5}  {:11.5}  {}  {:8.4}  {:7.4}  {:8.4}  {:+.1}%\n",
            r.dim,
            r.packing,
            r.activation,
            r.reactive_fraction,
            r.reactive_fraction_error,
            r.reactive_fraction_theory,
            sigmas,
            r.rate_constant,
            r.rate_constant_error,
            r.rate_constant_theory,
            100.0 * (r.rate_constant / r.rate_constant_theory - 1.0)
        );
    }
    if !px.is_empty() {
        s += &format!(
            "Prigogine-Xhrouet: A + A -> B + B in a closed box, {} discs (spheres), all A at the start, until {} of them are left:\n  dim  packing  E*/kT  fraction    error  exp(-E*/kT)  deficit   error  exp(-E*/kT_A)  lowest kT_A\n",
            args.px_n, args.px_until
        );
        for p in px {
            s += &format!(
                "  {:3}  {:7.3}  {:5.2}  {:8.5}  {:7.5}  {:11.5}  {:6.1}%  {:5.1}%  {:13.5}  {:.3} +- {:.3}\n",
                p.dim,
                p.packing,
                p.activation,
                p.reactive_fraction,
                p.reactive_fraction_error,
                p.reactive_fraction_equilibrium,
                100.0 * p.deficit,
                100.0 * p.deficit_error,
                p.reactive_fraction_temperature,
                p.temperature_a_min,
                p.temperature_a_min_error
            );
        }
    }
    if interrupted {
        s += "interrupted: results so far\n";
    }
    s += &files_line(files);
    s
}
