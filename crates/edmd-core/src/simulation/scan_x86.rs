//! The 3D prediction's scan in the x86-64-v3 event loop: the candidates' contact terms four at
//! a time (AVX2).
//!
//! The cells around the sphere are read from the grid's copy of each cell's first four
//! spheres ([`CellGrid::first_and_next`]): one 16-byte load and store per cell into a batch,
//! the batch's length moved on by the count of spheres among the four (no branch per cell;
//! whether a cell holds none, one or two is a coin toss), the rest of a list walked only
//! when a cell holds four or more. The batch's records are then read four at a time (two
//! 32-byte loads each: position and velocity's `x`, then velocity's `y`, `z`, the clock and
//! the radius), turned into columns, and the contact terms worked out on the four lanes with
//! the same operations, in the same order, as the scalar kernel (`contact_terms` in
//! `predict/disc_disc.rs`, `Candidates::visit` in `predict.rs`): separate multiplications and
//! additions, never fused, so that every lane is bit-identical to the scalar result. Which
//! pairs meet is kept as a bit mask, and their roots are taken in the order found
//! (`Nearest::take`), so that the earliest pair and the second are the scalar scan's, to the
//! bit: the portable loop, which keeps the scalar scan, gives the same trajectory
//! (`the_x86_64_v3_scan_gives_the_portable_trajectory_bit_for_bit_in_3d` in
//! `tests/three_d.rs`). Used for contact times in the textbook form only; systems whose
//! candidates can be far apart (`predict::far_contacts`) keep the scalar scan.

// The intrinsics, the records read as `f64`s and the dimension's cast need `unsafe`; each
// block says why it holds.
#![allow(unsafe_code)]

use std::arch::x86_64::*;
use std::mem::{offset_of, size_of};

use crate::cells::grid::CellCoord;
use crate::cells::{CellGrid, NONE};
use crate::math::Vector;
use crate::predict::{contact_root, ContactTerms};

use super::predict::Nearest;
use super::Body;

/// Candidates gathered before their terms are worked out: a multiple of [`LANES`], more than
/// a dense fluid's 27 cells hold (about 25 at packing 0.45), so that a scan is one batch.
const BATCH: usize = 64;

/// From how many spheres the scan prefetches the candidates' records as it gathers them: where
/// the records (80 bytes each) outgrow a core's L2 cache of 1 or 2 MiB. Below, they are
/// there already and the prefetches cost 7% (BENCHMARKS.md).
const FETCH_FROM: usize = 1 << 14;

/// The candidates worked out at once.
const LANES: usize = 4;

// The kernel reads a sphere's record as eight `f64`s: position, velocity, clock, radius.
const _: () = {
    assert!(offset_of!(Body<3>, pos) == 0);
    assert!(offset_of!(Body<3>, vel) == 24);
    assert!(offset_of!(Body<3>, time) == 48);
    assert!(offset_of!(Body<3>, radius) == 56);
    assert!(size_of::<Vector<3>>() == 24);
    assert!(BATCH.is_multiple_of(LANES));
};

/// The candidates of a scan, gathered for [`terms_x4`]: scratch space that lives with the
/// simulation.
/// No alignment beyond `f64`'s is asked (the stores are unaligned ones): a `Simulation` held
/// by Python lives where Python's allocator puts it, 16-byte aligned, and an aligned 32-byte
/// store there faulted.
#[derive(Clone, Debug)]
pub(super) struct Batch {
    /// The candidates' contact terms, as [`crate::predict::ContactTerms`].
    b: [f64; BATCH],
    c: [f64; BATCH],
    d: [f64; BATCH],
    shift: [[f64; BATCH]; 3],
    idx: [u32; BATCH],
}

impl Default for Batch {
    fn default() -> Self {
        Batch {
            b: [0.0; BATCH],
            c: [0.0; BATCH],
            d: [0.0; BATCH],
            shift: [[0.0; BATCH]; 3],
            idx: [0; BATCH],
        }
    }
}

