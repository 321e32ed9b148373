//! Regression tests for the defects of the issue tracker, one test per thing that broke. Each
//! header says what it was.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use crate::support::{example, names, run, shared, signalled, write};

const P10_LINE: &str = "0.5 0.5 0.01 0 0.05 1 1 2 3";

/// Asserts exit status 2 with one line on standard error containing `expect`, and no panic.
fn refused_with(out: &std::process::Output, expect: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(expect), "expected {expect:?} in {err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// A small Princeton file that ships with the project, for the tests of options and outputs.
fn gas() -> String {
    example("gas-300.txt").to_string_lossy().into_owned()
}

/// True when this process may not create files in `/dev`, so that a regression of the device
/// fix fails with an error instead of replacing a system device by a regular file (as root,
/// the old code turned `/dev/null` and `/dev/full` into regular files). As root the device
/// tests print a SKIPPED line and pass: Rust's test harness has no real skip.
fn devices_safe_to_test(test: &str) -> bool {
    let probe = Path::new("/dev").join(format!(".edmd-probe-{}", std::process::id()));
    if std::fs::File::create(&probe).is_ok() {
        let _ = std::fs::remove_file(&probe);
        crate::support::skipped(
            test,
            "/dev is writable (root?), and a regression would replace system devices",
        );
        return false;
    }
    true
}

fn is_char_device(p: &str) -> bool {
    use std::os::unix::fs::FileTypeExt;
    std::fs::metadata(p).unwrap().file_type().is_char_device()
}

// 1. `-o /dev/full` turned /dev/full into a regular file (exit 0): the temporary file was
// renamed over the device.
#[test]
fn output_to_dev_full_is_a_write_error_and_keeps_the_device() {
    if !Path::new("/dev/full").exists()
        || !devices_safe_to_test("output_to_dev_full_is_a_write_error_and_keeps_the_device")
    {
        return;
    }
    let out = run(
        "edmd",
        &["run", &gas(), "--until", "1", "-o", "/dev/full"],
        None,
    );
    refused_with(&out, "/dev/full: cannot write");
    assert!(is_char_device("/dev/full"));
    let out = run("edmd", &["gen", "single", "-o", "/dev/full"], None);
    refused_with(&out, "/dev/full: cannot write");
    assert!(is_char_device("/dev/full"));
}

// 1. `-o /dev/null` (run and gen) replaced /dev/null by a regular file.
#[test]
fn output_to_dev_null_keeps_the_device() {
    if !devices_safe_to_test("output_to_dev_null_keeps_the_device") {
        return;
    }
    let out = run(
        "edmd",
        &["run", &gas(), "--until", "1", "-o", "/dev/null"],
        None,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(is_char_device("/dev/null"));
    let out = run("edmd", &["gen", "single", "-o", "/dev/null"], None);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(is_char_device("/dev/null"));
}

// 1. A FIFO given as the output was replaced by a regular file instead of written through.
#[test]
fn output_to_a_fifo_is_written_through() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        crate::support::skipped(
            "output_to_a_fifo_is_written_through",
            "mkfifo is not available",
        );
        return;
    }
    let (tx, rx) = std::sync::mpsc::channel();
    {
        let fifo = fifo.clone();
        // Blocks until a writer opens the FIFO; the old code never did (it replaced the FIFO).
        std::thread::spawn(move || tx.send(std::fs::read_to_string(fifo).unwrap()));
    }
    let out = run(
        "edmd",
        &["gen", "single", "-o", fifo.to_str().unwrap()],
        None,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = rx
        .recv_timeout(Duration::from_secs(30))
        .expect("nothing was written into the FIFO");
    assert!(text.starts_with('1'), "{text:?}");
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    assert_eq!(names(dir.path()), ["pipe"]);
}

// 1. A symbolic link given as the output was replaced by a file, its target left untouched.
#[test]
fn output_through_a_symlink_writes_the_target_and_keeps_the_link() {
    let dir = tempfile::tempdir().unwrap();
    let target = write(&dir, "target.txt", "old\n");
    let link = dir.path().join("link.txt");
    std::os::unix::fs::symlink("target.txt", &link).unwrap();
    let out = run(
        "edmd",
        &["run", &gas(), "--until", "1", "-o", link.to_str().unwrap()],
        None,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    let text = std::fs::read_to_string(&target).unwrap();
    assert!(text.starts_with("300\n"), "{text}");
    assert_eq!(names(dir.path()), ["link.txt", "target.txt"]);
}

// 2. `--trajectory` naming the input file replaced the input.
#[test]
fn trajectory_onto_the_input_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "in.txt", &format!("1\n{P10_LINE}\n"));
    let out = run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "1",
            "--trajectory",
            &f,
            "--every",
            "0.5",
        ],
        None,
    );
    refused_with(&out, "would overwrite the input");
    assert_eq!(
        std::fs::read_to_string(&f).unwrap(),
        format!("1\n{P10_LINE}\n")
    );
}

