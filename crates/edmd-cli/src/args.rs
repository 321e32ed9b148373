//! Command-line arguments as plain values (the first of the two stages; commands validate).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

pub use edmd::options::*;

/// Exact event-driven molecular dynamics of hard discs.
#[derive(Debug, Parser)]
#[command(
    name = "edmd",
    version,
    about = "Exact event-driven molecular dynamics of hard discs"
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate a data file (Princeton or course format) up to a time and write the final state.
    Run(RunArgs),
    /// Time the event loop on a melted lattice fluid; prints one JSON line.
    Bench(BenchArgs),
    /// A long run of a dense periodic fluid (10^9 collisions by default), checked every so
    /// often for overlaps, discs outside the box, energy and momentum drift, a clock that stops,
    /// and memory growth.
    Soak(crate::commands::soak::SoakArgs),
    /// Render frames without a screen: an animated GIF, an MP4 (with ffmpeg) or PNG files.
    Render(crate::commands::render::RenderArgs),
    /// Open the viewer window (the separate edmd-view program).
    #[command(disable_help_flag = true)]
    View {
        /// Arguments for edmd-view (see edmd-view --help).
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// Generate a configuration (the Princeton data sets, fluids, mixtures).
    Gen(edmd::gen::GenCommand),
    /// Compress to a jammed packing (Lubachevsky-Stillinger: the particles grow while they
    /// move), or to a packing fraction below jamming.
    Pack(edmd::pack::PackArgs),
    /// Run one of the experiments (writes CSV files and plots).
    #[command(subcommand)]
    Experiment(crate::commands::experiment::Experiment),
}

/// `edmd run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Input file (`-` for standard input): a data file, or a checkpoint to continue.
    pub file: String,
    /// End time of the simulation (absolute: a run continued from a checkpoint at time T0 runs
    /// from T0 to this time). Any finite time is taken, however many events it needs; Ctrl-C
    /// (SIGTERM, SIGHUP) stops the run within a second, with exit status 130.
    #[arg(long, value_name = "T", value_parser = parse_time, allow_negative_numbers = true)]
    pub until: f64,
    /// Write the final state here, in the input's format (`-` for standard output).
    #[arg(long, short, value_name = "OUT")]
    pub output: Option<String>,
    /// Input format.
    #[arg(long, value_enum, default_value_t = FormatArg::Auto)]
    pub format: FormatArg,
    /// Column order of radius and mass in the Princeton format.
    /// Princeton files only (default: radius-mass); refused for course files, which have no such
    /// columns.
    #[arg(long, value_enum)]
    pub columns: Option<ColumnsArg>,
    /// The frame of a GSD input file to start from, counted from 0 (negative from the end;
    /// default the last). GSD files only.
    #[arg(long, value_name = "K", allow_negative_numbers = true)]
    pub frame: Option<i64>,
    /// Collision rule (default: swap for course files, as the course's `particles` does;
    /// elastic for every other file).
    #[arg(long, value_enum)]
    pub rule: Option<RuleArg>,
    /// Run a file with overlapping discs or discs outside the box: discs outside are moved in to
    /// touch the wall, overlapping pairs that approach collide at once, separating ones pass
    /// freely until apart.
    #[arg(long)]
    pub allow_overlaps: bool,
    /// Multi-disc collisions: discs touching a colliding pair (gap below 1e-3 of the contact
    /// distance) take part at the same instant, as stiff elastic (Hertz) contacts. Needs the
    /// elastic rule. For billiard breaks and Newton's cradles.
    #[arg(long)]
    pub multi: bool,
    /// Write an exact checkpoint of the whole engine state here at the end (and every
    /// --checkpoint-every on the way), replaced atomically each time; `edmd run CHECKPOINT
    /// --until T2` continues the run bit for bit.
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Simulated time between checkpoints.
    #[arg(long, value_name = "DT", value_parser = parse_positive, requires = "checkpoint", allow_negative_numbers = true)]
    pub checkpoint_every: Option<f64>,
    /// Write frames to this extended XYZ file (OVITO, ASE). At most 10^6 frames and about
    /// 100 GB (estimated before the run from the first frame's size; more is refused).
    #[arg(long, value_name = "FILE.xyz", requires = "every")]
    pub trajectory: Option<PathBuf>,
    /// Interval between trajectory frames.
    #[arg(long, value_name = "DT", value_parser = parse_positive, requires = "trajectory", allow_negative_numbers = true)]
    pub every: Option<f64>,
    /// Attach measurements (comma-separated): temperature, pressure, collisions, speeds, msd,
    /// species, energy, rdf, kinetics (species counts over time and the reaction rules' rate
    /// constants), viscosity (the shear viscosity, periodic boxes only), conductivity (the thermal
    /// conductivity), shear-stress (the shear stress and viscosity of a sheared run). Their
    /// summaries go into the run's summary, and their time series to CSV
    /// files in --out-dir when it is given (none are written without it).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub measure: Vec<edmd::measure::Measure>,
    /// Interval between measurement samples (default: a hundredth of the run's length). With
    /// --measure, or on a checkpoint that carries measurements.
    #[arg(long, value_name = "DT", value_parser = parse_positive, allow_negative_numbers = true)]
    pub sample_every: Option<f64>,
    /// Folder for the measurement CSV files (created if missing; files of the same names there
    /// are replaced). Without it no CSV file is written and the results are only in the summary.
    /// The old spelling `--measure-dir` still works.
    #[arg(long = "out-dir", alias = "measure-dir", value_name = "DIR")]
    pub measure_dir: Option<PathBuf>,
    /// Print the summary as one JSON object on standard output.
    #[arg(long)]
    pub json: bool,
    /// Check invariants at the end (no overlap, every disc in the box) and fail if broken.
    #[arg(long)]
    pub check: bool,
    /// A heat bath (default none: energy is conserved). `andersen` redraws each particle's
    /// velocity from the Maxwell-Boltzmann distribution at --kT, at the times of a Poisson
    /// process of --rate per particle; seeded (--seed), and carried by checkpoints.
    #[arg(long, value_enum, requires_all = ["kt", "rate"])]
    pub thermostat: Option<ThermostatArg>,
    /// The bath's temperature (energy units), with --thermostat.
    #[arg(long = "kT", alias = "kt", value_name = "T", value_parser = parse_positive, requires = "thermostat", allow_negative_numbers = true)]
    pub kt: Option<f64>,
    /// Redraws per particle per unit time, with --thermostat.
    #[arg(long, value_name = "NU", value_parser = parse_positive, requires = "thermostat", allow_negative_numbers = true)]
    pub rate: Option<f64>,
    /// Seed of the random draws (default 1): the thermostat's redraws (--thermostat) and the
    /// draws of reaction rules whose probability is below 1 (a file's '# edmd reaction'
    /// lines). Carried by checkpoints.
    #[arg(long)]
    pub seed: Option<u64>,
}

