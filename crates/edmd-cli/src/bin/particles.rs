//! `particles FILE T`: the "Collisions" course program.

#![forbid(unsafe_code)]

use std::process::ExitCode;

use edmd::front::{exit_with, parse_args};
use edmd_cli::commands::particles::{run, ParticlesArgs};

fn main() -> ExitCode {
    let args: ParticlesArgs = match parse_args("particles") {
        Ok(a) => a,
        Err(code) => return code,
    };
    exit_with("particles", run(&args, &mut std::io::stdout().lock()))
}
