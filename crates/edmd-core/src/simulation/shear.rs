//! Lees-Edwards boundaries (see [`crate::state::shear`]): the images across y slide along x.
//!
//! Positions stay in the box and velocities are the lab frame's; what the images change is
//! handled where pairs across the y boundary meet:
//!
//! - **Predictions.** A disc in the top or bottom row of cells scans, across the boundary, the
//!   four columns (times three along z) of the other row whose slid images can come within a
//!   cell width of its own column while the images slide by at most one more cell
//!   (`CellGrid::for_each_cell_sheared`), each candidate at its image's position and velocity
//!   (`+-gamma L_y` along x): the relative motion is straight, so contact times are the hard
//!   cores' closed form. The slide is cut into epochs, one per cell width slid, and each disc
//!   in a boundary row has the epoch's end as an event of its own (`Pending::Slide`), so that
//!   it scans again before a pair it did not scan can come within reach: for a pair across the
//!   boundary that meets at `t_c`, the later of the two discs' last events before `t_c` (slides
//!   included) saw the other in its scan.
//! - **Collisions across the boundary** take the partner at its image (`collide_sheared`),
//!   whatever the rule (elastic, inelastic, reactive).
//! - **Crossing the boundary** shifts the disc's x by `-+delta` and its x velocity by
//!   `-+gamma L_y`, and files it in its new column (`cross_sheared`).
//!
//! The epochs are worked out from the time alone (`LeesEdwards::epoch`), so that a prediction
//! and the checkpoint reader's [`Simulation::own_event`] agree to the bit, and so that the
//! epoch a prediction scans for always runs on past its time.

use crate::error::Error;
use crate::events::{EventKind, EventRecord, Pending, Side};
use crate::math::Vector;
use crate::state::{Boundary, Shear};

use super::predict::Nearest;
use super::{Body, Simulation};
use crate::cells::{CellGrid, Visit};
use crate::predict::contact_terms;

/// The shear's state: the rate, and the slide of the images as a function of time.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct LeesEdwards {
    /// `gamma`.
    pub(super) rate: f64,
    /// The time from which `start` counts.
    pub(super) origin: f64,
    /// Cells slid at `origin`, in `[0, columns)`.
    pub(super) start: f64,
    /// `gamma L_y`: the images' speed along x relative to the box (above; below its negative).
    pub(super) speed: f64,
    /// Cell widths slid per unit time, `gamma L_y / w`.
    per_time: f64,
    /// Width of the grid's columns along x.
    width: f64,
    /// Columns along x.
    columns: u32,
    /// The box's height, `L_y`.
    height: f64,
}

impl LeesEdwards {
    /// The shear `s` set at time `origin` in a grid of `columns` columns over `lengths`.
    pub(super) fn new<const D: usize>(
        s: Shear,
        origin: f64,
        columns: u32,
        lengths: [f64; D],
    ) -> Self {
        let width = lengths[0] / f64::from(columns);
        let speed = s.rate * lengths[1];
        LeesEdwards {
            rate: s.rate,
            origin,
            // An offset a hair below `L_x` can round to a whole turn of columns: the slide is
            // kept in `[0, columns)`, as the checkpoint reader requires, by at most an ulp.
            start: (s.offset / width).clamp(0.0, f64::from(columns).next_down()),
            speed,
            per_time: speed / width,
            width,
            columns,
            height: lengths[1],
        }
    }

    /// Cells slid at `t` (not reduced: grows without bound with `t`).
    #[inline(always)]
    fn slid(&self, t: f64) -> f64 {
        self.start + (t - self.origin) * self.per_time
    }

    /// The images' offset above at `t`, in `[0, L_x]`.
    pub(super) fn offset(&self, t: f64) -> f64 {
        let s = self.slid(t);
        let n = f64::from(self.columns);
        (s - n * (s / n).floor()) * self.width
    }

    /// The images' offset at `t` not reduced modulo `L_x`: how far they have slid since the
    /// shear was set, plus its offset then.
    pub(super) fn slide(&self, t: f64) -> f64 {
        self.slid(t) * self.width
    }