// 2. `-o md/temperature.csv --measure temperature --measure-dir md` had the CSV file overwrite
// the final state.
#[test]
fn output_and_a_measurement_file_of_the_same_name_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let md = dir.path().join("md");
    let out = run(
        "edmd",
        &[
            "run",
            &gas(),
            "--until",
            "1",
            "-o",
            md.join("temperature.csv").to_str().unwrap(),
            "--measure",
            "temperature",
            "--measure-dir",
            md.to_str().unwrap(),
        ],
        None,
    );
    refused_with(&out, "name the same file");
    assert!(!md.exists());
}

// 2. An input inside the measurement folder under a measurement's name was overwritten.
#[test]
fn input_named_like_a_measurement_file_is_not_overwritten() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "speeds.csv", &format!("1\n{P10_LINE}\n"));
    let out = run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "1",
            "--measure",
            "speeds",
            "--measure-dir",
            dir.path().to_str().unwrap(),
        ],
        None,
    );
    refused_with(&out, "would overwrite the input");
    assert_eq!(
        std::fs::read_to_string(&f).unwrap(),
        format!("1\n{P10_LINE}\n")
    );
}

// 3. SIGTERM during `run` left `.out.txt.edmd-PID.tmp` and `.traj.xyz.edmd-PID.tmp`.
#[test]
fn sigterm_during_run_leaves_no_temporary_files() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.txt");
    std::fs::copy(shared!("algs4/p2000.txt"), &input).unwrap();
    let (code, _, _) = signalled(
        dir.path(),
        &[
            "run",
            "in.txt",
            "--until",
            "5e5",
            "-o",
            "out.txt",
            "--trajectory",
            "traj.xyz",
            "--every",
            "100",
        ],
        "-TERM",
        Duration::from_millis(1500),
    );
    assert_ne!(code, Some(0));
    assert_eq!(names(dir.path()), ["in.txt"]);
}

// 3. `render` on SIGINT or SIGTERM left its temporary GIF or a folder of partial frames.
#[test]
fn signals_during_render_leave_no_partial_output() {
    for (signal, out) in [
        ("-TERM", "movie.gif"),
        ("-INT", "movie.gif"),
        ("-TERM", "frames/"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        std::fs::copy(shared!("algs4/p2000.txt"), dir.path().join("in.txt")).unwrap();
        let (code, _, _) = signalled(
            dir.path(),
            &[
                "render", "in.txt", "-o", out, "--until", "3000", "--fps", "25",
            ],
            signal,
            Duration::from_millis(1500),
        );
        assert_ne!(code, Some(0), "{signal} {out}");
        assert_eq!(names(dir.path()), ["in.txt"], "{signal} {out}");
    }
}

// SIGTERM during `render` was heeded only between frames: with frames far apart in simulated
// time (`p2000.txt --until 500000 --fps 1 --time-scale 50000`, 18 s a frame in a release
// build) the program went on for the rest of the frame.
#[test]
fn sigterm_during_a_long_render_frame_stops_within_seconds() {
    for out in ["movie.gif", "frames/"] {
        let dir = tempfile::tempdir().unwrap();
        std::fs::copy(shared!("algs4/p2000.txt"), dir.path().join("in.txt")).unwrap();
        let (code, _, err) = signalled(
            dir.path(),
            &[
                "render",
                "in.txt",
                "-o",
                out,
                "--until",
                "500000",
                "--fps",
                "1",
                "--time-scale",
                "50000",
            ],
            "-TERM",
            Duration::from_millis(1000),
        );
        assert_ne!(code, Some(0), "{out}");
        assert!(err.contains("interrupted"), "{out}: {err}");
        assert_eq!(names(dir.path()), ["in.txt"], "{out}");
    }
}

// 4. `--until 7.4e17` or `--fps 1e300` overflowed the frame count: "0 frames", a 39-byte GIF,
// exit 0.
#[test]
fn render_frame_count_overflow_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let gif = dir.path().join("f.gif");
    let p = gas();
    for extra in [["--until", "7.4e17"], ["--fps", "1e300"]] {
        let mut args = vec!["render", &p, "-o", gif.to_str().unwrap()];
        args.extend(extra);
        if extra[0] != "--until" {
            args.extend(["--until", "1"]);
        }
        let out = run("edmd", &args, None);
        refused_with(&out, "frames is too many");
        assert!(!gif.exists());
    }
}

// 5. `edmd run /dev/zero` grew to 3 GB and `/dev/urandom` kept reading past the first invalid
// byte.
#[test]
fn endless_binary_input_stops_at_the_first_bad_byte() {
    for (dev, what) in [
        ("/dev/zero", "/dev/zero:1: not a text file"),
        ("/dev/urandom", "/dev/urandom:"),
    ] {
        if !Path::new(dev).exists() {
            continue;
        }
        let out = run("edmd", &["run", dev, "--until", "1"], None);
        refused_with(&out, what);
    }
}

// 5. A line longer than 64 KiB was read whole, however long.
#[test]
fn overlong_line_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "long.txt", &format!("1\n{}\n", "1".repeat(70_000)));
    let out = run("edmd", &["run", &f, "--until", "1"], None);
    refused_with(&out, "long.txt:2: the line is longer than 64 KiB");
}

