//! Exact checkpoints of a compression: [`Packer::checkpoint`] and [`Packer::from_checkpoint`].
//!
//! A packer is only ever seen by its caller at a synchronisation (after [`Packer::new`], and
//! at each measured one through [`Packer::run_with`]): every particle is then at time 0 (the
//! clock re-based), velocities have just been rescaled, and every event has just been
//! predicted from the present state. So the state is the particles (position, velocity,
//! initial diameter, mass, collision count, colour and species), the box, the options, the
//! scale `s0`, whether neighbour lists are on, the cell grid's shape and its lists in their
//! order (candidates met in that order decide exact ties), the counters, the pressure
//! accumulators and last measured values, and the stall watcher's count. Everything else is
//! rebuilt as the synchronisation built it: the growth rate per unit diameter, the volume, the
//! kinetic energy (`sum m / 2` after a rescaling), the grid's widths and deadline, the
//! neighbour lists (built from the positions in particle order), every prediction and the
//! queue (a tournament: its winners follow from the leaves alone). A compression continued
//! from a checkpoint is therefore bit for bit the one that was never stopped.
//!
//! The frame (`EDMDPACK`, version, dimension, length, CRC-32) is the run checkpoint's
//! (`crate::frame`); each refuses the other kind by name. Every count is bounded by the bytes
//! present before anything is allocated, every index is checked, and the particles go through
//! the constructor's own checks (finite numbers, inside the walls, no overlaps).

use crate::error::Error;
use crate::frame::{self, Reader, Writer};
use crate::math::Vector;
use crate::state::{Boundary, Disc, SimBox};

use super::{Next, Packer, Particle, NONE};
use crate::pack::PackOptions;

/// The first bytes of a packing checkpoint.
pub const PACK_MAGIC: &[u8; 8] = frame::PACK.magic;

/// The packing checkpoint format this build writes (and reads).
pub const PACK_FORMAT_VERSION: u32 = frame::PACK.version;

/// Whether `bytes` start like a packing checkpoint (the magic number).
pub fn is_pack_checkpoint(bytes: &[u8]) -> bool {
    bytes.starts_with(PACK_MAGIC)
}

/// The dimension a packing checkpoint holds, after checking its frame (magic, version, length,
/// checksum).
pub fn pack_checkpoint_dim(bytes: &[u8]) -> Result<usize, Error> {
    frame::open(bytes, &frame::PACK).map(|(dim, _, _)| dim)
}

fn bad<T>(what: impl Into<String>) -> Result<T, Error> {
    Err(Error::Checkpoint(what.into()))
}

fn optional(w: &mut Writer, x: Option<f64>) {
    match x {
        None => w.u8(0),
        Some(v) => {
            w.u8(1);
            w.f64(v);
        }
    }
}

fn read_optional(r: &mut Reader, what: &str) -> Result<Option<f64>, Error> {
    if !r.flag(what)? {
        return Ok(None);
    }
    let v = r.f64()?;
    if !v.is_finite() {
        return bad(format!("{what} {v}"));
    }
    Ok(Some(v))
}

/// Bytes per particle: position, velocity, initial diameter, mass, count, colour, species, the
/// next particle in its cell.
const fn particle_bytes(d: usize) -> usize {
    16 * d + 8 + 8 + 8 + 3 + 4 + 4
}

impl<const D: usize> Packer<D> {
    /// The whole state as a packing checkpoint file's bytes, with `extra` bytes of the caller's
    /// kept alongside (returned by [`Self::from_checkpoint`]). Taken where the caller sees the
    /// packer: after [`Self::new`] or in the callback of [`Self::run_with`].
    pub fn checkpoint(&self, extra: &[u8]) -> Vec<u8> {
        debug_assert!(self.now == 0.0 && self.parts.iter().all(|p| p.time == 0.0));
        let n = self.parts.len();
        let mut w = Writer::begin(
            &frame::PACK,
            D,
            256 + particle_bytes(D) * n + 4 * self.head.len() + extra.len(),
        );
        for a in 0..D {
            w.f64(self.sim_box.lengths[a]);
            w.u8(self.sim_box.is_periodic(a) as u8);
        }
        let o = &self.options;
        w.f64(o.growth_rate);
        w.f64(o.max_pressure);
        optional(&mut w, o.target_packing);
        w.f64(o.collisions_per_rescale);
        w.f64(o.min_relative_change);
        w.f64(self.s0);
        w.u8(self.lists as u8);
        for c in [
            self.collisions,
            self.wall_collisions,
            self.events,
            self.rescales,
            self.interval_collisions,
            self.same_time,
        ] {
            w.u64(c);
        }
        for x in [
            self.virial,
            self.wall_impulse,
            self.ke_integral,
            self.interval_time,
        ] {
            w.f64(x);
        }
        optional(&mut w, self.pressure);
        optional(&mut w, self.last_packing);
        w.len(n);
        for (i, (p, (colour, species))) in self.parts.iter().zip(&self.labels).enumerate() {
            for a in 0..D {
                w.f64(p.pos[a]);
            }
            for a in 0..D {
                w.f64(p.vel[a]);
            }
            w.f64(p.d0);
            w.f64(p.mass);
            w.u64(p.count);
            for c in colour {
                w.u8(*c);
            }
            w.u32(*species as u32);
            w.u32(self.link_next[i]);
        }
        for a in 0..D {
            w.len(self.cells[a]);
        }
        w.len(self.head.len());
        for &h in &self.head {
            w.u32(h);
        }
        w.bytes(extra);
        w.seal()
    }

