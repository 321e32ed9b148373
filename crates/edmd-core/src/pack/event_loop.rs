//! The growing-particle event loop: [`Packer`].
//!
//! A specialised copy of the engine's loop (one pending event per particle, its own clock per
//! particle, cell crossings as events, stale pair events recognised by the partner's collision
//! counter), with these differences:
//! - every diameter is its initial diameter times a common scale `s(t) = s0 + g t`, so contact
//!   distances grow linearly (`predict.rs`) and collisions follow the LS rule (`resolve.rs`);
//! - the grid's cells must stay at least one *current* largest diameter wide: each grid is
//!   built with a margin and has a deadline, the time the diameter reaches the cell width;
//! - every so often (`PackOptions::collisions_per_rescale` collisions per particle, and at the
//!   grid's deadline) the loop *synchronises*: every particle is moved to the present, the
//!   pressure of the interval is measured, velocities are scaled back to an rms speed of 1,
//!   the clock is re-based to 0 (`s0` takes the present scale), the grid is rebuilt if the
//!   diameter needs wider cells, and every event is predicted again;
//! - above [`LIST_PACKING`], neighbour lists replace the cell crossings (see there);
//! - the queue is the [`TournamentQueue`]: near jamming the event times bunch so tightly that
//!   the calendar queue's sorted current bucket overfills (measured, N = 1000 in 3D: 15% of
//!   the time in its insertions, and the whole run 1.3 times slower).

use crate::error::Error;
use crate::math::Vector;
use crate::predict::interval_exit_or_inf;
use crate::schedule::{EventQueue, TournamentQueue};
use crate::state::{Colour, Disc, SimBox};

use super::predict::{growing_contact_time, growing_wall_time};
use super::resolve::{ls_impulse, reduced_mass};
use super::start::ball_volume;
use super::{PackOptions, Packing, Status, Stop};

mod persist;

pub use persist::{is_pack_checkpoint, pack_checkpoint_dim, PACK_FORMAT_VERSION, PACK_MAGIC};

/// Cells are built this much (relatively) wider than the largest diameter, so that a grid
/// lasts while the diameter grows by that much.
const GRID_MARGIN: f64 = 0.05;

/// Above this packing fraction (2D, 3D) the loop keeps neighbour lists instead of cell
/// crossings: each particle's candidates are the particles within its contact distance plus
/// [`LIST_SKIN`] largest diameters, listed at each synchronisation. Near jamming particles
/// move very little between two synchronisations, so the lists stay valid, and they hold about
/// a third of the candidates of the `3^D` cells around a particle.
const LIST_PACKING: [f64; 2] = [0.75, 0.55];

/// The skin of the neighbour lists, in largest diameters.
const LIST_SKIN: f64 = 0.2;

/// End of a cell list.
const NONE: u32 = u32::MAX;

/// Events between two looks at the caller's stop request ([`Packer::run_watched`]): a few
/// milliseconds of work, so that Ctrl-C is answered at once whatever the number of particles
/// and however far apart the rescalings are.
const STOP_EVERY: u64 = 1 << 16;

/// The reduced pressure (2D, 3D) above which a packing counts as jammed: where the contact gap
/// tolerance `1000 d / p` ([`crate::pack::gap_tolerance`]) falls below its cap of 1%, so that
/// contacts mean something. A packing fraction that stops changing below it has stopped because
/// the growth is too slow for double precision, not because the particles jammed.
const JAMMED_PRESSURE: [f64; 2] = [2e5, 3e5];

/// A particle whose diameter comes within this fraction of the box's width between two walls
/// is caged by the walls alone (see [`Packer::caged`]).
const CAGE_GAP: f64 = 1e-9;

/// A particle's one pending event.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Next {
    /// Nothing will happen.
    Never,
    /// A collision with `j`, predicted when `j` had had `count` collisions.
    Pair { j: u32, count: u64 },
    /// A wall on `axis` (the upper one if `high`).
    Wall { axis: u8, high: bool },
    /// Leaving the cell on `axis` through its upper face if `high`.
    Cell { axis: u8, high: bool },
    /// Having moved a quarter of the lists' skin since they were built: time to build them
    /// again (a synchronisation).
    Moved,
}

#[derive(Clone, Copy, Debug)]
struct Particle<const D: usize> {
    /// Position at the particle's own time `time`.
    pos: Vector<D>,
    vel: Vector<D>,
    time: f64,
    /// Diameter at scale 1.
    d0: f64,
    mass: f64,
    /// Collisions (pair and wall) so far: a pair event whose partner's count has moved on is
    /// stale.
    count: u64,
    cell: u32,
    next: Next,
}

/// The axes' names, in messages.
const AXES: [&str; 3] = ["x", "y", "z"];

/// Refuses a compression to jamming of particles that all lie on one line (plane) across which
/// none of them moves: every collision then pushes along it, so they stay on it and the
/// compression can only jam them as a chain along it, however large the box (Princeton's `squeeze.txt`: three discs at
/// y = 0.3 moving along x "packed" to a reduced pressure of 0.0, the walls across the line
/// never struck).
fn flat<const D: usize>(discs: &[Disc<D>]) -> Result<(), Error> {
    if discs.len() < 2 {
        return Ok(());
    }
    for a in 0..D {
        let at = discs[0].pos[a];
        if discs.iter().all(|d| d.pos[a] == at && d.vel[a] == 0.0) {
            let what = if D == 3 { "plane" } else { "line" };
            return Err(Error::Invalid(format!(
                "pack: every particle is on the {what} {} = {at} and none moves across it, so they stay on it and can only jam in a chain along it: give them velocities across it, or a start off the {what}",
                AXES[a]
            )));
        }
    }
    Ok(())
}

