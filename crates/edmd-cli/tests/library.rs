//! The library and the command line are one program: a run read, measured and checkpointed
//! through the `edmd` library ends in the file and the measurements `edmd run` gives, bit for bit.

use edmd::checkpoint::{checkpoint_bytes, from_checkpoint_bytes, Measuring};
use edmd::io::princeton::ColumnOrder;
use edmd::io::AnyLoaded;
use edmd::measure::Measure;

use crate::support::{example, ok_stdout, run, summary};

#[test]
fn the_library_gives_what_edmd_run_gives() {
    let dir = tempfile::tempdir().unwrap();
    let file = example("gas-300.txt");
    let file = file.to_str().unwrap();
    let out = dir.path().join("out.txt");
    let cli = summary(&run(
        "edmd",
        &[
            "run",
            file,
            "--until",
            "10",
            "--measure",
            "temperature,pressure,msd",
            "--sample-every",
            "0.5",
            "-o",
            out.to_str().unwrap(),
            "--json",
        ],
        None,
    ));

    let AnyLoaded::Two(system) =
        edmd::input::read_any(file, None, ColumnOrder::RadiusMass, None).unwrap()
    else {
        panic!("gas-300.txt is a 2D file");
    };
    let mut sim = edmd::input::build(file, &system, edmd::engine::Options::default()).unwrap();
    let which = [Measure::Temperature, Measure::Pressure, Measure::Msd];
    let mut measuring = Measuring::new(&sim, &which, 0.5);
    // Half-way through a checkpoint, and the rest from it.
    assert!(measuring.run_to(&mut sim, 4.25).unwrap());
    let bytes = checkpoint_bytes(&sim, system.format, Some(&measuring)).unwrap();
    let (mut sim, format, measuring) = from_checkpoint_bytes::<2>(&bytes).unwrap();
    let mut measuring = measuring.unwrap();
    assert!(measuring.run_to(&mut sim, 10.0).unwrap());
    assert_eq!(measuring.samples, 20);

    let mut text = Vec::new();
    edmd::io::write(
        &mut text,
        &sim.discs(),
        sim.sim_box(),
        sim.barriers(),
        format,
        sim.time(),
    )
    .unwrap();
    assert!(
        text == std::fs::read(&out).unwrap(),
        "the final states differ"
    );
    // Compared as the program prints them: both through serde_json's text.
    let printed = serde_json::to_string(&measuring.obs.results(&sim).0).unwrap();
    let reread: serde_json::Value = serde_json::from_str(&printed).unwrap();
    assert_eq!(reread, cli["measurements"]);
    assert_eq!(
        sim.stats().disc_disc,
        cli["disc_collisions"].as_u64().unwrap()
    );
}

/// A file with reaction rules, read and built by the library with a seed, measured (kinetics)
/// and continued from a checkpoint, ends where `edmd run --seed` ends: the same state, rules
/// and species written, the same reactions and measurements.
#[test]
fn the_library_reacts_as_edmd_run_does() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("r.txt");
    let file = file.to_str().unwrap();
    ok_stdout(&run(
        "edmd",
        &[
            "gen",
            "fluid",
            "--dim",
            "3",
            "--n",
            "250",
            "--packing",
            "0.3",
            "--boundary",
            "periodic",
            "--species",
            "0.7,0.3",
            "--reaction",
            "0 + 0 -> 1 + 1 activation 1 probability 0.4 heat 0.2",
            "--reaction",
            "1 + 1 -> 0 + 0 activation 1.5 probability 0.9",
            "-o",
            file,
        ],
        None,
    ));
    let out = dir.path().join("out.txt");
    let cli = summary(&run(
        "edmd",
        &[
            "run",
            file,
            "--until",
            "6",
            "--seed",
            "4",
            "--measure",
            "kinetics",
            "--sample-every",
            "0.5",
            "-o",
            out.to_str().unwrap(),
            "--json",
        ],
        None,
    ));

    let AnyLoaded::Three(system) =
        edmd::input::read_any(file, None, ColumnOrder::RadiusMass, None).unwrap()
    else {
        panic!("a 3D file");
    };
    let mut sim =
        edmd::input::build_seeded(file, &system, edmd::engine::Options::default(), 4).unwrap();
    let mut measuring = Measuring::new(&sim, &[Measure::Kinetics], 0.5);
    assert!(measuring.run_to(&mut sim, 2.75).unwrap());
    let bytes = checkpoint_bytes(&sim, system.format, Some(&measuring)).unwrap();
    let (mut sim, format, measuring) = from_checkpoint_bytes::<3>(&bytes).unwrap();
    let mut measuring = measuring.unwrap();
    assert!(measuring.run_to(&mut sim, 6.0).unwrap());

    let rules = &sim.reactions().unwrap().rules;
    let mut text = Vec::new();
    let interactions = edmd::io::Interactions {
        reactions: rules,
        ..edmd::io::Interactions::HARD
    };
    edmd::io::write_full(
        &mut text,
        &sim.discs(),
        sim.sim_box(),
        sim.barriers(),
        interactions,
        format,
        sim.time(),
    )
    .unwrap();
    assert!(
        text == std::fs::read(&out).unwrap(),
        "the final states differ"
    );
    let printed = serde_json::to_string(&measuring.obs.results(&sim).0).unwrap();
    let reread: serde_json::Value = serde_json::from_str(&printed).unwrap();
    assert_eq!(reread, cli["measurements"]);
    assert_eq!(
        sim.reaction_counts().to_vec(),
        cli["reactions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["reactions"].as_u64().unwrap())
            .collect::<Vec<_>>()
    );
    assert!(sim.reaction_counts().iter().all(|&k| k > 0));
}
