//! Exact checkpoints of compressions (`Packer::checkpoint`, `Packer::from_checkpoint`): a
//! compression stopped at checkpoints and continued from their bytes, once or in a chain, ends
//! in the packing of the one never stopped, bit for bit; in 2D and 3D, with walls and
//! periodic, with the cell grid and with neighbour lists. And the reader refuses every damaged
//! file with an `Error::Checkpoint`, never a panic.

use edmd_core::pack::{
    is_pack_checkpoint, pack_checkpoint_dim, random_start, PackOptions, PackSizes, Packer, Packing,
    Stop, PACK_FORMAT_VERSION,
};
use edmd_core::{Boundary, Disc, Error, Options, SimBox, Simulation};

const BIDISPERSE: PackSizes = PackSizes::Binary {
    size_ratio: 1.4,
    fraction_large: 0.5,
};

/// Every bit of a packing: particles, box, packing fraction, pressure, counters, stop.
fn bits<const D: usize>(p: &Packing<D>) -> Vec<u64> {
    let mut b = Vec::new();
    for d in &p.discs {
        for a in 0..D {
            b.extend([d.pos[a].to_bits(), d.vel[a].to_bits()]);
        }
        b.extend([d.radius.to_bits(), d.mass.to_bits(), d.species as u64]);
        b.extend(d.colour.iter().map(|&c| c as u64));
    }
    b.extend(p.sim_box.lengths.iter().map(|l| l.to_bits()));
    b.extend([
        p.packing_fraction.to_bits(),
        p.reduced_pressure.map_or(u64::MAX, f64::to_bits),
        p.collisions,
        p.wall_collisions,
        p.events,
        p.rescales,
        p.stop as u64,
    ]);
    b
}

/// The compression never stopped, and at each measured synchronisation whether neighbour
/// lists were on.
fn straight<const D: usize>(
    discs: &[Disc<D>],
    sim_box: SimBox<D>,
    options: PackOptions,
) -> (Packing<D>, Vec<bool>) {
    let mut lists = Vec::new();
    let p = Packer::new(discs, sim_box, options)
        .unwrap()
        .run_with(|pk| {
            lists.push(pk.neighbour_lists());
            true
        })
        .unwrap();
    (p, lists)
}

/// The compression stopped at each measured synchronisation in `at` (counted from the start;
/// 0 is the start itself), checkpointed there and continued from the bytes alone. Returns the
/// final packing and whether each checkpoint had neighbour lists on.
fn chained<const D: usize>(
    discs: &[Disc<D>],
    sim_box: SimBox<D>,
    options: PackOptions,
    at: &[usize],
) -> (Packing<D>, Vec<bool>) {
    let mut packer = Packer::new(discs, sim_box, options).unwrap();
    let mut done = 0;
    let mut lists = Vec::new();
    for &k in at {
        let bytes = if k == done {
            packer.checkpoint(b"caller")
        } else {
            let mut ck = None;
            let mut seen = done;
            let p = packer
                .run_with(|pk| {
                    seen += 1;
                    if seen == k {
                        ck = Some(pk.checkpoint(b"caller"));
                    }
                    seen < k
                })
                .unwrap();
            assert_eq!(p.stop, Stop::Interrupted, "the run ended before sync {k}");
            ck.unwrap()
        };
        assert!(is_pack_checkpoint(&bytes));
        assert_eq!(pack_checkpoint_dim(&bytes).unwrap(), D);
        let (back, extra) = Packer::<D>::from_checkpoint(&bytes).unwrap();
        assert_eq!(extra, b"caller");
        assert!(
            back.checkpoint(&extra) == bytes,
            "a checkpoint read back does not give the same bytes"
        );
        lists.push(back.neighbour_lists());
        packer = back;
        done = k;
    }
    (packer.run(|_| true).unwrap(), lists)
}

/// Checkpoints at the start, early, at a third and two thirds of the way, at the first
/// measured synchronisation with neighbour lists and at the last one (one chain), and at each of those alone: every continuation gives
/// the packing of the run never stopped. Returns whether the checkpoints had lists on.
fn check_exact<const D: usize>(
    n: usize,
    sizes: PackSizes,
    boundary: Boundary,
    options: PackOptions,
    seed: u64,
) -> Vec<bool> {
    let (discs, sim_box) = random_start::<D>(n, sizes, boundary, seed).unwrap();
    let (whole, syncs) = straight(&discs, sim_box, options);
    let s = syncs.len();
    assert!(s >= 6, "only {s} synchronisations");
    let mut at = vec![0, 1, s / 3, 2 * s / 3, s - 1];
    // The first with neighbour lists, if any.
    at.extend(syncs.iter().position(|&l| l).map(|k| k + 1));
    at.sort();
    at.dedup();
    let (p, lists) = chained(&discs, sim_box, options, &at);
    assert_eq!(p, whole);
    assert!(
        bits(&p) == bits(&whole),
        "a chain of checkpoints changed the packing"
    );
    for &k in &at[1..] {
        let (p, _) = chained(&discs, sim_box, options, &[k]);
        assert!(
            bits(&p) == bits(&whole),
            "a checkpoint at sync {k} changed the packing"
        );
    }
    lists
}

fn jam(pressure: f64) -> PackOptions {
    PackOptions {
        max_pressure: pressure,
        ..PackOptions::default()
    }
}

#[test]
fn a_continued_compression_of_discs_in_a_periodic_box_is_the_uninterrupted_one() {
    let lists = check_exact::<2>(150, BIDISPERSE, Boundary::Periodic, jam(1e8), 3);
    assert!(lists.contains(&false) && lists.contains(&true), "{lists:?}");
}

