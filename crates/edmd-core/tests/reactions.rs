//! Reactive collisions: the rules' kinematics (heat into the normal relative motion, momentum
//! conserved), the line-of-centres law in equilibrium, exact checkpoints, and the refusal of
//! rules that cannot be.

use crate::support::obs;
use edmd_core::measure::theory::line_of_centres_fraction;
use edmd_core::setup::lattice_fluid_in;
use edmd_core::{
    Boundary, Disc, Error, EventKind, EventRecord, Observer, Options, Potential, Reaction,
    Reactions, SimBox, Simulation, Vector,
};

fn rule(a: u16, b: u16, c: u16, d: u16, activation: f64) -> Reaction {
    Reaction {
        reactants: (a, b),
        products: (c, d),
        activation,
        probability: 1.0,
        heat: 0.0,
    }
}

/// A fluid of `n` at packing `eta`, kT 1 (the generator's), half of species 0 and half of 1,
/// shuffled: labels alternating in the generator's order (cell order) put unlike discs next
/// to each other, which in a dense 2D fluid, where discs keep their neighbours for long,
/// biased the reactive fraction 2% low.
fn fluid<const D: usize>(n: usize, eta: f64, seed: u64) -> Simulation<D> {
    let (mut discs, bx) = lattice_fluid_in::<D>(n, eta, Boundary::Periodic, seed).unwrap();
    let mut labels: Vec<u16> = (0..n).map(|k| (k % 2) as u16).collect();
    // Fisher-Yates with SplitMix64.
    let mut z = seed;
    for k in (1..n).rev() {
        z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut x = z;
        x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        x ^= x >> 31;
        labels.swap(k, (x % (k as u64 + 1)) as usize);
    }
    for (d, s) in discs.iter_mut().zip(labels) {
        d.species = s;
    }
    Simulation::new(&discs, bx, Options::default()).unwrap()
}

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

fn head_on(u: f64, species: (u16, u16)) -> Simulation<2> {
    let mut a = Disc::new(Vector::new([5.0, 5.0]), Vector::new([u, 0.0]), 0.5);
    let mut b = Disc::new(Vector::new([7.0, 5.0]), Vector::new([0.0, 0.0]), 0.5);
    b.mass = 3.0;
    a.species = species.0;
    b.species = species.1;
    Simulation::new(&[a, b], SimBox::periodic([20.0, 20.0]), Options::default()).unwrap()
}

#[test]
fn heat_goes_into_the_normal_relative_motion() {
    // Masses 1 and 3 (reduced mass 3/4), closing at 2: normal kinetic energy 3/2. With heat
    // 1/2 the pair leaves at sqrt(4 + 2 (1/2) / (3/4)) = sqrt(16/3), momentum 2 kept.
    let mut sim = head_on(2.0, (0, 1));
    let mut r = rule(1, 0, 2, 3, 1.5);
    r.heat = 0.5;
    sim.set_reactions(Some(Reactions::new(vec![r]))).unwrap();
    let mut log = Log::default();
    sim.run_until(1.0, &mut obs(&mut log));
    assert!(matches!(
        log.0[..],
        [EventRecord {
            kind: EventKind::Reaction { rule: 0, .. },
            ..
        }]
    ));
    // The rule names species 1 first: disc 1 (species 1) becomes 2, disc 0 becomes 3.
    assert_eq!((sim.species(0), sim.species(1)), (3, 2));
    let (v0, v1) = (sim.velocity(0)[0], sim.velocity(1)[0]);
    assert!((v1 - v0 - (16.0f64 / 3.0).sqrt()).abs() < 1e-14);
    assert!((v0 + 3.0 * v1 - 2.0).abs() < 1e-14);
    assert!((sim.kinetic_energy() - 2.0 - 0.5).abs() < 1e-14);
    assert_eq!(sim.reaction_heat(), 0.5);
    assert_eq!(sim.reaction_counts(), &[1]);
    assert_eq!(sim.stats().reaction, 1);
    assert_eq!(sim.stats().disc_disc, 1);
}

