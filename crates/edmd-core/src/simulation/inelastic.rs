//! Inelastic collisions (see [`crate::state::restitution`]): the normal relative velocity of a
//! pair, or of a disc at a wall, reversed and shrunk by the coefficient of restitution, with
//! the TC model's elastic collisions in quick succession.

use crate::error::Error;
use crate::events::{EventKind, EventRecord, Side, Wall};
use crate::resolve::elastic;
use crate::state::{Restitution, RestitutionLaw};

use super::Simulation;

/// The restitution as the event loop reads it.
#[derive(Clone, Debug)]
pub(super) struct Dissipation {
    pub(super) restitution: Restitution,
    /// Per pair of species `(a, b)` below `width`, at `a * width + b`, its law; pairs beyond
    /// take `restitution.all`.
    table: Vec<RestitutionLaw>,
    width: usize,
    /// Per disc, the time of its last collision (with a disc or a wall), for the TC model;
    /// empty when `tc` is 0.
    pub(super) last: Vec<f64>,
    /// Kinetic energy lost so far: kinetic energy plus this is conserved to rounding.
    pub(super) lost: f64,
    /// The normal relative speed below which a collision is elastic: [`FLOOR`] of the discs'
    /// speed scale when the restitution was set. A gas left to cool would otherwise slow
    /// without end, until the squares of its relative velocities in the contact times
    /// underflow (below 1e-154 of the speed scale) and rounding lets pairs overlap.
    pub(super) floor: f64,
}

/// The fraction of the speed scale below which collisions are elastic (see
/// [`Dissipation::floor`]): far below what any run resolves (an energy of 1e-60 of the
/// start's), far above where contact times lose their digits.
pub const FLOOR: f64 = 1e-30;

impl Dissipation {
    /// The tables for `restitution` (checked on its own) and `n` discs, none of which has
    /// collided yet.
    pub(super) fn new(restitution: Restitution, n: usize, floor: f64) -> Result<Self, Error> {
        restitution.validate()?;
        let width = restitution
            .pairs
            .iter()
            .map(|&(a, b, _)| a.max(b) as usize + 1)
            .max()
            .unwrap_or(0);
        let mut table = vec![restitution.all; width * width];
        for &(a, b, law) in &restitution.pairs {
            table[a as usize * width + b as usize] = law;
            table[b as usize * width + a as usize] = law;
        }
        let last = if restitution.tc > 0.0 {
            vec![f64::NEG_INFINITY; n]
        } else {
            Vec::new()
        };
        Ok(Dissipation {
            restitution,
            table,
            width,
            last,
            lost: 0.0,
            floor,
        })
    }

    /// Bytes held by the tables and the TC model's times.
    pub(super) fn memory_bytes(&self) -> usize {
        self.table.capacity() * size_of::<RestitutionLaw>() + self.last.capacity() * 8
    }

    #[inline(always)]
    fn law(&self, a: u16, b: u16) -> RestitutionLaw {
        let (a, b) = (a as usize, b as usize);
        if a < self.width && b < self.width {
            self.table[a * self.width + b]
        } else {
            self.restitution.all
        }
    }

    /// Whether the TC model makes a collision of the discs at `t` elastic, and notes `t` as
    /// their last collision.
    #[inline(always)]
    fn tc_elastic(&mut self, discs: &[usize], t: f64) -> bool {
        if self.last.is_empty() {
            return false;
        }
        let tc = self.restitution.tc;
        let mut quick = false;
        for &d in discs {
            quick |= t - self.last[d] < tc;
            self.last[d] = t;
        }
        quick
    }
}

impl<const D: usize> Simulation<D> {
    /// Makes collisions inelastic under `restitution` from now on (`None`, or a restitution
    /// with every coefficient 1: elastic, the default). Refused with the reason for
    /// coefficients that cannot be (see [`Restitution::validate`]), and beside a stepped
    /// potential, reaction rules, multi-disc collisions or a rule other than the elastic one.
    /// The energy lost so far starts again from 0, and the TC model's clock with no disc
    /// having collided.
    pub fn set_restitution(&mut self, restitution: Option<Restitution>) -> Result<(), Error> {
        let Some(restitution) = restitution else {
            self.dissipation = None;
            return Ok(());
        };
        restitution.validate()?;
        if restitution.is_elastic() {
            self.dissipation = None;
            return Ok(());
        }
        self.restitution_fits()?;
        if self.gravity.is_some() {
            super::field::grains_in_field(&restitution).map_err(Error::BadRestitution)?;
        }
        let mass = self.mass.iter().sum::<f64>() / self.mass.len().max(1) as f64;
        let floor = FLOOR * (self.mean_mv2 / mass).sqrt();
        let floor = if floor.is_finite() { floor } else { 0.0 };
        self.dissipation = Some(Box::new(Dissipation::new(
            restitution,
            self.body.len(),
            floor,
        )?));
        Ok(())
    }

