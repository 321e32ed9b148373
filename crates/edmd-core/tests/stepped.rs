//! Stepped pair potentials: exact two-body kinematics at wells and shoulders, energy and
//! momentum conservation in fluids, shells that always match the distances, exact checkpoints
//! and the refusal of potentials that cannot be.

use crate::support::obs;
use edmd_core::setup::lattice_fluid_in;
use edmd_core::{
    Boundary, Disc, Error, EventKind, EventRecord, Observer, Options, PairSteps, Potential, SimBox,
    Simulation, Step, StepHit, Vector,
};

/// Every event, in order.
#[derive(Default)]
struct Log<const D: usize>(Vec<EventRecord<D>>);

impl<const D: usize> Observer<D> for Log<D> {
    fn on_event(&mut self, e: &EventRecord<D>, _: &Simulation<D>) {
        if !e.kind.is_bookkeeping() {
            self.0.push(*e);
        }
    }
}

fn pair(x: f64, u: f64, potential: &Potential) -> Simulation<2> {
    let discs = [
        Disc::new(Vector::new([5.0, 10.0]), Vector::new([u, 0.0]), 0.5),
        Disc::new(Vector::new([5.0 + x, 10.0]), Vector::new([0.0, 0.0]), 0.5),
    ];
    Simulation::with_potential_at(
        &discs,
        SimBox::periodic([20.0, 20.0]),
        &[],
        potential,
        Options::default(),
        0.0,
    )
    .unwrap()
}

fn energy<const D: usize>(sim: &Simulation<D>) -> f64 {
    sim.kinetic_energy() + sim.potential_energy()
}

#[test]
fn a_pair_falls_into_a_well_bounces_off_the_core_and_climbs_out() {
    // Diameter 1, masses 1 (reduced mass 1/2), a well of depth 1 out to 1.5. Closing at speed
    // 1 from 3 apart: in at t = 1.5, where the normal speed becomes sqrt(1 + 2 * 1 / (1/2)) =
    // sqrt(5); the cores meet 0.5 further on, and the pair leaves the well 0.5 after that
    // with its kinetic energy along the line 5/4 > 1, at speed sqrt(5 - 4) = 1.
    let well = Potential::single(0, 0, 1.5, -1.0);
    let mut sim = pair(3.0, 1.0, &well);
    assert_eq!(sim.potential_energy(), 0.0);
    let mut log = Log::default();
    sim.run_until(10.0, &mut obs(&mut log));
    let kinds: Vec<_> = log.0.iter().map(|e| e.kind).collect();
    assert!(
        matches!(
            kinds[..],
            [
                EventKind::Step {
                    hit: StepHit::Entered,
                    ..
                },
                EventKind::DiscDisc { .. },
                EventKind::Step {
                    hit: StepHit::Left,
                    ..
                },
            ]
        ),
        "{kinds:?}"
    );
    let s5 = 5f64.sqrt();
    let times = [1.5, 1.5 + 0.5 / s5, 1.5 + 1.0 / s5];
    for (e, t) in log.0.iter().zip(times) {
        assert!((e.time - t).abs() < 1e-14, "{} against {t}", e.time);
    }
    // Out again with the speeds it came in with, exchanged (an elastic pair of equal masses).
    assert!(
        (sim.velocity(0)[0] - 0.0).abs() < 1e-14,
        "{:?}",
        sim.velocity(0)
    );
    assert!(
        (sim.velocity(1)[0] - 1.0).abs() < 1e-14,
        "{:?}",
        sim.velocity(1)
    );
    assert_eq!(sim.potential_energy(), 0.0);
    assert!(sim.shells().is_empty());
    assert_eq!(sim.stats().step, 2);
    assert_eq!(sim.stats().disc_disc, 1);
}

#[test]
fn a_pair_without_the_energy_to_leave_stays_in_the_well() {
    // Inside the well (1.2 apart), receding at relative speed 0.5: kinetic energy along the
    // line 1/16, below the depth, so the pair rattles between the core and the well's edge.
    let well = Potential::single(0, 0, 1.5, -1.0);
    let mut sim = pair(1.2, -0.5, &well);
    assert_eq!(sim.shells(), [(0, 1, 1)]);
    assert_eq!(sim.potential_energy(), -1.0);
    let e0 = energy(&sim);
    let mut log = Log::default();
    sim.run_until(100.0, &mut obs(&mut log));
    assert!(log.0.len() > 50, "{} events", log.0.len());
    for e in &log.0 {
        match e.kind {
            EventKind::Step { hit, .. } => assert_eq!(hit, StepHit::Held),
            EventKind::DiscDisc { .. } => {}
            k => panic!("{k:?}"),
        }
    }
    assert_eq!(sim.shells(), [(0, 1, 1)]);
    assert!((energy(&sim) - e0).abs() < 1e-14);
}

