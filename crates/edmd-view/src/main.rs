//! `edmd-view`: the interactive viewer (see the `edmd_view` library for the options).

#![forbid(unsafe_code)]

fn main() -> std::process::ExitCode {
    edmd_view::main()
}
