//! Lees-Edwards boundaries: pairs across the sliding boundary meet at their images' exact
//! times, no pair is let through in sheared dense fluids (checked against every pair, not the
//! grid's scan), shear at rate 0 is the plain periodic run, checkpoints continue bit for bit,
//! the thermostat draws about the streaming profile, temperature and speeds are measured
//! relative to it, and the refusals.

use crate::support::obs;
use edmd_core::measure::{kinetic_temperature, Speeds};
use edmd_core::setup::lattice_fluid_in;
use edmd_core::{
    Andersen, Boundary, Disc, Error, EventKind, Gravity, Options, Restitution, RestitutionLaw,
    Shear, SimBox, Simulation, Vector,
};

/// Every pair's distance at its nearest image (slid across y), against its contact distance:
/// the largest overlap, relative. Independent of the cell grid.
fn worst_overlap<const D: usize>(sim: &Simulation<D>) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..sim.len() {
        for j in i + 1..sim.len() {
            let (dr, _) = sim.separation(i, j);
            let sigma = sim.radius(i) + sim.radius(j);
            worst = worst.max((sigma - dr.norm2().sqrt()) / sigma);
        }
    }
    worst
}

#[test]
fn a_pair_across_the_boundary_meets_at_its_images_time() {
    // Box 10 x 10, rate 0.1: the images above slide at +1 along x. Disc 0 near the top at
    // (5, 9.6), at rest; disc 1 near the bottom at (0.6, 0.4), at rest, whose image above is
    // at (0.6 + t, 10.4), slid past three columns of cells before it comes near. Contact
    // (diameter 1) when the image is 0.6 short along x (dy = 0.8): t = 3.8.
    let mut discs = vec![
        Disc::new(Vector::new([5.0, 9.6]), Vector::new([0.0, 0.0]), 0.5),
        Disc::new(Vector::new([0.6, 0.4]), Vector::new([0.0, 0.0]), 0.5),
    ];
    // Spectators at rest in the middle, so that the grid has eight columns: the pair is not
    // in each other's scan at the start.
    for k in 0..36 {
        let (x, y) = (0.6 + 1.1 * (k % 9) as f64, 3.2 + 1.1 * (k / 9) as f64);
        discs.push(Disc::new(Vector::new([x, y]), Vector::new([0.0, 0.0]), 0.5));
    }
    let mut sim =
        Simulation::new(&discs, SimBox::periodic([10.0, 10.0]), Options::default()).unwrap();
    assert_eq!(sim.grid_dims(), [8, 8]);
    sim.set_shear(Some(Shear::new(0.1))).unwrap();
    let mut hit = None;
    while hit.is_none() {
        let e = sim.step(10.0).expect("an event");
        if let EventKind::DiscDisc { .. } = e.kind {
            hit = Some(e);
        }
    }
    let e = hit.unwrap();
    assert!((e.time - 3.8).abs() < 1e-14, "{}", e.time);
    // Equal masses, the image closing at (1, 0) along the line of centres n = (-0.6, 0.8) (from
    // disc 0 to the image): disc 0 takes (dv . n) n = (0.36, -0.48), the image the rest,
    // (0.64, 0.48), which in the lab, less the slide, is (-0.36, 0.48).
    let v0 = sim.velocity(0);
    let v1 = sim.velocity(1);
    assert!((v0 - Vector::new([0.36, -0.48])).norm2() < 1e-28, "{v0:?}");
    assert!((v1 - Vector::new([-0.36, 0.48])).norm2() < 1e-28, "{v1:?}");
}

/// A lattice fluid of `n` at `packing`, sheared at `rate` (thermostat at kT 1) from the
/// streaming profile.
fn sheared_fluid<const D: usize>(n: usize, packing: f64, rate: f64, seed: u64) -> Simulation<D> {
    let (discs, bx) = lattice_fluid_in::<D>(n, packing, Boundary::Periodic, seed).unwrap();
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    sim.set_shear(Some(Shear::new(rate))).unwrap();
    let ly = bx.lengths[1];
    let ys: Vec<f64> = (0..sim.len()).map(|i| sim.position(i)[1]).collect();
    sim.modify_velocities(|i, mut v| {
        v[0] += rate * (ys[i] - 0.5 * ly);
        v
    });
    sim.set_thermostat(Some(Andersen {
        kt: 1.0,
        rate: 0.5,
        seed,
    }))
    .unwrap();
    sim
}

