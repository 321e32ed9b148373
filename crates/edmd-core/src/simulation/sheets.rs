//! One-dimensional self-gravity (see [`crate::state::self_gravity`]): rods on a line, each
//! accelerated by its rank, flying on parabolas between events.
//!
//! Hard rods keep their order, so a rod's rank, and with it its acceleration
//! `coupling (M_right - M_left)`, is fixed when the self-gravity is set. Only neighbours in that
//! order can meet (Noullez, Fanelli and Aurell's algorithm), so a prediction looks at two rods,
//! not at cells: the grid is one cell, which keeps every disc filed without crossings. A pair's
//! gap `y = x_right - x_left` closes on a parabola whose acceleration `a_right - a_left` is
//! below 0 (they attract), and leaves `[sigma, inf)` at the root of a quadratic, computed as the
//! walls' and cells' exits are in a field (`interval_exit_accel_or_inf`), so that it loses no
//! digits and a gap a rounding error below contact closes at once. The events are the
//! straight-line engine's (collisions, walls, redraws); the extras' copy of the loop advances
//! an event's discs along their parabolas before its handler runs, as in a uniform field.

use crate::cells::CellGrid;
use crate::error::Error;
use crate::events::Pending;
use crate::math::Vector;
use crate::predict::interval::interval_exit_accel_or_inf;
use crate::schedule::EventQueue;
use crate::state::{Gravity, SelfGravity};

use super::{Simulation, NO_PARTNER};

/// The self-gravity of a run: the coupling, each rod's rank and acceleration.
#[derive(Clone, Debug)]
pub(super) struct Sheets {
    pub(super) gravity: SelfGravity,
    /// Each disc's rank from the left, `0..n`.
    pub(super) rank: Vec<u32>,
    /// The disc at each rank.
    pub(super) order: Vec<u32>,
    /// Each disc's acceleration, `coupling (M_right - M_left)`.
    accel: Vec<f64>,
}

impl Sheets {
    /// The self-gravity of discs in `order` (left to right) with masses `mass`.
    pub(super) fn new(gravity: SelfGravity, order: Vec<u32>, mass: &[f64]) -> Self {
        let n = order.len();
        let mut rank = vec![0u32; n];
        let mut accel = vec![0.0; n];
        let total: f64 = order.iter().map(|&i| mass[i as usize]).sum();
        let mut left = 0.0;
        for (r, &i) in order.iter().enumerate() {
            let i = i as usize;
            rank[i] = r as u32;
            let right = (total - left - mass[i]).max(0.0);
            accel[i] = gravity.coupling * (right - left);
            left += mass[i];
        }
        Sheets {
            gravity,
            rank,
            order,
            accel,
        }
    }

    /// Disc `i`'s flight: a uniform field of its own along the line.
    #[inline(always)]
    pub(super) fn field(&self, i: usize) -> Gravity {
        Gravity {
            axis: 0,
            g: self.accel[i],
        }
    }

    /// Disc `i`'s neighbours on its left and right (`NO_PARTNER` at an end).
    #[inline(always)]
    pub(super) fn neighbours(&self, i: usize) -> [u32; 2] {
        let r = self.rank[i] as usize;
        let left = if r > 0 { self.order[r - 1] } else { NO_PARTNER };
        let right = self.order.get(r + 1).copied().unwrap_or(NO_PARTNER);
        [left, right]
    }

    pub(super) fn memory_bytes(&self) -> usize {
        self.rank.capacity() * 4 + self.order.capacity() * 4 + self.accel.capacity() * 8
    }
}

/// The time from now until a gap `y` (at least `sigma`, or a rounding error below), opening
/// at `w` and accelerated at `a < 0`, closes to `sigma`: always finite, as the pair attracts.
#[inline(always)]
pub(super) fn closing_time(y: f64, w: f64, a: f64, sigma: f64) -> f64 {
    interval_exit_accel_or_inf(y, w, a, sigma, f64::INFINITY).0
}

