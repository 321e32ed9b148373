//! A uniform grid of cells no narrower than the largest disc diameter, with one intrusive
//! singly linked list of discs per cell.
//!
//! Two discs more than one cell apart along any axis cannot touch, so a disc's collision
//! partners before its next cell crossing are all in the `3^D` cells around its own. Cell
//! crossings are events of their own (see [`crate::predict::interval`]). On a periodic axis the
//! neighbour cells wrap around, carrying the image shift `±L` with them; at least 3 cells are
//! required there so that the wrapped neighbours are distinct.

use crate::error::Error;
use crate::hint::filled;
use crate::math::{select, Vector};
use crate::predict::{interval_exit_accel_or_inf, interval_exit_or_inf, Side};
use crate::state::SimBox;

/// "No disc": the end of a cell's list.
pub const NONE: u32 = u32::MAX;

/// Cell coordinates of one cell.
pub type CellCoord<const D: usize = 2> = [u32; D];

/// Bits that hold a coordinate below `d`.
fn bits(d: u64) -> u32 {
    64 - (d.max(1) - 1).leading_zeros()
}

/// Bits that hold a cell's coordinates on every axis, side by side (see [`Coder`]).
fn code_bits(counts: &[u64]) -> u32 {
    counts.iter().map(|&d| bits(d)).sum()
}

/// A cell's coordinates side by side in 32 bits, axis `a` from bit `shift[a]`: 4 bytes a disc
/// for the cell it is in rather than `4 D`, read back with a shift and a mask (BENCHMARKS.md,
/// "Memory at scale").
#[derive(Clone, Copy, Debug)]
struct Coder<const D: usize> {
    shift: [u32; D],
    mask: [u32; D],
}

impl<const D: usize> Coder<D> {
    /// The coder for a grid of `counts` cells, if their coordinates fit in 32 bits.
    fn new(counts: [u64; D]) -> Option<Self> {
        if code_bits(&counts) > 32 {
            return None;
        }
        let (mut shift, mut mask) = ([0u32; D], [0u32; D]);
        let mut at = 0;
        for a in 0..D {
            shift[a] = at;
            mask[a] = ((1u64 << bits(counts[a])) - 1) as u32;
            at += bits(counts[a]);
        }
        Some(Coder { shift, mask })
    }

    #[inline(always)]
    fn encode(&self, c: CellCoord<D>) -> u32 {
        // Coordinates are below their axis's count, so they fit their bits; an axis of one
        // cell (shift possibly 32, taken as 0 by the wrapping shift) only ever has 0.
        let mut k = 0;
        for a in 0..D {
            k |= c[a].wrapping_shl(self.shift[a]);
        }
        k
    }

    #[inline(always)]
    fn decode(&self, k: u32) -> CellCoord<D> {
        // An axis of one cell has no bits: its mask is 0, and its shift may be 32, which the
        // wrapping shifts take as 0.
        std::array::from_fn(|a| k.wrapping_shr(self.shift[a]) & self.mask[a])
    }
}

/// The grid and the discs' places in it.
#[derive(Clone, Debug)]
pub struct CellGrid<const D: usize = 2> {
    dims: [u32; D],
    width: [f64; D],
    lengths: [f64; D],
    periodic: [bool; D],
    stride: [usize; D],
    /// The `3^D` neighbour offsets (the first [`Self::NEIGHBOURS`] of the array).
    offsets: [[i32; D]; MAX_NEIGHBOURS],
    /// The offsets as linear cell-index differences (valid away from the grid's edges). A
    /// fixed-size array scanned over a constant count, so that the scan is unrolled: a loop of
    /// 9 is a branch the predictor misses once a scan.
    linear_offsets: [isize; MAX_NEIGHBOURS],
    head: Vec<u32>,
    /// The next disc in the same cell. Singly linked: a cell holds about one disc (3D) or
    /// less (2D), so taking a disc out walks at most a step or two, and a back link would
    /// cost 4 bytes per disc (issue 9's memory budget, BENCHMARKS.md).
    next: Vec<u32>,
    /// 3D only (empty in 2D): each cell's first four discs, in the order of its list, `NONE`
    /// past its end, so that the x86-64-v3 scan reads a cell with one load and no branch
    /// (`simulation/scan_x86.rs`); the list goes on from the fourth's `next`.
    first: Vec<[u32; 4]>,
    /// Each disc's cell, coded by `coder` ([`Self::cell_counts`] keeps a grid within 32 bits).
    code: Vec<u32>,
    coder: Coder<D>,
}

impl<const D: usize> CellGrid<D> {
    /// Number of cells around a cell, itself included: `3^D`.
    pub const NEIGHBOURS: usize = neighbours(D);

    /// A grid for `n` discs whose largest diameter is `max_diameter`.
    ///
    /// Cells are at least `max_diameter` wide on every axis; in a sparse system they are made
    /// wider, so that there are about two cells per disc and memory stays O(N) whatever the
    /// box's shape: at most [`Self::max_cells`] cells in all (see [`Self::cell_counts`]).
    pub fn new(sim_box: &SimBox<D>, n: usize, max_diameter: f64) -> Result<Self, Error> {
        let counts = Self::cell_counts(sim_box, n, max_diameter)?;
        Self::with_counts(sim_box, n, counts)
    }