#[test]
fn temperature_and_speeds_are_those_of_the_peculiar_velocities() {
    // The lattice's velocities are drawn at kT 1 exactly; the profile added on top carries
    // `<u^2> = gamma^2 L_y^2 / 12` per disc (unit masses), `<u^2> / D` of temperature in the
    // lab's velocities (15.6 in 2D here, 2.1 in 3D), which is flow, not heat. The kinetic
    // temperature and the speeds are taken relative to it, in 2D and 3D, at the start and
    // along the run (where the shear has heated the fluid); the lab's temperature stays above
    // by the flow's share, within a quarter of it (the cross term `2 <u c_x> / D` fluctuates
    // by about 5% of it in 3D).
    fn check<const D: usize>(mut sim: Simulation<D>) {
        let n = sim.len() as f64;
        let lab = |sim: &Simulation<D>| 2.0 * sim.kinetic_energy() / (D as f64 * n);
        let (rate, ly) = (sim.shear().unwrap().rate, sim.sim_box().lengths[1]);
        let flow = rate * rate * ly * ly / (12.0 * D as f64);
        let kt = kinetic_temperature(&sim);
        assert!((kt - 1.0).abs() < 1e-9, "{kt}");
        assert!(
            (lab(&sim) - kt - flow).abs() < 0.25 * flow,
            "{} {kt} {flow}",
            lab(&sim)
        );
        sim.run_until(3.0, &mut ());
        let kt = kinetic_temperature(&sim);
        let peculiar = 2.0 * sim.peculiar_kinetic_energy() / (D as f64 * n);
        assert!((kt - peculiar).abs() < 1e-12 * peculiar, "{kt} {peculiar}");
        assert!(kt > 1.2, "the shear heats: {kt}");
        assert!(
            (lab(&sim) - kt - flow).abs() < 0.25 * flow,
            "{} {kt} {flow}",
            lab(&sim)
        );
        let mut speeds = Speeds::new(40, 10.0);
        speeds.sample(&sim);
        for (i, &v) in speeds.speeds().iter().enumerate() {
            assert_eq!(v, sim.peculiar_velocity(i).norm2().sqrt(), "disc {i}");
        }
    }
    check(sheared_fluid::<2>(400, 0.3, 0.6, 11));
    check(sheared_fluid::<3>(500, 0.3, 0.9, 12));
}

#[test]
fn no_pair_is_let_through_in_strongly_sheared_dense_fluids() {
    // Slides of several cells per mean free time across the boundary: a pair the scans missed
    // would overlap, and every pair is looked at, at its nearest slid image.
    let mut sim2 = sheared_fluid::<2>(400, 0.6, 1.0, 3);
    let mut sim3 = sheared_fluid::<3>(500, 0.4, 0.8, 4);
    for k in 1..=10 {
        let t = 0.5 * k as f64;
        sim2.run_until(t, &mut ());
        sim3.run_until(t, &mut ());
        let (w2, w3) = (worst_overlap(&sim2), worst_overlap(&sim3));
        assert!(
            w2 < 1e-9 && w3 < 1e-9,
            "t = {t}: overlaps {w2:e} (2D), {w3:e} (3D)"
        );
        assert!(sim2.stalled().is_none() && sim3.stalled().is_none());
    }
    let (s2, s3) = (sim2.stats(), sim3.stats());
    assert!(
        s2.disc_disc > 20_000 && s3.disc_disc > 20_000,
        "{s2:?} {s3:?}"
    );
}

