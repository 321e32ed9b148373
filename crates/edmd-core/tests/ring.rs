//! A ring patch: flights under Hill's equations against a brute-force search of the same
//! dynamics, a lone particle's epicycle across the shearing boundaries, exact checkpoints, the
//! shear's heating and its balance by inelastic collisions, and the refusals.

use edmd_core::predict::hill;
use edmd_core::setup::ring::RingPatch;
use edmd_core::{
    Disc, Error, EventKind, Gravity, Options, Restitution, Ring, Shear, SimBox, Simulation, Vector,
};

/// Equal discs of radius 0.5 in the plane, by a brute-force simulation of the same dynamics:
/// every pair's separation sampled along Hill's flights every `1e-3` to find the earliest
/// contact, that contact bisected to the last bit, all discs advanced to it, the elastic
/// impulse applied. Positions relative to the patch's centre, never folded (the discs stay
/// far from the boundaries).
fn brute_force(
    mut p: Vec<Vector<2>>,
    mut v: Vec<Vector<2>>,
    omega: f64,
    t_end: f64,
) -> (Vec<Vector<2>>, usize) {
    let n = p.len();
    let mut t = 0.0;
    let mut collisions = 0;
    let gap = |p: &[Vector<2>], v: &[Vector<2>], i: usize, j: usize, tau: f64| {
        let (d, _) = hill::advance(p[j] - p[i], v[j] - v[i], omega, tau);
        d.norm2() - 1.0
    };
    loop {
        let mut first: Option<(f64, usize, usize)> = None;
        let h = 1e-3;
        for i in 0..n {
            for j in i + 1..n {
                let mut a = 0.0;
                // Receding from a contact they are at now: skip past it.
                let (d0, w0) = (p[j] - p[i], v[j] - v[i]);
                let touching = d0.norm2() - 1.0 < 1e-9 && d0.dot(w0) >= 0.0;
                while a < t_end - t && first.is_none_or(|(tf, _, _)| a < tf) {
                    let b = (a + h).min(t_end - t);
                    if gap(&p, &v, i, j, b) <= 0.0
                        && !(touching && a == 0.0 && gap(&p, &v, i, j, b) > -1e-6)
                    {
                        let (mut lo, mut hi) = (a, b);
                        for _ in 0..200 {
                            let m = 0.5 * (lo + hi);
                            if m <= lo || m >= hi {
                                break;
                            }
                            if gap(&p, &v, i, j, m) <= 0.0 {
                                hi = m;
                            } else {
                                lo = m;
                            }
                        }
                        if first.is_none_or(|(tf, _, _)| lo < tf) {
                            first = Some((lo, i, j));
                        }
                        break;
                    }
                    a = b;
                }
            }
        }
        let Some((dt, i, j)) = first else {
            for k in 0..n {
                (p[k], v[k]) = hill::advance(p[k], v[k], omega, t_end - t);
            }
            return (p, collisions);
        };
        for k in 0..n {
            (p[k], v[k]) = hill::advance(p[k], v[k], omega, dt);
        }
        t += dt;
        let d = p[j] - p[i];
        let u = d * (1.0 / d.norm2().sqrt());
        let vn = (v[j] - v[i]).dot(u);
        v[i] += u * vn;
        v[j] -= u * vn;
        collisions += 1;
    }
}

