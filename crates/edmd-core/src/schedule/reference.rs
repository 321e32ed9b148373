//! The naive reference queue: a linear scan. Slow and obviously right; the tournament tree is
//! checked against it by property tests.

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

    fn min(&self) -> Option<(usize, f64)> {
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
    use super::super::TournamentQueue;
    use super::*;
    use proptest::prelude::*;

    fn op() -> impl Strategy<Value = (usize, f64)> {
        // Times from a small set so that ties are common; inf included.
        (
            0usize..64,
            prop_oneof![(0u8..8).prop_map(|k| k as f64 * 0.5), Just(f64::INFINITY)],
        )
    }

    proptest! {
        #[test]
        fn tournament_matches_reference(n in 1usize..40, ops in proptest::collection::vec(op(), 0..300)) {
            let mut a = TournamentQueue::with_len(n);
            let mut b = ReferenceQueue::with_len(n);
            prop_assert_eq!(a.min(), b.min());
            for (i, t) in ops {
                let i = i % n;
                a.set(i, t);
                b.set(i, t);
                prop_assert_eq!(a.min(), b.min());
                prop_assert_eq!(a.get(i), b.get(i));
            }
        }
    }

    #[test]
    fn empty_queue_has_no_min() {
        assert_eq!(TournamentQueue::with_len(0).min(), None);
        assert_eq!(ReferenceQueue::with_len(0).min(), None);
    }
}
