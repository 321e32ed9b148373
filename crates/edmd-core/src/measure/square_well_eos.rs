//! Equation of state of the three-dimensional square-well fluid of variable range, from
//! R. Espíndola-Heredia, F. del Río and A. Malijevský, "Optimized equation of the state of the
//! square-well fluid of variable range based on a fourth-order free-energy expansion",
//! J. Chem. Phys. 130, 024509 (2009), doi:10.1063/1.3054361.
//!
//! The pair potential is infinite for `r < sigma`, `-epsilon` for `sigma < r < lambda sigma` and
//! zero beyond. Everything here is in reduced units: `sigma = 1`, `epsilon = 1`, `k = 1`, so the
//! arguments are `kt = T* = kT / epsilon` and `rho = rho* = N sigma^3 / V`.
//!
//! The residual Helmholtz energy per particle over `kT` is a fourth-order high-temperature
//! expansion on top of the Carnahan-Starling hard-sphere term,
//! `alpha_r = a_HS(rho) + a_1(rho) / T* + a_2(rho) / T*^2 + a_3(rho) / T*^3 + a_4(rho) / T*^4`,
//! with the `a_n` fitted to simulation data as functions of `rho*` and `lambda`.
//!
//! This is a port of the class `EspindolaHeredia2009` of teqp (github.com/usnistgov/teqp, file
//! `include/teqp/models/model_potentials/squarewell.hpp`, commit 6fd8a29); the coefficients are
//! copied from there digit for digit. One deliberate difference: for `lambda > 2` teqp writes the
//! constants `-17/2`, `-17/6` and `-17/24` of `a_32`, `a_33`, `a_34` as C++ integer divisions
//! (giving -8, -2 and 0); here they are the real fractions, which make those terms continuous at
//! `lambda = 2`. Inside the fitted range ([`LAMBDA_RANGE`]) the two agree.
//!
//! Density derivatives are taken exactly with forward-mode dual numbers; the temperature
//! dependence is an explicit polynomial in `1 / T*`, differentiated analytically.

use std::f64::consts::PI;
use std::ops::{Add, Div, Mul, RangeInclusive};

/// Well ranges `lambda` (in units of `sigma`) that the fit of Espíndola-Heredia et al. (2009)
/// covers, taken as `1.1..=2.0`. The functions accept any `lambda > 1` (teqp carries the exact
/// `lambda > 2` branches of the third-order coefficients), but outside this range the fitted
/// parts (`gamma_n`, `phi_i`, `K_i`) are extrapolations.
pub const LAMBDA_RANGE: RangeInclusive<f64> = 1.1..=2.0;

/// Whether `lambda` lies in [`LAMBDA_RANGE`], the well ranges the fit covers.
pub fn lambda_in_fit_range(lambda: f64) -> bool {
    LAMBDA_RANGE.contains(&lambda)
}

/// Residual Helmholtz energy per particle over `kT`, `alpha_r(T*, rho*) = A_r / (N k T)`, of the
/// square-well fluid of range `lambda` (Espíndola-Heredia, del Río and Malijevský, J. Chem.
/// Phys. 130, 024509 (2009); teqp's `squarewell.hpp`, `EspindolaHeredia2009::alphar`).
///
/// `kt` is `T* = kT / epsilon` and `rho` is `rho* = N sigma^3 / V`; the hard-sphere part has its
/// pole at `rho* = 6 / pi`, and the result is meaningful only for fluid densities `0 <= rho*`
/// well below that, and for `T* > 0` (the fitted terms are a series in `1 / T*`, so they are
/// least reliable at low temperature). Nothing panics: out-of-range input gives whatever the
/// floating-point formula gives (e.g. NaN at `lambda = 1`).
pub fn alpha_r(lambda: f64, kt: f64, rho: f64) -> f64 {
    let t = Terms::new(lambda, Dual::constant(rho));
    t.hs.v
        + t.a
            .iter()
            .enumerate()
            .map(|(k, a)| a.v / kt.powi(k as i32 + 1))
            .sum::<f64>()
}