    /// A grid for `n` discs with `counts` cells along each axis (each at least 1, and at most
    /// [`Self::max_cells`] in all).
    pub fn with_counts(sim_box: &SimBox<D>, n: usize, counts: [u64; D]) -> Result<Self, Error> {
        if counts.iter().any(|&c| c == 0 || c > u32::MAX as u64 / 4)
            || counts.iter().fold(1u64, |t, &c| t.saturating_mul(c)) > Self::max_cells(n) as u64
            || Coder::new(counts).is_none()
        {
            return Err(Error::Invalid(format!("too many cells ({counts:?})")));
        }
        let mut dims = [1u32; D];
        let mut width = [0.0; D];
        let mut periodic = [false; D];
        let mut stride = [0usize; D];
        let mut total = 1usize;
        for a in 0..D {
            let d = counts[a];
            periodic[a] = sim_box.is_periodic(a);
            dims[a] = d as u32;
            width[a] = sim_box.lengths[a] / d as f64;
            stride[a] = total;
            total = total
                .checked_mul(d as usize)
                .ok_or_else(|| Error::Invalid("too many cells".into()))?;
        }
        let coder = Coder::new(counts).expect("checked above");
        let offsets = neighbour_offsets::<D>();
        let linear_offsets =
            offsets.map(|o| (0..D).map(|a| o[a] as isize * stride[a] as isize).sum());
        Ok(CellGrid {
            dims,
            width,
            lengths: sim_box.lengths,
            periodic,
            stride,
            offsets,
            linear_offsets,
            head: filled(NONE, total),
            next: filled(NONE, n),
            first: filled([NONE; 4], if D == 3 { total } else { 0 }),
            code: filled(0, n),
            coder,
        })
    }

    /// The most cells a grid for `n` discs has: `4 n + 3^D`.
    pub fn max_cells(n: usize) -> usize {
        4usize.saturating_mul(n.max(1)) + Self::NEIGHBOURS
    }

    /// Cells per axis for `n` discs whose largest diameter is `max_diameter`.
    ///
    /// First as the grid has always been sized: one cell width for every axis, the larger of
    /// `max_diameter` and the width that gives two cells per disc over the whole box, each axis
    /// then getting at least one cell (three on a periodic axis). For a box of ordinary shape
    /// that makes at most about `2 N` cells and is kept as it is, so that trajectories do not
    /// change. In a box much longer on one axis than on the others (`1 x 10^18`) the short axes
    /// are rounded up to their one (or three) cells while the long one still gets its share of
    /// the whole volume, which made `10^9` cells of 4 bytes each for two discs. So when that
    /// count exceeds [`Self::max_cells`], the counts are shared out per axis instead: an axis
    /// too short for its minimum count at the common width is given that minimum, the cell
    /// budget `2 N` is divided by it, and the width is worked out again over the remaining
    /// axes, until every remaining axis takes at least its minimum. Then the product of the
    /// counts is at most `2 N` (or `3^D`, all axes at their minimum), and every cell is still
    /// at least `max_diameter` wide.
    ///
    /// Last, if a cell's coordinates would not fit in 32 bits side by side (only beyond some
    /// `5 10^8` spheres, or `2 10^9` discs), the axis with the most cells is given half as many
    /// until they do: wider cells, never narrower.
    pub fn cell_counts(
        sim_box: &SimBox<D>,
        n: usize,
        max_diameter: f64,
    ) -> Result<[u64; D], Error> {
        let mut counts = Self::cell_counts_in_any_bits(sim_box, n, max_diameter)?;
        while code_bits(&counts) > 32 {
            let a = (0..D).max_by_key(|&a| counts[a]).expect("D >= 1");
            let fewest = if sim_box.is_periodic(a) { 3 } else { 1 };
            counts[a] = (counts[a] / 2).max(fewest);
        }
        Ok(counts)
    }

    fn cell_counts_in_any_bits(
        sim_box: &SimBox<D>,
        n: usize,
        max_diameter: f64,
    ) -> Result<[u64; D], Error> {
        let most = u32::MAX as u64 / 4;
        let mut fewest = [1u64; D];
        let mut widest = [1u64; D];
        for a in 0..D {
            let l = sim_box.lengths[a];
            widest[a] = ((l / max_diameter).floor() as u64).clamp(1, most);
            if sim_box.is_periodic(a) {
                if widest[a] < 3 {
                    return Err(Error::PeriodicBoxTooSmall {
                        axis: a,
                        length: l,
                        min: 3.0 * max_diameter,
                    });
                }
                fewest[a] = 3;
            }
        }
        let cells = 2.0 * n.max(1) as f64;
        let sized = |target: f64, a: usize| {
            ((sim_box.lengths[a] / target).floor() as u64)
                .clamp(1, widest[a])
                .max(fewest[a])
        };
        let sparse_width = (sim_box.volume() / cells).powf(1.0 / D as f64);
        let target = max_diameter.max(sparse_width);
        let counts: [u64; D] = std::array::from_fn(|a| sized(target, a));
        let total = counts.iter().fold(1u64, |t, &d| t.saturating_mul(d));
        if total <= Self::max_cells(n) as u64 {
            return Ok(counts);
        }
        let mut fixed = [false; D];
        loop {
            let (mut budget, mut volume, mut free) = (cells, 1.0, 0);
            for a in 0..D {
                if fixed[a] {
                    budget /= fewest[a] as f64;
                } else {
                    volume *= sim_box.lengths[a];
                    free += 1;
                }
            }
            if free == 0 {
                return Ok(fewest);
            }
            let target = max_diameter.max((volume / budget).powf(1.0 / free as f64));
            let mut more = false;
            for a in 0..D {
                if !fixed[a] && sim_box.lengths[a] / target < fewest[a] as f64 {
                    fixed[a] = true;
                    more = true;
                }
            }
            if !more {
                return Ok(std::array::from_fn(|a| {
                    if fixed[a] {
                        fewest[a]
                    } else {
                        sized(target, a)
                    }
                }));
            }
        }
    }

    /// Number of cells per axis.
    pub fn dims(&self) -> [u32; D] {
        self.dims
    }

    /// Cell coordinates of a position (clamped into the grid).
    pub fn coord_of(&self, p: Vector<D>) -> CellCoord<D> {
        let mut c = [0u32; D];
        for a in 0..D {
            let k = (p[a] / self.width[a]).floor();
            c[a] = if k < 0.0 {
                0
            } else {
                (k as u64).min(self.dims[a] as u64 - 1) as u32
            };
        }
        c
    }

