//! `particles FILE T`: the "Collisions" course program.
//!
//! Reads the course format, processes every collision with time `<= T` using the swap rule,
//! advances every disc to `T` and prints `x, y, wall_collisions, disc_collisions` per disc with
//! the course's `printf("%.6f, %.6f, %d, %d\n", ...)` (Rust's `{:.6}` rounds like C's `%.6f`).

use std::io::Write;

use anyhow::{Context, Result};
use clap::Parser;
use edmd_core::{CollisionCounter, CollisionRule, Options, OverlapPolicy};
use edmd_io::Format;

use crate::args::parse_time;
use edmd::input::{build_with_hint, load, read_text};

/// The course program: simulate N equal discs in a box up to time T.
#[derive(Debug, Parser)]
#[command(name = "particles", version)]
pub struct ParticlesArgs {
    /// Input file in the course format (N, R, Lx Ly, then x y u v per disc).
    pub file: String,
    /// End time.
    #[arg(value_parser = parse_time, allow_negative_numbers = true)]
    pub end_time: f64,
}

/// Runs the course program, writing its lines to `out`.
pub fn run(args: &ParticlesArgs, out: &mut impl Write) -> Result<()> {
    let text = read_text(&args.file)?;
    let sys = load(&args.file, &text, Some(Format::Course), Default::default())?;
    let mut sim = build_with_hint(
        &args.file,
        &sys,
        Options {
            rule: CollisionRule::Swap,
            overlaps: OverlapPolicy::Refuse,
            multi: None,
        },
        false,
    )?;
    let mut counter = CollisionCounter::new(sim.len());
    edmd::run_until(&mut sim, args.end_time, &mut counter).with_context(|| args.file.clone())?;
    let mut buf = String::with_capacity(48 * sim.len());
    for i in 0..sim.len() {
        let p = sim.position(i);
        buf += &format!(
            "{:.6}, {:.6}, {}, {}\n",
            p[0], p[1], counter.wall[i], counter.disc[i]
        );
    }
    out.write_all(buf.as_bytes())?;
    out.flush()?;
    Ok(())
}
