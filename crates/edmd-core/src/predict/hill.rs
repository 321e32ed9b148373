//! Flights under Hill's equations, and the times of events along them.
//!
//! In the frame that rotates with a ring's local orbital frequency `Omega`, with x along the
//! orbit (the flow), y outwards from the patch's centre and z out of the ring plane, a
//! particle flies as Hill's equations say:
//!
//! ```text
//! x'' = -2 Omega y'        y'' = 2 Omega x' + 3 Omega^2 y        z'' = -Omega^2 z
//! ```
//!
//! The solution is an epicycle about a guiding centre that drifts with the Keplerian shear
//! `x' = -3/2 Omega y_g` ([`advance`]): with `C = x'_0 + 2 Omega y_0` (conserved) and
//! `tau = t - t_0`,
//!
//! ```text
//! x = x_0 + C (4 S - 3 tau) - 2 y_0 sin(Omega tau) - 2 y'_0 K
//! y = y_0 cos(Omega tau) + y'_0 S + 2 C K
//! z = z_0 cos(Omega tau) + z'_0 S
//! ```
//!
//! with `S = sin(Omega tau) / Omega` and `K = (1 - cos(Omega tau)) / Omega` (taken as
//! `2 sin^2(Omega tau / 2) / Omega`, which keeps its digits for small `Omega tau`).
//!
//! The equations are linear, so the difference of two flights is a flight too, and so is a
//! flight's image shifted by `L_y` radially and moving at `-3/2 Omega L_y` along x (the
//! shearing-periodic images). A pair's separation `d(tau)` is therefore [`advance`] of its
//! separation and relative velocity now. The contact `|d(tau)|^2 = sigma^2` has no closed
//! form; [`first_root`] brackets it from below with a bound on the second derivative (the
//! safe-step method of Frenkel and Maguire, Mol. Phys. 49, 503 (1983), the one DynamO's
//! `frenkelRootSearch` uses for its non-linear flights; M. N. Bannerman, R. Sargant and
//! L. Lue, J. Comput. Chem. 32, 3329 (2011)): from a point where `f >= 0`, `f(tau + delta) >=
//! f + f' delta - M delta^2 / 2` for `|f''| <= M`, so the step to that parabola's first root
//! never passes a root of `f`. Near a simple root the steps converge quadratically; it stops
//! when `f` is within [`CONTACT_TOLERANCE`] of zero, which leaves a gap of at most about
//! `CONTACT_TOLERANCE / 2` contact distances at the contact it reports.

use crate::math::Vector;

/// The relative tolerance of a contact found by [`contact_time`]: `|d|^2 <= sigma^2 (1 +
/// CONTACT_TOLERANCE)`, a gap of at most `5e-13` of the contact distance.
pub const CONTACT_TOLERANCE: f64 = 1e-12;

/// The most safe steps a search takes before it gives up with the time it reached (which is
/// then a time before any root: the caller looks again from there).
pub const MAX_STEPS: u32 = 200;

/// `(sin(w t) / w, (1 - cos(w t)) / w, sin(w t), cos(w t))`, without cancellation for small
/// `w t`: all from the half angle's sine and cosine (one call of `sin_cos`, where two calls
/// took a third of a ring's time).
#[inline(always)]
fn trig(omega: f64, tau: f64) -> (f64, f64, f64, f64) {
    if omega == 0.0 {
        return (tau, 0.0, 0.0, 1.0);
    }
    let (sh, ch) = (0.5 * omega * tau).sin_cos();
    let s = 2.0 * sh * ch;
    let k = 2.0 * sh * sh;
    (s / omega, k / omega, s, 1.0 - k)
}

/// Position and velocity after `tau` along the flight from `p` and `v` (relative to the
/// patch's centre radially and vertically; any x), at orbital frequency `omega >= 0`. Two
/// or three dimensions (x, y and z); `omega = 0` is the straight line.
#[inline]
pub fn advance<const D: usize>(
    p: Vector<D>,
    v: Vector<D>,
    omega: f64,
    tau: f64,
) -> (Vector<D>, Vector<D>) {
    debug_assert!(D >= 2);
    let (s1, k1, s, c) = trig(omega, tau);
    let (y0, u, w) = (p[1], v[0], v[1]);
    let cc = u + 2.0 * omega * y0;
    let mut q = p;
    let mut dq = v;
    q[0] = p[0] + cc * (4.0 * s1 - 3.0 * tau) - 2.0 * y0 * s - 2.0 * w * k1;
    q[1] = y0 * c + w * s1 + 2.0 * cc * k1;
    dq[0] = cc * (4.0 * c - 3.0) - 2.0 * omega * y0 * c - 2.0 * w * s;
    dq[1] = (2.0 * cc - omega * y0) * s + w * c;
    if D > 2 {
        q[2] = p[2] * c + v[2] * s1;
        dq[2] = -omega * p[2] * s + v[2] * c;
    }
    (q, dq)
}