/// The Lubachevsky-Stillinger compression of one system (see the module `pack`).
pub struct Packer<const D: usize> {
    parts: Vec<Particle<D>>,
    /// Colour and species of each particle, handed back untouched.
    labels: Vec<(Colour, u16)>,
    sim_box: SimBox<D>,
    options: PackOptions,
    queue: TournamentQueue,
    /// Cell lists.
    head: Vec<u32>,
    link_next: Vec<u32>,
    link_prev: Vec<u32>,
    cells: [usize; D],
    width: [f64; D],
    /// Neighbour lists (when `lists`): particle `i`'s are `nbr[nbr_start[i]..nbr_start[i +
    /// 1]]`, each a particle and the code of its periodic image shift (`shifts`), built at the
    /// positions `origin` with the skin `skin`.
    lists: bool,
    nbr_start: Vec<u32>,
    nbr: Vec<(u32, u32)>,
    shifts: Vec<Vector<D>>,
    origin: Vec<Vector<D>>,
    skin: f64,
    /// A particle has moved far enough that the lists must be built again.
    lists_expired: bool,
    /// Scale at the start of the interval (time 0) and its growth rate.
    s0: f64,
    g: f64,
    d0_max: f64,
    /// Particles' total volume at scale 1.
    vol0: f64,
    now: f64,
    /// The next synchronisation is due no later than this time (the grid's deadline).
    grid_deadline: f64,
    /// Time at which the target packing fraction is reached (`+inf` without one).
    target_time: f64,
    /// Time at which the largest particle's diameter comes within [`CAGE_GAP`] of the
    /// narrowest width between two walls (`+inf` in a periodic box).
    cage_time: f64,
    /// Interval accumulators: the pair virial `sum |r_ij| J_el`, the wall impulses, the
    /// kinetic energy and its time integral.
    virial: f64,
    wall_impulse: f64,
    ke: f64,
    ke_integral: f64,
    ke_time: f64,
    /// Measured interval length in total (the clock is re-based at each synchronisation).
    interval_time: f64,
    interval_collisions: u64,
    collisions: u64,
    wall_collisions: u64,
    events: u64,
    rescales: u64,
    pressure: Option<f64>,
    last_packing: Option<f64>,
    /// Events in a row at one time (the stall watcher's count, carried over synchronisations).
    same_time: u64,
}

impl<const D: usize> Packer<D> {
    /// Prepares the compression of `discs` in `sim_box`. The discs must not overlap (the same
    /// check as [`crate::Simulation::new`]) and must not all be at rest; their radii are the
    /// initial sizes, which all grow by a common factor. Velocities are scaled at once to an
    /// rms speed of 1.
    pub fn new(discs: &[Disc<D>], sim_box: SimBox<D>, options: PackOptions) -> Result<Self, Error> {
        options.validate()?;
        // The engine's own validation: box, discs, overlaps, discs outside the walls.
        crate::Simulation::new(discs, sim_box, crate::Options::default())?;
        if discs.iter().all(|d| d.vel == Vector::ZERO) {
            return Err(Error::Invalid(
                "pack: every particle is at rest; give them velocities".into(),
            ));
        }
        if options.target_packing.is_none() {
            // (With a target the compression stops there, and a line of particles at that
            // packing fraction is what was asked for.)
            flat(discs)?;
        }
        let parts: Vec<Particle<D>> = discs
            .iter()
            .map(|d| Particle {
                pos: sim_box.wrap(d.pos),
                vel: d.vel,
                time: 0.0,
                d0: 2.0 * d.radius,
                mass: d.mass,
                count: 0,
                cell: 0,
                next: Next::Never,
            })
            .collect();
        let labels = discs.iter().map(|d| (d.colour, d.species)).collect();
        let mut packer = Packer::assemble(parts, labels, sim_box, options);
        if let Some(target) = options.target_packing {
            let phi = packer.packing_fraction();
            if target <= phi {
                return Err(Error::Invalid(format!(
                    "pack: the target packing fraction {target:?} is not above the start's {phi:?}"
                )));
            }
            // Equal particles pack no closer than the hexagonal or face-centred cubic
            // crystal (Thue; Hales); mixtures can, by how much depends on their make-up.
            let close = if D == 3 {
                std::f64::consts::PI / (3.0 * 2f64.sqrt())
            } else {
                std::f64::consts::PI / (2.0 * 3f64.sqrt())
            };
            let equal = discs.iter().all(|d| d.radius == discs[0].radius);
            if equal && target >= close {
                let what = if D == 3 { "spheres" } else { "discs" };
                return Err(Error::Invalid(format!(
                    "pack: the target packing fraction {target:?} is beyond the closest packing of equal {what} ({close:.4}): no packing reaches it"
                )));
            }
        }
        packer.too_slow()?;
        packer.rescale_velocities();
        packer.rebuild_grid(true)?;
        packer.predict_all();
        Ok(packer)
    }

