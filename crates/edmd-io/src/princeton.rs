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
//!   - `# edmd time T`: the time the state is at (default 0). `edmd run` writes it into the
//!     states it writes and starts its clock there, so that chained runs keep the true time;
//!   - `# edmd potential A B R1 E1 [R2 E2 ...]`: a stepped pair potential between species `A`
//!     and `B` (see `edmd_core::Potential`): outside the hard core (the sum of the radii), steps
//!     at distances `R1 < R2 < ...`, where the pair's energy changes by `Ek` as it moves inward
//!     across `Rk` (`# edmd potential 0 0 1.5 -1` is a square well of depth 1 out to 1.5, `1.5
//!     1` a shoulder of height 1); one line per pair of species;
//!   - `# edmd restitution ...`: inelastic collisions (see `edmd_core::Restitution` and
//!     [`crate::restitution`] for the grammar): `E` or `bridges VC` for every pair of species,
//!     `A B E` or `A B bridges VC` for one pair, `walls E` for the walls, `tc T` for the TC
//!     model's time; one line for each, and they do not go with a stepped potential or
//!     reaction rules;
//!   - `# edmd gravity AXIS G`: a uniform field (see `edmd_core::Gravity`): every disc
//!     accelerated at `G` along axis `x`, `y` (or `z` in 3D), negative towards 0; the axis
//!     must have walls; at most once, and not with a stepped potential or barriers;
//!   - `# edmd shear RATE [OFFSET]`: Lees-Edwards boundaries (see `edmd_core::Shear`): the
//!     images across y slide along x at `RATE * LY` relative to the box, those above shifted by
//!     `OFFSET` (in `[0, LX)`, default 0) at the file's time, so that the streaming velocity
//!     is `RATE (y - LY / 2)` along x. The velocities are the lab's, the profile included. x
//!     and y must be periodic; at most once, and not with a stepped potential, a field or
//!     barriers. `edmd run` writes the offset it reached, so a written state continues the
//!     same flow;
//!   - `# edmd ring OMEGA [OFFSET]`: a patch of a planetary ring (see `edmd_core::Ring`):
//!     particles fly under Hill's equations at the orbital frequency `OMEGA` (x along the
//!     orbit, y radial, z vertical, about the box's centre), with Lees-Edwards boundaries at
//!     the Keplerian shear rate `-3/2 OMEGA`, the images above shifted by `OFFSET` (in
//!     `[0, LX)`, default 0) at the file's time. The velocities are the lab's, the Keplerian
//!     flow `-3/2 OMEGA (y - LY / 2)` along x included. x and y must be periodic and, in 3D, z
//!     must have walls (`# edmd boundary periodic periodic walls`); 2D and 3D files only, at
//!     most once, and not with `# edmd shear` (the ring sets its own), a field, a stepped
//!     potential or barriers; a constant restitution below 1 needs the TC model beside it
//!     (`# edmd restitution tc T`), lest a cold patch collapse. `edmd run` writes the offset
//!     it reached;
//!   - `# edmd self-gravity C`: one-dimensional self-gravity of strength `C` (see
//!     `edmd_core::SelfGravity`): each rod is accelerated by `C` times the mass on its right
//!     less the mass on its left, as parallel sheets of mass are (`C` is `2 pi G` per unit
//!     area). 1D files only, `C` a finite number above 0, the line with walls, at most once,
//!     and not with a field, a stepped potential, reaction rules or restitution;
//!   - `# edmd reaction A + B -> C + D [activation E] [probability P] [heat Q]`: a reaction
//!     rule (see `edmd_core::Reaction` and [`crate::reaction`] for the grammar): a disc of
//!     species `A` colliding with one of `B` with at least `E` of kinetic energy in their
//!     relative motion along the line of centres (default 0) becomes `C` and the other `D`,
//!     with probability `P` (default 1), and `Q` is released into their normal relative motion
//!     (default 0); one line per rule, at most one rule per pair of species (`A + B` and
//!     `B + A` are one pair). Every reactant must be a species some disc has or some rule
//!     makes, and rules do not go with a stepped potential. The draws' seed is not in the file:
//!     it is a run's (`edmd run --seed`), as the thermostat's is;
//! - an optional tenth column on any disc line: the species, a whole number (default 0);
//! - `# edmd dim 3` (before the first disc line): a 3D file of spheres. Disc lines are then
//!   `rx ry rz vx vy vz radius mass r g b [species]` (mass before radius with
//!   [`ColumnOrder::MassRadius`]), the box defaults to the unit cube with walls,
//!   `# edmd box LX LY LZ` takes three lengths and `# edmd boundary` one word or three;
//!   barriers are 2D only. `# edmd dim 2` is allowed and changes nothing.
//! - `# edmd dim 1` (before the first disc line): a 1D file of hard rods on a line, each line
//!   `rx vx radius mass r g b [species]` (a rod's length is twice its radius; mass before
//!   radius with [`ColumnOrder::MassRadius`]), the line `[0, 1]` with walls by default,
//!   `# edmd box L` and `# edmd boundary walls|periodic` with one value; no barriers, shear or
//!   field across a missing axis (a field along `x` is allowed).

use edmd_core::{
    Barrier, Boundary, Demon, Disc, Gravity, PairSteps, Potential, Reaction, Restitution, Ring,
    SelfGravity, Shear, SimBox, Step, Vector,
};

use crate::text::{count, err, exact, expect_end, number, Lines};
use crate::{Format, Interactions, LoadedSystem, ParseError};

/// Order of the radius and mass columns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColumnOrder {
    /// `... radius mass r g b`, as in the published data files.
    #[default]
    RadiusMass,
    /// `... mass radius r g b`, as in the assignment's prose.
    MassRadius,
}

/// Reads the Princeton format: a 2D file (a file with `# edmd dim 3` is refused with a line
/// saying so; read it with [`parse_in`]`::<3>` or [`crate::parse_any`]).
pub fn parse(text: &str, order: ColumnOrder) -> Result<LoadedSystem, ParseError> {
    parse_in::<2>(text, order)
}

/// The dimension a Princeton file declares: 1 or 3 with a `# edmd dim 1` or `# edmd dim 3`
/// directive, else 2. The
/// directive must come before the first disc line, at most once.
pub fn declared_dim(text: &str) -> Result<usize, ParseError> {
    let mut lines = Lines::new(text);
    let mut data_lines = 0;
    let mut seen = 0;
    loop {
        let before = lines.directives.len();
        let next = lines.next_fields();
        for (line, w) in &lines.directives[before..] {
            if w.first() != Some(&"dim") {
                continue;
            }
            if data_lines >= 2 {
                return Err(err(
                    *line,
                    "'# edmd dim' must come before the first disc line",
                ));
            }
            if seen > 0 {
                return Err(err(
                    *line,
                    format!("a second '# edmd dim' line (the first is line {seen}); give it once"),
                ));
            }
            seen = *line;
        }
        if next.is_none() || data_lines >= 2 {
            break;
        }
        data_lines += 1;
    }
    let Some((line, w)) = lines
        .directives
        .iter()
        .find(|(_, w)| w.first() == Some(&"dim"))
    else {
        return Ok(2);
    };
    match &w[1..] {
        ["1"] => Ok(1),
        ["2"] => Ok(2),
        ["3"] => Ok(3),
        _ => Err(err(
            *line,
            format!(
                "expected '# edmd dim 1', '# edmd dim 2' or '# edmd dim 3', found '# edmd {}'",
                w.join(" ")
            ),
        )),
    }
}

