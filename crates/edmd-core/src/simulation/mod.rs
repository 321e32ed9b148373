//! The simulation: state, cell grid, event queue and the event loop.
//!
//! # The flow of an event
//! 1. The queue's front disc `i` and its one pending event are read. What the next three
//!    queued discs will need is prefetched (`prefetch_upcoming`).
//! 2. A disc-disc event whose partner has collided since the prediction (its counter moved on)
//!    is stale: `i` is predicted again and the loop goes on. Nothing else is ever stale, because
//!    a disc is predicted again whenever its own velocity changes.
//! 3. Otherwise the discs involved are advanced to the event time (each disc keeps its own
//!    clock and is only moved when it takes part in an event), the collision rule or the wall
//!    reflection or the cell move is applied, and each disc involved is predicted again: walls,
//!    its cell's exit, and every disc in the `3^D` cells around it, keeping only the earliest.
//! 4. Observers are shown the event.
//!
//! The loop is compiled twice, portable and for x86-64-v3, and the copy is chosen at run time
//! (`run_chunk`); both give bit-identical results. Between chunks of events the loop looks at
//! the clock, and stops a run whose clock has stopped advancing (`stall.rs`).
//!
//! # Exactness
//! Event times are `t_event + dt` with `dt >= 0` from the closed-form kernels, so time never goes
//! backwards. A pair at contact after a collision is separating, and separating pairs are never
//! predicted to collide, so a pair cannot collide twice on one contact. A pair found overlapping
//! (by rounding) and approaching collides at once. Wall collisions put the disc exactly at the
//! contact position. Overlaps stay within rounding, far below [`OVERLAP_TOLERANCE`].
//!
//! # Ties
//! Events at exactly equal times run in order of the disc whose schedule holds them (lowest
//! index first). A disc's own candidates tie-break in the order cell crossing (or a stepped
//! disc's list departure), walls (axis order), then discs in cell-scan order (a stepped disc's
//! neighbours in list order): the first found is kept.

mod barriers;
mod centres;
mod check;
mod cluster;
mod event_loop;
mod field;
mod images;
mod inelastic;
mod lists;
mod options;
mod per_disc;
mod persist;
mod predict;
mod reactions;
mod ring;
#[cfg(target_arch = "x86_64")]
mod scan_x86;
mod shear;
mod sheets;
mod stall;
mod steps;
#[cfg(target_arch = "x86_64")]
mod steps_x86;
mod thermostat;

pub use check::OverlapReport;
pub use event_loop::x86_64_v3_available;
pub use options::{
    MultiContact, Options, OverlapPolicy, Stats, OVERLAP_ROUNDING, OVERLAP_TOLERANCE,
};
pub use persist::{
    checkpoint_dim, is_checkpoint, FORMAT_VERSION as CHECKPOINT_VERSION, MAGIC as CHECKPOINT_MAGIC,
};
pub use stall::{Stall, StallCause, CREEP_EVENTS_SPAN, MIN_STALL_EVENTS, STALL_EVENTS_PER_DISC};
pub use thermostat::Andersen;

use crate::cells::CellGrid;
use crate::error::Error;
use crate::events::Pending;
use crate::hint::{records, Records};
use crate::math::Vector;
use crate::resolve::CollisionRule;
use crate::schedule::{CalendarQueue, EventQueue};
use crate::state::{Barrier, Colour, Disc, Gravity, Potential, SimBox, System};
use barriers::validate_barriers;
use check::validate_discs;
use per_disc::PerDisc;

/// Everything the event loop reads or writes for one disc: its motion (for predictions
/// against it), its counter (to validate events naming it) and its pending event (read when
/// it reaches the front of the queue). 64 bytes in 2D, one cache line (the records' array
/// starts on a line, [`crate::hint::records`]); 80 in 3D, where a sphere's motion takes the
/// first 64 bytes, without padding to 128: a record straddles two lines, but the array is
/// 5/8 the size, which at N = 4000 (320 KB) fits the L2 cache and at N = 10^5 does better
/// in L3 (BENCHMARKS.md).
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub(crate) struct Body<const D: usize> {
    pos: Vector<D>,
    vel: Vector<D>,
    /// The disc's own clock: `pos` is its position at this time.
    time: f64,
    radius: f64,
    /// Velocity changes so far: validates pending events that name this disc as partner.
    count: u32,
    /// This disc's one scheduled event.
    pending: Pending,
}