/// Compressibility factor `Z = P / (rho kT) = 1 + rho* (d alpha_r / d rho*)` at constant `T*`,
/// of the square-well fluid of range `lambda` (Espíndola-Heredia et al., J. Chem. Phys. 130,
/// 024509 (2009), as implemented in teqp's `squarewell.hpp`). Arguments as in [`alpha_r`]; the
/// density derivative is exact (dual numbers).
pub fn compressibility(lambda: f64, kt: f64, rho: f64) -> f64 {
    let t = Terms::new(lambda, Dual::variable(rho));
    let da = t.hs.d
        + t.a
            .iter()
            .enumerate()
            .map(|(k, a)| a.d / kt.powi(k as i32 + 1))
            .sum::<f64>();
    1.0 + rho * da
}

/// Excess (configurational) internal energy per particle in units of `epsilon`,
/// `U_ex / (N epsilon) = -T*^2 (d alpha_r / d T*)` at constant `rho*` (with `k = 1`), of the
/// square-well fluid of range `lambda` (Espíndola-Heredia et al., J. Chem. Phys. 130, 024509
/// (2009), as implemented in teqp's `squarewell.hpp`). Since
/// `alpha_r = a_HS + sum_n a_n / T*^n`, this is `sum_n n a_n / T*^(n-1)`: minus half the mean
/// number of neighbours inside the well, so negative. teqp's `Ar10 = -T* d alpha_r / d T*` is
/// this over `T*`. Arguments as in [`alpha_r`].
pub fn energy_per_particle(lambda: f64, kt: f64, rho: f64) -> f64 {
    let t = Terms::new(lambda, Dual::constant(rho));
    t.a.iter()
        .enumerate()
        .map(|(k, a)| (k + 1) as f64 * a.v / kt.powi(k as i32))
        .sum()
}

// ---------------------------------------------------------------------------------------------
// Coefficients, copied exactly from teqp, include/teqp/models/model_potentials/squarewell.hpp
// (class EspindolaHeredia2009: `phivals`, `thetavals`, `gammanvals`).
// ---------------------------------------------------------------------------------------------

/// `phi_i(lambda) = sum_{n=0}^{7} PHI[i-1][n] lambda^n`, i = 1, 2 (teqp `phivals`).
#[rustfmt::skip]
const PHI: [[f64; 8]; 2] = [
    [-1320.19, 5124.1, -8145.37, 6895.8, -3381.42, 968.739, -151.255, 9.98592],
    [1049.76, -4023.29, 6305.95, -5265.42, 2553.84, -727.3, 113.631, -7.56266],
];

/// `theta_3` and `theta_4` of `K_i` (teqp `thetavals`, keys 3 and 4).
#[rustfmt::skip]
const THETA: [[f64; 8]; 2] = [
    [0.0, -945.597, 1326.61, -471.688, 0.0, 23.2271, -2.63477, 0.0],
    [0.0, 4131.09, -10501.1, 8909.18, -2521.96, -16.7882, 19.5315, -1.27373],
];

/// `gamma_n`, n = 1..4 (teqp `gammanvals`).
#[rustfmt::skip]
const GAMMA: [[f64; 15]; 4] = [
    [
        0.0, -59.0464, 26.098, 26.4454, 7.40136, 11.0743, -5.49152, 0.781823, -0.0319751,
        0.827621, 0.605635, -0.254959, 0.0377111, -0.00210896, 0.0000452328,
    ],
    [
        0.0, 214.316, -88.1394, 273.3, 95.9759, 71.1228, -40.2656, 5.94069, -0.23842, -2.17558,
        -1.29255, 0.554993, -0.0857543, 0.00492511, -0.000107067,
    ],
    [
        0.0, -225.479, 88.8202, 250.472, 90.2606, 57.0274, -33.2376, 4.99527, -0.195714,
        1.84677, 0.99813, -0.440314, 0.0708793, -0.00416274, 0.0000917291,
    ],
    [
        0.0, 65.0504, -25.096, 74.3095, 26.2153, 18.4397, -10.0891, 1.50243, -0.057694,
        -1.87154, -1.01682, 0.445247, -0.0725107, 0.00427862, -0.0000949723,
    ],
];

