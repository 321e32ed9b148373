//! GSD files: round trips through HOOMD's float32 chunks and edmd's float64 copies, frame
//! selection, the HOOMD schema's defaults, files written by the `gsd` Python package, and bad
//! files (one-line errors, never a panic).

use std::path::{Path, PathBuf};

use edmd_core::{Boundary, Disc, Options, SimBox, Simulation, Vector};
use edmd_io::gsd::{self, Precision, State, Writer};
use edmd_io::AnyLoaded;
use hoomd_gsd::file_layer::GsdFile;
use proptest::prelude::*;

/// `2^-24`: float32's unit roundoff.
const U32: f64 = 1.0 / 16_777_216.0;

fn temp() -> tempfile::TempDir {
    tempfile::tempdir().expect("a temporary folder")
}

fn two(a: AnyLoaded) -> edmd_io::LoadedSystem<2> {
    match a {
        AnyLoaded::Two(s) => s,
        AnyLoaded::Three(_) => panic!("read as 3D"),
        AnyLoaded::One(_) => panic!("read as 1D"),
    }
}

fn three(a: AnyLoaded) -> edmd_io::LoadedSystem<3> {
    match a {
        AnyLoaded::Three(s) => s,
        AnyLoaded::Two(_) => panic!("read as 2D"),
        AnyLoaded::One(_) => panic!("read as 1D"),
    }
}

/// Discs from numbers in [0, 1): positions anywhere in the box (including 0 and just below L),
/// velocities of either sign, radii, masses, species, colours.
fn discs<const D: usize>(u: &[f64], lengths: [f64; D]) -> Vec<Disc<D>> {
    let per = 2 * D + 3;
    u.chunks_exact(per)
        .enumerate()
        .map(|(i, c)| Disc {
            pos: Vector(std::array::from_fn(|a| {
                // Every 5th disc sits on the faces: at 0 or just below L.
                match i % 5 {
                    3 => 0.0,
                    4 => lengths[a] * (1.0 - 1e-12),
                    _ => c[a] * lengths[a],
                }
            })),
            vel: Vector(std::array::from_fn(|a| (c[D + a] - 0.5) * 7.0)),
            radius: 0.001 + 0.1 * c[2 * D],
            mass: 0.1 + 10.0 * c[2 * D + 1],
            colour: [i as u8, (3 * i) as u8, 7],
            species: (c[2 * D + 2] * 5.0) as u16,
        })
        .collect()
}

/// The float32 round trip's checks (see `edmd_io::gsd`, "Precision"): each position within
/// `L 2^-24` of where it was (`L 2^-23` where a point on a walled axis was moved in from the
/// far face), on periodic axes up to a whole box (the image count then says so); velocities to
/// relative `2^-24`; radii and masses as float32 rounds them; species, colours, walls and the
/// time exactly.
fn check_float32<const D: usize>(
    before: &[Disc<D>],
    b: &SimBox<D>,
    time: f64,
    frame: &gsd::GsdFrame,
    after: &edmd_io::LoadedSystem<D>,
) {
    assert!(!frame.exact);
    assert_eq!(after.time, time);
    assert_eq!(after.sim_box.boundaries, b.boundaries);
    assert_eq!(after.discs.len(), before.len());
    for a in 0..D {
        assert_eq!(after.sim_box.lengths[a], b.lengths[a] as f32 as f64);
    }
    for (i, (d, e)) in before.iter().zip(&after.discs).enumerate() {
        for a in 0..D {
            let l = b.lengths[a];
            let l_read = after.sim_box.lengths[a];
            assert!(
                (0.0..l_read).contains(&e.pos[a]),
                "disc {i} axis {a}: {} outside [0, {l_read})",
                e.pos[a]
            );
            // The image count read says how many boxes the point was moved by.
            let moved = e.pos[a] + frame.images[i][a] as f64 * l_read - d.pos[a];
            let near_far_face = l - d.pos[a] < l * 1e-6;
            let bound = if b.is_periodic(a) || !near_far_face {
                l * U32
            } else {
                2.0 * l * U32
            };
            assert!(
                moved.abs() <= bound * (1.0 + 1e-9),
                "disc {i} axis {a}: moved by {moved:e}, more than {bound:e}"
            );
            if !b.is_periodic(a) {
                assert_eq!(frame.images[i][a], 0);
            }
            assert!((e.vel[a] - d.vel[a]).abs() <= d.vel[a].abs() * U32);
        }
        assert_eq!(e.radius, (2.0 * d.radius) as f32 as f64 / 2.0);
        assert_eq!(e.mass, d.mass as f32 as f64);
        assert_eq!(e.species, d.species);
        assert_eq!(e.colour, d.colour);
    }
}

