//! Shear viscosity by the Einstein-Helfand route, and Enskog's viscosity to compare it with.
//!
//! **The Helfand moment.** For an off-diagonal pair of axes `a != b` the momentum flux
//! integrated over a window of length `tau` is
//!
//! `Delta G_ab(tau) = integral of sum_i m_i v_ia v_ib dt + sum_collisions r_ij,a J_ij,b`
//!
//! over the window: the kinetic part is constant between events (its running total is
//! integrated exactly, piece by piece) and the collisions add their momentum transfer at once,
//! `r_ij` the minimum-image separation at contact and `J_ij` the impulse `i` received. The
//! shear viscosity is
//!
//! `eta = lim_{tau -> inf} <Delta G_ab(tau)^2> / (2 V kT tau)`
//!
//! (E. Helfand, Phys. Rev. 119, 1 (1960); with impulsive forces and periodic boundaries,
//! B. J. Alder, D. M. Gass and T. E. Wainwright, J. Chem. Phys. 53, 3813 (1970), and J. J.
//! Erpenbeck, Phys. Rev. E 51, 4296 (1995), who shows that this minimum-image form is the
//! Green-Kubo integral of the stress autocorrelation; M. P. Allen and D. J. Tildesley,
//! *Computer Simulation of Liquids*, 2nd ed. (2017), section 8.5). It is averaged over the
//! off-diagonal components, `xy` in 2D and `xy`, `xz`, `yz` in 3D, which are equivalent in an
//! isotropic fluid. The velocities are taken relative to the centre of mass (`sum m v_a v_b -
//! P_a P_b / M`), so that a drifting system, or a thermostat's kicks to the total momentum, add
//! nothing that grows as `tau^2`.
//!
//! **Windows.** The moment's running integral is recorded on a grid of `spacing` (taken at the
//! first event past each grid time, from the running totals, so the record is exact); every
//! grid point ends one window of each length `m * spacing`, `m = 1..=lags`, whose squares
//! are summed per length (the multiple-time-origin form of DynamO's `ViscosityE` plugin, M. N.
//! Bannerman et al., J. Comput. Chem. 32, 3329 (2011)). `<Delta G^2>` grows as `2 V kT eta tau
//! - c` once `tau` passes the stress's correlation time, `c` coming from the decay of the
//! correlation; so `eta` is the slope of `<Delta G^2> / (2 V kT)` fitted against `tau` over the
//! longer windows (`tau` from half the longest to the longest), which `c` does not bias,
//! while the ratio `<Delta G^2> / (2 V kT tau)` ([`Viscosity::curve`]) approaches it
//! from below as `c / tau`.
//!
//! **Errors.** The grid points are cut into blocks of `block_windows` longest windows; each
//! block gives its own fit, and the error is their spread over `sqrt(blocks)`
//! ([`Estimate`]). Blocks several windows long are nearly independent.
//!
//! **What it refuses** ([`unsupported`]): walls on any axis and internal barriers (their
//! forces on the fluid are not pair impulses, and the moment needs a periodic box), a field
//! (the velocities change between events), Lees-Edwards shear (the images slide; a sheared
//! system's viscosity is [`super::shear_stress`]'s), and multi-disc contacts (an event carries one
//! disc's impulse only). A stepped potential's step events are pair impulses along the line of
//! centres and count as collisions; reactions are collisions too. An Andersen thermostat's
//! redraws change the kinetic total (followed through their impulses) but exchange momentum
//! with the bath, not between pairs, so they add nothing to the collisional part; the bath
//! does perturb the dynamics, so the viscosity of a run with a thermostat depends on its rate.
//!
//! **Theory.** [`enskog_ratio`] is Enskog's `eta_E / eta_0` for equal hard spheres or discs,
//! [`dilute_viscosity`] the first Sonine approximation `eta_0` it is reduced by, and
//! [`CHAPMAN_COWLING_SPHERES`] the factor the higher Sonine approximations give spheres.

use std::f64::consts::PI;

use super::stats::{linear_fit, Estimate};
use super::theory::{boltzmann_viscosity, contact_value, enskog_collision_frequency_in};
use crate::events::{EventKind, EventRecord};
use crate::observer::Observer;
use crate::simulation::Simulation;

/// The dilute-gas shear viscosity of equal hard spheres (`dim` 3) or discs (2) of diameter
/// `sigma` and mass `m` at `kt`, in the first Sonine approximation of the Chapman-Enskog
/// solution: `(5 / 16) sqrt(m kT / pi) / sigma^2` for spheres (S. Chapman and T. G. Cowling,
/// *The Mathematical Theory of Non-Uniform Gases*, 3rd ed. (1970), section 10.21) and
/// `(1 / (2 sigma)) sqrt(m kT / pi)` for discs (D. M. Gass, J. Chem. Phys. 54, 1898 (1971)):
/// [`boltzmann_viscosity`], the unit of the granular viscosities, under the name this module's
/// readers look for.
pub fn dilute_viscosity(dim: usize, sigma: f64, kt: f64, m: f64) -> f64 {
    boltzmann_viscosity(dim, sigma, kt, m)
}

