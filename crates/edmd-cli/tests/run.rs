//! `edmd run` on real files: all 25 Princeton data files, the course format, chaining, stdin.

use crate::support::{example, ok_stdout, run, shared, summary, write};

#[test]
fn all_princeton_data_files_load_and_run() {
    let dir = shared!("algs4");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names.len(), 25);
    for name in names {
        let path = dir.join(&name);
        let p = path.to_str().unwrap();
        let refused = name == "diffusion3.txt" || name == "billiards-overflow.txt";
        let out = run(
            "edmd",
            &["run", p, "--until", "200", "--json", "--check"],
            None,
        );
        if refused {
            assert_eq!(out.status.code(), Some(2), "{name} should be refused");
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(err.lines().count(), 1, "{err}");
            assert!(err.contains("--allow-overlaps"), "{err}");
            let out = run(
                "edmd",
                &["run", p, "--until", "200", "--json", "--allow-overlaps"],
                None,
            );
            let s = summary(&out);
            assert!(
                s["relative_energy_change"].as_f64().unwrap().abs() < 1e-12,
                "{name}: {s}"
            );
        } else {
            let s = summary(&out);
            assert!(
                s["relative_energy_change"].as_f64().unwrap().abs() < 1e-12,
                "{name}: {s}"
            );
            assert_eq!(
                s["n"].as_u64().unwrap() as usize,
                std::fs::read_to_string(&path)
                    .unwrap()
                    .trim()
                    .lines()
                    .next()
                    .unwrap()
                    .trim()
                    .parse::<usize>()
                    .unwrap()
            );
        }
    }
}

#[test]
fn refusals_name_the_first_offending_line_and_the_count() {
    let out = run(
        "edmd",
        &[
            "run",
            shared!("algs4/diffusion3.txt").to_str().unwrap(),
            "--until",
            "1",
        ],
        None,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("diffusion3.txt:12:")
            && err.contains("line 11")
            && err.contains("90 overlapping pair"),
        "{err}"
    );
    let out = run(
        "edmd",
        &[
            "run",
            shared!("algs4/billiards-overflow.txt").to_str().unwrap(),
            "--until",
            "1",
        ],
        None,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("billiards-overflow.txt:5:") && err.contains("2 such disc"),
        "{err}"
    );
}

#[test]
fn rounding_level_contacts_in_real_files_are_accepted() {
    // brownian.txt, brownian2.txt and diffusion.txt have pairs touching with overlaps ~2e-16.
    for name in ["brownian.txt", "brownian2.txt", "diffusion.txt"] {
        let out = run(
            "edmd",
            &[
                "run",
                shared!(&format!("algs4/{name}")).to_str().unwrap(),
                "--until",
                "1",
            ],
            None,
        );
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn output_is_written_in_the_input_format_and_chains() {
    let dir = tempfile::tempdir().unwrap();
    let cradle = example("newton-cradle.txt");
    let a = dir.path().join("a.txt");
    let b = dir.path().join("b.txt");
    let direct = dir.path().join("direct.txt");
    let c = cradle.to_str().unwrap();
    ok_stdout(&run(
        "edmd",
        &["run", c, "--until", "4", "--output", a.to_str().unwrap()],
        None,
    ));
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            a.to_str().unwrap(),
            "--until",
            "7",
            "--output",
            b.to_str().unwrap(),
        ],
        None,
    ));
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            c,
            "--until",
            "7",
            "--output",
            direct.to_str().unwrap(),
        ],
        None,
    ));
    let read = |p: &std::path::Path| -> Vec<Vec<f64>> {
        std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .skip(1)
            .filter(|l| !l.starts_with('#'))
            .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let (chained, straight) = (read(&b), read(&direct));
    assert_eq!(chained.len(), 5);
    for (x, y) in chained.iter().zip(&straight) {
        assert_eq!(x.len(), 9);
        for k in 0..9 {
            assert!((x[k] - y[k]).abs() < 1e-12, "{x:?} vs {y:?}");
        }
    }
    // The striker's momentum went down the line: the last disc moves, the first has stopped.
    assert!(
        straight[4][2] > 0.0 && straight[0][2] == 0.0,
        "{straight:?}"
    );
}

