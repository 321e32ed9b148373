//! Physics checked against physics: kinetic theory and the hard-disc equation of state.
//!
//! Every test has a fixed seed and states the formula it checks, its source and its tolerance.
//! Units: disc diameter `sigma = 1`, mass `m = 1`, `k_B = 1`, `kT = 1` (as
//! [`lattice_fluid`] sets up).

use crate::support::obs;
use edmd_core::measure::{
    kinetic_temperature, rayleigh_cdf, Collisions, Diffusion, Pressure, SpeciesHalves, Speeds,
    Temperature,
};
use edmd_core::setup::lattice_fluid;
use edmd_core::{Boundary, Options, SimBox, Simulation};
use std::f64::consts::PI;

use crate::support::{digest, random_discs};

/// Runs `sim` until there have been `per_disc` more collisions per disc.
fn melt(sim: &mut Simulation, per_disc: u64) {
    let target = sim.stats().disc_disc + per_disc * sim.len() as u64 / 2;
    while sim.stats().disc_disc < target {
        sim.run_until(sim.time() + 0.5, &mut ());
    }
}

/// A lattice fluid melted for `per_disc` collisions per disc.
fn melted(n: usize, packing: f64, boundary: Boundary, seed: u64, per_disc: u64) -> Simulation {
    let (discs, bx) = lattice_fluid(n, packing, boundary, seed).unwrap();
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    melt(&mut sim, per_disc);
    sim
}

/// Henderson's equation of state for hard discs, `Z = (1 + eta^2/8) / (1 - eta)^2`
/// (D. Henderson, Mol. Phys. 30, 971 (1975)).
fn henderson_z(eta: f64) -> f64 {
    (1.0 + eta * eta / 8.0) / (1.0 - eta).powi(2)
}

/// Henderson's contact value of the pair distribution, `g(sigma) = (1 - 7 eta/16) / (1 - eta)^2`.
/// It is his equation of state read through the hard-disc virial relation
/// `Z = 1 + 2 eta g(sigma)`: `Z - 1 = (2 eta - 7 eta^2/8) / (1 - eta)^2`.
fn henderson_contact(eta: f64) -> f64 {
    (1.0 - 7.0 * eta / 16.0) / (1.0 - eta).powi(2)
}

#[test]
fn henderson_contact_value_matches_his_equation_of_state() {
    for eta in [0.05, 0.2, 0.4, 0.6] {
        let z = 1.0 + 2.0 * eta * henderson_contact(eta);
        assert!((z - henderson_z(eta)).abs() < 1e-14, "eta {eta}");
    }
}

#[test]
fn speeds_relax_to_the_two_dimensional_maxwell_boltzmann_law() {
    // 2D Maxwell-Boltzmann (Rayleigh): f(v) = (m v / kT) exp(-m v^2 / 2kT),
    // F(v) = 1 - exp(-m v^2 / 2kT). Every disc starts with the same speed sqrt(2 kT / m)
    // (random directions, in opposite pairs so the momentum is zero, so kT = 1 exactly): far
    // from the law, which the dynamics alone must produce. After 40 collisions per disc, pool
    // 5 snapshots of 1000 discs taken 5 collisions per disc apart (collision frequency at
    // eta = 0.3 is about 2.4 per unit time). Kolmogorov-Smirnov: p > 0.01.
    let (mut discs, bx) = lattice_fluid(1000, 0.3, Boundary::Periodic, 11).unwrap();
    for k in (0..discs.len()).step_by(2) {
        let v = discs[k].vel * (2.0 / discs[k].vel.norm2()).sqrt();
        discs[k].vel = v;
        discs[k + 1].vel = -v;
    }
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    let kt = kinetic_temperature(&sim);
    assert!((kt - 1.0).abs() < 1e-12);
    let mut start = Speeds::new(40, 5.0);
    start.sample(&sim);
    let before = start.ks_rayleigh(kt);
    eprintln!(
        "speeds at the start: D = {:.3}, p = {:.1e}",
        before.statistic, before.p_value
    );
    assert!(before.p_value < 1e-10);
    melt(&mut sim, 40);
    let mut speeds = Speeds::new(40, 5.0);
    for _ in 0..5 {
        sim.run_until(sim.time() + 2.0, &mut ());
        speeds.sample(&sim);
    }
    let s = speeds.summary(kt);
    eprintln!(
        "speeds: n = {}, D = {:.4}, p = {:.3}; rms {:.4} (theory {:.4}), mean {:.4} (theory {:.4})",
        s.samples, s.ks.statistic, s.ks.p_value, s.rms, s.rms_theory, s.mean, s.mean_theory
    );
    assert_eq!(s.samples, 5000);
    assert!(s.ks.p_value > 0.01, "Rayleigh law rejected: {:?}", s.ks);
    // The rms speed is fixed by the energy: sqrt(2 kT / m) exactly for each snapshot.
    assert!((s.rms - s.rms_theory).abs() < 1e-12);
    // The same test rejects wrong laws: kT doubled, and kT off by 10 %.
    for (factor, p_max) in [(2.0, 1e-10), (1.1, 0.01)] {
        let wrong = speeds.ks_test(|v, m| rayleigh_cdf(v, m, factor * kt));
        eprintln!(
            "speeds against kT x {factor}: D = {:.4}, p = {:.2e}",
            wrong.statistic, wrong.p_value
        );
        assert!(
            wrong.p_value < p_max,
            "kT x {factor} not rejected: {wrong:?}"
        );
    }
}

