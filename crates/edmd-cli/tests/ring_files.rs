//! Ring patches through the files, `edmd gen ring` and `edmd run`: a generated patch is on
//! the Keplerian flow with the dispersion asked for; `edmd run` reports Omega and the
//! dispersion about the flow, heats an elastic patch and cools one under Bridges' law; the
//! states it writes carry the ring and its offset and run again; checkpoints continue bit for
//! bit; the example runs; bad files and options are refused in one line with exit status 2.

use crate::support::{example, refused, run, summary, write};

fn f(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is not a number in {v}"))
}

/// `edmd gen ring --n 300` with `extra` options into `path`, asserting success.
fn gen_ring(path: &str, extra: &[&str]) {
    let mut args = vec!["gen", "ring", "--n", "300"];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["-o", path]);
    let out = run("edmd", &args, None);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The numbers of the particle lines of a Princeton file.
fn rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .skip(1)
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(' ').map(|w| w.parse().unwrap()).collect())
        .collect()
}

/// `edmd run FILE --until T --json` (with `extra`), its summary.
fn run_json(file: &str, until: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["run", file, "--until", until, "--json"];
    args.extend_from_slice(extra);
    summary(&run("edmd", &args, None))
}

#[test]
fn gen_ring_is_a_patch_on_the_keplerian_flow() {
    let dir = tempfile::tempdir().unwrap();
    let patch = dir.path().join("patch.txt");
    let patch = patch.to_str().unwrap();
    gen_ring(
        patch,
        &["--omega", "2", "--dispersion", "1.5", "--seed", "7"],
    );
    let text = std::fs::read_to_string(patch).unwrap();
    // 3D by default, radius 0.5, optical depth 0.25: L = sqrt(300 pi 0.25 / 0.25).
    let side = (300.0 * std::f64::consts::PI).sqrt();
    let head: Vec<&str> = text.lines().take(5).collect();
    assert_eq!(head[1], "# edmd dim 3", "{head:?}");
    assert_eq!(head[2], format!("# edmd box {side:?} {side:?} 60.0"));
    assert_eq!(head[3], "# edmd boundary periodic periodic walls");
    assert_eq!(head[4], "# edmd ring 2.0 0.0");
    let r = rows(&text);
    assert_eq!(r.len(), 300);
    assert!(r.iter().all(|p| p[6] == 0.5 && p[7] == 1.0));
    // x velocities fall along y at 3/2 Omega = 3 (the fit's noise: a dispersion of 3 over
    // 300 particles spread over some 30 in y, about 0.02).
    let n = r.len() as f64;
    let mean = |k: usize| r.iter().map(|p| p[k]).sum::<f64>() / n;
    let (my, mu) = (mean(1), mean(3));
    let sxy: f64 = r.iter().map(|p| (p[1] - my) * (p[3] - mu)).sum();
    let sxx: f64 = r.iter().map(|p| (p[1] - my).powi(2)).sum();
    assert!((sxy / sxx + 3.0).abs() < 0.1, "slope {}", sxy / sxx);
    // The radial and vertical velocities have the dispersion 1.5 Omega d = 3 (to 10%: 300
    // samples give about 4%).
    for k in [4, 5] {
        let rms = (r.iter().map(|p| p[k] * p[k]).sum::<f64>() / n).sqrt();
        assert!((rms / 3.0 - 1.0).abs() < 0.1, "axis {k}: rms {rms}");
    }
    // A 2D patch when asked.
    let flat = dir.path().join("flat.txt");
    gen_ring(flat.to_str().unwrap(), &["--dim", "2"]);
    let text = std::fs::read_to_string(&flat).unwrap();
    assert!(
        text.contains("# edmd boundary periodic periodic\n# edmd ring 1.0 0.0\n"),
        "{}",
        &text[..200]
    );
    assert!(!text.contains("# edmd dim"));
}

