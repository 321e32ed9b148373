//! Measurements: observers and samplers that any run can attach. The engine never knows about
//! them, and they do no I/O: callers format the summaries and time series.
//!
//! Each measurement is a struct with `sample(&mut self, sim)` for the snapshots (or block ends)
//! the caller chooses, an [`Observer`](crate::Observer) implementation where it needs every
//! event, and a `summary` returning a plain struct. Time series are `Vec<(t, value)>`.
//!
//! | module | measures | needs events |
//! |---|---|---|
//! | [`temperature`] | kinetic temperature `kT = sum m v^2 / (2N)` | no |
//! | [`pressure`] | wall pressure, collision-virial pressure, `Z = PA / (N kT)` with block errors | yes |
//! | [`collisions`] | collision frequency, free paths and free times with histograms | yes |
//! | [`speeds`] | speed histogram, RMS speed, Kolmogorov-Smirnov test against the 2D Maxwell-Boltzmann law | no |
//! | [`diffusion`] | mean square displacement and the diffusion coefficient | no |
//! | [`species`] | composition of the two halves of the box over time | no |
//! | [`energy`] | kinetic, potential and total energy; heat capacity in a heat bath | no |
//! | [`kinetics`] | species counts over time and each reaction rule's rate constant with block errors | yes |
//! | [`rdf`] | the radial distribution function `g(r)` | no |
//! | [`shear_stress`] | the shear stress of a sheared system and its viscosity `-P_xy / gamma`, exact time integrals, with block errors | yes |
//! | [`viscosity`] | shear viscosity by the Einstein-Helfand route, with block errors; Enskog's viscosity | yes |
//! | [`conductivity`] | thermal conductivity by the Einstein-Helfand route, with block errors | yes |
//!
//! ```
//! use edmd_core::measure::{Collisions, Pressure};
//! use edmd_core::setup::lattice_fluid;
//! use edmd_core::{Boundary, Options, Simulation};
//!
//! let (discs, bx) = lattice_fluid(200, 0.3, Boundary::Periodic, 1).unwrap();
//! let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
//! sim.run_until(5.0, &mut ()); // melt the lattice
//! let mut pressure = Pressure::new(&sim);
//! let mut collisions = Collisions::new(&sim, 50, 5.0, 5.0);
//! for k in 1..=4 {
//!     sim.run_until(5.0 + k as f64, &mut (&mut pressure, &mut collisions));
//!     pressure.sample(&sim);
//!     collisions.sample(&sim);
//! }
//! let z = pressure.summary().z;
//! assert!(z.value > 1.5 && z.blocks == 4);
//! assert!(collisions.summary().frequency.value > 0.0);
//! ```

pub mod collisions;
pub mod column;
pub mod conductivity;
pub mod diffusion;
pub mod energy;
pub mod kinetics;
pub mod pressure;
pub mod rdf;
pub mod shear_stress;
pub mod species;
pub mod speeds;
pub mod square_well_eos;
pub mod stats;
pub mod temperature;
pub mod theory;
pub mod viscosity;

pub use collisions::{CollisionBlock, CollisionSummary, Collisions, DiscFlights};
pub use conductivity::{Conductivity, ConductivityBlock, ConductivitySummary};
pub use diffusion::{Diffusion, DiffusionFit};
pub use energy::{Energy, EnergySummary};
pub use kinetics::{Kinetics, RuleRate};
pub use pressure::{Pressure, PressureBlock, PressureSummary};
pub use rdf::Rdf;
pub use shear_stress::{ShearStress, ShearStressBlock, ShearStressSummary};
pub use species::{SpeciesHalves, SpeciesSnapshot, SpeciesSummary};
pub use speeds::{maxwell_cdf, maxwell_pdf, rayleigh_cdf, rayleigh_pdf, SpeedSummary, Speeds};
pub use stats::{
    block_error, kolmogorov_q, ks_test, linear_fit, variance, Estimate, Histogram, KsTest,
};
pub use temperature::{kinetic_temperature, Temperature, TemperatureSummary};
pub use viscosity::{Viscosity, ViscosityBlock, ViscositySummary};
