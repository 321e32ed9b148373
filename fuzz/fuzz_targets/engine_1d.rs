//! The engine in 1D: random valid systems of hard rods (lengths, masses, positions, walls or a
//! periodic line, exact contacts, multi-disc collisions, the swap rule, a field), a third of
//! the elastic ones between walls under self-gravity (sheets), run for up to 2000 events with
//! the invariants checked (see `edmd_fuzz::engine`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| edmd_fuzz::engine::<1>(data, 24));