// 5. Options that cost without bound: `--sample-every 1e-9` (2.3 GB), `brownian --samples 1e9`
// (7.8 GB), `gen dense --n 1`, `--packing 1e-300` in gen, bench and the experiments (never
// finished), `mfp --measure 0` (NaN CSV files, exit 0).
#[test]
fn unbounded_options_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let f = dir.path().join("x.txt");
    let fs = f.to_str().unwrap();
    let p = gas();
    let cases: &[(&[&str], &str)] = &[
        (
            &[
                "run",
                &p,
                "--until",
                "1",
                "--measure",
                "temperature",
                "--sample-every",
                "1e-9",
            ],
            "--sample-every must be >= 1e-6",
        ),
        (
            &[
                "run",
                &p,
                "--until",
                "1",
                "--trajectory",
                fs,
                "--every",
                "1e-9",
            ],
            "--every must be >= 1e-6",
        ),
        (
            &[
                "experiment",
                "brownian",
                "--samples",
                "1000000000",
                "--out-dir",
                d,
            ],
            "--samples must be from 40 to 100000",
        ),
        (
            &["gen", "dense", "--n", "1", "-o", fs],
            "--n must be from 2",
        ),
        (
            &["gen", "fluid", "--packing", "1e-300", "-o", fs],
            "packing fraction 1e-300 is below 0.001",
        ),
        (
            &["bench", "--n", "100", "--packing", "1e-300"],
            "packing fraction 1e-300 is outside [0.001,",
        ),
        (
            &["experiment", "eos", "--packing", "1e-300", "--out-dir", d],
            "outside [0.001,",
        ),
        (
            &["experiment", "mfp", "--packing", "1e-300", "--out-dir", d],
            "outside [0.001,",
        ),
        (
            &[
                "experiment",
                "maxwell",
                "--packing",
                "1e-300",
                "--out-dir",
                d,
            ],
            "outside [0.001,",
        ),
        (
            &["experiment", "mfp", "--measure", "0", "--out-dir", d],
            "--collisions must be from 1",
        ),
    ];
    for (args, expect) in cases {
        let out = run("edmd", args, None);
        refused_with(&out, expect);
    }
    assert!(!f.exists());
    assert!(names(dir.path()).is_empty(), "{:?}", names(dir.path()));
}

// 6. A `#` comment line before N broke format detection.
#[test]
fn comment_before_the_count_keeps_the_format() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(
        &dir,
        "c.txt",
        "# my comment\n2\n0.25 0.5 0.01 0 0.05 1 1 2 3\n0.75 0.5 -0.01 0 0.05 1 1 2 3\n",
    );
    let out = run("edmd", &["run", &f, "--until", "1", "--json"], None);
    let text = crate::support::ok_stdout(&out);
    assert!(text.contains("\"format\":\"princeton\""), "{text}");
}

// 6. Two `# edmd box` lines, or two contradictory `boundary` lines, were silently accepted.
#[test]
fn repeated_box_and_boundary_lines_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(
        &dir,
        "b.txt",
        &format!("1\n# edmd box 2 2\n# edmd box 3 3\n{P10_LINE}\n"),
    );
    refused_with(
        &run("edmd", &["run", &f, "--until", "1"], None),
        "b.txt:3: a second '# edmd box' line",
    );
    let f = write(
        &dir,
        "c.txt",
        &format!("1\n# edmd boundary walls\n# edmd boundary periodic\n{P10_LINE}\n"),
    );
    refused_with(
        &run("edmd", &["run", &f, "--until", "1"], None),
        "c.txt:3: a second '# edmd boundary' line",
    );
}

// 6. `--json -o -` mixed the JSON summary and the state on standard output; `--trajectory -`
// made a file named `-`.
#[test]
fn json_with_state_on_stdout_and_trajectory_dash_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = gas();
    let out = run(
        "edmd",
        &["run", &p, "--until", "1", "--json", "-o", "-"],
        None,
    );
    refused_with(&out, "--json and --output -");
    assert!(out.stdout.is_empty());
    let out = Command::new(env!("CARGO_BIN_EXE_edmd"))
        .args([
            "run",
            &p,
            "--until",
            "1",
            "--trajectory",
            "-",
            "--every",
            "0.5",
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    refused_with(&out, "--trajectory -");
    assert!(names(dir.path()).is_empty());
}

// 6. `render -o out.png` made a folder of frames, and `-o /` wrote frames into `/`.
#[test]
fn render_output_must_be_gif_mp4_or_a_frame_folder() {
    let dir = tempfile::tempdir().unwrap();
    let p = gas();
    for name in ["out.png", "out.txt", "out.avi"] {
        let o = dir.path().join(name);
        let out = run(
            "edmd",
            &["render", &p, "-o", o.to_str().unwrap(), "--until", "0.1"],
            None,
        );
        refused_with(&out, "give NAME.gif, NAME.mp4, or a folder");
    }
    let out = run("edmd", &["render", &p, "-o", "/", "--until", "0.1"], None);
    refused_with(&out, "the frame folder is not empty");
    assert!(names(dir.path()).is_empty());
    // A new folder given with a slash still works.
    let frames = dir.path().join("frames/");
    let out = run(
        "edmd",
        &[
            "render",
            &p,
            "-o",
            frames.to_str().unwrap(),
            "--until",
            "0.04",
            "--fps",
            "25",
            "--size",
            "32x32",
        ],
        None,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(names(&frames), ["frame_000000.png", "frame_000001.png"]);
}

// 6. Negative option values were taken for flags (`billiards --gap -0.5`, `--sample-every -1`).
#[test]
fn negative_option_values_get_the_allowed_range() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let out = run(
        "edmd",
        &["experiment", "billiards", "--gap", "-0.5", "--out-dir", d],
        None,
    );
    refused_with(&out, "--gap must be in [0, 0.04)");
    let p = gas();
    let out = run(
        "edmd",
        &[
            "run",
            &p,
            "--until",
            "1",
            "--measure",
            "temperature",
            "--sample-every",
            "-1",
        ],
        None,
    );
    refused_with(&out, "must be > 0, found -1");
}

// 6. `bench --n 2 --packing 0.5` exited with status 1, not 2.
#[test]
fn bench_too_small_a_box_is_a_user_error() {
    let out = run("edmd", &["bench", "--n", "2", "--packing", "0.5"], None);
    refused_with(&out, "bench:");
}

// 6. `particles`' messages suggested `--allow-overlaps`, which it refuses.
#[test]
fn particles_does_not_suggest_an_option_it_lacks() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "o.txt", "2\n0.1\n1 1\n0.5 0.5 0 0\n0.55 0.5 0 0\n");
    let out = run("particles", &[&f, "1"], None);
    refused_with(&out, "edmd run --rule swap --allow-overlaps");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("; --allow-overlaps"), "{err}");
}