#[test]
fn shear_at_rate_zero_is_the_periodic_run() {
    let (discs, bx) = lattice_fluid_in::<2>(300, 0.5, Boundary::Periodic, 9).unwrap();
    let mut plain = Simulation::new(&discs, bx, Options::default()).unwrap();
    let mut sheared = plain.clone();
    sheared.set_shear(Some(Shear::new(0.0))).unwrap();
    plain.run_until(1.5, &mut ());
    sheared.run_until(1.5, &mut ());
    assert_eq!(plain.stats().disc_disc, sheared.stats().disc_disc);
    for i in 0..plain.len() {
        let d = (plain.position(i) - sheared.position(i)).norm2().sqrt();
        assert!(d < 1e-8, "disc {i} is {d} away");
    }
}

#[test]
fn a_disc_crossing_the_boundary_keeps_its_unwrapped_straight_line() {
    // Alone in the box, the disc flies straight through the images: each crossing of the top
    // takes it to the slid image below (x - delta, v_x - gamma L_y), and its unwrapped
    // position stays on the line it started on.
    let d = Disc::new(Vector::new([2.0, 5.0]), Vector::new([0.3, 1.0]), 0.5);
    let mut sim =
        Simulation::new(&[d], SimBox::periodic([10.0, 10.0]), Options::default()).unwrap();
    sim.set_shear(Some(Shear::new(0.2))).unwrap();
    for t in [3.0, 7.0, 18.0, 35.0] {
        sim.run_until(t, &mut ());
        let u = sim.unwrapped_position(0);
        let want = Vector::new([2.0 + 0.3 * t, 5.0 + t]);
        assert!(
            (u - want).norm2().sqrt() < 1e-12,
            "t = {t}: {u:?} for {want:?}"
        );
        // In the box, its velocity is the straight line's less the slide per crossing.
        let crossings = ((5.0 + t) / 10.0).floor();
        let v = sim.velocity(0);
        assert!((v[0] - (0.3 - 2.0 * crossings)).abs() < 1e-12, "{v:?}");
    }
}

#[test]
fn a_sheared_run_continues_from_its_checkpoint_bit_for_bit() {
    for dim in [2, 3] {
        if dim == 2 {
            let mut sim = sheared_fluid::<2>(200, 0.5, 0.7, 5);
            continues(&mut sim);
        } else {
            let mut sim = sheared_fluid::<3>(256, 0.35, 0.5, 6);
            continues(&mut sim);
        }
    }
}

fn continues<const D: usize>(sim: &mut Simulation<D>) {
    sim.run_until(2.0, &mut ());
    let bytes = sim.to_checkpoint(&[]);
    let (mut back, _) = Simulation::<D>::from_checkpoint(&bytes).unwrap();
    assert_eq!(back.shear(), sim.shear());
    sim.run_until(4.0, &mut ());
    back.run_until(4.0, &mut ());
    assert_eq!(sim.stats(), back.stats());
    for i in 0..sim.len() {
        assert_eq!(sim.position(i).0, back.position(i).0, "disc {i}");
        assert_eq!(sim.velocity(i).0, back.velocity(i).0, "disc {i}");
    }
}

#[test]
fn the_thermostat_keeps_the_streaming_profile_and_its_temperature() {
    // Velocities relative to the profile u_x = gamma (y - L_y / 2) drawn at kT 1: after many
    // redraws the mean x velocity in each slab follows the profile, and the peculiar
    // temperature settles above the bath's, where the redraws (0.5 per disc per unit time)
    // take out what the shear puts in: per disc `eta gamma^2 / rho`, about 0.1 here
    // (eta ~ 0.4 at packing 0.3), so kT ~ 1.2.
    let rate = 0.3;
    let mut sim = sheared_fluid::<2>(900, 0.3, rate, 8);
    let ly = sim.sim_box().lengths[1];
    let slabs = 6;
    let mut sum = vec![0.0; slabs];
    let mut count = vec![0.0; slabs];
    let mut kt = 0.0;
    for k in 1..=40 {
        sim.run_until(10.0 + k as f64 * 0.5, &mut ());
        for i in 0..sim.len() {
            let p = sim.position(i);
            let s = ((p[1] / ly * slabs as f64) as usize).min(slabs - 1);
            sum[s] += sim.velocity(i)[0];
            count[s] += 1.0;
        }
        kt += sim.peculiar_kinetic_energy() / sim.len() as f64 / 40.0;
    }
    for s in 0..slabs {
        let y = (s as f64 + 0.5) * ly / slabs as f64;
        let want = rate * (y - 0.5 * ly);
        let got = sum[s] / count[s];
        // 6000 samples of a unit variance per slab, correlated in time: 0.1 is ~5 sigma.
        assert!((got - want).abs() < 0.1, "slab {s}: {got} for {want}");
    }
    assert!(kt > 1.05 && kt < 1.4, "kT {kt}");
}