impl<const D: usize> Simulation<D> {
    /// Puts the discs under one-dimensional self-gravity from now on (`None`: none, the
    /// default). Refused with the reason unless the line has walls (the sheet model lives on
    /// an unbounded line: the walls hold it where its energy keeps it from going), and beside
    /// a uniform field, a stepped potential, reactions, restitution or multi-disc collisions.
    /// Each disc's rank is its place from the left now.
    pub fn set_self_gravity(&mut self, gravity: Option<SelfGravity>) -> Result<(), Error> {
        match gravity {
            Some(g) => {
                g.validate(D)?;
                self.self_gravity_fits()?;
            }
            // Nothing to undo; and the grid below is not the one a stepped potential's lists
            // or a ring need, which self-gravity does not go with.
            None if self.sheets.is_none() => return Ok(()),
            None => {}
        }
        let now = self.now;
        for i in 0..self.body.len() {
            let f = self.flight(i);
            self.body[i].advance_in(now, f);
        }
        self.event_time = now;
        self.sheets = gravity.map(|g| {
            let mut order: Vec<u32> = (0..self.body.len() as u32).collect();
            order.sort_by(|&a, &b| {
                let (pa, pb) = (self.body[a as usize].pos[0], self.body[b as usize].pos[0]);
                pa.total_cmp(&pb).then(a.cmp(&b))
            });
            Box::new(Sheets::new(g, order, &self.mass.to_vec()))
        });
        self.grid = self.sheets_grid(self.sheets.is_some())?;
        self.file_all_in_grid();
        let min_diameter = self
            .body
            .iter()
            .map(|b| 2.0 * b.radius)
            .fold(f64::INFINITY, f64::min);
        self.far_contacts = super::predict::far_contacts(&self.grid, &self.sim_box, min_diameter);
        self.creep_span = self.creep_span();
        self.schedule_all();
        Ok(())
    }

    /// The grid: one cell under self-gravity (its predictions never look at cells), else cells
    /// as wide as the largest diameter.
    fn sheets_grid(&self, sheets: bool) -> Result<CellGrid<D>, Error> {
        let n = self.body.len();
        let width = if sheets {
            self.sim_box.lengths[0]
        } else if n == 0 {
            1.0
        } else {
            self.body.iter().map(|b| 2.0 * b.radius).fold(0.0, f64::max)
        };
        CellGrid::new(&self.sim_box, n, width)
    }

    /// Refuses self-gravity with what it does not go with.
    pub(super) fn self_gravity_fits(&self) -> Result<(), Error> {
        let refuse = |what: &str| Err(Error::BadSelfGravity(what.to_string()));
        if self.sim_box.is_periodic(0) {
            return refuse(
                "self-gravity needs walls on the line: it pulls towards the mass on either side, which a periodic line does not have",
            );
        }
        if self.gravity.is_some() {
            return refuse("self-gravity does not go with a uniform field");
        }
        if self.steps.is_some() {
            return refuse("self-gravity does not go with a stepped potential");
        }
        if self.multi.is_some() {
            return refuse("self-gravity does not go with multi-disc collisions");
        }
        if self.chemistry.is_some() {
            return refuse("self-gravity does not go with reactions");
        }
        if self.dissipation.is_some() {
            return refuse("self-gravity does not go with inelastic collisions");
        }
        if self.rule != crate::CollisionRule::Elastic {
            return refuse("self-gravity needs the elastic collision rule");
        }
        Ok(())
    }

    /// The self-gravity, if any.
    pub fn self_gravity(&self) -> Option<SelfGravity> {
        self.sheets.as_deref().map(|s| s.gravity)
    }

    /// Disc `i`'s rank from the left under self-gravity (fixed: rods keep their order).
    pub fn rank(&self, i: usize) -> Option<usize> {
        self.sheets.as_deref().map(|s| s.rank[i] as usize)
    }

    /// Disc `i`'s acceleration, under self-gravity or a uniform field (0 along other axes).
    pub fn acceleration(&self, i: usize) -> Vector<D> {
        match self.flight(i) {
            Some(f) => super::field::acceleration::<D>(f),
            None => Vector::ZERO,
        }
    }

    /// The self-gravity's potential energy now: of the sheets the rods stand for, `sum over
    /// pairs coupling m_i m_j |y_i - y_j|` with `y` each rod's position less the contact
    /// distances of the pairs to its left (so that touching rods are sheets at one place).
    /// Worked out as `-sum m a y`, the accelerations summing to nothing with their masses; 0
    /// without self-gravity.
    pub fn self_gravity_energy(&self) -> f64 {
        match (self.sheets.as_deref(), self.sheet_positions()) {
            (Some(s), Some(y)) => (0..y.len())
                .map(|i| -self.mass[i] * s.accel[i] * y[i])
                .sum(),
            _ => 0.0,
        }
    }

    /// The sheets' positions now (see [`Self::self_gravity_energy`]), in input order; `None`
    /// without self-gravity.
    pub fn sheet_positions(&self) -> Option<Vec<f64>> {
        let s = self.sheets.as_deref()?;
        let mut y = vec![0.0; self.body.len()];
        let mut taken = 0.0;
        for (r, &i) in s.order.iter().enumerate() {
            let i = i as usize;
            if r > 0 {
                taken += self.body[s.order[r - 1] as usize].radius + self.body[i].radius;
            }
            y[i] = self.position_of(i, self.now)[0] - taken;
        }
        Some(y)
    }

