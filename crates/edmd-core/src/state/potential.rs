//! Stepped pair potentials: a hard core plus steps, per pair of species.
//!
//! A pair of discs `i`, `j` interacts through a hard core at the contact distance
//! `sigma = r_i + r_j` (their radii) and, when their species have steps, through a piecewise
//! constant potential outside it. Steps are listed from the innermost out; step `k` is at distance `radius` with `energy` the change in
//! the pair's potential energy when the pair moves *inwards* across it: a square well of depth
//! `e` and range `lambda sigma` is one step `(lambda sigma, -e)`, a square shoulder of height
//! `e` is `(lambda sigma, +e)`, and a ramp of many steps approximates a soft potential (as
//! DynamO's `Stepped` does). The pair's energy between steps `k` and `k + 1` is the sum of the
//! energies of the steps outside it, `k + 1` and on (the potential is zero outside every
//! step).

use crate::error::Error;

/// One step of a stepped potential.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// Distance between centres at which the step stands.
    pub radius: f64,
    /// Change in the pair's potential energy when it moves inwards across the step (negative
    /// for a well, positive for a shoulder).
    pub energy: f64,
}

/// The steps of one pair of species, innermost first.
#[derive(Clone, Debug, PartialEq)]
pub struct PairSteps {
    /// The two species (in either order).
    pub species: (u16, u16),
    /// The steps, in increasing radius.
    pub steps: Vec<Step>,
}

/// The most steps one pair of species may have (a pair's shell is kept in a byte).
pub const MAX_STEPS: usize = 255;

/// The most species a stepped potential names (the engine keeps a table per pair).
pub const MAX_POTENTIAL_SPECIES: u16 = 256;

/// The largest size of a step's energy. Beyond some 10^300 the speed a pair gains in a well
/// overflows and the run ends in NaN; this bound keeps every sum of steps and of pairs finite
/// with room to spare (the masses are checked against it with the discs).
pub const MAX_STEP_ENERGY: f64 = 1e100;

/// A stepped potential: the steps of each pair of species that has any. Pairs not named are
/// hard cores only.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Potential {
    /// Per pair of species, its steps.
    pub pairs: Vec<PairSteps>,
}

/// Why steps of these energies are too large for a pair of discs whose lighter is of mass
/// `lightest`, if they are. A pair crossing every step gains at most the sum of their sizes,
/// and its relative speed squared twice that over the reduced mass (at least half the lighter
/// mass); that is kept below 10^200, so that speeds, and sums over many pairs, stay finite.
pub fn steps_too_large(steps: &[Step], lightest: f64) -> Option<String> {
    let gain: f64 = steps.iter().map(|s| s.energy.abs()).sum();
    let speed2 = 4.0 * gain / lightest;
    (gain > 0.0 && (speed2.is_nan() || speed2 > 1e200)).then(|| {
        format!(
            "steps of {gain:e} in all are too large for discs of mass {lightest:e}: the speeds they give would overflow"
        )
    })
}

impl Potential {
    /// A square well (`energy < 0`) or shoulder (`energy > 0`) of one step at `radius`
    /// between species `a` and `b`.
    pub fn single(a: u16, b: u16, radius: f64, energy: f64) -> Self {
        Potential {
            pairs: vec![PairSteps {
                species: (a, b),
                steps: vec![Step { radius, energy }],
            }],
        }
    }

    /// Whether no pair has a step (the hard core alone).
    pub fn is_hard(&self) -> bool {
        self.pairs.iter().all(|p| p.steps.is_empty())
    }

    /// The steps of species `a` and `b` (empty if none).
    pub fn steps(&self, a: u16, b: u16) -> &[Step] {
        self.pairs
            .iter()
            .find(|p| p.species == (a, b) || p.species == (b, a))
            .map_or(&[], |p| &p.steps)
    }

    /// Checks the potential on its own: species below [`MAX_POTENTIAL_SPECIES`], each pair named
    /// once, steps finite and their energies at most [`MAX_STEP_ENERGY`] in size, in strictly
    /// increasing radius, at most [`MAX_STEPS`] per pair. (That
    /// every step lies outside the hard core of the discs it applies to is checked with the
    /// discs, by the simulation.)
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |msg: String| Err(Error::BadPotential(msg));
        for (k, p) in self.pairs.iter().enumerate() {
            let (a, b) = p.species;
            if a >= MAX_POTENTIAL_SPECIES || b >= MAX_POTENTIAL_SPECIES {
                return bad(format!(
                    "species {a} {b}: species must be below {MAX_POTENTIAL_SPECIES}"
                ));
            }
            if self.pairs[..k]
                .iter()
                .any(|q| q.species == (a, b) || q.species == (b, a))
            {
                return bad(format!("species {a} {b}: the pair is given twice"));
            }
            if p.steps.len() > MAX_STEPS {
                return bad(format!(
                    "species {a} {b}: {} steps, at most {MAX_STEPS}",
                    p.steps.len()
                ));
            }
            for (s, step) in p.steps.iter().enumerate() {
                if !(step.radius.is_finite() && step.radius > 0.0) {
                    return bad(format!(
                        "species {a} {b}: step radius {} is not a finite positive number",
                        step.radius
                    ));
                }
                if !step.energy.is_finite() {
                    return bad(format!(
                        "species {a} {b}: step energy {} is not finite",
                        step.energy
                    ));
                }
                if step.energy.abs() > MAX_STEP_ENERGY {
                    return bad(format!(
                        "species {a} {b}: step energy {:e} is larger than {MAX_STEP_ENERGY:e} in size",
                        step.energy
                    ));
                }
                if s > 0 && step.radius <= p.steps[s - 1].radius {
                    return bad(format!(
                        "species {a} {b}: the steps must be in increasing radius ({} after {})",
                        step.radius,
                        p.steps[s - 1].radius
                    ));
                }
            }
        }
        Ok(())
    }
}
