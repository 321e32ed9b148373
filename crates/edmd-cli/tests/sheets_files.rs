//! Self-gravitating sheets through the files, `edmd gen sheets` and `edmd run`: a generated
//! water bag is uniform in its rectangle of phase space with its `# edmd self-gravity` line;
//! `edmd run` conserves the energy with the sheets' potential energy counted, reports the
//! coupling, that energy and the virial ratio, and meets the virial theorem on time averages;
//! the states it writes keep the directive and run again; checkpoints continue bit for bit;
//! the example runs; bad files and options are refused in one line with exit status 2, before
//! anything is written.

use crate::support::{example, refused, run, summary, write};

fn f(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is not a number in {v}"))
}

/// `edmd gen sheets` with `extra` options into `path`, asserting success.
fn gen_sheets(path: &str, extra: &[&str]) {
    let mut args = vec!["gen", "sheets"];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["-o", path]);
    let out = run("edmd", &args, None);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The numbers of the rod lines of a Princeton file (`x v radius mass r g b`).
fn rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .skip(1)
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(' ').map(|w| w.parse().unwrap()).collect())
        .collect()
}

/// The sheets' potential energy of equal rods of mass 1 from their lines, worked out afresh:
/// the positions sorted, each less the contact distances of the rods to its left (the
/// sheets' positions), then `coupling sum over pairs |y_i - y_j|`, which in order is
/// `coupling sum_r y_r (2 r - (N - 1))`.
fn sheets_energy(rows: &[Vec<f64>], coupling: f64) -> f64 {
    let mut x: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    x.sort_by(f64::total_cmp);
    let sigma = 2.0 * rows[0][2];
    let n = x.len() as f64;
    x.iter()
        .enumerate()
        .map(|(r, &x)| coupling * (x - r as f64 * sigma) * (2.0 * r as f64 - (n - 1.0)))
        .sum()
}

/// `edmd run FILE --until T --json` (with `extra`), its summary.
fn run_json(file: &str, until: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["run", file, "--until", until, "--json"];
    args.extend_from_slice(extra);
    summary(&run("edmd", &args, None))
}

#[test]
fn gen_sheets_is_a_water_bag_with_its_self_gravity() {
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("bag.txt");
    let bag = bag.to_str().unwrap();
    gen_sheets(bag, &["--n", "400", "--seed", "3"]);
    let text = std::fs::read_to_string(bag).unwrap();
    let head: Vec<&str> = text.lines().take(4).collect();
    assert_eq!(head[0], "400");
    assert_eq!(head[1], "# edmd dim 1", "{head:?}");
    assert!(head[2].starts_with("# edmd box "), "{head:?}");
    // The coupling 1/N by default, so that the whole mass pulls with 1.
    assert_eq!(head[3], "# edmd self-gravity 0.0025", "{head:?}");
    let length: f64 = head[2]["# edmd box ".len()..].parse().unwrap();
    // The walls 1.25 times as far from the middle as the energy lets a sheet go, or as 16
    // bag widths if that is nearer: far from the bag, which spans [-1, 1].
    assert!((20.0..=40.01).contains(&length), "{length}");
    let r = rows(&text);
    assert_eq!(r.len(), 400);
    assert!(r.iter().all(|p| p[2] == 1e-7 && p[3] == 1.0), "{:?}", r[0]);
    // Positions uniform in [-1, 1] and velocities in [-1, 1], both shifted to put the centre
    // of mass at rest in the middle of the line: the means are 0 to rounding, the extremes
    // near 1 (400 draws leave about 1/200 to the edge), the variances 1/3 (to 10%: 400
    // samples give about 5%).
    let n = r.len() as f64;
    let mid = length / 2.0;
    for (k, centre) in [(0, mid), (1, 0.0)] {
        let mean = r.iter().map(|p| p[k]).sum::<f64>() / n;
        assert!(
            (mean - centre).abs() < 1e-9 * length,
            "column {k}: mean {mean}"
        );
        let far = r.iter().map(|p| (p[k] - centre).abs()).fold(0.0, f64::max);
        assert!(far > 0.95 && far < 1.05, "column {k}: farthest {far}");
        let var = r.iter().map(|p| (p[k] - centre).powi(2)).sum::<f64>() / n;
        assert!((3.0 * var - 1.0).abs() < 0.1, "column {k}: variance {var}");
    }
    // Options change what they name.
    let wide = dir.path().join("wide.txt");
    gen_sheets(
        wide.to_str().unwrap(),
        &[
            "--n",
            "50",
            "--width",
            "2",
            "--speed",
            "3",
            "--coupling",
            "0.5",
        ],
    );
    let text = std::fs::read_to_string(&wide).unwrap();
    assert!(text.contains("\n# edmd self-gravity 0.5\n"), "{text}");
    let r = rows(&text);
    let vmax = r.iter().map(|p| p[1].abs()).fold(0.0, f64::max);
    assert!(vmax > 2.0 && vmax < 3.2, "{vmax}");
}

