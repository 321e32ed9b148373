//! The Andersen thermostat: the bath's temperature is reached, redraws come at the rate asked
//! for, and a run with a thermostat is the same however it is sliced or checkpointed.

use crate::support::obs;
use edmd_core::setup::lattice_fluid_in;
use edmd_core::{
    Andersen, Boundary, EventKind, EventRecord, Observer, Options, Potential, Simulation,
};

#[derive(Default)]
struct Log<const D: usize>(Vec<EventRecord<D>>);

impl<const D: usize> Observer<D> for Log<D> {
    fn on_event(&mut self, e: &EventRecord<D>, _: &Simulation<D>) {
        self.0.push(*e);
    }
}

fn fluid<const D: usize>(n: usize, potential: &Potential, kt: f64) -> Simulation<D> {
    let (discs, bx) = lattice_fluid_in::<D>(n, 0.3, Boundary::Periodic, 5).unwrap();
    let mut sim =
        Simulation::with_potential_at(&discs, bx, &[], potential, Options::default(), 0.0).unwrap();
    sim.set_thermostat(Some(Andersen {
        kt,
        rate: 1.0,
        seed: 7,
    }))
    .unwrap();
    sim
}

/// The kinetic temperature `2 KE / (D N)`, averaged over `samples` times `dt` apart.
fn temperature<const D: usize>(sim: &mut Simulation<D>, samples: usize, dt: f64) -> f64 {
    let mut sum = 0.0;
    for _ in 0..samples {
        let t = sim.time() + dt;
        sim.run_until(t, &mut ());
        sum += 2.0 * sim.kinetic_energy() / (D * sim.len()) as f64;
    }
    sum / samples as f64
}

#[test]
fn the_bath_sets_the_temperature_of_hard_and_square_well_fluids() {
    // Hard discs start at kT = 1 and a bath at 2; a square-well fluid's start, at kT = 1,
    // warms as pairs fall into wells, and the bath at 1.5 holds it there. Averages over 200
    // samples of 500 particles: the standard error of the mean kinetic temperature is about
    // kT sqrt(2 / (D N)) / sqrt(200 / correlation) ~ 0.01 kT; 3% is several of them.
    fn check<const D: usize>(potential: Potential, kt: f64) {
        let mut sim = fluid::<D>(500, &potential, kt);
        temperature(&mut sim, 10, 1.0);
        let redraws0 = sim.stats().thermostat;
        let t0 = sim.time();
        let measured = temperature(&mut sim, 200, 0.1);
        assert!(
            (measured - kt).abs() < 0.03 * kt,
            "{D}D: kT {measured} in a bath at {kt}"
        );
        // Poisson redraws at rate 1 per particle: 500 * 20 = 10^4 expected, sd 100.
        let redraws = (sim.stats().thermostat - redraws0) as f64;
        let expected = 500.0 * (sim.time() - t0);
        assert!(
            (redraws - expected).abs() < 5.0 * expected.sqrt(),
            "{redraws} redraws, {expected} expected"
        );
    }
    check::<2>(Potential::default(), 2.0);
    check::<3>(Potential::default(), 2.0);
    check::<2>(Potential::single(0, 0, 1.5, -1.0), 1.5);
    check::<3>(Potential::single(0, 0, 1.5, -1.0), 1.5);
}

#[test]
fn a_thermostatted_run_is_the_same_sliced_or_continued_from_a_checkpoint() {
    fn check<const D: usize>(potential: Potential) {
        let mut whole = fluid::<D>(200, &potential, 1.5);
        let mut sliced = whole.clone();
        let mut a = Log::default();
        whole.run_until(8.0, &mut obs(&mut a));
        let mut b = Log::default();
        for k in 1..=8 {
            sliced.run_until(0.5 * k as f64, &mut obs(&mut b));
        }
        let bytes = sliced.to_checkpoint(&[]);
        let (mut resumed, _) = Simulation::<D>::from_checkpoint(&bytes).unwrap();
        assert_eq!(resumed.thermostat(), whole.thermostat());
        resumed.run_until(8.0, &mut obs(&mut b));
        assert!(a.0 == b.0, "the events differ");
        assert!(a
            .0
            .iter()
            .any(|e| matches!(e.kind, EventKind::Thermostat { .. })));
        assert_eq!(whole.stats(), resumed.stats());
    }
    check::<2>(Potential::default());
    check::<3>(Potential::single(0, 0, 1.5, -1.0));
}

