//! Ready-made systems: lattices and fluids for benchmarks, tests and generators.

pub mod compress;
pub mod fluid;
pub mod generators;
pub mod lattice;
pub mod order;
pub mod placement;

pub use fluid::{melting_threshold, packing_of, Fluid, MeltReport, Mixture, Sizes};
pub use generators::{generate, GenKind};
pub use lattice::{lattice_fluid, thermal_velocities};
pub use order::{local_psi6, psi6, Neighbours};
