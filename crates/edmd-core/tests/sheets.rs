//! One-dimensional self-gravity: the sheet model's exact two-body motion, energy and momentum
//! conserved to rounding, the order kept, the virial theorem, exact checkpoints, and the
//! refusals.

use edmd_core::setup::sheets::WaterBag;
use edmd_core::{
    Andersen, Disc, Error, EventKind, Gravity, Options, Restitution, SelfGravity, SimBox,
    Simulation, Vector,
};

fn bag(n: usize, seed: u64) -> Simulation<1> {
    let (discs, sim_box) = WaterBag {
        n,
        width: 1.0,
        speed: 0.5,
        radius: 1e-4,
        coupling: 1.0,
        seed,
    }
    .build()
    .unwrap();
    let mut sim = Simulation::new(&discs, sim_box, Options::default()).unwrap();
    sim.set_self_gravity(Some(SelfGravity { coupling: 1.0 }))
        .unwrap();
    sim
}

fn energy(sim: &Simulation<1>) -> f64 {
    sim.kinetic_energy() + sim.potential_energy()
}

#[test]
fn two_sheets_fall_together_and_bounce_at_the_closed_form_times() {
    // Two unit masses at rest, their gap 2 beyond contact, coupling 0.5: each is pulled at 0.5
    // towards the other, so the gap closes as 2 - t^2 / 2 and they meet at t = 2, at speeds 1.
    // They exchange velocities, fly apart to the same gap at t = 4 and meet again at t = 6.
    let r = 0.25;
    let discs = [
        Disc::new(Vector::new([4.0]), Vector::new([0.0]), r),
        Disc::new(Vector::new([6.5]), Vector::new([0.0]), r),
    ];
    let mut sim = Simulation::new(&discs, SimBox::walls([20.0]), Options::default()).unwrap();
    sim.set_self_gravity(Some(SelfGravity { coupling: 0.5 }))
        .unwrap();
    assert_eq!(sim.acceleration(0), Vector::new([0.5]));
    assert_eq!(sim.acceleration(1), Vector::new([-0.5]));
    // The sheets' energy: coupling times their separation less the contact distance.
    assert!((sim.potential_energy() - 0.5 * 2.0).abs() < 1e-15);
    let mut times = Vec::new();
    while times.len() < 3 {
        let e = sim.step(100.0).expect("an event");
        assert!(matches!(e.kind, EventKind::DiscDisc { .. }), "{e:?}");
        times.push(e.time);
    }
    for (t, want) in times.iter().zip([2.0, 6.0, 10.0]) {
        assert!((t - want).abs() < 1e-14, "{times:?}");
    }
    sim.run_until(4.0 + 8.0, &mut ());
    // At t = 12 (a turning point): at rest, back where they started.
    assert!(
        (sim.position(0)[0] - 4.0).abs() < 1e-13,
        "{:?}",
        sim.position(0)
    );
    assert!(
        (sim.position(1)[0] - 6.5).abs() < 1e-13,
        "{:?}",
        sim.position(1)
    );
    assert!(sim.velocity(0)[0].abs() < 1e-13);
}

#[test]
fn a_water_bag_conserves_energy_and_momentum_and_keeps_its_order() {
    let mut sim = bag(200, 3);
    let (e0, p0) = (energy(&sim), sim.momentum()[0]);
    let scale = sim.kinetic_energy().max(sim.potential_energy());
    let mut events = 0;
    for k in 1..=20 {
        sim.run_until(5.0 * k as f64, &mut ());
        // The order is kept: ranks never change and neighbours in order never overlap.
        assert_eq!(sim.overlaps(edmd_core::OVERLAP_TOLERANCE).count, 0);
        let e = energy(&sim);
        // Rounding over about 10^6 events, each exact to a few ulps of the energy scale.
        assert!(
            (e - e0).abs() < 1e-10 * scale,
            "t {}: {e} against {e0}",
            sim.time()
        );
        assert!(
            (sim.momentum()[0] - p0).abs() < 1e-10,
            "{}",
            sim.momentum()[0]
        );
        events = sim.stats().disc_disc;
    }
    assert!(events > 100_000, "{events} collisions");
    assert_eq!(sim.stats().wall, 0, "the box is out of the bag's reach");
    let mut by_rank: Vec<(usize, f64)> = (0..sim.len())
        .map(|i| (sim.rank(i).unwrap(), sim.position(i)[0]))
        .collect();
    by_rank.sort_by_key(|p| p.0);
    assert!(by_rank.windows(2).all(|w| w[0].1 < w[1].1));
}