// 6. A failed experiment left an empty output folder behind.
#[test]
fn failed_experiment_removes_the_folder_it_created() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("new");
    let out = run(
        "edmd",
        &[
            "experiment",
            "brownian",
            "--n",
            "20000",
            "--until",
            "1",
            "--out-dir",
            o.to_str().unwrap(),
        ],
        None,
    );
    refused_with(&out, "brownian:");
    assert!(!o.exists());
}

// 7. `run --measure` took a list of measurements while `experiment --measure` took a number of
// collisions, and the folder was `--measure-dir` in one place and `--out-dir` in the other.
// Now: `--collisions N` and `--out-dir DIR` everywhere; the old spellings still work.
#[test]
fn run_and_experiments_spell_their_options_alike() {
    let dir = tempfile::tempdir().unwrap();
    let m = dir.path().join("m");
    let p = gas();
    let out = run(
        "edmd",
        &[
            "run",
            &p,
            "--until",
            "1",
            "--measure",
            "temperature",
            "--out-dir",
            m.to_str().unwrap(),
        ],
        None,
    );
    crate::support::ok_stdout(&out);
    assert!(m.join("temperature.csv").exists());
    for flag in ["--collisions", "--measure"] {
        let e = dir.path().join(flag.trim_start_matches('-'));
        let out = run(
            "edmd",
            &[
                "experiment",
                "mfp",
                "--packing",
                "0.2",
                "--n",
                "100",
                flag,
                "20",
                "--json",
                "--out-dir",
                e.to_str().unwrap(),
            ],
            None,
        );
        crate::support::ok_stdout(&out);
    }
}

// 7. `edmd experiment mfp` read 1-2.5% low by default: 50 collisions per disc leave the long
// flights still in progress at the end uncounted.
#[test]
fn mfp_default_reads_within_one_percent_of_enskog() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(
        "edmd",
        &[
            "experiment",
            "mfp",
            "--json",
            "--out-dir",
            dir.path().to_str().unwrap(),
        ],
        None,
    );
    let v: serde_json::Value = serde_json::from_str(&crate::support::ok_stdout(&out)).unwrap();
    for r in v["results"].as_array().unwrap() {
        let ratio =
            r["mean_free_path"].as_f64().unwrap() / r["enskog_mean_free_path"].as_f64().unwrap();
        assert!((ratio - 1.0).abs() < 0.01, "{r}");
    }
}

// 6. `--columns` was silently ignored on course files.
#[test]
fn columns_on_a_course_file_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "c.txt", "1\n0.1\n1 1\n0.5 0.5 0.1 0\n");
    let out = run(
        "edmd",
        &["run", &f, "--until", "1", "--columns", "mass-radius"],
        None,
    );
    refused_with(&out, "--columns applies to the Princeton format");
    // Without --columns the file runs.
    crate::support::ok_stdout(&run("edmd", &["run", &f, "--until", "1"], None));
}