impl<const D: usize> Body<D> {
    #[inline(always)]
    fn position_at(&self, t: f64) -> Vector<D> {
        self.pos.advanced(self.vel, t - self.time)
    }

    #[inline(always)]
    fn advance_to(&mut self, t: f64) {
        self.pos = self.position_at(t);
        self.time = t;
    }
}

/// A hard-disc system being simulated.
#[derive(Clone, Debug)]
pub struct Simulation<const D: usize = 2> {
    sim_box: SimBox<D>,
    rule: CollisionRule,
    body: Records<Body<D>>,
    mass: PerDisc<f64>,
    colour: PerDisc<Colour>,
    species: PerDisc<u16>,
    /// Periodic images crossed per disc, for unwrapped positions.
    image: images::Images<D>,
    queue: CalendarQueue,
    grid: CellGrid<D>,
    /// Whether the grid's candidates can be far enough for contact times to need the far form
    /// (`predict::far_contacts`).
    far_contacts: bool,
    /// Time of the last processed event: the reference time of predictions.
    event_time: f64,
    /// Observation time, `>= event_time`.
    now: f64,
    adjusted: usize,
    /// Internal walls.
    barriers: Vec<Barrier>,
    /// Per disc, bit `k` set when the disc is on the low side of barrier `k` (demon doors
    /// decide by the side a disc comes from). Empty without barriers.
    below: Vec<u8>,
    /// Twice the mean of `m v^2` over the discs (`4 KE / n`), the demon's yardstick and the
    /// measure of the fastest speed energy allows (constant: energy is conserved; set again
    /// by [`Self::modify_velocities`]).
    mean_mv2: f64,
    /// The stall watcher's creep bound: a chunk of events that moves the clock by no more
    /// than this counts as standing still (`stall.rs`, `Simulation::creep_span`).
    creep_span: f64,
    multi: Option<MultiContact>,
    /// The discs of the last multi-disc collision.
    last_cluster: Vec<usize>,
    /// Scratch space of the predictions: the candidates that meet ([`predict::Kept`]).
    kept: predict::Kept,
    /// Scratch space of the x86-64-v3 scan in 3D: the candidates gathered
    /// ([`scan_x86::Batch`]).
    #[cfg(target_arch = "x86_64")]
    batch: scan_x86::Batch,
    /// 3D: each sphere's second-earliest event from its last prediction (`+inf` and nothing
    /// when its earliest is its own: a cell exit or a wall), for `discard_if_stale`. 24 bytes
    /// per sphere.
    second: Vec<(f64, Pending)>,
    /// Run the event loop compiled for x86-64-v3 (see `run_chunk`).
    v3: bool,
    /// Events in a row at `event_time` counted so far (a lower bound; see `stall.rs`).
    still: u64,
    /// `event_time` at the start of the stall watcher's current chunk of events.
    chunk_time: f64,
    /// Events run in the stall watcher's current chunk (below `STALL_CHUNK`).
    chunk_events: u64,
    /// Set when the clock stopped advancing: the loops then do nothing.
    stall: Option<Stall>,
    /// The stepped potential and the shells of its pairs; `None` for hard cores alone, which
    /// run the event loop compiled without it (`run_chunk`).
    steps: Option<Box<steps::Steps<D>>>,
    /// The Andersen thermostat, with each disc's next redraw; `None`: energy is conserved.
    bath: Option<Box<thermostat::Bath>>,
    /// The reaction rules, with the heat released and the reactions counted; `None`: every
    /// collision is elastic.
    chemistry: Option<Box<reactions::Chemistry>>,
    /// The restitution, with the energy lost and the TC model's clock; `None`: collisions
    /// are elastic.
    dissipation: Option<Box<inelastic::Dissipation>>,
    /// A uniform field; `None`: discs fly straight.
    gravity: Option<Gravity>,
    /// Lees-Edwards boundaries; `None`: plain periodic images (or walls).
    shear: Option<Box<shear::LeesEdwards>>,
    /// One-dimensional self-gravity, with each rod's rank and acceleration; `None`: none.
    sheets: Option<Box<sheets::Sheets>>,
    /// A ring patch: Hill's flights, with the shear at `-3/2 Omega`; `None`: none.
    ring: Option<Box<ring::Orbits>>,
    /// Event counts (last: the fields above keep their places as counts are added).
    stats: Stats,
}

