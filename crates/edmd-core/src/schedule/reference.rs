//! The naive reference queue: a linear scan. Slow and obviously right; the tournament tree and
//! the calendar queue are checked against it by property tests.

use super::EventQueue;

/// Linear-scan queue.
#[derive(Clone, Debug, Default)]
pub struct ReferenceQueue {
    keys: Vec<f64>,
}

impl EventQueue for ReferenceQueue {
    fn with_len(n: usize) -> Self {
        ReferenceQueue {
            keys: vec![f64::INFINITY; n],
        }
    }

    fn set(&mut self, i: usize, t: f64) {
        self.keys[i] = t;
    }

    fn min(&mut self) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for (i, &t) in self.keys.iter().enumerate() {
            if best.is_none_or(|(_, bt)| t < bt) {
                best = Some((i, t));
            }
        }
        best
    }

    fn get(&self, i: usize) -> f64 {
        self.keys[i]
    }
}

#[cfg(test)]
mod tests {
    use super::super::{CalendarQueue, TournamentQueue};
    use super::*;
    use proptest::prelude::*;

    fn op() -> impl Strategy<Value = (usize, f64)> {
        // Times from a small set so that ties are common; inf included.
        (
            0usize..64,
            prop_oneof![(0u8..8).prop_map(|k| k as f64 * 0.5), Just(f64::INFINITY)],
        )
    }

    /// Runs `ops` on `a` and the reference, comparing the minimum after each (its disc only
    /// when its time is finite: with every time `+inf` the disc is unspecified).
    fn matches_reference<Q: EventQueue>(
        mut a: Q,
        n: usize,
        ops: &[(usize, f64)],
    ) -> Result<(), TestCaseError> {
        let mut b = ReferenceQueue::with_len(n);
        let same = |x: Option<(usize, f64)>, y: Option<(usize, f64)>| match (x, y) {
            (Some((_, tx)), Some((_, ty))) if tx == f64::INFINITY => tx == ty,
            _ => x == y,
        };
        prop_assert!(same(a.min(), b.min()));
        for &(i, t) in ops {
            let i = i % n;
            a.set(i, t);
            b.set(i, t);
            let (x, y) = (a.min(), b.min());
            prop_assert!(same(x, y), "{:?} vs {:?}", x, y);
            prop_assert_eq!(a.get(i), b.get(i));
        }
        Ok(())
    }

    /// As the engine uses a queue: the front disc's time moves on to a time no earlier than
    /// it, and so do other discs' times.
    fn engine_like(
        mut a: CalendarQueue,
        n: usize,
        steps: &[(bool, usize, f64)],
    ) -> Result<(), TestCaseError> {
        let mut b = ReferenceQueue::with_len(n);
        a.begin_bulk();
        for i in 0..n {
            let t = (i % 5) as f64 * 0.25;
            a.set(i, t);
            b.set(i, t);
        }
        a.end_bulk(0.0);
        for &(front, i, dt) in steps {
            let (x, y) = (a.min(), b.min());
            prop_assert_eq!(x, y);
            let (m, now) = x.unwrap();
            if now == f64::INFINITY {
                break;
            }
            let i = if front { m } else { i % n };
            a.set(i, now + dt);
            b.set(i, now + dt);
        }
        Ok(())
    }

    proptest! {
        #[test]
        fn tournament_matches_reference(n in 1usize..40, ops in proptest::collection::vec(op(), 0..300)) {
            matches_reference(TournamentQueue::with_len(n), n, &ops)?;
        }

        #[test]
        fn calendar_matches_reference(n in 1usize..40, ops in proptest::collection::vec(op(), 0..300)) {
            matches_reference(CalendarQueue::with_len(n), n, &ops)?;
        }

        #[test]
        fn calendar_matches_reference_in_engine_use(
            n in 1usize..200,
            steps in proptest::collection::vec(
                (any::<bool>(), 0usize..200, prop_oneof![
                    4 => (0u32..40).prop_map(|k| k as f64 * 0.125),
                    1 => (0u32..1000).prop_map(|k| k as f64 * 37.0),
                    1 => Just(f64::INFINITY),
                ]),
                0..2000,
            ),
        ) {
            engine_like(CalendarQueue::with_len(n), n, &steps)?;
        }
    }

    #[test]
    fn empty_queue_has_no_min() {
        assert_eq!(TournamentQueue::with_len(0).min(), None);
        assert_eq!(CalendarQueue::with_len(0).min(), None);
        assert_eq!(ReferenceQueue::with_len(0).min(), None);
    }
}
