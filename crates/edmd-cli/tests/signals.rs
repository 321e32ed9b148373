//! A signal must stop every long command within about a second, with one exit status, 130:
//! an experiment over a long span (`edmd experiment demon --until 1e7`) looks at the stop flag
//! inside the span, and `run`, `render`, `soak` and the experiments all end with 130, a
//! signal before a command installed its handler included.

use std::time::Duration;

use crate::support::{example, names, signalled};

#[test]
fn every_long_command_stops_on_sigterm_with_status_130_and_no_temporary_file() {
    let gas = example("gas-300.txt");
    let gas = gas.to_str().unwrap();
    // (what, arguments, what the last line must say, files left in the folder)
    let cases: [(&str, Vec<&str>, &str, &[&str]); 6] = [
        (
            "run",
            vec![
                "run",
                gas,
                "--until",
                "5e6",
                "-o",
                "out.txt",
                "--trajectory",
                "t.xyz",
                "--every",
                "5e3",
            ],
            "nothing written",
            &[],
        ),
        (
            "run, continued after a checkpoint",
            vec![
                "run",
                gas,
                "--until",
                "5e6",
                "--checkpoint",
                "run.ck",
                "--checkpoint-every",
                "500",
            ],
            "checkpoint at t = ",
            &["run.ck"],
        ),
        ("soak", vec!["soak"], "soak: interrupted", &[]),
        (
            "an experiment with a huge span",
            vec![
                "experiment",
                "demon",
                "--until",
                "1e7",
                "--samples",
                "1",
                "--out-dir",
                "out",
            ],
            "results so far are written",
            &["out"],
        ),
        (
            // Stopped while following the first model's balls: it once said "the results so
            // far are written (wrote: )".
            "billiards, stopped before its first result",
            vec![
                "experiment",
                "billiards",
                "--follow",
                "1e6",
                "--out-dir",
                "out",
            ],
            "nothing written",
            &[],
        ),
        (
            "render",
            vec![
                "render",
                gas,
                "-o",
                "movie.gif",
                "--until",
                "5e6",
                "--fps",
                "1",
                "--time-scale",
                "1e6",
            ],
            "nothing written",
            &[],
        ),
    ];
    for (what, args, says, left) in cases {
        let dir = tempfile::tempdir().unwrap();
        let (code, seconds, err) =
            signalled(dir.path(), &args, "-TERM", Duration::from_millis(1500));
        assert_eq!(code, Some(130), "{what}: {err}");
        let last = err.trim_end().lines().last().unwrap_or_default();
        assert!(
            last.contains("interrupted") && last.contains(says),
            "{what}: {err}"
        );
        assert_eq!(names(dir.path()), left, "{what}: {seconds} s");
        if what.starts_with("an experiment") {
            let out = names(&dir.path().join("out"));
            assert_eq!(out, ["demon.csv", "demon.png", "demon.svg"], "{what}");
        }
    }
}
