//! Exact checkpoints: a run stopped at T1, saved, read back and continued to T2 is bit for bit
//! the run that went straight to T2 (the whole saved state at T2 is the same bytes), for walls
//! and periodic boxes, barriers with a demon, multi-disc collisions and spheres; and no damaged
//! checkpoint is ever read as a state.

use edmd_core::setup::generators::{generate, GenKind};
use edmd_core::setup::lattice::lattice_fluid_in;
use edmd_core::{
    checkpoint_dim, Barrier, Boundary, Demon, Disc, Error, MultiContact, Options, SimBox,
    Simulation, Vector, CHECKPOINT_VERSION,
};

use crate::support::{random_discs, reframed};

/// Runs `sim` to `t1`, checkpoints, reads back, runs both the original and the copy to `t2`
/// (the original never stopped: `run_until(t1)` changes nothing but the observation time), and
/// compares the final states byte for byte, the event counts and the extra bytes.
fn continues_exactly<const D: usize>(mut sim: Simulation<D>, t1: f64, t2: f64, what: &str) {
    let mut straight = sim.clone();
    straight.run_until(t2, &mut ());
    sim.run_until(t1, &mut ());
    let bytes = sim.to_checkpoint(b"extra");
    assert_eq!(checkpoint_dim(&bytes).unwrap(), D);
    let (mut resumed, extra) = Simulation::<D>::from_checkpoint(&bytes).unwrap();
    assert_eq!(extra, b"extra");
    assert_eq!(
        resumed.to_checkpoint(b""),
        sim.to_checkpoint(b""),
        "{what}: read back differs"
    );
    resumed.run_until(t2, &mut ());
    sim.run_until(t2, &mut ());
    assert!(
        straight.stats().disc_disc > 100,
        "{what}: too few collisions to tell"
    );
    assert_eq!(resumed.stats(), straight.stats(), "{what}: event counts");
    assert_eq!(
        resumed.to_checkpoint(b""),
        straight.to_checkpoint(b""),
        "{what}: the continued run differs from the uninterrupted one"
    );
    assert_eq!(
        sim.to_checkpoint(b""),
        straight.to_checkpoint(b""),
        "{what}: stopping changed the run"
    );
}

#[test]
fn restarts_are_exact_with_walls_and_periodic_boxes() {
    for (boundary, seed) in [(Boundary::Walls, 1), (Boundary::Periodic, 2)] {
        let (discs, bx) = lattice_fluid_in::<2>(400, 0.5, boundary, seed).unwrap();
        let sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        continues_exactly(sim, 3.3, 7.1, &format!("{boundary:?}"));
    }
    // Discs of different sizes and masses.
    let discs = random_discs(200, 30.0, 0.2, 0.8, true, 3);
    let sim = Simulation::new(&discs, SimBox::walls([30.0, 30.0]), Options::default()).unwrap();
    continues_exactly(sim, 11.0, 25.0, "mixed sizes");
}

#[test]
fn restarts_are_exact_with_barriers_a_demon_and_multi_disc_collisions() {
    let discs = random_discs(150, 20.0, 0.3, 0.3, true, 4);
    let discs: Vec<_> = discs
        .into_iter()
        .filter(|d| (d.pos[0] - 10.0).abs() > 0.4)
        .collect();
    let door = Barrier {
        door: Some((8.0, 12.0)),
        demon: Some(Demon {
            fast: 1.0,
            slow: 1.0,
        }),
        ..Barrier::solid(0, 10.0)
    };
    let sim = Simulation::with_barriers(
        &discs,
        SimBox::walls([20.0, 20.0]),
        &[door],
        Options::default(),
    )
    .unwrap();
    continues_exactly(sim, 5.0, 40.0, "demon");
    let system = generate(&GenKind::from_name("dense").unwrap(), 5).unwrap();
    let options = Options {
        multi: Some(MultiContact::default()),
        ..Options::default()
    };
    let sim = Simulation::from_system(&system, options).unwrap();
    continues_exactly(sim, 30.0, 200.0, "multi");
}

