//! A patch of a planetary ring (see [`crate::state::ring`]): flights under Hill's equations
//! in a shearing-periodic box.
//!
//! The ring is the Lees-Edwards boundaries of `shear.rs` at the rate `-3/2 Omega`, with the
//! flights of `predict/hill.rs` in place of straight lines. The images across y are flights
//! too (Hill's equations are linear, and the Keplerian flow is one of their solutions), so
//! the scans and the collisions across the boundary are the shear's, with the candidates at
//! their images' positions and velocities.
//!
//! - **Contacts** have no closed form: a pair's contact time is bracketed from below
//!   (`hill::contact_time`) and looked for only up to the disc's next event of its own and
//!   the earliest contact found so far. A search that does not settle within its steps
//!   leaves a `Pending::Recheck` at the time it reached, where the disc is predicted again.
//! - **The grid.** Exact cell-crossing times would need the roots of `x(t)`, which has no
//!   closed form either. Instead the cells are wider than the largest diameter by a margin on
//!   each side (`Orbits::margin`), and a disc is filed again (`Pending::Refile`) at a time
//!   bracketed from below before it strays a margin out of its cell: then every disc is
//!   within a margin of its cell, so two discs in contact are still in neighbouring cells.
//!   A refile takes a disc across the box's edges (and across y to the slid images).
//! - **Walls** along z (3D) are met at the times `hill::edge_time` brackets, to `1e-12` of
//!   the radius.
//! - Every disc is looked at again at least every `1/(2 Omega)` (the bounds on the flights'
//!   curvature, and the steps of the searches, stay small).

use crate::error::Error;
use crate::events::{EventKind, EventRecord, Pending, Side};
use crate::math::Vector;
use crate::predict::hill::{self, Edge, Found};
use crate::state::{Boundary, Ring, Shear, SimBox};

use super::predict::Nearest;
use super::shear::LeesEdwards;
use super::{Body, Simulation, NO_PARTNER};
use crate::cells::{CellGrid, Visit};

/// How much wider than the largest diameter the ring's cells are, at least: a margin of a
/// tenth of it on each side.
const CELL_SLACK: f64 = 1.2;

/// The ring's grid: in the plane, cells as narrow as [`CELL_SLACK`] diameters allow while
/// there are no more than two per disc; along z (3D) one cell. A patch is a thin layer in a
/// tall box, and a grid sized for the box's volume put a few cells' worth of discs in each
/// mid-plane cell (60 candidates per prediction at 1000 spheres).
pub(super) fn ring_grid<const D: usize>(
    sim_box: &SimBox<D>,
    n: usize,
    reach: f64,
) -> Result<CellGrid<D>, Error> {
    let narrowest = CELL_SLACK * reach;
    let area = sim_box.lengths[0] * sim_box.lengths[1];
    let sparse = (area / (2.0 * n.max(1) as f64)).sqrt();
    let mut counts = [1u64; D];
    for a in 0..2 {
        let most = (sim_box.lengths[a] / narrowest).floor();
        if most.is_nan() || most < 3.0 {
            return Err(Error::BadRing(format!(
                "the patch is {} across (axis {a}), too small for particles {reach} across: it takes at least {} ({CELL_SLACK} diameters for each of 3 cells)",
                sim_box.lengths[a],
                3.0 * narrowest
            )));
        }
        let fit = (sim_box.lengths[a] / sparse).floor();
        counts[a] = fit.clamp(3.0, most.min(u32::MAX as f64 / 4.0)) as u64;
    }
    // Within the grid's budget: in a long box three cells across the short side can leave
    // the long side more than its share.
    let budget = CellGrid::<D>::max_cells(n) as u64;
    while counts[0] * counts[1] > budget && counts[0].max(counts[1]) > 3 {
        let a = if counts[0] >= counts[1] { 0 } else { 1 };
        counts[a] = (budget / counts[1 - a]).clamp(3, counts[a] - 1);
    }
    CellGrid::with_counts(sim_box, n, counts)
}

/// The ring's state: the orbital frequency, the patch's centre and the cells' margins.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Orbits {
    pub(super) ring: Ring,
    /// The patch's centre: `L_y / 2` radially, `L_z / 2` vertically (0 along x).
    pub(super) centre: [f64; 3],
    /// How far a disc may stray out of its cell along each axis before it is filed again.
    pub(super) margin: [f64; 3],
    /// The longest a disc goes without a prediction, `1 / (2 Omega)`.
    pub(super) horizon: f64,
}

