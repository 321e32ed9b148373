//! Hard rods on a line (`D = 1`): the exact Tonks equation of state from the collision virial,
//! the conservation laws, the exchange of velocities at each collision of equal masses, the
//! generator and exact checkpoints.

use edmd_core::measure::theory::tonks_z;
use edmd_core::measure::{kinetic_temperature, Pressure};
use edmd_core::setup::lattice::{lattice_fluid_in, rods};
use edmd_core::setup::packing_of;
use edmd_core::{
    checkpoint_dim, Boundary, Disc, EventKind, EventRecord, Observer, Options, SimBox, Simulation,
    Vector,
};

/// A periodic line of `n` rods (length 1, mass 1, kT = 1) covering the fraction `eta`.
fn line(n: usize, eta: f64, boundary: Boundary, seed: u64) -> Simulation<1> {
    let (discs, bx) = rods(n, eta, boundary, seed).unwrap();
    Simulation::new(&discs, bx, Options::default()).unwrap()
}

/// Runs until `count` more rod-rod collisions have happened.
fn run_collisions(sim: &mut Simulation<1>, count: u64, obs: &mut dyn Observer<1>) {
    let target = sim.stats().disc_disc + count;
    while sim.stats().disc_disc < target {
        sim.run_events(1000, &mut &mut *obs);
    }
}

/// Tonks (Phys. Rev. 50, 955 (1936)): hard rods of length sigma on a line of length L are
/// points on the free length `L - N sigma`, so `Z = P L / (N kT) = 1 / (1 - eta)` exactly, at
/// any N. The virial measures it: with equal masses each collision exchanges the velocities,
/// so the rods' velocities are the points' and the pair `(k, l)` meets `|v_k - v_l| / (L - N
/// sigma)` times per unit time with `r.J = sigma m |v_k - v_l|`; the sum over pairs gives
/// `Z - 1 = eta / (1 - eta)` for zero total momentum, whatever the velocities. So the only error
/// is that of sampling the meetings over a finite time: with 400 rods and 200 collisions per
/// rod the blocks scatter by about 0.2 % of Z. Tolerance: 1 % of Z, and 4 standard errors.
#[test]
fn the_virial_pressure_of_hard_rods_is_tonks_exact_equation_of_state() {
    let n = 400;
    for (k, eta) in [0.2, 0.5, 0.8].into_iter().enumerate() {
        let mut sim = line(n, eta, Boundary::Periodic, 11 + k as u64);
        assert!((packing_of(&sim.discs(), sim.sim_box()) - eta).abs() < 1e-12);
        run_collisions(&mut sim, 20 * n as u64, &mut ());
        let mut p = Pressure::new(&sim);
        for _ in 0..20 {
            run_collisions(&mut sim, 10 * n as u64, &mut p);
            p.sample(&sim);
        }
        let s = p.summary();
        let exact = tonks_z(eta);
        let dev = s.z.value - exact;
        eprintln!(
            "eta {eta}: Z = {:.5} +- {:.5}, Tonks {exact:.5} ({:+.3} %)",
            s.z.value,
            s.z.error,
            100.0 * dev / exact
        );
        assert!(
            dev.abs() < 0.01 * exact,
            "eta {eta}: Z {} vs {exact}",
            s.z.value
        );
        assert!(
            dev.abs() < 4.0 * s.z.error.max(1e-4 * exact),
            "eta {eta}: Z {} +- {} vs {exact}",
            s.z.value,
            s.z.error
        );
        assert!((s.kt - 1.0).abs() < 1e-9, "kT {}", s.kt);
    }
}

/// Between walls the rods' configurations are those of `N` points on the free length
/// `L - N sigma`, so the exact (canonical) pressure is `P = N kT / (L - N sigma)` (Tonks 1936),
/// which the walls' impulses measure directly; the virial with the effective length `L - sigma`
/// (the line the centres reach) gives the same (Pressure's documentation). A run holds its
/// energy fixed, which changes the pressure by a relative `O(1/N)`: at N = 200 with 400
/// collisions per rod, 1.5 % covers both that and the sampling.
#[test]
fn wall_and_virial_pressures_of_rods_between_walls_agree() {
    let n = 200;
    let eta = 0.5;
    let mut sim = line(n, eta, Boundary::Walls, 5);
    run_collisions(&mut sim, 20 * n as u64, &mut ());
    let mut p = Pressure::new(&sim);
    for _ in 0..20 {
        run_collisions(&mut sim, 20 * n as u64, &mut p);
        p.sample(&sim);
    }
    let s = p.summary();
    let length = sim.sim_box().lengths[0];
    let tonks = n as f64 * s.kt / (length - n as f64);
    let wall = s.wall.unwrap().value;
    eprintln!(
        "walls: P_wall {wall:.5}, P_virial {:.5}, Tonks {tonks:.5}",
        s.virial.value
    );
    assert!((wall / s.virial.value - 1.0).abs() < 0.015);
    assert!((wall / tonks - 1.0).abs() < 0.015);
}

/// Checks at each pair event that the two rods swapped velocities (equal masses, head-on: the
/// elastic rule gives each the other's velocity). The engine's impulse is the general
/// `2 mu (dv . dr) dr / |dr|^2`, and the contact distance `|dr|` carries the positions' rounding,
/// so each new velocity is the other's old one to a few units in the last place:
/// `1e-14` of the speed is the bound (an ulp of a speed near 1 is `2.2e-16`).
#[derive(Default)]
struct Exchanges {
    before: Vec<f64>,
    count: usize,
    worst: f64,
}

