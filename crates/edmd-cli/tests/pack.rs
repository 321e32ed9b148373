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