#[test]
fn shear_is_refused_where_it_cannot_be() {
    let d = Disc::new(Vector::new([2.0, 5.0]), Vector::new([0.3, 1.0]), 0.5);
    let walled = SimBox {
        lengths: [10.0, 10.0],
        boundaries: [Boundary::Periodic, Boundary::Walls],
    };
    let mut sim = Simulation::new(&[d], walled, Options::default()).unwrap();
    let e = sim.set_shear(Some(Shear::new(0.1))).unwrap_err();
    assert!(matches!(e, Error::BadShear(_)), "{e}");
    let mut sim =
        Simulation::new(&[d], SimBox::periodic([10.0, 10.0]), Options::default()).unwrap();
    for bad in [
        Shear::new(f64::NAN),
        Shear::new(f64::INFINITY),
        Shear {
            rate: 0.1,
            offset: 10.0,
        },
        Shear {
            rate: 0.1,
            offset: -1.0,
        },
    ] {
        assert!(matches!(sim.set_shear(Some(bad)), Err(Error::BadShear(_))));
    }
    assert_eq!(sim.shear(), None);
    sim.set_shear(Some(Shear::new(0.1))).unwrap();
    let e = sim
        .set_gravity(Some(Gravity { axis: 1, g: -1.0 }))
        .unwrap_err();
    assert!(matches!(e, Error::BadField(_)), "{e}");
    // Images that would overlap a disc at the offset given.
    let pair = [
        Disc::new(Vector::new([5.0, 9.6]), Vector::new([0.0, 0.0]), 0.5),
        Disc::new(Vector::new([2.0, 0.4]), Vector::new([0.0, 0.0]), 0.5),
    ];
    let mut sim =
        Simulation::new(&pair, SimBox::periodic([10.0, 10.0]), Options::default()).unwrap();
    let e = sim
        .set_shear(Some(Shear {
            rate: 0.1,
            offset: 3.0,
        }))
        .unwrap_err();
    assert!(e.to_string().contains("overlap"), "{e}");
    assert_eq!(sim.shear(), None);
}

#[test]
fn inelastic_sheared_grains_reach_a_steady_temperature() {
    // Uniformly sheared inelastic discs (no thermostat): viscous heating balances the
    // collisional loss, and the granular temperature settles (Lun et al. 1984; it scales as
    // (gamma sigma)^2 / (1 - e^2)).
    let (discs, bx) = lattice_fluid_in::<2>(400, 0.3, Boundary::Periodic, 2).unwrap();
    let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
    sim.set_shear(Some(Shear::new(0.5))).unwrap();
    sim.set_restitution(Some(Restitution {
        all: RestitutionLaw::Constant(0.8),
        ..Restitution::default()
    }))
    .unwrap();
    let mut temps = Vec::new();
    for k in 1..=30 {
        sim.run_until(k as f64 * 5.0, &mut ());
        temps.push(sim.peculiar_kinetic_energy() / sim.len() as f64);
    }
    let late = &temps[20..];
    let mean = late.iter().sum::<f64>() / late.len() as f64;
    let spread = late.iter().map(|t| (t - mean).abs()).fold(0.0, f64::max);
    assert!(spread < 0.3 * mean, "{temps:?}");
    assert!(sim.dissipated() > 0.0);
    assert!(worst_overlap(&sim) < 1e-9);
}

