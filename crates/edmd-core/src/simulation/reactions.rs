//! Reactive collisions (see [`crate::state::reaction`]): a collision of two species that have
//! a rule may change their species and colours and release heat into their normal relative
//! motion.
//!
//! The draw of a rule whose probability is below 1 (and, for like reactants with unlike
//! products, which becomes which) comes from a hash of the seed, the lower-numbered disc, its
//! collision counter before the collision and the other disc: a pair meets with those values
//! once, so a run gives the same draws however it is sliced, and a checkpoint needs no
//! generator state (the counters are in it already).

use crate::error::Error;
use crate::events::{EventKind, EventRecord};
use crate::resolve::elastic;
use crate::state::{Colour, Reactions};

use super::Simulation;

/// The rules as the event loop reads them.
#[derive(Clone, Debug)]
pub(super) struct Chemistry {
    pub(super) reactions: Reactions,
    /// Per ordered pair of species `(a, b)` below `width`, at `a * width + b`: the rule's
    /// index plus one, or 0 for none; its top bit set when the rule names the pair the other
    /// way round.
    table: Vec<u32>,
    width: usize,
    /// Per species below `width`, the colour a disc takes on becoming it, if any.
    colour: Vec<Option<Colour>>,
    /// Heat released so far (the sum of the rules' heats over the reactions that happened):
    /// kinetic energy less this is conserved.
    pub(super) heat: f64,
    /// Reactions so far, per rule.
    pub(super) count: Vec<u64>,
}

const SWAPPED: u32 = 1 << 31;

impl Chemistry {
    /// The rules, checked on their own (see [`Reactions::validate`]).
    pub(super) fn new(reactions: Reactions) -> Result<Self, Error> {
        reactions.validate()?;
        let width = reactions
            .rules
            .iter()
            .flat_map(|r| [r.reactants.0, r.reactants.1, r.products.0, r.products.1])
            .chain(reactions.colours.iter().map(|&(s, _)| s))
            .map(|s| s as usize + 1)
            .max()
            .unwrap_or(0);
        let mut table = vec![0u32; width * width];
        for (k, r) in reactions.rules.iter().enumerate() {
            let (a, b) = (r.reactants.0 as usize, r.reactants.1 as usize);
            table[a * width + b] = k as u32 + 1;
            if a != b {
                table[b * width + a] = (k as u32 + 1) | SWAPPED;
            }
        }
        let mut colour = vec![None; width];
        for &(s, c) in &reactions.colours {
            colour[s as usize] = Some(c);
        }
        let count = vec![0; reactions.rules.len()];
        Ok(Chemistry {
            reactions,
            table,
            width,
            colour,
            heat: 0.0,
            count,
        })
    }

    /// Bytes held by the tables.
    pub(super) fn memory_bytes(&self) -> usize {
        self.table.capacity() * 4 + self.colour.capacity() * 4 + self.count.capacity() * 8
    }

    /// Refuses a rule whose reactant no disc is (of `species`) and no rule makes: it could
    /// never happen, and is most likely a mistyped species.
    fn check_reactants(&self, species: &[u16]) -> Result<(), Error> {
        let mut present = vec![false; self.width];
        for &s in species {
            if let Some(p) = present.get_mut(s as usize) {
                *p = true;
            }
        }
        for r in &self.reactions.rules {
            present[r.products.0 as usize] = true;
            present[r.products.1 as usize] = true;
        }
        for r in &self.reactions.rules {
            for s in [r.reactants.0, r.reactants.1] {
                if !present[s as usize] {
                    return Err(Error::BadReaction(format!(
                        "{} + {} -> {} + {}: no disc is of species {s} and no rule makes it",
                        r.reactants.0, r.reactants.1, r.products.0, r.products.1
                    )));
                }
            }
        }
        Ok(())
    }

    /// The rule for discs of species `a` and `b`, and whether it names them the other way
    /// round.
    #[inline(always)]
    fn rule(&self, a: u16, b: u16) -> Option<(usize, bool)> {
        let (a, b) = (a as usize, b as usize);
        if a >= self.width || b >= self.width {
            return None;
        }
        match self.table[a * self.width + b] {
            0 => None,
            e => Some((((e & !SWAPPED) - 1) as usize, e & SWAPPED != 0)),
        }
    }
}

