//! The "Collisions" course format.
//!
//! ```text
//! N
//! R
//! Lx Ly
//! x y u v      (N lines)
//! ```
//! All discs have radius `R` and equal (unit) mass; the box has walls at `0, Lx` and `0, Ly`.

use edmd_core::{Disc, SimBox, Vector};

use crate::text::{count, err, exact, expect_end, number, numbers, Lines};
use crate::{Format, LoadedSystem, ParseError};

/// A course-format system.
#[derive(Clone, Debug, PartialEq)]
pub struct CourseSystem {
    /// Common radius.
    pub radius: f64,
    /// Box lengths.
    pub lengths: [f64; 2],
    /// Discs (unit mass).
    pub discs: Vec<Disc>,
    /// 1-based line of each disc.
    pub lines: Vec<usize>,
}

impl CourseSystem {
    /// As a [`LoadedSystem`] with a walled box.
    pub fn into_loaded(self) -> LoadedSystem {
        LoadedSystem {
            discs: self.discs,
            sim_box: SimBox::walls(self.lengths),
            barriers: Vec::new(),
            lines: self.lines,
            format: Format::Course,
            time: 0.0,
            potential: Default::default(),
            reactions: Vec::new(),
            restitution: None,
            gravity: None,
            shear: None,
            ring: None,
            self_gravity: None,
        }
    }
}

/// Reads the course format.
pub fn parse(text: &str) -> Result<CourseSystem, ParseError> {
    let mut lines = Lines::new(text);
    let n = count(&mut lines)?;
    let (line, f) = lines.expect_fields("the radius (line 2)")?;
    if f.len() != 1 {
        return Err(err(
            line,
            format!("expected the radius alone, found {} fields", f.len()),
        ));
    }
    let radius = number(line, f[0], "radius")?;
    if radius <= 0.0 {
        return Err(err(line, format!("radius must be > 0, found {radius}")));
    }
    let (line, f) = lines.expect_fields("the box size Lx Ly (line 3)")?;
    let l = numbers(line, &f, &["Lx", "Ly"])?;
    for (k, name) in ["Lx", "Ly"].iter().enumerate() {
        if l[k] <= 0.0 {
            return Err(err(line, format!("{name} must be > 0, found {}", l[k])));
        }
    }
    let mut discs = Vec::with_capacity(n.min(1 << 24));
    let mut at = Vec::with_capacity(n.min(1 << 24));
    for k in 0..n {
        let (line, f) = lines.expect_fields(&format!("disc {} of {n}", k + 1))?;
        let x = numbers(line, &f, &["x", "y", "u", "v"])?;
        discs.push(Disc::new(
            Vector::new([x[0], x[1]]),
            Vector::new([x[2], x[3]]),
            radius,
        ));
        at.push(line);
    }
    expect_end(&mut lines, n)?;
    // A directive would otherwise be passed over without a word, the run not being the one
    // the file seems to describe.
    if let Some((line, words)) = lines.directives.first() {
        return Err(err(
            *line,
            format!(
                "`# edmd {}` is a directive of the Princeton format; the course format has none",
                words.first().copied().unwrap_or("")
            ),
        ));
    }
    Ok(CourseSystem {
        radius,
        lengths: [l[0], l[1]],
        discs,
        lines: at,
    })
}

/// Why a system cannot be written in the course format without losing something, if it cannot.
pub fn fits(
    discs: &[Disc],
    sim_box: &SimBox,
    barriers: &[edmd_core::Barrier],
) -> Result<(), String> {
    if let Some(d) = discs
        .iter()
        .find(|d| d.radius != discs[0].radius || d.mass != discs[0].mass)
    {
        return Err(format!(
            "the course format has one radius and one mass for all discs (found {} and {})",
            d.radius, d.mass
        ));
    }
    if sim_box.boundaries != [edmd_core::Boundary::Walls; 2] {
        return Err("the course format has walls only".into());
    }
    if !barriers.is_empty() {
        return Err("the course format has no internal barriers".into());
    }
    Ok(())
}