/// The event queue for `n` discs: about one bucket per disc (a power of two at or above `n`).
/// The buckets hold a few events each; with one bucket per disc rather than two the calendar's
/// horizon is half as far ahead (three times the mean time to an event rather than six), so a
/// few more events wait in the overflow, which costs nothing measurable (BENCHMARKS.md,
/// "Memory at scale") and saves 4 bytes per disc. The order of events does not depend on the
/// number of buckets: equal times are sorted by disc index in any bucket.
pub(crate) fn new_queue(n: usize) -> CalendarQueue {
    CalendarQueue::with_buckets(n, n)
}

/// "No partner found" in `predict` (disc indices are below `u32::MAX`).
pub(crate) const NO_PARTNER: u32 = u32::MAX;

/// "No disc" in the list of discs to predict again after an event.
pub(crate) const NO_DISC: usize = usize::MAX;

/// The most internal barriers a simulation takes.
pub const MAX_BARRIERS: usize = 8;

/// The discs a simulation is built from: borrowed, or owned and given back to the allocator
/// as they are read ([`Simulation::with_potential_owned`]).
enum Input<'a, const D: usize> {
    Borrowed(&'a [Disc<D>]),
    Owned(Vec<Disc<D>>),
}

/// The engine's per-disc arrays made from the input, with the discs found outside the box
/// (the first, and how many: each was moved in).
struct Tables<const D: usize> {
    body: Records<Body<D>>,
    mass: PerDisc<f64>,
    colour: PerDisc<Colour>,
    species: PerDisc<u16>,
    outside: (Option<usize>, usize),
}

impl<const D: usize> Input<'_, D> {
    fn as_slice(&self) -> &[Disc<D>] {
        match self {
            Input::Borrowed(d) => d,
            Input::Owned(d) => d,
        }
    }

    /// The records at `t0`, each disc put in the box on its walled axes (a rounding error out
    /// after a run wrote the state; [`Error::OutsideBox`] judges the rest).
    fn into_tables(self, sim_box: &SimBox<D>, t0: f64) -> Tables<D> {
        let n = self.as_slice().len();
        let mut t = Tables {
            body: records(n),
            mass: PerDisc::new(),
            colour: PerDisc::new(),
            species: PerDisc::new(),
            outside: (None, 0),
        };
        let mut take = |k: usize, d: &Disc<D>| {
            let mut pos = sim_box.wrap(d.pos);
            let mut moved = false;
            for a in 0..D {
                if sim_box.is_periodic(a) {
                    continue;
                }
                let (lo, hi) = (d.radius, sim_box.lengths[a] - d.radius);
                let tol = OVERLAP_TOLERANCE * d.radius;
                moved |= pos[a] < lo - tol || pos[a] > hi + tol;
                pos[a] = pos[a].clamp(lo, hi);
            }
            if moved {
                t.outside.0 = Some(t.outside.0.map_or(k, |f: usize| f.min(k)));
                t.outside.1 += 1;
            }
            t.body.push(Body {
                pos,
                vel: d.vel,
                time: t0,
                radius: d.radius,
                count: 0,
                pending: Pending::Nothing,
            });
            t.mass.push(d.mass);
            t.colour.push(d.colour);
            t.species.push(d.species);
        };
        match self {
            Input::Borrowed(discs) => {
                for (k, d) in discs.iter().enumerate() {
                    take(k, d);
                }
            }
            Input::Owned(mut discs) => {
                // From the end, shrinking the input every sixteenth (a large array's tail pages
                // go back to the system without a copy), then put in order.
                let chunk = (n / 16).max(1 << 16);
                while let Some(d) = discs.pop() {
                    take(discs.len(), &d);
                    if discs.len() % chunk == 0 {
                        discs.shrink_to_fit();
                    }
                }
                t.body.reverse();
                t.mass.reverse();
                t.colour.reverse();
                t.species.reverse();
            }
        }
        t.mass.shrink_to_fit();
        t.colour.shrink_to_fit();
        t.species.shrink_to_fit();
        t
    }
}

