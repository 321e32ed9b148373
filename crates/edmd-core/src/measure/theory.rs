//! Reference formulas for hard discs and hard spheres (diameter `sigma`, packing fraction
//! `eta`), written once for the experiments and measurements that compare against them.

use std::f64::consts::PI;

/// Henderson's equation of state, `Z = (1 + eta^2 / 8) / (1 - eta)^2`
/// (Mol. Phys. 30, 971 (1975)).
pub fn henderson_z(eta: f64) -> f64 {
    (1.0 + eta * eta / 8.0) / ((1.0 - eta) * (1.0 - eta))
}

/// Henderson's contact value of the pair distribution, `g(sigma) = (1 - 7 eta / 16) / (1 - eta)^2`
/// (consistent with [`henderson_z`] through `Z = 1 + 2 eta g(sigma)`).
pub fn henderson_contact(eta: f64) -> f64 {
    (1.0 - 7.0 * eta / 16.0) / ((1.0 - eta) * (1.0 - eta))
}

/// Number density of discs of diameter `sigma` at packing fraction `eta`.
pub fn number_density(eta: f64, sigma: f64) -> f64 {
    eta / (PI * sigma * sigma / 4.0)
}

/// Enskog's collision frequency per disc, `omega = 2 n sigma g(sigma) sqrt(pi kT / m)`
/// (Gass, J. Chem. Phys. 54, 1898 (1971)).
pub fn enskog_collision_frequency(eta: f64, sigma: f64, kt: f64, m: f64) -> f64 {
    2.0 * number_density(eta, sigma) * sigma * henderson_contact(eta) * (PI * kt / m).sqrt()
}

/// Enskog's mean free path `<v> / omega = 1 / (2 sqrt(2) n sigma g(sigma))`, with the 2D mean
/// speed `<v> = sqrt(pi kT / 2m)`.
pub fn enskog_mean_free_path(eta: f64, sigma: f64) -> f64 {
    1.0 / (2.0 * 2f64.sqrt() * number_density(eta, sigma) * sigma * henderson_contact(eta))
}

/// The hard-sphere equation of state of M. Pieprzyk, M. N. Bannerman, A. C. Brańka, M. Chudak
/// and D. M. Heyes, Phys. Chem. Chem. Phys. 21, 6886 (2019), fitted to long event-driven runs
/// extrapolated to infinite N: `Z = 1 + sum c_k Y^k`, `Y = eta / (1 - eta)`, with the
/// coefficients of Bannerman's Revised-Enskog calculator (`enskog.hpp`, `HEYES`; their
/// expansion in `eta` reproduces the exact virial coefficients `B2` to `B6`). Carnahan-Starling
/// is up to 0.28 % below it between 0.3 and 0.45.
pub fn pieprzyk_z(eta: f64) -> f64 {
    const C: [(i32, f64); 11] = [
        (1, 4.0),
        (2, 6.0),
        (3, 2.364_768_4),
        (4, -0.869_855_1),
        (5, 1.106_280_3),
        (6, -1.101_422_1),
        (7, 0.666_058_66),
        (8, -0.036_334_31),
        (10, -0.209_651_64),
        (14, 0.105_555_69),
        (22, -0.008_723_80),
    ];
    let y = eta / (1.0 - eta);
    1.0 + C.iter().map(|&(k, c)| c * y.powi(k)).sum::<f64>()
}

/// The Carnahan-Starling hard-sphere equation of state
/// `Z = (1 + eta + eta^2 - eta^3) / (1 - eta)^3` (J. Chem. Phys. 51, 635 (1969)).
pub fn carnahan_starling_z(eta: f64) -> f64 {
    (1.0 + eta + eta * eta - eta * eta * eta) / (1.0 - eta).powi(3)
}

/// The collision rate per particle that an equation of state implies, exactly, for equal hard
/// particles of diameter `sigma` and mass `m` in equilibrium at `kT`: `Gamma = 2 D (Z - 1)
/// sqrt(kT / (pi m)) / sigma` in `dim` dimensions (`4 (Z - 1) ...` for discs, `6 (Z - 1) ...`
/// for spheres). From the virial `Z - 1 = sum r.J / (D N kT t)`, each collision giving
/// `r.J = sigma m |v_n|` with the mean normal speed of colliding pairs `sqrt(pi kT / m)`, and
/// `N Gamma / 2` collisions per unit time (derivation in `docs/notes/research-3d.md`).
pub fn collision_rate_from_z(z: f64, dim: usize, sigma: f64, kt: f64, m: f64) -> f64 {
    2.0 * dim as f64 * (z - 1.0) * (kt / (PI * m)).sqrt() / sigma
}

/// The exact equation of state of hard rods on a line, `Z = P L / (N kT) = 1 / (1 - eta)`, with
/// `eta = N sigma / L` the fraction of the line the rods cover (L. Tonks, Phys. Rev. 50, 955
/// (1936)): each rod moves in the free length `L - N sigma` as if it were a point.
pub fn tonks_z(eta: f64) -> f64 {
    1.0 / (1.0 - eta)
}

/// The reference equation of state in `dim` dimensions: Tonks's for rods ([`tonks_z`], exact),
/// Henderson's for discs ([`henderson_z`]), Pieprzyk et al.'s for spheres ([`pieprzyk_z`]).
pub fn reference_z(eta: f64, dim: usize) -> f64 {
    if dim == 1 {
        tonks_z(eta)
    } else if dim == 3 {
        pieprzyk_z(eta)
    } else {
        henderson_z(eta)
    }
}