    /// A compression continued from packing checkpoint bytes, and the caller's extra bytes.
    /// Fails with [`Error::Checkpoint`] on anything that is not a whole, intact packing
    /// checkpoint of dimension `D` written by this format version.
    pub fn from_checkpoint(bytes: &[u8]) -> Result<(Self, Vec<u8>), Error> {
        let (_version, payload) = frame::open_as::<D>(bytes, &frame::PACK)?;
        let mut r = Reader::new(payload);
        let mut lengths = [0.0; D];
        let mut boundaries = [Boundary::Walls; D];
        for a in 0..D {
            lengths[a] = r.f64()?;
            if r.flag("periodic")? {
                boundaries[a] = Boundary::Periodic;
            }
            if !(lengths[a].is_finite() && lengths[a] > 0.0) {
                return bad(format!("box length {}", lengths[a]));
            }
        }
        let sim_box = SimBox {
            lengths,
            boundaries,
        };
        if !sim_box.volume().is_finite() {
            return bad(format!(
                "a box of volume {} (lengths {lengths:?})",
                sim_box.volume()
            ));
        }
        let options = PackOptions {
            growth_rate: r.f64()?,
            max_pressure: r.f64()?,
            target_packing: read_optional(&mut r, "target packing")?,
            collisions_per_rescale: r.f64()?,
            min_relative_change: r.f64()?,
        };
        options
            .validate()
            .map_err(|e| Error::Checkpoint(format!("options: {e}")))?;
        let s0 = r.f64()?;
        if !(s0.is_finite() && s0 > 0.0) {
            return bad(format!("scale {s0}"));
        }
        let lists = r.flag("neighbour lists")?;
        let [collisions, wall_collisions, events, rescales, interval_collisions, same_time] =
            [r.u64()?, r.u64()?, r.u64()?, r.u64()?, r.u64()?, r.u64()?];
        let [virial, wall_impulse, ke_integral, interval_time] =
            [r.f64()?, r.f64()?, r.f64()?, r.f64()?];
        if ![virial, wall_impulse, ke_integral, interval_time]
            .iter()
            .all(|x| x.is_finite() && *x >= 0.0)
        {
            return bad("an accumulated virial, impulse or time that is not a finite number");
        }
        let pressure = read_optional(&mut r, "pressure")?;
        let last_packing = read_optional(&mut r, "last packing")?;
        let n = r.len(particle_bytes(D))?;
        if n == 0 || n >= u32::MAX as usize {
            return bad(format!("{n} particles"));
        }
        let mut parts = Vec::with_capacity(n);
        let mut labels = Vec::with_capacity(n);
        let mut next = Vec::with_capacity(n);
        for _ in 0..n {
            let mut pos = Vector::ZERO;
            let mut vel = Vector::ZERO;
            for a in 0..D {
                pos[a] = r.f64()?;
            }
            for a in 0..D {
                vel[a] = r.f64()?;
            }
            let (d0, mass, count) = (r.f64()?, r.f64()?, r.u64()?);
            let colour = [r.u8()?, r.u8()?, r.u8()?];
            let sp = r.u32()?;
            let species = u16::try_from(sp).or_else(|_| bad(format!("species {sp}")))?;
            next.push(r.u32()?);
            parts.push(Particle {
                pos,
                vel,
                time: 0.0,
                d0,
                mass,
                count,
                cell: 0,
                next: Next::Never,
            });
            labels.push((colour, species));
        }
        // The constructor's checks on the particles at their present size: finite numbers,
        // positive sizes and masses, inside the walls, no overlaps.
        let discs: Vec<Disc<D>> = parts
            .iter()
            .map(|p| Disc {
                mass: p.mass,
                ..Disc::new(p.pos, p.vel, 0.5 * p.d0 * s0)
            })
            .collect();
        crate::Simulation::new(&discs, sim_box, crate::Options::default())
            .map_err(|e| Error::Checkpoint(e.to_string()))?;
        // The rescaling just before the checkpoint left an rms speed of 1 (`sum m v^2 = sum m`,
        // to rounding). A particle far faster than that would cross its cells a huge number of
        // times before anything else happened (found by fuzzing: a velocity of 1e86).
        let (mv2, m) = parts.iter().fold((0.0, 0.0), |(mv2, m), p| {
            (mv2 + p.mass * p.vel.norm2(), m + p.mass)
        });
        let ms = mv2 / m;
        if ms.is_nan() || (ms - 1.0).abs() > 1e-6 {
            return bad(format!(
                "velocities of mean square {ms} (mass-weighted) where the rescaling leaves 1"
            ));
        }
        let mut cells = [0usize; D];
        for c in &mut cells {
            *c = r.u64()?.try_into().unwrap_or(usize::MAX);
        }
        let count = r.len(4)?;
        let product = cells.iter().try_fold(1usize, |p, &c| p.checked_mul(c));
        if product != Some(count) {
            return bad(format!("a grid of {cells:?} cells with {count} lists"));
        }
        let mut head = Vec::with_capacity(count);
        for _ in 0..count {
            head.push(r.u32()?);
        }
        let extra = r.bytes()?.to_vec();
        if !r.at_end() {
            return bad("bytes after the end of the state");
        }

        let mut packer = Packer::assemble(parts, labels, sim_box, options);
        packer.s0 = s0;
        packer.lists = lists;
        packer.collisions = collisions;
        packer.wall_collisions = wall_collisions;
        packer.events = events;
        packer.rescales = rescales;
        packer.interval_collisions = interval_collisions;
        packer.same_time = same_time;
        packer.virial = virial;
        packer.wall_impulse = wall_impulse;
        packer.ke_integral = ke_integral;
        packer.interval_time = interval_time;
        packer.pressure = pressure;
        packer.last_packing = last_packing;
        // As the last rescaling left it (`rescale_velocities`: the masses summed in order).
        packer.ke = 0.5 * packer.parts.iter().fold(0.0, |m, p| m + p.mass);
        let shape = packer
            .grid_shape()
            .map_err(|e| Error::Checkpoint(e.to_string()))?;
        if shape != cells {
            return bad(format!(
                "a grid of {cells:?} cells where the particles' size gives {shape:?}"
            ));
        }
        packer.cells = cells;
        packer.width = std::array::from_fn(|a| sim_box.lengths[a] / cells[a] as f64);
        packer.restore_lists(&head, &next)?;
        packer
            .rebuild_grid(false)
            .map_err(|e| Error::Checkpoint(e.to_string()))?;
        if lists {
            // The grid was rebuilt in particle order from the wrapped positions, as the
            // synchronisation did: a genuine checkpoint holds exactly that.
            let same_positions = packer.parts.iter().zip(&discs).all(|(p, d)| p.pos == d.pos);
            if packer.head != head || packer.link_next != next || !same_positions {
                return bad("cell lists out of the order a rebuild gives them");
            }
            packer.build_lists();
        }
        // Finite sizes in a finite box can still overflow the particles' total volume.
        let phi = packer.packing_fraction();
        if !(phi.is_finite() && phi > 0.0) {
            return bad(format!("packing fraction {phi}"));
        }
        packer.predict_all();
        Ok((packer, extra))
    }

