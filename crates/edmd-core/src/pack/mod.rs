//! Packings: Lubachevsky-Stillinger compression of hard discs and spheres to jamming.
//!
//! The particles move and collide while every diameter grows by a common factor, linearly in
//! time (B. D. Lubachevsky and F. H. Stillinger, J. Stat. Phys. 60, 561 (1990); made fast by
//! A. Donev, S. Torquato and F. H. Stillinger, J. Comput. Phys. 202, 737 and 765 (2005), and
//! used for jammed packings by M. Skoge, A. Donev, F. H. Stillinger and S. Torquato, PRE 74,
//! 041127 (2006)).
//!
//! - **Growth.** The largest diameter grows as `dD/dt = G v_rms` with the dimensionless
//!   growth rate `G` ([`PackOptions::growth_rate`]) and `v_rms = 1`, the rms speed the
//!   rescaling restores (Skoge and Donev's `spheres` grows radii at `g = G / 2` with unit
//!   speeds). Each diameter is its initial diameter times the common factor.
//! - **Collisions.** Contact times solve `|r + v t| = a + b t` (`predict.rs`); the LS rule
//!   sends a pair apart faster than its contact grows (`resolve.rs`); walls likewise.
//! - **Rescaling.** Collisions feed kinetic energy in, so after every
//!   [`PackOptions::collisions_per_rescale`] collisions per particle the loop moves every
//!   particle to the present, scales all velocities by one factor back to an rms speed of 1
//!   (mass-weighted: `sum m v^2 = sum m`), re-bases the clock to 0 and predicts every event
//!   again (Skoge and Donev's "synchronise"), so neither the energy nor the clock grows
//!   without bound.
//! - **Pressure.** Over the interval between two rescalings, the reduced pressure is
//!   `p = PV / (N kT) = 1 + W / (2 int K dt)` in a periodic box, with `W = sum |r_ij| J_el`
//!   the collisional virial of the elastic part of the impulses (the growth part is left out,
//!   as Skoge and Donev do) and `int K dt` the time integral of the kinetic energy (exact:
//!   `K` is constant between collisions). With walls, it is the walls' elastic momentum
//!   transfer per area and time, `p = P V / (N kT)`.
//! - **Stopping.** When `p` reaches [`PackOptions::max_pressure`] ([`Stop::Pressure`]), when
//!   the packing fraction grows by less than [`PackOptions::min_relative_change`] over an
//!   interval ([`Stop::Converged`]), or exactly at [`PackOptions::target_packing`]
//!   ([`Stop::Packing`]). A clock that stops advancing (`max(10^6, 100 N)` events at one
//!   instant) ends the run with an error rather than a hang.
//! - **Refusals.** What would not be a packing is an error, not a stop: a packing fraction
//!   that stops changing while the pressure is far from jamming (the growth too slow for
//!   double precision), a growth rate too small to change the diameters at all (refused by
//!   [`Packer::new`]), particles all on one line or plane and none moving across it (they
//!   can only jam as a chain along it), and a particle grown to the width of the box between
//!   two walls (caged by the walls, whatever the others do).
//!
//! Exactness: particles never overlap by more than rounding; the contact analysis reports the
//! smallest gap ([`Contacts::min_gap`]). Every choice is deterministic, so the same start and
//! options give the same packing bit for bit.
//!
//! ```
//! use edmd_core::pack::{random_start, PackOptions, PackSizes, Packer};
//! use edmd_core::Boundary;
//!
//! let (discs, sim_box) = random_start::<2>(100, PackSizes::MONODISPERSE, Boundary::Periodic, 1)
//!     .unwrap();
//! let options = PackOptions { target_packing: Some(0.5), ..PackOptions::default() };
//! let packing = Packer::new(&discs, sim_box, options).unwrap().run(|_| true).unwrap();
//! assert!((packing.packing_fraction - 0.5).abs() < 1e-12);
//! ```

mod bins;
pub mod contacts;
pub mod event_loop;
pub mod predict;
pub mod resolve;
pub mod start;

pub use contacts::{contacts, gap_tolerance, Contacts};
pub use event_loop::{
    is_pack_checkpoint, pack_checkpoint_dim, Packer, PACK_FORMAT_VERSION, PACK_MAGIC,
};
pub use start::{random_start, PackSizes, START_PACKING};

use crate::error::Error;
use crate::state::{Disc, SimBox};

