//! Random sequential addition: discs placed one by one at uniformly random free positions.
//!
//! Each disc is tried at uniformly random positions (its centre kept far enough inside the
//! region that the whole disc lies in it) until it overlaps neither the discs placed before it
//! nor the fixed ones; a cell grid keeps each try O(1). Random sequential addition of equal
//! discs jams at an area fraction of 0.547 and slows down well before, so requests above
//! [`MAX_RANDOM_FILL`] are refused.

use rand::Rng;

use crate::cells::CellGrid;
use crate::error::Error;
use crate::math::{Vector, DIM};
use crate::state::{Disc, SimBox};

/// Highest area fraction (discs' area over the region's) placed by random sequential addition.
pub const MAX_RANDOM_FILL: f64 = 0.4;

/// Tries per disc before giving up.
const TRIES: u32 = 100_000;

/// An axis-aligned rectangle `[lo, hi]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    /// Lower corner.
    pub lo: [f64; DIM],
    /// Upper corner.
    pub hi: [f64; DIM],
}

impl Region {
    /// The rectangle `[0, L]` of a box.
    pub fn of(sim_box: &SimBox) -> Self {
        Region {
            lo: [0.0; DIM],
            hi: sim_box.lengths,
        }
    }

    fn area(&self) -> f64 {
        (0..DIM).map(|a| self.hi[a] - self.lo[a]).product()
    }
}

/// Positions for discs of the given radii inside `region` (a part of `sim_box`), overlapping
/// neither each other nor `fixed`, with every random choice from `rng`. `kind` names the
/// caller in error messages.
pub fn random_positions(
    kind: &str,
    radii: &[f64],
    region: Region,
    fixed: &[Disc],
    sim_box: &SimBox,
    rng: &mut impl Rng,
) -> Result<Vec<Vector>, Error> {
    let disc_area: f64 = radii
        .iter()
        .map(|r| std::f64::consts::PI * r * r)
        .sum::<f64>()
        + fixed
            .iter()
            .map(|d| std::f64::consts::PI * d.radius * d.radius)
            .sum::<f64>();
    let fill = disc_area / region.area();
    if fill > MAX_RANDOM_FILL {
        return Err(Error::Invalid(format!(
            "{kind}: the discs would cover {:.1}% of their region, more than the {:.0}% that random \
             placement allows; use fewer or smaller discs",
            100.0 * fill,
            100.0 * MAX_RANDOM_FILL
        )));
    }
    for &r in radii {
        if (0..DIM).any(|a| 2.0 * r >= region.hi[a] - region.lo[a]) {
            return Err(Error::Invalid(format!(
                "{kind}: a disc of radius {r} does not fit in its region"
            )));
        }
    }
    let d_max = radii
        .iter()
        .chain(fixed.iter().map(|d| &d.radius))
        .fold(0.0f64, |m, &r| m.max(2.0 * r));
    let mut grid = CellGrid::new(sim_box, fixed.len() + radii.len(), d_max)
        .map_err(|e| Error::Invalid(format!("{kind}: {e}")))?;
    let mut placed: Vec<(Vector, f64)> = Vec::with_capacity(fixed.len() + radii.len());
    for d in fixed {
        grid.insert(placed.len(), grid.coord_of(d.pos));
        placed.push((d.pos, d.radius));
    }
    for (k, &r) in radii.iter().enumerate() {
        let mut found = None;
        for _ in 0..TRIES {
            let mut p = Vector::ZERO;
            for a in 0..DIM {
                p[a] = rng.random_range(region.lo[a] + r..region.hi[a] - r);
            }
            let mut free = true;
            grid.for_each_near(grid.coord_of(p), |j, shift| {
                let (q, rj) = placed[j];
                let sigma = r + rj;
                free &= (q + shift - p).norm2() >= sigma * sigma;
            });
            if free {
                found = Some(p);
                break;
            }
        }
        let p = found.ok_or_else(|| {
            Error::Invalid(format!(
                "{kind}: no free place found for disc {k} of {} after {TRIES} tries; use fewer or smaller discs",
                radii.len()
            ))
        })?;
        grid.insert(placed.len(), grid.coord_of(p));
        placed.push((p, r));
    }
    Ok(placed[fixed.len()..].iter().map(|&(p, _)| p).collect())
}