#[test]
fn a_continued_compression_of_discs_between_walls_is_the_uninterrupted_one() {
    let lists = check_exact::<2>(120, BIDISPERSE, Boundary::Walls, jam(1e8), 4);
    assert!(lists.contains(&false) && lists.contains(&true), "{lists:?}");
}

#[test]
fn a_continued_compression_of_spheres_in_a_periodic_box_is_the_uninterrupted_one() {
    let lists = check_exact::<3>(
        150,
        PackSizes::MONODISPERSE,
        Boundary::Periodic,
        jam(1e8),
        5,
    );
    assert!(lists.contains(&false) && lists.contains(&true), "{lists:?}");
}

#[test]
fn a_continued_compression_of_polydisperse_spheres_between_walls_is_the_uninterrupted_one() {
    let sizes = PackSizes::Polydisperse { std: 0.1 };
    let lists = check_exact::<3>(300, sizes, Boundary::Walls, jam(1e8), 6);
    assert!(lists.contains(&false) && lists.contains(&true), "{lists:?}");
}

#[test]
fn a_continued_compression_to_a_target_packing_fraction_is_the_uninterrupted_one() {
    let options = PackOptions {
        target_packing: Some(0.5),
        ..PackOptions::default()
    };
    check_exact::<3>(200, PackSizes::MONODISPERSE, Boundary::Periodic, options, 7);
}

/// A small checkpoint with neighbour lists on, and one on the cell grid.
fn small_checkpoints() -> Vec<Vec<u8>> {
    let (discs, sim_box) = random_start::<2>(24, BIDISPERSE, Boundary::Walls, 9).unwrap();
    let mut out = vec![Packer::new(&discs, sim_box, jam(1e6))
        .unwrap()
        .checkpoint(b"x")];
    let mut got = None;
    Packer::new(&discs, sim_box, jam(1e6))
        .unwrap()
        .run_with(|pk| {
            if pk.neighbour_lists() {
                got = Some(pk.checkpoint(b"x"));
            }
            got.is_none()
        })
        .unwrap();
    out.push(got.expect("lists on before jamming"));
    out
}

/// Runs a continued compression for a few synchronisations at most.
fn run_a_little<const D: usize>(p: Packer<D>) {
    let mut k = 0;
    let _ = p.run_with(|_| {
        k += 1;
        k < 3
    });
}

#[test]
fn a_damaged_packing_checkpoint_is_an_error_never_a_panic() {
    for good in small_checkpoints() {
        Packer::<2>::from_checkpoint(&good).unwrap();
        for len in 0..good.len() {
            assert!(
                matches!(
                    Packer::<2>::from_checkpoint(&good[..len]),
                    Err(Error::Checkpoint(_))
                ),
                "truncated to {len} bytes, accepted"
            );
        }
        for byte in 0..good.len() {
            for bit in [0, 3, 7] {
                let mut bad = good.clone();
                bad[byte] ^= 1 << bit;
                assert!(
                    matches!(
                        Packer::<2>::from_checkpoint(&bad),
                        Err(Error::Checkpoint(_))
                    ),
                    "flipping bit {bit} of byte {byte} was not noticed"
                );
                // The same damage behind a correct checksum reaches the structural checks:
                // refused, or read back to the same bytes and run.
                let end = bad.len() - 4;
                let crc = crc32fast::hash(&bad[..end]);
                bad[end..].copy_from_slice(&crc.to_le_bytes());
                match Packer::<2>::from_checkpoint(&bad) {
                    Ok((p, extra)) => {
                        assert!(p.checkpoint(&extra) == bad, "byte {byte} bit {bit}");
                        // (A damaged rescaling interval may ask for 10^6 collisions per
                        // particle between two looks: bounded, but slow here.)
                        if p.options().collisions_per_rescale <= 100.0 {
                            run_a_little(p);
                        }
                    }
                    Err(Error::Checkpoint(_)) => {}
                    Err(e) => panic!("byte {byte} bit {bit}: {e}"),
                }
            }
        }
        let mut newer = good.clone();
        newer[8..12].copy_from_slice(&(PACK_FORMAT_VERSION + 1).to_le_bytes());
        match Packer::<2>::from_checkpoint(&newer) {
            Err(Error::Checkpoint(m)) => assert!(m.contains("newer"), "{m}"),
            other => panic!("{:?}", other.err()),
        }
        match Packer::<3>::from_checkpoint(&good) {
            Err(Error::Checkpoint(m)) => assert!(m.contains("2D"), "{m}"),
            other => panic!("{:?}", other.err()),
        }
        // A run's checkpoint and a packing's are told apart by name, both ways.
        match Simulation::<2>::from_checkpoint(&good) {
            Err(Error::Checkpoint(m)) => assert!(m.contains("packing checkpoint"), "{m}"),
            other => panic!("{:?}", other.err()),
        }
    }
    let discs = [Disc::new(
        edmd_core::Vector::new([1.0, 1.0]),
        edmd_core::Vector::new([1.0, 0.0]),
        0.1,
    )];
    let run = Simulation::new(&discs, SimBox::walls([2.0, 2.0]), Options::default())
        .unwrap()
        .to_checkpoint(b"");
    match Packer::<2>::from_checkpoint(&run) {
        Err(Error::Checkpoint(m)) => assert!(m.contains("run checkpoint"), "{m}"),
        other => panic!("{:?}", other.err()),
    }
    for foreign in [&b"2\n0.5 0.5 0 0 0.1 1 0 0 0\n"[..], b"", b"EDMDPACK"] {
        assert!(matches!(
            Packer::<2>::from_checkpoint(foreign),
            Err(Error::Checkpoint(_))
        ));
    }
}
