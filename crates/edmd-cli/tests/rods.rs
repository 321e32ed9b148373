//! Rods on a line from the command line: `gen fluid --dim 1` (seeded), `run` on 1D files
//! (measured, checkpointed and continued bit for bit, a trajectory), `render` of the strip,
//! `experiment eos --dim 1` against Tonks's exact equation of state, and the one-line
//! refusals of malformed 1D input and of what a line cannot do.

use crate::support::{ok_stdout, refused, run, summary, write};

fn gen(dir: &tempfile::TempDir, name: &str, extra: &[&str]) -> String {
    let path = dir.path().join(name);
    let path = path.to_str().unwrap().to_string();
    let mut args = vec![
        "gen",
        "fluid",
        "--dim",
        "1",
        "--n",
        "200",
        "--packing",
        "0.6",
        "-o",
        &path,
    ];
    if !extra.contains(&"--seed") {
        args.extend_from_slice(&["--seed", "4"]);
    }
    args.extend_from_slice(extra);
    ok_stdout(&run("edmd", &args, None));
    path
}

#[test]
fn generated_rods_are_seeded_and_run_with_energy_kept() {
    let dir = tempfile::tempdir().unwrap();
    let f = gen(&dir, "f.txt", &[]);
    let text = std::fs::read_to_string(&f).unwrap();
    assert!(
        text.starts_with(
            "200\n# edmd dim 1\n# edmd box 333.33333333333337\n# edmd boundary periodic\n"
        ),
        "{}",
        &text[..80]
    );
    // The same seed gives the same file, another seed another.
    assert_eq!(
        std::fs::read_to_string(gen(&dir, "g.txt", &[])).unwrap(),
        text
    );
    let other = gen(&dir, "h.txt", &["--seed", "5"]);
    assert_ne!(std::fs::read_to_string(other).unwrap(), text);
    let out = dir.path().join("out.txt");
    let s = summary(&run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "20",
            "--json",
            "--check",
            "-o",
            out.to_str().unwrap(),
        ],
        None,
    ));
    assert_eq!(s["dim"], 1);
    assert_eq!(s["n"], 200);
    assert!(s["disc_collisions"].as_u64().unwrap() > 2000, "{s}");
    assert!(s["relative_energy_change"].as_f64().unwrap().abs() < 1e-12);
    let written = std::fs::read_to_string(out).unwrap();
    assert!(written.starts_with("200\n# edmd dim 1\n"), "{written}");
    assert!(written.contains("# edmd time 20"), "{written}");
    // Between walls, with --kt.
    let w = gen(&dir, "w.txt", &["--boundary", "walls", "--kt", "2"]);
    let s = summary(&run(
        "edmd",
        &["run", &w, "--until", "5", "--json", "--check"],
        None,
    ));
    assert!(s["wall_collisions"].as_u64().unwrap() > 0, "{s}");
}

#[test]
fn a_checkpointed_run_of_rods_continues_bit_for_bit_with_its_measurements() {
    let dir = tempfile::tempdir().unwrap();
    let f = gen(&dir, "f.txt", &[]);
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let measure = ["--measure", "pressure", "--sample-every", "1"];
    let mut straight = vec!["run", &f, "--until", "30", "-o"];
    let straight_out = p("straight.txt");
    straight.push(&straight_out);
    straight.extend_from_slice(&measure);
    let straight_dir = p("m1");
    straight.extend_from_slice(&["--out-dir", &straight_dir]);
    ok_stdout(&run("edmd", &straight, None));
    let ck = p("ck");
    let mut first = vec!["run", &f, "--until", "12", "--checkpoint", &ck];
    first.extend_from_slice(&measure);
    ok_stdout(&run("edmd", &first, None));
    let resumed_out = p("resumed.txt");
    let resumed_dir = p("m2");
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            &ck,
            "--until",
            "30",
            "-o",
            &resumed_out,
            "--out-dir",
            &resumed_dir,
        ],
        None,
    ));
    assert_eq!(
        std::fs::read_to_string(&straight_out).unwrap(),
        std::fs::read_to_string(&resumed_out).unwrap()
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("m1/pressure.csv")).unwrap(),
        std::fs::read_to_string(dir.path().join("m2/pressure.csv")).unwrap()
    );
}