#[test]
fn run_conserves_the_energy_and_meets_the_virial_theorem() {
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("bag.txt");
    let bag = bag.to_str().unwrap();
    gen_sheets(bag, &["--n", "200"]);
    let end = dir.path().join("end.txt");
    let end = end.to_str().unwrap();
    // 60 dynamical times (the unit is sqrt(width / (coupling M)) = 1), sampled 600 times.
    let s = run_json(
        bag,
        "60",
        &["--measure", "energy", "--sample-every", "0.1", "-o", end],
    );
    assert_eq!(f(&s, "self_gravity"), 0.005);
    assert!(f(&s, "disc_collisions") > 1e5, "{s}");
    // Exact flights: the energy, kinetic plus the sheets' U, is conserved to rounding. Left
    // out, U would show as a change of order 10% (K alone swings with the bag).
    let change = f(&s, "relative_energy_change");
    assert!(change.abs() < 1e-10, "{s}");
    // The summary's U is the sheets' energy of the state written, worked out afresh.
    let written = rows(&std::fs::read_to_string(end).unwrap());
    let u = sheets_energy(&written, 0.005);
    assert!(
        (f(&s, "sheets_energy") - u).abs() < 1e-9 * u,
        "{} against {u}",
        f(&s, "sheets_energy")
    );
    let k: f64 = written.iter().map(|p| 0.5 * p[1] * p[1]).sum();
    assert!((f(&s, "virial_ratio") - 2.0 * k / u).abs() < 1e-9, "{s}");
    // The virial theorem for a potential homogeneous of degree 1 in the separations:
    // 2 <K> = <U> on time averages (the bag's 2K/U oscillates by about 10%, in beats; the
    // average over 60 dynamical times is within a few per cent; measured 0.9995).
    let e = &s["measurements"]["energy"];
    let kinetic = e["kinetic_per_particle"]["value"].as_f64().unwrap();
    let potential = e["potential_per_particle"]["value"].as_f64().unwrap();
    let ratio = 2.0 * kinetic / potential;
    assert!((ratio - 1.0).abs() < 0.05, "2<K>/<U> = {ratio}: {e}");
    // The human summary names the coupling and the virial ratio.
    let out = run("edmd", &["run", bag, "--until", "1"], None);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("self-gravity: coupling 0.005, sheets' potential energy")
            && text.contains("virial ratio 2K/U"),
        "{text}"
    );
    // Without self-gravity the field is null and the others absent.
    let rods = dir.path().join("rods.txt");
    let rods = rods.to_str().unwrap();
    let gen = run(
        "edmd",
        &["gen", "fluid", "--dim", "1", "--n", "20", "-o", rods],
        None,
    );
    assert!(gen.status.success());
    let plain = run_json(rods, "1", &[]);
    assert!(plain["self_gravity"].is_null(), "{plain}");
    assert!(plain.get("sheets_energy").is_none() && plain.get("virial_ratio").is_none());
}