// 7. `edmd run` on a course-format file used the elastic rule unless told `--rule swap`, so by
// default it disagreed with `particles` on the same file. The course file's own rule (swap) is
// now the default for course files.
#[test]
fn run_on_a_course_file_agrees_with_particles_by_default() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.txt");
    let normal = shared!("assignment/normal.txt");
    let normal = normal.to_str().unwrap();
    crate::support::ok_stdout(&run(
        "edmd",
        &["run", normal, "--until", "20", "-o", out.to_str().unwrap()],
        None,
    ));
    let particles = crate::support::ok_stdout(&run("particles", &[normal, "20"], None));
    let state = std::fs::read_to_string(&out).unwrap();
    // The state file: N, R, "Lx Ly", then "x y u v" per disc; particles: "x, y, walls, discs".
    let discs: Vec<&str> = state.lines().skip(3).collect();
    assert_eq!(discs.len(), particles.lines().count());
    for (d, p) in discs.iter().zip(particles.lines()) {
        let xy: Vec<f64> = d
            .split_whitespace()
            .take(2)
            .map(|x| x.parse().unwrap())
            .collect();
        assert_eq!(
            format!("{:.6}, {:.6}", xy[0], xy[1]),
            p.splitn(3, ", ").take(2).collect::<Vec<_>>().join(", ")
        );
    }
    // The elastic rule is still there when asked for, and it ends elsewhere.
    crate::support::ok_stdout(&run(
        "edmd",
        &[
            "run",
            normal,
            "--until",
            "20",
            "--rule",
            "elastic",
            "-o",
            out.to_str().unwrap(),
        ],
        None,
    ));
    assert_ne!(std::fs::read_to_string(&out).unwrap(), state);
}

// 7. A restarted run (`edmd run state.txt --until 50`) started its clock at 0 again. The state
// file now carries its time (`# edmd time T`), a run from it starts there, `--until` is the
// absolute end time, and chained runs report the true time.
#[test]
fn chained_runs_keep_the_true_time() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let gas = crate::support::example("gas-300.txt");
    let json = |args: &[&str]| -> serde_json::Value {
        serde_json::from_str(crate::support::ok_stdout(&run("edmd", args, None)).trim()).unwrap()
    };
    json(&[
        "run",
        gas.to_str().unwrap(),
        "--until",
        "5",
        "-o",
        &p("a.txt"),
        "--json",
    ]);
    assert!(std::fs::read_to_string(p("a.txt"))
        .unwrap()
        .contains("# edmd time 5"));
    let traj = p("t.xyz");
    let s = json(&[
        "run",
        &p("a.txt"),
        "--until",
        "8",
        "-o",
        &p("b.txt"),
        "--json",
        "--trajectory",
        &traj,
        "--every",
        "1",
    ]);
    assert_eq!(s["until"], 8.0);
    assert!(std::fs::read_to_string(p("b.txt"))
        .unwrap()
        .contains("# edmd time 8"));
    // Frames at the absolute times 5, 6, 7, 8.
    let frames = std::fs::read_to_string(&traj).unwrap();
    let times: Vec<&str> = frames
        .lines()
        .filter_map(|l| l.split("Time=").nth(1))
        .map(|t| t.split_whitespace().next().unwrap())
        .collect();
    assert_eq!(times, ["5.0", "6.0", "7.0", "8.0"], "{times:?}");
    refused_with(
        &run("edmd", &["run", &p("b.txt"), "--until", "7"], None),
        "the state is at t = 8",
    );
    // `render` too: the film of a.txt (t = 5) to t = 6 at 2 frames per unit of time has the
    // frames 5, 5.5 and 6, not 13 frames from 0.
    refused_with(
        &run(
            "edmd",
            &["render", &p("b.txt"), "--until", "7", "-o", &p("f.gif")],
            None,
        ),
        "the state is at t = 8",
    );
    let frames = p("frames/");
    crate::support::ok_stdout(&run(
        "edmd",
        &[
            "render",
            &p("a.txt"),
            "--until",
            "6",
            "--fps",
            "2",
            "--size",
            "64x64",
            "-o",
            &frames,
        ],
        None,
    ));
    assert_eq!(std::fs::read_dir(&frames).unwrap().count(), 3);
}

/// Runs `program ARGS` in `dir` with its address space limited to `mb` megabytes, and fails
/// unless it ends within `secs` seconds. Standard output and error go to files in `dir`
/// (`.stdout`, `.stderr`), read back into the returned output.
fn within(dir: &Path, program: &str, args: &[&str], mb: u64, secs: u64) -> std::process::Output {
    let exe = match program {
        "edmd" => env!("CARGO_BIN_EXE_edmd"),
        _ => env!("CARGO_BIN_EXE_particles"),
    };
    let (out, err) = (dir.join(".stdout"), dir.join(".stderr"));
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {} && exec \"$0\" \"$@\"", mb * 1024))
        .arg(exe)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + Duration::from_secs(secs);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{program} {args:?} did not end within {secs} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let read = |p: &Path| {
        let b = std::fs::read(p).unwrap();
        std::fs::remove_file(p).unwrap();
        b
    };
    std::process::Output {
        status,
        stdout: read(&out),
        stderr: read(&err),
    }
}