impl<const D: usize> Simulation<D> {
    /// Builds and validates a simulation at time 0.
    pub fn new(discs: &[Disc<D>], sim_box: SimBox<D>, options: Options) -> Result<Self, Error> {
        Self::with_barriers(discs, sim_box, &[], options)
    }

    /// Builds and validates a simulation of a [`System`] (discs, box and barriers) at time 0.
    pub fn from_system(system: &System<D>, options: Options) -> Result<Self, Error> {
        Self::with_barriers(&system.discs, system.sim_box, &system.barriers, options)
    }

    /// Builds and validates a simulation with internal barriers at time 0.
    pub fn with_barriers(
        discs: &[Disc<D>],
        sim_box: SimBox<D>,
        barriers: &[Barrier],
        options: Options,
    ) -> Result<Self, Error> {
        Self::with_barriers_at(discs, sim_box, barriers, options, 0.0)
    }

    /// Builds and validates a simulation whose state is at time `t0` (a state file that carries
    /// its time): the discs are where they are at `t0` and the run goes on from there. Overlaps
    /// are judged as a run judges them at `t0` (the rounding allowance of [`Self::overlaps`]
    /// grows with the time), so a state that a run wrote at `t0` reads back. Refused for a time
    /// that is not finite or is negative, and from [`Self::clock_limit`] on.
    pub fn with_barriers_at(
        discs: &[Disc<D>],
        sim_box: SimBox<D>,
        barriers: &[Barrier],
        options: Options,
        t0: f64,
    ) -> Result<Self, Error> {
        Self::assemble(Input::Borrowed(discs), sim_box, barriers, None, options, t0)
    }

    /// [`Self::with_barriers_at`] with a stepped pair potential (see [`Potential`]): each pair
    /// starts in the shell its distance puts it in, and the potential energy of the start is
    /// counted. Refused with the reason for a potential that cannot be (steps out of order or
    /// inside the hard core, a species no disc has), with multi-disc collisions, or with a rule
    /// other than the elastic one.
    pub fn with_potential_at(
        discs: &[Disc<D>],
        sim_box: SimBox<D>,
        barriers: &[Barrier],
        potential: &Potential,
        options: Options,
        t0: f64,
    ) -> Result<Self, Error> {
        Self::assemble(
            Input::Borrowed(discs),
            sim_box,
            barriers,
            Some(potential),
            options,
            t0,
        )
    }

    /// [`Self::with_potential_at`] taking the discs by value: their array is given back to the
    /// allocator as the engine's own arrays fill, so that the input and the engine are never
    /// both held whole (at 10^8 discs the input alone is 5.6 GB). The same simulation, to the
    /// bit.
    pub fn with_potential_owned(
        discs: Vec<Disc<D>>,
        sim_box: SimBox<D>,
        barriers: &[Barrier],
        potential: &Potential,
        options: Options,
        t0: f64,
    ) -> Result<Self, Error> {
        Self::assemble(
            Input::Owned(discs),
            sim_box,
            barriers,
            Some(potential),
            options,
            t0,
        )
    }