    /// The epoch a prediction at `t` scans for: `(k mod columns, frac, end)`, the images
    /// having slid `k + frac` cells at `t`, and staying within `[k, k + 1]` cells until `end`,
    /// which is later than `t` (`+inf` at rate 0). At an epoch's end itself (the disc's
    /// `Pending::Slide`) the next epoch is taken even where rounding puts the slide a hair
    /// short of it, so that the next end is always ahead.
    #[inline(always)]
    pub(super) fn epoch(&self, t: f64) -> (i64, f64, f64) {
        let s = self.slid(t);
        let mut k = s.floor();
        let end = |k: f64| {
            let edge = if self.per_time > 0.0 { k + 1.0 } else { k };
            self.origin + (edge - self.start) / self.per_time
        };
        let mut t_end = f64::INFINITY;
        if self.per_time != 0.0 {
            t_end = end(k);
            if t_end <= t {
                k += self.per_time.signum();
                t_end = end(k);
            }
        }
        let n = f64::from(self.columns);
        let k_mod = (k - n * (k / n).floor()) as i64 % i64::from(self.columns);
        (k_mod, s - k, t_end)
    }

    /// The streaming velocity along x at height `y`, `gamma (y - L_y / 2)`.
    #[inline(always)]
    pub(super) fn stream(&self, y: f64) -> f64 {
        self.rate * (y - 0.5 * self.height)
    }
}

/// Calls `f(cell, shift, dv)` for every cell a disc in cell `c` of a boundary row scans at `t`:
/// its own side's cells, and across y the slid images' columns for the epoch at `t`
/// ([`CellGrid::for_each_cell_sheared`]), each with its image shift and the images' extra
/// velocity (`+-gamma L_y` along x across the boundary, zero on its own side).
#[inline(always)]
pub(super) fn cells_across<const D: usize>(
    grid: &CellGrid<D>,
    s: &LeesEdwards,
    c: [u32; D],
    t: f64,
    mut f: impl FnMut(usize, Vector<D>, Vector<D>),
) {
    let (k, frac, _) = s.epoch(t);
    let above = c[1] + 1 == grid.dims()[1];
    let mut dv = Vector::ZERO;
    dv[0] = if above { s.speed } else { -s.speed };
    grid.for_each_cell_sheared(c, above, k, frac, |cell, shift, across| {
        f(cell, shift, if across { dv } else { Vector::ZERO })
    });
}

impl<const D: usize> Simulation<D> {
    /// Shears the system from now on with Lees-Edwards boundaries (`None`: plain periodic
    /// boundaries, the default): flow along x, gradient along y, the images across y sliding
    /// at `shear.rate * L_y` from an offset `shear.offset` now. Refused with the reason for
    /// shear that cannot be ([`Shear::validate`]), with walls on x or y, beside a stepped
    /// potential, a field, barriers or multi-disc collisions, and where the images at the
    /// offset given overlap the discs. Velocities are not changed: to start on the streaming
    /// profile, add `rate * (y - L_y / 2)` to each x velocity ([`Self::modify_velocities`]).
    pub fn set_shear(&mut self, shear: Option<Shear>) -> Result<(), Error> {
        if let Some(s) = shear {
            s.validate(D, self.sim_box.lengths[0])?;
            self.shear_fits()?;
        }
        let now = self.now;
        for b in self.body.iter_mut() {
            b.advance_to(now);
        }
        self.event_time = now;
        let old = self.shear.take();
        self.shear = shear.map(|s| {
            Box::new(LeesEdwards::new(
                s,
                now,
                self.grid.dims()[0],
                self.sim_box.lengths,
            ))
        });
        let report = self.overlaps(super::OVERLAP_TOLERANCE);
        if let Some((i, j, overlap)) = report.first {
            self.shear = old;
            self.schedule_all();
            return Err(Error::BadShear(format!(
                "at this offset discs {i} and {j} overlap across the boundary by {:.3e} of their contact distance ({} pairs)",
                overlap, report.count
            )));
        }
        self.creep_span = self.creep_span();
        self.schedule_all();
        Ok(())
    }

    /// Refuses shear with what it does not go with.
    pub(super) fn shear_fits(&self) -> Result<(), Error> {
        let refuse = |what: &str| Err(Error::BadShear(what.to_string()));
        if D < 2
            || self.sim_box.boundaries[0] != Boundary::Periodic
            || self.sim_box.boundaries[1] != Boundary::Periodic
        {
            return refuse("Lees-Edwards boundaries need periodic x and y axes");
        }
        if self.steps.is_some() {
            return refuse("shear does not go with a stepped potential");
        }
        if self.gravity.is_some() {
            return refuse("shear does not go with a field");
        }
        if !self.barriers.is_empty() {
            return refuse("shear does not go with barriers");
        }
        if self.multi.is_some() {
            return refuse("shear does not go with multi-disc collisions");
        }
        if self.ring.is_some() {
            return refuse("a ring sets its own shear, at -3/2 times its orbital frequency");
        }
        Ok(())
    }