/// The factor by which the higher Sonine approximations raise the first one's viscosity of a
/// dilute gas of hard spheres, `[eta]_inf = 1.016 [eta]_1` (Chapman and Cowling (1970),
/// sections 10.21 and 16.41). Enskog's dense-gas viscosity takes it on its kinetic part only,
/// see [`enskog_ratio_chapman_cowling`].
pub const CHAPMAN_COWLING_SPHERES: f64 = 1.016;

/// Enskog's shear viscosity of equal hard spheres (`dim` 3) or discs (2) at packing fraction
/// `packing` with the contact value `chi` of the pair distribution, reduced by
/// [`dilute_viscosity`]: for spheres
/// `(1 + 8 phi chi / 5)^2 / chi + 768 phi^2 chi / (25 pi)` (Chapman and Cowling (1970), section
/// 16.41, in its first Sonine approximation; the same as DynamO's `Enskog::shearViscosity`),
/// for discs `1 / chi + 2 phi + (1 + 8 / pi) phi^2 chi` (Gass 1971). The first term is the
/// kinetic transport with its collisional transfer, the second the collisional part proper;
/// both go to 1 and 0 in the dilute limit.
pub fn enskog_ratio(dim: usize, packing: f64, chi: f64) -> f64 {
    let phi = packing;
    if dim == 3 {
        let kinetic = 1.0 + 8.0 * phi * chi / 5.0;
        kinetic * kinetic / chi + 768.0 * phi * phi * chi / (25.0 * PI)
    } else {
        1.0 / chi + 2.0 * phi + (1.0 + 8.0 / PI) * phi * phi * chi
    }
}

/// [`enskog_ratio`] for spheres with the higher Sonine approximations' factor
/// [`CHAPMAN_COWLING_SPHERES`] on its kinetic term, as Chapman and Cowling (1970, section
/// 16.41) write Enskog's viscosity: `1.016 (1 + 8 phi chi / 5)^2 / chi + 768 phi^2 chi / (25
/// pi)`. `1.016` in the dilute limit.
pub fn enskog_ratio_chapman_cowling(packing: f64, chi: f64) -> f64 {
    let phi = packing;
    let kinetic = 1.0 + 8.0 * phi * chi / 5.0;
    CHAPMAN_COWLING_SPHERES * kinetic * kinetic / chi + 768.0 * phi * phi * chi / (25.0 * PI)
}

/// Enskog's shear viscosity `eta_E` of equal hard spheres or discs of diameter `sigma` and
/// mass `m` at packing fraction `packing` and `kt`: [`enskog_ratio`] times
/// [`dilute_viscosity`], with the contact value of the project's reference equation of state
/// ([`contact_value`]: Pieprzyk et al.'s for spheres, Henderson's for discs).
pub fn enskog_viscosity(dim: usize, packing: f64, sigma: f64, kt: f64, m: f64) -> f64 {
    enskog_ratio(dim, packing, contact_value(packing, dim)) * dilute_viscosity(dim, sigma, kt, m)
}

/// Why a transport coefficient by the Einstein-Helfand route cannot be measured on `sim`, as
/// the end of a sentence whose subject is the coefficient ("needs a periodic box ..."), or
/// `None` when nothing in the box or the flights stands in the way. The shear viscosity and
/// the thermal conductivity ([`super::conductivity`]) share it.
pub(crate) fn unsupported_box<const D: usize>(sim: &Simulation<D>) -> Option<&'static str> {
    if (0..D).any(|a| !sim.sim_box().is_periodic(a)) {
        Some("needs a periodic box (no walls on any axis)")
    } else if !sim.barriers().is_empty() {
        Some("needs a box without barriers")
    } else if sim.gravity().is_some() {
        Some("is not measured in a field")
    } else if sim.shear().is_some() {
        // Equilibrium fluctuations: a sheared system's images slide, and its viscosity is the
        // shear stress's (`shear_stress`).
        Some("is not measured under shear (sliding images)")
    } else if sim.multi().is_some() {
        Some("needs binary collisions (not multi-disc contacts)")
    } else {
        None
    }
}

/// Why the shear viscosity cannot be measured on `sim`, or `None` when it can (see the module
/// documentation).
pub fn unsupported<const D: usize>(sim: &Simulation<D>) -> Option<String> {
    unsupported_box(sim).map(|why| format!("the shear viscosity {why}"))
}

/// The Einstein-Helfand shear viscosity, accumulated window by window. Attach it as an
/// observer; [`sample`](Viscosity::sample) brings it up to the simulation's time.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Viscosity {
    dim: usize,
    n: usize,
    volume: f64,
    total_mass: f64,
    /// Packing fraction, mean diameter and mean mass, for Enskog's value.
    packing: f64,
    sigma: f64,
    mass: f64,
    /// The grid, the running totals and integrals, and the windows' sums. Its fields follow
    /// the ones above in the order this struct had them before they were shared with the
    /// thermal conductivity, so that checkpoints written then read the same.
    windows: Windows,
    blocks: Vec<ViscosityBlock>,
}

/// One block of a viscosity measurement.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ViscosityBlock {
    /// Start time.
    pub start: f64,
    /// End time.
    pub end: f64,
    /// Time-averaged `kT` over the block (relative to the centre of mass).
    pub kt: f64,
    /// `<Delta G^2>` per window length (`1..=lags` grid steps), over the windows ending in the
    /// block.
    pub mean_square: Vec<f64>,
    /// The block's viscosity: the fitted slope of `<Delta G^2> / (2 V kT)`.
    pub eta: f64,
}