#[test]
fn below_the_activation_energy_or_unable_to_pay_the_heat_a_collision_is_elastic() {
    // Normal kinetic energy 3/2: an activation of 1.6 stops the rule, and so does an
    // endothermic heat of -1.6, which the normal motion cannot pay.
    let mut endothermic = rule(0, 1, 2, 2, 0.0);
    endothermic.heat = -1.6;
    for r in [rule(0, 1, 2, 2, 1.6), endothermic] {
        let mut plain = head_on(2.0, (0, 1));
        let mut sim = head_on(2.0, (0, 1));
        sim.set_reactions(Some(Reactions::new(vec![r]))).unwrap();
        let (mut a, mut b) = (Log::default(), Log::default());
        plain.run_until(1.0, &mut obs(&mut a));
        sim.run_until(1.0, &mut obs(&mut b));
        assert_eq!(a.0, b.0);
        assert_eq!((sim.species(0), sim.species(1)), (0, 1));
        assert_eq!(sim.reaction_counts(), &[0]);
    }
}

#[test]
fn rules_without_heat_leave_the_motion_bit_for_bit_as_it_was() {
    // A + B -> B + A at every collision: the labels move, the trajectory is the elastic one.
    for dim3 in [false, true] {
        let same = |mut a: Vec<(f64, u64)>, b: Vec<(f64, u64)>| {
            a.retain(|x| x.1 != u64::MAX);
            assert_eq!(a, b);
        };
        if dim3 {
            let mut plain = fluid::<3>(500, 0.3, 4);
            let mut sim = plain.clone();
            sim.set_reactions(Some(Reactions::new(vec![rule(0, 1, 1, 0, 0.0)])))
                .unwrap();
            let (a, b) = (trace(&mut plain, 5.0), trace(&mut sim, 5.0));
            same(a, b);
            assert!(sim.reaction_counts()[0] > 500);
            assert_eq!(plain.momentum(), sim.momentum());
        } else {
            let mut plain = fluid::<2>(500, 0.4, 4);
            let mut sim = plain.clone();
            sim.set_reactions(Some(Reactions::new(vec![rule(0, 1, 1, 0, 0.0)])))
                .unwrap();
            let (a, b) = (trace(&mut plain, 5.0), trace(&mut sim, 5.0));
            same(a, b);
            assert!(sim.reaction_counts()[0] > 500);
        }
    }
}

/// Each pair event's time and the bits of the impulse's first component (cell crossings marked
/// with `u64::MAX`, for the caller to drop).
fn trace<const D: usize>(sim: &mut Simulation<D>, t: f64) -> Vec<(f64, u64)> {
    struct T(Vec<(f64, u64)>);
    impl<const D: usize> Observer<D> for T {
        fn on_event(&mut self, e: &EventRecord<D>, _: &Simulation<D>) {
            let bits = match e.kind {
                EventKind::DiscDisc { .. } | EventKind::Reaction { .. } => e.impulse[0].to_bits(),
                _ => u64::MAX,
            };
            self.0.push((e.time, bits));
        }
    }
    let mut log = T(Vec::new());
    sim.run_until(t, &mut obs(&mut log));
    log.0.retain(|x| x.1 != u64::MAX);
    log.0
}

#[test]
fn kinetic_energy_less_the_heat_released_is_conserved() {
    // A + B -> C + C releasing 0.3, C + C -> A + B absorbing it, in 2D and 3D.
    let rules = || {
        let mut forward = rule(0, 1, 2, 2, 0.5);
        forward.heat = 0.3;
        let mut back = rule(2, 2, 0, 1, 0.8);
        back.heat = -0.3;
        back.probability = 0.5;
        Reactions {
            rules: vec![forward, back],
            seed: 9,
            colours: vec![(2, [200, 0, 0])],
        }
    };
    let mut s2 = fluid::<2>(400, 0.5, 2);
    let mut s3 = fluid::<3>(400, 0.35, 2);
    s2.set_reactions(Some(rules())).unwrap();
    s3.set_reactions(Some(rules())).unwrap();
    let (e2, p2) = (s2.kinetic_energy(), s2.momentum());
    let (e3, p3) = (s3.kinetic_energy(), s3.momentum());
    s2.run_until(20.0, &mut ());
    s3.run_until(20.0, &mut ());
    for (c, e0, e1) in [
        (
            s2.reaction_counts(),
            e2,
            s2.kinetic_energy() - s2.reaction_heat(),
        ),
        (
            s3.reaction_counts(),
            e3,
            s3.kinetic_energy() - s3.reaction_heat(),
        ),
    ] {
        assert!(c[0] > 100 && c[1] > 100, "{c:?}");
        // Rounding: a few ulps per collision over some 10^4 collisions.
        assert!((e1 - e0).abs() < 1e-10 * e0, "{e0} {e1}");
    }
    assert!((s2.momentum() - p2).norm2().sqrt() < 1e-11);
    assert!((s3.momentum() - p3).norm2().sqrt() < 1e-11);
    // Species 2 takes its colour; the others keep theirs.
    let c = (0..s2.len()).find(|&i| s2.species(i) == 2).unwrap();
    assert_eq!(s2.colour(c), [200, 0, 0]);
    // Species are conserved in pairs: every reaction turns an A and a B into two Cs or back.
    let count = |s: &Simulation<2>, k| (0..s.len()).filter(|&i| s.species(i) == k).count();
    assert_eq!(count(&s2, 0), count(&s2, 1));
    assert_eq!(count(&s2, 0) + count(&s2, 2) / 2 * 2 + count(&s2, 1), 400);
}

