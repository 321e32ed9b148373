//! Reading a data file into a validated simulation, with every problem traced to its line.

use std::io::Read;

use anyhow::Result;
use edmd_core::{Error as EngineError, Options, OverlapPolicy, Simulation};
use edmd_io::princeton::ColumnOrder;
use edmd_io::{AnyLoaded, Format, LoadedSystem};

use crate::user_error;

/// The longest line a data file may have.
pub const MAX_LINE: usize = 64 * 1024;
/// The largest data file read (about ten million discs).
pub const MAX_FILE: usize = 1 << 30;

/// Reads `path` (`-` for standard input) as text, stopping at the first problem: a NUL byte
/// or invalid UTF-8 (not a text file), a line longer than [`MAX_LINE`], or more than
/// [`MAX_FILE`] bytes. So `/dev/zero` or `/dev/urandom` end at once with a message naming the
/// line.
pub fn read_text(path: &str) -> Result<String> {
    let mut reader: Box<dyn Read> = if path == "-" {
        Box::new(std::io::stdin().lock())
    } else {
        if std::fs::metadata(path).is_ok_and(|m| m.is_dir()) {
            return user_error(format!("{path}: cannot read: is a folder, not a data file"));
        }
        match std::fs::File::open(path) {
            Ok(f) => Box::new(f),
            Err(e) => return user_error(format!("{path}: cannot read: {e}")),
        }
    };
    let mut bytes: Vec<u8> = Vec::new();
    let mut chunk = vec![0u8; 64 * 1024];
    let mut line = 1usize;
    let mut line_len = 0usize;
    // Bytes before `checked` are valid UTF-8 and have been scanned.
    let mut checked = 0usize;
    loop {
        let got = match reader.read(&mut chunk) {
            Ok(0) => break,
            Ok(k) => k,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return user_error(format!("{path}: cannot read: {e}")),
        };
        if bytes.len() + got > MAX_FILE {
            return user_error(format!(
                "{path}: the file is larger than {} MiB, the most a data file may have",
                MAX_FILE >> 20
            ));
        }
        bytes.extend_from_slice(&chunk[..got]);
        let valid_to = match std::str::from_utf8(&bytes[checked..]) {
            Ok(_) => bytes.len(),
            Err(e) if e.error_len().is_none() => checked + e.valid_up_to(),
            Err(e) => {
                let bad = checked + e.valid_up_to();
                scan(path, &bytes[checked..bad], &mut line, &mut line_len)
                    .or_else(|msg| not_text(path, &bytes, msg))?;
                return not_text(
                    path,
                    &bytes,
                    format!("{path}:{line}: not a text file (invalid UTF-8)"),
                );
            }
        };
        scan(path, &bytes[checked..valid_to], &mut line, &mut line_len)
            .or_else(|msg| not_text(path, &bytes, msg))?;
        checked = valid_to;
    }
    if checked < bytes.len() {
        return not_text(
            path,
            &bytes,
            format!("{path}:{line}: not a text file (invalid UTF-8)"),
        );
    }
    Ok(String::from_utf8(bytes).expect("checked"))
}

/// Refuses a file that is not text (`msg` says why), or, when it is one of edmd's own
/// checkpoints (they are binary), says so and what continues it: a data file was expected.
fn not_text<T>(path: &str, bytes: &[u8], msg: String) -> Result<T> {
    user_error(checkpoint_kind(path, bytes).unwrap_or(msg))
}

/// Reads any data file `edmd run` takes: a GSD file (HOOMD schema; known by its first bytes or a
/// `.gsd` name), frame `frame` of it (negative from the end; the last by default), or else a
/// text file in the course or Princeton format ([`read_text`], [`load_any`]). Notes the GSD
/// reader makes (float64 copies not used, and why) go to standard error.
pub fn read_any(
    path: &str,
    format: Option<Format>,
    order: ColumnOrder,
    frame: Option<i64>,
) -> Result<AnyLoaded> {
    if path != "-" {
        let mut start = [0u8; 8];
        let magic = std::fs::File::open(path)
            .and_then(|mut f| f.read_exact(&mut start))
            .is_ok()
            && edmd_io::gsd::is_gsd(&start);
        if magic || path.ends_with(".gsd") {
            if format.is_some() {
                return user_error(format!(
                    "{path}: a GSD file: --format applies to text files"
                ));
            }
            return match edmd_io::gsd::read_frame(path, frame.unwrap_or(-1)) {
                Ok(f) => {
                    for note in &f.notes {
                        eprintln!("{path}: note: {note}");
                    }
                    Ok(f.system)
                }
                Err(e) => user_error(e.to_string()),
            };
        }
    }
    if frame.is_some() {
        return user_error(format!("{path}: --frame applies to GSD files"));
    }
    let text = read_text(path)?;
    load_any(path, &text, format, order)
}