#[test]
fn the_measured_pressure_and_the_experiment_follow_tonks() {
    let dir = tempfile::tempdir().unwrap();
    // The experiment: Z within 1.5 % of 1 / (1 - eta) and within 4 errors, at 0.2, 0.5 and
    // 0.8 with 300 rods and 400 collisions per rod (the error is about 0.3 % of Z there; see
    // the engine's test `rods.rs` for why the virial gives Tonks's law at any N).
    let out = dir.path().join("eos");
    let s = summary(&run(
        "edmd",
        &[
            "experiment",
            "eos",
            "--dim",
            "1",
            "--n",
            "300",
            "--packing",
            "0.2,0.5,0.8",
            "--collisions",
            "400",
            "--melt",
            "20",
            "--out-dir",
            out.to_str().unwrap(),
            "--json",
        ],
        None,
    ));
    assert_eq!(s["experiment"], "eos");
    assert_eq!(s["dim"], 1);
    let results = s["results"].as_array().unwrap();
    assert_eq!(results.len(), 3);
    for r in results {
        let eta = r["packing"].as_f64().unwrap();
        let (z, err) = (r["Z"].as_f64().unwrap(), r["Z_err"].as_f64().unwrap());
        let tonks = r["tonks"].as_f64().unwrap();
        assert_eq!(tonks, 1.0 / (1.0 - eta));
        assert!(r.get("henderson").is_none() && r.get("pieprzyk").is_none());
        assert!(
            (z / tonks - 1.0).abs() < 0.015,
            "eta {eta}: Z {z} vs {tonks}"
        );
        assert!(
            (z - tonks).abs() < 4.0 * err,
            "eta {eta}: Z {z} +- {err} vs {tonks}"
        );
        // The collision rate and the one Z implies agree.
        let rate = r["collision_rate"].as_array().unwrap();
        let (measured, implied) = (rate[0].as_f64().unwrap(), rate[1].as_f64().unwrap());
        assert!(
            (measured / implied - 1.0).abs() < 0.03,
            "{measured} {implied}"
        );
    }
    let csv = std::fs::read_to_string(out.join("eos.csv")).unwrap();
    assert!(csv.starts_with("packing,Z,Z_err,tonks,"), "{csv}");
    assert!(out.join("eos.png").exists() && out.join("eos.svg").exists());
    // `run --measure pressure` on a generated line says the same at 0.6: Z = 2.5.
    let f = gen(&dir, "f.txt", &[]);
    let s = summary(&run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "200",
            "--measure",
            "pressure",
            "--out-dir",
            dir.path().join("m").to_str().unwrap(),
            "--json",
        ],
        None,
    ));
    let p = &s["measurements"]["pressure"];
    assert_eq!(p["length"].as_f64().unwrap(), 200.0 / 0.6);
    let z = p["Z"]["value"].as_f64().unwrap();
    assert!((z / 2.5 - 1.0).abs() < 0.02, "Z {z}");
}

#[test]
fn rods_render_as_a_strip_and_go_into_a_trajectory() {
    let dir = tempfile::tempdir().unwrap();
    let f = gen(&dir, "f.txt", &[]);
    let frames = dir.path().join("frames/");
    let out = run(
        "edmd",
        &[
            "render",
            &f,
            "--until",
            "1",
            "--fps",
            "2",
            "--size",
            "600x60",
            "-o",
            frames.to_str().unwrap(),
        ],
        None,
    );
    let text = ok_stdout(&out);
    assert!(text.contains("3 frames of 600x60"), "{text}");
    assert!(frames.join("frame_000002.png").exists());
    let traj = dir.path().join("t.xyz");
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            &f,
            "--until",
            "2",
            "--every",
            "1",
            "--trajectory",
            traj.to_str().unwrap(),
        ],
        None,
    ));
    let xyz = std::fs::read_to_string(traj).unwrap();
    assert_eq!(xyz.matches("Lattice=").count(), 3);
    assert!(xyz.contains("pbc=\"T F F\""), "{}", &xyz[..200]);
}