    #[inline(always)]
    fn linear(&self, c: CellCoord<D>) -> usize {
        let mut k = 0;
        for a in 0..D {
            k += c[a] as usize * self.stride[a];
        }
        k
    }

    /// The index of cell `c` among [`Self::cell_count`] (as [`Self::for_each_cell_near`]
    /// gives them).
    #[inline(always)]
    pub(crate) fn index_of(&self, c: CellCoord<D>) -> usize {
        self.linear(c)
    }

    /// How many cells the grid has.
    pub(crate) fn cell_count(&self) -> usize {
        self.head.len()
    }

    /// The cell disc `i` is filed in.
    #[inline(always)]
    pub fn cell_of(&self, i: usize) -> CellCoord<D> {
        self.coder.decode(self.code[i])
    }

    /// Prefetches the entry that says which cell disc `i` is in.
    #[inline(always)]
    pub(crate) fn prefetch_cell_of(&self, i: usize) {
        crate::hint::prefetch(&self.code[i]);
    }

    /// Prefetches the list heads of the cells around disc `i`'s (away from the grid's edges;
    /// a hint only).
    #[inline(always)]
    pub(crate) fn prefetch_heads_around(&self, i: usize) {
        let c = self.cell_of(i);
        if self.interior(c) {
            let base = self.linear(c) as isize;
            for &off in &self.linear_offsets[..Self::NEIGHBOURS] {
                let k = (base + off) as usize;
                // In 3D the scan reads the cells' first discs, not the heads.
                if D == 3 {
                    crate::hint::prefetch(&self.first[k]);
                } else {
                    crate::hint::prefetch(&self.head[k]);
                }
            }
        }
    }

    /// Calls `f` with the first disc of each cell around disc `i`'s (away from the grid's
    /// edges), for prefetching; with `NONE` for an empty cell (no branch: whether a cell is
    /// empty is a coin toss).
    #[inline(always)]
    pub(crate) fn prefetch_first_around(&self, i: usize, mut f: impl FnMut(u32)) {
        let c = self.cell_of(i);
        if self.interior(c) {
            let base = self.linear(c) as isize;
            for &off in &self.linear_offsets[..Self::NEIGHBOURS] {
                let k = (base + off) as usize;
                f(if D == 3 {
                    self.first[k][0]
                } else {
                    self.head[k]
                });
            }
        }
    }

    /// Files disc `i` in cell `c`.
    pub fn insert(&mut self, i: usize, c: CellCoord<D>) {
        let k = self.linear(c);
        self.next[i] = self.head[k];
        self.head[k] = i as u32;
        self.code[i] = self.coder.encode(c);
        self.refresh_first(k);
    }

    /// Copies the first four discs of cell `k`'s list into [`Self::first`] (3D).
    #[inline]
    fn refresh_first(&mut self, k: usize) {
        if D == 3 {
            let mut j = self.head[k];
            let mut first = [NONE; 4];
            for slot in &mut first {
                if j == NONE {
                    break;
                }
                *slot = j;
                j = self.next[j as usize];
            }
            self.first[k] = first;
        }
    }

    /// Takes disc `i` out of its cell.
    pub fn remove(&mut self, i: usize) {
        let k = self.linear(self.cell_of(i));
        let n = self.next[i];
        let mut p = self.head[k];
        if p == i as u32 {
            self.head[k] = n;
        } else {
            while self.next[p as usize] != i as u32 {
                p = self.next[p as usize];
            }
            self.next[p as usize] = n;
        }
        self.refresh_first(k);
    }

    /// Empties every cell.
    pub fn clear(&mut self) {
        self.head.fill(NONE);
        self.first.fill([NONE; 4]);
    }

    /// Time until disc `i` (at `p`, moving at `v`) leaves its cell, with the axis and side
    /// (`true` for the high side); `+inf` if it never does. On ties the lower axis wins.
    ///
    /// On a walled axis the outermost cells have no outer crossing: the wall comes first.
    /// Computed without branches on the direction of motion (BENCHMARKS.md).
    #[inline(always)]
    pub fn exit_time(&self, i: usize, p: Vector<D>, v: Vector<D>) -> (f64, usize, bool) {
        let c = self.cell_of(i);
        let (mut best, mut axis, mut high) = (f64::INFINITY, 0usize, false);
        for a in 0..D {
            let walled = !self.periodic[a];
            // Selected by bit masks, not branches: which cell a disc is in is not predictable.
            let first = c[a] == 0;
            let last = c[a] + 1 >= self.dims[a];
            let lo = select(
                first & walled,
                f64::NEG_INFINITY,
                c[a] as f64 * self.width[a],
            );
            let edge = select(walled, f64::INFINITY, self.lengths[a]);
            let hi = select(last, edge, (c[a] + 1) as f64 * self.width[a]);
            let (dt, h) = interval_exit_or_inf(p[a], v[a], lo, hi);
            let earlier = dt < best;
            axis = if earlier { a } else { axis };
            high = (earlier & h) | (!earlier & high);
            best = best.min(dt);
        }
        (best, axis, high)
    }

    /// [`Self::exit_time`] for a disc accelerated at `g` along `axis` (a field): along that
    /// axis its coordinate follows a parabola ([`interval_exit_accel_or_inf`]). Without
    /// branches on the direction of motion, as [`Self::exit_time`].
    #[inline(always)]
    pub fn exit_time_accel(
        &self,
        i: usize,
        p: Vector<D>,
        v: Vector<D>,
        axis: usize,
        g: f64,
    ) -> (f64, usize, bool) {
        let c = self.cell_of(i);
        let (mut best, mut best_axis, mut high) = (f64::INFINITY, 0usize, false);
        for a in 0..D {
            let walled = !self.periodic[a];
            let first = c[a] == 0;
            let last = c[a] + 1 >= self.dims[a];
            let lo = select(
                first & walled,
                f64::NEG_INFINITY,
                c[a] as f64 * self.width[a],
            );
            let edge = select(walled, f64::INFINITY, self.lengths[a]);
            let hi = select(last, edge, (c[a] + 1) as f64 * self.width[a]);
            let ga = select(a == axis, g, 0.0);
            let (dt, h) = interval_exit_accel_or_inf(p[a], v[a], ga, lo, hi);
            let earlier = dt < best;
            best_axis = if earlier { a } else { best_axis };
            high = (earlier & h) | (!earlier & high);
            best = best.min(dt);
        }
        (best, best_axis, high)
    }

