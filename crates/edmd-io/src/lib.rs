//! # edmd-io: the file formats edmd reads and writes
//!
//! - [`course`]: the "Collisions" course format (`N`, `R`, `Lx Ly`, then `x y u v` per disc).
//! - [`princeton`]: the Princeton CollisionSystem format (`N`, then
//!   `rx ry vx vy radius mass r g b` per disc, in the unit box with walls).
//! - [`xyz`]: extended XYZ trajectory frames, as read by OVITO and ASE.
//!
//! Readers never panic on bad input: they return a [`ParseError`] naming the line and what is
//! wrong, and engine-level problems (overlaps, discs outside the box) can be traced back to a
//! line through the per-disc line numbers every reader returns.

#![forbid(unsafe_code)]

pub mod course;
pub mod princeton;
mod text;
pub mod xyz;

pub use text::ParseError;

use edmd_core::{Barrier, Disc, SimBox};

/// A system read from a file, with the line each disc came from.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedSystem {
    /// The discs, in file order.
    pub discs: Vec<Disc>,
    /// The box.
    pub sim_box: SimBox,
    /// Internal barriers (Princeton extension).
    pub barriers: Vec<Barrier>,
    /// 1-based line number of each disc.
    pub lines: Vec<usize>,
    /// The format it was read in.
    pub format: Format,
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
    // Blank lines and `#` comments (allowed anywhere, also before N) say nothing of the format.
    let mut lines = text
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    lines.next()?;
    match lines.next()?.split_whitespace().count() {
        1 => Some(Format::Course),
        _ => Some(Format::Princeton(princeton::ColumnOrder::default())),
    }
}

/// Reads `text` in `format`.
pub fn parse(text: &str, format: Format) -> Result<LoadedSystem, ParseError> {
    match format {
        Format::Course => course::parse(text).map(|c| c.into_loaded()),
        Format::Princeton(order) => princeton::parse(text, order),
    }
}

/// Writes discs in `format` (the course format keeps only the first radius, the box lengths and
/// no barriers: check [`course::fits`] first).
pub fn write(
    out: &mut impl std::io::Write,
    discs: &[Disc],
    sim_box: &SimBox,
    barriers: &[Barrier],
    format: Format,
) -> std::io::Result<()> {
    match format {
        Format::Course => course::write(out, discs, sim_box),
        Format::Princeton(order) => princeton::write(out, discs, sim_box, barriers, order),
    }
}
