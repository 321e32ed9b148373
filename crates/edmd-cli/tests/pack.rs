//! `edmd pack`: a packing written by the command, its JSON summary, `edmd run` reading it, and
//! refusals of bad options (one line, exit status 2, no output file).

use crate::support::{ok_stdout, refused, run, shared, summary};

#[test]
fn a_packing_is_summarised_and_runs_in_edmd_run() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("glass.txt");
    let f = f.to_str().unwrap();
    let pack = |out: &str| {
        run(
            "edmd",
            &[
                "pack",
                "--dim",
                "3",
                "--n",
                "200",
                "--packing",
                "0.55",
                "--seed",
                "3",
                "-o",
                out,
                "--json",
            ],
            None,
        )
    };
    let s = summary(&pack(f));
    for key in [
        "packing_fraction",
        "reduced_pressure",
        "rattlers",
        "mean_contacts",
        "gap_tolerance",
        "wall_seconds",
        "collisions",
        "dim",
        "n",
        "growth_rate",
        "seed",
    ] {
        assert!(s.get(key).is_some(), "{key} missing from {s}");
    }
    assert_eq!(s["dim"], 3);
    assert_eq!(s["n"], 200);
    assert_eq!(s["stop"], "packing");
    assert!((s["packing_fraction"].as_f64().unwrap() - 0.55).abs() < 1e-12);
    let text = std::fs::read_to_string(f).unwrap();
    assert!(text.starts_with("200\n# edmd dim 3\n"), "{}", &text[..40]);
    // The same seed writes the same file.
    let again = dir.path().join("again.txt");
    ok_stdout(&pack(again.to_str().unwrap()));
    assert_eq!(std::fs::read_to_string(&again).unwrap(), text);
    // `edmd run` reads it and runs it, checking overlaps at the end.
    let out = run(
        "edmd",
        &["run", f, "--until", "0.05", "--check", "--json"],
        None,
    );
    summary(&out);
    // Packing on from the file to jamming.
    let jammed = dir.path().join("jammed.txt");
    let s = summary(&run(
        "edmd",
        &[
            "pack",
            f,
            "--pressure",
            "1e9",
            "-o",
            jammed.to_str().unwrap(),
            "--json",
        ],
        None,
    ));
    assert!(s["reduced_pressure"].as_f64().unwrap() >= 1e9);
    assert!(s["packing_fraction"].as_f64().unwrap() > 0.6);
}

#[test]
fn bad_pack_options_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("p.txt");
    let f = f.to_str().unwrap();
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["pack", "--n", "100", "--growth-rate", "0", "-o", f],
            &["growth"],
        ),
        (
            &["pack", "--n", "100", "--growth-rate", "3", "-o", f],
            &["growth rate"],
        ),
        (&["pack", "-o", f], &["--n"]),
        (
            &[
                "pack",
                "--n",
                "100",
                "--size-ratio",
                "1.4",
                "--polydispersity",
                "0.1",
                "-o",
                f,
            ],
            &["exclude"],
        ),
        (
            &["pack", "--n", "100", "--polydispersity", "0.9", "-o", f],
            &["polydispersity"],
        ),
        (
            &[
                "pack",
                "--n",
                "100",
                "--packing",
                "1.5",
                "-o",
                f,
                "--dim",
                "3",
            ],
            &["--packing"],
        ),
        (
            &["pack", "--n", "100", "--dim", "4", "-o", f],
            &["dimension"],
        ),
        (&["pack", "missing.txt", "-o", f], &["missing.txt"]),
        (
            &["pack", "--n", "100", "-o", "-", "--json"],
            &["standard output"],
        ),
    ];
    for (args, words) in cases {
        let out = run("edmd", args, None);
        refused(&out, words);
        assert!(!std::path::Path::new(f).exists(), "{args:?} wrote a file");
    }
}

/// The summary without what depends on the clock or the output's name.
fn steady(mut s: serde_json::Value) -> serde_json::Value {
    let m = s.as_object_mut().unwrap();
    for k in ["wall_seconds", "collisions_per_second", "output"] {
        assert!(m.remove(k).is_some(), "{k} missing");
    }
    s
}