    /// The fastest a disc can gain in speed across the box under self-gravity or a field,
    /// squared: `2 |a| L` for the largest acceleration.
    pub(super) fn fall_speed2(&self) -> f64 {
        match (self.sheets.as_deref(), self.gravity) {
            (Some(s), _) => {
                let a = s.accel.iter().fold(0.0f64, |m, a| m.max(a.abs()));
                2.0 * a * self.sim_box.lengths[0]
            }
            (None, Some(f)) => 2.0 * f.g.abs() * self.sim_box.lengths[f.axis],
            (None, None) => 0.0,
        }
    }

    /// Disc `i`'s earliest event of its own under self-gravity (a wall or a redraw), from
    /// `pos` and `vel` at its own clock `t0`. Predictions and [`Self::own_event`] both take it.
    #[inline(always)]
    pub(super) fn own_event_sheets(
        &self,
        i: usize,
        t0: f64,
        pos: Vector<D>,
        vel: Vector<D>,
        s: &Sheets,
    ) -> (f64, Pending) {
        let radius = self.body[i].radius;
        let (dt, high) = interval_exit_accel_or_inf(
            pos[0],
            vel[0],
            s.accel[i],
            radius,
            self.sim_box.lengths[0] - radius,
        );
        let (best_t, best) = if dt == f64::INFINITY {
            (f64::INFINITY, Pending::Nothing)
        } else {
            (
                t0 + dt,
                Pending::Wall {
                    axis: 0,
                    side: if high {
                        crate::Side::High
                    } else {
                        crate::Side::Low
                    },
                },
            )
        };
        self.bath_event(i, best_t, best)
    }

    /// [`Self::predict`] under self-gravity: the disc advanced along its parabola, its own
    /// events, and its two neighbours in order at their positions and velocities now.
    #[inline(always)]
    pub(super) fn predict_sheets(&mut self, i: usize) {
        let t0 = self.event_time;
        let s = self.sheets.as_deref().expect("self-gravity");
        self.body[i].advance_in(t0, Some(s.field(i)));
        let (pos, vel, radius) = {
            let b = &self.body[i];
            (b.pos, b.vel, b.radius)
        };
        let (mut best_t, own) = self.own_event_sheets(i, t0, pos, vel, s);
        let mut partner = NO_PARTNER;
        let [left, right] = s.neighbours(i);
        for (j, sign) in [(left, -1.0), (right, 1.0)] {
            if j == NO_PARTNER {
                continue;
            }
            let ju = j as usize;
            let bj = &self.body[ju];
            let fj = Some(s.field(ju));
            let (pj, vj) = (bj.position_in(t0, fj), bj.velocity_in(t0, fj));
            let t = t0
                + closing_time(
                    sign * (pj[0] - pos[0]),
                    sign * (vj[0] - vel[0]),
                    sign * (s.accel[ju] - s.accel[i]),
                    radius + bj.radius,
                );
            if t < best_t {
                best_t = t;
                partner = j;
            }
        }
        self.schedule(i, own, (best_t, partner, f64::INFINITY, NO_PARTNER));
    }

    /// [`Self::missed_contact`] under self-gravity: each pair of neighbours in order, its
    /// closing time against the earlier of the times either looks at the other again, and the
    /// gap then, with the same allowance for rounding.
    pub(super) fn missed_contact_sheets(&self, s: &Sheets) -> Option<(usize, usize, f64, f64)> {
        let t0 = self.event_time;
        let longest = self.sim_box.lengths[0];
        for w in s.order.windows(2) {
            let (i, j) = (w[0] as usize, w[1] as usize);
            let (pi, vi) = (self.position_of(i, t0), self.velocity_of(i, t0));
            let (pj, vj) = (self.position_of(j, t0), self.velocity_of(j, t0));
            let (y, v, a) = (pj[0] - pi[0], vj[0] - vi[0], s.accel[j] - s.accel[i]);
            let sigma = self.body[i].radius + self.body[j].radius;
            let allowed = |dt: f64, t: f64| {
                let speeds = vi.norm2().sqrt() + vj.norm2().sqrt() + (a * dt).abs();
                sigma * (1.0 - super::OVERLAP_TOLERANCE)
                    - super::OVERLAP_ROUNDING * (longest + speeds * t.abs())
            };
            // Out of order, or through each other, already.
            if y < allowed(0.0, t0) {
                return Some((i, j, t0, t0));
            }
            let t_contact = t0 + closing_time(y, v, a, sigma);
            let again = self.queue.get(i).min(self.queue.get(j));
            if again <= t_contact {
                continue;
            }
            let dt = again - t0;
            if y + v * dt + 0.5 * a * dt * dt < allowed(dt, again) {
                return Some((i, j, t_contact, again));
            }
        }
        None
    }
}
