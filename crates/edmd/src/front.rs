//! What every command-line front door shares (`edmd`, `particles`, `edmd-view`): usage
//! errors in one line, the exit statuses (0 done, 1 an internal error, 2 a user's mistake,
//! [`crate::INTERRUPTED_STATUS`] stopped by a signal), and standard output that survives a
//! closed pipe.

use std::process::ExitCode;

use crate::{is_user_error, Interrupted, INTERRUPTED_STATUS};

/// Prints a line on standard output. A closed pipe (`edmd ... | head`) is not an error: the
/// reader has what it wanted, so the program ends quietly instead of panicking like
/// `println!`.
pub fn print_line(text: &str) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = writeln!(out, "{text}").and_then(|_| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to standard output: {e}");
        std::process::exit(1);
    }
}

/// Runs a command body and turns its outcome into an exit status, printing errors in one line.
pub fn exit_with(program: &str, result: anyhow::Result<()>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e)
            if e.downcast_ref::<std::io::Error>()
                .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe) =>
        {
            // The reader went away (`particles f 10 | head`): it has what it wanted.
            ExitCode::SUCCESS
        }
        Err(e) if e.downcast_ref::<Interrupted>().is_some() => {
            eprintln!("{program}: {}", error_line(&e));
            ExitCode::from(INTERRUPTED_STATUS)
        }
        Err(e) => {
            let user = is_user_error(&e);
            eprintln!("{program}: error: {}", error_line(&e));
            ExitCode::from(if user { 2 } else { 1 })
        }
    }
}

/// An error and its causes on one line, its numbers short (see [`shorten_numbers`]).
fn error_line(e: &anyhow::Error) -> String {
    shorten_numbers(&format!("{e:#}").replace('\n', " "))
}

/// Numbers written out in full by `{}` (1e300 as 301 digits, 1e-300 as 300 zeros and a one)
/// in a message, whoever wrote it, shortened to Rust's `{:?}` form (`1e300`), which reads back
/// to the same number.
pub fn shorten_numbers(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut digits = String::new();
    let flush = |digits: &mut String, out: &mut String| {
        let significant = digits.trim_start_matches(['0', '.']).len();
        match digits.parse::<f64>() {
            Ok(x) if (significant > 20 || digits.len() > 24) && x.is_finite() => {
                out.push_str(&format!("{x:?}"))
            }
            _ => out.push_str(digits),
        }
        digits.clear();
    };
    for c in message.chars() {
        if c.is_ascii_digit() || (c == '.' && !digits.is_empty() && !digits.contains('.')) {
            digits.push(c);
        } else {
            flush(&mut digits, &mut out);
            out.push(c);
        }
    }
    flush(&mut digits, &mut out);
    out
}

/// Parses command-line arguments with clap; usage errors become one line and exit status 2,
/// `--help` and `--version` print as usual and exit 0.
pub fn parse_args<P: clap::Parser>(program: &str) -> Result<P, ExitCode> {
    match P::try_parse() {
        Ok(p) => Ok(p),
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                let _ = e.print();
                return Err(
                    if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                        ExitCode::from(2)
                    } else {
                        ExitCode::SUCCESS
                    },
                );
            }
            let args = std::env::args_os()
                .map(|a| a.to_string_lossy().into_owned())
                .collect();
            let message =
                hyphen_value::<P>(&e, args).unwrap_or_else(|| one_line(&e.render().to_string()));
            eprintln!("{program}: error: {message} (try '{program} --help')");
            Err(ExitCode::from(2))
        }
    }
}

/// clap reads a value that starts with '-' and is no plain number (`--packing -inf`,
/// `--dim -1` where negatives are not allowed, `--activation -0,0`) as an unknown option, and
/// says only "unexpected argument '-i'". When the word before it is an option that takes a
/// value, this says which option and how to give it such a value.
fn hyphen_value<P: clap::CommandFactory>(e: &clap::Error, args: Vec<String>) -> Option<String> {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if e.kind() != ErrorKind::UnknownArgument {
        return None;
    }
    let Some(ContextValue::String(bad)) = e.get(ContextKind::InvalidArg) else {
        return None;
    };
    fn find(c: &clap::Command, name: &str) -> bool {
        c.get_arguments()
            .any(|a| a.get_long() == Some(name) && a.get_action().takes_values())
            || c.get_subcommands().any(|s| find(s, name))
    }
    let command = P::command();
    let takes_value = |name: &str| find(&command, name);
    args.windows(2).find_map(|w| {
        let (option, value) = (&w[0], &w[1]);
        let name = option.strip_prefix("--")?;
        // A word that starts with "--" is an option given where a value was due (a value
        // forgotten, an option misspelt), not a value.
        let is_value = value.starts_with(bad.as_str()) && !value.starts_with("--");
        (is_value && !name.contains('=') && takes_value(name)).then(|| {
            format!("{option} {value}: a value that starts with '-' reads as an option; write {option}={value}")
        })
    })
}

/// clap's message without the usage block, folded into one line.
fn one_line(rendered: &str) -> String {
    let body: Vec<&str> = rendered
        .lines()
        .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    body.join(" ").trim_start_matches("error: ").to_string()
}

#[cfg(test)]
mod tests {
    use super::shorten_numbers;

    #[test]
    fn long_numbers_are_shortened_and_short_ones_kept() {
        let big = format!("found {} and {}", 1e300, 1e-300);
        assert_eq!(shorten_numbers(&big), "found 1e300 and 1e-300");
        // What a user reads as written stays: counts, times, file lines.
        let plain = "line 12: 0.000001 is 1000000 times 3.14159265358979, 65536 discs.";
        assert_eq!(shorten_numbers(plain), plain);
        // Digits that are not a number Rust reads are kept as they are.
        assert_eq!(shorten_numbers("v1.2.3"), "v1.2.3");
    }
}
