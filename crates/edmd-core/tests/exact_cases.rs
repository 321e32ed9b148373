//! Hand-derived cases with exact answers.

use crate::support::obs;
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
    sim.run_until(4.0, &mut obs(&mut c));
    assert_eq!(c.wall[0], 2);
    assert_eq!(sim.velocity(0), v(-1.0, -1.0));
    sim.run_until(8.0, &mut obs(&mut c));
    assert_eq!(sim.position(0), v(5.0, 5.0));
    sim.run_until(12.0, &mut obs(&mut c));
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
        sim.run_until(2.0, &mut obs(&mut c));
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
    sim.run_until(3.0, &mut obs(&mut c));
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
    sim.run_until(0.1 + 1e-12, &mut obs(&mut c));
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

mod barriers {
    use crate::support::obs;
    use edmd_core::setup::lattice_fluid;
    use edmd_core::{
        Barrier, BarrierHit, Boundary, Demon, Disc, EventKind, EventRecord, Observer, Options,
        SimBox, Simulation, Vector,
    };

    fn v(x: f64, y: f64) -> Vector {
        Vector::new([x, y])
    }

    #[test]
    fn solid_partition_reflects_exactly() {
        // Barrier at x = 5; disc r = 1 from (2, 3) at (1, 0): touches at t = 2 (x = 4), back at
        // x = 2 at t = 4.
        let d = [Disc::new(v(2.0, 3.0), v(1.0, 0.0), 1.0)];
        let mut sim = Simulation::with_barriers(
            &d,
            SimBox::walls([10.0, 10.0]),
            &[Barrier::solid(0, 5.0)],
            Options::default(),
        )
        .unwrap();
        sim.run_until(4.0, &mut ());
        assert_eq!(sim.stats().barrier, 1);
        assert_eq!(sim.position(0), v(2.0, 3.0));
        assert_eq!(sim.velocity(0), v(-1.0, 0.0));
    }

    #[test]
    fn door_edge_bounce_is_elastic_and_normal() {
        // Door (4, 8) in a barrier at x = 5; disc r = 1 at y = 4.5 moving +x hits the edge (5, 4)
        // with the normal from the edge to the centre n = (-sqrt(0.75), 0.5).
        let d = [Disc::new(v(2.0, 4.5), v(1.0, 0.0), 1.0)];
        let w = Barrier {
            axis: 0,
            position: 5.0,
            door: Some((4.0, 8.0)),
            demon: None,
        };
        let mut sim =
            Simulation::with_barriers(&d, SimBox::walls([10.0, 10.0]), &[w], Options::default())
                .unwrap();
        sim.run_until(3.0, &mut ());
        assert_eq!(sim.stats().barrier, 1);
        let vel = sim.velocity(0);
        let n = v(-0.75f64.sqrt(), 0.5);
        // v' = v - 2 (v.n) n with v = (1, 0): (1 - 2*0.75, 2*sqrt(0.75)*0.5) = (-0.5, sqrt(0.75)).
        assert!(
            (vel - v(-0.5, 0.75f64.sqrt())).norm2().sqrt() < 1e-14,
            "{vel:?}"
        );
        assert!((vel.norm2() - 1.0).abs() < 1e-15);
        // Only the normal component changed: the tangential one is kept.
        let t = v(0.5, 0.75f64.sqrt());
        assert!((vel.dot(t) - v(1.0, 0.0).dot(t)).abs() < 1e-15);
        assert!((vel.dot(n) + v(1.0, 0.0).dot(n)).abs() < 1e-15);
    }

    #[test]
    fn a_centred_disc_goes_through_an_open_door() {
        let d = [Disc::new(v(2.0, 6.0), v(1.0, 0.0), 1.0)];
        let w = Barrier {
            axis: 0,
            position: 5.0,
            door: Some((4.0, 8.0)),
            demon: None,
        };
        let mut sim =
            Simulation::with_barriers(&d, SimBox::walls([10.0, 10.0]), &[w], Options::default())
                .unwrap();
        sim.run_until(6.0, &mut ());
        assert_eq!(sim.stats().barrier, 0);
        assert_eq!(sim.position(0), v(8.0, 6.0));
    }

