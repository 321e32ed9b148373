//! The density of a column of hard discs or spheres in a uniform field `g`, in equilibrium at
//! `kT`: the barometric law of the ideal gas and the local-density approximation for the dense
//! fluid.
//!
//! Heights `h` are those of the particles' centres above the lowest a centre can be (a radius
//! above the floor), up to the column's `height` (a radius below the ceiling); densities are
//! numbers of centres per unit volume (area in 2D). A column holds `load` particles per unit
//! area of the floor (per unit length in 2D), and its scale height is `lambda = kT / (m |g|)`.
//!
//! - **Barometric law**: an ideal gas has `n(h) = n(0) exp(-h / lambda)`, normalised so that
//!   `Int_0^height n dh = load` ([`barometric_density`]), and mean height
//!   `lambda - height / (exp(height / lambda) - 1)` ([`barometric_mean_height`]).
//! - **Local-density approximation** (LDA): the fluid at each height is the bulk fluid at the
//!   local density, so that hydrostatic balance `dP/dh = -m g n` with `P = n kT Z(eta)` gives
//!   `d(beta P)/dn dn/dh = -n / lambda`. [`lda_profile`] integrates `d ln n / dh =
//!   -1 / (lambda d(beta P)/dn)` upwards from the floor with fourth-order Runge-Kutta steps and
//!   finds the floor density by bisection so that Simpson's integral of the profile is the load.
//!   The walls' own structure (the layers of particles packed against a hard wall, a few
//!   diameters deep) is outside it, as are gradient corrections of order `(sigma / lambda)^2`.
//!   With `Z = 1` it is the barometric law.
//!
//! ```
//! use edmd_core::measure::column::{barometric_density, lda_profile, Column, HardFluid};
//!
//! let column = Column { scale_height: 5.0, height: 20.0, load: 0.05 };
//! let ideal = lda_profile(&HardFluid::ideal(2), &column, 2000).unwrap();
//! let law = barometric_density(3.0, &column);
//! assert!((ideal.at(3.0) / law - 1.0).abs() < 1e-9);
//! let discs = lda_profile(&HardFluid::reference(2), &column, 2000).unwrap();
//! // Excluded volume lifts the column: fewer discs at the floor than the ideal gas puts there.
//! assert!(discs.floor_density() < ideal.floor_density());
//! ```

use super::theory;

/// A column in a field: its scale height, its height and how many particles it holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Column {
    /// `kT / (m |g|)`, in the units of the heights.
    pub scale_height: f64,
    /// The range of the centres' heights: the box's height less a diameter.
    pub height: f64,
    /// Particles per unit area of the floor (per unit length in 2D).
    pub load: f64,
}

/// The ideal gas's density at height `h` in `column`: `load exp(-h / lambda) / (lambda (1 -
/// exp(-height / lambda)))`.
pub fn barometric_density(h: f64, column: &Column) -> f64 {
    let (l, x) = (column.scale_height, column.height / column.scale_height);
    // lambda (1 - exp(-x)) written with expm1, exact for a column much lower than lambda.
    column.load * (-h / l).exp() / (-l * (-x).exp_m1())
}

/// The ideal gas's mean height in a column of height `height` and scale height `lambda`:
/// `lambda - height / (exp(height / lambda) - 1)`, from 0 for `lambda -> 0` to `height / 2` for
/// `lambda -> infinity`.
pub fn barometric_mean_height(scale_height: f64, height: f64) -> f64 {
    let x = height / scale_height;
    if x < 1e-4 {
        // The two terms cancel: the series, good to x^3.
        return height * (0.5 - x / 12.0);
    }
    scale_height - height / x.exp_m1()
}