fn write_one<const D: usize>(
    path: &Path,
    d: &[Disc<D>],
    b: &SimBox<D>,
    time: f64,
    precision: Precision,
) {
    gsd::write_file(path, d, b, time, precision).expect("written");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn a_2d_round_trip_keeps_float32_precision(
        u in prop::collection::vec(0.0f64..1.0, 7 * 12),
        lx in 0.01f64..1e4, ly in 0.01f64..1e4,
        walls in prop::array::uniform2(any::<bool>()),
        time in 0.0f64..1e6,
    ) {
        let dir = temp();
        let path = dir.path().join("s.gsd");
        let lengths = [lx, ly];
        let mut b = SimBox::periodic(lengths);
        for a in 0..2 {
            if walls[a] { b.boundaries[a] = Boundary::Walls; }
        }
        let d = discs(&u, lengths);
        write_one(&path, &d, &b, time, Precision::Float32);
        let f = gsd::read_frame(&path, 0).expect("read");
        let s = match &f.system { AnyLoaded::Two(s) => s.clone(), _ => panic!("3D") };
        check_float32(&d, &b, time, &f, &s);
        // And exactly with the float64 copies.
        write_one(&path, &d, &b, time, Precision::Exact);
        let f = gsd::read_frame(&path, -1).expect("read");
        prop_assert!(f.exact);
        prop_assert!(f.notes.is_empty(), "{:?}", f.notes);
        let s = two(f.system);
        prop_assert_eq!(s.discs, d);
        prop_assert_eq!(s.sim_box, b);
        prop_assert_eq!(s.time, time);
        prop_assert!(f.images.iter().all(|i| *i == [0, 0, 0]));
    }

    #[test]
    fn a_3d_round_trip_keeps_float32_precision(
        u in prop::collection::vec(0.0f64..1.0, 9 * 12),
        l in prop::array::uniform3(0.01f64..1e4),
        walls in prop::array::uniform3(any::<bool>()),
    ) {
        let dir = temp();
        let path = dir.path().join("s.gsd");
        let mut b = SimBox::periodic(l);
        for a in 0..3 {
            if walls[a] { b.boundaries[a] = Boundary::Walls; }
        }
        let d = discs(&u, l);
        write_one(&path, &d, &b, 2.5, Precision::Float32);
        let f = gsd::read_frame(&path, 0).expect("read");
        let s = match &f.system { AnyLoaded::Three(s) => s.clone(), _ => panic!("2D") };
        check_float32(&d, &b, 2.5, &f, &s);
        write_one(&path, &d, &b, 2.5, Precision::Exact);
        let s = three(gsd::read_any(&path, 0).expect("read"));
        prop_assert_eq!(s.discs, d);
        prop_assert_eq!(s.sim_box, b);
    }
}

/// A point just below a periodic axis's L rounds onto HOOMD's far face `+L/2`; it is written
/// at `-L/2` one image on, and read back at 0 with that image, the same place.
#[test]
fn a_point_on_the_far_face_comes_back_one_image_on() {
    let dir = temp();
    let path = dir.path().join("s.gsd");
    let b = SimBox::periodic([1.0, 1.0]);
    let d = vec![Disc::new(
        Vector([1.0 - 1e-12, 0.5]),
        Vector([1.0, 0.0]),
        0.1,
    )];
    write_one(&path, &d, &b, 0.0, Precision::Float32);
    let f = gsd::read_frame(&path, 0).expect("read");
    let s = two(f.system);
    assert_eq!(s.discs[0].pos[0], 0.0);
    assert_eq!(f.images[0], [1, 0, 0]);
    // With the exact copies the position is the one written and the image the true one.
    write_one(&path, &d, &b, 0.0, Precision::Exact);
    let f = gsd::read_frame(&path, 0).expect("read");
    assert_eq!(f.images[0], [0, 0, 0]);
    assert_eq!(two(f.system).discs, d);
}

