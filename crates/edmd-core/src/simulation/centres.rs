//! A stepped potential's list centres in 3D, filed by cell in the cells themselves: what the
//! x86-64-v3 loop reads to make a sphere's list again (`steps_x86::listed`).
//!
//! The grid files each sphere by its list centre (`steps.rs`), but reading the centres
//! through it means a load from `Steps::centre` at a random place for each of the some 135
//! spheres of the 27 cells around a list, which made the list-making memory-bound. Here each
//! cell holds the coordinates of its first [`SLOTS`] spheres as columns (four lanes to a
//! load, no transposing) and the ids of the rest, whose centres are read from
//! `Steps::centre`. A cell holds the same spheres as the grid's cell of the same index, in
//! any order: the list made from them is sorted. A centre moves only when its sphere's list
//! is made again, and each move is filed here as in the grid.

use crate::cells::CellGrid;
use crate::math::Vector;

/// How many spheres a cell holds with their coordinates: the cells are at least a list
/// radius wide, which holds five spheres on average in the square-well fluid of
/// BENCHMARKS.md (at packing 0.3), more than eight in fewer than one cell in ten.
pub(super) const SLOTS: usize = 8;

/// One cell's spheres: the coordinates of the first `len` of them as columns, their ids,
/// and the ids of those beyond [`SLOTS`].
#[derive(Clone, Debug, Default)]
#[repr(C, align(64))]
pub(super) struct Cell {
    pub(super) x: [f64; SLOTS],
    pub(super) y: [f64; SLOTS],
    pub(super) z: [f64; SLOTS],
    pub(super) id: [u32; SLOTS],
    pub(super) len: u32,
    pub(super) more: Vec<u32>,
}

impl Cell {
    fn put(&mut self, s: usize, j: u32, c: [f64; 3]) {
        self.x[s] = c[0];
        self.y[s] = c[1];
        self.z[s] = c[2];
        self.id[s] = j;
    }
}

/// Every cell's spheres with their list centres (empty outside 3D).
#[derive(Clone, Debug, Default)]
pub(super) struct Centres {
    pub(super) cells: Vec<Cell>,
}

/// A 3D centre's coordinates.
fn xyz<const D: usize>(c: Vector<D>) -> [f64; 3] {
    [c[0], c[1], c[2]]
}

impl Centres {
    /// Files every sphere as the grid files it, at its centre in `centre` (3D; nothing
    /// otherwise).
    pub(super) fn refile<const D: usize>(&mut self, grid: &CellGrid<D>, centre: &[Vector<D>]) {
        self.cells.clear();
        if D != 3 {
            return;
        }
        let n = grid.cell_count();
        if self.cells.capacity() < n {
            // Read at random by every list made: past the TLB's reach, huge pages.
            self.cells = Vec::with_capacity(n);
            crate::hint::huge_pages(&mut self.cells);
        }
        self.cells.resize_with(n, Cell::default);
        for (j, &c) in centre.iter().enumerate() {
            self.file(grid.index_of(grid.cell_of(j)), j as u32, c);
        }
    }

    /// Files sphere `j` in cell `k` at centre `c`.
    pub(super) fn file<const D: usize>(&mut self, k: usize, j: u32, c: Vector<D>) {
        let cell = &mut self.cells[k];
        let s = cell.len as usize;
        if s < SLOTS {
            cell.put(s, j, xyz(c));
            cell.len += 1;
        } else {
            cell.more.push(j);
        }
    }

    /// Takes sphere `j` out of cell `k`, where it must be filed (checked in debug builds);
    /// a sphere beyond the slots takes its place, its centre read from `centre`.
    pub(super) fn unfile<const D: usize>(&mut self, k: usize, j: u32, centre: &[Vector<D>]) {
        let cell = &mut self.cells[k];
        let len = cell.len as usize;
        if let Some(s) = cell.id[..len].iter().position(|&x| x == j) {
            if let Some(q) = cell.more.pop() {
                cell.put(s, q, xyz(centre[q as usize]));
            } else {
                let last = len - 1;
                let (x, y, z, id) = (cell.x[last], cell.y[last], cell.z[last], cell.id[last]);
                cell.put(s, id, [x, y, z]);
                cell.len -= 1;
            }
        } else {
            let s = cell.more.iter().position(|&x| x == j);
            debug_assert!(s.is_some(), "sphere {j} is not filed in cell {k}");
            if let Some(s) = s {
                cell.more.swap_remove(s);
            }
        }
    }

    /// Sphere `j`, filed in cell `k`, has its centre moved to `c` within the cell.
    pub(super) fn moved<const D: usize>(&mut self, k: usize, j: u32, c: Vector<D>) {
        let cell = &mut self.cells[k];
        if let Some(s) = cell.id[..cell.len as usize].iter().position(|&x| x == j) {
            cell.put(s, j, xyz(c));
        } else {
            // One beyond the slots has its centre read from `Steps::centre`.
            debug_assert!(
                cell.more.contains(&j),
                "sphere {j} is not filed in cell {k}"
            );
        }
    }

    /// Bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.cells.capacity() * size_of::<Cell>()
            + self
                .cells
                .iter()
                .map(|c| c.more.capacity() * 4)
                .sum::<usize>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// The spheres of cell `k` with their centres as filed, in order of id.
    fn held(c: &Centres, k: usize, centre: &[Vector<3>]) -> Vec<(u32, [f64; 3])> {
        let cell = &c.cells[k];
        let mut v: Vec<_> = (0..cell.len as usize)
            .map(|s| (cell.id[s], [cell.x[s], cell.y[s], cell.z[s]]))
            .chain(cell.more.iter().map(|&j| (j, xyz(centre[j as usize]))))
            .collect();
        v.sort_by_key(|e| e.0);
        v
    }

    #[test]
    fn cells_hold_what_was_filed_through_overflow_and_moves() {
        // Two cells, up to 20 spheres in one (beyond the slots), filed, moved and taken out
        // at random; after each change each cell holds exactly its spheres at their centres.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(7);
        let n = 20;
        let mut centre = vec![Vector::<3>::ZERO; n];
        let mut home: Vec<Option<usize>> = vec![None; n];
        let mut c = Centres {
            cells: vec![Cell::default(), Cell::default()],
        };
        for _ in 0..5000 {
            let j = rng.random_range(0..n);
            let p = Vector::new([rng.random(), rng.random(), rng.random()]);
            match (home[j], rng.random_range(0..3)) {
                (None, _) => {
                    let k = rng.random_range(0..2);
                    centre[j] = p;
                    c.file(k, j as u32, p);
                    home[j] = Some(k);
                }
                (Some(k), 0) => {
                    c.unfile(k, j as u32, &centre);
                    home[j] = None;
                }
                (Some(k), 1) => {
                    centre[j] = p;
                    c.moved(k, j as u32, p);
                    if !c.cells[k].more.contains(&(j as u32)) {
                        // A sphere in the slots has its coordinates there.
                        assert!(held(&c, k, &centre).contains(&(j as u32, xyz(p))));
                    }
                }
                (Some(k), _) => {
                    centre[j] = p;
                    c.unfile(k, j as u32, &centre);
                    c.file(1 - k, j as u32, p);
                    home[j] = Some(1 - k);
                }
            }
            for k in 0..2 {
                let want: Vec<_> = (0..n)
                    .filter(|&j| home[j] == Some(k))
                    .map(|j| (j as u32, xyz(centre[j])))
                    .collect();
                assert_eq!(held(&c, k, &centre), want, "cell {k}");
                assert!(c.cells[k].more.is_empty() || c.cells[k].len as usize == SLOTS);
            }
        }
    }
}
