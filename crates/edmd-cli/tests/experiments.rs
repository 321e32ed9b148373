//! `edmd experiment NAME`: each writes its CSV files and plots and prints a summary that says
//! what the physics says.

use serde_json::Value;

use crate::support::{names, ok_stdout, refused, run};

fn experiment(args: &[&str]) -> (Value, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let mut full = vec!["experiment"];
    full.extend_from_slice(args);
    full.extend_from_slice(&["--json", "--out-dir", dir.path().to_str().unwrap()]);
    let out = run("edmd", &full, None);
    let v: Value = serde_json::from_str(ok_stdout(&out).trim()).expect("one JSON object");
    (v, dir)
}

fn assert_files(dir: &tempfile::TempDir, names: &[&str]) {
    for name in names {
        let p = dir.path().join(name);
        let len = std::fs::metadata(&p)
            .unwrap_or_else(|_| panic!("{name} missing"))
            .len();
        assert!(len > 100, "{name} is nearly empty");
        if name.ends_with(".png") {
            let bytes = std::fs::read(&p).unwrap();
            assert_eq!(&bytes[1..4], b"PNG");
        }
    }
}

#[test]
fn billiards_break_is_symmetric_with_multi_disc_collisions_only() {
    let (v, dir) = experiment(&["billiards"]);
    let breaks = v["breaks"].as_array().unwrap();
    assert_eq!(breaks[0]["model"], "multi");
    assert!(breaks[0]["mirror_mismatch"].as_f64().unwrap() < 1e-9, "{v}");
    assert!(breaks[1]["mirror_mismatch"].as_f64().unwrap() > 1e-3, "{v}");
    assert_eq!(breaks[0]["moving"], 16);
    for b in breaks {
        assert!(b["relative_energy_change"].as_f64().unwrap().abs() < 1e-12);
    }
    assert_files(
        &dir,
        &[
            "billiards_multi.csv",
            "billiards_multi.png",
            "billiards_multi.svg",
            "billiards_binary.png",
        ],
    );
}

#[test]
fn reversibility_returns_short_runs_and_loses_long_ones() {
    let (v, dir) = experiment(&["reversibility", "--times", "0.5,1,16"]);
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 3);
    assert!(runs[0]["max_error"].as_f64().unwrap() < 1e-9, "{v}");
    assert!(
        runs[2]["max_error"].as_f64().unwrap() > 1e-3,
        "rounding growth should show: {v}"
    );
    assert_files(
        &dir,
        &[
            "reversibility.csv",
            "reversibility.png",
            "reversibility.svg",
        ],
    );
}

#[test]
fn experiment_options_are_validated() {
    for args in [
        vec!["experiment", "reversibility", "--times", "0,1"],
        vec!["experiment", "billiards", "--rows", "0"],
        vec!["experiment", "billiards", "--gap", "0.5"],
        vec!["experiment", "teleport"],
    ] {
        let out = run("edmd", &args, None);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr).lines().count(),
            1,
            "{args:?}"
        );
    }
}

#[test]
fn eos_json_has_z_with_error_bars_near_henderson() {
    let (v, dir) = experiment(&["eos", "--packing", "0.2,0.4", "--n", "500"]);
    let results = v["results"].as_array().unwrap();
    assert_eq!(results.len(), 2);
    for r in results {
        let (eta, z, err) = (
            r["packing"].as_f64().unwrap(),
            r["Z"].as_f64().unwrap(),
            r["Z_err"].as_f64().unwrap(),
        );
        // Henderson: Z = (1 + eta^2/8) / (1 - eta)^2.
        let h = (1.0 + eta * eta / 8.0) / ((1.0 - eta) * (1.0 - eta));
        assert!((z / h - 1.0).abs() < 0.015, "{r}");
        assert!(err > 0.0 && err < 0.02 * z, "{r}");
        assert!(
            r["relative_energy_change"].as_f64().unwrap().abs() < 1e-12,
            "{r}"
        );
    }
    assert_files(&dir, &["eos.csv", "eos.png", "eos.svg"]);
}

#[test]
fn maxwell_relaxes_an_equal_speed_start_to_rayleigh() {
    let (v, dir) = experiment(&["maxwell", "--n", "1000"]);
    assert!(v["ks_p_value"].as_f64().unwrap() > 0.01, "{v}");
    assert!(v["initial_ks_p_value"].as_f64().unwrap() < 1e-6, "{v}");
    assert!(
        v["relative_energy_change"].as_f64().unwrap().abs() < 1e-12,
        "{v}"
    );
    let rms = v["rms_speed"].as_array().unwrap();
    assert!(
        (rms[0].as_f64().unwrap() / rms[1].as_f64().unwrap() - 1.0).abs() < 1e-9,
        "rms speed is fixed by the energy: {v}"
    );
    assert_files(&dir, &["maxwell.csv", "maxwell.png", "maxwell.svg"]);
}

#[test]
fn mfp_follows_enskog() {
    let (v, dir) = experiment(&["mfp", "--packing", "0.1,0.3", "--n", "600"]);
    for r in v["results"].as_array().unwrap() {
        let (m, e) = (
            r["mean_free_path"].as_f64().unwrap(),
            r["enskog_mean_free_path"].as_f64().unwrap(),
        );
        assert!((m / e - 1.0).abs() < 0.06, "{r}");
        assert!(
            r["relative_energy_change"].as_f64().unwrap().abs() < 1e-12,
            "{r}"
        );
    }
    assert_files(
        &dir,
        &[
            "mfp.csv",
            "mfp.png",
            "mfp_free_path.png",
            "mfp_free_time.svg",
        ],
    );
}

