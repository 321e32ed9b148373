//! Integration tests of the engine, compiled as one binary.

mod support;

mod checkpoint;
mod clock;
mod exact_cases;
mod fuzz_regressions;
mod generators;
mod gravity;
mod inelastic;
mod invariants;
mod memory;
mod naive_reference;
mod pack;
mod pack_checkpoint;
mod physics;
mod reactions;
mod ring;
mod rods;
mod shear;
mod sheets;
mod stall;
mod stepped;
mod thermostat;
mod three_d;