/// A run in a periodic box: the image counts written are those of the unwrapped positions.
#[test]
fn a_simulation_frame_keeps_its_unwrapped_positions() {
    let dir = temp();
    let path = dir.path().join("run.gsd");
    let n = 20;
    let b = SimBox::periodic([10.0, 10.0]);
    let d: Vec<Disc> = (0..n)
        .map(|i| {
            let (x, y) = ((i % 5) as f64 * 2.0 + 1.0, (i / 5) as f64 * 2.0 + 1.0);
            Disc::new(Vector([x, y]), Vector([3.0 + i as f64 * 0.1, -2.0]), 0.3)
        })
        .collect();
    let mut sim = Simulation::new(&d, b, Options::default()).expect("valid");
    let mut w = Writer::create(&path, Precision::Float32).expect("created");
    w.append_simulation(&sim).expect("frame 0");
    sim.run_until(25.0, &mut ());
    w.append_simulation(&sim).expect("frame 1");
    w.finish().expect("finished");
    let f = gsd::read_frame(&path, 1).expect("read");
    assert_eq!(f.step, sim.stats().disc_disc);
    let s = two(f.system.clone());
    assert_eq!(s.time, 25.0);
    let mut moved = 0;
    for i in 0..n {
        let u = sim.unwrapped_position(i);
        for a in 0..2 {
            let back = s.discs[i].pos[a] + f.images[i][a] as f64 * s.sim_box.lengths[a];
            // The image count times the float32 box length adds its rounding (exact here: 10).
            assert!((back - u[a]).abs() <= 10.0 * U32 * (1.0 + f.images[i][a].abs() as f64));
            moved += (f.images[i][a] != 0) as usize;
        }
    }
    assert!(moved > 0, "no disc crossed the box: the test shows nothing");
}

#[test]
fn frames_are_chosen_from_either_end() {
    let dir = temp();
    let path = dir.path().join("t.gsd");
    let b = SimBox::walls([4.0, 4.0]);
    let mut w = Writer::create(&path, Precision::Float32).expect("created");
    for k in 0..3 {
        let d = vec![Disc::new(
            Vector([1.0 + k as f64, 2.0]),
            Vector([0.0, 0.0]),
            0.2,
        )];
        w.append(&State {
            discs: &d,
            sim_box: &b,
            images: None,
            time: 10.0 * k as f64,
            step: k,
        })
        .expect("frame");
    }
    w.finish().expect("finished");
    assert_eq!(gsd::frame_count(&path), Ok(3));
    for (k, want) in [
        (0, 0.0),
        (1, 10.0),
        (2, 20.0),
        (-1, 20.0),
        (-2, 10.0),
        (-3, 0.0),
    ] {
        let f = gsd::read_frame(&path, k).expect("read");
        assert_eq!(two(f.system.clone()).time, want, "frame {k}");
        assert_eq!(two(f.system).discs[0].pos[0], 1.0 + want / 10.0);
        assert_eq!(f.frames, 3);
    }
    for k in [3, -4, i64::MAX, i64::MIN] {
        let e = gsd::read_frame(&path, k).expect_err("out of range");
        assert!(
            e.to_string().contains(&format!(
                "frame {k} is out of range: the file has 3 frame(s)"
            )),
            "{e}"
        );
    }
}

