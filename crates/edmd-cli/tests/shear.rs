//! Lees-Edwards boundaries from the command line: `edmd gen --shear` files start on the
//! streaming profile and run under `edmd run` with the rate and the temperature about the
//! profile in the summary; written states carry the offset reached and continue the flow;
//! checkpoints continue bit for bit; the example sheared grains run; and bad input is refused
//! in one line with exit status 2, nothing written.

use crate::support::{example, refused, run, summary, write};

fn f(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is not a number in {v}"))
}

/// `edmd gen fluid --shear RATE` with `extra` options into `path`, asserting success.
fn gen_sheared(path: &str, rate: &str, extra: &[&str]) {
    let mut args = vec![
        "gen",
        "fluid",
        "--n",
        "300",
        "--packing",
        "0.3",
        "--shear",
        rate,
    ];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["-o", path]);
    let out = run("edmd", &args, None);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The numbers of the disc lines of a 2D Princeton file, and its box `[LX, LY]`.
fn disc_rows(text: &str) -> (Vec<Vec<f64>>, [f64; 2]) {
    let mut lengths = [1.0, 1.0];
    let mut rows = Vec::new();
    for line in text.lines().skip(1) {
        if let Some(rest) = line.strip_prefix("# edmd box ") {
            let l: Vec<f64> = rest.split(' ').map(|w| w.parse().unwrap()).collect();
            lengths = [l[0], l[1]];
        } else if !line.starts_with('#') {
            rows.push(line.split(' ').map(|w| w.parse().unwrap()).collect());
        }
    }
    (rows, lengths)
}

#[test]
fn gen_shear_starts_on_the_profile_and_run_reports_the_flow() {
    let dir = tempfile::tempdir().unwrap();
    let flow = dir.path().join("flow.txt");
    let flow = flow.to_str().unwrap();
    // A negative rate in exponent form, which an option taking negative numbers alone refuses.
    gen_sheared(flow, "-5e-1", &["--restitution", "0.8"]);
    let text = std::fs::read_to_string(flow).unwrap();
    for line in [
        "# edmd boundary periodic periodic",
        "# edmd shear -0.5 0",
        "# edmd restitution 0.8",
    ] {
        assert!(text.contains(line), "{line} missing from\n{}", &text[..300]);
    }
    // The x velocities' slope against y is the rate (the thermal part averages out to within
    // its noise: 300 discs of unit rms speed over a box some 28 high).
    let (rows, [_, ly]) = disc_rows(&text);
    let n = rows.len() as f64;
    let (my, mv) = (
        rows.iter().map(|r| r[1]).sum::<f64>() / n,
        rows.iter().map(|r| r[2]).sum::<f64>() / n,
    );
    let sxy: f64 = rows.iter().map(|r| (r[1] - my) * (r[2] - mv)).sum();
    let sxx: f64 = rows.iter().map(|r| (r[1] - my).powi(2)).sum();
    let slope = sxy / sxx;
    assert!(
        (slope + 0.5).abs() < 0.05,
        "slope {slope} (box height {ly})"
    );

    let state = dir.path().join("flow-5.txt");
    let s = summary(&run(
        "edmd",
        &[
            "run",
            flow,
            "--until",
            "5",
            "--json",
            "--output",
            state.to_str().unwrap(),
        ],
        None,
    ));
    assert_eq!(f(&s, "shear_rate"), -0.5);
    let offset = f(&s, "shear_offset");
    let kt = f(&s, "peculiar_kt");
    assert!(f(&s, "dissipated") > 0.0, "{s}");
    // Inelastic grains cool below the start's kT = 1 while the shear heats them.
    assert!(kt > 0.0 && kt < 1.0, "{s}");
    // The state written carries the offset reached at its time, and reads back into the same
    // flow: run on from it, it reaches the offset the run straight through reaches.
    let written = std::fs::read_to_string(&state).unwrap();
    assert!(written.contains("# edmd time 5.0\n"), "{}", &written[..300]);
    let line = written
        .lines()
        .find(|l| l.starts_with("# edmd shear "))
        .unwrap();
    let words: Vec<f64> = line[13..].split(' ').map(|w| w.parse().unwrap()).collect();
    assert_eq!(words, [-0.5, offset]);
    let on = summary(&run(
        "edmd",
        &["run", state.to_str().unwrap(), "--until", "8", "--json"],
        None,
    ));
    let straight = summary(&run("edmd", &["run", flow, "--until", "8", "--json"], None));
    assert!((f(&on, "shear_offset") - f(&straight, "shear_offset")).abs() < 1e-9);
    assert_eq!(on["shear_rate"], straight["shear_rate"]);

    // The text summary says it too.
    let out = run("edmd", &["run", flow, "--until", "1"], None);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("shear: rate -0.5, images' offset")
            && text.contains("about the streaming profile"),
        "{text}"
    );
}

