//! Equilibrium fluids of equal discs and of mixtures, made with the engine itself.
//!
//! Both are made the same way ([`Recipe`] holds the knobs):
//!
//! 1. **Lattice.** The discs are put on randomly chosen sites of a triangular lattice with a
//!    few percent of its sites left empty (vacancies let a crystal melt quickly instead of
//!    waiting for defects to form), spaced for the largest disc, in a near-square box sized so
//!    that the packing is [`Recipe::melt_packing`] (0.6), or the requested packing if lower, or
//!    the densest that the lattice allows if that is lower still. Velocities are
//!    Maxwell-Boltzmann at `kT = 1` with zero total momentum and kinetic energy exactly `N kT`.
//! 2. **Melting.** The engine runs the discs until the global bond-orientational order
//!    `|psi_6|` (six nearest neighbours, [`super::order`]) falls below a threshold
//!    ([`melting_threshold`]), checked after 5 collisions per disc and then after every further
//!    one. A lattice that has not melted within a bounded number of collisions is an error.
//!
//! Spheres (`generate_in::<3>`) are made the same way from a face-centred cubic lattice with
//! vacancies, melted at a packing of at most [`MELT_PACKING_3D`], and the order parameter is the
//! amplitude of the lattice's own density wave: `sqrt(mean |rho_k|^2)` over the four `{111}`
//! reciprocal vectors of the (uniformly shrinking) cubic cell, `rho_k = (1/N) sum exp(i k.r)`,
//! near 1 on the lattice and about `1/sqrt(N)` in a fluid, judged against the same
//! [`melting_threshold`]. Spheres are fluid up to [`FLUID_MAX_PACKING_3D`].
//! 3. **Compression**, if the requested packing is higher: positions and box are scaled down in
//!    stages, each followed by removal of the few overlaps it makes and a collision per disc of
//!    engine time ([`super::compress`]). The last stage lands on the box that gives exactly the
//!    requested packing.
//! 4. **Equilibration and check.** The engine runs [`Recipe::equilibrate_collisions_per_disc`]
//!    (20) collisions per disc at the final packing, and `|psi_6|` must be below the threshold
//!    (checked then and after every further collision per disc, up to a bound); a system that
//!    stays ordered is an error.
//!
//! Melting at 0.6 and compressing is much faster than melting at the final packing: a lattice
//! with 6% vacancies melts at 0.6 within 5 to 7 collisions per disc, while at 0.70 it needed
//! 500 to over 1000 (N = 400 and 1000) to fall below `3 / sqrt(N)`. Equal discs are liquid
//! only up to a packing of 0.70 ([`FLUID_MAX_PACKING`]); mixtures of unequal sizes stay
//! disordered up to jamming, near which the compression runs out of stages and gives up.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

use super::compress::compress;
use super::generators::{BLUE, RED};
use super::lattice::{ball_volume, close_packing, fcc_sites, root, thermal_velocities};
use super::order::{fcc_order, psi6, Neighbours};
use super::MIN_PACKING;
use crate::error::Error;
use crate::math::Vector;
use crate::simulation::{Options, Simulation};
use crate::state::{Boundary, Disc, SimBox, System};

/// Fewest discs for a fluid or a mixture: the melting criterion needs a few dozen discs.
pub const MIN_FLUID_DISCS: usize = 20;

/// Highest packing of a [`Fluid`]. Equal hard discs are liquid only up to 0.700; then come
/// liquid-hexatic coexistence (to 0.716), the hexatic phase (to 0.720) and the solid (E. P.
/// Bernard and W. Krauth, Phys. Rev. Lett. 107, 155704 (2011)). Denser disordered systems are
/// mixtures.
pub const FLUID_MAX_PACKING: f64 = 0.70;

/// Highest packing of a [`Fluid`] of spheres (3D). The hard-sphere fluid freezes at 0.494 and
/// the solid melts at 0.545 (W. G. Hoover and F. H. Ree, J. Chem. Phys. 49, 3609 (1968));
/// between them a fluid is metastable, and at 0.50 it stays a fluid for far longer than any
/// run here (crystal nucleation needs packings near 0.53 to be quick: S. Auer and D. Frenkel,
/// Nature 409, 1020 (2001)).
pub const FLUID_MAX_PACKING_3D: f64 = 0.50;