#[test]
fn course_format_is_detected_and_written_back() {
    let dir = tempfile::tempdir().unwrap();
    let out_path = dir.path().join("out.txt");
    let input = shared!("assignment/normal.txt");
    let out = run(
        "edmd",
        &[
            "run",
            input.to_str().unwrap(),
            "--until",
            "20",
            "--rule",
            "swap",
            "--output",
            out_path.to_str().unwrap(),
        ],
        None,
    );
    ok_stdout(&out);
    let text = std::fs::read_to_string(&out_path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(&lines[..3], &["5", "1.0", "15.1 13.2"]);
    // Same final positions as the course program's expected output.
    let expected = std::fs::read_to_string(shared!("assignment/normal_T20_expected.txt")).unwrap();
    for (l, e) in lines[3..].iter().zip(expected.lines()) {
        let x: Vec<f64> = l.split_whitespace().map(|v| v.parse().unwrap()).collect();
        assert_eq!(
            format!("{:.6}, {:.6}", x[0], x[1]),
            e.rsplitn(3, ", ").nth(2).unwrap()
        );
    }
}

#[test]
fn standard_input_and_output() {
    let text = std::fs::read_to_string(example("course-7.txt")).unwrap();
    let out = run(
        "edmd",
        &["run", "-", "--until", "5", "--output", "-"],
        Some(&text),
    );
    let stdout = ok_stdout(&out);
    assert_eq!(stdout.lines().count(), 3 + 7);
    // With the state on standard output, the summary goes to standard error.
    assert!(String::from_utf8_lossy(&out.stderr).contains("simulated to t = 5"));
}

#[test]
fn same_input_same_output_and_quiet_stderr() {
    let dir = tempfile::tempdir().unwrap();
    let gas = example("gas-300.txt");
    let mut outs = vec![];
    for k in 0..2 {
        let o = dir.path().join(format!("o{k}.txt"));
        let out = run(
            "edmd",
            &[
                "run",
                gas.to_str().unwrap(),
                "--until",
                "100",
                "--output",
                o.to_str().unwrap(),
            ],
            None,
        );
        ok_stdout(&out);
        // Not a terminal: no progress bar, nothing on standard error.
        assert!(
            out.stderr.is_empty(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        outs.push(std::fs::read(&o).unwrap());
    }
    assert_eq!(outs[0], outs[1]);
}

#[test]
fn mass_first_column_order_is_selectable() {
    let dir = tempfile::tempdir().unwrap();
    // As mass-radius: mass 0.02, radius 10 would not fit the unit box; as radius-mass it runs.
    let f = write(&dir, "p.txt", "1\n0.5 0.5 0.01 0 0.02 10 1 2 3\n");
    assert!(run("edmd", &["run", &f, "--until", "1"], None)
        .status
        .success());
    let out = run(
        "edmd",
        &["run", &f, "--until", "1", "--columns", "mass-radius"],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("p.txt:2:"));
    let f = write(&dir, "q.txt", "1\n0.5 0.5 0.01 0 10 0.02 1 2 3\n");
    let o = dir.path().join("o.txt");
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "1",
            "--columns",
            "mass-radius",
            "-o",
            o.to_str().unwrap(),
        ],
        None,
    ));
    assert!(std::fs::read_to_string(&o)
        .unwrap()
        .contains(" 10.0 0.02 1 2 3"));
}

#[test]
fn json_summary_has_the_promised_fields() {
    let out = run(
        "edmd",
        &[
            "run",
            example("brownian-demo.txt").to_str().unwrap(),
            "--until",
            "20",
            "--json",
        ],
        None,
    );
    let s = summary(&out);
    for key in [
        "disc_collisions",
        "wall_collisions",
        "cell_crossings",
        "collisions_per_second",
        "relative_energy_change",
        "seconds",
    ] {
        assert!(s.get(key).is_some(), "missing {key}: {s}");
    }
    assert!(s["disc_collisions"].as_u64().unwrap() > 100);
}

#[test]
fn extended_princeton_files_with_box_barriers_and_species_chain() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(
        &dir,
        "demon.txt",
        "4\n# edmd box 2 1\n# edmd barrier x 1 door 0.3 0.7 demon 1.2 0.8\n0.5 0.5 0.01 0.001 0.05 1 255 0 0\n0.5 0.2 -0.02 0.003 0.05 1 0 0 255 1\n1.5 0.5 -0.01 0.002 0.05 1 0 255 0 1\n1.5 0.8 0.002 0.001 0.05 1 0 255 0\n",
    );
    let o = dir.path().join("o.txt");
    let out = run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "500",
            "--output",
            o.to_str().unwrap(),
            "--check",
            "--json",
        ],
        None,
    );
    let s = summary(&out);
    assert!(s["barrier_events"].as_u64().unwrap() > 0, "{s}");
    let text = std::fs::read_to_string(&o).unwrap();
    assert!(
        text.contains("# edmd box 2.0 1.0")
            && text.contains("# edmd barrier x 1.0 door 0.3 0.7 demon 1.2 0.8"),
        "{text}"
    );
    // Species survive the round trip, and the written file runs again.
    assert_eq!(
        text.lines().filter(|l| l.ends_with(" 1")).count(),
        2,
        "{text}"
    );
    ok_stdout(&run(
        "edmd",
        &["run", o.to_str().unwrap(), "--until", "510"],
        None,
    ));
}

