//! The engine in 2D: random valid systems (radii, masses, positions, walls or periodic axes,
//! barriers with doors and demons, exact contacts, multi-disc collisions, the swap rule), run
//! for up to 2000 events with the invariants checked (see `edmd_fuzz::engine`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| edmd_fuzz::engine::<2>(data, 24));
