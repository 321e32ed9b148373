//! Contacts, rattlers and the contact number of a packing.
//!
//! A jammed packing at reduced pressure `p` has its contacting pairs at gaps of order
//! `sigma / p` (in the free-volume picture, `h / sigma ~ d / p` in `d` dimensions), while the
//! nearest pairs that do not touch are at gaps many orders larger. Two particles are counted as
//! touching when their gap is below `gap_tolerance * sigma_ij` (a particle and a wall when the
//! gap to the wall is below `gap_tolerance` times its diameter). [`gap_tolerance`] picks
//! `1000 d / p`, well above the contact gaps and, at `p = 1e12`, below `1e-8`.
//!
//! Rattlers are particles held by fewer than `d + 1` contacts, which cannot be locally stable;
//! they are removed one by one together with their contacts, until every particle left has at
//! least `d + 1` (Donev, Torquato and Stillinger, J. Appl. Phys. 95, 989 (2004); Skoge et al.,
//! PRE 74, 041127 (2006)). The mean contact number counts the remaining particles' contacts
//! with each other (and with walls).

use crate::math::Vector;
use crate::state::{Disc, SimBox};

use super::bins::Bins;

/// The largest gap tolerance [`gap_tolerance`] returns: at low pressures (a dense fluid, not a
/// packing) every pair closer than 1% of its contact distance counts.
pub const MAX_GAP_TOLERANCE: f64 = 1e-2;

/// The relative gap below which two particles count as touching, at reduced pressure
/// `pressure` in `dim` dimensions: `1000 dim / p`, at most [`MAX_GAP_TOLERANCE`].
pub fn gap_tolerance(pressure: f64, dim: usize) -> f64 {
    let t = 1000.0 * dim as f64 / pressure;
    if t.is_finite() && t > 0.0 {
        t.min(MAX_GAP_TOLERANCE)
    } else {
        MAX_GAP_TOLERANCE
    }
}

/// The contacts of a packing.
#[derive(Clone, Debug, PartialEq)]
pub struct Contacts {
    /// The relative gap tolerance used.
    pub gap_tolerance: f64,
    /// True for each rattler.
    pub rattler: Vec<bool>,
    /// Number of rattlers.
    pub rattlers: usize,
    /// Contacts of each particle with non-rattlers and walls (0 for rattlers).
    pub contacts: Vec<u32>,
    /// Mean contacts per non-rattler (`NaN` if every particle rattles).
    pub mean_contacts: f64,
    /// The smallest relative gap `(|r_ij| - sigma_ij) / sigma_ij` over all pairs (negative: an
    /// overlap); `+inf` for fewer than two particles with no neighbours.
    pub min_gap: f64,
}

/// Finds the contacts and rattlers of `discs` in `sim_box` with relative gap tolerance `tol`.
pub fn contacts<const D: usize>(discs: &[Disc<D>], sim_box: &SimBox<D>, tol: f64) -> Contacts {
    let n = discs.len();
    let d_max = discs.iter().map(|d| 2.0 * d.radius).fold(0.0, f64::max);
    let mut bins = Bins::new(sim_box, d_max * (1.0 + tol), n);
    for (i, d) in discs.iter().enumerate() {
        bins.insert(i, sim_box.wrap(d.pos));
    }
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); n];
    let mut walls = vec![0u32; n];
    let mut min_gap = f64::INFINITY;
    for (i, d) in discs.iter().enumerate() {
        let p: Vector<D> = sim_box.wrap(d.pos);
        for j in bins.near(p) {
            if j <= i {
                continue;
            }
            let o = &discs[j];
            let sigma = d.radius + o.radius;
            let gap = (sim_box
                .minimum_image(sim_box.wrap(o.pos) - p)
                .norm2()
                .sqrt()
                - sigma)
                / sigma;
            min_gap = min_gap.min(gap);
            if gap < tol {
                neighbours[i].push(j as u32);
                neighbours[j].push(i as u32);
            }
        }
        for a in 0..D {
            if !sim_box.is_periodic(a) {
                let lo = (p[a] - d.radius) / (2.0 * d.radius);
                let hi = (sim_box.lengths[a] - p[a] - d.radius) / (2.0 * d.radius);
                walls[i] += (lo < tol) as u32 + (hi < tol) as u32;
            }
        }
    }
    let mut z: Vec<u32> = (0..n)
        .map(|i| neighbours[i].len() as u32 + walls[i])
        .collect();
    let mut rattler = vec![false; n];
    let mut stack: Vec<usize> = (0..n).filter(|&i| z[i] < (D + 1) as u32).collect();
    while let Some(i) = stack.pop() {
        if rattler[i] {
            continue;
        }
        rattler[i] = true;
        for &j in &neighbours[i] {
            let j = j as usize;
            if !rattler[j] {
                z[j] -= 1;
                if z[j] < (D + 1) as u32 {
                    stack.push(j);
                }
            }
        }
        z[i] = 0;
    }
    let rattlers = rattler.iter().filter(|&&r| r).count();
    let total: u64 = z.iter().map(|&k| k as u64).sum();
    Contacts {
        gap_tolerance: tol,
        rattlers,
        mean_contacts: total as f64 / (n - rattlers) as f64,
        contacts: z,
        rattler,
        min_gap,
    }
}