/// The contact value of the pair distribution implied by [`reference_z`] through the virial
/// relation `Z = 1 + eta g` (rods: `g = 1 / (1 - eta)`), `Z = 1 + 2 eta g` (discs) or
/// `Z = 1 + 4 eta g` (spheres).
pub fn contact_value(eta: f64, dim: usize) -> f64 {
    if dim == 1 {
        tonks_z(eta)
    } else if dim == 3 {
        (pieprzyk_z(eta) - 1.0) / (4.0 * eta)
    } else {
        henderson_contact(eta)
    }
}

/// Number density of particles of diameter `sigma` at packing fraction `eta` in `dim`
/// dimensions (`eta / sigma`, `eta / (pi sigma^2 / 4)` or `eta / (pi sigma^3 / 6)`).
pub fn number_density_in(eta: f64, sigma: f64, dim: usize) -> f64 {
    if dim == 1 {
        eta / sigma
    } else if dim == 3 {
        eta / (PI * sigma.powi(3) / 6.0)
    } else {
        number_density(eta, sigma)
    }
}

/// Enskog's collision frequency per particle in `dim` dimensions: `2 n sigma g sqrt(pi kT/m)`
/// for discs ([`enskog_collision_frequency`]), `4 n sigma^2 g sqrt(pi kT/m)` for spheres
/// (Chapman and Cowling, *The Mathematical Theory of Non-Uniform Gases* (1970), section 16.9,
/// with Enskog's factor `g(sigma)`), with `g` from [`contact_value`].
pub fn enskog_collision_frequency_in(eta: f64, sigma: f64, kt: f64, m: f64, dim: usize) -> f64 {
    if dim == 3 {
        4.0 * number_density_in(eta, sigma, 3)
            * sigma
            * sigma
            * contact_value(eta, 3)
            * (PI * kt / m).sqrt()
    } else {
        enskog_collision_frequency(eta, sigma, kt, m)
    }
}

/// The fraction of collisions in an equilibrium fluid whose kinetic energy of relative motion
/// along the line of centres, `mu v_n^2 / 2`, is at least `activation` (the line-of-centres
/// law): `exp(-activation / kT)`, in two dimensions as in three, dilute or dense.
///
/// At contact the colliding pairs cross the contact surface at the rate of the flux of an
/// equilibrium fluid through it, so `v_n` is distributed as `v_n exp(-mu v_n^2 / 2kT)` for
/// `v_n > 0` whatever the dimension (the normal component of a Maxwellian relative velocity,
/// weighted by the flux; positions and velocities are independent in equilibrium, so the
/// pair correlation at contact changes how many pairs collide, not how fast): the fraction
/// above `v*` is `exp(-mu v*^2 / 2kT)`. In three dimensions this is the line-of-centres model
/// of collision theory (Present, *Kinetic Theory of Gases* (1958), section 8.2; Levine,
/// *Molecular Reaction Dynamics* (2005), section 3.2.1), whose reaction cross section
/// `pi sigma^2 (1 - E*/E)` gives the same `exp(-E*/kT)`.
pub fn line_of_centres_fraction(activation: f64, kt: f64) -> f64 {
    (-activation / kt).exp()
}

/// The rate constant `k` of a reaction `A + B -> ...` of equal hard particles (diameter
/// `sigma`, mass `m`) at packing fraction `eta`, each collision of an `A` with a `B` reacting
/// when its normal kinetic energy is at least `activation` (with probability 1): reactions per
/// unit volume and time are `k n_A n_B` (`k n_A^2 / 2` for like reactants). It is Enskog's
/// collision rate per pair, `omega / n` ([`enskog_collision_frequency_in`], with the contact
/// value of the whole fluid), times [`line_of_centres_fraction`].
pub fn line_of_centres_rate_constant(
    eta: f64,
    sigma: f64,
    kt: f64,
    m: f64,
    dim: usize,
    activation: f64,
) -> f64 {
    enskog_collision_frequency_in(eta, sigma, kt, m, dim) / number_density_in(eta, sigma, dim)
        * line_of_centres_fraction(activation, kt)
}

