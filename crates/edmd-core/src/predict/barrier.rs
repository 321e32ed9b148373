//! Disc-barrier contact: the face of an internal wall, and the edges of its door.
//!
//! A barrier perpendicular to axis `a` at `x0` is a zero-thickness wall; its solid parts are
//! the stretches outside the door `(lo, hi)` along the other axis `b`. A disc of radius `r`
//! touches a face when its centre reaches `x0 - r` (coming from below) or `x0 + r` (from above)
//! with the contact point outside the door; it touches a door edge, a point, when its centre
//! comes within `r` of it (the disc-disc kernel with a point at rest and `sigma = r`). A disc
//! whose face contact would fall inside the door goes into the doorway instead, where only the
//! edges can stop it.
//!
//! Barriers are two-dimensional (a line across a plane box; its door an interval along the
//! other axis): the kernels take vectors of any dimension so that the one event loop can call
//! them, but [`crate::Simulation`] refuses barriers in a box of more than two dimensions.

use crate::math::{Vector, DIM};
use crate::predict::{interval_exit, time_to_contact};

/// Where a disc meets a barrier first, if at all.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Contact {
    /// The solid face.
    Face,
    /// A door edge: `0` the edge at `lo`, `1` the one at `hi`.
    Edge(u8),
}

/// The other axis of the plane (barriers are 2D).
#[inline(always)]
pub fn across(axis: usize) -> usize {
    (axis + 1) % DIM
}

/// Time until a disc at `p` moving at `v` with radius `r` touches the barrier (axis `axis`,
/// position `x0`, door `door`), and where.
#[inline]
pub fn time_to_barrier<const D: usize>(
    p: Vector<D>,
    v: Vector<D>,
    r: f64,
    axis: usize,
    x0: f64,
    door: Option<(f64, f64)>,
) -> Option<(f64, Contact)> {
    let b = across(axis);
    let mut best: Option<(f64, Contact)> = None;
    // The face on the disc's side, reached only if moving towards it.
    let face = if p[axis] < x0 {
        interval_exit(p[axis], v[axis], f64::NEG_INFINITY, x0 - r).filter(|_| v[axis] > 0.0)
    } else {
        interval_exit(p[axis], v[axis], x0 + r, f64::INFINITY).filter(|_| v[axis] < 0.0)
    };
    if let Some((dt, _)) = face {
        let y = p[b] + v[b] * dt;
        let solid = match door {
            None => true,
            Some((lo, hi)) => y <= lo || y >= hi,
        };
        if solid && dt.is_finite() {
            best = Some((dt, Contact::Face));
        }
    }
    if let Some((lo, hi)) = door {
        for (k, e) in [lo, hi].into_iter().enumerate() {
            let mut q = Vector::ZERO;
            q[axis] = x0;
            q[b] = e;
            if let Some(dt) = time_to_contact(q - p, -v, r) {
                if best.is_none_or(|(t, _)| dt < t) {
                    best = Some((dt, Contact::Edge(k as u8)));
                }
            }
        }
    }
    best
}

/// Time until the centre of a disc on the `below` side (`p[axis] < x0` when true) moving at `v`
/// reaches the barrier plane, if it is then inside the door: the moment a demon decides.
#[inline]
pub fn time_to_doorway<const D: usize>(
    p: Vector<D>,
    v: Vector<D>,
    axis: usize,
    x0: f64,
    door: (f64, f64),
    below: bool,
) -> Option<f64> {
    let toward = if below { v[axis] > 0.0 } else { v[axis] < 0.0 };
    if !toward {
        return None;
    }
    let dt = ((x0 - p[axis]) / v[axis]).max(0.0);
    let y = p[across(axis)] + v[across(axis)] * dt;
    (y > door.0 && y < door.1).then_some(dt)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector {
        Vector::new([x, y])
    }

    #[test]
    fn solid_barrier_face() {
        // Barrier x = 5, disc r = 1 at x = 2 moving +1: face contact when x = 4, t = 2.
        assert_eq!(
            time_to_barrier(v(2.0, 3.0), v(1.0, 0.5), 1.0, 0, 5.0, None),
            Some((2.0, Contact::Face))
        );
        // From above, moving -2 from x = 9: contact at x = 6, t = 1.5.
        assert_eq!(
            time_to_barrier(v(9.0, 3.0), v(-2.0, 0.0), 1.0, 0, 5.0, None),
            Some((1.5, Contact::Face))
        );
        // Moving away: nothing.
        assert_eq!(
            time_to_barrier(v(2.0, 3.0), v(-1.0, 0.0), 1.0, 0, 5.0, None),
            None
        );
    }

    #[test]
    fn door_lets_a_centred_disc_through_and_edges_stop_others() {
        let door = Some((4.0, 8.0));
        // Centred in a door of width 4 with r = 1: passes, touches nothing.
        assert_eq!(
            time_to_barrier(v(2.0, 6.0), v(1.0, 0.0), 1.0, 0, 5.0, door),
            None
        );
        // At y = 4.5, moving +x: the lower edge (5, 4) is hit when (x - 5)^2 + 0.25 = 1,
        // x = 5 - sqrt(0.75), t = 3 - sqrt(0.75).
        let (t, c) = time_to_barrier(v(2.0, 4.5), v(1.0, 0.0), 1.0, 0, 5.0, door).unwrap();
        assert_eq!(c, Contact::Edge(0));
        assert!((t - (3.0 - 0.75f64.sqrt())).abs() < 1e-15);
        // At y = 3.9 the contact point at t = 2 is on the solid part: face.
        assert_eq!(
            time_to_barrier(v(2.0, 3.9), v(1.0, 0.0), 1.0, 0, 5.0, door),
            Some((2.0, Contact::Face))
        );
    }

    #[test]
    fn doorway_time_is_the_centre_crossing() {
        assert_eq!(
            time_to_doorway(v(2.0, 6.0), v(1.0, 0.0), 0, 5.0, (4.0, 8.0), true),
            Some(3.0)
        );
        assert_eq!(
            time_to_doorway(v(2.0, 6.0), v(1.0, 0.0), 0, 5.0, (4.0, 8.0), false),
            None
        );
        assert_eq!(
            time_to_doorway(v(2.0, 9.0), v(1.0, 0.0), 0, 5.0, (4.0, 8.0), true),
            None
        );
    }
}