impl Orbits {
    pub(super) fn new<const D: usize>(
        ring: Ring,
        sim_box_lengths: [f64; D],
        grid: &CellGrid<D>,
        reach: f64,
    ) -> Self {
        let dims = grid.dims();
        let mut centre = [0.0; 3];
        let mut margin = [0.0; 3];
        for a in 0..D {
            if a > 0 {
                centre[a] = 0.5 * sim_box_lengths[a];
            }
            let width = sim_box_lengths[a] / f64::from(dims[a]);
            margin[a] = 0.5 * (width - reach);
        }
        Orbits {
            ring,
            centre,
            margin,
            horizon: 0.5 / ring.omega,
        }
    }

    /// A position relative to the patch's centre.
    #[inline(always)]
    fn local<const D: usize>(&self, mut p: Vector<D>) -> Vector<D> {
        for a in 1..D {
            p[a] -= self.centre[a];
        }
        p
    }

    /// A position relative to the centre back in the box's frame.
    #[inline(always)]
    fn global<const D: usize>(&self, mut p: Vector<D>) -> Vector<D> {
        for a in 1..D {
            p[a] += self.centre[a];
        }
        p
    }
}

impl<const D: usize> Body<D> {
    /// The position and velocity at `t` along the disc's flight under Hill's equations.
    #[inline(always)]
    pub(super) fn on_orbit(&self, t: f64, o: &Orbits) -> (Vector<D>, Vector<D>) {
        // At its own clock, the record itself (through the centre and back would move the
        // last bits).
        if t == self.time {
            return (self.pos, self.vel);
        }
        let (q, w) = hill::advance(o.local(self.pos), self.vel, o.ring.omega, t - self.time);
        (o.global(q), w)
    }

    /// Moves the disc's clock to `t` along its flight.
    #[inline(always)]
    pub(super) fn advance_on_orbit(&mut self, t: f64, o: &Orbits) {
        let (p, v) = self.on_orbit(t, o);
        self.pos = p;
        self.vel = v;
        self.time = t;
    }
}

impl<const D: usize> Simulation<D> {
    /// Makes the system a patch of a planetary ring from now on (`None`: none, the default):
    /// flights under Hill's equations at the orbital frequency `ring.omega` (x along the
    /// orbit, y radial, z vertical, measured from the box's centre), and Lees-Edwards
    /// boundaries at the Keplerian shear rate `-3/2 Omega` (the images' offset kept if the
    /// system was sheared, else 0). The velocities are not changed: to start on the Keplerian
    /// flow, add `-3/2 Omega (y - L_y / 2)` to each x velocity ([`Self::modify_velocities`]).
    /// Refused with the reason unless x and y are periodic (and z, in 3D, has walls), and
    /// beside a field, self-gravity, a stepped potential, barriers or multi-disc collisions.
    /// `None` after a ring takes its shear away too.
    pub fn set_ring(&mut self, ring: Option<Ring>) -> Result<(), Error> {
        if let Some(r) = ring {
            r.validate(D)?;
            self.ring_fits()?;
        }
        let now = self.now;
        let had = self.ring.is_some();
        if let Some(o) = self.ring.take() {
            for b in self.body.iter_mut() {
                b.advance_on_orbit(now, &o);
            }
            self.shear = None;
        }
        for b in self.body.iter_mut() {
            b.advance_to(now);
        }
        self.event_time = now;
        let reach = self
            .body
            .iter()
            .map(|b| 2.0 * b.radius)
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        let n = self.body.len();
        let Some(r) = ring else {
            if !had {
                return Ok(());
            }
            self.grid = CellGrid::new(&self.sim_box, n, if n == 0 { 1.0 } else { reach })?;
            self.fold_into_box();
            self.file_all_in_grid();
            self.creep_span = self.creep_span();
            self.schedule_all();
            return Ok(());
        };
        let offset = self.shear().map_or(0.0, |s| s.offset);
        let old = (self.grid.clone(), self.shear.take());
        self.grid = ring_grid(&self.sim_box, n, reach)?;
        self.ring = Some(Box::new(Orbits::new(
            r,
            self.sim_box.lengths,
            &self.grid,
            reach,
        )));
        let s = Shear {
            rate: r.shear_rate(),
            offset,
        };
        self.shear = Some(Box::new(LeesEdwards::new(
            s,
            now,
            self.grid.dims()[0],
            self.sim_box.lengths,
        )));
        self.fold_into_box();
        self.file_all_in_grid();
        let report = self.overlaps(super::OVERLAP_TOLERANCE);
        if let Some((i, j, overlap)) = report.first {
            self.ring = None;
            (self.grid, self.shear) = old;
            self.file_all_in_grid();
            self.schedule_all();
            return Err(Error::BadRing(format!(
                "discs {i} and {j} overlap across the sheared boundary by {:.3e} of their contact distance ({} pairs)",
                overlap, report.count
            )));
        }
        self.far_contacts = false;
        self.creep_span = self.creep_span();
        self.schedule_all();
        Ok(())
    }

