//! Building from discs given by value, and the per-disc tables held once for equal discs:
//! the same simulation as ever, with less memory (BENCHMARKS.md, "Memory at scale").

use edmd_core::setup::lattice::lattice_fluid_in;
use edmd_core::{Boundary, Disc, Error, Options, OverlapPolicy, Potential, SimBox, Simulation};

fn run_to_debug<const D: usize>(mut sim: Simulation<D>, t: f64) -> String {
    sim.run_until(t, &mut ());
    format!(
        "{:?} {:?} {}",
        sim.discs(),
        sim.stats(),
        sim.adjusted_discs()
    )
}

/// Mixed masses, colours and species, and discs a little outside the walled box (moved in,
/// under `OverlapPolicy::Allow`): the owned input makes the borrowed one's simulation, event
/// for event and to the bit.
#[test]
fn discs_given_by_value_make_the_same_run() {
    let (mut discs, sim_box) = lattice_fluid_in::<2>(2000, 0.5, Boundary::Walls, 7).unwrap();
    for (k, d) in discs.iter_mut().enumerate() {
        if k % 7 == 3 {
            d.mass = 2.5;
            d.colour = [200, 10, 10];
            d.species = 1;
        }
    }
    // Two discs just past the left wall; the lowest index must be the one reported.
    discs[5].pos[0] = discs[5].radius * (1.0 - 1e-6);
    discs[900].pos[0] = discs[900].radius * (1.0 - 1e-6);
    let options = Options {
        overlaps: OverlapPolicy::Allow,
        ..Options::default()
    };
    let hard = Potential::default();
    let a = Simulation::with_potential_at(&discs, sim_box, &[], &hard, options, 0.0).unwrap();
    let b =
        Simulation::with_potential_owned(discs.clone(), sim_box, &[], &hard, options, 0.0).unwrap();
    assert_eq!(a.adjusted_discs(), 2);
    assert_eq!(b.adjusted_discs(), 2);
    assert_eq!(run_to_debug(a, 5.0), run_to_debug(b, 5.0));

    let refuse = Options::default();
    let first = |r: Result<Simulation<2>, Error>| match r {
        Err(Error::OutsideBox { first, count }) => (first, count),
        other => panic!("expected OutsideBox, got {:?}", other.map(|_| ())),
    };
    assert_eq!(
        first(Simulation::with_potential_at(
            &discs,
            sim_box,
            &[],
            &hard,
            refuse,
            0.0
        )),
        (5, 2)
    );
    assert_eq!(
        first(Simulation::with_potential_owned(
            discs,
            sim_box,
            &[],
            &hard,
            refuse,
            0.0
        )),
        (5, 2)
    );
}

/// In 3D and with discs of one kind the two make the same run too (the tables held once).
#[test]
fn equal_spheres_given_by_value_make_the_same_run() {
    let (discs, sim_box) = lattice_fluid_in::<3>(500, 0.4, Boundary::Periodic, 3).unwrap();
    let hard = Potential::default();
    let o = Options::default();
    let a = Simulation::with_potential_at(&discs, sim_box, &[], &hard, o, 0.0).unwrap();
    let b = Simulation::with_potential_owned(discs, sim_box, &[], &hard, o, 0.0).unwrap();
    assert_eq!(run_to_debug(a, 3.0), run_to_debug(b, 3.0));
}

/// Equal discs keep one mass, colour and species for all: a single disc made heavier costs
/// the whole mass array (8 bytes a disc) and nothing else.
#[test]
fn equal_discs_hold_their_mass_once() {
    let n = 4000;
    let (discs, sim_box): (Vec<Disc<2>>, SimBox<2>) =
        lattice_fluid_in::<2>(n, 0.4, Boundary::Periodic, 1).unwrap();
    let equal = Simulation::new(&discs, sim_box, Options::default()).unwrap();
    let mut one_heavy = discs.clone();
    one_heavy[17].mass = 3.0;
    let mixed = Simulation::new(&one_heavy, sim_box, Options::default()).unwrap();
    assert_eq!(mixed.memory_bytes() - equal.memory_bytes(), 8 * n);
    assert_eq!(equal.mass(17), 1.0);
    assert_eq!(mixed.mass(17), 3.0);
    assert_eq!(mixed.mass(18), 1.0);
}
