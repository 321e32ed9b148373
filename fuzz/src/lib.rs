//! Shared pieces of the fuzz targets: valid systems built from the fuzzer's bytes, the
//! invariant checks run after every chunk of events, the checks on a reader's result, and the
//! framing that lets the fuzzer mutate a checkpoint's payload behind a correct checksum.
//!
//! Two known engine defects, fixed elsewhere, are kept out of reach here (RELIABILITY.md):
//! boxes much longer on one axis than another (the cell grid then allocates gigabytes), and
//! discs as wide as the box (the clock can stop). [`box_is_tame`] and [`discs_are_tame`] say
//! whether a system is clear of both.

use arbitrary::{Result, Unstructured};
use edmd_core::pack::Packer;
use edmd_core::{
    Andersen, Barrier, Boundary, CollisionRule, Demon, Disc, Error, EventKind, EventRecord,
    Gravity, MultiContact, Observer, Options, OverlapPolicy, PairSteps, Potential, Reaction,
    Reactions, Restitution, RestitutionLaw, Ring, SelfGravity, Shear, SimBox, Simulation, Step,
    Vector, OVERLAP_TOLERANCE,
};

/// The longest box axis over the shortest that the targets build (known defect 1).
pub const MAX_ASPECT: f64 = 100.0;

/// Largest diameter, relative to the shortest box length, that the targets build (known
/// defect 2).
pub const MAX_DIAMETER: f64 = 0.9;

/// Relative energy drift allowed over a run.
pub const ENERGY_TOLERANCE: f64 = 1e-9;

/// Whether the box is clear of known defect 1 (every length finite and positive, aspect ratio
/// at most [`MAX_ASPECT`]).
pub fn box_is_tame(lengths: &[f64]) -> bool {
    let lo = lengths.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = lengths.iter().copied().fold(0.0, f64::max);
    lengths.iter().all(|l| l.is_finite() && *l > 0.0) && hi <= MAX_ASPECT * lo
}

/// Whether the discs are clear of known defect 2 (every diameter below [`MAX_DIAMETER`] times
/// the shortest box length).
pub fn discs_are_tame<const D: usize>(discs: &[Disc<D>], sim_box: &SimBox<D>) -> bool {
    let lmin = sim_box
        .lengths
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    discs.iter().all(|d| 2.0 * d.radius < MAX_DIAMETER * lmin)
}

/// A number in `[0, 1]` from two bytes.
fn unit(u: &mut Unstructured) -> Result<f64> {
    Ok(f64::from(u.arbitrary::<u16>()?) / f64::from(u16::MAX))
}

/// A system and how to run it.
#[derive(Clone, Debug)]
pub struct Setup<const D: usize> {
    /// The discs (valid, not overlapping, inside the box: the generator drops those that are
    /// not).
    pub discs: Vec<Disc<D>>,
    /// The box.
    pub sim_box: SimBox<D>,
    /// Barriers (2D only).
    pub barriers: Vec<Barrier>,
    /// Rule and multi-contact.
    pub options: Options,
    /// Events to run.
    pub events: u64,
    /// A stepped pair potential (elastic runs without multi-disc collisions), or hard cores.
    pub potential: Option<Potential>,
    /// Reaction rules (elastic runs without multi-disc collisions or a potential), with the
    /// discs' species drawn for them.
    pub reactions: Option<Reactions>,
    /// Restitution (elastic runs without multi-disc collisions, a potential or rules).
    pub restitution: Option<Restitution>,
    /// A uniform field (without a potential, barriers or multi-disc collisions).
    pub gravity: Option<Gravity>,
    /// Lees-Edwards boundaries (periodic x and y, without a field, a potential, barriers or
    /// multi-disc collisions).
    pub shear: Option<Shear>,
    /// An Andersen thermostat (sheared systems only: it draws about the streaming profile).
    pub thermostat: Option<Andersen>,
    /// A ring patch (a third of the sheared systems whose z axis, in 3D, has walls): Hill's
    /// flights, the shear's rate becoming the Keplerian one.
    pub ring: Option<Ring>,
    /// One-dimensional self-gravity (a third of the 1D systems between walls with the elastic
    /// rule and nothing else): sheets, each rod on a parabola of its own between events.
    pub self_gravity: Option<SelfGravity>,
}