/// Writes discs in the course format (the radius of the first disc is written; an empty system
/// gets radius 1).
pub fn write(
    out: &mut impl std::io::Write,
    discs: &[Disc],
    sim_box: &SimBox,
) -> std::io::Result<()> {
    writeln!(out, "{}", discs.len())?;
    writeln!(out, "{}", exact(discs.first().map_or(1.0, |d| d.radius)))?;
    writeln!(
        out,
        "{} {}",
        exact(sim_box.lengths[0]),
        exact(sim_box.lengths[1])
    )?;
    for d in discs {
        writeln!(
            out,
            "{} {} {} {}",
            exact(d.pos[0]),
            exact(d.pos[1]),
            exact(d.vel[0]),
            exact(d.vel[1])
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_course_example() {
        let s = parse("3\n0.1\n10 8\n5 6 -0.09 -0.38\n3 2  0.15  0.1\n6 1 -0.2   0.15").unwrap();
        assert_eq!(s.radius, 0.1);
        assert_eq!(s.lengths, [10.0, 8.0]);
        assert_eq!(s.discs[2].vel, Vector::new([-0.2, 0.15]));
        assert_eq!(s.lines, vec![4, 5, 6]);
    }

    #[test]
    fn round_trips_exactly() {
        let s = parse("2\n0.25\n3 4\n1 1 0.1 -0.30000000000000004\n2 2 1e-300 5\n").unwrap();
        let mut out = Vec::new();
        write(&mut out, &s.discs, &SimBox::walls(s.lengths)).unwrap();
        let t = parse(std::str::from_utf8(&out).unwrap()).unwrap();
        assert_eq!(s.discs, t.discs);
    }

    #[test]
    fn every_malformation_names_its_line() {
        let cases: &[(&str, usize, &str)] = &[
            ("", 1, "empty"),
            ("x\n", 1, "whole number"),
            ("-2\n", 1, "whole number"),
            ("2\n", 1, "file ends before the radius"),
            ("1\n0\n1 1\n0.5 0.5 1 1\n", 2, "radius must be > 0"),
            ("1\n1 2\n", 2, "radius alone"),
            ("1\n1\n5\n", 3, "expected 2 numbers"),
            ("1\n1\n5 -5\n", 3, "Ly must be > 0"),
            ("2\n1\n5 5\n1 1 1 1\n", 4, "file ends before disc 2 of 2"),
            ("1\n1\n5 5\n1 1 1\n", 4, "expected 4 numbers"),
            ("1\n1\n5 5\n1 abc 1 1\n", 4, "y is not a number: 'abc'"),
            ("1\n1\n5 5\n1 NaN 1 1\n", 4, "y is not finite"),
            ("1\n1\n5 5\n1 1 inf 1\n", 4, "u is not finite"),
            ("1\n1\n5 5\n1 1 1 1\n2 2 2 2\n", 5, "more disc lines"),
            (
                "1\n1\n5 5\n1 1 1 1\n# edmd box 20 20\n",
                5,
                "`# edmd box` is a directive",
            ),
            (
                "1\n# edmd potential 0 0 1.5 -1\n1\n5 5\n1 1 1 1\n",
                2,
                "course format has none",
            ),
        ];
        for (text, line, what) in cases {
            let e = parse(text).unwrap_err();
            assert_eq!(e.line, *line, "{text:?}: {e}");
            assert!(e.message.contains(what), "{text:?}: {e}");
        }
    }

    /// A file saved with a byte order mark (some Windows editors) reads as the same file,
    /// in either format, and its format is still told apart.
    #[test]
    fn a_byte_order_mark_is_not_part_of_the_file() {
        let text = "# two discs\n2\n0.5\n10 10\n2 5 1 0\n8 5 -1 0\n";
        let marked = format!("\u{feff}{text}");
        assert_eq!(parse(&marked).unwrap(), parse(text).unwrap());
        assert_eq!(crate::detect(&marked), Some(crate::Format::Course));
        let princeton = "1\n0.5 0.5 0 0 0.01 1 0 0 0\n";
        let order = crate::princeton::ColumnOrder::default();
        assert_eq!(
            crate::princeton::parse(&format!("\u{feff}{princeton}"), order).unwrap(),
            crate::princeton::parse(princeton, order).unwrap()
        );
    }
}
