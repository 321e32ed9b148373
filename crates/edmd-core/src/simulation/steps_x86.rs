//! A stepped potential's 3D scan in the x86-64-v3 event loop: a sphere's neighbour list four
//! at a time (AVX2), for potentials whose one table serves every pair ([`Steps::uniform`]).
//!
//! Each group of four neighbours is read as the hard-core scan reads its candidates
//! (`scan_x86.rs`: two 32-byte loads per record, turned into columns), the edges of each
//! one's shell as a row of [`Edges`] (the edge a pair meets next from inside its shell, or
//! the outermost step from outside them all, and the edge it leaves by), and on the four
//! lanes at once the contact terms and the time of the next event: each lane picks the
//! operands of the root it needs (the contact or the departure), so that one square root and
//! one division serve the four. The same operations in the same order as the scalar scan
//! ([`super::steps::scan_stepped`], `contact_terms`, `contact_root` and `exit_time`), never
//! fused, so that each lane is the scalar result to the bit; the times are then handed to
//! `Nearest` one by one in the list's order, without a branch, as the scalar scan hands
//! them. The portable loop, which keeps the scalar scan, gives the same trajectory
//! (`the_x86_64_v3_stepped_scan_gives_the_portable_trajectory_bit_for_bit` in
//! `tests/stepped.rs`).

// The intrinsics, the records read as `f64`s and the dimension's cast need `unsafe`; each
// block says why it holds.
#![allow(unsafe_code)]

use std::arch::x86_64::*;

use crate::cells::grid::CellCoord;
use crate::cells::CellGrid;
use crate::math::Vector;

use super::centres::{Cell, SLOTS};
use super::predict::Nearest;
use super::scan_x86::columns;
use super::steps::{Edges, Steps};
use super::Body;

/// From how many spheres the scan asks for its neighbours' records, and the list-making for
/// its cells, before it reads them: where those outgrow a core's L2 cache (as
/// `scan_x86::FETCH_FROM`).
const FETCH_FROM: usize = 1 << 14;

/// Sphere `i`'s neighbours (`i` advanced to `t0`), their event times handed to `nearest` as
/// [`super::steps::scan_stepped`] hands them, for a simulation whose steps have
/// [`Steps::uniform`] edges.
///
/// # Safety
/// The processor must have AVX2 (the x86-64-v3 loop's features).
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
pub(super) unsafe fn scan<const D: usize>(
    body: &[Body<D>],
    steps: &Steps<D>,
    i: usize,
    t0: f64,
    nearest: &mut Nearest<'_>,
) {
    assert!(D == 3);
    // SAFETY: `D` is 3, so these are the same types.
    let (body, steps): (&[Body<3>], &Steps<3>) = unsafe {
        (
            std::slice::from_raw_parts(body.as_ptr().cast::<Body<3>>(), body.len()),
            &*(steps as *const Steps<D>).cast::<Steps<3>>(),
        )
    };
    let Some(edges) = &steps.uniform else {
        unreachable!("the x86-64-v3 stepped scan is for one table");
    };
    let own = &body[i];
    let list = steps.near.get(i);
    if body.len() >= FETCH_FROM {
        // Every neighbour's record asked for before the first is read.
        for &(j, _) in list {
            let p = (&body[j as usize] as *const Body<3>).cast::<i8>();
            _mm_prefetch::<_MM_HINT_T0>(p);
            _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(63));
        }
    }
    for group in list.chunks(4) {
        let mut who = [i as u32; 4];
        let mut shell = [0usize; 4];
        for (l, &(j, s)) in group.iter().enumerate() {
            who[l] = j;
            shell[l] = s as usize;
        }
        let times = lanes(body, own, edges, steps, t0, who, shell);
        for l in 0..group.len() {
            nearest.take(times[l], who[l]);
        }
    }
}