/// Highest packing at which a lattice of spheres is placed and melted: a face-centred cubic
/// crystal with vacancies at 0.35 is far below the solid's melting packing and melts within a
/// few collisions per sphere.
pub const MELT_PACKING_3D: f64 = 0.35;

/// The default threshold on `|psi_6|` for `n` discs: `10 / sqrt(n)`, but never above 0.5.
///
/// If the local order parameters of a configuration are correlated over patches of about `m`
/// discs, `|psi_6|` is about `sqrt(m / n)`: `1 / sqrt(n)` for an uncorrelated liquid, 1 for a
/// crystal. The threshold lets orientational correlations extend over some 100 discs (a
/// correlation length of about 5 diameters, reached in liquids just below the hexatic packing
/// 0.70, and by wall layering) but not over the whole box; the cap of 0.5 keeps small systems
/// clear of a crystal with vacancies (0.8 to 0.95) and of a polycrystal of two or three grains.
pub fn melting_threshold(n: usize) -> f64 {
    (10.0 / (n.max(1) as f64).sqrt()).min(0.5)
}

/// A fluid of equal discs (diameter 1, mass 1, black, `kT = 1`) at a packing fraction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fluid {
    /// Number of discs, at least [`MIN_FLUID_DISCS`]. Default 400.
    pub n: usize,
    /// Packing fraction `N pi / 4 / area`, in `(0, 0.70]` ([`FLUID_MAX_PACKING`]). Default 0.6.
    pub packing: f64,
    /// Boundary on both axes. Default periodic.
    pub boundary: Boundary,
    /// How the fluid is made and checked.
    pub recipe: Recipe,
}

impl Default for Fluid {
    fn default() -> Self {
        Fluid {
            n: 400,
            packing: 0.6,
            boundary: Boundary::Periodic,
            recipe: Recipe::default(),
        }
    }
}

/// The disc sizes of a [`Mixture`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sizes {
    /// Small discs of diameter 1 (species 0, blue) and large ones of diameter `size_ratio`
    /// (species 1, red).
    Binary {
        /// Large over small diameter, in `[1, 10]`. Default 1.4.
        size_ratio: f64,
        /// Number fraction of large discs, in `[0, 1]`; the number of large discs is
        /// `round(fraction_large * n)`. Default 0.5.
        fraction_large: f64,
    },
    /// Diameters drawn uniformly from `[1 - spread, 1 + spread]` (mean 1, relative standard
    /// deviation `spread / sqrt(3)`), species 0, grey.
    Polydisperse {
        /// Relative half-width of the diameter distribution, in `[0, 0.5]`. Default 0.1.
        spread: f64,
    },
}

impl Default for Sizes {
    fn default() -> Self {
        Sizes::Binary {
            size_ratio: 1.4,
            fraction_large: 0.5,
        }
    }
}

/// A fluid mixture of discs of different sizes (mass 1 each, `kT = 1`) at a packing fraction.
///
/// Reachable with the default [`Recipe`]: up to a packing of about 0.82 (0.81 with walls, where
/// the layers at the walls are less dense); 0.80 takes 0.2 to 0.7 s for 400 to 1000 discs.
/// Measured limits for 400 discs, where the compression gave up: binary 1.4 with half large
/// 0.833 periodic and 0.816 with walls; polydisperse with spread 0.1 and 0.2, 0.839 and 0.831
/// periodic, 0.817 with walls. Nearly equal sizes (`size_ratio` near 1, `spread` near 0) order
/// above a packing of about 0.70 like equal discs, and the final check may then fail.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mixture {
    /// Number of discs, at least [`MIN_FLUID_DISCS`]. Default 400.
    pub n: usize,
    /// Packing fraction `sum pi r^2 / area`, in `(0, 0.9069)`. Default 0.7.
    pub packing: f64,
    /// Boundary on both axes. Default periodic.
    pub boundary: Boundary,
    /// The size distribution. Default binary, size ratio 1.4, half the discs large.
    pub sizes: Sizes,
    /// How the mixture is made and checked.
    pub recipe: Recipe,
}

impl Default for Mixture {
    fn default() -> Self {
        Mixture {
            n: 400,
            packing: 0.7,
            boundary: Boundary::Periodic,
            sizes: Sizes::default(),
            recipe: Recipe::default(),
        }
    }
}

