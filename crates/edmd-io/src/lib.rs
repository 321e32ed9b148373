//! # edmd-io: the file formats edmd reads and writes
//!
//! - [`course`]: the "Collisions" course format (`N`, `R`, `Lx Ly`, then `x y u v` per disc).
//! - [`princeton`]: the Princeton CollisionSystem format (`N`, then
//!   `rx ry vx vy radius mass r g b` per disc, in the unit box with walls), with edmd's
//!   extension, which includes 3D files of spheres (`# edmd dim 3`) and 1D files of hard rods
//!   (`# edmd dim 1`), stepped potentials and
//!   reaction rules ([`reaction`]: the text of a rule).
//! - [`xyz`]: extended XYZ trajectory frames, as read by OVITO and ASE.
//! - [`gsd`]: HOOMD GSD frames, written and read (through the `hoomd-gsd` crate), so that
//!   HOOMD-blue and edmd continue each other's systems.
//!
//! Readers never panic on bad input: they return a [`ParseError`] naming the line and what is
//! wrong, and engine-level problems (overlaps, discs outside the box) can be traced back to a
//! line through the per-disc line numbers every reader returns.

#![forbid(unsafe_code)]

pub mod course;
pub mod gsd;
pub mod princeton;
pub mod reaction;
pub mod restitution;
mod text;
pub mod xyz;

pub use text::ParseError;

use edmd_core::{
    Barrier, Disc, Gravity, Potential, Reaction, Restitution, Ring, SelfGravity, Shear, SimBox,
};

/// A system read from a file, with the line each disc came from (`D = 3` for spheres).
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedSystem<const D: usize = 2> {
    /// The discs, in file order.
    pub discs: Vec<Disc<D>>,
    /// The box.
    pub sim_box: SimBox<D>,
    /// Internal barriers (Princeton extension).
    pub barriers: Vec<Barrier>,
    /// 1-based line number of each disc.
    pub lines: Vec<usize>,
    /// The format it was read in.
    pub format: Format,
    /// The time the state is at (`# edmd time T`; 0 without it, and always 0 in the course
    /// format, which has no place for it).
    pub time: f64,
    /// The stepped pair potential (`# edmd potential`; none: hard cores alone).
    pub potential: Potential,
    /// The reaction rules (`# edmd reaction`, in file order; none: collisions never react).
    /// Only the Princeton format holds them.
    pub reactions: Vec<Reaction>,
    /// The restitution (`# edmd restitution`; none: collisions are elastic). Only the
    /// Princeton format holds it.
    pub restitution: Option<Restitution>,
    /// The uniform field (`# edmd gravity`; none: discs fly straight). Only the Princeton
    /// format holds it.
    pub gravity: Option<Gravity>,
    /// Lees-Edwards boundaries (`# edmd shear`; none: plain periodic or walled axes), with the
    /// images' offset at [`LoadedSystem::time`]. Only the Princeton format holds it.
    pub shear: Option<Shear>,
    /// A patch of a planetary ring (`# edmd ring OMEGA [OFFSET]`; none: none). Its
    /// Lees-Edwards boundaries are in [`LoadedSystem::shear`] (rate `-3/2 OMEGA`, the file's
    /// offset), so that a reader sets that shear first and the ring then keeps its offset.
    /// Only the Princeton format holds it.
    pub ring: Option<Ring>,
    /// One-dimensional self-gravity (`# edmd self-gravity C`, 1D files only; none: none).
    /// Only the Princeton format holds it.
    pub self_gravity: Option<SelfGravity>,
}

/// How particles interact besides their hard cores, as the Princeton format's directives say
/// it: the stepped potential, the reaction rules, the restitution, the field, the shear and
/// the self-gravity.
#[derive(Clone, Copy, Debug)]
pub struct Interactions<'a> {
    /// The stepped pair potential (no pairs: hard cores).
    pub potential: &'a Potential,
    /// The reaction rules (none: collisions never react).
    pub reactions: &'a [Reaction],
    /// The restitution (none: collisions are elastic).
    pub restitution: Option<&'a Restitution>,
    /// The uniform field (none: discs fly straight).
    pub gravity: Option<Gravity>,
    /// Lees-Edwards boundaries, with the images' offset at the time written (none: none).
    pub shear: Option<Shear>,
    /// One-dimensional self-gravity (none: none), written as `# edmd self-gravity C`.
    pub self_gravity: Option<SelfGravity>,
}

/// Hard cores with no steps, for [`Interactions::HARD`].
static NO_STEPS: Potential = Potential { pairs: Vec::new() };

impl Interactions<'_> {
    /// Hard cores alone, no reactions.
    pub const HARD: Interactions<'static> = Interactions {
        potential: &NO_STEPS,
        reactions: &[],
        restitution: None,
        gravity: None,
        shear: None,
        self_gravity: None,
    };

    /// Whether there is nothing besides hard cores.
    pub fn is_hard(&self) -> bool {
        self.potential.is_hard()
            && self.reactions.is_empty()
            && self.restitution.is_none()
            && self.gravity.is_none()
            && self.shear.is_none()
            && self.self_gravity.is_none()
    }
}

/// The input formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The course format.
    Course,
    /// The Princeton format with the given column order.
    Princeton(princeton::ColumnOrder),
}

/// Guesses the format from the second non-blank line: a lone number (the radius) means the
/// course format, anything else the Princeton format (whose reader then says what is wrong
/// with a malformed line). `None` if the file has fewer than two non-blank lines.
pub fn detect(text: &str) -> Option<Format> {
    // Blank lines and `#` comments (allowed anywhere, also before N) say nothing of the format,
    // nor does a byte order mark.
    let mut lines = text
        .strip_prefix('\u{feff}')
        .unwrap_or(text)
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    lines.next()?;
    match lines.next()?.split_whitespace().count() {
        1 => Some(Format::Course),
        _ => Some(Format::Princeton(princeton::ColumnOrder::default())),
    }
}