// 10. Two discs in `# edmd box 1 1e18` took 4.2 GB (walls) or 12.6 GB (periodic) in the cell
// grid, and a course file with box `15.1 1e20` 4.2 GB: the long axis got about 10^9 cells. Each
// run here must now finish within 20 s in 256 MB of address space.
#[test]
fn long_thin_boxes_run_in_little_memory() {
    let dir = tempfile::tempdir().unwrap();
    let two = "0.5 0.5 0 1 0.01 1 0 0 0\n0.5 10 0 -1 0.01 1 0 0 0\n";
    let two_3d = "0.5 0.5 0.5 0 0 1 0.01 1 0 0 0\n0.5 0.5 10 0 0 -1 0.01 1 0 0 0\n";
    let files = [
        write(&dir, "walls.txt", &format!("2\n# edmd box 1 1e18\n{two}")),
        write(
            &dir,
            "periodic.txt",
            &format!("2\n# edmd box 1 1e18\n# edmd boundary periodic\n{two}"),
        ),
        write(
            &dir,
            "walls3.txt",
            &format!("2\n# edmd dim 3\n# edmd box 1 1 1e18\n{two_3d}"),
        ),
        write(
            &dir,
            "periodic3.txt",
            &format!("2\n# edmd dim 3\n# edmd box 1 1e18 1e18\n# edmd boundary periodic\n{two_3d}"),
        ),
        write(
            &dir,
            "course.txt",
            "2\n0.5\n15.1 1e20\n1 1 0 1\n5 10 0 -1\n",
        ),
    ];
    for f in &files {
        let out = within(
            dir.path(),
            "edmd",
            &["run", f, "--until", "20", "-o", "out.txt"],
            256,
            20,
        );
        assert!(
            out.status.success(),
            "{f}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(dir.path().join("out.txt").exists(), "{f}");
    }
    let out = within(dir.path(), "particles", &[&files[4], "20"], 256, 20);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        text,
        "1.000000, 21.000000, 0, 0\n5.000000, 11.000000, 1, 0\n"
    );
}

// 10. A disc of radius exactly half the box (Princeton `0.5 0.5 0.01 0 0.5 ...`, or `particles`
// on the course file `1 / 0.5 / 1 1 / 0.5 0.5 0.1 0`) never ended: its wall collisions were all
// at one instant. Refused now, naming the line.
#[test]
fn disc_filling_the_box_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "half.txt", "1\n0.5 0.5 0.01 0 0.5 1 50 50 50\n");
    let c = write(&dir, "half_course.txt", "1\n0.5\n1 1\n0.5 0.5 0.1 0\n");
    let out = within(
        dir.path(),
        "edmd",
        &["run", &p, "--until", "1", "-o", "out.txt"],
        256,
        20,
    );
    refused_with(&out, "half.txt:2: diameter 1 does not fit in the box");
    let out = within(dir.path(), "particles", &[&c, "1"], 256, 20);
    refused_with(
        &out,
        "half_course.txt:4: diameter 1 does not fit in the box",
    );
    assert_eq!(names(dir.path()), ["half.txt", "half_course.txt"]);
}

// 10. A 20 x 20 square lattice of touching discs filling the box, or a column of touching discs
// filling its height, never ended: the clock stopped at t = 0. Now `run`, `render` and
// `particles` stop within seconds with one line naming the discs, exit status 2, and write
// nothing.
#[test]
fn runs_whose_clock_stops_fail_naming_the_discs() {
    let dir = tempfile::tempdir().unwrap();
    let mut lattice = String::from("400\n# edmd box 20 20\n");
    for k in 0..400 {
        let (i, j) = ((k / 20) as f64, (k % 20) as f64);
        let (u, v) = (
            ((i * 7.0 + j * 3.0) % 5.0) - 2.0,
            ((i * 3.0 + j) % 3.0) - 1.0,
        );
        lattice += &format!("{} {} {u} {v} 0.5 1 0 0 0\n", 0.5 + i, 0.5 + j);
    }
    let mut column = String::from("10\n# edmd box 5 10\n");
    let mut course = String::from("10\n0.5\n5 10\n");
    for k in 0..10 {
        let v = 0.3 - 0.1 * k as f64;
        column += &format!("2.5 {} 0 {v} 0.5 1 0 0 0\n", 0.5 + k as f64);
        course += &format!("2.5 {} 0 {v}\n", 0.5 + k as f64);
    }
    let lattice = write(&dir, "lattice.txt", &lattice);
    let column = write(&dir, "column.txt", &column);
    let course = write(&dir, "course.txt", &course);
    for f in [&lattice, &column] {
        let out = within(
            dir.path(),
            "edmd",
            &[
                "run",
                f,
                "--until",
                "10",
                "-o",
                "out.txt",
                "--trajectory",
                "t.xyz",
                "--every",
                "0.5",
            ],
            256,
            30,
        );
        refused_with(&out, "the clock stopped advancing at t = 0");
        refused_with(&out, "among discs 0, 1, 2");
        refused_with(&out, "nothing written");
    }
    let out = within(
        dir.path(),
        "edmd",
        &["render", &column, "--until", "2", "-o", "movie.gif"],
        512,
        30,
    );
    refused_with(&out, "the clock stopped advancing at t = 0");
    let out = within(dir.path(), "particles", &[&course, "10"], 256, 30);
    refused_with(&out, "the clock stopped advancing at t = 0");
    assert!(out.stdout.is_empty());
    assert_eq!(
        names(dir.path()),
        ["column.txt", "course.txt", "lattice.txt"]
    );
}