    fn assemble(
        input: Input<'_, D>,
        sim_box: SimBox<D>,
        barriers: &[Barrier],
        potential: Option<&Potential>,
        options: Options,
        t0: f64,
    ) -> Result<Self, Error> {
        let discs = input.as_slice();
        if !(t0.is_finite() && t0 >= 0.0) {
            return Err(Error::Invalid(format!(
                "start time {t0:?} is not a finite time >= 0"
            )));
        }
        if discs.len() > crate::schedule::calendar::MAX_LEN {
            return Err(Error::Invalid(format!("too many discs ({})", discs.len())));
        }
        for a in 0..D {
            let l = sim_box.lengths[a];
            if !(l.is_finite() && l > 0.0) {
                return Err(Error::BadBox { axis: a, length: l });
            }
        }
        validate_discs(discs, &sim_box)?;
        if let Some(mc) = options.multi {
            if !(mc.tolerance.is_finite() && mc.tolerance >= 0.0 && mc.tolerance < 0.5) {
                return Err(Error::Invalid(format!(
                    "multi-contact tolerance {} is outside [0, 0.5)",
                    mc.tolerance
                )));
            }
            if !(mc.exponent.is_finite() && (1.0..=3.0).contains(&mc.exponent)) {
                return Err(Error::Invalid(format!(
                    "multi-contact exponent {} is outside [1, 3]",
                    mc.exponent
                )));
            }
            if options.rule != CollisionRule::Elastic {
                return Err(Error::Invalid(
                    "multi-disc collisions need the elastic rule".into(),
                ));
            }
        }
        if options.rule == CollisionRule::Swap {
            if let Some((k, d)) = discs
                .iter()
                .enumerate()
                .find(|(_, d)| d.mass != discs[0].mass)
            {
                return Err(Error::SwapNeedsEqualMasses {
                    index: k,
                    mass: d.mass,
                    mass0: discs[0].mass,
                });
            }
        }
        let steps = match potential {
            None => None,
            Some(p) => {
                p.validate()?;
                if p.is_hard() {
                    None
                } else {
                    if options.multi.is_some() {
                        return Err(Error::Invalid(
                            "multi-disc collisions do not go with a stepped potential".into(),
                        ));
                    }
                    if options.rule != CollisionRule::Elastic {
                        return Err(Error::Invalid(
                            "a stepped potential needs the elastic rule".into(),
                        ));
                    }
                    Some(Box::new(steps::Steps::new(p, discs, &sim_box)?))
                }
            }
        };
        // Cells at least as wide as the longest reach of a pair (the largest diameter), or
        // under a stepped potential as the neighbour lists' radius, which adds the skin to the
        // outermost step.
        let max_diameter = steps.as_ref().map_or_else(
            || discs.iter().map(|d| 2.0 * d.radius).fold(0.0, f64::max),
            |s| s.list_radius,
        );
        let min_diameter = discs
            .iter()
            .map(|d| 2.0 * d.radius)
            .fold(f64::INFINITY, f64::min);
        let n = discs.len();
        let tables = input.into_tables(&sim_box, t0);
        if let (Some(first), count) = tables.outside {
            if options.overlaps == OverlapPolicy::Refuse {
                return Err(Error::OutsideBox { first, count });
            }
        }
        let grid = CellGrid::new(&sim_box, n, if n == 0 { 1.0 } else { max_diameter })?;
        let far_contacts = predict::far_contacts(&grid, &sim_box, min_diameter);
        let mut sim = Simulation {
            sim_box,
            rule: options.rule,
            body: tables.body,
            mass: tables.mass,
            colour: tables.colour,
            species: tables.species,
            image: images::Images::new(n),
            queue: new_queue(n),
            grid,
            far_contacts,
            event_time: t0,
            now: t0,
            stats: Stats::default(),
            adjusted: tables.outside.1,
            barriers: Vec::new(),
            below: Vec::new(),
            mean_mv2: 0.0,
            creep_span: 0.0,
            multi: options.multi,
            last_cluster: Vec::new(),
            kept: predict::Kept::default(),
            #[cfg(target_arch = "x86_64")]
            batch: Default::default(),
            second: vec![(f64::INFINITY, Pending::Nothing); if D == 3 { n } else { 0 }],
            v3: false,
            still: 0,
            chunk_time: t0,
            chunk_events: 0,
            stall: None,
            steps,
            bath: None,
            chemistry: None,
            dissipation: None,
            gravity: None,
            shear: None,
            sheets: None,
            ring: None,
        };
        sim.check_clock(t0)?;
        sim.set_portable_loop(false);
        validate_barriers(barriers, &sim.sim_box)?;
        sim.barriers = barriers.to_vec();
        sim.below = vec![0; if barriers.is_empty() { 0 } else { n }];
        sim.mean_mv2 = sim.mean_mv2_now();
        sim.creep_span = sim.creep_span();
        sim.file_all_in_grid();
        sim.make_lists(None);
        if options.overlaps == OverlapPolicy::Refuse {
            if let Some((disc, barrier)) = sim.barrier_overlap() {
                return Err(Error::BarrierOverlap { disc, barrier });
            }
            let report = sim.overlaps(OVERLAP_TOLERANCE);
            if let Some((i, j, overlap)) = report.first {
                return Err(Error::Overlap {
                    i,
                    j,
                    overlap,
                    count: report.count,
                });
            }
        }
        sim.schedule_all();
        Ok(sim)
    }