/// Reads `text` in `format`, as a 2D system (a 3D file is an error saying so).
pub fn parse(text: &str, format: Format) -> Result<LoadedSystem, ParseError> {
    match format {
        Format::Course => course::parse(text).map(|c| c.into_loaded()),
        Format::Princeton(order) => princeton::parse(text, order),
    }
}

/// A system of any dimension, as the file declares it.
#[derive(Clone, Debug, PartialEq)]
pub enum AnyLoaded {
    /// Rods on a line (`# edmd dim 1`).
    One(LoadedSystem<1>),
    /// Discs.
    Two(LoadedSystem<2>),
    /// Spheres (`# edmd dim 3`).
    Three(LoadedSystem<3>),
}

impl AnyLoaded {
    /// 1, 2 or 3.
    pub fn dim(&self) -> usize {
        match self {
            AnyLoaded::One(_) => 1,
            AnyLoaded::Two(_) => 2,
            AnyLoaded::Three(_) => 3,
        }
    }
}

/// The dimension `text` declares in `format`: the course format is 2D; a Princeton file is 3D
/// with a `# edmd dim 3` directive, 1D with `# edmd dim 1`.
pub fn dim_of(text: &str, format: Format) -> Result<usize, ParseError> {
    match format {
        Format::Course => Ok(2),
        Format::Princeton(_) => princeton::declared_dim(text),
    }
}

/// Reads `text` in `format`, in the dimension the file declares.
pub fn parse_any(text: &str, format: Format) -> Result<AnyLoaded, ParseError> {
    match (dim_of(text, format)?, format) {
        (3, Format::Princeton(order)) => {
            princeton::parse_in::<3>(text, order).map(AnyLoaded::Three)
        }
        (1, Format::Princeton(order)) => princeton::parse_in::<1>(text, order).map(AnyLoaded::One),
        _ => parse(text, format).map(AnyLoaded::Two),
    }
}

/// Writes discs (or spheres) in `format`, at `time` (kept by the Princeton format as
/// `# edmd time T` when it is not 0). The course format is 2D and keeps only the first
/// radius, the box lengths and no barriers: check [`course::fits`] first; a 3D system in it is
/// an `InvalidInput` error.
pub fn write<const D: usize>(
    out: &mut impl std::io::Write,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    barriers: &[Barrier],
    format: Format,
    time: f64,
) -> std::io::Result<()> {
    write_with(
        out,
        discs,
        sim_box,
        barriers,
        &Potential::default(),
        format,
        time,
    )
}

/// [`write`] with a stepped potential (the Princeton format keeps it as `# edmd potential`
/// lines; the course format has no place for one: an `InvalidInput` error).
pub fn write_with<const D: usize>(
    out: &mut impl std::io::Write,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    barriers: &[Barrier],
    potential: &Potential,
    format: Format,
    time: f64,
) -> std::io::Result<()> {
    let interactions = Interactions {
        potential,
        ..Interactions::HARD
    };
    write_full(out, discs, sim_box, barriers, interactions, format, time)
}

/// [`write`] with the stepped potential and the reaction rules (the Princeton format keeps
/// them as `# edmd potential` and `# edmd reaction` lines; the course format has no place for
/// either: an `InvalidInput` error).
pub fn write_full<const D: usize>(
    out: &mut impl std::io::Write,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    barriers: &[Barrier],
    interactions: Interactions,
    format: Format,
    time: f64,
) -> std::io::Result<()> {
    write_full_ring(
        out,
        discs,
        sim_box,
        barriers,
        interactions,
        None,
        format,
        time,
    )
}

/// [`write_full`] of a patch of a planetary ring (`ring`; none: as [`write_full`]), which the
/// Princeton format keeps as `# edmd ring OMEGA OFFSET` in place of the shear's line (the
/// offset is `interactions.shear`'s); the course format has no place for one.
#[allow(clippy::too_many_arguments)]
pub fn write_full_ring<const D: usize>(
    out: &mut impl std::io::Write,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    barriers: &[Barrier],
    interactions: Interactions,
    ring: Option<Ring>,
    format: Format,
    time: f64,
) -> std::io::Result<()> {
    if format == Format::Course && ring.is_some() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the course format has no place for a ring patch",
        ));
    }
    if format == Format::Course && !interactions.potential.is_hard() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the course format has no place for a stepped potential",
        ));
    }
    if format == Format::Course && !interactions.reactions.is_empty() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the course format has no place for reaction rules",
        ));
    }
    if format == Format::Course && interactions.gravity.is_some() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the course format has no place for a field",
        ));
    }
    if format == Format::Course && interactions.shear.is_some() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the course format has no place for shear",
        ));
    }
    if format == Format::Course && interactions.restitution.is_some() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the course format has no place for restitution",
        ));
    }
    match format {
        Format::Course if D == 2 => {
            let flat: Vec<Disc> = discs.iter().map(|d| d.with_dim()).collect();
            let flat_box = SimBox {
                lengths: [sim_box.lengths[0], sim_box.lengths[1]],
                boundaries: [sim_box.boundaries[0], sim_box.boundaries[1]],
            };
            course::write(out, &flat, &flat_box)
        }
        Format::Course => Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("the course format holds 2D systems only, not {D}D"),
        )),
        Format::Princeton(order) => princeton::write_full_ring(
            out,
            discs,
            sim_box,
            barriers,
            interactions,
            ring,
            order,
            time,
        ),
    }
}
