//! Discs on a triangular lattice, or spheres on a face-centred cubic one, at a chosen packing
//! fraction, with thermal velocities.
//!
//! The triangular lattice is the densest packing of equal discs (`pi / (2 sqrt 3) = 0.9069`),
//! and the FCC lattice the densest of equal spheres (`pi / (3 sqrt 2) = 0.7405`), so every
//! fluid density is reachable from them. Melting is the caller's job: run the system for some
//! collisions per particle.

use rand::{Rng, SeedableRng};
use rand_distr::StandardNormal;
use rand_pcg::Pcg64Mcg;

use crate::error::Error;
use crate::math::{Vector, DIM};
use crate::state::{Boundary, Disc, SimBox};

/// Close packing fraction of discs, `pi / (2 sqrt 3)`.
pub const CLOSE_PACKING: f64 = 0.906_899_682_117_108_9;

/// Close packing fraction of spheres (FCC), `pi / (3 sqrt 2)`.
pub const CLOSE_PACKING_3D: f64 = 0.740_480_489_693_061;

/// Close packing fraction in `dim` dimensions (1, 2 or 3): rods end to end cover the whole line.
pub fn close_packing(dim: usize) -> f64 {
    if dim == 1 {
        1.0
    } else if dim == 3 {
        CLOSE_PACKING_3D
    } else {
        CLOSE_PACKING
    }
}

/// Volume of a `dim`-dimensional ball (1, 2 or 3) of diameter `d`: `d` (a rod's length),
/// `pi d^2 / 4` or `pi d^3 / 6`.
pub fn ball_volume(d: f64, dim: usize) -> f64 {
    if dim == 1 {
        d
    } else if dim == 3 {
        std::f64::consts::PI * d * d * d / 6.0
    } else {
        0.25 * std::f64::consts::PI * d * d
    }
}

/// `x^(1/dim)` for `dim` 1, 2 or 3 (`sqrt` and `cbrt`, exact where `powf` is not).
pub(crate) fn root(x: f64, dim: usize) -> f64 {
    if dim == 1 {
        x
    } else if dim == 3 {
        x.cbrt()
    } else {
        x.sqrt()
    }
}

/// The sites of a face-centred cubic lattice of at least `m` sites in `k^3` cubic cells (the
/// smallest cube that holds them), in units of the cubic cell's side, in cell order (so that
/// the first `m` sites fill whole layers first), and the box size in those units. A periodic
/// box is `k` cells wide; a walled one keeps half a nearest-neighbour distance (`1 / (2 sqrt 2)`)
/// clear of each wall.
pub(crate) fn fcc_sites(m: usize, boundary: Boundary) -> (Vec<[f64; 3]>, [f64; 3]) {
    let mut k = ((m as f64 / 4.0).cbrt().ceil() as usize).max(1);
    while 4 * k * k * k < m {
        k += 1;
    }
    let half_nn = 0.25 * std::f64::consts::SQRT_2;
    let (x0, size) = match boundary {
        Boundary::Periodic => (0.25, k as f64),
        Boundary::Walls => (half_nn, k as f64 - 0.5 + 2.0 * half_nn),
    };
    const BASIS: [[f64; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.5, 0.0, 0.5],
        [0.0, 0.5, 0.5],
    ];
    let mut sites = Vec::with_capacity(4 * k * k * k);
    for z in 0..k {
        for y in 0..k {
            for x in 0..k {
                for b in BASIS {
                    let c = [x as f64, y as f64, z as f64];
                    sites.push(std::array::from_fn(|a| x0 + c[a] + b[a]));
                }
            }
        }
    }
    (sites, [size; 3])
}