/// How a [`Fluid`] or a [`Mixture`] is made (see the module doc) and how much work it may take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Recipe {
    /// Fraction of the starting lattice's sites left empty, in `[0, 0.5]` (rounded up to fill
    /// whole rows). Default 0.06.
    pub vacancies: f64,
    /// Highest packing at which the lattice is placed and melted; denser systems are compressed
    /// from here. In `(0, 0.70]`. Default 0.6.
    pub melt_packing: f64,
    /// Threshold on `|psi_6|` for "melted" and for the final check; `None` for
    /// [`melting_threshold`]`(n)`. Default `None`.
    pub psi6_threshold: Option<f64>,
    /// Collisions per disc run at the final packing before the final check. Default 20.
    pub equilibrate_collisions_per_disc: u32,
    /// Collisions per disc allowed for the melting and for the final check each, after which a
    /// system still above the threshold is an error. Default 500.
    pub max_collisions_per_disc: u32,
    /// Compression stages allowed. Default 20000.
    pub max_stages: u32,
}

impl Default for Recipe {
    fn default() -> Self {
        Recipe {
            vacancies: 0.06,
            melt_packing: 0.6,
            psi6_threshold: None,
            equilibrate_collisions_per_disc: 20,
            max_collisions_per_disc: 500,
            max_stages: 20_000,
        }
    }
}

/// How a generated fluid or mixture was made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeltReport {
    /// Packing at which the lattice was melted.
    pub melt_packing: f64,
    /// Collisions per disc (`2 x disc-disc collisions / N`) run until the lattice had melted.
    pub melt_collisions_per_disc: f64,
    /// Compression stages, retried ones included (0 when the lattice was placed at the
    /// requested packing).
    pub stages: u32,
    /// Collisions per disc run in all (melting, compression, equilibration and final check).
    pub collisions_per_disc: f64,
    /// The order parameter of the returned configuration: in 2D `|psi_6|` (six nearest
    /// neighbours), in 3D the amplitude of the FCC lattice's density wave (see the module doc).
    pub psi6: f64,
    /// The threshold it is below.
    pub threshold: f64,
    /// Packing fraction of the returned configuration.
    pub packing: f64,
}

impl Fluid {
    /// Builds the fluid; every random choice comes from `seed`.
    pub fn generate(&self, seed: u64) -> Result<System, Error> {
        self.generate_with_report(seed).map(|(s, _)| s)
    }

    /// Builds the fluid and reports how it was made.
    pub fn generate_with_report(&self, seed: u64) -> Result<(System, MeltReport), Error> {
        self.generate_in::<2>(seed)
    }

    /// Builds the fluid in `D` dimensions (2: discs, 3: spheres of diameter 1, up to a packing
    /// of [`FLUID_MAX_PACKING_3D`], melted from a face-centred cubic lattice) and reports how it
    /// was made.
    pub fn generate_in<const D: usize>(&self, seed: u64) -> Result<(System<D>, MeltReport), Error> {
        check_dim(D)?;
        if D == 2 && self.packing > FLUID_MAX_PACKING {
            return Err(Error::Invalid(format!(
                "fluid: packing {} is above {FLUID_MAX_PACKING}, where equal hard discs stop being a liquid \
                 (hexatic from 0.700, solid from 0.720); use a mixture for a denser disordered system",
                self.packing
            )));
        }
        if D == 3 && self.packing > FLUID_MAX_PACKING_3D {
            return Err(Error::Invalid(format!(
                "fluid: packing {} is above {FLUID_MAX_PACKING_3D}: hard spheres freeze at 0.494 and a denser \
                 fluid soon crystallises; use a mixture for a denser disordered system",
                self.packing
            )));
        }
        let discs = vec![Disc::new(Vector::ZERO, Vector::ZERO, 0.5); self.n];
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        make(
            "fluid",
            discs,
            self.packing,
            self.boundary,
            &self.recipe,
            &mut rng,
        )
    }
}

impl Mixture {
    /// Builds the mixture; every random choice comes from `seed`.
    pub fn generate(&self, seed: u64) -> Result<System, Error> {
        self.generate_with_report(seed).map(|(s, _)| s)
    }

    /// Builds the mixture and reports how it was made.
    pub fn generate_with_report(&self, seed: u64) -> Result<(System, MeltReport), Error> {
        self.generate_in::<2>(seed)
    }