/// A chunk missing from a frame is frame 0's (the HOOMD schema's rule), else the default; and
/// `Lz = 0` alone makes a frame 2D.
#[test]
fn missing_chunks_come_from_frame_0_or_the_defaults() {
    let dir = temp();
    let path = dir.path().join("h.gsd");
    {
        let mut g = GsdFile::create(&path, "test", "hoomd", (1, 4)).expect("created");
        g.write_scalars("configuration/box", [6.0f32, 4.0, 0.0, 0.0, 0.0, 0.0])
            .unwrap();
        g.write_scalars("particles/N", [2u32]).unwrap();
        g.write_arrays("particles/position", [[0.0f32, 0.0, 0.0], [1.0, -1.0, 0.0]])
            .unwrap();
        g.write_scalars("particles/diameter", [0.5f32, 0.25])
            .unwrap();
        g.write_scalars("particles/typeid", [1u32, 0]).unwrap();
        g.write_arrays("particles/types", [[b'A', 0], [b'B', 0]])
            .unwrap();
        g.end_frame().unwrap();
        g.write_scalars("configuration/step", [7u64]).unwrap();
        g.write_arrays(
            "particles/position",
            [[2.0f32, 1.0, 0.0], [-3.0, -2.0, 0.0]],
        )
        .unwrap();
        g.end_frame().unwrap();
        g.sync_all().unwrap();
    }
    let f = gsd::read_frame(&path, -1).expect("read");
    assert_eq!(f.step, 7);
    let s = two(f.system);
    assert_eq!(s.sim_box, SimBox::periodic([6.0, 4.0]));
    assert_eq!(s.discs[0].pos, Vector([5.0, 3.0]));
    assert_eq!(s.discs[1].pos, Vector([0.0, 0.0]));
    assert_eq!((s.discs[0].radius, s.discs[1].radius), (0.25, 0.125));
    assert_eq!((s.discs[0].species, s.discs[1].species), (1, 0));
    assert_eq!((s.discs[0].mass, s.discs[0].vel), (1.0, Vector([0.0, 0.0])));
    assert_eq!(s.time, 0.0);
    assert_eq!(s.lines, vec![1, 2]);
}

/// Per-particle chunks come from frame 0 only when it has as many particles: with another N
/// they take the schema's defaults (as the `gsd` package reads them).
#[test]
fn frame_0_lends_particle_chunks_only_to_frames_of_its_size() {
    let dir = temp();
    let path = dir.path().join("n.gsd");
    {
        let mut g = GsdFile::create(&path, "test", "hoomd", (1, 4)).expect("created");
        g.write_scalars("particles/N", [1u32]).unwrap();
        g.write_arrays("particles/position", [[0.0f32; 3]]).unwrap();
        g.write_scalars("particles/diameter", [0.5f32]).unwrap();
        g.end_frame().unwrap();
        g.write_scalars("particles/N", [2u32]).unwrap();
        g.write_arrays("particles/position", [[0.0f32; 3], [0.25, 0.0, 0.0]])
            .unwrap();
        g.end_frame().unwrap();
        g.sync_all().unwrap();
    }
    let s = three(gsd::read_any(&path, 1).expect("read"));
    assert_eq!((s.discs[0].radius, s.discs[1].radius), (0.5, 0.5));
    let s = three(gsd::read_any(&path, 0).expect("read"));
    assert_eq!(s.discs[0].radius, 0.25);
}

/// edmd's float64 copies are used only when they agree with HOOMD's chunks: a file whose
/// positions another program changed is read from the changed positions.
#[test]
fn stale_exact_copies_are_ignored_with_a_note() {
    let dir = temp();
    let path = dir.path().join("e.gsd");
    {
        let mut g = GsdFile::create(&path, "test", "hoomd", (1, 4)).expect("created");
        g.write_scalars("configuration/box", [2.0f32, 2.0, 2.0, 0.0, 0.0, 0.0])
            .unwrap();
        g.write_scalars("particles/N", [1u32]).unwrap();
        g.write_arrays("particles/position", [[0.5f32, 0.0, 0.0]])
            .unwrap();
        g.write_scalars("log/edmd/box", [2.0f64, 2.0, 2.0]).unwrap();
        g.write_arrays("log/edmd/position", [[1.0f64, 1.0, 1.0]])
            .unwrap();
        g.write_arrays("log/edmd/velocity", [[0.0f64, 0.0, 0.0]])
            .unwrap();
        g.end_frame().unwrap();
        g.sync_all().unwrap();
    }
    let f = gsd::read_frame(&path, 0).expect("read");
    assert!(!f.exact);
    assert_eq!(f.notes.len(), 1, "{:?}", f.notes);
    assert!(
        f.notes[0].contains("log/edmd/position does not match"),
        "{:?}",
        f.notes
    );
    assert_eq!(three(f.system).discs[0].pos, Vector([1.5, 1.0, 1.0]));
}

// ------------------------------------------------------------------------------------------
// Bad files

/// A file of one frame written with `hoomd-gsd`'s file layer, chunk by chunk.
fn hoomd_file(path: &Path, frame: impl FnOnce(&mut GsdFile)) {
    let mut g = GsdFile::create(path, "test", "hoomd", (1, 4)).expect("created");
    frame(&mut g);
    g.end_frame().unwrap();
    g.sync_all().unwrap();
}