/// The scale height whose barometric mean height in a column of height `height` is `mean`
/// (the maximum-likelihood fit of the barometric law to heights whose mean is `mean`), or
/// `None` for a mean outside `(0, height / 2)`, which no falling density has.
pub fn scale_height_from_mean(mean: f64, height: f64) -> Option<f64> {
    if !(mean > 0.0 && mean < 0.5 * height && height.is_finite()) {
        return None;
    }
    // The mean height grows with lambda: bisection on ln lambda, far beyond both ends.
    let (mut lo, mut hi) = ((mean * 1e-3).ln(), (height * 1e6).ln());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if barometric_mean_height(mid.exp(), height) < mean {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some((0.5 * (lo + hi)).exp())
}

/// A fluid's equation of state, for the local-density approximation.
#[derive(Clone, Copy, Debug)]
pub struct HardFluid {
    /// The compressibility factor `Z = beta P / n` as a function of the packing fraction.
    pub z: fn(f64) -> f64,
    /// The volume (area in 2D) of a particle: packing fraction over number density.
    pub particle_volume: f64,
    /// The densest packing fraction the equation of state is taken to hold at.
    pub max_packing: f64,
}

impl HardFluid {
    /// Discs (`dim` 2) or spheres (3) of unit diameter with edmd's reference equation of state
    /// ([`theory::reference_z`]: Henderson's for discs, Pieprzyk et al.'s for spheres), up to
    /// freezing (packing 0.70 for discs, 0.494 for spheres).
    pub fn reference(dim: usize) -> Self {
        let z: fn(f64) -> f64 = if dim == 3 {
            theory::pieprzyk_z
        } else {
            theory::henderson_z
        };
        HardFluid {
            z,
            particle_volume: crate::setup::lattice::ball_volume(1.0, dim),
            max_packing: if dim == 3 { 0.494 } else { 0.70 },
        }
    }

    /// Points of unit diameter's volume in `dim` dimensions that do not interact (`Z = 1`):
    /// the barometric law.
    pub fn ideal(dim: usize) -> Self {
        HardFluid {
            z: |_| 1.0,
            particle_volume: crate::setup::lattice::ball_volume(1.0, dim),
            max_packing: f64::INFINITY,
        }
    }

    /// `beta P = n Z(eta)` at number density `n`.
    pub fn pressure(&self, n: f64) -> f64 {
        n * (self.z)(self.particle_volume * n)
    }

    /// `d(beta P)/dn = d(eta Z)/d eta`, by a central difference a ten-thousandth of `eta` wide
    /// (the rounding of `eta Z` then costs about 1e-12 of it, the truncation 1e-8 of `Z''`).
    fn compressibility(&self, n: f64) -> f64 {
        let eta = self.particle_volume * n;
        let d = 1e-4 * eta;
        let p = |e: f64| e * (self.z)(e);
        (p(eta + d) - p(eta - d)) / (2.0 * d)
    }
}

/// A density profile on an even grid of heights from 0 to the column's height.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// The grid's spacing.
    pub step: f64,
    /// The density at heights `0, step, 2 step, ...`.
    pub density: Vec<f64>,
}

impl Profile {
    /// The density at the floor (height 0).
    pub fn floor_density(&self) -> f64 {
        self.density[0]
    }

    /// The density at height `h`, with `ln n` interpolated linearly between grid points (exact
    /// for the barometric law); the end values beyond the grid.
    pub fn at(&self, h: f64) -> f64 {
        let last = self.density.len() - 1;
        let x = (h / self.step).clamp(0.0, last as f64);
        let k = (x.floor() as usize).min(last.saturating_sub(1));
        let f = x - k as f64;
        if last == 0 {
            return self.density[0];
        }
        (self.density[k].ln() * (1.0 - f) + self.density[k + 1].ln() * f).exp()
    }

    /// Simpson's integral of `n(h) h^power` over the column (the grid has an even number of
    /// steps): the load for `power` 0, the load times the mean height for 1.
    pub fn moment(&self, power: i32) -> f64 {
        let last = self.density.len() - 1;
        let term = |k: usize| self.density[k] * (k as f64 * self.step).powi(power);
        let inner: f64 = (1..last)
            .map(|k| if k % 2 == 1 { 4.0 } else { 2.0 } * term(k))
            .sum();
        self.step / 3.0 * (term(0) + inner + term(last))
    }

    /// The particles per unit area of floor.
    pub fn load(&self) -> f64 {
        self.moment(0)
    }

    /// The mean height of the particles.
    pub fn mean_height(&self) -> f64 {
        self.moment(1) / self.moment(0)
    }
}

/// The profile of `fluid` from `n(0) = floor_density` in `column` (its load unused), by
/// `steps` fourth-order Runge-Kutta steps of `d ln n / dh = -1 / (lambda d(beta P)/dn)`
/// (`steps` made even, for Simpson's rule).
pub fn lda_from_floor(
    fluid: &HardFluid,
    column: &Column,
    floor_density: f64,
    steps: usize,
) -> Profile {
    let steps = (steps.max(2) + 1) & !1;
    let dh = column.height / steps as f64;
    let slope = |u: f64| -1.0 / (column.scale_height * fluid.compressibility(u.exp()));
    let mut u = floor_density.ln();
    let mut density = Vec::with_capacity(steps + 1);
    density.push(floor_density);
    for _ in 0..steps {
        let k1 = slope(u);
        let k2 = slope(u + 0.5 * dh * k1);
        let k3 = slope(u + 0.5 * dh * k2);
        let k4 = slope(u + dh * k3);
        u += dh / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        density.push(u.exp());
    }
    Profile { step: dh, density }
}