/// `--checkpoint-every 0` checkpoints at every rescaling, so the last checkpoint is the last
/// rescaling before the stop: continued from it (in place), the packing file and the summary
/// are those of the run never stopped, byte for byte.
#[test]
fn a_packing_continued_from_its_checkpoint_is_the_uninterrupted_one_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    for start in [
        &["--n", "80", "--size-ratio", "1.4", "--pressure", "1e7"][..],
        &[
            "--dim",
            "3",
            "--n",
            "60",
            "--boundary",
            "walls",
            "--pressure",
            "1e7",
        ],
    ] {
        let whole = p("whole.txt");
        let mut args = vec!["pack", "--seed", "4", "-o", &whole, "--json"];
        args.extend_from_slice(start);
        let s_whole = steady(summary(&run("edmd", &args, None)));
        let (part, ck) = (p("part.txt"), p("ck"));
        let mut args = vec!["pack", "--seed", "4", "-o", &part, "--json"];
        args.extend_from_slice(start);
        args.extend_from_slice(&["--checkpoint", &ck, "--checkpoint-every", "0"]);
        summary(&run("edmd", &args, None));
        assert!(std::fs::read(&ck).unwrap().starts_with(b"EDMDPACK"));
        let cont = p("cont.txt");
        let s_cont = steady(summary(&run(
            "edmd",
            &["pack", &ck, "--checkpoint", &ck, "-o", &cont, "--json"],
            None,
        )));
        assert_eq!(s_cont, s_whole);
        assert!(std::fs::read(&cont).unwrap() == std::fs::read(&whole).unwrap());
    }
}

/// Ctrl-C writes a checkpoint at the next rescaling and ends with one line, leaving no
/// temporary file; two legs stopped so and a third to the end give the packing of the run
/// never stopped, byte for byte (wherever the signals land).
#[test]
fn ctrl_c_checkpoints_and_a_chain_of_continuations_is_the_uninterrupted_run() {
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let start = [
        "--n",
        "300",
        "--size-ratio",
        "1.4",
        "--pressure",
        "1e10",
        "--seed",
        "2",
    ];
    let whole = p("whole.txt");
    let mut args = vec!["pack", "-o", &whole];
    args.extend_from_slice(&start);
    ok_stdout(&run("edmd", &args, None));
    let (ck, out) = (p("ck"), p("out.txt"));
    let mut interrupted = 0;
    for leg in 0..3 {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_edmd"));
        cmd.arg("pack");
        if leg == 0 {
            cmd.args(start);
        } else {
            cmd.arg(&ck);
        }
        cmd.args(["--checkpoint", &ck, "--checkpoint-every", "0", "-o", &out])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        let before = std::fs::metadata(&ck).and_then(|m| m.modified()).ok();
        let child = cmd.spawn().unwrap();
        if leg < 2 {
            // Once the leg has written a checkpoint of its own, stop it.
            let t = Instant::now();
            while t.elapsed() < Duration::from_secs(60) {
                let now = std::fs::metadata(&ck).and_then(|m| m.modified()).ok();
                if now.is_some() && now != before {
                    break;
                }
                std::thread::sleep(Duration::from_millis(20));
            }
            Command::new("kill")
                .args(["-INT", &child.id().to_string()])
                .status()
                .unwrap();
        }
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains("panicked"), "{err}");
        if o.status.success() {
            // The leg ended before the signal came: it wrote the packing.
            break;
        }
        interrupted += 1;
        assert!(
            err.contains("interrupted") && err.contains("continues it"),
            "{err}"
        );
        let mut left: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, ["ck", "whole.txt"], "leg {leg}: {err}");
    }
    assert!(interrupted > 0, "no leg was interrupted");
    assert!(std::fs::read(&out).unwrap() == std::fs::read(&whole).unwrap());
}