#[test]
fn demon_heats_one_side_and_cools_the_other_without_work() {
    let (v, dir) = experiment(&["demon", "--n", "150", "--until", "3000"]);
    let (start, end) = (v["start"].as_array().unwrap(), v["end"].as_array().unwrap());
    let (l0, r0) = (start[0].as_f64().unwrap(), start[1].as_f64().unwrap());
    let (l1, r1) = (end[0].as_f64().unwrap(), end[1].as_f64().unwrap());
    assert!(
        (r0 / l0 - 1.0).abs() < 0.3,
        "sides start near the same temperature: {v}"
    );
    assert!(r1 > 1.5 * l1, "right should be much hotter: {v}");
    assert!(
        v["passed"].as_u64().unwrap() > 20 && v["shut"].as_u64().unwrap() > 20,
        "{v}"
    );
    assert!(v["relative_energy_change"].as_f64().unwrap().abs() < 1e-12);
    assert_files(&dir, &["demon.csv", "demon.png", "demon.svg"]);
}

#[test]
fn diffusion_mixes_the_two_species_evenly() {
    let (v, dir) = experiment(&["diffusion", "--n", "150", "--until", "2000"]);
    assert!((v["blue_left"].as_f64().unwrap() - 0.5).abs() < 0.12, "{v}");
    assert!(
        (v["green_left"].as_f64().unwrap() - 0.5).abs() < 0.12,
        "{v}"
    );
    assert!(v["mixing_time"].as_f64().is_some(), "{v}");
    assert!(v["diffusion_coefficient"].as_f64().unwrap() > 0.0, "{v}");
    assert_files(
        &dir,
        &["diffusion.csv", "diffusion.png", "diffusion_msd.csv"],
    );
}

#[test]
fn brownian_big_disc_diffuses() {
    let (v, dir) = experiment(&[
        "brownian",
        "--n",
        "500",
        "--until",
        "2000",
        "--samples",
        "400",
    ]);
    assert!(v["diffusion_coefficient"].as_f64().unwrap() > 0.0, "{v}");
    assert!(v["relative_energy_change"].as_f64().unwrap().abs() < 1e-12);
    assert_files(
        &dir,
        &[
            "brownian_path.csv",
            "brownian_path.png",
            "brownian_msd.png",
            "brownian_msd.svg",
        ],
    );
}

