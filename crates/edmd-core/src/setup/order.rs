//! Bond-orientational order: the local and global hexatic order parameter `psi_6`.
//!
//! For disc `j` with neighbours `k`, `psi_6(j) = (1/n_j) sum_k exp(6 i theta_jk)`, where
//! `theta_jk` is the angle of the bond `r_k - r_j` (minimum image on periodic axes). The global
//! value is `|psi_6| = |(1/N) sum_j psi_6(j)|`: 1 for a perfect triangular lattice, of order
//! `1/sqrt(N)` for a liquid (a sum of `N` unit vectors with random phases), in between for a
//! polycrystal or a hexatic. A disc without neighbours contributes 0.
//!
//! Neighbours are found with the engine's cell grid ([`crate::cells::CellGrid`]). A disc with
//! fewer than `k` candidates within the search radius is looked up again in a grid of twice
//! the radius, and so on; a scan over all discs is left for when no such grid can be built (a
//! periodic box shorter than three search radii).

use crate::cells::CellGrid;
use crate::math::{Vector, DIM};
use crate::state::{Disc, SimBox};

/// Which discs count as the neighbours of a disc.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Neighbours {
    /// The `k` nearest discs (fewer only if there are not that many other discs). `Nearest(6)`
    /// is the usual choice and gives exactly 1 on a perfect periodic triangular lattice.
    Nearest(usize),
    /// Every disc whose centre is within this distance (on periodic axes it should not exceed
    /// half the box length). On a triangular lattice any cutoff between the first and second
    /// shells (`a` and `sqrt(3) a`) gives exactly 1, walls included.
    Within(f64),
}

/// The local order parameter `psi_6(j)` of every disc, as `[re, im]`.
pub fn local_psi6(discs: &[Disc], sim_box: &SimBox, neighbours: Neighbours) -> Vec<[f64; 2]> {
    let n = discs.len();
    let pos: Vec<Vector> = discs.iter().map(|d| sim_box.wrap(d.pos)).collect();
    // Search radius: given, or 1.5 triangular-lattice spacings at this number density (the
    // six nearest neighbours of a dense liquid or a crystal lie well inside).
    let radius = match neighbours {
        Neighbours::Within(rc) => rc,
        Neighbours::Nearest(_) => {
            let spacing = (2.0 * sim_box.volume() / (3f64.sqrt() * n.max(1) as f64)).sqrt();
            1.5 * spacing
        }
    };
    let build = |r: f64| -> Option<CellGrid> {
        if !(r.is_finite() && r > 0.0) {
            return None;
        }
        CellGrid::new(sim_box, n, r).ok().map(|mut g| {
            for (i, &p) in pos.iter().enumerate() {
                g.insert(i, g.coord_of(p));
            }
            g
        })
    };
    // Grids of doubling search radius, each built when a disc first needs it: a disc in a void
    // of a dense liquid can have fewer than `k` discs within the first radius, and scanning
    // all discs for each of those made this O(N^2) (2 min 40 s of `edmd gen fluid --n 100000`).
    let mut levels: Vec<(f64, Option<CellGrid>)> = vec![(radius, build(radius))];
    let mut bonds: Vec<(f64, Vector)> = Vec::new();
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut complete = false;
        for level in 0.. {
            if level == levels.len() {
                let r = 2.0 * levels[level - 1].0;
                levels.push((r, build(r)));
            }
            let (r, Some(g)) = &levels[level] else {
                break;
            };
            bonds.clear();
            g.for_each_near(g.cell_of(i), |j, shift| {
                if j != i {
                    let d = pos[j] + shift - pos[i];
                    bonds.push((d.norm2(), d));
                }
            });
            complete = match neighbours {
                Neighbours::Within(_) => true,
                Neighbours::Nearest(k) => {
                    let k = k.min(n - 1);
                    k == 0 || (bonds.len() >= k && kth_smallest(&mut bonds, k) <= r * r)
                }
            };
            if complete || matches!(neighbours, Neighbours::Within(_)) {
                break;
            }
        }
        if !complete {
            bonds.clear();
            for j in (0..n).filter(|&j| j != i) {
                let d = sim_box.minimum_image(pos[j] - pos[i]);
                bonds.push((d.norm2(), d));
            }
        }
        let chosen: &[(f64, Vector)] = match neighbours {
            Neighbours::Within(rc) => {
                bonds.retain(|b| b.0 <= rc * rc);
                &bonds
            }
            Neighbours::Nearest(k) => {
                let k = k.min(bonds.len());
                if k > 0 {
                    kth_smallest(&mut bonds, k);
                }
                &bonds[..k]
            }
        };
        out.push(mean_phase(chosen));
    }
    out
}

/// The global order `|psi_6| = |(1/N) sum_j psi_6(j)|` (0 for no discs).
pub fn psi6(discs: &[Disc], sim_box: &SimBox, neighbours: Neighbours) -> f64 {
    if discs.is_empty() {
        return 0.0;
    }
    let local = local_psi6(discs, sim_box, neighbours);
    let (re, im) = local
        .iter()
        .fold((0.0, 0.0), |(re, im), z| (re + z[0], im + z[1]));
    let n = discs.len() as f64;
    (re / n).hypot(im / n)
}

