//! Packings (`edmd_core::pack`): the Lubachevsky-Stillinger compression against a
//! hand-derived collision, determinism, exactness (no overlaps, a file `edmd run` accepts) and
//! jamming against published values.

use edmd_core::pack::{
    contacts, gap_tolerance, random_start, PackOptions, PackSizes, Packer, Packing, Stop,
};
use edmd_core::{Boundary, Disc, Error, Options, SimBox, Simulation, Vector, OVERLAP_TOLERANCE};

fn pack<const D: usize>(
    n: usize,
    sizes: PackSizes,
    boundary: Boundary,
    options: PackOptions,
    seed: u64,
) -> Packing<D> {
    let (discs, sim_box) = random_start::<D>(n, sizes, boundary, seed).unwrap();
    Packer::new(&discs, sim_box, options)
        .unwrap()
        .run(|_| true)
        .unwrap()
}

const BIDISPERSE: PackSizes = PackSizes::Binary {
    size_ratio: 1.4,
    fraction_large: 0.5,
};

/// Exactness: no pair overlaps beyond the engine's tolerance, and the engine accepts the
/// packing as a start.
fn assert_exact<const D: usize>(p: &Packing<D>) {
    let c = contacts(&p.discs, &p.sim_box, 1e-9);
    assert!(c.min_gap > -OVERLAP_TOLERANCE, "overlap {}", c.min_gap);
    Simulation::new(&p.discs, p.sim_box, Options::default()).unwrap();
}

/// Two discs of diameter 1 in a periodic 10 x 10 box, at x = 3 and 7 (y = 5), meeting head-on
/// at speeds +-1 (rms speed 1, so the packer does not rescale them), growing at G = 0.5:
/// the contact distance is `1 + 0.5 t` and the centres are `4 - 2 t` apart, so they touch at
/// `t = 3 / 2.5 = 1.2`. The LS rule (Donev, Torquato and Stillinger, J. Comput. Phys. 202, 737
/// (2005)) with normal relative velocity `u = -2` and contact growth speed `b = 0.5` gives
/// `u' = 2b - u = 3`: velocities -+1.5. Stopped at t = 1.5 by the target packing fraction
/// `2 pi (1.75/2)^2 / 100`: the discs are at 4.2 -+ 1.5 * 0.3.
#[test]
fn two_growing_discs_meet_when_the_formula_says_and_leave_with_the_ls_velocities() {
    let discs = [
        Disc::new(Vector::new([3.0, 5.0]), Vector::new([1.0, 0.0]), 0.5),
        Disc::new(Vector::new([7.0, 5.0]), Vector::new([-1.0, 0.0]), 0.5),
    ];
    let target = 2.0 * std::f64::consts::PI * 0.875 * 0.875 / 100.0;
    let options = PackOptions {
        growth_rate: 0.5,
        target_packing: Some(target),
        ..PackOptions::default()
    };
    let p = Packer::new(&discs, SimBox::periodic([10.0, 10.0]), options)
        .unwrap()
        .run(|_| true)
        .unwrap();
    assert_eq!(p.stop, Stop::Packing);
    assert_eq!(p.collisions, 1);
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert!(close(p.discs[0].vel[0], -1.5), "{:?}", p.discs[0].vel);
    assert!(close(p.discs[1].vel[0], 1.5), "{:?}", p.discs[1].vel);
    assert!(close(p.discs[0].pos[0], 4.2 - 0.45), "{:?}", p.discs[0].pos);
    assert!(close(p.discs[1].pos[0], 5.8 + 0.45), "{:?}", p.discs[1].pos);
    assert!(close(p.discs[0].radius, 0.875));
    assert_eq!(p.discs[0].vel[1], 0.0);
}

#[test]
fn the_same_seed_gives_the_same_packing_bit_for_bit() {
    let options = PackOptions {
        max_pressure: 1e6,
        ..PackOptions::default()
    };
    let a = pack::<2>(200, BIDISPERSE, Boundary::Periodic, options, 7);
    let b = pack::<2>(200, BIDISPERSE, Boundary::Periodic, options, 7);
    assert_eq!(a, b);
    let c = pack::<2>(200, BIDISPERSE, Boundary::Periodic, options, 8);
    assert_ne!(a.discs, c.discs);
}