#[test]
fn a_disc_cutting_a_barrier_is_refused_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(
        &dir,
        "cut.txt",
        "1\n# edmd barrier x 0.5\n0.5 0.5 0 0 0.1 1 1 1 1\n",
    );
    let out = run("edmd", &["run", &f, "--until", "1"], None);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("cut.txt:3: this disc cuts into barrier 1"),
        "{err}"
    );
}

#[test]
fn measurements_write_csv_files_and_join_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let m = dir.path().join("m");
    let out = run(
        "edmd",
        &[
            "run",
            example("gas-300.txt").to_str().unwrap(),
            "--until",
            "400",
            "--measure",
            "temperature,pressure,collisions,speeds,msd,species",
            "--sample-every",
            "20",
            "--measure-dir",
            m.to_str().unwrap(),
            "--json",
        ],
        None,
    );
    let s = summary(&out);
    let meas = &s["measurements"];
    // Temperature is constant (energy is conserved): kT = sum m v^2 / 2N.
    let t = &meas["temperature"];
    assert!(
        (t["max"].as_f64().unwrap() / t["min"].as_f64().unwrap() - 1.0).abs() < 1e-12,
        "{t}"
    );
    // Wall and virial pressure agree within their errors.
    let p = &meas["pressure"];
    let (pv, pw) = (&p["virial"], &p["wall"]);
    let diff = (pv["value"].as_f64().unwrap() - pw["value"].as_f64().unwrap()).abs();
    let err = pv["error"]
        .as_f64()
        .unwrap()
        .hypot(pw["error"].as_f64().unwrap());
    assert!(diff < 4.0 * err, "{p}");
    assert!(
        meas["speeds"]["ks_p_value"].as_f64().unwrap() > 1e-3,
        "{meas}"
    );
    assert!(meas["collisions"]["mean_free_path"].as_f64().unwrap() > 0.0);
    for f in [
        "temperature.csv",
        "pressure.csv",
        "collision_frequency.csv",
        "free_paths.csv",
        "free_times.csv",
        "speeds.csv",
        "msd.csv",
        "species.csv",
    ] {
        let text = std::fs::read_to_string(m.join(f)).unwrap_or_else(|_| panic!("{f} missing"));
        assert!(text.lines().count() >= 3, "{f}: {text}");
    }
    assert_eq!(
        std::fs::read_to_string(m.join("temperature.csv"))
            .unwrap()
            .lines()
            .count(),
        1 + 20
    );
}

