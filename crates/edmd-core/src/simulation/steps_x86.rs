//! A stepped potential's 3D scan in the x86-64-v3 event loop: a sphere's neighbour list four
//! at a time (AVX2), for potentials whose one table serves every pair ([`Steps::uniform`]).
//!
//! Each group of four neighbours is read as the hard-core scan reads its candidates
//! (`scan_x86.rs`: two 32-byte loads per record, turned into columns), the shell of each
//! looked up in [`Edges`] (the edge a pair meets next from inside its shell, or the outermost
//! step from outside them all, and the edge it leaves by), and on the four lanes at once the
//! contact terms, the contact time and the departure time, both roots taken whether or not
//! the lane needs them. The same operations in the same order as the scalar scan
//! ([`super::steps::scan_stepped`], `contact_terms`, `contact_root` and `exit_time`), never
//! fused, so that each lane is the scalar result to the bit; the lanes are then handed to
//! `Nearest` one by one in the list's order, a pair outside every step offered as a hard
//! core's is, one inside a step taken with its time, as the scalar scan does. The portable
//! loop, which keeps the scalar scan, gives the same trajectory
//! (`the_x86_64_v3_stepped_scan_gives_the_portable_trajectory_bit_for_bit` in
//! `tests/stepped.rs`).

// The intrinsics, the records read as `f64`s and the dimension's cast need `unsafe`; each
// block says why it holds.
#![allow(unsafe_code)]

use std::arch::x86_64::*;

use crate::cells::grid::CellCoord;
use crate::cells::{CellGrid, NONE};
use crate::math::Vector;
use crate::predict::ContactTerms;

use super::predict::Nearest;
use super::scan_x86::columns;
use super::steps::{Edges, Steps};
use super::Body;

/// From how many spheres the scan asks for its neighbours' records before it reads them:
/// where the records outgrow a core's L2 cache (as `scan_x86::FETCH_FROM`).
const FETCH_FROM: usize = 1 << 14;

/// Sphere `i`'s neighbours (`i` advanced to `t0`), offered to `nearest` as
/// [`super::steps::scan_stepped`] offers them, for a simulation whose steps have
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
    let list = &steps.near[i];
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
        let mut shell = [0u8; 4];
        for (l, &(j, s)) in group.iter().enumerate() {
            who[l] = j;
            shell[l] = s;
        }
        let (terms, times) = lanes(body, own, steps, edges, t0, who, shell);
        for l in 0..group.len() {
            if shell[l] == 0 {
                nearest.offer(
                    who[l] as usize,
                    ContactTerms {
                        b: terms[0][l],
                        c: terms[1][l],
                        d: terms[2][l],
                    },
                );
            } else {
                nearest.take(times[l], who[l]);
            }
        }
    }
}

/// The four neighbours `who` in shells `shell`: their contact terms against `own` (`b`, `c`,
/// `d`: the contact with the outermost step or the hard core from outside every step, with
/// the shell's inner edge from inside one), and, for those inside a step, the time of their
/// next event, the contact if they meet the inner edge, else the departure through the outer.
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
#[inline]
fn lanes(
    body: &[Body<3>],
    own: &Body<3>,
    steps: &Steps<3>,
    edges: &Edges,
    t0: f64,
    who: [u32; 4],
    shell: [u8; 4],
) -> ([[f64; 4]; 3], [f64; 4]) {
    // Four records as rows: [x, y, z, vx] and [vy, vz, t, r] (`scan_x86.rs` asserts the
    // layout).
    let rows = who.map(|j| {
        let p = (&body[j as usize] as *const Body<3>).cast::<f64>();
        // SAFETY: a record starts with these eight `f64`s.
        unsafe { (_mm256_loadu_pd(p), _mm256_loadu_pd(p.add(4))) }
    });
    let [x, y, z, vx] = columns(rows.map(|r| r.0));
    let [vy, vz, t, r] = columns(rows.map(|r| r.1));
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
    // Each lane's edges by its shell: the inner edge (the outermost step or the core, the
    // farther, outside every step; the core in the innermost shell), and the outer one.
    let s = _mm256_setr_pd(
        f64::from(shell[0]),
        f64::from(shell[1]),
        f64::from(shell[2]),
        f64::from(shell[3]),
    );
    let pick = |table: &[f64]| {
        _mm256_setr_pd(
            table[shell[0] as usize],
            table[shell[1] as usize],
            table[shell[2] as usize],
            table[shell[3] as usize],
        )
    };
    let outside = _mm256_cmp_pd::<_CMP_EQ_OQ>(s, zero);
    let innermost = _mm256_cmp_pd::<_CMP_EQ_OQ>(s, _mm256_set1_pd(f64::from(edges.innermost)));
    let inner = _mm256_blendv_pd(pick(&edges.inner), sigma, innermost);
    let inner = _mm256_blendv_pd(
        inner,
        _mm256_max_pd(_mm256_set1_pd(edges.reach), sigma),
        outside,
    );
    let outer = pick(&edges.outer);
    // `contact_terms`, summed from the first product (the scalar one starts from `-0.0`).
    let dot = |p: [__m256d; 3], q: [__m256d; 3]| {
        let s = _mm256_mul_pd(p[0], q[0]);
        let s = _mm256_add_pd(s, _mm256_mul_pd(p[1], q[1]));
        _mm256_add_pd(s, _mm256_mul_pd(p[2], q[2]))
    };
    let b = dot(dr, dv);
    let r2 = dot(dr, dr);
    let c = _mm256_sub_pd(r2, _mm256_mul_pd(inner, inner));
    let a = dot(dv, dv);
    let d = _mm256_sub_pd(_mm256_mul_pd(b, b), _mm256_mul_pd(a, c));
    let meets = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_LT_OQ>(b, zero),
        _mm256_cmp_pd::<_CMP_GE_OQ>(d, zero),
    );
    // `contact_root`: `(c / (-b + sqrt(max(d, 0)))).max(0)`.
    let root = _mm256_sqrt_pd(_mm256_max_pd(d, zero));
    let contact = _mm256_max_pd(
        _mm256_div_pd(c, _mm256_add_pd(_mm256_xor_pd(b, sign), root)),
        zero,
    );
    // `exit_time` through the outer edge: `b`, `a` and `|dr|^2` as above (the scalar sums
    // from `0.0` differ from these only in the sign of a zero, which decides nothing there).
    let c_out = _mm256_sub_pd(r2, _mm256_mul_pd(outer, outer));
    let root_out = _mm256_sqrt_pd(_mm256_max_pd(
        _mm256_sub_pd(_mm256_mul_pd(b, b), _mm256_mul_pd(a, c_out)),
        zero,
    ));
    let receding = _mm256_cmp_pd::<_CMP_GT_OQ>(b, zero);
    let leaving = _mm256_div_pd(_mm256_xor_pd(c_out, sign), _mm256_add_pd(b, root_out));
    let crossing = _mm256_div_pd(_mm256_sub_pd(root_out, b), a);
    let exit = _mm256_blendv_pd(crossing, leaving, receding);
    let gone = _mm256_and_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(c_out, zero), receding);
    let exit = _mm256_blendv_pd(exit, zero, gone);
    let still = _mm256_cmp_pd::<_CMP_EQ_OQ>(a, zero);
    let exit = _mm256_blendv_pd(exit, _mm256_set1_pd(f64::INFINITY), still);
    let time = _mm256_add_pd(_mm256_set1_pd(t0), _mm256_blendv_pd(exit, contact, meets));
    let out = |v: __m256d| {
        let mut x = [0.0; 4];
        // SAFETY: four `f64`s.
        unsafe { _mm256_storeu_pd(x.as_mut_ptr(), v) };
        x
    };
    ([out(b), out(c), out(d)], out(time))
}

