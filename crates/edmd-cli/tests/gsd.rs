//! GSD files as input: a frame of a HOOMD GSD file continues in `edmd run`, bad ones get one
//! line and exit status 2.

use crate::support::{example, ok_stdout, refused, run};

#[test]
fn a_gsd_state_runs_like_the_text_state_it_was_written_from() {
    let dir = tempfile::tempdir().unwrap();
    let text = example("spheres-500.txt");
    let text = text.to_str().unwrap();
    let gsd = dir.path().join("spheres.gsd");
    // The text file's state, written as GSD with edmd's exact copies, then both run on.
    let sys = match edmd_io::parse_any(
        &std::fs::read_to_string(text).unwrap(),
        edmd_io::Format::Princeton(Default::default()),
    )
    .unwrap()
    {
        edmd_io::AnyLoaded::Three(sys) => sys,
        _ => panic!("spheres-500.txt is 3D"),
    };
    edmd_io::gsd::write_file(
        &gsd,
        &sys.discs,
        &sys.sim_box,
        0.0,
        edmd_io::gsd::Precision::Exact,
    )
    .unwrap();
    let a = dir.path().join("a.txt");
    let b = dir.path().join("b.txt");
    ok_stdout(&run(
        "edmd",
        &["run", text, "--until", "2", "-o", a.to_str().unwrap()],
        None,
    ));
    ok_stdout(&run(
        "edmd",
        &[
            "run",
            gsd.to_str().unwrap(),
            "--until",
            "2",
            "-o",
            b.to_str().unwrap(),
        ],
        None,
    ));
    let (a, b) = (
        std::fs::read_to_string(&a).unwrap(),
        std::fs::read_to_string(&b).unwrap(),
    );
    // The same spheres in the same order, to the bit (GSD carries no colour for black
    // spheres and the same box).
    assert_eq!(a, b);
    // A frame that is not there, and --frame on a text file.
    refused(
        &run(
            "edmd",
            &["run", gsd.to_str().unwrap(), "--until", "1", "--frame", "3"],
            None,
        ),
        &["spheres.gsd", "frame"],
    );
    refused(
        &run("edmd", &["run", text, "--until", "1", "--frame", "0"], None),
        &["--frame applies to GSD files"],
    );
}

#[test]
fn a_bad_gsd_file_is_one_line_and_status_2() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.gsd");
    let mut bytes = vec![0xDF, 0x65, 0xDF, 0x65, 0xDF, 0x65, 0xDF, 0x65];
    bytes.extend_from_slice(b" and then nothing a GSD file has");
    std::fs::write(&bad, bytes).unwrap();
    let out = dir.path().join("out.txt");
    refused(
        &run(
            "edmd",
            &[
                "run",
                bad.to_str().unwrap(),
                "--until",
                "1",
                "-o",
                out.to_str().unwrap(),
            ],
            None,
        ),
        &["bad.gsd"],
    );
    assert!(!out.exists());
}
