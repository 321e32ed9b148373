//! Multi-disc collisions: the cluster of discs touching a colliding pair, resolved at once.

use super::{MultiContact, Simulation};
use crate::events::{EventKind, EventRecord};
use crate::math::Vector;

impl<const D: usize> Simulation<D> {
    /// The discs of the last collision if it involved more than two (empty after a binary
    /// one). Observers of multi-disc runs read it on each `DiscDisc` event: the event's
    /// impulse is that of disc `i` only.
    pub fn last_cluster(&self) -> &[usize] {
        &self.last_cluster
    }

    /// Resolves the collision of `i` and `j` together with every disc touching them, if there
    /// is any; `None` (nothing changed) for a plain pair.
    pub(super) fn collide_cluster(
        &mut self,
        i: usize,
        j: usize,
        t: f64,
        mc: MultiContact,
    ) -> Option<EventRecord<D>> {
        // Breadth-first over contacts (gap <= tolerance * sigma), positions at time t, in the
        // frame of periodic images of the disc each one was reached from.
        let mut members = vec![i, j];
        let mut frame = vec![self.body[i].position_at(t), Vector::ZERO];
        frame[1] = frame[0]
            + self
                .sim_box
                .minimum_image(self.body[j].position_at(t) - frame[0]);
        let mut contacts = Vec::new();
        let mut k = 0;
        while k < members.len() {
            let a = members[k];
            let pa = frame[k];
            let ra = self.body[a].radius;
            let mut found = Vec::new();
            self.grid.for_each_near(self.grid.cell_of(a), |b, _| {
                if b == a {
                    return;
                }
                let pb = pa + self.sim_box.minimum_image(self.body[b].position_at(t) - pa);
                let sigma = ra + self.body[b].radius;
                if (pb - pa).norm2().sqrt() <= sigma * (1.0 + mc.tolerance) {
                    found.push((b, pb));
                }
            });
            for (b, pb) in found {
                let kb = match members.iter().position(|&x| x == b) {
                    Some(kb) => kb,
                    None => {
                        members.push(b);
                        frame.push(pb);
                        members.len() - 1
                    }
                };
                let (lo, hi) = (k.min(kb), k.max(kb));
                if !contacts.iter().any(|&(x, y, _)| (x, y) == (lo, hi)) {
                    let d = frame[hi] - frame[lo];
                    contacts.push((lo, hi, d / d.norm2().sqrt()));
                }
            }
            k += 1;
        }
        if members.len() <= 2 {
            return None;
        }
        // The colliding pair is a contact even where rounding puts it a hair beyond the
        // tolerance (with tolerance 0 it was left out: its collision was never resolved and
        // came round again at the same time, the clock stopped). Added last, so that where
        // the search found it the contacts are as they were.
        if !contacts.iter().any(|&(x, y, _)| (x, y) == (0, 1)) {
            let d = frame[1] - frame[0];
            contacts.push((0, 1, d / d.norm2().sqrt()));
        }
        let mut vel: Vec<Vector<D>> = members.iter().map(|&x| self.body[x].vel).collect();
        let mass: Vec<f64> = members.iter().map(|&x| self.mass[x]).collect();
        let cc: Vec<crate::resolve::cluster::ClusterContact<D>> = contacts
            .iter()
            .map(|&(a, b, normal)| crate::resolve::cluster::ClusterContact { a, b, normal })
            .collect();
        let before = self.body[i].vel;
        let outcome = crate::resolve::cluster::resolve_cluster(&mut vel, &mass, &cc, mc.exponent);
        if !outcome.finished {
            self.record_cluster_stall(t, &members);
        }
        for (k, &x) in members.iter().enumerate() {
            self.body[x].advance_to(t);
            self.body[x].vel = vel[k];
            self.body[x].count = self.body[x].count.wrapping_add(1);
        }
        self.stats.disc_disc = self.stats.disc_disc.wrapping_add(1);
        for &x in &members {
            self.predict_outlined(x);
        }
        let impulse = (self.body[i].vel - before) * self.mass[i];
        self.last_cluster = members;
        Some(EventRecord {
            time: t,
            kind: EventKind::DiscDisc { i, j },
            impulse,
        })
    }
}