/// A random valid system: box lengths within [`MAX_ASPECT`], walls or periodic per axis, up to
/// `max_n` discs with equal or mixed radii and masses, placed at random or in exact contact
/// with an earlier disc (multi-disc contacts, Newton's cradles), velocities random, zero or
/// along one axis, up to two barriers with doors and demons (2D), the elastic or swap rule,
/// with or without multi-disc collisions.
pub fn setup<const D: usize>(u: &mut Unstructured, max_n: usize) -> Result<Setup<D>> {
    let base = 0.5 + 9.5 * unit(u)?;
    let mut lengths = [base; D];
    for l in lengths.iter_mut().skip(1) {
        // A factor in [0.1, 10]: the aspect ratio stays within 100.
        *l = base * 10f64.powf(2.0 * unit(u)? - 1.0);
    }
    let mut boundaries = [Boundary::Walls; D];
    for b in boundaries.iter_mut() {
        if u.ratio(1, 3)? {
            *b = Boundary::Periodic;
        }
    }
    let sim_box = SimBox {
        lengths,
        boundaries,
    };
    let lmin = lengths.iter().copied().fold(f64::INFINITY, f64::min);
    let any_periodic = boundaries.contains(&Boundary::Periodic);
    // Periodic axes need three diameters; walled ones take up to MAX_DIAMETER of the box.
    let r_cap = if any_periodic {
        lmin / 6.5
    } else {
        0.49 * MAX_DIAMETER * lmin
    };
    let r_common = r_cap * (0.002 + 0.998 * unit(u)?.powi(3));
    let mixed_radii = u.ratio(1, 3)?;
    let mixed_masses = u.ratio(1, 3)?;

    let mut barriers = Vec::new();
    if D == 2 && !any_periodic {
        for _ in 0..u.int_in_range(0..=2)? {
            let axis = u.int_in_range(0..=1usize)?;
            let mut b = Barrier::solid(axis, lengths[axis] * (0.05 + 0.9 * unit(u)?));
            if u.arbitrary::<bool>()? {
                let across = lengths[1 - axis];
                let lo = across * 0.9 * unit(u)?;
                let hi = lo + (across - lo) * (0.05 + 0.95 * unit(u)?);
                b.door = Some((lo, hi));
                if u.arbitrary::<bool>()? {
                    b.demon = Some(Demon {
                        fast: 3.0 * unit(u)?,
                        slow: 3.0 * unit(u)?,
                    });
                }
            }
            barriers.push(b);
        }
    }

    let n = u.int_in_range(0..=max_n)?;
    let vmax = 10f64.powf(2.0 * unit(u)? - 1.0);
    let mut discs: Vec<Disc<D>> = Vec::with_capacity(n);
    for _ in 0..n {
        let radius = if mixed_radii {
            r_common * (0.2 + 0.8 * unit(u)?)
        } else {
            r_common
        };
        let mut pos = Vector::<D>::ZERO;
        match u.int_in_range(0..=3u8)? {
            // In contact with an earlier disc, along an axis or in any direction, touching
            // exactly or nearly.
            k @ 1..=3 if !discs.is_empty() => {
                let other = discs[u.choose_index(discs.len())?];
                let mut dir = Vector::<D>::ZERO;
                if k == 1 {
                    dir[u.choose_index(D)?] = if u.arbitrary::<bool>()? { 1.0 } else { -1.0 };
                } else {
                    for a in 0..D {
                        dir[a] = 2.0 * unit(u)? - 1.0;
                    }
                }
                let norm = dir.norm2().sqrt();
                if norm == 0.0 {
                    continue;
                }
                let gap = match u.int_in_range(0..=2u8)? {
                    0 => 0.0,
                    1 => 1e-12,
                    _ => 1e-3 * unit(u)?,
                };
                let reach = (radius + other.radius) * (1.0 + gap) / norm;
                for a in 0..D {
                    pos[a] = other.pos[a] + dir[a] * reach;
                }
                pos = sim_box.wrap(pos);
            }
            _ => {
                for a in 0..D {
                    pos[a] = if boundaries[a] == Boundary::Periodic {
                        lengths[a] * unit(u)?
                    } else {
                        radius + (lengths[a] - 2.0 * radius) * unit(u)?
                    };
                }
            }
        }
        let mut vel = Vector::<D>::ZERO;
        match u.int_in_range(0..=3u8)? {
            0 => {}
            1 => vel[u.choose_index(D)?] = vmax * (2.0 * unit(u)? - 1.0),
            _ => {
                for a in 0..D {
                    vel[a] = vmax * (2.0 * unit(u)? - 1.0);
                }
            }
        }
        // Mass ratios up to 100: a light disc pinched between heavy ones bounces about
        // `sqrt(M / m)` times in a multi-disc collision, each bounce some 2000 integrator
        // steps, so larger ratios make slow inputs rather than new paths. (Extreme ratios end
        // the run with a stall, tested in crates/edmd-core/tests/fuzz_regressions.rs; the
        // checkpoint target meets them too.)
        let mass = if mixed_masses {
            10f64.powf(2.0 * unit(u)? - 1.0)
        } else {
            1.0
        };
        let disc = Disc {
            pos,
            vel,
            mass,
            radius,
            colour: [0; 3],
            species: 0,
        };
        if fits(&disc, &discs, &sim_box, &barriers) {
            discs.push(disc);
        }
    }
    let equal_masses = discs.iter().all(|d| d.mass == discs[0].mass);
    let rule = if equal_masses && u.ratio(1, 6)? {
        CollisionRule::Swap
    } else {
        CollisionRule::Elastic
    };
    let multi = if rule == CollisionRule::Elastic && u.ratio(1, 3)? {
        Some(if u.arbitrary::<bool>()? {
            MultiContact::default()
        } else {
            MultiContact {
                tolerance: 0.1 * unit(u)?,
                exponent: 1.0 + 2.0 * unit(u)?,
            }
        })
    } else {
        None
    };
    let options = Options {
        rule,
        overlaps: OverlapPolicy::Refuse,
        multi,
    };
    let events = u.int_in_range(1..=2000u64)?;
    // Drawn last, so that the inputs found before stepped potentials still build the systems
    // they built: one to three steps outside the largest contact distance, wells and
    // shoulders, deep or shallow against the kinetic energy, for the neighbour lists and the
    // shells (a periodic box too small for them refuses the input).
    let mut potential = None;
    if rule == CollisionRule::Elastic && multi.is_none() && u.ratio(1, 3)? {
        let core = discs.iter().map(|d| 2.0 * d.radius).fold(0.0, f64::max);
        let mut radius = core.max(f64::MIN_POSITIVE);
        let mut steps = Vec::new();
        for _ in 0..u.int_in_range(1..=3u8)? {
            radius *= 1.0 + 0.6 * unit(u)?.max(1e-3);
            let energy = vmax * vmax * (4.0 * unit(u)? - 2.0);
            steps.push(Step { radius, energy });
        }
        potential = Some(Potential {
            pairs: vec![PairSteps {
                species: (0, 0),
                steps,
            }],
        });
    }
    // Drawn after the potential, for the same reason: a third of the other elastic systems
    // react, their discs of species 0 to 2, one to three rules among species 0 to 3 (one per
    // pair), activation energies from none to twice the largest kinetic energy scale,
    // probabilities of 1 or less, heat released or absorbed on that scale, or none.
    let mut reactions = None;
    if rule == CollisionRule::Elastic && multi.is_none() && potential.is_none() && u.ratio(1, 3)? {
        for d in &mut discs {
            d.species = u.int_in_range(0..=2u16)?;
        }
        let scale = vmax * vmax;
        let mut rules: Vec<Reaction> = Vec::new();
        for _ in 0..u.int_in_range(1..=3u8)? {
            let (a, b) = (u.int_in_range(0..=3u16)?, u.int_in_range(0..=3u16)?);
            let products = (u.int_in_range(0..=3u16)?, u.int_in_range(0..=3u16)?);
            let activation = if u.arbitrary::<bool>()? {
                0.0
            } else {
                2.0 * scale * unit(u)?
            };
            let probability = if u.arbitrary::<bool>()? {
                1.0
            } else {
                unit(u)?
            };
            let heat = match u.int_in_range(0..=2u8)? {
                0 => 0.0,
                _ => scale * (2.0 * unit(u)? - 1.0),
            };
            if rules
                .iter()
                .all(|r| r.reactants != (a, b) && r.reactants != (b, a))
            {
                rules.push(Reaction {
                    reactants: (a, b),
                    products,
                    activation,
                    probability,
                    heat,
                });
            }
        }
        let mut r = Reactions {
            rules,
            seed: u.arbitrary()?,
            colours: Vec::new(),
        };
        r.fill_colours(discs.iter().map(|d| (d.species, d.colour)));
        reactions = Some(r);
    }
    // Drawn last, for the same reason: a third of the remaining elastic systems collide
    // inelastically, every pair and the walls with a coefficient from 0 to 1 or Bridges' law
    // with a speed on the scale of theirs, species 0 and 1 with a law of their own, and the TC
    // model on or off.
    let mut restitution = None;
    if rule == CollisionRule::Elastic
        && multi.is_none()
        && potential.is_none()
        && reactions.is_none()
        && u.ratio(1, 3)?
    {
        let law = |u: &mut Unstructured| -> arbitrary::Result<RestitutionLaw> {
            Ok(if u.arbitrary::<bool>()? {
                RestitutionLaw::Constant(unit(u)?)
            } else {
                RestitutionLaw::Bridges {
                    v_c: vmax * unit(u)?.max(1e-3),
                }
            })
        };
        for d in &mut discs {
            d.species = u.int_in_range(0..=1u16)?;
        }
        let all = law(u)?;
        let pairs = if u.arbitrary::<bool>()? {
            vec![(0, 1, law(u)?)]
        } else {
            Vec::new()
        };
        let tc = if u.arbitrary::<bool>()? {
            0.0
        } else {
            1e-3 * unit(u)?
        };
        restitution = Some(Restitution {
            all,
            pairs,
            wall: unit(u)?,
            tc,
        });
    }
    // And a third of the systems without a potential, barriers or multi-disc collisions fall
    // in a field along a walled axis, up to ten times the speed scale squared over the box:
    // from a gentle pull to a heap. Inelastic ones then take the TC model and walls that do
    // not stop a disc dead, as the engine asks.
    let walled: Vec<usize> = (0..D).filter(|&a| !sim_box.is_periodic(a)).collect();
    let mut gravity = None;
    if potential.is_none()
        && barriers.is_empty()
        && multi.is_none()
        && !walled.is_empty()
        && u.ratio(1, 3)?
    {
        let axis = walled[u.int_in_range(0..=walled.len() - 1)?];
        let scale = vmax * vmax / sim_box.lengths[axis];
        let g = scale * 10.0 * (2.0 * unit(u)? - 1.0);
        if g != 0.0 {
            gravity = Some(Gravity { axis, g });
            if let Some(r) = &mut restitution {
                r.tc = r.tc.max(1e-4);
                r.wall = r.wall.max(0.05);
            }
        }
    }
    // And a third of the rest with periodic x and y shear, at up to twice the speed scale
    // over the box's height either way (the images sliding by up to four times the speed
    // scale), the images at an offset anywhere in the box; half of those with a thermostat
    // drawing about the streaming profile.
    let mut shear = None;
    let mut thermostat = None;
    let mut ring = None;
    if potential.is_none()
        && barriers.is_empty()
        && multi.is_none()
        && gravity.is_none()
        && D >= 2
        && sim_box.is_periodic(0)
        && sim_box.is_periodic(1)
        && u.ratio(1, 3)?
    {
        let rate = 2.0 * vmax / sim_box.lengths[1] * (2.0 * unit(u)? - 1.0);
        let offset = match u.int_in_range(0..=2u8)? {
            0 => 0.0,
            _ => (unit(u)? * sim_box.lengths[0]).min(sim_box.lengths[0].next_down()),
        };
        shear = Some(Shear { rate, offset });
        if (D == 2 || !sim_box.is_periodic(2)) && u.ratio(1, 3)? {
            ring = Some(Ring {
                omega: (rate.abs() / 1.5).max(1e-3 * vmax / sim_box.lengths[1]),
            });
        }
        if u.arbitrary::<bool>()? {
            thermostat = Some(Andersen {
                kt: (vmax * vmax * unit(u)?).max(1e-6),
                rate: unit(u)?.max(1e-3) * vmax / sim_box.lengths[1],
                seed: u.arbitrary()?,
            });
        }
    }
    // Drawn last, and in 1D only, so that the 2D and 3D inputs found before build the systems
    // they built: a third of the elastic rods between walls with nothing else attract as
    // sheets, the whole mass pulling from a hundredth to ten times the speed scale squared
    // over the line; half of them in a heat bath.
    let mut self_gravity = None;
    if D == 1
        && rule == CollisionRule::Elastic
        && multi.is_none()
        && potential.is_none()
        && reactions.is_none()
        && restitution.is_none()
        && gravity.is_none()
        && !sim_box.is_periodic(0)
        && !discs.is_empty()
        && u.ratio(1, 3)?
    {
        let mass: f64 = discs.iter().map(|d| d.mass).sum();
        let pull = vmax * vmax / sim_box.lengths[0] * 10f64.powf(3.0 * unit(u)? - 2.0);
        self_gravity = Some(SelfGravity {
            coupling: pull / mass,
        });
        if u.arbitrary::<bool>()? {
            thermostat = Some(Andersen {
                kt: (vmax * vmax * unit(u)?).max(1e-6),
                rate: unit(u)?.max(1e-3) * vmax / sim_box.lengths[0],
                seed: u.arbitrary()?,
            });
        }
    }
    Ok(Setup {
        discs,
        sim_box,
        barriers,
        options,
        events,
        potential,
        reactions,
        restitution,
        gravity,
        shear,
        thermostat,
        ring,
        self_gravity,
    })
}