#[test]
fn a_closed_pipe_is_not_a_panic() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_particles"))
        .args([shared!("assignment/normal.txt").to_str().unwrap(), "20"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
}

/// `edmd gen fluid --species ... --reaction ...` into `dir/name`: 400 discs at packing 0.3 in a
/// periodic box, kT 1 (the generator's).
fn reactive_fluid(dir: &tempfile::TempDir, name: &str, species: &str, rules: &[&str]) -> String {
    let path = dir.path().join(name).to_str().unwrap().to_string();
    let mut args = vec![
        "gen",
        "fluid",
        "--n",
        "400",
        "--packing",
        "0.3",
        "--boundary",
        "periodic",
        "--species",
        species,
        "-o",
        &path,
    ];
    for r in rules {
        args.extend_from_slice(&["--reaction", r]);
    }
    ok_stdout(&run("edmd", &args, None));
    path
}

/// A file's reaction rules make its run reactive: the summary counts each rule's reactions
/// and the heat released, the energy less that heat is conserved, and the state written keeps
/// the rules and the discs' new species (and reads back).
#[test]
fn reactive_runs_report_their_reactions_and_write_their_rules_back() {
    let dir = tempfile::tempdir().unwrap();
    let f = reactive_fluid(
        &dir,
        "r.txt",
        "0.5,0.5",
        &[
            "0 + 1 -> 2 + 2 activation 1 heat 0.5",
            "2+2->0+1 activation 2 probability 0.5 heat -0.5",
        ],
    );
    let text = std::fs::read_to_string(&f).unwrap();
    assert!(
        text.contains("# edmd reaction 0 + 1 -> 2 + 2 activation 1.0 heat 0.5\n# edmd reaction 2 + 2 -> 0 + 1 activation 2.0 probability 0.5 heat -0.5\n"),
        "{text}"
    );
    let out = dir.path().join("out.txt");
    let s = summary(&run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "10",
            "-o",
            out.to_str().unwrap(),
            "--json",
        ],
        None,
    ));
    let rules = s["reactions"].as_array().unwrap();
    assert_eq!(rules.len(), 2);
    assert_eq!(rules[0]["rule"], "0 + 1 -> 2 + 2 activation 1.0 heat 0.5");
    assert_eq!(rules[0]["reactants"], serde_json::json!([0, 1]));
    let (forward, back) = (
        rules[0]["reactions"].as_u64().unwrap(),
        rules[1]["reactions"].as_u64().unwrap(),
    );
    assert!(forward > 50 && back > 0, "{s}");
    // Each forward reaction releases 0.5, each backward one takes 0.5 back.
    let heat = s["reaction_heat"].as_f64().unwrap();
    assert_eq!(heat, 0.5 * (forward as f64 - back as f64));
    assert!(
        s["relative_energy_change"].as_f64().unwrap().abs() < 1e-12,
        "{s}"
    );
    // The state written: the rules, and species 2 where the reactions made it (in its colour).
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(written.contains("# edmd reaction 0 + 1 -> 2 + 2 activation 1.0 heat 0.5\n"));
    let twos = written
        .lines()
        .filter(|l| !l.starts_with('#') && l.ends_with(" 2"))
        .count() as u64;
    assert_eq!(twos, 2 * (forward - back));
    let green = written
        .lines()
        .filter(|l| l.ends_with(" 44 160 44 2"))
        .count() as u64;
    assert_eq!(green, twos, "species 2 takes its colour");
    // It runs on, reactive, from the time it is at.
    let again = summary(&run(
        "edmd",
        &["run", out.to_str().unwrap(), "--until", "12", "--json"],
        None,
    ));
    assert_eq!(again["reactions"].as_array().unwrap().len(), 2);
    // The human summary says it in a line.
    let human = ok_stdout(&run("edmd", &["run", &f, "--until", "10"], None));
    assert!(
        human.contains(&format!(
            "reactions: {forward} by 0 + 1 -> 2 + 2 activation 1.0 heat 0.5, {back} by 2 + 2 -> 0 + 1 activation 2.0 probability 0.5 heat -0.5; heat released {heat}"
        )),
        "{human}"
    );
}

/// A rule whose activation energy no pair reaches never fires, and the run is the hard-disc run
/// bit for bit: a collision the rules pass over is the elastic collision.
#[test]
fn rules_that_never_fire_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let f = reactive_fluid(&dir, "plain.txt", "0.5,0.5", &[]);
    let text = std::fs::read_to_string(&f).unwrap();
    let reactive = text.replacen('\n', "\n# edmd reaction 0 + 1 -> 1 + 1 activation 1e6\n", 1);
    let g = write(&dir, "never.txt", &reactive);
    let state = |file: &str, out: &str| {
        let o = dir.path().join(out);
        let s = summary(&run(
            "edmd",
            &[
                "run",
                file,
                "--until",
                "20",
                "-o",
                o.to_str().unwrap(),
                "--json",
            ],
            None,
        ));
        let text = std::fs::read_to_string(o).unwrap();
        let discs: Vec<String> = text
            .lines()
            .filter(|l| !l.starts_with("# edmd reaction"))
            .map(String::from)
            .collect();
        (s["disc_collisions"].clone(), discs)
    };
    let (plain_collisions, plain) = state(&f, "a.txt");
    let (collisions, with_rules) = state(&g, "b.txt");
    assert_eq!(collisions, plain_collisions);
    assert!(
        with_rules == plain,
        "a rule that never fires changed the run"
    );
}