/// Options a checkpoint carries, damaged checkpoints, and a checkpoint of the other kind: one
/// line and exit status 2, no output written.
#[test]
fn bad_packing_checkpoints_and_options_beside_them_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let (ck, out) = (p("ck"), p("out.txt"));
    ok_stdout(&run(
        "edmd",
        &[
            "pack",
            "--n",
            "40",
            "--pressure",
            "1e5",
            "-o",
            &out,
            "--checkpoint",
            &ck,
            "--checkpoint-every",
            "0",
        ],
        None,
    ));
    std::fs::remove_file(&out).unwrap();
    for (flag, carried) in [
        (&["--n", "41"][..], "40"),
        (&["--dim", "3"], "2"),
        (&["--growth-rate", "0.01"], "0.02"),
        (&["--pressure", "1e6"], "1e5"),
        (&["--packing", "0.5"], "none"),
        (&["--seed", "3"], "1"),
        (&["--boundary", "walls"], "periodic"),
        (&["--size-ratio", "1.4"], "1"),
        (&["--polydispersity", "0.1"], "other sizes"),
    ] {
        let mut args = vec!["pack", &ck, "-o", &out];
        args.extend_from_slice(flag);
        refused(
            &run("edmd", &args, None),
            &["carried by the checkpoint", flag[0], flag[1], carried],
        );
    }
    let good = std::fs::read(&ck).unwrap();
    let bad = p("bad");
    let mut newer = good.clone();
    newer[8] += 1;
    let mut flipped = good.clone();
    flipped[good.len() / 2] ^= 0x10;
    for (bytes, words) in [
        (good[..good.len() / 3].to_vec(), &["truncated"][..]),
        (flipped, &["corrupted"]),
        (newer, &["newer"]),
    ] {
        std::fs::write(&bad, &bytes).unwrap();
        refused(&run("edmd", &["pack", &bad, "-o", &out], None), words);
    }
    // A packing checkpoint given to `edmd run`, and a run's to `edmd pack`.
    refused(
        &run("edmd", &["run", &ck, "--until", "1", "-o", &out], None),
        &["packing checkpoint", "edmd pack"],
    );
    let run_ck = p("run.ck");
    let state = p("state.txt");
    std::fs::write(&state, "1\n0.5 0.5 0.1 0 0.1 1 0 0 0\n").unwrap();
    ok_stdout(&run(
        "edmd",
        &["run", &state, "--until", "1", "--checkpoint", &run_ck],
        None,
    ));
    refused(
        &run("edmd", &["pack", &run_ck, "-o", &out], None),
        &["run checkpoint", "edmd run"],
    );
    assert!(!std::path::Path::new(&out).exists());
}

// A start file with a disc outside the box or two overlapping discs was refused as "disc 0 is
// outside the box" or "discs 9 and 10 overlap", without the file or the line; and
// `--packing 1e-300` was printed as a 300-digit decimal.
#[test]
fn a_refused_start_names_its_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.txt");
    let out = out.to_str().unwrap();
    for (file, words) in [
        (
            "algs4/billiards-overflow.txt",
            &["billiards-overflow.txt:5: this disc is not inside the box"][..],
        ),
        (
            "algs4/diffusion3.txt",
            &["diffusion3.txt:12: this disc overlaps the disc on line 11"][..],
        ),
    ] {
        let f = shared!(file);
        refused(
            &run("edmd", &["pack", f.to_str().unwrap(), "-o", out], None),
            words,
        );
        assert!(!std::path::Path::new(out).exists());
    }
    let out = run(
        "edmd",
        &["pack", "--n", "10", "--packing", "1e-300", "-o", out],
        None,
    );
    refused(&out, &["1e-300"]);
    assert!(String::from_utf8_lossy(&out.stderr).len() < 200);
}

/// An output that cannot be created is refused before the compression, not after it (a
/// compression may take hours): here a checkpoint at every rescaling would be on disc if the
/// compression had run.
#[test]
fn an_unwritable_output_is_refused_before_the_compression() {
    let dir = tempfile::tempdir().unwrap();
    let ck = dir.path().join("pack.ck");
    let out = dir.path().join("no-such-folder").join("glass.txt");
    let o = run(
        "edmd",
        &[
            "pack",
            "--n",
            "200",
            "--checkpoint",
            ck.to_str().unwrap(),
            "--checkpoint-every",
            "0",
            "-o",
            out.to_str().unwrap(),
        ],
        None,
    );
    refused(
        &o,
        &["no-such-folder", "is in a folder that does not exist"],
    );
    assert!(
        !ck.exists(),
        "the compression ran before the output was tried"
    );
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

// Continuing a checkpoint with the command line that made it (what one types again after a
// crash: `edmd pack --dim 3 --n 100000 ... --checkpoint slow.ck` with the checkpoint as the
// input) was refused, `--dim 3` or `--growth-rate 0.02` "carried by the checkpoint" although
// equal to what it carries. Equal values are accepted; a different one is refused, naming
// both (in `bad_packing_checkpoints_and_options_beside_them_are_refused_in_one_line`).
#[test]
fn options_equal_to_those_a_checkpoint_carries_are_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let (ck, whole, out) = (p("ck"), p("whole.txt"), p("out.txt"));
    let options = [
        "--dim",
        "3",
        "--n",
        "60",
        "--size-ratio",
        "1.2",
        "--fraction-large",
        "0.3",
        "--boundary",
        "walls",
        "--growth-rate",
        "0.02",
        "--pressure",
        "1e6",
        "--seed",
        "7",
    ];
    let mut args = vec!["pack", "-o", &whole, "--json"];
    args.extend_from_slice(&options);
    let s_whole = steady(summary(&run("edmd", &args, None)));
    let mut args = vec!["pack", "-o", &out];
    args.extend_from_slice(&options);
    args.extend_from_slice(&["--checkpoint", &ck, "--checkpoint-every", "0"]);
    ok_stdout(&run("edmd", &args, None));
    let cont = p("cont.txt");
    let mut args = vec!["pack", &ck, "-o", &cont, "--json", "--checkpoint", &ck];
    args.extend_from_slice(&options);
    let s_cont = steady(summary(&run("edmd", &args, None)));
    assert_eq!(s_cont, s_whole);
    assert!(std::fs::read(&cont).unwrap() == std::fs::read(&whole).unwrap());
}