/// Counts collisions of unlike species (judged before the event) and reactions.
struct Unlike {
    species: Vec<u16>,
    collisions: u64,
    reactions: u64,
}

impl<const D: usize> Observer<D> for Unlike {
    fn on_event(&mut self, e: &EventRecord<D>, sim: &Simulation<D>) {
        match e.kind {
            EventKind::DiscDisc { i, j } => {
                self.collisions += (self.species[i] != self.species[j]) as u64;
            }
            EventKind::Reaction { i, j, .. } => {
                self.collisions += 1;
                self.reactions += 1;
                self.species[i] = sim.species(i);
                self.species[j] = sim.species(j);
            }
            _ => {}
        }
    }
}

#[test]
fn the_reactive_fraction_follows_the_line_of_centres_law() {
    // A + B -> B + A exchanges labels at reactive collisions, which leaves each species'
    // velocities Maxwellian (the exchange is symmetric in the two), so the fraction of A-B
    // collisions that react is exp(-E*/kT) (`line_of_centres_fraction`, derived there), in 2D
    // and 3D, dilute and dense. kT = 1 (the generator's). About 4 10^4 A-B collisions per
    // case: the standard error of a fraction near 0.37 is about 0.0025 and of one near 0.05
    // 0.0011; the tolerance is 0.01 (4 to 9 standard errors, leaving room for the correlation
    // of successive collisions).
    for (dim, eta, activation) in [(2, 0.1, 1.0), (2, 0.6, 3.0), (3, 0.05, 1.0), (3, 0.4, 2.0)] {
        let fraction = if dim == 2 {
            let mut sim = fluid::<2>(2000, eta, 11);
            measure(&mut sim, activation)
        } else {
            let mut sim = fluid::<3>(2000, eta, 11);
            measure(&mut sim, activation)
        };
        let theory = line_of_centres_fraction(activation, 1.0);
        assert!(
            (fraction - theory).abs() < 0.01,
            "dim {dim} eta {eta} E* {activation}: {fraction} against {theory}"
        );
    }
}

fn measure<const D: usize>(sim: &mut Simulation<D>, activation: f64) -> f64 {
    let kt = 2.0 * sim.kinetic_energy() / (D * sim.len()) as f64;
    assert!((kt - 1.0).abs() < 1e-9, "{kt}");
    sim.set_reactions(Some(Reactions::new(vec![rule(0, 1, 1, 0, activation)])))
        .unwrap();
    let mut o = Unlike {
        species: (0..sim.len()).map(|i| sim.species(i)).collect(),
        collisions: 0,
        reactions: 0,
    };
    // Equilibrate, then count 8 10^4 collisions (half unlike).
    sim.run_events(200_000, &mut ());
    o.species = (0..sim.len()).map(|i| sim.species(i)).collect();
    while o.collisions < 40_000 {
        sim.run_events(10_000, &mut obs(&mut o));
    }
    o.reactions as f64 / o.collisions as f64
}

