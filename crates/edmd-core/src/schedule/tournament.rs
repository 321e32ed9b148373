//! A complete binary tournament tree (as in DynamO's CBT sorter): leaves are discs, each inner
//! node holds the winner (earliest time, and that time) of its two children. Changing one
//! disc's time replays the matches on its path to the root, reading only the siblings on the
//! path (the keys live in the nodes, so there is no random access to a separate key array), and
//! stops as soon as a match's result is unchanged. The minimum is read from the root in O(1).

use super::EventQueue;

#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    time: f64,
    disc: u32,
}

/// Tournament tree over per-disc event times.
#[derive(Clone, Debug)]
pub struct TournamentQueue {
    n: usize,
    /// Number of leaves, a power of two `>= max(n, 2)`.
    m: usize,
    /// `nodes[1]` is the root, `nodes[m + i]` the leaf of disc `i`; padding leaves hold `+inf`.
    nodes: Vec<Node>,
}

impl TournamentQueue {
    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<Node>()
    }
}

impl EventQueue for TournamentQueue {
    fn with_len(n: usize) -> Self {
        let m = n.max(2).next_power_of_two();
        let mut nodes = vec![
            Node {
                time: f64::INFINITY,
                disc: 0
            };
            2 * m
        ];
        for i in 0..m {
            nodes[m + i].disc = i as u32;
        }
        // All times equal: the left child (lower indices) wins everywhere.
        for k in (1..m).rev() {
            nodes[k] = nodes[2 * k];
        }
        TournamentQueue { n, m, nodes }
    }

    #[inline]
    fn set(&mut self, i: usize, t: f64) {
        debug_assert!(!t.is_nan());
        let mut k = self.m + i;
        self.nodes[k].time = t;
        while k > 1 {
            let parent = k >> 1;
            let (l, r) = (self.nodes[k & !1], self.nodes[k | 1]);
            // Strict `<`: on equal times the left child, whose subtree holds lower indices, wins.
            let w = if r.time < l.time { r } else { l };
            if self.nodes[parent] == w {
                // Unchanged result: every match above is unchanged too.
                break;
            }
            self.nodes[parent] = w;
            k = parent;
        }
    }

    #[inline]
    fn min(&mut self) -> Option<(usize, f64)> {
        if self.n == 0 {
            return None;
        }
        let w = self.nodes[1];
        Some((w.disc as usize, w.time))
    }

    #[inline]
    fn get(&self, i: usize) -> f64 {
        self.nodes[self.m + i].time
    }
}