/// The constant `1.5129` in `Chi` (teqp `Chi`).
const CHI_RHO2: f64 = 1.5129;

// ---------------------------------------------------------------------------------------------
// Functions of lambda alone (teqp's private members of the same names).
// ---------------------------------------------------------------------------------------------

fn p1(l: f64) -> f64 {
    l.powi(6) - 18.0 * l.powi(4) + 32.0 * l.powi(3) - 15.0
}

fn p2(l: f64) -> f64 {
    -2.0 * l.powi(6) + 36.0 * l.powi(4) - 32.0 * l.powi(3) - 18.0 * l.powi(2) + 16.0
}

fn p3(l: f64) -> f64 {
    6.0 * l.powi(6) - 18.0 * l.powi(4) + 18.0 * l.powi(2) - 6.0
}

fn p4(l: f64) -> f64 {
    32.0 * l.powi(3) - 18.0 * l.powi(2) - 48.0
}

fn p5(l: f64) -> f64 {
    5.0 * l.powi(6) - 32.0 * l.powi(3) + 18.0 * l.powi(2) + 26.0
}

/// `a_2i = -2 pi / (3 i!) (lambda^3 - 1)`: the low-density limits of `a_i / rho` (from `B2`).
fn a2i(i: u32, l: f64) -> f64 {
    let fact: f64 = (1..=i).map(f64::from).product();
    -2.0 * PI / (3.0 * fact) * (l.powi(3) - 1.0)
}

/// `(pi / 6)^2`, the prefactor of the exact third-virial parts `a_3i`.
fn pi6sq() -> f64 {
    (PI / 6.0).powi(2)
}

fn a31(l: f64) -> f64 {
    -pi6sq() * p1(l.min(2.0))
}

fn a32(l: f64) -> f64 {
    if l <= 2.0 {
        pi6sq() * (p2(l) - p1(l) / 2.0)
    } else {
        pi6sq() * (-17.0 / 2.0 + p4(l))
    }
}

fn a33(l: f64) -> f64 {
    if l <= 2.0 {
        pi6sq() * (p2(l) - p1(l) / 6.0 - p3(l))
    } else {
        pi6sq() * (-17.0 / 6.0 + p4(l) - p5(l))
    }
}

fn a34(l: f64) -> f64 {
    if l <= 2.0 {
        pi6sq() * (-p1(l) / 24.0 + 7.0 * p2(l) / 12.0 - 3.0 * p3(l) / 2.0)
    } else {
        pi6sq() * (-17.0 / 24.0 + 7.0 * p4(l) / 12.0 - 3.0 * p5(l) / 2.0)
    }
}

fn gamma_n(n: usize, l: f64) -> f64 {
    let g = &GAMMA[n - 1];
    let x = l.powi(3) - 1.0;
    let r = g[3] + (4..9).map(|j| g[j] * x.powi(j as i32 - 2)).sum::<f64>();
    let q = g[9] + (10..15).map(|j| g[j] * x.powi(j as i32 - 7)).sum::<f64>();
    g[1] * l + g[2] * l * l + r / q
}

fn phi_i(i: usize, l: f64) -> f64 {
    PHI[i - 1]
        .iter()
        .enumerate()
        .map(|(n, c)| c * l.powi(n as i32))
        .sum()
}

/// `K_i(rho) = rho^2 sum_{n=1}^{4} theta_n lambda^n / (1 + rho sum_{n=5}^{7} theta_n lambda^(n-4))`,
/// i = 3, 4.
fn k_i(i: usize, rho: Dual, l: f64) -> Dual {
    let th = &THETA[i - 3];
    let num: f64 = (1..5).map(|n| th[n] * l.powi(n as i32)).sum();
    let den: f64 = (5..8).map(|n| th[n] * l.powi(n as i32 - 4)).sum();
    (rho * rho * num) / (rho * den + 1.0)
}