    /// Refuses a growth rate too small to change the diameters in double precision between two
    /// rescalings (`--growth-rate 1e-300` "converged" at once and handed back the start as a
    /// packing). The interval is overestimated as the time to cross the box's longest side
    /// `collisions_per_rescale` times at the rms speed 1 (a particle meets others long before
    /// it crosses the box); if the packing fraction would change by less than
    /// [`PackOptions::min_relative_change`] even then, the first measured intervals would stop
    /// the compression as converged, and with a change below the rounding of the scale nothing
    /// would ever move.
    fn too_slow(&self) -> Result<(), Error> {
        self.check_growth_rate(self.options.growth_rate)
    }

    /// Whether this start could be compressed at growth rate `rate` instead of its own: the
    /// check [`Packer::new`] makes of its rate (too slow for double precision), so that a
    /// caller with several rates can ask for each on one packer before any work.
    pub fn check_growth_rate(&self, rate: f64) -> Result<(), Error> {
        let longest = self.sim_box.lengths.iter().copied().fold(0.0, f64::max);
        let t = self.options.collisions_per_rescale * longest;
        // The scale grows as s0 + g t with g proportional to the rate.
        let s = self.s0 + self.g * (rate / self.options.growth_rate) * t;
        let change = (s / self.s0).powi(D as i32) - 1.0;
        if !(change >= self.options.min_relative_change && s > self.s0) {
            return Err(Error::Invalid(format!(
                "pack: growth rate {rate:e} is too slow to change the diameters in double precision (the packing fraction would change by {change:.1e} relatively between two rescalings, below the {:.0e} that counts as converged): the compression would stop at once; use a larger --growth-rate",
                self.options.min_relative_change
            )));
        }
        Ok(())
    }

    /// The particle and the walled axis on which a particle's diameter is within `gap` of the
    /// box's width (relatively): caged between two walls, it is held by them alone and no
    /// packing of the others follows from it.
    fn caged(&self, gap: f64) -> Option<(usize, usize)> {
        let s = self.scale(self.now);
        let (i, p) = self
            .parts
            .iter()
            .enumerate()
            .fold((0, &self.parts[0]), |best, (i, p)| {
                if p.d0 > best.1.d0 {
                    (i, p)
                } else {
                    best
                }
            });
        (0..D)
            .filter(|&a| !self.sim_box.is_periodic(a))
            .find(|&a| p.d0 * s >= (1.0 - gap) * self.sim_box.lengths[a])
            .map(|a| (i, a))
    }

    /// The refusal of a compression in which particle `i` has grown to the box's width on
    /// `axis` between two walls.
    fn caged_error(&self, i: usize, axis: usize) -> Error {
        Error::Invalid(format!(
            "pack: particle {i} has grown to the width of the box between the walls on {} (diameter {:.9} in a box {:.9} wide, at packing fraction {:.6}): caged by the walls alone, it cannot jam with the others; give a larger box or smaller particles",
            AXES[axis],
            self.parts[i].d0 * self.scale(self.now),
            self.sim_box.lengths[axis],
            self.packing_fraction()
        ))
    }

    /// A packer of `parts` at time 0 and scale 1, before the grid, the velocities' rescaling
    /// and the predictions (all that follows from the particles, the box and the options).
    fn assemble(
        parts: Vec<Particle<D>>,
        labels: Vec<(Colour, u16)>,
        sim_box: SimBox<D>,
        options: PackOptions,
    ) -> Self {
        let n = parts.len();
        let d0_max = parts.iter().map(|p| p.d0).fold(0.0, f64::max);
        let vol0 = parts.iter().map(|p| ball_volume::<D>(p.d0)).sum();
        Packer {
            parts,
            labels,
            sim_box,
            queue: TournamentQueue::with_len(n),
            head: Vec::new(),
            link_next: vec![NONE; n],
            link_prev: vec![NONE; n],
            cells: [1; D],
            width: sim_box.lengths,
            lists: false,
            nbr_start: Vec::new(),
            nbr: Vec::new(),
            shifts: (0..3usize.pow(D as u32))
                .map(|k| {
                    Vector(std::array::from_fn(|a| {
                        let off = (k / 3usize.pow(a as u32)) % 3;
                        (off as f64 - 1.0) * sim_box.lengths[a]
                    }))
                })
                .collect(),
            origin: Vec::new(),
            skin: 0.0,
            lists_expired: false,
            s0: 1.0,
            g: options.growth_rate / d0_max,
            d0_max,
            vol0,
            now: 0.0,
            grid_deadline: f64::INFINITY,
            target_time: f64::INFINITY,
            cage_time: f64::INFINITY,
            virial: 0.0,
            wall_impulse: 0.0,
            ke: 0.0,
            ke_integral: 0.0,
            ke_time: 0.0,
            interval_time: 0.0,
            interval_collisions: 0,
            collisions: 0,
            wall_collisions: 0,
            events: 0,
            rescales: 0,
            pressure: None,
            last_packing: None,
            same_time: 0,
            options,
        }
    }

