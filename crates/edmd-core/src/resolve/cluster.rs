//! Multi-disc collisions: the impulsive limit of stiff elastic contacts.
//!
//! When a struck disc touches others (a racked triangle, a Newton's cradle), the binary rule
//! has to process the contacts one after another in some order, and the order decides the
//! outcome: a symmetric rack breaks asymmetrically. Real balls are elastic solids, and during
//! the very short impact every contact in the cluster pushes at the same time. This kernel
//! models exactly that: each contact `k` between discs `a` and `b` (unit normal `n_k` from
//! `a` to `b`) is a spring with force `f_k = delta_k^p` along `n_k` (Hertz: `p = 3/2` for
//! elastic spheres), where `delta_k >= 0` is its compression, growing at the contact's closing
//! speed `-(v_b - v_a) . n_k` and never pulling (no tension). Positions are frozen (the impact
//! is instantaneous on the scale of the motion); the impact ends when no contact is compressed
//! or closing. For a power-law force the outcome does not depend on the stiffness, so there is
//! no free parameter besides `p`.
//!
//! The compressions and velocities are integrated with the leapfrog scheme, which treats every
//! contact at once: a symmetric cluster hit symmetrically stays symmetric (to rounding). The
//! outgoing velocities conserve momentum exactly (internal forces come in pairs); the small
//! energy error of the integrator (about 1e-7 relative) is removed at the end by scaling the
//! velocities relative to the cluster's centre of mass, so kinetic energy is conserved to
//! rounding as well.

use crate::math::Vector;

/// One contact of a cluster.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterContact<const D: usize = 2> {
    /// First disc (index into the cluster's arrays).
    pub a: usize,
    /// Second disc.
    pub b: usize,
    /// Unit normal from `a` to `b`.
    pub normal: Vector<D>,
}

/// The most contact updates (steps times contacts) one cluster may take: about 0.2 s. Ordinary
/// clusters take a few thousand steps; a cluster that needs more (masses or speeds in contact
/// that differ by many orders of magnitude: a light disc pinched between heavy ones bounces
/// about `sqrt(M / m)` times) is given up, see [`Outcome::finished`].
pub const MAX_CONTACT_STEPS: usize = 10_000_000;

/// Closing speeds at or below this fraction of the cluster's largest speed (relative to its
/// centre of mass) are rounding, not motion: the integrator's forces can no longer change such
/// a velocity, so waiting for them would never end. Such contacts are settled by the binary
/// elastic rule instead (see [`resolve_cluster`]).
const ROUNDING_SPEED: f64 = 1e-9;

/// Spring energy, relative to the cluster's kinetic energy, that counts as none.
const ROUNDING_ENERGY: f64 = 1e-15;

/// What [`resolve_cluster`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The total impulse along each contact's normal (received by `b`; `a` receives the
    /// negative).
    pub impulse: Vec<f64>,
    /// Integration steps taken.
    pub steps: usize,
    /// False if the impact did not end within [`MAX_CONTACT_STEPS`]. The velocities are then
    /// those reached, with the energy restored and every contact left opening, but they are not
    /// the impact's outcome.
    pub finished: bool,
}

