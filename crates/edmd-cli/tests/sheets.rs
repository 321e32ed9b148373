//! `edmd experiment sheets`: the virial theorem on the isolated water bag, the isothermal
//! sheet in the heat bath, the files, bad options.

use serde_json::Value;

use crate::support::{names, refused, run, summary};

fn num(r: &Value, key: &str) -> f64 {
    r[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {r}"))
}

#[test]
fn the_virial_theorem_and_the_isothermal_sheet_hold() {
    // 200 sheets, 20 dynamical times isolated and 40 in the bath: about 3.5 10^5 crossings.
    let dir = tempfile::tempdir().unwrap();
    let out = run(
        "edmd",
        &[
            "experiment",
            "sheets",
            "--n",
            "200",
            "--time",
            "20",
            "--bath-time",
            "40",
            "--frames",
            "10",
            "--json",
            "--out-dir",
            dir.path().to_str().unwrap(),
        ],
        None,
    );
    let v = summary(&out);
    assert_eq!(v["experiment"], "sheets");
    assert_eq!(v["interrupted"], false);
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    // The virial theorem, 2<K> = <U>, on both runs: within 4 of their block errors, which the
    // slow oscillation of the bag leaves at a few per cent over 10 dynamical times.
    for r in rows {
        let (ratio, error) = (num(r, "virial_ratio"), num(r, "virial_ratio_error"));
        assert_eq!(num(r, "virial_theory"), 1.0);
        assert!(error > 0.0 && error < 0.05, "{r}");
        assert!((ratio - 1.0).abs() < 4.0 * error, "{r}");
    }
    assert_eq!(num(&v, "virial_ratio"), num(&rows[0], "virial_ratio"));
    for r in rows {
        assert_eq!(num(r, "wall_hits"), 0.0, "{r}");
    }
    // The isolated run conserves the energy to rounding.
    assert!(
        num(&rows[0], "relative_energy_change").abs() < 1e-10,
        "{}",
        rows[0]
    );
    // The bath: kT near the bath's 0.5, and x0 from the positions' variance against Spitzer's
    // 2 kT / (coupling M) within 4 of their combined errors (each about 1%).
    let bath = &rows[1];
    assert_eq!(bath["start"], "heat bath");
    assert!((num(bath, "kt") - 0.5).abs() < 0.05, "{bath}");
    let (x0, e) = (num(bath, "x0"), num(bath, "x0_error"));
    let (t, te) = (num(bath, "x0_theory"), num(bath, "x0_theory_error"));
    assert!((x0 - t).abs() < 4.0 * (e * e + te * te).sqrt(), "{bath}");
    assert!(num(bath, "profile_chi2") < 4.0, "{bath}");
    assert_eq!(
        names(dir.path()),
        [
            "sheets-phase-plane.gif",
            "sheets-profile.csv",
            "sheets-profile.png",
            "sheets-profile.svg",
            "sheets-virial.csv",
            "sheets-virial.png",
            "sheets-virial.svg"
        ]
    );
}

#[test]
fn bad_options_are_refused() {
    for (args, words) in [
        (vec!["--n", "5"], "--n"),
        (vec!["--time", "0"], "--time"),
        (vec!["--bath-time", "1"], "--bath-time"),
        (vec!["--frames", "0"], "--frames"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path().join("out");
        let mut a = vec!["experiment", "sheets", "--out-dir", d.to_str().unwrap()];
        a.extend(args);
        refused(&run("edmd", &a, None), &[words]);
        assert!(!d.exists(), "nothing written");
    }
}
