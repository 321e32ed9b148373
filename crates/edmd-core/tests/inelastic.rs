//! Inelastic collisions: the kinematics of a collision with restitution (normal velocity
//! reversed and shrunk, momentum conserved, the energy lost counted), the walls', Bridges'
//! law, the TC model against inelastic collapse, Haff's law, and exact checkpoints.

use edmd_core::measure::theory::{enskog_collision_frequency_in, haff_temperature, haff_time};
use edmd_core::setup::lattice_fluid_in;
use edmd_core::{
    Boundary, Disc, Error, Options, Reaction, Reactions, Restitution, RestitutionLaw, SimBox,
    Simulation, Vector,
};

fn head_on(u: f64) -> Simulation<2> {
    let a = Disc::new(Vector::new([5.0, 5.0]), Vector::new([u, 0.0]), 0.5);
    let mut b = Disc::new(Vector::new([7.0, 5.0]), Vector::new([0.0, 0.0]), 0.5);
    b.mass = 3.0;
    Simulation::new(&[a, b], SimBox::periodic([20.0, 20.0]), Options::default()).unwrap()
}

fn momentum<const D: usize>(sim: &Simulation<D>) -> Vector<D> {
    let mut p = Vector::ZERO;
    for i in 0..sim.len() {
        p += sim.velocity(i) * sim.mass(i);
    }
    p
}

#[test]
fn the_normal_relative_velocity_is_reversed_and_shrunk_by_e() {
    // Masses 1 and 3, closing at 2: with e = 1/2 they part at 1. Momentum 2 gives the
    // velocities -1/4 and 3/4; the reduced mass 3/4 loses (1 - 1/4) (3/4) 4 / 2 = 9/8.
    let mut sim = head_on(2.0);
    sim.set_restitution(Some(Restitution::constant(0.5)))
        .unwrap();
    sim.run_until(1.0, &mut ());
    assert_eq!(sim.stats().disc_disc, 1);
    assert!(
        (sim.velocity(0)[0] + 0.25).abs() < 1e-15,
        "{:?}",
        sim.velocity(0)
    );
    assert!((sim.velocity(1)[0] - 0.75).abs() < 1e-15);
    assert!((sim.dissipated() - 9.0 / 8.0).abs() < 1e-15);
    assert!((sim.kinetic_energy() + sim.dissipated() - 2.0).abs() < 1e-14);
}

#[test]
fn bridges_law_gives_its_coefficient_at_the_impact_speed() {
    // Closing at 2 with v_c = 0.25: e = 8^-0.234; below v_c a collision is elastic.
    let law = RestitutionLaw::Bridges { v_c: 0.25 };
    let e = 8f64.powf(-0.234);
    let mut sim = head_on(2.0);
    sim.set_restitution(Some(Restitution {
        all: law,
        ..Default::default()
    }))
    .unwrap();
    sim.run_until(1.0, &mut ());
    let parting = sim.velocity(1)[0] - sim.velocity(0)[0];
    assert!(
        (parting - 2.0 * e).abs() < 1e-14,
        "{parting} against {}",
        2.0 * e
    );
    let mut slow = head_on(0.2);
    slow.set_restitution(Some(Restitution {
        all: law,
        ..Default::default()
    }))
    .unwrap();
    slow.run_until(10.0, &mut ());
    assert_eq!(slow.stats().disc_disc, 1);
    assert_eq!(slow.dissipated(), 0.0);
}