#[test]
fn bad_thermostat_settings_are_refused() {
    let mut sim = fluid::<2>(50, &Potential::default(), 1.0);
    for (kt, rate) in [
        (0.0, 1.0),
        (f64::NAN, 1.0),
        // Speeds drawn at kT 1e308 overflowed: the run stopped as "jammed".
        (1e101, 1.0),
        (1.0, -1.0),
        (1.0, f64::INFINITY),
    ] {
        let e = sim.set_thermostat(Some(Andersen { kt, rate, seed: 1 }));
        assert!(e.unwrap_err().to_string().contains("thermostat"));
    }
    // Off again: energy is conserved from then on.
    sim.set_thermostat(None).unwrap();
    let e0 = sim.kinetic_energy();
    sim.run_until(sim.time() + 5.0, &mut ());
    assert!((sim.kinetic_energy() - e0).abs() < 1e-12 * e0);
}

#[test]
fn a_dilute_square_well_gas_has_g_of_r_the_boltzmann_factor_of_the_well() {
    // At low density g(r) = exp(-u(r)/kT) (Hansen and McDonald, Theory of Simple Liquids,
    // section 2.5): 0 inside the core, e^{1/1.5} = 1.948 in the well (1 < r < 1.5), 1
    // beyond. 1000 spheres at rho = 0.01: about 100 pairs in wells per sample, 300 samples a
    // bath redraw apart; corrections of order rho (a few percent at most here) and the
    // counting error (about 1%) are inside the 6% allowed.
    use edmd_core::measure::Rdf;
    let rho = 0.01;
    let (discs, bx) = lattice_fluid_in::<3>(
        1000,
        rho * std::f64::consts::PI / 6.0,
        Boundary::Periodic,
        2,
    )
    .unwrap();
    let mut sim = Simulation::with_potential_at(
        &discs,
        bx,
        &[],
        &Potential::single(0, 0, 1.5, -1.0),
        Options::default(),
        0.0,
    )
    .unwrap();
    sim.set_thermostat(Some(Andersen {
        kt: 1.5,
        rate: 1.0,
        seed: 3,
    }))
    .unwrap();
    sim.run_until(200.0, &mut ());
    let mut rdf = Rdf::new(&sim, 2.0, 8);
    for k in 1..=300 {
        sim.run_until(200.0 + k as f64, &mut ());
        rdf.sample(&sim);
    }
    let g = rdf.curve::<3>();
    assert_eq!(g.len(), 8);
    let boltzmann = (1.0f64 / 1.5).exp();
    for &(r, gr) in &g {
        let want = if r < 1.0 {
            0.0
        } else if r < 1.5 {
            boltzmann
        } else {
            1.0
        };
        assert!(
            (gr - want).abs() <= 0.06 * want,
            "g({r}) = {gr}, want {want}: {g:?}"
        );
    }
}

#[test]
fn the_heat_capacity_of_a_dilute_gas_in_the_bath_is_the_ideal_gas_one() {
    // C_V / (N k) = var(E) / (N kT^2) -> D/2 for an ideal gas (here 200 hard spheres at
    // packing 0.001, whose excess is of order 1e-3). 6000 samples half a redraw time apart
    // (consecutive ones correlated by e^{-1}): the variance's error is about 2%; 10% is
    // allowed (20000 samples gave 1.494 +- 0.018).
    use edmd_core::measure::Energy;
    let (discs, bx) = lattice_fluid_in::<3>(200, 0.001, Boundary::Periodic, 4).unwrap();
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    sim.set_thermostat(Some(Andersen {
        kt: 2.0,
        rate: 2.0,
        seed: 9,
    }))
    .unwrap();
    sim.run_until(20.0, &mut ());
    let mut energy = Energy::new();
    for k in 1..=6000 {
        sim.run_until(20.0 + 0.5 * k as f64, &mut ());
        energy.sample(&sim);
    }
    let s = energy.summary();
    let cv = s.heat_capacity.expect("a bath");
    assert!((cv.value - 1.5).abs() < 0.15, "C_V/Nk = {cv:?}");
    assert!(cv.error > 0.0 && cv.error < 0.1, "{cv:?}");
    assert!((s.kinetic_per_particle.value - 3.0).abs() < 0.1, "{s:?}");
    assert!(s.drift.is_nan(), "no drift in a bath");
}
