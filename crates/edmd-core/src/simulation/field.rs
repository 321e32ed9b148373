//! A uniform field (see [`crate::state::gravity`]): discs fly on parabolas between events.
//!
//! The hard cores' copies of the event loop never see it: a field sends the loop to the copy
//! with extras (`run_chunk`), which advances the discs of an event along their parabolas
//! before its handler runs (so that the handlers' own advances change nothing), and whose
//! predictions extrapolate the candidates along theirs, with the walls and cell crossings
//! along the field's axis at the roots of a quadratic.

use crate::error::Error;
use crate::math::Vector;
use crate::state::Gravity;

use super::{Body, Simulation};

/// Refuses inelastic collisions in a field without what keeps them from collapsing: grains
/// coming to rest on the floor, or on each other, would collide infinitely often in a finite
/// time. The TC model (`tc > 0`) bounds the rate of their collisions, and a disc at rest on a
/// wall of coefficient 0 would meet it again at once, for ever.
pub(super) fn grains_in_field(r: &crate::state::Restitution) -> Result<(), String> {
    if r.tc <= 0.0 {
        return Err(
            "inelastic collisions in a field need the TC model (tc > 0): grains coming to rest on the floor would otherwise collide infinitely often in a finite time"
                .into(),
        );
    }
    if r.wall == 0.0 {
        return Err(
            "in a field the walls' restitution must be above 0: a disc stopped dead at the floor would meet it again at once, for ever"
                .into(),
        );
    }
    Ok(())
}

/// The field's acceleration as a vector (`g` along its axis, 0 across). Built without indexing
/// by the axis, which would put the vectors it is added to in memory and back: per candidate
/// of a prediction, that store and reload made runs in a field half as fast.
#[inline(always)]
pub(super) fn acceleration<const D: usize>(f: Gravity) -> Vector<D> {
    Vector(std::array::from_fn(|a| if a == f.axis { f.g } else { 0.0 }))
}

impl<const D: usize> Body<D> {
    /// The position at `t` under the field (if any).
    #[inline(always)]
    pub(super) fn position_in(&self, t: f64, field: Option<Gravity>) -> Vector<D> {
        let p = self.position_at(t);
        match field {
            Some(f) => {
                let dt = t - self.time;
                p + acceleration::<D>(f) * (0.5 * dt * dt)
            }
            None => p,
        }
    }

    /// The velocity at `t` under the field (if any).
    #[inline(always)]
    pub(super) fn velocity_in(&self, t: f64, field: Option<Gravity>) -> Vector<D> {
        match field {
            Some(f) => self.vel + acceleration::<D>(f) * (t - self.time),
            None => self.vel,
        }
    }

    /// Moves the disc's clock to `t` under the field (if any).
    #[inline(always)]
    pub(super) fn advance_in(&mut self, t: f64, field: Option<Gravity>) {
        let p = self.position_in(t, field);
        self.vel = self.velocity_in(t, field);
        self.pos = p;
        self.time = t;
    }
}

impl<const D: usize> Simulation<D> {
    /// Puts the discs in a uniform field from now on (`None`: none, the default): each disc's
    /// velocity along `gravity.axis` grows by `gravity.g` per unit time. Refused with the
    /// reason for a field that cannot be ([`Gravity::validate`]), along a periodic axis (a
    /// disc would fall for ever), and beside a stepped potential, barriers or multi-disc
    /// collisions.
    pub fn set_gravity(&mut self, gravity: Option<Gravity>) -> Result<(), Error> {
        if let Some(f) = gravity {
            f.validate(D)?;
            self.gravity_fits(f)?;
        }
        // Every disc to now under the old field, then every event predicted under the new.
        let now = self.now;
        let old = self.gravity;
        for b in self.body.iter_mut() {
            b.advance_in(now, old);
        }
        self.event_time = now;
        self.gravity = gravity;
        self.schedule_all();
        Ok(())
    }

    /// Refuses a field with what it does not go with.
    pub(super) fn gravity_fits(&self, f: Gravity) -> Result<(), Error> {
        let refuse = |what: &str| Err(Error::BadField(what.to_string()));
        if self.sim_box.is_periodic(f.axis) {
            return refuse(
                "the field's axis must have walls: along a periodic axis a disc would fall for ever",
            );
        }
        if self.steps.is_some() {
            return refuse("a field does not go with a stepped potential");
        }
        if !self.barriers.is_empty() {
            return refuse("a field does not go with barriers");
        }
        if self.multi.is_some() {
            return refuse("a field does not go with multi-disc collisions");
        }
        if self.shear.is_some() {
            return refuse("a field does not go with shear");
        }
        if self.sheets.is_some() {
            return refuse("a field does not go with self-gravity");
        }
        if self.ring.is_some() {
            return refuse("a field does not go with a ring");
        }
        if let Some(d) = &self.dissipation {
            grains_in_field(&d.restitution).map_err(Error::BadField)?;
        }
        Ok(())
    }

    /// The field, if any.
    pub fn gravity(&self) -> Option<Gravity> {
        self.gravity
    }

    /// The field's potential energy now, `-sum m g x` over the discs (`x` the coordinate
    /// along the field's axis, from the wall at 0); 0 without a field.
    pub fn field_energy(&self) -> f64 {
        let Some(f) = self.gravity else {
            return 0.0;
        };
        self.body
            .iter()
            .zip(self.mass.iter())
            .map(|(b, m)| -m * f.g * b.position_in(self.now, self.gravity)[f.axis])
            .sum()
    }

    /// Disc `i`'s flight: the uniform field, its own under self-gravity, or none.
    #[inline(always)]
    pub(super) fn flight(&self, i: usize) -> Option<Gravity> {
        match self.sheets.as_deref() {
            Some(s) => Some(s.field(i)),
            None => self.gravity,
        }
    }

    /// Disc `i`'s position at `t` (extrapolated from its own clock, on its flight).
    #[inline]
    pub(super) fn position_of(&self, i: usize, t: f64) -> Vector<D> {
        if let Some(o) = self.ring.as_deref() {
            return self.body[i].on_orbit(t, o).0;
        }
        self.body[i].position_in(t, self.flight(i))
    }

    /// Disc `i`'s velocity at `t` (on its flight).
    #[inline]
    pub(super) fn velocity_of(&self, i: usize, t: f64) -> Vector<D> {
        if let Some(o) = self.ring.as_deref() {
            return self.body[i].on_orbit(t, o).1;
        }
        self.body[i].velocity_in(t, self.flight(i))
    }
}
