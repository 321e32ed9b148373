//! End-to-end tests of the `edmd` and `particles` programs, compiled as one binary.

mod support;

mod bad_input;
mod barometric;
mod bench;
mod checkpoint;
mod chemistry;
mod clock;
mod defects;
mod experiments;
mod front;
mod granular;
mod gsd;
mod hard_disc_transition;
mod library;
mod limits;
mod pack;
mod particles;
mod render;
mod ring;
mod ring_files;
mod rods;
mod run;
mod shear;
mod sheets;
mod sheets_files;
mod signals;
mod soak;
mod three_d;
mod trajectory;
mod viscosity;
