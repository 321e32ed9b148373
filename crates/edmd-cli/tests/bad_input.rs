//! Every malformed input: one line on standard error naming the file and line, exit status 2,
//! no panic, no output file.

use crate::support::{run, write};

/// Runs `edmd run FILE --until 1 --output OUT` on `text` and checks the refusal.
fn refused(text: &str, expect: &str) {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "bad.txt", text);
    let out_path = dir.path().join("out.txt");
    let out = run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "1",
            "--output",
            out_path.to_str().unwrap(),
        ],
        None,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{text:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{text:?}: {err}");
    assert!(
        err.contains(expect),
        "{text:?}: expected {expect:?} in {err}"
    );
    assert!(!err.contains("panicked"));
    assert!(out.stdout.is_empty());
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        left.len(),
        1,
        "output or temporary files left behind: {left:?}"
    );
}

#[test]
fn malformed_princeton_files() {
    let ok = "0.5 0.5 0.01 0 0.05 1 1 2 3";
    refused("", "bad.txt:1: the file is empty");
    refused("\n\n  \n", "bad.txt:1: the file is empty");
    refused("two\n", "bad.txt:1:");
    refused(
        &format!("2\n{ok}\n"),
        "bad.txt:2: file ends before disc 2 of 2",
    );
    refused(&format!("1\n{ok}\n{ok}\n"), "bad.txt:3: more disc lines");
    refused(
        "1\n0.5 0.5 0.01 0 0.05 1 1 2\n",
        "bad.txt:2: expected 9 fields",
    );
    refused(
        "1\n0.5 half 0.01 0 0.05 1 1 2 3\n",
        "bad.txt:2: ry is not a number: 'half'",
    );
    refused(
        "1\n0.5 0.5 NaN 0 0.05 1 1 2 3\n",
        "bad.txt:2: vx is not finite",
    );
    refused(
        "1\n0.5 0.5 0 inf 0.05 1 1 2 3\n",
        "bad.txt:2: vy is not finite",
    );
    refused(
        "1\n0.5 0.5 0 0 0 1 1 2 3\n",
        "bad.txt:2: radius must be > 0",
    );
    refused(
        "1\n0.5 0.5 0 0 0.05 -1 1 2 3\n",
        "bad.txt:2: mass must be > 0",
    );
    refused("1\n0.5 0.5 0 0 0.05 1 1 2 300\n", "bad.txt:2: colour b");
    refused(
        &format!("2\n{ok}\n1.2 0.5 0 0 0.05 1 1 2 3\n"),
        "bad.txt:3: this disc is not inside the box",
    );
    refused(
        &format!("2\n{ok}\n0.52 0.5 0 0 0.05 1 1 2 3\n"),
        "bad.txt:3: this disc overlaps the disc on line 2",
    );
    refused(
        "1\n0.5 0.5 0 0 0.7 1 1 2 3\n",
        "bad.txt:2: diameter 1.4 does not fit",
    );
    refused("1\n1 2 3\n", "bad.txt:2: expected 9 fields");
}

/// Reaction rules that cannot be: each refused at its line, with what is wrong.
#[test]
fn malformed_reaction_rules() {
    let discs = "0.3 0.5 0.01 0 0.05 1 1 2 3 0\n0.7 0.5 0 0 0.05 1 1 2 3 1\n";
    let with = |rules: &str| format!("2\n{rules}{discs}");
    for (rules, expect) in [
        (
            "# edmd reaction 0 + 1 -> 2 + 2 probability 1.5\n",
            "bad.txt:2: reaction: the probability must be in [0, 1], found 1.5",
        ),
        (
            "# edmd reaction 0 + 1 -> 2 + 2 activation -1\n",
            "bad.txt:2: reaction: the activation energy must be >= 0, found -1",
        ),
        (
            "# edmd reaction 0 + 1 -> 2 + 2 heat inf\n",
            "bad.txt:2: reaction: heat must be a finite number, found 'inf'",
        ),
        (
            "# edmd reaction 0 + 1 -> 2 + 2 activation NaN\n",
            "bad.txt:2: reaction: activation must be a finite number, found 'NaN'",
        ),
        (
            "# edmd reaction 0 + 5 -> 2 + 2\n",
            "bad.txt:2: reaction: no disc is of species 5 and no rule makes it",
        ),
        (
            "# edmd reaction 0 + 1 -> 2 + 2\n# edmd reaction 1 + 0 -> 1 + 1\n",
            "bad.txt:3: a second reaction rule for species 1 and 0 (the first is line 2)",
        ),
        (
            "# edmd reaction A + B -> C + D\n",
            "bad.txt:2: reaction: expected 'A + B -> C + D",
        ),
        (
            "# edmd reaction 0 + 1 -> 2 + 300\n",
            "bad.txt:2: reaction: species must be whole numbers from 0 to 255, found '300'",
        ),
        (
            "# edmd potential 0 1 0.2 -1\n# edmd reaction 0 + 1 -> 2 + 2\n",
            "bad.txt:3: reaction rules do not go with a stepped potential (line 2)",
        ),
    ] {
        refused(&with(rules), expect);
    }
}