/// The time of the next event of each of the four neighbours `who` in shells `shell` with
/// `own`: its arrival at the shell's inner edge if it gets there (the outermost step or the
/// core from outside every step), else its departure through the outer edge, `+inf` for a
/// pair outside every step that does not meet the outermost one. One square root and one
/// division serve both roots: each lane picks the discriminant, the numerator and the
/// denominator of the root it needs, and the scalar's one (`contact_root` or `exit_time`)
/// is that quotient of the same operands.
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
#[inline]
fn lanes(
    body: &[Body<3>],
    own: &Body<3>,
    edges: &Edges,
    steps: &Steps<3>,
    t0: f64,
    who: [u32; 4],
    shell: [usize; 4],
) -> [f64; 4] {
    // Four records as rows: [x, y, z, vx] and [vy, vz, t, r] (`scan_x86.rs` asserts the
    // layout).
    let rows = who.map(|j| {
        let p = (&body[j as usize] as *const Body<3>).cast::<f64>();
        // SAFETY: a record starts with these eight `f64`s.
        unsafe { (_mm256_loadu_pd(p), _mm256_loadu_pd(p.add(4))) }
    });
    let [x, y, z, vx] = columns(rows.map(|r| r.0));
    let [vy, vz, t, r] = columns(rows.map(|r| r.1));
    // Each lane's edges by its shell (`Edges::rows`).
    let [inner, outer, outside, _] = columns(shell.map(|s| {
        let row = &edges.rows[s];
        // SAFETY: a row is four `f64`s.
        unsafe { _mm256_loadu_pd(row.as_ptr()) }
    }));
    let pos = [x, y, z];
    let vel = [vx, vy, vz];
    let zero = _mm256_setzero_pd();
    let sign = _mm256_set1_pd(-0.0);
    // `Body::position_at(t0)`, less the sphere's own position, at its nearest image
    // (`Steps::nearest_image`: both choices worked out from the displacement, then selected).
    let dt = _mm256_sub_pd(_mm256_set1_pd(t0), t);
    let dr = [0, 1, 2].map(|a| {
        let p = _mm256_add_pd(pos[a], _mm256_mul_pd(vel[a], dt));
        let d = _mm256_sub_pd(p, _mm256_set1_pd(own.pos[a]));
        let (l, h) = (steps.lengths[a], steps.half[a]);
        let down = _mm256_cmp_pd::<_CMP_GT_OQ>(d, _mm256_set1_pd(h));
        let up = _mm256_cmp_pd::<_CMP_LT_OQ>(d, _mm256_set1_pd(-h));
        let near = _mm256_blendv_pd(d, _mm256_add_pd(d, _mm256_set1_pd(l)), up);
        _mm256_blendv_pd(near, _mm256_sub_pd(d, _mm256_set1_pd(l)), down)
    });
    let dv = [0, 1, 2].map(|a| _mm256_sub_pd(vel[a], _mm256_set1_pd(own.vel[a])));
    let sigma = _mm256_add_pd(_mm256_set1_pd(own.radius), r);
    let inner = _mm256_max_pd(inner, sigma);
    // `contact_terms`, summed from the first product (the scalar one starts from `-0.0`).
    let dot = |p: [__m256d; 3], q: [__m256d; 3]| {
        let s = _mm256_mul_pd(p[0], q[0]);
        let s = _mm256_add_pd(s, _mm256_mul_pd(p[1], q[1]));
        _mm256_add_pd(s, _mm256_mul_pd(p[2], q[2]))
    };
    let b = dot(dr, dv);
    let r2 = dot(dr, dr);
    let a = dot(dv, dv);
    let bb = _mm256_mul_pd(b, b);
    let c = _mm256_sub_pd(r2, _mm256_mul_pd(inner, inner));
    let d = _mm256_sub_pd(bb, _mm256_mul_pd(a, c));
    let meets = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_LT_OQ>(b, zero),
        _mm256_cmp_pd::<_CMP_GE_OQ>(d, zero),
    );
    // `exit_time` through the outer edge: `b`, `a` and `|dr|^2` as above (the scalar sums
    // from `0.0` differ from these only in the sign of a zero, which decides nothing there).
    let c_out = _mm256_sub_pd(r2, _mm256_mul_pd(outer, outer));
    let d_out = _mm256_sub_pd(bb, _mm256_mul_pd(a, c_out));
    let receding = _mm256_cmp_pd::<_CMP_GT_OQ>(b, zero);
    let root = _mm256_sqrt_pd(_mm256_max_pd(_mm256_blendv_pd(d_out, d, meets), zero));
    // `contact_root`: `c / (-b + root)`; `exit_time`: `-c / (b + root)` receding, else
    // `(root - b) / a`.
    let num = _mm256_blendv_pd(
        _mm256_blendv_pd(_mm256_sub_pd(root, b), _mm256_xor_pd(c_out, sign), receding),
        c,
        meets,
    );
    let den = _mm256_blendv_pd(
        _mm256_blendv_pd(a, _mm256_add_pd(b, root), receding),
        _mm256_add_pd(_mm256_xor_pd(b, sign), root),
        meets,
    );
    let q = _mm256_div_pd(num, den);
    let contact = _mm256_max_pd(q, zero);
    let gone = _mm256_and_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(c_out, zero), receding);
    let exit = _mm256_blendv_pd(q, zero, gone);
    let still = _mm256_cmp_pd::<_CMP_EQ_OQ>(a, zero);
    let exit = _mm256_blendv_pd(exit, _mm256_set1_pd(f64::INFINITY), still);
    let exit = _mm256_blendv_pd(exit, _mm256_set1_pd(f64::INFINITY), outside);
    let time = _mm256_add_pd(_mm256_set1_pd(t0), _mm256_blendv_pd(exit, contact, meets));
    let mut out = [0.0; 4];
    // SAFETY: four `f64`s.
    unsafe { _mm256_storeu_pd(out.as_mut_ptr(), time) };
    out
}

