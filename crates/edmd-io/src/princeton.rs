//! The Princeton CollisionSystem format.
//!
//! ```text
//! N
//! rx ry vx vy radius mass r g b     (N lines; r g b integers 0..=255)
//! ```
//! The box is the unit square with walls. The 25 published data files put the radius before the
//! mass (`p10.txt`: `... 0.02 10 ...`), while the assignment's prose lists mass first; the files'
//! order is the default ([`ColumnOrder::RadiusMass`]).
//!
//! # edmd's extension
//! Every published file is also a valid extended file. The extension adds:
//! - comment lines, whose first non-blank character is `#`, anywhere;
//! - directives, comments of the form `# edmd ...`:
//!   - `# edmd box LX LY`: the box `[0, LX] x [0, LY]` (default: the unit square);
//!   - `# edmd boundary X Y`: `walls` or `periodic` per axis (one word applies to both;
//!     default: walls);
//!   - `# edmd barrier AXIS POSITION [door LO HI [demon FAST SLOW]]`: an internal wall across
//!     the box perpendicular to axis `x` or `y` at `POSITION`, with an optional door and demon
//!     (see `edmd_core::Barrier`); repeatable;
//! - an optional tenth column on any disc line: the species, a whole number (default 0).

use edmd_core::{Barrier, Boundary, Demon, Disc, SimBox, Vector};

use crate::text::{count, err, exact, expect_end, number, Lines};
use crate::{Format, LoadedSystem, ParseError};

/// Order of the radius and mass columns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColumnOrder {
    /// `... radius mass r g b`, as in the published data files.
    #[default]
    RadiusMass,
    /// `... mass radius r g b`, as in the assignment's prose.
    MassRadius,
}

/// Reads the Princeton format.
pub fn parse(text: &str, order: ColumnOrder) -> Result<LoadedSystem, ParseError> {
    let mut lines = Lines::new(text);
    let n = count(&mut lines)?;
    let (ir, im) = match order {
        ColumnOrder::RadiusMass => (4, 5),
        ColumnOrder::MassRadius => (5, 4),
    };
    let mut names = ["rx", "ry", "vx", "vy", "", "", "r", "g", "b"];
    names[ir] = "radius";
    names[im] = "mass";
    let mut discs = Vec::with_capacity(n.min(1 << 24));
    let mut at = Vec::with_capacity(n.min(1 << 24));
    for k in 0..n {
        let (line, f) = lines.expect_fields(&format!("disc {} of {n}", k + 1))?;
        if f.len() != 9 && f.len() != 10 {
            return Err(err(
                line,
                format!(
                    "expected 9 fields ({}) or 10 (with species), found {}",
                    names.join(" "),
                    f.len()
                ),
            ));
        }
        let species = match f.get(9) {
            None => 0,
            Some(w) => w.parse::<u16>().map_err(|_| {
                err(
                    line,
                    format!("species must be a whole number from 0 to 65535, found '{w}'"),
                )
            })?,
        };
        let mut x = [0.0; 6];
        for c in 0..6 {
            x[c] = number(line, f[c], names[c])?;
        }
        let mut colour = [0u8; 3];
        for c in 0..3 {
            colour[c] = f[6 + c].parse::<u8>().map_err(|_| {
                err(
                    line,
                    format!(
                        "colour {} must be a whole number from 0 to 255, found '{}'",
                        names[6 + c],
                        f[6 + c]
                    ),
                )
            })?;
        }
        let (radius, mass) = (x[ir], x[im]);
        if radius <= 0.0 {
            return Err(err(line, format!("radius must be > 0, found {radius}")));
        }
        if mass <= 0.0 {
            return Err(err(line, format!("mass must be > 0, found {mass}")));
        }
        discs.push(Disc {
            pos: Vector::new([x[0], x[1]]),
            vel: Vector::new([x[2], x[3]]),
            mass,
            radius,
            colour,
            species,
        });
        at.push(line);
    }
    expect_end(&mut lines, n)?;
    let (sim_box, barriers) = directives(&lines.directives)?;
    Ok(LoadedSystem {
        discs,
        sim_box,
        barriers,
        lines: at,
        format: Format::Princeton(order),
    })
}