/// Whether `d` lies inside the walls, clear of the barriers and of every disc in `placed`.
fn fits<const D: usize>(
    d: &Disc<D>,
    placed: &[Disc<D>],
    sim_box: &SimBox<D>,
    barriers: &[Barrier],
) -> bool {
    // A little stricter than the engine, so rounding never makes it refuse a placed disc.
    let strict = 1e-6;
    let inside = (0..D).all(|a| {
        sim_box.is_periodic(a)
            || (d.pos[a] >= d.radius * (1.0 + strict)
                && d.pos[a] <= sim_box.lengths[a] - d.radius * (1.0 + strict))
    });
    let clear_of_barriers = barriers
        .iter()
        .all(|b| (d.pos[b.axis] - b.position).abs() > d.radius * (1.0 + strict));
    let clear_of_discs = placed.iter().all(|o| {
        let sigma = d.radius + o.radius;
        sim_box.minimum_image(d.pos - o.pos).norm2().sqrt() >= sigma * (1.0 - 1e-12)
    });
    inside && clear_of_barriers && clear_of_discs
}

/// Watches events: times finite and never decreasing, a count per kind, and a reaction's
/// discs of its products' species.
#[derive(Debug, Default)]
pub struct Watch {
    /// Time of the last event seen.
    pub last: f64,
    /// Disc-disc (reactions included), wall, cell-crossing, barrier, step, thermostat and
    /// neighbour-list events seen.
    pub counts: [u64; 7],
    /// Reactions seen.
    pub reactions: u64,
}