    #[test]
    fn partition_keeps_a_dense_gas_on_its_sides() {
        let (discs, bx) = lattice_fluid(400, 0.4, Boundary::Walls, 4).unwrap();
        let x0 = bx.lengths[0] / 2.0;
        // Keep only discs clear of the partition.
        let discs: Vec<Disc> = discs
            .into_iter()
            .filter(|d| (d.pos[0] - x0).abs() > d.radius)
            .collect();
        let side: Vec<bool> = discs.iter().map(|d| d.pos[0] < x0).collect();
        let mut sim =
            Simulation::with_barriers(&discs, bx, &[Barrier::solid(0, x0)], Options::default())
                .unwrap();
        let e0 = sim.kinetic_energy();
        for k in 1..=10 {
            sim.run_until(k as f64 * 3.0, &mut ());
            assert!(
                sim.barrier_overlap().is_none(),
                "disc cuts the partition at t = {}",
                sim.time()
            );
            for (i, &s) in side.iter().enumerate() {
                assert_eq!(sim.position(i)[0] < x0, s, "disc {i} crossed the partition");
            }
        }
        assert!(sim.stats().barrier > 100, "{:?}", sim.stats());
        assert!(((sim.kinetic_energy() - e0) / e0).abs() < 1e-12);
        // Removing it lets them mix.
        sim.set_barriers(&[]).unwrap();
        sim.run_until(300.0, &mut ());
        let crossed = side
            .iter()
            .enumerate()
            .filter(|&(i, &s)| (sim.position(i)[0] < x0) != s)
            .count();
        assert!(crossed > 20, "{crossed}");
    }

    /// Checks every demon decision against its rule.
    struct DemonWatch {
        mean: f64,
        passed: [u64; 2],
        shut: u64,
    }

    impl Observer for DemonWatch {
        fn on_event(&mut self, e: &EventRecord, sim: &Simulation) {
            if let EventKind::Barrier { i, hit, .. } = e.kind {
                let m = sim.mass(i);
                let mv2 = m * sim.velocity(i).norm2();
                let from_left = sim.velocity(i)[0] > 0.0;
                match hit {
                    BarrierHit::DoorPassed if from_left => {
                        assert!(mv2 >= 1.5 * self.mean, "slow disc let through to the right");
                        self.passed[0] += 1;
                    }
                    BarrierHit::DoorPassed => {
                        assert!(mv2 <= 0.7 * self.mean, "fast disc let through to the left");
                        self.passed[1] += 1;
                    }
                    BarrierHit::DoorShut => self.shut += 1,
                    _ => {}
                }
            }
        }
    }

    #[test]
    fn maxwells_demon_sorts_fast_from_slow() {
        let (discs, bx) = lattice_fluid(300, 0.2, Boundary::Walls, 8).unwrap();
        let x0 = bx.lengths[0] / 2.0;
        let discs: Vec<Disc> = discs
            .into_iter()
            .filter(|d| (d.pos[0] - x0).abs() > d.radius)
            .collect();
        let (ly, n) = (bx.lengths[1], discs.len());
        let w = Barrier {
            axis: 0,
            position: x0,
            door: Some((ly / 2.0 - 5.0, ly / 2.0 + 5.0)),
            demon: Some(Demon {
                fast: 1.5,
                slow: 0.7,
            }),
        };
        let mut sim = Simulation::with_barriers(&discs, bx, &[w], Options::default()).unwrap();
        let mean = 4.0 * sim.kinetic_energy() / n as f64;
        let mut watch = DemonWatch {
            mean,
            passed: [0, 0],
            shut: 0,
        };
        let e0 = sim.kinetic_energy();
        sim.run_until(1500.0, &mut obs(&mut watch));
        assert!(
            watch.passed[0] > 5 && watch.passed[1] > 5 && watch.shut > 5,
            "{:?} {}",
            watch.passed,
            watch.shut
        );
        assert!(((sim.kinetic_energy() - e0) / e0).abs() < 1e-12);
        // Temperature (mean kinetic energy per disc) right vs left.
        let (mut ke, mut cnt) = ([0.0; 2], [0usize; 2]);
        for i in 0..n {
            let s = (sim.position(i)[0] > x0) as usize;
            ke[s] += 0.5 * sim.mass(i) * sim.velocity(i).norm2();
            cnt[s] += 1;
        }
        let (tl, tr) = (ke[0] / cnt[0] as f64, ke[1] / cnt[1] as f64);
        // Measured: left 0.88, right 1.35 (mean kinetic energy per disc, started at 1).
        assert!(tr > 1.3 * tl, "right {tr} should be hotter than left {tl}");
        assert!(sim.barrier_overlap().is_none());
    }