/// Resolves an impulsive multi-contact collision in place.
///
/// The impact ends when every contact is released and opening, or when what is left is
/// rounding: closing speeds below `1e-9` of the largest speed with no spring energy to speak of
/// (two touching discs moving together stay at a closing speed of `1e-13` or so, and the force
/// their tiny compression makes is below what a velocity can resolve). Afterwards, any contact
/// still closing by a rounding amount has the binary elastic rule applied to it (a few passes
/// over the contacts), so that no contact leaves closing and collides again at once.
pub fn resolve_cluster<const D: usize>(
    vel: &mut [Vector<D>],
    mass: &[f64],
    contacts: &[ClusterContact<D>],
    exponent: f64,
) -> Outcome {
    let n = vel.len();
    let m_total: f64 = mass.iter().sum();
    let momentum = vel
        .iter()
        .zip(mass)
        .fold(Vector::ZERO, |p, (v, &m)| p + *v * m);
    let v_cm = momentum / m_total;
    let ke_rel0: f64 = vel
        .iter()
        .zip(mass)
        .map(|(v, &m)| 0.5 * m * (*v - v_cm).norm2())
        .sum();
    let closing = |vel: &[Vector<D>], c: &ClusterContact<D>| -(vel[c.b] - vel[c.a]).dot(c.normal);
    let mut delta = vec![0.0; contacts.len()];
    let mut outcome = Outcome {
        impulse: vec![0.0; contacts.len()],
        steps: 0,
        finished: true,
    };
    // Time scale: the fastest closing speed and lightest reduced mass set how long an impact
    // takes; for f = delta^p, the impact time is ~ (mu / v^(p-1))^(1/(p+1)) up to a constant.
    let v_max = contacts
        .iter()
        .map(|c| closing(vel, c).abs())
        .fold(0.0, f64::max);
    if v_max == 0.0 || contacts.is_empty() {
        return outcome;
    }
    let v_ref = vel
        .iter()
        .map(|v| (*v - v_cm).norm2().sqrt())
        .fold(v_max, f64::max);
    let u_tol = ROUNDING_SPEED * v_ref;
    let e_tol = ROUNDING_ENERGY * ke_rel0;
    let mu_min = contacts
        .iter()
        .map(|c| mass[c.a] * mass[c.b] / (mass[c.a] + mass[c.b]))
        .fold(f64::INFINITY, f64::min);
    let t_scale = (mu_min / v_max.powf(exponent - 1.0)).powf(1.0 / (exponent + 1.0));
    // Closing so slowly that the contact's time scale is beyond any number (`v_max^2`
    // underflowing at exponent 3, say): stepping it with an infinite step gave infinite
    // velocities. Such contacts are not stepped; the pairwise settling below parts them.
    let too_slow = t_scale == f64::INFINITY;
    let dt = t_scale / 2000.0;
    let force = |d: f64| if d > 0.0 { d.powf(exponent) } else { 0.0 };
    let spring = |d: f64| force(d) * d / (exponent + 1.0);
    let max_steps = MAX_CONTACT_STEPS / contacts.len();
    outcome.finished = too_slow;
    while !too_slow && outcome.steps < max_steps {
        outcome.steps += 1;
        // Leapfrog: compressions move a full step with the current velocities, then the
        // velocities take the forces at the new compressions.
        for (k, c) in contacts.iter().enumerate() {
            delta[k] = (delta[k] + closing(vel, c) * dt).max(0.0);
        }
        for (k, c) in contacts.iter().enumerate() {
            let j = force(delta[k]) * dt;
            if j > 0.0 {
                vel[c.a] -= c.normal * (j / mass[c.a]);
                vel[c.b] += c.normal * (j / mass[c.b]);
                outcome.impulse[k] += j;
            }
        }
        let over = contacts.iter().zip(&delta).all(|(c, &d)| {
            let u = closing(vel, c);
            (d == 0.0 && u <= 0.0) || (u.abs() <= u_tol && spring(d) <= e_tol)
        });
        if over {
            outcome.finished = true;
            break;
        }
    }
    // Remove the integrator's energy error relative to the centre of mass.
    let v_cm1 = vel
        .iter()
        .zip(mass)
        .fold(Vector::ZERO, |p, (v, &m)| p + *v * m)
        / m_total;
    let ke_rel1: f64 = vel
        .iter()
        .zip(mass)
        .map(|(v, &m)| 0.5 * m * (*v - v_cm1).norm2())
        .sum();
    if ke_rel1 > 0.0 {
        let s = (ke_rel0 / ke_rel1).sqrt();
        for v in vel.iter_mut().take(n) {
            *v = v_cm + (*v - v_cm1) * s;
        }
    }
    // Contacts still closing (by rounding, or because the impact was given up) take the binary
    // elastic rule, which conserves momentum and energy.
    for _ in 0..16 {
        let mut settled = true;
        for (k, c) in contacts.iter().enumerate() {
            let u = closing(vel, c);
            if u > 0.0 {
                settled = false;
                let mu = mass[c.a] * mass[c.b] / (mass[c.a] + mass[c.b]);
                let j = 2.0 * mu * u;
                vel[c.a] -= c.normal * (j / mass[c.a]);
                vel[c.b] += c.normal * (j / mass[c.b]);
                outcome.impulse[k] += j;
            }
        }
        if settled {
            break;
        }
    }
    outcome
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector {
        Vector::new([x, y])
    }

    fn energy(vel: &[Vector], mass: &[f64]) -> f64 {
        vel.iter().zip(mass).map(|(v, m)| 0.5 * m * v.norm2()).sum()
    }

    /// Found by fuzzing (`read_checkpoint`,
    /// `fuzz/corpus/read_checkpoint/read_checkpoint-nonfinite-after-run`): two touching discs
    /// closing at a subnormal speed (1.8e-314) beside a third, contact exponent 3. The
    /// contact's time scale `(mu / v^2)^(1/4)` overflowed to infinity, the first step's
    /// impulse with it, and the discs' velocities became infinite, their positions NaN. Such
    /// a contact is not stepped: the pairwise settling parts the two as the binary rule does.
    #[test]
    fn a_contact_closing_too_slowly_for_its_time_scale_to_be_a_number_is_parted_without_stepping() {
        for exponent in [1.0, 1.5, 3.0] {
            let mut vel = vec![v(1.8e-314, 0.0), v(0.0, 0.0), v(-0.44, 0.0)];
            let before = vel.clone();
            let contact = ClusterContact {
                a: 0,
                b: 1,
                normal: v(0.7, -0.7),
            };
            let out = resolve_cluster(&mut vel, &[1.0; 3], &[contact], exponent);
            assert!(vel.iter().all(|v| v.is_finite()), "{exponent}: {vel:?}");
            assert!(out.finished, "{exponent}");
            assert!(
                (vel[1] - vel[0]).dot(contact.normal) >= 0.0,
                "{exponent}: still closing"
            );
            assert_eq!(vel[2], before[2]);
        }
    }

    #[test]
    fn two_discs_reproduce_the_elastic_binary_rule() {
        // A single contact is an ordinary elastic collision: equal masses head-on swap.
        let mut vel = vec![v(1.0, 0.0), v(0.0, 0.0)];
        resolve_cluster(
            &mut vel,
            &[1.0, 1.0],
            &[ClusterContact {
                a: 0,
                b: 1,
                normal: v(1.0, 0.0),
            }],
            1.5,
        );
        assert!((vel[0] - v(0.0, 0.0)).norm2().sqrt() < 1e-6, "{vel:?}");
        assert!((vel[1] - v(1.0, 0.0)).norm2().sqrt() < 1e-6, "{vel:?}");
    }

    #[test]
    fn symmetric_wedge_breaks_symmetrically_and_conserves() {
        // Disc 0 moving +x strikes discs 1 and 2 touching it at +-30 degrees.
        let (c, s) = (3f64.sqrt() / 2.0, 0.5);
        let mut vel = vec![v(1.0, 0.0), v(0.0, 0.0), v(0.0, 0.0)];
        let mass = [1.0, 1.0, 1.0];
        let contacts = [
            ClusterContact {
                a: 0,
                b: 1,
                normal: v(c, s),
            },
            ClusterContact {
                a: 0,
                b: 2,
                normal: v(c, -s),
            },
        ];
        let e0 = energy(&vel, &mass);
        resolve_cluster(&mut vel, &mass, &contacts, 1.5);
        assert!(
            (vel[1][0] - vel[2][0]).abs() < 1e-12 && (vel[1][1] + vel[2][1]).abs() < 1e-12,
            "{vel:?}"
        );
        assert!(vel[0][1].abs() < 1e-12);
        let p: Vector = vel.iter().fold(Vector::ZERO, |a, b| a + *b);
        assert!((p - v(1.0, 0.0)).norm2().sqrt() < 1e-12);
        assert!((energy(&vel, &mass) - e0).abs() < 1e-12);
        // Both struck discs leave along their line of centres.
        assert!((vel[1][1] / vel[1][0] - s / c).abs() < 1e-9);
    }
}