    /// Whether `p` is in disc `i`'s cell, give or take `slack` on each axis: the cell as
    /// [`Self::exit_time`] bounds it (an end cell of a walled axis reaches out to the wall; the two must stay in step).
    /// For checking checkpoints: a disc filed in a cell it is not in is missed by the scans
    /// of its neighbours.
    pub(crate) fn holds(&self, i: usize, p: Vector<D>, slack: f64) -> bool {
        let c = self.cell_of(i);
        (0..D).all(|a| {
            let walled = !self.periodic[a];
            let last = c[a] + 1 >= self.dims[a];
            let lo = if c[a] == 0 {
                if walled {
                    f64::NEG_INFINITY
                } else {
                    0.0
                }
            } else {
                c[a] as f64 * self.width[a]
            };
            let hi = match (last, walled) {
                (true, true) => f64::INFINITY,
                (true, false) => self.lengths[a],
                _ => (c[a] + 1) as f64 * self.width[a],
            };
            p[a] >= lo - slack && p[a] <= hi + slack
        })
    }

    /// Moves disc `i` one cell along `axis` towards `side`. Returns the image shift (`-1`, `0` or
    /// `+1` box lengths) that a periodic wrap applies to the disc's coordinate on that axis.
    pub fn cross(&mut self, i: usize, axis: usize, side: Side) -> i32 {
        let mut c = self.cell_of(i);
        let d = self.dims[axis];
        let mut wrap = 0;
        match side {
            Side::High => {
                if c[axis] + 1 == d {
                    c[axis] = 0;
                    wrap = -1;
                } else {
                    c[axis] += 1;
                }
            }
            Side::Low => {
                if c[axis] == 0 {
                    c[axis] = d - 1;
                    wrap = 1;
                } else {
                    c[axis] -= 1;
                }
            }
        }
        self.remove(i);
        self.insert(i, c);
        wrap
    }

    /// Calls `f(j, shift)` for every disc `j` in the cells around `c` (including `c` itself),
    /// where `shift` is the periodic image offset to add to `j`'s position.
    #[inline(always)]
    pub fn for_each_near(&self, c: CellCoord<D>, f: impl FnMut(usize, Vector<D>)) {
        self.visit_near(c, f)
    }

