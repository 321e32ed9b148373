//! Ready-made systems: lattices and fluids for benchmarks, tests and generators.

pub mod compress;
pub mod fluid;
pub mod generators;
pub mod lattice;
pub mod order;
pub mod placement;
pub mod ring;
pub mod sheets;

/// The lowest packing fraction the fluid, mixture and `dense` generators accept: below it,
/// melting or equilibrating by collisions takes hours (each collision costs some hundreds of
/// cell crossings at `1e-3` already), and near 0 it never ends.
pub const MIN_PACKING: f64 = 1e-3;

pub use fluid::{melting_threshold, packing_of, Fluid, MeltReport, Mixture, Sizes};
pub use generators::{generate, GenKind};
pub use lattice::{lattice_fluid, lattice_fluid_in, thermal_velocities};
pub use order::{fcc_order, local_psi6, psi6, Neighbours};
