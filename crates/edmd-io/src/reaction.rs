//! The text of a reaction rule, as the Princeton format's `# edmd reaction` directive and
//! `edmd gen --reaction` write it:
//!
//! ```text
//! A + B -> C + D [activation E] [probability P] [heat Q]
//! ```
//!
//! `A`, `B`, `C`, `D` are species (whole numbers below [`MAX_REACTION_SPECIES`]); the spaces
//! around `+` and `->` may be left out (`0+1->2+2`). The options come after the equation, in
//! any order, each at most once: the activation energy `E` (`>= 0`, default 0), the
//! probability `P` that a collision above it reacts (in `[0, 1]`, default 1) and the heat `Q`
//! released into the pair's normal relative motion (negative: absorbed; default 0). See
//! `edmd_core::Reaction` for what a rule does.

use edmd_core::{Reaction, Reactions, MAX_REACTION_SPECIES};

/// How a rule is written, for messages.
pub const USAGE: &str = "A + B -> C + D [activation E] [probability P] [heat Q]";

/// Reads one rule from its words (those after `reaction` in the directive), or says what is
/// wrong with it.
pub fn parse(words: &[&str]) -> Result<Reaction, String> {
    let usage = || {
        format!("expected '{USAGE}' (species whole numbers from 0 to {MAX_REACTION_SPECIES_LAST})")
    };
    // The equation runs up to the first word that starts with a letter: species are numbers,
    // the options' names words.
    let split = words
        .iter()
        .position(|w| w.starts_with(|c: char| c.is_ascii_alphabetic()))
        .unwrap_or(words.len());
    let equation: String = words[..split].concat();
    if equation.is_empty() {
        return Err(usage());
    }
    let Some((left, right)) = equation.split_once("->") else {
        return Err(usage());
    };
    let pair = |side: &str| -> Result<(u16, u16), String> {
        let Some((a, b)) = side.split_once('+') else {
            return Err(usage());
        };
        Ok((species(a)?, species(b)?))
    };
    let (reactants, products) = (pair(left)?, pair(right)?);
    let mut rule = Reaction {
        reactants,
        products,
        activation: 0.0,
        probability: 1.0,
        heat: 0.0,
    };
    let mut seen: Vec<&str> = Vec::new();
    let mut rest = &words[split..];
    while let [name, tail @ ..] = rest {
        let field = match *name {
            "activation" => &mut rule.activation,
            "probability" => &mut rule.probability,
            "heat" => &mut rule.heat,
            other => {
                return Err(format!(
                "unknown word '{other}' after the equation (activation E, probability P, heat Q)"
            ))
            }
        };
        if seen.contains(name) {
            return Err(format!("{name} is given twice"));
        }
        seen.push(name);
        let Some((value, tail)) = tail.split_first() else {
            return Err(format!("{name} needs a number after it"));
        };
        *field = value
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("{name} must be a finite number, found '{value}'"))?;
        rest = tail;
    }
    if rule.activation < 0.0 {
        return Err(format!(
            "the activation energy must be >= 0, found {}",
            rule.activation
        ));
    }
    if !(0.0..=1.0).contains(&rule.probability) {
        return Err(format!(
            "the probability must be in [0, 1], found {}",
            rule.probability
        ));
    }
    // What the engine checks of one rule, so that a rule read is one it takes.
    Reactions::new(vec![rule])
        .validate()
        .map_err(|e| e.to_string())?;
    Ok(rule)
}

/// [`parse`] on a rule written as one string (`edmd gen --reaction '0+1->2+2 activation 1'`).
pub fn parse_text(text: &str) -> Result<Reaction, String> {
    parse(&text.split_whitespace().collect::<Vec<_>>())
}

const MAX_REACTION_SPECIES_LAST: u16 = MAX_REACTION_SPECIES - 1;

fn species(s: &str) -> Result<u16, String> {
    s.parse::<u16>()
        .ok()
        .filter(|&k| k < MAX_REACTION_SPECIES)
        .ok_or_else(|| {
            format!(
                "species must be whole numbers from 0 to {MAX_REACTION_SPECIES_LAST}, found '{s}'"
            )
        })
}