impl Observer<1> for Exchanges {
    fn on_event(&mut self, e: &EventRecord<1>, sim: &Simulation<1>) {
        if let EventKind::DiscDisc { i, j } = e.kind {
            let (vi, vj) = (sim.velocity(i)[0], sim.velocity(j)[0]);
            let scale = self.before[i].abs().max(self.before[j].abs());
            let off = (vi - self.before[j]).abs().max((vj - self.before[i]).abs());
            self.worst = self.worst.max(off / scale);
            self.count += 1;
        }
        self.before = (0..sim.len()).map(|k| sim.velocity(k)[0]).collect();
    }
}

#[test]
fn equal_rods_exchange_velocities_and_conserve_energy_and_momentum() {
    let mut sim = line(100, 0.6, Boundary::Periodic, 3);
    let (e0, p0) = (sim.kinetic_energy(), sim.momentum()[0]);
    let mut speeds: Vec<f64> = sim.discs().iter().map(|d| d.vel[0]).collect();
    let mut obs = Exchanges {
        before: speeds.clone(),
        ..Default::default()
    };
    run_collisions(&mut sim, 20_000, &mut obs);
    assert!(obs.count >= 20_000);
    assert!(
        obs.worst < 1e-14,
        "worst relative exchange error {}",
        obs.worst
    );
    // Velocities are only ever exchanged: the set of them is the set at the start.
    let mut now: Vec<f64> = sim.discs().iter().map(|d| d.vel[0]).collect();
    speeds.sort_by(f64::total_cmp);
    now.sort_by(f64::total_cmp);
    for (a, b) in speeds.iter().zip(&now) {
        assert!((a - b).abs() < 1e-12, "{a} became {b}");
    }
    assert!((sim.kinetic_energy() / e0 - 1.0).abs() < 1e-12);
    assert!((sim.momentum()[0] - p0).abs() < 1e-12);
    assert_eq!(sim.overlaps(1e-9).count, 0);
    // Rods never pass each other: their order round the ring never changes.
    let xs: Vec<f64> = sim.discs().iter().map(|d| d.pos[0]).collect();
    let descents = (0..xs.len())
        .filter(|&k| xs[(k + 1) % xs.len()] < xs[k])
        .count();
    assert_eq!(descents, 1, "the rods' cyclic order changed");
}

#[test]
fn unequal_rods_obey_the_one_dimensional_elastic_rule() {
    // m1 = 1 at +2, m2 = 3 at 0, head-on: v1' = (m1 - m2) / (m1 + m2) v1 = -1,
    // v2' = 2 m1 / (m1 + m2) v1 = 1 (both exact in binary).
    let mut a = Disc::new(Vector([1.0]), Vector([2.0]), 0.5);
    a.mass = 1.0;
    let mut b = Disc::new(Vector([4.0]), Vector([0.0]), 0.5);
    b.mass = 3.0;
    let mut sim = Simulation::new(&[a, b], SimBox::walls([10.0]), Options::default()).unwrap();
    sim.run_until(1.25, &mut ());
    assert_eq!(sim.stats().disc_disc, 1);
    assert_eq!(sim.velocity(0)[0], -1.0);
    assert_eq!(sim.velocity(1)[0], 1.0);
    assert_eq!(sim.kinetic_energy(), 2.0);
}

#[test]
fn a_checkpoint_of_rods_continues_bit_for_bit() {
    for boundary in [Boundary::Periodic, Boundary::Walls] {
        let mut sim = line(300, 0.7, boundary, 9);
        let mut straight = sim.clone();
        straight.run_until(40.0, &mut ());
        sim.run_until(13.0, &mut ());
        let bytes = sim.to_checkpoint(b"rods");
        assert_eq!(checkpoint_dim(&bytes).unwrap(), 1);
        let (mut resumed, extra) = Simulation::<1>::from_checkpoint(&bytes).unwrap();
        assert_eq!(extra, b"rods");
        resumed.run_until(40.0, &mut ());
        assert!(straight.stats().disc_disc > 10_000);
        assert_eq!(resumed.stats(), straight.stats());
        assert_eq!(resumed.to_checkpoint(b""), straight.to_checkpoint(b""));
        // A 1D checkpoint is not read as 2D.
        assert!(Simulation::<2>::from_checkpoint(&bytes).is_err());
    }
}

#[test]
fn the_rod_generator_is_seeded_even_and_at_rest_as_a_whole() {
    let (a, bx) = rods(50, 0.4, Boundary::Walls, 7).unwrap();
    let (b, _) = rods(50, 0.4, Boundary::Walls, 7).unwrap();
    let (c, _) = rods(50, 0.4, Boundary::Walls, 8).unwrap();
    assert_eq!(a, b);
    assert_ne!(a, c);
    assert_eq!(bx.lengths, [125.0]);
    let gap = 125.0 / 50.0;
    for (k, d) in a.iter().enumerate() {
        assert!((d.pos[0] - (k as f64 + 0.5) * gap).abs() < 1e-12);
    }
    let p: f64 = a.iter().map(|d| d.mass * d.vel[0]).sum();
    assert!(p.abs() < 1e-12);
    let sim = Simulation::new(&a, bx, Options::default()).unwrap();
    assert!((kinetic_temperature(&sim) - 1.0).abs() < 1e-12);
    // The generic entry point makes the same line.
    let (d, bx1) = lattice_fluid_in::<1>(50, 0.4, Boundary::Walls, 7).unwrap();
    assert_eq!((d, bx1), (a, bx));
    assert!(rods(10, 1.0, Boundary::Periodic, 1).is_err());
    assert!(rods(0, 0.5, Boundary::Periodic, 1).is_err());
}