/// Puts the `k` smallest bonds (by squared length) first and returns the `k`-th squared length.
fn kth_smallest(bonds: &mut [(f64, Vector)], k: usize) -> f64 {
    bonds.select_nth_unstable_by(k - 1, |a, b| a.0.total_cmp(&b.0));
    bonds[k - 1].0
}

/// `(1/n) sum exp(6 i theta)` over the bonds, as `[re, im]` (0 for no bonds).
fn mean_phase(bonds: &[(f64, Vector)]) -> [f64; 2] {
    debug_assert_eq!(DIM, 2, "psi_6 is defined in two dimensions");
    if bonds.is_empty() {
        return [0.0, 0.0];
    }
    let (mut re, mut im) = (0.0, 0.0);
    for (_, d) in bonds {
        let theta = 6.0 * d[1].atan2(d[0]);
        re += theta.cos();
        im += theta.sin();
    }
    let n = bonds.len() as f64;
    [re / n, im / n]
}

/// The amplitude of a face-centred cubic lattice's density wave: `sqrt(mean over the four
/// {111} vectors k of |(1/N) sum_j exp(i k . r_j)|^2)` with `k = 2 pi (+-1, +-1, +-1) / a`,
/// where the box holds `cells[a]` cubic cells of side `a = L / cells` along each axis. It is 1
/// on the lattice (whatever its offset), the Debye-Waller factor in a thermal crystal, and
/// about `1 / sqrt(N)` in a fluid (the 3D counterpart of [`psi6`] for telling them apart).
pub fn fcc_order(discs: &[Disc<3>], sim_box: &SimBox<3>, cells: [f64; 3]) -> f64 {
    let k: [f64; 3] =
        std::array::from_fn(|a| 2.0 * std::f64::consts::PI * cells[a] / sim_box.lengths[a]);
    let signs = [
        [1.0, 1.0, 1.0],
        [1.0, 1.0, -1.0],
        [1.0, -1.0, 1.0],
        [-1.0, 1.0, 1.0],
    ];
    let n = discs.len().max(1) as f64;
    let mut sum = 0.0;
    for s in signs {
        let (mut re, mut im) = (0.0, 0.0);
        for d in discs {
            let phase: f64 = (0..3).map(|a| s[a] * k[a] * d.pos[a]).sum();
            re += phase.cos();
            im += phase.sin();
        }
        sum += (re * re + im * im) / (n * n);
    }
    (sum / signs.len() as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::setup::lattice_fluid;
    use crate::state::Boundary;

    #[test]
    fn perfect_periodic_lattice_has_psi6_one() {
        let (discs, bx) = lattice_fluid(24 * 20, 0.6, Boundary::Periodic, 3).unwrap();
        let v = psi6(&discs, &bx, Neighbours::Nearest(6));
        assert!((v - 1.0).abs() < 1e-9, "{v}");
        let (discs, bx) = lattice_fluid(300, 0.6, Boundary::Walls, 3).unwrap();
        let a = (discs[1].pos - discs[0].pos).norm2().sqrt();
        let v = psi6(&discs, &bx, Neighbours::Within(1.2 * a));
        assert!((v - 1.0).abs() < 1e-9, "{v}");
    }

    /// Discs placed uniformly at random leave voids: many have fewer than 6 discs within the
    /// first search radius and are looked up in the wider grids. Every local value must match a
    /// brute-force scan over all discs.
    #[test]
    fn discs_in_voids_find_their_nearest_neighbours() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(7);
        let bx = SimBox::periodic([40.0, 30.0]);
        let discs: Vec<Disc> = (0..600)
            .map(|_| {
                let p = Vector::new([rng.random_range(0.0..40.0), rng.random_range(0.0..30.0)]);
                Disc::new(p, Vector::ZERO, 0.1)
            })
            .collect();
        let fast = local_psi6(&discs, &bx, Neighbours::Nearest(6));
        let spacing = (2.0 * bx.volume() / (3f64.sqrt() * 600.0)).sqrt();
        let mut in_voids = 0;
        for (i, d) in discs.iter().enumerate() {
            let mut bonds: Vec<(f64, Vector)> = (0..discs.len())
                .filter(|&j| j != i)
                .map(|j| {
                    let r = bx.minimum_image(discs[j].pos - d.pos);
                    (r.norm2(), r)
                })
                .collect();
            let sixth = kth_smallest(&mut bonds, 6);
            in_voids += (sixth > (1.5 * spacing).powi(2)) as usize;
            let want = mean_phase(&bonds[..6]);
            for c in 0..2 {
                assert!(
                    (fast[i][c] - want[c]).abs() < 1e-12,
                    "disc {i}: {:?} vs {want:?}",
                    fast[i]
                );
            }
        }
        assert!(in_voids > 20, "only {in_voids} discs in voids");
    }

    #[test]
    fn tiny_systems_use_the_full_scan() {
        let discs: Vec<Disc> = (0..3)
            .map(|k| Disc::new(Vector::new([1.0 + k as f64, 1.0]), Vector::ZERO, 0.1))
            .collect();
        let bx = SimBox::walls([5.0, 5.0]);
        // All bonds lie along x: exactly 1.
        assert!((psi6(&discs, &bx, Neighbours::Nearest(6)) - 1.0).abs() < 1e-12);
        assert_eq!(psi6(&discs[..1], &bx, Neighbours::Nearest(6)), 0.0);
        assert_eq!(psi6(&[], &bx, Neighbours::Nearest(6)), 0.0);
    }
}
