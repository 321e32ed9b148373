//! The configuration generators: validity, determinism, the physics they promise, and clear
//! refusals of what cannot be built.

use edmd_core::setup::fluid::{Recipe, FLUID_MAX_PACKING};
use edmd_core::setup::generators::{
    Brownian, Dense, Diffusion1, Diffusion2, Lattice, OneRed, Single, DIFFUSION2_PARTITION,
};
use edmd_core::setup::{
    generate, lattice_fluid, melting_threshold, packing_of, psi6, Fluid, GenKind, Mixture,
    Neighbours, Sizes,
};
use edmd_core::{Boundary, Error, Options, Simulation, System, Vector};

/// Builds a simulation (which validates) and checks overlaps and walls once more.
fn assert_valid(name: &str, s: &System) -> Simulation {
    assert!(s.barriers.is_empty(), "{name}: barriers");
    let sim = Simulation::new(&s.discs, s.sim_box, Options::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(sim.overlaps(1e-9).count, 0, "{name}: overlaps");
    assert!(sim.discs_outside(1e-9).is_empty(), "{name}: outside");
    assert!(sim.adjusted_discs() == 0, "{name}: adjusted");
    sim
}

fn momentum(s: &System) -> Vector {
    s.discs.iter().fold(Vector::ZERO, |p, d| p + d.vel * d.mass)
}

fn kinetic_energy(s: &System) -> f64 {
    s.discs.iter().map(|d| d.kinetic_energy()).sum()
}

fn invalid(r: Result<System, Error>, words: &[&str]) {
    match r {
        Err(Error::Invalid(m)) => {
            for w in words {
                assert!(m.contains(w), "message {m:?} lacks {w:?}");
            }
        }
        Err(e) => panic!("expected Error::Invalid containing {words:?}, got {e:?}"),
        Ok(s) => panic!(
            "expected Error::Invalid containing {words:?}, got {} discs",
            s.discs.len()
        ),
    }
}

#[test]
fn every_kind_builds_a_valid_simulation() {
    for name in GenKind::NAMES {
        let kind = GenKind::from_name(name).unwrap();
        assert_eq!(kind.name(), name);
        let s = generate(&kind, 11).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!s.discs.is_empty(), "{name}");
        assert_valid(name, &s);
        if name != "fluid" && name != "mixture" {
            assert_eq!(s.sim_box, edmd_core::SimBox::unit(), "{name}");
        }
    }
    match GenKind::from_name("billiards") {
        Err(Error::Invalid(m)) => assert!(m.contains("billiards") && m.contains("one-red"), "{m}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn same_seed_same_discs_other_seed_other_discs() {
    let small = [
        GenKind::Fluid(Fluid {
            n: 100,
            ..Fluid::default()
        }),
        GenKind::Mixture(Mixture {
            n: 100,
            ..Mixture::default()
        }),
    ];
    let kinds = GenKind::NAMES[..9]
        .iter()
        .map(|n| GenKind::from_name(n).unwrap())
        .chain(small);
    for kind in kinds {
        let name = kind.name();
        let a = generate(&kind, 5).unwrap();
        let b = generate(&kind, 5).unwrap();
        assert_eq!(a, b, "{name}: same seed");
        let c = generate(&kind, 6).unwrap();
        if name == "head-on" || name == "angled" {
            assert_eq!(a, c, "{name} has no random choices");
        } else {
            assert_ne!(a.discs, c.discs, "{name}: other seed");
        }
    }
}

#[test]
fn lattice_has_zero_momentum_equal_speeds_and_the_requested_temperature() {
    for n in [100, 101, 2, 3] {
        let kt = 3e-5;
        let p = Lattice {
            n,
            kt,
            mass: 2.0,
            ..Lattice::default()
        };
        let s = generate(&GenKind::Lattice(p), 3).unwrap();
        assert_eq!(s.discs.len(), n);
        let speed = (2.0 * kt / 2.0f64).sqrt();
        assert!(momentum(&s).norm2().sqrt() < 1e-12 * speed, "n = {n}");
        let per_disc = kinetic_energy(&s) / n as f64;
        assert!((per_disc / kt - 1.0).abs() < 1e-12, "n = {n}: {per_disc}");
        for d in &s.discs {
            assert!((d.vel.norm2().sqrt() / speed - 1.0).abs() < 1e-12);
        }
    }
}

#[test]
fn princeton_kinds_look_like_the_data_files() {
    let s = generate(&GenKind::OneRed(OneRed::default()), 1).unwrap();
    assert_eq!(s.discs.len(), 101);
    assert_eq!(s.discs[0].colour, [200, 0, 0]);
    assert!(s.discs[1..]
        .iter()
        .all(|d| d.colour == [0, 0, 200] && d.vel == Vector::ZERO));

    let s = generate(&GenKind::Brownian(Brownian::default()), 1).unwrap();
    assert_eq!(s.discs[0].pos, Vector::new([0.5, 0.5]));
    assert_eq!((s.discs[0].mass, s.discs[0].colour), (100.0, [200, 0, 0]));
    assert!(momentum(&s).norm2().sqrt() < 1e-15);

    let p = Diffusion1::default();
    let s = generate(&GenKind::Diffusion1(p), 1).unwrap();
    let half = 0.5 * p.region;
    assert!(s.discs.iter().all(
        |d| (0..2).all(|a| (d.pos[a] - 0.5).abs() <= half - p.radius)
            && (d.vel.norm2().sqrt() - p.speed).abs() < 1e-15
    ));

    let p = Diffusion2::default();
    let s = generate(&GenKind::Diffusion2(p), 1).unwrap();
    assert_eq!(s.discs.len(), 2 * p.n);
    for (species, colour) in [(0u16, [0, 0, 200]), (1, [0, 200, 0])] {
        let side: Vec<_> = s.discs.iter().filter(|d| d.species == species).collect();
        assert_eq!(side.len(), p.n);
        assert!(side.iter().all(|d| d.colour == colour));
        assert!(side.iter().all(|d| {
            let gap = d.pos[0] - DIFFUSION2_PARTITION;
            if species == 0 {
                gap <= -d.radius
            } else {
                gap >= d.radius
            }
        }));
        // Each half was thermalised at kT on its own: its energy is n kT (conserved).
        let ke: f64 = side.iter().map(|d| d.kinetic_energy()).sum();
        assert!((ke / (p.n as f64 * p.kt) - 1.0).abs() < 1e-9, "{ke}");
    }

    let p = Dense::default();
    let s = generate(&GenKind::Dense(p), 1).unwrap();
    let area: f64 = s
        .discs
        .iter()
        .map(|d| std::f64::consts::PI * d.radius * d.radius)
        .sum();
    assert!((area - p.packing).abs() < 1e-12);
}

#[test]
fn perfect_triangular_lattice_has_psi6_one() {
    let (discs, sim_box) = lattice_fluid(24 * 20, 0.7, Boundary::Periodic, 1).unwrap();
    let v = psi6(&discs, &sim_box, Neighbours::Nearest(6));
    assert!((v - 1.0).abs() < 1e-9, "{v}");
    // So a lattice never passes for melted.
    assert!(v > melting_threshold(discs.len()));
}

#[test]
fn fluid_at_070_melts_with_either_boundary() {
    for (n, boundary) in [(400, Boundary::Periodic), (1000, Boundary::Walls)] {
        let f = Fluid {
            n,
            packing: FLUID_MAX_PACKING,
            boundary,
            ..Fluid::default()
        };
        let (s, report) = f.generate_with_report(2).unwrap();
        assert_eq!(s.discs.len(), n);
        assert_eq!(s.sim_box.boundaries, [boundary; 2]);
        assert!((packing_of(&s.discs, &s.sim_box) - 0.70).abs() < 1e-12);
        let order = psi6(&s.discs, &s.sim_box, Neighbours::Nearest(6));
        assert_eq!(order, report.psi6);
        assert!(order < melting_threshold(n), "{order}");
        assert!((kinetic_energy(&s) / n as f64 - 1.0).abs() < 1e-9);
        assert!(s.discs.iter().all(|d| d.radius == 0.5 && d.mass == 1.0));
        assert_valid("fluid", &s);
    }
}

#[test]
fn a_lattice_that_cannot_melt_is_an_error() {
    // Melting a full lattice at 0.70 takes far more than 5 collisions per disc.
    let f = Fluid {
        n: 100,
        packing: 0.7,
        recipe: Recipe {
            vacancies: 0.0,
            melt_packing: 0.7,
            max_collisions_per_disc: 5,
            ..Recipe::default()
        },
        ..Fluid::default()
    };
    invalid(f.generate(1), &["fluid", "did not melt"]);
}

#[test]
fn mixtures_have_the_requested_composition_and_packing() {
    let m = Mixture {
        n: 400,
        packing: 0.78,
        sizes: Sizes::Binary {
            size_ratio: 1.4,
            fraction_large: 0.3,
        },
        ..Mixture::default()
    };
    let (s, report) = m.generate_with_report(4).unwrap();
    let large: Vec<_> = s.discs.iter().filter(|d| d.species == 1).collect();
    assert_eq!(large.len(), 120);
    assert!(large.iter().all(|d| d.radius == 0.7));
    assert!(s.discs.iter().all(|d| d.species == 1 || d.radius == 0.5));
    assert!((packing_of(&s.discs, &s.sim_box) - 0.78).abs() < 1e-12);
    assert!(report.stages > 0);
    assert_valid("binary", &s);

    let m = Mixture {
        n: 300,
        packing: 0.75,
        boundary: Boundary::Walls,
        sizes: Sizes::Polydisperse { spread: 0.15 },
        ..Mixture::default()
    };
    let s = m.generate(4).unwrap();
    assert!(s
        .discs
        .iter()
        .all(|d| (0.85..=1.15).contains(&(2.0 * d.radius))));
    assert!((packing_of(&s.discs, &s.sim_box) - 0.75).abs() < 1e-12);
    assert_valid("polydisperse", &s);
}

#[test]
fn unreachable_requests_are_errors() {
    let fluid = |n, packing| {
        GenKind::Fluid(Fluid {
            n,
            packing,
            ..Fluid::default()
        })
    };
    invalid(generate(&fluid(400, 0.95), 1), &["fluid", "0.95"]);
    invalid(generate(&fluid(400, 0.75), 1), &["fluid", "0.75", "0.7"]);
    invalid(generate(&fluid(0, 0.5), 1), &["fluid", "at least"]);
    invalid(generate(&fluid(400, -0.1), 1), &["fluid", "outside"]);
    let mixture = |packing, sizes| {
        GenKind::Mixture(Mixture {
            packing,
            sizes,
            ..Mixture::default()
        })
    };
    invalid(
        generate(&mixture(0.95, Sizes::default()), 1),
        &["mixture", "0.95"],
    );
    let binary = |size_ratio, fraction_large| Sizes::Binary {
        size_ratio,
        fraction_large,
    };
    invalid(
        generate(&mixture(0.7, binary(-1.4, 0.5)), 1),
        &["size ratio"],
    );
    invalid(generate(&mixture(0.7, binary(1.4, 1.5)), 1), &["fraction"]);
    invalid(
        generate(&mixture(0.7, Sizes::Polydisperse { spread: -0.1 }), 1),
        &["spread"],
    );
    // Bounded effort: too few compression stages to get there.
    let m = Mixture {
        packing: 0.8,
        recipe: Recipe {
            max_stages: 3,
            ..Recipe::default()
        },
        ..Mixture::default()
    };
    invalid(m.generate(1), &["mixture", "compression", "stages"]);

    let lattice = |n, radius| {
        GenKind::Lattice(Lattice {
            n,
            radius,
            ..Lattice::default()
        })
    };
    invalid(generate(&lattice(0, 0.01), 1), &["lattice", "at least"]);
    invalid(generate(&lattice(100, -0.01), 1), &["lattice", "radius"]);
    invalid(generate(&lattice(100, 0.06), 1), &["lattice", "radius"]);
    invalid(
        generate(
            &GenKind::OneRed(OneRed {
                n: 0,
                ..OneRed::default()
            }),
            1,
        ),
        &["one-red", "at least"],
    );
    invalid(
        generate(
            &GenKind::OneRed(OneRed {
                n: 2000,
                ..OneRed::default()
            }),
            1,
        ),
        &["one-red", "%"],
    );
    invalid(
        generate(
            &GenKind::Single(Single {
                radius: 0.6,
                ..Single::default()
            }),
            1,
        ),
        &["single", "radius"],
    );
    invalid(
        generate(
            &GenKind::Single(Single {
                speed: -1.0,
                ..Single::default()
            }),
            1,
        ),
        &["single", "speed"],
    );
    for packing in [0.95, 0.9] {
        invalid(
            generate(
                &GenKind::Dense(Dense {
                    packing,
                    ..Dense::default()
                }),
                1,
            ),
            &["dense", "packing"],
        );
    }
    invalid(
        generate(
            &GenKind::Brownian(Brownian {
                big_radius: 0.6,
                ..Brownian::default()
            }),
            1,
        ),
        &["brownian", "big radius"],
    );
    invalid(
        generate(
            &GenKind::Diffusion1(Diffusion1 {
                region: 0.05,
                ..Diffusion1::default()
            }),
            1,
        ),
        &["diffusion1", "%"],
    );
    invalid(
        generate(
            &GenKind::Diffusion2(Diffusion2 {
                radius: 1e-7,
                n: 3,
                ..Diffusion2::default()
            }),
            1,
        ),
        &["diffusion2", "collide"],
    );
}

// Regression: the library generators accepted packings near 0 (a fluid at packing 1e-300,
// whose box is so large that melting by collisions never ends) and `dense` with one disc
// (which never collides, so its compression never ends); only the command line refused them.
#[test]
fn generators_refuse_runs_that_never_finish() {
    use edmd_core::setup::MIN_PACKING;
    for packing in [1e-300, 1e-4, MIN_PACKING / 2.0] {
        let fluid = Fluid {
            n: 100,
            packing,
            ..Fluid::default()
        };
        invalid(fluid.generate(1), &["fluid", "packing"]);
        assert!(matches!(
            fluid.generate_in::<3>(1),
            Err(Error::Invalid(m)) if m.contains("packing")
        ));
        invalid(generate(&GenKind::Fluid(fluid), 1), &["fluid", "packing"]);
        let mixture = Mixture {
            n: 100,
            packing,
            ..Mixture::default()
        };
        invalid(mixture.generate(1), &["packing"]);
        invalid(
            generate(
                &GenKind::Dense(Dense {
                    packing,
                    ..Dense::default()
                }),
                1,
            ),
            &["dense", "packing"],
        );
    }
    invalid(
        generate(
            &GenKind::Dense(Dense {
                n: 1,
                ..Dense::default()
            }),
            1,
        ),
        &["dense", "at least 2"],
    );
}

/// Fluids and mixtures come out in the order of the cells (a largest diameter wide, the last
/// axis slowest) that hold them, so that neighbours sit near each other in memory
/// (BENCHMARKS.md): each particle's cell is at or after the one before it,
/// and most particles share a row of cells with the one before.
#[test]
fn fluids_and_mixtures_come_out_in_cell_order() {
    let fluid = Fluid {
        n: 400,
        packing: 0.5,
        ..Fluid::default()
    };
    let mixture = Mixture {
        n: 400,
        packing: 0.6,
        ..Mixture::default()
    };
    for s in [fluid.generate(3).unwrap(), mixture.generate(3).unwrap()] {
        let width = s.discs.iter().map(|d| 2.0 * d.radius).fold(0.0, f64::max);
        let cells = s.sim_box.lengths.map(|l| (l / width).floor());
        let cell = |p: Vector, a: usize| (p[a] / s.sim_box.lengths[a] * cells[a]).floor();
        let key = |p: Vector| cell(p, 1) * cells[0] + cell(p, 0);
        let keys: Vec<f64> = s.discs.iter().map(|d| key(d.pos)).collect();
        assert!(keys.windows(2).all(|w| w[0] <= w[1]), "{keys:?}");
        let same_row = s
            .discs
            .windows(2)
            .filter(|w| cell(w[0].pos, 1) == cell(w[1].pos, 1))
            .count();
        assert!(same_row > 300, "{same_row} of 399");
    }
}