/// Pushes `j` onto `out` for every sphere `j` other than `i` filed in the cells around
/// `c` whose list centre is nearer `p` than the lists' radius: the spheres of `i`'s list made
/// at `p` (`for_each_listed` in `steps.rs`, in another order). The centres are read from the
/// cells ([`super::centres`]), a cell's eight slots at a time, and their distances worked out
/// on four lanes in the scalar's operations (`Steps::nearest_image`, `Vector::norm2`), so
/// that the same spheres are found; those beyond a cell's slots one by one.
///
/// # Safety
/// The processor must have AVX2 (the x86-64-v3 loop's features).
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
pub(super) unsafe fn listed<const D: usize>(
    grid: &CellGrid<D>,
    steps: &Steps<D>,
    c: CellCoord<D>,
    p: Vector<D>,
    i: usize,
    out: &mut Vec<u32>,
) {
    assert!(D == 3);
    // SAFETY: `D` is 3, so these are the same types.
    let (grid, steps): (&CellGrid<3>, &Steps<3>) = unsafe {
        (
            &*(grid as *const CellGrid<D>).cast::<CellGrid<3>>(),
            &*(steps as *const Steps<D>).cast::<Steps<3>>(),
        )
    };
    let c = [c[0], c[1], c[2]];
    let p = Vector::new([p[0], p[1], p[2]]);
    let limit = steps.list_radius * steps.list_radius;
    let cells = &steps.filed.cells;
    let centre = &steps.centre;
    if centre.len() >= FETCH_FROM {
        // Every line of the 27 cells asked for before the first is read, so that their
        // misses overlap; below, the cells are in the L2 cache already.
        grid.for_each_cell_near(c, |k, _| {
            let cell = &cells[k];
            crate::hint::prefetch(&cell.x);
            crate::hint::prefetch(&cell.y);
            crate::hint::prefetch(&cell.z);
            crate::hint::prefetch(&cell.id);
        });
    }
    let at = p.0.map(|x| _mm256_set1_pd(x));
    let under = _mm256_set1_pd(limit);
    grid.for_each_cell_near(
        c,
        #[inline(always)]
        |k, shift| {
            let cell = &cells[k];
            // The cell's eight slots at once, those past its length and `i` itself masked
            // off: a loop over the slots it holds mispredicted its end at nearly every cell.
            let len = cell.len as usize;
            let shift = shift.0.map(|x| _mm256_set1_pd(x));
            // SAFETY: eight `u32`s.
            let ids = unsafe { _mm256_loadu_si256(cell.id.as_ptr().cast()) };
            let hits = (within(cell, 0, shift, at, under) | within(cell, 4, shift, at, under) << 4)
                & ((1u32 << len) - 1)
                & !slot_of(ids, i as u32);
            push_hits(out, ids, hits);
            for &j in &cell.more {
                let ju = j as usize;
                if ju != i && steps.nearest_image(centre[ju] - p).norm2() < limit {
                    out.push(j);
                }
            }
        },
    );
}