/// Result of a viscosity measurement. See the module documentation for the method.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ViscositySummary {
    /// The shear viscosity with its block error (`NaN` before the first block closes).
    pub eta: Estimate,
    /// The ratio `<Delta G^2> / (2 V kT tau)` at the longest window (approaches `eta` from
    /// below as the windows lengthen).
    pub eta_at_window: f64,
    /// The longest window, `lags * spacing`.
    pub window: f64,
    /// The shortest window in the fit (half the longest).
    pub fit_from: f64,
    /// The grid spacing.
    pub spacing: f64,
    /// `kT`, time-averaged over the closed blocks.
    pub kt: f64,
    /// Time covered by the closed blocks.
    pub elapsed: f64,
    /// Enskog's viscosity at the system's packing fraction and the measured `kT`
    /// ([`enskog_viscosity`], with the mean diameter and mass).
    pub eta_enskog: f64,
    /// The packing fraction.
    pub packing: f64,
}

/// Windows per block unless the caller says otherwise.
pub const BLOCK_WINDOWS: usize = 4;
/// Grid points per mean collision time in [`Viscosity::for_fluid`].
pub const POINTS_PER_COLLISION: f64 = 4.0;
/// Longest window in mean collision times in [`Viscosity::for_fluid`].
pub const WINDOW_COLLISIONS: f64 = 10.0;

/// The off-diagonal pairs of axes in `dim` dimensions.
fn pairs(dim: usize) -> &'static [(usize, usize)] {
    if dim == 3 {
        &[(0, 1), (0, 2), (1, 2)]
    } else {
        &[(0, 1)]
    }
}

/// The Einstein-Helfand machinery that does not depend on which flux is integrated, shared by
/// the shear viscosity and the thermal conductivity ([`super::conductivity`]): a grid of
/// points `spacing` apart from `start`, the moment's components recorded at each in a ring of
/// the last `lags + 1`, the squares of their changes over every window of `1..=lags` grid steps
/// ending there summed per window length (averaged over the components), blocks of
/// `block_windows` longest windows, and the integral of `sum m v^2 - P^2 / M` for the blocks'
/// temperatures.
///
/// The owner keeps its running totals in `kinetic` and `momentum` (their meaning is its own),
/// adds the collisions' jumps to `moment`, and brings the integrals along with
/// [`Windows::advance_to`], handing over the rates the totals give; the closed blocks come back
/// for it to fit and keep.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Windows {
    /// Time between grid points; windows are `1..=lags` grid steps long.
    spacing: f64,
    lags: usize,
    /// Longest windows per block.
    block_windows: usize,
    /// Time of grid point 0.
    start: f64,
    /// Time the running integrals have been brought to.
    now: f64,
    /// The owner's running totals of the particles' velocities (constant between events).
    pub(crate) kinetic: Vec<f64>,
    /// Total momentum.
    pub(crate) momentum: Vec<f64>,
    /// The Helfand moment's components since `start`.
    pub(crate) moment: Vec<f64>,
    /// `integral of (sum m v^2 - P^2 / M) dt` since `start`.
    twice_ke: f64,
    /// Grid points recorded so far (the next is at `start + points * spacing`).
    points: u64,
    /// The moment at the last `lags + 1` grid points, a ring of `lags + 1` rows.
    ring: Vec<f64>,
    /// The current block: its first grid point, `twice_ke` there, and per window length the
    /// sum of squares (over windows, averaged over the components) and the windows.
    block_first: u64,
    block_twice_ke: f64,
    block_sums: Vec<f64>,
    block_counts: Vec<u64>,
    /// Totals over all closed blocks, per window length.
    sums: Vec<f64>,
    counts: Vec<u64>,
}

/// A block [`Windows`] closed: its times, `integral of (sum m v^2 - P^2 / M) dt` over it, and
/// `<Delta G^2>` per window length over the windows ending in it.
pub(crate) struct ClosedBlock {
    pub(crate) start: f64,
    pub(crate) end: f64,
    pub(crate) twice_ke: f64,
    pub(crate) mean_square: Vec<f64>,
}

impl Windows {
    /// A grid from `start` with `components` moment components and `totals` running totals in
    /// `dim` dimensions, its first point recorded.
    ///
    /// # Panics
    /// If `spacing` is not positive and finite, or `lags` or `block_windows` is 0.
    pub(crate) fn new(
        spacing: f64,
        lags: usize,
        block_windows: usize,
        start: f64,
        (dim, components, totals): (usize, usize, usize),
    ) -> Self {
        assert!(
            spacing.is_finite() && spacing > 0.0,
            "the grid spacing must be positive"
        );
        assert!(
            lags > 0 && block_windows > 0,
            "windows and blocks must be at least one"
        );
        let mut w = Windows {
            spacing,
            lags,
            block_windows,
            start,
            now: start,
            kinetic: vec![0.0; totals],
            momentum: vec![0.0; dim],
            moment: vec![0.0; components],
            twice_ke: 0.0,
            points: 0,
            ring: vec![0.0; (lags + 1) * components],
            block_first: 0,
            block_twice_ke: 0.0,
            block_sums: vec![0.0; lags],
            block_counts: vec![0; lags],
            sums: vec![0.0; lags],
            counts: vec![0; lags],
        };
        // Point 0 closes nothing.
        let _ = w.record_point();
        w
    }

