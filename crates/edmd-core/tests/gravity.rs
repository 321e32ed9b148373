//! A uniform field: parabolic flights with exact wall and cell-crossing times, energy (kinetic
//! plus the field's) conserved, the barometric law in a dilute column, exact checkpoints, and
//! the refusals.

use edmd_core::setup::lattice_fluid_in;
use edmd_core::{
    Boundary, Disc, Error, Gravity, Options, Potential, Restitution, RestitutionLaw, SimBox,
    Simulation, Vector, OVERLAP_TOLERANCE,
};

fn down(g: f64) -> Option<Gravity> {
    Some(Gravity { axis: 1, g })
}

#[test]
fn a_dropped_disc_bounces_at_the_free_fall_times() {
    // Dropped from rest at y = 5 + 0.5 onto the floor (centre at 0.5) under g = -2: it lands
    // at t = sqrt(2 h / g) = sqrt(5) and, the floor elastic, is back at rest at 5.5 at
    // 2 sqrt(5), landing again at 3 sqrt(5). Meanwhile it crosses cells on the way.
    let d = Disc::new(Vector::new([2.0, 5.5]), Vector::new([0.0, 0.0]), 0.5);
    let mut sim = Simulation::new(&[d], SimBox::walls([4.0, 10.0]), Options::default()).unwrap();
    sim.set_gravity(down(-2.0)).unwrap();
    let e0 = sim.kinetic_energy() + sim.potential_energy();
    assert!((e0 - 2.0 * 5.5).abs() < 1e-15, "{e0}");
    let t = 5f64.sqrt();
    let mut apex = sim.clone();
    apex.run_until(2.0 * t, &mut ());
    assert!(
        (apex.position(0)[1] - 5.5).abs() < 1e-13,
        "{:?}",
        apex.position(0)
    );
    assert!(apex.velocity(0)[1].abs() < 1e-13);
    let mut walls = Vec::new();
    while walls.len() < 2 {
        let e = sim.step(100.0).expect("an event");
        if let edmd_core::EventKind::Wall { .. } = e.kind {
            walls.push(e.time);
        }
    }
    assert!((walls[0] - t).abs() < 1e-14, "{walls:?}");
    assert!((walls[1] - 3.0 * t).abs() < 1e-14, "{walls:?}");
    let e = sim.kinetic_energy() + sim.potential_energy();
    assert!((e - e0).abs() < 1e-13, "{e} against {e0}");
}

#[test]
fn a_thrown_sphere_meets_the_side_wall_on_its_parabola() {
    // 3D, the field along z: thrown at (1, 0, 3) from (1, 5, 1) in a box 6 wide along x, the
    // sphere (radius 0.5) meets the wall at x = 5.5 at t = 4.5, where z = 1 + 3t - t^2/2.
    let d = Disc::new(
        Vector::new([1.0, 5.0, 1.0]),
        Vector::new([1.0, 0.0, 3.0]),
        0.5,
    );
    let mut sim =
        Simulation::new(&[d], SimBox::walls([6.0, 10.0, 20.0]), Options::default()).unwrap();
    sim.set_gravity(Some(Gravity { axis: 2, g: -1.0 })).unwrap();
    let mut first_wall = None;
    while first_wall.is_none() {
        let e = sim.step(100.0).expect("an event");
        if let edmd_core::EventKind::Wall { wall, .. } = e.kind {
            first_wall = Some((e.time, wall.axis));
        }
    }
    let (t, axis) = first_wall.unwrap();
    assert_eq!(axis, 0);
    assert!((t - 4.5).abs() < 1e-14, "{t}");
    let z = 1.0 + 3.0 * 4.5 - 0.5 * 4.5 * 4.5;
    assert!(
        (sim.position(0)[2] - z).abs() < 1e-13,
        "{:?}",
        sim.position(0)
    );
    assert!((sim.velocity(0)[2] - (3.0 - 4.5)).abs() < 1e-14);
}

/// A fluid in a box with a floor and a ceiling (periodic sideways), in a field strong enough
/// to pack its lower half: energy conserved to rounding, no overlaps, nobody outside.
fn column<const D: usize>(n: usize, eta: f64, g: f64) -> Simulation<D> {
    let (discs, mut bx) = lattice_fluid_in::<D>(n, eta, Boundary::Walls, 5).unwrap();
    // Placed between walls, so sideways images keep their distance too.
    for a in 0..D - 1 {
        bx.boundaries[a] = Boundary::Periodic;
    }
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    sim.set_gravity(Some(Gravity { axis: D - 1, g })).unwrap();
    sim
}

fn conserves<const D: usize>(n: usize, eta: f64) {
    let mut sim = column::<D>(n, eta, -0.2);
    let e0 = sim.kinetic_energy() + sim.potential_energy();
    let scale = sim.kinetic_energy() + sim.potential_energy().abs();
    sim.run_events(200_000, &mut ());
    let e = sim.kinetic_energy() + sim.potential_energy();
    assert!((e - e0).abs() < 1e-10 * scale, "{e} against {e0}");
    assert!(sim.overlaps(OVERLAP_TOLERANCE).first.is_none());
    assert!(sim.discs_outside(OVERLAP_TOLERANCE).is_empty());
    assert!(sim.stalled().is_none());
}

