//! The text of inelastic collisions, as the Princeton format's `# edmd restitution` directive,
//! `edmd gen --restitution` and Python read and write it. Each directive line says one thing:
//!
//! ```text
//! E                 every pair of species: constant coefficient E in [0, 1]
//! bridges VC        every pair: Bridges, Hatzes and Lin's e(v) = min(1, (v / VC)^-0.234)
//! A B E             species A and B (either order): constant E
//! A B bridges VC    species A and B: Bridges' law
//! walls E           the walls' coefficient
//! tc T              the TC model's time (a collision within T of either disc's previous one
//!                   is elastic; 0: off)
//! ```
//!
//! See `edmd_core::Restitution` for what they do.

use edmd_core::state::MAX_RESTITUTION_SPECIES;
use edmd_core::{Restitution, RestitutionLaw};

/// How a directive is written, for messages.
pub const USAGE: &str = "E | bridges VC | A B E | A B bridges VC | walls E | tc T";

/// Which part of a [`Restitution`] a line set: a second line for the same part is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// The law of every pair.
    All,
    /// The law of one pair of species (in the order given).
    Pair(u16, u16),
    /// The walls' coefficient.
    Walls,
    /// The TC model's time.
    Tc,
}

impl Part {
    /// Whether two parts name the same thing (a pair in either order).
    pub fn same(self, other: Part) -> bool {
        match (self, other) {
            (Part::Pair(a, b), Part::Pair(c, d)) => (a, b) == (c, d) || (a, b) == (d, c),
            _ => self == other,
        }
    }

    /// What the part is, for messages.
    pub fn name(self) -> String {
        match self {
            Part::All => "every pair".into(),
            Part::Pair(a, b) => format!("species {a} and {b}"),
            Part::Walls => "the walls".into(),
            Part::Tc => "tc".into(),
        }
    }
}

fn value(word: &str, what: &str) -> Result<f64, String> {
    let x: f64 = word
        .parse()
        .map_err(|_| format!("{what} is not a number: '{word}'"))?;
    if !x.is_finite() {
        return Err(format!("{what} is not finite: '{word}'"));
    }
    Ok(x)
}

fn coefficient(word: &str) -> Result<f64, String> {
    let e = value(word, "the coefficient")?;
    if !(0.0..=1.0).contains(&e) {
        return Err(format!("the coefficient must be in [0, 1], found {e}"));
    }
    Ok(e)
}

fn law(words: &[&str]) -> Result<RestitutionLaw, String> {
    match words {
        [e] if *e != "bridges" => Ok(RestitutionLaw::Constant(coefficient(e)?)),
        ["bridges", vc] => {
            let v_c = value(vc, "Bridges' speed VC")?;
            if v_c <= 0.0 {
                return Err(format!("Bridges' speed VC must be > 0, found {v_c}"));
            }
            Ok(RestitutionLaw::Bridges { v_c })
        }
        _ => Err(format!("expected '{USAGE}'")),
    }
}

fn species(word: &str) -> Result<u16, String> {
    word.parse::<u16>()
        .ok()
        .filter(|&s| s < MAX_RESTITUTION_SPECIES)
        .ok_or_else(|| {
            format!(
                "species must be a whole number from 0 to {}, found '{word}'",
                MAX_RESTITUTION_SPECIES - 1
            )
        })
}

/// Reads one directive's words (those after `restitution`) into `into`; returns the part it
/// set, or says what is wrong. The caller refuses a part given twice ([`Part::same`]).
pub fn parse(words: &[&str], into: &mut Restitution) -> Result<Part, String> {
    match words {
        ["walls", e] => {
            into.wall = coefficient(e)?;
            Ok(Part::Walls)
        }
        ["tc", t] => {
            let tc = value(t, "tc")?;
            if tc < 0.0 {
                return Err(format!("tc must be >= 0, found {tc}"));
            }
            into.tc = tc;
            Ok(Part::Tc)
        }
        [a, b, rest @ ..]
            if !rest.is_empty()
                && a.starts_with(|c: char| c.is_ascii_digit())
                && *b != "bridges" =>
        {
            let (a, b) = (species(a)?, species(b)?);
            into.pairs.push((a, b, law(rest)?));
            Ok(Part::Pair(a, b))
        }
        _ => {
            into.all = law(words)?;
            Ok(Part::All)
        }
    }
}