    /// Whether the sizes are those of a measurement of `components` moment components and
    /// `totals` running totals (checked on measurements read back from a checkpoint).
    pub(crate) fn has_sizes(&self, components: usize, totals: usize) -> bool {
        self.moment.len() == components
            && self.kinetic.len() == totals
            && self.ring.len() == (self.lags + 1) * components
            && self.block_sums.len() == self.lags
            && self.block_counts.len() == self.lags
            && self.sums.len() == self.lags
            && self.counts.len() == self.lags
    }

    /// The grid spacing and the number of window lengths.
    pub(crate) fn grid(&self) -> (f64, usize) {
        (self.spacing, self.lags)
    }

    /// Integrates the moment at `rates` and `sum m v^2 - P^2 / M` at `twice_ke` from `now` to
    /// `t` (`t >= now`).
    fn stream(&mut self, t: f64, rates: &[f64], twice_ke: f64) {
        let dt = t - self.now;
        if dt <= 0.0 {
            return;
        }
        for (g, &r) in self.moment.iter_mut().zip(rates) {
            *g += r * dt;
        }
        self.twice_ke += twice_ke * dt;
        self.now = t;
    }

    /// Brings the integrals to `t` at the rates given (constant since the last event),
    /// recording every grid point up to it on the way; returns the blocks that closed.
    pub(crate) fn advance_to(&mut self, t: f64, rates: &[f64], twice_ke: f64) -> Vec<ClosedBlock> {
        let mut closed = Vec::new();
        loop {
            let next = self.start + self.points as f64 * self.spacing;
            if next > t {
                break;
            }
            self.stream(next, rates, twice_ke);
            closed.extend(self.record_point());
        }
        self.stream(t, rates, twice_ke);
        closed
    }

    /// Records the moment at the grid point `points` (the integrals are at its time), adds the
    /// windows ending there and closes the block when it is full.
    fn record_point(&mut self) -> Option<ClosedBlock> {
        let np = self.moment.len();
        let rows = self.lags + 1;
        let k = self.points;
        let row = (k % rows as u64) as usize;
        self.ring[row * np..(row + 1) * np].copy_from_slice(&self.moment);
        for m in 1..=self.lags.min(k as usize) {
            let back = ((k - m as u64) % rows as u64) as usize;
            let mut sq = 0.0;
            for c in 0..np {
                let d = self.moment[c] - self.ring[back * np + c];
                sq += d * d;
            }
            self.block_sums[m - 1] += sq / np as f64;
            self.block_counts[m - 1] += 1;
        }
        self.points += 1;
        if k == 0 {
            self.block_first = 0;
            self.block_twice_ke = self.twice_ke;
            None
        } else if k - self.block_first >= (self.lags * self.block_windows) as u64 {
            Some(self.close_block(k))
        } else {
            None
        }
    }

    /// Closes the block ending at grid point `k` and starts the next there.
    fn close_block(&mut self, k: u64) -> ClosedBlock {
        let start = self.start + self.block_first as f64 * self.spacing;
        let end = self.start + k as f64 * self.spacing;
        let twice_ke = self.twice_ke - self.block_twice_ke;
        let mean_square = means(&self.block_sums, &self.block_counts);
        for m in 0..self.lags {
            self.sums[m] += self.block_sums[m];
            self.counts[m] += self.block_counts[m];
        }
        self.block_sums.iter_mut().for_each(|s| *s = 0.0);
        self.block_counts.iter_mut().for_each(|c| *c = 0);
        self.block_first = k;
        self.block_twice_ke = self.twice_ke;
        ClosedBlock {
            start,
            end,
            twice_ke,
            mean_square,
        }
    }

    /// The first window length (in grid steps, from 1) of the fit.
    fn fit_first(&self) -> usize {
        (self.lags / 2).max(1)
    }

    /// The shortest window in the fit.
    pub(crate) fn fit_from(&self) -> f64 {
        self.fit_first() as f64 * self.spacing
    }

    /// The longest window.
    pub(crate) fn window(&self) -> f64 {
        self.lags as f64 * self.spacing
    }

    /// The slope of `<Delta G^2> / scale` against `tau` over the fitted windows.
    pub(crate) fn fit(&self, mean_square: &[f64], scale: f64) -> f64 {
        let points: Vec<(f64, f64)> = (self.fit_first()..=self.lags)
            .map(|m| (m as f64 * self.spacing, mean_square[m - 1] / scale))
            .filter(|p| p.1.is_finite())
            .collect();
        match linear_fit(&points) {
            Some((slope, _)) => slope,
            // One window length: the ratio itself.
            None => points.first().map_or(f64::NAN, |p| p.1 / p.0),
        }
    }

    /// `<Delta G^2>` per window length over the closed blocks (`NaN` where none).
    pub(crate) fn mean_square(&self) -> Vec<f64> {
        means(&self.sums, &self.counts)
    }

