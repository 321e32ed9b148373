//! Large absolute times. A state file carrying `# edmd time 1e16` ran with `--check`, exited 0
//! and wrote overlapping discs that edmd then refused: at such times floating-point times are
//! too far apart to place a disc at contact. A start time or an end time (`--until`) from the
//! clock's limit on is refused with the reason; below it a state written late reads back and
//! the chain goes on.

use crate::support::{ok_stdout, refused, run, write};

/// Two discs of Princeton's `p10.txt` size and speed (radius 0.02, speed 0.01) at `time`.
fn state_at(dir: &tempfile::TempDir, time: &str) -> String {
    write(
        dir,
        "late.txt",
        &format!(
            "2\n# edmd time {time}\n0.25 0.5 0.01 0 0.02 1 0 0 0\n0.75 0.5 -0.01 0.001 0.02 1 0 0 0\n"
        ),
    )
}

#[test]
fn start_and_end_times_beyond_the_clock_limit_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.txt");
    let out = out.to_str().unwrap();
    for t in ["1e13", "1e14", "1e15", "1e16", "1e17"] {
        let f = state_at(&dir, t);
        let until = format!("{}", t.parse::<f64>().unwrap() * 2.0);
        refused(
            &run(
                "edmd",
                &["run", &f, "--until", &until, "--check", "-o", out],
                None,
            ),
            &["late.txt", &format!("t = {t}"), "too late for the clock"],
        );
        assert!(!std::path::Path::new(out).exists());
    }
    // A state at t = 0 asked to run to 1e16, or to the largest finite time.
    let f = state_at(&dir, "0");
    for until in ["1e16", "1e308"] {
        refused(
            &run("edmd", &["run", &f, "--until", until, "-o", out], None),
            &["--until", "too late for the clock"],
        );
        assert!(!std::path::Path::new(out).exists());
    }
}

#[test]
fn a_state_written_at_a_late_time_chains() {
    let dir = tempfile::tempdir().unwrap();
    let f = state_at(&dir, "1e6");
    let a = dir.path().join("a.txt");
    let b = dir.path().join("b.txt");
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "1000100",
            "--check",
            "-o",
            a.to_str().unwrap(),
        ],
        None,
    ));
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            a.to_str().unwrap(),
            "--until",
            "1000200",
            "--check",
            "-o",
            b.to_str().unwrap(),
        ],
        None,
    ));
    let text = std::fs::read_to_string(&b).unwrap();
    assert!(text.contains("# edmd time 1000200"), "{text}");
}