    /// The shear, if any, with the images' offset now.
    pub fn shear(&self) -> Option<Shear> {
        self.shear.as_deref().map(|s| Shear {
            rate: s.rate,
            offset: s.offset(self.now).min(self.sim_box.lengths[0].next_down()),
        })
    }

    /// The streaming velocity at `p` (zero without shear): `gamma (y - L_y / 2)` along x.
    pub fn streaming_velocity(&self, p: Vector<D>) -> Vector<D> {
        let mut u = Vector::ZERO;
        if let Some(s) = self.shear.as_deref() {
            u[0] = s.stream(p[1]);
        }
        u
    }

    /// Disc `i`'s velocity relative to the streaming profile now (its velocity without shear).
    /// Taken at the height the disc's record holds, not folded into the box: just after a
    /// crossing of the boundary that height can be a rounding error outside, and the velocity
    /// is that of the image it is in (folded, the profile would be off by `gamma L_y`).
    pub fn peculiar_velocity(&self, i: usize) -> Vector<D> {
        if self.ring.is_some() {
            let (p, v) = self.observed(i, self.now);
            return v - self.streaming_velocity(p);
        }
        let p = self.position_of(i, self.now);
        self.velocity(i) - self.streaming_velocity(p)
    }

    /// The kinetic energy of the velocities relative to the streaming profile,
    /// `sum m |v - u(y)|^2 / 2` ([`Self::kinetic_energy`] without shear).
    pub fn peculiar_kinetic_energy(&self) -> f64 {
        (0..self.len())
            .map(|i| 0.5 * self.mass[i] * self.peculiar_velocity(i).norm2())
            .sum()
    }

    /// The separation `r_j - r_i` of discs `i` and `j` at the current time, and `v_j - v_i`,
    /// between `i` and `j`'s nearest image (under shear, the images across y slid and moving).
    pub fn separation(&self, i: usize, j: usize) -> (Vector<D>, Vector<D>) {
        let t = self.now;
        let (pi, pj) = (self.position_of(i, t), self.position_of(j, t));
        let (vi, vj) = (self.velocity_of(i, t), self.velocity_of(j, t));
        let (shift, dv) = self.image_across(pi, pj, t);
        (self.sim_box.minimum_image(pj + shift - pi), vj + dv - vi)
    }

    /// Under shear, the shift of position and of velocity that takes a disc at `pj` to its
    /// image across y nearest `pi` at `t`, when they are more than half the box apart along y;
    /// zero otherwise.
    #[inline(always)]
    pub(super) fn image_across(
        &self,
        pi: Vector<D>,
        pj: Vector<D>,
        t: f64,
    ) -> (Vector<D>, Vector<D>) {
        let (mut shift, mut dv) = (Vector::ZERO, Vector::ZERO);
        if let Some(s) = self.shear.as_deref() {
            let ly = self.sim_box.lengths[1];
            let dy = pj[1] - pi[1];
            if dy.abs() > 0.5 * ly {
                // `j` near the top and `i` near the bottom: `j`'s image below (`-1`).
                let sign = if dy > 0.0 { -1.0 } else { 1.0 };
                shift[0] = sign * s.offset(t);
                shift[1] = sign * ly;
                dv[0] = sign * s.speed;
            }
        }
        (shift, dv)
    }

    /// Calls `f(j, shift, dv)` for every disc `j` a scan from disc `i`'s cell at `t` finds:
    /// `shift` and `dv` take `j` to the image the scan sees (the periodic shift; under shear,
    /// across y, the slid image and its velocity). For the checks, which must see what the
    /// predictions saw.
    pub(super) fn for_each_neighbour(
        &self,
        i: usize,
        t: f64,
        mut f: impl FnMut(usize, Vector<D>, Vector<D>),
    ) {
        if let Some(s) = self.sheets.as_deref() {
            // Rods that keep their order meet only their neighbours in it.
            for j in s.neighbours(i) {
                if j != super::NO_PARTNER {
                    f(j as usize, Vector::ZERO, Vector::ZERO);
                }
            }
            return;
        }
        let c = self.grid.cell_of(i);
        if let Some(s) = self.shear.as_deref() {
            let rows = self.grid.dims()[1];
            if c[1] == 0 || c[1] + 1 == rows {
                cells_across(&self.grid, s, c, t, |cell, shift, dv| {
                    self.grid
                        .visit_cell(cell, shift, &mut |j: usize, shift: Vector<D>| {
                            f(j, shift, dv)
                        });
                });
                return;
            }
        }
        self.grid
            .for_each_near(c, |j, shift| f(j, shift, Vector::ZERO));
    }

