//! Spheres from the command line: `gen --dim 3`, `run` on 3D files (chained, with a
//! trajectory that ASE reads), and clear refusals of malformed 3D input.

use crate::support::{example, ok_stdout, refused, run, summary, write};

#[test]
fn generated_sphere_fluid_runs_and_chains() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("f.txt");
    let f = f.to_str().unwrap();
    let gen = |out: &str| {
        run(
            "edmd",
            &[
                "gen",
                "fluid",
                "--dim",
                "3",
                "--n",
                "300",
                "--packing",
                "0.4",
                "--seed",
                "5",
                "-o",
                out,
            ],
            None,
        )
    };
    ok_stdout(&gen(f));
    let text = std::fs::read_to_string(f).unwrap();
    assert!(text.starts_with("300\n# edmd dim 3\n"), "{}", &text[..40]);
    // The same seed gives the same file.
    let again = dir.path().join("g.txt");
    ok_stdout(&gen(again.to_str().unwrap()));
    assert_eq!(std::fs::read_to_string(&again).unwrap(), text);
    // Run to 2 in one go, and to 1 then on to 2 from the written state: the chained run keeps
    // the box and the spheres, conserves energy and ends at a valid state.
    let one = dir.path().join("one.txt");
    let s = summary(&run(
        "edmd",
        &[
            "run",
            f,
            "--until",
            "1",
            "--json",
            "--check",
            "-o",
            one.to_str().unwrap(),
        ],
        None,
    ));
    assert_eq!(s["dim"], 3);
    assert_eq!(s["n"], 300);
    assert!(s["disc_collisions"].as_u64().unwrap() > 1000, "{s}");
    assert!(s["relative_energy_change"].as_f64().unwrap().abs() < 1e-12);
    let two = summary(&run(
        "edmd",
        &[
            "run",
            one.to_str().unwrap(),
            "--until",
            "1",
            "--json",
            "--check",
        ],
        None,
    ));
    assert_eq!(two["dim"], 3);
    let state = std::fs::read_to_string(&one).unwrap();
    assert_eq!(state.lines().nth(2), text.lines().nth(2), "the box line");
}

#[test]
fn the_shipped_sphere_example_runs_with_measurements() {
    let dir = tempfile::tempdir().unwrap();
    let m = dir.path().join("m");
    let s = summary(&run(
        "edmd",
        &[
            "run",
            example("spheres-500.txt").to_str().unwrap(),
            "--until",
            "5",
            "--json",
            "--measure",
            "pressure,speeds",
            "--measure-dir",
            m.to_str().unwrap(),
        ],
        None,
    ));
    let z = s["measurements"]["pressure"]["Z"]["value"]
        .as_f64()
        .unwrap();
    // Packing 0.3: Z = 3.984 (Pieprzyk et al. 2019); a short run of 500 spheres is within 3%.
    assert!((z / 3.984 - 1.0).abs() < 0.03, "Z = {z}");
    let speeds = &s["measurements"]["speeds"];
    assert!(speeds["rms_maxwell"].as_f64().unwrap() > 0.0, "{speeds}");
    let csv = std::fs::read_to_string(m.join("speeds.csv")).unwrap();
    assert!(csv.starts_with("speed,density,maxwell_density"), "{csv}");
}

#[test]
fn malformed_3d_input_is_refused_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let cases: &[(&str, &[&str])] = &[
        (
            "1\n# edmd dim 3\n0.5 0.5 0 0 0.1 1 0 0 0\n",
            &[":3:", "expected 11 fields"],
        ),
        (
            "1\n# edmd dim 4\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 0\n",
            &[":2:", "dim 3"],
        ),
        (
            "1\n# edmd dim 3\n# edmd barrier x 0.5\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 0\n",
            &[":3:", "2D files only"],
        ),
        // A sphere outside the unit cube, and two overlapping spheres.
        (
            "1\n# edmd dim 3\n0.5 0.5 1.5 0 0 0 0.1 1 0 0 0\n",
            &[":3:", "not inside the box"],
        ),
        (
            "2\n# edmd dim 3\n0.5 0.5 0.5 0 0 0 0.1 1 0 0 0\n0.5 0.5 0.6 0 0 0 0.1 1 0 0 0\n",
            &[":4:", "overlaps"],
        ),
    ];
    for (k, (text, words)) in cases.iter().enumerate() {
        let f = write(&dir, &format!("bad{k}.txt"), text);
        refused(&run("edmd", &["run", &f, "--until", "1"], None), words);
    }
    refused(
        &run("edmd", &["gen", "single", "--dim", "3", "-o", "-"], None),
        &["fluids and mixtures only"],
    );
    refused(
        &run("edmd", &["gen", "fluid", "--dim", "4", "-o", "-"], None),
        &["2 or 3"],
    );
    refused(
        &run(
            "edmd",
            &["gen", "fluid", "--dim", "3", "--packing", "0.55", "-o", "-"],
            None,
        ),
        &["0.494"],
    );
}

