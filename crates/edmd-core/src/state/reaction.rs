//! Reactive collisions: rules that change the species of colliding discs.
//!
//! A rule `A + B -> C + D` applies when a disc of species `A` collides with one of species `B`
//! and the kinetic energy of their relative motion along the line of centres,
//! `mu v_n^2 / 2` (`mu` the reduced mass, `v_n` the normal relative velocity), is at least the
//! activation energy; it then happens with its probability. The disc of species `A` becomes
//! `C`, the one of `B` becomes `D`, and the heat `Q` is released into the normal relative
//! motion: the pair separates with `mu v_n'^2 / 2 = mu v_n^2 / 2 + Q`, momentum conserved
//! exactly. An endothermic rule (`Q < 0`) that the normal motion cannot pay for is a plain
//! elastic collision. With no heat the velocities change exactly as in an elastic collision,
//! bit for bit.
//!
//! Species differ in label and colour only: a disc keeps its mass and radius when it reacts
//! (products of another size would overlap their neighbours, or leave a gap that no exact
//! dynamics fills). The species' masses and radii are whatever the discs of that species have.

use crate::error::Error;
use crate::state::Colour;

/// One reaction rule, `reactants.0 + reactants.1 -> products.0 + products.1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reaction {
    /// The two species that react (in either order).
    pub reactants: (u16, u16),
    /// What they become: the disc of species `reactants.0` becomes `products.0`, the other
    /// `products.1`. For like reactants (`A + A -> C + D`) each of the two is as likely to
    /// become `C`.
    pub products: (u16, u16),
    /// The least kinetic energy of the relative motion along the line of centres for the
    /// reaction to happen (`>= 0`).
    pub activation: f64,
    /// The probability that a collision above the activation energy reacts (in `[0, 1]`).
    pub probability: f64,
    /// Heat released into the pair's normal relative motion (negative: absorbed from it).
    pub heat: f64,
}

/// The most species reaction rules may name (the engine keeps a table per pair).
pub const MAX_REACTION_SPECIES: u16 = 256;

/// A set of reaction rules, with the seed of their random draws and the colour each species
/// takes when a disc becomes it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Reactions {
    /// The rules, at most one per pair of species.
    pub rules: Vec<Reaction>,
    /// Seed of the draws of rules whose probability is below 1 (and of which of two like
    /// reactants becomes which product).
    pub seed: u64,
    /// The colour a disc takes when it becomes a species: `(species, colour)`. A species not
    /// listed keeps the disc's colour.
    pub colours: Vec<(u16, Colour)>,
}

impl Reactions {
    /// Rules with seed 0 and no colours.
    pub fn new(rules: Vec<Reaction>) -> Self {
        Reactions {
            rules,
            ..Self::default()
        }
    }

    /// Checks the rules on their own: species below [`MAX_REACTION_SPECIES`], activation
    /// energies finite and `>= 0`, probabilities in `[0, 1]`, heats finite, and at most one
    /// rule per pair of species (`A + B` and `B + A` are the same pair). That every reactant
    /// is a species some disc has or some rule makes is checked with the discs, by the
    /// simulation.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |msg: String| Err(Error::BadReaction(msg));
        for (k, r) in self.rules.iter().enumerate() {
            let (a, b) = r.reactants;
            let name = format!("{a} + {b} -> {} + {}", r.products.0, r.products.1);
            for s in [a, b, r.products.0, r.products.1] {
                if s >= MAX_REACTION_SPECIES {
                    return bad(format!(
                        "{name}: species must be below {MAX_REACTION_SPECIES}, found {s}"
                    ));
                }
            }
            if !(r.activation.is_finite() && r.activation >= 0.0) {
                return bad(format!(
                    "{name}: the activation energy must be a finite number >= 0, found {:?}",
                    r.activation
                ));
            }
            if !(r.probability.is_finite() && (0.0..=1.0).contains(&r.probability)) {
                return bad(format!(
                    "{name}: the probability must be in [0, 1], found {:?}",
                    r.probability
                ));
            }
            if !r.heat.is_finite() {
                return bad(format!(
                    "{name}: the heat must be finite, found {:?}",
                    r.heat
                ));
            }
            if let Some(q) = self.rules[..k]
                .iter()
                .find(|q| q.reactants == (a, b) || q.reactants == (b, a))
            {
                return bad(format!(
                    "{name}: a second rule for species {a} and {b} (the first is {} + {} -> {} + {}); give each pair one rule",
                    q.reactants.0, q.reactants.1, q.products.0, q.products.1
                ));
            }
        }
        for &(s, _) in &self.colours {
            if s >= MAX_REACTION_SPECIES {
                return bad(format!(
                    "colour of species {s}: species must be below {MAX_REACTION_SPECIES}"
                ));
            }
        }
        Ok(())
    }

    /// Gives every species a rule makes a colour, where [`Self::colours`] has none: the colour
    /// of the first disc of that species in `discs` (`(species, colour)` per disc), or else
    /// [`species_colour`]'s. The file readers and Python call this, so that products look
    /// alike wherever they are made.
    pub fn fill_colours(&mut self, discs: impl IntoIterator<Item = (u16, Colour)>) {
        let mut first: Vec<(u16, Colour)> = Vec::new();
        for (s, c) in discs {
            if !first.iter().any(|f| f.0 == s) {
                first.push((s, c));
            }
        }
        let made: Vec<u16> = self
            .rules
            .iter()
            .flat_map(|r| [r.products.0, r.products.1])
            .collect();
        for s in made {
            if self.colours.iter().any(|c| c.0 == s) {
                continue;
            }
            let c = first
                .iter()
                .find(|f| f.0 == s)
                .map_or_else(|| species_colour(s), |f| f.1);
            self.colours.push((s, c));
        }
    }

    /// The rule for a pair of species, and whether it names them the other way round.
    pub fn rule_for(&self, a: u16, b: u16) -> Option<(usize, bool)> {
        self.rules.iter().enumerate().find_map(|(k, r)| {
            if r.reactants == (a, b) {
                Some((k, false))
            } else if r.reactants == (b, a) {
                Some((k, true))
            } else {
                None
            }
        })
    }
}