    /// Whether disc `i` is filed in a row of cells next to the sheared boundary.
    #[inline(always)]
    pub(super) fn in_boundary_row(&self, i: usize) -> bool {
        let y = self.grid.cell_of(i)[1];
        y == 0 || y + 1 == self.grid.dims()[1]
    }

    /// The collision of `i` and `j` at `t` under shear: the partner taken to its image near
    /// `i` (position and velocity), the rule applied there, and the partner brought back.
    #[inline(never)]
    pub(super) fn collide_sheared(
        &mut self,
        i: usize,
        j: usize,
        t: f64,
    ) -> (EventRecord<D>, [usize; 2]) {
        self.body[i].advance_to(t);
        self.body[j].advance_to(t);
        let (pj, vj) = (self.body[j].pos, self.body[j].vel);
        let (shift, dv) = self.image_across(self.body[i].pos, pj, t);
        self.body[j].pos = pj + shift;
        self.body[j].vel = vj + dv;
        let out = if self.dissipation.is_some() {
            self.collide_inelastic(i, j, t)
        } else if self.chemistry.is_some() {
            self.collide_reactive(i, j, t)
        } else {
            self.collide(i, j, t)
        };
        self.body[j].pos = pj;
        self.body[j].vel -= dv;
        out
    }

    /// Disc `i` crossing into the next cell at `t` under shear: across the y boundary its x
    /// and x velocity change to the images' and it is filed in its new column.
    #[inline(never)]
    pub(super) fn cross_sheared(
        &mut self,
        i: usize,
        axis: usize,
        side: Side,
        t: f64,
    ) -> EventRecord<D> {
        let rows = self.grid.dims()[1];
        let row = self.grid.cell_of(i)[1];
        let wraps_y = axis == 1
            && match side {
                Side::High => row + 1 == rows,
                Side::Low => row == 0,
            };
        let record = self.cross(i, axis, side, t);
        if wraps_y {
            let s = self.shear.as_deref().expect("shear");
            // Up through the top: to the images below, `-delta` and `-gamma L_y`.
            let sign = if side == Side::High { -1.0 } else { 1.0 };
            let lx = self.sim_box.lengths[0];
            let slid = s.slid(t);
            let n = f64::from(s.columns);
            let whole = (slid / n).floor();
            let offset = (slid - n * whole) * s.width;
            let b = &mut self.body[i];
            let mut x = b.pos[0] + sign * offset;
            let wraps = (x / lx).floor();
            x -= wraps * lx;
            if x >= lx {
                x -= lx;
            }
            b.pos[0] = x.max(0.0);
            b.vel[0] += sign * s.speed;
            // Unwrapped, the disc is where it was: `x + image_x L_x + image_y delta(t)`, with
            // `delta(t) = offset + whole L_x` (`unwrapped_position`).
            let di = wraps as i64 + sign as i64 * whole as i64;
            self.image.add(i, 0, di as i32);
            let mut c = self.grid.cell_of(i);
            c[0] = self.grid.coord_of(self.body[i].pos)[0];
            self.grid.remove(i);
            self.grid.insert(i, c);
        }
        record
    }

    /// Disc `i`'s slide event at `t`: the images across y have slid a cell further, and its
    /// scan across them is made again (no velocity change).
    #[inline(never)]
    pub(super) fn slide(&mut self, i: usize, t: f64) -> EventRecord<D> {
        self.body[i].advance_to(t);
        self.stats.cell_crossing = self.stats.cell_crossing.wrapping_add(1);
        EventRecord {
            time: t,
            kind: EventKind::Slide { i },
            impulse: Vector::ZERO,
        }
    }