#[test]
fn collisions_follow_hills_equations_as_a_brute_force_search_finds_them() {
    let omega = 0.2;
    let side = 60.0;
    let c = 0.5 * side;
    // Six discs in a cluster at the centre, moving a little about the Keplerian flow.
    let start = [
        ([0.0, 0.0], [0.3, 0.1]),
        ([1.6, 0.3], [-0.4, 0.05]),
        ([-1.5, -0.8], [0.35, 0.2]),
        ([0.4, 1.9], [0.0, -0.45]),
        ([-0.3, -2.2], [0.1, 0.5]),
        ([2.4, -1.7], [-0.3, 0.3]),
    ];
    let p: Vec<Vector<2>> = start.iter().map(|s| Vector::new(s.0)).collect();
    // Drawn towards one another, so that they meet several times.
    let v: Vec<Vector<2>> = start
        .iter()
        .map(|s| Vector::new(s.1) * 0.5 - Vector::new(s.0) * 0.3)
        .collect();
    let discs: Vec<Disc<2>> = p
        .iter()
        .zip(&v)
        .map(|(&p, &v)| Disc::new(p + Vector::new([c, c]), v, 0.5))
        .collect();
    let mut sim =
        Simulation::new(&discs, SimBox::periodic([side, side]), Options::default()).unwrap();
    sim.set_ring(Some(Ring { omega })).unwrap();
    let t_end = 12.0;
    let mut met = 0;
    while let Some(e) = sim.step(t_end) {
        met += matches!(e.kind, EventKind::DiscDisc { .. }) as usize;
    }
    sim.run_until(t_end, &mut ());
    let (want, collisions) = brute_force(p, v, omega, t_end);
    assert_eq!(met, collisions, "collisions");
    assert!(collisions >= 5, "only {collisions} collisions");
    for (k, w) in want.iter().enumerate() {
        let got = sim.unwrapped_position(k) - Vector::new([c, c]);
        assert!(
            (got - *w).norm2().sqrt() < 1e-7,
            "disc {k}: {got:?} against {w:?}"
        );
    }
}

#[test]
fn a_lone_particle_keeps_its_epicycle_across_the_shearing_boundaries() {
    // A particle whose epicycle and drift take it across y and x many times: unwrapped, it is
    // on the one flight from its start (an image of a flight is a flight).
    let omega = 1.0;
    let side = 6.0;
    let (p0, v0) = (Vector::new([1.0, 2.0]), Vector::new([0.7, 4.0]));
    let d = Disc::new(p0, v0, 0.1);
    let mut sim =
        Simulation::new(&[d], SimBox::periodic([side, side]), Options::default()).unwrap();
    sim.set_ring(Some(Ring { omega })).unwrap();
    let centre = Vector::new([0.0, 0.5 * side]);
    let mut crossings = 0;
    let mut last = 0.0;
    while let Some(e) = sim.step(40.0) {
        if let EventKind::CellCrossing { i: 0, axis: 1, .. } = e.kind {
            crossings += 1;
        }
        last = e.time;
    }
    assert!(last > 39.0);
    sim.run_until(40.0, &mut ());
    let (want, wv) = hill::advance(p0 - centre, v0, omega, 40.0);
    let got = sim.unwrapped_position(0) - centre;
    assert!(
        (got - want).norm2().sqrt() < 1e-10 * (1.0 + want.norm2().sqrt()),
        "{got:?} against {want:?}"
    );
    // In the box, its velocity is the flight's less the images' speed for each crossing up.
    let shift = sim.velocity(0) - wv;
    let per = 1.5 * omega * side;
    assert!((shift[0] / per - (shift[0] / per).round()).abs() < 1e-9 && shift[1].abs() < 1e-12);
    assert!(crossings > 5, "{crossings} crossings of y");
}

fn patch<const D: usize>(n: usize, dispersion: f64, seed: u64) -> Simulation<D> {
    let (discs, sim_box) = RingPatch {
        n,
        tau: 0.25,
        radius: 0.5,
        omega: 1.0,
        dispersion,
        height: 60.0,
        seed,
    }
    .build::<D>()
    .unwrap();
    Simulation::new(&discs, sim_box, Options::default()).unwrap()
}

fn dispersion<const D: usize>(sim: &Simulation<D>) -> f64 {
    let n = sim.len();
    ((0..n)
        .map(|i| sim.peculiar_velocity(i).norm2())
        .sum::<f64>()
        / (n * D) as f64)
        .sqrt()
}

#[test]
fn checkpoints_continue_a_ring_to_the_bit() {
    for seed in [1, 2] {
        let mut a = patch::<3>(120, 2.0, seed);
        let mut r = Restitution::constant(0.5);
        r.tc = 1e-3;
        a.set_restitution(Some(r)).unwrap();
        a.set_ring(Some(Ring { omega: 1.0 })).unwrap();
        let mut b = a.clone();
        a.run_until(6.0, &mut ());
        b.run_until(2.5, &mut ());
        let (mut c, _) = Simulation::<3>::from_checkpoint(&b.to_checkpoint(&[])).unwrap();
        assert_eq!(c.ring(), Some(Ring { omega: 1.0 }));
        c.run_until(6.0, &mut ());
        assert!(a.stats().disc_disc > 100);
        for i in 0..a.len() {
            assert_eq!(a.position(i), c.position(i), "disc {i}");
            assert_eq!(a.velocity(i), c.velocity(i), "disc {i}");
        }
        assert_eq!(a.overlaps(1e-9).count, 0);
    }
}

