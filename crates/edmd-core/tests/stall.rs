//! Issue 10: time that stops advancing hung the program. A disc as wide as the box is refused
//! when the simulation is built; discs jammed so that their events all fall at one instant stop
//! the run with a [`Stall`] naming them, within the documented limit of events.

use edmd_core::simulation::{Stall, MIN_STALL_EVENTS};
use edmd_core::{Disc, Error, Options, SimBox, Simulation, Vector};

fn disc<const D: usize>(pos: [f64; D], vel: [f64; D], radius: f64) -> Disc<D> {
    Disc {
        pos: Vector::new(pos),
        vel: Vector::new(vel),
        mass: 1.0,
        radius,
        colour: [0, 0, 0],
        species: 0,
    }
}

/// A column of `n` touching discs of diameter 1 filling the height of a `5 x n` walled box,
/// moving up and down at different speeds.
fn column(n: usize) -> Simulation {
    let discs: Vec<Disc> = (0..n)
        .map(|k| disc([2.5, 0.5 + k as f64], [0.0, 0.3 - 0.1 * k as f64], 0.5))
        .collect();
    Simulation::new(&discs, SimBox::walls([5.0, n as f64]), Options::default()).unwrap()
}

/// A `k x k` square lattice of touching discs of diameter 1 filling a `k x k` walled box.
fn square_lattice(k: usize) -> Simulation {
    let mut discs = Vec::new();
    for i in 0..k {
        for j in 0..k {
            let (a, b) = (i as f64, j as f64);
            discs.push(disc(
                [0.5 + a, 0.5 + b],
                [
                    ((a * 7.0 + b * 3.0) % 5.0) - 2.0,
                    ((a * 3.0 + b) % 3.0) - 1.0,
                ],
                0.5,
            ));
        }
    }
    let kf = k as f64;
    Simulation::new(&discs, SimBox::walls([kf, kf]), Options::default()).unwrap()
}

/// Asserts a stall at time 0 within the limit plus one chunk and the sample, naming `named`.
fn assert_stalled(sim: &Simulation, named: &[usize], count: usize) -> Stall {
    let s = sim.stalled().expect("the run stalled").clone();
    assert_eq!(s.time, 0.0);
    assert!(s.events > sim.stall_limit(), "{s:?}");
    assert!(s.events < sim.stall_limit() + 2 * (1 << 16) + 4096, "{s:?}");
    assert_eq!(s.discs, named, "{s}");
    assert_eq!(s.count, count, "{s}");
    assert_eq!(sim.time(), 0.0, "the clock must stay where it stopped");
    let text = s.to_string();
    assert!(text.contains("clock stopped advancing at t = 0"), "{text}");
    assert!(text.contains("discs 0, 1, 2"), "{text}");
    s
}

// Regression (issue 10): a disc of radius exactly half the box (`1` / `0.5 0.5 0.01 0 0.5 ...`)
// bounced between the walls at one instant for ever. Refused now, in 2D and 3D; on a periodic
// axis the cell grid refuses any box under 3 diameters.
#[test]
fn disc_as_wide_as_the_box_is_refused() {
    let d = [disc([0.5, 0.5], [0.01, 0.0], 0.5)];
    assert_eq!(
        Simulation::new(&d, SimBox::unit(), Options::default()).unwrap_err(),
        Error::DiscFillsBox {
            index: 0,
            axis: 0,
            diameter: 1.0,
            length: 1.0
        }
    );
    let d = [disc([0.5, 1.0], [0.0, 1.0], 0.5)];
    assert!(matches!(
        Simulation::new(&d, SimBox::walls([2.0, 1.0]), Options::default()),
        Err(Error::DiscFillsBox { axis: 1, .. })
    ));
    let d = [disc([1.0, 1.0, 0.5], [0.0, 0.0, 1.0], 0.5)];
    assert!(matches!(
        Simulation::new(&d, SimBox::walls([2.0, 2.0, 1.0]), Options::default()),
        Err(Error::DiscFillsBox { axis: 2, .. })
    ));
    let d = [disc([0.5, 0.5], [0.01, 0.0], 0.5)];
    assert!(matches!(
        Simulation::new(&d, SimBox::periodic([1.0, 1.0]), Options::default()),
        Err(Error::PeriodicBoxTooSmall { .. })
    ));
    // Just narrower than the box: it moves, and the clock advances.
    let d = [disc([0.5, 0.5], [1.0, 0.0], 0.499)];
    let mut sim = Simulation::new(&d, SimBox::walls([1.0, 2.0]), Options::default()).unwrap();
    sim.run_until(1.0, &mut ());
    assert!(sim.stalled().is_none());
    assert!((499..=501).contains(&sim.stats().wall), "{:?}", sim.stats());
}