/// The scan of the 27 cells around `c` for the sphere `i` (advanced to `t0`): every
/// candidate's contact terms offered to `nearest` in the order `Candidates` offers them.
///
/// # Safety
/// The processor must have AVX2 (the x86-64-v3 loop's features).
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
pub(super) unsafe fn scan<const D: usize>(
    grid: &CellGrid<D>,
    c: CellCoord<D>,
    body: &[Body<D>],
    i: usize,
    t0: f64,
    nearest: &mut Nearest<'_>,
    batch: &mut Batch,
) {
    assert!(D == 3);
    // SAFETY: `D` is 3, so these are the same types.
    let (grid, body): (&CellGrid<3>, &[Body<3>]) = unsafe {
        (
            &*(grid as *const CellGrid<D>).cast::<CellGrid<3>>(),
            std::slice::from_raw_parts(body.as_ptr().cast::<Body<3>>(), body.len()),
        )
    };
    let c = [c[0], c[1], c[2]];
    match (grid.interior(c), body.len() >= FETCH_FROM) {
        (true, false) => gather::<false, false>(grid, c, body, i, t0, nearest, batch),
        (true, true) => gather::<false, true>(grid, c, body, i, t0, nearest, batch),
        (false, false) => gather::<true, false>(grid, c, body, i, t0, nearest, batch),
        (false, true) => gather::<true, true>(grid, c, body, i, t0, nearest, batch),
    }
}

/// [`scan`]: each cell's first four discs into the batch with one load and one store, the
/// count of those that are discs added to the batch's length (no branch: whether a cell holds
/// none, one or two is a coin toss), the rest of a list walked when a cell holds four or
/// more; with `SHIFT`, each candidate's image shift beside it (near the grid's edges).
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
#[inline]
fn gather<const SHIFT: bool, const FETCH: bool>(
    grid: &CellGrid<3>,
    c: CellCoord<3>,
    body: &[Body<3>],
    i: usize,
    t0: f64,
    nearest: &mut Nearest<'_>,
    batch: &mut Batch,
) {
    let own = &body[i];
    let (first, next) = grid.first_and_next();
    let none = _mm_set1_epi32(NONE as i32);
    let last = body.len() - 1;
    let mut n = 0usize;
    grid.for_each_cell_near(
        c,
        #[inline(always)]
        |k, shift| {
            if n > BATCH - LANES {
                let end = pad(batch, n, i);
                terms_x4::<SHIFT>(body, own, t0, batch, end, nearest);
                n = 0;
            }
            // SAFETY: `n + 4 <= BATCH`.
            let slots = unsafe { _mm_loadu_si128(first[k].as_ptr().cast()) };
            unsafe { _mm_storeu_si128(batch.idx.as_mut_ptr().add(n).cast(), slots) };
            if SHIFT {
                for a in 0..3 {
                    // SAFETY: as above.
                    unsafe {
                        _mm256_storeu_pd(
                            batch.shift[a].as_mut_ptr().add(n),
                            _mm256_set1_pd(shift[a]),
                        )
                    };
                }
            }
            let empty = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(slots, none)));
            n += 4 - empty.count_ones() as usize;
            // The first two discs' records asked for now, to be read by `terms_x4` once the
            // 27 cells are gathered (a cell holds about one; `NONE` reads some disc's).
            if FETCH {
                for &j in &first[k][..2] {
                    let p = body
                        .as_ptr()
                        .wrapping_add((j as usize).min(last))
                        .cast::<i8>();
                    _mm_prefetch::<_MM_HINT_T0>(p);
                    _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(63));
                }
            }
            let fourth = first[k][3];
            if fourth != NONE {
                let mut j = next[fourth as usize];
                while j != NONE {
                    if n == BATCH {
                        terms_x4::<SHIFT>(body, own, t0, batch, n, nearest);
                        n = 0;
                    }
                    batch.idx[n] = j;
                    for a in 0..3 {
                        batch.shift[a][n] = shift[a];
                    }
                    n += 1;
                    j = next[j as usize];
                }
            }
        },
    );
    let end = pad(batch, n, i);
    terms_x4::<SHIFT>(body, own, t0, batch, end, nearest);
}

/// Fills the batch from `n` up to a multiple of four with the sphere itself, at `dr = 0` and
/// `dv = 0` (or a whole box length), which never meets (`b = 0`); returns the new length.
#[inline(always)]
fn pad(batch: &mut Batch, n: usize, i: usize) -> usize {
    let end = n.next_multiple_of(LANES).min(BATCH);
    for k in n..end {
        batch.idx[k] = i as u32;
        for a in 0..3 {
            batch.shift[a][k] = 0.0;
        }
    }
    end
}