/// The brute-force simulator under shear: all discs on one clock, every pair against each of
/// its images around it (three rows of images along y, slid by `+-delta`, five along x), the
/// earliest contact taken, the discs moved and folded back into the box by the Lees-Edwards
/// rule. O(N^2) per event and obviously right. Returns `(time, i, j)` per collision.
fn naive_sheared<const D: usize>(
    discs: &mut [Disc<D>],
    lengths: [f64; D],
    rate: f64,
    t_end: f64,
) -> Vec<(f64, usize, usize)> {
    let (lx, ly) = (lengths[0], lengths[1]);
    let speed = rate * ly;
    let n = discs.len();
    let mut t = 0.0f64;
    let mut events = Vec::new();
    let fold = |d: &mut Disc<D>, t: f64| {
        let delta = (speed * t).rem_euclid(lx);
        while d.pos[1] >= ly {
            d.pos[1] -= ly;
            d.pos[0] -= delta;
            d.vel[0] -= speed;
        }
        while d.pos[1] < 0.0 {
            d.pos[1] += ly;
            d.pos[0] += delta;
            d.vel[0] += speed;
        }
        for a in 0..D {
            if a != 1 {
                d.pos[a] = d.pos[a].rem_euclid(lengths[a]);
            }
        }
    };
    loop {
        let delta = (speed * t).rem_euclid(lx);
        let mut best = (f64::INFINITY, 0, 0, Vector::<D>::ZERO, Vector::<D>::ZERO);
        for i in 0..n {
            for j in i + 1..n {
                for ny in [-1.0, 0.0, 1.0] {
                    for nx in [-2.0, -1.0, 0.0, 1.0, 2.0] {
                        let mut shift = Vector::<D>::ZERO;
                        shift[0] = nx * lx + ny * delta;
                        shift[1] = ny * ly;
                        let mut dv = discs[j].vel - discs[i].vel;
                        dv[0] += ny * speed;
                        let z_images: &[f64] = if D == 3 { &[-1.0, 0.0, 1.0] } else { &[0.0] };
                        for &nz in z_images {
                            if D == 3 {
                                shift[2] = nz * lengths[2];
                            }
                            let dr = discs[j].pos + shift - discs[i].pos;
                            let b = dr.dot(dv);
                            if b >= 0.0 {
                                continue;
                            }
                            let s = discs[i].radius + discs[j].radius;
                            let d = b * b - dv.norm2() * (dr.norm2() - s * s);
                            if d < 0.0 {
                                continue;
                            }
                            let dt = (-(b + d.sqrt()) / dv.norm2()).max(0.0);
                            if dt < best.0 {
                                let mut img_dv = Vector::<D>::ZERO;
                                img_dv[0] = ny * speed;
                                best = (dt, i, j, shift, img_dv);
                            }
                        }
                    }
                }
            }
        }
        if t + best.0 > t_end {
            return events;
        }
        t += best.0;
        for d in discs.iter_mut() {
            d.pos = d.pos.advanced(d.vel, best.0);
        }
        let (_, i, j, shift, img_dv) = best;
        // The shift was the image's at the prediction: the slide since then moves it on.
        let mut moved = shift;
        moved[0] += img_dv[0] * best.0;
        let dr = discs[j].pos + moved - discs[i].pos;
        let dv = discs[j].vel + img_dv - discs[i].vel;
        let (mi, mj) = (discs[i].mass, discs[j].mass);
        let jmp: Vector<D> = dr * (2.0 * mi * mj * dv.dot(dr) / ((mi + mj) * dr.norm2()));
        discs[i].vel += jmp / mi;
        discs[j].vel -= jmp / mj;
        for d in discs.iter_mut() {
            fold(d, t);
        }
        events.push((t, i, j));
    }
}

#[derive(Default)]
struct Pairs(Vec<(f64, usize, usize)>);