#[test]
fn the_virial_theorem_holds_on_time_averages() {
    // U is homogeneous of degree 1 in the separations, so 2 <K> = <U> (Noullez et al.
    // check their integrator on it). 256 sheets from a water bag, averaged over 400 samples
    // after 20 crossing times: the ratio within 3% (the samples are correlated over a few
    // crossing times, about 20 independent blocks' worth).
    let mut sim = bag(256, 11);
    sim.run_until(40.0, &mut ());
    let (mut k, mut u) = (0.0, 0.0);
    for s in 1..=400 {
        sim.run_until(40.0 + 0.5 * s as f64, &mut ());
        k += sim.kinetic_energy();
        u += sim.potential_energy();
    }
    let ratio = 2.0 * k / u;
    assert!((ratio - 1.0).abs() < 0.03, "2<K>/<U> = {ratio}");
}

#[test]
fn checkpoints_continue_bit_for_bit() {
    let mut sim = bag(64, 5);
    sim.set_thermostat(Some(Andersen {
        kt: 0.1,
        rate: 0.2,
        seed: 9,
    }))
    .unwrap();
    sim.run_until(7.3, &mut ());
    let bytes = sim.to_checkpoint(&[]);
    let mut back = Simulation::<1>::from_checkpoint(&bytes).unwrap().0;
    assert_eq!(back.self_gravity(), Some(SelfGravity { coupling: 1.0 }));
    sim.run_until(20.0, &mut ());
    back.run_until(20.0, &mut ());
    assert_eq!(sim.stats(), back.stats());
    for i in 0..sim.len() {
        assert_eq!(sim.position(i), back.position(i));
        assert_eq!(sim.velocity(i), back.velocity(i));
        assert_eq!(sim.rank(i), back.rank(i));
    }
    assert_eq!(sim.to_checkpoint(&[]), back.to_checkpoint(&[]));
}

#[test]
fn a_checkpoint_whose_order_is_not_the_rods_is_refused() {
    let sim = bag(8, 2);
    let mut bytes = sim.to_checkpoint(&[]);
    // The order is the last n u32 before the caller's bytes (none here: a length of 0) and
    // the CRC; swap the first two ranks and fix the CRC.
    let n = sim.len();
    let end = bytes.len() - 4 - 8;
    let start = end - 4 * n;
    let (a, b) = (start, start + 4);
    for k in 0..4 {
        bytes.swap(a + k, b + k);
    }
    let body = bytes.len() - 4;
    let crc = crc32fast::hash(&bytes[..body]);
    bytes[body..].copy_from_slice(&crc.to_le_bytes());
    let err = Simulation::<1>::from_checkpoint(&bytes).unwrap_err();
    assert!(err.to_string().contains("meet at"), "{err}");
}

#[test]
fn what_self_gravity_does_not_go_with_is_refused() {
    let g = Some(SelfGravity { coupling: 1.0 });
    let d = [Disc::new(Vector::new([1.0]), Vector::new([0.0]), 0.1)];
    // A periodic line.
    let mut sim = Simulation::new(&d, SimBox::periodic([5.0]), Options::default()).unwrap();
    assert!(matches!(
        sim.set_self_gravity(g),
        Err(Error::BadSelfGravity(_))
    ));
    // Two dimensions.
    let d2 = [Disc::new(
        Vector::new([1.0, 1.0]),
        Vector::new([0.0, 0.0]),
        0.1,
    )];
    let mut sim2 = Simulation::new(&d2, SimBox::walls([5.0, 5.0]), Options::default()).unwrap();
    assert!(matches!(
        sim2.set_self_gravity(g),
        Err(Error::BadSelfGravity(_))
    ));
    // A coupling that cannot be.
    let mut sim = Simulation::new(&d, SimBox::walls([5.0]), Options::default()).unwrap();
    for c in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(sim
            .set_self_gravity(Some(SelfGravity { coupling: c }))
            .is_err());
    }
    // Beside a field or restitution, either way round.
    sim.set_gravity(Some(Gravity { axis: 0, g: -1.0 })).unwrap();
    assert!(sim.set_self_gravity(g).is_err());
    sim.set_gravity(None).unwrap();
    sim.set_self_gravity(g).unwrap();
    assert!(sim.set_gravity(Some(Gravity { axis: 0, g: -1.0 })).is_err());
    assert!(sim
        .set_restitution(Some(Restitution::constant(0.5)))
        .is_err());
    sim.set_self_gravity(None).unwrap();
    assert_eq!(sim.self_gravity(), None);
}

#[test]
fn switched_off_the_rods_fly_straight_again() {
    let mut sim = bag(50, 4);
    sim.run_until(3.0, &mut ());
    sim.set_self_gravity(None).unwrap();
    let ke = sim.kinetic_energy();
    sim.run_until(30.0, &mut ());
    assert!((sim.kinetic_energy() - ke).abs() < 1e-12 * ke);
    assert_eq!(sim.overlaps(edmd_core::OVERLAP_TOLERANCE).count, 0);
    assert!(sim.stats().cell_crossing > 0);
}