/// The packing's discs in the order of cells a diameter wide, the last axis slowest (the
/// fluid generators' order): the key of each line of a Princeton file.
fn cell_keys(text: &str, dim: usize) -> Vec<u64> {
    let mut lines = text.lines();
    let n: usize = lines.next().unwrap().trim().parse().unwrap();
    let mut lengths = vec![0.0; dim];
    let mut rows = Vec::new();
    for line in lines {
        let f: Vec<&str> = line.split_whitespace().collect();
        if line.starts_with("# edmd box") {
            for a in 0..dim {
                lengths[a] = f[3 + a].parse().unwrap();
            }
        }
        if line.starts_with('#') || f.is_empty() {
            continue;
        }
        let x: Vec<f64> = f.iter().map(|v| v.parse().unwrap()).collect();
        // x, v, radius, mass, colour.
        rows.push((x[..dim].to_vec(), x[2 * dim]));
    }
    assert_eq!(rows.len(), n);
    let width = rows.iter().map(|r| 2.0 * r.1).fold(0.0, f64::max);
    let cells: Vec<u64> = lengths.iter().map(|l| (l / width).floor() as u64).collect();
    rows.iter()
        .map(|(x, _)| {
            (0..dim).rev().fold(0u64, |k, a| {
                let c = ((x[a] / lengths[a] * cells[a] as f64).floor() as u64).min(cells[a] - 1);
                k * cells[a] + c
            })
        })
        .collect()
}

// `edmd pack` wrote its packing in the random order of the start, so that a run of it read
// each particle's neighbours from all over memory; the fluid generators write theirs in cell
// order. The packing is now written in that order, from a random start and from a checkpoint
// alike.
#[test]
fn a_packing_is_written_in_cell_order() {
    let dir = tempfile::tempdir().unwrap();
    for dim in ["2", "3"] {
        let f = dir.path().join(format!("p{dim}.txt"));
        ok_stdout(&run(
            "edmd",
            &[
                "pack",
                "--dim",
                dim,
                "--n",
                "300",
                "--size-ratio",
                "1.4",
                "--pressure",
                "1e5",
                "--boundary",
                "walls",
                "-o",
                f.to_str().unwrap(),
            ],
            None,
        ));
        let text = std::fs::read_to_string(&f).unwrap();
        assert!(text.contains("# edmd box"), "{}", &text[..80]);
        let keys = cell_keys(&text, dim.parse().unwrap());
        assert!(keys.windows(2).all(|w| w[0] <= w[1]), "{dim}D: {keys:?}");
    }
}

// Results that cannot be right were written as packings or ended with advice that did not
// fit: Princeton's squeeze.txt (three discs on the line y = 0.3 moving along it) "packed" to a
// reduced pressure of 0.0; one large and one tiny disc between walls ran for over a minute and
// ended with "ask for a lower --pressure" at a reduced pressure of 23.6, the large disc having
// grown to the box's width; `--growth-rate 1e-300` "converged" and wrote the random start;
// a growth rate just fast enough to change the packing fraction "converged" in the dilute
// fluid. Each is now refused in one line with its reason (exit status 2, nothing written),
// at once.
#[test]
fn packings_that_cannot_be_right_are_refused_with_their_reason() {
    use std::time::{Duration, Instant};
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.txt");
    let out = out.to_str().unwrap();
    let cage = dir.path().join("cage.txt");
    std::fs::write(
        &cage,
        "2\n0.5 0.5 0.3 0.2 0.2 1 0 0 0\n0.05 0.05 -0.1 0.4 0.01 1 0 0 0\n",
    )
    .unwrap();
    let squeeze = shared!("algs4/squeeze.txt");
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["pack", squeeze.to_str().unwrap(), "-o", out],
            &["line y = 0.3", "none moves across it"],
        ),
        (
            &["pack", cage.to_str().unwrap(), "-o", out],
            &["particle 0", "width of the box between the walls", "caged"],
        ),
        (
            &["pack", "--n", "100", "--growth-rate", "1e-300", "-o", out],
            &["growth rate 1e-300 is too slow", "--growth-rate"],
        ),
        (
            &["pack", "--n", "100", "--growth-rate", "8e-18", "-o", out],
            &["stopped changing", "far from jamming", "--growth-rate"],
        ),
    ];
    for (args, words) in cases {
        let t = Instant::now();
        let o = run("edmd", args, None);
        refused(&o, words);
        assert!(
            t.elapsed() < Duration::from_secs(20),
            "{args:?}: {:?}",
            t.elapsed()
        );
        assert!(!std::path::Path::new(out).exists(), "{args:?} wrote a file");
    }
}