impl<const D: usize> edmd_core::Observer<D> for Pairs {
    fn on_event(&mut self, e: &edmd_core::EventRecord<D>, _: &Simulation<D>) {
        if let EventKind::DiscDisc { i, j } = e.kind {
            self.0.push((e.time, i.min(j), i.max(j)));
        }
    }
}

/// `n` discs placed at random without overlap in a periodic box `l` wide, each velocity
/// component up to `v_max`.
fn scattered<const D: usize>(n: usize, l: f64, v_max: f64, seed: u64) -> Vec<Disc<D>> {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut discs: Vec<Disc<D>> = Vec::new();
    while discs.len() < n {
        let p = Vector::<D>(std::array::from_fn(|_| next() * l));
        let v = Vector::<D>(std::array::from_fn(|_| v_max * (next() * 2.0 - 1.0)));
        let clear = discs.iter().all(|d| {
            let mut dr = d.pos - p;
            for a in 0..D {
                dr[a] -= l * (dr[a] / l).round();
            }
            // Clear of the images across y at offset 0, as the start is.
            dr.norm2() > 1.1 * 1.1
        });
        if clear {
            discs.push(Disc::new(p, v, 0.5));
        }
    }
    discs
}

#[test]
fn same_collisions_as_the_brute_force_simulator_under_shear() {
    // Slow discs (each velocity component below 0.1) under a strong shear (the images slide
    // at 4 to 7 per unit time, past many cells between a disc's own events, so that most
    // collisions are across the boundary): every collision in the same order, at the same
    // time, as the simulator that looks at every pair and image at every event.
    for (seed, rate) in [(1, 0.4), (2, -0.6), (3, 0.5)] {
        let l = 12.0;
        let discs = scattered::<2>(40, l, 0.1, seed);
        let mut sim =
            Simulation::new(&discs, SimBox::periodic([l, l]), Options::default()).unwrap();
        sim.set_shear(Some(Shear::new(rate))).unwrap();
        let mut reference = discs.clone();
        let expected = naive_sheared(&mut reference, [l, l], rate, 10.0);
        let mut log = Pairs::default();
        sim.run_until(10.0, &mut obs(&mut log));
        compare(seed, &log.0, &expected);
    }
    let l = 7.0;
    let discs = scattered::<3>(40, l, 0.1, 7);
    let mut sim = Simulation::new(&discs, SimBox::periodic([l; 3]), Options::default()).unwrap();
    sim.set_shear(Some(Shear::new(0.7))).unwrap();
    let mut reference = discs.clone();
    let expected = naive_sheared(&mut reference, [l; 3], 0.7, 10.0);
    let mut log = Pairs::default();
    sim.run_until(10.0, &mut obs(&mut log));
    compare(7, &log.0, &expected);
}

/// The first 100 collisions the same, in order, to 1e-9 in time. Rounding differs between the
/// two, and collisions amplify it, so that after some 150 collisions here the times part
/// beyond that.
fn compare(seed: u64, got: &[(f64, usize, usize)], expected: &[(f64, usize, usize)]) {
    assert!(
        expected.len() >= 100,
        "seed {seed}: {} collisions",
        expected.len()
    );
    assert!(got.len() >= 100, "seed {seed}: {} collisions", got.len());
    for (k, (a, b)) in got.iter().zip(expected).take(100).enumerate() {
        assert_eq!(
            (a.1, a.2),
            (b.1, b.2),
            "seed {seed}: collision {k}: {a:?} vs {b:?}"
        );
        assert!(
            (a.0 - b.0).abs() < 1e-9,
            "seed {seed}: collision {k}: {a:?} vs {b:?}"
        );
    }
}