#[test]
fn restarts_are_exact_for_spheres() {
    let (discs, bx) = lattice_fluid_in::<3>(500, 0.4, Boundary::Periodic, 6).unwrap();
    let sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    continues_exactly(sim, 1.7, 3.9, "spheres");
    assert!(matches!(
        Simulation::<2>::from_checkpoint(&Simulation::new(&discs, bx, Options::default()).unwrap().to_checkpoint(b"")),
        Err(Error::Checkpoint(m)) if m.contains("3D checkpoint")
    ));
}

// Version 1 lacked the stall watcher's place in its chunk (16 bytes after the
// count of events in a row): it is still read, as if at a chunk's start. (Version 3 added the
// spheres' second events, a section 2D checkpoints do not have, and version 4 the stepped
// potential and the thermostat, a byte each when there are none; version 5 changed only
// the stepped potential's section; version 6 added the reaction rules, a byte when there are
// none; version 7 the restitution and the field, a byte each; version 8 the shear, a byte;
// version 9 the self-gravity, a byte; version 10 the ring, a byte.)
#[test]
fn version_1_checkpoints_are_still_read() {
    let discs = random_discs(6, 10.0, 0.3, 0.5, true, 7);
    let mut sim = Simulation::new(&discs, SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
    sim.run_until(2.0, &mut ());
    let v2 = sim.to_checkpoint(b"options");
    assert_eq!(CHECKPOINT_VERSION, 10);
    // Payload end: ..., the count (8), the chunk's time (8) and events (8), no stall (1), no
    // stepped potential (1) and no thermostat (1, both from version 4), no reaction rules (1,
    // from version 6), no restitution and no field (1 each, from version 7), no shear (1,
    // from version 8), no self-gravity (1, from version 9), no ring (1, from version 10), the
    // caller's bytes (a length, 8, and 7 bytes); then the CRC-32 (4).
    let tail = 1 + 1 + 1 + 1 + 1 + 1 + 1 + 1 + 1 + 8 + 7 + 4;
    let cut = v2.len() - tail - 16;
    let mut v1 = [
        &v2[..cut],
        &v2[cut + 16..cut + 17],
        &v2[cut + 25..v2.len() - 4],
    ]
    .concat();
    v1[8..12].copy_from_slice(&1u32.to_le_bytes());
    let payload = (v1.len() - 24) as u64;
    v1[16..24].copy_from_slice(&payload.to_le_bytes());
    let crc = crc32fast::hash(&v1);
    v1.extend_from_slice(&crc.to_le_bytes());
    let (mut old, extra) = Simulation::<2>::from_checkpoint(&v1).unwrap();
    assert_eq!(extra, b"options");
    let (mut new, _) = Simulation::<2>::from_checkpoint(&v2).unwrap();
    old.run_until(5.0, &mut ());
    new.run_until(5.0, &mut ());
    assert_eq!(old.discs(), new.discs());
}

#[test]
fn damaged_checkpoints_are_refused_never_read() {
    // Every truncation, every single flipped bit in a small checkpoint, a newer version and
    // foreign bytes: each an Error::Checkpoint, no panic.
    let discs = random_discs(6, 10.0, 0.3, 0.5, true, 7);
    let mut sim = Simulation::new(&discs, SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
    sim.run_until(2.0, &mut ());
    let good = sim.to_checkpoint(b"options");
    assert!(Simulation::<2>::from_checkpoint(&good).is_ok());
    for len in 0..good.len() {
        assert!(
            matches!(
                Simulation::<2>::from_checkpoint(&good[..len]),
                Err(Error::Checkpoint(_))
            ),
            "{len}"
        );
    }
    for byte in 0..good.len() {
        for bit in 0..8 {
            let mut bad = good.clone();
            bad[byte] ^= 1 << bit;
            assert!(
                matches!(
                    Simulation::<2>::from_checkpoint(&bad),
                    Err(Error::Checkpoint(_))
                ),
                "flipping bit {bit} of byte {byte} was not noticed"
            );
        }
    }
    let mut newer = good.clone();
    newer[8..12].copy_from_slice(&(CHECKPOINT_VERSION + 1).to_le_bytes());
    match Simulation::<2>::from_checkpoint(&newer) {
        Err(Error::Checkpoint(m)) => assert!(m.contains("newer"), "{m}"),
        other => panic!("{other:?}"),
    }
    // A version no edmd will write for a long while is a damaged header (random bytes after the
    // magic number were once reported as "format version 1535297744 is newer").
    newer[8..12].copy_from_slice(&1_535_297_744u32.to_le_bytes());
    match Simulation::<2>::from_checkpoint(&newer) {
        Err(Error::Checkpoint(m)) => assert!(m.contains("corrupted"), "{m}"),
        other => panic!("{other:?}"),
    }
    for foreign in [&b"2\n0.5 0.5 0 0 0.1 1 0 0 0\n"[..], b"", b"EDMDCKPT"] {
        assert!(matches!(
            Simulation::<2>::from_checkpoint(foreign),
            Err(Error::Checkpoint(_))
        ));
    }
}

/// Asserts that `bytes` is refused as a `D`-dimensional checkpoint with a message containing
/// `what`.
fn refused<const D: usize>(bytes: &[u8], what: &str) {
    match Simulation::<D>::from_checkpoint(bytes) {
        Err(Error::Checkpoint(m)) => assert!(m.contains(what), "{m}"),
        other => panic!("{what}: {:?}", other.map(|_| ())),
    }
}

/// Two discs (or spheres) of radius 0.5 at x = 2 and 8, mid-box (y, z = 5) in a box of side
/// 10, closing head on at unit speeds: they meet at t = 2.5 ((8 - 2 - 1) / 2).
fn head_on<const D: usize>() -> [Disc<D>; 2] {
    let at = |x: f64| Vector(std::array::from_fn(|a| if a == 0 { x } else { 5.0 }));
    let along = |v: f64| Vector(std::array::from_fn(|a| if a == 0 { v } else { 0.0 }));
    [
        Disc::new(at(2.0), along(1.0), 0.5),
        Disc::new(at(8.0), along(-1.0), 0.5),
    ]
}

// Format 3 carries each sphere's second-earliest event, on which a stale
// event falls back without a scan. Two spheres in a walled box of one cell per axis closing
// head on: each has the collision at t = 2.5 ((8 - 2 - 1) / 2) first and its wall contact at
// t = 7.5 (x = 9.5 and x = 0.5) second. The second events are the payload's last section
// before the caller's bytes (here a length of 0, 8 bytes): per sphere its time (8 bytes) and
// event (code 2, a wall, then the axis and the side), 11 bytes each.
#[test]
fn second_events_are_carried_checked_and_optional_in_older_checkpoints() {
    let spheres = head_on::<3>();
    let sim = Simulation::new(&spheres, SimBox::walls([10.0; 3]), Options::default()).unwrap();
    assert_eq!(sim.grid_dims(), [1, 1, 1]);
    let good = sim.to_checkpoint(b"");
    // Before the caller's bytes (8) and the CRC-32 (4): no stepped potential, no thermostat (a
    // byte each, from format 4), no reaction rules (a byte, from format 6), no restitution
    // and no field (a byte each, from format 7), no shear (a byte, from format 8), no
    // self-gravity (a byte, from format 9), no ring (a byte, from format 10).
    let end = good.len() - 4 - 8 - 8;
    let at = end - 22;
    let second = |high: u8| [&7.5f64.to_le_bytes()[..], &[2, 0, high]].concat();
    assert_eq!(&good[at..end], [second(1), second(0)].concat());
    // Without its checksum, at `version`, framed again.
    let at_version = |mut bytes: Vec<u8>, version: u32| {
        bytes.truncate(bytes.len() - 4);
        bytes[8..12].copy_from_slice(&version.to_le_bytes());
        reframed(bytes)
    };
    // A wall contact that is not the one the motion gives, and one before the first event.
    for (t, what) in [
        (7.25, "not the one its motion gives"),
        (2.0, "with its first at"),
    ] {
        let mut bad = good.clone();
        bad[at..at + 8].copy_from_slice(&f64::to_le_bytes(t));
        refused::<3>(&at_version(bad, CHECKPOINT_VERSION), what);
    }
    // A collision of sphere 0 with itself as its second event.
    let mut bad = good[..at].to_vec();
    bad.extend_from_slice(&7.5f64.to_le_bytes());
    bad.extend_from_slice(&[1, 0, 0, 0, 0, 0, 0, 0, 0]);
    bad.extend_from_slice(&good[at + 11..]);
    refused::<3>(
        &at_version(bad, CHECKPOINT_VERSION),
        "a collision with itself",
    );
    // Format 2 had no second events: read, it runs on as the same physics.
    let v2 = at_version([&good[..at], &good[end + 8..]].concat(), 2);
    let (mut old, _) = Simulation::<3>::from_checkpoint(&v2).unwrap();
    let (mut new, _) = Simulation::<3>::from_checkpoint(&good).unwrap();
    old.run_until(20.0, &mut ());
    new.run_until(20.0, &mut ());
    assert_eq!(old.discs(), new.discs());
    assert_eq!(
        old.stats().disc_disc,
        3,
        "at t = 2.5, 10.5 and 18.5, each sphere meeting its wall between"
    );
    assert_eq!(old.stats().disc_disc, new.stats().disc_disc);
    assert_eq!(old.stats().wall, new.stats().wall);
}

/// A pair's pending collisions cannot be recomputed to the bit from a checkpoint (a partner's
/// record may have moved on since), so each is read as it is; but a pair whose events would let
/// it pass through a contact is refused: one of the two must look at the other again (its
/// event, or in 3D the second event a stale one falls back on) before they would overlap
/// beyond what the overlap check allows. Two discs meeting head on at t = 2.5 (x = 4.5 and
/// 5.5; a 2 by 2 grid, so neither crosses into the other's cell first).
#[test]
fn pending_events_that_let_a_pair_pass_through_a_contact_are_refused() {
    let discs = head_on::<2>();
    let sim = Simulation::new(&discs, SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
    assert_eq!(sim.grid_dims(), [2, 2]);
    let good = sim.to_checkpoint(b"");
    // Each disc's record: after the 100 bytes before the discs and their count, its position,
    // velocity, clock, radius and counter (52 bytes), its event (code 1, partner, counter seen)
    // and the event's time; 92 bytes in all.
    let event = |k: usize| 24 + 108 + 92 * k + 52;
    for (k, partner) in [(0, 1), (1, 0)] {
        let at = event(k);
        assert_eq!(&good[at..at + 9], &[1, partner, 0, 0, 0, 0, 0, 0, 0]);
        assert_eq!(good[at + 9..at + 17], 2.5f64.to_le_bytes());
    }
    let with_times = |t: f64| {
        let mut bytes = good[..good.len() - 4].to_vec();
        for k in 0..2 {
            bytes[event(k) + 9..event(k) + 17].copy_from_slice(&t.to_le_bytes());
        }
        reframed(bytes)
    };
    // Each an event with the right partner, but both at t = 2.9: by then the discs would
    // overlap by 0.8 of their contact distance.
    refused::<2>(
        &with_times(2.9),
        "discs 0 and 1 meet at t = 2.5, but neither has an event that looks at the other before t = 2.9",
    );
    // A hair late (2e-12 of the contact distance by then) is within the overlap check's
    // tolerance (1e-9), as rounding is, and is read.
    assert!(Simulation::<2>::from_checkpoint(&with_times(2.5 + 1e-12)).is_ok());
    assert!(Simulation::<2>::from_checkpoint(&with_times(2.5)).is_ok());
}

/// The same for spheres, through their second events: a stale event falls back on the second
/// without looking around, so a pair whose two events are both stale (their partners' counters
/// moved on) and whose second events are later than the contact would pass through it. Two
/// spheres meeting at t = 2.5, each with its wall at t = 7.5 as its second event (the test
/// above).
#[test]
fn stale_events_whose_second_events_let_a_pair_of_spheres_pass_through_are_refused() {
    let spheres = head_on::<3>();
    let sim = Simulation::new(&spheres, SimBox::walls([10.0; 3]), Options::default()).unwrap();
    let good = sim.to_checkpoint(b"");
    // Records of 112 bytes after the 109 bytes before the spheres and their count: position,
    // velocity, clock, radius and counter (68 bytes), then the event: code 1, the partner and
    // the counter seen (its bytes 5 to 8).
    let seen = |k: usize| 24 + 117 + 112 * k + 68 + 5;
    for k in 0..2 {
        assert_eq!(
            &good[seen(k) - 5..seen(k) + 4],
            &[1, 1 - k as u8, 0, 0, 0, 0, 0, 0, 0]
        );
    }
    let stale = |which: &[usize]| {
        let mut bytes = good[..good.len() - 4].to_vec();
        for &k in which {
            bytes[seen(k)] = 7;
        }
        reframed(bytes)
    };
    refused::<3>(
        &stale(&[0, 1]),
        "discs 0 and 1 meet at t = 2.5, but neither has an event that looks at the other before t = 7.5",
    );
    // One stale event is a state a run can reach (its partner changed course since, and was
    // predicted again): sphere 0 falls back on its wall, and sphere 1's live event is the
    // collision, at t = 2.5 as before.
    for which in [&[0][..], &[1]] {
        let (mut one, _) = Simulation::<3>::from_checkpoint(&stale(which)).unwrap();
        one.run_until(3.0, &mut ());
        assert_eq!(one.stats().disc_disc, 1);
        assert!(one.overlaps(0.0).count == 0);
    }
}

/// The demon's yardstick, twice the mean `m v^2`, is kept from the start (energy is
/// conserved), set again when the velocities are changed, and checked on reading against the
/// discs' kinetic energy: one that is not theirs would move a demon's thresholds and, far too
/// large, keep the stall watcher from seeing a creeping clock.
#[test]
fn the_mean_kinetic_energy_carried_is_the_discs_own() {
    let discs = random_discs(20, 10.0, 0.2, 0.4, true, 8);
    let mut sim = Simulation::new(&discs, SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
    sim.run_until(1.0, &mut ());
    // Changed velocities (Python's `velocities` setter) are carried with their own yardstick.
    sim.modify_velocities(|_, v| v * 3.0);
    let good = sim.to_checkpoint(b"");
    let (mut copy, _) = Simulation::<2>::from_checkpoint(&good).unwrap();
    copy.run_until(2.0, &mut ());
    // The yardstick follows the box lengths and boundaries (18 bytes), the rule, the
    // multi-contact code, the two clocks, five counters and the adjusted count: 84 bytes in.
    let at = 24 + 84;
    let mean = f64::from_le_bytes(good[at..at + 8].try_into().unwrap());
    assert_eq!(mean, 4.0 * sim.kinetic_energy() / 20.0);
    for forged in [
        mean * 10.0,
        mean * (1.0 + 1e-5),
        f64::NAN,
        f64::INFINITY,
        -mean,
    ] {
        let mut bad = good[..good.len() - 4].to_vec();
        bad[at..at + 8].copy_from_slice(&forged.to_le_bytes());
        refused::<2>(&reframed(bad), "mean m v^2");
    }
    // Rounding is not refused: energy is conserved to far better than 1e-6.
    let mut close = good[..good.len() - 4].to_vec();
    close[at..at + 8].copy_from_slice(&(mean * (1.0 + 1e-9)).to_le_bytes());
    assert!(Simulation::<2>::from_checkpoint(&reframed(close)).is_ok());
}

/// Found by a new user's fuzzing of checkpoints: a disc's position was
/// read without asking whether the cell it is filed in holds it. One byte moved a sphere
/// across the box, into other spheres; the scans of its new neighbours, which look in their
/// own cells, never saw it, so it overlapped them for the rest of the run, and `edmd run
/// --check` (which looks the same way) passed. A disc must now be in its cell, to within the
/// rounding a crossing leaves.
#[test]
fn a_disc_filed_in_a_cell_that_does_not_hold_it_is_refused() {
    let discs = head_on::<2>();
    let sim = Simulation::new(&discs, SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
    assert_eq!(sim.grid_dims(), [2, 2]);
    let good = sim.to_checkpoint(b"");
    // Disc 1's y (its record 92 bytes after disc 0's, which follows the 100 bytes before the
    // discs and their count), in cell [1, 1] (y from 5 up to the wall).
    let at = 24 + 108 + 92 + 8;
    assert_eq!(good[at..at + 8], 5.0f64.to_le_bytes());
    let with_y = |y: f64| {
        let mut bytes = good[..good.len() - 4].to_vec();
        bytes[at..at + 8].copy_from_slice(&y.to_le_bytes());
        reframed(bytes)
    };
    // Moved down into cell [1, 0], where nothing else refuses it: moving along x, it still
    // leaves its cell (as filed) at x = 5, after its pending collision.
    refused::<2>(
        &with_y(2.0),
        "disc 1 is filed in cell [1, 1], which does not hold it",
    );
    // Anywhere in its cell it is read (its events are another matter).
    assert!(Simulation::<2>::from_checkpoint(&with_y(5.25)).is_ok());
}
