//! `edmd experiment NAME`: the measurements of the Princeton assignment, each a command that
//! prints a summary and writes CSV files and plots (PNG and SVG) into `--out-dir`.

pub mod annihilation;
pub mod barometric;
pub mod billiards;
pub mod brownian;
pub mod common;
pub mod cooling;
pub mod demon;
pub mod diffusion;
pub mod eos;
pub mod front;
pub mod hard_disc;
pub mod jamming;
pub mod maxwell;
pub mod mfp;
pub mod reaction;
pub mod reversibility;
pub mod ring;
pub mod sheets;
pub mod shoulder;
pub mod square_well;
pub mod viscosity;

use anyhow::Result;
use clap::Subcommand;

/// The experiments.
#[derive(Debug, Subcommand)]
pub enum Experiment {
    /// A + A -> inert in 2D: the density of A against time, against the mean-field law with
    /// the line-of-centres rate constant early on and Lee's diffusion-limited law late.
    Annihilation(annihilation::AnnihilationArgs),
    /// A gas column in a field: density against height against the barometric law (dilute)
    /// and the local-density approximation with the hard-disc (sphere) equation of state
    /// (dense); the temperature against height.
    Barometric(barometric::BarometricArgs),
    /// Break a racked triangle with multi-disc and with binary collisions; plot both.
    Billiards(billiards::BilliardsArgs),
    /// Brownian motion: the path and mean square displacement of one big disc among small ones.
    Brownian(brownian::BrownianArgs),
    /// A granular gas cooling: T(t) against Haff's law with t0 from Enskog's collision
    /// frequency, until the shear instability of boxes wider than the critical size L_c.
    Cooling(cooling::CoolingArgs),
    /// Maxwell's demon: a door that sorts fast from slow discs; the temperature of each side.
    Demon(demon::DemonArgs),
    /// Two gases mixing after the partition between them is removed.
    Diffusion(diffusion::DiffusionArgs),
    /// The equation of state: Z = PA/(NkT) (PV/(NkT) for spheres) against packing, with
    /// Henderson's formula (Pieprzyk et al.'s for spheres). Writes eos.csv, eos.png and eos.svg
    /// into --out-dir (default: the current folder, where files of those names are replaced).
    Eos(eos::EosArgs),
    /// A reaction front, A + B -> 2A invading B: its speed against Fisher-KPP's 2 sqrt(D k),
    /// with D and k measured by edmd.
    Front(front::FrontArgs),
    /// Hard discs across the liquid-hexatic transition: beta P d^2 against packing from 0.698
    /// to 0.720 at N = 256^2, a chain of checkpointed runs, against Engel et al.'s (2013) EDMD
    /// and Monte Carlo data.
    HardDiscTransition(hard_disc::HardDiscArgs),
    /// The jammed packing fraction against the compression rate (Lubachevsky-Stillinger).
    Jamming(jamming::JammingArgs),
    /// The speed histogram against the 2D Maxwell-Boltzmann (Rayleigh) law.
    Maxwell(maxwell::MaxwellArgs),
    /// Free path and free time histograms; mean free path against density.
    Mfp(mfp::MfpArgs),
    /// Reactive collisions: the rate constant against the line-of-centres law over activation
    /// energies, in 2D and 3D, dilute and dense, and the Prigogine-Xhrouet effect.
    Reaction(reaction::ReactionArgs),
    /// Run forward, reverse the velocities, run back: how far from the start do the discs land?
    Reversibility(reversibility::ReversibilityArgs),
    /// A patch of a planetary ring (the shearing sheet): the velocity dispersion and optical
    /// depth against time from cold and hot starts, on both sides of Goldreich and Tremaine's
    /// critical restitution, and with Bridges' law; a movie of the patch.
    Ring(ring::RingArgs),
    /// One-dimensional self-gravitating sheets from a water bag: the virial theorem on time
    /// averages, the slow relaxation as a phase-plane movie, and the density in a heat bath
    /// against the isothermal sheet (Spitzer's sech^2).
    Sheets(sheets::SheetsArgs),
    /// The square-shoulder model (Young and Alder): the isostructural solid-solid transition
    /// as a loop or plateau of the pressure against density, and the exact second virial
    /// coefficient at low density.
    Shoulder(shoulder::ShoulderArgs),
    /// The square-well fluid in a heat bath: Z and the energy per particle against density,
    /// with the exact low-density limits and (3D) Espindola-Heredia et al.'s equation of state.
    SquareWell(square_well::SquareWellArgs),
    /// The shear viscosity of hard spheres (discs) by the Einstein-Helfand route, against
    /// Enskog's theory, at several packing fractions.
    Viscosity(viscosity::ViscosityArgs),
}

/// Runs an experiment.
pub fn run(which: &Experiment) -> Result<()> {
    common::install_ctrlc();
    // `jamming` stops at the packer's next velocity rescaling, which can be far off.
    if !matches!(which, Experiment::Jamming(_)) {
        common::stop_promptly();
    }
    let result = match which {
        Experiment::Annihilation(a) => annihilation::run(a),
        Experiment::Barometric(a) => barometric::run(a),
        Experiment::Billiards(a) => billiards::run(a),
        Experiment::Brownian(a) => brownian::run(a),
        Experiment::Cooling(a) => cooling::run(a),
        Experiment::Demon(a) => demon::run(a),
        Experiment::Diffusion(a) => diffusion::run(a),
        Experiment::Eos(a) => eos::run(a),
        Experiment::Front(a) => front::run(a),
        Experiment::HardDiscTransition(a) => hard_disc::run(a),
        Experiment::Jamming(a) => jamming::run(a),
        Experiment::Maxwell(a) => maxwell::run(a),
        Experiment::Mfp(a) => mfp::run(a),
        Experiment::Reaction(a) => reaction::run(a),
        Experiment::Reversibility(a) => reversibility::run(a),
        Experiment::Ring(a) => ring::run(a),
        Experiment::Sheets(a) => sheets::run(a),
        Experiment::Shoulder(a) => shoulder::run(a),
        Experiment::SquareWell(a) => square_well::run(a),
        Experiment::Viscosity(a) => viscosity::run(a),
    };
    // The experiments end a stopped run with `Interrupted` themselves; `jamming` writes its
    // results so far and returns, so its exit status is set here.
    let result = match (result, which) {
        (Ok(()), Experiment::Jamming(a)) if common::stop_requested() => edmd::interrupted(format!(
            "interrupted: the results so far are written in {}",
            a.common.out_dir.display()
        )),
        (r, _) => r,
    };
    if result.is_err() {
        // A failed experiment leaves no empty folder behind (only those this run created).
        edmd::stop::remove_created_dirs();
    }
    result
}