/// Rules with what they do not go with, and `--seed` with nothing to seed: one line naming the
/// file, exit status 2, nothing written.
#[test]
fn reaction_rules_refuse_what_they_do_not_go_with() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(
        &dir,
        "r.txt",
        "2\n# edmd reaction 0 + 1 -> 2 + 2\n0.3 0.5 0.01 0 0.05 1 1 2 3 0\n0.7 0.5 0 0 0.05 1 1 2 3 1\n",
    );
    let plain = write(&dir, "plain.txt", "1\n0.5 0.5 0.01 0 0.05 1 1 2 3\n");
    let out = dir.path().join("out.txt");
    let out = out.to_str().unwrap();
    for (args, expect) in [
        (
            vec!["run", &f, "--until", "1", "--rule", "swap", "-o", out],
            "r.txt: reaction rules need the elastic rule (the file's '# edmd reaction' lines)",
        ),
        (
            vec!["run", &f, "--until", "1", "--multi", "-o", out],
            "r.txt: reaction rules do not go with multi-disc collisions",
        ),
        (
            vec!["run", &plain, "--until", "1", "--seed", "3", "-o", out],
            "plain.txt: --seed seeds the thermostat's redraws and the draws of reaction rules",
        ),
    ] {
        let o = run("edmd", &args, None);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(expect), "{args:?}: {err}");
        assert!(!std::path::Path::new(out).exists());
    }
}

/// `edmd gen`'s species and reaction options: each mistake in one line, exit status 2, no file.
#[test]
fn bad_species_and_reaction_options_of_gen() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("g.txt");
    let out = out.to_str().unwrap();
    let gen = |extra: &[&str]| {
        let mut args = vec!["gen", "fluid", "--n", "50", "-o", out];
        args.extend_from_slice(extra);
        args.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (gen(&["--species", "0.5,x"]), "each fraction must be a number >= 0, found 'x'"),
        (gen(&["--species", "0.5,-0.5,1"]), "found '-0.5'"),
        (gen(&["--species", "0.5,nan"]), "found 'nan'"),
        (gen(&["--species", "0.5,0.4"]), "the fractions must sum to 1, and they sum to 0.9"),
        (
            gen(&["--species", "1", "--reaction", "0 + 2 -> 1 + 1"]),
            "--reaction '0 + 2 -> 1 + 1': no disc is of species 2 and no rule makes it",
        ),
        (
            gen(&["--reaction", "0 + 0 -> 1 + 1 probability 2"]),
            "gen fluid: --reaction '0 + 0 -> 1 + 1 probability 2': the probability must be in [0, 1], found 2",
        ),
        (
            gen(&["--reaction", "0 + 0 -> 1 + 1", "--reaction", "0 + 0 -> 2 + 2"]),
            "a second rule for species 0 and 0",
        ),
        (
            gen(&["--reaction", "0 + 0 -> 1 + 1", "--well", "1.5"]),
            "--reaction does not go with --well or --shoulder",
        ),
        (
            gen(&["--species", "0.5,0.5", "--shoulder", "1.5"]),
            "--species does not go with --well or --shoulder",
        ),
        (
            ["gen", "lattice", "--species", "1", "-o", out]
                .into_iter()
                .map(String::from)
                .collect(),
            "gen lattice: --species applies to fluid",
        ),
        (
            ["gen", "lattice", "--course", "--reaction", "0+0->0+0", "-o", out]
                .into_iter()
                .map(String::from)
                .collect(),
            "the course format has no place for reaction rules",
        ),
    ];
    for (args, expect) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run("edmd", &args, None);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(expect), "{args:?}: {err}");
        assert!(!std::path::Path::new(out).exists(), "{args:?} wrote a file");
    }
}