#[test]
fn every_generator_writes_a_file_that_runs_and_the_seed_decides() {
    let dir = tempfile::tempdir().unwrap();
    for kind in edmd_core::setup::GenKind::NAMES {
        let f = dir.path().join(format!("{kind}.txt"));
        let g = dir.path().join(format!("{kind}-again.txt"));
        for p in [&f, &g] {
            let out = run(
                "edmd",
                &["gen", kind, "--seed", "5", "-o", p.to_str().unwrap()],
                None,
            );
            assert!(
                out.status.success(),
                "{kind}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        assert_eq!(
            std::fs::read(&f).unwrap(),
            std::fs::read(&g).unwrap(),
            "{kind}: same seed, same file"
        );
        let out = run(
            "edmd",
            &["run", f.to_str().unwrap(), "--until", "10", "--check"],
            None,
        );
        assert!(
            out.status.success(),
            "{kind}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let a = dir.path().join("a.txt");
    ok_stdout(&run(
        "edmd",
        &["gen", "fluid", "--seed", "6", "-o", a.to_str().unwrap()],
        None,
    ));
    assert_ne!(
        std::fs::read(&a).unwrap(),
        std::fs::read(dir.path().join("fluid.txt")).unwrap()
    );
}

#[test]
fn generators_take_their_options_and_refuse_the_impossible() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("f.txt");
    let fp = f.to_str().unwrap();
    ok_stdout(&run(
        "edmd",
        &[
            "gen",
            "fluid",
            "--n",
            "300",
            "--packing",
            "0.7",
            "--boundary",
            "walls",
            "-o",
            fp,
        ],
        None,
    ));
    let text = std::fs::read_to_string(&f).unwrap();
    assert_eq!(text.lines().next(), Some("300"));
    assert!(
        text.contains("# edmd box"),
        "fluids say their box: {}",
        &text[..200]
    );
    ok_stdout(&run(
        "edmd",
        &[
            "gen",
            "mixture",
            "--spread",
            "0.2",
            "--packing",
            "0.6",
            "-o",
            fp,
        ],
        None,
    ));
    ok_stdout(&run(
        "edmd",
        &["gen", "lattice", "--n", "50", "--course", "-o", fp],
        None,
    ));
    assert_eq!(
        std::fs::read_to_string(&f).unwrap().lines().nth(1),
        Some("0.01")
    );
    for (args, expect) in [
        (
            vec!["gen", "fluid", "--packing", "0.95", "-o", fp],
            "packing",
        ),
        (
            vec!["gen", "fluid", "--n", "-4", "-o", fp],
            "--n must be at least 1",
        ),
        (
            vec!["gen", "single", "--packing", "0.3", "-o", fp],
            "--packing does not apply",
        ),
        (vec!["gen", "warp-drive", "-o", fp], "unknown kind"),
        (
            vec![
                "gen",
                "mixture",
                "--spread",
                "0.1",
                "--size-ratio",
                "2",
                "-o",
                fp,
            ],
            "exclude each other",
        ),
        (
            vec!["gen", "mixture", "--course", "-o", fp],
            "course format",
        ),
        (vec!["experiment", "demon", "--door", "2"], "--door"),
        // Narrower than a disc: nothing passes (1e-308 named the core's "barrier 0").
        (
            vec!["experiment", "demon", "--door", "1e-308"],
            "wider than a disc",
        ),
        // Once "brownian: brownian: the discs would cover 197.1% ... use fewer or smaller discs".
        (
            vec!["experiment", "brownian", "--n", "100000"],
            "brownian: --n must be from 1 to 19971",
        ),
        (
            vec!["experiment", "maxwell", "--bins", "1"],
            "--bins must be from 2",
        ),
        (
            vec!["experiment", "reversibility", "--n", "1"],
            "--n must be from 2",
        ),
        (
            vec!["experiment", "jamming", "--n", "20"],
            "--n must be from 53",
        ),
    ] {
        let out = run("edmd", &args, None);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(expect) && err.lines().count() == 1,
            "{args:?}: {err}"
        );
    }
}

#[test]
fn ctrl_c_stops_a_long_experiment_and_keeps_its_results() {
    use std::process::{Command, Stdio};
    let dir = tempfile::tempdir().unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_edmd"))
        .args([
            "experiment",
            "eos",
            "--packing",
            "0.1,0.2,0.3,0.4,0.5,0.6",
            "--n",
            "3000",
            "--measure",
            "3000",
            "--json",
            "--out-dir",
        ])
        .arg(dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Let it finish at least the first packing fraction, then press Ctrl-C.
    std::thread::sleep(std::time::Duration::from_millis(2500));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    // The results so far are written, and the exit status says the run was cut short.
    assert_eq!(
        out.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_str(String::from_utf8_lossy(&out.stdout).trim()).unwrap();
    assert_eq!(v["interrupted"], true, "{v}");
    let done = v["results"].as_array().unwrap().len();
    assert!(done < 6, "{v}");
    let csv = std::fs::read_to_string(dir.path().join("eos.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + done);
    assert!(String::from_utf8_lossy(&out.stderr).contains("stopping"));
}

#[test]
fn eos_of_spheres_matches_pieprzyk_and_the_collision_rate_relation() {
    // Pieprzyk, Bannerman, Branka, Chudak and Heyes, PCCP 21, 6886 (2019), the most accurate
    // published hard-sphere equation of state; the collision rate per sphere must equal
    // 6 (Z - 1) sqrt(kT / (pi m)) / sigma for the measured Z (an exact relation).
    let (v, dir) = experiment(&[
        "eos",
        "--dim",
        "3",
        "--packing",
        "0.3,0.45",
        "--n",
        "1000",
        "--collisions",
        "400",
    ]);
    assert_eq!(v["dim"], 3);
    for r in v["results"].as_array().unwrap() {
        let (z, err, reference) = (
            r["Z"].as_f64().unwrap(),
            r["Z_err"].as_f64().unwrap(),
            r["pieprzyk"].as_f64().unwrap(),
        );
        assert!(r.get("henderson").is_none(), "{r}");
        assert!((z / reference - 1.0).abs() < 0.005, "{r}");
        assert!((z - reference).abs() < 4.0 * err, "{r}");
        let rate = r["collision_rate"].as_array().unwrap();
        let (measured, implied) = (rate[0].as_f64().unwrap(), rate[1].as_f64().unwrap());
        assert!((measured / implied - 1.0).abs() < 0.01, "{r}");
    }
    assert_files(&dir, &["eos.csv", "eos.png", "eos.svg"]);
    let csv = std::fs::read_to_string(dir.path().join("eos.csv")).unwrap();
    assert!(csv.starts_with("packing,Z,Z_err,pieprzyk,"), "{csv}");
}

#[test]
fn spheres_relax_to_the_3d_maxwell_law_and_follow_enskog() {
    let (v, _dir) = experiment(&["maxwell", "--dim", "3", "--n", "1000"]);
    assert!(v["ks_p_value"].as_f64().unwrap() > 0.01, "{v}");
    assert!(v["initial_ks_p_value"].as_f64().unwrap() < 1e-6, "{v}");
    // The mean speed of the 3D law, sqrt(8 kT / (pi m)), not the 2D one.
    let mean = v["mean_speed"].as_array().unwrap();
    let kt = v["kt"].as_f64().unwrap();
    assert!((mean[1].as_f64().unwrap() - (8.0 * kt / std::f64::consts::PI).sqrt()).abs() < 1e-12);
    assert!(
        (mean[0].as_f64().unwrap() / mean[1].as_f64().unwrap() - 1.0).abs() < 0.01,
        "{v}"
    );
    // Enskog's mean free path for spheres, 1 / (sqrt(2) pi n sigma^2 g), g from the EOS.
    let (v, _dir) = experiment(&["mfp", "--dim", "3", "--packing", "0.1,0.4", "--n", "600"]);
    for r in v["results"].as_array().unwrap() {
        let (m, e) = (
            r["mean_free_path"].as_f64().unwrap(),
            r["enskog_mean_free_path"].as_f64().unwrap(),
        );
        assert!((m / e - 1.0).abs() < 0.01, "{r}");
    }
    let out = run("edmd", &["experiment", "eos", "--dim", "4"], None);
    assert_eq!(out.status.code(), Some(2));
    let out = run(
        "edmd",
        &["experiment", "eos", "--dim", "3", "--packing", "0.55"],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(String::from_utf8_lossy(&out.stderr).lines().count(), 1);
}

/// Slower compression packs denser (Skoge, Donev, Stillinger and Torquato, PRE 74, 041127
/// (2006)); the JSON has one row per rate, and the CSV files and the plot are written.
#[test]
fn jamming_slower_compression_packs_denser() {
    for dim in ["3", "2"] {
        let (v, dir) = experiment(&[
            "jamming",
            "--dim",
            dim,
            "--n",
            "100",
            "--rates",
            "0.2,0.02",
            "--seeds",
            "1",
            "--pressure",
            "1e6",
        ]);
        assert_eq!(v["experiment"], "jamming");
        assert_eq!(v["interrupted"], false);
        let rows = v["rows"].as_array().unwrap();
        assert_eq!(rows.len(), 2, "{v}");
        let phi: Vec<f64> = rows
            .iter()
            .map(|r| r["packing_fraction"].as_f64().unwrap())
            .collect();
        let (lo, hi) = if dim == "3" {
            (0.55, 0.66)
        } else {
            (0.78, 0.86)
        };
        for (r, &p) in rows.iter().zip(&phi) {
            assert!(p > lo && p < hi, "{r}");
            assert!(r["packing_fraction_err"].is_null(), "{r}");
            let rattlers = r["rattler_fraction"].as_f64().unwrap();
            assert!((0.0..=1.0).contains(&rattlers), "{r}");
            assert_eq!(r["crystallised"].as_f64(), Some(0.0), "{r}");
            assert!(r["collisions"].as_f64().unwrap() > 0.0, "{r}");
            assert_eq!(r["runs"].as_array().unwrap().len(), 1, "{r}");
        }
        assert_eq!(rows[0]["rate"].as_f64(), Some(0.2));
        assert!(phi[1] >= phi[0], "{phi:?}");
        // The slow compression reaches a rigid backbone: contacts near isostatic 2 dim.
        let z = rows[1]["mean_contacts"].as_f64().unwrap();
        let d: f64 = dim.parse().unwrap();
        assert!(z > 2.0 * d - 1.5 && z < 2.0 * d + 0.5, "{}", rows[1]);
        assert_files(
            &dir,
            &[
                "jamming.csv",
                "jamming_runs.csv",
                "jamming.png",
                "jamming.svg",
            ],
        );
        let csv = std::fs::read_to_string(dir.path().join("jamming.csv")).unwrap();
        assert!(csv.starts_with("rate,packing_fraction,packing_fraction_err,mean_contacts"));
        assert_eq!(csv.lines().count(), 3);
    }
}

#[test]
fn jamming_options_are_validated() {
    for args in [
        vec!["experiment", "jamming", "--rates", "0"],
        vec!["experiment", "jamming", "--rates", "2"],
        vec!["experiment", "jamming", "--seeds", "0"],
        vec!["experiment", "jamming", "--n", "3"],
        vec!["experiment", "jamming", "--pressure", "0.5"],
        vec!["experiment", "jamming", "--fraction-large", "0.3"],
        vec!["experiment", "jamming", "--size-ratio", "20"],
        vec!["experiment", "jamming", "--crystal-packing", "5"],
    ] {
        let out = run("edmd", &args, None);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr).lines().count(),
            1,
            "{args:?}"
        );
    }
}

#[test]
fn square_well_json_rows_meet_the_exact_low_density_limits() {
    // At rho = 0.005 (3D) and 0.01 (2D), lambda 1.5, kT 1.5: Z = 1 + B2 rho + O(rho^2) with the
    // exact B2 (3D: (2 pi / 3)(1 - (lambda^3 - 1)(e^{1/kT} - 1)) = -2.620; 2D: (pi / 2)(1 -
    // (lambda^2 - 1)(...)) = -0.290), U/N = (rho/2) Int u e^{-u/kT} dr. The second-order
    // terms are below 1e-4 here; the runs aim at 2% errors, and each value must be within
    // four of its errors (plus the neglected order) of the limit.
    for (dim, rho) in [("3", 0.005), ("2", 0.01)] {
        let (v, dir) = experiment(&[
            "square-well",
            "--dim",
            dim,
            "--density",
            &rho.to_string(),
            "--n",
            "400",
            "--precision",
            "0.02",
        ]);
        assert_eq!(v["experiment"], "square-well");
        let rows = v["rows"].as_array().unwrap();
        assert_eq!(rows.len(), 1);
        let r = &rows[0];
        let f = |k: &str| r[k].as_f64().unwrap_or_else(|| panic!("{k} in {r}"));
        assert_eq!((f("density"), f("kt"), f("lambda")), (rho, 1.5, 1.5));
        let (z, z_err, z2) = (f("Z"), f("Z_error"), f("Z_second_virial"));
        assert!(z_err > 0.0 && (z - z2).abs() < 4.0 * z_err + 2e-4, "{r}");
        let (u, u_err, u1) = (
            f("energy_per_particle"),
            f("energy_per_particle_error"),
            f("energy_per_particle_low_density"),
        );
        assert!(u < 0.0 && u_err > 0.0, "{r}");
        assert!((u - u1).abs() < 4.0 * u_err + 0.01 * u1.abs(), "{r}");
        assert!((f("kinetic_temperature") - 1.5).abs() < 0.05, "{r}");
        assert_files(
            &dir,
            &[
                "square-well.csv",
                "square-well-z.png",
                "square-well-z.svg",
                "square-well-energy.png",
                "square-well-energy.svg",
            ],
        );
    }
}

#[test]
fn square_well_refuses_bad_options_in_one_line() {
    for (args, words) in [
        (&["--lambda", "1"][..], "--lambda"),
        (&["--kt", "0"][..], "--kt"),
        (&["--density", "2"][..], "density 2"),
        (&["--precision", "0"][..], "--precision"),
        (&["--n", "3"][..], "--n"),
        // Each density would wait 10 / rate to settle: hours.
        (&["--rate", "0.001"][..], "--rate must be from 0.01"),
        (
            &["--density", "0.2,0.1,0.2"][..],
            "density 0.2 is given twice",
        ),
    ] {
        let mut a = vec!["experiment", "square-well"];
        a.extend_from_slice(args);
        refused(&run("edmd", &a, None), &[words]);
    }
    refused(
        &run(
            "edmd",
            &["experiment", "shoulder", "--density", "0.9,0.9"],
            None,
        ),
        &["density 0.9 is given twice"],
    );
}

#[test]
fn a_failed_experiment_leaves_none_of_the_folders_it_made() {
    // Stopped before its first point is done, the chain has written nothing: the output
    // folder, and the two above it that it made, are removed.
    let dir = tempfile::tempdir().unwrap();
    let (code, _, err) = crate::support::signalled(
        dir.path(),
        &[
            "experiment",
            "hard-disc-transition",
            "--packings",
            "0.7",
            "--out-dir",
            "n1/a/b",
        ],
        "-TERM",
        std::time::Duration::from_millis(1500),
    );
    assert_eq!(code, Some(130), "{err}");
    assert!(err.contains("nothing written"), "{err}");
    assert!(names(dir.path()).is_empty(), "{:?}", names(dir.path()));
    // A box too small for the range at the second density is refused before the first runs,
    // before any folder is made.
    let out = dir.path().join("n2/a");
    let r = run(
        "edmd",
        &[
            "experiment",
            "square-well",
            "--n",
            "1000",
            "--density",
            "0.05,0.8",
            "--lambda",
            "5",
            "--out-dir",
            out.to_str().unwrap(),
        ],
        None,
    );
    refused(&r, &["square-well: density 0.8", "three times the reach"]);
    assert!(names(dir.path()).is_empty(), "{:?}", names(dir.path()));
}

#[test]
fn shoulder_crystals_go_from_expanded_to_condensed_and_the_dilute_gas_meets_b2() {
    // Discs with a shoulder of height 1 out to 1.1 at kT = 0.25: the expanded triangular
    // crystal at rho = 0.8 has its neighbours 1.2 apart, outside the shoulders (U/N near 0);
    // the condensed one at rho = 1.12, 1.015 apart, has all six inside (U/N = 3 exactly, as no
    // pair can leave). The dilute gas at rho = 0.01 meets 1 + B2 rho, B2 = (pi/2)(1 + (1.1^2 -
    // 1)(1 - e^{-4})) = 1.8932 (exact), within its errors.
    let (v, dir) = experiment(&[
        "shoulder",
        "--density",
        "0.8,1.12",
        "--cells",
        "8",
        "--precision",
        "0.03",
        "--max-blocks",
        "60",
    ]);
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 3);
    let f = |r: &Value, k: &str| r[k].as_f64().unwrap_or_else(|| panic!("{k} in {r}"));
    let (dilute, expanded, condensed) = (&rows[0], &rows[1], &rows[2]);
    assert_eq!(dilute["start"], "fluid");
    let b2 = std::f64::consts::PI / 2.0 * (1.0 + (1.1f64.powi(2) - 1.0) * (1.0 - (-4.0f64).exp()));
    assert!((f(dilute, "Z_second_virial") - (1.0 + 0.01 * b2)).abs() < 1e-12);
    assert!(
        (f(dilute, "Z") - f(dilute, "Z_second_virial")).abs() < 4.0 * f(dilute, "Z_error") + 1e-3,
        "{dilute}"
    );
    assert!(f(expanded, "energy_per_particle") < 0.2, "{expanded}");
    assert_eq!(f(condensed, "energy_per_particle"), 3.0, "{condensed}");
    assert!(f(condensed, "pressure") > f(expanded, "pressure"));
    let p0 = v["transition_pressure_zero_temperature"].as_f64().unwrap();
    // 3 / ((sqrt(3)/2)(1.1^2 - 1)).
    assert!((p0 - 3.0 / (3f64.sqrt() / 2.0 * 0.21)).abs() < 1e-9, "{p0}");
    assert_files(
        &dir,
        &[
            "shoulder.csv",
            "shoulder-pressure.png",
            "shoulder-pressure.svg",
            "shoulder-energy.png",
            "shoulder-energy.svg",
        ],
    );
}

#[test]
fn cooling_follows_haffs_law_below_the_critical_size_and_leaves_it_above() {
    // Discs at packing 0.05 with e = 0.9: the critical size of the shear instability is
    // L_c = 126.6 diameters (Garzó and Dufty's Enskog coefficients). 250 discs fill a box of
    // 0.50 L_c, stable; 4000 one of 1.98 L_c, whose longest shear waves grow.
    let (v, dir) = experiment(&[
        "cooling",
        "--dim",
        "2",
        "--restitution",
        "0.9",
        "--packing",
        "0.05",
        "--n",
        "250,4000",
        "--runs",
        "3",
        "--collisions",
        "100",
    ]);
    assert_eq!(v["experiment"], "cooling");
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    let f = |r: &Value, k: &str| r[k].as_f64().unwrap_or_else(|| panic!("{k} in {r}"));
    let (stable, unstable) = (&rows[0], &rows[1]);
    for k in ["t0", "t0_error", "collision_frequency", "kt0"] {
        assert_eq!(v[k], stable[k], "{k}: the first row's, at the top");
    }
    for r in rows {
        assert_eq!(
            (f(r, "dim"), f(r, "restitution"), f(r, "packing")),
            (2.0, 0.9, 0.05)
        );
        assert!((f(r, "critical_length") - 126.6).abs() < 0.1, "{r}");
        assert!((f(r, "kt0") - 1.0).abs() < 1e-9, "{r}");
        assert!(
            f(r, "tc") > 0.0 && f(r, "tc_elastic_fraction") < 1e-3,
            "{r}"
        );
        // Enskog's collision frequency at T0, measured while still elastic: within four
        // errors and 1% (Enskog's contact value neglects correlations of a few tenths of a per
        // cent at this density).
        let (w, w_err, w_th) = (
            f(r, "collision_frequency"),
            f(r, "collision_frequency_error"),
            f(r, "collision_frequency_theory"),
        );
        assert!((w - w_th).abs() < 4.0 * w_err + 0.01 * w_th, "{r}");
    }
    assert!(f(stable, "length_ratio") < 1.0 && f(unstable, "length_ratio") > 1.9);
    // Haff's time fitted before the onset against 2D / ((1 - e^2)(1 + 3 a2/16) omega_Enskog):
    // within three errors and 3%. Enskog's theory assumes uncorrelated velocities before a
    // collision; in the cooling gas they are correlated, which lowers the cooling rate by about
    // 1% here (t0 1.2% above, 16 runs of 600 discs), and the Sonine correction is itself 0.5%.
    // The Maxwellian t0 with the dimension off by one (3D's 6 for 2D's 4) is 50% away.
    for r in rows {
        let (t0, err, th) = (f(r, "t0"), f(r, "t0_error"), f(r, "t0_theory"));
        assert!(err > 0.0 && (t0 - th).abs() < 3.0 * err + 0.03 * th, "{r}");
    }
    // The stable box's shear waves never hold 8% of the energy (ten times their equilibrium
    // share 2/N; they settle at x/(x - 1) = 4/3 times it); the other's reach 2% after about
    // 50 collisions per disc, as linear fluctuating hydrodynamics predicts: within 30% (each
    // run's start is one draw of the equilibrium fluctuations it amplifies, and nonlinear
    // saturation begins at a few per cent).
    assert!(stable["onset_collisions"].is_null(), "{stable}");
    assert!(stable["onset_collisions_theory"].is_null(), "{stable}");
    let (onset, predicted) = (
        f(unstable, "onset_collisions"),
        f(unstable, "onset_collisions_theory"),
    );
    assert!((onset / predicted - 1.0).abs() < 0.3, "{unstable}");
    // A run whose longest waves start unusually still can take twice as long: two of three.
    assert!(f(unstable, "onset_runs") >= 2.0, "{unstable}");
    assert_files(
        &dir,
        &[
            "cooling.csv",
            "cooling-runs.csv",
            "cooling-samples.csv",
            "cooling-temperature.png",
            "cooling-temperature.svg",
            "cooling-shear.png",
            "cooling-shear.svg",
            "cooling-snapshot-250.png",
            "cooling-snapshot-4000.png",
        ],
    );
}

#[test]
fn cooling_refuses_bad_options_in_one_line() {
    for (args, words) in [
        (&["--restitution", "1"][..], "--restitution"),
        (&["--restitution", "0"][..], "--restitution"),
        (&["--restitution", "NaN"][..], "--restitution"),
        (&["--restitution", "-0.5"][..], "--restitution"),
        (&["--packing", "0.8"][..], "packing fraction 0.8"),
        (&["--packing", "0"][..], "packing fraction 0"),
        (
            &["--dim", "3", "--packing", "0.6"][..],
            "packing fraction 0.6",
        ),
        (&["--n", "10"][..], "--n"),
        (&["--runs", "1"][..], "--runs"),
        (&["--tc", "-1"][..], "--tc"),
        (&["--collisions", "inf"][..], "--collisions"),
        (&["--onset-fraction", "1"][..], "--onset-fraction"),
        // So close to elastic that the run has no fall of the temperature to fit (t0 was NaN,
        // fitted over "0-0 collisions").
        (&["--restitution", "0.9999999999"][..], "at most 0.99999"),
        (&["--restitution", "0.9999"][..], "at least 6932"),
        // Echoed as read, not rounded to 18446744073709552000.
        (
            &["--collisions", "18446744073709551615"][..],
            "1.8446744073709552e19",
        ),
    ] {
        let mut a = vec!["experiment", "cooling"];
        a.extend_from_slice(args);
        refused(&run("edmd", &a, None), &[words]);
    }
}

#[test]
fn an_output_name_taken_by_a_folder_is_refused_before_the_work() {
    // Each experiment declares the files it will write; a folder of one of those names in
    // --out-dir would make the writing fail after the whole run, so it is refused first: exit
    // status 2, one line naming it, nothing written. The names are the last or the computed
    // ones each experiment writes (a figure per packing, a snapshot per size, a checkpoint).
    let cases: [(&str, &[&str], &str); 20] = [
        ("annihilation", &[], "annihilation-lee.svg"),
        ("barometric", &[], "barometric-packing-0.01.png"),
        ("billiards", &[], "billiards_binary.csv"),
        ("brownian", &[], "brownian_msd.png"),
        ("cooling", &["--n", "500,800"], "cooling-snapshot-800.png"),
        ("demon", &[], "demon.csv"),
        ("diffusion", &[], "diffusion_msd.csv"),
        ("eos", &[], "eos.png"),
        ("front", &[], "front-shape.svg"),
        (
            "hard-disc-transition",
            &["--packings", "0.7,0.72"],
            "hard-disc-0.7200.checkpoint",
        ),
        ("jamming", &[], "jamming_runs.csv"),
        ("maxwell", &[], "maxwell.svg"),
        ("mfp", &[], "mfp_free_time.png"),
        ("reaction", &[], "prigogine-xhrouet-speeds.csv"),
        ("reversibility", &[], "reversibility.png"),
        ("ring", &[], "ring-patch.gif"),
        ("sheets", &[], "sheets-phase-plane.gif"),
        ("shoulder", &[], "shoulder-energy.png"),
        ("square-well", &[], "square-well-z.svg"),
        ("viscosity", &[], "conductivity.png"),
    ];
    for (name, extra, taken) in cases {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join(taken)).unwrap();
        let mut args = vec!["experiment", name];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out-dir", dir.path().to_str().unwrap()]);
        let out = run("edmd", &args, None);
        refused(&out, &[taken, "is a folder", "--out-dir"]);
        assert_eq!(names(dir.path()), [taken], "{name}");
    }
    // A link to nowhere in a file's place, an --out-dir that is a file, and one inside a
    // file: found at the start, not when the results are written.
    let dir = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink("/nonexistent/x", dir.path().join("eos.png")).unwrap();
    let d = dir.path().to_str().unwrap();
    refused(
        &run("edmd", &["experiment", "eos", "--out-dir", d], None),
        &["eos.png", "a link to a place that does not exist"],
    );
    let file = dir.path().join("a-file");
    std::fs::write(&file, "x").unwrap();
    let f = file.to_str().unwrap();
    refused(
        &run("edmd", &["experiment", "eos", "--out-dir", f], None),
        &["--out-dir is not a folder"],
    );
    let inside = format!("{f}/sub");
    refused(
        &run("edmd", &["experiment", "eos", "--out-dir", &inside], None),
        &["--out-dir cannot be made"],
    );
    assert_eq!(names(dir.path()), ["a-file", "eos.png"]);
}

#[test]
fn a_value_given_twice_in_a_list_option_is_refused() {
    // Repeated list options add to the list; a value given twice would run the same point
    // twice and write its files over (barometric wrote one figure three times).
    let cases: [(&str, &[&str], &str); 10] = [
        (
            "barometric",
            &["--packing", "0.01", "--packing", "0.01,0.01"],
            "--packing 0.01",
        ),
        ("eos", &["--packing", "0.1,0.2,0.1"], "packing fraction 0.1"),
        (
            "viscosity",
            &["--packing", "0.1", "--packing", "0.1"],
            "packing fraction 0.1",
        ),
        ("mfp", &["--packing", "0.3,0.3"], "packing fraction 0.3"),
        (
            "ring",
            &["--restitution", "bridges,bridges"],
            "--restitution bridges",
        ),
        ("cooling", &["--n", "100,100"], "--n 100"),
        ("reaction", &["--activation", "1,1"], "--activation 1 "),
        (
            "reaction",
            &["--px-activation", "2,2"],
            "--px-activation 2 ",
        ),
        ("jamming", &["--rates", "0.2,0.2"], "--rates 0.2"),
        ("reversibility", &["--times", "1,1"], "--times 1 "),
    ];
    for (name, extra, words) in cases {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let mut args = vec!["experiment", name];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out-dir", out.to_str().unwrap()]);
        refused(&run("edmd", &args, None), &[words, "given twice"]);
        assert!(names(dir.path()).is_empty(), "{name}");
    }
}

#[test]
fn cooling_with_a_huge_tc_reports_it_finite() {
    // The mean of the runs' tc summed them first, and two 1e308s made it inf.
    let (v, _dir) = experiment(&[
        "cooling",
        "--n",
        "250",
        "--runs",
        "2",
        "--collisions",
        "20",
        "--restitution",
        "0.8",
        "--tc",
        "1e308",
    ]);
    let tc = v["rows"][0]["tc"].as_f64().unwrap();
    assert_eq!(tc, 1e308, "{v}");
}

#[test]
fn list_defaults_are_shown_as_the_parser_reads_them() {
    // Shown space-separated ("[default: 0.05 0.1 ...]"), they could not be pasted back.
    for (name, shown) in [
        ("mfp", "[default: 0.05,0.1,0.2,0.3,0.4,0.5]"),
        ("reversibility", "[default: 0.5,1,2,3,4,6,8,12,16]"),
        ("reaction", "[default: 0,0.5,1,2,3,4]"),
        ("reaction", "[default: 1,2,3]"),
    ] {
        let help = ok_stdout(&run("edmd", &["experiment", name, "--help"], None));
        assert!(help.contains(shown), "{name}: {help}");
    }
}

// Each of these once ran to the end and printed NaN or inf, or was refused in another
// command's words.
#[test]
fn experiments_say_what_a_missing_value_means_and_refuse_in_their_own_words() {
    let text = |args: &[&str]| {
        let dir = tempfile::tempdir().unwrap();
        let mut a = vec!["experiment"];
        a.extend_from_slice(args);
        a.extend(["--out-dir", dir.path().to_str().unwrap()]);
        ok_stdout(&run("edmd", &a, None))
    };
    // One start has no spread, and a packing whose every particle rattles has no contacts.
    let jam = text(&[
        "jamming",
        "--dim",
        "2",
        "--fraction-large",
        "0.3",
        "--n",
        "100",
        "--seeds",
        "1",
        "--rates",
        "0.2",
    ]);
    assert!(!jam.contains("NaN"), "{jam}");
    assert!(
        jam.contains("1 start per rate") && jam.contains("30:70"),
        "{jam}"
    );
    assert!(jam.contains("G = 0.2: every particle rattles"), "{jam}");
    // Lee's law starts at its t_0: before, a dash.
    let lee = text(&["annihilation", "--n", "500", "--until", "30"]);
    assert!(
        !lee.contains("NaN") && lee.contains("          -   "),
        "{lee}"
    );
    // With no A left, no rate constant.
    let gone = text(&[
        "annihilation",
        "--n",
        "64",
        "--probability",
        "1",
        "--until",
        "2000",
        "--runs",
        "2",
    ]);
    assert!(!gone.contains("NaN") && gone.contains("0.000e0"), "{gone}");
    // A patch denser than any monolayer is not given a monolayer's depth (it was "inf").
    let ring = text(&[
        "ring",
        "--tau",
        "1",
        "--n",
        "100",
        "--orbits",
        "4",
        "--restitution",
        "0.5",
        "--start",
        "cold",
        "--frames",
        "2",
    ]);
    assert!(
        !ring.contains("inf") && ring.contains("above 0.907"),
        "{ring}"
    );
    // Without the TC model the gas collapses: said, and the fits stop before it (they were
    // "over 0-0 collisions", with exit 0 and no word of it).
    let cool = text(&[
        "cooling",
        "--tc",
        "0",
        "--restitution",
        "0.1",
        "--packing",
        "0.6",
        "--n",
        "1000",
        "--runs",
        "2",
    ]);
    assert!(cool.contains("inelastic collapse in 2 of 2 runs"), "{cool}");
    assert!(!cool.contains("fitted over 0-0"), "{cool}");

    for (args, words) in [
        (
            &["jamming", "--rates", "1e-308"][..],
            &["jamming: growth rate 1e-308 is too slow", "faster --rates"][..],
        ),
        (
            &["jamming", "--size-ratio", "20"][..],
            &["jamming: size ratio 20", "--size-ratio"][..],
        ),
        (
            &["jamming", "--fraction-large", "0.3"][..],
            &["--size-ratio for spheres"][..],
        ),
        // Its MSD was fitted over the later half of the run, where 5 samples put one.
        (
            &["annihilation", "--samples", "5"][..],
            &["--samples 5", "at least 14"][..],
        ),
        // The conductivity's blocks are half as many: 1 gave no error bar.
        (
            &["viscosity", "--blocks", "3"][..],
            &["--blocks must be from 4"][..],
        ),
        (
            &["reaction", "--packing", "0.6"][..],
            &["reaction, for spheres", "--dim"][..],
        ),
        (
            &["demon", "--until", "1e308"][..],
            &["--until must be above 0 and at most 1e7"][..],
        ),
        (&["diffusion", "--until", "1e8"][..], &["--until"][..]),
        (&["brownian", "--until", "1e308"][..], &["--until"][..]),
        (&["billiards", "--follow", "1e308"][..], &["--follow"][..]),
        (
            &["reversibility", "--times", "1,1e308"][..],
            &["--times"][..],
        ),
        // clap reads these values as options: the message names the option and the way out.
        (
            &["eos", "--packing", "-inf"][..],
            &["--packing -inf", "--packing=-inf"][..],
        ),
        (&["eos", "--dim", "-1"][..], &["--dim=-1"][..]),
        // An option where a value was due is no value starting with '-'.
        (
            &["eos", "--packing", "--bogus"][..],
            &["unexpected argument '--bogus'"][..],
        ),
        (
            &["jamming", "--rates", "0.2,1e-300"][..],
            &["1e-300 is too slow", "faster --rates"][..],
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out_dir = dir.path().join("out");
        let mut a = vec!["experiment"];
        a.extend_from_slice(args);
        a.extend(["--out-dir", out_dir.to_str().unwrap()]);
        refused(&run("edmd", &a, None), words);
        assert!(!out_dir.exists(), "{args:?}");
    }
}