/// `--measure kinetics` measures each rule's rate constant, which in an equilibrium fluid is
/// the line-of-centres value, Enskog's collision rate per pair times `exp(-E*/kT)` (theory in
/// `edmd_core::measure::theory::line_of_centres_rate_constant`; Present, *Kinetic Theory of
/// Gases* (1958), section 8.2): the rule `0 + 1 -> 1 + 0` exchanges the species, so the
/// fluid stays as it was. 2D discs at packing 0.3, kT 1, E* = 1: measured within three block
/// errors plus 2% (the contact value of Henderson's equation of state; 400 discs), and the
/// species counts, written to kinetics.csv at every sample, stay at 200 each.
#[test]
fn kinetics_measures_the_line_of_centres_rate_constant() {
    use edmd::engine::measure::theory::line_of_centres_rate_constant;
    let dir = tempfile::tempdir().unwrap();
    let f = reactive_fluid(&dir, "eq.txt", "0.5,0.5", &["0 + 1 -> 1 + 0 activation 1"]);
    let m = dir.path().join("m");
    let s = summary(&run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "200",
            "--measure",
            "kinetics,temperature",
            "--sample-every",
            "10",
            "--out-dir",
            m.to_str().unwrap(),
            "--json",
        ],
        None,
    ));
    let meas = &s["measurements"];
    let kt = meas["temperature"]["mean"].as_f64().unwrap();
    assert!((kt - 1.0).abs() < 1e-9, "{kt}");
    let kin = &meas["kinetics"];
    assert_eq!(kin["samples"], 20);
    assert_eq!(kin["counts"], serde_json::json!([200, 200]));
    let rule = &kin["rules"][0];
    assert_eq!(rule["rule"], "0 + 1 -> 1 + 0");
    assert_eq!(rule["reactions"], s["reactions"][0]["reactions"]);
    let k = &rule["rate_constant"];
    let (value, error) = (k["value"].as_f64().unwrap(), k["error"].as_f64().unwrap());
    assert_eq!(k["blocks"], 20);
    let theory = line_of_centres_rate_constant(0.3, 1.0, kt, 1.0, 2, 1.0);
    assert!(
        (value - theory).abs() < 3.0 * error + 0.02 * theory,
        "k = {value} +- {error}, theory {theory}"
    );
    assert!(error < 0.02 * theory, "{error}");
    let csv = std::fs::read_to_string(m.join("kinetics.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("time,species0,species1"));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 21);
    assert!(rows.iter().all(|r| r.ends_with(",200.0,200.0")), "{csv}");
}

/// The draws of rules with a probability below 1 come from `--seed` (default 1): the same seed
/// gives the same run, another seed another run.
#[test]
fn the_seed_of_the_draws_is_the_runs() {
    let dir = tempfile::tempdir().unwrap();
    let f = reactive_fluid(
        &dir,
        "p.txt",
        "0.5,0.5",
        &["0 + 1 -> 1 + 0 activation 0.5 probability 0.5"],
    );
    let out = |seed: Option<&str>, name: &str| {
        let o = dir.path().join(name);
        let mut args = vec!["run", &f, "--until", "5", "-o", o.to_str().unwrap()];
        if let Some(s) = seed {
            args.extend_from_slice(&["--seed", s]);
        }
        ok_stdout(&run("edmd", &args, None));
        std::fs::read(o).unwrap()
    };
    let default = out(None, "a.txt");
    assert!(
        out(Some("1"), "b.txt") == default,
        "--seed 1 is the default"
    );
    assert!(
        out(Some("2"), "c.txt") != default,
        "--seed 2 draws otherwise"
    );
}

/// `edmd pack` compresses a file's particles, keeping their species, and writes the file's
/// reaction rules with the packing, so that the denser system reacts as the file did.
#[test]
fn a_packing_keeps_its_files_reaction_rules() {
    let dir = tempfile::tempdir().unwrap();
    let f = reactive_fluid(&dir, "loose.txt", "0.5,0.5", &["0+1->1+1 activation 2"]);
    let packed = dir.path().join("dense.txt");
    let packed = packed.to_str().unwrap();
    ok_stdout(&run(
        "edmd",
        &["pack", &f, "--packing", "0.5", "-o", packed],
        None,
    ));
    let text = std::fs::read_to_string(packed).unwrap();
    assert!(
        text.contains("\n# edmd reaction 0 + 1 -> 1 + 1 activation 2.0\n"),
        "{text}"
    );
    let species = |t: &str| {
        let mut s: Vec<char> = t
            .lines()
            .filter(|l| !l.starts_with('#') && l.split_whitespace().count() == 10)
            .map(|l| l.chars().last().unwrap())
            .collect();
        s.sort_unstable();
        s
    };
    assert_eq!(
        species(&text),
        species(&std::fs::read_to_string(&f).unwrap())
    );
    let s = summary(&run(
        "edmd",
        &["run", packed, "--until", "1", "--json"],
        None,
    ));
    assert_eq!(s["reactions"].as_array().unwrap().len(), 1);
}