    #[test]
    fn invalid_barriers_are_refused() {
        let d = [Disc::new(v(5.0, 3.0), v(1.0, 0.0), 1.0)];
        let bx = SimBox::walls([10.0, 10.0]);
        assert!(
            Simulation::with_barriers(&d, bx, &[Barrier::solid(0, 5.5)], Options::default())
                .is_err()
        );
        assert!(
            Simulation::with_barriers(&[], bx, &[Barrier::solid(0, 11.0)], Options::default())
                .is_err()
        );
        assert!(Simulation::with_barriers(
            &[],
            bx,
            &[Barrier {
                axis: 0,
                position: 5.0,
                door: Some((6.0, 4.0)),
                demon: None
            }],
            Options::default()
        )
        .is_err());
        let demon = Some(Demon {
            fast: 1.0,
            slow: 1.0,
        });
        assert!(Simulation::with_barriers(
            &[],
            bx,
            &[Barrier {
                axis: 0,
                position: 5.0,
                door: None,
                demon
            }],
            Options::default()
        )
        .is_err());
        assert!(Simulation::with_barriers(
            &[],
            SimBox::periodic([10.0, 10.0]),
            &[Barrier::solid(0, 5.0)],
            Options::default()
        )
        .is_err());
    }
}

mod multi_contact {
    use edmd_core::{Disc, MultiContact, Options, SimBox, Simulation, Vector};

    /// The 15-ball rack of the Princeton data file billiards5.txt (radius 0.029, spacing
    /// 0.06: gaps of 0.002), struck dead centre by the cue ball.
    fn rack() -> Vec<Disc> {
        let r = 0.029;
        let mut discs = Vec::new();
        let h = 0.06 * 3f64.sqrt() / 2.0;
        for row in 0..5 {
            for k in 0..(5 - row) {
                let x = 0.5 - 0.03 * (4 - row) as f64 + 0.06 * k as f64;
                discs.push(Disc::new(
                    Vector::new([x, 0.8 - h * row as f64]),
                    Vector::ZERO,
                    r,
                ));
            }
        }
        discs.push(Disc::new(
            Vector::new([0.5, 0.1]),
            Vector::new([0.0, 0.1]),
            r,
        ));
        discs
    }

    /// Largest mismatch between each ball's velocity and its mirror ball's mirrored velocity.
    fn mirror_mismatch(sim: &Simulation, discs: &[Disc]) -> f64 {
        let mut worst: f64 = 0.0;
        for (i, d) in discs.iter().enumerate() {
            let j = (0..discs.len())
                .find(|&j| {
                    (discs[j].pos[0] - (1.0 - d.pos[0])).abs() < 1e-9
                        && (discs[j].pos[1] - d.pos[1]).abs() < 1e-9
                })
                .unwrap();
            let (vi, vj) = (sim.velocity(i), sim.velocity(j));
            worst = worst.max((vi[0] + vj[0]).abs()).max((vi[1] - vj[1]).abs());
        }
        worst
    }

    #[test]
    fn a_symmetric_rack_breaks_symmetrically() {
        let discs = rack();
        let options = Options {
            multi: Some(MultiContact {
                tolerance: 0.05,
                exponent: 1.5,
            }),
            ..Default::default()
        };
        let mut sim = Simulation::new(&discs, SimBox::unit(), options).unwrap();
        let e0 = sim.kinetic_energy();
        // Just after the cue ball reaches the apex (gap 0.592 - 0.1 - 0.058 = 0.434 at 0.1/s).
        sim.run_until(4.5, &mut ());
        assert_eq!(sim.last_cluster().len(), 16, "the whole rack takes part");
        assert!(((sim.kinetic_energy() - e0) / e0).abs() < 1e-12);
        assert!(
            mirror_mismatch(&sim, &discs) < 1e-9,
            "{}",
            mirror_mismatch(&sim, &discs)
        );
        // Binary collisions one after another break the same rack asymmetrically.
        let mut binary = Simulation::new(&discs, SimBox::unit(), Options::default()).unwrap();
        binary.run_until(4.5, &mut ());
        assert!(binary.stats().disc_disc > 3);
        assert!(
            mirror_mismatch(&binary, &discs) > 1e-3,
            "{}",
            mirror_mismatch(&binary, &discs)
        );
    }
}
