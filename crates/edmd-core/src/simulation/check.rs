//! Invariant checks (overlaps, discs outside the box) and input validation.

use super::Simulation;
use crate::error::Error;
use crate::state::{Disc, SimBox};

impl<const D: usize> Simulation<D> {
    /// Overlapping pairs at the current time: those closer than `sigma (1 - tol)`, less the
    /// rounding allowance [`super::OVERLAP_ROUNDING`]` (L + (|v_i| + |v_j|) |t|)`.
    pub fn overlaps(&self, tol: f64) -> OverlapReport {
        let mut report = OverlapReport::default();
        let now = self.now;
        let longest = self.sim_box.lengths.iter().copied().fold(0.0, f64::max);
        let speed = |k: usize| self.body[k].vel.norm2().sqrt();
        for i in 0..self.len() {
            let pi = self.body[i].position_at(now);
            self.grid.for_each_near(self.grid.cell_of(i), |j, shift| {
                if j <= i {
                    return;
                }
                let pj = self.body[j].position_at(now) + shift;
                let sigma = self.body[i].radius + self.body[j].radius;
                let d = (pj - pi).norm2().sqrt();
                let rounding =
                    super::OVERLAP_ROUNDING * (longest + (speed(i) + speed(j)) * now.abs());
                if d < sigma * (1.0 - tol) - rounding {
                    report.count += 1;
                    let overlap = (sigma - d) / sigma;
                    // "First" is the pair completed earliest in input order.
                    if report.first.is_none_or(|(fi, fj, _)| (j, i) < (fj, fi)) {
                        report.first = Some((i, j, overlap));
                    }
                }
            });
        }
        report
    }

    /// Discs outside the box (walled axes) at the current time, beyond `tol` relative to radius.
    pub fn discs_outside(&self, tol: f64) -> Vec<usize> {
        (0..self.len())
            .filter(|&i| {
                let p = self.body[i].position_at(self.now);
                let r = self.body[i].radius;
                (0..D).any(|a| {
                    !self.sim_box.is_periodic(a)
                        && (p[a] < r * (1.0 - tol)
                            || p[a] > self.sim_box.lengths[a] - r * (1.0 - tol))
                })
            })
            .collect()
    }
}

/// Result of [`Simulation::overlaps`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OverlapReport {
    /// Number of overlapping pairs.
    pub count: usize,
    /// The pair completed earliest in input order, `(i, j, (sigma - d)/sigma)` with `i < j`.
    pub first: Option<(usize, usize, f64)>,
}

pub(super) fn validate_discs<const D: usize>(
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
) -> Result<(), Error> {
    for (k, d) in discs.iter().enumerate() {
        let bad = |what: &str| {
            Err(Error::BadDisc {
                index: k,
                what: what.to_string(),
            })
        };
        if !d.pos.is_finite() {
            return bad("position is not finite");
        }
        if !d.vel.is_finite() {
            return bad("velocity is not finite");
        }
        if !(d.radius.is_finite() && d.radius > 0.0) {
            return bad(&format!(
                "radius {} is not a finite positive number",
                d.radius
            ));
        }
        if !(d.mass.is_finite() && d.mass > 0.0) {
            return bad(&format!("mass {} is not a finite positive number", d.mass));
        }
        if !(0.5 * d.mass * d.vel.norm2()).is_finite() {
            return bad("kinetic energy is not finite (speed or mass too large)");
        }
        // A disc exactly as wide as the box is refused too: its wall collisions would all be
        // at one instant, and the clock would never advance. (On a periodic axis the cell grid
        // refuses boxes under 3 diameters, so a disc never meets its own image.)
        for a in 0..D {
            if !sim_box.is_periodic(a) && 2.0 * d.radius >= sim_box.lengths[a] {
                return Err(Error::DiscFillsBox {
                    index: k,
                    axis: a,
                    diameter: 2.0 * d.radius,
                    length: sim_box.lengths[a],
                });
            }
        }
    }
    Ok(())
}
