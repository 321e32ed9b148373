//! `edmd run --checkpoint`: a run stopped and continued from its checkpoint ends bit for bit
//! where the uninterrupted run ends, and damaged checkpoints are refused in one line.

use crate::support::{example, ok_stdout, refused, run, summary};

/// Runs `file` to `t2` directly, and to `t1` with checkpoints then on to `t2` from the
/// checkpoint (twice, the second time replacing the checkpoint in place), and compares.
fn chain(file: &str, t1: &str, t2: &str, every: &str) {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let direct = summary(&run(
        "edmd",
        &["run", file, "--until", t2, "-o", &p("direct.txt"), "--json"],
        None,
    ));
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            file,
            "--until",
            t1,
            "--checkpoint",
            &p("ck"),
            "--checkpoint-every",
            every,
        ],
        None,
    ));
    let resumed = summary(&run(
        "edmd",
        &[
            "run",
            &p("ck"),
            "--until",
            t2,
            "-o",
            &p("resumed.txt"),
            "--json",
        ],
        None,
    ));
    for key in [
        "disc_collisions",
        "wall_collisions",
        "cell_crossings",
        "stale_events",
        "n",
        "dim",
    ] {
        assert_eq!(resumed[key], direct[key], "{file}: {key}");
    }
    let a = std::fs::read(p("direct.txt")).unwrap();
    assert_eq!(
        std::fs::read(p("resumed.txt")).unwrap(),
        a,
        "{file}: final states differ"
    );
    // Continuing in place: the checkpoint is replaced by the later one.
    ok_stdout(&run(
        "edmd",
        &["run", &p("ck"), "--until", t2, "--checkpoint", &p("ck")],
        None,
    ));
    ok_stdout(&run(
        "edmd",
        &["run", &p("ck"), "--until", t2, "-o", &p("again.txt")],
        None,
    ));
    assert_eq!(
        std::fs::read(p("again.txt")).unwrap(),
        a,
        "{file}: in place"
    );
}

#[test]
fn a_continued_run_ends_where_the_uninterrupted_one_does() {
    chain(example("gas-300.txt").to_str().unwrap(), "7.3", "20", "2");
    chain(
        example("spheres-500.txt").to_str().unwrap(),
        "1.1",
        "3",
        "0.5",
    );
    chain(example("course-7.txt").to_str().unwrap(), "3", "9", "1");
}

/// Measurements go on where they stopped: a run measured to T1 with checkpoints and continued
/// to T2 writes the same CSV files and the same summary as the run measured straight to T2.
#[test]
fn a_continued_run_goes_on_measuring_where_it_stopped() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let all = "temperature,pressure,collisions,speeds,msd,species";
    for (file, t1, t2) in [
        ("gas-300.txt", "7.3", "20"),
        ("spheres-500.txt", "1.1", "3"),
    ] {
        let file = example(file);
        let file = file.to_str().unwrap();
        let measured = |args: &[&str], out_dir: &str| {
            let mut all_args = args.to_vec();
            all_args.extend_from_slice(&["--measure", all, "--sample-every", "0.25", "--json"]);
            all_args.extend_from_slice(&["--measure-dir", out_dir]);
            summary(&run("edmd", &all_args, None))["measurements"].clone()
        };
        let direct = measured(&["run", file, "--until", t2], &p("direct"));
        measured(
            &["run", file, "--until", t1, "--checkpoint", &p("ck")],
            &p("first"),
        );
        // The continued run is told nothing of the measurements: the checkpoint carries them.
        let resumed = summary(&run(
            "edmd",
            &[
                "run",
                &p("ck"),
                "--until",
                t2,
                "--json",
                "--measure-dir",
                &p("resumed"),
            ],
            None,
        ))["measurements"]
            .clone();
        assert!(direct["pressure"].is_object(), "{direct}");
        assert_eq!(resumed, direct, "{file}: summaries differ");
        for csv in [
            "temperature.csv",
            "pressure.csv",
            "collision_frequency.csv",
            "free_paths.csv",
            "free_times.csv",
            "speeds.csv",
            "msd.csv",
            "species.csv",
        ] {
            let a = std::fs::read(dir.path().join("direct").join(csv)).unwrap();
            let b = std::fs::read(dir.path().join("resumed").join(csv)).unwrap();
            assert!(a.len() > 20, "{csv} is nearly empty");
            assert_eq!(a, b, "{file}: {csv} differs");
        }
        // Asking for other measurements or another interval on the way is refused.
        refused(
            &run(
                "edmd",
                &["run", &p("ck"), "--until", t2, "--measure", "pressure"],
                None,
            ),
            &["goes on measuring", "collisions"],
        );
        refused(
            &run(
                "edmd",
                &["run", &p("ck"), "--until", t2, "--sample-every", "0.5"],
                None,
            ),
            &["samples every 0.25"],
        );
    }
}