    /// Builds the mixture in `D` dimensions (2: discs, 3: spheres, placed on a face-centred
    /// cubic lattice spaced for the largest) and reports how it was made.
    pub fn generate_in<const D: usize>(&self, seed: u64) -> Result<(System<D>, MeltReport), Error> {
        check_dim(D)?;
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        let discs = self.discs(&mut rng)?;
        make(
            "mixture",
            discs,
            self.packing,
            self.boundary,
            &self.recipe,
            &mut rng,
        )
    }

    /// The `n` discs (sizes, species, colours), in random order.
    fn discs<const D: usize>(&self, rng: &mut impl Rng) -> Result<Vec<Disc<D>>, Error> {
        let n = self.n;
        let disc = |d: f64, species: u16, colour| Disc {
            species,
            colour,
            ..Disc::new(Vector::ZERO, Vector::ZERO, 0.5 * d)
        };
        match self.sizes {
            Sizes::Binary {
                size_ratio,
                fraction_large,
            } => {
                if !(1.0..=10.0).contains(&size_ratio) {
                    return Err(Error::Invalid(format!(
                        "mixture: size ratio {size_ratio} is outside [1, 10] (large over small diameter)"
                    )));
                }
                if !(0.0..=1.0).contains(&fraction_large) {
                    return Err(Error::Invalid(format!(
                        "mixture: number fraction of large discs {fraction_large} is outside [0, 1]"
                    )));
                }
                let large = (fraction_large * n as f64).round() as usize;
                let mut discs: Vec<Disc<D>> = (0..n)
                    .map(|k| {
                        if k < large {
                            disc(size_ratio, 1, RED)
                        } else {
                            disc(1.0, 0, BLUE)
                        }
                    })
                    .collect();
                shuffle(&mut discs, rng);
                Ok(discs)
            }
            Sizes::Polydisperse { spread } => {
                if !(0.0..=0.5).contains(&spread) {
                    return Err(Error::Invalid(format!(
                        "mixture: diameter spread {spread} is outside [0, 0.5] (diameters 1 - spread to 1 + spread)"
                    )));
                }
                Ok((0..n)
                    .map(|_| {
                        disc(
                            1.0 + spread * (2.0 * rng.random::<f64>() - 1.0),
                            0,
                            [128; 3],
                        )
                    })
                    .collect())
            }
        }
    }
}

/// Places `discs` (sizes and labels set) on a lattice, melts, compresses, equilibrates and
/// checks them (see the module doc).
fn make<const D: usize>(
    kind: &str,
    discs: Vec<Disc<D>>,
    packing: f64,
    boundary: Boundary,
    recipe: &Recipe,
    rng: &mut impl Rng,
) -> Result<(System<D>, MeltReport), Error> {
    let n = discs.len();
    check(kind, n, packing, D, recipe)?;
    let threshold = recipe
        .psi6_threshold
        .unwrap_or_else(|| melting_threshold(n));
    let diameters: Vec<f64> = discs.iter().map(|d| 2.0 * d.radius).collect();
    let lat = Lattice::<D>::new(n, recipe.vacancies, boundary);
    let melt_packing = if D == 3 {
        recipe.melt_packing.min(MELT_PACKING_3D)
    } else {
        recipe.melt_packing
    };
    let start = packing
        .min(melt_packing)
        .min(lat.densest_packing(&diameters));
    let mut sim = new_simulation(lat.place(discs, start, rng), kind)?;
    let max = recipe.max_collisions_per_disc;
    let melted = settle(&mut sim, &lat, threshold, 5, max).map_err(|psi| {
        Error::Invalid(format!(
            "{kind}: the starting lattice did not melt at packing {start:.4} within {max} collisions per disc \
             (|psi_6| = {psi:.3}, threshold {threshold:.3}); lower the melting packing or raise the vacancies"
        ))
    })?;
    let mut work = 0.0;
    let mut stages = 0;
    if start < packing {
        let target = lat.box_lengths(&diameters, packing);
        let c = compress(sim, target, recipe.max_stages).map_err(|(reached, k)| {
            Error::Invalid(format!(
                "{kind}: compression reached packing {reached:.4} but not {packing} within {k} stages: \
                 too near jamming (about 0.82 is reachable, 0.81 with walls)"
            ))
        })?;
        (sim, stages) = (c.sim, c.stages);
        work += c.collisions_per_disc;
    }
    let equilibrate = recipe.equilibrate_collisions_per_disc;
    settle(&mut sim, &lat, threshold, equilibrate, equilibrate + max).map_err(|psi| {
        let phases = if D == 3 {
            "hard spheres freeze above 0.494"
        } else {
            "hard discs are hexatic above about 0.70 and solid above 0.72"
        };
        Error::Invalid(format!(
            "{kind}: at packing {packing} the system stayed ordered ({} = {psi:.3} after {} collisions per particle, \
             threshold {threshold:.3}): {phases}",
            lat.order_name(),
            equilibrate + max
        ))
    })?;
    let mut discs = sim.discs();
    in_cell_order(&mut discs, sim.sim_box());
    let system = System {
        discs,
        sim_box: *sim.sim_box(),
        barriers: Vec::new(),
    };
    let report = MeltReport {
        melt_packing: start,
        melt_collisions_per_disc: melted,
        stages,
        collisions_per_disc: work + collisions_per_disc(&sim),
        psi6: lat.order(&system.discs, &system.sim_box),
        threshold,
        packing: packing_of(&system.discs, &system.sim_box),
    };
    Ok((system, report))
}

