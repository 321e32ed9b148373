//! Running the programs and finding the shared data.

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

/// Path of a file under `../shared/data/` (beside the repository: the course's public inputs
/// and Princeton's data files, which the project reads in place and does not ship), or `None`
/// when that folder is missing, as in a fresh clone on its own. Tests go through [`shared!`],
/// which then skips. With `EDMD_REQUIRE_SHARED=1` (CI) a missing file fails instead.
pub fn shared_data(rel: &str) -> Option<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data");
    let p = root.join(rel);
    if p.exists() {
        return Some(p);
    }
    let required = std::env::var_os("EDMD_REQUIRE_SHARED").is_some_and(|v| v == "1");
    assert!(
        !required && !root.exists(),
        "shared data file {} is missing (shared/ must sit beside the repository)",
        p.display()
    );
    None
}

/// `shared!("algs4/p10.txt")`: the path of a file under `../shared/data/`
/// ([`shared_data`]); when the folder is missing, a SKIPPED line and a return from the test.
macro_rules! shared {
    ($rel:expr) => {
        match crate::support::shared_data($rel) {
            Some(p) => p,
            None => {
                crate::support::skipped(
                    module_path!(),
                    &format!(
                        "../shared/data/{} is missing (the course's and Princeton's public data files sit beside the repository)",
                        $rel
                    ),
                );
                return;
            }
        }
    };
}
pub(crate) use shared;

/// The names of the entries of `dir`, sorted: what a command left in a folder.
pub fn names(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
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

/// Starts `edmd ARGS` in `dir`, sends it `signal` (`-TERM`, `-INT`, ...) after `wait`, and
/// returns the exit code, the seconds from the signal to the end, and standard error. Fails
/// if the command ended before the signal or is still running 5 s after it.
pub fn signalled(
    dir: &std::path::Path,
    args: &[&str],
    signal: &str,
    wait: std::time::Duration,
) -> (Option<i32>, f64, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_edmd"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(wait);
    assert!(
        child.try_wait().unwrap().is_none(),
        "{args:?} ended before the signal: make it longer"
    );
    let sent = std::time::Instant::now();
    assert!(Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if sent.elapsed() > std::time::Duration::from_secs(5) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{args:?} did not end within 5 s of {signal}");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    let seconds = sent.elapsed().as_secs_f64();
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    (status.code(), seconds, err)
}