#[test]
fn damaged_or_misused_checkpoints_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let ck = dir.path().join("ck");
    let ck_s = ck.to_str().unwrap();
    let gas = example("gas-300.txt");
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            gas.to_str().unwrap(),
            "--until",
            "2",
            "--checkpoint",
            ck_s,
        ],
        None,
    ));
    let good = std::fs::read(&ck).unwrap();
    let write = |name: &str, bytes: &[u8]| {
        let f = dir.path().join(name);
        std::fs::write(&f, bytes).unwrap();
        f.to_str().unwrap().to_string()
    };
    let truncated = write("t", &good[..good.len() / 2]);
    refused(
        &run("edmd", &["run", &truncated, "--until", "5"], None),
        &["checkpoint", "truncated"],
    );
    let mut flipped = good.clone();
    flipped[good.len() / 2] ^= 0x10;
    let flipped = write("f", &flipped);
    refused(
        &run("edmd", &["run", &flipped, "--until", "5"], None),
        &["checkpoint", "checksum"],
    );
    let mut newer = good.clone();
    newer[8..12].copy_from_slice(&(edmd_core::CHECKPOINT_VERSION + 1).to_le_bytes());
    let newer = write("n", &newer);
    refused(
        &run("edmd", &["run", &newer, "--until", "5"], None),
        &["newer"],
    );
    refused(
        &run("edmd", &["run", ck_s, "--until", "1"], None),
        &["t = 2"],
    );
    refused(
        &run("edmd", &["run", ck_s, "--until", "5", "--multi"], None),
        &["carries its run's options"],
    );
    // The checkpoint may not replace the input data file or another output.
    let data = write("data.txt", &std::fs::read(&gas).unwrap());
    refused(
        &run(
            "edmd",
            &["run", &data, "--until", "1", "--checkpoint", &data],
            None,
        ),
        &["input"],
    );
    assert_eq!(std::fs::read(&data).unwrap(), std::fs::read(&gas).unwrap());
}

// `edmd render`, `particles` and `edmd view` given an edmd checkpoint (a binary file) said
// "not a text file (NUL byte)" instead of what the file is and what continues it.
#[test]
fn a_checkpoint_given_for_a_data_file_is_named_with_what_continues_it() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_owned();
    let gas = crate::support::example("gas-300.txt");
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            gas.to_str().unwrap(),
            "--until",
            "0.1",
            "--checkpoint",
            &p("run.ck"),
        ],
        None,
    ));
    ok_stdout(&run(
        "edmd",
        &[
            "pack",
            "--n",
            "20",
            "--packing",
            "0.3",
            "-o",
            &p("packed.txt"),
            "--checkpoint",
            &p("pack.ck"),
            "--checkpoint-every",
            "0",
        ],
        None,
    ));
    let run_ck = p("run.ck");
    let pack_ck = p("pack.ck");
    let gif = p("out.gif");
    let said_run = format!(
        "{run_ck}: an edmd run checkpoint, not a data file: `edmd run {run_ck}` continues it"
    );
    let said_pack = format!("{pack_ck}: an edmd packing checkpoint, not a data file: `edmd pack {pack_ck} -o OUT` continues it");
    for (program, args, said) in [
        (
            "edmd",
            vec!["render", &run_ck, "-o", &gif, "--until", "1"],
            &said_run,
        ),
        (
            "edmd",
            vec!["render", &pack_ck, "-o", &gif, "--until", "1"],
            &said_pack,
        ),
        ("particles", vec![&run_ck, "1"], &said_run),
        ("particles", vec![&pack_ck, "1"], &said_pack),
    ] {
        let out = run(program, &args, None);
        crate::support::refused(&out, &[said.as_str()]);
    }
    assert!(!std::path::Path::new(&gif).exists());
    // `edmd pack` continues its own checkpoints and names a run's.
    let out = run("edmd", &["pack", &run_ck, "-o", &p("x.txt")], None);
    crate::support::refused(&out, &["run.ck: a run checkpoint (edmd run continues it)"]);
}

/// A reactive run (rules with probabilities below 1, like reactants, heat released and taken)
/// continued from its checkpoint ends where the uninterrupted run ends, bit for bit, with the
/// same reactions, heat and kinetics; the checkpoint carries the rules and the seed of their
/// draws, so `--seed` given again must be the same.
#[test]
fn a_reactive_run_continues_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let f = p("r.txt");
    ok_stdout(&run(
        "edmd",
        &[
            "gen",
            "fluid",
            "--n",
            "300",
            "--packing",
            "0.35",
            "--boundary",
            "periodic",
            "--species",
            "0.4,0.4,0.2",
            "--reaction",
            "0 + 1 -> 2 + 2 activation 0.8 probability 0.6 heat 0.3",
            "--reaction",
            "2 + 2 -> 0 + 1 activation 1.5 probability 0.7 heat -0.3",
            "--reaction",
            "1 + 1 -> 0 + 2 activation 1 probability 0.2",
            "-o",
            &f,
        ],
        None,
    ));
    let measure = [
        "--measure",
        "kinetics",
        "--sample-every",
        "0.5",
        "--seed",
        "9",
    ];
    let run_json = |args: &[&str]| {
        let mut all = args.to_vec();
        all.extend_from_slice(&measure);
        all.push("--json");
        summary(&run("edmd", &all, None))
    };
    let direct = run_json(&["run", &f, "--until", "12", "-o", &p("direct.txt")]);
    run_json(&[
        "run",
        &f,
        "--until",
        "5.3",
        "--checkpoint",
        &p("ck"),
        "--checkpoint-every",
        "2",
    ]);
    let resumed = run_json(&["run", &p("ck"), "--until", "12", "-o", &p("resumed.txt")]);
    for key in [
        "disc_collisions",
        "reactions",
        "reaction_heat",
        "measurements",
    ] {
        assert_eq!(resumed[key], direct[key], "{key}");
    }
    assert!(direct["reactions"][0]["reactions"].as_u64().unwrap() > 0);
    assert!(
        std::fs::read(p("resumed.txt")).unwrap() == std::fs::read(p("direct.txt")).unwrap(),
        "final states differ"
    );
    refused(
        &run(
            "edmd",
            &["run", &p("ck"), "--until", "12", "--seed", "8"],
            None,
        ),
        &["--seed 8 differs", "--seed 9"],
    );
}