fn error_of(path: &Path, frame: i64) -> String {
    let e = gsd::read_frame(path, frame).expect_err("a bad file");
    let s = e.to_string();
    assert!(s.starts_with(&format!("{}: ", path.display())), "{s}");
    assert!(!s.contains('\n'), "{s}");
    s
}

#[test]
fn bad_files_give_one_line_naming_the_file_and_the_problem() {
    let dir = temp();
    let at = |name: &str| dir.path().join(name);
    let cases: Vec<(PathBuf, &str)> = vec![
        {
            let p = at("empty.gsd");
            std::fs::write(&p, b"").unwrap();
            (p, "the file is empty")
        },
        {
            let p = at("text.gsd");
            std::fs::write(&p, b"2\n0.1\n1 1\n").unwrap();
            (p, "not a GSD file")
        },
        {
            let p = at("short.gsd");
            std::fs::write(&p, gsd::MAGIC).unwrap();
            (p, "less than the 256-byte header")
        },
        (dir.path().to_path_buf(), "is a folder"),
        (at("missing.gsd"), "cannot read"),
        {
            let p = at("schema.gsd");
            let g = GsdFile::create(&p, "test", "other", (1, 0)).unwrap();
            drop(g);
            (p, "the GSD schema is 'other'")
        },
        {
            let p = at("noframes.gsd");
            drop(GsdFile::create(&p, "test", "hoomd", (1, 4)).unwrap());
            (p, "the file has no frames")
        },
        {
            let p = at("noposition.gsd");
            hoomd_file(&p, |g| g.write_scalars("particles/N", [3u32]).unwrap());
            (
                p,
                "particles/N is 3 but there is no particles/position chunk",
            )
        },
        {
            let p = at("mismatch.gsd");
            hoomd_file(&p, |g| {
                g.write_scalars("particles/N", [2u32]).unwrap();
                g.write_arrays("particles/position", [[0f32; 3]; 2])
                    .unwrap();
                g.write_arrays("particles/velocity", [[0f32; 3]; 3])
                    .unwrap();
            });
            (p, "particles/velocity has 3 row(s) but particles/N is 2")
        },
        {
            let p = at("nan.gsd");
            hoomd_file(&p, |g| {
                g.write_scalars("particles/N", [2u32]).unwrap();
                g.write_arrays("particles/position", [[0f32; 3], [0.0, f32::NAN, 0.0]])
                    .unwrap();
            });
            (
                p,
                "particles/position: particle 1 has a value that is not finite (NaN)",
            )
        },
        {
            let p = at("infbox.gsd");
            hoomd_file(&p, |g| {
                g.write_scalars(
                    "configuration/box",
                    [f32::INFINITY, 1.0, 1.0, 0.0, 0.0, 0.0],
                )
                .unwrap()
            });
            (p, "configuration/box: value 0 is not finite (inf)")
        },
        {
            let p = at("zerobox.gsd");
            hoomd_file(&p, |g| {
                g.write_scalars("configuration/box", [1.0f32, 0.0, 1.0, 0.0, 0.0, 0.0])
                    .unwrap()
            });
            (p, "the box's y length is 0: box lengths must be > 0")
        },
        {
            let p = at("negativebox.gsd");
            hoomd_file(&p, |g| {
                g.write_scalars("configuration/box", [-2.0f32, 1.0, 1.0, 0.0, 0.0, 0.0])
                    .unwrap()
            });
            (p, "the box's x length is -2")
        },
        {
            let p = at("tilt.gsd");
            hoomd_file(&p, |g| {
                g.write_scalars("configuration/box", [2.0f32, 2.0, 2.0, 0.5, 0.0, 0.0])
                    .unwrap()
            });
            (
                p,
                "the box is tilted (xy xz yz = 0.5 0 0): edmd's box is rectangular",
            )
        },
        {
            let p = at("dims.gsd");
            hoomd_file(&p, |g| {
                g.write_scalars("configuration/dimensions", [4u8]).unwrap()
            });
            (p, "configuration/dimensions is 4")
        },
        {
            let p = at("intpos.gsd");
            hoomd_file(&p, |g| {
                g.write_scalars("particles/N", [1u32]).unwrap();
                g.write_arrays("particles/position", [[0i32; 3]]).unwrap();
            });
            (
                p,
                "particles/position is int32; the HOOMD schema has float32 (or float64)",
            )
        },
        {
            let p = at("typeid.gsd");
            hoomd_file(&p, |g| {
                g.write_scalars("particles/N", [1u32]).unwrap();
                g.write_arrays("particles/position", [[0f32; 3]]).unwrap();
                g.write_scalars("particles/typeid", [2u32]).unwrap();
                g.write_arrays("particles/types", [[b'A', 0], [b'B', 0]])
                    .unwrap();
            });
            (
                p,
                "particle 0 has typeid 2 but particles/types names 2 type(s)",
            )
        },
        {
            let p = at("mass.gsd");
            hoomd_file(&p, |g| {
                g.write_scalars("particles/N", [1u32]).unwrap();
                g.write_arrays("particles/position", [[0f32; 3]]).unwrap();
                g.write_scalars("particles/mass", [0f32]).unwrap();
            });
            (p, "particle 0 has mass 0: masses must be > 0")
        },
        {
            let p = at("z2d.gsd");
            hoomd_file(&p, |g| {
                g.write_scalars("configuration/dimensions", [2u8]).unwrap();
                g.write_scalars("particles/N", [1u32]).unwrap();
                g.write_arrays("particles/position", [[0.0f32, 0.0, 0.25]])
                    .unwrap();
            });
            (p, "particle 0 has z = 0.25 and vz = 0 in a 2D frame")
        },
    ];
    for (path, want) in &cases {
        let s = error_of(path, 0);
        assert!(
            s.contains(want),
            "{}: expected '{want}' in: {s}",
            path.display()
        );
    }
    let p = &cases[0].0;
    assert!(error_of(p, -1).contains("the file is empty"));
}

