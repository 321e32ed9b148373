//! `edmd soak`, short: the invariants hold over a short dense run in 1D, 2D and 3D (RELIABILITY.md
//! records the long one, 10^9 collisions).

use crate::support::{ok_stdout, run};

#[test]
fn a_short_soak_passes_every_check() {
    for (dim, n) in [("1", "1000"), ("2", "1000"), ("3", "864")] {
        let out = run(
            "edmd",
            &[
                "soak",
                "--dim",
                dim,
                "--n",
                n,
                "--collisions",
                "3e5",
                "--checks",
                "6",
                "--json",
            ],
            None,
        );
        let s: serde_json::Value = serde_json::from_str(ok_stdout(&out).trim()).unwrap();
        assert_eq!(s["ok"], true, "{s}");
        assert_eq!(s["last"]["collisions"], 300_000, "{s}");
        assert_eq!(s["last"]["overlaps"], 0);
        assert!(s["max_energy_drift"].as_f64().unwrap() < 1e-12, "{s}");
    }
}

#[test]
fn soak_options_out_of_range_are_refused() {
    for args in [
        &["soak", "--collisions", "0"][..],
        &["soak", "--collisions", "1.5"],
        &["soak", "--n", "1"],
        &["soak", "--packing", "0.95"],
        &["soak", "--dim", "4"],
        // More checks than collisions found the clock "stopped" between two checks.
        &[
            "soak",
            "--n",
            "100",
            "--collisions",
            "1000",
            "--checks",
            "100000",
        ],
    ] {
        let out = run("edmd", args, None);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr).trim().lines().count(),
            1
        );
    }
}