/// A uniform number in `[0, 1)` and a fair bit from the seed, a disc, its counter and its
/// partner (SplitMix64's finaliser over their mix).
fn draw(seed: u64, lo: usize, count: u32, hi: usize) -> (f64, bool) {
    let mut z = seed
        ^ 0x5EAC_7104_0000_0001
        ^ (lo as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ u64::from(count).wrapping_mul(0xD1B5_4A32_D192_ED03)
        ^ (hi as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    ((z >> 11) as f64 * (1.0 / (1u64 << 53) as f64), z & 1 == 1)
}

impl<const D: usize> Simulation<D> {
    /// Makes collisions reactive under `reactions` from now on (`None`: none, the default).
    /// Refused with the reason for rules that cannot be (see [`Reactions::validate`]; at time
    /// 0, a start, a reactant no disc is and no rule makes, most likely a mistyped species,
    /// where a later state may have used a reactant up), and with a stepped potential (whose pair tables
    /// are per species, so a reaction would change a pair's shell), multi-disc collisions or
    /// a rule other than the elastic one. Reactions counted so far start again from 0.
    pub fn set_reactions(&mut self, reactions: Option<Reactions>) -> Result<(), Error> {
        let Some(reactions) = reactions else {
            self.chemistry = None;
            return Ok(());
        };
        self.reactions_fit()?;
        self.chemistry = if reactions.rules.is_empty() {
            None
        } else {
            let chem = Chemistry::new(reactions)?;
            // A later state may have used a reactant up.
            if self.now == 0.0 {
                chem.check_reactants(&self.species.to_vec())?;
            }
            Some(Box::new(chem))
        };
        Ok(())
    }

    /// Refuses reaction rules with what they do not go with.
    pub(super) fn reactions_fit(&self) -> Result<(), Error> {
        if self.steps.is_some() {
            return Err(Error::BadReaction(
                "rules do not go with a stepped potential (its pairs' steps depend on their species)"
                    .into(),
            ));
        }
        if self.dissipation.is_some() {
            return Err(Error::BadReaction(
                "rules do not go with inelastic collisions".into(),
            ));
        }
        if self.sheets.is_some() {
            return Err(Error::BadReaction(
                "rules do not go with self-gravity".into(),
            ));
        }
        if self.multi.is_some() {
            return Err(Error::BadReaction(
                "rules do not go with multi-disc collisions".into(),
            ));
        }
        if self.rule != crate::resolve::CollisionRule::Elastic {
            return Err(Error::BadReaction("rules need the elastic rule".into()));
        }
        Ok(())
    }

    /// The reaction rules, if collisions are reactive.
    pub fn reactions(&self) -> Option<&Reactions> {
        self.chemistry.as_ref().map(|c| &c.reactions)
    }

    /// Reactions so far, per rule (empty without rules).
    pub fn reaction_counts(&self) -> &[u64] {
        self.chemistry.as_ref().map_or(&[], |c| &c.count)
    }

    /// Heat released by the reactions so far (0 without rules): the kinetic energy less this
    /// is conserved to rounding.
    pub fn reaction_heat(&self) -> f64 {
        self.chemistry.as_ref().map_or(0.0, |c| c.heat)
    }

    /// Resolves the collision of `i` and `j` under the reaction rules; returns the record and
    /// the discs to predict again.
    #[inline(always)]
    pub(super) fn collide_reactive(
        &mut self,
        i: usize,
        j: usize,
        t: f64,
    ) -> (EventRecord<D>, [usize; 2]) {
        let chem = self.chemistry.as_deref().expect("reaction rules");
        let Some((k, swapped)) = chem.rule(self.species[i], self.species[j]) else {
            return self.collide(i, j, t);
        };
        let rule = chem.reactions.rules[k];
        self.body[i].advance_to(t);
        self.body[j].advance_to(t);
        let dr = self
            .sim_box
            .minimum_image(self.body[j].pos - self.body[i].pos);
        let (vi, vj) = (self.body[i].vel, self.body[j].vel);
        let (mi, mj) = (self.mass[i], self.mass[j]);
        let dv = vj - vi;
        let dot = dv.dot(dr);
        let r2 = dr.norm2();
        let mu = mi * mj / (mi + mj);
        // Normal relative speed squared, and what it is after the heat is released.
        let vn2 = dot * dot / r2;
        let after = vn2 + 2.0 * rule.heat / mu;
        let (lo, hi) = if i < j { (i, j) } else { (j, i) };
        let (u, bit) = if rule.probability < 1.0 || rule.reactants.0 == rule.reactants.1 {
            draw(chem.reactions.seed, lo, self.body[lo].count, hi)
        } else {
            (0.0, false)
        };
        let reacts =
            dot < 0.0 && 0.5 * mu * vn2 >= rule.activation && u < rule.probability && after >= 0.0;
        // A pair that does not react collides elastically, with the impulse the elastic rule
        // (which reactions require) gives, worked out here from the contact already computed.
        let impulse = if !reacts || rule.heat == 0.0 {
            elastic::impulse(dr, dv, mi, mj)
        } else {
            // The normal relative velocity goes from `dot / |dr|` (< 0) to `+sqrt(after)`.
            dr * (mu * (dot / r2 - after.sqrt() / r2.sqrt()))
        };
        self.body[i].vel = vi + impulse / mi;
        self.body[j].vel = vj - impulse / mj;
        self.body[i].count = self.body[i].count.wrapping_add(1);
        self.body[j].count = self.body[j].count.wrapping_add(1);
        self.stats.disc_disc = self.stats.disc_disc.wrapping_add(1);
        if !reacts {
            let record = EventRecord {
                time: t,
                kind: EventKind::DiscDisc { i, j },
                impulse,
            };
            return (record, [i, j]);
        }
        // Which disc becomes which product: the one of the rule's first species becomes its
        // first product; of like reactants, either, by the draw.
        let (ci, cj) = if rule.reactants.0 == rule.reactants.1 {
            if bit == (i < j) {
                (rule.products.0, rule.products.1)
            } else {
                (rule.products.1, rule.products.0)
            }
        } else if swapped {
            (rule.products.1, rule.products.0)
        } else {
            (rule.products.0, rule.products.1)
        };
        let chem = self.chemistry.as_deref_mut().expect("reaction rules");
        for (d, s) in [(i, ci), (j, cj)] {
            self.species[d] = s;
            if let Some(c) = chem.colour[s as usize] {
                self.colour[d] = c;
            }
        }
        chem.heat += rule.heat;
        chem.count[k] += 1;
        self.stats.reaction = self.stats.reaction.wrapping_add(1);
        let record = EventRecord {
            time: t,
            kind: EventKind::Reaction { i, j, rule: k },
            impulse,
        };
        (record, [i, j])
    }
}