    fn file_all_in_grid(&mut self) {
        self.grid.clear();
        for i in 0..self.body.len() {
            let c = self.grid.coord_of(self.body[i].pos);
            self.grid.insert(i, c);
        }
    }

    fn schedule_all(&mut self) {
        self.queue.begin_bulk();
        for i in 0..self.body.len() {
            if !self.below.is_empty() {
                let p = self.body[i].position_at(self.event_time);
                self.below[i] = self
                    .barriers
                    .iter()
                    .enumerate()
                    .fold(0u8, |m, (k, b)| m | (((p[b.axis] < b.position) as u8) << k));
            }
            self.predict_outlined(i);
        }
        self.queue.end_bulk(self.event_time);
    }

    /// Number of discs.
    pub fn len(&self) -> usize {
        self.body.len()
    }

    /// True if there are no discs.
    pub fn is_empty(&self) -> bool {
        self.body.is_empty()
    }

    /// The box.
    pub fn sim_box(&self) -> &SimBox<D> {
        &self.sim_box
    }

    /// The collision rule.
    pub fn rule(&self) -> CollisionRule {
        self.rule
    }

    /// The multi-disc contact settings (`None`: every collision is binary).
    pub fn multi(&self) -> Option<MultiContact> {
        self.multi
    }

    /// Current (observation) time.
    pub fn time(&self) -> f64 {
        self.now
    }

    /// Event counts so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// How many input discs were moved into the box under [`OverlapPolicy::Allow`].
    pub fn adjusted_discs(&self) -> usize {
        self.adjusted
    }

    /// Cells per axis of the grid.
    pub fn grid_dims(&self) -> [u32; D] {
        self.grid.dims()
    }

    /// Position of disc `i` at the current time (in the primary box on periodic axes).
    pub fn position(&self, i: usize) -> Vector<D> {
        if self.ring.is_some() {
            return self.observed(i, self.now).0;
        }
        self.sim_box.wrap(self.position_of(i, self.now))
    }

    /// Position of disc `i` at the current time, not folded back into the box: the displacement
    /// since time 0 is `unwrapped_position(i) - initial position`. Under shear a disc that has
    /// crossed the y boundary `n` times (up less down) is `n` images up, each slid by the
    /// images' offset (counted from when the shear was set, without wrapping).
    pub fn unwrapped_position(&self, i: usize) -> Vector<D> {
        let mut p = self.position_of(i, self.now);
        let image = self.image.get(i);
        for a in 0..D {
            p[a] += image[a] as f64 * self.sim_box.lengths[a];
        }
        if let Some(s) = self.shear.as_deref() {
            p[0] += image[1] as f64 * s.slide(self.now);
        }
        p
    }

    /// Velocity of disc `i` at the current time.
    pub fn velocity(&self, i: usize) -> Vector<D> {
        if self.ring.is_some() {
            return self.observed(i, self.now).1;
        }
        self.velocity_of(i, self.now)
    }

    /// Mass of disc `i`.
    pub fn mass(&self, i: usize) -> f64 {
        self.mass[i]
    }

    /// Radius of disc `i`.
    pub fn radius(&self, i: usize) -> f64 {
        self.body[i].radius
    }

    /// Colour of disc `i`.
    pub fn colour(&self, i: usize) -> Colour {
        self.colour[i]
    }

    /// Species of disc `i`.
    pub fn species(&self, i: usize) -> u16 {
        self.species[i]
    }

    /// Disc `i` as a [`Disc`] at the current time.
    pub fn disc(&self, i: usize) -> Disc<D> {
        Disc {
            pos: self.position(i),
            vel: self.velocity(i),
            mass: self.mass[i],
            radius: self.body[i].radius,
            colour: self.colour[i],
            species: self.species[i],
        }
    }

