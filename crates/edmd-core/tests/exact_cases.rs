//! Hand-derived cases with exact answers.

use edmd_core::{CollisionCounter, CollisionRule, Disc, Options, SimBox, Simulation, Vector};

fn v(x: f64, y: f64) -> Vector {
    Vector::new([x, y])
}

#[test]
fn disc_aimed_at_a_corner_hits_two_walls_at_once() {
    // Box 10 x 10, R = 1, from (5, 5) at (1, 1): reaches (9, 9), touching both walls, at t = 4;
    // comes back along the diagonal to (5, 5) at t = 8, reaches (1, 1) at t = 12.
    let d = [Disc::new(v(5.0, 5.0), v(1.0, 1.0), 1.0)];
    let mut sim = Simulation::new(&d, SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
    let mut c = CollisionCounter::new(1);
    sim.run_until(4.0, &mut c);
    assert_eq!(c.wall[0], 2);
    assert_eq!(sim.velocity(0), v(-1.0, -1.0));
    sim.run_until(8.0, &mut c);
    assert_eq!(sim.position(0), v(5.0, 5.0));
    sim.run_until(12.0, &mut c);
    assert_eq!(c.wall[0], 4);
}

#[test]
fn head_on_equal_masses_exchange_velocities() {
    // Gap 4 - 2 = 2 closing at 2: contact at t = 1 at x = 4 and 6; then they move apart.
    let d = [
        Disc::new(v(3.0, 5.0), v(1.0, 0.0), 1.0),
        Disc::new(v(7.0, 5.0), v(-1.0, 0.0), 1.0),
    ];
    for rule in [CollisionRule::Elastic, CollisionRule::Swap] {
        let mut sim = Simulation::new(
            &d,
            SimBox::walls([10.0, 10.0]),
            Options {
                rule,
                ..Default::default()
            },
        )
        .unwrap();
        let mut c = CollisionCounter::new(2);
        sim.run_until(2.0, &mut c);
        assert_eq!(c.disc, vec![1, 1]);
        assert_eq!(sim.position(0), v(3.0, 5.0));
        assert_eq!(sim.position(1), v(7.0, 5.0));
        assert_eq!(sim.velocity(0), v(-1.0, 0.0));
    }
}

#[test]
fn oblique_collision_at_rest_target_goes_off_at_right_angles() {
    // Disc 0 at (2, 5 + 1) moving (1, 0) hits disc 1 at rest at (5 + sqrt 3, 5), radius 1 each:
    // contact when the centres are 2 apart, line of centres at 30 degrees below horizontal.
    // Contact point: x0 = 5 + sqrt3 - sqrt(4 - 1) = 5, at t = 3.
    let s3 = 3f64.sqrt();
    let d = [
        Disc::new(v(2.0, 6.0), v(1.0, 0.0), 1.0),
        Disc::new(v(5.0 + s3, 5.0), v(0.0, 0.0), 1.0),
    ];
    let mut sim = Simulation::new(&d, SimBox::walls([20.0, 20.0]), Options::default()).unwrap();
    let mut c = CollisionCounter::new(2);
    sim.run_until(3.0, &mut c);
    assert_eq!(c.disc, vec![1, 1]);
    // Elastic, equal masses: the target takes the normal component along n = (sqrt3/2, -1/2):
    // v1' = (v.n) n = (sqrt3/2)(sqrt3/2, -1/2) = (3/4, -sqrt3/4); v0' = (1/4, sqrt3/4).
    let (v0, v1) = (sim.velocity(0), sim.velocity(1));
    assert!((v1 - v(0.75, -s3 / 4.0)).norm2().sqrt() < 1e-14, "{v1:?}");
    assert!((v0 - v(0.25, s3 / 4.0)).norm2().sqrt() < 1e-14, "{v0:?}");
    assert!(
        v0.dot(v1).abs() < 1e-14,
        "equal masses leave at right angles"
    );
}

#[test]
fn periodic_boundary_carries_a_disc_round() {
    // Box 10 x 10 periodic, disc at (1, 1) moving (3, 0): after t = 3 it is at (0, 1) again
    // after wrapping once; unwrapped position 10.
    let d = [Disc::new(v(1.0, 1.0), v(3.0, 0.0), 0.5)];
    let mut sim = Simulation::new(&d, SimBox::periodic([10.0, 10.0]), Options::default()).unwrap();
    sim.run_until(3.0, &mut ());
    assert!(
        (sim.position(0) - v(0.0, 1.0)).norm2() < 1e-24,
        "{:?}",
        sim.position(0)
    );
    assert!((sim.unwrapped_position(0) - v(10.0, 1.0)).norm2() < 1e-24);
}

#[test]
fn pair_colliding_across_the_periodic_boundary() {
    // Discs at x = 0.5 and x = 9.5 in a periodic box of 10, radius 0.4: 1 apart through the
    // boundary, gap 0.2, closing at 2 -> contact at t = 0.1.
    let d = [
        Disc::new(v(0.5, 5.0), v(-1.0, 0.0), 0.4),
        Disc::new(v(9.5, 5.0), v(1.0, 0.0), 0.4),
    ];
    let mut sim = Simulation::new(&d, SimBox::periodic([10.0, 10.0]), Options::default()).unwrap();
    let mut c = CollisionCounter::new(2);
    sim.run_until(0.1 + 1e-12, &mut c);
    assert_eq!(c.disc, vec![1, 1]);
    assert_eq!(sim.velocity(0), v(1.0, 0.0));
}

#[test]
fn touching_discs_at_rest_stay_put() {
    let d = [
        Disc::new(v(2.0, 2.0), v(0.0, 0.0), 1.0),
        Disc::new(v(4.0, 2.0), v(0.0, 0.0), 1.0),
    ];
    let mut sim = Simulation::new(&d, SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
    assert_eq!(sim.next_event_time(), None);
    sim.run_until(100.0, &mut ());
    assert_eq!(sim.stats().disc_disc, 0);
    assert_eq!(sim.time(), 100.0);
}

#[test]
fn newtons_cradle_passes_the_momentum_down_the_line() {
    // Three touching discs at rest and a fourth coming in: with equal masses each binary
    // collision hands on the velocity, so the last disc leaves with it and the others stop.
    let d = [
        Disc::new(v(1.0, 5.0), v(1.0, 0.0), 0.5),
        Disc::new(v(4.0, 5.0), v(0.0, 0.0), 0.5),
        Disc::new(v(5.0, 5.0), v(0.0, 0.0), 0.5),
        Disc::new(v(6.0, 5.0), v(0.0, 0.0), 0.5),
    ];
    let mut sim = Simulation::new(&d, SimBox::walls([20.0, 10.0]), Options::default()).unwrap();
    sim.run_until(3.0, &mut ());
    assert_eq!(sim.stats().disc_disc, 3);
    assert_eq!(sim.velocity(3), v(1.0, 0.0));
    for i in 0..3 {
        assert_eq!(sim.velocity(i), v(0.0, 0.0));
    }
}