#[test]
fn the_shear_heats_an_elastic_patch_and_inelastic_collisions_hold_it() {
    // Elastic collisions turn the shear's work into heat without end (2D, quick); with
    // e = 0.25 the patch cools from a hot start to a steady dispersion of about Omega d.
    let mut hot = patch::<2>(150, 1.0, 3);
    hot.set_ring(Some(Ring { omega: 1.0 })).unwrap();
    let before = dispersion(&hot);
    hot.run_until(10.0, &mut ());
    assert!(
        dispersion(&hot) > 2.0 * before,
        "{} against {before}",
        dispersion(&hot)
    );
    assert_eq!(hot.overlaps(1e-9).count, 0);

    let mut cooled = patch::<2>(150, 4.0, 3);
    let mut r = Restitution::constant(0.25);
    r.tc = 1e-3;
    cooled.set_restitution(Some(r)).unwrap();
    cooled.set_ring(Some(Ring { omega: 1.0 })).unwrap();
    cooled.run_until(30.0, &mut ());
    let settled = dispersion(&cooled);
    assert!(settled < 2.0 && settled > 0.1, "{settled}");
    assert_eq!(cooled.overlaps(1e-9).count, 0);
}

#[test]
fn a_ring_is_refused_where_it_cannot_be() {
    let d = [Disc::new(Vector::new([1.0, 1.0]), Vector::ZERO, 0.1)];
    let mut walls = Simulation::new(&d, SimBox::walls([10.0, 10.0]), Options::default()).unwrap();
    assert!(matches!(
        walls.set_ring(Some(Ring { omega: 1.0 })),
        Err(Error::BadRing(_))
    ));
    let mut sim = Simulation::new(&d, SimBox::periodic([10.0, 10.0]), Options::default()).unwrap();
    for omega in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            sim.set_ring(Some(Ring { omega })),
            Err(Error::BadRing(_))
        ));
    }
    let d3 = [Disc::new(Vector::new([1.0, 1.0, 1.0]), Vector::ZERO, 0.1)];
    let mut periodic_z =
        Simulation::new(&d3, SimBox::periodic([10.0; 3]), Options::default()).unwrap();
    assert!(matches!(
        periodic_z.set_ring(Some(Ring { omega: 1.0 })),
        Err(Error::BadRing(_))
    ));
    let d1 = [Disc::new(Vector::new([1.0]), Vector::ZERO, 0.1)];
    let mut line = Simulation::new(&d1, SimBox::periodic([10.0]), Options::default()).unwrap();
    assert!(matches!(
        line.set_ring(Some(Ring { omega: 1.0 })),
        Err(Error::BadRing(_))
    ));
    // With a ring, its shear is its own, and a field is refused; taking the ring away leaves
    // straight flights and no shear.
    sim.set_ring(Some(Ring { omega: 2.0 })).unwrap();
    assert_eq!(sim.shear().map(|s| s.rate), Some(-3.0));
    assert!(matches!(
        sim.set_shear(Some(Shear::new(0.1))),
        Err(Error::BadShear(_))
    ));
    let mut walled_y = Simulation::new(&d3, SimBox::walls([10.0; 3]), Options::default()).unwrap();
    walled_y
        .set_gravity(Some(Gravity { axis: 2, g: -1.0 }))
        .unwrap();
    sim.set_ring(None).unwrap();
    assert_eq!((sim.ring(), sim.shear()), (None, None));
    let mut plain = Simulation::new(
        &[Disc::new(
            Vector::new([1.0, 1.0]),
            Vector::new([1.0, 0.5]),
            0.1,
        )],
        SimBox::periodic([10.0, 10.0]),
        Options::default(),
    )
    .unwrap();
    plain.run_until(3.0, &mut ());
    sim.modify_velocities(|_, _| Vector::new([1.0, 0.5]));
    sim.run_until(sim.time() + 3.0, &mut ());
    assert_eq!(sim.position(0), plain.position(0));
}