impl<const D: usize> Observer<D> for Watch {
    fn on_event(&mut self, e: &EventRecord<D>, sim: &Simulation<D>) {
        assert!(e.time.is_finite(), "event at time {}", e.time);
        assert!(
            e.time >= self.last,
            "time went back: {} after {}",
            e.time,
            self.last
        );
        assert_eq!(
            sim.time(),
            e.time,
            "the simulation's clock is not the event's time"
        );
        assert!(e.impulse.is_finite(), "impulse {:?}", e.impulse);
        self.last = e.time;
        if let EventKind::Reaction { i, j, rule } = e.kind {
            let r = sim.reactions().expect("a reaction without rules").rules[rule];
            let (mut made, mut now) = (
                [r.products.0, r.products.1],
                [sim.species(i), sim.species(j)],
            );
            made.sort_unstable();
            now.sort_unstable();
            assert_eq!(
                now, made,
                "a reaction's discs are not of its products' species"
            );
            self.reactions += 1;
        }
        let k = match e.kind {
            EventKind::DiscDisc { .. } | EventKind::Reaction { .. } => 0,
            EventKind::Wall { .. } => 1,
            EventKind::CellCrossing { .. } | EventKind::Slide { .. } => 2,
            EventKind::Barrier { .. } => 3,
            EventKind::Step { .. } => 4,
            EventKind::Thermostat { .. } => 5,
            EventKind::NeighbourList { .. } => 6,
        };
        self.counts[k] += 1;
    }
}

/// Runs `events` events in chunks, checking after each: every counter moved by exactly the
/// events seen, energy conserved (and momentum in a fully periodic box) where nothing feeds or
/// drains it (the thermostat's redraws and the sliding images of shear do), no overlaps, no
/// disc outside the box, the clock not gone back, the shear's rate kept and its offset in the
/// box. Returns the events run.
pub fn run_checked<const D: usize>(sim: &mut Simulation<D>, events: u64) -> u64 {
    // Reactions release their heat into the kinetic energy: the energy less the heat released
    // is conserved.
    // is conserved; inelastic collisions lose it: the energy plus the loss is conserved.
    let energy = |sim: &Simulation<D>| {
        sim.kinetic_energy() + sim.potential_energy() - sim.reaction_heat() + sim.dissipated()
    };
    let e0 = energy(sim);
    // Steps exchange kinetic energy with the potential's: the drift is judged against the
    // largest of the energies, at the start and now.
    let scale0 = e0
        .abs()
        .max(sim.kinetic_energy())
        .max(sim.potential_energy().abs());
    let p0 = sim.momentum();
    let scale: f64 = (0..sim.len())
        .map(|i| sim.mass(i) * sim.velocity(i).norm2().sqrt())
        .sum();
    let shear0 = sim.shear();
    let closed = shear0.is_none() && sim.thermostat().is_none();
    let all_periodic = (0..D).all(|a| sim.sim_box().is_periodic(a)) && sim.barriers().is_empty();
    let mut watch = Watch {
        last: sim.time(),
        counts: [0; 7],
        reactions: 0,
    };
    let mut done = 0;
    while done < events {
        let chunk = (events - done).min(97);
        let before = sim.stats();
        let seen = watch.counts;
        let reactions_seen = watch.reactions;
        let k = sim.run_events(chunk, &mut watch);
        done += k;
        let after = sim.stats();
        let moved = [
            after.disc_disc - before.disc_disc,
            after.wall - before.wall,
            after.cell_crossing - before.cell_crossing,
            after.barrier - before.barrier,
            after.step - before.step,
            after.thermostat - before.thermostat,
            after.neighbour_list - before.neighbour_list,
        ];
        let delta: Vec<u64> = (0..7).map(|a| watch.counts[a] - seen[a]).collect();
        assert_eq!(
            moved.to_vec(),
            delta,
            "stats moved other than the events seen"
        );
        assert_eq!(
            moved.iter().sum::<u64>(),
            k,
            "run_events counted other than the events"
        );
        assert_eq!(
            after.reaction - before.reaction,
            watch.reactions - reactions_seen,
            "reactions counted other than those seen"
        );
        assert_eq!(
            sim.reaction_counts().iter().sum::<u64>(),
            after.reaction,
            "the rules' counts do not add up to the reactions"
        );
        assert!(after.stale >= before.stale);
        assert!(
            sim.dissipated() >= 0.0 && sim.dissipated().is_finite(),
            "energy lost {}",
            sim.dissipated()
        );
        assert!(
            sim.time() >= watch.last || k == 0,
            "clock behind the last event"
        );
        if let (Some(s0), Some(s)) = (shear0, sim.shear()) {
            assert_eq!(
                s.rate.to_bits(),
                s0.rate.to_bits(),
                "the shear rate changed"
            );
            assert!(
                (0.0..sim.sim_box().lengths[0]).contains(&s.offset),
                "the images' offset {} outside the box",
                s.offset
            );
        }
        let e = energy(sim);
        assert!(
            !closed
                || (e - e0).abs()
                    <= ENERGY_TOLERANCE
                        * scale0
                            .max(sim.kinetic_energy())
                            .max(sim.potential_energy().abs()),
            "energy {e} drifted from {e0} after {done} events"
        );
        let mismatched = sim.shell_mismatches(1e-9);
        assert!(
            mismatched.is_empty(),
            "shells that disagree with the distances after {done} events: {mismatched:?}"
        );
        if all_periodic && closed {
            let p = sim.momentum();
            assert!(
                (p - p0).norm2().sqrt() <= ENERGY_TOLERANCE * scale.max(f64::MIN_POSITIVE),
                "momentum {p:?} drifted from {p0:?} after {done} events"
            );
        }
        let report = sim.overlaps(OVERLAP_TOLERANCE);
        assert_eq!(report.count, 0, "overlap after {done} events: {report:?}");
        let outside = sim.discs_outside(OVERLAP_TOLERANCE);
        assert!(
            outside.is_empty(),
            "discs {outside:?} outside after {done} events"
        );
        if k < chunk {
            break;
        }
    }
    done
}