#[test]
fn a_checkpointed_reactive_run_goes_on_bit_for_bit() {
    let rules = Reactions {
        rules: vec![
            Reaction {
                probability: 0.4,
                heat: 0.2,
                ..rule(0, 1, 2, 2, 0.5)
            },
            Reaction {
                probability: 0.7,
                heat: -0.2,
                ..rule(2, 2, 0, 1, 0.5)
            },
        ],
        seed: 77,
        colours: vec![(2, [1, 2, 3])],
    };
    let mut whole = fluid::<3>(300, 0.3, 5);
    whole.set_reactions(Some(rules)).unwrap();
    let mut first = whole.clone();
    let full = trace(&mut whole, 6.0);
    let mut part = trace(&mut first, 3.0);
    let bytes = first.to_checkpoint(b"x");
    let (mut second, extra) = Simulation::<3>::from_checkpoint(&bytes).unwrap();
    assert_eq!(extra, b"x");
    assert_eq!(second.to_checkpoint(b"x"), bytes);
    assert_eq!(second.reactions(), first.reactions());
    part.extend(trace(&mut second, 6.0));
    assert_eq!(part, full);
    assert_eq!(second.reaction_counts(), whole.reaction_counts());
    assert_eq!(
        second.reaction_heat().to_bits(),
        whole.reaction_heat().to_bits()
    );
    assert_eq!(second.stats(), whole.stats());
    assert!(whole.reaction_counts().iter().all(|&c| c > 10));
    for i in 0..whole.len() {
        assert_eq!(second.species(i), whole.species(i));
        assert_eq!(second.colour(i), whole.colour(i));
    }
}

#[test]
fn like_reactants_become_either_product_with_equal_chance() {
    // A + A -> B + C: of nearly a thousand reactions, the disc whose schedule held the event
    // becomes B about half the time (binomial, standard deviation 1.6%).
    let mut sim = fluid::<2>(2000, 0.3, 3);
    let all_a: Vec<Disc<2>> = sim
        .discs()
        .into_iter()
        .map(|mut d| {
            d.species = 0;
            d
        })
        .collect();
    sim = Simulation::new(&all_a, *sim.sim_box(), Options::default()).unwrap();
    sim.set_reactions(Some(Reactions {
        rules: vec![rule(0, 0, 1, 2, 0.0)],
        seed: 5,
        colours: vec![],
    }))
    .unwrap();
    struct Held(u64, u64);
    impl Observer<2> for Held {
        fn on_event(&mut self, e: &EventRecord<2>, sim: &Simulation<2>) {
            if let EventKind::Reaction { i, .. } = e.kind {
                self.0 += (sim.species(i) == 1) as u64;
                self.1 += 1;
            }
        }
    }
    let mut h = Held(0, 0);
    sim.run_until(50.0, &mut obs(&mut h));
    // Nearly every A has reacted (an A left alone among the products waits for another).
    assert!(h.1 > 950, "{}", h.1);
    let share = h.0 as f64 / h.1 as f64;
    assert!((share - 0.5).abs() < 0.06, "{share}");
}

#[test]
fn rules_that_cannot_be_are_refused() {
    let mut sim = fluid::<2>(100, 0.3, 1);
    let e = sim
        .set_reactions(Some(Reactions::new(vec![rule(0, 5, 1, 1, 0.0)])))
        .unwrap_err();
    assert!(
        e.to_string()
            .contains("no disc is of species 5 and no rule makes it"),
        "{e}"
    );
    // A reactant that another rule makes is known.
    sim.set_reactions(Some(Reactions::new(vec![
        rule(0, 5, 1, 1, 0.0),
        rule(0, 1, 5, 5, 0.0),
    ])))
    .unwrap();
    // A later state may have used a reactant up: its rules are taken as they are.
    sim.run_until(0.5, &mut ());
    sim.set_reactions(Some(Reactions::new(vec![rule(0, 5, 1, 1, 0.0)])))
        .unwrap();
    let e = sim
        .set_reactions(Some(Reactions::new(vec![Reaction {
            probability: -0.1,
            ..rule(0, 1, 1, 1, 0.0)
        }])))
        .unwrap_err();
    assert!(matches!(e, Error::BadReaction(_)), "{e}");
    let (discs, bx) = lattice_fluid_in::<2>(100, 0.3, Boundary::Periodic, 1).unwrap();
    let mut well = Simulation::with_potential_at(
        &discs,
        bx,
        &[],
        &Potential::single(0, 0, 1.5, -1.0),
        Options::default(),
        0.0,
    )
    .unwrap();
    let e = well
        .set_reactions(Some(Reactions::new(vec![rule(0, 0, 1, 1, 0.0)])))
        .unwrap_err();
    assert!(e.to_string().contains("stepped potential"), "{e}");
}
