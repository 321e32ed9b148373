//! The Princeton CollisionSystem format.
//!
//! ```text
//! N
//! rx ry vx vy radius mass r g b     (N lines; r g b integers 0..=255)
//! ```
//! The box is the unit square with walls. The 25 published data files put the radius before the
//! mass (`p10.txt`: `... 0.02 10 ...`), while the assignment's prose lists mass first; the files'
//! order is the default ([`ColumnOrder::RadiusMass`]).

use edmd_core::{Disc, SimBox, Vector};

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
        if f.len() != 9 {
            return Err(err(
                line,
                format!("expected 9 fields ({}), found {}", names.join(" "), f.len()),
            ));
        }
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
            species: 0,
        });
        at.push(line);
    }
    expect_end(&mut lines, n)?;
    Ok(LoadedSystem {
        discs,
        sim_box: SimBox::unit(),
        lines: at,
        format: Format::Princeton(order),
    })
}

/// Writes discs in the Princeton format, numbers in their shortest exact form.
pub fn write(
    out: &mut impl std::io::Write,
    discs: &[Disc],
    order: ColumnOrder,
) -> std::io::Result<()> {
    writeln!(out, "{}", discs.len())?;
    for d in discs {
        let (a, b) = match order {
            ColumnOrder::RadiusMass => (d.radius, d.mass),
            ColumnOrder::MassRadius => (d.mass, d.radius),
        };
        writeln!(
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
        write(&mut out, &s.discs, ColumnOrder::MassRadius).unwrap();
        assert_eq!(
            parse(std::str::from_utf8(&out).unwrap(), ColumnOrder::MassRadius)
                .unwrap()
                .discs,
            s.discs
        );
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
