//! `edmd pack`: a packing written by the command, its JSON summary, `edmd run` reading it, and
//! refusals of bad options (one line, exit status 2, no output file).

use crate::support::{ok_stdout, refused, run, summary};

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
    for flag in [
        &["--n", "40"][..],
        &["--dim", "2"],
        &["--growth-rate", "0.01"],
        &["--pressure", "1e6"],
        &["--packing", "0.5"],
        &["--seed", "3"],
        &["--boundary", "walls"],
    ] {
        let mut args = vec!["pack", &ck, "-o", &out];
        args.extend_from_slice(flag);
        refused(
            &run("edmd", &args, None),
            &["carried by the checkpoint", flag[0]],
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
        let f = crate::support::shared(file);
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