    /// Refuses a ring with what it does not go with.
    pub(super) fn ring_fits(&self) -> Result<(), Error> {
        let refuse = |what: &str| Err(Error::BadRing(what.to_string()));
        if D < 2
            || self.sim_box.boundaries[0] != Boundary::Periodic
            || self.sim_box.boundaries[1] != Boundary::Periodic
        {
            return refuse("a ring patch needs periodic x (along the orbit) and y (radial) axes");
        }
        if D > 2 && self.sim_box.boundaries[2] == Boundary::Periodic {
            return refuse(
                "a ring patch needs walls along z: the vertical pull is towards the mid-plane, which a periodic axis does not have",
            );
        }
        if self.steps.is_some() {
            return refuse("a ring does not go with a stepped potential");
        }
        if self.gravity.is_some() {
            return refuse("a ring does not go with a uniform field");
        }
        if self.sheets.is_some() {
            return refuse("a ring does not go with self-gravity");
        }
        if !self.barriers.is_empty() {
            return refuse("a ring does not go with barriers");
        }
        if self.multi.is_some() {
            return refuse("a ring does not go with multi-disc collisions");
        }
        Ok(())
    }

    /// The ring, if any.
    pub fn ring(&self) -> Option<Ring> {
        self.ring.as_deref().map(|o| o.ring)
    }

    /// The ring's potential energy now, `sum m (-3/2 Omega^2 y^2 + Omega^2 z^2 / 2)` with y
    /// and z from the patch's centre (0 without a ring): the tidal and vertical potential of
    /// Hill's equations, whose sum with the kinetic energy (the Jacobi integral) flights and
    /// elastic collisions conserve. Crossings of the sheared boundary change it (the shear
    /// heats the patch), and so do inelastic collisions.
    pub fn ring_energy(&self) -> f64 {
        let Some(o) = self.ring.as_deref() else {
            return 0.0;
        };
        let w2 = o.ring.omega * o.ring.omega;
        (0..self.len())
            .map(|i| {
                let p = o.local(self.observed(i, self.now).0);
                let z2 = if D > 2 { p[2] * p[2] } else { 0.0 };
                self.mass[i] * w2 * (-1.5 * p[1] * p[1] + 0.5 * z2)
            })
            .sum()
    }

    /// Disc `i`'s position and velocity at `t` as the box shows them: a disc a margin across
    /// the y boundary (not yet filed again) at its image in the box, slid and moving with
    /// the images, and x folded into the box.
    pub(super) fn observed(&self, i: usize, t: f64) -> (Vector<D>, Vector<D>) {
        let o = self.ring.as_deref().expect("a ring");
        let (mut p, mut v) = self.body[i].on_orbit(t, o);
        let [lx, ly] = [self.sim_box.lengths[0], self.sim_box.lengths[1]];
        if !(0.0..ly).contains(&p[1]) {
            let sign = if p[1] >= ly { -1.0 } else { 1.0 };
            p[1] = (p[1] + sign * ly).clamp(0.0, ly.next_down());
            if let Some(s) = self.shear.as_deref() {
                p[0] += sign * s.offset(t);
                v[0] += sign * s.speed;
            }
        }
        p[0] = (p[0] - lx * (p[0] / lx).floor()).clamp(0.0, lx.next_down());
        (p, v)
    }

    /// Brings every disc's record into the box (x and y), across y to the slid images: a
    /// disc's record may lie a cell's margin outside it under a ring. Records at the same
    /// clock only.
    fn fold_into_box(&mut self) {
        for i in 0..self.body.len() {
            self.fold(i, self.body[i].time);
        }
    }

