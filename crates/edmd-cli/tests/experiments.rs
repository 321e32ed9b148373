//! `edmd experiment NAME`: each writes its CSV files and plots and prints a summary that says
//! what the physics says.

use serde_json::Value;

use crate::support::{ok_stdout, run};

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
        let len = std::fs::metadata(&p).unwrap_or_else(|_| panic!("{name} missing")).len();
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
    assert_files(&dir, &["billiards_multi.csv", "billiards_multi.png", "billiards_multi.svg", "billiards_binary.png"]);
}

#[test]
fn reversibility_returns_short_runs_and_loses_long_ones() {
    let (v, dir) = experiment(&["reversibility", "--times", "0.5,1,16"]);
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 3);
    assert!(runs[0]["max_error"].as_f64().unwrap() < 1e-9, "{v}");
    assert!(runs[2]["max_error"].as_f64().unwrap() > 1e-3, "rounding growth should show: {v}");
    assert_files(&dir, &["reversibility.csv", "reversibility.png", "reversibility.svg"]);
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
        assert_eq!(String::from_utf8_lossy(&out.stderr).lines().count(), 1, "{args:?}");
    }
}

#[test]
fn eos_json_has_z_with_error_bars_near_henderson() {
    let (v, dir) = experiment(&["eos", "--packing", "0.2,0.4", "--n", "500"]);
    let results = v["results"].as_array().unwrap();
    assert_eq!(results.len(), 2);
    for r in results {
        let (eta, z, err) = (r["packing"].as_f64().unwrap(), r["Z"].as_f64().unwrap(), r["Z_err"].as_f64().unwrap());
        // Henderson: Z = (1 + eta^2/8) / (1 - eta)^2.
        let h = (1.0 + eta * eta / 8.0) / ((1.0 - eta) * (1.0 - eta));
        assert!((z / h - 1.0).abs() < 0.015, "{r}");
        assert!(err > 0.0 && err < 0.02 * z, "{r}");
    }
    assert_files(&dir, &["eos.csv", "eos.png", "eos.svg"]);
}

#[test]
fn maxwell_relaxes_an_equal_speed_start_to_rayleigh() {
    let (v, dir) = experiment(&["maxwell", "--n", "1000"]);
    assert!(v["ks_p_value"].as_f64().unwrap() > 0.01, "{v}");
    assert!(v["initial_ks_p_value"].as_f64().unwrap() < 1e-6, "{v}");
    let rms = v["rms_speed"].as_array().unwrap();
    assert!((rms[0].as_f64().unwrap() / rms[1].as_f64().unwrap() - 1.0).abs() < 1e-9, "rms speed is fixed by the energy: {v}");
    assert_files(&dir, &["maxwell.csv", "maxwell.png", "maxwell.svg"]);
}

#[test]
fn mfp_follows_enskog() {
    let (v, dir) = experiment(&["mfp", "--packing", "0.1,0.3", "--n", "600"]);
    for r in v["results"].as_array().unwrap() {
        let (m, e) = (r["mean_free_path"].as_f64().unwrap(), r["enskog_mean_free_path"].as_f64().unwrap());
        assert!((m / e - 1.0).abs() < 0.06, "{r}");
    }
    assert_files(&dir, &["mfp.csv", "mfp.png", "mfp_free_path.png", "mfp_free_time.svg"]);
}
