//! The starting fluid and the simulations the front runs in: the lattice, its melting, the
//! labels and the rule.

use anyhow::Result;
use edmd_core::setup::{melting_threshold, psi6, thermal_velocities, Neighbours};
use edmd_core::state::species_colour;
use edmd_core::{Disc, Options, Reaction, Reactions, SimBox, Simulation, Vector};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;

use super::super::common::run_collisions;
use super::frame::Frame;
use super::{FrontArgs, A, B};

/// `n` discs in a periodic `length x width` box on a triangular lattice with at least 6% of
/// its sites empty (vacancies let it melt within a few collisions per disc), stretched a
/// little to fit the box, the empty sites spread evenly; velocities Gaussian at `kT = 1` with
/// no total momentum; all `B`.
fn strip_lattice(n: usize, length: f64, width: f64, seed: u64) -> Result<Vec<Disc>> {
    let sites = (n as f64 * 1.06).ceil();
    let a = (2.0 * length * width / (3f64.sqrt() * sites)).sqrt();
    let mut rows = ((width / (a * 3f64.sqrt() / 2.0)).round() as usize).max(2);
    rows += rows % 2;
    let cols = (sites as usize).div_ceil(rows).max(1);
    let (dx, dy) = (length / cols as f64, width / rows as f64);
    if dx < 1.0 + 1e-9 || (0.25 * dx * dx + dy * dy).sqrt() < 1.0 + 1e-9 {
        return edmd::user_error(format!(
            "front: {n} discs do not fit a lattice in a {length} x {width} box: make it wider or the packing lower"
        ));
    }
    let total = rows * cols;
    let mut discs: Vec<Disc> = (0..n)
        .map(|i| {
            let site = i * total / n;
            let (r, c) = (site / cols, site % cols);
            let x = (c as f64 + 0.25 + 0.5 * (r % 2) as f64) * dx;
            let y = (r as f64 + 0.5) * dy;
            Disc {
                species: B,
                colour: species_colour(B),
                ..Disc::new(Vector::new([x, y]), Vector::ZERO, 0.5)
            }
        })
        .collect();
    thermal_velocities(&mut discs, 1.0, &mut Pcg64Mcg::seed_from_u64(seed));
    Ok(discs)
}

/// Gives disc `d` species `s` and its colour.
pub(super) fn label(d: &mut Disc, s: u16) {
    d.species = s;
    d.colour = species_colour(s);
}

/// A new simulation of `discs` at time `t`; with `draw`, under the rule `A + B -> A + A` with
/// the `draw`-th seed (each build gets its own: the collision counters the draws hash start
/// again from 0).
pub(super) fn build(
    args: &FrontArgs,
    discs: &[Disc],
    bx: SimBox,
    t: f64,
    draw: Option<u64>,
) -> Result<Simulation> {
    let mut sim = Simulation::with_barriers_at(discs, bx, &[], Options::default(), t)
        .or_else(|e| edmd::user_error(format!("front: {e}")))?;
    if let Some(k) = draw {
        let seed = args
            .common
            .seed
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(k.wrapping_mul(0xD1B5_4A32_D192_ED03));
        let rule = Reaction {
            reactants: (A, B),
            products: (A, A),
            activation: args.activation,
            probability: args.probability,
            heat: 0.0,
        };
        let reactions = Reactions {
            rules: vec![rule],
            seed,
            colours: vec![(A, species_colour(A))],
        };
        sim.set_reactions(Some(reactions))
            .or_else(|e| edmd::user_error(format!("front: {e}")))?;
    }
    Ok(sim)
}

/// The melted fluid of the whole box, all `B`: 10 collisions per disc at a time until the
/// bond-orientational order is that of a liquid; `None` when a stop was requested.
pub(super) fn fluid(args: &FrontArgs, frame: &Frame) -> Result<Option<Simulation>> {
    let n = (frame.density * frame.length * frame.width).round() as usize;
    let discs = strip_lattice(n, frame.length, frame.width, args.common.seed)?;
    let bx = SimBox::periodic([frame.length, frame.width]);
    let mut sim = build(args, &discs, bx, 0.0, None)?;
    for _ in 0..30 {
        if !run_collisions(&mut sim, 5 * n as u64)? {
            return Ok(None);
        }
        if psi6(&sim.discs(), sim.sim_box(), Neighbours::Nearest(6)) < melting_threshold(n) {
            return Ok(Some(sim));
        }
    }
    edmd::user_error("front: the lattice did not melt within 300 collisions per disc")
}
