//! A brute-force event-driven simulator written straight from the Princeton assignment's
//! formulas: every event, all pairs and all walls are examined and every disc is moved. O(N^2)
//! per event, no cells, no queue, no local clocks: obviously right, and slow.

use edmd_core::{Disc, Vector};

/// A processed event: `(time, i, Some(j))` for a pair, `(time, i, None)` for a wall.
pub type NaiveEvent = (f64, usize, Option<usize>);

/// Runs until `t_end` in the walled box `[0, l]^D` with the elastic rule; returns the events.
pub fn run<const D: usize>(discs: &mut [Disc<D>], l: f64, t_end: f64) -> Vec<NaiveEvent> {
    let n = discs.len();
    let mut t = 0.0;
    let mut events = Vec::new();
    loop {
        let mut best = (f64::INFINITY, 0usize, None, 0usize);
        for i in 0..n {
            for a in 0..D {
                let (x, v, r) = (discs[i].pos[a], discs[i].vel[a], discs[i].radius);
                let dt = if v > 0.0 {
                    (l - r - x) / v
                } else if v < 0.0 {
                    (r - x) / v
                } else {
                    f64::INFINITY
                };
                if dt.max(0.0) < best.0 {
                    best = (dt.max(0.0), i, None, a);
                }
            }
            for j in i + 1..n {
                let dr = discs[j].pos - discs[i].pos;
                let dv = discs[j].vel - discs[i].vel;
                let b = dr.dot(dv);
                if b >= 0.0 {
                    continue;
                }
                let s = discs[i].radius + discs[j].radius;
                let d = b * b - dv.norm2() * (dr.norm2() - s * s);
                if d < 0.0 {
                    continue;
                }
                let dt = (-(b + d.sqrt()) / dv.norm2()).max(0.0);
                if dt < best.0 {
                    best = (dt, i, Some(j), 0);
                }
            }
        }
        if t + best.0 > t_end {
            return events;
        }
        for d in discs.iter_mut() {
            d.pos = d.pos.advanced(d.vel, best.0);
        }
        t += best.0;
        let (i, a) = (best.1, best.3);
        match best.2 {
            None => discs[i].vel[a] = -discs[i].vel[a],
            Some(j) => {
                let dr = discs[j].pos - discs[i].pos;
                let dv = discs[j].vel - discs[i].vel;
                let (mi, mj) = (discs[i].mass, discs[j].mass);
                let jmp: Vector<D> = dr * (2.0 * mi * mj * dv.dot(dr) / ((mi + mj) * dr.norm2()));
                discs[i].vel += jmp / mi;
                discs[j].vel -= jmp / mj;
            }
        }
        events.push((t, i, best.2));
    }
}
