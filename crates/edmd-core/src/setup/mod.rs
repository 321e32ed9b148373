//! Ready-made systems: lattices and fluids for benchmarks, tests and generators.

pub mod lattice;

pub use lattice::{lattice_fluid, thermal_velocities};