/// The whole engine check for one input: build the system (a refusal ends the input), run
/// half the events checked, write a checkpoint and read it back (it must give the same bytes),
/// then run the other half both in the original (checked) and in the copy read back (on the
/// portable loop): both must end bit for bit in the same state.
pub fn engine<const D: usize>(data: &[u8], max_n: usize) {
    let mut u = Unstructured::new(data);
    let Ok(s) = setup::<D>(&mut u, max_n) else {
        return;
    };
    let built = match &s.potential {
        None => Simulation::with_barriers(&s.discs, s.sim_box, &s.barriers, s.options),
        Some(p) => {
            Simulation::with_potential_at(&s.discs, s.sim_box, &s.barriers, p, s.options, 0.0)
        }
    };
    let Ok(mut sim) = built else {
        return;
    };
    if sim.set_reactions(s.reactions.clone()).is_err() {
        return;
    }
    sim.set_gravity(s.gravity)
        .expect("a field the generator made");
    sim.set_restitution(s.restitution.clone())
        .expect("restitution the generator made");
    match sim.set_shear(s.shear) {
        Ok(()) => {}
        // Discs the generator placed clear of the plain images may touch the slid ones.
        Err(Error::BadShear(m)) if m.contains("overlap") => return,
        Err(e) => panic!("shear the generator made: {e}"),
    }
    match sim.set_ring(s.ring) {
        Ok(()) => {}
        // As for the shear; and a box too small for the ring's wider cells.
        Err(Error::BadRing(m)) if m.contains("overlap") || m.contains("too small") => return,
        Err(e) => panic!("a ring the generator made: {e}"),
    }
    sim.set_self_gravity(s.self_gravity)
        .expect("self-gravity the generator made");
    sim.set_thermostat(s.thermostat)
        .expect("a thermostat the generator made");
    let first = run_checked(&mut sim, s.events / 2);
    let ck = sim.to_checkpoint(b"fuzz");
    let (mut copy, extra) = Simulation::<D>::from_checkpoint(&ck).expect("own checkpoint");
    assert_eq!(extra, b"fuzz");
    assert_eq!(
        copy.to_checkpoint(b"fuzz"),
        ck,
        "checkpoint does not round-trip"
    );
    copy.set_portable_loop(true);
    if first == s.events / 2 {
        let rest = s.events - first;
        let a = run_checked(&mut sim, rest);
        let b = copy.run_events(rest, &mut ());
        assert_eq!(a, b);
    }
    assert!(
        sim.to_checkpoint(b"") == copy.to_checkpoint(b""),
        "a run continued from a checkpoint differs from the run never stopped"
    );
}

/// What every reader target checks of a parse error: a line inside the file (1 for an empty
/// one) and a message.
pub fn check_error(text: &str, line: usize, message: &str) {
    let lines = text.lines().count().max(1);
    assert!(
        (1..=lines).contains(&line),
        "error at line {line} of a {lines}-line file: {message}"
    );
    assert!(!message.is_empty());
}

/// What every reader target does with a system it read: one line per disc, in increasing order;
/// the engine builds it or refuses it (never panics), with overlaps refused or allowed; if
/// allowed, a few events run.
pub fn check_loaded<const D: usize>(sys: &edmd_io::LoadedSystem<D>, text: &str) {
    assert_eq!(sys.lines.len(), sys.discs.len());
    assert!(sys.lines.windows(2).all(|w| w[0] < w[1]));
    assert!(sys
        .lines
        .iter()
        .all(|&l| l >= 1 && l <= text.lines().count()));
    if !box_is_tame(&sys.sim_box.lengths) {
        return;
    }
    let refuse = Options::default();
    // The rules the reader accepts, the engine takes (with the elastic rule).
    let reactions = (!sys.reactions.is_empty()).then(|| Reactions::new(sys.reactions.clone()));
    let build = |options| {
        Simulation::with_potential_at(
            &sys.discs,
            sys.sim_box,
            &sys.barriers,
            &sys.potential,
            options,
            0.0,
        )
        .and_then(|mut sim| {
            sim.set_reactions(reactions.clone())
                .expect("rules the reader accepted");
            sim.set_gravity(sys.gravity)
                .expect("a field the reader accepted");
            sim.set_restitution(sys.restitution.clone())
                .expect("restitution the reader accepted");
            // Refused only where the images at the file's offset overlap a disc.
            match sim.set_shear(sys.shear) {
                Err(Error::BadShear(m)) if !m.contains("overlap") => {
                    panic!("shear the reader accepted: {m}")
                }
                Err(e) => Err(e),
                // A ring (its shear set first, at the file's offset, as `edmd run` sets it) is
                // refused only where the slid images overlap a disc or the patch is too
                // small for its particles.
                Ok(()) => match sim.set_ring(sys.ring) {
                    Err(Error::BadRing(m))
                        if !(m.contains("overlap") || m.contains("too small")) =>
                    {
                        panic!("a ring the reader accepted: {m}")
                    }
                    Err(e) => Err(e),
                    // The self-gravity the reader accepts, the engine takes with the elastic
                    // rule and binary collisions.
                    Ok(()) => {
                        sim.set_self_gravity(sys.self_gravity)
                            .expect("self-gravity the reader accepted");
                        Ok(sim)
                    }
                },
            }
        })
    };
    let _ = build(refuse);
    if !discs_are_tame(&sys.discs, &sys.sim_box) || sys.discs.len() > 5000 {
        return;
    }
    let allow = Options {
        overlaps: OverlapPolicy::Allow,
        ..Options::default()
    };
    if let Ok(mut sim) = build(allow) {
        sim.run_events(64, &mut ());
        // A stepped potential's energy is a sum of its steps' energies over the pairs.
        assert!(sim.potential_energy().is_finite());
        assert!(sim.reaction_heat().is_finite());
        assert!(sim.dissipated().is_finite());
    }
}

/// Header bytes of a checkpoint: magic, version, dimension, payload length.
pub const CHECKPOINT_HEADER: usize = 24;

/// A checkpoint file around `payload`: magic, version, dimension, the payload's length, the
/// payload and its CRC-32, as `to_checkpoint` writes them.
pub fn frame_checkpoint(dim: u32, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(CHECKPOINT_HEADER + payload.len() + 4);
    out.extend_from_slice(b"EDMDCKPT");
    out.extend_from_slice(&edmd_core::CHECKPOINT_VERSION.to_le_bytes());
    out.extend_from_slice(&dim.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(payload);
    let crc = crc32(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// CRC-32 (IEEE), as the checkpoint uses; bitwise, the inputs are small.
pub fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
        }
    }
    !crc
}

/// The box lengths at the start of a checkpoint payload of dimension `dim` (each a length and
/// a boundary byte), or `None` if the payload is shorter.
pub fn checkpoint_box(dim: usize, payload: &[u8]) -> Option<Vec<f64>> {
    (0..dim)
        .map(|a| {
            let at = 9 * a;
            let b = payload.get(at..at + 8)?;
            Some(f64::from_le_bytes(b.try_into().ok()?))
        })
        .collect()
}

