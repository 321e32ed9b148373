//! `edmd`: exact event-driven molecular dynamics of hard discs.

use std::process::ExitCode;

use edmd_cli::args::{Cli, Command};
use edmd_cli::{commands, exit_with, parse_args};

fn main() -> ExitCode {
    let cli: Cli = match parse_args("edmd") {
        Ok(c) => c,
        Err(code) => return code,
    };
    let result = match &cli.command {
        Command::Run(a) => commands::run::run(a),
        Command::Bench(a) => commands::bench::run(a),
        Command::Gen(a) => commands::gen::run(a),
        Command::Experiment(e) => commands::experiment::run(e),
    };
    exit_with("edmd", result)
}