// Regression (issue 10): a column of touching discs filling the box's height collided at one
// instant for ever, and `run_until` never returned.
#[test]
fn jammed_column_stops_and_names_its_discs() {
    let mut sim = column(10);
    sim.run_until(10.0, &mut ());
    let s = assert_stalled(&sim, &[0, 1, 2, 3, 4, 5, 6, 7], 10);
    // Stalled for good: nothing more happens, the clock stays.
    let stats = sim.stats();
    sim.run_until(20.0, &mut ());
    assert_eq!(sim.run_events(100, &mut ()), 0);
    assert!(sim.step(30.0).is_none());
    assert_eq!(sim.stats(), stats);
    assert_eq!(sim.time(), 0.0);
    assert_eq!(sim.stalled(), Some(&s));
}

// Regression (issue 10): a 20 x 20 square lattice of touching discs filling the box never
// ended.
#[test]
fn jammed_square_lattice_stops() {
    let mut sim = square_lattice(20);
    assert_eq!(sim.stall_limit(), MIN_STALL_EVENTS);
    sim.run_until(1.0, &mut ());
    let s = sim.stalled().expect("stalled");
    assert!(
        s.count >= 2 && s.discs.len() == s.count.min(Stall::NAMED),
        "{s}"
    );
}

// Event by event (`step`), as the viewer goes, the count is kept as the loops keep it, by
// chunks of 65 536 events counted from the start (so stepping and running agree), and the stall
// names the discs with an event pending at that instant. The column jams at t = 0, so the
// first chunk past 10^6 events stops it: 16 chunks.
#[test]
fn stepping_a_jammed_column_stops() {
    let mut sim = column(10);
    let mut k = 0u64;
    let stop = 16 * 65_536;
    assert!(stop > MIN_STALL_EVENTS && stop - 65_536 <= MIN_STALL_EVENTS);
    while sim.step(10.0).is_some() {
        k += 1;
        assert!(k <= stop, "step never stopped");
    }
    assert_eq!(k, stop);
    let s = sim.stalled().expect("stalled");
    assert_eq!(s.events, stop);
    assert!(!s.discs.is_empty());
    // Running gets there at the same event.
    let mut run = column(10);
    run.run_until(10.0, &mut ());
    let r = run.stalled().expect("stalled");
    // The loop runs 4096 events more to name the discs.
    assert_eq!((r.time, r.events), (s.time, stop + 4096));
}

// Many simultaneous events are not a stall: a square lattice of touching discs all moving
// alike (so never colliding), one disc in the middle of each cell, crosses cell boundaries all
// at once, 900 events at a time, many times over; the count starts again at each instant.
#[test]
fn simultaneous_events_are_not_a_stall() {
    let mut discs = Vec::new();
    for i in 0..30 {
        for j in 0..30 {
            discs.push(disc(
                [1.0 + 2.0 * i as f64, 1.0 + 2.0 * j as f64],
                [1.0, 0.5],
                1.0,
            ));
        }
    }
    let mut sim =
        Simulation::new(&discs, SimBox::periodic([60.0, 60.0]), Options::default()).unwrap();
    assert_eq!(sim.grid_dims(), [30, 30]);
    sim.run_until(200.0, &mut ());
    assert!(sim.stalled().is_none());
    assert_eq!(sim.time(), 200.0);
    assert_eq!(sim.stats().disc_disc, 0);
    assert!(sim.stats().cell_crossing >= 130_000, "{:?}", sim.stats());
}

// The count of events in a row is part of the state: a run checkpointed in the middle of a
// stall and continued stops exactly where the run that was never checkpointed stops (without
// the count it would go on for 500 000 events more), and a stalled state reads back stalled.
#[test]
fn stall_count_survives_a_checkpoint() {
    let mut sim = column(10);
    assert_eq!(sim.run_events(500_000, &mut ()), 500_000);
    assert!(sim.stalled().is_none());
    let (mut resumed, _) = Simulation::<2>::from_checkpoint(&sim.to_checkpoint(b"")).unwrap();
    sim.run_until(10.0, &mut ());
    resumed.run_until(10.0, &mut ());
    assert!(sim.stalled().is_some());
    assert_eq!(resumed.stalled(), sim.stalled());
    assert_eq!(resumed.stats(), sim.stats());
    let bytes = resumed.to_checkpoint(b"");
    assert_eq!(bytes, sim.to_checkpoint(b""));
    let (mut again, _) = Simulation::<2>::from_checkpoint(&bytes).unwrap();
    assert_eq!(again.stalled(), sim.stalled());
    assert_eq!(again.run_events(10, &mut ()), 0);
    assert_eq!(again.to_checkpoint(b""), bytes);
}

