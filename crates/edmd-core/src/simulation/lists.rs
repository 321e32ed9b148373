//! A stepped potential's neighbour lists, one row of a slab per disc.
//!
//! A disc's list is read at each of its predictions and changed where a pair comes, goes or
//! changes shell. Lists held as one allocation each cost two dependent loads to reach (the
//! list's header, then its entries), scattered over the heap in small pages. Here disc `i`'s
//! list sits at a place known from `i` alone, row `i` of one array (on huge pages when large):
//! its first entry holds the list's length, the rest its entries in order. A row is wide
//! enough for half again the lists' expected length ([`Lists::new`]); a longer list is held
//! apart ("spilled") until it fits again, and when more than one disc in [`CROWDED`] has its
//! list apart (a dense liquid beside its vapour, say), the rows are made twice as wide.

use std::collections::HashMap;

use crate::hint::Records;

/// A neighbour and the pair's shell (0 outside every step).
pub(super) type Entry = (u32, u8);

/// The length word of a row whose list is held apart.
const SPILLED: u32 = u32::MAX;

/// The rows are widened when more than one disc in this many has its list held apart.
const CROWDED: usize = 32;

/// Per disc, its neighbours in increasing order, each with the pair's shell.
#[derive(Clone, Debug)]
pub(super) struct Lists {
    /// Entries per row: the length and at most `width - 1` neighbours.
    width: usize,
    rows: Records<Entry>,
    /// The lists too long for their rows, by disc.
    spilled: HashMap<u32, Vec<Entry>>,
}

impl Lists {
    /// Empty lists for `n` discs, rows wide enough for `expected` neighbours and half again
    /// (a power of two of entries, so that rows keep to whole cache lines).
    pub(super) fn new(n: usize, expected: f64) -> Self {
        let want = (1.5 * expected).ceil().clamp(7.0, 1023.0) as usize + 1;
        let width = want.next_power_of_two();
        let mut rows = crate::hint::records(n.saturating_mul(width));
        rows.resize(n * width, (0, 0));
        Lists {
            width,
            rows,
            spilled: HashMap::new(),
        }
    }

    /// How many discs have lists.
    pub(super) fn len(&self) -> usize {
        self.rows.len() / self.width
    }

    /// Disc `i`'s list.
    #[inline(always)]
    pub(super) fn get(&self, i: usize) -> &[Entry] {
        let row = self.row(i);
        let len = row[0].0;
        if len == SPILLED {
            &self.spilled[&(i as u32)]
        } else {
            &row[1..1 + len as usize]
        }
    }

    /// The start of disc `i`'s row, for prefetching: its length and first entries.
    #[inline(always)]
    pub(super) fn row(&self, i: usize) -> &[Entry] {
        &self.rows[i * self.width..(i + 1) * self.width]
    }

    /// Every disc's list, in order of disc.
    pub(super) fn iter(&self) -> impl Iterator<Item = &[Entry]> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    /// Makes disc `i`'s list `list` (in order).
    pub(super) fn set(&mut self, i: usize, list: &[Entry]) {
        if !self.place(i, list) {
            self.widen_if_crowded();
        }
    }

    /// Writes `list` into disc `i`'s row, or holds it apart if it does not fit there (false).
    fn place(&mut self, i: usize, list: &[Entry]) -> bool {
        let w = self.width;
        let row = &mut self.rows[i * w..(i + 1) * w];
        if row[0].0 == SPILLED {
            self.spilled.remove(&(i as u32));
        }
        if list.len() < w {
            row[0].0 = list.len() as u32;
            row[1..1 + list.len()].copy_from_slice(list);
            true
        } else {
            row[0].0 = SPILLED;
            self.spilled.insert(i as u32, list.to_vec());
            false
        }
    }

    /// Makes the rows twice as wide while more than one disc in [`CROWDED`] has its list
    /// held apart.
    fn widen_if_crowded(&mut self) {
        while self.spilled.len() * CROWDED > self.len() && self.width < 1 << 20 {
            let lists: Vec<Vec<Entry>> = self.iter().map(<[Entry]>::to_vec).collect();
            let n = lists.len();
            self.width *= 2;
            self.rows = crate::hint::records(n.saturating_mul(self.width));
            self.rows.resize(n * self.width, (0, 0));
            self.spilled.clear();
            for (i, l) in lists.iter().enumerate() {
                self.place(i, l);
            }
        }
    }

    /// Empties every list.
    pub(super) fn clear(&mut self) {
        for i in 0..self.len() {
            self.rows[i * self.width].0 = 0;
        }
        self.spilled.clear();
    }

    /// Sets the shell of `j` in disc `i`'s list to `s`, listing `j` if it is not.
    pub(super) fn put(&mut self, i: usize, j: u32, s: u8) {
        self.list(i, j, s, true);
    }

    /// Lists `j` in disc `i`'s list in shell 0, if it is not listed already.
    pub(super) fn join(&mut self, i: usize, j: u32) {
        self.list(i, j, 0, false);
    }