#[test]
fn a_target_packing_fraction_is_reached_exactly_and_runs_in_the_engine() {
    for boundary in [Boundary::Periodic, Boundary::Walls] {
        let options = PackOptions {
            target_packing: Some(0.5),
            ..PackOptions::default()
        };
        let p = pack::<3>(300, PackSizes::MONODISPERSE, boundary, options, 3);
        assert_eq!(p.stop, Stop::Packing);
        assert!(
            (p.packing_fraction - 0.5).abs() < 1e-12,
            "{}",
            p.packing_fraction
        );
        let phi = edmd_core::setup::packing_of(&p.discs, &p.sim_box);
        assert!((phi - 0.5).abs() < 1e-12, "{phi}");
        assert_exact(&p);
        // Below jamming the pressure is the dense fluid's, finite (Carnahan-Starling gives
        // Z = 13 at 0.5; a compressed LS fluid is somewhat above equilibrium).
        let z = p.reduced_pressure.unwrap();
        assert!((8.0..40.0).contains(&z), "{z}");
    }
}

/// 2D 50:50 bidisperse discs with diameter ratio 1.4 at G = 0.02. O'Hern, Silbert, Liu and
/// Nagel, PRE 68, 011306 (2003), find phi_J = 0.842 for N -> infinity (soft discs, fast
/// quench); LS compressions of hard discs at this rate jam at the same place (measured here
/// at N = 1000, seed 1: 0.8431). At N = 300 the sample-to-sample spread
/// is about 0.005, so the tolerance is 0.012.
#[test]
fn bidisperse_discs_jam_near_the_ohern_packing_fraction() {
    let p = pack::<2>(
        300,
        BIDISPERSE,
        Boundary::Periodic,
        PackOptions::default(),
        1,
    );
    assert!(
        matches!(p.stop, Stop::Pressure | Stop::Converged),
        "{:?}",
        p.stop
    );
    assert!(p.reduced_pressure.unwrap() > 1e11);
    assert!(
        (p.packing_fraction - 0.842).abs() < 0.012,
        "{}",
        p.packing_fraction
    );
    assert_exact(&p);
}

/// 3D monodisperse spheres at G = 0.02: Skoge, Donev, Stillinger and Torquato, PRE 74, 041127
/// (2006), jam near phi = 0.64 (their code, run here at N = 1000 from packing 0.01 to
/// pressure 1e12, gives 0.637 at G = 0.02 and 0.647 at G = 0.002: issue 12). At N = 400 the
/// sample spread is about 0.005; tolerance 0.012.
#[test]
fn monodisperse_spheres_jam_near_the_skoge_packing_fraction() {
    let p = pack::<3>(
        400,
        PackSizes::MONODISPERSE,
        Boundary::Periodic,
        PackOptions::default(),
        2,
    );
    assert!(
        matches!(p.stop, Stop::Pressure | Stop::Converged),
        "{:?}",
        p.stop
    );
    assert!(
        (p.packing_fraction - 0.637).abs() < 0.012,
        "{}",
        p.packing_fraction
    );
    assert_exact(&p);
}

/// Slowly grown (G = 0.002) bidisperse discs are jammed: the non-rattlers are isostatic,
/// `z = 2 d = 4` up to the `2d/N` finite-size term and what the gap tolerance misses
/// (`1000 d / p`), and the rattlers are a few percent (issue 12 expects about 5% in 2D;
/// measured here at N = 1000: 7.2%, z = 3.95).
#[test]
fn slowly_grown_discs_are_isostatic_with_a_few_percent_rattlers() {
    let options = PackOptions {
        growth_rate: 0.002,
        ..PackOptions::default()
    };
    let p = pack::<2>(150, BIDISPERSE, Boundary::Periodic, options, 4);
    let tol = gap_tolerance(p.reduced_pressure.unwrap(), 2);
    let c = contacts(&p.discs, &p.sim_box, tol);
    let rattlers = c.rattlers as f64 / 150.0;
    assert!(
        (3.85..=4.05).contains(&c.mean_contacts),
        "z {} rattlers {rattlers}",
        c.mean_contacts
    );
    assert!((0.0..0.15).contains(&rattlers), "{rattlers}");
    assert_exact(&p);
}

#[test]
fn walls_hold_a_jammed_packing_inside() {
    let options = PackOptions {
        max_pressure: 1e9,
        ..PackOptions::default()
    };
    let p = pack::<2>(200, BIDISPERSE, Boundary::Walls, options, 5);
    assert!(p.wall_collisions > 0);
    assert!(p.reduced_pressure.unwrap() >= 1e9);
    // Walls leave room along them: below the periodic packing fraction.
    assert!(
        (0.76..0.85).contains(&p.packing_fraction),
        "{}",
        p.packing_fraction
    );
    assert_exact(&p);
}

