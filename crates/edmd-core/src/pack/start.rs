//! Random starts: particle sizes and random non-overlapping positions at a low packing.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

use super::bins::Bins;
use crate::error::Error;
use crate::math::Vector;
use crate::setup::generators::{BLUE, RED};
use crate::setup::thermal_velocities;
use crate::state::{Boundary, Disc, SimBox};

/// Packing fraction of a random start: dilute enough that random positions rarely overlap
/// (each particle is tried until it overlaps none placed before it).
pub const START_PACKING: f64 = 0.01;

/// Tries per particle before the random start gives up.
const TRIES: u32 = 10_000;

/// The particle sizes of a packing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PackSizes {
    /// Small particles of diameter 1 and a number fraction `fraction_large` of large ones of
    /// diameter `size_ratio` (species 1, red; the small ones species 0, blue). `size_ratio = 1`
    /// is monodisperse.
    Binary {
        /// Large over small diameter, in `[1, 10]`.
        size_ratio: f64,
        /// Number fraction of large particles, in `[0, 1]`.
        fraction_large: f64,
    },
    /// Diameters uniform in `1 +- sqrt(3) S`: mean 1 and relative standard deviation `S`, in
    /// `(0, 0.5]` (so the smallest diameter is above `0.13`).
    Polydisperse {
        /// Relative standard deviation `S` of the diameters.
        std: f64,
    },
}

impl PackSizes {
    /// Equal particles of diameter 1.
    pub const MONODISPERSE: PackSizes = PackSizes::Binary {
        size_ratio: 1.0,
        fraction_large: 0.0,
    };

    /// Checks the parameters' ranges.
    pub fn validate(&self) -> Result<(), Error> {
        match *self {
            PackSizes::Binary {
                size_ratio,
                fraction_large,
            } => {
                if !(1.0..=10.0).contains(&size_ratio) {
                    return Err(Error::Invalid(format!(
                        "pack: size ratio {size_ratio} is outside [1, 10] (large over small diameter)"
                    )));
                }
                if !(0.0..=1.0).contains(&fraction_large) {
                    return Err(Error::Invalid(format!(
                        "pack: number fraction of large particles {fraction_large} is outside [0, 1]"
                    )));
                }
            }
            PackSizes::Polydisperse { std } => {
                if !(std > 0.0 && std <= 0.5) {
                    return Err(Error::Invalid(format!(
                        "pack: polydispersity {std} is outside (0, 0.5] (relative standard deviation of the diameters)"
                    )));
                }
            }
        }
        Ok(())
    }

    /// `n` particles of these sizes at the origin, at rest, in random order.
    fn particles<const D: usize>(&self, n: usize, rng: &mut impl Rng) -> Vec<Disc<D>> {
        let make = |d: f64, species: u16, colour| Disc {
            species,
            colour,
            ..Disc::new(Vector::ZERO, Vector::ZERO, 0.5 * d)
        };
        match *self {
            PackSizes::Binary {
                size_ratio,
                fraction_large,
            } => {
                let large = (fraction_large * n as f64).round() as usize;
                let mut v: Vec<Disc<D>> = (0..n)
                    .map(|k| {
                        if k < large && size_ratio != 1.0 {
                            make(size_ratio, 1, RED)
                        } else {
                            make(1.0, 0, BLUE)
                        }
                    })
                    .collect();
                crate::setup::fluid::shuffle(&mut v, rng);
                v
            }
            PackSizes::Polydisperse { std } => {
                let w = 3f64.sqrt() * std;
                (0..n)
                    .map(|_| make(1.0 + w * (2.0 * rng.random::<f64>() - 1.0), 0, [128; 3]))
                    .collect()
            }
        }
    }
}

/// Volume of a ball of diameter `d` in `D` dimensions (area of a disc in 2D).
pub fn ball_volume<const D: usize>(d: f64) -> f64 {
    let r = 0.5 * d;
    match D {
        2 => std::f64::consts::PI * r * r,
        3 => 4.0 / 3.0 * std::f64::consts::PI * r * r * r,
        _ => unreachable!("edmd has 2D and 3D engines"),
    }
}

/// `n` particles of the given sizes at random non-overlapping positions in a cubic (square)
/// box at packing fraction [`START_PACKING`], with thermal velocities (`kT = 1`, zero total
/// momentum). The box's volume is the particles' total volume at their nominal sizes (diameter
/// 1 for the small ones), so that the nominal sizes would fill it (packing fraction 1) and
/// the radii are scaled down to reach [`START_PACKING`]. Every random choice comes from `seed`.
pub fn random_start<const D: usize>(
    n: usize,
    sizes: PackSizes,
    boundary: Boundary,
    seed: u64,
) -> Result<(Vec<Disc<D>>, SimBox<D>), Error> {
    sizes.validate()?;
    if n == 0 {
        return Err(Error::Invalid("pack: no particles (n = 0)".into()));
    }
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut discs = sizes.particles::<D>(n, &mut rng);
    let volume: f64 = discs.iter().map(|d| ball_volume::<D>(2.0 * d.radius)).sum();
    let l = volume.powf(1.0 / D as f64);
    let sim_box = SimBox {
        lengths: [l; D],
        boundaries: [boundary; D],
    };
    let scale = START_PACKING.powf(1.0 / D as f64);
    for d in &mut discs {
        d.radius *= scale;
    }
    place(&mut discs, &sim_box, &mut rng)?;
    thermal_velocities(&mut discs, 1.0, &mut rng);
    Ok((discs, sim_box))
}

/// Random sequential placement, each particle tried until it overlaps none placed before it.
fn place<const D: usize>(
    discs: &mut [Disc<D>],
    sim_box: &SimBox<D>,
    rng: &mut impl Rng,
) -> Result<(), Error> {
    let d_max = discs.iter().map(|d| 2.0 * d.radius).fold(0.0, f64::max);
    let mut bins = Bins::new(sim_box, d_max, discs.len());
    for i in 0..discs.len() {
        let r = discs[i].radius;
        let mut placed = false;
        for _ in 0..TRIES {
            let p = Vector(std::array::from_fn(|a| {
                let l = sim_box.lengths[a];
                if sim_box.is_periodic(a) {
                    rng.random::<f64>() * l
                } else {
                    r + rng.random::<f64>() * (l - 2.0 * r)
                }
            }));
            let free = bins.near(p).all(|j| {
                let o = &discs[j];
                let s = r + o.radius;
                sim_box.minimum_image(o.pos - p).norm2() > s * s
            });
            if free {
                discs[i].pos = p;
                bins.insert(i, p);
                placed = true;
                break;
            }
        }
        if !placed {
            return Err(Error::Invalid(format!(
                "pack: no free place found for particle {i} after {TRIES} tries"
            )));
        }
    }
    Ok(())
}
