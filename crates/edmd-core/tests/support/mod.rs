//! Shared helpers: random systems and a brute-force reference simulator.

pub mod naive;

use edmd_core::{Disc, Observer, Simulation, Vector};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// `n` non-overlapping discs placed at random (rejection sampling) in `[0, l]^2`, radii in
/// `[r_min, r_max]`, masses in `[0.5, 4]`, velocity components in `[-1, 1]`. With `walls`, the
/// discs keep clear of the walls.
pub fn random_discs(n: usize, l: f64, r_min: f64, r_max: f64, walls: bool, seed: u64) -> Vec<Disc> {
    random_discs_in::<2>(n, l, r_min, r_max, walls, seed)
}

/// [`random_discs`] in `D` dimensions, in the cube `[0, l]^D`.
pub fn random_discs_in<const D: usize>(
    n: usize,
    l: f64,
    r_min: f64,
    r_max: f64,
    walls: bool,
    seed: u64,
) -> Vec<Disc<D>> {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut discs: Vec<Disc<D>> = Vec::new();
    let mut tries = 0;
    while discs.len() < n {
        tries += 1;
        assert!(tries < 1_000_000, "could not place {n} discs");
        let r = rng.random_range(r_min..=r_max);
        let m = if walls { 0.0 } else { r };
        let p = Vector(std::array::from_fn(|_| rng.random_range(m..l - m)));
        let clear = discs.iter().all(|d| {
            let mut dx = d.pos - p;
            if !walls {
                for a in 0..D {
                    dx[a] -= l * (dx[a] / l).round();
                }
            }
            dx.norm2() > (d.radius + r).powi(2) * (1.0 + 1e-6)
        });
        let inside = !walls || (0..D).all(|a| p[a] >= r && p[a] <= l - r);
        if clear && inside {
            let v = Vector(std::array::from_fn(|_| rng.random_range(-1.0..1.0)));
            let mut d = Disc::new(p, v, r);
            d.mass = rng.random_range(0.5..4.0);
            discs.push(d);
        }
    }
    discs
}

/// FNV-1a over the bits of every position and velocity: a digest of a run's outcome.
pub fn digest(discs: &[Disc]) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for d in discs {
        for x in [d.pos[0], d.pos[1], d.vel[0], d.vel[1]] {
            for b in x.to_bits().to_le_bytes() {
                h ^= b as u64;
                h = h.wrapping_mul(0x100000001b3);
            }
        }
    }
    h
}

/// The bits of every sphere's position and velocity: two runs that agree on these ran the
/// same trajectory to the bit.
pub fn bits_3d(s: &Simulation<3>) -> Vec<[u64; 6]> {
    s.discs()
        .iter()
        .map(|d| std::array::from_fn(|a| [d.pos, d.vel][a / 3][a % 3].to_bits()))
        .collect()
}

/// A checkpoint file from its header and payload without the checksum (`bytes`, whose header
/// may carry any payload length): the header's payload length set and the CRC-32 appended,
/// so that only the payload's own checks can refuse it.
pub fn reframed(mut bytes: Vec<u8>) -> Vec<u8> {
    let payload = (bytes.len() - 24) as u64;
    bytes[16..24].copy_from_slice(&payload.to_le_bytes());
    let crc = crc32fast::hash(&bytes);
    bytes.extend_from_slice(&crc.to_le_bytes());
    bytes
}

/// The observer as a trait object: the engine's loop is compiled once for each type of
/// observer it runs with, and this binary's tests, passing theirs through here, share one
/// copy per dimension. With a copy for each of the tests' 25 observers the binary took 895 s
/// to build on two cores (963 s of CPU); with them shared, 163 s (205 s).
pub fn obs<const D: usize>(o: &mut impl Observer<D>) -> &mut dyn Observer<D> {
    o
}