// 10, found again by a review: the same lattice and column of touching discs with
// random velocities (radius 0.025 in the unit box) collide across gaps of rounding size, so the
// clock crept (1e-12 after 8 million events) and `run` and `particles` never finished. They now
// stop as the runs above do.
#[test]
fn runs_whose_clock_creeps_fail_naming_the_discs() {
    let dir = tempfile::tempdir().unwrap();
    let mut x: u64 = 7;
    let mut random = || {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let (mut lattice, mut course) = (String::from("400\n"), String::from("400\n0.025\n1 1\n"));
    for k in 0..400 {
        let (i, j) = ((k / 20) as f64, (k % 20) as f64);
        let (u, v) = (random(), random());
        let (px, py) = (0.025 + 0.05 * i, 0.025 + 0.05 * j);
        lattice += &format!("{px} {py} {u} {v} 0.025 1 0 0 0\n");
        course += &format!("{px} {py} {u} {v}\n");
    }
    let lattice = write(&dir, "lattice.txt", &lattice);
    let course = write(&dir, "course.txt", &course);
    let out = within(
        dir.path(),
        "edmd",
        &["run", &lattice, "--until", "10", "-o", "out.txt"],
        256,
        30,
    );
    refused_with(&out, "the clock stopped advancing at t = ");
    refused_with(&out, "moved it by next to nothing, among discs");
    refused_with(&out, "nothing written");
    let out = within(dir.path(), "particles", &[&course, "10"], 256, 30);
    refused_with(&out, "the clock stopped advancing at t = ");
    assert!(out.stdout.is_empty());
    assert_eq!(names(dir.path()), ["course.txt", "lattice.txt"]);
}

// 11. With multi-disc collisions, a light disc pinched between two discs 10^12 times heavier
// ran the contact integrator for ever (found by fuzzing). Now the run stops at once with one
// line saying why, exit status 2, and writes nothing.
#[test]
fn multi_disc_collisions_at_extreme_mass_ratios_fail_saying_why() {
    let dir = tempfile::tempdir().unwrap();
    let pinch = write(
        &dir,
        "pinch.txt",
        "3\n# edmd box 10 10\n\
         3 5 1 0 0.5 1e12 0 0 0\n\
         4 5 0 0 0.5 1 0 0 0\n\
         5 5 -1 0 0.5 1e12 0 0 0\n",
    );
    let out = within(
        dir.path(),
        "edmd",
        &["run", &pinch, "--until", "10", "--multi", "-o", "out.txt"],
        256,
        30,
    );
    refused_with(
        &out,
        "a multi-disc collision at t = 0 did not end within 10000000 contact steps, among discs 0, 1, 2",
    );
    refused_with(&out, "nothing written");
    assert_eq!(names(dir.path()), ["pinch.txt"]);
}

/// Found by a new user's walk through 3D : an output that could never be
/// written was found only when it was written, after the work: `-o newdir/` (a folder that
/// does not exist, by its trailing `/`) after the whole run; `--checkpoint newd/` or a
/// checkpoint in a missing folder when the first one fell due (for `edmd pack`, never in a
/// short run, and with all the work lost at Ctrl-C); and `--out-dir` naming a file after the
/// run, with the other outputs written and left behind (exit status 2). Each is now refused
/// before any work, with nothing written.
#[test]
fn outputs_that_could_never_be_written_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let input = write(&dir, "in.txt", &format!("1\n{P10_LINE}\n"));
    let (out, ck, xyz) = (d("out.txt"), d("ck.ck"), d("t.xyz"));
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<String>>();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            s(&["run", &input, "--until", "5", "-o", &d("newdir/")]),
            "--output names a folder",
        ),
        (
            s(&[
                "run",
                &input,
                "--until",
                "5",
                "-o",
                &out,
                "--checkpoint",
                &d("newd/"),
            ]),
            "--checkpoint names a folder",
        ),
        (
            s(&[
                "run",
                &input,
                "--until",
                "5",
                "-o",
                &out,
                "--checkpoint",
                &d("nod/ck"),
            ]),
            "--checkpoint is in a folder that does not exist",
        ),
        (
            s(&[
                "run",
                &input,
                "--until",
                "5",
                "-o",
                &out,
                "--trajectory",
                &d("nod/t.xyz"),
                "--every",
                "1",
            ]),
            "--trajectory is in a folder that does not exist",
        ),
        (
            s(&[
                "run",
                &input,
                "--until",
                "5",
                "-o",
                &out,
                "--checkpoint",
                &ck,
                "--trajectory",
                &xyz,
                "--every",
                "1",
                "--measure",
                "pressure",
                "--out-dir",
                &input,
            ]),
            "--out-dir names a file, not a folder",
        ),
        (
            // Inside a file: the folder could never be made.
            s(&[
                "run",
                &input,
                "--until",
                "5",
                "-o",
                &out,
                "--checkpoint",
                &ck,
                "--measure",
                "pressure",
                "--out-dir",
                &format!("{input}/m"),
            ]),
            "--out-dir: the folder cannot be made",
        ),
        (
            // The state file's own name: the folder could not be made once it was written.
            s(&[
                "run",
                &input,
                "--until",
                "5",
                "-o",
                &out,
                "--measure",
                "pressure",
                "--out-dir",
                &out,
            ]),
            "--out-dir names the file --output writes",
        ),
        (
            s(&[
                "gen",
                "fluid",
                "--dim",
                "3",
                "--n",
                "100",
                "-o",
                &d("newd/"),
            ]),
            "--output names a folder",
        ),
        (
            s(&[
                "pack",
                "--dim",
                "3",
                "--n",
                "100",
                "-o",
                &out,
                "--checkpoint",
                &d("nod/p.ck"),
            ]),
            "--checkpoint is in a folder that does not exist",
        ),
        (
            s(&[
                "pack",
                "--dim",
                "3",
                "--n",
                "100",
                "-o",
                &dir.path().to_string_lossy(),
            ]),
            "-o names a folder",
        ),
    ];
    for (args, expect) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let result = run("edmd", &args, None);
        refused_with(&result, expect);
        assert_eq!(names(dir.path()), ["in.txt"], "{args:?}");
    }
    // A folder that exists, with a file name in it, is fine.
    std::fs::create_dir(d("sub")).unwrap();
    let ok = run(
        "edmd",
        &[
            "run",
            &input,
            "--until",
            "1",
            "-o",
            &d("sub/out.txt"),
            "--checkpoint",
            &d("sub/ck"),
        ],
        None,
    );
    assert_eq!(
        ok.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
}