#[test]
fn dilute_collision_frequency_agrees_with_enskog_theory() {
    // Enskog collision frequency per disc for hard discs (D. M. Gass, J. Chem. Phys. 54, 1898
    // (1971)): omega_E = 2 n sigma g(sigma) sqrt(pi kT / m), the Boltzmann rate 2 n sigma
    // <|v_12|> (2D mean relative speed sqrt(pi kT / m)) times Henderson's contact value. For hard
    // discs in equilibrium it is exact given the exact g(sigma), and Henderson's g(sigma) is
    // exact to O(eta^3) (0.01 % here). Periodic, eta = 0.05, N = 4000.
    let (n, eta) = (4000, 0.05);
    let mut sim = melted(n, eta, Boundary::Periodic, 5, 10);
    let mut c = Collisions::new(&sim, 50, 50.0, 50.0);
    for _ in 0..20 {
        sim.run_until(sim.time() + 25.0, &mut obs(&mut c));
        c.sample(&sim);
    }
    let s = c.summary();
    let density = n as f64 / sim.sim_box().volume();
    let kt = kinetic_temperature(&sim);
    let boltzmann = 2.0 * density * (PI * kt).sqrt();
    let enskog = boltzmann * henderson_contact(eta);
    let f = s.frequency;
    let sigmas = (f.value - enskog) / f.error;
    eprintln!(
        "collision frequency: {:.5} +- {:.5} ({} collisions), Enskog {enskog:.5} ({sigmas:+.2} sigma), \
         Boltzmann {boltzmann:.5}; mean free path {:.3}, mean free time {:.3}",
        f.value, f.error, s.disc_disc, s.mean_free_path, s.mean_free_time
    );
    // The statistical error must be small enough for the test to tell Enskog from Boltzmann
    // (8 % apart here).
    assert!(f.error < 0.003 * f.value, "{f:?}");
    assert!(sigmas.abs() < 3.0, "{sigmas} sigma from Enskog");
    assert!((f.value - boltzmann).abs() > 10.0 * f.error);
    // Free flights: mean free time 1/omega and mean free path <v>/omega with the 2D mean
    // speed <v> = sqrt(pi kT / 2m), both biased low by about 1/(omega t) = 0.8 % here (flights
    // cut by the ends of the run are left out).
    let mean_speed = (PI * kt / 2.0).sqrt();
    let (tau, ell) = (
        s.mean_free_time * f.value,
        s.mean_free_path * f.value / mean_speed,
    );
    eprintln!("mean free time * omega = {tau:.4}, mean free path * omega / <v> = {ell:.4}");
    assert!((tau - 1.0).abs() < 0.02 && (ell - 1.0).abs() < 0.02);
}