    /// Lists `j` in disc `i`'s list in shell `s`, or (`reshell`) sets its shell there.
    fn list(&mut self, i: usize, j: u32, s: u8, reshell: bool) {
        let w = self.width;
        let row = &mut self.rows[i * w..(i + 1) * w];
        let len = row[0].0;
        if len == SPILLED {
            let list = self.spilled.get_mut(&(i as u32)).expect("a spilled list");
            match find(list, j) {
                Ok(k) if reshell => list[k].1 = s,
                Ok(_) => {}
                Err(k) => list.insert(k, (j, s)),
            }
            return;
        }
        let len = len as usize;
        match find(&row[1..1 + len], j) {
            Ok(k) if reshell => row[1 + k].1 = s,
            Ok(_) => {}
            Err(k) if len + 1 < w => {
                row.copy_within(1 + k..1 + len, 2 + k);
                row[1 + k] = (j, s);
                row[0].0 += 1;
            }
            Err(k) => {
                let mut list = row[1..1 + len].to_vec();
                list.insert(k, (j, s));
                self.set(i, &list);
            }
        }
    }

    /// Takes `j` out of disc `i`'s list, if it is there.
    pub(super) fn remove(&mut self, i: usize, j: u32) {
        let w = self.width;
        let row = &mut self.rows[i * w..(i + 1) * w];
        let len = row[0].0;
        if len == SPILLED {
            let list = self.spilled.get_mut(&(i as u32)).expect("a spilled list");
            if let Ok(k) = find(list, j) {
                list.remove(k);
                if list.len() < w {
                    let list = self.spilled.remove(&(i as u32)).expect("a spilled list");
                    self.set(i, &list);
                }
            }
            return;
        }
        let len = len as usize;
        if let Ok(k) = find(&row[1..1 + len], j) {
            row.copy_within(2 + k..1 + len, 1 + k);
            row[0].0 -= 1;
        }
    }

    /// Bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.rows.capacity() * size_of::<Entry>()
            + self
                .spilled
                .values()
                .map(|l| l.capacity() * size_of::<Entry>() + 32)
                .sum::<usize>()
    }
}

/// Where `j` is in a sorted neighbour list.
#[inline(always)]
pub(super) fn find(list: &[Entry], j: u32) -> Result<usize, usize> {
    list.binary_search_by_key(&j, |e| e.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn a_long_list_is_held_apart_until_it_fits_and_crowding_widens_the_rows() {
        let mut lists = Lists::new(64, 4.0);
        assert_eq!(lists.width, 8);
        for j in 0..10 {
            lists.put(0, 30 - j, 1);
        }
        assert_eq!(lists.spilled.len(), 1);
        let want: Vec<Entry> = (21..=30).map(|j| (j, 1)).collect();
        assert_eq!(lists.get(0), &want[..]);
        for j in 21..24 {
            lists.remove(0, j);
        }
        assert!(lists.spilled.is_empty());
        assert_eq!(lists.get(0), &want[3..]);
        // A second and a third list held apart: more than one disc in 32 of the 64.
        let long: Vec<Entry> = (0..12).map(|j| (j, 0)).collect();
        lists.set(1, &long);
        lists.set(2, &long);
        assert_eq!(lists.spilled.len(), 2);
        assert_eq!(lists.width, 8);
        lists.set(3, &long);
        assert_eq!((lists.width, lists.spilled.len()), (16, 0));
        assert_eq!(lists.get(0), &want[3..]);
        assert!((1..4).all(|i| lists.get(i) == &long[..]));
    }

    #[test]
    fn rows_and_spilled_lists_hold_what_a_sorted_vec_would() {
        // Lists of up to 40 neighbours, from rows of 8 (7 entries) widened as they crowd:
        // entries put, reshelled, removed and whole lists set at random, against plain
        // sorted vectors.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(11);
        let n = 100;
        let mut lists = Lists::new(n, 4.0);
        let mut want: Vec<Vec<Entry>> = vec![Vec::new(); n];
        for _ in 0..5000 {
            let i = rng.random_range(0..n);
            let j = rng.random_range(0..40u32);
            let s = rng.random_range(0..3u8);
            match rng.random_range(0..10) {
                0..=4 => {
                    lists.put(i, j, s);
                    match find(&want[i], j) {
                        Ok(k) => want[i][k].1 = s,
                        Err(k) => want[i].insert(k, (j, s)),
                    }
                }
                5 => {
                    lists.join(i, j);
                    if let Err(k) = find(&want[i], j) {
                        want[i].insert(k, (j, 0));
                    }
                }
                6..=8 => {
                    lists.remove(i, j);
                    if let Ok(k) = find(&want[i], j) {
                        want[i].remove(k);
                    }
                }
                _ => {
                    let mut l = Vec::new();
                    for j in 0..40u32 {
                        if rng.random_bool(0.2) {
                            l.push((j, rng.random_range(0..3u8)));
                        }
                    }
                    lists.set(i, &l);
                    want[i] = l;
                }
            }
            assert_eq!(lists.get(i), &want[i][..], "disc {i}");
        }
        assert!(lists.width > 8);
        assert!(lists.iter().eq(want.iter().map(|w| &w[..])));
        lists.clear();
        assert!(lists.iter().all(|l| l.is_empty()));
    }
}