    /// `(tau, <Delta G^2> / (scale tau), <Delta G^2>)` per window length over the closed
    /// blocks.
    pub(crate) fn curve(&self, scale: f64) -> Vec<(f64, f64, f64)> {
        (1..=self.lags)
            .filter(|&m| self.counts[m - 1] > 0)
            .map(|m| {
                let tau = m as f64 * self.spacing;
                let msq = self.sums[m - 1] / self.counts[m - 1] as f64;
                (tau, msq / (scale * tau), msq)
            })
            .collect()
    }
}

/// Sums over counts, `NaN` where the count is 0.
fn means(sums: &[f64], counts: &[u64]) -> Vec<f64> {
    sums.iter()
        .zip(counts)
        .map(|(&s, &c)| if c > 0 { s / c as f64 } else { f64::NAN })
        .collect()
}

/// The time-averaged `kT` of blocks given as `(start, end, kT)` (`NaN` for none).
pub(crate) fn mean_kt(blocks: impl Iterator<Item = (f64, f64, f64)> + Clone) -> f64 {
    let elapsed: f64 = blocks.clone().map(|(s, e, _)| e - s).sum();
    blocks.map(|(s, e, kt)| kt * (e - s)).sum::<f64>() / elapsed
}

/// The packing fraction, mean diameter and mean mass of `sim`'s particles.
pub(crate) fn composition<const D: usize>(sim: &Simulation<D>) -> (f64, f64, f64) {
    let n = sim.len();
    let volume = sim.sim_box().volume();
    let unit = if D == 3 { PI / 6.0 } else { PI / 4.0 };
    let diameters = (0..n).map(|i| 2.0 * sim.radius(i));
    let covered: f64 = diameters.clone().map(|d| unit * d.powi(D as i32)).sum();
    (
        covered / volume,
        diameters.sum::<f64>() / n.max(1) as f64,
        (0..n).map(|i| sim.mass(i)).sum::<f64>() / n.max(1) as f64,
    )
}

/// `sum m v^2 - P^2 / M` from the total of `m v^2`, the momentum and the total mass.
pub(crate) fn twice_ke_relative(sum_mv2: f64, momentum: &[f64], total_mass: f64) -> f64 {
    let p2: f64 = momentum.iter().map(|p| p * p).sum();
    let drift = if total_mass > 0.0 {
        p2 / total_mass
    } else {
        0.0
    };
    sum_mv2 - drift
}

impl Viscosity {
    /// Starts measuring on `sim` now, with grid points `spacing` apart, windows up to `lags`
    /// of them and blocks of `block_windows` longest windows. Check [`unsupported`] first: on a
    /// system it refuses the result means nothing.
    ///
    /// # Panics
    /// If `spacing` is not positive and finite, or `lags` or `block_windows` is 0.
    pub fn new<const D: usize>(
        sim: &Simulation<D>,
        spacing: f64,
        lags: usize,
        block_windows: usize,
    ) -> Self {
        let n = sim.len();
        let (packing, sigma, mass) = composition(sim);
        let np = pairs(D).len();
        let mut v = Viscosity {
            dim: D,
            n,
            volume: sim.sim_box().volume(),
            total_mass: (0..n).map(|i| sim.mass(i)).sum(),
            packing,
            sigma,
            mass,
            windows: Windows::new(spacing, lags, block_windows, sim.time(), (D, np, np + 1)),
            blocks: Vec::new(),
        };
        v.recount(sim);
        v
    }

    /// [`Viscosity::new`] with the grid sized by Enskog's mean collision time `t_c` at the
    /// system's packing fraction and temperature: points `t_c / 4` apart, windows up to `10
    /// t_c`, fitted from `5 t_c`, blocks of four windows. The stress correlation of a dilute
    /// gas decays as `exp(-t / 1.2 t_c)`, which leaves 1.5 % of the integral beyond `5 t_c`; fits
    /// over windows up to `10 t_c` and `40 t_c` agree within their errors for spheres at packing
    /// 0.02 and 0.4 and discs at 0.1 and 0.5, the longer ones twice as noisy. A system with no collisions to size it by (empty, at rest)
    /// gets the unit spacing.
    pub fn for_fluid<const D: usize>(sim: &Simulation<D>) -> Self {
        let probe = Self::new(sim, 1.0, 1, 1);
        let kt = probe.kinetic_kt();
        let rate = enskog_collision_frequency_in(probe.packing, probe.sigma, kt, probe.mass, D);
        let spacing = 1.0 / (POINTS_PER_COLLISION * rate);
        let spacing = if spacing.is_finite() && spacing > 0.0 {
            spacing
        } else {
            1.0
        };
        let lags = (WINDOW_COLLISIONS * POINTS_PER_COLLISION) as usize;
        Self::new(sim, spacing, lags, BLOCK_WINDOWS)
    }

    /// Whether this measurement can go on observing `sim` (same particles and box).
    pub fn fits<const D: usize>(&self, sim: &Simulation<D>) -> bool {
        self.dim == D
            && self.n == sim.len()
            && self.volume == sim.sim_box().volume()
            && self.windows.momentum.len() == D
            && self.windows.has_sizes(pairs(D).len(), pairs(D).len() + 1)
            && unsupported(sim).is_none()
    }

    /// `kT` from the kinetic totals now (relative to the centre of mass).
    fn kinetic_kt(&self) -> f64 {
        self.twice_ke_now() / (self.dim * self.n.max(1)) as f64
    }