/// Parameters of a compression.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PackOptions {
    /// Dimensionless growth rate `G` of the largest diameter, `dD/dt = G v_rms`, in
    /// `(0, 1]`. Default 0.02 (a disordered jammed packing).
    pub growth_rate: f64,
    /// Stop when the reduced pressure reaches this. Default `1e12`.
    pub max_pressure: f64,
    /// Stop exactly at this packing fraction (below jamming), if given.
    pub target_packing: Option<f64>,
    /// Collisions per particle between two rescalings (each pair collision counts once).
    /// Default 10: the kinetic energy grows by some tens of percent in between; 2, 5, 10 and
    /// 20 gave the same packing fraction within 0.0025 (N = 1000, 3D, G = 0.02), and each
    /// rescaling costs about as much as N collisions.
    pub collisions_per_rescale: f64,
    /// Stop when the packing fraction grows by less than this (relatively) between two
    /// rescalings. Default `1e-14`, a few times the rounding of the positions.
    pub min_relative_change: f64,
}

impl Default for PackOptions {
    fn default() -> Self {
        PackOptions {
            growth_rate: 0.02,
            max_pressure: 1e12,
            target_packing: None,
            collisions_per_rescale: 10.0,
            min_relative_change: 1e-14,
        }
    }
}

impl PackOptions {
    /// Checks every parameter's range.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |what: String| Err(Error::Invalid(format!("pack: {what}")));
        if !(self.growth_rate > 0.0 && self.growth_rate <= 1.0) {
            return bad(format!(
                "growth rate {} is outside (0, 1]",
                self.growth_rate
            ));
        }
        if !(self.max_pressure > 1.0 && self.max_pressure.is_finite()) {
            return bad(format!(
                "pressure {} must be a finite number above 1 (the ideal gas's)",
                self.max_pressure
            ));
        }
        if let Some(phi) = self.target_packing {
            if !(phi > 0.0 && phi < 1.0) {
                return bad(format!("target packing fraction {phi:?} is outside (0, 1)"));
            }
        }
        if !(self.collisions_per_rescale >= 0.01 && self.collisions_per_rescale <= 1e6) {
            return bad(format!(
                "collisions per rescale {} is outside [0.01, 1e6]",
                self.collisions_per_rescale
            ));
        }
        if !(self.min_relative_change >= 0.0 && self.min_relative_change < 1.0) {
            return bad(format!(
                "relative change {} is outside [0, 1)",
                self.min_relative_change
            ));
        }
        Ok(())
    }
}

/// Why a compression stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// The reduced pressure reached [`PackOptions::max_pressure`].
    Pressure,
    /// The packing fraction stopped changing ([`PackOptions::min_relative_change`]).
    Converged,
    /// The target packing fraction was reached.
    Packing,
    /// The progress callback or the stop request ([`Packer::run_watched`]) asked to stop.
    Interrupted,
}

impl Stop {
    /// A short name (`pressure`, `converged`, `packing`, `interrupted`).
    pub fn name(self) -> &'static str {
        match self {
            Stop::Pressure => "pressure",
            Stop::Converged => "converged",
            Stop::Packing => "packing",
            Stop::Interrupted => "interrupted",
        }
    }
}

/// The state handed to the progress callback at each rescaling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Status {
    /// Packing fraction now.
    pub packing_fraction: f64,
    /// Reduced pressure of the last interval (`None` before the first).
    pub reduced_pressure: Option<f64>,
    /// Pair collisions so far.
    pub collisions: u64,
}

/// The result of a compression.
#[derive(Clone, Debug, PartialEq)]
pub struct Packing<const D: usize> {
    /// The particles at the end (positions in the box, final radii, velocities of rms
    /// speed about 1).
    pub discs: Vec<Disc<D>>,
    /// The box.
    pub sim_box: SimBox<D>,
    /// Packing fraction.
    pub packing_fraction: f64,
    /// Reduced pressure `PV / (NkT)` of the last interval (`None` if none was measured).
    pub reduced_pressure: Option<f64>,
    /// Pair collisions.
    pub collisions: u64,
    /// Wall collisions.
    pub wall_collisions: u64,
    /// Events of every kind (collisions, cell crossings, stale predictions).
    pub events: u64,
    /// Velocity rescalings (synchronisations).
    pub rescales: u64,
    /// Why it stopped.
    pub stop: Stop,
}