#[test]
fn run_heats_an_elastic_patch_and_cools_one_under_bridges_law() {
    let dir = tempfile::tempdir().unwrap();
    let (elastic, bridges) = (dir.path().join("e.txt"), dir.path().join("b.txt"));
    let (elastic, bridges) = (elastic.to_str().unwrap(), bridges.to_str().unwrap());
    gen_ring(elastic, &[]);
    gen_ring(bridges, &["--restitution", "bridges 0.01"]);
    // The dispersion at the start, about 2 Omega d as generated.
    let start = run_json(elastic, "0", &[]);
    assert_eq!(f(&start, "ring_omega"), 1.0);
    assert_eq!(f(&start, "shear_rate"), -1.5);
    let c0 = f(&start, "dispersion");
    assert!((c0 / 2.0 - 1.0).abs() < 0.1, "{start}");
    // Elastic particles turn the shear's work into random motion (viscous heating) with
    // nothing to lose it: the dispersion grows, by half at least within 8 / Omega (measured:
    // 2.07 to 4.6).
    let heated = run_json(elastic, "8", &["--check"]);
    assert!(f(&heated, "dispersion") > 1.5 * c0, "{heated}");
    // Bridges' law at v_c = 0.01 (e about 0.3 at these speeds) loses more than the shear
    // gives: the dispersion falls (measured: 2.07 to 1.55), staying well above 0.
    let cooled = run_json(bridges, "8", &["--check"]);
    let c = f(&cooled, "dispersion");
    assert!(c < 0.9 * c0 && c > 0.2 * c0, "{cooled}");
    assert!(f(&cooled, "dissipated") > 0.0);
    // The human summary names the patch.
    let out = run("edmd", &["run", bridges, "--until", "1"], None);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("ring patch: Omega 1 (shear rate -1.5)")
            && text.contains("velocity dispersion")
            && text.contains("about the Keplerian flow"),
        "{text}"
    );
}

#[test]
fn a_written_ring_state_keeps_its_ring_and_runs_again() {
    let dir = tempfile::tempdir().unwrap();
    let patch = dir.path().join("patch.txt");
    let patch = patch.to_str().unwrap();
    // 2D: the offset at t = 2.3 is -1.5 L 2.3 mod L = 0.55 L, not a whole number of boxes.
    gen_ring(patch, &["--dim", "2", "--restitution", "bridges 0.01"]);
    let mid = dir.path().join("mid.txt");
    let mid = mid.to_str().unwrap();
    let first = run_json(patch, "2.3", &["-o", mid]);
    let text = std::fs::read_to_string(mid).unwrap();
    let offset = f(&first, "shear_offset");
    let side = (300.0 * std::f64::consts::PI).sqrt();
    assert!((offset - 0.55 * side).abs() < 1e-6 * side, "{first}");
    assert!(text.contains("# edmd time 2.3\n"), "{}", &text[..300]);
    assert!(
        text.contains(&format!("# edmd ring 1.0 {offset:?}\n")),
        "{}",
        &text[..300]
    );
    assert!(!text.contains("# edmd shear"));
    let again = run_json(mid, "4", &["--check"]);
    assert_eq!(f(&again, "ring_omega"), 1.0);
    // The images slid on from where the file left them: 1.5 L 4 mod L = 0.
    let end = f(&again, "shear_offset");
    assert!(end < 1e-6 * side || side - end < 1e-6 * side, "{again}");
    assert!(f(&again, "dispersion").is_finite());
}

#[test]
fn a_ring_checkpoint_continues_as_the_run_never_stopped() {
    let dir = tempfile::tempdir().unwrap();
    let patch = dir.path().join("patch.txt");
    let patch = patch.to_str().unwrap();
    gen_ring(
        patch,
        &["--restitution", "0.5", "--restitution", "tc 0.001"],
    );
    let ck = dir.path().join("patch.ck");
    let ck = ck.to_str().unwrap();
    run_json(patch, "2.5", &["--checkpoint", ck]);
    let (a, b) = (dir.path().join("a.txt"), dir.path().join("b.txt"));
    let on = run_json(ck, "5", &["-o", a.to_str().unwrap()]);
    let straight = run_json(patch, "5", &["-o", b.to_str().unwrap()]);
    for key in [
        "disc_collisions",
        "cell_crossings",
        "shear_offset",
        "dispersion",
        "dissipated",
        "ring_energy",
    ] {
        assert_eq!(on[key], straight[key], "{key}: {on} against {straight}");
    }
    let (a, b) = (
        std::fs::read_to_string(&a).unwrap(),
        std::fs::read_to_string(&b).unwrap(),
    );
    assert!(a.contains("# edmd ring 1.0 "));
    assert_eq!(a, b);
}

#[test]
fn the_example_ring_patch_runs() {
    let patch = example("ring-3d.txt");
    let s = run_json(patch.to_str().unwrap(), "5", &["--check"]);
    assert_eq!(f(&s, "ring_omega"), 1.0);
    assert!(f(&s, "dissipated") > 0.0);
    assert!(f(&s, "dispersion") > 0.0);
}

