//! Issue 24, classes 2 to 5: limits that held for a first leg but not on every path, carried
//! options refused even when given again unchanged, 2D words in 3D output, and measurement
//! files written into the current folder unasked.

use std::path::Path;

use crate::support::{example, names, ok_stdout, refused, run, summary};

/// `edmd ARGS` run in `dir`.
fn edmd_in(dir: &Path, args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_edmd"))
        .args(args)
        .current_dir(dir)
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap()
}

// Class 2. The 10^6-sample limit was checked against `--sample-every` on the first leg only: a
// checkpoint with measurements continued to a far `--until` kept every sample in memory
// without bound (here 1.001e6 samples, which the old code took, and wrote).
#[test]
fn continued_runs_keep_the_sample_limit_counted_from_the_start() {
    let dir = tempfile::tempdir().unwrap();
    let gas = example("gas-300.txt");
    let out = edmd_in(
        dir.path(),
        &[
            "run",
            gas.to_str().unwrap(),
            "--until",
            "1",
            "--measure",
            "temperature",
            "--sample-every",
            "0.001",
            "--checkpoint",
            "run.ck",
        ],
    );
    ok_stdout(&out);
    let continued = |until: &str| {
        edmd_in(
            dir.path(),
            &[
                "run",
                "run.ck",
                "--until",
                until,
                "-o",
                "out.txt",
                "--checkpoint",
                "next.ck",
                "--out-dir",
                "m",
            ],
        )
    };
    refused(
        &continued("1001"),
        &["run.ck", "1.001e6 samples", "at most 1000000", "1e3"],
    );
    assert_eq!(names(dir.path()), ["run.ck"]);
    // Within the limit, counted from the run's start (t = 0), it goes on.
    ok_stdout(&continued("999"));
}

// Class 2. A `--trajectory` of any size was started: frames x discs x bytes per line was never
// estimated (20 164 discs, 100 001 frames: about 2e11 bytes).
#[test]
fn trajectories_beyond_100_gb_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let side = 142;
    let mut text = format!("{}\n", side * side);
    for i in 0..side * side {
        let (x, y) = ((i % side) as f64 + 0.5, (i / side) as f64 + 0.5);
        let v = if i % 2 == 0 { 0.1 } else { -0.1 };
        text += &format!(
            "{:.6} {:.6} {v} {v} 0.001 1 0 0 0\n",
            x / side as f64,
            y / side as f64
        );
    }
    std::fs::write(dir.path().join("in.txt"), text).unwrap();
    let out = edmd_in(
        dir.path(),
        &[
            "run",
            "in.txt",
            "--until",
            "50000",
            "--trajectory",
            "t.xyz",
            "--every",
            "0.5",
            "-o",
            "out.txt",
        ],
    );
    refused(
        &out,
        &["--trajectory t.xyz", "100001 frames", "bytes", "100 GB"],
    );
    assert_eq!(names(dir.path()), ["in.txt"]);
    // From standard input too (the estimate does not need the file).
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_edmd"))
        .args([
            "run",
            "-",
            "--until",
            "50000",
            "--trajectory",
            "t.xyz",
            "--every",
            "0.5",
        ])
        .current_dir(dir.path())
        .stdin(std::fs::File::open(dir.path().join("in.txt")).unwrap())
        .output()
        .unwrap();
    refused(&out, &["--trajectory t.xyz", "bytes"]);
    assert_eq!(names(dir.path()), ["in.txt"]);
}