// ---------------------------------------------------------------------------------------------
// The density-dependent terms.
// ---------------------------------------------------------------------------------------------

/// `a_HS` and `a_1..a_4` at one density, each with its density derivative.
struct Terms {
    hs: Dual,
    a: [Dual; 4],
}

impl Terms {
    fn new(l: f64, rho: Dual) -> Terms {
        // Carnahan-Starling, written as in teqp: -3 pi rho (pi rho - 8) / (pi rho - 6)^2.
        let prho = rho * PI;
        let hs = (prho * (-3.0)) * (prho + (-8.0)) / ((prho + (-6.0)) * (prho + (-6.0)));

        let mut a1 = rho * a2i(1, l) + rho.powi(2) * a31(l);
        for i in 1..5 {
            a1 = a1 + rho.powi(i as i32 + 2) * gamma_n(i, l);
        }

        let chi = rho * a2i(2, l) * (rho.powi(2) * (-1.0 / CHI_RHO2) + 1.0);
        let a22 = a2i(2, l);
        let a23 = a2i(3, l);
        let a24 = a2i(4, l);
        let e2 = rho * (a32(l) / a22) + rho.powi(3) * phi_i(1, l) + rho.powi(4) * phi_i(2, l);
        let a2 = chi * e2.exp();
        let e3 = rho * (a33(l) / a23) + k_i(3, rho, l);
        let a3 = rho * a23 * e3.exp();
        let e4 = rho * (a34(l) / a24) + k_i(4, rho, l);
        let a4 = rho * a24 * e4.exp();

        Terms {
            hs,
            a: [a1, a2, a3, a4],
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Minimal forward-mode dual numbers: value `v` and derivative `d` with respect to rho.
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Copy, Debug)]
struct Dual {
    v: f64,
    d: f64,
}

impl Dual {
    fn constant(v: f64) -> Dual {
        Dual { v, d: 0.0 }
    }

    fn variable(v: f64) -> Dual {
        Dual { v, d: 1.0 }
    }

    fn exp(self) -> Dual {
        let e = self.v.exp();
        Dual {
            v: e,
            d: e * self.d,
        }
    }

    fn powi(self, n: i32) -> Dual {
        match n {
            0 => Dual::constant(1.0),
            _ => Dual {
                v: self.v.powi(n),
                d: f64::from(n) * self.v.powi(n - 1) * self.d,
            },
        }
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual {
            v: self.v + o.v,
            d: self.d + o.d,
        }
    }
}

impl Add<f64> for Dual {
    type Output = Dual;
    fn add(self, o: f64) -> Dual {
        Dual {
            v: self.v + o,
            d: self.d,
        }
    }
}

impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
        }
    }
}

impl Mul<f64> for Dual {
    type Output = Dual;
    fn mul(self, o: f64) -> Dual {
        Dual {
            v: self.v * o,
            d: self.d * o,
        }
    }
}

impl Div for Dual {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        Dual {
            v: self.v / o.v,
            d: (self.d * o.v - self.v * o.d) / (o.v * o.v),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    /// teqp's src/tests/catch_test_SW.cxx, "simple evaluation of s^+ for square well EOS":
    /// lambda = 1.5 at T* = 1.3144366466267958, rho* = 0.2862336473147125, where teqp lists
    /// `alphar_target = -0.8061758248466638` and asserts
    /// `s^+ = alpha_r - Ar10 = 1.0031288550954747` (Ar10 = -T d alpha_r / dT = U / (N T*)).
    #[test]
    fn teqp_unit_test_values() {
        let (l, t, r) = (1.5, 1.3144366466267958, 0.2862336473147125);
        let ar = alpha_r(l, t, r);
        assert!(rel(ar, -0.8061758248466638) < 1e-9, "alpha_r = {ar:.16}");
        let splus = ar - energy_per_particle(l, t, r) / t;
        assert!(rel(splus, 1.0031288550954747) < 1e-9, "s+ = {splus:.16}");
    }