/// Reads a Princeton file of dimension `D` (1, 2 or 3): `rx ry [rz] vx vy [vz] radius mass r g
/// b [species]` per disc, `rx vx radius mass r g b [species]` per rod (see the module doc). A file that declares another dimension is an
/// error at its `dim` directive (or at line 1 for a 2D file read as 3D).
pub fn parse_in<const D: usize>(
    text: &str,
    order: ColumnOrder,
) -> Result<LoadedSystem<D>, ParseError> {
    let declared = declared_dim(text)?;
    if declared != D {
        let line = dim_line(text).unwrap_or(1);
        return Err(err(
            line,
            if declared != 2 {
                format!("this is a {declared}D file ('# edmd dim {declared}'); this reader takes {D}D files")
            } else {
                format!("this is a 2D file (no '# edmd dim 3' line); a {D}D file was expected")
            },
        ));
    }
    let mut lines = Lines::new(text);
    let n = count(&mut lines)?;
    let (ir, im) = match order {
        ColumnOrder::RadiusMass => (2 * D, 2 * D + 1),
        ColumnOrder::MassRadius => (2 * D + 1, 2 * D),
    };
    let mut names: Vec<&str> = if D == 1 {
        vec!["rx", "vx", "", "", "r", "g", "b"]
    } else if D == 3 {
        vec!["rx", "ry", "rz", "vx", "vy", "vz", "", "", "r", "g", "b"]
    } else {
        vec!["rx", "ry", "vx", "vy", "", "", "r", "g", "b"]
    };
    names[ir] = "radius";
    names[im] = "mass";
    let columns = names.len();
    let mut discs = Vec::with_capacity(n.min(1 << 24));
    let mut at = Vec::with_capacity(n.min(1 << 24));
    for k in 0..n {
        let (line, f) = lines.expect_fields(&format!("disc {} of {n}", k + 1))?;
        if f.len() != columns && f.len() != columns + 1 {
            // The other dimension's line: say how a file declares it (the directive may be
            // missing, misspelt, in capitals or after the discs).
            let hint = match (D, f.len()) {
                (1 | 2, 11 | 12) => {
                    " (a sphere's line: a 3D file says '# edmd dim 3' before its discs)"
                }
                (2 | 3, 7 | 8) => " (a rod's line: a 1D file says '# edmd dim 1' before its rods)",
                (1, 9 | 10) => " (a disc's line: a 2D file has no '# edmd dim' line)",
                (3, 9 | 10) => " (a disc's line: a 2D file has no '# edmd dim 3')",
                _ => "",
            };
            return Err(err(
                line,
                format!(
                    "expected {columns} fields ({}) or {} (with species), found {}{hint}",
                    names.join(" "),
                    columns + 1,
                    f.len()
                ),
            ));
        }
        let species = match f.get(columns) {
            None => 0,
            Some(w) => w.parse::<u16>().map_err(|_| {
                err(
                    line,
                    format!("species must be a whole number from 0 to 65535, found '{w}'"),
                )
            })?,
        };
        let mut x = [0.0; 8];
        for c in 0..2 * D + 2 {
            x[c] = number(line, f[c], names[c])?;
        }
        let mut colour = [0u8; 3];
        for c in 0..3 {
            let w = f[2 * D + 2 + c];
            colour[c] = w.parse::<u8>().map_err(|_| {
                err(
                    line,
                    format!(
                        "colour {} must be a whole number from 0 to 255, found '{w}'",
                        names[2 * D + 2 + c],
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
            pos: Vector(std::array::from_fn(|a| x[a])),
            vel: Vector(std::array::from_fn(|a| x[D + a])),
            mass,
            radius,
            colour,
            species,
        });
        at.push(line);
    }
    expect_end(&mut lines, n)?;
    let d = directives::<D>(&lines.directives)?;
    check_potential(&d.potential, &discs)?;
    // The engine keeps a potential's tables per pair of the species present, so a disc's
    // species bounds them as the directive's do.
    if let Some((first, _)) = d.potential.first() {
        let most = edmd_core::state::MAX_POTENTIAL_SPECIES;
        if let Some(k) = discs.iter().position(|x| x.species >= most) {
            return Err(err(
                at[k],
                format!(
                    "species {}: with a stepped potential (line {first}) species go from 0 to {}",
                    discs[k].species,
                    most - 1
                ),
            ));
        }
    }
    check_reactions(&d.reactions, &d.potential, &discs, d.time)?;
    check_shear(&d)?;
    check_ring(&d)?;
    check_self_gravity(&d)?;
    if let Some((line, f)) = d.gravity {
        if d.sim_box.is_periodic(f.axis) {
            return Err(err(
                line,
                format!(
                    "gravity: the field's axis {} must have walls (along a periodic axis a disc would fall for ever)",
                    ["x", "y", "z"][f.axis]
                ),
            ));
        }
        if let Some((first, _)) = d.potential.first() {
            return Err(err(
                line,
                format!("gravity does not go with a stepped potential (line {first})"),
            ));
        }
        if !d.barriers.is_empty() {
            return Err(err(line, "gravity does not go with barriers"));
        }
        if let Some((_, r)) = &d.restitution {
            if !r.is_elastic() && r.tc <= 0.0 {
                return Err(err(
                    line,
                    "gravity with inelastic collisions needs the TC model ('# edmd restitution tc T', T > 0): grains coming to rest on the floor would otherwise collide infinitely often in a finite time",
                ));
            }
            if r.wall == 0.0 {
                return Err(err(
                    line,
                    "gravity needs the walls' restitution above 0: a disc stopped dead at the floor would meet it again at once",
                ));
            }
        }
    }
    if let Some((line, _)) = d.restitution {
        let other = match (d.potential.first(), d.reactions.first()) {
            (Some((first, _)), _) => Some(("a stepped potential", first)),
            (_, Some((first, _))) => Some(("reaction rules", first)),
            _ => None,
        };
        if let Some((what, first)) = other {
            return Err(err(
                line,
                format!("restitution does not go with {what} (line {first})"),
            ));
        }
    }
    Ok(LoadedSystem {
        discs,
        sim_box: d.sim_box,
        barriers: d.barriers,
        lines: at,
        format: Format::Princeton(order),
        time: d.time,
        potential: Potential {
            pairs: d.potential.into_iter().map(|(_, p)| p).collect(),
        },
        reactions: d.reactions.into_iter().map(|(_, r)| r).collect(),
        restitution: d.restitution.map(|(_, r)| r),
        gravity: d.gravity.map(|(_, f)| f),
        // A ring's boundaries are a shear at the Keplerian rate, from the file's offset.
        shear: match d.ring {
            Some((_, r, offset)) => Some(Shear {
                rate: r.shear_rate(),
                offset,
            }),
            None => d.shear.map(|(_, s)| s),
        },
        ring: d.ring.map(|(_, r, _)| r),
        self_gravity: d.self_gravity.map(|(_, g)| g),
    })
}

/// Refuses `# edmd self-gravity` outside a 1D file, on a periodic line and beside what the
/// engine's sheets do not go with (a field, a stepped potential, reaction rules,
/// restitution), and a coupling that is not a finite number above 0.
fn check_self_gravity<const D: usize>(d: &Directives<D>) -> Result<(), ParseError> {
    let Some((line, g)) = d.self_gravity else {
        return Ok(());
    };
    if D != 1 {
        return Err(err(
            line,
            format!("self-gravity: sheets live on a line, in a 1D file ('# edmd dim 1'), not in this {D}D file"),
        ));
    }
    let other = [
        ("a field", d.gravity.map(|(l, _)| l)),
        ("a stepped potential", d.potential.first().map(|(l, _)| *l)),
        ("reaction rules", d.reactions.first().map(|(l, _)| *l)),
        ("restitution", d.restitution.as_ref().map(|(l, _)| *l)),
    ];
    if let Some((what, Some(first))) = other.iter().find(|(_, l)| l.is_some()) {
        return Err(err(
            line,
            format!("self-gravity does not go with {what} (line {first})"),
        ));
    }
    if d.sim_box.is_periodic(0) {
        return Err(err(
            line,
            "self-gravity: the line must have walls (a periodic line has no mass on either side to pull towards)",
        ));
    }
    g.validate(D).map_err(|e| err(line, e.to_string()))
}

/// Refuses `# edmd ring` in a 1D file and beside what a ring patch does not go with: its own
/// shear's line, a field, a stepped potential, barriers, x or y not periodic, z not walled
/// (3D), a frequency that is not a finite number above 0 and an offset outside `[0, LX)`.
fn check_ring<const D: usize>(d: &Directives<D>) -> Result<(), ParseError> {
    let Some((line, ring, offset)) = d.ring else {
        return Ok(());
    };
    if D < 2 {
        return Err(err(
            line,
            "ring: a ring patch has a radial (y) axis, and a 1D file has none",
        ));
    }
    if let Some((first, _)) = d.shear {
        return Err(err(
            line,
            format!("ring does not go with '# edmd shear' (line {first}): the ring shears the patch at -3/2 OMEGA itself"),
        ));
    }
    if let Some((first, _)) = d.gravity {
        return Err(err(
            line,
            format!(
                "ring does not go with gravity (line {first}): the ring has its own vertical pull"
            ),
        ));
    }
    if let Some((first, _)) = d.potential.first() {
        return Err(err(
            line,
            format!("ring does not go with a stepped potential (line {first})"),
        ));
    }
    if !d.barriers.is_empty() {
        return Err(err(line, "ring does not go with barriers"));
    }
    if !(d.sim_box.is_periodic(0) && d.sim_box.is_periodic(1)) {
        let hint = if D == 3 {
            "'# edmd boundary periodic periodic walls'"
        } else {
            "'# edmd boundary periodic'"
        };
        return Err(err(
            line,
            format!("ring: a ring patch needs periodic x and y axes ({hint})"),
        ));
    }
    if D == 3 && d.sim_box.is_periodic(2) {
        return Err(err(
            line,
            "ring: a ring patch needs walls along z ('# edmd boundary periodic periodic walls')",
        ));
    }
    if let Some((first, r)) = &d.restitution {
        if crate::restitution::collapses_without_tc(r) {
            return Err(err(
                line,
                format!("ring with a constant restitution below 1 (line {first}) needs the TC model ('# edmd restitution tc T', T > 0; 'tc 0.001' for OMEGA 1), or a cold dense patch collapses; Bridges' law needs none"),
            ));
        }
    }
    ring.validate(D).map_err(|e| err(line, e.to_string()))?;
    let lx = d.sim_box.lengths[0];
    if !(0.0..lx).contains(&offset) {
        return Err(err(
            line,
            format!("ring: the offset must be in [0, L_x) = [0, {lx}), found {offset}"),
        ));
    }
    Ok(())
}

/// Refuses `# edmd shear` beside what Lees-Edwards boundaries do not go with: a field, a
/// stepped potential, barriers, walls on x or y, and an offset outside `[0, LX)`.
fn check_shear<const D: usize>(d: &Directives<D>) -> Result<(), ParseError> {
    let Some((line, s)) = d.shear else {
        return Ok(());
    };
    if D < 2 {
        return Err(err(
            line,
            "shear: Lees-Edwards boundaries slide the images across y, and a 1D file has no y axis",
        ));
    }
    if let Some((first, _)) = d.gravity {
        return Err(err(
            line,
            format!("shear does not go with gravity (line {first})"),
        ));
    }
    if let Some((first, _)) = d.potential.first() {
        return Err(err(
            line,
            format!("shear does not go with a stepped potential (line {first})"),
        ));
    }
    if !d.barriers.is_empty() {
        return Err(err(line, "shear does not go with barriers"));
    }
    if !(d.sim_box.is_periodic(0) && d.sim_box.is_periodic(1)) {
        return Err(err(
            line,
            "shear: Lees-Edwards boundaries need periodic x and y axes ('# edmd boundary periodic')",
        ));
    }
    s.validate(D, d.sim_box.lengths[0])
        .map_err(|e| err(line, e.to_string()))
}

/// The line of the first `# edmd dim` directive, if any.
fn dim_line(text: &str) -> Option<usize> {
    let mut lines = Lines::new(text);
    while lines.next_fields().is_some() {}
    lines
        .directives
        .iter()
        .find(|(_, w)| w.first() == Some(&"dim"))
        .map(|(l, _)| *l)
}

/// What the `# edmd` directives say, the potential's pairs and the rules with their lines.
struct Directives<const D: usize> {
    sim_box: SimBox<D>,
    barriers: Vec<Barrier>,
    time: f64,
    potential: Vec<(usize, PairSteps)>,
    reactions: Vec<(usize, Reaction)>,
    /// The restitution, with the line of its first directive.
    restitution: Option<(usize, Restitution)>,
    /// The field, with its line.
    gravity: Option<(usize, Gravity)>,
    /// The shear, with its line.
    shear: Option<(usize, Shear)>,
    /// The ring and its images' offset, with its line.
    ring: Option<(usize, Ring, f64)>,
    /// The self-gravity, with its line.
    self_gravity: Option<(usize, SelfGravity)>,
}

/// Interprets the `# edmd` directives.
fn directives<const D: usize>(list: &[(usize, Vec<&str>)]) -> Result<Directives<D>, ParseError> {
    let mut sim_box = SimBox::<D>::walls([1.0; D]);
    let mut potential: Vec<(usize, PairSteps)> = Vec::new();
    let mut reactions: Vec<(usize, Reaction)> = Vec::new();
    let mut restitution: Option<(usize, Restitution)> = None;
    let mut gravity: Option<(usize, Gravity)> = None;
    let mut seen_gravity: Option<usize> = None;
    let mut shear: Option<(usize, Shear)> = None;
    let mut seen_shear: Option<usize> = None;
    let mut ring: Option<(usize, Ring, f64)> = None;
    let mut seen_ring: Option<usize> = None;
    let mut self_gravity: Option<(usize, SelfGravity)> = None;
    let mut seen_self_gravity: Option<usize> = None;
    let mut parts: Vec<(usize, crate::restitution::Part)> = Vec::new();
    let mut barriers = Vec::new();
    let mut time = 0.0;
    let mut seen_time: Option<usize> = None;
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
                let l = crate::text::numbers(line, &w[1..], &["LX", "LY", "LZ"][..D])?;
                if l.iter().any(|&x| x <= 0.0) {
                    return Err(err(line, "box lengths must be > 0"));
                }
                sim_box.lengths = std::array::from_fn(|a| l[a]);
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
                    [b] => sim_box.boundaries = [kind(b)?; D],
                    each if each.len() == D => {
                        for a in 0..D {
                            sim_box.boundaries[a] = kind(each[a])?;
                        }
                    }
                    _ if D == 3 => return Err(err(line, "expected 'boundary X [Y Z]'")),
                    _ if D == 1 => return Err(err(line, "expected 'boundary X' (one axis in a 1D file)")),
                    _ => return Err(err(line, "expected 'boundary X [Y]'")),
                }
            }
            Some("time") => {
                once(&mut seen_time, "time")?;
                time = crate::text::numbers(line, &w[1..], &["T"])?[0];
                if time < 0.0 {
                    return Err(err(line, "the time must be >= 0"));
                }
            }
            Some("potential") => {
                let pair = pair_steps(line, &w[1..])?;
                if let Some((first, _)) = potential.iter().find(|(_, q)| {
                    q.species == pair.species || q.species == (pair.species.1, pair.species.0)
                }) {
                    return Err(err(
                        line,
                        format!(
                            "a second potential for species {} {} (the first is line {first}); give each pair once",
                            pair.species.0, pair.species.1
                        ),
                    ));
                }
                potential.push((line, pair));
            }
            Some("reaction") => {
                let r = crate::reaction::parse(&w[1..])
                    .map_err(|e| err(line, format!("reaction: {e}")))?;
                let (a, b) = r.reactants;
                if let Some((first, _)) = reactions
                    .iter()
                    .find(|(_, q)| q.reactants == (a, b) || q.reactants == (b, a))
                {
                    return Err(err(
                        line,
                        format!(
                            "a second reaction rule for species {a} and {b} (the first is line {first}); give each pair one rule"
                        ),
                    ));
                }
                reactions.push((line, r));
            }
            Some("gravity") => {
                once(&mut seen_gravity, "gravity")?;
                let usage = if D == 3 {
                    "expected 'gravity x|y|z G'"
                } else if D == 1 {
                    "expected 'gravity x G' (a 1D file has the x axis alone)"
                } else {
                    "expected 'gravity x|y G'"
                };
                let [axis, g] = &w[1..] else {
                    return Err(err(line, usage));
                };
                let axis = match *axis {
                    "x" => 0,
                    "y" if D >= 2 => 1,
                    "z" if D == 3 => 2,
                    _ => return Err(err(line, usage)),
                };
                let f = Gravity {
                    axis,
                    g: number(line, g, "G")?,
                };
                f.validate(D).map_err(|e| err(line, e.to_string()))?;
                gravity = Some((line, f));
            }
            Some("shear") => {
                once(&mut seen_shear, "shear")?;
                let (rate, offset) = match &w[1..] {
                    [rate] => (number(line, rate, "RATE")?, 0.0),
                    [rate, offset] => (number(line, rate, "RATE")?, number(line, offset, "OFFSET")?),
                    _ => return Err(err(line, "expected 'shear RATE [OFFSET]'")),
                };
                shear = Some((line, Shear { rate, offset }));
            }
            Some("ring") => {
                once(&mut seen_ring, "ring")?;
                let (omega, offset) = match &w[1..] {
                    [omega] => (number(line, omega, "OMEGA")?, 0.0),
                    [omega, offset] => (
                        number(line, omega, "OMEGA")?,
                        number(line, offset, "OFFSET")?,
                    ),
                    _ => return Err(err(line, "expected 'ring OMEGA [OFFSET]'")),
                };
                ring = Some((line, Ring { omega }, offset));
            }
            Some("self-gravity") => {
                once(&mut seen_self_gravity, "self-gravity")?;
                let [c] = &w[1..] else {
                    return Err(err(line, "expected 'self-gravity C'"));
                };
                let coupling = number(line, c, "C")?;
                self_gravity = Some((line, SelfGravity { coupling }));
            }
            Some("restitution") => {
                let (_, r) = restitution.get_or_insert_with(|| (line, Restitution::default()));
                let part = crate::restitution::parse(&w[1..], r)
                    .map_err(|e| err(line, format!("restitution: {e}")))?;
                if let Some((first, _)) = parts.iter().find(|(_, q)| q.same(part)) {
                    return Err(err(
                        line,
                        format!(
                            "a second restitution for {} (the first is line {first}); give it once",
                            part.name()
                        ),
                    ));
                }
                parts.push((line, part));
            }
            Some("barrier") if D != 2 => {
                return Err(err(
                    line,
                    format!("barriers exist in 2D files only, not in this {D}D file"),
                ))
            }
            Some("barrier") => barriers.push(barrier(line, &w[1..])?),
            // Read before the discs by `declared_dim`.
            Some("dim") => {}
            Some(other) => {
                return Err(err(
                    line,
                    format!("unknown edmd directive '{other}' (dim, box, boundary, barrier, time, potential, reaction, restitution, gravity, shear, ring, self-gravity)"),
                ))
            }
            None => return Err(err(line, "empty edmd directive")),
        }
    }
    Ok(Directives {
        sim_box,
        barriers,
        time,
        potential,
        reactions,
        restitution,
        gravity,
        shear,
        ring,
        self_gravity,
    })
}