    /// [`Self::for_each_near`] with a [`Visit`].
    #[inline(always)]
    pub fn visit_near(&self, c: CellCoord<D>, mut f: impl Visit<D>) {
        if self.interior(c) {
            // Away from the edges: no wrapping, no shift, plain index arithmetic.
            let base = self.linear(c) as isize;
            for &off in &self.linear_offsets[..Self::NEIGHBOURS] {
                let mut j = self.head[(base + off) as usize];
                while j != NONE {
                    f.visit(j as usize, Vector::ZERO);
                    j = self.next[j as usize];
                }
            }
            return;
        }
        'cells: for off in &self.offsets[..Self::NEIGHBOURS] {
            let mut k = 0usize;
            let mut shift = Vector::ZERO;
            for a in 0..D {
                let d = self.dims[a] as i64;
                let mut x = c[a] as i64 + off[a] as i64;
                if x < 0 || x >= d {
                    if !self.periodic[a] {
                        continue 'cells;
                    }
                    if x < 0 {
                        x += d;
                        shift[a] = -self.lengths[a];
                    } else {
                        x -= d;
                        shift[a] = self.lengths[a];
                    }
                }
                k += x as usize * self.stride[a];
            }
            let mut j = self.head[k];
            while j != NONE {
                f.visit(j as usize, shift);
                j = self.next[j as usize];
            }
        }
    }

    /// [`Self::for_each_near`], with the neighbour cells near the grid's edges and their image
    /// shifts worked out once per axis (three choices each) rather than once per cell and
    /// axis. In 3D a third of the cells of a 16^3 grid (N = 4000) touch an edge. The same discs
    /// are visited in the same order.
    #[inline(always)]
    pub fn for_each_near_edges_once(&self, c: CellCoord<D>, f: impl FnMut(usize, Vector<D>)) {
        self.visit_near_edges_once(c, f)
    }

    /// [`Self::for_each_near_edges_once`] with a [`Visit`].
    #[inline(always)]
    pub fn visit_near_edges_once(&self, c: CellCoord<D>, mut f: impl Visit<D>) {
        self.for_each_cell_near(
            c,
            #[inline(always)]
            |k, shift| {
                let mut j = self.head[k];
                while j != NONE {
                    f.visit(j as usize, shift);
                    j = self.next[j as usize];
                }
            },
        );
    }

    /// Whether the cells around `c` are all within the grid, with no image shift.
    #[inline(always)]
    pub(crate) fn interior(&self, c: CellCoord<D>) -> bool {
        (0..D).all(|a| c[a] >= 1 && c[a] + 2 <= self.dims[a])
    }

    /// Calls `f(k, shift)` for each cell `k` around `c` (itself included), in the order of
    /// [`Self::for_each_near`], `shift` being the periodic image offset of its discs. Away
    /// from the grid's edges the shift is `-0.0` (`x + -0.0` is `x` for every `x`, so the
    /// compiler drops the addition, where `x + 0.0` turns `-0.0` into `0.0` and must be kept);
    /// near them the neighbour cells are worked out once per axis (a third of the cells at
    /// N = 4000 touch an edge; BENCHMARKS.md).
    #[inline(always)]
    pub(crate) fn for_each_cell_near(&self, c: CellCoord<D>, mut f: impl FnMut(usize, Vector<D>)) {
        if self.interior(c) {
            let base = self.linear(c) as isize;
            for &off in &self.linear_offsets[..Self::NEIGHBOURS] {
                f((base + off) as usize, Vector::new([-0.0; D]));
            }
            return;
        }
        // Per axis and offset -1, 0, +1: the index term, the shift, and whether that cell
        // exists (not beyond a wall).
        let mut term = [[0usize; 3]; D];
        let mut shift_of = [[0.0f64; 3]; D];
        let mut exists = [[true; 3]; D];
        for a in 0..D {
            let d = self.dims[a] as i64;
            for m in 0..3 {
                let mut x = c[a] as i64 + m as i64 - 1;
                if x < 0 || x >= d {
                    exists[a][m] = self.periodic[a];
                    shift_of[a][m] = if x < 0 {
                        -self.lengths[a]
                    } else {
                        self.lengths[a]
                    };
                    // One cell past either end: a division (`rem_euclid`) cost more.
                    x = if x < 0 { x + d } else { x - d };
                }
                term[a][m] = x as usize * self.stride[a];
            }
        }
        'cells: for off in &self.offsets[..Self::NEIGHBOURS] {
            let mut k = 0usize;
            let mut shift = Vector::ZERO;
            for a in 0..D {
                let m = (off[a] + 1) as usize;
                if !exists[a][m] {
                    continue 'cells;
                }
                k += term[a][m];
                shift[a] = shift_of[a][m];
            }
            f(k, shift);
        }
    }

    /// Calls `f.visit(j, shift)` for every disc `j` filed in cell `k` (a linear index from
    /// [`Self::for_each_cell_sheared`]).
    #[inline(always)]
    pub(crate) fn visit_cell(&self, k: usize, shift: Vector<D>, f: &mut impl Visit<D>) {
        let mut j = self.head[k];
        while j != NONE {
            f.visit(j as usize, shift);
            j = self.next[j as usize];
        }
    }

    /// [`Self::for_each_cell_near`] for a cell `c` in the top (`above = true`) or bottom row
    /// along y under Lees-Edwards boundaries, whose images across y have slid along x by
    /// `slid` cell widths (`slid = k + frac`, `k` reduced modulo the columns, `0 <= frac < 1`
    /// as long as the images slide no further than the next whole cell):
    /// `f(cell, shift, across)`. The cells on this side are those of the plain scan; across
    /// the boundary, the four columns (times three along z in 3D) that the slid images of
    /// the other row's discs can bring within a cell width of `c`'s column while `slid` stays
    /// in `[k, k + 1]`, each with its image shift (`+-L_y` along y, the slide and any wrap
    /// along x).
    pub(crate) fn for_each_cell_sheared(
        &self,
        c: CellCoord<D>,
        above: bool,
        k: i64,
        frac: f64,
        mut f: impl FnMut(usize, Vector<D>, bool),
    ) {
        let across = if above { 1 } else { -1 };
        let mut term = [[0usize; 3]; D];
        let mut shift_of = [[0.0f64; 3]; D];
        let mut exists = [[true; 3]; D];
        for a in 0..D {
            let d = self.dims[a] as i64;
            for m in 0..3 {
                let mut x = c[a] as i64 + m as i64 - 1;
                if x < 0 || x >= d {
                    exists[a][m] = self.periodic[a];
                    shift_of[a][m] = if x < 0 {
                        -self.lengths[a]
                    } else {
                        self.lengths[a]
                    };
                    // One cell past either end: a division (`rem_euclid`) cost more.
                    x = if x < 0 { x + d } else { x - d };
                }
                term[a][m] = x as usize * self.stride[a];
            }
        }
        'cells: for off in &self.offsets[..Self::NEIGHBOURS] {
            if off[1] == across {
                continue;
            }
            let mut k = 0usize;
            let mut shift = Vector::ZERO;
            for a in 0..D {
                let m = (off[a] + 1) as usize;
                if !exists[a][m] {
                    continue 'cells;
                }
                k += term[a][m];
                shift[a] = shift_of[a][m];
            }
            f(k, shift, false);
        }
        // Across: the images above are shifted by +slid cells, those below by -slid. A disc
        // in column m of the other row has its image in columns m + slid (above) or m - slid
        // (below), which reach within a cell of column c for m = c - k - 2 ..= c - k + 1
        // (above) or c + k - 1 ..= c + k + 2 (below).
        let (nx, width) = (self.dims[0] as i64, self.width[0]);
        let row = if above { 0 } else { self.dims[1] as usize - 1 };
        let (first, sign) = if above { (-2, 1.0) } else { (-1, -1.0) };
        let cx = c[0] as i64;
        let mut z_cells = [(0usize, 0.0f64); 3];
        let mut z_count = 1;
        if D == 3 {
            z_count = 0;
            for m in 0..3 {
                if exists[2][m] {
                    z_cells[z_count] = (term[2][m], shift_of[2][m]);
                    z_count += 1;
                }
            }
        }
        for o in first..first + 4 {
            let m = if above { cx - k + o } else { cx + k + o };
            let col = m.rem_euclid(nx);
            let mut shift = Vector::ZERO;
            shift[0] = ((cx + o - col) as f64 + sign * frac) * width;
            shift[1] = sign * self.lengths[1];
            for &(zt, zs) in &z_cells[..z_count] {
                if D == 3 {
                    shift[2] = zs;
                }
                let k = col as usize * self.stride[0] + row * self.stride[1] + zt;
                f(k, shift, true);
            }
        }
    }

    /// The cells' first four discs ([`Self::first`]; 3D) and the lists' links.
    #[inline(always)]
    pub(crate) fn first_and_next(&self) -> (&[[u32; 4]], &[u32]) {
        (&self.first, &self.next)
    }

    /// The grid's lists as they stand: cell heads, per-disc next and previous, and each disc's
    /// cell (for checkpoints). The back links are worked out here: the checkpoint format has
    /// them from the time the lists were doubly linked.
    #[allow(clippy::type_complexity)]
    pub(crate) fn lists(&self) -> (&[u32], &[u32], Vec<u32>, Vec<CellCoord<D>>) {
        let mut prev = vec![NONE; self.next.len()];
        for &h in &self.head {
            let mut j = h;
            while j != NONE {
                let n = self.next[j as usize];
                if n != NONE {
                    prev[n as usize] = j;
                }
                j = n;
            }
        }
        let cell = (0..self.code.len()).map(|i| self.cell_of(i)).collect();
        (&self.head, &self.next, prev, cell)
    }

    /// Puts back lists taken by [`Self::lists`] from a grid built the same way, after checking
    /// that they are consistent: the same number of cells, every disc in exactly one list, the
    /// list of the cell it says it is in, with matching back links.
    pub(crate) fn restore(
        &mut self,
        head: Vec<u32>,
        next: Vec<u32>,
        prev: Vec<u32>,
        cell: Vec<CellCoord<D>>,
    ) -> Result<(), String> {
        let n = self.next.len();
        if head.len() != self.head.len() || next.len() != n || prev.len() != n || cell.len() != n {
            return Err(format!(
                "{} cells and {} discs where the box makes {} and {n}",
                head.len(),
                next.len(),
                self.head.len()
            ));
        }
        let mut seen = vec![false; n];
        for (k, &h) in head.iter().enumerate() {
            let mut j = h;
            let mut before = NONE;
            while j != NONE {
                let i = j as usize;
                if i >= n || seen[i] {
                    return Err(format!("cell {k} lists disc {j} wrongly"));
                }
                seen[i] = true;
                if (0..D).any(|a| cell[i][a] >= self.dims[a]) || self.linear(cell[i]) != k {
                    return Err(format!("disc {i} is listed in cell {k} but says otherwise"));
                }
                if prev[i] != before {
                    return Err(format!("disc {i} has a wrong back link"));
                }
                before = j;
                j = next[i];
            }
        }
        if let Some(i) = seen.iter().position(|s| !s) {
            return Err(format!("disc {i} is in no cell"));
        }
        let code = cell.iter().map(|&c| self.coder.encode(c)).collect();
        (self.head, self.next, self.code) = (head, next, code);
        for k in 0..self.first.len() {
            self.refresh_first(k);
        }
        Ok(())
    }

    /// Bytes held by the grid.
    pub fn memory_bytes(&self) -> usize {
        self.head.capacity() * 4
            + self.next.capacity() * 4
            + self.first.capacity() * 16
            + self.code.capacity() * 4
    }
}

