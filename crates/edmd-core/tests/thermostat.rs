//! The Andersen thermostat: the bath's temperature is reached, redraws come at the rate asked
//! for, and a run with a thermostat is the same however it is sliced or checkpointed.

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
        whole.run_until(8.0, &mut a);
        let mut b = Log::default();
        for k in 1..=8 {
            sliced.run_until(0.5 * k as f64, &mut b);
        }
        let bytes = sliced.to_checkpoint(&[]);
        let (mut resumed, _) = Simulation::<D>::from_checkpoint(&bytes).unwrap();
        assert_eq!(resumed.thermostat(), whole.thermostat());
        resumed.run_until(8.0, &mut b);
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