/// [`lattice_fluid`] in `D` dimensions: rods (length 1, mass 1) evenly spaced on a line of
/// length `n / packing` in 1D ([`rods`]), discs on a triangular lattice in 2D (exactly
/// [`lattice_fluid`]), spheres (diameter 1, mass 1) on a face-centred cubic lattice in a cube
/// in 3D, the first `n` sites filled layer by layer. Velocities Gaussian at `kT = 1`, zero total
/// momentum.
///
/// # Panics
/// If `D` is not 1, 2 or 3.
pub fn lattice_fluid_in<const D: usize>(
    n: usize,
    packing: f64,
    boundary: Boundary,
    seed: u64,
) -> Result<(Vec<Disc<D>>, SimBox<D>), Error> {
    assert!(
        (1..=3).contains(&D),
        "lattices are made in 1, 2 or 3 dimensions"
    );
    if D == 1 {
        let (discs, bx) = rods(n, packing, boundary, seed)?;
        return Ok((
            discs.iter().map(|d| d.with_dim()).collect(),
            SimBox {
                lengths: std::array::from_fn(|_| bx.lengths[0]),
                boundaries: [boundary; D],
            },
        ));
    }
    if D == 2 {
        let (discs, bx) = lattice_fluid(n, packing, boundary, seed)?;
        return Ok((
            // By value: the same layout, so the discs stay in their array (no second copy of
            // the input at 10^8 discs).
            discs.into_iter().map(|d| d.with_dim()).collect(),
            SimBox {
                lengths: std::array::from_fn(|a| bx.lengths[a]),
                boundaries: [boundary; D],
            },
        ));
    }
    if n == 0 {
        return Err(Error::Invalid(
            "the number of spheres must be at least 1".into(),
        ));
    }
    if !(packing > 0.0 && packing < CLOSE_PACKING_3D) {
        return Err(Error::Invalid(format!(
            "packing fraction {packing} is outside (0, {CLOSE_PACKING_3D:.4})"
        )));
    }
    let (sites, size) = fcc_sites(n, boundary);
    let volume = n as f64 * ball_volume(1.0, 3);
    let a = (volume / (packing * size[0] * size[1] * size[2])).cbrt();
    if a / std::f64::consts::SQRT_2 < 1.0 + 1e-9 {
        return Err(Error::Invalid(format!(
            "packing fraction {packing} does not fit {n} spheres on a lattice in this box"
        )));
    }
    let mut discs: Vec<Disc<D>> = sites[..n]
        .iter()
        .map(|s| Disc::new(Vector(std::array::from_fn(|k| s[k] * a)), Vector::ZERO, 0.5))
        .collect();
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    thermal_velocities(&mut discs, 1.0, &mut rng);
    Ok((
        discs,
        SimBox {
            lengths: std::array::from_fn(|k| size[k] * a),
            boundaries: [boundary; D],
        },
    ))
}

/// `n` hard rods (length 1, mass 1) on a line of length `L = n / packing`, evenly spaced
/// (centres at `(k + 1/2) L / n`, so a walled line keeps half a gap clear of each wall and a
/// periodic one has equal gaps all round), with Gaussian velocities at `kT = 1`, zero total
/// momentum. In one dimension the even spacing is already as good a start as any: rods never
/// pass each other, so there is no lattice to melt, and a few collisions per rod bring the
/// gaps to their equilibrium distribution.
pub fn rods(
    n: usize,
    packing: f64,
    boundary: Boundary,
    seed: u64,
) -> Result<(Vec<Disc<1>>, SimBox<1>), Error> {
    if n == 0 {
        return Err(Error::Invalid(
            "the number of rods must be at least 1".into(),
        ));
    }
    if !(packing > 0.0 && packing < 1.0) {
        return Err(Error::Invalid(format!(
            "packing fraction {packing} is outside (0, 1) (the fraction of the line the rods cover)"
        )));
    }
    let length = n as f64 / packing;
    let gap = length / n as f64;
    let mut discs: Vec<Disc<1>> = (0..n)
        .map(|k| Disc::new(Vector([(k as f64 + 0.5) * gap]), Vector::ZERO, 0.5))
        .collect();
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    thermal_velocities(&mut discs, 1.0, &mut rng);
    Ok((
        discs,
        SimBox {
            lengths: [length],
            boundaries: [boundary],
        },
    ))
}