/// Whether `r` has a constant coefficient below 1 (for every pair or some pair) without the TC
/// model: on a ring patch, which a cold dense layer of such particles would reach, inelastic
/// collapse (infinitely many collisions in a finite time). Bridges' law, elastic at low
/// speeds, does not collapse.
pub fn collapses_without_tc(r: &Restitution) -> bool {
    let below_1 = |l: &RestitutionLaw| matches!(*l, RestitutionLaw::Constant(e) if e < 1.0);
    r.tc <= 0.0 && (below_1(&r.all) || r.pairs.iter().any(|p| below_1(&p.2)))
}

/// The directive lines' words (without `# edmd restitution`) that give `r` back, leaving out
/// what is as by default.
pub fn lines(r: &Restitution) -> Vec<String> {
    let law = |l: RestitutionLaw| match l {
        RestitutionLaw::Constant(e) => crate::text::exact(e),
        RestitutionLaw::Bridges { v_c } => format!("bridges {}", crate::text::exact(v_c)),
    };
    let mut out = Vec::new();
    if r.all != RestitutionLaw::Constant(1.0) {
        out.push(law(r.all));
    }
    for &(a, b, l) in &r.pairs {
        out.push(format!("{a} {b} {}", law(l)));
    }
    if r.wall != 1.0 {
        out.push(format!("walls {}", crate::text::exact(r.wall)));
    }
    if r.tc != 0.0 {
        out.push(format!("tc {}", crate::text::exact(r.tc)));
    }
    // Restitution that is all defaults (`# edmd restitution tc 0` alone) is still
    // restitution: one line keeps it, so that it reads back as it was.
    if out.is_empty() {
        out.push(law(r.all));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (found by fuzzing the Princeton reader, `fuzz/corpus/read_princeton/
    /// read_princeton-elastic-restitution-written-back`): a file whose only restitution line
    /// was `tc 0` read as elastic restitution, which was written back as no line at all, so
    /// the state written read back without restitution.
    #[test]
    fn restitution_of_defaults_alone_is_written_back() {
        let mut r = Restitution::default();
        parse(&["tc", "0"], &mut r).unwrap();
        assert_eq!(lines(&r), vec!["1.0".to_string()]);
        let mut back = Restitution::default();
        parse(&["1.0"], &mut back).unwrap();
        assert_eq!(back, r);
    }

    fn read(lines: &[&str]) -> Result<Restitution, String> {
        let mut r = Restitution::default();
        for l in lines {
            let w: Vec<&str> = l.split_whitespace().collect();
            parse(&w, &mut r)?;
        }
        Ok(r)
    }

    #[test]
    fn every_form_is_read_and_written_back() {
        let text = [
            "0.9",
            "0 1 bridges 0.25",
            "2 2 0.5",
            "walls 0.75",
            "tc 0.001",
        ];
        let r = read(&text).unwrap();
        assert_eq!(r.all, RestitutionLaw::Constant(0.9));
        assert_eq!(
            r.pairs,
            vec![
                (0, 1, RestitutionLaw::Bridges { v_c: 0.25 }),
                (2, 2, RestitutionLaw::Constant(0.5))
            ]
        );
        assert_eq!((r.wall, r.tc), (0.75, 0.001));
        assert_eq!(lines(&r), text);
        assert_eq!(
            read(&["bridges 2"]).unwrap().all,
            RestitutionLaw::Bridges { v_c: 2.0 }
        );
    }

    #[test]
    fn bad_lines_say_what_is_wrong() {
        for (line, want) in [
            ("1.5", "the coefficient must be in [0, 1], found 1.5"),
            ("nan", "not finite"),
            ("bridges 0", "VC must be > 0"),
            ("bridges", "expected"),
            ("walls -1", "must be in [0, 1]"),
            ("tc -1", "tc must be >= 0"),
            ("0 1", "expected"),
            ("0 300 0.5", "species must be a whole number from 0 to 255"),
            ("x 1 0.5", "expected"),
            ("", "expected"),
        ] {
            let e = read(&[line]).unwrap_err();
            assert!(e.contains(want), "{line}: {e}");
        }
    }
}
