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
use serde::Serialize;

use super::common::{
    check_count, check_n, check_once, check_packings, interrupted_after, out_dir, outputs, report,
    stop_requested, CommonArgs, Progress,
};

mod equilibrium;
mod figures;
mod fluid;
mod prigogine_xhrouet;
mod table;

use equilibrium::{equilibrium, Row};
use prigogine_xhrouet::{prigogine_xhrouet, PxRun};

/// Options of `edmd experiment reaction`.
#[derive(Debug, Args)]
pub struct ReactionArgs {
    /// Dimension: 2 (discs) or 3 (spheres) [default: both].
    #[arg(long, value_parser = crate::args::parse_dim)]
    pub dim: Option<usize>,
    /// Activation energies E*/kT of the equilibrium runs, comma-separated (each from 0 to 10).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0,0.5,1,2,3,4",
        allow_negative_numbers = true
    )]
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
    #[arg(
        long = "px-activation",
        value_delimiter = ',',
        default_value = "1,2,3",
        allow_negative_numbers = true
    )]
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

/// The summary.
#[derive(Debug, Serialize)]
struct Summary {
    /// Experiment name.
    experiment: &'static str,
    /// Dimensions run.
    dims: Vec<usize>,
    /// Disc-disc collisions per disc measured at each activation energy, in each run.
    collisions: u64,
    /// Independent fluids per packing fraction.
    runs: u64,
    /// One row per dimension, packing fraction and activation energy, in equilibrium.
    rows: Vec<Row>,
    /// What the rows are compared with.
    theory: &'static str,
    /// One entry per dimension and activation energy: `A + A -> B + B` in a closed box.
    prigogine_xhrouet: Vec<PxRun>,
    /// What the Prigogine-Xhrouet runs are compared with.
    prigogine_xhrouet_theory: &'static str,
    /// True if stopped by Ctrl-C early.
    interrupted: bool,
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
    let dir = out_dir(
        &args.common,
        &outputs(
            &["reaction", "prigogine-xhrouet", "prigogine-xhrouet-speeds"],
            &[
                "reaction",
                "reaction-ratio",
                "reaction-rate",
                "prigogine-xhrouet",
                "prigogine-xhrouet-speeds",
            ],
        ),
    )?
    .to_path_buf();
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
    let files = figures::write_outputs(&dir, &rows, &px)?;
    let human = table::human(args, &rows, &px, interrupted, &files);
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
    check_once("reaction", "--activation", &args.activation)?;
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
    check_once("reaction", "--px-activation", &args.px_activation)?;
    for &dim in dims {
        // Fluid: below freezing, 0.70 for discs; spheres up to 0.50 (the generator makes 0.50).
        let max = if dim == 3 { 0.500_000_1 } else { 0.70 };
        let who = match (dim, dims.len()) {
            (3, 1) => "reaction, for spheres",
            (3, _) => "reaction, for spheres (both dimensions run unless --dim says one)",
            (_, 1) => "reaction",
            _ => "reaction, for discs",
        };
        check_packings(who, &packings(args, dim), max)?;
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