/// Pushes `(j, 0)` onto `out` for every sphere `j` other than `i` filed in the cells around
/// `c` whose list centre is nearer `p` than the lists' radius: the spheres of `i`'s list made
/// at `p` (`for_each_listed` in `steps.rs`, in another order). Each cell's first four spheres
/// are read with one load ([`CellGrid::first_and_next`]) and their distances worked out on
/// four lanes, in the scalar's operations (`Steps::nearest_image`, `Vector::norm2`), so that
/// the same spheres are found; the rest of a cell's list is walked one by one.
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
    out: &mut Vec<(u32, u8)>,
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
    let (first, next) = grid.first_and_next();
    let centre = &steps.centre;
    grid.for_each_cell_near(
        c,
        #[inline(always)]
        |k, _| {
            let slots = first[k];
            let mut hits = within(centre, steps, p, limit, slots, i);
            while hits != 0 {
                let l = hits.trailing_zeros() as usize;
                hits &= hits - 1;
                if slots[l] as usize != i {
                    out.push((slots[l], 0));
                }
            }
            if slots[3] != NONE {
                let mut j = next[slots[3] as usize];
                while j != NONE {
                    let ju = j as usize;
                    if ju != i && steps.nearest_image(centre[ju] - p).norm2() < limit {
                        out.push((j, 0));
                    }
                    j = next[ju];
                }
            }
        },
    );
}

/// Which of the four `slots` (a cell's first four spheres, `NONE` past its end) have their
/// list centres nearer `p` than `sqrt(limit)`, as a bit mask: `Steps::nearest_image`, then
/// `norm2` summed from the first square (the scalar one starts from `0.0`, and `0.0 + x` is
/// `x` for a square).
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,movbe")]
#[inline]
fn within(
    centre: &[Vector<3>],
    steps: &Steps<3>,
    p: Vector<3>,
    limit: f64,
    slots: [u32; 4],
    i: usize,
) -> u32 {
    let xyz = _mm256_setr_epi64x(-1, -1, -1, 0);
    // The centres as rows `[x, y, z, 0]` (an empty slot reads sphere `i`'s).
    let mut rows = [_mm256_setzero_pd(); 4];
    let mut empty = 0u32;
    for l in 0..4 {
        let j = if slots[l] == NONE {
            empty |= 1 << l;
            i
        } else {
            slots[l] as usize
        };
        // SAFETY: the mask reads the three coordinates of a centre.
        rows[l] = unsafe { _mm256_maskload_pd(centre[j].0.as_ptr(), xyz) };
    }
    let [x, y, z, _] = columns(rows);
    let mut r2 = _mm256_setzero_pd();
    for (a, d) in [x, y, z].into_iter().enumerate() {
        let (l, h) = (_mm256_set1_pd(steps.lengths[a]), steps.half[a]);
        let d = _mm256_sub_pd(d, _mm256_set1_pd(p[a]));
        let down = _mm256_cmp_pd::<_CMP_GT_OQ>(d, _mm256_set1_pd(h));
        let up = _mm256_cmp_pd::<_CMP_LT_OQ>(d, _mm256_set1_pd(-h));
        let near = _mm256_blendv_pd(d, _mm256_add_pd(d, l), up);
        let d = _mm256_blendv_pd(near, _mm256_sub_pd(d, l), down);
        let sq = _mm256_mul_pd(d, d);
        r2 = if a == 0 { sq } else { _mm256_add_pd(r2, sq) };
    }
    _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(r2, _mm256_set1_pd(limit))) as u32 & !empty
}