    /// All discs at the current time, in input order.
    pub fn discs(&self) -> Vec<Disc<D>> {
        (0..self.len()).map(|i| self.disc(i)).collect()
    }

    /// Total kinetic energy `sum m v^2 / 2` at the current time.
    pub fn kinetic_energy(&self) -> f64 {
        if self.sheets.is_some() || self.ring.is_some() {
            return self.kinetic_energy_sheets();
        }
        self.body
            .iter()
            .zip(self.mass.iter())
            .map(|(b, m)| 0.5 * m * b.velocity_in(self.now, self.gravity).norm2())
            .sum()
    }

    /// [`Self::kinetic_energy`] under self-gravity, each disc on its own parabola, or on a
    /// ring, each on its orbit (as the box shows it, [`Self::velocity`]).
    fn kinetic_energy_sheets(&self) -> f64 {
        (0..self.body.len())
            .map(|i| 0.5 * self.mass[i] * self.velocity(i).norm2())
            .sum()
    }

    /// Total momentum `sum m v` at the current time.
    pub fn momentum(&self) -> Vector<D> {
        let mut p = Vector::ZERO;
        for i in 0..self.body.len() {
            p += self.velocity(i) * self.mass[i];
        }
        p
    }

    /// The demon's yardstick [`Self::mean_mv2`] worked out from the present velocities.
    fn mean_mv2_now(&self) -> f64 {
        if self.body.is_empty() {
            0.0
        } else {
            4.0 * self.kinetic_energy() / self.body.len() as f64
        }
    }

    /// Reverses every velocity at the current time (time-reversal experiments) and schedules
    /// everything again. The kinetic energy is the same, bit for bit, and so are the demon's
    /// yardstick and the stall watcher's creep bound.
    pub fn reverse_velocities(&mut self) {
        self.replace_velocities(|_, v| -v);
    }

    /// Replaces every velocity by `f(i, v)` at the current time and schedules everything again.
    /// What depends on the kinetic energy follows it: the demon's yardstick (the mean `m v^2`)
    /// and the stall watcher's creep bound (from the fastest speed energy allows), which would
    /// otherwise, after speeds raised a hundred-million-fold, take an honest run for a creeping
    /// one.
    pub fn modify_velocities(&mut self, f: impl FnMut(usize, Vector<D>) -> Vector<D>) {
        self.replace_velocities(f);
        self.mean_mv2 = self.mean_mv2_now();
        self.creep_span = self.creep_span();
    }

    fn replace_velocities(&mut self, mut f: impl FnMut(usize, Vector<D>) -> Vector<D>) {
        let now = self.now;
        for i in 0..self.body.len() {
            let field = self.flight(i);
            let b = &mut self.body[i];
            b.advance_in(now, field);
            b.vel = f(i, b.vel);
            b.count = b.count.wrapping_add(1);
        }
        self.event_time = now;
        self.schedule_all();
    }

    /// Sets the clock of a simulation that has not run yet to `t0` (a state file that carries
    /// its time: the discs are where they are at `t0`, and the run goes on from there).
    /// Refused once an event has happened, for a time that is not finite or is negative, and
    /// from [`Self::clock_limit`] on; a no-op when the clock is at `t0` already.
    /// [`Self::with_barriers_at`] does the same while building, and judges the discs' overlaps
    /// at `t0`.
    pub fn start_at(&mut self, t0: f64) -> Result<(), Error> {
        if !(t0.is_finite() && t0 >= 0.0) {
            return Err(Error::Invalid(format!(
                "start time {t0:?} is not a finite time >= 0"
            )));
        }
        if self.stats == Stats::default() && self.now == t0 && self.event_time == t0 {
            return Ok(());
        }
        if self.stats != Stats::default() || self.now != 0.0 {
            return Err(Error::Invalid(
                "the clock can be set only before the run starts".into(),
            ));
        }
        self.check_clock(t0)?;
        for b in self.body.iter_mut() {
            b.time = t0;
        }
        self.event_time = t0;
        self.chunk_time = t0;
        self.now = t0;
        self.schedule_all();
        Ok(())
    }