/// The whole checkpoint check for one file: the frame and the dimension read without a panic;
/// an accepted checkpoint gives back the same bytes, runs a bounded number of events, and its
/// checkpoint after the run reads back to the same bytes again.
pub fn checkpoint(bytes: &[u8]) {
    let dim = edmd_core::checkpoint_dim(bytes);
    let one = Simulation::<1>::from_checkpoint(bytes);
    let two = Simulation::<2>::from_checkpoint(bytes);
    let three = Simulation::<3>::from_checkpoint(bytes);
    match dim {
        Ok(1) => {
            assert!(
                two.is_err() && three.is_err(),
                "a 1D checkpoint read as 2D or 3D"
            );
            if let Ok((sim, extra)) = one {
                accepted(bytes, sim, &extra);
            }
        }
        Ok(2) => {
            assert!(
                one.is_err() && three.is_err(),
                "a 2D checkpoint read as 1D or 3D"
            );
            if let Ok((sim, extra)) = two {
                accepted(bytes, sim, &extra);
            }
        }
        Ok(3) => {
            assert!(
                one.is_err() && two.is_err(),
                "a 3D checkpoint read as 1D or 2D"
            );
            if let Ok((sim, extra)) = three {
                accepted(bytes, sim, &extra);
            }
        }
        Ok(d) => panic!("checkpoint_dim gave {d}"),
        Err(_) => assert!(
            one.is_err() && two.is_err() && three.is_err(),
            "frame refused, body read"
        ),
    }
}

fn accepted<const D: usize>(bytes: &[u8], mut sim: Simulation<D>, extra: &[u8]) {
    // A checkpoint of an older format version is written back in the current one, which
    // must then round-trip.
    let written = sim.to_checkpoint(extra);
    if bytes.get(8..12) == Some(&edmd_core::CHECKPOINT_VERSION.to_le_bytes()[..]) {
        assert!(
            written == bytes,
            "an accepted checkpoint does not round-trip"
        );
    } else {
        let (copy, _) =
            Simulation::<D>::from_checkpoint(&written).expect("an older checkpoint written anew");
        assert!(
            copy.to_checkpoint(extra) == written,
            "an older checkpoint written anew does not round-trip"
        );
    }
    // The reader refuses discs outside the box but not overlapping pairs (a run may allow
    // them, `OverlapPolicy::Allow`): a checkpoint with overlaps is read, not run.
    if sim.overlaps(OVERLAP_TOLERANCE).count > 0 {
        return;
    }
    let t0 = sim.time();
    sim.run_events(300, &mut ());
    assert!(sim.time() >= t0, "time went back");
    let again = sim.to_checkpoint(extra);
    let (copy, _) = Simulation::<D>::from_checkpoint(&again).expect("checkpoint after a run");
    assert!(copy.to_checkpoint(extra) == again);
}