    /// Takes the cell lists as written (`head` of each cell, `next` of each particle), checking
    /// every index, that each particle is in exactly one list, and (with the cell grid in use)
    /// that it is in the cell its position says, within rounding.
    fn restore_lists(&mut self, head: &[u32], next: &[u32]) -> Result<(), Error> {
        let n = self.parts.len();
        let mut seen = vec![false; n];
        self.head = head.to_vec();
        for (k, &h) in head.iter().enumerate() {
            let c = self.coords(k);
            let mut prev = NONE;
            let mut j = h;
            while j != NONE {
                let ju = j as usize;
                if ju >= n || seen[ju] {
                    return bad(format!("cell {k}: particle {j} of {n}, or met twice"));
                }
                seen[ju] = true;
                self.link_prev[ju] = prev;
                self.link_next[ju] = next[ju];
                self.parts[ju].cell = k as u32;
                if !self.lists && !self.in_cell(ju, c) {
                    return bad(format!("particle {j} is not in its cell {k}"));
                }
                prev = j;
                j = next[ju];
            }
        }
        if let Some(i) = seen.iter().position(|s| !s) {
            return bad(format!("particle {i} is in no cell"));
        }
        Ok(())
    }

    /// Whether particle `i` is in the cell at `c` (an edge cell at a wall reaches beyond the
    /// wall), within a millionth of a cell's width.
    fn in_cell(&self, i: usize, c: [usize; D]) -> bool {
        (0..D).all(|a| {
            let w = self.width[a];
            let x = self.parts[i].pos[a];
            let periodic = self.sim_box.is_periodic(a);
            let lo_open = !periodic && c[a] == 0;
            let hi_open = !periodic && c[a] + 1 == self.cells[a];
            let tol = 1e-6 * w;
            (lo_open || x >= c[a] as f64 * w - tol) && (hi_open || x <= (c[a] + 1) as f64 * w + tol)
        })
    }
}