    /// The packing fraction now.
    pub fn packing_fraction(&self) -> f64 {
        self.vol0 * self.scale(self.now).powi(D as i32) / self.sim_box.volume()
    }

    #[inline(always)]
    fn scale(&self, t: f64) -> f64 {
        self.s0 + self.g * t
    }

    /// Runs until a stopping rule holds. `progress` is called at every synchronisation with
    /// the state so far; returning `false` stops the run ([`Stop::Interrupted`]).
    pub fn run(self, mut progress: impl FnMut(&Status) -> bool) -> Result<Packing<D>, Error> {
        self.run_with(|packer| progress(&packer.status()))
    }

    /// [`Self::run`], with the packer itself handed to `progress` at every measured
    /// synchronisation, where [`Self::checkpoint`] may be taken (and [`Self::status`] read).
    pub fn run_with(self, progress: impl FnMut(&Packer<D>) -> bool) -> Result<Packing<D>, Error> {
        self.run_watched(progress, || false)
    }

    /// [`Self::run_with`], also asking `stop` every 65 536 events (a few milliseconds) whether
    /// to stop ([`Stop::Interrupted`]): the rescalings, where `progress` is called, come every
    /// `collisions_per_rescale` collisions per particle, which for 10^6 particles is minutes
    /// apart. Looking changes nothing: a run never stopped is the same bit for bit. A run
    /// stopped between rescalings cannot be checkpointed where it stopped; the last state
    /// `progress` saw can.
    pub fn run_watched(
        mut self,
        mut progress: impl FnMut(&Packer<D>) -> bool,
        mut stop: impl FnMut() -> bool,
    ) -> Result<Packing<D>, Error> {
        let n = self.parts.len() as u64;
        let per_sync = ((self.options.collisions_per_rescale * n as f64) as u64).max(1);
        let stall_limit = (100 * n).max(1_000_000);
        // Zero wherever the caller can see the packer (at its start and after an event).
        let mut idle_syncs = 0u32;
        // The first look is at once: a request that came while the packer was being built
        // is answered before any work.
        let mut until_look = 1;
        let stop = loop {
            until_look -= 1;
            if until_look == 0 {
                until_look = STOP_EVERY;
                if stop() {
                    break Stop::Interrupted;
                }
            }
            let (i, t) = self.queue.min().expect("one event per particle");
            let deadline = self.grid_deadline.min(self.target_time);
            if t >= self.cage_time && self.cage_time < deadline {
                // The largest particle is about to fill the box between two walls: its
                // collisions with them would come ever faster until the clock stops.
                self.now = self.cage_time;
                self.advance_all();
                let (i, a) = self.caged(2.0 * CAGE_GAP).unwrap_or((0, 0));
                return Err(self.caged_error(i, a));
            }
            if t >= deadline {
                if self.target_time <= self.grid_deadline {
                    self.now = self.target_time;
                    self.advance_all();
                    break Stop::Packing;
                }
                // Nothing happens before the deadline: everyone moves to it, so that the
                // diameter reaches the cell width (or the lists' limit) and the next grid is
                // coarser, or the box too small.
                self.now = self.now.max(deadline);
                idle_syncs += 1;
                if idle_syncs > 1000 {
                    return Err(Error::Invalid(format!(
                        "pack: the clock stopped: {idle_syncs} grid rebuilds without an event, at packing fraction {:.9}",
                        self.packing_fraction()
                    )));
                }
                self.synchronise(false)?;
                continue;
            }
            idle_syncs = 0;
            if t == self.now {
                self.same_time = self.same_time.saturating_add(1);
                if self.same_time > stall_limit {
                    return Err(self.stalled(i));
                }
            } else {
                self.same_time = 0;
            }
            self.now = t;
            self.events = self.events.wrapping_add(1);
            self.step(i);
            if self.lists_expired {
                self.lists_expired = false;
                self.synchronise(false)?;
                continue;
            }
            if self.interval_collisions >= per_sync {
                if let Some(stop) = self.synchronise(true)? {
                    break stop;
                }
                if !progress(&self) {
                    break Stop::Interrupted;
                }
            }
        };
        Ok(self.finish(stop))
    }

    /// The refusal of a run whose clock stopped at particle `i`. Near jamming that is the
    /// gaps reaching the rounding of the positions, and a lower `--pressure` stops first; at
    /// a pressure far from that (a file with one large and one tiny disc between walls stopped
    /// so at a reduced pressure of 9.4, with that advice) the pressure cannot be the cause, and
    /// the message says so rather than advise it.
    fn stalled(&self, i: usize) -> Error {
        let phi = self.packing_fraction();
        let head = format!(
            "pack: the clock stopped: {} events in a row at one time, at packing fraction {phi:.9}, around particle {i}",
            self.same_time
        );
        Error::Invalid(match self.pressure {
            Some(p) if p >= JAMMED_PRESSURE[D - 2] => format!(
                "{head} and reduced pressure {p:.3e}: the particles are jammed beyond what double precision resolves; ask for a lower --pressure"
            ),
            Some(p) => format!(
                "{head}, where the last reduced pressure measured was {p:.3e}, far from jamming: some particles are held in a cluster that double precision cannot resolve, not jammed; no packing follows from it"
            ),
            None => format!(
                "{head}, before any reduced pressure was measured: some particles are held in a cluster that double precision cannot resolve, not jammed; no packing follows from it"
            ),
        })
    }