    /// Folds disc `i`'s record into the box at its clock `t`; returns the axis and side of
    /// the last fold (`None`: none).
    fn fold(&mut self, i: usize, t: f64) -> Option<(usize, Side)> {
        let mut folded = None;
        let [lx, ly] = [self.sim_box.lengths[0], self.sim_box.lengths[1]];
        let y = self.body[i].pos[1];
        if self.sim_box.is_periodic(1) && !(0.0..ly).contains(&y) {
            // Up through the top: to the images below, `-delta` and `-gamma L_y` (as
            // `cross_sheared`).
            let up = y >= ly;
            let sign = if up { -1.0 } else { 1.0 };
            let b = &mut self.body[i];
            b.pos[1] += sign * ly;
            b.pos[1] = b.pos[1].clamp(0.0, ly.next_down());
            self.image.add(i, 1, -(sign as i32));
            if let Some(s) = self.shear.as_deref() {
                let slid = s.slide(t) / lx;
                let whole = slid.floor();
                let offset = s.offset(t);
                let b = &mut self.body[i];
                b.pos[0] += sign * offset;
                b.vel[0] += sign * s.speed;
                self.image.add(i, 0, (sign * whole) as i32);
            }
            folded = Some((1, if up { Side::High } else { Side::Low }));
        }
        let x = self.body[i].pos[0];
        if self.sim_box.is_periodic(0) && !(0.0..lx).contains(&x) {
            let wraps = (x / lx).floor();
            let b = &mut self.body[i];
            b.pos[0] = (x - wraps * lx).clamp(0.0, lx.next_down());
            self.image.add(i, 0, wraps as i32);
            folded = Some((0, if wraps > 0.0 { Side::High } else { Side::Low }));
        }
        folded
    }

    /// Disc `i` filed again at `t` (its `Pending::Refile` or `Pending::Recheck`): folded into
    /// the box if it strayed out, and into the cell its position is in. Reported as a cell
    /// crossing (along the axis it left the box, or the first axis its cell changed on).
    #[inline(never)]
    pub(super) fn refile(&mut self, i: usize, t: f64) -> EventRecord<D> {
        let o = self.ring.as_deref().expect("a ring");
        self.body[i].advance_on_orbit(t, o);
        let folded = self.fold(i, t);
        let old = self.grid.cell_of(i);
        let c = self.grid.coord_of(self.body[i].pos);
        let mut moved = folded;
        if c != old {
            self.grid.remove(i);
            self.grid.insert(i, c);
            if moved.is_none() {
                let a = (0..D).find(|&a| c[a] != old[a]).unwrap_or(0);
                moved = Some((a, if c[a] > old[a] { Side::High } else { Side::Low }));
            }
        }
        self.stats.cell_crossing = self.stats.cell_crossing.wrapping_add(1);
        let (axis, side) = moved.unwrap_or((0, Side::High));
        EventRecord {
            time: t,
            kind: EventKind::CellCrossing { i, axis, side },
            impulse: Vector::ZERO,
        }
    }

    /// Disc `i`'s own events on a ring from `pos` and `vel` at its clock `t0`: a wall along z,
    /// the end of the shear's epoch in a boundary row, a redraw, and its refiling (before it
    /// strays a margin out of its cell, and at the latest after [`Orbits::horizon`]).
    /// Predictions and [`Self::own_event`] both take it, so they agree to the bit.
    pub(super) fn own_event_ring(
        &self,
        i: usize,
        t0: f64,
        pos: Vector<D>,
        vel: Vector<D>,
    ) -> (f64, Pending) {
        let o = self.ring.as_deref().expect("a ring");
        let omega = o.ring.omega;
        let (mut best_t, mut best) = (t0 + o.horizon, Pending::Refile);
        if self.in_boundary_row(i) {
            let s = self.shear.as_deref().expect("shear");
            let (_, _, end) = s.epoch(t0);
            if end < best_t {
                best_t = end;
                best = Pending::Slide;
            }
        }
        (best_t, best) = self.bath_event(i, best_t, best);
        let p = o.local(pos);
        let radius = self.body[i].radius;
        for a in 2..D {
            for high in [false, true] {
                let edge = if high {
                    self.sim_box.lengths[a] - radius
                } else {
                    radius
                } - o.centre[a];
                let edge = Edge {
                    axis: a,
                    at: edge,
                    high,
                };
                match hill::edge_time(p, vel, omega, edge, 1e-12 * radius, best_t - t0) {
                    Found::At(dt) => {
                        best_t = t0 + dt;
                        best = Pending::Wall {
                            axis: a as u8,
                            side: if high { Side::High } else { Side::Low },
                        };
                    }
                    Found::Unresolved(dt) => {
                        best_t = t0 + dt;
                        best = Pending::Refile;
                    }
                    Found::Never => {}
                }
            }
        }
        // Filed again before it strays a margin out of its cell: the searches stop within
        // half the margin of that edge (a time before it, all the same).
        let c = self.grid.cell_of(i);
        let dims = self.grid.dims();
        for a in 0..D {
            if !self.sim_box.is_periodic(a) && dims[a] == 1 {
                continue;
            }
            let width = self.sim_box.lengths[a] / f64::from(dims[a]);
            let m = o.margin[a];
            let lo = f64::from(c[a]) * width - m - o.centre[a];
            let hi = f64::from(c[a] + 1) * width + m - o.centre[a];
            for (edge, high) in [(lo, false), (hi, true)] {
                let edge = Edge {
                    axis: a,
                    at: edge,
                    high,
                };
                match hill::edge_time(p, vel, omega, edge, 0.5 * m, best_t - t0) {
                    Found::At(dt) | Found::Unresolved(dt) => {
                        best_t = t0 + dt;
                        best = Pending::Refile;
                    }
                    Found::Never => {}
                }
            }
        }
        (best_t, best)
    }