#[test]
fn bad_1d_lines_and_what_a_line_cannot_do_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = write(
        &dir,
        "bad.txt",
        "2\n# edmd dim 1\n# edmd box 10\n1 0.5 0.5 1 0 0 0\n3 0.5 0.5 0 0 0\n",
    );
    refused(
        &run("edmd", &["run", &bad, "--until", "1"], None),
        &[
            "bad.txt:5:",
            "expected 7 fields (rx vx radius mass r g b)",
            "found 6",
        ],
    );
    let negative = write(
        &dir,
        "neg.txt",
        "1\n# edmd dim 1\n# edmd box 10\n1 0.5 -0.5 1 0 0 0\n",
    );
    refused(
        &run(
            "edmd",
            &["render", &negative, "--until", "1", "-o", "x.gif"],
            None,
        ),
        &["neg.txt:4:", "radius must be > 0"],
    );
    let overlap = write(
        &dir,
        "overlap.txt",
        "2\n# edmd dim 1\n# edmd box 10\n1 0.5 0.5 1 0 0 0\n1.5 0.5 0.5 1 0 0 0\n",
    );
    refused(
        &run("edmd", &["run", &overlap, "--until", "1"], None),
        &["overlap.txt"],
    );
    let sheared = write(
        &dir,
        "shear.txt",
        "1\n# edmd dim 1\n# edmd boundary periodic\n# edmd shear 1\n0.5 0 0.1 1 0 0 0\n",
    );
    refused(
        &run("edmd", &["run", &sheared, "--until", "1"], None),
        &["shear.txt:4:", "no y axis"],
    );
    let f = gen(&dir, "f.txt", &[]);
    // Measurements that mean nothing on a line.
    for m in ["speeds", "viscosity", "conductivity"] {
        refused(
            &run("edmd", &["run", &f, "--until", "1", "--measure", m], None),
            &[&format!("--measure {m}: not on a line (1D)")],
        );
    }
    // Options across a missing axis, and formats that hold no line.
    let o = dir.path().join("x.txt");
    let o = o.to_str().unwrap();
    for (extra, words) in [
        (&["--shear", "1"][..], &["no y axis"][..]),
        (
            &["--course"][..],
            &["course format holds 2D systems only"][..],
        ),
    ] {
        let mut args = vec!["gen", "fluid", "--dim", "1", "-o", o];
        args.extend_from_slice(extra);
        refused(&run("edmd", &args, None), words);
    }
    refused(
        &run("edmd", &["gen", "lattice", "--dim", "1", "-o", o], None),
        &["--dim 1 makes fluids only"],
    );
    refused(
        &run(
            "edmd",
            &["gen", "fluid", "--dim", "1", "--packing", "1", "-o", o],
            None,
        ),
        &["outside (0, 1)"],
    );
    refused(
        &run("edmd", &["pack", &f, "-o", o], None),
        &["1D file (rods on a line)"],
    );
    refused(
        &run("edmd", &["pack", "--dim", "1", "--n", "10", "-o", o], None),
        &["--dim 1"],
    );
    refused(
        &run(
            "edmd",
            &[
                "render", &f, "--until", "1", "--view", "30,20", "-o", "x.gif",
            ],
            None,
        ),
        &["--view applies to 3D files", "1D"],
    );
    refused(
        &run("edmd", &["experiment", "maxwell", "--dim", "1"], None),
        &["--dim 1"],
    );
}
