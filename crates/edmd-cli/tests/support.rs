//! Running the programs and finding the shared data.

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

/// Path of a file under `../shared/data/` (beside the repository), which tests read in place.
pub fn shared(rel: &str) -> PathBuf {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data")
        .join(rel);
    assert!(
        p.exists(),
        "shared data file {} is missing (shared/ must sit beside the repository)",
        p.display()
    );
    p
}

/// Path of one of the project's own example files.
pub fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/data")
        .join(name)
}

/// Runs a program with arguments (and optional standard input).
pub fn run(program: &str, args: &[&str], stdin: Option<&str>) -> Output {
    let exe = match program {
        "edmd" => env!("CARGO_BIN_EXE_edmd"),
        "particles" => env!("CARGO_BIN_EXE_particles"),
        _ => unreachable!(),
    };
    let mut cmd = Command::new(exe);
    cmd.args(args).stdin(if stdin.is_some() {
        Stdio::piped()
    } else {
        Stdio::null()
    });
    cmd.stdout(Stdio::piped()).stderr(Stdio::piped());
    let mut child = cmd.spawn().expect("program starts");
    if let Some(text) = stdin {
        use std::io::Write;
        child
            .stdin
            .take()
            .unwrap()
            .write_all(text.as_bytes())
            .unwrap();
    }
    child.wait_with_output().unwrap()
}

/// Standard output as text, asserting success.
pub fn ok_stdout(out: &Output) -> String {
    assert!(
        out.status.success(),
        "failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// Writes `text` to a file in `dir` and returns its path as a string.
pub fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> String {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

/// Says on standard error, past the test harness's capture, that a test did not run its checks.
/// Rust's test harness has no real skip: the test still counts as passed, so the line is the
/// only sign.
pub fn skipped(test: &str, why: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "SKIPPED {test}: {why}");
}

/// The one JSON object a successful `--json` run prints.
pub fn summary(out: &Output) -> serde_json::Value {
    serde_json::from_str(ok_stdout(out).trim()).expect("one JSON object")
}

/// Exit status 2 and one line on standard error containing every word of `words`.
pub fn refused(out: &Output, words: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    for w in words {
        assert!(err.contains(w), "{err:?} lacks {w:?}");
    }
}