/// For each of the 16 masks of four lanes, the bytes of `_mm_shuffle_epi8` that gather the
/// lanes set, in order, to the front.
const GATHER: [[u8; 16]; 16] = {
    let mut table = [[0x80u8; 16]; 16];
    let mut m = 0;
    while m < 16 {
        let mut to = 0;
        let mut lane = 0;
        while lane < 4 {
            if m & (1 << lane) != 0 {
                let mut b = 0;
                while b < 4 {
                    table[m][4 * to + b] = (4 * lane + b) as u8;
                    b += 1;
                }
                to += 1;
            }
            lane += 1;
        }
        m += 1;
    }
    table
};

/// Appends to `out` those of a cell's eight slot ids `ids` whose bits are set in `hits`, in
/// order of slot, without a branch on the mask: each half's ids gathered to the front and
/// stored whole, the next store starting past those kept.
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
#[inline]
fn push_hits(out: &mut Vec<u32>, ids: __m256i, hits: u32) {
    const { assert!(SLOTS == 8) };
    out.reserve(SLOTS);
    let len = out.len();
    let (low, high) = ((hits & 15) as usize, (hits >> 4 & 15) as usize);
    // SAFETY: the two 16-byte stores end at most eight `u32`s past `len`, within the
    // capacity just reserved, and only the ones kept are counted.
    unsafe {
        let to = out.as_mut_ptr().add(len);
        let first = _mm_shuffle_epi8(
            _mm256_castsi256_si128(ids),
            _mm_loadu_si128(GATHER[low].as_ptr().cast()),
        );
        _mm_storeu_si128(to.cast(), first);
        let kept = low.count_ones() as usize;
        let second = _mm_shuffle_epi8(
            _mm256_extracti128_si256::<1>(ids),
            _mm_loadu_si128(GATHER[high].as_ptr().cast()),
        );
        _mm_storeu_si128(to.add(kept).cast(), second);
        out.set_len(len + kept + high.count_ones() as usize);
    }
}

/// Which of a cell's eight slot ids `ids` are sphere `i`, as a bit mask (the sphere is not
/// its own neighbour).
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
#[inline]
fn slot_of(ids: __m256i, i: u32) -> u32 {
    let same = _mm256_cmpeq_epi32(ids, _mm256_set1_epi32(i as i32));
    _mm256_movemask_ps(_mm256_castsi256_ps(same)) as u32
}

/// Which of the four centres from slot `g` of `cell` are nearer `p` than `sqrt(limit)`, as a
/// bit mask (`p`, `shift` and `limit` each broadcast to the four lanes): the displacement,
/// plus the cell's `shift` to its image around `p` (`-0.0`, or a box length across a
/// periodic side), then `norm2` summed from the first square (the scalar one starts from
/// `0.0`, and `0.0 + x` is `x` for a square). For a centre within the lists' radius the shift
/// is `Steps::nearest_image`'s choice, in the same operation (`d - l` is `d + (-l)`, and
/// `d + (-0.0)` is `d`), so the same spheres are found; the image of one beyond it may differ,
/// but it is beyond it either way (the cells are a list radius wide).
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
#[inline]
fn within(cell: &Cell, g: usize, shift: [__m256d; 3], p: [__m256d; 3], limit: __m256d) -> u32 {
    let mut r2 = _mm256_setzero_pd();
    for (a, column) in [&cell.x, &cell.y, &cell.z].into_iter().enumerate() {
        let four = &column[g..g + 4];
        // SAFETY: four `f64`s.
        let d = unsafe { _mm256_loadu_pd(four.as_ptr()) };
        let d = _mm256_add_pd(_mm256_sub_pd(d, p[a]), shift[a]);
        let sq = _mm256_mul_pd(d, d);
        r2 = if a == 0 { sq } else { _mm256_add_pd(r2, sq) };
    }
    _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(r2, limit)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slots_kept_are_appended_in_order_of_slot() {
        if !crate::simulation::x86_64_v3_available() {
            return;
        }
        let id: [u32; SLOTS] = [10, 11, 12, 13, 14, 15, 16, 17];
        for hits in 0..256u32 {
            let mut out = vec![7];
            // SAFETY: the processor has AVX2 (checked above); eight `u32`s.
            unsafe { push_hits(&mut out, _mm256_loadu_si256(id.as_ptr().cast()), hits) };
            let want: Vec<u32> = std::iter::once(7)
                .chain((0..SLOTS).filter(|&s| hits >> s & 1 == 1).map(|s| id[s]))
                .collect();
            assert_eq!(out, want, "mask {hits:08b}");
        }
    }
}