/// Interprets the `# edmd` directives.
fn directives(list: &[(usize, Vec<&str>)]) -> Result<(SimBox, Vec<Barrier>), ParseError> {
    let mut sim_box = SimBox::unit();
    let mut barriers = Vec::new();
    // The line of the first `box` and `boundary` directive: a second one is refused rather than
    // silently replacing the first.
    let mut seen_box: Option<usize> = None;
    let mut seen_boundary: Option<usize> = None;
    for (line, w) in list {
        let line = *line;
        let once = |seen: &mut Option<usize>, what: &str| match *seen {
            Some(first) => Err(err(
                line,
                format!("a second '# edmd {what}' line (the first is line {first}); give it once"),
            )),
            None => {
                *seen = Some(line);
                Ok(())
            }
        };
        match w.first().copied() {
            Some("box") => {
                once(&mut seen_box, "box")?;
                let l = crate::text::numbers(line, &w[1..], &["LX", "LY"])?;
                if l.iter().any(|&x| x <= 0.0) {
                    return Err(err(line, "box lengths must be > 0"));
                }
                sim_box.lengths = [l[0], l[1]];
            }
            Some("boundary") => {
                once(&mut seen_boundary, "boundary")?;
                let kind = |s: &str| match s {
                    "walls" => Ok(Boundary::Walls),
                    "periodic" => Ok(Boundary::Periodic),
                    _ => Err(err(
                        line,
                        format!("boundary must be 'walls' or 'periodic', found '{s}'"),
                    )),
                };
                match &w[1..] {
                    [b] => sim_box.boundaries = [kind(b)?; 2],
                    [x, y] => sim_box.boundaries = [kind(x)?, kind(y)?],
                    _ => return Err(err(line, "expected 'boundary X [Y]'")),
                }
            }
            Some("barrier") => barriers.push(barrier(line, &w[1..])?),
            Some(other) => {
                return Err(err(
                    line,
                    format!("unknown edmd directive '{other}' (box, boundary, barrier)"),
                ))
            }
            None => return Err(err(line, "empty edmd directive")),
        }
    }
    Ok((sim_box, barriers))
}

/// `AXIS POSITION [door LO HI [demon FAST SLOW]]`.
fn barrier(line: usize, w: &[&str]) -> Result<Barrier, ParseError> {
    let usage = "expected 'barrier x|y POSITION [door LO HI [demon FAST SLOW]]'";
    let axis = match w.first().copied() {
        Some("x") => 0,
        Some("y") => 1,
        _ => return Err(err(line, usage)),
    };
    let position = number(
        line,
        w.get(1).ok_or_else(|| err(line, usage))?,
        "barrier position",
    )?;
    let mut b = Barrier::solid(axis, position);
    match w.get(2..).unwrap_or(&[]) {
        [] => {}
        ["door", lo, hi, rest @ ..] => {
            b.door = Some((number(line, lo, "door LO")?, number(line, hi, "door HI")?));
            match rest {
                [] => {}
                ["demon", fast, slow] => {
                    b.demon = Some(Demon {
                        fast: number(line, fast, "demon FAST")?,
                        slow: number(line, slow, "demon SLOW")?,
                    })
                }
                _ => return Err(err(line, usage)),
            }
        }
        _ => return Err(err(line, usage)),
    }
    Ok(b)
}

