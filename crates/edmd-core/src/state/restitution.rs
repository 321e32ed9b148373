//! Inelastic collisions: a coefficient of normal restitution per pair of species, and one for
//! the walls.
//!
//! At a collision the normal relative velocity `v_n` becomes `-e v_n`, momentum conserved
//! exactly, and the pair loses `(1 - e^2) mu v_n^2 / 2` of kinetic energy (`mu` the reduced
//! mass); the tangential velocities are those of smooth discs, unchanged. `e` is a constant,
//! or Bridges, Hatzes and Lin's law for ice (Nature 309, 333 (1984)),
//! `e(v_n) = min(1, (|v_n| / v_c)^-0.234)`: elastic below the speed `v_c`, softer above.
//!
//! Inelastic collapse (infinitely many collisions in a finite time, as three discs in a row
//! lose their relative motion) would stop the clock; the TC model of Luding and McNamara
//! (Granular Matter 1, 113 (1998)) prevents it: a collision that comes less than `tc` after
//! either disc's previous one (with a disc or a wall) is elastic. Dense clusters then keep a
//! little kinetic energy: their collisions come about every `tc`, so that only about a fraction
//! `t_collision / tc` of them dissipate. `tc = 0` (the default) turns the model off.

use crate::error::Error;

/// The exponent of Bridges, Hatzes and Lin's law.
pub const BRIDGES_EXPONENT: f64 = 0.234;

/// A coefficient of normal restitution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RestitutionLaw {
    /// The same `e` in `[0, 1]` at every speed (1: elastic).
    Constant(f64),
    /// `e(v_n) = min(1, (|v_n| / v_c)^-0.234)` (Bridges, Hatzes and Lin 1984), `v_c > 0`.
    Bridges {
        /// The normal impact speed below which collisions are elastic.
        v_c: f64,
    },
}

impl RestitutionLaw {
    /// The coefficient at normal relative speed `vn` (`>= 0`).
    #[inline(always)]
    pub fn at(&self, vn: f64) -> f64 {
        match *self {
            RestitutionLaw::Constant(e) => e,
            RestitutionLaw::Bridges { v_c } => {
                if vn <= v_c {
                    1.0
                } else {
                    (vn / v_c).powf(-BRIDGES_EXPONENT)
                }
            }
        }
    }

    /// Whether every collision under this law is elastic.
    pub fn is_elastic(&self) -> bool {
        matches!(*self, RestitutionLaw::Constant(e) if e == 1.0)
    }

    fn validate(&self, what: &str) -> Result<(), Error> {
        match *self {
            RestitutionLaw::Constant(e) if !(e.is_finite() && (0.0..=1.0).contains(&e)) => Err(
                Error::BadRestitution(format!("{what}: e must be in [0, 1], found {e:?}")),
            ),
            RestitutionLaw::Bridges { v_c } if !(v_c.is_finite() && v_c > 0.0) => {
                Err(Error::BadRestitution(format!(
                    "{what}: Bridges' speed v_c must be a finite number > 0, found {v_c:?}"
                )))
            }
            _ => Ok(()),
        }
    }
}

/// The most species restitution pairs may name (the engine keeps a table per pair).
pub const MAX_RESTITUTION_SPECIES: u16 = 256;

/// How inelastic collisions are: per pair of species, at the walls, and the TC model's time.
#[derive(Clone, Debug, PartialEq)]
pub struct Restitution {
    /// The law of every pair of species not in [`Self::pairs`].
    pub all: RestitutionLaw,
    /// Laws for given pairs of species `(a, b, law)`, `(a, b)` and `(b, a)` being one pair.
    pub pairs: Vec<(u16, u16, RestitutionLaw)>,
    /// The walls' coefficient, in `[0, 1]` (1: they reflect elastically).
    pub wall: f64,
    /// The TC model's time (`>= 0`; 0: off): a collision less than `tc` after either disc's
    /// previous one is elastic.
    pub tc: f64,
}

impl Default for Restitution {
    fn default() -> Self {
        Restitution {
            all: RestitutionLaw::Constant(1.0),
            pairs: Vec::new(),
            wall: 1.0,
            tc: 0.0,
        }
    }
}

impl Restitution {
    /// The same constant `e` for every pair, elastic walls, no TC model.
    pub fn constant(e: f64) -> Self {
        Restitution {
            all: RestitutionLaw::Constant(e),
            ..Self::default()
        }
    }