// Class 3. Continuing a checkpoint with the options it carries, given again unchanged (the
// command line run again after a crash), was refused; now only a different value is, with
// one line naming the option and both values. The same options give the same run.
#[test]
fn resuming_with_the_carried_options_is_accepted_and_a_different_one_named() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let gas = example("gas-300.txt");
    let gas = gas.to_str().unwrap();
    let course = example("course-7.txt");
    let course = course.to_str().unwrap();
    let first = [
        "--rule",
        "elastic",
        "--multi",
        "--format",
        "princeton",
        "--columns",
        "radius-mass",
        "--measure",
        "pressure",
        "--sample-every",
        "0.5",
    ];
    let ck = p("m.ck");
    let mut args = vec!["run", gas, "--until", "2", "--checkpoint", &ck];
    args.extend(first);
    ok_stdout(&run("edmd", &args, None));
    let bare = p("bare.txt");
    ok_stdout(&run(
        "edmd",
        &["run", &p("m.ck"), "--until", "4", "-o", &bare],
        None,
    ));
    let again = p("again.txt");
    let mut args = vec!["run", &ck, "--until", "4", "-o", &again];
    args.extend(first);
    args.push("--allow-overlaps");
    ok_stdout(&run("edmd", &args, None));
    assert_eq!(
        std::fs::read(&bare).unwrap(),
        std::fs::read(&again).unwrap()
    );
    // Different values, each named with both.
    for (option, given, carried) in [
        (&["--rule", "swap"][..], "--rule swap", "--rule elastic"),
        (
            &["--format", "course"][..],
            "--format course",
            "--format princeton",
        ),
        (
            &["--columns", "mass-radius"][..],
            "--columns mass-radius",
            "--columns radius-mass",
        ),
        (&["--measure", "speeds"][..], "--measure speeds", "pressure"),
        (
            &["--sample-every", "0.25"][..],
            "--sample-every 0.25",
            "0.5",
        ),
    ] {
        let mut args = vec!["run", ck.as_str(), "--until", "4"];
        args.extend(option);
        refused(&run("edmd", &args, None), &[given, carried]);
    }
    // A course file's checkpoint: the swap rule and the course format carried.
    ok_stdout(&run(
        "edmd",
        &["run", course, "--until", "1", "--checkpoint", &p("c.ck")],
        None,
    ));
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            &p("c.ck"),
            "--until",
            "2",
            "--rule",
            "swap",
            "--format",
            "course",
        ],
        None,
    ));
    refused(
        &run(
            "edmd",
            &["run", &p("c.ck"), "--until", "2", "--multi"],
            None,
        ),
        &["--multi", "binary collisions"],
    );
    refused(
        &run(
            "edmd",
            &[
                "run",
                &p("c.ck"),
                "--until",
                "2",
                "--columns",
                "radius-mass",
            ],
            None,
        ),
        &["--columns radius-mass", "course file"],
    );
}

// Class 4. The pressure measurement of a 3D run called the box's volume `area` and
// `effective_area` in its JSON.
#[test]
fn the_pressure_of_spheres_names_a_volume() {
    let spheres = example("spheres-500.txt");
    let gas = example("gas-300.txt");
    for (file, size) in [(&spheres, "volume"), (&gas, "area")] {
        let s = summary(&run(
            "edmd",
            &[
                "run",
                file.to_str().unwrap(),
                "--until",
                "1",
                "--measure",
                "pressure",
                "--json",
            ],
            None,
        ));
        let p = s["measurements"]["pressure"].as_object().unwrap();
        for other in ["area", "volume"].iter().filter(|w| **w != size) {
            assert!(!p.contains_key(*other), "{size}: {p:?}");
            assert!(
                !p.contains_key(&format!("effective_{other}")),
                "{size}: {p:?}"
            );
        }
        assert!(p[size].as_f64().unwrap() > 0.0, "{p:?}");
        assert!(p[&format!("effective_{size}")].as_f64().unwrap() > 0.0);
    }
}

// Class 5. `edmd run --measure` without `--out-dir` replaced `pressure.csv` (and the other
// measurement files) in the current folder, a file the user never named.
#[test]
fn measurements_write_no_file_unless_out_dir_is_given() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("pressure.csv"), "mine\n").unwrap();
    let gas = example("gas-300.txt");
    let out = edmd_in(
        dir.path(),
        &[
            "run",
            gas.to_str().unwrap(),
            "--until",
            "1",
            "--measure",
            "pressure,temperature",
        ],
    );
    let text = ok_stdout(&out);
    assert!(text.contains("no files written"), "{text}");
    assert_eq!(names(dir.path()), ["pressure.csv"]);
    assert_eq!(
        std::fs::read_to_string(dir.path().join("pressure.csv")).unwrap(),
        "mine\n"
    );
    let out = edmd_in(
        dir.path(),
        &[
            "run",
            gas.to_str().unwrap(),
            "--until",
            "1",
            "--measure",
            "pressure",
            "--out-dir",
            "m",
        ],
    );
    ok_stdout(&out);
    assert_eq!(names(&dir.path().join("m")), ["pressure.csv"]);
}

// A file of zero discs with `--measure speeds` (or `collisions`) panicked: the histograms'
// ranges came from the discs' speeds, and there were none.
#[test]
fn measurements_of_an_empty_system_do_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("none.txt"), "0\n").unwrap();
    for m in ["speeds", "collisions", "temperature,pressure,msd,species"] {
        let out = edmd_in(
            dir.path(),
            &["run", "none.txt", "--until", "1", "--measure", m, "--json"],
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{m}: {err}");
        assert!(out.status.success(), "{m}: {err}");
    }
}
