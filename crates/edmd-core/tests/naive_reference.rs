//! The engine (cells, tournament queue, local clocks, lazy invalidation) against the naive
//! O(N^2)-per-event simulator: the same collisions, in the same order, at the same times.
//! Rounding differs between the two, and hard-disc dynamics amplify differences by roughly
//! the ratio of free path to diameter per collision, so the comparison covers the stretch
//! before that growth reaches the tolerance.

use crate::support::obs;
use edmd_core::{EventKind, EventRecord, Observer, Options, SimBox, Simulation};

use crate::support::{naive, random_discs};

#[derive(Default)]
struct Log(Vec<(f64, usize, Option<usize>)>);

impl Observer for Log {
    fn on_event(&mut self, e: &EventRecord, _: &Simulation) {
        match e.kind {
            EventKind::DiscDisc { i, j } => self.0.push((e.time, i.min(j), Some(i.max(j)))),
            EventKind::Wall { i, .. } => self.0.push((e.time, i, None)),
            _ => {}
        }
    }
}

#[test]
fn same_events_as_the_brute_force_simulator() {
    for seed in 0..6 {
        let l = 10.0;
        let discs = random_discs(40, l, 0.2, 0.5, true, seed);
        let mut sim = Simulation::new(&discs, SimBox::walls([l, l]), Options::default()).unwrap();
        let mut log = Log::default();
        let mut reference = discs.clone();
        let expected = naive::run(&mut reference, l, 5.0);
        sim.run_until(5.0, &mut obs(&mut log));
        assert!(
            expected.len() > 80,
            "seed {seed}: too few events ({}) to compare",
            expected.len()
        );
        assert_eq!(
            log.0.len(),
            expected.len(),
            "seed {seed}: event counts differ"
        );
        for (k, (a, b)) in log.0.iter().zip(&expected).enumerate() {
            assert_eq!(
                (a.1, a.2),
                (b.1, b.2),
                "seed {seed}: event {k} differs: {a:?} vs {b:?}"
            );
            assert!(
                (a.0 - b.0).abs() < 1e-9,
                "seed {seed}: event {k} time {a:?} vs {b:?}"
            );
        }
    }
}
