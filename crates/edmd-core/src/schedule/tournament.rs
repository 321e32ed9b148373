//! A complete binary tournament tree (as in DynamO's CBT sorter): leaves are discs, each inner
//! node holds the winner (earliest time) of its two children. Changing one disc's time replays
//! the matches on its path to the root: `log2 N` comparisons, no allocation, and the minimum is
//! read from the root in O(1).

use super::EventQueue;

/// Tournament tree over per-disc event times.
#[derive(Clone, Debug)]
pub struct TournamentQueue {
    n: usize,
    /// Number of leaves, a power of two `>= max(n, 2)`.
    m: usize,
    /// Times, padded with `+inf` up to `m`.
    keys: Vec<f64>,
    /// `winners[k]` for inner node `k` in `1..m` (index 0 unused).
    winners: Vec<u32>,
}

impl TournamentQueue {
    #[inline(always)]
    fn player(&self, node: usize) -> u32 {
        if node >= self.m {
            (node - self.m) as u32
        } else {
            self.winners[node]
        }
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.keys.capacity() * 8 + self.winners.capacity() * 4
    }
}

impl EventQueue for TournamentQueue {
    fn with_len(n: usize) -> Self {
        let m = n.max(2).next_power_of_two();
        let mut q = TournamentQueue { n, m, keys: vec![f64::INFINITY; m], winners: vec![0; m] };
        // Initial matches: all times equal, so the left (lower-index) player wins everywhere.
        for node in (1..m).rev() {
            q.winners[node] = q.player(2 * node);
        }
        q
    }

    #[inline]
    fn set(&mut self, i: usize, t: f64) {
        debug_assert!(!t.is_nan());
        self.keys[i] = t;
        let mut node = (self.m + i) >> 1;
        while node >= 1 {
            let l = self.player(2 * node);
            let r = self.player(2 * node + 1);
            // Strict `<`: on equal times the left player, whose subtree holds lower indices, wins.
            self.winners[node] = if self.keys[r as usize] < self.keys[l as usize] { r } else { l };
            node >>= 1;
        }
    }

    #[inline]
    fn min(&self) -> Option<(usize, f64)> {
        if self.n == 0 {
            return None;
        }
        let w = self.winners[1] as usize;
        Some((w, self.keys[w]))
    }

    #[inline]
    fn get(&self, i: usize) -> f64 {
        self.keys[i]
    }
}