/// The sheet model as its definition reads, by brute force: point sheets that pass through
/// each other, each accelerated by `coupling (n_right - n_left)` from the order of the moment,
/// the next crossing the earliest root over the pairs adjacent in that order, every sheet moved
/// to it. Returns the sheets' positions and velocities at `t_end`, in order along the line.
fn passing_sheets(mut y: Vec<f64>, mut v: Vec<f64>, coupling: f64, t_end: f64) -> Vec<(f64, f64)> {
    let n = y.len();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| y[a].total_cmp(&y[b]));
    let mut t = 0.0;
    loop {
        let mut a = vec![0.0; n];
        for (r, &k) in order.iter().enumerate() {
            a[k] = coupling * ((n - 1 - r) as f64 - r as f64);
        }
        // The earliest crossing of neighbours: gap g + w s + A s^2 / 2 = 0, A < 0. (A pair
        // that has just crossed is in its new order, separating: its root is its next
        // crossing, after its flight apart and back.)
        let (mut next, mut at) = (f64::INFINITY, 0);
        for r in 0..n - 1 {
            let (k, l) = (order[r], order[r + 1]);
            let (g, w, acc) = (y[l] - y[k], v[l] - v[k], a[l] - a[k]);
            let s = ((w + (w * w - 2.0 * acc * g).max(0.0).sqrt()) / -acc).max(0.0);
            if s < next {
                (next, at) = (s, r);
            }
        }
        let step = next.min(t_end - t);
        for k in 0..n {
            y[k] += v[k] * step + 0.5 * a[k] * step * step;
            v[k] += a[k] * step;
        }
        t += step;
        if t >= t_end {
            return order.iter().map(|&k| (y[k], v[k])).collect();
        }
        order.swap(at, at + 1);
    }
}

#[test]
fn the_rods_move_as_sheets_passing_through_each_other() {
    // Twelve sheets from a water bag, against the brute-force sheet model above, over 600
    // crossings: the positions (rods' lengths taken out) and velocities along the line agree
    // to 1e-9. (The motion is chaotic: the two computations' rounding differences grow about
    // threefold per unit of time, 1e-12 after 200 crossings and 1e-10 after 600.)
    let sim0 = bag(12, 8);
    let y0 = sim0.sheet_positions().unwrap();
    let v0: Vec<f64> = (0..12).map(|i| sim0.velocity(i)[0]).collect();
    let t_end = 6.0;
    let want = passing_sheets(y0, v0, 1.0, t_end);
    let mut sim = sim0.clone();
    sim.run_until(t_end, &mut ());
    assert!(sim.stats().disc_disc > 500, "{:?}", sim.stats());
    let y = sim.sheet_positions().unwrap();
    let mut got: Vec<(f64, f64)> = (0..12).map(|i| (y[i], sim.velocity(i)[0])).collect();
    got.sort_by(|p, q| p.0.total_cmp(&q.0));
    for (g, w) in got.iter().zip(&want) {
        assert!(
            (g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9,
            "{got:?}\n{want:?}"
        );
    }
}

#[test]
fn sheets_have_no_clock_limit_and_start_at_any_time() {
    // Rods 2e-8 long at speeds near 0.5: as hard rods the clock could not place them from a
    // time near 2^-3 (`clock_limit`); sheets keep their order, and have no limit.
    let (discs, sim_box) = WaterBag {
        n: 50,
        width: 1.0,
        speed: 0.5,
        radius: 1e-8,
        coupling: 1.0 / 50.0,
        seed: 4,
    }
    .build()
    .unwrap();
    let hard = Simulation::new(&discs, sim_box, Options::default()).unwrap();
    let limit = hard.clock_limit();
    assert!(limit < 1.0, "{limit}");
    assert!(matches!(
        hard.check_clock(40.0),
        Err(Error::ClockResolution { .. })
    ));
    let mut sim = Simulation::new(&discs, sim_box, Options::default()).unwrap();
    sim.set_self_gravity(Some(SelfGravity {
        coupling: 1.0 / 50.0,
    }))
    .unwrap();
    assert_eq!(sim.clock_limit(), f64::INFINITY);
    sim.check_clock(1e6).unwrap();
    // A state at t = 40, far past the hard rods' limit, starts there and runs on in order.
    sim.start_at(40.0).unwrap();
    let e0 = energy(&sim);
    sim.run_until(45.0, &mut ());
    assert_eq!(sim.time(), 45.0);
    assert!(sim.stats().disc_disc > 100, "{:?}", sim.stats());
    assert!(((energy(&sim) - e0) / e0).abs() < 1e-12);
    assert_eq!(sim.overlaps(1e-9).count, 0);
}