/// What a scan of the cells around a disc ([`CellGrid::for_each_near`]) does with each disc
/// `j` it finds, `shift` being the periodic image offset to add to `j`'s position. Any
/// `FnMut(usize, Vector<D>)` is one; the engine's prediction implements it on a type of its
/// own, whose `visit` is inlined by force: a closure is inlined at the compiler's discretion,
/// and outlined (its two call sites in a scan, its body grown) it runs without the x86-64-v3
/// loop's instruction set (BENCHMARKS.md).
pub trait Visit<const D: usize> {
    /// Disc `j`, at `shift` from where it is filed.
    fn visit(&mut self, j: usize, shift: Vector<D>);
}

impl<const D: usize, F: FnMut(usize, Vector<D>)> Visit<D> for F {
    #[inline(always)]
    fn visit(&mut self, j: usize, shift: Vector<D>) {
        self(j, shift)
    }
}

/// The most cells around a cell the grid handles: `3^3`.
pub const MAX_NEIGHBOURS: usize = 27;

/// `3^d`, checked to fit [`MAX_NEIGHBOURS`] (at compile time where it is used as a constant).
const fn neighbours(d: usize) -> usize {
    let n = 3usize.pow(d as u32);
    assert!(
        n <= MAX_NEIGHBOURS,
        "the cell grid handles at most 3 dimensions"
    );
    n
}