    /// The options of the compression.
    pub fn options(&self) -> &PackOptions {
        &self.options
    }

    /// The number of particles.
    pub fn particle_count(&self) -> usize {
        self.parts.len()
    }

    /// The box.
    pub fn sim_box(&self) -> &SimBox<D> {
        &self.sim_box
    }

    /// Whether neighbour lists have replaced the cell crossings (above [`LIST_PACKING`]).
    pub fn neighbour_lists(&self) -> bool {
        self.lists
    }

    /// The state so far: packing fraction, reduced pressure of the last interval, collisions.
    pub fn status(&self) -> Status {
        Status {
            packing_fraction: self.packing_fraction(),
            reduced_pressure: self.pressure,
            collisions: self.collisions,
        }
    }

    /// Handles particle `i`'s event at `self.now`.
    fn step(&mut self, i: usize) {
        match self.parts[i].next {
            Next::Pair { j, count } => {
                let j = j as usize;
                self.advance(i);
                if self.parts[j].count == count {
                    self.advance(j);
                    self.collide(i, j);
                    self.predict(j);
                }
            }
            Next::Wall { axis, high } => {
                self.advance(i);
                self.wall(i, axis as usize, high);
            }
            Next::Cell { axis, high } => {
                self.advance(i);
                self.cross(i, axis as usize, high);
            }
            Next::Moved => {
                self.advance(i);
                self.lists_expired = true;
                return;
            }
            // Only reached with every time infinite, which the deadline catches first.
            Next::Never => {}
        }
        self.predict(i);
    }

    #[inline(always)]
    fn advance(&mut self, i: usize) {
        let p = &mut self.parts[i];
        p.pos = p.pos.advanced(p.vel, self.now - p.time);
        p.time = self.now;
    }

    fn advance_all(&mut self) {
        for i in 0..self.parts.len() {
            self.advance(i);
        }
    }

    /// The kinetic energy changes now: its integral so far is closed.
    #[inline(always)]
    fn close_ke(&mut self) {
        self.ke_integral += self.ke * (self.now - self.ke_time);
        self.ke_time = self.now;
    }

    fn collide(&mut self, i: usize, j: usize) {
        self.close_ke();
        let (pi, pj) = (self.parts[i], self.parts[j]);
        let dr = self.sim_box.minimum_image(pj.pos - pi.pos);
        let dist = dr.norm2().sqrt();
        let n = dr / dist;
        let u = (pj.vel - pi.vel).dot(n);
        let b = 0.5 * (pi.d0 + pj.d0) * self.g;
        let imp = ls_impulse(u, b, reduced_mass(pi.mass, pj.mass));
        let vi = pi.vel - n * (imp.total / pi.mass);
        let vj = pj.vel + n * (imp.total / pj.mass);
        self.ke += 0.5
            * (pi.mass * (vi.norm2() - pi.vel.norm2()) + pj.mass * (vj.norm2() - pj.vel.norm2()));
        self.parts[i].vel = vi;
        self.parts[j].vel = vj;
        self.parts[i].count = self.parts[i].count.wrapping_add(1);
        self.parts[j].count = self.parts[j].count.wrapping_add(1);
        self.virial += dist * imp.elastic;
        self.collisions = self.collisions.wrapping_add(1);
        self.interval_collisions = self.interval_collisions.wrapping_add(1);
    }

    fn wall(&mut self, i: usize, a: usize, high: bool) {
        self.close_ke();
        let s = self.scale(self.now);
        let p = &mut self.parts[i];
        let r = 0.5 * p.d0 * s;
        let rdot = 0.5 * p.d0 * self.g;
        let inward = if high { -1.0 } else { 1.0 };
        let u = inward * p.vel[a];
        let imp = ls_impulse(u, rdot, p.mass);
        let old = p.vel.norm2();
        p.vel[a] += inward * imp.total / p.mass;
        p.pos[a] = if high { self.sim_box.lengths[a] - r } else { r };
        p.count = p.count.wrapping_add(1);
        self.ke += 0.5 * p.mass * (p.vel.norm2() - old);
        self.wall_impulse += imp.elastic;
        self.wall_collisions = self.wall_collisions.wrapping_add(1);
    }

    fn cross(&mut self, i: usize, a: usize, high: bool) {
        let mut c = self.coords(self.parts[i].cell as usize);
        let m = self.cells[a];
        if high {
            if c[a] + 1 == m {
                c[a] = 0;
                self.parts[i].pos[a] -= self.sim_box.lengths[a];
            } else {
                c[a] += 1;
            }
        } else if c[a] == 0 {
            c[a] = m - 1;
            self.parts[i].pos[a] += self.sim_box.lengths[a];
        } else {
            c[a] -= 1;
        }
        self.unlink(i);
        let k = self.index(c);
        self.link(i, k);
    }

    /// Predicts particle `i`'s next event from `self.now` (`i` is at `self.now`).
    fn predict(&mut self, i: usize) {
        if self.lists {
            self.predict_listed(i);
        } else {
            self.predict_cells(i);
        }
    }