/// A packing checkpoint file around `payload`, as `Packer::checkpoint` frames it (the run
/// checkpoint's frame with the magic number `EDMDPACK`).
pub fn frame_pack_checkpoint(dim: u32, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(CHECKPOINT_HEADER + payload.len() + 4);
    out.extend_from_slice(edmd_core::pack::PACK_MAGIC);
    out.extend_from_slice(&edmd_core::pack::PACK_FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&dim.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(payload);
    let crc = crc32(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// The whole check for one packing checkpoint file: the frame and the dimension read without a
/// panic, and agree; an accepted checkpoint gives back the same bytes, and (with tame options)
/// its compression runs for up to three measured synchronisations, whose checkpoint reads back
/// to the same bytes again.
pub fn pack_checkpoint(bytes: &[u8]) {
    let dim = edmd_core::pack::pack_checkpoint_dim(bytes);
    let two = Packer::<2>::from_checkpoint(bytes);
    let three = Packer::<3>::from_checkpoint(bytes);
    match dim {
        Ok(2) => {
            assert!(three.is_err(), "a 2D checkpoint read as 3D");
            if let Ok((p, extra)) = two {
                pack_accepted(bytes, p, &extra);
            }
        }
        Ok(3) => {
            assert!(two.is_err(), "a 3D checkpoint read as 2D");
            if let Ok((p, extra)) = three {
                pack_accepted(bytes, p, &extra);
            }
        }
        Ok(d) => panic!("pack_checkpoint_dim gave {d}"),
        Err(_) => assert!(two.is_err() && three.is_err(), "frame refused, body read"),
    }
}

fn pack_accepted<const D: usize>(bytes: &[u8], packer: Packer<D>, extra: &[u8]) {
    assert!(
        packer.checkpoint(extra) == bytes,
        "an accepted packing checkpoint does not round-trip"
    );
    // A mutated interval of up to 10^6 collisions per particle, or a growth so slow that
    // nothing happens for ages, is valid but takes long: not run.
    let o = packer.options();
    if o.collisions_per_rescale > 100.0 || o.growth_rate < 1e-3 {
        return;
    }
    let mut k = 0;
    let mut last = None;
    let _ = packer.run_with(|pk| {
        k += 1;
        last = Some(pk.checkpoint(extra));
        k < 3
    });
    if let Some(again) = last {
        let (copy, _) = Packer::<D>::from_checkpoint(&again).expect("checkpoint after a run");
        assert!(copy.checkpoint(extra) == again);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_matches_the_engine() {
        let sim = Simulation::new(
            &[Disc::new(
                Vector::new([1.0, 1.0]),
                Vector::new([1.0, 0.5]),
                0.1,
            )],
            SimBox::walls([2.0, 3.0]),
            Options::default(),
        )
        .unwrap();
        let ck = sim.to_checkpoint(b"x");
        let payload = &ck[CHECKPOINT_HEADER..ck.len() - 4];
        assert_eq!(frame_checkpoint(2, payload), ck);
    }

    /// Writes the engine and checkpoint seed corpora (the checkpoint seeds are payloads after a
    /// mode byte): run with
    /// `cargo test --manifest-path fuzz/Cargo.toml -- --ignored write_seed_corpus`.
    #[test]
    #[ignore]
    fn write_seed_corpus() {
        let corpus = concat!(env!("CARGO_MANIFEST_DIR"), "/corpus");
        for (k, data) in seed_inputs().iter().enumerate() {
            for target in ["engine_1d", "engine_2d", "engine_3d"] {
                std::fs::create_dir_all(format!("{corpus}/{target}")).unwrap();
                std::fs::write(format!("{corpus}/{target}/seed-{k:02}"), data).unwrap();
            }
        }
        let dir = format!("{corpus}/read_checkpoint");
        std::fs::create_dir_all(&dir).unwrap();
        let mut k = 0;
        let mut put = |dim: u8, ck: Vec<u8>| {
            let mut seed = vec![dim - 2];
            seed.extend_from_slice(&ck[CHECKPOINT_HEADER..ck.len() - 4]);
            std::fs::write(format!("{dir}/seed-{k:02}"), seed).unwrap();
            k += 1;
        };
        for data in seed_inputs() {
            let mut u = Unstructured::new(&data);
            if let Ok(s) = setup::<2>(&mut u, 6) {
                if let Ok(mut sim) =
                    Simulation::with_barriers(&s.discs, s.sim_box, &s.barriers, s.options)
                {
                    sim.run_events(20, &mut ());
                    put(2, sim.to_checkpoint(b"seed"));
                }
            }
            let mut u = Unstructured::new(&data);
            if let Ok(s) = setup::<3>(&mut u, 5) {
                if let Ok(mut sim) = Simulation::new(&s.discs, s.sim_box, s.options) {
                    sim.run_events(20, &mut ());
                    put(3, sim.to_checkpoint(b""));
                }
            }
        }
    }

    /// Writes the checkpoint seeds with reaction rules (format 6: the rules, their seed and
    /// colours, the heat released and the counts), payloads after a mode byte: reactive fluids
    /// in 2D and 3D run until some of their discs have reacted. Run with
    /// `cargo test --manifest-path fuzz/Cargo.toml -- --ignored write_reaction_seeds`.
    #[test]
    #[ignore]
    fn write_reaction_seeds() {
        use edmd_core::setup::lattice_fluid_in;
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/corpus/read_checkpoint");
        fn reactive<const D: usize>(n: usize, eta: f64) -> Vec<u8> {
            let (mut discs, bx) = lattice_fluid_in::<D>(n, eta, Boundary::Periodic, 3).unwrap();
            for (k, d) in discs.iter_mut().enumerate() {
                d.species = (k % 3) as u16;
            }
            let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
            let rule = |a, b, c, d, activation, probability, heat| Reaction {
                reactants: (a, b),
                products: (c, d),
                activation,
                probability,
                heat,
            };
            let mut r = Reactions {
                rules: vec![
                    rule(0, 1, 2, 3, 0.5, 1.0, 0.25),
                    rule(2, 2, 0, 1, 1.0, 0.5, -0.5),
                    rule(3, 1, 1, 1, 0.0, 0.3, 0.0),
                ],
                seed: 7,
                colours: vec![(3, [10, 200, 30])],
            };
            r.fill_colours(discs.iter().map(|d| (d.species, d.colour)));
            sim.set_reactions(Some(r)).unwrap();
            sim.run_events(40 * n as u64, &mut ());
            assert!(sim.stats().reaction > 0);
            sim.to_checkpoint(b"")
        }
        for (name, dim, ck) in [
            ("seed-reactions-2d", 2u8, reactive::<2>(24, 0.4)),
            ("seed-reactions-3d", 3u8, reactive::<3>(32, 0.3)),
        ] {
            let mut seed = vec![dim - 2];
            seed.extend_from_slice(&ck[CHECKPOINT_HEADER..ck.len() - 4]);
            std::fs::write(format!("{dir}/{name}"), seed).unwrap();
        }
    }

    /// Writes the checkpoint seeds with restitution (format 7: the laws, the walls', the TC
    /// model's time and each disc's last collision, the energy lost), payloads after a mode
    /// byte: granular gases in 2D and 3D run until they have lost some energy. Run with
    /// `cargo test --manifest-path fuzz/Cargo.toml -- --ignored write_restitution_seeds`.
    #[test]
    #[ignore]
    fn write_restitution_seeds() {
        use edmd_core::setup::lattice_fluid_in;
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/corpus/read_checkpoint");
        fn granular<const D: usize>(n: usize, eta: f64) -> Vec<u8> {
            let (mut discs, bx) = lattice_fluid_in::<D>(n, eta, Boundary::Walls, 3).unwrap();
            for (k, d) in discs.iter_mut().enumerate() {
                d.species = (k % 2) as u16;
            }
            let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
            sim.set_restitution(Some(Restitution {
                all: RestitutionLaw::Constant(0.8),
                pairs: vec![(0, 1, RestitutionLaw::Bridges { v_c: 0.3 })],
                wall: 0.9,
                tc: 1e-3,
            }))
            .unwrap();
            sim.run_events(40 * n as u64, &mut ());
            assert!(sim.dissipated() > 0.0);
            sim.to_checkpoint(b"")
        }
        for (name, dim, ck) in [
            ("seed-restitution-2d", 2u8, granular::<2>(24, 0.4)),
            ("seed-restitution-3d", 3u8, granular::<3>(32, 0.3)),
        ] {
            let mut seed = vec![dim - 2];
            seed.extend_from_slice(&ck[CHECKPOINT_HEADER..ck.len() - 4]);
            std::fs::write(format!("{dir}/{name}"), seed).unwrap();
        }
    }

    /// Writes the checkpoint seeds with shear (format 8: the rate, the images' slide and its
    /// epoch, each boundary-row disc's slide event), payloads after a mode byte: sheared
    /// fluids in 2D and 3D, inelastic in 2D and thermostatted in 3D, run until the images have
    /// slid past several cells. Run with
    /// `cargo test --manifest-path fuzz/Cargo.toml -- --ignored write_shear_seeds`.
    #[test]
    #[ignore]
    fn write_shear_seeds() {
        use edmd_core::setup::lattice_fluid_in;
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/corpus/read_checkpoint");
        fn sheared<const D: usize>(n: usize, eta: f64, rate: f64) -> Vec<u8> {
            let (discs, bx) = lattice_fluid_in::<D>(n, eta, Boundary::Periodic, 5).unwrap();
            let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
            if D == 2 {
                sim.set_restitution(Some(Restitution {
                    all: RestitutionLaw::Constant(0.8),
                    pairs: Vec::new(),
                    wall: 1.0,
                    tc: 0.0,
                }))
                .unwrap();
            } else {
                sim.set_thermostat(Some(Andersen {
                    kt: 1.0,
                    rate: 0.5,
                    seed: 7,
                }))
                .unwrap();
            }
            sim.set_shear(Some(Shear { rate, offset: 0.0 })).unwrap();
            let ly = bx.lengths[1];
            let ys: Vec<f64> = (0..sim.len()).map(|i| sim.position(i)[1]).collect();
            sim.modify_velocities(|i, mut v| {
                v[0] += rate * (ys[i] - 0.5 * ly);
                v
            });
            sim.run_events(40 * n as u64, &mut ());
            assert!(sim.shear().unwrap().offset > 0.0);
            sim.to_checkpoint(b"")
        }
        for (name, dim, ck) in [
            ("seed-shear-2d", 2u8, sheared::<2>(24, 0.4, 0.5)),
            ("seed-shear-3d", 3u8, sheared::<3>(32, 0.3, -0.4)),
        ] {
            let mut seed = vec![dim - 2];
            seed.extend_from_slice(&ck[CHECKPOINT_HEADER..ck.len() - 4]);
            std::fs::write(format!("{dir}/{name}"), seed).unwrap();
        }
    }

    /// Writes the packing checkpoint seed corpus (payloads after a mode byte): run with
    /// `cargo test --manifest-path fuzz/Cargo.toml -- --ignored write_pack_seed_corpus`.
    #[test]
    #[ignore]
    fn write_pack_seed_corpus() {
        use edmd_core::pack::{random_start, PackOptions, PackSizes};
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/corpus/read_pack_checkpoint");
        std::fs::create_dir_all(dir).unwrap();
        let mut k = 0;
        let mut put = |dim: u8, ck: Vec<u8>| {
            let mut seed = vec![dim - 2];
            seed.extend_from_slice(&ck[CHECKPOINT_HEADER..ck.len() - 4]);
            std::fs::write(format!("{dir}/seed-{k:02}"), seed).unwrap();
            k += 1;
        };
        let options = PackOptions {
            max_pressure: 1e6,
            ..PackOptions::default()
        };
        let binary = PackSizes::Binary {
            size_ratio: 1.4,
            fraction_large: 0.5,
        };
        for boundary in [Boundary::Periodic, Boundary::Walls] {
            // At the start, and at the first synchronisation with neighbour lists.
            let (discs, sim_box) = random_start::<2>(12, binary, boundary, 1).unwrap();
            let p = Packer::new(&discs, sim_box, options).unwrap();
            put(2, p.checkpoint(b"seed"));
            let mut got = None;
            let _ = p.run_with(|pk| {
                if pk.neighbour_lists() {
                    got = Some(pk.checkpoint(b""));
                }
                got.is_none()
            });
            // (Twelve discs between walls jam before the lists come on.)
            if let Some(ck) = got {
                put(2, ck);
            }
            let sizes = PackSizes::Polydisperse { std: 0.1 };
            let (discs, sim_box) = random_start::<3>(27, sizes, boundary, 2).unwrap();
            let p = Packer::new(&discs, sim_box, options).unwrap();
            let mut syncs = 0;
            let mut got = None;
            let _ = p.run_with(|pk| {
                syncs += 1;
                got = Some(pk.checkpoint(b""));
                syncs < 4
            });
            put(3, got.unwrap());
        }
    }

    /// Triage: shows what an input of a checkpoint or engine target builds and runs it event by
    /// event with timings. `EDMD_FUZZ_INPUT=FILE EDMD_FUZZ_TARGET=read_checkpoint cargo test
    /// --release --manifest-path fuzz/Cargo.toml -- --ignored --nocapture show_input`.
    #[test]
    #[ignore]
    fn show_input() {
        let Ok(path) = std::env::var("EDMD_FUZZ_INPUT") else {
            return;
        };
        let data = std::fs::read(path).unwrap();
        let target = std::env::var("EDMD_FUZZ_TARGET").unwrap_or_default();
        match target.as_str() {
            "engine_2d" => show_setup::<2>(&data, 24),
            "engine_3d" => show_setup::<3>(&data, 16),
            _ => {
                let bytes = if data[0] & 0x80 != 0 {
                    data[1..].to_vec()
                } else {
                    frame_checkpoint(2 + u32::from(data[0] & 1), &data[1..])
                };
                match edmd_core::checkpoint_dim(&bytes) {
                    Ok(2) => show_checkpoint::<2>(&bytes),
                    Ok(3) => show_checkpoint::<3>(&bytes),
                    other => println!("frame: {other:?}"),
                }
            }
        }
    }

    fn show_setup<const D: usize>(data: &[u8], max_n: usize) {
        let s = setup::<D>(&mut Unstructured::new(data), max_n).unwrap();
        println!("{s:#?}");
        let sim = Simulation::with_barriers(&s.discs, s.sim_box, &s.barriers, s.options)
            .and_then(|mut sim| sim.set_reactions(s.reactions.clone()).map(|()| sim))
            .and_then(|mut sim| sim.set_gravity(s.gravity).map(|()| sim))
            .and_then(|mut sim| sim.set_restitution(s.restitution.clone()).map(|()| sim))
            .and_then(|mut sim| sim.set_shear(s.shear).map(|()| sim))
            .and_then(|mut sim| sim.set_ring(s.ring).map(|()| sim))
            .and_then(|mut sim| sim.set_self_gravity(s.self_gravity).map(|()| sim))
            .and_then(|mut sim| sim.set_thermostat(s.thermostat).map(|()| sim));
        match sim {
            Ok(sim) => show_run(sim, s.events),
            Err(e) => println!("refused: {e}"),
        }
    }

    fn show_checkpoint<const D: usize>(bytes: &[u8]) {
        match Simulation::<D>::from_checkpoint(bytes) {
            Ok((sim, extra)) => {
                println!("{sim:#?}");
                let again = sim.to_checkpoint(&extra);
                if let Some(k) = (0..bytes.len()).find(|&k| again.get(k) != Some(&bytes[k])) {
                    println!("round trip differs from byte {k} (payload {})", k - 24);
                }
                show_run(sim, 300);
            }
            Err(e) => println!("refused: {e}"),
        }
    }

    fn show_run<const D: usize>(mut sim: Simulation<D>, events: u64) {
        for k in 0..events {
            let start = std::time::Instant::now();
            let Some(e) = sim.step(f64::INFINITY) else {
                println!("{k}: nothing ahead");
                break;
            };
            println!(
                "{k}: {:?} at {} ({:?}), energy {}",
                e.kind,
                e.time,
                start.elapsed(),
                sim.kinetic_energy()
            );
        }
    }

    /// A few fixed pseudo-random inputs for the generator.
    fn seed_inputs() -> Vec<Vec<u8>> {
        (0..6u64)
            .map(|s| {
                let mut x = 0x9E37_79B9_7F4A_7C15u64.wrapping_mul(s + 1);
                (0..160)
                    .map(|_| {
                        x ^= x << 13;
                        x ^= x >> 7;
                        x ^= x << 17;
                        (x >> 24) as u8
                    })
                    .collect()
            })
            .collect()
    }
}