/// Steady shear against Enskog: discs at packing 0.3 sheared at a reduced rate of 0.09
/// (Newtonian there), the bath's redraws rare (0.1 per disc per unit time, against about 3
/// collisions). Enskog's viscosity for discs (D. M. Gass, J. Chem. Phys. 54, 1898 (1971)) at the
/// measured temperature; molecular dynamics finds the hard-disc fluid within a few per cent of
/// it at this density (Garcia-Rojo, Luding and Brey, Phys. Rev. E 74, 061305 (2006)); the
/// bath's redraws lower it by a per cent or two. Tolerance 6%, about 3.5 standard errors.
#[test]
fn steady_shear_gives_enskogs_viscosity_at_moderate_density() {
    use edmd_core::measure::viscosity::enskog_viscosity;
    use edmd_core::measure::ShearStress;
    let mut sim = sheared_fluid::<2>(1600, 0.3, 0.1, 11);
    sim.set_thermostat(Some(Andersen {
        kt: 1.0,
        rate: 0.1,
        seed: 3,
    }))
    .unwrap();
    sim.run_until(30.0, &mut ());
    let mut m = ShearStress::new(&sim).unwrap();
    for k in 1..=20 {
        sim.run_until(30.0 + 15.0 * k as f64, &mut obs(&mut m));
        m.sample(&sim);
    }
    let s = m.summary(1.0, 1.0).unwrap();
    let enskog = enskog_viscosity(2, 0.3, 1.0, s.kt.value, 1.0);
    let ratio = s.eta.value / enskog;
    assert!(
        (ratio - 1.0).abs() < 0.06,
        "eta {} +- {} against Enskog's {enskog} at kT {}",
        s.eta.value,
        s.eta.error,
        s.kt.value
    );
    assert!(s.reduced_rate < 0.1, "{}", s.reduced_rate);
    assert!(s.kinetic < 0.0 && s.collisional < 0.0, "{s:?}");
}

#[test]
fn sheared_spheres_run_the_same_in_the_portable_and_the_x86_64_v3_loops() {
    let mut fast = sheared_fluid::<3>(500, 0.4, 0.5, 12);
    let mut portable = fast.clone();
    portable.set_portable_loop(true);
    fast.run_until(3.0, &mut ());
    portable.run_until(3.0, &mut ());
    assert_eq!(fast.stats(), portable.stats());
    for i in 0..fast.len() {
        assert_eq!(fast.position(i).0, portable.position(i).0, "sphere {i}");
        assert_eq!(fast.velocity(i).0, portable.velocity(i).0, "sphere {i}");
    }
}

/// The kinetic shear stress integrated exactly over each flight is the time average of the
/// instantaneous `sum m c_x c_y / V`, sampled every 1e-4 over two time units (about 400
/// crossings of cells and of the boundary, collisions and redraws): to 1e-4, the sampling's
/// own error. A disc just across the boundary can sit a rounding error outside the box; folded
/// back, its profile velocity was off by `gamma L_y`, which made the stress 3% too large.
#[test]
fn the_exact_stress_integrals_are_the_time_average_of_the_stress() {
    use edmd_core::measure::ShearStress;
    for thermostat in [false, true] {
        let mut sim = sheared_fluid::<2>(30, 0.1, 0.3, 11);
        if !thermostat {
            sim.set_thermostat(None).unwrap();
        }
        sim.run_until(5.0, &mut ());
        let mut m = ShearStress::new(&sim).unwrap();
        let v = sim.sim_box().volume();
        let t0 = sim.time();
        let n = 20000;
        let mut sampled = 0.0;
        for k in 1..=n {
            sim.run_until(t0 + 1e-4 * k as f64, &mut obs(&mut m));
            let s: f64 = (0..sim.len())
                .map(|i| {
                    let c = sim.peculiar_velocity(i);
                    sim.mass(i) * c[0] * c[1]
                })
                .sum();
            sampled += s / v / n as f64;
        }
        m.sample(&sim);
        let exact = m.blocks()[0].kinetic;
        assert!(
            (exact - sampled).abs() < 1e-4 * sampled.abs(),
            "thermostat {thermostat}: {exact} against {sampled}"
        );
        assert!(sim.stats().cell_crossing > 300, "{:?}", sim.stats());
    }
}
