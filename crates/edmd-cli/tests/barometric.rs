//! `edmd experiment barometric`: a dilute column against the barometric law, a dense one
//! against the local-density approximation, a flat temperature, the files, bad options.

use serde_json::Value;

use crate::support::{names, refused, run, summary};

fn num(r: &Value, key: &str) -> f64 {
    r[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {r}"))
}

#[test]
fn a_dilute_column_is_barometric_and_a_dense_one_follows_the_lda() {
    // 400 discs per column, 800 samples: about a second in release.
    let dir = tempfile::tempdir().unwrap();
    let out = run(
        "edmd",
        &[
            "experiment",
            "barometric",
            "--packing",
            "0.01,0.5",
            "--n",
            "400",
            "--samples",
            "800",
            "--json",
            "--out-dir",
            dir.path().to_str().unwrap(),
        ],
        None,
    );
    let v = summary(&out);
    assert_eq!(v["experiment"], "barometric");
    assert_eq!(v["interrupted"], false);
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for r in rows {
        for key in [
            "dim",
            "n",
            "g",
            "packing",
            "box_width",
            "box_height",
            "kt",
            "kt_error",
            "kt_slope",
            "kt_slope_error",
            "kt_chi2",
            "scale_height",
            "scale_height_error",
            "scale_height_theory",
            "scale_height_theory_error",
            "scale_height_lda",
            "mean_height",
            "mean_height_error",
            "mean_height_barometric",
            "mean_height_lda",
            "packing_floor_lda",
            "compared_from",
            "chi2_barometric",
            "chi2_lda",
            "chi2_lda_above",
            "packing_max_deviation_lda",
            "packing_max_deviation_lda_above",
            "floor_excess",
            "floor_excess_error",
            "samples",
            "sample_interval",
            "time",
        ] {
            num(r, key);
        }
        assert_eq!((num(r, "dim"), num(r, "n"), num(r, "g")), (2.0, 400.0, 0.2));
        // The bath held kT = 1 and left the column with an energy drawn from its canonical
        // spread: in the dilute column kinetic and field energy each hold kT per disc, so kT
        // is spread by 1/sqrt(2N) = 3.5% (0.93 to 1.07 over ten seeds); four times that.
        assert!((num(r, "kt") - 1.0).abs() < 0.15, "{r}");
        // Equipartition in a field: the temperature does not change with height (a
        // microcanonical column of N discs leans by 1/(2N) per scale height, 0.001 here),
        // within four errors of its slope from the blocks.
        assert!(
            num(r, "kt_slope").abs() < 4.0 * num(r, "kt_slope_error") + 0.002,
            "{r}"
        );
        assert!(num(r, "compared_from") >= 5.0 && num(r, "compared_from") < 6.5);
    }
    let (dilute, dense) = (&rows[0], &rows[1]);

    // The fitted scale height against kT/(m g): within three times the sum of the two errors
    // (from blocks; they are anticorrelated, a column that stands higher being cooler, so that
    // their sum bounds the error of the difference) plus the lift by excluded volume that the
    // barometric law leaves out and the LDA puts at 1.3% at floor packing 0.01 (measured
    // within 0.3% of the LDA over eight seeds of the default run).
    let (fit, err) = (
        num(dilute, "scale_height"),
        num(dilute, "scale_height_error"),
    );
    let (law, law_err) = (
        num(dilute, "scale_height_theory"),
        num(dilute, "scale_height_theory_error"),
    );
    let lift = num(dilute, "scale_height_lda") - law;
    assert!(lift > 0.005 * law && lift < 0.02 * law, "{dilute}");
    assert!(
        (fit - law).abs() < 3.0 * (err + law_err) + lift,
        "fitted {fit} ± {err} against kT/mg {law} ± {law_err} (lift {lift}): {dilute}"
    );
    assert!(
        (fit - law - lift).abs() < 3.0 * (err + law_err) + 0.005 * law,
        "{dilute}"
    );

    // The dense column is far from barometric, and above the floor's layers it is the LDA's
    // to within the errors (chi^2 per bin near 1 in the default run; 3 allows for the block
    // errors' own scatter) and 0.01 in packing. The floor holds extra discs in its layers.
    assert!(num(dense, "chi2_barometric") > 100.0, "{dense}");
    assert!(num(dense, "chi2_lda_above") < 3.0, "{dense}");
    assert!(
        num(dense, "packing_max_deviation_lda_above") < 0.01,
        "{dense}"
    );
    assert!(
        num(dense, "floor_excess") > 3.0 * num(dense, "floor_excess_error"),
        "{dense}"
    );
    assert!(num(dense, "scale_height") > 2.0 * num(dense, "scale_height_theory"));

    assert_eq!(
        names(dir.path()),
        [
            "barometric-packing-0.01.png",
            "barometric-packing-0.01.svg",
            "barometric-packing-0.5.png",
            "barometric-packing-0.5.svg",
            "barometric-temperature.csv",
            "barometric-temperature.png",
            "barometric-temperature.svg",
            "barometric.csv",
        ]
    );
    let csv = std::fs::read_to_string(dir.path().join("barometric.csv")).unwrap();
    assert!(csv.starts_with("packing,height,density,density_error,barometric,lda,lda_above\n"));
}

#[test]
fn barometric_refuses_bad_options_in_one_line() {
    for (args, words) in [
        (&["--g", "0"][..], "--g"),
        (&["--g", "nan"][..], "--g"),
        (&["--g", "-0.2"][..], "--g"),
        (&["--g", "inf"][..], "--g"),
        (&["--n", "3"][..], "--n"),
        (&["--packing", "0.9"][..], "--packing 0.9"),
        (&["--packing", "0"][..], "--packing 0"),
        (&["--samples", "10"][..], "--samples"),
        (&["--bin", "0"][..], "--bin"),
        (&["--dim", "3", "--packing", "0.48"][..], "--packing 0.48"),
        // Too few discs for a box wider than three diameters at this packing.
        (&["--n", "50", "--packing", "0.55"][..], "too few"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out_dir = dir.path().join("out");
        let mut a = vec!["experiment", "barometric"];
        a.extend_from_slice(args);
        a.extend_from_slice(&["--out-dir", out_dir.to_str().unwrap()]);
        refused(&run("edmd", &a, None), &[words]);
        assert!(!out_dir.exists(), "{args:?} left a folder");
    }
}