#[test]
fn a_wall_with_restitution_returns_a_disc_slower() {
    let d = Disc::new(Vector::new([2.0, 2.0]), Vector::new([-1.0, 0.5]), 0.5);
    let mut sim = Simulation::new(&[d], SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
    sim.set_restitution(Some(Restitution {
        wall: 0.25,
        ..Default::default()
    }))
    .unwrap();
    sim.run_until(2.0, &mut ());
    assert_eq!(sim.stats().wall, 1);
    assert_eq!(sim.velocity(0), Vector::new([0.25, 0.5]));
    assert!((sim.dissipated() - 0.5 * (1.0 - 1.0 / 16.0)).abs() < 1e-15);
}

#[test]
fn elastic_restitution_is_the_hard_cores_bit_for_bit() {
    // e = 1 everywhere is no restitution at all; a pair law of 1 beside inelastic walls runs
    // the elastic impulse, so a periodic fluid's events are the elastic run's.
    let (discs, bx) = lattice_fluid_in::<2>(400, 0.4, Boundary::Periodic, 3).unwrap();
    let mut plain = Simulation::new(&discs, bx, Options::default()).unwrap();
    let mut ruled = plain.clone();
    ruled
        .set_restitution(Some(Restitution::constant(1.0)))
        .unwrap();
    assert!(ruled.restitution().is_none());
    ruled
        .set_restitution(Some(Restitution {
            wall: 0.5,
            ..Default::default()
        }))
        .unwrap();
    assert!(ruled.restitution().is_some());
    plain.run_until(20.0, &mut ());
    ruled.run_until(20.0, &mut ());
    assert_eq!(plain.stats().disc_disc, ruled.stats().disc_disc);
    for i in 0..plain.len() {
        assert_eq!(plain.position(i), ruled.position(i));
        assert_eq!(plain.velocity(i), ruled.velocity(i));
    }
}

/// Momentum is conserved to rounding, kinetic energy plus the energy lost too, and no cores
/// overlap, in 2D and 3D, over many collisions at e = 0.8.
fn conserves<const D: usize>(n: usize, eta: f64) {
    let (discs, bx) = lattice_fluid_in::<D>(n, eta, Boundary::Periodic, 7).unwrap();
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    let e0 = sim.kinetic_energy();
    let p0 = momentum(&sim);
    sim.set_restitution(Some(Restitution {
        all: RestitutionLaw::Constant(0.8),
        tc: 1e-4,
        ..Default::default()
    }))
    .unwrap();
    sim.run_events(200_000, &mut ());
    assert!(
        sim.dissipated() > 0.5 * e0,
        "lost {} of {e0}",
        sim.dissipated()
    );
    let e = sim.kinetic_energy() + sim.dissipated();
    assert!((e - e0).abs() < 1e-10 * e0, "{e} against {e0}");
    let p = momentum(&sim);
    assert!((p - p0).norm2().sqrt() < 1e-9 * (2.0 * e0).sqrt(), "{p:?}");
    assert!(sim.overlaps(edmd_core::OVERLAP_TOLERANCE).first.is_none());
}

#[test]
fn momentum_and_energy_with_the_loss_are_conserved_in_2d() {
    conserves::<2>(1000, 0.3);
}

#[test]
fn momentum_and_energy_with_the_loss_are_conserved_in_3d() {
    conserves::<3>(1000, 0.2);
}

/// A dense 2D fluid at e = 0.3: clusters form whose discs lose their relative motion in
/// infinitely many collisions in a finite time (inelastic collapse, McNamara and Young, Phys.
/// Rev. E 50, R28 (1994)).
fn dense(tc: f64) -> Simulation<2> {
    let (discs, bx) = lattice_fluid_in::<2>(1000, 0.5, Boundary::Periodic, 3).unwrap();
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    sim.set_restitution(Some(Restitution {
        all: RestitutionLaw::Constant(0.3),
        tc,
        ..Default::default()
    }))
    .unwrap();
    sim
}

#[test]
fn inelastic_collapse_stops_the_clock_without_the_tc_model_and_not_with_it() {
    // Without the model the clock stops within a few collisions per disc, and the stall
    // watcher ends the run.
    let mut collapse = dense(0.0);
    collapse.run_until(100.0, &mut ());
    let stall = collapse.stalled().expect("the collapse stops the clock");
    assert!(stall.time < 10.0, "{stall:?}");
    // With it the fluid goes on cooling: a thousandth of its energy left at t = 100.
    let mut tc = dense(1e-3);
    let e0 = tc.kinetic_energy();
    tc.run_until(100.0, &mut ());
    assert!(tc.stalled().is_none());
    assert!(tc.kinetic_energy() < 0.01 * e0, "{}", tc.kinetic_energy());
    assert!(tc.overlaps(edmd_core::OVERLAP_TOLERANCE).first.is_none());
}

#[test]
fn a_checkpoint_continues_bit_for_bit() {
    let (discs, bx) = lattice_fluid_in::<3>(500, 0.3, Boundary::Walls, 5).unwrap();
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    sim.set_restitution(Some(Restitution {
        all: RestitutionLaw::Bridges { v_c: 0.5 },
        pairs: vec![(0, 0, RestitutionLaw::Constant(0.7))],
        wall: 0.9,
        tc: 1e-3,
    }))
    .unwrap();
    sim.run_events(20_000, &mut ());
    let bytes = sim.to_checkpoint(&[]);
    let (mut back, _) = Simulation::<3>::from_checkpoint(&bytes).unwrap();
    assert_eq!(back.restitution(), sim.restitution());
    assert_eq!(back.dissipated(), sim.dissipated());
    sim.run_events(20_000, &mut ());
    back.run_events(20_000, &mut ());
    assert_eq!(back.dissipated(), sim.dissipated());
    assert_eq!(back.stats().disc_disc, sim.stats().disc_disc);
    for i in 0..sim.len() {
        assert_eq!(back.position(i), sim.position(i));
        assert_eq!(back.velocity(i), sim.velocity(i));
    }
}

#[test]
fn restitution_is_refused_with_what_it_does_not_go_with() {
    let mut sim = head_on(1.0);
    let e = sim
        .set_restitution(Some(Restitution::constant(1.5)))
        .unwrap_err();
    assert!(matches!(e, Error::BadRestitution(_)), "{e}");
    sim.set_reactions(Some(Reactions::new(vec![Reaction {
        reactants: (0, 0),
        products: (0, 0),
        activation: 0.0,
        probability: 1.0,
        heat: 0.0,
    }])))
    .unwrap();
    let e = sim
        .set_restitution(Some(Restitution::constant(0.5)))
        .unwrap_err();
    assert!(e.to_string().contains("reaction rules"), "{e}");
    sim.set_reactions(None).unwrap();
    sim.set_restitution(Some(Restitution::constant(0.5)))
        .unwrap();
    let e = sim
        .set_reactions(Some(Reactions::new(vec![Reaction {
            reactants: (0, 0),
            products: (0, 0),
            activation: 0.0,
            probability: 1.0,
            heat: 0.0,
        }])))
        .unwrap_err();
    assert!(e.to_string().contains("inelastic"), "{e}");
}

/// Haff's law in a dilute 2D gas: at e = 0.95 and packing 0.05 the gas stays homogeneous
/// while it cools to a quarter of its temperature (its box of 126 diameters is below the
/// clustering instability's critical size at this density and e), and T(t) follows
/// `T0 / (1 + t/t0)^2` with `t0` from Enskog's collision frequency. The velocity
/// distribution's Sonine correction changes the cooling rate by about 0.1% at this e (van
/// Noije and Ernst, Granular Matter 1, 57 (1998)), and a gas of 1000 discs measures T to
/// about 3%/sqrt(1000) per sample: 3% bounds both.
#[test]
fn a_dilute_gas_cools_by_haffs_law() {
    let (n, eta, e) = (1000usize, 0.05, 0.95);
    let (discs, bx) = lattice_fluid_in::<2>(n, eta, Boundary::Periodic, 11).unwrap();
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    sim.run_until(50.0, &mut ());
    let kt0 = sim.kinetic_energy() / n as f64;
    let start = sim.time();
    sim.set_restitution(Some(Restitution::constant(e))).unwrap();
    let omega0 = enskog_collision_frequency_in(eta, 1.0, kt0, 1.0, 2);
    let t0 = haff_time(2, e, omega0);
    for k in 1..=10 {
        let t = k as f64 * t0 / 10.0;
        sim.run_until(start + t, &mut ());
        let kt = sim.kinetic_energy() / n as f64;
        let want = haff_temperature(t, kt0, t0);
        assert!(
            (kt / want - 1.0).abs() < 0.03,
            "t = {t}: kT {kt} against Haff's {want}"
        );
    }
}