/// Puts `discs` in the order of the cells (about a diameter wide, the last axis slowest) that
/// hold them, so that the discs around any one sit near it in memory: a run then reads fewer
/// cache lines per prediction. In random order, as the lattice's random sites left them, a
/// fluid of 10^5 spheres ran 10 to 25% slower (BENCHMARKS.md). Discs in one
/// cell keep their order (a stable sort), so the result is a function of the discs alone.
pub(crate) fn in_cell_order<const D: usize>(discs: &mut [Disc<D>], sim_box: &SimBox<D>) {
    let width = discs.iter().map(|d| 2.0 * d.radius).fold(0.0, f64::max);
    if discs.is_empty() || width <= 0.0 {
        return;
    }
    let cells = sim_box
        .lengths
        .map(|l| ((l / width).floor() as u64).clamp(1, 1 << 20));
    let key = |d: &Disc<D>| {
        (0..D).rev().fold(0u64, |k, a| {
            let c = ((d.pos[a] / sim_box.lengths[a] * cells[a] as f64).floor() as u64)
                .min(cells[a] - 1);
            k * cells[a] + c
        })
    };
    discs.sort_by_cached_key(key);
}

/// Checks the parameters that fluids and mixtures share.
fn check(kind: &str, n: usize, packing: f64, dim: usize, recipe: &Recipe) -> Result<(), Error> {
    let bad = |what: String| Err(Error::Invalid(format!("{kind}: {what}")));
    if n < MIN_FLUID_DISCS {
        let what = if dim == 3 { "spheres" } else { "discs" };
        return bad(format!("needs at least {MIN_FLUID_DISCS} {what}, got {n}"));
    }
    let close = close_packing(dim);
    if !(packing >= MIN_PACKING && packing < close) {
        let what = if dim == 3 { "spheres" } else { "discs" };
        return bad(format!(
            "packing fraction {packing} is outside [{MIN_PACKING}, {close:.4}) (close packing of {what}; \
             lower packings take hours to melt)"
        ));
    }
    if !(0.0..=0.5).contains(&recipe.vacancies) {
        return bad(format!(
            "vacancy fraction {} is outside [0, 0.5]",
            recipe.vacancies
        ));
    }
    if !(recipe.melt_packing > 0.0 && recipe.melt_packing <= 0.7) {
        return bad(format!(
            "melting packing {} is outside (0, 0.7]",
            recipe.melt_packing
        ));
    }
    if let Some(t) = recipe.psi6_threshold {
        if !(t > 0.0 && t < 1.0) {
            return bad(format!("psi_6 threshold {t} is outside (0, 1)"));
        }
    }
    Ok(())
}

/// The starting lattice: triangular in 2D, face-centred cubic in 3D, with at least
/// `n / (1 - vacancies)` sites in a near-square box or a cube, in units of the lattice's own
/// length (the spacing in 2D, the cubic cell's side in 3D). Periodic 2D boxes get an even
/// number of rows, so that the staggered rows match across the boundary; walled boxes keep half
/// a nearest-neighbour distance clear of the walls.
struct Lattice<const D: usize> {
    sites: Vec<Vector<D>>,
    /// Box lengths in lattice units.
    size: [f64; D],
    /// Nearest-neighbour distance in lattice units: 1 (triangular), `1 / sqrt 2` (FCC).
    nearest: f64,
    boundary: Boundary,
}