/// Bounds on the flight from `p` and `v`: `(a_x, a_y, a_z)`, the largest accelerations along
/// each axis anywhere on it (`2 Omega^2 E`, `Omega^2 E` and `Omega^2 E_z` for epicycles of
/// radial amplitude `E` and vertical amplitude `E_z`, both constants of the motion).
#[inline]
pub fn acceleration_bounds<const D: usize>(p: Vector<D>, v: Vector<D>, omega: f64) -> [f64; 3] {
    // Radially y - y_g = a cos + b sin, with y_g = 2 C / Omega, written so that it does
    // not divide by Omega: Omega^2 E = Omega |(y_0 - y_g, y'_0 / Omega)| Omega.
    let cc = v[0] + 2.0 * omega * p[1];
    let oa = omega * p[1] - 2.0 * cc; // Omega (y_0 - y_g)
    let e = omega * norm(oa, v[1]); // Omega^2 E
    let ez = if D > 2 {
        omega * norm(omega * p[2], v[2])
    } else {
        0.0
    };
    // A little more than the bounds, against rounding in their own arithmetic.
    let pad = 1.0 + 1e-12;
    [2.0 * e * pad, e * pad, ez * pad]
}

/// `sqrt(a^2 + b^2)`, by `hypot` only where the squares overflow (`hypot` took 40% of a
/// ring's time when it was called for every candidate).
#[inline(always)]
fn norm(a: f64, b: f64) -> f64 {
    let s = (a * a + b * b).sqrt();
    if s.is_finite() {
        s
    } else {
        a.hypot(b)
    }
}

/// The outcome of a search along a flight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Found {
    /// The event is at this time from now.
    At(f64),
    /// None before the horizon.
    Never,
    /// The search stopped after [`MAX_STEPS`] at this time, before any root: look again
    /// from there.
    Unresolved(f64),
}

/// A bound on `|f''|` over a window of length `w` ahead: `c0 + c1 w + c2 w^2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curvature {
    /// The bound's terms in `w^0`, `w^1` and `w^2`.
    pub c: [f64; 3],
}

impl Curvature {
    #[inline(always)]
    fn over(&self, w: f64) -> f64 {
        self.c[0] + w * (self.c[1] + w * self.c[2])
    }
}

/// How far `f` (at `g >= 0`, slope `df`) can go with `|f''| <= m` before it can reach zero:
/// the first root of `g + df d - m d^2 / 2`, in the form without cancellation.
#[inline(always)]
fn safe_step(g: f64, df: f64, m: f64) -> f64 {
    let disc = (df * df + 2.0 * m * g).sqrt();
    if df < 0.0 {
        2.0 * g / (disc - df)
    } else if m > 0.0 {
        (df + disc) / m
    } else {
        f64::INFINITY
    }
}