/// The local-density approximation's profile of `fluid` in `column`: [`lda_from_floor`] with
/// the floor density found by bisection so that the profile holds the column's load (a denser
/// floor is denser at every height, so the load grows with it). `None` if the load needs a floor
/// denser than `fluid.max_packing`, or the column is not a column (lengths not positive and
/// finite, no load).
pub fn lda_profile(fluid: &HardFluid, column: &Column, steps: usize) -> Option<Profile> {
    let ok = |x: f64| x.is_finite() && x > 0.0;
    if !(ok(column.scale_height) && ok(column.height) && ok(column.load)) {
        return None;
    }
    // The ideal gas's floor density bounds the fluid's from above, when it is the lower.
    let ideal = barometric_density(0.0, column);
    let mut hi = (fluid.max_packing / fluid.particle_volume).min(ideal);
    if lda_from_floor(fluid, column, hi, steps).load() < column.load {
        // A stiffer fluid than the ideal gas only if its Z < 1 somewhere: bisect up to its top.
        hi = fluid.max_packing / fluid.particle_volume;
        if !ok(hi) || lda_from_floor(fluid, column, hi, steps).load() < column.load {
            return None;
        }
    }
    let mut lo = 0.0;
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if lda_from_floor(fluid, column, mid, steps).load() < column.load {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    Some(lda_from_floor(fluid, column, 0.5 * (lo + hi), steps))
}

#[cfg(test)]
mod tests {
    use super::*;

    const COLUMN: Column = Column {
        scale_height: 5.0,
        height: 20.0,
        load: 0.06,
    };

    #[test]
    fn the_barometric_law_holds_its_load_and_its_mean_height() {
        let ideal = lda_profile(&HardFluid::ideal(2), &COLUMN, 4000).unwrap();
        let exact = Profile {
            step: ideal.step,
            density: (0..ideal.density.len())
                .map(|k| barometric_density(k as f64 * ideal.step, &COLUMN))
                .collect(),
        };
        assert!((exact.load() / COLUMN.load - 1.0).abs() < 1e-12);
        let want = barometric_mean_height(5.0, 20.0);
        assert!((exact.mean_height() / want - 1.0).abs() < 1e-12);
        // 5 (1 - 4 e^-4 / (1 - e^-4)) = 4.6268...
        assert!((want - 5.0 * (1.0 - 4.0 * (-4f64).exp() / (1.0 - (-4f64).exp()))).abs() < 1e-12);
    }

    #[test]
    fn the_lda_with_z_one_is_the_barometric_law() {
        let ideal = lda_profile(&HardFluid::ideal(3), &COLUMN, 2000).unwrap();
        for h in [0.0, 0.37, 5.0, 12.5, 20.0] {
            let law = barometric_density(h, &COLUMN);
            assert!(
                (ideal.at(h) / law - 1.0).abs() < 1e-9,
                "{h}: {} {law}",
                ideal.at(h)
            );
        }
    }

    #[test]
    fn the_lda_conserves_the_load_and_balances_the_weight() {
        // A dense 2D column: Henderson's discs, floor packing about 0.55.
        let fluid = HardFluid::reference(2);
        let column = Column {
            scale_height: 10.0,
            height: 100.0,
            load: 35.0,
        };
        let p = lda_profile(&fluid, &column, 4000).unwrap();
        assert!((p.load() / column.load - 1.0).abs() < 1e-9, "{}", p.load());
        let eta0 = fluid.particle_volume * p.floor_density();
        assert!(eta0 > 0.5 && eta0 < 0.6, "{eta0}");
        // Hydrostatics: the floor bears the weight of the column less what the ceiling bears,
        // beta (P(0) - P(H)) = load / lambda, which the integration never imposed.
        let top = *p.density.last().unwrap();
        let balance =
            (fluid.pressure(p.floor_density()) - fluid.pressure(top)) * column.scale_height;
        assert!((balance / column.load - 1.0).abs() < 1e-7, "{balance}");
        // Halving the steps changes nothing that matters.
        let coarse = lda_profile(&fluid, &column, 2000).unwrap();
        for h in [0.0, 10.0, 40.0, 80.0] {
            assert!((coarse.at(h) / p.at(h) - 1.0).abs() < 1e-9, "{h}");
        }
    }

    #[test]
    fn excluded_volume_lifts_a_column_and_spheres_too() {
        for dim in [2, 3] {
            let hard = lda_profile(&HardFluid::reference(dim), &COLUMN, 2000).unwrap();
            let ideal = barometric_mean_height(COLUMN.scale_height, COLUMN.height);
            assert!(hard.mean_height() > ideal, "{dim}");
            // At a floor packing near 0.01 the lift is about a per cent.
            assert!(hard.mean_height() < 1.03 * ideal, "{dim}");
        }
    }

    #[test]
    fn the_fitted_scale_height_inverts_the_mean() {
        for (l, h) in [(5.0, 20.0), (0.3, 20.0), (50.0, 20.0), (1e5, 1.0)] {
            let m = barometric_mean_height(l, h);
            let back = scale_height_from_mean(m, h).unwrap();
            assert!((back / l - 1.0).abs() < 1e-9, "{l} {h}: {back}");
        }
        assert_eq!(scale_height_from_mean(10.0, 20.0), None);
        assert_eq!(scale_height_from_mean(0.0, 20.0), None);
        assert_eq!(scale_height_from_mean(f64::NAN, 20.0), None);
    }

    #[test]
    fn a_load_the_fluid_cannot_hold_is_refused() {
        let fluid = HardFluid::reference(2);
        let heavy = Column {
            load: 1e4,
            ..COLUMN
        };
        assert_eq!(lda_profile(&fluid, &heavy, 200), None);
        let none = Column {
            load: 0.0,
            ..COLUMN
        };
        assert_eq!(lda_profile(&fluid, &none, 200), None);
    }
}
