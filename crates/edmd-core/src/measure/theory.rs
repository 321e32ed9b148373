//! Reference formulas for hard discs (diameter `sigma`, packing fraction `eta`), written once
//! for the experiments and measurements that compare against them.

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

#[cfg(test)]
mod tests {
    use super::*;

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