#[test]
fn bad_options_and_starts_are_refused() {
    let (discs, sim_box) =
        random_start::<2>(50, PackSizes::MONODISPERSE, Boundary::Periodic, 1).unwrap();
    for bad in [
        PackOptions {
            growth_rate: 0.0,
            ..PackOptions::default()
        },
        PackOptions {
            max_pressure: f64::NAN,
            ..PackOptions::default()
        },
        PackOptions {
            target_packing: Some(1.2),
            ..PackOptions::default()
        },
        // Below the start's packing fraction.
        PackOptions {
            target_packing: Some(0.001),
            ..PackOptions::default()
        },
    ] {
        assert!(matches!(
            Packer::new(&discs, sim_box, bad),
            Err(Error::Invalid(_))
        ));
    }
    let mut overlapping = discs.clone();
    overlapping[1].pos = overlapping[0].pos;
    assert!(matches!(
        Packer::new(&overlapping, sim_box, PackOptions::default()),
        Err(Error::Overlap { .. })
    ));
    let mut at_rest = discs;
    for d in &mut at_rest {
        d.vel = Vector::ZERO;
    }
    assert!(Packer::new(&at_rest, sim_box, PackOptions::default()).is_err());
    assert!(PackSizes::Polydisperse { std: 0.7 }.validate().is_err());
}

/// No packing of equal discs passes the hexagonal one (`pi / (2 sqrt 3)`, Thue), nor of equal
/// spheres the face-centred cubic (`pi / (3 sqrt 2)`, Hales): such a target was accepted and
/// the compression stopped on pressure short of it (found by a new user's walk).
/// Mixtures can pack closer, and keep any target below 1.
#[test]
fn targets_beyond_the_closest_packing_of_equal_particles_are_refused() {
    let target = |phi: f64| PackOptions {
        target_packing: Some(phi),
        ..PackOptions::default()
    };
    let (discs, b2) =
        random_start::<2>(50, PackSizes::MONODISPERSE, Boundary::Periodic, 1).unwrap();
    let (spheres, b3) =
        random_start::<3>(50, PackSizes::MONODISPERSE, Boundary::Periodic, 1).unwrap();
    let refused = |r: Result<Packer<2>, Error>| match r {
        Err(Error::Invalid(m)) => assert!(
            m.contains("beyond the closest packing of equal discs (0.9069)"),
            "{m}"
        ),
        other => panic!("{:?}", other.map(|_| ())),
    };
    refused(Packer::new(&discs, b2, target(0.907)));
    assert!(Packer::new(&discs, b2, target(0.906)).is_ok());
    match Packer::new(&spheres, b3, target(0.7405)) {
        Err(Error::Invalid(m)) => assert!(m.contains("equal spheres (0.7405)"), "{m}"),
        other => panic!("{:?}", other.map(|_| ())),
    }
    assert!(Packer::new(&spheres, b3, target(0.7404)).is_ok());
    let mut mixed = discs.clone();
    for d in mixed.iter_mut().step_by(2) {
        d.radius *= 0.7;
    }
    assert!(Packer::new(&mixed, b2, target(0.95)).is_ok());
}

/// Too few particles for a periodic box: they grow to a third of it and the packer stops with
/// an error instead of letting a particle meet its own image.
#[test]
fn a_periodic_box_too_small_for_the_particles_is_an_error_not_a_hang() {
    let e = match Packer::new(
        &random_start::<3>(8, PackSizes::MONODISPERSE, Boundary::Periodic, 1)
            .unwrap()
            .0,
        random_start::<3>(8, PackSizes::MONODISPERSE, Boundary::Periodic, 1)
            .unwrap()
            .1,
        PackOptions::default(),
    )
    .unwrap()
    .run(|_| true)
    {
        Err(e) => e.to_string(),
        Ok(p) => panic!("packed {p:?}"),
    };
    assert!(e.contains("too few particles"), "{e}");
}