/// Enskog's mean free path `<v> / omega` in `dim` dimensions: `1 / (2 sqrt(2) n sigma g)` for
/// discs ([`enskog_mean_free_path`]), `1 / (sqrt(2) pi n sigma^2 g)` for spheres (mean speed
/// `sqrt(8 kT / (pi m))`).
pub fn enskog_mean_free_path_in(eta: f64, sigma: f64, dim: usize) -> f64 {
    if dim == 3 {
        1.0 / (2f64.sqrt()
            * PI
            * number_density_in(eta, sigma, 3)
            * sigma
            * sigma
            * contact_value(eta, 3))
    } else {
        enskog_mean_free_path(eta, sigma)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tonks_equation_of_state_has_every_virial_coefficient_one_and_its_contact_value() {
        // 1 / (1 - eta) = 1 + eta + eta^2 + ...: every reduced virial coefficient of hard rods
        // is 1 (Tonks 1936), and Z = 1 + eta g(sigma) with g(sigma) = 1 / (1 - eta).
        let eta = 0.01;
        assert!((tonks_z(eta) - (1.0 + eta + eta * eta + eta.powi(3))).abs() < 2e-8);
        assert_eq!(tonks_z(0.5), 2.0);
        assert_eq!(reference_z(0.8, 1), tonks_z(0.8));
        for eta in [0.2, 0.5, 0.8] {
            let z = 1.0 + eta * contact_value(eta, 1);
            assert!((z - tonks_z(eta)).abs() < 1e-12);
        }
        assert_eq!(number_density_in(0.5, 2.0, 1), 0.25);
    }

    #[test]
    fn pieprzyk_equation_of_state_has_the_exact_virial_coefficients_and_its_published_values() {
        // Low density: Z = 1 + B2 eta + B3 eta^2 + ..., B2 = 4, B3 = 10 (exact).
        let eta = 1e-4;
        let b = (pieprzyk_z(eta) - 1.0 - 4.0 * eta) / (eta * eta);
        assert!((b - 10.0).abs() < 0.01, "B3 {b}");
        // Values of the fit computed independently (docs/notes/research-3d.md, section 1).
        for (eta, z) in [
            (0.1, 1.52165),
            (0.3, 3.98398),
            (0.45, 9.40411),
            (0.5, 13.01668),
        ] {
            assert!(
                (pieprzyk_z(eta) - z).abs() < 2e-5,
                "{eta}: {}",
                pieprzyk_z(eta)
            );
        }
        // Carnahan-Starling is within 0.3 % of it, and below it.
        for eta in [0.2, 0.3, 0.4, 0.45] {
            let r = carnahan_starling_z(eta) / pieprzyk_z(eta) - 1.0;
            assert!(r < 0.0 && r > -0.003, "{eta}: {r}");
        }
    }

    #[test]
    fn enskog_in_3d_is_consistent_with_the_collision_rate_relation_and_the_mean_speed() {
        // Enskog's frequency with g from Z is the rate the virial relation gives for that Z,
        // and the mean free path is the 3D mean speed over it.
        for eta in [0.1, 0.3, 0.45] {
            let (kt, m) = (1.3, 0.7);
            let omega = enskog_collision_frequency_in(eta, 1.0, kt, m, 3);
            let from_z = collision_rate_from_z(pieprzyk_z(eta), 3, 1.0, kt, m);
            assert!((omega / from_z - 1.0).abs() < 1e-12, "{omega} {from_z}");
            let mean_speed = (8.0 * kt / (PI * m)).sqrt();
            let lambda = enskog_mean_free_path_in(eta, 1.0, 3);
            assert!((lambda / (mean_speed / omega) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn collision_rate_from_z_matches_enskog_in_2d() {
        // In 2D, Z - 1 = 2 eta g and Enskog's rate 2 n sigma g sqrt(pi kT/m) are the same
        // relation written with g: the two must agree for any g.
        for eta in [0.1, 0.4, 0.6] {
            let z = henderson_z(eta);
            let rate = collision_rate_from_z(z, 2, 1.0, 1.3, 0.7);
            let enskog = enskog_collision_frequency(eta, 1.0, 1.3, 0.7);
            assert!((rate / enskog - 1.0).abs() < 1e-12, "{rate} {enskog}");
        }
    }

    #[test]
    fn contact_value_and_equation_of_state_agree() {
        for eta in [0.1, 0.3, 0.6] {
            assert!((henderson_z(eta) - (1.0 + 2.0 * eta * henderson_contact(eta))).abs() < 1e-12);
            let (kt, m) = (1.0, 1.0);
            let v_mean = (PI * kt / (2.0 * m)).sqrt();
            let ratio = v_mean
                / enskog_collision_frequency(eta, 1.0, kt, m)
                / enskog_mean_free_path(eta, 1.0);
            assert!((ratio - 1.0).abs() < 1e-12);
        }
    }
}

/// The volume (area in 2D) of a ball of radius `r`.
fn ball(dim: usize, r: f64) -> f64 {
    crate::setup::lattice::ball_volume(2.0 * r, dim)
}

/// The shells of a stepped potential outside a hard core `sigma`: `(inner radius, outer radius,
/// energy)`, from the core out (steps innermost first, each with the energy change on crossing
/// it inward, as [`crate::Potential`] takes them).
fn shells(sigma: f64, steps: &[crate::Step]) -> Vec<(f64, f64, f64)> {
    let mut out = Vec::with_capacity(steps.len());
    let mut inner = sigma;
    for (k, s) in steps.iter().enumerate() {
        let u: f64 = steps[k..].iter().map(|x| x.energy).sum();
        out.push((inner, s.radius, u));
        inner = s.radius;
    }
    out
}

/// The exact second virial coefficient of a hard core `sigma` with `steps` at temperature
/// `kt`, in `dim` dimensions: `B2 = -1/2 Int (exp(-u(r)/kT) - 1) dr`, which for a stepped
/// potential is `1/2 [V(sigma) - sum_k (V(r_k) - V(r_{k-1})) (exp(-u_k/kT) - 1)]` with `V` the
/// volume (area) of a ball and `u_k` the energy between steps `k - 1` and `k` (McQuarrie,
/// *Statistical Mechanics* (1976), eq. 12-40; for a square well of depth `e` and range
/// `lambda sigma` in 3D it is `(2 pi sigma^3 / 3) (1 - (lambda^3 - 1)(exp(e/kT) - 1))`).
pub fn stepped_b2(dim: usize, sigma: f64, steps: &[crate::Step], kt: f64) -> f64 {
    let mut b = ball(dim, sigma);
    for (lo, hi, u) in shells(sigma, steps) {
        b -= (ball(dim, hi) - ball(dim, lo)) * ((-u / kt).exp() - 1.0);
    }
    0.5 * b
}

/// The potential energy per particle of a dilute gas with a stepped potential to first order
/// in the number density `rho`: `U/N = (rho / 2) Int u(r) exp(-u(r)/kT) dr`, the pair
/// distribution at low density being the Boltzmann factor (Hansen and McDonald, *Theory of
/// Simple Liquids*, 4th ed. (2013), section 2.5).
pub fn stepped_energy_low_density(
    dim: usize,
    sigma: f64,
    steps: &[crate::Step],
    kt: f64,
    rho: f64,
) -> f64 {
    let mut sum = 0.0;
    for (lo, hi, u) in shells(sigma, steps) {
        sum += (ball(dim, hi) - ball(dim, lo)) * u * (-u / kt).exp();
    }
    0.5 * rho * sum
}

#[cfg(test)]
mod stepped_tests {
    use super::*;

    #[test]
    fn the_square_well_b2_is_the_textbook_one() {
        // 3D: (2 pi / 3)(1 - (lambda^3 - 1)(e^{1/kT} - 1)); 2D: (pi / 2)(1 - (lambda^2 - 1)(...)).
        let well = [crate::Step {
            radius: 1.5,
            energy: -1.0,
        }];
        for kt in [1.0f64, 1.5, 3.0] {
            let f = (1.0 / kt).exp() - 1.0;
            let b3 = 2.0 * std::f64::consts::PI / 3.0 * (1.0 - (1.5f64.powi(3) - 1.0) * f);
            let b2 = std::f64::consts::PI / 2.0 * (1.0 - (1.5f64.powi(2) - 1.0) * f);
            assert!((stepped_b2(3, 1.0, &well, kt) - b3).abs() < 1e-13);
            assert!((stepped_b2(2, 1.0, &well, kt) - b2).abs() < 1e-13);
        }
        // kT = 1.5, lambda = 1.5, 3D: B2 = -2.61981 sigma^3.
        assert!((stepped_b2(3, 1.0, &well, 1.5) + 2.61981).abs() < 1e-5);
        // No steps: the hard core, 2 pi sigma^3 / 3 and pi sigma^2 / 2.
        assert!((stepped_b2(3, 1.0, &[], 1.0) - 2.0 * std::f64::consts::PI / 3.0).abs() < 1e-15);
    }
}

/// Haff's time `t0` of a granular gas cooling homogeneously, `T(t) = T0 / (1 + t/t0)^2`
/// (Haff, J. Fluid Mech. 134, 401 (1983)), for smooth discs (`dim` 2) or spheres (3) with a
/// constant coefficient of normal restitution `e`, at collision frequency `omega0` per
/// particle at `T0`: `t0 = 2 dim / ((1 - e^2) omega0)` (infinite for `e = 1`).
///
/// A collision loses `(1 - e^2) mu v_n^2 / 2` of kinetic energy, and over a Maxwellian's
/// collisions `mu v_n^2 / 2` averages `kT` in any dimension (`v_n` distributed as
/// `v_n exp(-mu v_n^2 / 2kT)`, as in [`line_of_centres_fraction`]). With `N omega / 2`
/// collisions per unit time and `dim N kT / 2` of kinetic energy,
/// `dT/dt = -(1 - e^2) omega T / dim`, and `omega` grows as `sqrt(T)`: integrating gives
/// Haff's law with this `t0` (Brilliantov and Poeschel, *Kinetic Theory of Granular Gases*
/// (2004), chapter 7, whose cooling coefficient is this one when the velocities stay
/// Maxwellian, to their Sonine correction `a2`, a few per cent at `e >= 0.8`).
pub fn haff_time(dim: usize, e: f64, omega0: f64) -> f64 {
    2.0 * dim as f64 / ((1.0 - e * e) * omega0)
}

/// Haff's law: the temperature at `t` of a gas at `kt0` at time 0 whose Haff time is `t0`
/// ([`haff_time`]).
pub fn haff_temperature(t: f64, kt0: f64, t0: f64) -> f64 {
    kt0 / ((1.0 + t / t0) * (1.0 + t / t0))
}

/// The first Sonine coefficient `a2` (the fourth cumulant) of the velocity distribution of
/// smooth hard discs (`dim` 2) or spheres (3) cooling homogeneously with restitution `e`,
/// `f = f_Maxwell (1 + a2 S2(c^2))`:
/// `a2 = 16 (1 - e)(1 - 2e^2) / (9 + 24 dim - e (41 - 8 dim) + 30 e^2 (1 - e))`
/// (T. P. C. van Noije and M. H. Ernst, Granular Matter 1, 57 (1998)), the linearised
/// condition that the fourth moment decays at twice the rate of the second. It is 0 for
/// `e = 1` and `e = 1/sqrt(2)`, and below 0.1 in size for `e >= 0.5`.
pub fn sonine_a2(dim: usize, e: f64) -> f64 {
    let d = dim as f64;
    16.0 * (1.0 - e) * (1.0 - 2.0 * e * e)
        / (9.0 + 24.0 * d - e * (41.0 - 8.0 * d) + 30.0 * e * e * (1.0 - e))
}

/// Haff's time with the Sonine correction, `t0 = 2 dim / ((1 - e^2)(1 + 3 a2 / 16) omega0)`
/// ([`haff_time`] over `1 + 3 a2 / 16`, [`sonine_a2`]), `omega0` the collision frequency per
/// particle of a Maxwellian gas at `T0` ([`enskog_collision_frequency_in`]). Averaging the
/// energy lost per collision, `|g.n|^3`, over the Sonine-corrected distribution multiplies it by
/// `1 + 3 a2 / 16` in any dimension (the cooling rate `zeta*` of V. Garzó and J. W. Dufty,
/// Phys. Rev. E 59, 5895 (1999); for spheres, N. V. Brilliantov and T. Pöschel, *Kinetic
/// Theory of Granular Gases* (2004)).
pub fn haff_time_sonine(dim: usize, e: f64, omega0: f64) -> f64 {
    haff_time(dim, e, omega0) / (1.0 + 3.0 * sonine_a2(dim, e) / 16.0)
}

/// How fast the temperature falls per collision in the homogeneous cooling state:
/// `-d ln T / d tau` with `tau` the collisions per particle (twice the collisions over `N`),
/// `(1 - e^2)(1 + 3 a2 / 16) / (dim (1 - a2 / 16))`. Each collision loses `(1 - e^2) T` on
/// average for Maxwellian velocities, times `1 + 3 a2 / 16` with the Sonine correction, while
/// the collision rate, an average of `|g.n|`, is multiplied by `1 - a2 / 16`. So
/// `T(tau) = T0 exp(-rate tau)` whatever the density, while Haff's law holds.
pub fn haff_decay_per_collision(dim: usize, e: f64) -> f64 {
    let a2 = sonine_a2(dim, e);
    (1.0 - e * e) * (1.0 + 3.0 * a2 / 16.0) / (dim as f64 * (1.0 - a2 / 16.0))
}

/// The shear viscosity of a dilute elastic gas of hard discs or spheres of diameter `sigma`
/// and mass `m` at `kt` in Boltzmann's first Sonine approximation,
/// `eta0 = ((dim + 2) / 8) Gamma(dim / 2) pi^((1 - dim) / 2) sigma^(1 - dim) sqrt(m kT)`:
/// `(5 / 16) sqrt(m kT / pi) / sigma^2` for spheres (Chapman and Cowling, *The Mathematical
/// Theory of Non-Uniform Gases* (1970), section 10.21), `(1 / 2) sqrt(m kT / pi) / sigma`
/// for discs (Gass, J. Chem. Phys. 54, 1898 (1971)). The unit of [`granular_viscosity`].
pub fn boltzmann_viscosity(dim: usize, sigma: f64, kt: f64, m: f64) -> f64 {
    let root = (m * kt / PI).sqrt();
    if dim == 3 {
        5.0 / 16.0 * root / (sigma * sigma)
    } else {
        0.5 * root / sigma
    }
}

/// The cooling rate of a granular fluid at packing fraction `eta` in the Enskog theory,
/// reduced by `nu0 = n kT / eta0` ([`boltzmann_viscosity`]):
/// `zeta* = ((dim + 2) / (4 dim)) g(sigma) (1 - e^2)(1 + 3 a2 / 16)` (Garzó and Dufty, Phys.
/// Rev. E 59, 5895 (1999)), with the contact value `g` of [`contact_value`] and `a2` of
/// [`sonine_a2`]. Multiplied out, `zeta = (1 - e^2)(1 + 3 a2 / 16) omega / dim` with
/// Enskog's `omega` ([`enskog_collision_frequency_in`]), the rate of [`haff_time_sonine`]:
/// `zeta = 2 / t0` at the start.
pub fn granular_cooling_rate(dim: usize, e: f64, eta: f64) -> f64 {
    let d = dim as f64;
    (d + 2.0) / (4.0 * d)
        * contact_value(eta, dim)
        * (1.0 - e * e)
        * (1.0 + 3.0 * sonine_a2(dim, e) / 16.0)
}

/// The shear viscosity of a granular fluid of smooth hard discs (`dim` 2) or spheres (3) with
/// restitution `e` at packing fraction `eta`, reduced by the dilute elastic gas's
/// ([`boltzmann_viscosity`]), in the Enskog theory's first Sonine approximation of Garzó and
/// Dufty (Phys. Rev. E 59, 5895 (1999), with Garzó, Phys. Rev. E 72, 021106 (2005)):
///
/// `eta* = [1 - 2^(dim-2)/(dim+2) (1+e)(1-3e) eta g] [1 + 2^(dim-1)/(dim+2) eta g (1+e)]
///  / (nu* - zeta*/2) + dim/(dim+2) gamma*`,
///
/// with `nu* = 3/(4 dim) g (1 - e + 2 dim/3)(1 + e)(1 + 7 a2/16)`, `zeta*` of
/// [`granular_cooling_rate`] and the collisional (bulk-viscosity-like) part
/// `gamma* = 2^(2 dim+1)/(pi (dim+2)) eta^2 g (1 + e)(1 - a2/16)`. For `e = 1` it is Enskog's
/// viscosity: `1/g + 16 eta/5 + (64/25)(1 + 12/pi) eta^2 g` for spheres (Chapman and Cowling
/// (1970), section 16.41, without their factor 1.016 of higher Sonine orders) and
/// `1/g + 2 eta + (1 + 8/pi) eta^2 g` for discs (Gass 1971). The `a2` factor in `nu*` differs
/// between Sonine schemes (Garzó, Santos and Montanero, Physica A 376, 94 (2007)), which moves
/// the critical length of [`critical_length`] by under 1% for `e >= 0.8`.
pub fn granular_viscosity(dim: usize, e: f64, eta: f64) -> f64 {
    let d = dim as f64;
    let g = contact_value(eta, dim);
    let a2 = sonine_a2(dim, e);
    let zeta = granular_cooling_rate(dim, e, eta);
    let nu = 3.0 / (4.0 * d) * g * (1.0 - e + 2.0 * d / 3.0) * (1.0 + e) * (1.0 + 7.0 * a2 / 16.0);
    let gamma = 2f64.powi(2 * dim as i32 + 1) / (PI * (d + 2.0))
        * eta
        * eta
        * g
        * (1.0 + e)
        * (1.0 - a2 / 16.0);
    let pd = 2f64.powi(dim as i32 - 2) / (d + 2.0);
    (1.0 - pd * (1.0 + e) * (1.0 - 3.0 * e) * eta * g) * (1.0 + 2.0 * pd * eta * g * (1.0 + e))
        / (nu - zeta / 2.0)
        + d / (d + 2.0) * gamma
}

/// The critical size `L_c` (in diameters) of a periodic square or cubic box beyond which the
/// homogeneous cooling state of a granular fluid (restitution `e`, packing fraction `eta`) is
/// unstable to shear (vortex) modes. In linear hydrodynamics a transverse velocity mode of
/// wavenumber `k` decays as `exp(-nu k^2 t)` (`nu = eta_s / (m n)` the kinematic viscosity)
/// while the thermal speed decays at `zeta / 2`, so relative to it the mode grows where
/// `k^2 < k_c^2 = m n zeta / (2 eta_s)`; the box's longest wave is `2 pi / L`, stable for
/// `L < L_c = 2 pi / k_c` (Goldhirsch and Zanetti, Phys. Rev. Lett. 70, 1619 (1993); van Noije,
/// Ernst, Brito and Orza, Phys. Rev. Lett. 79, 411 (1997); Garzó, Phys. Rev. E 72, 021106
/// (2005)). With the Enskog coefficients of [`granular_viscosity`] and
/// [`granular_cooling_rate`]:
/// `L_c = (dim + 2) pi^(3/2) / (2^(dim+1) dim eta) sqrt(2 eta* / zeta*)`, infinite at `e = 1`,
/// and `1.271 / (eta sqrt(1 - e^2))` for dilute spheres near `e = 1`.
pub fn critical_length(dim: usize, e: f64, eta: f64) -> f64 {
    let d = dim as f64;
    let zeta = granular_cooling_rate(dim, e, eta);
    if zeta <= 0.0 {
        return f64::INFINITY;
    }
    (d + 2.0) * PI.powf(1.5) / (2f64.powi(dim as i32 + 1) * d * eta)
        * (2.0 * granular_viscosity(dim, e, eta) / zeta).sqrt()
}

/// The transverse current of a shear mode in the homogeneous cooling state, relative to its
/// equilibrium value, after `tau` collisions per particle: `y = <|J_perp(k)|^2> / (N kT / m)`
/// per polarisation, starting from an elastic fluid (`y = 1`), for a mode with
/// `x = (k / k_c)^2` (`(L_c / L)^2` for the box's longest wave, [`critical_length`]):
/// `y = (exp(r (1 - x) tau) - x) / (1 - x)`, `r` of [`haff_decay_per_collision`].
///
/// Fluctuating hydrodynamics (van Noije, Ernst, Brito and Orza, Phys. Rev. Lett. 79, 411
/// (1997)): the scaled amplitude grows at `zeta - 2 nu k^2` while the noise, at the local
/// temperature, feeds it at `2 nu k^2`; per collision `dy/dtau = r ((1 - x) y + x)`. Below the
/// critical size (`x > 1`) `y` settles at `x / (x - 1)`; above, it grows exponentially.
pub fn shear_mode_growth(dim: usize, e: f64, x: f64, tau: f64) -> f64 {
    let r = haff_decay_per_collision(dim, e);
    if (1.0 - x).abs() < 1e-12 {
        return 1.0 + r * tau;
    }
    (((1.0 - x) * r * tau).exp() - x) / (1.0 - x)
}

#[cfg(test)]
mod granular_tests {
    use super::*;

    #[test]
    fn sonine_a2_vanishes_when_elastic_and_solves_the_moment_condition() {
        for dim in [2, 3] {
            assert_eq!(sonine_a2(dim, 1.0), 0.0);
            assert!(sonine_a2(dim, 0.5f64.sqrt()).abs() < 1e-15);
        }
        // Spheres: the linearised condition mu4 = 5 mu2 (1 + a2) with the collision moments
        // (per mu20 = 1) mu21 = 3/16, mu40 = 9/2 + e^2, mu41 = 3 (69 + 10 e^2)/32 + 2/(1 - e)
        // gives a2 = (mu40 - 5) / (5 (1 + mu21) - mu41), the formula's value.
        for e in [0.3, 0.5, 0.8, 0.9, 0.95] {
            let (mu21, mu40) = (3.0 / 16.0, 4.5 + e * e);
            let mu41 = 3.0 * (69.0 + 10.0 * e * e) / 32.0 + 2.0 / (1.0 - e);
            let a2 = (mu40 - 5.0) / (5.0 * (1.0 + mu21) - mu41);
            assert!((sonine_a2(3, e) - a2).abs() < 1e-14, "{e}");
        }
        // Published values at e = 0.9: -0.0146 (spheres), -0.0269 (discs).
        assert!((sonine_a2(3, 0.9) + 0.01456).abs() < 1e-5);
        assert!((sonine_a2(2, 0.9) + 0.02686).abs() < 1e-5);
    }

    #[test]
    fn haff_times_with_and_without_a2_and_the_decay_per_collision_agree() {
        for dim in [2, 3] {
            let (e, omega) = (0.8, 1.7);
            let a2 = sonine_a2(dim, e);
            let t0 = haff_time_sonine(dim, e, omega);
            assert!((t0 * (1.0 + 3.0 * a2 / 16.0) - haff_time(dim, e, omega)).abs() < 1e-12);
            // ln T falls by 2 ln(1 + t/t0) while tau grows by omega_HCS t0 ln(1 + t/t0), with
            // the HCS rate omega (1 - a2/16): their ratio is the decay per collision.
            let per = 2.0 / (omega * (1.0 - a2 / 16.0) * t0);
            assert!((per - haff_decay_per_collision(dim, e)).abs() < 1e-12);
            // The Enskog cooling rate is (1 - e^2)(1 + 3 a2/16) omega / dim in units of
            // nu0 = n kT / eta0.
            let eta = 0.2;
            let omega = enskog_collision_frequency_in(eta, 1.0, 1.0, 1.0, dim);
            let nu0 = number_density_in(eta, 1.0, dim) / boltzmann_viscosity(dim, 1.0, 1.0, 1.0);
            let zeta = (1.0 - e * e) * (1.0 + 3.0 * a2 / 16.0) * omega / dim as f64;
            assert!((granular_cooling_rate(dim, e, eta) * nu0 / zeta - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn the_elastic_limit_of_the_granular_viscosity_is_enskogs() {
        for eta in [0.01, 0.1, 0.3, 0.45] {
            let g = contact_value(eta, 3);
            let enskog =
                1.0 / g + 16.0 * eta / 5.0 + 64.0 / 25.0 * (1.0 + 12.0 / PI) * eta * eta * g;
            assert!(
                (granular_viscosity(3, 1.0, eta) / enskog - 1.0).abs() < 1e-12,
                "{eta}"
            );
            let g = contact_value(eta, 2);
            let gass = 1.0 / g + 2.0 * eta + (1.0 + 8.0 / PI) * eta * eta * g;
            assert!(
                (granular_viscosity(2, 1.0, eta) / gass - 1.0).abs() < 1e-12,
                "{eta}"
            );
        }
        // The dilute limit is Boltzmann's: 1 (with inelasticity, 1/(nu* - zeta*/2)).
        assert!((granular_viscosity(3, 1.0, 1e-6) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn the_critical_length_has_its_limits() {
        assert!(critical_length(2, 1.0, 0.1).is_infinite());
        // Dilute, nearly elastic: eta* = 1 and zeta* = (dim + 2)(1 - e^2)/(4 dim), so
        // L_c eta sqrt(1 - e^2) = (dim+2) pi^1.5 / (2^(dim+1) dim) sqrt(8 dim / (dim + 2)):
        // 1.2708 for spheres, 2.7842 for discs.
        let e: f64 = 0.9999;
        let eta = 1e-6;
        for (dim, want) in [(3, 1.2708), (2, 2.7842)] {
            let got = critical_length(dim, e, eta) * eta * (1.0 - e * e).sqrt();
            assert!((got - want).abs() < 1e-3, "{dim}: {got}");
        }
        // Denser, more inelastic: smaller. Discs at 0.1 and e = 0.9: about 62 diameters.
        assert!(critical_length(2, 0.9, 0.2) < critical_length(2, 0.9, 0.1));
        assert!(critical_length(2, 0.8, 0.1) < critical_length(2, 0.9, 0.1));
        assert!((critical_length(2, 0.9, 0.1) - 61.9).abs() < 0.1);
    }

    #[test]
    fn the_shear_mode_grows_above_the_critical_size_and_settles_below() {
        let r = haff_decay_per_collision(2, 0.9);
        assert_eq!(shear_mode_growth(2, 0.9, 0.5, 0.0), 1.0);
        // Below: settles at x / (x - 1).
        assert!((shear_mode_growth(2, 0.9, 2.0, 1e4) - 2.0).abs() < 1e-12);
        // Above: the rate r (1 - x), and at x = 1 the linear growth r tau.
        let (a, b) = (
            shear_mode_growth(2, 0.9, 0.25, 100.0),
            shear_mode_growth(2, 0.9, 0.25, 101.0),
        );
        assert!(((b / a).ln() - 0.75 * r).abs() < 1e-3);
        assert!((shear_mode_growth(2, 0.9, 1.0, 10.0) - (1.0 + 10.0 * r)).abs() < 1e-12);
        assert!((shear_mode_growth(2, 0.9, 1.0 + 1e-9, 10.0) - (1.0 + 10.0 * r)).abs() < 1e-6);
    }
}

/// The thermal conductivity of a dilute gas of equal hard spheres (`dim` 3) or discs (2) of
/// diameter `sigma` and mass `m` at `kt`, with `k_B = 1`, in the first Sonine approximation of
/// the Chapman-Enskog solution: `lambda_0 = (dim (dim + 2) / (2 (dim - 1))) k_B eta_0 / m`
/// with [`boltzmann_viscosity`]'s `eta_0`, so `(75 / 64) sqrt(kT / (pi m)) / sigma^2` for
/// spheres (S. Chapman and T. G. Cowling, *The Mathematical Theory of Non-Uniform Gases*, 3rd
/// ed. (1970), section 10.21, where `lambda = (15 / 4) k_B eta / m` in this approximation) and
/// `(2 / sigma) sqrt(kT / (pi m))` for discs (D. M. Gass, J. Chem. Phys. 54, 1898 (1971), with
/// `lambda = 4 k_B eta / m`). Its unit is `k_B` per length and time in 3D (`k_B` per time in
/// 2D).
pub fn dilute_conductivity(dim: usize, sigma: f64, kt: f64, m: f64) -> f64 {
    let d = dim as f64;
    d * (d + 2.0) / (2.0 * (d - 1.0)) * boltzmann_viscosity(dim, sigma, kt, m) / m
}

/// The factor by which the higher Sonine approximations raise the first one's thermal
/// conductivity of a dilute gas of hard spheres, `[lambda]_inf = 1.025 [lambda]_1` (Chapman
/// and Cowling (1970), sections 10.21 and 16.5; 1.016 for the viscosity). Enskog's dense-gas
/// conductivity takes it on its kinetic part only, see
/// [`enskog_conductivity_ratio_chapman_cowling`].
pub const CONDUCTIVITY_SONINE_SPHERES: f64 = 1.025;

/// Enskog's thermal conductivity of equal hard spheres (`dim` 3) or discs (2) at packing
/// fraction `packing` with the contact value `chi` of the pair distribution, reduced by
/// [`dilute_conductivity`], in the first Sonine approximation:
///
/// `lambda_E / lambda_0 = (1 + 12 phi chi / 5)^2 / chi + 512 phi^2 chi / (25 pi)` for spheres,
/// `(1 + 3 phi chi / 2)^2 / chi + 4 phi^2 chi / pi` for discs.
///
/// The first term is the kinetic flux with the collisional transfer of the kinetic part (the
/// factor `1 + 3 . 2^(dim-1) phi chi / (dim + 2)` twice), the second the collisional transfer
/// of the local equilibrium's energy, `2^(2 dim + 2) (dim - 1) phi^2 chi / ((dim + 2)^2 pi)`.
/// For spheres it is Chapman and Cowling's `1/chi + 1.2 b rho + 0.7674 (b rho)^2 chi` with
/// `b rho = 4 phi` (section 16.5; they print `0.7575` with the factor 1.025 taken out of
/// everything), for discs Gass's `1/chi + 3 phi + (9/4 + 4/pi) phi^2 chi` (1971); both are the
/// elastic limit of V. Garzó and J. W. Dufty's `d`-dimensional Enskog conductivity (Phys. Rev.
/// E 59, 5895 (1999)). `chi = g(sigma)` is the one the viscosity uses ([`contact_value`]).
pub fn enskog_conductivity_ratio(dim: usize, packing: f64, chi: f64) -> f64 {
    let (d, phi) = (dim as f64, packing);
    let kinetic = 1.0 + 3.0 * 2f64.powi(dim as i32 - 1) * phi * chi / (d + 2.0);
    let collisional =
        2f64.powi(2 * dim as i32 + 2) * (d - 1.0) * phi * phi * chi / ((d + 2.0).powi(2) * PI);
    kinetic * kinetic / chi + collisional
}

/// [`enskog_conductivity_ratio`] for spheres with the higher Sonine approximations' factor
/// [`CONDUCTIVITY_SONINE_SPHERES`] on its kinetic term, as Chapman and Cowling (1970, section
/// 16.5) write Enskog's conductivity: `1.025 (1 + 12 phi chi / 5)^2 / chi + 512 phi^2 chi /
/// (25 pi)`, or `1.025 (1/chi + 1.2 b rho + 0.7575 (b rho)^2 chi)`. `1.025` in the dilute
/// limit.
pub fn enskog_conductivity_ratio_chapman_cowling(packing: f64, chi: f64) -> f64 {
    let phi = packing;
    let kinetic = 1.0 + 12.0 * phi * chi / 5.0;
    CONDUCTIVITY_SONINE_SPHERES * kinetic * kinetic / chi + 512.0 * phi * phi * chi / (25.0 * PI)
}

/// Enskog's thermal conductivity `lambda_E` of equal hard spheres or discs of diameter `sigma`
/// and mass `m` at packing fraction `packing` and `kt` (`k_B = 1`):
/// [`enskog_conductivity_ratio`] times [`dilute_conductivity`], with the contact value of the
/// project's reference equation of state ([`contact_value`]).
pub fn enskog_conductivity(dim: usize, packing: f64, sigma: f64, kt: f64, m: f64) -> f64 {
    enskog_conductivity_ratio(dim, packing, contact_value(packing, dim))
        * dilute_conductivity(dim, sigma, kt, m)
}

#[cfg(test)]
mod conductivity_tests {
    use super::*;

    #[test]
    fn dilute_conductivities_are_the_textbook_ones() {
        // 75 / (64 sqrt(pi)) for spheres, 2 / sqrt(pi) for discs, at sigma = m = kT = 1.
        assert!((dilute_conductivity(3, 1.0, 1.0, 1.0) - 0.661_159_66).abs() < 1e-8);
        let two_over_root_pi = std::f64::consts::FRAC_2_SQRT_PI;
        assert!((dilute_conductivity(2, 1.0, 1.0, 1.0) - two_over_root_pi).abs() < 1e-15);
        // lambda_0 = (15/4) eta_0 / m and 4 eta_0 / m (the Eucken ratios of the first Sonine
        // approximation), and the scaling sqrt(kT / m) / sigma^(dim - 1).
        for (dim, eucken) in [(3, 3.75), (2, 4.0)] {
            let (s, kt, m) = (1.3, 2.0, 0.7);
            let ratio = dilute_conductivity(dim, s, kt, m) * m / boltzmann_viscosity(dim, s, kt, m);
            assert!((ratio - eucken).abs() < 1e-12, "{dim}");
        }
        let ratio = dilute_conductivity(3, 2.0, 4.0, 9.0) / dilute_conductivity(3, 1.0, 1.0, 1.0);
        assert!((ratio - (4.0f64 / 9.0).sqrt() / 4.0).abs() < 1e-12);
    }

    #[test]
    fn enskog_conductivity_goes_to_the_dilute_gas_and_matches_the_printed_forms() {
        for dim in [2, 3] {
            let phi = 1e-6;
            let r = enskog_conductivity_ratio(dim, phi, contact_value(phi, dim));
            assert!((r - 1.0).abs() < 1e-5, "{dim}: {r}");
        }
        assert!((enskog_conductivity_ratio_chapman_cowling(1e-6, 1.0) - 1.025).abs() < 1e-5);
        // Spheres: Chapman and Cowling's 1/chi + 1.2 b rho + (9/25 + 32/(25 pi)) (b rho)^2 chi,
        // b rho = 4 phi; with the factor 1.025 on the kinetic part, their printed 0.7575.
        let (phi, chi) = (PI / 12.0, 2.160_462);
        let brho = 4.0 * phi;
        let cc = 1.0 / chi + 1.2 * brho + (9.0 / 25.0 + 32.0 / (25.0 * PI)) * brho * brho * chi;
        assert!((enskog_conductivity_ratio(3, phi, chi) - cc).abs() < 1e-12);
        let printed = 1.025 * (1.0 / chi + 1.2 * brho + 0.7575 * brho * brho * chi);
        let ours = enskog_conductivity_ratio_chapman_cowling(phi, chi);
        assert!((ours / printed - 1.0).abs() < 2e-4, "{ours} {printed}");
        // Discs: Gass's 1/chi + 3 phi + (9/4 + 4/pi) phi^2 chi.
        let (phi, chi): (f64, f64) = (0.3, 1.6);
        let gass = 1.0 / chi + 3.0 * phi + (9.0 / 4.0 + 4.0 / PI) * phi * phi * chi;
        assert!((enskog_conductivity_ratio(2, phi, chi) - gass).abs() < 1e-12);
        // The full value at unit sigma, m, kT.
        let e = enskog_conductivity(3, 0.25, 1.0, 1.0, 1.0);
        let want = enskog_conductivity_ratio(3, 0.25, contact_value(0.25, 3)) * 0.661_159_66;
        assert!((e - want).abs() < 1e-7);
    }
}