    /// `sum m v^2 - P^2 / M` now.
    fn twice_ke_now(&self) -> f64 {
        let w = &self.windows;
        twice_ke_relative(
            w.kinetic[pairs(self.dim).len()],
            &w.momentum,
            self.total_mass,
        )
    }

    /// The kinetic totals worked out again from the velocities (at a sample, so that rounding
    /// does not accumulate and velocities changed between runs are taken up).
    fn recount<const D: usize>(&mut self, sim: &Simulation<D>) {
        self.windows.kinetic.iter_mut().for_each(|k| *k = 0.0);
        self.windows.momentum.iter_mut().for_each(|p| *p = 0.0);
        for i in 0..sim.len() {
            self.add_disc(sim.mass(i), sim.velocity(i).0.as_slice(), 1.0);
        }
    }

    /// Adds `sign` times disc's contributions to the kinetic totals and the momentum.
    fn add_disc(&mut self, m: f64, v: &[f64], sign: f64) {
        let ps = pairs(self.dim);
        let w = &mut self.windows;
        for (k, &(a, b)) in ps.iter().enumerate() {
            w.kinetic[k] += sign * m * v[a] * v[b];
        }
        w.kinetic[ps.len()] += sign * m * v.iter().map(|x| x * x).sum::<f64>();
        for (p, x) in w.momentum.iter_mut().zip(v) {
            *p += sign * m * x;
        }
    }

    /// Brings the integrals to `t`, recording every grid point up to it on the way and fitting
    /// the blocks that close.
    fn advance_to(&mut self, t: f64) {
        // The kinetic stress relative to the centre of mass, constant since the last event.
        let mut rates = [0.0; 3];
        let ps = pairs(self.dim);
        let w = &self.windows;
        for (k, &(a, b)) in ps.iter().enumerate() {
            let drift = if self.total_mass > 0.0 {
                w.momentum[a] * w.momentum[b] / self.total_mass
            } else {
                0.0
            };
            rates[k] = w.kinetic[k] - drift;
        }
        let twice_ke = self.twice_ke_now();
        for c in self.windows.advance_to(t, &rates[..ps.len()], twice_ke) {
            let kt = c.twice_ke / ((c.end - c.start) * (self.dim * self.n) as f64);
            let eta = self.windows.fit(&c.mean_square, 2.0 * self.volume * kt);
            self.blocks.push(ViscosityBlock {
                start: c.start,
                end: c.end,
                kt,
                mean_square: c.mean_square,
                eta,
            });
        }
    }

    /// Brings the measurement up to the simulation's current time and takes up its velocities
    /// again. Call it before reading the results, and after changing velocities by hand.
    pub fn sample<const D: usize>(&mut self, sim: &Simulation<D>) {
        self.advance_to(sim.time());
        self.recount(sim);
    }

    /// The closed blocks.
    pub fn blocks(&self) -> &[ViscosityBlock] {
        &self.blocks
    }

    /// The grid spacing and the number of window lengths.
    pub fn grid(&self) -> (f64, usize) {
        self.windows.grid()
    }

    /// Time-averaged `kT` over the closed blocks (`NaN` before the first).
    fn mean_kt(&self) -> f64 {
        mean_kt(self.blocks.iter().map(|b| (b.start, b.end, b.kt)))
    }

    /// `(tau, <Delta G^2> / (2 V kT tau), <Delta G^2>)` per window length over the closed
    /// blocks (empty before the first).
    pub fn curve(&self) -> Vec<(f64, f64, f64)> {
        if self.blocks.is_empty() {
            return Vec::new();
        }
        self.windows.curve(2.0 * self.volume * self.mean_kt())
    }

    /// The viscosity over the closed blocks, with its error.
    pub fn summary(&self) -> ViscositySummary {
        let kt = self.mean_kt();
        let mean_square = self.windows.mean_square();
        let scale = 2.0 * self.volume * kt;
        let eta = if self.blocks.is_empty() {
            f64::NAN
        } else {
            self.windows.fit(&mean_square, scale)
        };
        let block_etas: Vec<f64> = self.blocks.iter().map(|b| b.eta).collect();
        let window = self.windows.window();
        ViscositySummary {
            eta: Estimate::new(eta, &block_etas),
            eta_at_window: mean_square[mean_square.len() - 1] / (scale * window),
            window,
            fit_from: self.windows.fit_from(),
            spacing: self.windows.grid().0,
            kt,
            elapsed: self.blocks.iter().map(|b| b.end - b.start).sum(),
            eta_enskog: enskog_viscosity(self.dim, self.packing, self.sigma, kt, self.mass),
            packing: self.packing,
        }
    }
}

