//! `edmd experiment hard-disc-transition`: the files and JSON fields of a tiny chain, a resumed
//! chain equal to the bit to one uninterrupted run, a report of the checkpoints that runs
//! nothing, bad options, and the pressure of a liquid against Henderson's equation of state.

use serde_json::Value;

use crate::support::{names, ok_stdout, refused, run, summary};

fn num(r: &Value, key: &str) -> f64 {
    r[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {r}"))
}

/// A row's measured values: those a resumed run must give to the bit.
const MEASURED: [&str; 6] = [
    "pressure",
    "pressure_error",
    "Z",
    "psi6",
    "collisions_per_disc",
    "production_per_disc",
];

/// Asserts that rows `a` and `b` hold the same `keys`, to the bit.
fn same_bits(a: &Value, b: &Value, keys: &[&str]) {
    for key in keys {
        assert_eq!(
            num(a, key).to_bits(),
            num(b, key).to_bits(),
            "{key}: {a} against {b}"
        );
    }
}

/// `edmd experiment hard-disc-transition --out-dir DIR EXTRA...`.
fn command(dir: &std::path::Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "experiment",
        "hard-disc-transition",
        "--out-dir",
        dir.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    run("edmd", &args, None)
}

/// The JSON summary of the command with `--json` and `extra`.
fn experiment(dir: &std::path::Path, extra: &[&str]) -> Value {
    let mut args = vec!["--json"];
    args.extend_from_slice(extra);
    summary(&command(dir, &args))
}

#[test]
fn hard_disc_a_tiny_chain_writes_its_rows_files_and_checkpoints() {
    let dir = tempfile::tempdir().unwrap();
    let v = experiment(
        dir.path(),
        &[
            "--n-side",
            "16",
            "--packings",
            "0.70,0.72",
            "--equilibrate",
            "20",
            "--collisions",
            "20",
            "--blocks",
            "4",
        ],
    );
    assert_eq!(v["experiment"], "hard-disc-transition");
    assert_eq!(v["interrupted"], false);
    assert_eq!(v["resumed"], false);
    assert_eq!(num(&v, "n"), 256.0);
    assert!(num(&v, "wall_seconds") > 0.0);
    assert!(num(&v, "collisions_per_second") > 0.0);
    // 2 points of 40 collisions per disc each, counted exactly.
    assert_eq!(num(&v, "collisions"), 2.0 * 40.0 * 256.0, "{v}");
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    // In increasing packing, each with Engel et al.'s values.
    assert_eq!(num(&rows[0], "packing"), 0.70);
    assert_eq!(num(&rows[1], "packing"), 0.72);
    assert_eq!(num(&rows[0], "reference_edmd"), 9.18896);
    assert_eq!(num(&rows[0], "reference_edmd_error"), 0.00024);
    assert_eq!(num(&rows[0], "reference_mpmc"), 9.187831);
    assert_eq!(num(&rows[1], "reference_mpmc_1024"), 9.23083);
    for r in rows {
        assert_eq!(num(r, "n"), 256.0);
        assert_eq!(num(r, "blocks"), 4.0);
        let p = num(r, "pressure");
        // 256 discs near the transition, barely relaxed from the lattice: within 25 % of 9.2.
        assert!(p > 8.0 && p < 11.5, "{r}");
        let e = num(r, "pressure_error");
        assert!(e > 0.0 && e < 0.5, "{r}");
        let eta = num(r, "packing");
        assert!((p - num(r, "Z") * 4.0 * eta / std::f64::consts::PI).abs() < 1e-9);
        assert_eq!(num(r, "production_per_disc"), 20.0);
        let psi6 = num(r, "psi6");
        assert!((0.0..=1.0).contains(&psi6), "{r}");
        // Four blocks: two against two.
        assert!(num(r, "drift_sigmas").is_finite(), "{r}");
    }
    // The lower point started from the upper one's equilibrated state: it carries its 20
    // collisions per disc as well as its own 40.
    assert_eq!(num(&rows[1], "collisions_per_disc"), 40.0);
    assert_eq!(num(&rows[0], "collisions_per_disc"), 60.0, "{v}");
    let files = names(dir.path());
    for f in [
        "hard-disc-eos.csv",
        "hard-disc-eos.png",
        "hard-disc-eos.svg",
        "hard-disc-0.7000.checkpoint",
        "hard-disc-0.7200.checkpoint",
    ] {
        assert!(files.iter().any(|n| n == f), "{f} missing: {files:?}");
    }
    let csv = std::fs::read_to_string(dir.path().join("hard-disc-eos.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3, "{csv}");
    assert!(lines[0].starts_with("packing,pressure,pressure_error,Z,Z_error,psi6,reference_edmd"));
    assert!(lines[1].starts_with("0.7,"), "{csv}");
    let png = std::fs::read(dir.path().join("hard-disc-eos.png")).unwrap();
    assert_eq!(&png[..4], b"\x89PNG");
    let svg = std::fs::read_to_string(dir.path().join("hard-disc-eos.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("Engel"));
    // The human summary's list of files written names the checkpoints it wrote too.
    let out = command(
        dir.path(),
        &[
            "--n-side",
            "16",
            "--packings",
            "0.70,0.72",
            "--resume",
            "--collisions",
            "4",
            "--blocks",
            "2",
        ],
    );
    let text = ok_stdout(&out);
    let wrote = text
        .lines()
        .find(|l| l.starts_with("wrote: "))
        .unwrap_or_default();
    for f in [
        "hard-disc-eos.csv",
        "hard-disc-0.7000.checkpoint",
        "hard-disc-0.7200.checkpoint",
    ] {
        assert!(wrote.contains(f), "{f} not in {wrote:?}");
    }
    // `edmd run` on a point's checkpoint names the experiment that continues it.
    let point = dir.path().join("hard-disc-0.7000.checkpoint");
    let out = run(
        "edmd",
        &["run", point.to_str().unwrap(), "--until", "1"],
        None,
    );
    refused(
        &out,
        &[
            "not a run's",
            "edmd experiment hard-disc-transition --resume",
        ],
    );
}

#[test]
fn hard_disc_resume_adds_up_to_one_uninterrupted_run_bit_for_bit() {
    let chained = tempfile::tempdir().unwrap();
    let whole = tempfile::tempdir().unwrap();
    let base = [
        "--n-side",
        "16",
        "--packings",
        "0.71,0.716",
        "--equilibrate",
        "10",
    ];
    let first = experiment(
        chained.path(),
        &[&base[..], &["--collisions", "10", "--blocks", "2"]].concat(),
    );
    // A fresh run does not overwrite a chain's checkpoints.
    let again = run(
        "edmd",
        &[
            "experiment",
            "hard-disc-transition",
            "--n-side",
            "16",
            "--packings",
            "0.71",
            "--out-dir",
            chained.path().to_str().unwrap(),
        ],
        None,
    );
    refused(&again, &["--resume", "hard-disc-0.7100.checkpoint"]);
    let resumed = experiment(
        chained.path(),
        &[
            "--n-side",
            "16",
            "--packings",
            "0.71,0.716",
            "--resume",
            "--collisions",
            "10",
            "--blocks",
            "2",
        ],
    );
    assert_eq!(resumed["resumed"], true);
    let once = experiment(
        whole.path(),
        &[&base[..], &["--collisions", "20", "--blocks", "4"]].concat(),
    );
    for k in 0..2 {
        let (a, b, c) = (&first["rows"][k], &resumed["rows"][k], &once["rows"][k]);
        assert_eq!(num(b, "blocks"), 4.0);
        // The collisions per disc add up: those of the first run and the resumed one's.
        let added = num(b, "collisions_per_disc") - num(a, "collisions_per_disc");
        assert_eq!(added, 10.0, "{a} {b}");
        same_bits(b, c, &MEASURED);
        assert!(num(b, "cpu_seconds") >= num(a, "cpu_seconds"));
    }
    // Dropping the blocks: --equilibrate with --resume starts measuring anew.
    let redone = experiment(
        chained.path(),
        &[
            "--n-side",
            "16",
            "--packings",
            "0.71,0.716",
            "--resume",
            "--equilibrate",
            "5",
            "--collisions",
            "10",
            "--blocks",
            "2",
        ],
    );
    for r in redone["rows"].as_array().unwrap() {
        assert_eq!(num(r, "blocks"), 2.0, "{r}");
        assert_eq!(num(r, "production_per_disc"), 10.0, "{r}");
    }
}

#[test]
fn hard_disc_collisions_0_reports_the_checkpoints_as_they_are() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let base = ["--n-side", "8", "--packings", "0.70,0.72"];
    let first = experiment(
        dir.path(),
        &[
            &base[..],
            &["--equilibrate", "5", "--collisions", "10", "--blocks", "2"],
        ]
        .concat(),
    );
    let checkpoints = ["hard-disc-0.7000.checkpoint", "hard-disc-0.7200.checkpoint"];
    let bytes = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    let before: Vec<Vec<u8>> = checkpoints.iter().map(|c| bytes(c)).collect();
    let report = experiment(
        dir.path(),
        &[&base[..], &["--resume", "--collisions", "0"]].concat(),
    );
    assert_eq!(report["collisions"], 0, "{report}");
    for k in 0..2 {
        let (a, b) = (&first["rows"][k], &report["rows"][k]);
        same_bits(a, b, &MEASURED);
        same_bits(a, b, &["blocks", "cpu_seconds"]);
    }
    // Nothing ran, so the checkpoints are as they were.
    for (c, b) in checkpoints.iter().zip(&before) {
        assert!(bytes(c) == *b, "{c} was written again");
    }
    // A damaged checkpoint is refused before any point runs: the sound one (0.72, which
    // runs first) is not continued and written again.
    let damaged = dir.path().join(checkpoints[0]);
    std::fs::write(&damaged, &before[0][..100]).unwrap();
    let out = run(
        "edmd",
        &[
            &["experiment", "hard-disc-transition", "--out-dir", d],
            &base[..],
            &["--resume", "--collisions", "10", "--blocks", "2"],
        ]
        .concat(),
        None,
    );
    refused(&out, &["hard-disc-0.7000.checkpoint"]);
    assert!(
        bytes(checkpoints[1]) == before[1],
        "0.72 ran before the refusal"
    );
    std::fs::write(&damaged, &before[0]).unwrap();
    // Refused: a point without a checkpoint, and dropping the blocks with nothing to measure.
    for (extra, words) in [
        (
            vec!["--packings", "0.70,0.71"],
            vec!["hard-disc-0.7100.checkpoint"],
        ),
        (
            vec!["--packings", "0.70", "--equilibrate", "5"],
            vec!["--equilibrate 5", "--collisions 0"],
        ),
    ] {
        let mut args = vec![
            "experiment",
            "hard-disc-transition",
            "--n-side",
            "8",
            "--resume",
            "--collisions",
            "0",
            "--out-dir",
            d,
        ];
        args.extend(extra);
        refused(&run("edmd", &args, None), &words);
    }
}

#[test]
fn hard_disc_bad_options_exit_2_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    for (extra, words) in [
        (vec!["--n-side", "5"], vec!["--n-side must be even"]),
        (vec!["--n-side", "0"], vec!["--n-side"]),
        // Its square overflows: refused, not a panic.
        (vec!["--n-side", "4294967296"], vec!["--n-side"]),
        (vec!["--packings", "0.9"], vec!["0.9", "outside"]),
        (vec!["--packings", "0.70,0.7"], vec!["given twice"]),
        (vec!["--blocks", "1"], vec!["--blocks must be from 2"]),
        (vec!["--collisions", "0"], vec!["--collisions"]),
        (vec!["--equilibrate", "-3"], vec!["--equilibrate"]),
    ] {
        let mut args = vec!["experiment", "hard-disc-transition", "--out-dir", d];
        args.extend(extra);
        refused(&run("edmd", &args, None), &words);
    }
    // A file that is not this experiment's checkpoint is refused by name.
    std::fs::write(
        dir.path().join("hard-disc-0.7000.checkpoint"),
        "not a checkpoint",
    )
    .unwrap();
    let out = command(
        dir.path(),
        &["--n-side", "16", "--packings", "0.70", "--resume"],
    );
    refused(&out, &["hard-disc-0.7000.checkpoint"]);
}

/// The virial series of hard discs through B10, in powers of the packing fraction: the
/// reduced coefficients `B_n / B_2^(n-1)` of Clisby and McCoy (J. Stat. Phys. 122, 15 (2006))
/// times `2^(n-1)`. At 0.30 the terms left out add about 1e-4; every known coefficient is
/// positive, so the truncated series is below the true value at any packing.
fn virial_b10(eta: f64) -> f64 {
    let b = [
        2.0, 3.12801, 4.25785, 5.33690, 6.36296, 7.3518, 8.3191, 9.2721, 10.2163,
    ];
    1.0 + b
        .iter()
        .enumerate()
        .map(|(k, c)| c * eta.powi(k as i32 + 1))
        .sum::<f64>()
}

#[test]
fn hard_disc_liquids_at_0_30_and_0_60_have_the_virial_series_pressure() {
    // 32^2 discs, the chain from the lattice at 0.60 expanded to 0.30. At 0.30 the series
    // through B10 is exact to 1e-4 (Z = 2.0632) and the measurement must agree within three
    // errors; at 0.60 (a liquid near the transition) the series is a lower bound (6.267), and
    // Henderson's approximate formula (1 + eta^2 / 8) / (1 - eta)^2 = 6.531 lies above the
    // measured 6.46.
    let dir = tempfile::tempdir().unwrap();
    let v = experiment(
        dir.path(),
        &[
            "--n-side",
            "32",
            "--packings",
            "0.30,0.60",
            "--equilibrate",
            "100",
            "--collisions",
            "400",
            "--blocks",
            "20",
        ],
    );
    let (dilute, dense) = (&v["rows"][0], &v["rows"][1]);
    let (z, e) = (num(dilute, "Z"), num(dilute, "Z_error"));
    assert!(e > 0.0 && e < 0.01, "{dilute}");
    assert!((z - virial_b10(0.30)).abs() < 3.0 * e + 2e-4, "{dilute}");
    let (z, e) = (num(dense, "Z"), num(dense, "Z_error"));
    assert!(e > 0.0 && e < 0.05, "{dense}");
    let henderson = (1.0 + 0.36 / 8.0) / (0.4 * 0.4);
    assert!(z > virial_b10(0.60) && z < henderson, "{dense}");
    for r in [dilute, dense] {
        assert!(num(r, "psi6") < 0.2, "a liquid: {r}");
        assert!(r["reference_edmd"].is_null());
    }
}
