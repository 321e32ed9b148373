//! The Princeton reader with edmd's directives, 1D, 2D and 3D: the first byte picks the column order
//! and the entry point (`princeton::parse` or `parse_any`), the rest is the file. Any text gives
//! a system or an error naming a line inside the file, never a panic; a system read is written
//! back and read again unchanged (its reaction rules to the bit, a ring with its offset, the self-gravity), and the engine builds or
//! refuses it without a panic, taking every reaction rule the reader accepted.
#![no_main]

use edmd_fuzz::{check_error, check_loaded};
use edmd_io::princeton::{self, ColumnOrder};
use edmd_io::{AnyLoaded, Format, Interactions, LoadedSystem};
use libfuzzer_sys::fuzz_target;

fn round_trip<const D: usize>(sys: &LoadedSystem<D>, order: ColumnOrder, text: &str) {
    let mut out = Vec::new();
    let interactions = Interactions {
        potential: &sys.potential,
        reactions: &sys.reactions,
        restitution: sys.restitution.as_ref(),
        gravity: sys.gravity,
        shear: sys.shear,
        self_gravity: sys.self_gravity,
    };
    princeton::write_full_ring(
        &mut out,
        &sys.discs,
        &sys.sim_box,
        &sys.barriers,
        interactions,
        sys.ring,
        order,
        sys.time,
    )
    .unwrap();
    let written = std::str::from_utf8(&out).unwrap();
    let again = princeton::parse_in::<D>(written, order).expect("what was written reads back");
    assert_eq!(again.discs, sys.discs);
    assert_eq!(again.sim_box, sys.sim_box);
    assert_eq!(again.barriers, sys.barriers);
    assert_eq!(again.time, sys.time);
    assert_eq!(again.potential, sys.potential);
    assert_eq!(again.reactions, sys.reactions);
    assert_eq!(again.restitution, sys.restitution);
    assert_eq!(again.gravity, sys.gravity);
    assert_eq!(again.shear, sys.shear);
    assert_eq!(again.ring, sys.ring);
    assert_eq!(again.self_gravity, sys.self_gravity);
    for (a, b) in again.reactions.iter().zip(&sys.reactions) {
        let bits =
            |r: &edmd_core::Reaction| [r.activation, r.probability, r.heat].map(f64::to_bits);
        assert_eq!(bits(a), bits(b), "a rule's numbers are not written exactly");
    }
    check_loaded(sys, text);
}

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    let Ok(text) = std::str::from_utf8(rest) else {
        return;
    };
    let order = if mode & 1 == 0 {
        ColumnOrder::RadiusMass
    } else {
        ColumnOrder::MassRadius
    };
    let format = Format::Princeton(order);
    let _ = edmd_io::detect(text);
    if mode & 2 == 0 {
        match princeton::parse(text, order) {
            Ok(sys) => round_trip(&sys, order, text),
            Err(e) => check_error(text, e.line, &e.message),
        }
        return;
    }
    let dim = edmd_io::dim_of(text, format);
    match edmd_io::parse_any(text, format) {
        Ok(any) => {
            assert_eq!(dim, Ok(any.dim()));
            match any {
                AnyLoaded::Two(sys) => round_trip(&sys, order, text),
                AnyLoaded::Three(sys) => round_trip(&sys, order, text),
                AnyLoaded::One(sys) => round_trip(&sys, order, text),
            }
        }
        Err(e) => check_error(text, e.line, &e.message),
    }
});
