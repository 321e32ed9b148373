//! `edmd`: exact event-driven molecular dynamics of hard discs.

#![forbid(unsafe_code)]

use std::process::ExitCode;

use edmd::front::{exit_with, parse_args};
use edmd_cli::args::{Cli, Command};
use edmd_cli::commands;

fn main() -> ExitCode {
    let cli: Cli = match parse_args("edmd") {
        Ok(c) => c,
        Err(code) => return code,
    };
    // Before any work, so that a signal is never met by the default action (which would leave
    // temporary files): each of these looks at the stop flag in every loop (the experiments
    // choose for themselves: `jamming` stops at the packer's pace).
    if matches!(
        cli.command,
        Command::Run(_) | Command::Soak(_) | Command::Render(_) | Command::Experiment(_)
    ) {
        commands::experiment::common::install_ctrlc();
        if !matches!(cli.command, Command::Experiment(_)) {
            commands::experiment::common::stop_promptly();
        }
    }
    let result = match &cli.command {
        Command::Run(a) => commands::run::run(a),
        Command::Bench(a) => commands::bench::run(a),
        Command::Soak(a) => commands::soak::run(a),
        Command::Gen(a) => edmd::gen::run(a),
        Command::Pack(a) => commands::pack::run(a),
        Command::Render(a) => commands::render::run(a),
        Command::View { args } => return view(args),
        Command::Experiment(e) => commands::experiment::run(e),
    };
    exit_with("edmd", result)
}

/// `edmd view ...` runs the viewer, a separate program so that the GUI stack stays out of
/// this one: `edmd-view` next to this executable, or on the PATH.
fn view(args: &[String]) -> ExitCode {
    let beside = std::env::current_exe()
        .ok()
        .and_then(|p| p.parent().map(|d| d.join("edmd-view")));
    let program = beside
        .filter(|p| p.exists())
        .unwrap_or_else(|| "edmd-view".into());
    match std::process::Command::new(&program).args(args).status() {
        Ok(s) => ExitCode::from(s.code().unwrap_or(1).clamp(0, 255) as u8),
        Err(_) => {
            eprintln!("edmd: error: the viewer 'edmd-view' is not built: run 'cargo build --release -p edmd-view' (or use 'edmd render' to make a GIF)");
            ExitCode::from(2)
        }
    }
}