impl<const D: usize> Lattice<D> {
    fn new(n: usize, vacancies: f64, boundary: Boundary) -> Self {
        let m = ((n as f64 / (1.0 - vacancies)).ceil() as usize).max(n);
        let (sites, size, nearest) = if D == 3 {
            let (s, size) = fcc_sites(m, boundary);
            (s, size, std::f64::consts::FRAC_1_SQRT_2)
        } else {
            let (s, size) = triangular_sites(m, boundary);
            (s, [size[0], size[1], 0.0], 1.0)
        };
        Lattice {
            sites: sites
                .iter()
                .map(|s| Vector(std::array::from_fn(|a| s[a])))
                .collect(),
            size: std::array::from_fn(|a| size[a]),
            nearest,
            boundary,
        }
    }

    /// The lattice unit that gives `packing` for particles of these diameters.
    fn spacing(&self, diameters: &[f64], packing: f64) -> f64 {
        let volume: f64 = diameters.iter().map(|&d| ball_volume(d, D)).sum();
        // `packing * size[0] * size[1] ...` in that order, as 2D always computed it.
        root(volume / self.size.iter().fold(packing, |p, s| p * s), D)
    }

    fn box_lengths(&self, diameters: &[f64], packing: f64) -> [f64; D] {
        let a = self.spacing(diameters, packing);
        self.size.map(|s| s * a)
    }

    /// The highest packing with the nearest-neighbour distance no less than the largest
    /// diameter.
    fn densest_packing(&self, diameters: &[f64]) -> f64 {
        let d_max = diameters.iter().cloned().fold(0.0, f64::max);
        let a1 = self.spacing(diameters, 1.0);
        (a1 * self.nearest / d_max).powi(D as i32)
    }

    /// The particles on randomly chosen sites (in random order), at `packing` (which must not
    /// exceed [`Self::densest_packing`]), with velocities at `kT = 1`.
    fn place(
        &self,
        mut discs: Vec<Disc<D>>,
        packing: f64,
        rng: &mut impl Rng,
    ) -> (Vec<Disc<D>>, SimBox<D>) {
        let diameters: Vec<f64> = discs.iter().map(|d| 2.0 * d.radius).collect();
        let a = self.spacing(&diameters, packing);
        let mut order: Vec<usize> = (0..self.sites.len()).collect();
        shuffle(&mut order, rng);
        for (d, &k) in discs.iter_mut().zip(&order) {
            d.pos = self.sites[k] * a;
        }
        thermal_velocities(&mut discs, 1.0, rng);
        let sim_box = SimBox {
            lengths: self.size.map(|s| s * a),
            boundaries: [self.boundary; D],
        };
        (discs, sim_box)
    }

    /// What [`Self::order`] measures, for messages.
    fn order_name(&self) -> &'static str {
        if D == 3 {
            "the FCC density wave |rho_k|"
        } else {
            "|psi_6|"
        }
    }

    /// The order parameter that tells the lattice from a fluid: in 2D the global
    /// bond-orientational order `|psi_6|` ([`super::order`]); in 3D the amplitude of the
    /// lattice's density wave ([`fcc_order`]) for the current cubic cell (the box shrinks
    /// uniformly, so it still holds `size` cells).
    fn order(&self, discs: &[Disc<D>], sim_box: &SimBox<D>) -> f64 {
        if D == 2 {
            let flat: Vec<Disc> = discs.iter().map(|d| d.with_dim()).collect();
            let flat_box = SimBox {
                lengths: [sim_box.lengths[0], sim_box.lengths[1]],
                boundaries: [sim_box.boundaries[0], sim_box.boundaries[1]],
            };
            return psi6(&flat, &flat_box, Neighbours::Nearest(6));
        }
        let flat: Vec<Disc<3>> = discs.iter().map(|d| d.with_dim()).collect();
        let cube = SimBox {
            lengths: std::array::from_fn(|a| sim_box.lengths[a.min(D - 1)]),
            boundaries: [sim_box.boundaries[0]; 3],
        };
        fcc_order(
            &flat,
            &cube,
            std::array::from_fn(|a| self.size[a.min(D - 1)]),
        )
    }
}