/// Four rows of four `f64`s as four columns: `[p0 q0 r0 s0] ... [p3 q3 r3 s3]` gives
/// `[p0 p1 p2 p3] ... [s0 s1 s2 s3]`.
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
#[inline]
pub(super) fn columns(rows: [__m256d; 4]) -> [__m256d; 4] {
    let lo01 = _mm256_unpacklo_pd(rows[0], rows[1]); // p0 p1 r0 r1
    let hi01 = _mm256_unpackhi_pd(rows[0], rows[1]); // q0 q1 s0 s1
    let lo23 = _mm256_unpacklo_pd(rows[2], rows[3]);
    let hi23 = _mm256_unpackhi_pd(rows[2], rows[3]);
    [
        _mm256_permute2f128_pd::<0x20>(lo01, lo23),
        _mm256_permute2f128_pd::<0x20>(hi01, hi23),
        _mm256_permute2f128_pd::<0x31>(lo01, lo23),
        _mm256_permute2f128_pd::<0x31>(hi01, hi23),
    ]
}

/// The contact terms of the first `n` candidates of `batch` (a multiple of four) against
/// `own`, the pairs that meet kept in `nearest` in their order.
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
#[inline]
fn terms_x4<const SHIFT: bool>(
    body: &[Body<3>],
    own: &Body<3>,
    t0: f64,
    batch: &mut Batch,
    n: usize,
    nearest: &mut Nearest<'_>,
) {
    let t0v = _mm256_set1_pd(t0);
    let pi = [0, 1, 2].map(|a| _mm256_set1_pd(own.pos[a]));
    let vi = [0, 1, 2].map(|a| _mm256_set1_pd(own.vel[a]));
    let ri = _mm256_set1_pd(own.radius);
    let zero = _mm256_setzero_pd();
    let mut meeting = 0u64;
    for g in (0..n.min(BATCH)).step_by(LANES) {
        // Four records as rows: [x, y, z, vx] and [vy, vz, t, r].
        let rows = [0, 1, 2, 3].map(|l| {
            let p = (&body[batch.idx[g + l] as usize] as *const Body<3>).cast::<f64>();
            // SAFETY: a record starts with these eight `f64`s (the assertions above).
            unsafe { (_mm256_loadu_pd(p), _mm256_loadu_pd(p.add(4))) }
        });
        let [x, y, z, vx] = columns(rows.map(|r| r.0));
        let [vy, vz, t, r] = columns(rows.map(|r| r.1));
        let pos = [x, y, z];
        let vel = [vx, vy, vz];
        // `Body::position_at(t0)` plus the shift, less the sphere's own position.
        let dt = _mm256_sub_pd(t0v, t);
        let dr = [0, 1, 2].map(|a| {
            let mut p = _mm256_add_pd(pos[a], _mm256_mul_pd(vel[a], dt));
            if SHIFT {
                // SAFETY: `g + 4 <= n <= BATCH`.
                p = _mm256_add_pd(p, unsafe {
                    _mm256_loadu_pd(batch.shift[a].as_ptr().add(g))
                });
            }
            _mm256_sub_pd(p, pi[a])
        });
        let dv = [0, 1, 2].map(|a| _mm256_sub_pd(vel[a], vi[a]));
        let sigma = _mm256_add_pd(ri, r);
        // `contact_terms`: sums from the first product (the scalar one starts from `-0.0`,
        // and `-0.0 + x` is `x`).
        let dot = |p: [__m256d; 3], q: [__m256d; 3]| {
            let s = _mm256_mul_pd(p[0], q[0]);
            let s = _mm256_add_pd(s, _mm256_mul_pd(p[1], q[1]));
            _mm256_add_pd(s, _mm256_mul_pd(p[2], q[2]))
        };
        let b = dot(dr, dv);
        let c = _mm256_sub_pd(dot(dr, dr), _mm256_mul_pd(sigma, sigma));
        let a = dot(dv, dv);
        let d = _mm256_sub_pd(_mm256_mul_pd(b, b), _mm256_mul_pd(a, c));
        // `ContactTerms::meets`: ordered comparisons, false for NaNs.
        let meets = _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_LT_OQ>(b, zero),
            _mm256_cmp_pd::<_CMP_GE_OQ>(d, zero),
        );
        meeting |= (_mm256_movemask_pd(meets) as u64) << g;
        // SAFETY: `g + 4 <= BATCH`.
        unsafe {
            _mm256_storeu_pd(batch.b.as_mut_ptr().add(g), b);
            _mm256_storeu_pd(batch.c.as_mut_ptr().add(g), c);
            _mm256_storeu_pd(batch.d.as_mut_ptr().add(g), d);
        }
    }
    // The roots of the pairs that meet, in the order found (`Nearest::roots`).
    while meeting != 0 {
        let g = meeting.trailing_zeros() as usize;
        meeting &= meeting - 1;
        let terms = ContactTerms {
            b: batch.b[g],
            c: batch.c[g],
            d: batch.d[g],
        };
        nearest.take(t0 + contact_root(terms), batch.idx[g]);
    }
}