#[test]
fn malformed_course_files() {
    refused(
        "1\n1\n10\n",
        "bad.txt:3: expected 2 numbers (Lx Ly), found 1",
    );
    refused("1\n-1\n10 10\n5 5 1 1\n", "bad.txt:2: radius must be > 0");
    refused("1\n1\n10 10\n5 5 1\n", "bad.txt:4: expected 4 numbers");
    refused(
        "2\n1\n10 10\n5 5 1 1\n5.5 5 1 1\n",
        "bad.txt:5: this disc overlaps the disc on line 4",
    );
    refused(
        "1\n1\n10 10\n0.5 5 1 1\n",
        "bad.txt:4: this disc is not inside the box",
    );
}

#[test]
fn unreadable_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    for args in [
        vec!["run", d, "--until", "1"],
        vec!["run", "/no/such/file.txt", "--until", "1"],
    ] {
        let out = run("edmd", &args, None);
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("cannot read") && err.lines().count() == 1,
            "{err}"
        );
    }
    let bin = dir.path().join("bin.txt");
    std::fs::write(&bin, [0xff, 0xfe, 0x00, 0x41]).unwrap();
    let out = run(
        "edmd",
        &["run", bin.to_str().unwrap(), "--until", "1"],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a text file"));
}

#[test]
fn bad_options_are_one_line_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "ok.txt", "1\n0.5 0.5 0.01 0 0.05 1 1 2 3\n");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["run", &f], "--until"),
        (vec!["run", &f, "--until", "-3"], ">= 0"),
        (vec!["run", &f, "--until", "soon"], "not a number"),
        (vec!["run", &f, "--until", "nan"], "finite"),
        (
            vec!["run", &f, "--until", "1", "--rule", "sticky"],
            "sticky",
        ),
        (
            vec!["run", &f, "--until", "1", "--trajectory", "t.xyz"],
            "--every",
        ),
        (
            vec![
                "run",
                &f,
                "--until",
                "1",
                "--trajectory",
                "t.xyz",
                "--every",
                "0",
            ],
            "> 0",
        ),
        (
            vec![
                "run",
                &f,
                "--until",
                "1",
                "--output",
                "/no/such/dir/out.txt",
            ],
            "--output is in a folder that does not exist (/no/such/dir)",
        ),
        (vec!["bench", "--n", "-5", "--packing", "0.5"], "-5"),
        (vec!["bench", "--n", "0", "--packing", "0.5"], ">= 1"),
        (vec!["frobnicate"], "frobnicate"),
    ];
    for (args, expect) in cases {
        let out = run("edmd", &args, None);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(expect), "{args:?}: {err}");
    }
}

#[test]
fn particles_refuses_bad_arguments_and_files() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "ok.txt", "1\n1\n10 10\n5 5 1 1\n");
    let bad = write(&dir, "bad.txt", "1\n1\n10 10\n5 5 x 1\n");
    let p = write(&dir, "p.txt", "1\n0.5 0.5 0.01 0 0.05 1 1 2 3\n");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec![&f], "END_TIME"),
        (vec![&f, "-1"], ">= 0"),
        (vec![&f, "x"], "not a number"),
        (vec![&bad, "1"], "bad.txt:4: u is not a number: 'x'"),
        (vec![&p, "1"], "p.txt:2: expected the radius alone"),
        (vec!["/no/such/file", "1"], "cannot read"),
    ];
    for (args, expect) in cases {
        let out = run("particles", &args, None);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(expect), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "partial output for {args:?}");
    }
}