#[test]
fn a_shoulder_too_high_to_climb_is_a_larger_hard_core() {
    // A shoulder of height 10 at 1.5 against a pair closing at speed 1 (1/4 along the line):
    // the pair bounces at 1.5 exactly as hard discs of diameter 1.5 do.
    let shoulder = Potential::single(0, 0, 1.5, 10.0);
    let mut sim = pair(3.0, 1.0, &shoulder);
    let mut log = Log::default();
    sim.run_until(3.0, &mut obs(&mut log));
    let discs = [
        Disc::new(Vector::new([5.0, 10.0]), Vector::new([1.0, 0.0]), 0.75),
        Disc::new(Vector::new([8.0, 10.0]), Vector::new([0.0, 0.0]), 0.75),
    ];
    let mut hard =
        Simulation::new(&discs, SimBox::periodic([20.0, 20.0]), Options::default()).unwrap();
    let mut hard_log = Log::default();
    hard.run_until(3.0, &mut obs(&mut hard_log));
    assert_eq!(log.0.len(), 1);
    assert!(matches!(
        log.0[0].kind,
        EventKind::Step {
            hit: StepHit::Repelled,
            ..
        }
    ));
    assert!((log.0[0].time - hard_log.0[0].time).abs() < 1e-15);
    for i in 0..2 {
        assert!((sim.velocity(i) - hard.velocity(i)).norm2() < 1e-28);
    }
    assert!(sim.shells().is_empty());
}

#[test]
fn a_low_shoulder_is_climbed_at_a_lower_speed() {
    // Height 0.1, kinetic energy along the line 1/4: over it, the normal speed
    // sqrt(1 - 2 * 0.1 / (1/2)) = sqrt(0.6); the cores meet 0.5 / sqrt(0.6) later.
    let shoulder = Potential::single(0, 0, 1.5, 0.1);
    let mut sim = pair(3.0, 1.0, &shoulder);
    let e0 = energy(&sim);
    let mut log = Log::default();
    sim.run_until(1.5 + 0.5 / 0.6f64.sqrt() + 1e-9, &mut obs(&mut log));
    assert!(matches!(
        log.0[0].kind,
        EventKind::Step {
            hit: StepHit::Entered,
            ..
        }
    ));
    assert!(matches!(log.0[1].kind, EventKind::DiscDisc { .. }));
    assert!((log.0[1].time - (1.5 + 0.5 / 0.6f64.sqrt())).abs() < 1e-14);
    assert_eq!(sim.potential_energy(), 0.1);
    assert!((energy(&sim) - e0).abs() < 1e-15);
}

/// A fluid of `n` particles of diameter 1 at packing fraction 0.3 and kT = 1.5 under
/// `potential`.
fn fluid<const D: usize>(n: usize, potential: &Potential) -> Simulation<D> {
    let (mut discs, bx) = lattice_fluid_in::<D>(n, 0.3, Boundary::Periodic, 3).unwrap();
    for d in &mut discs {
        d.vel = d.vel * 1.5f64.sqrt();
    }
    Simulation::with_potential_at(&discs, bx, &[], potential, Options::default(), 0.0).unwrap()
}

/// A square well of depth 1 and range 1.5, and a ramp of three steps either side of zero.
fn potentials() -> [Potential; 2] {
    let ramp = Potential {
        pairs: vec![PairSteps {
            species: (0, 0),
            steps: vec![
                Step {
                    radius: 1.1,
                    energy: 0.7,
                },
                Step {
                    radius: 1.3,
                    energy: -0.4,
                },
                Step {
                    radius: 1.6,
                    energy: -0.5,
                },
            ],
        }],
    };
    [Potential::single(0, 0, 1.5, -1.0), ramp]
}

fn conserves<const D: usize>(n: usize) {
    for potential in potentials() {
        let mut sim = fluid::<D>(n, &potential);
        let e0 = energy(&sim);
        let p0 = sim.momentum();
        let u0 = sim.potential_energy();
        for _ in 0..20 {
            sim.run_events(10_000, &mut ());
            assert!(sim.stalled().is_none());
            let e = energy(&sim);
            // Each event changes the energy by a rounding of its terms; 2 10^5 of them in a
            // random walk stay far below 1e-10 of the total.
            assert!((e - e0).abs() < 1e-10 * e0.abs(), "E {e} from {e0}");
            assert!((sim.momentum() - p0).norm2().sqrt() < 1e-9, "momentum");
            let bad = sim.shell_mismatches(1e-9);
            assert!(
                bad.is_empty(),
                "shells that disagree with the distances: {bad:?}"
            );
            let o = sim.overlaps(edmd_core::OVERLAP_TOLERANCE);
            assert!(o.first.is_none(), "{:?}", o.first);
        }
        let st = sim.stats();
        assert!(st.step > 10_000 && st.disc_disc > 1_000, "{st:?}");
        assert_ne!(sim.potential_energy(), u0);
    }
}

