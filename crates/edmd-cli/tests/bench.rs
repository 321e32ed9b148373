//! `edmd bench` prints one JSON line with the promised fields (speed itself is recorded in
//! BENCHMARKS.md, never asserted).

use crate::support::{ok_stdout, run};

/// `edmd bench` on 400 discs at packing 0.6, 2 + 2 collisions per disc, with `extra` options:
/// its one line of output, parsed.
fn small_bench(extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "bench",
        "--n",
        "400",
        "--packing",
        "0.6",
        "--melt",
        "2",
        "--collisions",
        "2",
    ];
    args.extend_from_slice(extra);
    let text = ok_stdout(&run("edmd", &args, None));
    assert_eq!(text.lines().count(), 1);
    serde_json::from_str(&text).unwrap()
}

#[test]
fn bench_prints_one_json_line() {
    let v = small_bench(&[]);
    for key in [
        "n",
        "packing",
        "collisions",
        "seconds",
        "collisions_per_second",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert!(v["collisions"].as_u64().unwrap() >= 800);
    assert!(v["relative_energy_change"].as_f64().unwrap().abs() < 1e-12);
    let walls = run(
        "edmd",
        &[
            "bench",
            "--n",
            "400",
            "--packing",
            "0.3",
            "--boundary",
            "walls",
            "--melt",
            "1",
            "--collisions",
            "1",
        ],
        None,
    );
    ok_stdout(&walls);
}

/// `--portable` times the portable event loop; both loops process the same events.
#[test]
fn portable_loop_processes_the_same_events() {
    let (fast, portable) = (small_bench(&[]), small_bench(&["--portable"]));
    assert_eq!(portable["event_loop"], "portable");
    let fast_loop = if edmd_core::simulation::x86_64_v3_available() {
        "x86-64-v3"
    } else {
        "portable"
    };
    assert_eq!(fast["event_loop"], fast_loop);
    for key in ["collisions", "events", "stale", "relative_energy_change"] {
        assert_eq!(fast[key], portable[key], "{key}");
    }
}

#[test]
fn impossible_packing_is_a_clear_error() {
    let out = run("edmd", &["bench", "--n", "400", "--packing", "0.95"], None);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("packing fraction 0.95"));
}

/// A line of rods: 400 of them, the same fields, the dimension said, energy kept.
#[test]
fn bench_times_rods_on_a_line() {
    let v = small_bench(&["--dim", "1"]);
    assert_eq!(v["dim"], 1);
    assert!(v["collisions"].as_u64().unwrap() >= 800);
    assert!(v["relative_energy_change"].as_f64().unwrap().abs() < 1e-12);
    assert!(v["setup_seconds"].as_f64().unwrap() >= 0.0);
    assert!(v["melt_seconds"].as_f64().unwrap() >= 0.0);
}

/// 2^31 discs need about 250 GB: refused in one line naming the need, before anything is
/// made; one more than that is past the 32-bit indices.
#[test]
fn a_bench_larger_than_the_memory_is_refused_at_once() {
    let out = run(
        "edmd",
        &["bench", "--n", "2147483648", "--packing", "0.6"],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("2147483648 discs need about 247.0 GB"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    let out = run(
        "edmd",
        &["bench", "--n", "2147483649", "--packing", "0.6"],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--n must be from 2 to 2147483648"));
}