#[test]
fn a_speed_whose_energy_overflows_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "fast.txt", "1\n0.5 0.5 1e308 1e308 0.1 1 0 0 0\n");
    let out = run("edmd", &["run", &f, "--until", "1"], None);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("fast.txt:2: kinetic energy is not finite"),
        "{err}"
    );
}

#[test]
fn ctrl_c_abandons_a_run_without_leaving_files() {
    use std::process::{Command, Stdio};
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.txt");
    let out = run(
        "edmd",
        &[
            "gen",
            "fluid",
            "--n",
            "5000",
            "--packing",
            "0.5",
            "-o",
            big.to_str().unwrap(),
        ],
        None,
    );
    assert!(out.status.success());
    let child = Command::new(env!("CARGO_BIN_EXE_edmd"))
        .args(["run", big.to_str().unwrap(), "--until", "1e6", "--output"])
        .arg(dir.path().join("out.txt"))
        .args(["--trajectory"])
        .arg(dir.path().join("t.xyz"))
        // 10^4 frames: within the 100 GB a trajectory may take.
        .args(["--every", "1e2"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    assert!(Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let out = child.wait_with_output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("interrupted") && !err.contains("panicked"),
        "{err}"
    );
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        left,
        vec![std::ffi::OsString::from("big.txt")],
        "files left behind"
    );
}

#[test]
fn steps_whose_speeds_would_overflow_are_refused() {
    let file = |potential: &str, mass: &str| {
        format!(
            "2\n# edmd box 8 8\n# edmd boundary periodic\n# edmd potential 0 0 {potential}\n\
             2 2 0.5 0 0.5 {mass} 0 0 0\n4 2 -0.5 0 0.5 {mass} 0 0 0\n"
        )
    };
    // A well of -1e308 made the speed of a pair entering it infinite, and the run panicked
    // on a NaN event time.
    refused(&file("1.5 -1e308", "1"), "bad.txt:4: ");
    refused(&file("1.5 -1e308", "1"), "larger than 1e100 in size");
    refused(&file("1.1 1e100 1.2 -1e101", "1"), "larger than 1e100");
    // Within the bound, but too deep for discs this light.
    refused(
        &file("1.5 -1e90", "1e-120"),
        "too large for discs of mass 1e-120",
    );
}

#[test]
fn a_course_file_refuses_directives() {
    refused(
        "2\n0.5\n10 10\n2 5 1 0\n8 5 -1 0\n# edmd potential 0 0 1.5 -1\n",
        "bad.txt:6: `# edmd potential` is a directive of the Princeton format",
    );
}

#[test]
fn gen_refuses_systems_the_run_would_refuse() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("g.txt");
    let o = out.to_str().unwrap();
    for (args, expect) in [
        (
            &["fluid", "--n", "100", "--packing", "0.3", "--well", "100"][..],
            "is too small for a range",
        ),
        (
            &[
                "fluid",
                "--dim",
                "3",
                "--n",
                "100",
                "--packing",
                "0.3",
                "--well",
                "3",
            ][..],
            "is too small for a range",
        ),
        (
            &[
                "fluid",
                "--n",
                "100",
                "--packing",
                "0.3",
                "--well",
                "1.5",
                "--depth",
                "1e308",
            ][..],
            "--depth must be above 0 and at most 1e100",
        ),
        (
            &["ring", "--n", "50", "--omega", "1e300"][..],
            "--omega must be a finite number > 0 and at most 1e6",
        ),
    ] {
        let mut a = vec!["gen"];
        a.extend_from_slice(args);
        a.extend_from_slice(&["-o", o]);
        let r = run("edmd", &a, None);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(expect),
            "{args:?}: expected {expect:?} in {err}"
        );
        assert!(!out.exists(), "{args:?} wrote {o}");
    }
}

#[test]
fn a_checkpoint_on_standard_input_is_refused_saying_how_to_continue_it() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "in.txt", "1\n0.5\n10 10\n5 5 1 0.5\n");
    let ck = dir.path().join("c.ck");
    let first = run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "1",
            "--checkpoint",
            ck.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(first.status.code(), Some(0));
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_edmd"))
        .args(["run", "-", "--until", "2"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(&std::fs::read(&ck).unwrap())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("a checkpoint is continued from its file"),
        "{err}"
    );
}