    /// The earliest wall of particle `p` (at scale `s`), if before `best`.
    #[inline(always)]
    fn walls(&self, p: &Particle<D>, s: f64, best: &mut f64, next: &mut Next) {
        for a in 0..D {
            if !self.sim_box.is_periodic(a) {
                let r = 0.5 * p.d0 * s;
                let rdot = 0.5 * p.d0 * self.g;
                let l = self.sim_box.lengths[a];
                if let Some((dt, side)) = growing_wall_time(p.pos[a], p.vel[a], r, rdot, 0.0, l) {
                    if dt < *best {
                        *best = dt;
                        *next = Next::Wall {
                            axis: a as u8,
                            high: side == crate::predict::Side::High,
                        };
                    }
                }
            }
        }
    }

    /// [`Self::predict`] with neighbour lists: the walls, the time at which the particle has
    /// moved a quarter of the skin from where the lists were built, and the listed particles.
    fn predict_listed(&mut self, i: usize) {
        let t = self.now;
        let p = self.parts[i];
        let s = self.scale(t);
        let mut best = f64::INFINITY;
        let mut next = Next::Never;
        self.walls(&p, s, &mut best, &mut next);
        // The larger root of |dr + v t| = delta, with |dr| <= delta (c <= 0).
        let dr = p.pos - self.origin[i];
        let delta = 0.25 * self.skin;
        let (a, b, c) = (p.vel.norm2(), dr.dot(p.vel), dr.norm2() - delta * delta);
        if a > 0.0 {
            let d = (b * b - a * c).max(0.0).sqrt();
            let dt = if b > 0.0 {
                (-c / (b + d)).max(0.0)
            } else {
                (d - b) / a
            };
            if dt < best {
                best = dt;
                next = Next::Moved;
            }
        }
        let range = self.nbr_start[i] as usize..self.nbr_start[i + 1] as usize;
        for &(j, code) in &self.nbr[range] {
            let q = &self.parts[j as usize];
            if let Some(dt) = self.pair_time(&p, q, self.shifts[code as usize], t, s) {
                if dt < best {
                    best = dt;
                    next = Next::Pair { j, count: q.count };
                }
            }
        }
        self.parts[i].next = next;
        self.queue.set(i, t + best);
    }

    /// Builds the neighbour lists at the present positions (every particle at `self.now`, in
    /// its cell).
    fn build_lists(&mut self) {
        let n = self.parts.len();
        let s = self.scale(self.now);
        self.nbr.clear();
        self.nbr_start.clear();
        self.origin.clear();
        for i in 0..n {
            self.nbr_start.push(self.nbr.len() as u32);
            let p = self.parts[i];
            self.origin.push(p.pos);
            let c = self.coords(p.cell as usize);
            for k in 0..3usize.pow(D as u32) {
                let Some((cell, code)) = self.neighbour_cell(c, k) else {
                    continue;
                };
                let mut j = self.head[cell];
                while j != NONE {
                    let ju = j as usize;
                    if ju != i {
                        let q = &self.parts[ju];
                        let cut = 0.5 * (p.d0 + q.d0) * s + self.skin;
                        let dr = q.pos + self.shifts[code] - p.pos;
                        if dr.norm2() < cut * cut {
                            self.nbr.push((j, code as u32));
                        }
                    }
                    j = self.link_next[ju];
                }
            }
        }
        self.nbr_start.push(self.nbr.len() as u32);
    }

    /// The `k`-th of the `3^D` cells around the cell at `c`, with the code of its periodic
    /// image shift (an index into `shifts`); `None` beyond a wall.
    #[inline(always)]
    fn neighbour_cell(&self, c: [usize; D], k: usize) -> Option<(usize, usize)> {
        let mut cc = [0usize; D];
        let mut code = 0;
        let mut rest = k;
        let mut pow = 1;
        for a in 0..D {
            let x = c[a] as isize + (rest % 3) as isize - 1;
            rest /= 3;
            let m = self.cells[a] as isize;
            let off = if x < 0 {
                if !self.sim_box.is_periodic(a) {
                    return None;
                }
                cc[a] = (x + m) as usize;
                0
            } else if x >= m {
                if !self.sim_box.is_periodic(a) {
                    return None;
                }
                cc[a] = (x - m) as usize;
                2
            } else {
                cc[a] = x as usize;
                1
            };
            code += off * pow;
            pow *= 3;
        }
        Some((self.index(cc), code))
    }

    /// [`Self::predict`] with the cell grid: the walls, the cell exits, and every particle in
    /// the `3^D` cells around.
    fn predict_cells(&mut self, i: usize) {
        let t = self.now;
        let p = self.parts[i];
        debug_assert_eq!(p.time, t);
        let s = self.scale(t);
        let mut best = f64::INFINITY;
        let mut next = Next::Never;
        self.walls(&p, s, &mut best, &mut next);
        let c = self.coords(p.cell as usize);
        for a in 0..D {
            let periodic = self.sim_box.is_periodic(a);
            let lo = if periodic || c[a] > 0 {
                c[a] as f64 * self.width[a]
            } else {
                f64::NEG_INFINITY
            };
            let hi = if periodic || c[a] + 1 < self.cells[a] {
                (c[a] + 1) as f64 * self.width[a]
            } else {
                f64::INFINITY
            };
            let (dt, high) = interval_exit_or_inf(p.pos[a], p.vel[a], lo, hi);
            if dt < best {
                best = dt;
                next = Next::Cell {
                    axis: a as u8,
                    high,
                };
            }
        }
        for k in 0..3usize.pow(D as u32) {
            let Some((cell, code)) = self.neighbour_cell(c, k) else {
                continue;
            };
            let shift = self.shifts[code];
            let mut j = self.head[cell];
            while j != NONE {
                let ju = j as usize;
                let q = &self.parts[ju];
                if ju != i {
                    if let Some(dt) = self.pair_time(&p, q, shift, t, s) {
                        if dt < best {
                            best = dt;
                            next = Next::Pair { j, count: q.count };
                        }
                    }
                }
                j = self.link_next[ju];
            }
        }
        self.parts[i].next = next;
        self.queue.set(i, t + best);
    }