/// Found by a new user's walk through 3D : `edmd render` drew a 3D file's
/// slice when given both `--view` and `--slice`, and a 2D file as always when given `--view`,
/// saying nothing of the option it dropped. Both are now refused before any work.
#[test]
fn render_options_that_cannot_both_apply_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("frames/").to_string_lossy().into_owned();
    let spheres = crate::support::example("spheres-500.txt");
    let discs = crate::support::example("gas-300.txt");
    let render = |file: &Path, extra: &[&str]| {
        let mut args = vec!["render", file.to_str().unwrap(), "-o", &out, "--until", "0"];
        args.extend_from_slice(extra);
        run("edmd", &args, None)
    };
    refused_with(
        &render(&spheres, &["--view", "30,20", "--slice", "z=3"]),
        "render: --view and --slice are two ways to draw a 3D file: give one",
    );
    refused_with(
        &render(&discs, &["--view", "30,20"]),
        "render: --view applies to 3D files, and this one is 2D",
    );
    assert!(!dir.path().join("frames").exists());
    let one = render(&spheres, &["--view", "40,10"]);
    assert_eq!(
        one.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&one.stderr)
    );
    assert!(String::from_utf8_lossy(&one.stdout).starts_with("1 frame of "));
}

/// Found by a new user's walk through 3D : the limit of a million frames,
/// samples or checkpoints was counted from t = 0, so a file at `# edmd time 1000000` could not
/// be run to 1000010 with frames every 0.5 (20 frames). It is now counted from the run's start.
#[test]
fn frame_limits_count_from_the_start_of_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let late = write(
        &dir,
        "late.txt",
        &format!("# edmd time 1000000\n1\n{P10_LINE}\n"),
    );
    let xyz = dir.path().join("t.xyz").to_string_lossy().into_owned();
    let go = |every: &str| {
        run(
            "edmd",
            &[
                "run",
                &late,
                "--until",
                "1000010",
                "--trajectory",
                &xyz,
                "--every",
                every,
                "-o",
                "-",
            ],
            None,
        )
    };
    let ok = go("0.5");
    assert_eq!(
        ok.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let frames = std::fs::read_to_string(&xyz).unwrap();
    assert_eq!(frames.lines().filter(|l| l.contains("Time=")).count(), 21);
    refused_with(
        &go("0.000001"),
        "--every 1e-6: 1.000e7 trajectory frames from t = 1000000 to 1000010 is too many",
    );
    // A film of the same file says when it starts: at the file's time, not at 0.
    let frames = dir.path().join("frames/").to_string_lossy().into_owned();
    let film = run(
        "edmd",
        &["render", &late, "--until", "1000001", "-o", &frames],
        None,
    );
    let said = String::from_utf8_lossy(&film.stdout);
    assert!(
        said.contains("frames of 480x480 written to") && said.contains("(t = 1000000 to 1000001)"),
        "{said}{}",
        String::from_utf8_lossy(&film.stderr)
    );
}

// `--kt 1e300` was echoed as its 301 digits, `--kt 1e-300` as 300 zeros and a one: every
// message's numbers are now written short, as they read back.
#[test]
fn numbers_in_messages_are_written_short() {
    for (kt, shown) in [("1e300", "found 1e300"), ("1e-300", "found 1e-300")] {
        let out = run(
            "edmd",
            &["experiment", "square-well", "--kt", kt, "--density", "0.1"],
            None,
        );
        crate::support::refused(&out, &["--kt", shown]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("0000000000"), "{err}");
    }
    // An experiment's human summary too (`to t = 0.000...0001` with 308 zeros).
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let out = run(
        "edmd",
        &[
            "experiment",
            "diffusion",
            "--n",
            "20",
            "--until",
            "1e-308",
            "--samples",
            "5",
            "--out-dir",
            d,
        ],
        None,
    );
    let said = crate::support::ok_stdout(&out);
    assert!(
        said.contains("1e-308") && !said.contains("0000000000"),
        "{said}"
    );
}