/// `edmd pack` spawned with `args`, its standard error piped.
fn spawn_pack(args: &[&str]) -> std::process::Child {
    std::process::Command::new(env!("CARGO_BIN_EXE_edmd"))
        .arg("pack")
        .args(args)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

/// Waits until `path` exists (at most a minute).
fn wait_for(path: &str) {
    let t = std::time::Instant::now();
    while !std::path::Path::new(path).exists() {
        assert!(t.elapsed().as_secs() < 60, "{path} never appeared");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
}

// SIGTERM (and Ctrl-C) were looked at only at the velocity rescalings, every 10 collisions per
// particle: `edmd pack` with 10^6 particles went on for minutes. And an interrupted `edmd pack`
// ended with exit status 1 like a failure. The packer now looks every 65 536 events and the
// command ends with status 130; with `--checkpoint`, after writing the last rescaling's
// checkpoint. Here the signal comes while the compression is under way (its first checkpoint
// written), in the middle of an interval of 10^5 collisions (a second or more in a debug
// build).
#[test]
fn sigterm_stops_a_large_compression_at_once_with_status_130() {
    use std::time::{Duration, Instant};
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let (ck, out) = (p("ck"), p("out.txt"));
    let mut child = spawn_pack(&[
        "--n",
        "10000",
        "-o",
        &out,
        "--checkpoint",
        &ck,
        "--checkpoint-every",
        "0",
    ]);
    wait_for(&ck);
    std::thread::sleep(Duration::from_millis(200));
    let t = Instant::now();
    std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(
            t.elapsed() < Duration::from_secs(5),
            "still running 5 s after SIGTERM"
        );
        std::thread::sleep(Duration::from_millis(5));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert_eq!(status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted") && err.contains("continues it"),
        "{err}"
    );
    assert!(std::fs::read(&ck).unwrap().starts_with(b"EDMDPACK"));
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(left.len(), 1, "{left:?}");
    // Without a checkpoint: the same status, nothing written.
    let child = spawn_pack(&["--n", "10000", "-o", &out]);
    std::thread::sleep(Duration::from_millis(1500));
    std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130));
    assert!(!std::path::Path::new(&out).exists());
}

// The output's temporary file was created before the compression (so that an unwritable path
// failed at once), and a SIGKILL, which no handler sees, left it behind, empty. The place is
// now checked without creating anything, and the temporary file made only when the packing is
// written.
#[test]
fn a_killed_compression_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.txt");
    let mut child = spawn_pack(&["--n", "20000", "-o", out.to_str().unwrap()]);
    std::thread::sleep(std::time::Duration::from_millis(800));
    child.kill().unwrap();
    child.wait().unwrap();
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

// A file with a stepped potential was packed as hard particles, the potential silently dropped
// from the packing written. Pack compresses hard particles: such a start is refused by name.
#[test]
fn a_start_with_a_stepped_potential_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let start = crate::support::write(
        &dir,
        "well.txt",
        "2\n# edmd box 6 6\n# edmd boundary periodic\n# edmd potential 0 0 1.5 -1\n1 1 0.5 0 0.5 1 0 0 0\n4 4 0 0.5 0.5 1 0 0 0\n",
    );
    let out = dir.path().join("packed.txt");
    let o = crate::support::run("edmd", &["pack", &start, "-o", out.to_str().unwrap()], None);
    crate::support::refused(&o, &["well.txt", "stepped potential"]);
    assert!(!out.exists());
}