    /// The time from `t` until `p` (at `t`) meets `q` (its image shifted by `shift`), their
    /// contact growing from the scale `s` at `t`.
    #[inline(always)]
    fn pair_time(
        &self,
        p: &Particle<D>,
        q: &Particle<D>,
        shift: Vector<D>,
        t: f64,
        s: f64,
    ) -> Option<f64> {
        let rj = q.pos.advanced(q.vel, t - q.time) + shift;
        let sigma0 = 0.5 * (p.d0 + q.d0);
        growing_contact_time(rj - p.pos, q.vel - p.vel, sigma0 * s, sigma0 * self.g)
    }

    fn predict_all(&mut self) {
        self.queue.begin_bulk();
        for i in 0..self.parts.len() {
            self.predict(i);
        }
        self.queue.end_bulk(self.now);
    }

    fn coords(&self, k: usize) -> [usize; D] {
        let mut k = k;
        std::array::from_fn(|a| {
            let c = k % self.cells[a];
            k /= self.cells[a];
            c
        })
    }

    fn index(&self, c: [usize; D]) -> usize {
        let mut k = 0;
        for a in (0..D).rev() {
            k = k * self.cells[a] + c[a];
        }
        k
    }

    fn link(&mut self, i: usize, k: usize) {
        let h = self.head[k];
        self.link_next[i] = h;
        self.link_prev[i] = NONE;
        if h != NONE {
            self.link_prev[h as usize] = i as u32;
        }
        self.head[k] = i as u32;
        self.parts[i].cell = k as u32;
    }

    fn unlink(&mut self, i: usize) {
        let (p, n) = (self.link_prev[i], self.link_next[i]);
        if p != NONE {
            self.link_next[p as usize] = n;
        } else {
            self.head[self.parts[i].cell as usize] = n;
        }
        if n != NONE {
            self.link_prev[n as usize] = p;
        }
    }

    /// The skin of the neighbour lists built now.
    fn list_skin(&self) -> f64 {
        LIST_SKIN * (self.d0_max * self.scale(self.now))
    }

    /// The shape of the grid for the present diameter. Fails when a periodic box has become
    /// too small for the particles.
    fn grid_shape(&self) -> Result<[usize; D], Error> {
        let n = self.parts.len();
        let d_now = self.d0_max * self.scale(self.now);
        let reach = if self.lists {
            d_now + self.list_skin()
        } else {
            d_now * (1.0 + GRID_MARGIN)
        };
        let want = reach.max((self.sim_box.volume() / (2 * n) as f64).powf(1.0 / D as f64));
        let mut cells = [1usize; D];
        for a in 0..D {
            let l = self.sim_box.lengths[a];
            cells[a] = ((l / want) as usize).max(1);
            if self.sim_box.is_periodic(a) && cells[a] < 3 {
                if l / 3.0 <= d_now {
                    return Err(Error::Invalid(format!(
                        "pack: the particles have grown to a third of the periodic box (diameter {d_now:.6}, box length {l:.6}, packing fraction {:.6}): too few particles for a periodic box; use more",
                        self.packing_fraction()
                    )));
                }
                cells[a] = 3;
            }
        }
        Ok(cells)
    }

    /// Builds the grid for the present diameter (if `force` or if its shape changes) and sets
    /// its deadline. Fails when a periodic box has become too small for the particles.
    fn rebuild_grid(&mut self, force: bool) -> Result<(), Error> {
        let n = self.parts.len();
        self.skin = self.list_skin();
        let cells = self.grid_shape()?;
        if force || self.lists || cells != self.cells {
            self.cells = cells;
            self.width = std::array::from_fn(|a| self.sim_box.lengths[a] / cells[a] as f64);
            self.head = vec![NONE; cells.iter().product()];
            for i in 0..n {
                if self.lists {
                    self.parts[i].pos = self.sim_box.wrap(self.parts[i].pos);
                }
                let pos = self.parts[i].pos;
                let c: [usize; D] = std::array::from_fn(|a| {
                    ((pos[a] / self.width[a]).max(0.0) as usize).min(cells[a] - 1)
                });
                let k = self.index(c);
                self.link(i, k);
            }
        }
        self.grid_deadline = if self.lists {
            // The growth may use half the skin, the two particles' motion the other half.
            0.5 * self.skin / (self.d0_max * self.g)
        } else {
            let w_min = self.width.iter().copied().fold(f64::INFINITY, f64::min);
            (w_min / self.d0_max - self.s0) / self.g
        };
        if let Some(target) = self.options.target_packing {
            let s_target = (target * self.sim_box.volume() / self.vol0).powf(1.0 / D as f64);
            self.target_time = (s_target - self.s0) / self.g;
        }
        let walled = (0..D)
            .filter(|&a| !self.sim_box.is_periodic(a))
            .map(|a| self.sim_box.lengths[a])
            .fold(f64::INFINITY, f64::min);
        self.cage_time = ((1.0 - CAGE_GAP) * walled / self.d0_max - self.s0) / self.g;
        Ok(())
    }