#[test]
fn bad_ring_files_are_refused_in_one_line_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let disc2 = "1 1 0 0 .5 1 0 0 0\n";
    let disc3 = "1 1 4 0 0 0 .5 1 0 0 0\n";
    for (text, words) in [
        (
            format!("1\n# edmd box 8 8\n# edmd ring 1\n{disc2}"),
            vec![":3:", "periodic x and y"],
        ),
        (
            format!("1\n# edmd dim 3\n# edmd box 8 8 8\n# edmd boundary periodic\n# edmd ring 1\n{disc3}"),
            vec![":5:", "walls along z"],
        ),
        (
            "1\n# edmd dim 1\n# edmd box 8\n# edmd ring 1\n1 0 .5 1 0 0 0\n".to_string(),
            vec![":4:", "1D file"],
        ),
        (
            format!("1\n# edmd box 8 8\n# edmd boundary periodic\n# edmd shear 1\n# edmd ring 1\n{disc2}"),
            vec![":5:", "'# edmd shear' (line 4)"],
        ),
        (
            format!("1\n# edmd dim 3\n# edmd box 8 8 8\n# edmd boundary periodic periodic walls\n# edmd gravity z -1\n# edmd ring 1\n{disc3}"),
            vec![":6:", "gravity (line 5)"],
        ),
        (
            format!("1\n# edmd box 8 8\n# edmd boundary periodic\n# edmd ring 1\n# edmd potential 0 0 1.5 -1\n{disc2}"),
            vec![":4:", "stepped potential (line 5)"],
        ),
        (
            format!("1\n# edmd box 8 8\n# edmd boundary periodic\n# edmd barrier x 4\n# edmd ring 1\n{disc2}"),
            vec![":5:", "barriers"],
        ),
        (
            format!("1\n# edmd box 8 8\n# edmd boundary periodic\n# edmd ring 0\n{disc2}"),
            vec![":4:", "above 0"],
        ),
        (
            format!("1\n# edmd box 8 8\n# edmd boundary periodic\n# edmd ring nan\n{disc2}"),
            vec![":4:", "OMEGA is not finite"],
        ),
        (
            format!("1\n# edmd box 8 8\n# edmd boundary periodic\n# edmd ring 1 8\n{disc2}"),
            vec![":4:", "[0, L_x) = [0, 8)"],
        ),
        (
            format!("1\n# edmd box 8 8\n# edmd boundary periodic\n# edmd ring 1 -1\n{disc2}"),
            vec![":4:", "offset"],
        ),
        (
            format!("1\n# edmd box 8 8\n# edmd boundary periodic\n# edmd ring 1\n# edmd restitution 0.5\n{disc2}"),
            vec![":4:", "TC model"],
        ),
    ] {
        let file = write(&dir, "bad.txt", &text);
        let out = run("edmd", &["run", &file, "--until", "1"], None);
        refused(&out, &words);
    }
    // With multi-disc collisions, the engine's refusal names the file's ring line.
    let file = write(
        &dir,
        "multi.txt",
        &format!("1\n# edmd box 8 8\n# edmd boundary periodic\n# edmd ring 1\n{disc2}"),
    );
    let out = run("edmd", &["run", &file, "--until", "1", "--multi"], None);
    refused(&out, &["'# edmd ring' line"]);
}

#[test]
fn bad_gen_ring_options_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let never = dir.path().join("never.txt");
    let o = never.to_str().unwrap();
    for (extra, words) in [
        (vec!["--restitution", "0.5"], vec!["TC model", "'tc T'"]),
        (vec!["--shear", "1"], vec!["--shear", "ring"]),
        (vec!["--gravity", "-1"], vec!["--gravity", "ring"]),
        (vec!["--well", "1.5"], vec!["--well"]),
        (vec!["--radius", "1"], vec!["--radius"]),
        (vec!["--boundary", "walls"], vec!["--boundary"]),
        (vec!["--course"], vec!["course format"]),
        (vec!["--dim", "1"], vec!["2 or 3 dimensions"]),
        (vec!["--dim", "2", "--height", "10"], vec!["--height"]),
        (vec!["--omega", "0"], vec!["--omega", "> 0"]),
        (vec!["--tau", "nan"], vec!["--tau", "finite"]),
        (vec!["--dispersion", "-1"], vec!["--dispersion", ">= 0"]),
        (vec!["--tau", "3"], vec!["optical depth 3"]),
        (vec!["--n", "1"], vec!["--n"]),
        (vec!["--n", "3"], vec!["use more particles"]),
        (vec!["--height", "2"], vec!["height"]),
    ] {
        let mut args = vec!["gen", "ring"];
        args.extend_from_slice(&extra);
        args.extend_from_slice(&["-o", o]);
        refused(&run("edmd", &args, None), &words);
        assert!(!never.exists(), "{extra:?} wrote a file");
    }
    // The ring's options belong to it alone.
    for flag in ["--tau", "--omega", "--dispersion", "--height"] {
        refused(
            &run("edmd", &["gen", "fluid", flag, "1", "-o", o], None),
            &[flag, "does not apply"],
        );
    }
}