/// `n` equal discs (diameter 1, mass 1) on a triangular lattice filling a near-square box at
/// packing fraction `packing`, with Gaussian velocities at `kT = 1`, zero total momentum.
pub fn lattice_fluid(
    n: usize,
    packing: f64,
    boundary: Boundary,
    seed: u64,
) -> Result<(Vec<Disc>, SimBox), Error> {
    if n == 0 {
        return Err(Error::Invalid(
            "the number of discs must be at least 1".into(),
        ));
    }
    if !(packing > 0.0 && packing < CLOSE_PACKING) {
        return Err(Error::Invalid(format!(
            "packing fraction {packing} is outside (0, {CLOSE_PACKING:.4})"
        )));
    }
    let r = 0.5;
    let h = 3f64.sqrt() / 2.0;
    let mut rows = ((n as f64 / h).sqrt().ceil() as usize).max(1);
    if boundary == Boundary::Periodic && rows % 2 == 1 {
        rows += 1;
    }
    let cols = n.div_ceil(rows).max(1);
    let disc_area = n as f64 * std::f64::consts::PI * r * r;
    // Box (in lattice spacings a) and the margin to keep discs off the walls.
    // Box size and first site, in lattice spacings: walls keep half a spacing of clearance.
    let (wx, wy, x0, y0) = match boundary {
        Boundary::Periodic => (cols as f64, rows as f64 * h, 0.25, h / 2.0),
        Boundary::Walls => (cols as f64 + 0.5, (rows - 1) as f64 * h + 1.0, 0.5, 0.5),
    };
    let a = (disc_area / (packing * wx * wy)).sqrt();
    if a < 2.0 * r * (1.0 + 1e-9) {
        return Err(Error::Invalid(format!(
            "packing fraction {packing} does not fit {n} discs on a lattice in this box (spacing {a:.4} < diameter 1)"
        )));
    }
    let lengths = [wx * a, wy * a];
    let sim_box = SimBox {
        lengths,
        boundaries: [boundary; DIM],
    };
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut discs = Vec::with_capacity(n);
    'fill: for row in 0..rows {
        for col in 0..cols {
            if discs.len() == n {
                break 'fill;
            }
            let shift = if row % 2 == 1 { 0.5 } else { 0.0 };
            let x = (x0 + col as f64 + shift) * a;
            let y = (y0 + row as f64 * h) * a;
            discs.push(Disc::new(Vector::new([x, y]), Vector::ZERO, r));
        }
    }
    thermal_velocities(&mut discs, 1.0, &mut rng);
    Ok((discs, sim_box))
}

/// Draws Maxwell-Boltzmann velocities at temperature `kt` (each component normal with variance
/// `kT/m`), removes the centre-of-mass velocity and rescales so that `sum m v^2 / 2 = DIM/2 N kT`
/// exactly (the equipartition value, `N kT` in 2D).
pub fn thermal_velocities<const D: usize>(discs: &mut [Disc<D>], kt: f64, rng: &mut impl Rng) {
    if discs.is_empty() {
        return;
    }
    let mut p = Vector::ZERO;
    let mut m_total = 0.0;
    for d in discs.iter_mut() {
        let s = (kt / d.mass).sqrt();
        for a in 0..D {
            let z: f64 = rng.sample(StandardNormal);
            d.vel[a] = s * z;
        }
        p += d.vel * d.mass;
        m_total += d.mass;
    }
    let v_cm = p / m_total;
    let mut ke = 0.0;
    for d in discs.iter_mut() {
        // A lone disc keeps its velocity (removing the centre-of-mass motion would stop it).
        if m_total > d.mass {
            d.vel -= v_cm;
        }
        ke += d.kinetic_energy();
    }
    let target = 0.5 * D as f64 * discs.len() as f64 * kt;
    if ke > 0.0 {
        let s = (target / ke).sqrt();
        for d in discs.iter_mut() {
            d.vel = d.vel * s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_has_requested_packing_and_no_overlap() {
        for &b in &[Boundary::Periodic, Boundary::Walls] {
            for &phi in &[0.1, 0.6, 0.85] {
                let (discs, bx) = lattice_fluid(1000, phi, b, 1).unwrap();
                assert_eq!(discs.len(), 1000);
                let area: f64 = discs
                    .iter()
                    .map(|d| std::f64::consts::PI * d.radius * d.radius)
                    .sum();
                assert!((area / bx.volume() - phi).abs() < 1e-12);
                let sim = crate::Simulation::new(&discs, bx, Default::default()).unwrap();
                assert_eq!(sim.overlaps(1e-9).count, 0);
                let p = sim.momentum();
                assert!(p.norm2().sqrt() < 1e-9);
                assert!((sim.kinetic_energy() - 1000.0).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn impossible_packing_is_refused() {
        assert!(lattice_fluid(100, 0.95, Boundary::Periodic, 1).is_err());
        assert!(lattice_fluid(0, 0.5, Boundary::Periodic, 1).is_err());
    }
}