impl RunArgs {
    /// The thermostat the options ask for.
    pub fn andersen(&self) -> Option<edmd_core::Andersen> {
        match (self.thermostat, self.kt, self.rate) {
            (Some(ThermostatArg::Andersen), Some(kt), Some(rate)) => Some(edmd_core::Andersen {
                kt,
                rate,
                seed: self.seed.unwrap_or(edmd::input::DEFAULT_SEED),
            }),
            _ => None,
        }
    }
}

/// `edmd bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Dimension: 2 (discs), 3 (spheres) or 1 (rods on a line).
    #[arg(long, default_value_t = 2, value_parser = parse_dim_with_rods)]
    pub dim: usize,
    /// Number of discs (spheres in 3D).
    #[arg(long, value_parser = parse_count, allow_negative_numbers = true)]
    pub n: usize,
    /// Packing fraction (area fraction; volume fraction in 3D) of the fluid.
    #[arg(long, value_parser = parse_positive, allow_negative_numbers = true)]
    pub packing: f64,
    /// Boundary conditions.
    #[arg(long, value_enum, default_value_t = BoundaryArg::Periodic)]
    pub boundary: BoundaryArg,
    /// Disc-disc collisions per disc run to melt the lattice before timing.
    #[arg(long, default_value_t = 20, allow_negative_numbers = true)]
    pub melt: u64,
    /// Disc-disc collisions per disc to time.
    #[arg(long, default_value_t = 50, allow_negative_numbers = true)]
    pub collisions: u64,
    /// Random seed for the velocities.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// Time the portable event loop even where the processor runs the x86-64-v3 one.
    #[arg(long)]
    pub portable: bool,
    /// A square-well fluid: a well of depth 1 out to LAMBDA diameters (energy conserved).
    #[arg(long, value_name = "LAMBDA", allow_negative_numbers = true)]
    pub well: Option<f64>,
    /// The fluid's temperature (its velocities; the lattice starts at kT 1).
    #[arg(long, value_parser = parse_positive, default_value_t = 1.0, allow_negative_numbers = true)]
    pub kt: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_requires_until_and_pairs_trajectory_with_every() {
        assert!(Cli::try_parse_from(["edmd", "run", "f.txt"]).is_err());
        assert!(Cli::try_parse_from([
            "edmd",
            "run",
            "f.txt",
            "--until",
            "1",
            "--trajectory",
            "t.xyz"
        ])
        .is_err());
        assert!(Cli::try_parse_from([
            "edmd",
            "run",
            "f.txt",
            "--until",
            "1",
            "--trajectory",
            "t.xyz",
            "--every",
            "0.1"
        ])
        .is_ok());
        assert!(
            Cli::try_parse_from(["edmd", "run", "f.txt", "--until", "1", "--rule", "bogus"])
                .is_err()
        );
    }
}