#[test]
fn a_sheared_checkpoint_continues_as_the_run_never_stopped() {
    let dir = tempfile::tempdir().unwrap();
    let flow = dir.path().join("flow.txt");
    let flow = flow.to_str().unwrap();
    gen_sheared(flow, "0.3", &[]);
    let ck = dir.path().join("flow.ck");
    let thermostat = ["--thermostat", "andersen", "--kT", "1", "--rate", "0.5"];
    let mut first = vec![
        "run",
        flow,
        "--until",
        "4",
        "--checkpoint",
        ck.to_str().unwrap(),
    ];
    first.extend_from_slice(&thermostat);
    summary(&run("edmd", &[&first[..], &["--json"]].concat(), None));
    let (a, b) = (dir.path().join("a.txt"), dir.path().join("b.txt"));
    let on = summary(&run(
        "edmd",
        &[
            "run",
            ck.to_str().unwrap(),
            "--until",
            "9",
            "--json",
            "-o",
            a.to_str().unwrap(),
        ],
        None,
    ));
    let mut straight = vec![
        "run",
        flow,
        "--until",
        "9",
        "--json",
        "-o",
        b.to_str().unwrap(),
    ];
    straight.extend_from_slice(&thermostat);
    let straight = summary(&run("edmd", &straight, None));
    for key in [
        "disc_collisions",
        "shear_offset",
        "peculiar_kt",
        "cell_crossings",
    ] {
        assert_eq!(on[key], straight[key], "{key}: {on} against {straight}");
    }
    // The states to the bit (the first line of each names no file).
    assert_eq!(
        std::fs::read_to_string(&a).unwrap(),
        std::fs::read_to_string(&b).unwrap()
    );
}

#[test]
fn sheared_spheres_run() {
    let dir = tempfile::tempdir().unwrap();
    let flow = dir.path().join("flow3.txt");
    let flow = flow.to_str().unwrap();
    gen_sheared(flow, "0.2", &["--dim", "3"]);
    let text = std::fs::read_to_string(flow).unwrap();
    assert!(text.contains("# edmd shear 0.2 0.0\n"));
    let s = summary(&run(
        "edmd",
        &["run", flow, "--until", "2", "--json", "--check"],
        None,
    ));
    assert_eq!(f(&s, "shear_rate"), 0.2);
    assert_eq!(s["dim"], 3);
}

#[test]
fn the_example_sheared_grains_run() {
    let grains = example("sheared-grains.txt");
    let s = summary(&run(
        "edmd",
        &[
            "run",
            grains.to_str().unwrap(),
            "--until",
            "5",
            "--json",
            "--check",
        ],
        None,
    ));
    assert!(f(&s, "dissipated") > 0.0);
    assert!(s["shear_rate"].is_number(), "{s}");
}

