//! `edmd render`: frames without a screen.

use crate::support::{ok_stdout, run};

#[test]
fn gif_of_a_generated_data_set_has_the_expected_frames_and_size() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("g.txt");
    ok_stdout(&run(
        "edmd",
        &[
            "gen",
            "one-red",
            "--n",
            "60",
            "--seed",
            "2",
            "-o",
            f.to_str().unwrap(),
        ],
        None,
    ));
    let gif_path = dir.path().join("out.gif");
    let out = run(
        "edmd",
        &[
            "render",
            f.to_str().unwrap(),
            "-o",
            gif_path.to_str().unwrap(),
            "--until",
            "30",
            "--fps",
            "5",
            "--time-scale",
            "10",
            "--size",
            "160x120",
        ],
        None,
    );
    ok_stdout(&out);
    // Frames at t = 0, 2, 4, ..., 30: 16 frames.
    let file = std::fs::File::open(&gif_path).unwrap();
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts.read_info(file).unwrap();
    assert_eq!((dec.width(), dec.height()), (160, 120));
    let mut frames = 0;
    let mut first: Option<Vec<u8>> = None;
    let mut changed = false;
    while let Some(frame) = dec.read_next_frame().unwrap() {
        frames += 1;
        assert_eq!(frame.delay, 20);
        match &first {
            None => first = Some(frame.buffer.to_vec()),
            Some(b) => changed |= b.as_slice() != &frame.buffer[..],
        }
    }
    assert_eq!(frames, 16);
    assert!(changed, "the discs should move between frames");
}

#[test]
fn png_frames_and_a_missing_ffmpeg() {
    let dir = tempfile::tempdir().unwrap();
    let input = crate::support::example("gas-300.txt");
    let frames = dir.path().join("frames");
    ok_stdout(&run(
        "edmd",
        &[
            "render",
            input.to_str().unwrap(),
            "-o",
            frames.to_str().unwrap(),
            "--until",
            "1",
            "--fps",
            "3",
        ],
        None,
    ));
    let mut names: Vec<String> = std::fs::read_dir(&frames)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "frame_000000.png",
            "frame_000001.png",
            "frame_000002.png",
            "frame_000003.png"
        ]
    );
    // Without ffmpeg on the PATH, an MP4 is a clear error naming the program.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_edmd"))
        .args([
            "render",
            input.to_str().unwrap(),
            "-o",
            dir.path().join("v.mp4").to_str().unwrap(),
            "--until",
            "1",
        ])
        .env("PATH", dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("ffmpeg") && err.lines().count() == 1, "{err}");
    for (args, expect) in [
        (
            vec![
                "render",
                input.to_str().unwrap(),
                "-o",
                "x.gif",
                "--until",
                "1",
                "--size",
                "10x10",
            ],
            "WIDTHxHEIGHT",
        ),
        (
            vec![
                "render",
                input.to_str().unwrap(),
                "-o",
                "x.gif",
                "--until",
                "-1",
            ],
            ">= 0",
        ),
        (
            vec![
                "render",
                input.to_str().unwrap(),
                "-o",
                "x.gif",
                "--until",
                "1e6",
                "--fps",
                "100",
            ],
            "too many",
        ),
        (
            vec![
                "render",
                input.to_str().unwrap(),
                "-o",
                "x.gif",
                "--until",
                "1e308",
                "--time-scale",
                "1e-300",
            ],
            "over 1e308 frames is too many",
        ),
    ] {
        let out = run("edmd", &args, None);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains(expect),
            "{args:?}"
        );
    }
}

/// Reads PNG frame `k` of a frame folder as RGB pixels.
fn frame(dir: &std::path::Path, k: usize) -> Vec<[u8; 3]> {
    let pm = edmd_draw::Pixmap::load_png(dir.join(format!("frame_{k:06}.png"))).unwrap();
    pm.pixels()
        .iter()
        .map(|p| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue()]
        })
        .collect()
}

#[test]
fn bonds_and_energy_colours_of_a_square_well_fluid() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("sw.txt");
    ok_stdout(&run(
        "edmd",
        &[
            "gen",
            "fluid",
            "--n",
            "120",
            "--packing",
            "0.3",
            "--well",
            "1.5",
            "--kt",
            "1",
            "--seed",
            "3",
            "-o",
            f.to_str().unwrap(),
        ],
        None,
    ));
    let render = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let mut args = vec![
            "render",
            f.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--until",
            "0.5",
            "--fps",
            "2",
            "--size",
            "200x200",
        ];
        args.extend_from_slice(extra);
        ok_stdout(&run("edmd", &args, None));
        assert_eq!(
            crate::support::names(&out),
            ["frame_000000.png", "frame_000001.png"]
        );
        out
    };
    let plain = render("plain", &[]);
    let bonds = render("bonds", &["--bonds"]);
    let energy = render("energy", &["--bonds", "--colour", "energy"]);
    let bond_like = |p: &&[u8; 3]| p[0] > 180 && (80..170).contains(&p[1]) && p[2] < 110;
    let blue = |p: &&[u8; 3]| p[2] as i32 > p[0] as i32 + 40;
    for k in 0..2 {
        let (a, b, c) = (frame(&plain, k), frame(&bonds, k), frame(&energy, k));
        assert_ne!(a, b, "frame {k}: the bonds changed nothing");
        // The fluid's discs are black: orange pixels are bonds, blue ones bound discs.
        assert_eq!(a.iter().filter(bond_like).count(), 0);
        let orange = b.iter().filter(bond_like).count();
        assert!(orange > 100, "frame {k}: {orange} bond pixels");
        assert_eq!(b.iter().filter(blue).count(), 0);
        let bound = c.iter().filter(blue).count();
        assert!(bound > 1000, "frame {k}: {bound} pixels of bound discs");
    }
}

#[test]
fn bonds_and_energy_colours_are_refused_for_hard_discs() {
    let dir = tempfile::tempdir().unwrap();
    let input = crate::support::example("gas-300.txt");
    for (extra, option) in [
        (vec!["--bonds"], "--bonds"),
        (vec!["--colour", "energy"], "--colour energy"),
        (vec!["--bonds", "--colour", "energy"], "--bonds"),
    ] {
        let out_dir = dir.path().join("frames");
        let mut args = vec![
            "render",
            input.to_str().unwrap(),
            "-o",
            out_dir.to_str().unwrap(),
            "--until",
            "1",
        ];
        args.extend_from_slice(&extra);
        let out = run("edmd", &args, None);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{extra:?}: {err}");
        assert!(
            err.contains(option) && err.contains("hard discs"),
            "{extra:?}: {err}"
        );
        assert!(!out_dir.exists(), "{extra:?}: an output was left");
    }
}
