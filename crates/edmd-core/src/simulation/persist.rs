//! Exact checkpoints: the whole engine state as bytes, and back.
//!
//! A checkpoint holds every disc's own clock, position and velocity at that clock (the bits,
//! not a rounded copy), its counter and pending event, mass, radius, colour, species and
//! periodic images; the cell grid's lists in their order (the order in which a prediction
//! meets candidates decides exact ties); the counters (the stall watcher's included: see
//! `stall.rs`), the options, the barriers, and bytes the
//! caller adds (the command line keeps its run's options and measurements there). The event
//! queue is rebuilt from the discs' event times: it hands out events by `(time, disc)` whatever
//! its internal layout, so the rebuilt queue gives the same events in the same order. A run
//! continued from a checkpoint is therefore bit for bit the run that was never stopped.
//!
//! The file is `EDMDCKPT`, a format version, the dimension, the payload length, the payload,
//! and a CRC-32 of everything before it, all little-endian. Reading checks the magic number,
//! the version, the dimension, the length and the checksum, and then every index and count in
//! the payload, so a truncated, corrupted or foreign file is an [`Error::Checkpoint`] naming
//! what is wrong, never a panic or a wrong run.

use crate::cells::CellGrid;
use crate::error::Error;
use crate::events::{Pending, Side};
use crate::math::Vector;
use crate::resolve::CollisionRule;
use crate::schedule::EventQueue;
use crate::state::{Barrier, Boundary, Demon, Disc, Restitution, RestitutionLaw, SimBox};

use super::{Body, MultiContact, Simulation, Stall, StallCause, Stats};

use crate::frame::{self, Reader, Writer};

/// The first bytes of every checkpoint.
pub const MAGIC: &[u8; 8] = frame::RUN.magic;

/// The checkpoint format this build writes. It reads this one, version 9 (which had no
/// ring), version 8 (which had no
/// self-gravity), version 7 (which had no shear), version 6 (which had no restitution or field), version 5 (which had no reaction rules), version 4 (whose stepped
/// potentials kept their discs' cells by position, with no neighbour lists: such a run
/// continues with its discs at the last event time and their lists made there, every event
/// predicted afresh, which is a faithful continuation but not the bits a version-4 build would
/// have gone on with), version 3 (which had no stepped
/// potentials: it continues with hard cores alone), version 2 (which lacked the
/// spheres' second-earliest events: a 3D version-2 checkpoint continues with none, so its
/// first stale events are predicted afresh) and version 1 (which also lacked the stall
/// watcher's chunk position: a version-1 checkpoint continues as if at a chunk's start).
pub const FORMAT_VERSION: u32 = frame::RUN.version;