/// ASE must read 3D trajectories too (see `trajectory::ase_reads_the_trajectory`).
#[test]
fn ase_reads_a_sphere_trajectory() {
    let has_ase = std::process::Command::new("python3")
        .args(["-c", "import ase"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_ase {
        assert!(
            std::env::var("EDMD_REQUIRE_ASE").is_err(),
            "EDMD_REQUIRE_ASE is set but python3 cannot import ase"
        );
        crate::support::skipped("ase_reads_a_sphere_trajectory", "python3 cannot import ase");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let t = dir.path().join("t.xyz");
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            example("spheres-500.txt").to_str().unwrap(),
            "--until",
            "2",
            "--trajectory",
            t.to_str().unwrap(),
            "--every",
            "1",
        ],
        None,
    ));
    let script = format!(
        "import ase.io, numpy as np\nf = ase.io.read(r'{}', index=':')\nassert len(f) == 3, len(f)\na = f[-1]\nassert len(a) == 500\nL = a.cell.lengths()\nassert abs(L[2] - L[0]) < 1e-9 and L[2] > 5, L\nassert a.pbc.all(), a.pbc\nz = a.positions[:, 2]\nassert z.min() >= 0 and z.max() <= L[2] and z.std() > 1, (z.min(), z.max())\nv = a.get_velocities()\nassert np.abs(v[:, 2]).max() > 0, 'vz zero'\nke = 0.5 * (a.get_masses()[:, None] * v**2).sum()\nassert abs(ke / 500 - 1.5) < 1e-9, ke\nprint('ok')",
        t.display()
    );
    let out = std::process::Command::new("python3")
        .args(["-c", &script])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn spheres_render_as_a_view_and_as_a_slice() {
    let dir = tempfile::tempdir().unwrap();
    let file = example("spheres-500.txt");
    let file = file.to_str().unwrap();
    let frames = |name: &str, extra: &[&str]| -> Vec<Vec<u8>> {
        let out = dir.path().join(name);
        let mut a = vec![
            "render",
            file,
            "-o",
            out.to_str().unwrap(),
            "--until",
            "1",
            "--fps",
            "2",
            "--size",
            "120x100",
        ];
        a.extend_from_slice(extra);
        ok_stdout(&run("edmd", &a, None));
        let mut opts = gif::DecodeOptions::new();
        opts.set_color_output(gif::ColorOutput::RGBA);
        let mut dec = opts.read_info(std::fs::File::open(&out).unwrap()).unwrap();
        assert_eq!((dec.width(), dec.height()), (120, 100));
        let mut all = Vec::new();
        while let Some(f) = dec.read_next_frame().unwrap() {
            all.push(f.buffer.to_vec());
        }
        all
    };
    let view = frames("v.gif", &["--view", "-60,35"]);
    assert_eq!(view.len(), 3);
    assert_ne!(view[0], view[2], "the spheres move");
    let other = frames("w.gif", &["--view", "30,20"]);
    assert_ne!(view[0], other[0], "another direction, another picture");
    let cut = frames("s.gif", &["--slice", "z=2.5"]);
    assert_ne!(cut[0], view[0]);
    // Distinct colours in the slice: white background, box edges and sphere colours.
    let colours: std::collections::HashSet<&[u8]> = cut[0].chunks(4).collect();
    assert!(colours.len() > 3, "{} colours", colours.len());
    refused(
        &run(
            "edmd",
            &[
                "render", file, "-o", "x.gif", "--until", "1", "--slice", "z=99",
            ],
            None,
        ),
        &["outside the box"],
    );
    refused(
        &run(
            "edmd",
            &[
                "render", file, "-o", "x.gif", "--until", "1", "--view", "0,100",
            ],
            None,
        ),
        &["ELEVATION"],
    );
}