/// `A B R1 E1 [R2 E2 ...]`: species, then steps in increasing radius.
fn pair_steps(line: usize, w: &[&str]) -> Result<PairSteps, ParseError> {
    let usage = "expected 'potential A B R1 E1 [R2 E2 ...]' (species A and B, then each step's radius and energy)";
    if w.len() < 4 || !w.len().is_multiple_of(2) {
        return Err(err(line, usage));
    }
    let species = |s: &str| {
        s.parse::<u16>()
            .ok()
            .filter(|&k| k < edmd_core::state::MAX_POTENTIAL_SPECIES)
            .ok_or_else(|| {
                err(
                    line,
                    format!(
                        "potential: species must be a whole number from 0 to {}, found '{s}'",
                        edmd_core::state::MAX_POTENTIAL_SPECIES - 1
                    ),
                )
            })
    };
    let (a, b) = (species(w[0])?, species(w[1])?);
    let mut steps = Vec::new();
    for pair in w[2..].chunks(2) {
        steps.push(Step {
            radius: number(line, pair[0], "step radius")?,
            energy: number(line, pair[1], "step energy")?,
        });
    }
    let p = PairSteps {
        species: (a, b),
        steps,
    };
    Potential {
        pairs: vec![p.clone()],
    }
    .validate()
    .map_err(|e| err(line, e.to_string()))?;
    Ok(p)
}