/// Equilibrated periodic fluid at packing `eta`: the compressibility factor from the virial.
fn measured_z(eta: f64, seed: u64) -> edmd_core::measure::Estimate {
    let n = 1000;
    let mut sim = melted(n, eta, Boundary::Periodic, seed, 20);
    let mut p = Pressure::new(&sim);
    // Blocks of about 10 collisions per disc.
    let block = 10.0 / (2.0 * 4.0 * eta / PI * PI.sqrt() * henderson_contact(eta));
    for _ in 0..20 {
        sim.run_until(sim.time() + block, &mut obs(&mut p));
        p.sample(&sim);
    }
    p.summary().z
}

#[test]
fn compressibility_factor_agrees_with_henderson() {
    // Collision virial Z = 1 + sum r_ij . J_ij / (2 t N kT) (Alder and Wainwright, J. Chem.
    // Phys. 33, 1439 (1960)) against Henderson's Z = (1 + eta^2/8) / (1 - eta)^2, within 1 %.
    for (eta, seed) in [(0.2, 21), (0.4, 22)] {
        let z = measured_z(eta, seed);
        let h = henderson_z(eta);
        eprintln!(
            "Z at eta = {eta}: {:.4} +- {:.4}, Henderson {h:.4} ({:+.3} %, {:+.2} sigma)",
            z.value,
            z.error,
            100.0 * (z.value / h - 1.0),
            (z.value - h) / z.error
        );
        assert!(z.error < 0.003 * h, "{z:?}");
        assert!((z.value / h - 1.0).abs() < 0.01, "Z = {z:?}, Henderson {h}");
    }
}

#[test]
fn wall_pressure_equals_virial_pressure_in_a_walled_box() {
    // Virial theorem in a box with walls: P_wall A_eff = N kT + sum r_ij . J_ij / (2t), with
    // A_eff = A - R (L_x + L_y) (derived in `measure::pressure`). The wall pressure is measured
    // directly as sum |J_n| / (perimeter t). The two must agree within their combined error
    // (errors from 40 blocks of about 30 collisions per disc). The box is small (200 discs,
    // eta = 0.3, about 23 diameters wide) so that the wall pressure, which only the discs at the
    // walls sample, is precise, and so that the area correction (4 %) is visible.
    // The virial theorem is an identity of the dynamics: over a run of length t the two sides
    // differ only by the change of sum m r.v divided by 2t, so they agree far better than the
    // statistical errors (measured: 6e-6 relative, 0.003 combined sigma; up to 4e-4 for other
    // seeds).
    let n = 200;
    let mut sim = melted(n, 0.3, Boundary::Walls, 31, 20);
    let mut p = Pressure::new(&sim);
    for _ in 0..40 {
        sim.run_until(sim.time() + 25.0, &mut obs(&mut p));
        p.sample(&sim);
    }
    let s = p.summary();
    let (w, v) = (s.wall.unwrap(), s.virial);
    let combined = w.error.hypot(v.error);
    let sigmas = (w.value - v.value) / combined;
    // The error of the difference block by block, which accounts for correlations.
    let differences: Vec<f64> = p
        .blocks()
        .iter()
        .map(|b| b.wall.unwrap() - b.virial)
        .collect();
    let paired = edmd_core::measure::block_error(&differences);
    let bare = v.value * s.effective_area / s.area;
    eprintln!(
        "walled box: P_wall {:.6} +- {:.6}, P_virial {:.6} +- {:.6} (relative difference \
         {:.1e}): {sigmas:+.3} combined sigma ({:+.3} sigma of the blockwise difference); with \
         the bare area {bare:.5} ({:+.1} sigma)",
        w.value,
        w.error,
        v.value,
        v.error,
        w.value / v.value - 1.0,
        (w.value - v.value) / paired,
        (w.value - bare) / combined
    );
    assert!(sigmas.abs() < 3.0, "{sigmas} sigma apart");
    assert!((w.value / v.value - 1.0).abs() < 2e-3);
    // The area correction matters at this size: without it the two would disagree.
    assert!((w.value - bare).abs() > 5.0 * combined);
}