#[test]
fn fluids_under_stepped_potentials_conserve_energy_and_keep_their_shells_2d() {
    conserves::<2>(400);
}

#[test]
fn fluids_under_stepped_potentials_conserve_energy_and_keep_their_shells_3d() {
    conserves::<3>(500);
}

#[test]
fn a_stepped_run_continues_from_its_checkpoint_bit_for_bit() {
    fn check<const D: usize>(n: usize) {
        for potential in potentials() {
            let mut sim = fluid::<D>(n, &potential);
            sim.run_events(30_000, &mut ());
            let bytes = sim.to_checkpoint(b"extra");
            let (mut resumed, extra) = Simulation::<D>::from_checkpoint(&bytes).unwrap();
            assert_eq!(extra, b"extra");
            assert_eq!(resumed.potential(), Some(&potential));
            let mut a = Log::default();
            let mut b = Log::default();
            sim.run_events(30_000, &mut obs(&mut a));
            resumed.run_events(30_000, &mut obs(&mut b));
            assert!(a.0 == b.0, "the events differ");
            assert_eq!(sim.shells(), resumed.shells());
            assert_eq!(sim.stats(), resumed.stats());
            assert_eq!(sim.potential_energy(), resumed.potential_energy());
        }
    }
    check::<2>(300);
    check::<3>(300);
}

/// Checkpoints of format 4, written by `edmd run --checkpoint` of edmd b89d52d (whose
/// stepped runs filed their discs by position, without neighbour lists) at t = 5: a 2D
/// square-well fluid of 120 discs under the Andersen thermostat, potential energy -136, and
/// a 3D one of 108 spheres run at constant energy, potential energy -450. Each continues
/// with its shells, its energy conserved (3D) and no shell or overlap out of place.
#[test]
fn version_4_stepped_checkpoints_continue_with_their_shells() {
    fn check<const D: usize>(file: &str, u: f64, nve: bool) {
        let path = format!("{}/tests/data/{file}", env!("CARGO_MANIFEST_DIR"));
        let bytes = std::fs::read(&path).unwrap();
        let (mut sim, _) = Simulation::<D>::from_checkpoint(&bytes).unwrap();
        assert_eq!(sim.time(), 5.0);
        assert_eq!(sim.potential_energy(), u);
        assert_eq!(sim.thermostat().is_some(), !nve);
        // Written again in the current format, it reads back to the same bytes and runs on
        // bit for bit.
        let bytes = sim.to_checkpoint(b"");
        let (mut again, _) = Simulation::<D>::from_checkpoint(&bytes).unwrap();
        assert!(again.to_checkpoint(b"") == bytes);
        let mut run_again = Log::default();
        again.run_events(5_000, &mut obs(&mut run_again));
        let e0 = energy(&sim);
        for k in 0..10 {
            let mut log = Log::default();
            sim.run_events(5_000, &mut obs(&mut log));
            if k == 0 {
                assert!(log.0 == run_again.0, "the events differ");
            }
            assert!(sim.shell_mismatches(1e-9).is_empty());
            assert!(sim.overlaps(edmd_core::OVERLAP_TOLERANCE).first.is_none());
            if nve {
                assert!((energy(&sim) - e0).abs() < 1e-10 * e0.abs());
            }
        }
        assert!(sim.stats().neighbour_list > 1000, "{:?}", sim.stats());
    }
    check::<2>("sw2d-v4.ckpt", -136.0, false);
    check::<3>("sw3d-v4.ckpt", -450.0, true);
}

#[test]
fn damaged_shells_in_a_checkpoint_are_refused() {
    let mut sim = fluid::<2>(100, &Potential::single(0, 0, 1.5, -1.0));
    sim.run_events(1000, &mut ());
    let bytes = sim.to_checkpoint(&[]);
    // Any flipped byte is caught by the checksum; a state whose shells disagree is written
    // with a valid one only by a bug, which the reader's own checks catch: every damaged
    // checkpoint is an error, never a panic.
    for k in (16..bytes.len()).step_by(97) {
        let mut b = bytes.clone();
        b[k] ^= 0x40;
        assert!(matches!(
            Simulation::<2>::from_checkpoint(&b),
            Err(Error::Checkpoint(_))
        ));
    }
}