    /// Checks the laws, the walls' coefficient and `tc`, and that no pair is named twice or
    /// names a species at or above [`MAX_RESTITUTION_SPECIES`].
    pub fn validate(&self) -> Result<(), Error> {
        self.all.validate("every pair")?;
        for (k, &(a, b, law)) in self.pairs.iter().enumerate() {
            let what = format!("species {a} and {b}");
            if a >= MAX_RESTITUTION_SPECIES || b >= MAX_RESTITUTION_SPECIES {
                return Err(Error::BadRestitution(format!(
                    "{what}: species must be below {MAX_RESTITUTION_SPECIES}"
                )));
            }
            law.validate(&what)?;
            if self.pairs[..k]
                .iter()
                .any(|&(c, d, _)| (c, d) == (a, b) || (c, d) == (b, a))
            {
                return Err(Error::BadRestitution(format!(
                    "{what}: the pair is given twice"
                )));
            }
        }
        if !(self.wall.is_finite() && (0.0..=1.0).contains(&self.wall)) {
            return Err(Error::BadRestitution(format!(
                "walls: e must be in [0, 1], found {:?}",
                self.wall
            )));
        }
        if !(self.tc.is_finite() && self.tc >= 0.0) {
            return Err(Error::BadRestitution(format!(
                "tc must be a finite number >= 0, found {:?}",
                self.tc
            )));
        }
        Ok(())
    }

    /// The law of discs of species `a` and `b`.
    pub fn law(&self, a: u16, b: u16) -> RestitutionLaw {
        self.pairs
            .iter()
            .find(|&&(c, d, _)| (c, d) == (a, b) || (c, d) == (b, a))
            .map_or(self.all, |&(_, _, law)| law)
    }

    /// Whether every collision, with discs and walls, is elastic.
    pub fn is_elastic(&self) -> bool {
        self.all.is_elastic() && self.pairs.iter().all(|p| p.2.is_elastic()) && self.wall == 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bridges_law_is_elastic_below_v_c_and_falls_as_a_power_above() {
        let law = RestitutionLaw::Bridges { v_c: 0.5 };
        assert_eq!(law.at(0.0), 1.0);
        assert_eq!(law.at(0.5), 1.0);
        // (4 / 0.5)^-0.234 = 8^-0.234 = 2^-0.702.
        assert!((law.at(4.0) - 2f64.powf(-0.702)).abs() < 1e-15);
    }

    #[test]
    fn bad_values_are_refused_with_what_is_wrong() {
        let cases = [
            (
                Restitution::constant(1.5),
                "every pair: e must be in [0, 1]",
            ),
            (
                Restitution::constant(f64::NAN),
                "e must be in [0, 1], found NaN",
            ),
            (
                Restitution {
                    all: RestitutionLaw::Bridges { v_c: 0.0 },
                    ..Default::default()
                },
                "v_c must be a finite number > 0",
            ),
            (
                Restitution {
                    wall: -0.1,
                    ..Default::default()
                },
                "walls: e must be in [0, 1]",
            ),
            (
                Restitution {
                    tc: f64::INFINITY,
                    ..Default::default()
                },
                "tc must be a finite number >= 0",
            ),
            (
                Restitution {
                    pairs: vec![
                        (0, 1, RestitutionLaw::Constant(0.5)),
                        (1, 0, RestitutionLaw::Constant(0.6)),
                    ],
                    ..Default::default()
                },
                "species 1 and 0: the pair is given twice",
            ),
            (
                Restitution {
                    pairs: vec![(0, 300, RestitutionLaw::Constant(0.5))],
                    ..Default::default()
                },
                "species must be below 256",
            ),
        ];
        for (r, want) in cases {
            let e = r.validate().unwrap_err().to_string();
            assert!(e.contains(want), "{e}");
        }
        assert!(Restitution::constant(0.0).validate().is_ok());
    }

    #[test]
    fn pairs_override_the_common_law_in_either_order() {
        let r = Restitution {
            all: RestitutionLaw::Constant(0.9),
            pairs: vec![(2, 0, RestitutionLaw::Constant(0.5))],
            ..Default::default()
        };
        assert_eq!(r.law(0, 2), RestitutionLaw::Constant(0.5));
        assert_eq!(r.law(2, 0), RestitutionLaw::Constant(0.5));
        assert_eq!(r.law(1, 1), RestitutionLaw::Constant(0.9));
        assert!(!r.is_elastic());
        assert!(Restitution::default().is_elastic());
    }
}