#[test]
fn reversing_velocities_returns_every_disc_to_its_start_after_a_thousand_collisions() {
    // Time reversal: run forward, reverse every velocity, run as long again; every disc must
    // come back to its start. Rounding errors grow exponentially (the Lyapunov instability of
    // hard discs), by a factor per collision per disc that falls with density because the free
    // path between defocusing collisions shortens. Measured (100 discs, walls, lattice fluid
    // melted; growth per collision per disc, error after about 1000 collisions):
    //   eta = 0.05: 40 to 60 (1e-10 to 1e-9 after only 120 collisions);
    //   eta = 0.126 in the unit box (R = 0.02, the Princeton p100 files): about 10 (1e-6,
    //     absolute in the unit box, after 400 to 500 collisions);
    //   eta = 0.3: 3.2 (1e-5 to 5e-4); eta = 0.5: 2.0 (1e-9 to 1e-8);
    //   eta = 0.6: 1.6 (2e-11 to 2e-9, this test); eta = 0.65: 1.55 (1e-11).
    // So 1e-6 after 1000 collisions is reachable only in a dense fluid; eta = 0.6 does it with
    // three decades or more to spare.
    for seed in 1..=3 {
        let mut sim = melted(100, 0.6, Boundary::Walls, seed, 40);
        let start = sim.discs();
        let t0 = sim.time();
        let c0 = sim.stats().disc_disc;
        while sim.stats().disc_disc - c0 < 1000 {
            sim.run_until(sim.time() + 0.01, &mut ());
        }
        let forward = sim.stats().disc_disc - c0;
        let t1 = sim.time();
        sim.reverse_velocities();
        sim.run_until(2.0 * t1 - t0, &mut ());
        let worst = (0..start.len())
            .map(|i| (sim.position(i) - start[i].pos).norm2().sqrt())
            .fold(0.0, f64::max);
        eprintln!("reversal, seed {seed}: {forward} collisions, worst miss {worst:.1e}");
        assert!(forward >= 1000);
        assert!(
            worst < 1e-6,
            "seed {seed}: a disc misses its start by {worst}"
        );
    }
}

#[test]
fn energy_is_conserved_with_every_measurement_attached() {
    // Observers see the state but cannot change it: the kinetic energy stays constant to
    // 1e-12 relative, and the trajectory is bit-identical to a run without them. Unequal
    // masses and radii, walls, two species.
    let mut discs = random_discs(300, 20.0, 0.2, 0.6, true, 41);
    for (k, d) in discs.iter_mut().enumerate() {
        d.species = (k % 2) as u16;
    }
    let bx = SimBox::walls([20.0, 20.0]);
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    let mut bare = sim.clone();
    let e0 = sim.kinetic_energy();
    let mut pressure = Pressure::new(&sim);
    let mut collisions = Collisions::new(&sim, 20, 5.0, 5.0);
    let mut temperature = Temperature::new();
    let mut speeds = Speeds::new(20, 3.0);
    let mut msd = Diffusion::new(&sim);
    let mut halves = SpeciesHalves::new(&sim, 0);
    for k in 1..=20 {
        sim.run_until(
            2.0 * k as f64,
            &mut obs(&mut (&mut pressure, &mut collisions)),
        );
        pressure.sample(&sim);
        collisions.sample(&sim);
        temperature.sample(&sim);
        speeds.sample(&sim);
        msd.sample(&sim);
        halves.sample(&sim);
    }
    bare.run_until(40.0, &mut ());
    assert!(sim.stats().disc_disc > 5_000, "{:?}", sim.stats());
    let drift = ((sim.kinetic_energy() - e0) / e0).abs();
    eprintln!("energy drift with observers: {drift:.1e}");
    assert!(drift < 1e-12);
    let t = temperature.summary();
    assert!((t.max - t.min) / t.mean < 1e-12);
    assert_eq!(digest(&sim.discs()), digest(&bare.discs()));
    assert_eq!(collisions.summary().disc_disc, sim.stats().disc_disc);
    assert_eq!(collisions.summary().wall, sim.stats().wall);
    assert_eq!(halves.snapshots().len(), 20);
}