/// A colour for species `s` that no disc of the input shows: ten well-separated colours
/// (Tableau's palette, as matplotlib's default cycle), repeating.
pub fn species_colour(s: u16) -> Colour {
    const PALETTE: [Colour; 10] = [
        [31, 119, 180],
        [255, 127, 14],
        [44, 160, 44],
        [214, 39, 40],
        [148, 103, 189],
        [140, 86, 75],
        [227, 119, 194],
        [127, 127, 127],
        [188, 189, 34],
        [23, 190, 207],
    ];
    PALETTE[s as usize % PALETTE.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rule(a: u16, b: u16, c: u16, d: u16) -> Reaction {
        Reaction {
            reactants: (a, b),
            products: (c, d),
            activation: 1.0,
            probability: 1.0,
            heat: 0.0,
        }
    }

    #[test]
    fn refuses_what_cannot_be() {
        let cases: Vec<(Reaction, &str)> = vec![
            (
                Reaction {
                    activation: -1.0,
                    ..rule(0, 1, 1, 1)
                },
                "activation energy",
            ),
            (
                Reaction {
                    activation: f64::NAN,
                    ..rule(0, 1, 1, 1)
                },
                "activation energy",
            ),
            (
                Reaction {
                    probability: 1.5,
                    ..rule(0, 1, 1, 1)
                },
                "probability",
            ),
            (
                Reaction {
                    heat: f64::INFINITY,
                    ..rule(0, 1, 1, 1)
                },
                "heat",
            ),
            (rule(0, 300, 1, 1), "below 256"),
        ];
        for (r, what) in cases {
            let e = Reactions::new(vec![r]).validate().unwrap_err().to_string();
            assert!(e.contains(what), "{e}");
        }
        let e = Reactions::new(vec![rule(0, 1, 2, 2), rule(1, 0, 3, 3)])
            .validate()
            .unwrap_err()
            .to_string();
        assert!(e.contains("a second rule for species 1 and 0"), "{e}");
        Reactions::new(vec![rule(0, 1, 2, 2), rule(0, 0, 3, 3)])
            .validate()
            .unwrap();
    }

    #[test]
    fn products_take_their_species_colour() {
        let mut r = Reactions::new(vec![rule(0, 1, 1, 2), rule(2, 2, 3, 3)]);
        r.colours.push((3, [9, 9, 9]));
        r.fill_colours([(0, [1, 1, 1]), (1, [5, 5, 5]), (1, [6, 6, 6])]);
        assert_eq!(
            r.colours,
            vec![(3, [9, 9, 9]), (1, [5, 5, 5]), (2, species_colour(2))]
        );
    }

    #[test]
    fn finds_the_rule_either_way_round() {
        let r = Reactions::new(vec![rule(0, 1, 2, 3)]);
        assert_eq!(r.rule_for(0, 1), Some((0, false)));
        assert_eq!(r.rule_for(1, 0), Some((0, true)));
        assert_eq!(r.rule_for(0, 0), None);
    }
}