/// `hoomd-gsd` asserts on some corrupt index entries and indexes its memory map with offsets
/// from the file; every truncation and many byte changes of a valid file must give an error
/// (or, where the change is harmless, a frame), never a panic and never the last-resort
/// `catch_unwind` in `read_frame` (which would mean `check_file` let something through).
#[test]
fn truncated_and_corrupted_files_never_panic() {
    let dir = temp();
    let good = dir.path().join("good.gsd");
    {
        let b = SimBox::periodic([3.0, 2.0, 1.0]);
        let mut w = Writer::create(&good, Precision::Exact).expect("created");
        for k in 0..2 {
            let d = vec![
                Disc::new(Vector([0.5, 0.5, 0.5]), Vector([1.0, 0.0, 0.0]), 0.1),
                Disc::new(Vector([2.0, 1.5, 0.5]), Vector([0.0, -1.0, 0.5]), 0.2),
            ];
            w.append(&State {
                discs: &d,
                sim_box: &b,
                images: None,
                time: k as f64,
                step: k,
            })
            .expect("frame");
        }
        w.finish().expect("finished");
    }
    let bytes = std::fs::read(&good).unwrap();
    assert!(gsd::read_frame(&good, -1).is_ok());
    let bad = dir.path().join("bad.gsd");
    let mut outcomes = [0usize; 2];
    let mut try_bytes = |b: &[u8], what: &str| {
        std::fs::write(&bad, b).unwrap();
        for frame in [0, -1] {
            let r = std::panic::catch_unwind(|| gsd::read_frame(&bad, frame));
            let r = r.unwrap_or_else(|_| panic!("panicked on {what}"));
            match r {
                Ok(_) => outcomes[0] += 1,
                Err(e) => {
                    let s = e.to_string();
                    assert!(!s.contains("the GSD reader failed"), "{what}: {s}");
                    assert!(!s.contains('\n'), "{what}: {s}");
                    outcomes[1] += 1;
                }
            }
        }
    };
    // Every truncation.
    for len in 0..bytes.len() {
        try_bytes(&bytes[..len], &format!("truncated to {len} bytes"));
    }
    // Every byte inverted, set to 0xFF, and set to 0x01; and every 8-byte word set to
    // a huge value (offsets, counts and sizes that overflow when added or multiplied).
    let mut b = bytes.clone();
    for at in 0..bytes.len() {
        for v in [!bytes[at], 0xFF, 0x01] {
            b[at] = v;
            try_bytes(&b, &format!("byte {at} set to {v:#x}"));
        }
        b[at] = bytes[at];
    }
    for at in (0..bytes.len() - 8).step_by(4) {
        for v in [u64::MAX, u64::MAX / 32 + 1, 1 << 62] {
            b[at..at + 8].copy_from_slice(&v.to_le_bytes());
            try_bytes(&b, &format!("word at {at} set to {v:#x}"));
        }
        b[at..at + 8].copy_from_slice(&bytes[at..at + 8]);
    }
    // Both outcomes happened: the changes reached both checked and unchecked places.
    assert!(outcomes[0] > 0 && outcomes[1] > 0, "{outcomes:?}");
}