#[test]
fn a_written_sheets_state_keeps_its_self_gravity_and_a_checkpoint_continues() {
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("bag.txt");
    let bag = bag.to_str().unwrap();
    // The default rods, 2e-7 long: hard rods that short could not be placed by the clock
    // past about t = 0.1 (`Simulation::clock_limit`), but sheets keep their order and have
    // no such limit, in a run and in the state it writes.
    gen_sheets(bag, &["--n", "100", "--coupling", "0.03"]);
    let mid = dir.path().join("mid.txt");
    let mid = mid.to_str().unwrap();
    let ck = dir.path().join("bag.ck");
    let ck = ck.to_str().unwrap();
    run_json(bag, "2.5", &["-o", mid, "--checkpoint", ck]);
    let text = std::fs::read_to_string(mid).unwrap();
    assert!(text.contains("# edmd time 2.5\n"), "{}", &text[..200]);
    assert!(
        text.contains("\n# edmd self-gravity 0.03\n"),
        "{}",
        &text[..200]
    );
    // The state written runs on under the same self-gravity, conserving the energy.
    let again = run_json(mid, "5", &["--check"]);
    assert_eq!(f(&again, "self_gravity"), 0.03);
    assert!(f(&again, "relative_energy_change").abs() < 1e-10, "{again}");
    // The checkpoint continues as the run never stopped.
    let (a, b) = (dir.path().join("a.txt"), dir.path().join("b.txt"));
    let on = run_json(ck, "5", &["-o", a.to_str().unwrap()]);
    let straight = run_json(bag, "5", &["-o", b.to_str().unwrap()]);
    for key in [
        "disc_collisions",
        "wall_collisions",
        "sheets_energy",
        "virial_ratio",
    ] {
        assert_eq!(on[key], straight[key], "{key}: {on} against {straight}");
    }
    let (a, b) = (
        std::fs::read_to_string(&a).unwrap(),
        std::fs::read_to_string(&b).unwrap(),
    );
    assert!(a.contains("# edmd self-gravity 0.03\n"));
    assert_eq!(a, b);
}

#[test]
fn the_example_water_bag_runs() {
    let bag = example("sheets-water-bag.txt");
    let text = std::fs::read_to_string(&bag).unwrap();
    assert!(text.contains("# edmd self-gravity 0.005\n"));
    let s = run_json(bag.to_str().unwrap(), "5", &["--check"]);
    assert_eq!(f(&s, "n"), 200.0);
    assert_eq!(f(&s, "self_gravity"), 0.005);
    assert!(f(&s, "relative_energy_change").abs() < 1e-10, "{s}");
}

