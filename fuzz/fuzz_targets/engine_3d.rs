//! The engine in 3D: random valid systems of spheres (no barriers), run for up to 2000 events
//! with the invariants checked (see `edmd_fuzz::engine`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| edmd_fuzz::engine::<3>(data, 16));