/// `A + B -> C + D`.
pub fn equation(r: &Reaction) -> String {
    format!(
        "{} + {} -> {} + {}",
        r.reactants.0, r.reactants.1, r.products.0, r.products.1
    )
}

/// The rule as [`parse`] reads it back to the same bits: the equation, then the options that
/// differ from their defaults, each number in its shortest exact form.
pub fn text(r: &Reaction) -> String {
    let mut t = equation(r);
    // -0 is written too: it reads back as the same bits.
    if r.activation != 0.0 || r.activation.is_sign_negative() {
        t += &format!(" activation {}", crate::text::exact(r.activation));
    }
    if r.probability != 1.0 {
        t += &format!(" probability {}", crate::text::exact(r.probability));
    }
    if r.heat != 0.0 || r.heat.is_sign_negative() {
        t += &format!(" heat {}", crate::text::exact(r.heat));
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_rule_with_or_without_spaces_and_options_in_any_order() {
        let r = parse_text("0 + 1 -> 2 + 2 probability 0.5 activation 1.5 heat -0.25").unwrap();
        assert_eq!(
            r,
            Reaction {
                reactants: (0, 1),
                products: (2, 2),
                activation: 1.5,
                probability: 0.5,
                heat: -0.25,
            }
        );
        assert_eq!(
            parse_text("0+1->2+2 activation 1.5 probability 0.5 heat -0.25"),
            Ok(r)
        );
        assert_eq!(
            parse_text("0 +1-> 2+ 2 heat -0.25 activation 1.5 probability .5"),
            Ok(r)
        );
        let plain = parse_text("3+3->4+5").unwrap();
        assert_eq!(
            (plain.activation, plain.probability, plain.heat),
            (0.0, 1.0, 0.0)
        );
    }

    #[test]
    fn writes_what_it_reads_bit_for_bit() {
        for text in [
            "0 + 1 -> 2 + 2",
            "0 + 1 -> 1 + 1 activation 0.30000000000000004 probability 0.1 heat -1e-300",
            "7 + 7 -> 0 + 255 heat 3.0",
            "1 + 0 -> 0 + 1 activation -0.0",
        ] {
            let r = parse_text(text).unwrap();
            assert_eq!(super::text(&r), text);
            let back = parse_text(&super::text(&r)).unwrap();
            assert_eq!(back.activation.to_bits(), r.activation.to_bits());
            assert_eq!(back.heat.to_bits(), r.heat.to_bits());
        }
    }

    #[test]
    fn says_what_is_wrong() {
        for (text, what) in [
            ("", "expected 'A + B -> C + D"),
            ("A + B -> C + D", "expected 'A + B -> C + D"),
            ("0 + 1 2 + 2", "expected 'A + B -> C + D"),
            ("0 1 -> 2 + 2", "expected 'A + B -> C + D"),
            ("0 + 1 -> 2 + 2 + 3", "found '2+3'"),
            ("0 + x1 -> 2 + 2", "expected 'A + B -> C + D"),
            ("0 + 1x -> 2 + 2", "found '1x'"),
            ("0 + -1 -> 2 + 2", "found '-1'"),
            ("0 + 1 -> 2 + 256", "from 0 to 255, found '256'"),
            ("0 + 1 -> 2 + 2 energy 1", "unknown word 'energy'"),
            ("0 + 1 -> 2 + 2 activation", "activation needs a number"),
            ("0 + 1 -> 2 + 2 activation -1", "must be >= 0, found -1"),
            (
                "0 + 1 -> 2 + 2 activation nan",
                "finite number, found 'nan'",
            ),
            ("0 + 1 -> 2 + 2 heat inf", "finite number, found 'inf'"),
            ("0 + 1 -> 2 + 2 probability 1.5", "in [0, 1], found 1.5"),
            ("0 + 1 -> 2 + 2 probability -0.1", "in [0, 1], found -0.1"),
            ("0 + 1 -> 2 + 2 heat 1 heat 2", "heat is given twice"),
            ("0 + 1 -> 2 + 2 heat 1 2", "unknown word"),
        ] {
            let e = parse_text(text).unwrap_err();
            assert!(e.contains(what), "{text:?}: {e}");
        }
    }
}
