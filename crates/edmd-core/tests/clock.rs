//! What the clock guarantees at large absolute times.
//!
//! A state file that carried `# edmd time 1e16` ran with `--check`, exited 0 and wrote
//! overlapping discs that edmd then refused: at t = 1e16 consecutive floating-point times are 2
//! apart, so no event time could put a pair at contact. Times from `Simulation::clock_limit` on
//! are now refused, and a state that a run wrote at a time below it reads back.

use edmd_core::{Disc, Error, Options, SimBox, Simulation, Vector, OVERLAP_TOLERANCE};

use crate::support::random_discs;

/// The spacing of floating-point numbers at `t` (`ulp(t)`, for `t > 0`).
fn ulp(t: f64) -> f64 {
    f64::from_bits(t.to_bits() + 1) - t
}

/// Two discs closing head on in a box of side `l`.
fn two_discs(speed: f64, radius: f64, l: f64) -> Vec<Disc> {
    vec![
        Disc::new(
            Vector::new([0.25 * l, 0.5 * l]),
            Vector::new([speed, 0.0]),
            radius,
        ),
        Disc::new(
            Vector::new([0.75 * l, 0.5 * l]),
            Vector::new([-speed, 0.0]),
            radius,
        ),
    ]
}

#[test]
fn the_clock_limit_is_the_first_time_whose_spacing_exceeds_the_tolerance() {
    for (speed, radius) in [(4.0, 0.5), (0.01, 0.02), (1e-3, 1e-4), (123.0, 0.03)] {
        let sim = Simulation::new(
            &two_discs(speed, radius, 10.0),
            SimBox::walls([10.0, 10.0]),
            Options::default(),
        )
        .unwrap();
        let limit = sim.clock_limit();
        let allowed = OVERLAP_TOLERANCE * 2.0 * radius / speed;
        let below = f64::from_bits(limit.to_bits() - 1);
        assert!(
            ulp(below) * speed <= OVERLAP_TOLERANCE * 2.0 * radius,
            "{speed} {radius}"
        );
        assert!(
            ulp(limit) > allowed,
            "{speed} {radius}: the limit could be later"
        );
        assert!(sim.check_clock(below).is_ok());
        assert!(matches!(
            sim.check_clock(limit),
            Err(Error::ClockResolution { .. })
        ));
    }
    // Unit discs at speed 4: 2^21.
    let sim = Simulation::new(
        &two_discs(4.0, 0.5, 10.0),
        SimBox::walls([10.0, 10.0]),
        Options::default(),
    )
    .unwrap();
    assert_eq!(sim.clock_limit(), 2f64.powi(21));
    // Nothing moves: every time is resolved.
    let still = Simulation::new(
        &two_discs(0.0, 0.1, 1.0),
        SimBox::walls([1.0, 1.0]),
        Options::default(),
    )
    .unwrap();
    assert_eq!(still.clock_limit(), f64::INFINITY);
}

#[test]
fn states_at_times_from_1e13_to_1e17_are_refused() {
    // Princeton's p10.txt: discs of radius 0.02 at speeds of about 0.01.
    let discs = two_discs(0.01, 0.02, 1.0);
    for t0 in [1e13, 1e14, 1e15, 1e16, 1e17] {
        let built = Simulation::with_barriers_at(
            &discs,
            SimBox::walls([1.0, 1.0]),
            &[],
            Options::default(),
            t0,
        );
        match built {
            Err(Error::ClockResolution { time, limit }) => {
                assert_eq!(time, t0);
                assert!(limit < 1e9, "{limit}");
            }
            other => panic!("t0 = {t0}: {:?}", other.map(|s| s.time())),
        }
        let mut sim =
            Simulation::new(&discs, SimBox::walls([1.0, 1.0]), Options::default()).unwrap();
        assert!(matches!(
            sim.start_at(t0),
            Err(Error::ClockResolution { .. })
        ));
    }
}

#[test]
fn a_state_written_late_reads_back_and_runs_without_overlaps() {
    // A dense fluid of unit-speed discs, started at 10^5 (below its limit of about 10^6) and
    // continued twice from the state it wrote, as chained runs do.
    let discs = random_discs(150, 20.0, 0.5, 0.5, false, 7);
    let bx = SimBox::periodic([20.0, 20.0]);
    let mut t = 1e5;
    let mut state = discs;
    for _ in 0..3 {
        let mut sim = Simulation::with_barriers_at(&state, bx, &[], Options::default(), t).unwrap();
        assert_eq!(sim.time(), t);
        assert!(t < sim.clock_limit());
        sim.run_until(t + 200.0, &mut ());
        assert!(sim.stats().disc_disc > 10_000, "{:?}", sim.stats());
        let o = sim.overlaps(OVERLAP_TOLERANCE);
        assert_eq!(o.count, 0, "{:?}", o.first);
        t = sim.time();
        state = sim.discs();
    }
}