#[test]
fn energy_with_the_field_s_is_conserved_in_2d() {
    conserves::<2>(1000, 0.3);
}

#[test]
fn energy_with_the_field_s_is_conserved_in_3d() {
    conserves::<3>(1000, 0.2);
}

#[test]
fn a_checkpoint_continues_bit_for_bit_in_a_field() {
    let mut sim = column::<3>(400, 0.3, -0.5);
    sim.set_restitution(Some(Restitution {
        all: RestitutionLaw::Constant(0.9),
        pairs: Vec::new(),
        wall: 0.8,
        tc: 1e-3,
    }))
    .unwrap();
    sim.run_events(30_000, &mut ());
    let bytes = sim.to_checkpoint(&[]);
    let (mut back, _) = Simulation::<3>::from_checkpoint(&bytes).unwrap();
    assert_eq!(back.gravity(), sim.gravity());
    sim.run_events(30_000, &mut ());
    back.run_events(30_000, &mut ());
    assert_eq!(back.to_checkpoint(&[]), sim.to_checkpoint(&[]));
}

/// The barometric law in a dilute 2D gas (packing 0.01 at the bottom, so excluded volume
/// changes the density by about 2%): heights are distributed as `exp(-m g y / kT)` between
/// the floor and the ceiling; the mean height above the floor, averaged over 200 samples of
/// 300 discs after they have settled, agrees with the law's within 4% (the samples are
/// correlated over a few mean collision times: about 30 independent ones, each with a
/// spread of about the scale height, give 1.5%; the excluded volume adds up to 2%).
#[test]
fn a_dilute_column_follows_the_barometric_law() {
    let n = 300;
    let (discs, mut bx) = lattice_fluid_in::<2>(n, 0.01, Boundary::Walls, 9).unwrap();
    bx.boundaries[0] = Boundary::Periodic;
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    let kt = sim.kinetic_energy() / n as f64;
    let height = bx.lengths[1] - 1.0;
    // A scale height of a quarter of the box.
    let g = -4.0 * kt / height;
    sim.set_gravity(Some(Gravity { axis: 1, g })).unwrap();
    let lambda = kt / -g;
    // Settle: many crossings of the scale height.
    let crossing = lambda / kt.sqrt();
    sim.run_until(sim.time() + 200.0 * crossing, &mut ());
    // The energy is the gas's now: kT from the kinetic energy.
    let kt = sim.kinetic_energy() / n as f64;
    let lambda = kt / -g;
    let (mut sum, mut samples) = (0.0, 0);
    for _ in 0..200 {
        sim.run_until(sim.time() + 5.0 * crossing, &mut ());
        for i in 0..n {
            sum += sim.position(i)[1] - 0.5;
        }
        samples += n;
    }
    let mean = sum / samples as f64;
    let x = height / lambda;
    let want = lambda * (1.0 - x * (-x).exp() / (1.0 - (-x).exp()));
    assert!(
        (mean / want - 1.0).abs() < 0.04,
        "mean height {mean} against the law's {want}"
    );
}

#[test]
fn fields_that_cannot_be_are_refused() {
    let d = Disc::new(Vector::new([2.0, 2.0]), Vector::new([0.0, 0.0]), 0.5);
    let mut sim = Simulation::new(&[d], SimBox::walls([4.0, 4.0]), Options::default()).unwrap();
    for (f, want) in [
        (
            Gravity { axis: 2, g: -1.0 },
            "axis must be below the dimension 2",
        ),
        (
            Gravity { axis: 1, g: 0.0 },
            "g must be a finite number other than 0",
        ),
        (
            Gravity {
                axis: 1,
                g: f64::NAN,
            },
            "found NaN",
        ),
    ] {
        let e = sim.set_gravity(Some(f)).unwrap_err();
        assert!(matches!(e, Error::BadField(_)), "{e}");
        assert!(e.to_string().contains(want), "{e}");
    }
    let mut periodic =
        Simulation::new(&[d], SimBox::periodic([4.0, 4.0]), Options::default()).unwrap();
    let e = periodic.set_gravity(down(-1.0)).unwrap_err();
    assert!(e.to_string().contains("fall for ever"), "{e}");
    let mut well = Simulation::with_potential_at(
        &[d],
        SimBox::walls([4.0, 4.0]),
        &[],
        &Potential::single(0, 0, 1.5, -1.0),
        Options::default(),
        0.0,
    )
    .unwrap();
    let e = well.set_gravity(down(-1.0)).unwrap_err();
    assert!(e.to_string().contains("stepped potential"), "{e}");
    // Inelastic collisions in a field need the TC model and walls that do not stop discs dead.
    sim.set_gravity(down(-1.0)).unwrap();
    let e = sim
        .set_restitution(Some(Restitution::constant(0.5)))
        .unwrap_err();
    assert!(e.to_string().contains("TC model"), "{e}");
    let e = sim
        .set_restitution(Some(Restitution {
            wall: 0.0,
            tc: 1e-3,
            ..Default::default()
        }))
        .unwrap_err();
    assert!(e.to_string().contains("above 0"), "{e}");
}