#[test]
fn bad_sheets_files_are_refused_in_one_line_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let never = dir.path().join("never.txt");
    let o = never.to_str().unwrap();
    let rod = "1 0 .1 1 0 0 0\n";
    let line = "1\n# edmd dim 1\n# edmd box 8\n";
    for (text, words) in [
        (
            "1\n# edmd box 8 8\n# edmd self-gravity 1\n1 1 0 0 .5 1 0 0 0\n".to_string(),
            vec![":3:", "1D file", "not in this 2D file"],
        ),
        (
            "1\n# edmd dim 3\n# edmd self-gravity 1\n.5 .5 .5 0 0 0 .1 1 0 0 0\n".to_string(),
            vec![":3:", "3D file"],
        ),
        (
            format!("{line}# edmd boundary periodic\n# edmd self-gravity 1\n{rod}"),
            vec![":5:", "walls"],
        ),
        (
            format!("{line}# edmd gravity x -1\n# edmd self-gravity 1\n{rod}"),
            vec![":5:", "a field (line 4)"],
        ),
        (
            format!("{line}# edmd self-gravity 1\n# edmd potential 0 0 .3 -1\n{rod}"),
            vec![":4:", "a stepped potential (line 5)"],
        ),
        (
            format!("{line}# edmd self-gravity 1\n# edmd reaction 0 + 0 -> 1 + 1\n{rod}"),
            vec![":4:", "reaction rules (line 5)"],
        ),
        (
            format!("{line}# edmd self-gravity 1\n# edmd restitution 0.9\n{rod}"),
            vec![":4:", "restitution (line 5)"],
        ),
        (
            format!("{line}# edmd self-gravity 1\n# edmd self-gravity 2\n{rod}"),
            vec![
                ":5:",
                "a second '# edmd self-gravity' line (the first is line 4)",
            ],
        ),
        (
            format!("{line}# edmd self-gravity\n{rod}"),
            vec![":4:", "expected 'self-gravity C'"],
        ),
        (
            format!("{line}# edmd self-gravity 1 2\n{rod}"),
            vec![":4:", "expected 'self-gravity C'"],
        ),
        (
            format!("{line}# edmd self-gravity heavy\n{rod}"),
            vec![":4:", "C is not a number"],
        ),
        (
            format!("{line}# edmd self-gravity inf\n{rod}"),
            vec![":4:", "C is not finite"],
        ),
        (
            format!("{line}# edmd self-gravity 0\n{rod}"),
            vec![":4:", "above 0"],
        ),
        (
            format!("{line}# edmd self-gravity -1\n{rod}"),
            vec![":4:", "above 0"],
        ),
    ] {
        let file = write(&dir, "bad.txt", &text);
        let out = run("edmd", &["run", &file, "--until", "1", "-o", o], None);
        refused(&out, &[&["bad.txt"][..], &words[..]].concat());
        assert!(!never.exists(), "{text} wrote a file");
    }
    // With the swap rule or multi-disc collisions the engine refuses, naming the file's line.
    let file = write(
        &dir,
        "pair.txt",
        "2\n# edmd dim 1\n# edmd box 8\n# edmd self-gravity 1\n2 0 .1 1 0 0 0\n6 0 .1 1 0 0 0\n",
    );
    for extra in [["--multi", ""], ["--rule", "swap"]] {
        let mut args = vec!["run", &file, "--until", "1", "-o", o];
        args.extend(extra.iter().filter(|w| !w.is_empty()));
        let out = run("edmd", &args, None);
        refused(&out, &["pair.txt", "'# edmd self-gravity' line"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.matches("self-gravity").count(), 2, "{err}");
        assert!(!never.exists(), "{extra:?} wrote a file");
    }
    // And the same pair runs without them.
    let s = run_json(&file, "1", &[]);
    assert_eq!(f(&s, "self_gravity"), 1.0);
}

#[test]
fn bad_gen_sheets_options_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let never = dir.path().join("never.txt");
    let o = never.to_str().unwrap();
    for (extra, words) in [
        (vec!["--dim", "2"], vec!["--dim 1", "not --dim 2"]),
        (vec!["--n", "1"], vec!["--n", "from 2"]),
        (vec!["--width", "0"], vec!["--width", "> 0"]),
        (vec!["--speed", "nan"], vec!["--speed", "finite"]),
        (vec!["--coupling", "-1"], vec!["--coupling", "> 0"]),
        (vec!["--radius", "0.01"], vec!["--radius", "a tenth"]),
        (
            vec!["--restitution", "0.9"],
            vec!["--restitution", "self-gravity"],
        ),
        (vec!["--well", "1.5"], vec!["--well", "sheets"]),
        (vec!["--gravity", "-1"], vec!["--gravity", "sheets"]),
        (vec!["--boundary", "periodic"], vec!["--boundary", "sheets"]),
        (vec!["--kt", "1"], vec!["--kt", "sheets"]),
        (vec!["--course"], vec!["course format"]),
    ] {
        let mut args = vec!["gen", "sheets"];
        args.extend_from_slice(&extra);
        args.extend_from_slice(&["-o", o]);
        refused(&run("edmd", &args, None), &words);
        assert!(!never.exists(), "{extra:?} wrote a file");
    }
    // The sheets' options belong to them alone.
    for flag in ["--width", "--coupling"] {
        refused(
            &run("edmd", &["gen", "fluid", flag, "1", "-o", o], None),
            &[flag, "does not apply"],
        );
        refused(
            &run("edmd", &["gen", "ring", flag, "1", "-o", o], None),
            &[flag, "does not apply"],
        );
    }
}