/// The first time in `[0, horizon]` at which `f` falls to within `tol` of zero, `eval(tau)`
/// giving `f`, `f'` and the [`Curvature`] bound ahead of `tau`. Each step is safe over the
/// rest of the horizon, then tried over a window twice its length, whose smaller bound
/// allows a longer step (the bound over the whole horizon grows with it).
/// `f(0)` may be a rounding error below zero: a pair (or a disc at a wall) found so and
/// approaching (`f' < 0`) meets at once; found so and receding, the search starts from
/// `f = 0`.
#[inline]
pub fn first_root(
    horizon: f64,
    tol: f64,
    mut eval: impl FnMut(f64) -> (f64, f64, Curvature),
) -> Found {
    let mut tau = 0.0;
    let (mut f, mut df, mut m) = eval(0.0);
    if f <= tol && df < 0.0 {
        return Found::At(0.0);
    }
    for _ in 0..MAX_STEPS {
        if tau >= horizon || tau.is_nan() {
            return Found::Never;
        }
        let g = f.max(0.0);
        let rest = horizon - tau;
        let first = safe_step(g, df, m.over(rest));
        // (Not below the rest, or NaN from numbers beyond range.)
        if first.partial_cmp(&rest) != Some(std::cmp::Ordering::Less) {
            return Found::Never;
        }
        let window = 2.0 * first;
        let step = if window < rest {
            safe_step(g, df, m.over(window)).min(window)
        } else {
            first
        };
        let next = tau + step;
        if next == tau {
            // A step too small to move the clock: at the root to the clock's resolution,
            // or (a bound too large for the numbers) nowhere it can say.
            return if f <= 4.0 * tol {
                Found::At(tau)
            } else {
                Found::Unresolved(tau)
            };
        }
        tau = next;
        (f, df, m) = eval(tau);
        // Within the tolerance and receding (`df > 0`, `f > 0`): a graze that does not touch.
        // Go on past it.
        if f <= tol && (df <= 0.0 || f <= 0.0) {
            return Found::At(tau);
        }
    }
    Found::Unresolved(tau)
}

/// The first time within `horizon` at which a pair whose separation is `d` and relative
/// velocity `dv` now (the partner's less the disc's) comes to contact distance `sigma`
/// under Hill's equations at `omega`.
#[inline]
pub fn contact_time<const D: usize>(
    d: Vector<D>,
    dv: Vector<D>,
    sigma: f64,
    omega: f64,
    horizon: f64,
) -> Found {
    let s2 = sigma * sigma;
    // A pair that cannot close the gap before the horizon at the fastest its relative speed
    // can grow is never looked at closer. `|d'| <= |d'_0| + a tau`.
    let [ax, ay, az] = acceleration_bounds(d, dv, omega);
    let a = (ax * ax + ay * ay + az * az).sqrt();
    let dist = d.norm2().sqrt();
    let speed = dv.norm2().sqrt();
    if horizon.is_finite() && dist - sigma > horizon * (speed + 0.5 * a * horizon) {
        return Found::Never;
    }
    let tol = CONTACT_TOLERANCE * s2;
    first_root(horizon, tol, |tau| {
        let (q, w) = if tau == 0.0 {
            (d, dv)
        } else {
            advance(d, dv, omega, tau)
        };
        // f'' = 2 (|d'|^2 + d . d''), and over a window W ahead |d'| <= |w| + a W and
        // |d| <= |q| + |w| W + a W^2: 2 ((|w| + a W)^2 + (|q| + |w| W + a W^2) a).
        let (r, v) = (q.norm2().sqrt(), w.norm2().sqrt());
        let c = [2.0 * (v * v + r * a), 6.0 * a * v, 4.0 * a * a];
        (q.norm2() - s2, 2.0 * q.dot(w), Curvature { c })
    })
}

/// A plane across one axis, reached from below (`high`) or from above.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// The axis it crosses.
    pub axis: usize,
    /// Where, along that axis.
    pub at: f64,
    /// Whether it is the high side of the interval the particle is in.
    pub high: bool,
}