    /// [`Self::predict`] on a ring: the disc's own events from [`Self::own_event_ring`], and
    /// its candidates (across the y boundary at their slid images) at the contact times
    /// `hill::contact_time` brackets, each looked for only as far as the earliest event so
    /// far. In 3D no second event is kept: the searches stop at the first.
    pub(super) fn predict_ring(&mut self, i: usize) {
        let t0 = self.event_time;
        let o = self.ring.as_deref().expect("a ring").clone();
        self.body[i].advance_on_orbit(t0, &o);
        let (pos, vel, radius) = {
            let b = &self.body[i];
            (b.pos, b.vel, b.radius)
        };
        let (best_t, best) = self.own_event_ring(i, t0, pos, vel);
        let nearest = Nearest::new(t0, best_t, &mut self.kept);
        let c = self.grid.cell_of(i);
        let mut scan = RingCandidates::<D> {
            body: &self.body,
            orbits: &o,
            i,
            t0,
            pos,
            vel,
            radius,
            dv: Vector::ZERO,
            recheck: f64::INFINITY,
            nearest,
        };
        let rows = self.grid.dims()[1];
        if c[1] == 0 || c[1] + 1 == rows {
            let s = self.shear.as_deref().expect("shear");
            let grid = &self.grid;
            super::shear::cells_across(grid, s, c, t0, |cell, shift, dv| {
                scan.dv = dv;
                grid.visit_cell(cell, shift, &mut &mut scan);
            });
        } else {
            self.grid.visit_near(c, &mut scan);
        }
        let recheck = scan.recheck;
        let (t, partner, _, _) = scan.nearest.settle();
        if recheck < t {
            self.schedule(
                i,
                Pending::Recheck,
                (recheck, NO_PARTNER, f64::INFINITY, NO_PARTNER),
            );
        } else {
            self.schedule(i, best, (t, partner, f64::INFINITY, NO_PARTNER));
        }
        if D == 3 {
            self.second[i] = (f64::INFINITY, Pending::Nothing);
        }
    }

    /// Whether a pair that [`Self::missed_contact`] looks at, `dr` apart and closing at `dv`
    /// at `t0`, comes to contact `sigma` on the ring before `again`: the time, if so.
    pub(super) fn ring_contact_before(
        &self,
        dr: Vector<D>,
        dv: Vector<D>,
        sigma: f64,
        t0: f64,
        again: f64,
    ) -> Option<f64> {
        let o = self.ring.as_deref()?;
        match hill::contact_time(dr, dv, sigma, o.ring.omega, again - t0) {
            Found::At(dt) if t0 + dt < again => Some(t0 + dt),
            _ => None,
        }
    }
}

/// A prediction's candidates on a ring: each at its image's position and velocity at `t0`.
struct RingCandidates<'a, const D: usize> {
    body: &'a [Body<D>],
    orbits: &'a Orbits,
    i: usize,
    t0: f64,
    pos: Vector<D>,
    vel: Vector<D>,
    radius: f64,
    /// The images' extra velocity across the y boundary.
    dv: Vector<D>,
    /// The earliest time a search stopped unsettled.
    recheck: f64,
    nearest: Nearest<'a>,
}

impl<const D: usize> Visit<D> for &mut RingCandidates<'_, D> {
    #[inline(always)]
    fn visit(&mut self, j: usize, shift: Vector<D>) {
        if j == self.i {
            return;
        }
        let bj = &self.body[j];
        let (pj, vj) = bj.on_orbit(self.t0, self.orbits);
        let horizon = self.nearest.best_t().min(self.recheck) - self.t0;
        match hill::contact_time(
            pj + shift - self.pos,
            vj + self.dv - self.vel,
            self.radius + bj.radius,
            self.orbits.ring.omega,
            horizon,
        ) {
            Found::At(dt) => self.nearest.take(self.t0 + dt, j as u32),
            Found::Unresolved(dt) => self.recheck = self.recheck.min(self.t0 + dt),
            Found::Never => {}
        }
    }
}