/// Writes discs in the Princeton format, numbers in their shortest exact form. Directives are
/// written only when the box, boundaries or barriers differ from the plain format's, and the
/// species column only when some species is not 0, so plain systems give plain files.
pub fn write(
    out: &mut impl std::io::Write,
    discs: &[Disc],
    sim_box: &SimBox,
    barriers: &[Barrier],
    order: ColumnOrder,
) -> std::io::Result<()> {
    writeln!(out, "{}", discs.len())?;
    if sim_box.lengths != [1.0, 1.0] {
        writeln!(
            out,
            "# edmd box {} {}",
            exact(sim_box.lengths[0]),
            exact(sim_box.lengths[1])
        )?;
    }
    if sim_box.boundaries != [Boundary::Walls; 2] {
        let name = |b: Boundary| {
            if b == Boundary::Walls {
                "walls"
            } else {
                "periodic"
            }
        };
        writeln!(
            out,
            "# edmd boundary {} {}",
            name(sim_box.boundaries[0]),
            name(sim_box.boundaries[1])
        )?;
    }
    for b in barriers {
        write!(
            out,
            "# edmd barrier {} {}",
            ["x", "y"][b.axis],
            exact(b.position)
        )?;
        if let Some((lo, hi)) = b.door {
            write!(out, " door {} {}", exact(lo), exact(hi))?;
            if let Some(d) = b.demon {
                write!(out, " demon {} {}", exact(d.fast), exact(d.slow))?;
            }
        }
        writeln!(out)?;
    }
    let with_species = discs.iter().any(|d| d.species != 0);
    for d in discs {
        let (a, b) = match order {
            ColumnOrder::RadiusMass => (d.radius, d.mass),
            ColumnOrder::MassRadius => (d.mass, d.radius),
        };
        write!(
            out,
            "{} {} {} {} {} {} {} {} {}",
            exact(d.pos[0]),
            exact(d.pos[1]),
            exact(d.vel[0]),
            exact(d.vel[1]),
            exact(a),
            exact(b),
            d.colour[0],
            d.colour[1],
            d.colour[2]
        )?;
        if with_species {
            write!(out, " {}", d.species)?;
        }
        writeln!(out)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO: &str = "2\n .1 .3 .01 0 .05 1 50 50 50\n.5 .3 -.01 0 .01 .0004 255 0 0\n\n";

    #[test]
    fn reads_radius_before_mass_by_default() {
        let s = parse(TWO, ColumnOrder::RadiusMass).unwrap();
        assert_eq!(s.discs[1].radius, 0.01);
        assert_eq!(s.discs[1].mass, 0.0004);
        assert_eq!(s.discs[1].colour, [255, 0, 0]);
        let s = parse(TWO, ColumnOrder::MassRadius).unwrap();
        assert_eq!(s.discs[1].radius, 0.0004);
        assert_eq!(s.discs[1].mass, 0.01);
    }

    #[test]
    fn round_trips_exactly() {
        let s = parse(TWO, ColumnOrder::MassRadius).unwrap();
        let mut out = Vec::new();
        write(
            &mut out,
            &s.discs,
            &s.sim_box,
            &s.barriers,
            ColumnOrder::MassRadius,
        )
        .unwrap();
        assert_eq!(
            parse(std::str::from_utf8(&out).unwrap(), ColumnOrder::MassRadius)
                .unwrap()
                .discs,
            s.discs
        );
    }

    #[test]
    fn extension_round_trips_and_plain_files_stay_plain() {
        let text = "# a comment\n2\n# edmd box 20 10\n# edmd boundary periodic walls\n# edmd barrier x 10 door 4 6 demon 1.5 0.5\n# edmd barrier y 5\n1 1 0 0 0.5 1 0 0 255 1\n3 3 0 0 0.5 1 0 255 0 0\n# trailing\n";
        let s = parse(text, ColumnOrder::default()).unwrap();
        assert_eq!(s.sim_box.lengths, [20.0, 10.0]);
        assert_eq!(s.sim_box.boundaries, [Boundary::Periodic, Boundary::Walls]);
        assert_eq!(s.barriers.len(), 2);
        assert_eq!(s.barriers[0].door, Some((4.0, 6.0)));
        assert_eq!(
            s.barriers[0].demon,
            Some(Demon {
                fast: 1.5,
                slow: 0.5
            })
        );
        assert_eq!(s.barriers[1], Barrier::solid(1, 5.0));
        assert_eq!((s.discs[0].species, s.discs[1].species), (1, 0));
        assert_eq!(s.lines, vec![7, 8]);
        let mut out = Vec::new();
        write(
            &mut out,
            &s.discs,
            &s.sim_box,
            &s.barriers,
            ColumnOrder::default(),
        )
        .unwrap();
        let back = parse(std::str::from_utf8(&out).unwrap(), ColumnOrder::default()).unwrap();
        assert_eq!(
            (&back.discs, back.sim_box, &back.barriers),
            (&s.discs, s.sim_box, &s.barriers)
        );
        // A plain system is written without directives or species.
        let plain = parse(TWO, ColumnOrder::default()).unwrap();
        let mut out = Vec::new();
        write(
            &mut out,
            &plain.discs,
            &plain.sim_box,
            &plain.barriers,
            ColumnOrder::default(),
        )
        .unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(!text.contains('#'));
        assert_eq!(text.lines().nth(1).unwrap().split_whitespace().count(), 9);
    }

    #[test]
    fn bad_directives_name_their_line() {
        let cases: &[(&str, usize, &str)] = &[
            ("0\n# edmd box 1\n", 2, "expected 2 numbers"),
            ("0\n# edmd box 1 -1\n", 2, "must be > 0"),
            ("0\n# edmd boundary round\n", 2, "'walls' or 'periodic'"),
            (
                "0\n# edmd box 2 2\n# edmd box 3 3\n",
                3,
                "a second '# edmd box' line (the first is line 2)",
            ),
            (
                "0\n# edmd boundary walls\n# edmd boundary periodic\n",
                3,
                "a second '# edmd boundary' line",
            ),
            ("0\n# edmd barrier z 1\n", 2, "expected 'barrier"),
            ("0\n# edmd barrier x 0.5 door 1\n", 2, "expected 'barrier"),
            ("0\n# edmd teleport\n", 2, "unknown edmd directive"),
            ("1\n.5 .5 0 0 .1 1 1 1 1 -3\n", 2, "species"),
        ];
        for (text, line, what) in cases {
            let e = parse(text, ColumnOrder::default()).unwrap_err();
            assert_eq!(e.line, *line, "{text:?}: {e}");
            assert!(e.message.contains(what), "{text:?}: {e}");
        }
    }

    #[test]
    fn malformations_name_their_line() {
        let cases: &[(&str, usize, &str)] = &[
            ("1\n.1 .3 .01 0 .05 1 50 50\n", 2, "expected 9 fields"),
            ("1\n.1 .3 .01 0 .05 1 50 50 256\n", 2, "colour b"),
            ("1\n.1 .3 .01 0 .05 1 50 x 1\n", 2, "colour g"),
            ("1\n.1 .3 .01 0 -1 1 50 50 50\n", 2, "radius must be > 0"),
            ("1\n.1 .3 .01 0 .05 0 50 50 50\n", 2, "mass must be > 0"),
            ("1\n.1 .3 .01 zz .05 1 50 50 50\n", 2, "vy is not a number"),
            (
                "3\n.1 .3 .01 0 .05 1 50 50 50\n",
                2,
                "file ends before disc 2 of 3",
            ),
        ];
        for (text, line, what) in cases {
            let e = parse(text, ColumnOrder::default()).unwrap_err();
            assert_eq!(e.line, *line, "{text:?}: {e}");
            assert!(e.message.contains(what), "{text:?}: {e}");
        }
    }
}
