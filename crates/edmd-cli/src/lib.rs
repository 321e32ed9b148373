//! # edmd-cli: the `edmd` and `particles` programs
//!
//! The command-line front door over the [`edmd`] library: clap's grammar of the commands and
//! their options ([`args`]), and each command's body ([`commands`]), which checks the options
//! against each other, calls the library, shows progress and prints the summary. Errors in what
//! the user gave are [`edmd::UserError`]s: one line on standard error and exit status 2
//! ([`edmd::front::exit_with`]). Nothing is written before everything has been validated, and
//! output files appear whole or not at all ([`edmd::output::AtomicFile`]).

#![forbid(unsafe_code)]

pub mod args;
pub mod commands;