#[test]
fn bad_shear_input_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out_file = dir.path().join("never.txt");
    let o = out_file.to_str().unwrap();
    for (args, words) in [
        (
            vec!["gen", "fluid", "--shear", "nan", "-o", o],
            vec!["--shear", "finite"],
        ),
        (
            vec![
                "gen",
                "fluid",
                "--shear",
                "1",
                "--boundary",
                "walls",
                "-o",
                o,
            ],
            vec!["--shear needs a periodic box"],
        ),
        (
            vec!["gen", "fluid", "--shear", "1", "--gravity", "-1", "-o", o],
            vec!["--shear does not go with --gravity"],
        ),
        (
            vec!["gen", "fluid", "--shear", "1", "--well", "1.5", "-o", o],
            vec!["--shear does not go with --well or --shoulder"],
        ),
        (
            vec!["gen", "fluid", "--shear", "1", "--course", "-o", o],
            vec!["course format"],
        ),
        (
            vec!["gen", "lattice", "--shear", "1", "-o", o],
            vec!["fluids and mixtures only"],
        ),
    ] {
        refused(&run("edmd", &args, None), &words);
        assert!(!out_file.exists(), "{args:?} wrote a file");
    }
    // Run options and states that the engine refuses under shear, named with the file.
    let fine = "2\n# edmd box 4 4\n# edmd boundary periodic\n# edmd shear 1 2\n1 1 0 0 .5 1 0 0 0\n3 3 0 0 .5 1 0 0 0\n";
    let path = write(&dir, "fine.txt", fine);
    refused(
        &run(
            "edmd",
            &["run", &path, "--until", "1", "--multi", "--output", o],
            None,
        ),
        &["fine.txt", "multi-disc collisions", "'# edmd shear' line"],
    );
    // Discs at (1, 0.2) and (3, 3.9): apart across the plain boundary, but the second's image
    // below, slid by -2 along x, sits at (1, -0.1).
    let slid = "2\n# edmd box 4 4\n# edmd boundary periodic\n# edmd shear 1 2\n1 .2 0 0 .5 1 0 0 0\n3 3.9 0 0 .5 1 0 0 0\n";
    let path = write(&dir, "slid.txt", slid);
    refused(
        &run("edmd", &["run", &path, "--until", "1", "--output", o], None),
        &[
            "slid.txt",
            "overlap across the boundary",
            "'# edmd shear' line",
        ],
    );
    assert!(!out_file.exists());
    for (text, words) in [
        ("1\n# edmd shear 1\n.5 .5 0 0 .1 1 0 0 0\n", vec![":2:", "periodic x and y"]),
        ("1\n# edmd boundary periodic walls\n# edmd shear 1\n.5 .5 0 0 .1 1 0 0 0\n", vec![":3:", "periodic x and y"]),
        ("1\n# edmd boundary periodic\n# edmd shear 1 1\n.5 .5 0 0 .1 1 0 0 0\n", vec![":3:", "offset must be in [0, L_x)"]),
        ("1\n# edmd boundary periodic\n# edmd shear x\n.5 .5 0 0 .1 1 0 0 0\n", vec![":3:", "RATE is not a number"]),
        ("1\n# edmd boundary periodic\n# edmd shear 1\n# edmd shear 1\n.5 .5 0 0 .1 1 0 0 0\n", vec![":4:", "a second '# edmd shear' line"]),
        ("1\n# edmd boundary periodic walls\n# edmd gravity y -1\n# edmd shear 1\n.5 .5 0 0 .1 1 0 0 0\n", vec![":4:", "shear does not go with gravity (line 3)"]),
        ("1\n# edmd boundary periodic\n# edmd shear 1\n# edmd barrier x 0.5\n.2 .5 0 0 .1 1 0 0 0\n", vec![":3:", "shear does not go with barriers"]),
        ("1\n# edmd boundary periodic\n# edmd shear 1\n# edmd potential 0 0 0.3 -1\n.5 .5 0 0 .1 1 0 0 0\n", vec![":3:", "stepped potential (line 4)"]),
    ] {
        let path = write(&dir, "bad.txt", text);
        refused(&run("edmd", &["run", &path, "--until", "1", "--output", o], None), &words);
        assert!(!out_file.exists());
    }
}