impl<const D: usize> Observer<D> for Viscosity {
    #[inline]
    fn on_event(&mut self, e: &EventRecord<D>, sim: &Simulation<D>) {
        // Each kind of event that changes velocities gives the discs it moved and their
        // impulses; bookkeeping only moves the grid along.
        let (i, j) = match e.kind {
            EventKind::DiscDisc { i, j }
            | EventKind::Reaction { i, j, .. }
            | EventKind::Step { i, j, .. } => (i, Some(j)),
            EventKind::Thermostat { i } => (i, None),
            // Refused before measuring (`unsupported`); a wall's or barrier's impulse is no
            // pair's, so it is left out rather than taken for one.
            EventKind::Wall { i, .. } | EventKind::Barrier { i, .. } => (i, None),
            EventKind::NeighbourList { .. }
            | EventKind::CellCrossing { .. }
            | EventKind::Slide { .. } => {
                self.advance_to(e.time);
                return;
            }
        };
        self.advance_to(e.time);
        let impulse = e.impulse;
        if impulse.0.iter().all(|&x| x == 0.0) {
            return;
        }
        // The kinetic totals go from the velocities before to those after: a disc of mass m
        // had v - J / m.
        let mut moved = |k: usize, sign: f64| {
            let m = sim.mass(k);
            let after = sim.velocity(k);
            let before = after - impulse * (sign / m);
            self.add_disc(m, before.0.as_slice(), -1.0);
            self.add_disc(m, after.0.as_slice(), 1.0);
        };
        moved(i, 1.0);
        if let Some(j) = j {
            moved(j, -1.0);
            let r = sim
                .sim_box()
                .minimum_image(sim.position(i) - sim.position(j));
            for (k, &(a, b)) in pairs(D).iter().enumerate() {
                // The symmetric form: the same as r_a J_b for central impulses, and not
                // dependent on which axis comes first when rounding makes them differ.
                self.windows.moment[k] += 0.5 * (r[a] * impulse[b] + r[b] * impulse[a]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::observer::obs;
    use crate::setup::lattice_fluid_in;
    use crate::{Boundary, Disc, Options, SimBox, Vector};

    #[test]
    fn dilute_viscosities_are_the_textbook_ones() {
        // 5 / (16 sqrt(pi)) for spheres, 1 / (2 sqrt(pi)) for discs, at sigma = m = kT = 1.
        assert!((dilute_viscosity(3, 1.0, 1.0, 1.0) - 0.176_309_24).abs() < 1e-8);
        assert!((dilute_viscosity(2, 1.0, 1.0, 1.0) - 0.282_094_79).abs() < 1e-8);
        // sqrt(m kT) / sigma^(D-1) scaling.
        let ratio = dilute_viscosity(3, 2.0, 4.0, 9.0) / dilute_viscosity(3, 1.0, 1.0, 1.0);
        assert!((ratio - 6.0 / 4.0).abs() < 1e-12);
    }

    #[test]
    fn enskog_goes_to_the_dilute_gas_and_matches_chapman_cowling() {
        for dim in [2, 3] {
            let phi = 1e-6;
            assert!((enskog_ratio(dim, phi, contact_value(phi, dim)) - 1.0).abs() < 1e-5);
        }
        assert!((enskog_ratio_chapman_cowling(1e-6, 1.0) - 1.016).abs() < 1e-5);
        // Chapman and Cowling's form, eta_E / eta_0 = 1/chi + 0.8 b rho + 0.7712 (b rho)^2 chi
        // with b rho = 4 phi (their 0.7614 has the factor 1.016 taken out of everything), at
        // rho sigma^3 = 0.5 (phi = pi / 12) with the Carnahan-Starling chi = 2.160462.
        let (phi, chi) = (PI / 12.0, 2.160_462);
        let brho = 4.0 * phi;
        let cc = 1.0 / chi + 0.8 * brho + (0.16 + 576.0 / (300.0 * PI)) * brho * brho * chi;
        assert!((enskog_ratio(3, phi, chi) - cc).abs() < 1e-12);
        assert!((enskog_ratio(3, phi, chi) - 3.127_65).abs() < 1e-4);
        // The elastic limit of the granular Enskog viscosity written out in `theory`.
        for dim in [2, 3] {
            for phi in [0.05, 0.2, 0.4] {
                let granular = crate::measure::theory::granular_viscosity(dim, 1.0, phi);
                let ours = enskog_ratio(dim, phi, contact_value(phi, dim));
                assert!((granular / ours - 1.0).abs() < 1e-12, "{dim} {phi}");
            }
        }
        // Discs: (1 + phi chi)^2 / chi + (8 / pi) phi^2 chi, Gass's kinetic and collisional parts.
        let (phi, chi): (f64, f64) = (0.3, 1.6);
        let gass = (1.0 + phi * chi).powi(2) / chi + 8.0 / PI * phi * phi * chi;
        assert!((enskog_ratio(2, phi, chi) - gass).abs() < 1e-12);
    }

    #[test]
    fn walls_are_refused_and_periodic_boxes_are_not() {
        let (discs, bx) = lattice_fluid_in::<2>(16, 0.2, Boundary::Walls, 1).unwrap();
        let sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        assert!(unsupported(&sim).unwrap().contains("periodic"));
        let (discs, bx) = lattice_fluid_in::<3>(32, 0.2, Boundary::Periodic, 1).unwrap();
        let sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        assert!(unsupported(&sim).is_none());
    }

    #[test]
    fn one_free_disc_integrates_its_kinetic_stress_exactly() {
        // Two discs of mass 2 moving apart at +-(3, 1) in a 100 x 100 periodic box (no
        // collision before t = 10, their images staying at least 30 apart): sum m v_x v_y =
        // 2 * 2 * 3 = 12 for all time, so every window of length tau has Delta G = 12 tau
        // exactly, the integral being taken piece by piece between the cell crossings.
        let mut a = Disc::new(Vector::new([50.0, 50.0]), Vector::new([3.0, 1.0]), 0.5);
        let mut b = Disc::new(Vector::new([20.0, 20.0]), Vector::new([-3.0, -1.0]), 0.5);
        a.mass = 2.0;
        b.mass = 2.0;
        let mut sim = Simulation::new(
            &[a, b],
            SimBox::periodic([100.0, 100.0]),
            Options::default(),
        )
        .unwrap();
        let mut v = Viscosity::new(&sim, 0.25, 4, 2);
        sim.run_until(9.0, &mut obs(&mut v));
        v.sample(&sim);
        // 36 grid steps: blocks of 8 steps close at 8, 16, 24, 32.
        assert_eq!(v.blocks().len(), 4);
        for (tau, _, msq) in v.curve() {
            assert!(
                (msq - (12.0 * tau).powi(2)).abs() < 1e-9 * msq,
                "{tau} {msq}"
            );
        }
        // kT = sum m v^2 / (D N) = 2 * 2 * 10 / 4 = 10.
        assert!((v.summary().kt - 10.0).abs() < 1e-12);
    }

    #[test]
    fn a_head_on_collision_adds_r_times_j() {
        // Two discs (radius 1, mass 1) meet head-on along the diagonal at t = 1: before, each
        // moves along (1, 1) / sqrt 2 towards the other and sum m v_x v_y = 2 * 1/2 = 1; the
        // collision reverses both, so the kinetic rate stays 1, and the collision adds
        // r_x J_y = (-sqrt2)(-sqrt2) = 2 (r = -2 (1,1)/sqrt2, J = -2 (1,1)/sqrt2). Over [0, 2]
        // with one window of length 2: Delta G = 1 * 2 + 2 = 4.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let discs = [
            Disc::new(
                Vector::new([10.0 - 2.0 * s, 10.0 - 2.0 * s]),
                Vector::new([s, s]),
                1.0,
            ),
            Disc::new(
                Vector::new([10.0 + 2.0 * s, 10.0 + 2.0 * s]),
                Vector::new([-s, -s]),
                1.0,
            ),
        ];
        let mut sim =
            Simulation::new(&discs, SimBox::periodic([40.0, 40.0]), Options::default()).unwrap();
        let mut v = Viscosity::new(&sim, 2.0, 1, 1);
        sim.run_until(2.5, &mut obs(&mut v));
        v.sample(&sim);
        assert_eq!(sim.stats().disc_disc, 1);
        let (tau, _, msq) = v.curve()[0];
        assert_eq!(tau, 2.0);
        assert!((msq - 16.0).abs() < 1e-9, "{msq}");
    }

    /// Runs a melted fluid of `n` equal particles at `packing` for `blocks` blocks of the
    /// default grid and returns the summary.
    fn measured<const D: usize>(n: usize, packing: f64, blocks: usize) -> ViscositySummary {
        let (discs, bx) = lattice_fluid_in::<D>(n, packing, Boundary::Periodic, 1).unwrap();
        let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        let (spacing, lags) = Viscosity::for_fluid(&sim).grid();
        // Melting: 50 mean collision times.
        sim.run_until(50.0 * POINTS_PER_COLLISION * spacing, &mut ());
        let mut v = Viscosity::for_fluid(&sim);
        let block = spacing * (lags * BLOCK_WINDOWS) as f64;
        sim.run_until(sim.time() + blocks as f64 * block, &mut obs(&mut v));
        v.sample(&sim);
        assert_eq!(v.blocks().len(), blocks);
        v.summary()
    }

    /// A dilute hard-sphere gas (phi = 0.02, 108 spheres): eta within 5 % of Chapman and
    /// Cowling's `1.016 eta_0` with Enskog's small density correction
    /// ([`enskog_ratio_chapman_cowling`]; 2 % above `1.016 eta_0` here), with an error bar
    /// under 3.5 % (measured +2.4 +- 2.9 %).
    #[test]
    fn dilute_spheres_have_the_chapman_enskog_viscosity() {
        let s = measured::<3>(108, 0.02, 240);
        let chi = contact_value(s.packing, 3);
        let expected =
            enskog_ratio_chapman_cowling(s.packing, chi) * dilute_viscosity(3, 1.0, s.kt, 1.0);
        let deviation = s.eta.value / expected - 1.0;
        assert!(
            deviation.abs() < 0.05 && s.eta.error < 0.035 * expected,
            "eta = {} +- {}, expected {expected}",
            s.eta.value,
            s.eta.error
        );
        // The ratio at the longest window is below the fitted slope (the correlation's decay).
        assert!(s.eta_at_window < s.eta.value);
    }

    /// A moderately dense hard-sphere fluid (phi = 0.3, 108 spheres): eta within 10 % of
    /// Enskog's value, 4.1 times the dilute gas's (longer runs measure 1.03 +- 0.02 times it with
    /// 108 spheres, 0.99 +- 0.03 with 256).
    #[test]
    fn dense_spheres_are_near_enskog() {
        let s = measured::<3>(108, 0.3, 320);
        let ratio = s.eta.value / s.eta_enskog;
        assert!(
            (ratio - 1.0).abs() < 0.10 && s.eta.error < 0.04 * s.eta_enskog,
            "eta = {} +- {}, Enskog {}",
            s.eta.value,
            s.eta.error,
            s.eta_enskog
        );
    }
}
