//! Regressions found by the fuzz targets (`fuzz/`, RELIABILITY.md), one test per defect, named
//! after what broke.

use edmd_core::{Barrier, Error, Options, SimBox, Simulation};

/// The checkpoint frame (magic, version, dimension, payload length) before the payload.
const HEADER: usize = 24;

/// `bytes` with `payload[at]` set to `value` and the CRC-32 recomputed, so that only the
/// payload's own checks can refuse it.
fn patched(bytes: &[u8], at: usize, value: u8) -> Vec<u8> {
    let mut out = bytes.to_vec();
    out[HEADER + at] = value;
    let end = out.len() - 4;
    let crc = crc32fast::hash(&out[..end]);
    out[end..].copy_from_slice(&crc.to_le_bytes());
    out
}

/// Found by fuzzing (`read_checkpoint`): a barrier's door and demon flags were read as "1 or
/// anything else", so a checkpoint with flag byte 4 was accepted as "no demon" and wrote back
/// as 0: an accepted checkpoint that did not round-trip. Flags other than 0 or 1 are now
/// refused.
#[test]
fn checkpoint_barrier_flags_other_than_0_or_1_are_refused() {
    let door = Barrier {
        door: Some((0.3, 0.7)),
        ..Barrier::solid(0, 1.0)
    };
    let sim =
        Simulation::with_barriers(&[], SimBox::walls([2.0, 1.0]), &[door], Options::default())
            .unwrap();
    let good = sim.to_checkpoint(b"");
    // Payload: box (2 x 9), rule, multi flag, two clocks, five counters, adjusted, mean m v^2,
    // the barrier count; then the barrier: axis, position, door flag, door, demon flag.
    let door_flag = 18 + 1 + 1 + 16 + 40 + 8 + 8 + 8 + 1 + 8;
    let demon_flag = door_flag + 1 + 16;
    assert_eq!(good[HEADER + door_flag], 1);
    assert_eq!(good[HEADER + demon_flag], 0);
    assert!(Simulation::<2>::from_checkpoint(&patched(&good, demon_flag, 0)).is_ok());
    for (at, what) in [(door_flag, "door"), (demon_flag, "demon")] {
        for value in [2, 4, 255] {
            match Simulation::<2>::from_checkpoint(&patched(&good, at, value)) {
                Err(Error::Checkpoint(m)) => assert!(m.contains(what), "{m}"),
                other => panic!("{what} flag {value}: {other:?}"),
            }
        }
    }
}