    /// The first time at which the clock no longer places these discs exactly: from there on,
    /// consecutive floating-point times (`ulp(t)`) are so far apart that the fastest disc moves
    /// more than the overlap tolerance ([`OVERLAP_TOLERANCE`] times the smallest diameter)
    /// between two of them, so that no event time can put a pair at contact to within the
    /// tolerance. A power of two, from the speeds now (`+inf` when no disc moves). Every event
    /// time is absolute, so this bounds a run's end, not its length: for discs of diameter 1 at
    /// a fastest speed of 4 it is 2^21, about 2 10^6.
    ///
    /// `+inf` under self-gravity, which has no such limit: its rods keep their order, a gap a
    /// rounding error below contact closes at once, and the order is checked with an allowance
    /// for the rounding of the positions and the time ([`Self::overlaps`]), so that rods far
    /// shorter than a position's rounding (sheets) run to any time.
    pub fn clock_limit(&self) -> f64 {
        if self.sheets.is_some() {
            return f64::INFINITY;
        }
        // In a field a disc gains at most `sqrt(2 |g| L)` of speed falling across the box.
        let fall = self.fall_speed2();
        // Under shear, pairs across y close at up to the images' speed more.
        let slide = self.shear.as_deref().map_or(0.0, |s| s.speed.abs());
        let v_max = (self
            .body
            .iter()
            .map(|b| b.vel.norm2())
            .fold(0.0, f64::max)
            .sqrt()
            + fall.sqrt()
            + slide)
            .max(0.0);
        let sigma_min = self
            .body
            .iter()
            .map(|b| 2.0 * b.radius)
            .fold(f64::INFINITY, f64::min);
        clock_limit(v_max, sigma_min)
    }

    /// Refuses a time at or beyond [`Self::clock_limit`] with [`Error::ClockResolution`]: for a
    /// run's end time, before the run (the engine's loop itself cannot fail).
    pub fn check_clock(&self, t: f64) -> Result<(), Error> {
        let limit = self.clock_limit();
        if t >= limit {
            return Err(Error::ClockResolution { time: t, limit });
        }
        Ok(())
    }

    /// Bytes held by the simulation's arrays (capacity, not just length).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.body.capacity() * size_of::<Body<D>>()
            + self.second.capacity() * size_of::<(f64, Pending)>()
            + self.mass.memory_bytes()
            + self.colour.memory_bytes()
            + self.species.memory_bytes()
            + self.image.memory_bytes()
            + self.queue.memory_bytes()
            + self.grid.memory_bytes()
            + self.steps.as_ref().map_or(0, |s| s.memory_bytes())
            + self.chemistry.as_ref().map_or(0, |c| c.memory_bytes())
            + self.dissipation.as_ref().map_or(0, |d| d.memory_bytes())
            + self.sheets.as_ref().map_or(0, |s| s.memory_bytes())
    }
}

/// [`Simulation::clock_limit`] for a fastest speed and a smallest diameter: `2^(e + 53)` with
/// `2^e <= tol sigma / v`, so that every `t` below it has `ulp(t) <= 2^(e - 52) <= tol sigma / v`
/// (`ulp(t) = 2^(floor(log2 t) - 52)`).
fn clock_limit(v_max: f64, sigma_min: f64) -> f64 {
    let step = OVERLAP_TOLERANCE * sigma_min / v_max;
    if step.is_nan() || step.is_infinite() {
        return f64::INFINITY;
    }
    // A step too small to represent: only time 0 itself is resolved.
    let e = if step > 0.0 {
        step.log2().floor() as i32
    } else {
        -1100
    };
    match e + 53 {
        // 2^1023 is the largest power of two; beyond it every finite time is resolved.
        k if k > 1023 => f64::INFINITY,
        k if k < -1022 => f64::MIN_POSITIVE,
        k => 2f64.powi(k),
    }
}

// The record sizes the layout notes on `Body` and BENCHMARKS.md rely on.
const _: () = assert!(size_of::<Body<2>>() == 64 && size_of::<Body<3>>() == 80);