/// The `3^D` offsets `{-1, 0, 1}^D` (then zeros to fill the array).
fn neighbour_offsets<const D: usize>() -> [[i32; D]; MAX_NEIGHBOURS] {
    let mut out = [[0; D]; MAX_NEIGHBOURS];
    for (k, o) in out.iter_mut().enumerate().take(neighbours(D)) {
        let mut r = k;
        for x in o.iter_mut() {
            *x = (r % 3) as i32 - 1;
            r /= 3;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn periodic_neighbours_wrap_with_shift() {
        let b = SimBox::periodic([3.0, 3.0]);
        let mut g = CellGrid::new(&b, 100, 1.0).unwrap();
        assert_eq!(g.dims(), [3, 3]);
        g.insert(0, [0, 0]);
        g.insert(1, [2, 0]);
        let mut seen = vec![];
        g.for_each_near([0, 0], |j, s| seen.push((j, s)));
        seen.sort_by_key(|a| a.0);
        assert_eq!(seen, vec![(0, Vector::ZERO), (1, Vector::new([-3.0, 0.0]))]);
    }

    #[test]
    fn walled_neighbours_do_not_wrap() {
        let b = SimBox::walls([3.0, 3.0]);
        let mut g = CellGrid::new(&b, 100, 1.0).unwrap();
        g.insert(0, [0, 0]);
        g.insert(1, [2, 0]);
        let mut seen = vec![];
        g.for_each_near([0, 0], |j, _| seen.push(j));
        assert_eq!(seen, vec![0]);
    }

    #[test]
    fn each_cells_first_four_follow_its_list_in_3d() {
        // 60 spheres in a 3 x 3 x 3 grid (cells of 5 or more), filed, crossed and taken out
        // at random: after every change each cell's first four are its list's first four, in
        // order, `NONE` past its end; and after the lists are put back from a checkpoint.
        let b = SimBox::periodic([3.0; 3]);
        let n = 60;
        let mut g = CellGrid::<3>::new(&b, n, 1.0).unwrap();
        let check = |g: &CellGrid<3>| {
            for (k, first) in g.first.iter().enumerate() {
                let mut list = vec![];
                let mut j = g.head[k];
                while j != NONE {
                    list.push(j);
                    j = g.next[j as usize];
                }
                list.resize(list.len().max(4), NONE);
                assert_eq!(first[..], list[..4], "cell {k}");
            }
        };
        let mut state = 5u64;
        let mut draw = |m: usize| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
            (state >> 33) as usize % m
        };
        for i in 0..n {
            g.insert(i, [draw(3) as u32, 0, draw(2) as u32]);
        }
        check(&g);
        assert!(
            g.first.iter().any(|f| f[3] != NONE),
            "no list longer than four"
        );
        for _ in 0..500 {
            let i = draw(n);
            let side = if draw(2) == 0 { Side::Low } else { Side::High };
            g.cross(i, draw(3), side);
            check(&g);
        }
        let (head, next, prev, cell) = g.lists();
        let (head, next, cell) = (head.to_vec(), next.to_vec(), cell.to_vec());
        let mut h = CellGrid::<3>::new(&b, n, 1.0).unwrap();
        h.restore(head, next, prev, cell).unwrap();
        check(&h);
        assert_eq!(h.first, g.first);
        g.clear();
        assert!(g.first.iter().all(|f| *f == [NONE; 4]));
    }

    #[test]
    fn crossing_moves_between_lists() {
        let b = SimBox::periodic([4.0, 4.0]);
        let mut g = CellGrid::new(&b, 100, 1.0).unwrap();
        g.insert(0, [3, 1]);
        g.insert(1, [3, 1]);
        g.insert(2, [3, 1]);
        assert_eq!(g.cross(1, 0, Side::High), -1);
        assert_eq!(g.cell_of(1), [0, 1]);
        let mut seen = vec![];
        g.for_each_near([3, 1], |j, _| seen.push(j));
        seen.sort();
        assert_eq!(seen, vec![0, 1, 2]);
        let mut own = vec![];
        g.for_each_near([1, 3], |j, _| own.push(j));
        assert!(own.is_empty());
    }

    #[test]
    fn removing_from_the_middle_of_a_list_keeps_the_order_and_the_back_links() {
        let b = SimBox::periodic([4.0, 4.0]);
        let mut g = CellGrid::new(&b, 100, 1.0).unwrap();
        for i in 0..4 {
            g.insert(i, [2, 2]);
        }
        g.remove(2);
        let mut seen = vec![];
        g.for_each_near([2, 2], |j, _| seen.push(j));
        assert_eq!(seen, vec![3, 1, 0]);
        let (_, next, prev, _) = g.lists();
        assert_eq!((next[3], prev[3], prev[1], prev[0]), (1, NONE, 3, 1));
        g.remove(0);
        g.remove(3);
        seen.clear();
        g.for_each_near([2, 2], |j, _| seen.push(j));
        assert_eq!(seen, vec![1]);
    }

    #[test]
    fn edges_once_scan_visits_what_the_plain_scan_visits() {
        // Every cell of a 3 x 4 x 5 grid, periodic on two axes and walled on one, each cell
        // holding 0 to 2 spheres: the same spheres, shifts and order.
        use crate::state::sim_box::Boundary::{Periodic, Walls};
        let b = SimBox {
            lengths: [3.0, 4.0, 5.0],
            boundaries: [Periodic, Walls, Periodic],
        };
        let mut g = CellGrid::<3>::new(&b, 60, 1.0).unwrap();
        assert_eq!(g.dims(), [3, 4, 5]);
        let mut i = 0;
        for z in 0..5 {
            for y in 0..4 {
                for x in 0..3 {
                    for _ in 0..(x + y + z) % 3 {
                        g.insert(i, [x, y, z]);
                        i += 1;
                    }
                }
            }
        }
        for z in 0..5 {
            for y in 0..4 {
                for x in 0..3 {
                    let (mut plain, mut once) = (vec![], vec![]);
                    g.for_each_near([x, y, z], |j, s| plain.push((j, s)));
                    g.for_each_near_edges_once([x, y, z], |j, s| once.push((j, s)));
                    assert_eq!(plain, once);
                }
            }
        }
    }

    #[test]
    fn exit_time_ignores_outer_walls() {
        let b = SimBox::walls([4.0, 4.0]);
        let mut g = CellGrid::new(&b, 100, 1.0).unwrap();
        g.insert(0, [3, 0]);
        // Moving +x in the last column: no crossing (wall first); moving +y: crosses at y = 1.
        let e = g.exit_time(0, Vector::new([3.5, 0.5]), Vector::new([1.0, 0.5]));
        assert_eq!(e, (1.0, 1, true));
        // At rest: never.
        let e = g.exit_time(0, Vector::new([3.5, 0.5]), Vector::ZERO);
        assert_eq!(e.0, f64::INFINITY);
    }

    #[test]
    fn sparse_systems_get_wider_cells() {
        // 2 discs in a 100 x 100 box: 2 cells per disc (4), not 10^4.
        let g = CellGrid::new(&SimBox::walls([100.0, 100.0]), 2, 1.0).unwrap();
        assert_eq!(g.dims(), [2, 2]);
        // Periodic axes keep at least 3 cells.
        let g = CellGrid::new(&SimBox::periodic([100.0, 100.0]), 1, 1.0).unwrap();
        assert_eq!(g.dims(), [3, 3]);
    }

    /// Each disc's cell is kept as its coordinates side by side in 32 bits: they read back
    /// exactly on every axis, an axis of one cell (no bits) included, and a grid whose
    /// coordinates would need more bits gets fewer, wider cells.
    #[test]
    fn cell_coordinates_fit_in_32_bits() {
        let b = SimBox::walls([1000.0, 1.0, 37.0]);
        let mut g = CellGrid::<3>::with_counts(&b, 10_000, [1000, 1, 37]).unwrap();
        for (i, c) in [[999, 0, 36], [0, 0, 0], [512, 0, 1], [1, 0, 35]]
            .into_iter()
            .enumerate()
        {
            g.insert(i, c);
            assert_eq!(g.cell_of(i), c);
        }
        // 2^30 - 1 cells on one axis, 4 on the next and one on the last: all 32 bits, the last
        // axis's shift 32.
        let coder = Coder::new([(1 << 30) - 1, 4, 1]).unwrap();
        for c in [[(1 << 30) - 2, 3, 0], [0, 0, 0], [5, 2, 0]] {
            assert_eq!(coder.decode(coder.encode(c)), c);
        }
        assert!(Coder::new([(1 << 30) - 1, 5, 1]).is_none());
        // 7 10^8 spheres of diameter 1 in a periodic box 1100 wide would have 1100 cells a
        // side, 11 bits each: one axis is halved.
        let counts =
            CellGrid::<3>::cell_counts(&SimBox::periodic([1100.0; 3]), 700_000_000, 1.0).unwrap();
        assert_eq!(counts, [1100, 1100, 550]);
        assert!(code_bits(&counts) <= 32);
    }

    #[test]
    fn small_periodic_box_is_refused() {
        let b = SimBox::periodic([2.5, 10.0]);
        assert!(matches!(
            CellGrid::new(&b, 4, 1.0),
            Err(Error::PeriodicBoxTooSmall { axis: 0, .. })
        ));
    }
    /// How the grid was sized before per-axis sizing: the reference for ordinary boxes.
    fn old_dims<const D: usize>(b: &SimBox<D>, n: usize, max_diameter: f64) -> [u32; D] {
        let sparse = (b.volume() / (2.0 * n.max(1) as f64)).powf(1.0 / D as f64);
        let target = max_diameter.max(sparse);
        std::array::from_fn(|a| {
            let l = b.lengths[a];
            let max_cells = ((l / max_diameter).floor() as u64).clamp(1, u32::MAX as u64 / 4);
            let d = ((l / target).floor() as u64).clamp(1, max_cells);
            (if b.is_periodic(a) { d.max(3) } else { d }) as u32
        })
    }

    fn cells<const D: usize>(g: &CellGrid<D>) -> u64 {
        g.dims().iter().map(|&d| d as u64).product()
    }

    // Regression: two discs in a `1 x 1e18` box took 4.2 GB (walls) or 12.6 GB (periodic) in
    // `CellGrid::new`, and a course file with box `15.1 1e20` 4.2 GB: the short axis was
    // rounded up to one cell (three when periodic) while the long one still got its share of the
    // whole volume, about 10^9 cells.
    #[test]
    fn long_thin_boxes_get_few_cells() {
        let cases_2d = [
            ([1.0, 1e18], 2, 0.02),
            ([1e18, 1.0], 2, 0.02),
            ([15.1, 1e20], 2, 1.0),
            ([1.0, 1e300], 1, 0.1),
            ([1e-3, 1e3], 1000, 1e-4),
        ];
        for (lengths, n, d) in cases_2d {
            for b in [SimBox::walls(lengths), SimBox::periodic(lengths)] {
                let g = CellGrid::new(&b, n, d).unwrap();
                assert!(
                    cells(&g) <= CellGrid::<2>::max_cells(n) as u64,
                    "{b:?}: {:?}",
                    g.dims()
                );
                for a in 0..2 {
                    assert!(
                        b.lengths[a] / g.dims()[a] as f64 >= d,
                        "{b:?}: {:?}",
                        g.dims()
                    );
                    assert!(!b.is_periodic(a) || g.dims()[a] >= 3);
                }
            }
        }
        let cases_3d = [
            ([1.0, 1.0, 1e18], 2, 0.02),
            ([1.0, 1e18, 1e18], 2, 0.02),
            ([1e18, 1.0, 1e9], 5, 0.02),
            ([15.1, 15.1, 1e20], 2, 1.0),
        ];
        for (lengths, n, d) in cases_3d {
            for b in [SimBox::walls(lengths), SimBox::periodic(lengths)] {
                let g = CellGrid::new(&b, n, d).unwrap();
                assert!(
                    cells(&g) <= CellGrid::<3>::max_cells(n) as u64,
                    "{b:?}: {:?}",
                    g.dims()
                );
                for a in 0..3 {
                    assert!(
                        b.lengths[a] / g.dims()[a] as f64 >= d,
                        "{b:?}: {:?}",
                        g.dims()
                    );
                    assert!(!b.is_periodic(a) || g.dims()[a] >= 3);
                }
            }
        }
        // The long axis still gets cells: a thin box is cut across its length.
        let g = CellGrid::new(&SimBox::walls([1.0, 1000.0]), 500, 0.5).unwrap();
        assert_eq!(g.dims(), [1, 1000]);
    }

    // Per-axis sizing must not move a cell boundary in an ordinary box: the cells' edges decide
    // when crossings happen, and so the rounding of every trajectory.
    #[test]
    fn ordinary_boxes_keep_their_grid() {
        for n in [1, 2, 3, 10, 100, 1000, 12345, 1 << 20] {
            for aspect in [1.0, 1.1, 1.5, 2.0, 3.0] {
                for d in [0.01, 0.1, 1.0] {
                    let l = (n as f64).sqrt() * 3.0 * d + 3.5 * d;
                    for b in [
                        SimBox::walls([l, l * aspect]),
                        SimBox::periodic([l * aspect, l]),
                    ] {
                        let g = CellGrid::new(&b, n, d).unwrap();
                        assert_eq!(g.dims(), old_dims(&b, n, d), "{b:?} n = {n}");
                    }
                    let l = (n as f64).cbrt() * 2.0 * d + 3.5 * d;
                    for b in [
                        SimBox::walls([l, l * aspect, l]),
                        SimBox::periodic([l, l, l * aspect]),
                    ] {
                        let g = CellGrid::new(&b, n, d).unwrap();
                        assert_eq!(g.dims(), old_dims(&b, n, d), "{b:?} n = {n}");
                    }
                }
            }
        }
    }
}
