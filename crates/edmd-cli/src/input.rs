//! Reading a data file into a validated simulation, with every problem traced to its line.

use std::io::Read;

use anyhow::Result;
use edmd_core::{Error as EngineError, Options, Simulation};
use edmd_io::princeton::ColumnOrder;
use edmd_io::{Format, LoadedSystem};

use crate::user_error;

/// Reads `path` (`-` for standard input) as text.
pub fn read_text(path: &str) -> Result<String> {
    let mut text = String::new();
    let res = if path == "-" {
        std::io::stdin().read_to_string(&mut text).map(|_| ())
    } else {
        std::fs::read_to_string(path).map(|t| text = t)
    };
    match res {
        Ok(()) => Ok(text),
        Err(e) if e.kind() == std::io::ErrorKind::InvalidData => {
            user_error(format!("{path}: not a text file (invalid UTF-8)"))
        }
        Err(e) => user_error(format!("{path}: cannot read: {e}")),
    }
}

/// Parses a file in `format` (`None`: detect; a detected Princeton file is read with `order`).
pub fn load(
    path: &str,
    text: &str,
    format: Option<Format>,
    order: ColumnOrder,
) -> Result<LoadedSystem> {
    let format = match format.or_else(|| edmd_io::detect(text)) {
        Some(Format::Princeton(_)) => Format::Princeton(order),
        Some(f) => f,
        // Too short to tell: the Princeton reader names the problem (empty, bad count, ...).
        None => Format::Princeton(order),
    };
    edmd_io::parse(text, format)
        .or_else(|e| user_error(format!("{path}:{}: {}", e.line, e.message)))
}

/// Builds the simulation, translating engine refusals into messages naming lines.
pub fn build(path: &str, sys: &LoadedSystem, options: Options) -> Result<Simulation> {
    Simulation::with_barriers(&sys.discs, sys.sim_box, &sys.barriers, options).or_else(|e| {
        let line = |i: usize| sys.lines.get(i).copied().unwrap_or(0);
        let msg = match e {
            EngineError::Overlap { i, j, overlap, count } => format!(
                "{path}:{}: this disc overlaps the disc on line {} by {overlap:.3e} of their contact distance ({count} overlapping pair(s) in all; --allow-overlaps runs it anyway)",
                line(j),
                line(i)
            ),
            EngineError::OutsideBox { first, count } => format!(
                "{path}:{}: this disc is not inside the box ({count} such disc(s) in all; --allow-overlaps moves them in)",
                line(first)
            ),
            EngineError::BadDisc { index, what } => format!("{path}:{}: {what}", line(index)),
            EngineError::SwapNeedsEqualMasses { index, mass, mass0 } => format!(
                "{path}:{}: the swap rule needs equal masses, but this disc has mass {mass} and the first has {mass0}",
                line(index)
            ),
            EngineError::BarrierOverlap { disc, barrier } => format!(
                "{path}:{}: this disc cuts into barrier {} (the {} '# edmd barrier' line)",
                line(disc),
                barrier + 1,
                ordinal(barrier + 1)
            ),
            other => format!("{path}: {other}"),
        };
        user_error(msg)
    })
}

/// "1st", "2nd", "3rd", "4th", ...
fn ordinal(k: usize) -> String {
    let suffix = match (k % 10, k % 100) {
        (1, r) if r != 11 => "st",
        (2, r) if r != 12 => "nd",
        (3, r) if r != 13 => "rd",
        _ => "th",
    };
    format!("{k}{suffix}")
}