    /// Disc `i`'s own events under shear from `pos` and `vel` at its clock `t0`: its cell exit,
    /// walls (along z), a redraw, and in a boundary row the end of the epoch. Predictions and
    /// [`Self::own_event`] both take it, so they agree to the bit.
    #[inline(always)]
    pub(super) fn own_event_sheared(
        &self,
        i: usize,
        t0: f64,
        pos: Vector<D>,
        vel: Vector<D>,
    ) -> (f64, Pending) {
        let (mut best_t, mut best) = (f64::INFINITY, Pending::Nothing);
        let (dt, axis, high) = self.grid.exit_time(i, pos, vel);
        if dt != f64::INFINITY {
            best_t = t0 + dt;
            best = Pending::Cell {
                axis: axis as u8,
                side: if high { Side::High } else { Side::Low },
            };
        }
        let radius = self.body[i].radius;
        for a in 2..D {
            if self.sim_box.is_periodic(a) {
                continue;
            }
            if let Some((dt, side)) = crate::predict::interval_exit(
                pos[a],
                vel[a],
                radius,
                self.sim_box.lengths[a] - radius,
            ) {
                if t0 + dt < best_t {
                    best_t = t0 + dt;
                    best = Pending::Wall {
                        axis: a as u8,
                        side,
                    };
                }
            }
        }
        if self.in_boundary_row(i) {
            let s = self.shear.as_deref().expect("shear");
            let (_, _, end) = s.epoch(t0);
            if end < best_t {
                best_t = end;
                best = Pending::Slide;
            }
        }
        self.bath_event(i, best_t, best)
    }
}

impl<const D: usize> Simulation<D> {
    /// [`Self::predict`] under shear: the disc's own events from [`Self::own_event_sheared`],
    /// and its candidates, across the y boundary at their slid images (see the module's
    /// notes). Inlined into the extras' copies of the loop only.
    #[inline(always)]
    pub(super) fn predict_sheared<const FAR: bool>(&mut self, i: usize) {
        let t0 = self.event_time;
        self.body[i].advance_to(t0);
        let (pos, vel, radius) = {
            let b = &self.body[i];
            (b.pos, b.vel, b.radius)
        };
        let (best_t, best) = self.own_event_sheared(i, t0, pos, vel);
        let nearest = Nearest::new(t0, best_t, &mut self.kept);
        let c = self.grid.cell_of(i);
        let mut scan = ShearCandidates::<D, FAR> {
            body: &self.body,
            t0,
            pos,
            vel,
            radius,
            dv: Vector::ZERO,
            nearest,
        };
        let rows = self.grid.dims()[1];
        if c[1] == 0 || c[1] + 1 == rows {
            let s = self.shear.as_deref().expect("shear");
            let grid = &self.grid;
            cells_across(grid, s, c, t0, |cell, shift, dv| {
                scan.dv = dv;
                grid.visit_cell(cell, shift, &mut &mut scan);
            });
            let settled = scan.nearest.settle();
            return self.schedule(i, best, settled);
        }
        // Away from the boundary the scan is the hard cores', four candidates at a time in
        // 3D on x86-64-v3 (the scalar scan made sheared runs 1.55 times as slow per event as
        // plain ones there).
        #[cfg(target_arch = "x86_64")]
        if D == 3 && !FAR && self.v3 {
            let mut nearest = scan.nearest;
            // SAFETY: `v3` is only set when the processor has AVX2 (`set_portable_loop`).
            #[allow(unsafe_code)]
            unsafe {
                super::scan_x86::scan(
                    &self.grid,
                    c,
                    &self.body,
                    i,
                    t0,
                    &mut nearest,
                    &mut self.batch,
                )
            };
            let settled = nearest.settle();
            return self.schedule(i, best, settled);
        }
        if D == 3 {
            self.grid.visit_near_edges_once(c, &mut scan);
        } else {
            self.grid.visit_near(c, &mut scan);
        }
        let settled = scan.nearest.settle();
        self.schedule(i, best, settled);
    }
}

/// A prediction's candidates under shear: each at its position at `t0` plus the shift the
/// scan gives, moving at its velocity plus `dv` (the images' speed across the y boundary).
pub(super) struct ShearCandidates<'a, const D: usize, const FAR: bool> {
    body: &'a [Body<D>],
    t0: f64,
    pos: Vector<D>,
    vel: Vector<D>,
    radius: f64,
    dv: Vector<D>,
    nearest: Nearest<'a>,
}

impl<const D: usize, const FAR: bool> Visit<D> for &mut ShearCandidates<'_, D, FAR> {
    #[inline(always)]
    fn visit(&mut self, j: usize, shift: Vector<D>) {
        let bj = &self.body[j];
        let pj = bj.position_at(self.t0) + shift;
        self.nearest.offer(
            j,
            contact_terms::<D, FAR>(
                pj - self.pos,
                bj.vel + self.dv - self.vel,
                self.radius + bj.radius,
            ),
        );
    }
}