/// Refuses, at its line, a potential naming a species no disc has or a step inside the hard
/// core of discs it applies to.
fn check_potential<const D: usize>(
    potential: &[(usize, PairSteps)],
    discs: &[Disc<D>],
) -> Result<(), ParseError> {
    for (line, p) in potential {
        let largest = |k: u16| {
            discs
                .iter()
                .filter(|d| d.species == k)
                .map(|d| d.radius)
                .fold(None, |m: Option<f64>, r| Some(m.map_or(r, |m| m.max(r))))
        };
        let (a, b) = p.species;
        let (Some(ra), Some(rb)) = (largest(a), largest(b)) else {
            let missing = if largest(a).is_none() { a } else { b };
            return Err(err(
                *line,
                format!("potential: no disc is of species {missing}"),
            ));
        };
        let lightest = discs
            .iter()
            .filter(|d| d.species == a || d.species == b)
            .map(|d| d.mass)
            .fold(f64::INFINITY, f64::min);
        if let Some(why) = edmd_core::state::steps_too_large(&p.steps, lightest) {
            return Err(err(*line, format!("potential: {why}")));
        }
        if let Some(s) = p.steps.first() {
            if s.radius <= ra + rb {
                return Err(err(
                    *line,
                    format!(
                        "potential: the step at {} is inside the hard core (contact distance {} of species {a} and {b})",
                        s.radius,
                        ra + rb
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Refuses, at its line, a rule with a reactant that no disc is and no rule makes in a start
/// (time 0: it could never happen, most likely a mistyped species; a state a run wrote later
/// may have used a reactant up), and rules beside a stepped potential (whose pairs' steps are
/// per species, so a reaction would move a pair to another potential).
fn check_reactions<const D: usize>(
    reactions: &[(usize, Reaction)],
    potential: &[(usize, PairSteps)],
    discs: &[Disc<D>],
    time: f64,
) -> Result<(), ParseError> {
    if let (Some((line, _)), Some((first, _))) = (reactions.first(), potential.first()) {
        return Err(err(
            *line,
            format!(
                "reaction rules do not go with a stepped potential (line {first}): a reaction would change a pair's steps"
            ),
        ));
    }
    let made: Vec<u16> = reactions
        .iter()
        .flat_map(|(_, r)| [r.products.0, r.products.1])
        .collect();
    for (line, r) in reactions.iter().filter(|_| time == 0.0) {
        for s in [r.reactants.0, r.reactants.1] {
            if !made.contains(&s) && !discs.iter().any(|d| d.species == s) {
                return Err(err(
                    *line,
                    format!("reaction: no disc is of species {s} and no rule makes it"),
                ));
            }
        }
    }
    Ok(())
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
/// species column only when some species is not 0, so plain systems give plain files. A 3D
/// (1D) system gets `# edmd dim 3` (`# edmd dim 1`) right after the count.
pub fn write<const D: usize>(
    out: &mut impl std::io::Write,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    barriers: &[Barrier],
    order: ColumnOrder,
    time: f64,
) -> std::io::Result<()> {
    write_with(
        out,
        discs,
        sim_box,
        barriers,
        &Potential::default(),
        order,
        time,
    )
}

/// [`write`] with a stepped potential, written as `# edmd potential` lines.
pub fn write_with<const D: usize>(
    out: &mut impl std::io::Write,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    barriers: &[Barrier],
    potential: &Potential,
    order: ColumnOrder,
    time: f64,
) -> std::io::Result<()> {
    write_full(
        out,
        discs,
        sim_box,
        barriers,
        Interactions {
            potential,
            ..Interactions::HARD
        },
        order,
        time,
    )
}

/// [`write`] with the stepped potential, the reaction rules and the restitution, written as
/// `# edmd potential`, `# edmd reaction` and `# edmd restitution` lines.
pub fn write_full<const D: usize>(
    out: &mut impl std::io::Write,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    barriers: &[Barrier],
    interactions: Interactions,
    order: ColumnOrder,
    time: f64,
) -> std::io::Result<()> {
    write_full_ring(
        out,
        discs,
        sim_box,
        barriers,
        interactions,
        None,
        order,
        time,
    )
}

/// [`write_full`] of a ring patch (`ring`; none: as [`write_full`]): `# edmd ring OMEGA
/// OFFSET`, the offset `interactions.shear`'s (0 without it), in place of the shear's line.
/// `interactions.self_gravity` is written as `# edmd self-gravity C`.
#[allow(clippy::too_many_arguments)]
pub fn write_full_ring<const D: usize>(
    out: &mut impl std::io::Write,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    barriers: &[Barrier],
    interactions: Interactions,
    ring: Option<Ring>,
    order: ColumnOrder,
    time: f64,
) -> std::io::Result<()> {
    let potential = interactions.potential;
    writeln!(out, "{}", discs.len())?;
    if D != 2 {
        writeln!(out, "# edmd dim {D}")?;
    }
    if sim_box.lengths != [1.0; D] {
        write!(out, "# edmd box")?;
        for l in sim_box.lengths {
            write!(out, " {}", exact(l))?;
        }
        writeln!(out)?;
    }
    if sim_box.boundaries != [Boundary::Walls; D] {
        let name = |b: Boundary| {
            if b == Boundary::Walls {
                "walls"
            } else {
                "periodic"
            }
        };
        write!(out, "# edmd boundary")?;
        for b in sim_box.boundaries {
            write!(out, " {}", name(b))?;
        }
        writeln!(out)?;
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
    if time != 0.0 {
        writeln!(out, "# edmd time {}", exact(time))?;
    }
    for p in potential.pairs.iter().filter(|p| !p.steps.is_empty()) {
        write!(out, "# edmd potential {} {}", p.species.0, p.species.1)?;
        for s in &p.steps {
            write!(out, " {} {}", exact(s.radius), exact(s.energy))?;
        }
        writeln!(out)?;
    }
    for r in interactions.reactions {
        writeln!(out, "# edmd reaction {}", crate::reaction::text(r))?;
    }
    if let Some(f) = interactions.gravity {
        writeln!(
            out,
            "# edmd gravity {} {}",
            ["x", "y", "z"][f.axis],
            exact(f.g)
        )?;
    }
    if let Some(r) = ring {
        let offset = interactions.shear.map_or(0.0, |s| s.offset);
        writeln!(out, "# edmd ring {} {}", exact(r.omega), exact(offset))?;
    } else if let Some(s) = interactions.shear {
        writeln!(out, "# edmd shear {} {}", exact(s.rate), exact(s.offset))?;
    }
    if let Some(g) = interactions.self_gravity {
        writeln!(out, "# edmd self-gravity {}", exact(g.coupling))?;
    }
    for l in interactions
        .restitution
        .map(crate::restitution::lines)
        .unwrap_or_default()
    {
        writeln!(out, "# edmd restitution {l}")?;
    }
    let with_species = discs.iter().any(|d| d.species != 0);
    for d in discs {
        let (a, b) = match order {
            ColumnOrder::RadiusMass => (d.radius, d.mass),
            ColumnOrder::MassRadius => (d.mass, d.radius),
        };
        for (k, x) in d.pos.0.iter().chain(&d.vel.0).enumerate() {
            if k > 0 {
                write!(out, " ")?;
            }
            write!(out, "{}", exact(*x))?;
        }
        write!(
            out,
            " {} {} {} {} {}",
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

    /// `# edmd time T` is read and written back, at most once, never negative; the course
    /// format has no place for it.
    #[test]
    fn the_state_carries_its_time() {
        let text =
            "2\n# edmd time 12.5\n .1 .3 .01 0 .05 1 50 50 50\n.5 .3 -.01 0 .01 .0004 255 0 0\n";
        let s = parse(text, ColumnOrder::default()).unwrap();
        assert_eq!(s.time, 12.5);
        assert_eq!(parse(TWO, ColumnOrder::default()).unwrap().time, 0.0);
        let mut out = Vec::new();
        let t = 0.1 + 0.2;
        write(
            &mut out,
            &s.discs,
            &s.sim_box,
            &[],
            ColumnOrder::default(),
            t,
        )
        .unwrap();
        let back = parse(std::str::from_utf8(&out).unwrap(), ColumnOrder::default()).unwrap();
        assert_eq!(back.time, t, "the time is written exactly");
        for (bad, what) in [
            ("# edmd time -1", ">= 0"),
            ("# edmd time 1 2", "expected 1 number (T)"),
            ("# edmd time 1\n# edmd time 2", "a second '# edmd time'"),
            ("# edmd time nan", "T"),
        ] {
            let text = format!("1\n{bad}\n.5 .5 0 0 .1 1 0 0 0\n");
            let e = parse(&text, ColumnOrder::default())
                .unwrap_err()
                .to_string();
            assert!(e.contains(what), "{bad}: {e}");
        }
    }

    /// `# edmd reaction` lines are read in file order, written back exactly (only the options
    /// that differ from their defaults), and a file without them is written without them.
    #[test]
    fn reaction_rules_are_read_and_written_back() {
        let text = "3\n# edmd box 4 4\n# edmd reaction 0 + 1 -> 2 + 2 activation 1.5 probability 0.5\n# edmd reaction 2+2->0+1 heat -0.25\n1 1 0 0 .5 1 0 0 0\n3 1 0 0 .5 1 0 0 0 1\n1 3 0 0 .5 1 0 0 0\n# edmd reaction 1 + 1 -> 1 + 1\n";
        let s = parse(text, ColumnOrder::default()).unwrap();
        let rule = |a, b, c, d, activation, probability, heat| Reaction {
            reactants: (a, b),
            products: (c, d),
            activation,
            probability,
            heat,
        };
        assert_eq!(
            s.reactions,
            vec![
                rule(0, 1, 2, 2, 1.5, 0.5, 0.0),
                rule(2, 2, 0, 1, 0.0, 1.0, -0.25),
                rule(1, 1, 1, 1, 0.0, 1.0, 0.0),
            ]
        );
        let mut out = Vec::new();
        let interactions = Interactions {
            potential: &s.potential,
            reactions: &s.reactions,
            restitution: s.restitution.as_ref(),
            gravity: s.gravity,
            shear: s.shear,
            self_gravity: s.self_gravity,
        };
        write_full(
            &mut out,
            &s.discs,
            &s.sim_box,
            &[],
            interactions,
            ColumnOrder::default(),
            0.0,
        )
        .unwrap();
        let written = String::from_utf8(out).unwrap();
        assert!(
            written.contains("# edmd reaction 0 + 1 -> 2 + 2 activation 1.5 probability 0.5\n# edmd reaction 2 + 2 -> 0 + 1 heat -0.25\n# edmd reaction 1 + 1 -> 1 + 1\n"),
            "{written}"
        );
        let back = parse(&written, ColumnOrder::default()).unwrap();
        assert_eq!(back.reactions, s.reactions);
        assert_eq!(back.discs, s.discs);
        assert!(parse(TWO, ColumnOrder::default())
            .unwrap()
            .reactions
            .is_empty());
        // 3D files take them too.
        let three = "1\n# edmd dim 3\n# edmd reaction 0 + 0 -> 1 + 1\n.5 .5 .5 0 0 0 .1 1 0 0 0\n";
        assert_eq!(
            parse_in::<3>(three, ColumnOrder::default())
                .unwrap()
                .reactions
                .len(),
            1
        );
        // The course format has no place for them.
        let e = crate::write_full(
            &mut Vec::new(),
            &s.discs,
            &s.sim_box,
            &[],
            interactions,
            Format::Course,
            0.0,
        )
        .unwrap_err();
        assert!(e.to_string().contains("reaction rules"), "{e}");
    }

    /// Every refusal names the rule's line and the problem: malformed rules, values out of
    /// range, two rules for one pair (either way round), a reactant nothing is or becomes, and
    /// rules beside a stepped potential.
    #[test]
    fn bad_reaction_rules_name_their_line() {
        let discs = ".5 .5 0 0 .1 1 0 0 0\n.2 .2 0 0 .1 1 0 0 0 1\n";
        let cases: &[(&str, usize, &str)] = &[
            ("# edmd reaction", 2, "reaction: expected 'A + B -> C + D"),
            (
                "# edmd reaction A + B -> C + D",
                2,
                "reaction: expected 'A + B -> C + D",
            ),
            (
                "# edmd reaction 0 + 1 -> 2",
                2,
                "reaction: expected 'A + B -> C + D",
            ),
            (
                "# edmd reaction 0 + 1 -> 2 + 999",
                2,
                "from 0 to 255, found '999'",
            ),
            (
                "# edmd reaction 0 + 1 -> 2 + 2 activation -1",
                2,
                "activation energy must be >= 0",
            ),
            (
                "# edmd reaction 0 + 1 -> 2 + 2 activation inf",
                2,
                "finite number",
            ),
            (
                "# edmd reaction 0 + 1 -> 2 + 2 probability 2",
                2,
                "probability must be in [0, 1]",
            ),
            (
                "# edmd reaction 0 + 1 -> 2 + 2 probability NaN",
                2,
                "finite number",
            ),
            (
                "# edmd reaction 0 + 1 -> 2 + 2 heat nan",
                2,
                "finite number",
            ),
            (
                "# edmd reaction 0 + 1 -> 2 + 2 speed 1",
                2,
                "unknown word 'speed'",
            ),
            (
                "# edmd reaction 0 + 1 -> 2 + 2\n# edmd reaction 1 + 0 -> 3 + 3",
                3,
                "a second reaction rule for species 1 and 0 (the first is line 2)",
            ),
            (
                "# edmd reaction 0 + 7 -> 2 + 2",
                2,
                "no disc is of species 7 and no rule makes it",
            ),
            (
                "# edmd potential 0 0 0.5 -1\n# edmd reaction 0 + 1 -> 2 + 2",
                3,
                "do not go with a stepped potential (line 2)",
            ),
        ];
        for (directives, line, what) in cases {
            let text = format!("2\n{directives}\n{discs}");
            let e = parse(&text, ColumnOrder::default()).unwrap_err();
            assert_eq!(e.line, *line, "{text:?}: {e}");
            assert!(e.message.contains(what), "{text:?}: {e}");
        }
        // A reactant that only a rule makes is fine: 2 + 2 happens once 0 + 1 has made 2s.
        let text =
            format!("2\n# edmd reaction 2 + 2 -> 0 + 1\n# edmd reaction 0 + 1 -> 2 + 2\n{discs}");
        assert_eq!(
            parse(&text, ColumnOrder::default())
                .unwrap()
                .reactions
                .len(),
            2
        );
        // A state written later may have used a reactant up: its rule reads back.
        let text = format!("2\n# edmd time 3.5\n# edmd reaction 0 + 7 -> 2 + 2\n{discs}");
        assert_eq!(parse(&text, ColumnOrder::default()).unwrap().time, 3.5);
    }

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
            0.0,
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
            0.0,
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
            0.0,
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
            // The potential's tables are per pair of species present: a species beyond those
            // a potential can name would make them gigabytes (found by fuzzing checkpoints).
            (
                "2\n# edmd box 10 10\n# edmd potential 0 0 1.5 -1\n2 2 1 0 .5 1 0 0 0\n5 5 0 1 .5 1 0 0 0 65535\n",
                5,
                "species 65535: with a stepped potential (line 3) species go from 0 to 255",
            ),
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
            // A sphere's line where the directive is misspelt (found by a new user's walk: the
            // message said nothing of the dimension).
            (
                "1\n# edmd dimm 3\n1 1 1 0 0 0 .1 1 0 0 0\n",
                3,
                "found 11 (a sphere's line: a 3D file says '# edmd dim 3' before its discs)",
            ),
        ];
        for (text, line, what) in cases {
            let e = parse(text, ColumnOrder::default()).unwrap_err();
            assert_eq!(e.line, *line, "{text:?}: {e}");
            assert!(e.message.contains(what), "{text:?}: {e}");
        }
    }

    const SPHERES: &str = "2\n# edmd dim 3\n# edmd box 4 5 6\n# edmd boundary periodic walls periodic\n1 1 1 0.1 -0.2 0.3 0.5 2 10 20 30\n3 3 3 0 0 -1 0.25 1 0 0 0 7\n";

    #[test]
    fn a_disc_line_in_a_3d_file_says_what_it_looks_like() {
        let e = parse_in::<3>(
            "1\n# edmd dim 3\n1 1 0 0 .1 1 0 0 0\n",
            ColumnOrder::RadiusMass,
        )
        .unwrap_err();
        assert_eq!(e.line, 3);
        assert!(
            e.message
                .ends_with("found 9 (a disc's line: a 2D file has no '# edmd dim 3')"),
            "{e}"
        );
    }

    #[test]
    fn spheres_are_read_and_round_trip_bit_for_bit() {
        assert_eq!(declared_dim(SPHERES), Ok(3));
        let s = parse_in::<3>(SPHERES, ColumnOrder::RadiusMass).unwrap();
        assert_eq!(s.sim_box.lengths, [4.0, 5.0, 6.0]);
        assert_eq!(
            s.sim_box.boundaries,
            [Boundary::Periodic, Boundary::Walls, Boundary::Periodic]
        );
        assert_eq!(s.discs[0].vel.0, [0.1, -0.2, 0.3]);
        assert_eq!((s.discs[0].radius, s.discs[0].mass), (0.5, 2.0));
        assert_eq!(s.discs[1].species, 7);
        assert_eq!(s.lines, vec![5, 6]);
        // Awkward numbers survive the trip exactly.
        let mut discs = s.discs.clone();
        discs[0].pos.0 = [0.1 + 0.2, 1.0 / 3.0, std::f64::consts::PI];
        let mut out = Vec::new();
        write(
            &mut out,
            &discs,
            &s.sim_box,
            &[],
            ColumnOrder::RadiusMass,
            0.0,
        )
        .unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with("2\n# edmd dim 3\n"), "{text}");
        let back = parse_in::<3>(&text, ColumnOrder::RadiusMass).unwrap();
        assert_eq!(back.discs, discs);
        assert_eq!(back.sim_box, s.sim_box);
        // The unit cube with walls is the default and is not written.
        let mut out = Vec::new();
        write(
            &mut out,
            &discs,
            &SimBox::walls([1.0; 3]),
            &[],
            ColumnOrder::MassRadius,
            0.0,
        )
        .unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(
            !text.contains("box") && !text.contains("boundary"),
            "{text}"
        );
        assert_eq!(
            parse_in::<3>(&text, ColumnOrder::MassRadius).unwrap().discs,
            discs
        );
    }

    #[test]
    fn a_file_read_in_the_wrong_dimension_says_so() {
        let e = parse(SPHERES, ColumnOrder::RadiusMass).unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.message.contains("3D file"), "{e}");
        let e = parse_in::<3>(TWO, ColumnOrder::RadiusMass).unwrap_err();
        assert!(e.message.contains("2D file"), "{e}");
        assert_eq!(declared_dim(TWO), Ok(2));
        // `dim 2` is allowed and changes nothing.
        let two = format!("# edmd dim 2\n{TWO}");
        assert_eq!(parse(&two, ColumnOrder::RadiusMass).unwrap().discs.len(), 2);
    }

    #[test]
    fn malformed_3d_files_name_the_line() {
        let cases: &[(&str, usize, &str)] = &[
            // A 2D disc line in a 3D file.
            (
                "1\n# edmd dim 3\n0.5 0.5 0 0 0.1 1 0 0 0\n",
                3,
                "expected 11 fields",
            ),
            // Too many fields.
            (
                "1\n# edmd dim 3\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 0 1 1\n",
                3,
                "expected 11 fields",
            ),
            // The directive after the first disc line.
            (
                "2\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 0\n# edmd dim 3\n0.2 0.2 0.2 0 0 0 0.1 1 0 0 0\n",
                3,
                "before the first disc",
            ),
            (
                "1\n# edmd dim 4\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 0\n",
                2,
                "dim 2' or '# edmd dim 3",
            ),
            (
                "1\n# edmd dim\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 0\n",
                2,
                "dim 2' or '# edmd dim 3",
            ),
            (
                "1\n# edmd dim 3\n# edmd dim 3\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 0\n",
                3,
                "second '# edmd dim'",
            ),
            (
                "1\n# edmd dim 3\n# edmd box 2 2\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 0\n",
                3,
                "expected 3 numbers",
            ),
            (
                "1\n# edmd dim 3\n# edmd boundary walls periodic\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 0\n",
                3,
                "boundary X [Y Z]",
            ),
            (
                "1\n# edmd dim 3\n# edmd barrier x 0.5\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 0\n",
                3,
                "2D files only",
            ),
            (
                "1\n# edmd dim 3\n0.5 0.5 zz 0 0 0 0.1 1 0 0 0\n",
                3,
                "rz is not a number",
            ),
            (
                "1\n# edmd dim 3\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 300\n",
                3,
                "colour b",
            ),
        ];
        for (text, line, words) in cases {
            let e = parse_in::<3>(text, ColumnOrder::RadiusMass).unwrap_err();
            assert_eq!(e.line, *line, "{text:?}: {e}");
            assert!(e.message.contains(words), "{text:?}: {e}");
        }
    }

    /// `# edmd restitution` lines are gathered into one restitution, written back as given,
    /// each part at most once, and refused beside a potential or rules.
    #[test]
    fn restitution_is_read_and_written_back() {
        let text = "1\n# edmd box 4 4\n# edmd restitution 0.9\n# edmd restitution walls 0.5\n# edmd restitution 0 0 bridges 0.1\n# edmd restitution tc 1e-4\n1 1 0 0 .5 1 0 0 0\n";
        let s = parse(text, ColumnOrder::default()).unwrap();
        let r = s.restitution.clone().unwrap();
        assert_eq!(r.all, edmd_core::RestitutionLaw::Constant(0.9));
        assert_eq!((r.wall, r.tc), (0.5, 1e-4));
        let mut out = Vec::new();
        let interactions = Interactions {
            potential: &s.potential,
            reactions: &s.reactions,
            restitution: s.restitution.as_ref(),
            gravity: s.gravity,
            shear: s.shear,
            self_gravity: s.self_gravity,
        };
        write_full(
            &mut out,
            &s.discs,
            &s.sim_box,
            &[],
            interactions,
            ColumnOrder::default(),
            0.0,
        )
        .unwrap();
        let back = parse(std::str::from_utf8(&out).unwrap(), ColumnOrder::default()).unwrap();
        assert_eq!(back.restitution, s.restitution);
        for (bad, want) in [
            (
                "# edmd restitution 0.9\n# edmd restitution 0.8\n",
                "line 3: a second restitution for every pair (the first is line 2)",
            ),
            (
                "# edmd restitution 0 1 0.9\n# edmd restitution 1 0 0.8\n",
                "line 3: a second restitution for species 1 and 0",
            ),
            (
                "# edmd restitution 2\n",
                "line 2: restitution: the coefficient must be in [0, 1], found 2",
            ),
            (
                "# edmd restitution 0.9\n# edmd potential 0 0 1.5 -1\n",
                "line 2: restitution does not go with a stepped potential (line 3)",
            ),
            (
                "# edmd restitution 0.9\n# edmd reaction 0 + 0 -> 1 + 1\n",
                "line 2: restitution does not go with reaction rules (line 3)",
            ),
        ] {
            let text = format!("1\n{bad}.5 .5 0 0 .1 1 0 0 0\n");
            let e = parse(&text, ColumnOrder::default())
                .unwrap_err()
                .to_string();
            assert!(e.contains(want), "{e}");
        }
    }

    /// `# edmd ring OMEGA [OFFSET]` gives the system its ring and the shear at the Keplerian
    /// rate from the offset, and is written back (with the offset, in place of the shear's
    /// line); every refusal names its line.
    #[test]
    fn ring_is_read_and_written_back() {
        let text = "1\n# edmd dim 3\n# edmd box 8 8 30\n# edmd boundary periodic periodic walls\n# edmd ring 2 1.5\n1 1 15 0 0 0 .5 1 0 0 0\n";
        let s = parse_in::<3>(text, ColumnOrder::default()).unwrap();
        assert_eq!(s.ring, Some(Ring { omega: 2.0 }));
        assert_eq!(
            s.shear,
            Some(Shear {
                rate: -3.0,
                offset: 1.5
            })
        );
        let mut out = Vec::new();
        let interactions = Interactions {
            shear: s.shear.map(|x| Shear {
                offset: 0.1 + 0.2,
                ..x
            }),
            ..Interactions::HARD
        };
        write_full_ring(
            &mut out,
            &s.discs,
            &s.sim_box,
            &[],
            interactions,
            s.ring,
            ColumnOrder::default(),
            0.0,
        )
        .unwrap();
        let written = std::str::from_utf8(&out).unwrap();
        assert!(
            written.contains("# edmd ring 2.0 0.30000000000000004\n"),
            "{written}"
        );
        assert!(!written.contains("shear"), "{written}");
        let back = parse_in::<3>(written, ColumnOrder::default()).unwrap();
        assert_eq!(back.ring, s.ring);
        assert_eq!(back.shear.map(|x| x.offset), Some(0.1 + 0.2));
        // 2D, offset 0 by default.
        let flat =
            "1\n# edmd box 8 8\n# edmd boundary periodic\n# edmd ring 1\n1 1 0 0 .5 1 0 0 0\n";
        let s2 = parse(flat, ColumnOrder::default()).unwrap();
        assert_eq!(s2.shear.map(|x| (x.rate, x.offset)), Some((-1.5, 0.0)));
        // The course format has no place for it.
        let e = crate::write_full_ring(
            &mut Vec::new(),
            &s2.discs,
            &s2.sim_box,
            &[],
            Interactions::HARD,
            s2.ring,
            Format::Course,
            0.0,
        )
        .unwrap_err();
        assert!(e.to_string().contains("ring patch"), "{e}");
        let plane = "# edmd boundary periodic\n";
        let column = "# edmd boundary periodic periodic walls\n";
        for (dim, boundary, bad, want) in [
            (2, plane, "# edmd ring 1\n# edmd ring 2\n", "line 4: a second '# edmd ring' line (the first is line 3)"),
            (2, plane, "# edmd ring\n", "line 3: expected 'ring OMEGA [OFFSET]'"),
            (2, plane, "# edmd ring 1 0 0\n", "line 3: expected 'ring OMEGA [OFFSET]'"),
            (2, plane, "# edmd ring fast\n", "line 3: OMEGA is not a number: 'fast'"),
            (2, plane, "# edmd ring inf\n", "line 3: OMEGA is not finite"),
            (2, plane, "# edmd ring 1 nan\n", "line 3: OFFSET is not finite"),
            (2, plane, "# edmd ring 0\n", "line 3: ring: the orbital frequency must be a finite number above 0"),
            (2, plane, "# edmd ring -1\n", "line 3: ring: the orbital frequency must be a finite number above 0"),
            (2, plane, "# edmd ring 1 -0.5\n", "line 3: ring: the offset must be in [0, L_x) = [0, 8)"),
            (2, plane, "# edmd ring 1 8\n", "line 3: ring: the offset must be in [0, L_x)"),
            (2, plane, "# edmd ring 1\n# edmd shear 1\n", "line 3: ring does not go with '# edmd shear' (line 4)"),
            (2, plane, "# edmd ring 1\n# edmd potential 0 0 1.5 -1\n", "line 3: ring does not go with a stepped potential (line 4)"),
            (2, plane, "# edmd ring 1\n# edmd barrier x 2\n", "line 3: ring does not go with barriers"),
            (2, plane, "# edmd ring 1\n# edmd restitution 0.5\n", "line 3: ring with a constant restitution below 1 (line 4) needs the TC model"),
            (2, "# edmd boundary periodic walls\n", "# edmd ring 1\n", "line 3: ring: a ring patch needs periodic x and y axes ('# edmd boundary periodic')"),
            (2, "", "# edmd ring 1\n", "line 3: ring: a ring patch needs periodic x and y axes"),
            (3, "# edmd boundary periodic\n", "# edmd ring 1\n", "line 3: ring: a ring patch needs walls along z"),
            (3, "# edmd boundary periodic walls walls\n", "# edmd ring 1\n", "line 3: ring: a ring patch needs periodic x and y axes ('# edmd boundary periodic periodic walls')"),
            (3, column, "# edmd ring 1\n# edmd gravity z -1\n", "line 3: ring does not go with gravity (line 4)"),
            (1, "# edmd boundary periodic\n", "# edmd ring 1\n", "line 3: ring: a ring patch has a radial (y) axis, and a 1D file has none"),
        ] {
            let (head, disc) = match dim {
                1 => ("# edmd dim 1\n# edmd box 8\n", "1 0 .1 1 0 0 0"),
                2 => ("# edmd box 8 8\n", "1 1 0 0 .1 1 0 0 0"),
                _ => ("# edmd dim 3\n# edmd box 8 8 8\n", "1 1 4 0 0 0 .1 1 0 0 0"),
            };
            // The ring's line is line 3 in each: the dimension's line, if any, goes after it.
            let (first, rest) = head.split_at(head.find('\n').unwrap() + 1);
            let text = if dim == 2 {
                format!("1\n{first}{bad}{boundary}{disc}\n")
            } else {
                format!("1\n{first}{bad}{rest}{boundary}{disc}\n")
            };
            let e = match dim {
                1 => parse_in::<1>(&text, ColumnOrder::default()).map(|_| ()),
                2 => parse_in::<2>(&text, ColumnOrder::default()).map(|_| ()),
                _ => parse_in::<3>(&text, ColumnOrder::default()).map(|_| ()),
            }
            .unwrap_err()
            .to_string();
            assert!(e.contains(want), "{text}: {e}");
            assert!(!e.contains('\n'), "{e}");
        }
    }

    /// `# edmd shear` is read (offset 0 by default) and written back with its offset, at most
    /// once, with periodic x and y, and not beside a field, a potential or barriers; every
    /// refusal names its line.
    #[test]
    fn shear_is_read_and_written_back() {
        let text =
            "1\n# edmd box 4 4\n# edmd boundary periodic\n# edmd shear -0.25\n1 1 0 0 .5 1 0 0 0\n";
        let s = parse(text, ColumnOrder::default()).unwrap();
        assert_eq!(s.shear, Some(Shear::new(-0.25)));
        let text = text.replace("-0.25", "0.1 3.9");
        let s = parse(&text, ColumnOrder::default()).unwrap();
        let want = Shear {
            rate: 0.1,
            offset: 3.9,
        };
        assert_eq!(s.shear, Some(want));
        let mut out = Vec::new();
        let interactions = Interactions {
            shear: s.shear,
            ..Interactions::HARD
        };
        write_full(
            &mut out,
            &s.discs,
            &s.sim_box,
            &[],
            interactions,
            ColumnOrder::default(),
            2.5,
        )
        .unwrap();
        let written = std::str::from_utf8(&out).unwrap();
        assert!(written.contains("# edmd shear 0.1 3.9\n"), "{written}");
        let back = parse(written, ColumnOrder::default()).unwrap();
        assert_eq!(back.shear, s.shear);
        assert_eq!(back.time, 2.5);
        let shear3 = "1\n# edmd dim 3\n# edmd boundary periodic periodic walls\n# edmd shear 1 0.5\n.5 .5 .5 0 0 0 .1 1 0 0 0\n";
        let s3 = parse_in::<3>(shear3, ColumnOrder::default()).unwrap();
        assert_eq!(s3.shear.map(|s| s.offset), Some(0.5));
        for (bad, want) in [
            (
                "# edmd shear 1\n# edmd shear 2\n",
                "line 4: a second '# edmd shear' line (the first is line 3)",
            ),
            ("# edmd shear\n", "line 3: expected 'shear RATE [OFFSET]'"),
            (
                "# edmd shear 1 0 0\n",
                "line 3: expected 'shear RATE [OFFSET]'",
            ),
            (
                "# edmd shear fast\n",
                "line 3: RATE is not a number: 'fast'",
            ),
            ("# edmd shear inf\n", "line 3: RATE is not finite"),
            ("# edmd shear 1 nan\n", "line 3: OFFSET is not finite"),
            (
                "# edmd shear 1 -0.5\n",
                "line 3: shear: the offset must be in [0, L_x) = [0, 4)",
            ),
            (
                "# edmd shear 1 4\n",
                "line 3: shear: the offset must be in [0, L_x)",
            ),
            (
                "# edmd shear 1\n# edmd potential 0 0 1.5 -1\n",
                "line 3: shear does not go with a stepped potential (line 4)",
            ),
            (
                "# edmd shear 1\n# edmd barrier x 2\n",
                "line 3: shear does not go with barriers",
            ),
        ] {
            let text =
                format!("1\n# edmd box 4 4\n{bad}# edmd boundary periodic\n1 1 0 0 .1 1 0 0 0\n");
            let e = parse(&text, ColumnOrder::default())
                .unwrap_err()
                .to_string();
            assert!(e.contains(want), "{e}");
        }
        for (boundary, want) in [
            (
                "periodic walls",
                "line 2: shear: Lees-Edwards boundaries need periodic x and y",
            ),
            (
                "walls periodic",
                "line 2: shear: Lees-Edwards boundaries need periodic x and y",
            ),
            (
                "walls",
                "line 2: shear: Lees-Edwards boundaries need periodic x and y",
            ),
        ] {
            let text =
                format!("1\n# edmd shear 1\n# edmd boundary {boundary}\n.5 .5 0 0 .1 1 0 0 0\n");
            let e = parse(&text, ColumnOrder::default())
                .unwrap_err()
                .to_string();
            assert!(e.contains(want), "{e}");
        }
        let text = "1\n# edmd box 4 4\n# edmd boundary periodic walls\n# edmd gravity y -1\n# edmd shear 1\n1 1 0 0 .5 1 0 0 0\n";
        let e = parse(text, ColumnOrder::default()).unwrap_err().to_string();
        assert!(
            e.contains("line 5: shear does not go with gravity (line 4)"),
            "{e}"
        );
        // The course format has no place for it.
        let mut out = Vec::new();
        let e = crate::write_full(
            &mut out,
            &s.discs,
            &s.sim_box,
            &[],
            interactions,
            Format::Course,
            0.0,
        )
        .unwrap_err();
        assert!(e.to_string().contains("no place for shear"), "{e}");
    }

    /// `# edmd gravity` is read and written back, at most once, along an axis with walls, and
    /// inelastic collisions beside it need the TC model.
    #[test]
    fn gravity_is_read_and_written_back() {
        let text = "1\n# edmd box 4 4\n# edmd boundary periodic walls\n# edmd gravity y -9.5\n1 1 0 0 .5 1 0 0 0\n";
        let s = parse(text, ColumnOrder::default()).unwrap();
        assert_eq!(s.gravity, Some(Gravity { axis: 1, g: -9.5 }));
        let mut out = Vec::new();
        let interactions = Interactions {
            potential: &s.potential,
            reactions: &s.reactions,
            restitution: None,
            gravity: s.gravity,
            shear: s.shear,
            self_gravity: s.self_gravity,
        };
        write_full(
            &mut out,
            &s.discs,
            &s.sim_box,
            &[],
            interactions,
            ColumnOrder::default(),
            0.0,
        )
        .unwrap();
        let back = parse(std::str::from_utf8(&out).unwrap(), ColumnOrder::default()).unwrap();
        assert_eq!(back.gravity, s.gravity);
        for (bad, want) in [
            (
                "# edmd gravity y -1\n# edmd gravity y -2\n",
                "line 3: a second '# edmd gravity' line",
            ),
            ("# edmd gravity z -1\n", "line 2: expected 'gravity x|y G'"),
            (
                "# edmd gravity y 0\n",
                "line 2: gravity: g must be a finite number other than 0",
            ),
            ("# edmd gravity y nan\n", "line 2: G is not"),
            (
                "# edmd boundary periodic\n# edmd gravity y -1\n",
                "line 3: gravity: the field's axis y must have walls",
            ),
            (
                "# edmd gravity y -1\n# edmd potential 0 0 1.5 -1\n",
                "line 2: gravity does not go with a stepped potential (line 3)",
            ),
            (
                "# edmd gravity y -1\n# edmd restitution 0.5\n",
                "line 2: gravity with inelastic collisions needs the TC model",
            ),
        ] {
            let text = format!("1\n{bad}.5 .5 0 0 .1 1 0 0 0\n");
            let e = parse(&text, ColumnOrder::default())
                .unwrap_err()
                .to_string();
            assert!(e.contains(want), "{e}");
        }
    }

    const RODS: &str = "3\n# edmd dim 1\n# edmd box 10\n# edmd boundary periodic\n1 0.5 0.5 1 10 20 30\n4.25 -1 0.5 2 0 0 0 3\n9.5 0.125 0.25 1 255 0 0\n";

    #[test]
    fn rods_are_read_and_round_trip_bit_for_bit() {
        assert_eq!(declared_dim(RODS), Ok(1));
        let s = parse_in::<1>(RODS, ColumnOrder::RadiusMass).unwrap();
        assert_eq!(s.sim_box, SimBox::periodic([10.0]));
        assert_eq!(s.discs[1].pos.0, [4.25]);
        assert_eq!(s.discs[1].vel.0, [-1.0]);
        assert_eq!((s.discs[1].radius, s.discs[1].mass), (0.5, 2.0));
        assert_eq!(s.discs[1].species, 3);
        assert_eq!(s.discs[0].colour, [10, 20, 30]);
        assert_eq!(s.lines, vec![5, 6, 7]);
        let mut discs = s.discs.clone();
        discs[0].pos.0 = [0.1 + 0.2];
        discs[2].vel.0 = [1.0 / 3.0];
        for order in [ColumnOrder::RadiusMass, ColumnOrder::MassRadius] {
            let mut out = Vec::new();
            write(&mut out, &discs, &s.sim_box, &[], order, 2.5).unwrap();
            let text = String::from_utf8(out).unwrap();
            assert!(
                text.starts_with("3\n# edmd dim 1\n# edmd box 10.0\n# edmd boundary periodic\n"),
                "{text}"
            );
            let back = parse_in::<1>(&text, order).unwrap();
            assert_eq!(back.discs, discs);
            assert_eq!(back.sim_box, s.sim_box);
            assert_eq!(back.time, 2.5);
        }
        // The unit line with walls is the default and is not written.
        let mut out = Vec::new();
        write(
            &mut out,
            &discs[..1],
            &SimBox::walls([1.0]),
            &[],
            ColumnOrder::RadiusMass,
            0.0,
        )
        .unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(
            text,
            "1\n# edmd dim 1\n0.30000000000000004 0.5 0.5 1.0 10 20 30\n"
        );
        // Read in another dimension, it says what it is.
        let e = parse(RODS, ColumnOrder::RadiusMass).unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.message.contains("1D file ('# edmd dim 1')"), "{e}");
        let e = parse_in::<1>(TWO, ColumnOrder::RadiusMass).unwrap_err();
        assert!(e.message.contains("2D file"), "{e}");
    }

    #[test]
    fn malformed_1d_files_name_the_line() {
        let cases: &[(&str, usize, &str)] = &[
            // A disc's line in a 1D file.
            (
                "1\n# edmd dim 1\n0.5 0.5 0 0 0.1 1 0 0 0\n",
                3,
                "found 9 (a disc's line: a 2D file has no '# edmd dim' line)",
            ),
            // A rod's line without the directive.
            (
                "1\n0.5 0 0.1 1 0 0 0\n",
                2,
                "found 7 (a rod's line: a 1D file says '# edmd dim 1' before its rods)",
            ),
            // Too few fields.
            (
                "1\n# edmd dim 1\n0.5 0 0.1 1\n",
                3,
                "expected 7 fields (rx vx radius mass r g b) or 8 (with species), found 4",
            ),
            ("1\n# edmd dim 1\n0.5 zz 0.1 1 0 0 0\n", 3, "vx"),
            (
                "1\n# edmd dim 1\n0.5 0 -0.1 1 0 0 0\n",
                3,
                "radius must be > 0",
            ),
            (
                "1\n# edmd dim 1\n0.5 0 0.1 0 0 0 0\n",
                3,
                "mass must be > 0",
            ),
            ("1\n# edmd dim 1\n0.5 0 0.1 1 0 0 256\n", 3, "colour b"),
            (
                "1\n# edmd dim 1\n0.5 0 0.1 1 0 0 0 x\n",
                3,
                "species must be a whole number",
            ),
            ("2\n# edmd dim 1\n0.5 0 0.1 1 0 0 0\n", 3, "disc 2 of 2"),
            // Directives with the other dimensions' values.
            (
                "1\n# edmd dim 1\n# edmd box 2 2\n0.5 0 0.1 1 0 0 0\n",
                3,
                "expected 1 number (LX), found 2",
            ),
            (
                "1\n# edmd dim 1\n# edmd boundary walls periodic\n0.5 0 0.1 1 0 0 0\n",
                3,
                "expected 'boundary X' (one axis in a 1D file)",
            ),
            (
                "1\n# edmd dim 1\n# edmd barrier x 0.5\n0.5 0 0.1 1 0 0 0\n",
                3,
                "barriers exist in 2D files only",
            ),
            (
                "1\n# edmd dim 1\n# edmd gravity y -1\n0.5 0 0.1 1 0 0 0\n",
                3,
                "expected 'gravity x G'",
            ),
            (
                "1\n# edmd dim 1\n# edmd boundary periodic\n# edmd shear 1\n0.5 0 0.1 1 0 0 0\n",
                4,
                "a 1D file has no y axis",
            ),
            (
                "1\n# edmd dim 0\n0.5 0 0.1 1 0 0 0\n",
                2,
                "expected '# edmd dim 1', '# edmd dim 2' or '# edmd dim 3'",
            ),
        ];
        for (text, line, want) in cases {
            let e = match declared_dim(text) {
                Ok(1) => parse_in::<1>(text, ColumnOrder::RadiusMass).unwrap_err(),
                Ok(_) => parse(text, ColumnOrder::RadiusMass).unwrap_err(),
                Err(e) => e,
            };
            assert_eq!(e.line, *line, "{text:?}: {e}");
            assert!(e.message.contains(want), "{text:?}: {e}");
        }
    }
}