/// The first time within `horizon` at which the flight from `p` and `v` reaches `edge`, to
/// within `tol`. For walls and for the grid.
#[inline]
pub fn edge_time<const D: usize>(
    p: Vector<D>,
    v: Vector<D>,
    omega: f64,
    edge: Edge,
    tol: f64,
    horizon: f64,
) -> Found {
    let Edge {
        axis,
        at: edge,
        high,
    } = edge;
    let a = acceleration_bounds(p, v, omega)[axis];
    let sign = if high { 1.0 } else { -1.0 };
    first_root(horizon, tol, |tau| {
        let (q, w) = if tau == 0.0 {
            (p, v)
        } else {
            advance(p, v, omega, tau)
        };
        (
            sign * (edge - q[axis]),
            -sign * w[axis],
            Curvature { c: [a, 0.0, 0.0] },
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hill's equations integrated by classical Runge-Kutta in small steps.
    fn integrate(p: Vector<3>, v: Vector<3>, omega: f64, tau: f64, steps: usize) -> Vector<3> {
        let f = |p: Vector<3>, v: Vector<3>| {
            Vector([
                -2.0 * omega * v[1],
                2.0 * omega * v[0] + 3.0 * omega * omega * p[1],
                -omega * omega * p[2],
            ])
        };
        let h = tau / steps as f64;
        let (mut p, mut v) = (p, v);
        for _ in 0..steps {
            let (k1p, k1v) = (v, f(p, v));
            let (k2p, k2v) = (
                v + k1v * (h / 2.0),
                f(p + k1p * (h / 2.0), v + k1v * (h / 2.0)),
            );
            let (k3p, k3v) = (
                v + k2v * (h / 2.0),
                f(p + k2p * (h / 2.0), v + k2v * (h / 2.0)),
            );
            let (k4p, k4v) = (v + k3v * h, f(p + k3p * h, v + k3v * h));
            p += (k1p + k2p * 2.0 + k3p * 2.0 + k4p) * (h / 6.0);
            v += (k1v + k2v * 2.0 + k3v * 2.0 + k4v) * (h / 6.0);
        }
        p
    }

    #[test]
    fn the_closed_form_solves_hills_equations() {
        let (p, v) = (Vector([0.3, -1.2, 0.4]), Vector([0.7, 0.25, -0.6]));
        for &omega in &[0.0, 1e-6, 0.5, 1.0, 3.0] {
            for &tau in &[1e-9, 0.01, 0.7, 5.0, 40.0] {
                let (q, _) = advance(p, v, omega, tau);
                let r = integrate(p, v, omega, tau, 20_000);
                let scale = 1.0 + r.norm2().sqrt();
                assert!(
                    (q - r).norm2().sqrt() < 1e-9 * scale,
                    "omega {omega} tau {tau}: {q:?} against {r:?}"
                );
            }
        }
    }

    #[test]
    fn velocities_are_the_positions_derivative_and_the_flow_is_keplerian() {
        let (p, v) = (Vector([1.0, 0.8, -0.2]), Vector([-0.3, 0.5, 0.1]));
        let (omega, tau, h) = (1.3, 2.1, 1e-6);
        let (_, w) = advance(p, v, omega, tau);
        let (a, _) = advance(p, v, omega, tau + h);
        let (b, _) = advance(p, v, omega, tau - h);
        assert!(((a - b) * (0.5 / h) - w).norm2().sqrt() < 1e-8);
        // On the shear flow, x' = -3/2 Omega y, a particle stays on it.
        let p = Vector([0.0, 2.0, 0.0]);
        let v = Vector([-1.5 * omega * 2.0, 0.0, 0.0]);
        let (q, w) = advance(p, v, omega, 10.0);
        assert!((q[1] - 2.0).abs() < 1e-13 && (w - v).norm2().sqrt() < 1e-13);
        assert!((q[0] + 30.0 * omega).abs() < 1e-12);
        // The Jacobi integral v^2 / 2 - 3/2 Omega^2 y^2 + Omega^2 z^2 / 2 is conserved.
        let jacobi = |p: Vector<3>, v: Vector<3>| {
            0.5 * v.norm2() - 1.5 * omega * omega * p[1] * p[1] + 0.5 * omega * omega * p[2] * p[2]
        };
        let (p, v) = (Vector([1.0, 0.8, -0.2]), Vector([-0.3, 0.5, 0.1]));
        let (q, w) = advance(p, v, omega, 7.7);
        assert!((jacobi(p, v) - jacobi(q, w)).abs() < 1e-13);
    }

    /// The first contact found by sampling finely and bisecting.
    fn brute(d: Vector<3>, dv: Vector<3>, sigma: f64, omega: f64, horizon: f64) -> Option<f64> {
        let f = |t: f64| advance(d, dv, omega, t).0.norm2() - sigma * sigma;
        let n = 200_000;
        let h = horizon / n as f64;
        for k in 0..n {
            let (a, b) = (k as f64 * h, (k + 1) as f64 * h);
            if f(b) <= 0.0 {
                let (mut lo, mut hi) = (a, b);
                for _ in 0..100 {
                    let m = 0.5 * (lo + hi);
                    if f(m) <= 0.0 {
                        hi = m
                    } else {
                        lo = m
                    }
                }
                return Some(hi);
            }
        }
        None
    }

    #[test]
    fn contacts_are_found_as_a_fine_search_finds_them() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rand = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let (mut met, mut missed) = (0, 0);
        for _ in 0..400 {
            let d = Vector([3.0 * rand(), 3.0 * rand(), 1.5 * rand()]);
            if d.norm2() <= 1.0 {
                continue;
            }
            // Half aimed at each other, half at random.
            let aim = if rand() > 0.0 { -0.9 } else { 0.0 };
            let dv = Vector([rand(), rand(), rand()]) * 0.8 + d * aim;
            // Slow to fast rotation: curved paths, and epicycles that turn pairs back.
            let omega = 0.05 + 0.6 * rand().abs();
            let horizon = 6.0;
            let want = brute(d, dv, 1.0, omega, horizon);
            let got = contact_time(d, dv, 1.0, omega, horizon);
            match (want, got) {
                (Some(t), Found::At(u)) => {
                    met += 1;
                    // The brute force's grid can step over a graze the search finds; where
                    // both find one, they agree.
                    assert!((t - u).abs() < 1e-6, "{d:?} {dv:?}: {t} against {u}");
                    let gap = advance(d, dv, omega, u).0.norm2() - 1.0;
                    assert!(gap.abs() <= 2.0 * CONTACT_TOLERANCE, "{gap}");
                }
                (None, Found::Never) => missed += 1,
                (None, Found::At(u)) => {
                    // A graze between the grid's points: it does touch there.
                    let gap = advance(d, dv, omega, u).0.norm2() - 1.0;
                    assert!(gap <= 2.0 * CONTACT_TOLERANCE);
                }
                other => panic!("{d:?} {dv:?} omega {omega}: {other:?}"),
            }
        }
        assert!(met > 50 && missed > 50, "{met} met, {missed} missed");
    }

    #[test]
    fn a_graze_is_not_stepped_over() {
        // A pair passing at a closest distance a hair inside contact, in a straight line
        // (omega 0) and with curvature.
        for &omega in &[0.0, 0.8] {
            let d = Vector([-4.0, 1.0 - 1e-9, 0.0]);
            let dv = Vector([1.0, 0.0, 0.0]);
            // Along x at speed 1 from -4: the closest pass near tau = 4 (curved a little).
            let got = contact_time(d, dv, 1.0, omega, 10.0);
            if omega == 0.0 {
                let Found::At(u) = got else { panic!("{got:?}") };
                assert!((u - (4.0 - (2e-9f64).sqrt())).abs() < 1e-6, "{u}");
            }
            // Just outside contact, nothing.
            let d = Vector([-4.0, 1.0 + 1e-9, 0.0]);
            assert_eq!(contact_time(d, dv, 1.0, 0.0, 10.0), Found::Never);
        }
    }

    #[test]
    fn a_pair_touching_and_receding_is_not_met_again_at_once() {
        let d = Vector([1.0, 0.0, 0.0]);
        let dv = Vector([0.5, 0.1, 0.0]);
        assert_eq!(contact_time(d, dv, 1.0, 1.0, 0.5), Found::Never);
        // Approaching at contact: at once.
        assert_eq!(contact_time(d, -dv, 1.0, 1.0, 0.5), Found::At(0.0));
    }

    #[test]
    fn edges_are_reached_when_the_orbit_says() {
        // Vertical oscillation of amplitude 1 from z = 0 upwards: reaches z = 0.5 at
        // Omega t = pi / 6.
        let omega = 2.0;
        let p = Vector([0.0, 0.0, 0.0]);
        let v = Vector([0.0, 0.0, omega]);
        let Found::At(t) = edge_time(
            p,
            v,
            omega,
            Edge {
                axis: 2,
                at: 0.5,
                high: true,
            },
            1e-14,
            10.0,
        ) else {
            panic!()
        };
        assert!(
            (t - std::f64::consts::PI / 6.0 / omega).abs() < 1e-12,
            "{t}"
        );
        // Never reaches z = 1.5.
        assert_eq!(
            edge_time(
                p,
                v,
                omega,
                Edge {
                    axis: 2,
                    at: 1.5,
                    high: true
                },
                1e-14,
                100.0
            ),
            Found::Never
        );
        // Down to z = -0.5 first at Omega t = pi + pi / 6.
        let Found::At(t) = edge_time(
            p,
            v,
            omega,
            Edge {
                axis: 2,
                at: -0.5,
                high: false,
            },
            1e-14,
            10.0,
        ) else {
            panic!()
        };
        assert!(
            (t - 7.0 * std::f64::consts::PI / 6.0 / omega).abs() < 1e-12,
            "{t}"
        );
    }
}