// ------------------------------------------------------------------------------------------
// The `gsd` Python package

/// The Python to run (`EDMD_PYTHON`, default `python3`) when it has the `gsd` package; `None`
/// (after a line starting SKIPPED) when it has not, unless `EDMD_REQUIRE_GSD=1`, which makes
/// that a failure.
fn python_with_gsd() -> Option<String> {
    let python = std::env::var("EDMD_PYTHON").unwrap_or_else(|_| "python3".into());
    let ok = std::process::Command::new(&python)
        .args(["-c", "import gsd.hoomd, numpy"])
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        return Some(python);
    }
    if std::env::var("EDMD_REQUIRE_GSD").as_deref() == Ok("1") {
        panic!("EDMD_REQUIRE_GSD=1 but '{python}' cannot import gsd.hoomd and numpy");
    }
    println!("SKIPPED: '{python}' has no gsd package (pip install gsd; EDMD_PYTHON names another Python)");
    None
}

fn run_python(python: &str, script: &str, args: &[&Path]) -> String {
    let out = std::process::Command::new(python)
        .arg("-c")
        .arg(script)
        .args(args)
        .output()
        .expect("python runs");
    assert!(
        out.status.success(),
        "python failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A HOOMD-style 2D trajectory written by the `gsd` package (image flags, typeid, types,
/// diameter, mass, velocity; a second frame holding only new positions) reads as HOOMD means it,
/// and a 3D frame in double precision as 3D, exactly.
#[test]
fn files_written_by_the_gsd_python_package_are_read() {
    let Some(python) = python_with_gsd() else {
        return;
    };
    let dir = temp();
    let (p2, p3) = (dir.path().join("h2.gsd"), dir.path().join("h3.gsd"));
    let script = r#"
import sys, gsd.hoomd
f = gsd.hoomd.Frame()
f.configuration.step = 1000
f.configuration.dimensions = 2
f.configuration.box = [10, 8, 0, 0, 0, 0]
f.particles.N = 3
f.particles.types = ['A', 'B']
f.particles.typeid = [0, 1, 1]
f.particles.position = [[-4.5, -3.5, 0], [0, 0, 0], [4.75, 3.5, 0]]
f.particles.velocity = [[1, 0, 0], [0, -2, 0], [0.5, 0.5, 0]]
f.particles.image = [[1, 0, 0], [0, -2, 0], [-1, 3, 0]]
f.particles.diameter = [1.0, 0.5, 0.5]
f.particles.mass = [1.0, 2.0, 2.0]
with gsd.hoomd.open(sys.argv[1], 'w') as t:
    t.append(f)
    g = gsd.hoomd.Frame()
    g.configuration.step = 2000
    g.configuration.box = [10, 8, 0, 0, 0, 0]
    g.configuration.dimensions = 2
    g.particles.N = 3
    g.particles.position = [[-4, -3, 0], [1, 1, 0], [-5, 3.75, 0]]
    t.append(g)
h = gsd.hoomd.Frame()
h.configuration.box = [3, 4, 5, 0, 0, 0]
h.particles.N = 1
h.particles.position = [[1 / 3, -1, 2]]
with gsd.hoomd.open(sys.argv[2], 'w', precision='double') as t:
    t.append(h)
"#;
    run_python(&python, script, &[&p2, &p3]);
    let f = gsd::read_frame(&p2, 0).expect("read");
    assert_eq!((f.step, f.frames), (1000, 2));
    assert_eq!(f.images, vec![[1, 0, 0], [0, -2, 0], [-1, 3, 0]]);
    let s = two(f.system);
    assert_eq!(s.sim_box, SimBox::periodic([10.0, 8.0]));
    let pos: Vec<_> = s.discs.iter().map(|d| d.pos).collect();
    assert_eq!(
        pos,
        vec![Vector([0.5, 0.5]), Vector([5.0, 4.0]), Vector([9.75, 7.5])]
    );
    let species: Vec<_> = s.discs.iter().map(|d| d.species).collect();
    assert_eq!(species, vec![0, 1, 1]);
    assert_eq!(s.discs[1].radius, 0.25);
    assert_eq!(s.discs[2].mass, 2.0);
    assert_eq!(s.discs[1].vel, Vector([0.0, -2.0]));
    // Frame 1 holds positions; the rest is frame 0's (or the schema's defaults).
    let f = gsd::read_frame(&p2, -1).expect("read");
    assert_eq!(f.step, 2000);
    let s = two(f.system);
    assert_eq!(s.discs[2].pos, Vector([0.0, 7.75]));
    assert_eq!(s.discs[1].radius, 0.25);
    assert_eq!(s.discs[1].species, 1);
    let s = three(gsd::read_any(&p3, 0).expect("read"));
    assert_eq!(s.sim_box, SimBox::periodic([3.0, 4.0, 5.0]));
    // Written in double precision (HOOMD schema 2.0): read exactly.
    assert_eq!(s.discs[0].pos, Vector([1.0 / 3.0 + 1.5, 1.0, 4.5]));
    assert_eq!((s.discs[0].radius, s.discs[0].mass), (0.5, 1.0));
}

/// What edmd writes, the `gsd` package reads: HOOMD's box, centred positions in `[-L/2, L/2)`,
/// types, and edmd's time and walls in `log/`.
#[test]
fn files_written_here_are_read_by_the_gsd_python_package() {
    let Some(python) = python_with_gsd() else {
        return;
    };
    let dir = temp();
    let path = dir.path().join("e.gsd");
    let mut b = SimBox::periodic([4.0, 2.0]);
    b.boundaries[1] = Boundary::Walls;
    let mut d = vec![
        Disc::new(Vector([1.0, 0.5]), Vector([0.25, -1.0]), 0.1),
        Disc::new(Vector([4.0 - 1e-12, 2.0 - 0.1]), Vector([0.0, 0.0]), 0.1),
    ];
    d[1].species = 2;
    d[1].mass = 3.0;
    write_one(&path, &d, &b, 12.5, Precision::Float32);
    let script = r#"
import sys, gsd.hoomd
with gsd.hoomd.open(sys.argv[1], 'r') as t:
    f = t[0]
    print(len(t), f.configuration.dimensions, list(map(float, f.configuration.box)))
    print(f.particles.N, list(map(int, f.particles.typeid)), f.particles.types)
    for p in f.particles.position:
        print(*map(float, p))
    print(list(map(int, f.particles.image[1])), list(map(float, f.particles.mass)))
    print(float(f.log['edmd/time'][0]), list(map(int, f.log['edmd/walls'])))
"#;
    let out = run_python(&python, script, &[&path]);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "1 2 [4.0, 2.0, 0.0, 0.0, 0.0, 0.0]");
    assert_eq!(lines[1], "2 [0, 2] ['A', 'B', 'C']");
    assert_eq!(lines[2], "-1.0 -0.5 0.0");
    // Just below L on the periodic x axis: written at -L/2, one image on.
    let p: Vec<f64> = lines[3].split(' ').map(|w| w.parse().unwrap()).collect();
    assert_eq!(p[0], -2.0);
    assert!((p[1] - 0.9).abs() < 1e-6);
    assert_eq!(lines[4], "[1, 0, 0] [1.0, 3.0]");
    assert_eq!(lines[5], "12.5 [0, 1, 0]");
}

#[test]
fn rods_on_a_line_are_refused_in_one_line_and_no_file_is_left() {
    let dir = temp();
    let path = dir.path().join("rods.gsd");
    let d = Disc::new(Vector([0.5]), Vector([1.0]), 0.25);
    let e = gsd::write_file(&path, &[d], &SimBox::walls([2.0]), 0.0, Precision::Exact).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("2D and 3D systems only, not 1D (rods on a line)"),
        "{text}"
    );
    assert!(!text.contains('\n'));
    assert!(!path.exists());
}