    /// Scales the velocities to an rms speed of 1 (mass-weighted: `sum m v^2 = sum m`).
    fn rescale_velocities(&mut self) {
        let (mut mv2, mut m) = (0.0, 0.0);
        for p in &self.parts {
            mv2 += p.mass * p.vel.norm2();
            m += p.mass;
        }
        let lambda = (m / mv2).sqrt();
        for p in &mut self.parts {
            p.vel = p.vel * lambda;
        }
        self.ke = 0.5 * m;
        self.rescales = self.rescales.wrapping_add(1);
    }

    /// Moves every particle to the present, measures the interval (when `measure`: an interval
    /// of the full number of collisions), rescales the velocities, re-bases the clock, rebuilds
    /// the grid if needed and predicts every event again. Returns a stopping reason if one
    /// holds.
    fn synchronise(&mut self, measure: bool) -> Result<Option<Stop>, Error> {
        self.advance_all();
        self.close_ke();
        self.interval_time += self.now;
        let mut stop = None;
        if measure && self.ke_integral > 0.0 {
            let walls = (0..D).any(|a| !self.sim_box.is_periodic(a));
            let p = if walls {
                let v = self.sim_box.volume();
                let area: f64 = (0..D)
                    .filter(|&a| !self.sim_box.is_periodic(a))
                    .map(|a| 2.0 * v / self.sim_box.lengths[a])
                    .sum();
                self.wall_impulse * v * D as f64 / (area * 2.0 * self.ke_integral)
            } else {
                1.0 + self.virial / (2.0 * self.ke_integral)
            };
            self.pressure = Some(p);
            let phi = self.packing_fraction();
            if p >= self.options.max_pressure {
                stop = Some(Stop::Pressure);
            } else if let Some(last) = self.last_packing {
                let change = (phi - last) / phi;
                if change < self.options.min_relative_change {
                    if p < JAMMED_PRESSURE[D - 2] {
                        return Err(Error::Invalid(format!(
                            "pack: the packing fraction stopped changing at {phi:.9} (by {change:.1e} relatively over the last {} collisions per particle) at reduced pressure {p:.3e}, far from jamming: growth rate {:e} is too slow for double precision here; use a larger --growth-rate",
                            self.options.collisions_per_rescale, self.options.growth_rate
                        )));
                    }
                    stop = Some(Stop::Converged);
                }
            }
            if stop.is_some() {
                // A particle held between two walls within the contacts' gap tolerance drives
                // the pressure up by itself: the others need not be jammed.
                let gap = crate::pack::gap_tolerance(p, D);
                if let Some((i, a)) = self.caged(gap) {
                    return Err(self.caged_error(i, a));
                }
            }
            self.last_packing = Some(phi);
            self.virial = 0.0;
            self.wall_impulse = 0.0;
            self.ke_integral = 0.0;
            self.interval_time = 0.0;
            self.interval_collisions = 0;
        }
        if stop.is_some() {
            return Ok(stop);
        }
        self.rescale_velocities();
        self.s0 = self.scale(self.now);
        self.now = 0.0;
        self.ke_time = 0.0;
        for p in &mut self.parts {
            p.time = 0.0;
        }
        if !self.lists && self.packing_fraction() >= LIST_PACKING[D - 2] {
            self.lists = true;
        }
        self.rebuild_grid(false)?;
        if self.lists {
            self.build_lists();
        }
        self.predict_all();
        Ok(None)
    }

    fn finish(mut self, stop: Stop) -> Packing<D> {
        self.advance_all();
        let s = self.scale(self.now);
        let discs = self
            .parts
            .iter()
            .zip(&self.labels)
            .map(|(p, &(colour, species))| Disc {
                pos: self.sim_box.wrap(p.pos),
                vel: p.vel,
                mass: p.mass,
                radius: 0.5 * p.d0 * s,
                colour,
                species,
            })
            .collect::<Vec<_>>();
        // Written in the order of the cells, as the fluid generators write theirs, so that a
        // run of the packing reads neighbours near each other in memory: the start's order
        // is random. A function of the final state alone, so a continued compression
        // orders its packing as the one never stopped.
        let mut discs = discs;
        if stop != Stop::Interrupted {
            // (An interrupted compression is not written; the sort would only delay the end.)
            crate::setup::fluid::in_cell_order(&mut discs, &self.sim_box);
        }
        Packing {
            packing_fraction: self.packing_fraction(),
            discs,
            sim_box: self.sim_box,
            reduced_pressure: self.pressure,
            collisions: self.collisions,
            wall_collisions: self.wall_collisions,
            events: self.events,
            rescales: self.rescales,
            stop,
        }
    }
}