/// Polydisperse spheres (uniform diameters, relative std 0.1) pack and keep their sizes'
/// ratios.
#[test]
fn polydisperse_spheres_keep_their_size_ratios() {
    let sizes = PackSizes::Polydisperse { std: 0.1 };
    let (start, _) = random_start::<3>(200, sizes, Boundary::Periodic, 6).unwrap();
    let options = PackOptions {
        max_pressure: 1e6,
        ..PackOptions::default()
    };
    let p = pack::<3>(200, sizes, Boundary::Periodic, options, 6);
    // The packing is in cell order, the start in random order: compared sorted by size.
    let sorted = |discs: &[Disc<3>]| {
        let mut r: Vec<f64> = discs.iter().map(|d| d.radius).collect();
        r.sort_by(f64::total_cmp);
        r
    };
    let (a, b) = (sorted(&p.discs), sorted(&start));
    let k = a[0] / b[0];
    for (a, b) in a.iter().zip(&b) {
        assert!((a / b / k - 1.0).abs() < 1e-12);
    }
    assert!(
        (0.6..0.68).contains(&p.packing_fraction),
        "{}",
        p.packing_fraction
    );
    assert_exact(&p);
}

// A compression looked for Ctrl-C only at its velocity rescalings, every
// `collisions_per_rescale` collisions per particle: minutes apart for 10^6 particles, or with
// many collisions asked for between rescalings. `run_watched` asks its `stop` every 65 536
// events: here, with 10^6 collisions per particle between rescalings, a request at the third
// look stops the run within three chunks of events, long before the first rescaling.
#[test]
fn a_stop_request_between_rescalings_is_answered_within_a_chunk_of_events() {
    let (discs, sim_box) = random_start::<2>(200, BIDISPERSE, Boundary::Periodic, 3).unwrap();
    let options = PackOptions {
        collisions_per_rescale: 1e6,
        ..PackOptions::default()
    };
    let mut looks = 0;
    let mut rescalings = 0;
    let p = Packer::new(&discs, sim_box, options)
        .unwrap()
        .run_watched(
            |_| {
                rescalings += 1;
                true
            },
            || {
                looks += 1;
                looks == 3
            },
        )
        .unwrap();
    assert_eq!(p.stop, Stop::Interrupted);
    assert_eq!(rescalings, 0);
    assert!(p.events <= 2 * 65_536 + 1, "{} events", p.events);
}

// Looking for a stop request changes nothing: the packing of a run asked "stop?" every chunk
// (and told no) is the one of `run`, bit for bit, and so are its events.
#[test]
fn looking_for_a_stop_request_leaves_the_packing_bit_for_bit() {
    let options = PackOptions {
        max_pressure: 1e6,
        ..PackOptions::default()
    };
    let (discs, sim_box) = random_start::<3>(300, BIDISPERSE, Boundary::Walls, 5).unwrap();
    let plain = Packer::new(&discs, sim_box, options)
        .unwrap()
        .run(|_| true)
        .unwrap();
    let mut looks = 0u64;
    let watched = Packer::new(&discs, sim_box, options)
        .unwrap()
        .run_watched(
            |_| true,
            || {
                looks += 1;
                false
            },
        )
        .unwrap();
    assert!(looks > 1, "{looks} looks");
    assert_eq!(watched, plain);
}

// A packing fraction that stopped changing was reported as converged (a jammed packing)
// whatever the pressure: growth too slow for double precision "converged" in the dilute fluid
// and the start was written as a packing. Far from jamming it is now an error naming the
// growth rate; and a growth rate too slow to change the packing fraction even over the
// longest interval is refused by `Packer::new`. (Here the relative change that counts as
// converged is raised to 10^-3, so that an ordinary growth rate meets both.)
#[test]
fn a_packing_fraction_that_stops_changing_far_from_jamming_is_an_error() {
    let (discs, sim_box) = random_start::<2>(100, BIDISPERSE, Boundary::Periodic, 1).unwrap();
    let options = |growth_rate| PackOptions {
        growth_rate,
        min_relative_change: 1e-3,
        ..PackOptions::default()
    };
    let e = Packer::new(&discs, sim_box, options(1e-7))
        .map(|_| ())
        .unwrap_err();
    assert!(e.to_string().contains("too slow"), "{e}");
    let e = Packer::new(&discs, sim_box, options(1e-5))
        .unwrap()
        .run(|_| true)
        .unwrap_err();
    assert!(e.to_string().contains("far from jamming"), "{e}");
    // Near jamming the same stop is a packing.
    let p = Packer::new(
        &discs,
        sim_box,
        PackOptions {
            min_relative_change: 1e-9,
            ..PackOptions::default()
        },
    )
    .unwrap()
    .run(|_| true)
    .unwrap();
    assert_eq!(p.stop, Stop::Converged);
    assert!(p.reduced_pressure.unwrap() > 2e5);
}