    /// Refuses restitution with what it does not go with.
    pub(super) fn restitution_fits(&self) -> Result<(), Error> {
        let refuse = |what: &str| {
            Err(Error::BadRestitution(format!(
                "inelastic collisions do not go with {what}"
            )))
        };
        if self.steps.is_some() {
            return refuse("a stepped potential");
        }
        if self.chemistry.is_some() {
            return refuse("reaction rules");
        }
        if self.sheets.is_some() {
            return refuse("self-gravity");
        }
        if self.multi.is_some() {
            return refuse("multi-disc collisions");
        }
        if self.rule != crate::resolve::CollisionRule::Elastic {
            return refuse("a collision rule other than the elastic one");
        }
        Ok(())
    }

    /// The restitution, if collisions are inelastic.
    pub fn restitution(&self) -> Option<&Restitution> {
        self.dissipation.as_ref().map(|d| &d.restitution)
    }

    /// Kinetic energy lost in inelastic collisions so far (0 when they are elastic): the
    /// kinetic energy plus this is conserved to rounding.
    pub fn dissipated(&self) -> f64 {
        self.dissipation.as_ref().map_or(0.0, |d| d.lost)
    }

    /// Resolves the collision of `i` and `j` under the restitution; returns the record and the
    /// discs to predict again.
    #[inline(always)]
    pub(super) fn collide_inelastic(
        &mut self,
        i: usize,
        j: usize,
        t: f64,
    ) -> (EventRecord<D>, [usize; 2]) {
        let (si, sj) = (self.species[i], self.species[j]);
        let diss = self.dissipation.as_deref_mut().expect("restitution");
        let law = diss.law(si, sj);
        let quick = diss.tc_elastic(&[i, j], t);
        self.body[i].advance_to(t);
        self.body[j].advance_to(t);
        let dr = self
            .sim_box
            .minimum_image(self.body[j].pos - self.body[i].pos);
        let (vi, vj) = (self.body[i].vel, self.body[j].vel);
        let (mi, mj) = (self.mass[i], self.mass[j]);
        let dv = vj - vi;
        let dot = dv.dot(dr);
        let r2 = dr.norm2();
        let vn2 = dot * dot / r2;
        let vn = vn2.sqrt();
        let e = if quick || dot >= 0.0 || vn < diss.floor {
            1.0
        } else {
            law.at(vn)
        };
        // e = 1 is the elastic rule's impulse to the bit.
        let impulse = if e == 1.0 {
            elastic::impulse(dr, dv, mi, mj)
        } else {
            let mu = mi * mj / (mi + mj);
            diss.lost += 0.5 * mu * vn2 * (1.0 - e * e);
            dr * ((1.0 + e) * mu * dot / r2)
        };
        self.body[i].vel = vi + impulse / mi;
        self.body[j].vel = vj - impulse / mj;
        self.body[i].count = self.body[i].count.wrapping_add(1);
        self.body[j].count = self.body[j].count.wrapping_add(1);
        self.stats.disc_disc = self.stats.disc_disc.wrapping_add(1);
        let record = EventRecord {
            time: t,
            kind: EventKind::DiscDisc { i, j },
            impulse,
        };
        (record, [i, j])
    }

    /// Disc `i` at a wall under the restitution: placed exactly at contact, its normal velocity
    /// reversed and multiplied by the walls' coefficient (1 within the TC model's time).
    #[inline(always)]
    pub(super) fn bounce_inelastic(
        &mut self,
        i: usize,
        axis: usize,
        side: Side,
        t: f64,
    ) -> EventRecord<D> {
        let diss = self.dissipation.as_deref_mut().expect("restitution");
        let quick = diss.tc_elastic(&[i], t);
        let slow = self.body[i].vel[axis].abs() < diss.floor;
        let e = if quick || slow {
            1.0
        } else {
            diss.restitution.wall
        };
        if e == 1.0 {
            return self.bounce(i, axis, side, t);
        }
        let m = self.mass[i];
        let b = &mut self.body[i];
        b.advance_to(t);
        b.pos[axis] = match side {
            Side::Low => b.radius,
            Side::High => self.sim_box.lengths[axis] - b.radius,
        };
        let v = b.vel[axis];
        let mut impulse = crate::math::Vector::ZERO;
        impulse[axis] = -(1.0 + e) * m * v;
        b.vel[axis] = -e * v;
        b.count = b.count.wrapping_add(1);
        diss.lost += 0.5 * m * v * v * (1.0 - e * e);
        self.stats.wall = self.stats.wall.wrapping_add(1);
        EventRecord {
            time: t,
            kind: EventKind::Wall {
                i,
                wall: Wall { axis, side },
            },
            impulse,
        }
    }
}