/// What a file starting with `start` is when it is an edmd checkpoint (a run's or a
/// packing's), with the command that continues it; `None` for any other file.
pub fn checkpoint_kind(path: &str, start: &[u8]) -> Option<String> {
    // A checkpoint is continued from its file, which it is written back to.
    if path == "-"
        && (start.starts_with(edmd_core::CHECKPOINT_MAGIC)
            || edmd_core::pack::is_pack_checkpoint(start))
    {
        return Some(
            "-: an edmd checkpoint on standard input: a checkpoint is continued from its file (`edmd run FILE`, or `edmd pack FILE -o OUT` for a packing's)".to_string(),
        );
    }
    if start.starts_with(edmd_core::CHECKPOINT_MAGIC) {
        Some(format!(
            "{path}: an edmd run checkpoint, not a data file: `edmd run {path}` continues it"
        ))
    } else if edmd_core::pack::is_pack_checkpoint(start) {
        Some(format!(
            "{path}: an edmd packing checkpoint, not a data file: `edmd pack {path} -o OUT` continues it"
        ))
    } else {
        None
    }
}

/// Counts lines in valid text, refusing NUL bytes and over-long lines (the message naming the
/// line).
fn scan(path: &str, text: &[u8], line: &mut usize, line_len: &mut usize) -> Result<(), String> {
    for &b in text {
        match b {
            b'\n' => {
                *line += 1;
                *line_len = 0;
            }
            0 => return Err(format!("{path}:{line}: not a text file (NUL byte)")),
            _ => {
                *line_len += 1;
                if *line_len > MAX_LINE {
                    return Err(format!(
                        "{path}:{line}: the line is longer than {} KiB",
                        MAX_LINE / 1024
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The format to read `text` in (`None`: detect; a detected Princeton file is read with
/// `order`).
fn resolve(text: &str, format: Option<Format>, order: ColumnOrder) -> Format {
    match format.or_else(|| edmd_io::detect(text)) {
        Some(Format::Princeton(_)) => Format::Princeton(order),
        Some(f) => f,
        // Too short to tell: the Princeton reader names the problem (empty, bad count, ...).
        None => Format::Princeton(order),
    }
}

/// Parses a 2D file in `format` (`None`: detect; a detected Princeton file is read with
/// `order`); a 3D file is an error naming its `dim` line.
pub fn load(
    path: &str,
    text: &str,
    format: Option<Format>,
    order: ColumnOrder,
) -> Result<LoadedSystem> {
    edmd_io::parse(text, resolve(text, format, order))
        .or_else(|e| user_error(format!("{path}:{}: {}", e.line, e.message)))
}

/// [`load`] in the dimension the file declares (2, or 3 with `# edmd dim 3`).
pub fn load_any(
    path: &str,
    text: &str,
    format: Option<Format>,
    order: ColumnOrder,
) -> Result<AnyLoaded> {
    edmd_io::parse_any(text, resolve(text, format, order))
        .or_else(|e| user_error(format!("{path}:{}: {}", e.line, e.message)))
}

/// The seed of the reactions' draws when none is given (`edmd run` without `--seed`), the
/// thermostat's default too.
pub const DEFAULT_SEED: u64 = 1;

/// Builds the simulation, translating engine refusals into messages naming lines. The file's
/// reaction rules, if any, make its collisions reactive, their draws seeded with
/// [`DEFAULT_SEED`] ([`build_seeded`] takes another seed).
pub fn build<const D: usize>(
    path: &str,
    sys: &LoadedSystem<D>,
    options: Options,
) -> Result<Simulation<D>> {
    build_seeded(path, sys, options, DEFAULT_SEED)
}

/// [`build`] with `seed` for the reactions' draws (`edmd run --seed`).
pub fn build_seeded<const D: usize>(
    path: &str,
    sys: &LoadedSystem<D>,
    options: Options,
    seed: u64,
) -> Result<Simulation<D>> {
    let mut sim = build_hard(path, sys, options, true)?;
    set_interactions(path, sys, &mut sim, seed)?;
    Ok(sim)
}

/// [`build`], with or without the hint that `--allow-overlaps` runs a refused file (the
/// `particles` program has no such option, so it points to `edmd run` instead).
pub fn build_with_hint<const D: usize>(
    path: &str,
    sys: &LoadedSystem<D>,
    options: Options,
    allow_overlaps_option: bool,
) -> Result<Simulation<D>> {
    let mut sim = build_hard(path, sys, options, allow_overlaps_option)?;
    set_interactions(path, sys, &mut sim, DEFAULT_SEED)?;
    Ok(sim)
}

/// Gives `sim`, built from `sys` with its hard cores and potential, the rest of the file's
/// interactions, in the order the engine takes them: the reactions (their draws seeded with
/// `seed`), the field, the restitution, the shear, the ring and the self-gravity.
fn set_interactions<const D: usize>(
    path: &str,
    sys: &LoadedSystem<D>,
    sim: &mut Simulation<D>,
    seed: u64,
) -> Result<()> {
    set_reactions(path, sys, sim, seed)?;
    set_gravity(path, sys, sim)?;
    set_restitution(path, sys, sim)?;
    set_shear(path, sys, sim)?;
    set_ring(path, sys, sim)?;
    set_self_gravity(path, sys, sim)
}

/// Makes the collisions of `sim`, built from `sys`, reactive under the file's rules (nothing
/// without rules): their draws seeded with `seed`, and each species a rule makes coloured as
/// the first disc of that species in the file, or else by
/// `edmd_core::state::species_colour`. Rules with the swap rule or multi-disc collisions are
/// refused in one line naming the file.
pub fn set_reactions<const D: usize>(
    path: &str,
    sys: &LoadedSystem<D>,
    sim: &mut Simulation<D>,
    seed: u64,
) -> Result<()> {
    if sys.reactions.is_empty() {
        return Ok(());
    }
    let mut reactions = edmd_core::Reactions {
        rules: sys.reactions.clone(),
        seed,
        colours: Vec::new(),
    };
    reactions.fill_colours(sys.discs.iter().map(|d| (d.species, d.colour)));
    sim.set_reactions(Some(reactions))
        .or_else(|e| user_error(format!("{path}: {e} (the file's '# edmd reaction' lines)")))
}

/// Makes the collisions of `sim`, built from `sys`, inelastic under the file's restitution
/// (nothing without it). Restitution with the swap rule or multi-disc collisions is refused in
/// one line naming the file.
pub fn set_restitution<const D: usize>(
    path: &str,
    sys: &LoadedSystem<D>,
    sim: &mut Simulation<D>,
) -> Result<()> {
    if sys.restitution.is_none() {
        return Ok(());
    }
    sim.set_restitution(sys.restitution.clone()).or_else(|e| {
        user_error(format!(
            "{path}: {e} (the file's '# edmd restitution' lines)"
        ))
    })
}

/// Puts `sim`, built from `sys`, in the file's field (nothing without one). A field with
/// multi-disc collisions is refused in one line naming the file.
pub fn set_gravity<const D: usize>(
    path: &str,
    sys: &LoadedSystem<D>,
    sim: &mut Simulation<D>,
) -> Result<()> {
    if sys.gravity.is_none() {
        return Ok(());
    }
    sim.set_gravity(sys.gravity)
        .or_else(|e| user_error(format!("{path}: {e} (the file's '# edmd gravity' line)")))
}

/// Shears `sim`, built from `sys`, with the file's Lees-Edwards boundaries from its offset at
/// the file's time (nothing without them). Shear with multi-disc collisions, or at an offset
/// where the slid images overlap discs, is refused in one line naming the file.
pub fn set_shear<const D: usize>(
    path: &str,
    sys: &LoadedSystem<D>,
    sim: &mut Simulation<D>,
) -> Result<()> {
    if sys.shear.is_none() {
        return Ok(());
    }
    // A ring's shear comes from its own line.
    let line = if sys.ring.is_some() { "ring" } else { "shear" };
    sim.set_shear(sys.shear)
        .or_else(|e| user_error(format!("{path}: {e} (the file's '# edmd {line}' line)")))
}

/// Makes `sim`, built from `sys` and sheared by [`set_shear`] at the file's offset, the
/// file's ring patch (nothing without one), which keeps that offset. A ring with multi-disc
/// collisions is refused in one line naming the file.
pub fn set_ring<const D: usize>(
    path: &str,
    sys: &LoadedSystem<D>,
    sim: &mut Simulation<D>,
) -> Result<()> {
    if sys.ring.is_none() {
        return Ok(());
    }
    sim.set_ring(sys.ring)
        .or_else(|e| user_error(format!("{path}: {e} (the file's '# edmd ring' line)")))
}

/// Puts `sim`, built from `sys` at time 0, under the file's one-dimensional self-gravity
/// (nothing without it), each rod's rank its place from the left now, then sets its clock to
/// the file's time (which may lie beyond the clock limit of hard rods that short). Self-gravity
/// with the swap rule or multi-disc collisions is refused in one line naming the file.
pub fn set_self_gravity<const D: usize>(
    path: &str,
    sys: &LoadedSystem<D>,
    sim: &mut Simulation<D>,
) -> Result<()> {
    if sys.self_gravity.is_none() {
        return Ok(());
    }
    sim.set_self_gravity(sys.self_gravity).or_else(|e| {
        user_error(format!(
            "{path}: {e} (the file's '# edmd self-gravity' line)"
        ))
    })?;
    sim.start_at(sys.time)
        .or_else(|e| user_error(format!("{path}: {e} (the file's '# edmd time' line)")))
}

/// The simulation of the discs, box, barriers and potential of `sys`, without its reactions.
fn build_hard<const D: usize>(
    path: &str,
    sys: &LoadedSystem<D>,
    options: Options,
    allow_overlaps_option: bool,
) -> Result<Simulation<D>> {
    let (overlap_hint, outside_hint) = if allow_overlaps_option {
        (
            "--allow-overlaps runs it anyway",
            "--allow-overlaps moves them in",
        )
    } else {
        (
            "particles refuses it; 'edmd run --rule swap --allow-overlaps' runs it",
            "particles refuses it; 'edmd run --rule swap --allow-overlaps' moves them in",
        )
    };
    // Under self-gravity the clock has no limit, which the engine knows once the self-gravity
    // is set: such a file is built at time 0 and its clock set by [`set_self_gravity`].
    let t0 = if sys.self_gravity.is_some() {
        0.0
    } else {
        sys.time
    };
    let make = |options| {
        if sys.potential.is_hard() {
            Simulation::with_barriers_at(&sys.discs, sys.sim_box, &sys.barriers, options, t0)
        } else {
            Simulation::with_potential_at(
                &sys.discs,
                sys.sim_box,
                &sys.barriers,
                &sys.potential,
                options,
                t0,
            )
        }
    };
    let built = match make(options) {
        // The engine checks the discs against the plain periodic images, which a sheared
        // file's slid images replace: a state `edmd run` wrote at an offset can touch a plain
        // image across y. Its overlaps are those `set_shear` checks, at the file's offset.
        Err(EngineError::Overlap { .. })
            if sys.shear.is_some_and(|s| s.offset != 0.0)
                && options.overlaps == OverlapPolicy::Refuse =>
        {
            make(Options {
                overlaps: OverlapPolicy::Allow,
                ..options
            })
        }
        other => other,
    };
    built.or_else(|e| {
        user_error(refusal_at_line(
            path,
            &sys.lines,
            e,
            (overlap_hint, outside_hint),
        ))
    })
}

/// The engine's refusal of the discs read from `path` as one line naming the offending disc's
/// line in the file (`lines[i]` is disc `i`'s line; `0` when unknown); `hints` (for an overlap,
/// for a disc outside the box) end those two messages with what to do. `edmd run`, `render`,
/// `particles` and `pack` all say it this way.
pub fn refusal_at_line(
    path: &str,
    lines: &[usize],
    e: EngineError,
    (overlap_hint, outside_hint): (&str, &str),
) -> String {
    let line = |i: usize| lines.get(i).copied().unwrap_or(0);
    match e {
        EngineError::Overlap { i, j, overlap, count } => format!(
            "{path}:{}: this disc overlaps the disc on line {} by {overlap:.3e} of their contact distance ({count} overlapping pair(s) in all; {overlap_hint})",
            line(j),
            line(i)
        ),
        EngineError::OutsideBox { first, count } => format!(
            "{path}:{}: this disc is not inside the box ({count} such disc(s) in all; {outside_hint})",
            line(first)
        ),
        EngineError::BadDisc { index, what } => format!("{path}:{}: {what}", line(index)),
        EngineError::DiscFillsBox {
            index,
            axis,
            diameter,
            length,
        } => format!(
            "{path}:{}: diameter {diameter} does not fit in the box: it is not less than the box's {} length {length}, between walls (a disc that reaches from wall to wall cannot move)",
            line(index),
            ["x", "y", "z"].get(axis).unwrap_or(&"?")
        ),
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
    }
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