    /// Z and U agree with central finite differences of alpha_r.
    #[test]
    fn derivatives_match_finite_differences() {
        for &(l, t, r) in &[
            (1.5, 1.5, 0.3),
            (1.2, 0.8, 0.7),
            (1.9, 2.5, 0.5),
            (1.1, 0.6, 0.85),
        ] {
            let h = 1e-5;
            let dadr = (alpha_r(l, t, r + h) - alpha_r(l, t, r - h)) / (2.0 * h);
            let z = compressibility(l, t, r);
            assert!(
                (z - (1.0 + r * dadr)).abs() < 1e-7 * (1.0 + z.abs()),
                "Z {z}"
            );
            let dadt = (alpha_r(l, t + h, r) - alpha_r(l, t - h, r)) / (2.0 * h);
            let u = energy_per_particle(l, t, r);
            assert!((u + t * t * dadt).abs() < 1e-7 * (1.0 + u.abs()), "U {u}");
        }
    }

    /// (Z - 1) / rho tends to the exact square-well B2* = (2 pi / 3)(1 - (l^3 - 1)(e^(1/T) - 1)).
    /// The EOS has the fourth-order truncation of e^(1/T) - 1 in it, so the match is to ~1%.
    #[test]
    fn low_density_limit_is_b2() {
        for &l in &[1.1, 1.5, 2.0] {
            for &t in &[1.0, 1.5, 3.0] {
                let rho = 1e-7;
                let b2 = (compressibility(l, t, rho) - 1.0) / rho;
                let exact = 2.0 * PI / 3.0 * (1.0 - (l * l * l - 1.0) * ((1.0 / t).exp_m1()));
                assert!(rel(b2, exact) < 0.01, "l {l} T {t}: {b2} vs {exact}");
                let x = 1.0 / t;
                let trunc = x + x * x / 2.0 + x.powi(3) / 6.0 + x.powi(4) / 24.0;
                let fourth = 2.0 * PI / 3.0 * (1.0 - (l * l * l - 1.0) * trunc);
                assert!(rel(b2, fourth) < 1e-5, "l {l} T {t}: {b2} vs {fourth}");
                assert!(energy_per_particle(l, t, rho).abs() < 1e-5);
            }
        }
    }

    /// lambda = 1.5, T* = 1.5: the values of an earlier independent Python port (to its three
    /// decimals: Z 0.539 and 4.272, U/N -2.379 and -5.907), and this port's own to 1e-9.
    #[test]
    fn sanity_values() {
        let (l, t) = (1.5, 1.5);
        let cases = [
            (0.3, 0.539, -2.379, REGRESSION[0]),
            (0.8, 4.272, -5.907, REGRESSION[1]),
        ];
        for (r, z_py, u_py, (z_here, u_here)) in cases {
            let (z, u) = (compressibility(l, t, r), energy_per_particle(l, t, r));
            assert!(
                (z - z_py).abs() < 1e-3 && (u - u_py).abs() < 1e-3,
                "rho {r}: {z} {u}"
            );
            assert!(
                rel(z, z_here) < 1e-9 && rel(u, u_here) < 1e-9,
                "rho {r}: {z:.15} {u:.15}"
            );
        }
    }

    /// (Z, U/N) at lambda = 1.5, T* = 1.5 and rho* = 0.3, 0.8, as this port gives them.
    const REGRESSION: [(f64, f64); 2] = [
        (0.539_448_909_043_024_1, -2.378_476_355_382_849),
        (4.271_989_048_835_129, -5.907_380_491_118_787),
    ];

    /// The lambda > 2 branches of a_32, a_33, a_34 join the lambda <= 2 ones continuously.
    #[test]
    fn third_order_coefficients_continuous_at_two() {
        let (lo, hi) = (2.0, 2.0 + 1e-12);
        for f in [a32 as fn(f64) -> f64, a33, a34] {
            assert!((f(lo) - f(hi)).abs() < 1e-9);
        }
        assert!(lambda_in_fit_range(1.5) && !lambda_in_fit_range(2.5));
    }
}