#[test]
fn potentials_that_cannot_be_are_refused_with_the_reason() {
    let discs = [
        Disc::new(Vector::new([2.0, 2.0]), Vector::new([1.0, 0.0]), 0.5),
        Disc::new(Vector::new([5.0, 2.0]), Vector::new([0.0, 0.0]), 0.5),
    ];
    let refuse = |p: Potential, words: &str| match Simulation::with_potential_at(
        &discs,
        SimBox::periodic([10.0, 10.0]),
        &[],
        &p,
        Options::default(),
        0.0,
    ) {
        Err(Error::BadPotential(m)) => assert!(m.contains(words), "{m}"),
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("accepted: {p:?}"),
    };
    let steps = |s: &[(f64, f64)]| Potential {
        pairs: vec![PairSteps {
            species: (0, 0),
            steps: s
                .iter()
                .map(|&(radius, energy)| Step { radius, energy })
                .collect(),
        }],
    };
    refuse(steps(&[(1.5, -1.0), (1.2, 0.5)]), "increasing radius");
    refuse(steps(&[(0.8, -1.0)]), "inside the hard core");
    refuse(steps(&[(1.5, f64::NAN)]), "not finite");
    refuse(steps(&[(f64::INFINITY, 1.0)]), "not a finite positive");
    refuse(
        Potential::single(0, 3, 1.5, -1.0),
        "no disc is of species 3",
    );
    let mut twice = Potential::single(0, 0, 1.5, -1.0);
    twice.pairs.push(twice.pairs[0].clone());
    refuse(twice, "given twice");
    // The swap rule and multi-disc collisions do not go with steps.
    let opts = Options {
        rule: edmd_core::CollisionRule::Swap,
        ..Options::default()
    };
    assert!(Simulation::with_potential_at(
        &discs,
        SimBox::periodic([10.0, 10.0]),
        &[],
        &Potential::single(0, 0, 1.5, -1.0),
        opts,
        0.0
    )
    .is_err());
}

#[test]
fn the_x86_64_v3_stepped_scan_gives_the_portable_trajectory_bit_for_bit() {
    // In 3D the x86-64-v3 loop reads a sphere's neighbour list four at a time and makes lists
    // again from the cells' first four spheres (`simulation/steps_x86.rs`); the portable loop
    // does both one at a time. The same operations in the same order, so the same events and
    // the same trajectory to the bit. The systems: the square well and the ramp of
    // `potentials()` in a periodic fluid (lists of about 20, shells from 0 to 3); the well
    // among spheres of several sizes between walls, whose contact distances differ pair by
    // pair; and a mixture whose two species have tables of their own, which keeps the
    // scalar scan in both loops and the new lists' cells four at a time in the fast one.
    let mut systems = Vec::new();
    for potential in potentials() {
        systems.push(fluid::<3>(1000, &potential));
    }
    let l = 9.0;
    let mut sizes = crate::support::random_discs_in::<3>(220, l, 0.3, 0.55, true, 7);
    for d in &mut sizes {
        d.mass = 1.0;
    }
    let well = Potential::single(0, 0, 1.5, -1.0);
    systems.push(
        Simulation::with_potential_at(
            &sizes,
            SimBox::walls([l; 3]),
            &[],
            &well,
            Options::default(),
            0.0,
        )
        .unwrap(),
    );
    let (mut discs, bx) = lattice_fluid_in::<3>(1000, 0.3, Boundary::Periodic, 5).unwrap();
    for d in discs.iter_mut().step_by(3) {
        d.species = 1;
    }
    let mixed = Potential {
        pairs: vec![
            PairSteps {
                species: (0, 0),
                steps: vec![Step {
                    radius: 1.5,
                    energy: -1.0,
                }],
            },
            PairSteps {
                species: (0, 1),
                steps: vec![Step {
                    radius: 1.2,
                    energy: 0.5,
                }],
            },
        ],
    };
    systems.push(
        Simulation::with_potential_at(&discs, bx, &[], &mixed, Options::default(), 0.0).unwrap(),
    );
    let v3 = edmd_core::simulation::x86_64_v3_available();
    for (k, mut fast) in systems.into_iter().enumerate() {
        let mut portable = fast.clone();
        assert!(!portable.set_portable_loop(true));
        assert_eq!(fast.set_portable_loop(false), v3);
        fast.run_events(60_000, &mut ());
        portable.run_events(60_000, &mut ());
        let st = fast.stats();
        assert!(
            st.step > 5_000 && st.disc_disc > 1_000 && st.neighbour_list > 1_000,
            "system {k}: {st:?}"
        );
        assert_eq!(st, portable.stats(), "system {k}");
        assert!(
            crate::support::bits_3d(&fast) == crate::support::bits_3d(&portable),
            "system {k}: trajectories differ"
        );
        assert_eq!(fast.shells(), portable.shells(), "system {k}");
    }
}
