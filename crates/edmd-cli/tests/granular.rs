//! Inelastic collisions and a uniform field from the command line: `edmd gen --restitution
//! --gravity` files run by `edmd run` with the energy lost counted and the energy (kinetic plus
//! the field's, plus the loss) conserved, states and checkpoints that carry both, the example
//! heap, and bad input refused in one line with exit status 2, nothing written.

use crate::support::{example, refused, run, summary, write};

fn f(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is not a number in {v}"))
}

#[test]
fn a_heap_falls_settles_and_keeps_its_energy_books() {
    let dir = tempfile::tempdir().unwrap();
    let heap = dir.path().join("heap.txt");
    let heap = heap.to_str().unwrap();
    // A negative exponent form, which an option that takes negative numbers alone would refuse.
    let out = run(
        "edmd",
        &[
            "gen",
            "fluid",
            "--n",
            "300",
            "--packing",
            "0.2",
            "--gravity",
            "-1e-0",
            "--restitution",
            "0.8",
            "--restitution",
            "walls 0.9",
            "--restitution",
            "tc 1e-3",
            "-o",
            heap,
        ],
        None,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(heap).unwrap();
    for line in [
        "# edmd boundary periodic walls",
        "# edmd gravity y -1",
        "# edmd restitution 0.8",
        "# edmd restitution walls 0.9",
        "# edmd restitution tc 0.001",
    ] {
        assert!(text.contains(line), "{line} missing from\n{}", &text[..300]);
    }
    let state = dir.path().join("heap-10.txt");
    let ck = dir.path().join("heap.ck");
    let s = summary(&run(
        "edmd",
        &[
            "run",
            heap,
            "--until",
            "10",
            "--json",
            "--output",
            state.to_str().unwrap(),
            "--checkpoint",
            ck.to_str().unwrap(),
        ],
        None,
    ));
    // The field's energy turned into motion, most of it lost in collisions; the books balance
    // to rounding.
    assert!(f(&s, "dissipated") > 0.0, "{s}");
    assert!(f(&s, "relative_energy_change").abs() < 1e-12, "{s}");
    let written = std::fs::read_to_string(&state).unwrap();
    assert!(
        written.contains("# edmd gravity y -1") && written.contains("# edmd restitution tc 0.001")
    );
    // The checkpoint goes on as the run never stopped would, its loss included.
    let on = summary(&run(
        "edmd",
        &["run", ck.to_str().unwrap(), "--until", "20", "--json"],
        None,
    ));
    let straight = summary(&run(
        "edmd",
        &["run", heap, "--until", "20", "--json"],
        None,
    ));
    assert_eq!(on["disc_collisions"], straight["disc_collisions"]);
    assert_eq!(f(&on, "dissipated"), f(&straight, "dissipated"));
}

#[test]
fn the_example_heap_runs() {
    let heap = example("granular-heap.txt");
    let s = summary(&run(
        "edmd",
        &["run", heap.to_str().unwrap(), "--until", "5", "--json"],
        None,
    ));
    assert!(f(&s, "dissipated") > 0.0);
    assert!(f(&s, "relative_energy_change").abs() < 1e-12, "{s}");
}

#[test]
fn bad_granular_input_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out_file = dir.path().join("never.txt");
    let o = out_file.to_str().unwrap();
    for (args, words) in [
        (
            vec!["gen", "fluid", "--restitution", "1.5", "-o", o],
            vec!["--restitution '1.5'", "[0, 1]"],
        ),
        (
            vec![
                "gen",
                "fluid",
                "--restitution",
                "0.9",
                "--restitution",
                "0.8",
                "-o",
                o,
            ],
            vec!["second restitution for every pair"],
        ),
        (
            vec!["gen", "fluid", "--gravity", "0", "-o", o],
            vec!["--gravity 0", "other than 0"],
        ),
        (
            vec!["gen", "fluid", "--gravity", "nan", "-o", o],
            vec!["--gravity"],
        ),
        (
            vec![
                "gen",
                "fluid",
                "--gravity",
                "-1",
                "--restitution",
                "0.5",
                "-o",
                o,
            ],
            vec!["TC model"],
        ),
        (
            vec!["gen", "fluid", "--course", "--restitution", "0.5", "-o", o],
            vec!["course format"],
        ),
    ] {
        refused(&run("edmd", &args, None), &words);
        assert!(!out_file.exists(), "{args:?} wrote a file");
    }
    for (text, words) in [
        ("1\n# edmd restitution 2\n.5 .5 0 0 .1 1 0 0 0\n", vec![":2:", "the coefficient must be in [0, 1]"]),
        ("1\n# edmd boundary periodic\n# edmd box 4 4\n# edmd gravity y -1\n1 1 0 0 .1 1 0 0 0\n", vec![":4:", "must have walls"]),
        ("1\n# edmd gravity y -1\n# edmd restitution 0.5\n.5 .5 0 0 .1 1 0 0 0\n", vec![":2:", "TC model"]),
    ] {
        let path = write(&dir, "bad.txt", text);
        refused(&run("edmd", &["run", &path, "--until", "1", "--output", o], None), &words);
        assert!(!out_file.exists());
    }
}