/// Velocities in (-1, 1) from a fixed sequence (a 64-bit linear congruential generator, Knuth's
/// MMIX constants), so that no two discs move alike.
fn scrambled(k: usize) -> Vec<[f64; 2]> {
    let mut x: u64 = 12345;
    let mut next = || {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    (0..k).map(|_| [next(), next()]).collect()
}

/// Regression (issue 10, found again by a review): a 20 x 20 lattice of
/// touching discs of radius 0.025 filling the unit box, with random velocities, and a column of
/// 20 such discs filling its height. Their events are not at one instant: the discs collide
/// across gaps of rounding size (1e-17), so millions of events moved the clock by 1e-12 in all
/// and `edmd run --until 10` would have taken years. They now stop as creeping stalls.
#[test]
fn touching_discs_with_random_velocities_stop_as_a_creeping_clock() {
    use edmd_core::simulation::StallCause;
    let r = 0.025;
    let v = scrambled(400);
    let mut lattice = Vec::new();
    for i in 0..20 {
        for j in 0..20 {
            let c = |k: usize| r + 2.0 * r * k as f64;
            lattice.push(disc([c(i), c(j)], v[20 * i + j], r));
        }
    }
    let column: Vec<Disc> = (0..20)
        .map(|k| disc([0.5, r + 2.0 * r * k as f64], v[k], r))
        .collect();
    for discs in [lattice, column] {
        let mut sim = Simulation::new(&discs, SimBox::unit(), Options::default()).unwrap();
        let start = std::time::Instant::now();
        sim.run_until(10.0, &mut ());
        let s = sim.stalled().expect("the run stalled").clone();
        assert_eq!(s.cause, StallCause::Creep, "{s}");
        assert!(s.time < 1e-9, "{s}");
        assert!(s.events > sim.stall_limit(), "{s:?}");
        assert!(!s.discs.is_empty(), "{s:?}");
        let text = s.to_string();
        assert!(text.contains("the clock stopped advancing"), "{text}");
        assert!(text.contains("jammed"), "{text}");
        // A few seconds at most in the optimised test build.
        assert!(start.elapsed().as_secs() < 20, "{:?}", start.elapsed());
        // Stopped the same way event by event.
        let mut stepped = Simulation::new(&discs, SimBox::unit(), Options::default()).unwrap();
        while stepped.step(10.0).is_some() {}
        assert_eq!(stepped.stalled().map(|s| s.cause), Some(StallCause::Creep));
    }
}

/// The creep bound leaves dense fluids alone: a fluid at packing 0.7 runs its course.
#[test]
fn a_dense_fluid_does_not_count_as_creeping() {
    let (discs, bx) =
        edmd_core::setup::lattice_fluid(400, 0.7, edmd_core::Boundary::Periodic, 3).unwrap();
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    sim.run_until(20.0, &mut ());
    assert!(sim.stalled().is_none());
    assert_eq!(sim.time(), 20.0);
    assert!(sim.stats().disc_disc > 50_000, "{:?}", sim.stats());
}

/// The creep bound follows the kinetic energy when the velocities are changed: a fluid whose
/// speeds are raised 10^13-fold (`modify_velocities`, as Python's `velocities` setter does)
/// runs its course as before, in a 10^13th of the time, where the bound kept from the start
/// took its chunks of events for a creeping clock (a stall after 1 052 672 events).
#[test]
fn a_fluid_made_faster_does_not_count_as_creeping() {
    let (discs, bx) =
        edmd_core::setup::lattice_fluid(400, 0.7, edmd_core::Boundary::Periodic, 3).unwrap();
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    let fast = 1e13;
    sim.modify_velocities(|_, v| v * fast);
    sim.run_until(600.0 / fast, &mut ());
    assert!(sim.stalled().is_none(), "{:?}", sim.stalled());
    assert!(sim.stats().disc_disc > 1_500_000, "{:?}", sim.stats());
}
