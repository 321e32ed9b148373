//! `edmd experiment ring`: Goldreich and Tremaine's two sides of the critical restitution on a
//! small patch, the JSON fields, the files, bad options.

use serde_json::Value;

use crate::support::{names, refused, run, summary};

fn num(r: &Value, key: &str) -> f64 {
    r[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {r}"))
}

#[test]
fn a_patch_settles_below_the_critical_restitution_and_heats_above_it() {
    // 100 spheres at optical depth 0.25, 20 orbits from a cold start: e = 0.25 settles within
    // two orbits, e = 0.9 passes the cap within a few.
    let dir = tempfile::tempdir().unwrap();
    let out = run(
        "edmd",
        &[
            "experiment",
            "ring",
            "--n",
            "100",
            "--orbits",
            "20",
            "--restitution",
            "0.25,0.9",
            "--start",
            "cold",
            "--frames",
            "4",
            "--json",
            "--out-dir",
            dir.path().to_str().unwrap(),
        ],
        None,
    );
    let v = summary(&out);
    assert_eq!(v["experiment"], "ring");
    assert_eq!(v["interrupted"], false);
    assert_eq!(num(&v, "critical_restitution"), 0.63);
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for r in rows {
        for key in [
            "dispersion",
            "dispersion_error",
            "thickness",
            "tau_dynamic",
            "tau_photometric",
            "wall_hits",
        ] {
            num(r, key);
        }
        assert_eq!(r["start"], "cold");
        assert!(
            r["steady"].is_boolean() && r["theory_steady"].is_boolean(),
            "{r}"
        );
    }
    let (low, high) = (&rows[0], &rows[1]);
    assert_eq!(num(low, "restitution"), 0.25);
    assert_eq!(low["steady"], true, "{low}");
    assert_eq!(low["theory_steady"], true);
    // A near-monolayer a fraction of Omega d hot, whose photometric depth lies between the
    // dynamical one and a monolayer's.
    let d = num(low, "dispersion");
    assert!(d > 0.2 && d < 1.5, "{low}");
    let tau_p = num(low, "tau_photometric");
    assert!(
        tau_p > 0.25 && tau_p < num(low, "tau_monolayer") + 0.01,
        "{low}"
    );
    assert_eq!(num(high, "restitution"), 0.9);
    assert_eq!(high["steady"], false, "{high}");
    assert_eq!(high["theory_steady"], false);
    assert_eq!(high["capped"], true, "{high}");
    assert!(num(high, "dispersion") > num(&v, "cap"), "{high}");
    assert_eq!(
        names(dir.path()),
        [
            "ring-dispersion.png",
            "ring-dispersion.svg",
            "ring-optical-depth.png",
            "ring-optical-depth.svg",
            "ring-patch.gif",
            "ring-time-series.csv",
            "ring.csv"
        ]
    );
}

#[test]
fn bad_options_are_refused() {
    for (args, words) in [
        (vec!["--restitution", "1.5"], "--restitution"),
        (vec!["--restitution", "x"], "--restitution"),
        (vec!["--n", "1"], "--n"),
        (vec!["--tau", "0"], "--tau"),
        // A grid of the patch's width squared overflowed or could not be allocated.
        (vec!["--tau", "1e-9"], "--tau must be from 1e-4"),
        (vec!["--orbits", "0"], "--orbits"),
        (vec!["--bridges-vc", "0"], "--bridges-vc"),
        (
            vec!["--bridges-vc", "1e-308"],
            "--bridges-vc must be from 0.001",
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path().join("out");
        let mut a = vec!["experiment", "ring", "--out-dir", d.to_str().unwrap()];
        a.extend(args);
        refused(&run("edmd", &a, None), &[words]);
        assert!(!d.exists(), "nothing written");
    }
}

#[test]
fn a_patch_that_collapses_names_the_restitution_that_made_it() {
    // Perfectly inelastic collisions jam the patch; the clock's stop used to be reported
    // without the option behind it.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("out");
    let out = run(
        "edmd",
        &[
            "experiment",
            "ring",
            "--restitution",
            "0",
            "--start",
            "cold",
            "--out-dir",
            d.to_str().unwrap(),
        ],
        None,
    );
    refused(
        &out,
        &[
            "ring: the run with --restitution 0 (cold start) stopped",
            "clock stopped advancing",
        ],
    );
    assert!(!d.exists(), "nothing written");
}