/// The sites of a triangular lattice of at least `m` sites (see [`Lattice`]), and the box
/// size in spacings.
fn triangular_sites(m: usize, boundary: Boundary) -> (Vec<[f64; 3]>, [f64; 2]) {
    let h = 3f64.sqrt() / 2.0;
    let mut rows = ((m as f64 / h).sqrt().ceil() as usize).max(1);
    if boundary == Boundary::Periodic && rows % 2 == 1 {
        rows += 1;
    }
    let cols = m.div_ceil(rows).max(1);
    let (size, x0, y0) = match boundary {
        Boundary::Periodic => ([cols as f64, rows as f64 * h], 0.25, h / 2.0),
        Boundary::Walls => ([cols as f64 + 0.5, (rows - 1) as f64 * h + 1.0], 0.5, 0.5),
    };
    let sites = (0..rows)
        .flat_map(|row| {
            (0..cols).map(move |col| {
                let shift = if row % 2 == 1 { 0.5 } else { 0.0 };
                [x0 + col as f64 + shift, y0 + row as f64 * h, 0.0]
            })
        })
        .collect();
    (sites, size)
}

/// Refuses a dimension the generators do not make.
fn check_dim(dim: usize) -> Result<(), Error> {
    if dim == 2 || dim == 3 {
        Ok(())
    } else {
        Err(Error::Invalid(format!(
            "fluids and mixtures are made in 2 or 3 dimensions, not {dim}"
        )))
    }
}

/// Fisher-Yates shuffle.
pub(crate) fn shuffle<T>(v: &mut [T], rng: &mut impl Rng) {
    for i in (1..v.len()).rev() {
        let j = rng.random_range(0..=i);
        v.swap(i, j);
    }
}

/// A simulation of generated discs; a refusal means a parameter the checks let through.
fn new_simulation<const D: usize>(
    (discs, sim_box): (Vec<Disc<D>>, SimBox<D>),
    kind: &str,
) -> Result<Simulation<D>, Error> {
    Simulation::new(&discs, sim_box, Options::default())
        .map_err(|e| Error::Invalid(format!("{kind}: the generated system is invalid: {e}")))
}

/// Collisions per disc run so far: `2 x disc-disc collisions / N`.
fn collisions_per_disc<const D: usize>(sim: &Simulation<D>) -> f64 {
    2.0 * sim.stats().disc_disc as f64 / sim.len().max(1) as f64
}

/// Runs until `target` disc-disc collisions have happened in all. Returns false if that took
/// more than `max_events` events (of any kind) or nothing will ever happen.
pub(crate) fn run_collisions<const D: usize>(
    sim: &mut Simulation<D>,
    target: u64,
    max_events: u64,
) -> bool {
    let chunk = (sim.len() as u64).max(64);
    let mut events = 0u64;
    while sim.stats().disc_disc < target {
        if events >= max_events || sim.run_events(chunk, &mut ()) < chunk {
            return sim.stats().disc_disc >= target;
        }
        events += chunk;
    }
    true
}

/// Runs until the lattice's order parameter ([`Lattice::order`]) is below `threshold`,
/// checking first after `first` collisions per disc (counted from now) and then after every
/// further one, up to `max`. Returns the collisions per disc it took, or the last order
/// parameter if `max` went by first.
fn settle<const D: usize>(
    sim: &mut Simulation<D>,
    lat: &Lattice<D>,
    threshold: f64,
    first: u32,
    max: u32,
) -> Result<f64, f64> {
    let n = sim.len() as u64;
    let start = sim.stats().disc_disc;
    let mut last = 1.0;
    for k in first..=max.max(first) {
        run_collisions(sim, start + (k as u64 * n).div_ceil(2), u64::MAX);
        last = lat.order(&sim.discs(), sim.sim_box());
        if last < threshold {
            return Ok(2.0 * (sim.stats().disc_disc - start) as f64 / n as f64);
        }
    }
    Err(last)
}

/// Packing fraction: `sum 2r / L` in 1D (the fraction of the line the rods cover),
/// `sum pi r^2 / area` in 2D, `sum 4/3 pi r^3 / volume` in 3D.
pub fn packing_of<const D: usize>(discs: &[Disc<D>], sim_box: &SimBox<D>) -> f64 {
    let volume: f64 = if D == 1 {
        discs.iter().map(|d| 2.0 * d.radius).sum()
    } else if D == 3 {
        discs
            .iter()
            .map(|d| 4.0 / 3.0 * std::f64::consts::PI * d.radius.powi(3))
            .sum()
    } else {
        discs
            .iter()
            .map(|d| std::f64::consts::PI * d.radius * d.radius)
            .sum()
    };
    volume / sim_box.volume()
}