/// Whether `bytes` start like a checkpoint (the magic number).
pub fn is_checkpoint(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

/// The dimension a checkpoint holds, after checking its frame (magic, version, length,
/// checksum).
pub fn checkpoint_dim(bytes: &[u8]) -> Result<usize, Error> {
    frame::open(bytes, &frame::RUN).map(|(dim, _, _)| dim)
}

fn bad<T>(what: impl Into<String>) -> Result<T, Error> {
    Err(Error::Checkpoint(what.into()))
}

fn side(x: u8) -> Result<Side, Error> {
    match x {
        0 => Ok(Side::Low),
        1 => Ok(Side::High),
        _ => bad(format!("side {x}")),
    }
}

/// An event of a disc's own motion, in words, for the reader's errors.
fn describe(p: Pending) -> String {
    let end = |s: Side| if s == Side::High { "high" } else { "low" };
    match p {
        Pending::Cell { axis, side } => format!("cell crossing (axis {axis}, {} side)", end(side)),
        Pending::Wall { axis, side } => format!("wall contact (axis {axis}, {} side)", end(side)),
        Pending::Barrier { index, part } => format!("barrier event ({index}, part {part})"),
        Pending::Disc { partner, .. } => format!("collision with disc {partner}"),
        Pending::Thermostat => "thermostat redraw".into(),
        Pending::Relist => "neighbour list's renewal".into(),
        Pending::Slide => "slide of the sheared images".into(),
        Pending::Refile => "refiling in the grid".into(),
        Pending::Recheck => "new look at a contact search".into(),
        Pending::Nothing => "no event".into(),
    }
}

/// A pending event as the checkpoint writes it.
fn write_pending(w: &mut Writer, p: Pending) {
    match p {
        Pending::Nothing => w.u8(0),
        Pending::Disc { partner, seen } => {
            w.u8(1);
            w.u32(partner);
            w.u32(seen);
        }
        Pending::Wall { axis, side } => {
            w.u8(2);
            w.u8(axis);
            w.u8(side_code(side));
        }
        Pending::Cell { axis, side } => {
            w.u8(3);
            w.u8(axis);
            w.u8(side_code(side));
        }
        Pending::Barrier { index, part } => {
            w.u8(4);
            w.u32(index as u32);
            w.u8(part);
        }
        Pending::Thermostat => w.u8(5),
        Pending::Relist => w.u8(6),
        Pending::Slide => w.u8(7),
        Pending::Refile => w.u8(8),
        Pending::Recheck => w.u8(9),
    }
}

/// A pending event of disc `i` of `n`, checked as far as it can be alone.
fn read_pending<const D: usize>(
    r: &mut Reader,
    i: usize,
    n: usize,
    barriers: &[Barrier],
) -> Result<Pending, Error> {
    let pending = match r.u8()? {
        0 => Pending::Nothing,
        1 => {
            let partner = r.u32()?;
            let seen = r.u32()?;
            if partner as usize >= n {
                return bad(format!("disc {i}: partner {partner} of {n}"));
            }
            if partner as usize == i {
                return bad(format!("disc {i}: a collision with itself"));
            }
            Pending::Disc { partner, seen }
        }
        k @ (2 | 3) => {
            let axis = r.u8()?;
            let s = side(r.u8()?)?;
            if axis as usize >= D {
                return bad(format!("disc {i}: axis {axis}"));
            }
            if k == 2 {
                Pending::Wall { axis, side: s }
            } else {
                Pending::Cell { axis, side: s }
            }
        }
        4 => {
            let index = r.u32()?;
            let part = r.u8()?;
            if index as usize >= barriers.len() || part > 3 {
                return bad(format!("disc {i}: barrier event {index}/{part}"));
            }
            // Door edges (1, 2) need a door, the doorway (3) a demon.
            let w = &barriers[index as usize];
            if (matches!(part, 1 | 2) && w.door.is_none()) || (part == 3 && w.demon.is_none()) {
                return bad(format!(
                    "disc {i}: barrier event {index}/{part} at a barrier without that door or demon"
                ));
            }
            Pending::Barrier {
                index: index as u16,
                part,
            }
        }
        5 => Pending::Thermostat,
        6 => Pending::Relist,
        7 => Pending::Slide,
        8 => Pending::Refile,
        9 => Pending::Recheck,
        x => return bad(format!("disc {i}: event code {x}")),
    };
    Ok(pending)
}

fn side_code(s: Side) -> u8 {
    match s {
        Side::Low => 0,
        Side::High => 1,
    }
}

impl<const D: usize> Simulation<D> {
    /// The whole state as a checkpoint file's bytes, with `extra` bytes of the caller's kept
    /// alongside (returned by [`Self::from_checkpoint`]).
    pub fn to_checkpoint(&self, extra: &[u8]) -> Vec<u8> {
        let mut w = Writer::begin(&frame::RUN, D, 128 * self.body.len() + extra.len());
        for a in 0..D {
            w.f64(self.sim_box.lengths[a]);
            w.u8((self.sim_box.boundaries[a] == Boundary::Periodic) as u8);
        }
        w.u8(match self.rule {
            CollisionRule::Elastic => 0,
            CollisionRule::Swap => 1,
        });
        match self.multi {
            None => w.u8(0),
            Some(m) => {
                w.u8(1);
                w.f64(m.tolerance);
                w.f64(m.exponent);
            }
        }
        w.f64(self.event_time);
        w.f64(self.now);
        for c in [
            self.stats.disc_disc,
            self.stats.wall,
            self.stats.cell_crossing,
            self.stats.stale,
            self.stats.barrier,
        ] {
            w.u64(c);
        }
        w.len(self.adjusted);
        w.f64(self.mean_mv2);
        w.len(self.barriers.len());
        for b in &self.barriers {
            w.u8(b.axis as u8);
            w.f64(b.position);
            match b.door {
                None => w.u8(0),
                Some((lo, hi)) => {
                    w.u8(1);
                    w.f64(lo);
                    w.f64(hi);
                }
            }
            match b.demon {
                None => w.u8(0),
                Some(d) => {
                    w.u8(1);
                    w.f64(d.fast);
                    w.f64(d.slow);
                }
            }
        }
        let n = self.body.len();
        w.len(n);
        for i in 0..n {
            let b = &self.body[i];
            for a in 0..D {
                w.f64(b.pos[a]);
            }
            for a in 0..D {
                w.f64(b.vel[a]);
            }
            w.f64(b.time);
            w.f64(b.radius);
            w.u32(b.count);
            write_pending(&mut w, b.pending);
            w.f64(self.queue.get(i));
            w.f64(self.mass[i]);
            for c in self.colour[i] {
                w.u8(c);
            }
            w.u32(self.species[i] as u32);
            for k in self.image.get(i) {
                w.u32(k as u32);
            }
            if !self.below.is_empty() {
                w.u8(self.below[i]);
            }
        }
        let (head, next, prev, cell) = self.grid.lists();
        w.len(head.len());
        for &h in head {
            w.u32(h);
        }
        for i in 0..n {
            w.u32(next[i]);
            w.u32(prev[i]);
            for a in 0..D {
                w.u32(cell[i][a]);
            }
        }
        w.len(self.last_cluster.len());
        for &k in &self.last_cluster {
            w.len(k);
        }
        w.u64(self.still);
        w.f64(self.chunk_time);
        w.u64(self.chunk_events);
        match &self.stall {
            None => w.u8(0),
            Some(s) => {
                w.u8(match s.cause {
                    StallCause::Clock => 1,
                    StallCause::Cluster => 2,
                    StallCause::Creep => 3,
                });
                w.f64(s.time);
                w.u64(s.events);
                w.len(s.count);
                w.len(s.discs.len());
                for &d in &s.discs {
                    w.len(d);
                }
            }
        }
        // 3D: each sphere's second-earliest event, which a stale event falls back on (format 3).
        if D == 3 {
            for &(t, p) in &self.second {
                w.f64(t);
                write_pending(&mut w, p);
            }
        }
        // The stepped potential, its step count, every disc's neighbour list with each pair's
        // shell, and where each list was made (format 5).
        match &self.steps {
            None => w.u8(0),
            Some(steps) => {
                w.u8(1);
                w.u64(self.stats.step);
                w.u64(self.stats.neighbour_list);
                let p = &steps.potential;
                w.len(p.pairs.len());
                for pair in &p.pairs {
                    w.u32(pair.species.0 as u32);
                    w.u32(pair.species.1 as u32);
                    w.len(pair.steps.len());
                    for st in &pair.steps {
                        w.f64(st.radius);
                        w.f64(st.energy);
                    }
                }
                for (list, centre) in steps.near.iter().zip(&steps.centre) {
                    for a in 0..D {
                        w.f64(centre[a]);
                    }
                    w.len(list.len());
                    for &(j, sh) in list {
                        w.u32(j);
                        w.u8(sh);
                    }
                }
            }
        }
        // The thermostat: its settings and each disc's next redraw and count (format 4).
        match &self.bath {
            None => w.u8(0),
            Some(b) => {
                w.u8(1);
                w.u64(self.stats.thermostat);
                w.f64(b.settings.kt);
                w.f64(b.settings.rate);
                w.u64(b.settings.seed);
                for i in 0..n {
                    w.f64(b.next[i]);
                    w.u32(b.count[i]);
                }
            }
        }
        // The reaction rules, their seed and colours, the heat released and the reactions
        // per rule (format 6).
        match &self.chemistry {
            None => w.u8(0),
            Some(c) => {
                w.u8(1);
                w.u64(self.stats.reaction);
                w.u64(c.reactions.seed);
                w.f64(c.heat);
                w.len(c.reactions.rules.len());
                for (r, &count) in c.reactions.rules.iter().zip(&c.count) {
                    for s in [r.reactants.0, r.reactants.1, r.products.0, r.products.1] {
                        w.u32(u32::from(s));
                    }
                    w.f64(r.activation);
                    w.f64(r.probability);
                    w.f64(r.heat);
                    w.u64(count);
                }
                w.len(c.reactions.colours.len());
                for &(s, colour) in &c.reactions.colours {
                    w.u32(u32::from(s));
                    for x in colour {
                        w.u8(x);
                    }
                }
            }
        }
        // The restitution, the energy lost and the TC model's clock (format 7).
        match &self.dissipation {
            None => w.u8(0),
            Some(d) => {
                w.u8(1);
                let law = |w: &mut Writer, law: RestitutionLaw| match law {
                    RestitutionLaw::Constant(e) => {
                        w.u8(0);
                        w.f64(e);
                    }
                    RestitutionLaw::Bridges { v_c } => {
                        w.u8(1);
                        w.f64(v_c);
                    }
                };
                let r = &d.restitution;
                law(&mut w, r.all);
                w.len(r.pairs.len());
                for &(a, b, l) in &r.pairs {
                    w.u32(u32::from(a));
                    w.u32(u32::from(b));
                    law(&mut w, l);
                }
                w.f64(r.wall);
                w.f64(r.tc);
                w.f64(d.lost);
                w.f64(d.floor);
                if r.tc > 0.0 {
                    for &t in &d.last {
                        w.f64(t);
                    }
                }
            }
        }
        // The field (format 7).
        match self.gravity {
            None => w.u8(0),
            Some(f) => {
                w.u8(1);
                w.u32(f.axis as u32);
                w.f64(f.g);
            }
        }
        // The shear (format 8).
        match self.shear.as_deref() {
            None => w.u8(0),
            Some(s) => {
                w.u8(1);
                w.f64(s.rate);
                w.f64(s.origin);
                w.f64(s.start);
            }
        }
        // The self-gravity (format 9): its coupling and the discs in order.
        match self.sheets.as_deref() {
            None => w.u8(0),
            Some(s) => {
                w.u8(1);
                w.f64(s.gravity.coupling);
                for &i in &s.order {
                    w.u32(i);
                }
            }
        }
        // The ring (format 10): its orbital frequency (the shear above is its own).
        match self.ring.as_deref() {
            None => w.u8(0),
            Some(o) => {
                w.u8(1);
                w.f64(o.ring.omega);
            }
        }
        w.bytes(extra);
        w.seal()
    }

    /// A simulation continued from checkpoint bytes, and the caller's extra bytes. Fails with
    /// [`Error::Checkpoint`] on anything that is not a whole, intact checkpoint of dimension
    /// `D` written by this format version.
    pub fn from_checkpoint(bytes: &[u8]) -> Result<(Self, Vec<u8>), Error> {
        let (version, payload) = frame::open_as::<D>(bytes, &frame::RUN)?;
        let mut r = Reader::new(payload);
        let mut lengths = [0.0; D];
        let mut boundaries = [Boundary::Walls; D];
        for a in 0..D {
            lengths[a] = r.f64()?;
            boundaries[a] = match r.u8()? {
                0 => Boundary::Walls,
                1 => Boundary::Periodic,
                x => return bad(format!("boundary code {x}")),
            };
            if !(lengths[a].is_finite() && lengths[a] > 0.0) {
                return bad(format!("box length {}", lengths[a]));
            }
        }
        let sim_box = SimBox {
            lengths,
            boundaries,
        };
        let rule = match r.u8()? {
            0 => CollisionRule::Elastic,
            1 => CollisionRule::Swap,
            x => return bad(format!("collision rule code {x}")),
        };
        let multi = match r.u8()? {
            0 => None,
            1 => Some(MultiContact {
                tolerance: r.f64()?,
                exponent: r.f64()?,
            }),
            x => return bad(format!("multi-contact code {x}")),
        };
        if let Some(mc) = multi {
            let ok = mc.tolerance.is_finite()
                && (0.0..0.5).contains(&mc.tolerance)
                && (1.0..=3.0).contains(&mc.exponent)
                && rule == CollisionRule::Elastic;
            if !ok {
                return bad(format!("multi-contact options {mc:?} with {rule:?}"));
            }
        }
        let event_time = r.f64()?;
        let now = r.f64()?;
        if !(event_time.is_finite() && now.is_finite() && now >= event_time) {
            return bad(format!("clock {event_time} / {now}"));
        }
        let stats = Stats {
            disc_disc: r.u64()?,
            wall: r.u64()?,
            cell_crossing: r.u64()?,
            stale: r.u64()?,
            barrier: r.u64()?,
            step: 0,
            thermostat: 0,
            neighbour_list: 0,
            reaction: 0,
        };
        let adjusted = r.u64()? as usize;
        let mean_mv2 = r.f64()?;
        let nb = r.len(10)?;
        let mut barriers = Vec::with_capacity(nb);
        for _ in 0..nb {
            let axis = r.u8()? as usize;
            let mut b = Barrier::solid(axis, r.f64()?);
            if r.flag("barrier door")? {
                b.door = Some((r.f64()?, r.f64()?));
            }
            if r.flag("barrier demon")? {
                b.demon = Some(Demon {
                    fast: r.f64()?,
                    slow: r.f64()?,
                });
            }
            barriers.push(b);
        }
        super::barriers::validate_barriers(&barriers, &sim_box)
            .map_err(|e| Error::Checkpoint(format!("barriers: {e}")))?;
        let n = r.len(8 * (2 * D + 5))?;
        if n > crate::schedule::calendar::MAX_LEN {
            return bad(format!("{n} discs"));
        }
        let mut body = crate::hint::records(n);
        let (mut mass, mut colour, mut species, mut image, mut below, mut times) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::new(),
            Vec::with_capacity(n),
        );
        for i in 0..n {
            let mut pos = Vector::ZERO;
            let mut vel = Vector::ZERO;
            for a in 0..D {
                pos[a] = r.f64()?;
            }
            for a in 0..D {
                vel[a] = r.f64()?;
            }
            let time = r.f64()?;
            let radius = r.f64()?;
            let count = r.u32()?;
            let pending = read_pending::<D>(&mut r, i, n, &barriers)?;
            let finite = (0..D).all(|a| pos[a].is_finite() && vel[a].is_finite());
            if !(finite && time.is_finite() && radius.is_finite() && radius > 0.0) {
                return bad(format!(
                    "disc {i}: a position, velocity, clock or radius that is not a finite number"
                ));
            }
            if (0..D).any(|a| !sim_box.is_periodic(a) && 2.0 * radius >= sim_box.lengths[a]) {
                return bad(format!("disc {i}: radius {radius} fills the box"));
            }
            // A disc's own clock is never past the last event, and where it is now is a number.
            if time > event_time || !pos.advanced(vel, now - time).is_finite() {
                return bad(format!(
                    "disc {i}: its clock {time} is after the last event or puts it out of range"
                ));
            }
            // Every event at or before the observation time has been handled (`run_until`),
            // so a pending one before it would turn the clock back.
            let t = r.f64()?;
            if t.is_nan() || t < now {
                return bad(format!("disc {i}: event time {t} before the clock {now}"));
            }
            if pending == Pending::Nothing && t != f64::INFINITY {
                return bad(format!("disc {i}: an event time {t} with no event"));
            }
            times.push(t);
            let m = r.f64()?;
            if !(m.is_finite() && m > 0.0) {
                return bad(format!("disc {i}: mass {m}"));
            }
            mass.push(m);
            colour.push([r.u8()?, r.u8()?, r.u8()?]);
            let sp = r.u32()?;
            species.push(u16::try_from(sp).or_else(|_| bad(format!("disc {i}: species {sp}")))?);
            let mut im = [0i32; D];
            for a in 0..D {
                im[a] = r.u32()? as i32;
            }
            image.push(im);
            if !barriers.is_empty() {
                below.push(r.u8()?);
            }
            body.push(Body {
                pos,
                vel,
                time,
                radius,
                count,
                pending,
            });
        }
        // What the constructor refuses (a kinetic energy that overflows, a disc wider than a
        // walled box) is refused here too.
        let discs: Vec<Disc<D>> = body
            .iter()
            .zip(&mass)
            .map(|(b, &m)| Disc {
                mass: m,
                ..Disc::new(b.pos, b.vel, b.radius)
            })
            .collect();
        super::check::validate_discs(&discs, &sim_box)
            .map_err(|e| Error::Checkpoint(e.to_string()))?;
        if rule == CollisionRule::Swap && mass.iter().any(|&m| m != mass[0]) {
            return bad("the swap rule with unequal masses");
        }
        let max_diameter = body.iter().map(|b| 2.0 * b.radius).fold(0.0, f64::max);
        let cells = r.len(4)?;
        let mut head = Vec::with_capacity(cells);
        for _ in 0..cells {
            head.push(r.u32()?);
        }
        let (mut next, mut prev, mut cell) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        for _ in 0..n {
            next.push(r.u32()?);
            prev.push(r.u32()?);
            let mut c = [0u32; D];
            for a in 0..D {
                c[a] = r.u32()?;
            }
            cell.push(c);
        }
        let k = r.len(8)?;
        let mut last_cluster = Vec::with_capacity(k);
        for _ in 0..k {
            let d = r.u64()? as usize;
            if d >= n {
                return bad(format!("cluster disc {d} of {n}"));
            }
            last_cluster.push(d);
        }
        let still = r.u64()?;
        let (chunk_time, chunk_events) = if version >= 2 {
            let t = r.f64()?;
            let k = r.u64()?;
            if k >= super::stall::STALL_CHUNK || !(t.is_finite() && t <= event_time) {
                return bad(format!("stall watcher at event {k} of its chunk, time {t}"));
            }
            (t, k)
        } else {
            (event_time, 0)
        };
        let stall = match r.u8()? {
            0 => None,
            code @ (1..=3) => {
                let time = r.f64()?;
                let events = r.u64()?;
                let count = r.u64()? as usize;
                let named = r.len(8)?;
                if named > Stall::NAMED || named > count || count > n {
                    return bad(format!("a stall naming {named} of {count} discs"));
                }
                let mut discs = Vec::with_capacity(named);
                for _ in 0..named {
                    let d = r.u64()? as usize;
                    if d >= n {
                        return bad(format!("stalled disc {d} of {n}"));
                    }
                    discs.push(d);
                }
                let cause = match code {
                    1 => StallCause::Clock,
                    2 => StallCause::Cluster,
                    _ => StallCause::Creep,
                };
                Some(Stall {
                    time,
                    events,
                    discs,
                    count,
                    cause,
                })
            }
            x => return bad(format!("stall code {x}")),
        };
        // 3D from format 3: the second-earliest events, no earlier than the first.
        let mut second = vec![(f64::INFINITY, Pending::Nothing); if D == 3 { n } else { 0 }];
        if D == 3 && version >= 3 {
            for (i, s) in second.iter_mut().enumerate() {
                let t = r.f64()?;
                let p = read_pending::<D>(&mut r, i, n, &barriers)?;
                if t.is_nan() || t < times[i] || (p == Pending::Nothing) != (t == f64::INFINITY) {
                    return bad(format!(
                        "disc {i}: a second event ({}) at t = {t} with its first at t = {}",
                        describe(p),
                        times[i]
                    ));
                }
                *s = (t, p);
            }
        }
        let mut steps = None;
        let (mut step_events, mut relists) = (0, 0);
        // Version 4's shells, whose lists are made afresh once the simulation is built.
        let mut shells_v4 = None;
        if version >= 4 && r.flag("stepped potential")? {
            step_events = r.u64()?;
            if version >= 5 {
                relists = r.u64()?;
            }
            let np = r.len(12)?;
            let mut potential = crate::state::Potential::default();
            for _ in 0..np {
                let a = r.u32()?;
                let b = r.u32()?;
                if a > u16::MAX as u32 || b > u16::MAX as u32 {
                    return bad(format!("potential species {a} {b}"));
                }
                let ns = r.len(16)?;
                let mut list = Vec::with_capacity(ns);
                for _ in 0..ns {
                    list.push(crate::state::Step {
                        radius: r.f64()?,
                        energy: r.f64()?,
                    });
                }
                potential.pairs.push(crate::state::PairSteps {
                    species: (a as u16, b as u16),
                    steps: list,
                });
            }
            let discs: Vec<Disc<D>> = (0..n)
                .map(|i| {
                    let mut d = Disc::new(body[i].pos, body[i].vel, body[i].radius);
                    d.species = species[i];
                    d
                })
                .collect();
            let mut st = super::steps::Steps::new(&potential, &discs, &sim_box)
                .or_else(|e| bad(format!("stepped potential: {e}")))?;
            let mut v4 = Vec::new();
            for i in 0..n {
                if version >= 5 {
                    let mut c = Vector::ZERO;
                    for a in 0..D {
                        c[a] = r.f64()?;
                    }
                    if !c.is_finite() {
                        return bad(format!("disc {i}: list centre {c:?}"));
                    }
                    st.centre[i] = c;
                }
                let k = r.len(5)?;
                let mut list = Vec::with_capacity(k);
                for _ in 0..k {
                    let j = r.u32()?;
                    let sh = r.u8()?;
                    if j as usize >= n || (version == 4 && sh == 0) {
                        return bad(format!("disc {i}: shell {sh} with disc {j}"));
                    }
                    list.push((j, sh));
                }
                if version >= 5 {
                    st.near.set(i, &list);
                } else {
                    list.sort_unstable_by_key(|e| e.0);
                    v4.push(list);
                }
            }
            if version == 4 {
                shells_v4 = Some(v4);
            }
            steps = Some(Box::new(st));
        }
        let mut bath = None;
        let mut redraws = 0;
        if version >= 4 && r.flag("thermostat")? {
            redraws = r.u64()?;
            let settings = super::Andersen {
                kt: r.f64()?,
                rate: r.f64()?,
                seed: r.u64()?,
            };
            settings
                .validate()
                .or_else(|e| bad(format!("thermostat: {e}")))?;
            let (mut next, mut count) = (Vec::with_capacity(n), Vec::with_capacity(n));
            for i in 0..n {
                let t = r.f64()?;
                if t.is_nan() || t < event_time {
                    return bad(format!("disc {i}: thermostat redraw at t = {t}"));
                }
                next.push(t);
                count.push(r.u32()?);
            }
            bath = Some(Box::new(super::thermostat::Bath {
                settings,
                next,
                count,
            }));
        }
        let mut chemistry = None;
        let mut reactions_so_far = 0;
        if version >= 6 && r.flag("reactions")? {
            reactions_so_far = r.u64()?;
            let seed = r.u64()?;
            let heat = r.f64()?;
            let nr = r.len(4 * 4 + 4 * 8)?;
            let species_of =
                |x: u32| u16::try_from(x).or_else(|_| bad(format!("reaction species {x}")));
            let (mut rules, mut counts) = (Vec::with_capacity(nr), Vec::with_capacity(nr));
            for _ in 0..nr {
                let reactants = (species_of(r.u32()?)?, species_of(r.u32()?)?);
                let products = (species_of(r.u32()?)?, species_of(r.u32()?)?);
                rules.push(crate::state::Reaction {
                    reactants,
                    products,
                    activation: r.f64()?,
                    probability: r.f64()?,
                    heat: r.f64()?,
                });
                counts.push(r.u64()?);
            }
            let nc = r.len(4 + 3)?;
            let mut colours = Vec::with_capacity(nc);
            for _ in 0..nc {
                let s = species_of(r.u32()?)?;
                colours.push((s, [r.u8()?, r.u8()?, r.u8()?]));
            }
            if !heat.is_finite() {
                return bad(format!("reaction heat {heat}"));
            }
            let mut chem = super::reactions::Chemistry::new(crate::state::Reactions {
                rules,
                seed,
                colours,
            })
            .or_else(|e| bad(e.to_string()))?;
            chem.heat = heat;
            chem.count = counts;
            chemistry = Some(Box::new(chem));
        }
        let mut dissipation = None;
        if version >= 7 && r.flag("restitution")? {
            let law = |r: &mut Reader| -> Result<RestitutionLaw, Error> {
                match r.u8()? {
                    0 => Ok(RestitutionLaw::Constant(r.f64()?)),
                    1 => Ok(RestitutionLaw::Bridges { v_c: r.f64()? }),
                    k => bad(format!("restitution law {k}")),
                }
            };
            let all = law(&mut r)?;
            let np = r.len(4 + 4 + 1 + 8)?;
            let mut pairs = Vec::with_capacity(np);
            for _ in 0..np {
                let species_of =
                    |x: u32| u16::try_from(x).or_else(|_| bad(format!("restitution species {x}")));
                let a = species_of(r.u32()?)?;
                let b = species_of(r.u32()?)?;
                pairs.push((a, b, law(&mut r)?));
            }
            let restitution = Restitution {
                all,
                pairs,
                wall: r.f64()?,
                tc: r.f64()?,
            };
            let lost = r.f64()?;
            if !(lost.is_finite() && lost >= 0.0) {
                return bad(format!("energy lost to restitution {lost}"));
            }
            let floor = r.f64()?;
            if !(floor.is_finite() && floor >= 0.0) {
                return bad(format!("restitution's elastic speed {floor}"));
            }
            let mut d = super::inelastic::Dissipation::new(restitution, n, floor)
                .or_else(|e| bad(e.to_string()))?;
            d.lost = lost;
            for i in 0..d.last.len() {
                let t = r.f64()?;
                if t.is_nan() || t > event_time {
                    return bad(format!("disc {i}: last collision at t = {t}"));
                }
                d.last[i] = t;
            }
            dissipation = Some(Box::new(d));
        }
        let mut gravity = None;
        if version >= 7 && r.flag("field")? {
            let f = crate::state::Gravity {
                axis: r.u32()? as usize,
                g: r.f64()?,
            };
            f.validate(D).or_else(|e| bad(e.to_string()))?;
            gravity = Some(f);
        }
        let mut shear_read = None;
        if version >= 8 && r.flag("shear")? {
            shear_read = Some((r.f64()?, r.f64()?, r.f64()?));
        }
        let mut sheets_read = None;
        if version >= 9 && r.flag("self-gravity")? {
            let g = crate::state::SelfGravity { coupling: r.f64()? };
            g.validate(D).or_else(|e| bad(e.to_string()))?;
            let mut seen = vec![false; n];
            let mut order = Vec::with_capacity(n.min(1 << 20));
            for _ in 0..n {
                let i = r.u32()?;
                if i as usize >= n || std::mem::replace(&mut seen[i as usize], true) {
                    return bad(format!(
                        "self-gravity: disc {i} out of range or in order twice"
                    ));
                }
                order.push(i);
            }
            sheets_read = Some((g, order));
        }
        let mut ring_read = None;
        if version >= 10 && r.flag("ring")? {
            let ring = crate::state::Ring { omega: r.f64()? };
            ring.validate(D).or_else(|e| bad(e.to_string()))?;
            if shear_read.is_none_or(|(rate, _, _)| rate != ring.shear_rate()) {
                return bad("a ring without its shear at -3/2 times its orbital frequency");
            }
            ring_read = Some(ring);
        }
        let extra = r.bytes()?.to_vec();
        if !r.at_end() {
            return bad("bytes after the end of the state");
        }
        // The grid as the simulation built it: cells as wide as the largest diameter, or the
        // lists' radius. A version-4 stepped run's grid (cells as wide as the outermost step,
        // discs filed by position) is made anew below, with its lists.
        let width = steps.as_ref().map_or(max_diameter, |s| s.list_radius);
        // Under self-gravity, one cell (`sheets.rs`).
        let width = if sheets_read.is_some() {
            sim_box.lengths[0]
        } else {
            width
        };
        let grid = if ring_read.is_some() {
            super::ring::ring_grid(&sim_box, n, max_diameter)
        } else {
            CellGrid::new(&sim_box, n, if n == 0 { 1.0 } else { width })
        };
        let mut grid = grid.map_err(|e| Error::Checkpoint(format!("cell grid: {e}")))?;
        if shells_v4.is_none() {
            grid.restore(head, next, prev, cell)
                .map_err(|what| Error::Checkpoint(format!("cell grid: {what}")))?;
        }
        let mut shear = None;
        if let Some((rate, origin, start)) = shear_read {
            let columns = grid.dims()[0];
            if !(origin.is_finite()
                && origin <= event_time
                && start >= 0.0
                && start < f64::from(columns))
            {
                return bad(format!("shear from t = {origin} at {start} cells"));
            }
            let width = sim_box.lengths[0] / f64::from(columns);
            let s = crate::state::Shear {
                rate,
                offset: (start * width).min(sim_box.lengths[0].next_down()),
            };
            s.validate(D, sim_box.lengths[0])
                .or_else(|e| bad(e.to_string()))?;
            let mut le = super::shear::LeesEdwards::new(s, origin, columns, sim_box.lengths);
            // The cells slid as written, to the bit (not through the offset).
            le.start = start;
            shear = Some(Box::new(le));
        }
        let mut queue = super::new_queue(n);
        queue.begin_bulk();
        for (i, &t) in times.iter().enumerate() {
            queue.set(i, t);
        }
        queue.end_bulk(event_time);
        let min_diameter = body
            .iter()
            .map(|b| 2.0 * b.radius)
            .fold(f64::INFINITY, f64::min);
        let far_contacts = super::predict::far_contacts(&grid, &sim_box, min_diameter);
        let sheets =
            sheets_read.map(|(g, order)| Box::new(super::sheets::Sheets::new(g, order, &mass)));
        let ring = ring_read.map(|r| {
            Box::new(super::ring::Orbits::new(
                r,
                sim_box.lengths,
                &grid,
                max_diameter,
            ))
        });
        let mut sim = Simulation {
            sim_box,
            rule,
            body,
            mass: super::PerDisc::from_vec(mass),
            colour: super::PerDisc::from_vec(colour),
            species: super::PerDisc::from_vec(species),
            image: super::images::Images::from_vec(image),
            queue,
            grid,
            far_contacts,
            event_time,
            now,
            stats,
            adjusted,
            barriers,
            below,
            mean_mv2,
            creep_span: 0.0,
            multi,
            last_cluster,
            kept: super::predict::Kept::default(),
            #[cfg(target_arch = "x86_64")]
            batch: Default::default(),
            second,
            v3: false,
            still,
            chunk_time,
            chunk_events,
            stall,
            steps,
            bath,
            chemistry,
            dissipation,
            gravity,
            shear,
            sheets,
            ring,
        };
        if let Some(f) = sim.gravity {
            sim.gravity_fits(f).or_else(|e| bad(e.to_string()))?;
        }
        if sim.ring.is_some() {
            sim.ring_fits().or_else(|e| bad(e.to_string()))?;
        } else if sim.shear.is_some() {
            sim.shear_fits().or_else(|e| bad(e.to_string()))?;
        }
        if sim.sheets.is_some() {
            sim.self_gravity_fits().or_else(|e| bad(e.to_string()))?;
        }
        if sim.chemistry.is_some() {
            sim.reactions_fit().or_else(|e| bad(e.to_string()))?;
        }
        if sim.dissipation.is_some() {
            sim.restitution_fits().or_else(|e| bad(e.to_string()))?;
        }
        sim.stats.reaction = reactions_so_far;
        sim.stats.step = step_events;
        sim.stats.neighbour_list = relists;
        sim.stats.thermostat = redraws;
        sim.set_portable_loop(false);
        // The yardstick is kept from the start (or the last change of velocities), and energy
        // is conserved to rounding (1e-9 relative in every fuzzed run, RELIABILITY.md): one that
        // is not the discs' would move the demon's thresholds and, far too large, keep the stall
        // watcher from seeing a creeping clock.
        // (Under a stepped potential kinetic energy is exchanged with the steps', under a
        // thermostat with the bath, with reactions that release heat with the reactants, in a
        // field with the field's, and inelastic collisions lose it, so only its finiteness is
        // checked then.)
        let now_mv2 = sim.mean_mv2_now();
        let stepped = sim.steps.is_some()
            || sim.bath.is_some()
            || sim.chemistry.as_ref().is_some_and(|c| c.heat != 0.0)
            || sim.dissipation.as_ref().is_some_and(|d| d.lost != 0.0)
            || sim.gravity.is_some()
            || sim.shear.is_some()
            || sim.sheets.is_some();
        if !(mean_mv2.is_finite() && (stepped || (mean_mv2 - now_mv2).abs() <= 1e-6 * now_mv2)) {
            return bad(format!(
                "mean m v^2 {mean_mv2}, where the discs' kinetic energy gives {now_mv2}"
            ));
        }
        sim.creep_span = sim.creep_span();
        // Every run keeps its discs inside their walls (a wall collision puts a disc exactly at
        // contact); one outside would be driven to huge energies by the walls.
        if let Some(&i) = sim.discs_outside(super::OVERLAP_TOLERANCE).first() {
            return bad(format!("disc {i} is outside the box"));
        }
        // A version-4 stepped run goes on from its discs at the last event time, with their
        // lists made there and every event predicted afresh.
        if let Some(shells) = shells_v4 {
            sim.make_lists(Some(&shells));
            sim.schedule_all();
        } else if let Some(st) = sim.steps.as_deref_mut() {
            st.filed.refile(&sim.grid, &st.centre);
        }
        // A disc is in the cell it is filed in (at its own clock; it stays there until its
        // event, which is no later than its cell exit, below): the scans of its neighbours
        // would miss it in any other. Crossings leave a disc on its new cell's edge, to within
        // the rounding of a position at an absolute time. Under a stepped potential a disc is
        // filed by its list's centre, which is in the box, and is no farther from it than half
        // the skin (its event is no later than its departure, below); its list holds every
        // disc whose centre is near.
        let longest = sim.sim_box.lengths.iter().copied().fold(0.0, f64::max);
        for (i, b) in sim.body.iter().enumerate() {
            // On a ring a disc strays up to its cell's margin before it is filed again.
            let margin = sim
                .ring
                .as_deref()
                .map_or(0.0, |o| o.margin.iter().copied().fold(0.0, f64::max));
            let slack = 1e-9 * max_diameter
                + margin
                + super::OVERLAP_ROUNDING * (longest + b.vel.norm2().sqrt() * b.time.abs());
            let (filed, leash) = match &sim.steps {
                Some(st) => (st.centre[i], Some((st.centre[i], st.leash))),
                None => (b.pos, None),
            };
            if !sim.grid.holds(i, filed, slack) {
                return bad(format!(
                    "disc {i} is filed in cell {:?}, which does not hold it",
                    sim.grid.cell_of(i)
                ));
            }
            if let Some((c, leash)) = leash {
                if (b.pos - c).norm2().sqrt() > leash + slack
                    || (0..D).any(|a| {
                        sim.sim_box.is_periodic(a)
                            && !(0.0..=sim.sim_box.lengths[a]).contains(&c[a])
                    })
                {
                    return bad(format!("disc {i}: list centre {c:?}, where it is not"));
                }
            }
        }
        if let Some(fault) = sim.list_fault() {
            return bad(fault);
        }
        // A disc's event is the earliest it has, so never later than its cell exit, wall or
        // barrier contact, which follow from its own motion alone (computed here exactly as
        // when it was predicted, from its own clock); a later one would let it pass through a
        // wall or a barrier. A pending event of one of those kinds is that one: a crossing out
        // of a walled axis's end cell, say, would wrap the disc to the far side of the box.
        for i in 0..n {
            let (bound, own) = sim.own_event(i);
            let first = (sim.queue.get(i), sim.body[i].pending);
            let second = sim.second.get(i).copied();
            let second = second.filter(|&(_, p)| p != Pending::Nothing);
            for (t, pending) in std::iter::once(first).chain(second) {
                if t > bound {
                    return bad(format!(
                        "disc {i}: its event at t = {t} is after it leaves its cell or meets a wall or barrier (t = {bound})"
                    ));
                }
                let own_kind = matches!(
                    pending,
                    Pending::Cell { .. }
                        | Pending::Relist
                        | Pending::Wall { .. }
                        | Pending::Barrier { .. }
                        | Pending::Thermostat
                        | Pending::Slide
                        | Pending::Refile
                );
                if own_kind && (t, pending) != (bound, own) {
                    return bad(format!(
                        "disc {i}: its {} at t = {t} is not the one its motion gives ({} at t = {bound})",
                        describe(pending),
                        describe(own)
                    ));
                }
            }
        }
        // Pending collisions cannot be checked to the bit (the reader's note on `own_event`),
        // but no pair may be let through a contact by them.
        if let Some((i, j, t, again)) = sim.missed_contact() {
            return bad(format!(
                "discs {i} and {j} meet at t = {t}, but neither has an event that looks at the other before t = {again}"
            ));
        }
        Ok((sim, extra))
    }
}
